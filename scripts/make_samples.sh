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

render() {  # name seed
  mkdir -p "$out/$1"
  "$softbench" render --plan "samples/$1/plan.yaml" --output "$out/$1/$1.mp4" \
    --truth "$out/$1/truth.csv" --plan-out "$out/$1/rendered.plan.yaml" \
    --resolution 1080p --codec h264 --crf 20 --keyframe-interval-s 2 --seed "$2"
}
render delta 11
render floating 12

if [[ "$out" == samples ]]; then
  (cd samples && sha256sum delta/delta.mp4 delta/truth.csv floating/floating.mp4 \
    floating/truth.csv > SHA256SUMS)
  ls -l samples/delta samples/floating
else
  (cd "$out" && sha256sum -c "$OLDPWD/samples/SHA256SUMS") && rm -rf "$out"
fi
