#!/usr/bin/env bash
# Peak memory (and time) of softbench validate on a 10-minute 4K video
# (issue 29: under 400 MB), against decoding the same file and nothing else
# (docs/benchmarks.md, "A 10-minute 4K video"):
#   decode only       ffmpeg -f null (default threads), the limit
#   full tracking     softbench validate (every frame measured, full report)
#   windows only      softbench validate --windows-only
# Rendering ten minutes of 4K takes hours on two cores, so the video is the
# formats benchmark's 16 s 4K H.264 clip (bench/run_formats_bench.sh, same
# render) joined to itself 38 times without re-encoding (FFmpeg's concat
# demuxer, -c copy): 608 s, 18 240 frames, 114 test points, every one with
# its truth. That is more test points than a 10-minute plan of 20 s holds
# (15), so more report crops and windows than a real run keeps: memory is
# measured on the heavier case. Each run is also scored against the truth.
# Usage: bench/run_memory_4k_bench.sh [rounds]   (default 1: a round takes
# about 15 minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/interleaved_rounds.sh
rounds=${1:-1}
./scripts/bootstrap.sh --bench
cmake --preset release >/dev/null && cmake --build --preset release >/dev/null

source bench/formats_clips.sh
render_formats_clip h264_4k --resolution 4k --codec h264
clips=$formats_clips
clip=$clips/h264_4k.mp4
media=build/bench-memory-4k
mkdir -p "$media"

copies=38
video=$media/h264_4k_10min.mp4
if [[ ! -f "$video" ]]; then
  list=$media/copies.txt
  : > "$list"
  for _ in $(seq "$copies"); do echo "file '$(realpath "$clip")'" >> "$list"; done
  ffmpeg -v error -f concat -safe 0 -i "$list" -map 0:v -c copy -y "$video"
fi
# The plan and the truth joined the same way: each copy's tests renamed
# (a -> a01, a02, ...) and every time moved on by the clip's duration.
duration=$(ffprobe -v error -show_entries format=duration -of csv=p=0 "$clip")
python3 - "$clips/h264_4k.plan.yaml" "$clips/h264_4k.truth.csv" "$copies" \
  "$duration" "$media/plan.yaml" "$media/truth.csv" <<'PY'
import csv, sys, yaml
plan_in, truth_in, copies, duration, plan_out, truth_out = sys.argv[1:]
copies, duration = int(copies), float(duration)
plan = yaml.safe_load(open(plan_in))
rows = list(csv.DictReader(open(truth_in)))
tests = []
for k in range(copies):
    for t in plan["tests"]:
        tests.append(dict(t, id=f"{t['id']}{k + 1:02d}",
                          actuate_s=t["actuate_s"] + k * duration,
                          release_s=t["release_s"] + k * duration))
plan["tests"] = tests
yaml.safe_dump(plan, open(plan_out, "w"), default_flow_style=None,
               sort_keys=False)
with open(truth_out, "w", newline="") as out:
    writer = csv.DictWriter(out, fieldnames=rows[0].keys())
    writer.writeheader()
    for k in range(copies):
        for r in rows:
            writer.writerow(dict(r, frame=int(r["frame"]) + k * len(rows),
                                 time_s=f"{float(r['time_s']) + k * duration:.6f}"))
PY
ffprobe -v error -select_streams v -show_entries stream=width,height,nb_frames,duration \
  -of csv=p=0 "$video" | awk -F, '{print "video: " $1 "x" $2 ", " $3 " s, " $4 " frames"}'

validate="./build/release/softbench --quiet validate $video --plan $media/plan.yaml"
commands=("ffmpeg -v error -i $video -map 0:v -f null -"
  "$validate --out $media/report-full"
  "$validate --windows-only --out $media/report-windows")
run_rounds "$rounds" "$media/times.txt" "${commands[@]}"
summarise_rounds "$media/times.txt" "decode only" "validate" \
  "validate --windows-only"
python3 scripts/score_against_truth.py "$media/truth.csv" "$media/report-full" \
  "every frame" | tail -1
python3 scripts/score_against_truth.py "$media/truth.csv" \
  "$media/report-windows" "windows only" | tail -1
