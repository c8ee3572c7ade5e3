#!/usr/bin/env bash
# A phone's image pipeline and shutter, stage by stage, on the same bench
# (issue 28): a still SDR delta (four test points, b slipping 0.1 mm;
# scripts/delta_four_points.plan.yaml) rendered at 1080p H.264 CRF 17
# plain, then through `render --isp` (a phone's pipeline), on a sensor
# finer than the video, with a Bayer filter demosaiced bilinearly and no
# lens blur, with the strongest processing, with exposure and white balance
# drifting, with strong local tone mapping alone, with strong temporal noise
# reduction under a slight tremor, and a rolling shutter under tremor
# against the tremor alone; each is measured by `validate` and scored
# against its truth (about 25 minutes). docs/measurement.md quotes the
# worst errors.
#   scripts/phone_pipeline_footage.sh OUT_DIR
set -euo pipefail
source "$(dirname "$0")/footage_setup.sh" "$@"

cp "$root/scripts/delta_four_points.plan.yaml" plan.yaml

case_() {  # name, then render's flags for it
  local name=$1
  shift
  render_and_validate "$name" --resolution 1080p --crf 17 "$@"
  "$root/scripts/score_against_truth.py" "$name/truth.csv" "$name/report" \
    "$name ($*)" | tail -1
}

case_ plain
case_ isp --isp
case_ isp-sensor-2 --isp --sensor-scale 2
case_ bayer-bilinear --bayer bilinear --sensor-full-well 6000
case_ isp-strong --isp --bayer bilinear --lens-blur 1.0 --tone-curve 1.0 \
  --sharpen 1.0,1.5
case_ exposure-drift --isp --exposure-drift 0.25 --white-balance-drift-k 300 \
  --drift-period-s 8
case_ local-tone --local-tone 0.6
case_ temporal-denoise --temporal-denoise 0.8 --camera-tremor-px 0.05
case_ tremor --camera-tremor-px 0.3
case_ rolling-shutter --camera-tremor-px 0.3 --rolling-shutter-ms 30
