#!/usr/bin/env python3
"""The intrinsics term against what a calibration one standard error off does.

  bench/score_intrinsics.py write DIR   writes DIR/exact.yaml (the render's
      lens) and DIR/off_std.yaml (every parameter moved by a fixed fraction
      of its standard error, about one in all, with those standard errors)
  bench/score_intrinsics.py score DIR   compares DIR/report_off_std with
      DIR/report_exact: each displacement's shift between the two, over the
      off run's intrinsics term (its u, both axes in quadrature)
"""
import csv
import json
import math
import statistics
import sys

# The render's lens (bench/run_intrinsics_bench.sh) at 1280x720.
FOCAL_PX = 26 * math.hypot(1280, 720) / math.hypot(36, 24)
TRUTH = [FOCAL_PX, FOCAL_PX, 639.5, 359.5, -0.12, 0.03, 0.0, 0.0, 0.0]
# A calibration's standard errors (fx fy cx cy [px], k1 k2 p1 p2 k3), and how
# many of them each parameter of the "calibrated" file is off.
STD = [1.5, 1.5, 1.2, 1.2, 0.004, 0.015, 2e-4, 2e-4, 0.0]
OFF = [0.8, -0.6, 1.1, -0.9, 1.0, -0.7, 0.5, -0.4, 0.0]


def matrix(rows, cols, values):
    data = ", ".join(repr(float(v)) for v in values)
    return f"!!opencv-matrix\n  rows: {rows}\n  cols: {cols}\n  dt: d\n  data: [{data}]\n"


def calibration(v, std=None):
    text = ("%YAML:1.0\n---\nimage_width: 1280\nimage_height: 720\n"
            "camera_matrix: " +
            matrix(3, 3, [v[0], 0, v[2], 0, v[1], v[3], 0, 0, 1]) +
            "distortion_coefficients: " + matrix(1, 5, v[4:]))
    if std:
        text += ("intrinsics_std_px_fx_fy_cx_cy: " + matrix(1, 4, std[:4]) +
                 "distortion_coefficients_std: " + matrix(1, 5, std[4:]))
    return text


def results(directory):
    with open(f"{directory}/results.csv") as f:
        return {(r["test_id"], r["head"]): r for r in csv.DictReader(f)
                if r["measured_dy_mm"]}


def score(directory):
    exact = results(f"{directory}/report_exact")
    off = results(f"{directory}/report_off_std")
    with open(f"{directory}/report_off_std/summary.json") as f:
        summary = json.load(f)
    term = {}
    for test in summary["tests"]:
        for head in test.get("uncertainty", []):
            for t in head["displacement"]["terms"]:
                if t["term"] == "intrinsics":
                    term[(test["id"], head["head"])] = math.hypot(
                        t["u_dy_mm"], t["u_dz_mm"])
    ratios, shifts = [], []
    for key, row in off.items():
        shift = math.hypot(
            float(row["measured_dy_mm"]) - float(exact[key]["measured_dy_mm"]),
            float(row["measured_dz_mm"]) - float(exact[key]["measured_dz_mm"]))
        shifts.append(shift)
        ratios.append(shift / term[key])
    print(f"shift off - exact: median {1e3 * statistics.median(shifts):.2f} um,"
          f" largest {1e3 * max(shifts):.2f} um; median term "
          f"{1e3 * statistics.median(term.values()):.2f} um; shift / term: "
          f"median {statistics.median(ratios):.2f}, range "
          f"{min(ratios):.2f}-{max(ratios):.2f} over {len(ratios)} test points")


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in ("write", "score"):
        sys.exit(__doc__)
    directory = sys.argv[2]
    if sys.argv[1] == "score":
        score(directory)
        return
    off = [t + s * k for t, s, k in zip(TRUTH, STD, OFF)]
    for name, text in (("exact", calibration(TRUTH)),
                       ("off_std", calibration(off, STD))):
        with open(f"{directory}/{name}.yaml", "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
