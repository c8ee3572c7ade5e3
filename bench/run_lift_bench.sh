#!/usr/bin/env bash
# Issue 27's lifting heads (docs/measurement.md, "Out of the plane"): the
# delta and the floating mechanism with heads lifted by up to 0.6 mm and
# tilted by up to 1 deg (bench/lift_*.plan.yaml), rendered at 1080p and a
# phone's 10 Mb/s into build/bench-lift/NAME, measured by `validate` as it
# decides by default (report/), with --no-lift-correction (report-left-in/)
# and with --lift-correction (report-corrected/), and each test point's lift
# and displacement compared with the render's truth (bench/score_lift.py).
#   bench/run_lift_bench.sh [delta|floating|delta_wide|floating_wide...]
# (default: delta floating). The _wide plans print each head's dots 2.36
# times further apart (toward the plate's corners): the dot spacing's share.
# SOFTBENCH=path runs another build. A clip is rendered once and kept.
# LIFT_CRF=N renders at that x264 quality instead of 10 Mb/s (CRF 4 is
# about 116 Mb/s at 1080p), into build/bench-lift/NAME-crfN: the bit rate's
# share of the lift's error. LIFT_HLG=1 renders as an iPhone writes by
# default (HEVC Main 10, HLG, BT.2020) at the same 10 Mb/s, into
# build/bench-lift/NAME-hlg: the codec's share at a phone's bit rate.
# LIFT_DISTANCE_MM=N puts the camera N mm above the dots instead of the
# renderer's 475 (every dot on another pixel phase), into DIR-dN.
# LIFT_FLAT=1 renders the plan with every head flat (no lift, no tilt), into
# DIR-flat: what an in-plane move alone reads as lift (docs/measurement.md,
# "An offset on each head's lifts").
set -euo pipefail
cd "$(dirname "$0")/.."
softbench=${SOFTBENCH:-./build/release/softbench}
[[ -x $softbench ]] || { echo "build first: cmake --build --preset release" >&2; exit 2; }
out=build/bench-lift
if [[ -n ${LIFT_CRF:-} && -n ${LIFT_HLG:-} ]]; then
  echo "LIFT_CRF and LIFT_HLG name two encodings; set one" >&2
  exit 2
fi
names=("$@")
[[ ${#names[@]} -gt 0 ]] || names=(delta floating)
for name in "${names[@]}"; do
  dir=$out/$name
  quality=(--bitrate-mbps 10)
  label=$name
  if [[ -n ${LIFT_CRF:-} ]]; then
    label="$name, CRF $LIFT_CRF"
    dir=$out/$name-crf$LIFT_CRF
    quality=(--crf "$LIFT_CRF")
  elif [[ -n ${LIFT_HLG:-} ]]; then
    label="$name, HEVC 10-bit HLG"
    dir=$out/$name-hlg
    quality=(--bitrate-mbps 10 --codec hevc --bit-depth 10 --hdr hlg)
  fi
  distance=()
  if [[ -n ${LIFT_DISTANCE_MM:-} ]]; then
    label="$label, camera $LIFT_DISTANCE_MM mm"
    dir=$dir-d$LIFT_DISTANCE_MM
    distance=(--distance-mm "$LIFT_DISTANCE_MM")
  fi
  plan=bench/lift_$name.plan.yaml
  if [[ -n ${LIFT_FLAT:-} ]]; then
    label="$label, heads flat"
    dir=$dir-flat
  fi
  mkdir -p "$dir"
  if [[ -n ${LIFT_FLAT:-} ]]; then
    flat='head_lift_mm: 0.0, head_tilt_deg: 0.0'
    sed -E "s/head_lift_mm: [0-9.]+, head_tilt_deg: [0-9.]+/$flat/" \
      "$plan" > "$dir/flat.plan.yaml"
    grep -q "$flat" "$dir/flat.plan.yaml" ||
      { echo "$plan: no 'head_lift_mm: X, head_tilt_deg: Y' to flatten" >&2; exit 2; }
    plan=$dir/flat.plan.yaml
  fi
  if [[ ! -f $dir/clip.mp4 ]]; then
    echo "rendering $dir/clip.mp4..." >&2
    $softbench --quiet render --plan "$plan" \
      --out "$dir/clip.tmp.mp4" --truth "$dir/truth.csv" \
      --plan-out "$dir/plan.yaml" --preset veryfast --resolution 1080p \
      "${quality[@]}" "${distance[@]}" --seed 27
    mv "$dir/clip.tmp.mp4" "$dir/clip.mp4"
  fi
  $softbench --quiet validate "$dir/clip.mp4" --plan "$dir/plan.yaml" \
    --out "$dir/report" | grep "their parallax" >&2 || true
  $softbench --quiet validate "$dir/clip.mp4" --plan "$dir/plan.yaml" \
    --no-lift-correction --out "$dir/report-left-in" >/dev/null
  $softbench --quiet validate "$dir/clip.mp4" --plan "$dir/plan.yaml" \
    --lift-correction --out "$dir/report-corrected" >/dev/null
  bench/score_lift.py "$dir/truth.csv" "$dir/report" "$label (default)"
  bench/score_lift.py "$dir/truth.csv" "$dir/report-left-in" \
    "$label (--no-lift-correction)"
  bench/score_lift.py "$dir/truth.csv" "$dir/report-corrected" \
    "$label (--lift-correction)"
done
