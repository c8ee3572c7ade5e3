#!/usr/bin/env bash
# The uncertainty budget's intrinsics term (docs/uncertainty.md): a 720p
# render of bench/coverage.plan.yaml through a wide, distorted, tilted lens
# (26 mm equivalent, k1 -0.12, k2 0.03, tilt 4,-2 deg), validated with its
# exact intrinsics and with a calibration about one standard error off in
# every parameter (the file with its standard errors); each displacement's
# shift between the two runs against the term (bench/score_intrinsics.py),
# and both runs' coverage against the truth (bench/score_coverage.py).
#   bench/run_intrinsics_bench.sh
# SOFTBENCH=path runs another build. The clip is rendered once into
# build/bench-intrinsics and kept; delete the folder to render it again.
set -euo pipefail
cd "$(dirname "$0")/.."
softbench=${SOFTBENCH:-./build/release/softbench}
[[ -x $softbench ]] || { echo "build first: cmake --build --preset release" >&2; exit 2; }
dir=build/bench-intrinsics
mkdir -p "$dir"
if [[ ! -f $dir/clip.mp4 ]]; then
  $softbench --quiet render --plan bench/coverage.plan.yaml \
    --out "$dir/clip.tmp.mp4" --truth "$dir/truth.csv" \
    --plan-out "$dir/plan.yaml" --preset veryfast --seed 26 \
    --resolution 720p --focal-35mm 26 --tilt-deg 4,-2 \
    --distortion=-0.12,0.03,0,0,0
  mv "$dir/clip.tmp.mp4" "$dir/clip.mp4"
fi
bench/score_intrinsics.py write "$dir"
rows=()
for v in exact off_std; do
  sed "s|^  plane_offset_mm: 16|  plane_offset_mm: 16\n  intrinsics: $v.yaml|" \
    "$dir/plan.yaml" >"$dir/plan_$v.yaml"
  $softbench --quiet validate "$dir/clip.mp4" --plan "$dir/plan_$v.yaml" \
    --out "$dir/report_$v" >/dev/null
  rows+=("$(bench/score_coverage.py "$dir/truth.csv" "$dir/report_$v" "$v")")
done
echo "| intrinsics | test points | RMS error [um] | max error [um] | median u [um] | median u / RMS | within u | within U = 2u | targets met |"
echo "|---|---|---|---|---|---|---|---|---|"
printf '%s\n' "${rows[@]}"
bench/score_intrinsics.py score "$dir"
