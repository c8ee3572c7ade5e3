#!/usr/bin/env bash
# Issue 26's coverage families (docs/uncertainty.md, "Coverage"): the
# delta's 24 test points of bench/coverage.plan.yaml rendered once per
# family into build/bench-coverage/FAMILY (107 s of video each; 720p but for
# 4k), measured by `validate`, and each test point's error against the
# render's truth compared with its reported u (bench/score_coverage.py);
# then the same with --windows-only.
#   bench/run_coverage_bench.sh [FAMILY...]   (default: all, 4k last)
# SOFTBENCH=path runs another build (a copy, while this one is rebuilt).
# Families: still shaken hdr_portrait drift vfr low_bitrate 4k; isp
# sharpened sharpened_crf8 still_crf8 sharpened_1080p_crf8 (issue 28's, not
# in the default). A clip is rendered once and kept; delete its folder to
# render it again.
set -euo pipefail
cd "$(dirname "$0")/.."
softbench=${SOFTBENCH:-./build/release/softbench}
[[ -x $softbench ]] || { echo "build first: cmake --build --preset release" >&2; exit 2; }
out=build/bench-coverage

family_options() {
  case $1 in
    still) echo "--resolution 720p" ;;
    # Drift, tremor and five knocks: inside t02's actuated and t11's initial
    # windows, between t05's and t16's initial and actuated windows, and in
    # t20's rest before its final window.
    shaken) echo "--resolution 720p --camera-drift-px 0.5,-0.3 --camera-tremor-px 0.08" \
      "--camera-bump 12.1:1.5,0.4,0.03 --camera-bump 24.0:-1.2,1.0,-0.02" \
      "--camera-bump 49.4:0.8,-1.5,0.02 --camera-bump 72.6:-2.0,-0.6,0.04" \
      "--camera-bump 93.0:1.0,1.2,-0.03" ;;
    # An iPhone's default: HLG 10-bit HEVC at 10 Mb/s, held upright.
    hdr_portrait) echo "--resolution 720x1280 --rotation 90 --codec hevc" \
      "--bit-depth 10 --hdr hlg --bitrate-mbps 10" ;;
    drift) echo "--resolution 720p --exposure-drift 0.3 --white-balance-drift-k 800" ;;
    vfr) echo "--resolution 720p --vfr-jitter 0.5" ;;
    low_bitrate) echo "--resolution 720p --bitrate-mbps 0.5" ;;
    4k) echo "--resolution 4k" ;;
    # A phone's image pipeline (issue 28): lens blur, an RGGB sensor with raw
    # noise demosaiced, its own tone curves, noise reduction and sharpening.
    isp) echo "--resolution 720p --isp" ;;
    # Pixel-sharp edges under the phone's S-curve and strong sharpening: the
    # largest per-dot pixel-phase bias (docs/measurement.md).
    sharpened) echo "--resolution 720p --tone-curve 0.6 --sharpen 1.5,1.0" ;;
    # The same at a high bit rate (CRF 8: about 22 Mb/s at 720p), where the
    # codec's term no longer hides the dots' own errors; the plain still
    # camera at that rate to compare; and 1080p, whose 17 px tag cells keep
    # the tag's scale out of the processing.
    sharpened_crf8) echo "--resolution 720p --tone-curve 0.6 --sharpen 1.5,1.0 --crf 8" ;;
    still_crf8) echo "--resolution 720p --crf 8" ;;
    sharpened_1080p_crf8) echo "--resolution 1080p --tone-curve 0.6 --sharpen 1.5,1.0 --crf 8" ;;
    *) echo "unknown family $1" >&2; exit 2 ;;
  esac
}

families=("$@")
[[ ${#families[@]} -gt 0 ]] ||
  families=(still shaken hdr_portrait drift vfr low_bitrate 4k)
rows=()
for family in "${families[@]}"; do
  options=$(family_options "$family")
  dir=$out/$family
  mkdir -p "$dir"
  if [[ ! -f $dir/clip.mp4 ]]; then
    echo "rendering $dir/clip.mp4 ($options)..." >&2
    # shellcheck disable=SC2086
    $softbench --quiet render --plan bench/coverage.plan.yaml \
      --out "$dir/clip.tmp.mp4" --truth "$dir/truth.csv" \
      --plan-out "$dir/plan.yaml" --preset veryfast \
      --seed 26 $options
    mv "$dir/clip.tmp.mp4" "$dir/clip.mp4"
  fi
  $softbench --quiet validate "$dir/clip.mp4" --plan "$dir/plan.yaml" \
    --out "$dir/report" >/dev/null
  rows+=("$(bench/score_coverage.py "$dir/truth.csv" "$dir/report" "$family")")
  $softbench --quiet validate "$dir/clip.mp4" --plan "$dir/plan.yaml" \
    --windows-only --out "$dir/report-windows" >/dev/null
  rows+=("$(bench/score_coverage.py "$dir/truth.csv" "$dir/report-windows" \
    "$family, --windows-only")")
done
echo "| family | test points | RMS error [um] | max error [um] | median u [um] | median u / RMS | within u | within U = 2u | targets met |"
echo "|---|---|---|---|---|---|---|---|---|"
printf '%s\n' "${rows[@]}"
