#!/usr/bin/env bash
# softbench validate (every frame registered and measured, full report)
# against decoding the same file and nothing else, on each format issue 29
# names (docs/benchmarks.md, "Validate against decode, format by format"):
#   samples/delta/delta.mp4   1080p 8-bit H.264, 114 s, a still camera
#   hlg_1080p.mp4             1080p 10-bit HEVC, HLG BT.2020 (a phone's default)
#   hevc_4k.mp4               4K 8-bit HEVC
#   h264_4k.mp4               4K 8-bit H.264
# The last three are rendered once into build/bench-formats from the same
# 16 s scene of the delta mechanism (bench/formats.plan.yaml, a still camera).
# Each round runs decode only (ffmpeg -f null, default threads: the limit)
# and validate (target: within 1.10x its wall and CPU time) on one file after
# the other (bench/interleaved_rounds.sh), and the ratios are taken within a
# round. The 10-minute 1080p H.264 video is bench/run_validate_bench.sh's.
# Usage: bench/run_formats_bench.sh [rounds]   (default 5; medians)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/interleaved_rounds.sh
rounds=${1:-5}
./scripts/bootstrap.sh --bench
cmake --preset release >/dev/null && cmake --build --preset release >/dev/null

source bench/formats_clips.sh
out=$formats_clips
render_formats_clip hlg_1080p --resolution 1080p --codec hevc --bit-depth 10 --hdr hlg
render_formats_clip hevc_4k --resolution 4k --codec hevc
render_formats_clip h264_4k --resolution 4k --codec h264

cases=("samples/delta/delta.mp4 samples/delta/rendered.plan.yaml")
for name in hlg_1080p hevc_4k h264_4k; do
  cases+=("$out/$name.mp4 $out/$name.plan.yaml")
done
for case in "${cases[@]}"; do
  read -r video plan <<<"$case"
  name=$(basename "$video" .mp4)
  ffprobe -v error -select_streams v -show_entries \
    stream=codec_name,pix_fmt,width,height,nb_frames,color_transfer \
    -of csv=p=0 "$video" | sed "s/^/$name: /"
  commands=("ffmpeg -v error -i $video -map 0:v -f null -"
    "./build/release/softbench --quiet validate $video --plan $plan --out $out/report-$name")
  run_rounds "$rounds" "$out/times-$name.txt" "${commands[@]}"
  summarise_rounds "$out/times-$name.txt" "decode only" "validate"
done
