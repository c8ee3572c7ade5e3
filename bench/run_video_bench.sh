#!/usr/bin/env bash
# Render, decode and measurement benchmarks side by side with their peers:
# ffmpeg (decode) and bench/peers/dots_opencv.py (the textbook Python/OpenCV
# dot pipeline), on the same files (docs/benchmarks.md).
# Usage: bench/run_video_bench.sh [repetitions]   (default 5)
set -euo pipefail
cd "$(dirname "$0")/.."
repetitions=${1:-5}
./scripts/bootstrap.sh --bench
cmake --preset release >/dev/null && cmake --build --preset release >/dev/null

# 11 s clips of the delta sample's scene (moving heads), in each codec and size.
media=build/bench-media
mkdir -p "$media"
cat > "$media/plan.yaml" <<'PLAN'
mechanism: delta
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 0, size_mm: 25}
scene: {lead_in_s: 1, hold_s: 3, rest_s: 2}
tests:
  - {id: a, pressures: [6, 6, 0]}
  - {id: b, pressures: [4, 6, 1]}
PLAN
files=()
for codec in h264 hevc; do
  for resolution in 1080p 4k; do
    file="$media/${codec}_${resolution}.mp4"
    if [[ ! -f "$file" ]]; then
      ./build/release/softbench --quiet render --plan "$media/plan.yaml" \
        --out "$file" --truth "$media/truth.csv" --resolution "$resolution" \
        --codec "$codec" --preset veryfast >/dev/null
    fi
    files+=("$file")
  done
done

# Repetitions run in random order, so a change in the shared host's load
# hits decode-only and tracking alike.
echo "== softbench (Google Benchmark, median of $repetitions, interleaved) =="
./build/release/bench/video_benchmark --benchmark_repetitions="$repetitions" \
  --benchmark_enable_random_interleaving=true \
  --benchmark_report_aggregates_only=true -- "${files[@]}" 2>/dev/null | grep -E 'median|^Run'

echo "== peer: ffmpeg -f null (decode only, default threads), median of $repetitions =="
for file in "${files[@]}"; do
  hyperfine --runs "$repetitions" --style none --export-json "$media/ff.json" \
    "ffmpeg -v error -i $file -f null -" >/dev/null
  median=$(python3 -c "import json; print(json.load(open('$media/ff.json'))['results'][0]['median'])")
  frames=$(ffprobe -v error -select_streams v -show_entries stream=nb_frames -of csv=p=0 "$file")
  echo "$(basename "$file"): median $median s, $frames frames"
done

echo "== peer: bench/peers/dots_opencv.py (Python + OpenCV, full frame), median of $repetitions =="
for file in "${files[@]}"; do
  fps=()
  for _ in $(seq "$repetitions"); do
    fps+=("$(/usr/bin/python3 bench/peers/dots_opencv.py "$file" | cut -d' ' -f3)")
  done
  median=$(printf '%s\n' "${fps[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  echo "$(basename "$file"): median $median fps"
done
