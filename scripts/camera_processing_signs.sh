#!/usr/bin/env bash
# What the tag's border shows of a camera's processing (issue 28), footage
# by footage: a short still delta clip (one test point) rendered plain, at
# other rates, sizes and formats, and through each stage of a phone's
# pipeline, then validated; prints one markdown row per clip with the signs
# (summary.json's camera_processing: each the median over the tag's first
# 10 frames) and the effects named. docs/measurement.md quotes the table.
# About 15 minutes (most of it the --sensor-scale 2 clip).
#   scripts/camera_processing_signs.sh OUT_DIR
set -euo pipefail
source "$(dirname "$0")/footage_setup.sh" "$@"

cat >plan.yaml <<'PLAN'
mechanism: delta
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 3, size_mm: 25}
scene: {settle_time_constant_s: 0.1, lead_in_s: 1.2, hold_s: 1.2, rest_s: 1.2}
tests:
  - {id: a, pressures: [6, 0, 0]}
PLAN

echo "| footage | edge shift [px] | halo [% of step] | white beyond / inside [%] | named |"
echo "|---|---|---|---|---|"
case_() {  # name, then render's flags for it
  local name=$1
  shift
  render_and_validate "$name" "$@"
  python3 - "$name/report/summary.json" "$*" <<'ROW'
import json, sys
p = json.load(open(sys.argv[1]))["camera_processing"]
named = "; ".join(e["effect"] for e in p["effects"]) or "none"
print(f"| `{sys.argv[2]}` | {p['edge_shift_px']:+.3f} | {p['halo_percent']:.1f} "
      f"| {p['white_ratio_percent']:+.2f} | {named} |")
ROW
}

case_ plain --resolution 1080p --crf 17
case_ plain-crf12 --resolution 1080p --crf 12
case_ plain-crf23 --resolution 1080p --crf 23
case_ plain-10mbps --resolution 1080p --bitrate-mbps 10
case_ plain-720p --resolution 720p --crf 17
case_ plain-4k --resolution 4k --crf 17
case_ hlg --resolution 1080p --codec hevc --bit-depth 10 --hdr hlg \
  --bitrate-mbps 10
case_ lens-blur --resolution 1080p --crf 17 --lens-blur 1.0
case_ bayer --resolution 1080p --crf 17 --bayer bilinear \
  --sensor-full-well 6000
case_ tone-curve --resolution 1080p --crf 17 --tone-curve 1.0
case_ sharpen-mild --resolution 1080p --crf 17 --sharpen 0.5,0.3
case_ sharpen --resolution 1080p --crf 17 --sharpen 1,0.8
case_ local-tone --resolution 1080p --crf 17 --local-tone 0.6
case_ isp --resolution 1080p --crf 17 --isp
case_ isp-strong --resolution 1080p --crf 17 --isp --bayer bilinear \
  --lens-blur 1.0 --tone-curve 1.0 --sharpen 1.0,1.5
case_ isp-sensor-2 --resolution 1080p --crf 17 --isp --sensor-scale 2
