#!/usr/bin/env python3
"""Two builds of softbench timed side by side on the benchmarks' workloads.

A refactoring must leave docs/benchmarks.md's figures no worse, and on a
shared 2-core host only figures measured in the same run can say so. Each
round runs every workload once with each build, the order alternating from
round to round, and the ratio new/old is taken within the round; the table
gives each workload's medians and the median and range of its ratios.

Usage (docs/benchmarks.md, "Two builds compared"):
  git worktree add /tmp/old COMMIT && (cd /tmp/old && cmake --preset release
      && cmake --build build/release --target softbench video_benchmark
         fit_benchmark model_benchmark)
  bench/compare_builds.py /tmp/old/build/release [--new build/release]
      [--rounds 5]
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def google_benchmark(binary, benchmark_filter, *files):
    """A Google Benchmark workload: the median real time [s] of one filter."""

    def run(build, scratch):
        output = subprocess.run(
            [os.path.join(build, "bench", binary),
             "--benchmark_filter=" + benchmark_filter,
             "--benchmark_repetitions=3",
             "--benchmark_report_aggregates_only=true",
             "--benchmark_format=json"] +
            (["--"] + [os.path.join(ROOT, f) for f in files] if files else []),
            check=True, capture_output=True, text=True).stdout
        medians = [b for b in json.loads(output)["benchmarks"]
                   if b.get("aggregate_name") == "median"]
        if len(medians) != 1:
            sys.exit(f"{binary} {benchmark_filter}: {len(medians)} benchmarks"
                     " matched; the filter must match exactly one")
        scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
        return medians[0]["real_time"] * scale[medians[0]["time_unit"]]

    run.binary = os.path.join("bench", binary)
    return run


def command(*arguments):
    """A softbench command: its wall time [s]. {scratch} is a fresh folder."""

    def run(build, scratch):
        argv = [os.path.join(build, "softbench"), "--quiet"] + [
            a.format(scratch=scratch, root=ROOT, logs=LOGS) for a in arguments]
        start = time.perf_counter()
        result = subprocess.run(argv, capture_output=True, text=True)
        elapsed = time.perf_counter() - start
        if result.returncode not in (0, 3):  # 3: tests flagged, still timed
            sys.exit(f"{' '.join(argv)} failed ({result.returncode}): "
                     f"{result.stderr.strip()}")
        return elapsed

    run.binary = "softbench"
    return run


# The thesis's protocol at 5700 Hz (docs/benchmarks.md, fit), written once.
LOGS = os.path.join(ROOT, "build/bench-fit/logs_5700")
DELTA = "samples/delta/delta.mp4"
PHONE = "samples/phone/phone.mp4"
WORKLOADS = [
    ("model: one delta solve", google_benchmark(
        "model_benchmark", "^BM_DeltaSolve")),
    ("model: floating map 3125 points, 1 thread", google_benchmark(
        "model_benchmark", "^BM_Map/Floating3125/1")),
    ("model: floating map 3125 points, all threads", google_benchmark(
        "model_benchmark", "^BM_Map/Floating3125/0")),
    ("render: one 1080p frame, heads moving", google_benchmark(
        "video_benchmark", "^BM_RenderFrame/1080p_moving")),
    ("decode: delta sample (1080p H.264, 3420 frames)", google_benchmark(
        "video_benchmark", "^BM_Decode/delta.mp4/decode_only", DELTA)),
    ("decode: phone sample (10-bit HEVC HLG portrait)", google_benchmark(
        "video_benchmark", "^BM_Decode/phone.mp4/with_luma", PHONE)),
    ("tracking: delta sample", google_benchmark(
        "video_benchmark", "^BM_Measure/delta.mp4/tracking", DELTA)),
    ("validate: delta sample, every frame", command(
        "validate", DELTA, "--plan", "{root}/samples/delta/rendered.plan.yaml",
        "--out", "{scratch}/delta")),
    ("validate --windows-only: delta sample", command(
        "validate", DELTA, "--plan", "{root}/samples/delta/rendered.plan.yaml",
        "--windows-only", "--out", "{scratch}/windows")),
    ("validate: phone sample (registered)", command(
        "validate", PHONE, "--plan", "{root}/samples/phone/rendered.plan.yaml",
        "--out", "{scratch}/phone")),
    ("fit: 24.0 M rows", command(
        "fit", "{logs}/manifest.yaml", "--out", "{scratch}/constants.yaml")),
]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("old", help="the old build folder (build/release)")
    parser.add_argument("--new", default=os.path.join(ROOT, "build/release"))
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--only", default="",
                        help="run the workloads whose name contains this")
    args = parser.parse_args()
    if args.rounds < 1:
        sys.exit("--rounds must be at least 1")
    builds = {"old": os.path.abspath(args.old), "new": os.path.abspath(args.new)}
    workloads = [w for w in WORKLOADS if args.only in w[0]]
    if not workloads:
        sys.exit(f"--only {args.only!r}: no workload's name contains it")
    for which, build in builds.items():
        for binary in sorted({run.binary for _, run in workloads}):
            if not os.access(os.path.join(build, binary), os.X_OK):
                sys.exit(f"{build}: no {binary} in this {which} build; build "
                         "it there (cmake --build BUILD --target softbench "
                         "video_benchmark fit_benchmark model_benchmark)")
    if any(name.startswith("fit") for name, _ in workloads) and \
            not os.path.exists(os.path.join(LOGS, "manifest.yaml")):
        print(f"writing the 24 M-row force logs to {LOGS} ...", file=sys.stderr)
        os.makedirs(os.path.dirname(LOGS), exist_ok=True)
        subprocess.run([os.path.join(builds["new"], "softbench"), "--quiet",
                        "synth-forces", "--rate", "5700", "--out", LOGS],
                       check=True, stdout=subprocess.DEVNULL)
    times = {name: {"old": [], "new": []} for name, _ in workloads}
    with tempfile.TemporaryDirectory() as scratch:
        for round_index in range(args.rounds):
            order = ["old", "new"] if round_index % 2 == 0 else ["new", "old"]
            for name, run in workloads:
                for which in order:
                    folder = os.path.join(scratch, which)
                    os.makedirs(folder, exist_ok=True)
                    times[name][which].append(run(builds[which], folder))
                ratio = times[name]["new"][-1] / times[name]["old"][-1]
                print(f"round {round_index + 1}: {name}: new/old {ratio:.3f}",
                      file=sys.stderr, flush=True)
    print(f"| workload | old (median) | new (median) | new / old: median of "
          f"{args.rounds} rounds (range) |")
    print("|---|---|---|---|")
    for name, _ in workloads:
        old, new = times[name]["old"], times[name]["new"]
        ratios = [n / o for n, o in zip(new, old)]
        print(f"| {name} | {seconds_text(statistics.median(old))} | "
              f"{seconds_text(statistics.median(new))} | "
              f"{statistics.median(ratios):.3f} ({min(ratios):.3f}–"
              f"{max(ratios):.3f}) |")


def seconds_text(value):
    """A time in the unit that suits it."""
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6)):
        if value >= scale:
            return f"{value / scale:.3g} {unit}"
    return f"{value / 1e-9:.3g} ns"


if __name__ == "__main__":
    main()
