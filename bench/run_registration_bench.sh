#!/usr/bin/env bash
# What registering every frame to the bench costs on what phones record:
# softbench validate with and without registration against decoding the same
# file and nothing else (docs/benchmarks.md, "Registration"), on
#   samples/phone/phone.mp4   1080x1920 HEVC Main 10, HLG BT.2020, portrait
#                             (rotation metadata), variable frame rate,
#                             10 Mb/s, 16.5 s, a camera that moves
#   phone_4k.mp4              the same scene at 4K in 8-bit HEVC at 40 Mb/s
#                             (rendered once into build/bench-registration)
# For each: decode only (ffmpeg -f null, default threads: the limit),
# validate (every frame registered and measured, full report) and validate
# --no-registration, interleaved per round (bench/interleaved_rounds.sh).
# Usage: bench/run_registration_bench.sh [rounds]   (default 5; medians)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/interleaved_rounds.sh
runs=${1:-5}
./scripts/bootstrap.sh --bench
cmake --preset release >/dev/null && cmake --build --preset release >/dev/null

out=build/bench-registration
mkdir -p "$out"
plan=samples/phone/rendered.plan.yaml
video_4k=$out/phone_4k.mp4
if [[ ! -f "$video_4k" ]]; then
  echo "rendering $video_4k (about 10 minutes on 2 cores)..."
  ./build/release/softbench --quiet render --plan samples/phone/plan.yaml \
    --out "$video_4k" --truth "$out/truth_4k.csv" \
    --plan-out "$out/phone_4k.plan.yaml" --resolution 4k --codec hevc \
    --preset fast --seed 13 --bitrate-mbps 40 --keyframe-interval-s 1 \
    --camera-drift-px 0.8,-0.6 --camera-tremor-px 0.16 \
    --camera-bump 2.5:4,1,0.05 --camera-bump 8.2:-3,2.4,-0.04 \
    --camera-bump 14:2.4,-3.2,0.03 --exposure-drift 0.3 \
    --white-balance-drift-k 300 --drift-period-s 8
fi

for case in "samples/phone/phone.mp4 $plan" "$video_4k $out/phone_4k.plan.yaml"; do
  read -r video video_plan <<<"$case"
  name=$(basename "$video" .mp4)
  ffprobe -v error -select_streams v -show_entries \
    stream=codec_name,pix_fmt,width,height,nb_frames,color_transfer \
    -of csv=p=0 "$video" | sed "s/^/$name: /"
  validate="./build/release/softbench --quiet validate $video --plan $video_plan"
  commands=("ffmpeg -v error -i $video -map 0:v -f null -"
    "$validate --out $out/$name-registered"
    "$validate --no-registration --out $out/$name-still")
  run_rounds "$runs" "$out/times-$name.txt" "${commands[@]}"
  summarise_rounds "$out/times-$name.txt" "decode only" "validate" \
    "validate --no-registration"
  wall_ratio "$out/times-$name.txt" 1 2 "registered / not registered, wall"
done
