#!/usr/bin/env python3
"""Scores a `validate` report against a render's truth.

Each test's measured displacement (REPORT/results.csv) against the truth's
median over the same windows (REPORT/summary.json gives the windows), for
the first head; and each registered frame's position (REPORT/trajectory.csv)
against the truth's, less the median error over the video.
  scripts/score_against_truth.py TRUTH.csv REPORT_DIR [LABEL]
Prints each test's error and, last, one line with the worst and the
per-frame RMS.
"""
import math
import csv
import json
import statistics
import sys


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    truth_path, report = sys.argv[1], sys.argv[2]
    label = sys.argv[3] if len(sys.argv) == 4 else report
    truth = list(csv.DictReader(open(truth_path)))
    summary = json.load(open(f"{report}/summary.json"))
    results = {r["test_id"]: r
               for r in csv.DictReader(open(f"{report}/results.csv"))}

    def median(window, column):
        return statistics.median(
            float(t[column]) for t in truth
            if window["start_s"] <= float(t["time_s"]) < window["end_s"])

    worst = 0.0
    for test in summary["tests"]:
        initial = test["windows"]["initial"]
        actuated = test["windows"]["actuated"]
        r = results[test["id"]]
        dy = float(r["measured_dy_mm"]) - (median(actuated, "y1_mm") -
                                           median(initial, "y1_mm"))
        dz = float(r["measured_dz_mm"]) - (median(actuated, "z1_mm") -
                                           median(initial, "z1_mm"))
        error = (dy * dy + dz * dz) ** 0.5
        worst = max(worst, error)
        print(f"  {test['id']}: {r['status']}, error {error:.4f} mm")
    frames = {int(t["frame"]): t for t in truth}
    errors = []
    for row in csv.DictReader(open(f"{report}/trajectory.csv")):
        if row["registered"] != "1" or not row["y_mm"] or not row["z_mm"]:
            continue
        t = frames[int(row["frame"])]
        errors.append((float(row["y_mm"]) - float(t["y1_mm"]),
                       float(row["z_mm"]) - float(t["z1_mm"])))
    centre = [statistics.median(e[k] for e in errors) for k in (0, 1)]
    rms = math.sqrt(
        sum((e[0] - centre[0]) ** 2 + (e[1] - centre[1]) ** 2
            for e in errors) / max(len(errors), 1))
    print(f"{label}: worst {worst:.4f} mm; per-frame RMS {rms:.4f} mm; "
          f"hysteresis flagged: "
          f"{summary['hysteresis']['flagged']}; camera moved in: "
          f"{summary['registration']['camera_moved_windows']}")


if __name__ == "__main__":
    main()
