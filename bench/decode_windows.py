#!/usr/bin/env python3
"""Decodes only the windows a validate report measured, with ffmpeg.

The peer of `validate --windows-only` (bench/run_validate_bench.sh): the
report's windows (REPORT/summary.json), merged where they meet, each
decoded by `ffmpeg -ss START -to END -i VIDEO -f null -` (a seek to the key
frame before START, then every frame to END) with one decoder thread, two
windows at a time, as validate's two workers do.
  bench/decode_windows.py VIDEO REPORT_DIR
With --count (not for timing: ffprobe decodes the whole video), prints the
frames a windows-only run must decode: those in the windows, and before
each window those from its key frame on, by picture type (a decoder that
skips frames nothing refers to, as validate's does while seeking, needs
the I and P frames of those and the B frames that are references).
  bench/decode_windows.py --count VIDEO REPORT_DIR
"""
import concurrent.futures
import json
import subprocess
import sys


def merged_windows(summary):
    spans = sorted((w["start_s"], w["end_s"]) for test in summary["tests"]
                   for w in test["windows"].values())
    merged = []
    for start, end in spans:
        if merged and start <= merged[-1][1] + 1e-3:
            merged[-1][1] = max(merged[-1][1], end)
        else:
            merged.append([start, end])
    return merged


def decode(video, span):
    subprocess.run(["ffmpeg", "-v", "error", "-threads", "1",
                    "-ss", f"{span[0]:.6f}", "-to", f"{span[1]:.6f}",
                    "-i", video, "-map", "0:v", "-f", "null", "-"],
                   check=True)


def count(video, spans):
    frames = subprocess.run(
        ["ffprobe", "-v", "error", "-select_streams", "v", "-show_entries",
         "frame=pts_time,pict_type,key_frame", "-of", "csv=p=0", video],
        check=True, capture_output=True, text=True).stdout.split()
    frames = [(float(t), k == "1", p[0]) for k, t, p in
              (f.split(",")[:3] for f in frames)]
    frames.sort()
    inside = 0
    before = {"I": 0, "P": 0, "B": 0}
    for start, end in spans:
        inside += sum(start - 1e-6 <= t < end - 1e-6 for t, _, _ in frames)
        keys = [i for i, (t, k, _) in enumerate(frames)
                if k and t <= start + 1e-6]
        for t, _, picture in frames[keys[-1] if keys else 0:]:
            if t >= start - 1e-6:
                break
            before[picture] = before.get(picture, 0) + 1
    print(f"{len(frames)} frames; in the windows {inside}; before them from "
          f"their key frames: {before}")


def main():
    counting = len(sys.argv) == 4 and sys.argv[1] == "--count"
    if len(sys.argv) != 3 and not counting:
        sys.exit(__doc__)
    video, report = sys.argv[-2:]
    with open(f"{report}/summary.json") as f:
        spans = merged_windows(json.load(f))
    if counting:
        count(video, spans)
        return
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        list(pool.map(lambda s: decode(video, s), spans))
    print(f"{len(spans)} windows, {sum(e - s for s, e in spans):.1f} s",
          file=sys.stderr)


if __name__ == "__main__":
    main()
