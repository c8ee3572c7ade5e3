#!/usr/bin/env bash
# Regenerates the sample videos and their truth from the plans in samples/,
# bit for bit: fixed seeds, single-threaded x264, bit-exact muxing.
#   scripts/make_samples.sh          re-render into samples/
#   scripts/make_samples.sh --check  re-render into a temporary folder and
#                                    compare with samples/SHA256SUMS
set -euo pipefail
cd "$(dirname "$0")/.."
softbench=./build/release/softbench
[[ -x $softbench ]] || { echo "build first: cmake --build --preset release" >&2; exit 2; }
out=samples
[[ "${1:-}" == "--check" ]] && out=$(mktemp -d)

render() {  # name seed format-rate-control-and-bench-conditions...
  mkdir -p "$out/$1"
  local name=$1 seed=$2
  shift 2
  "$softbench" render --plan "samples/$name/plan.yaml" \
    --out "$out/$name/$name.mp4" --truth "$out/$name/truth.csv" \
    --plan-out "$out/$name/rendered.plan.yaml" --seed "$seed" "$@"
}
# CRF 17 (2.4 Mb/s, still a quarter of a phone's rate): at CRF 20 (0.75
# Mb/s) the quantiser costs the still heads of both mechanisms up to 0.006
# mm, as each window of a still head shows the same few codec errors.
render delta 11 --resolution 1080p --codec h264 --crf 17 \
  --keyframe-interval-s 2
render floating 12 --resolution 1080p --codec h264 --crf 17 \
  --keyframe-interval-s 2
# A phone on a tripod (samples/phone/plan.yaml says what happens when), as
# an iPhone records by default: portrait, HEVC Main 10 with HLG and BT.2020,
# variable frame rate.
render phone 13 --resolution 1080x1920 --rotation 90 --codec hevc \
  --bit-depth 10 --hdr hlg --vfr-jitter 0.5 \
  --bitrate-mbps 10 --keyframe-interval-s 1 \
  --camera-drift-px 0.4,-0.3 --camera-tremor-px 0.08 \
  --camera-bump 2.5:2,0.5,0.05 --camera-bump 8.2:-1.5,1.2,-0.04 \
  --camera-bump 14:1.2,-1.6,0.03 --exposure-drift 0.3 \
  --white-balance-drift-k 300 --drift-period-s 8

if [[ "$out" == samples ]]; then
  (cd samples && sha256sum delta/delta.mp4 delta/truth.csv floating/floating.mp4 \
    floating/truth.csv phone/phone.mp4 phone/truth.csv > SHA256SUMS)
  ls -l samples/delta samples/floating samples/phone
else
  (cd "$out" && sha256sum -c "$OLDPWD/samples/SHA256SUMS") && rm -rf "$out"
fi
