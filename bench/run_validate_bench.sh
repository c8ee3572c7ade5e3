#!/usr/bin/env bash
# softbench validate on a 10-minute 1080p H.264 bench video (the thesis's
# protocol: 20 s holds, 20 s rests, 15 test points), against decoding the same
# file and nothing else (docs/benchmarks.md):
#   decode only       ffmpeg -f null (default threads), the limit
#   full tracking     softbench validate (every frame measured, full report)
#   windows only      softbench validate --windows-only (seeks to the windows)
#   windows, decode   ffmpeg decoding only those windows, two at a time
#                     (bench/decode_windows.py), the peer of windows only
# Usage: bench/run_validate_bench.sh [rounds]   (default 5; medians)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/interleaved_rounds.sh
runs=${1:-5}
./scripts/bootstrap.sh --bench
cmake --preset release >/dev/null && cmake --build --preset release >/dev/null

media=build/bench-validate
mkdir -p "$media"
video=$media/delta_10min.mp4
if [[ ! -f "$video" ]]; then
  echo "rendering $video (about 20 minutes on 2 cores)..."
  ./build/release/softbench --quiet render --plan bench/validate_10min.plan.yaml \
    --out "$video" --truth "$media/truth.csv" \
    --plan-out "$media/rendered.plan.yaml" --resolution 1080p --codec h264 \
    --preset veryfast --seed 21
fi
ffprobe -v error -select_streams v -show_entries stream=width,height,nb_frames,duration \
  -of csv=p=0 "$video" | awk -F, '{print "video: " $1 "x" $2 ", " $3 " s, " $4 " frames"}'

validate="./build/release/softbench --quiet validate $video --plan $media/rendered.plan.yaml"
commands=("ffmpeg -v error -i $video -map 0:v -f null -"
  "$validate --out $media/report-full"
  "$validate --windows-only --out $media/report-windows"
  "bench/decode_windows.py $video $media/report-windows")
# The windows' decode needs their times: from a windows-only run first.
[[ -f $media/report-windows/summary.json ]] || $validate --windows-only \
  --out "$media/report-windows" >/dev/null
run_rounds "$runs" "$media/times.txt" "${commands[@]}"
summarise_rounds "$media/times.txt" "decode only" "validate" \
  "validate --windows-only" "ffmpeg, the windows only"
wall_ratio "$media/times.txt" 1 2 "every frame / windows only, wall (target >= 15)"
wall_ratio "$media/times.txt" 1 3 "every frame / ffmpeg's windows only, wall"
bench/decode_windows.py --count "$video" "$media/report-windows"
