#!/usr/bin/env python3
"""Scores a `validate` report's uncertainties against a render's truth.

For each scored test point and head: the error of the measured displacement
(REPORT/results.csv) against the truth's median over the same windows
(REPORT/summary.json), and whether it lies within the report's u_mm and
within U = 2 u_mm. Issue 26's targets: at least 95 % within U, at least 60 %
within u, median u at most 2x the RMS error.
  bench/score_coverage.py TRUTH.csv REPORT_DIR LABEL [--tests]
Prints one table row (markdown); --tests prints each test point first.
"""
import csv
import json
import math
import statistics
import sys


def main():
    args = [a for a in sys.argv[1:] if a != "--tests"]
    if len(args) != 3:
        sys.exit(__doc__)
    truth_path, report, label = args
    truth = list(csv.DictReader(open(truth_path)))
    summary = json.load(open(f"{report}/summary.json"))
    rows = list(csv.DictReader(open(f"{report}/results.csv")))
    heads = list(dict.fromkeys(r["head"] for r in rows))

    def median(window, column):
        return statistics.median(
            float(t[column]) for t in truth
            if window["start_s"] <= float(t["time_s"]) < window["end_s"])

    errors, uncertainties = [], []
    for test in summary["tests"]:
        initial = test["windows"]["initial"]
        actuated = test["windows"]["actuated"]
        for h, head in enumerate(heads, start=1):
            row = next(r for r in rows
                       if r["test_id"] == test["id"] and r["head"] == head)
            if not row["u_mm"]:
                continue  # not scored
            ey = float(row["measured_dy_mm"]) - (
                median(actuated, f"y{h}_mm") - median(initial, f"y{h}_mm"))
            ez = float(row["measured_dz_mm"]) - (
                median(actuated, f"z{h}_mm") - median(initial, f"z{h}_mm"))
            error, u = math.hypot(ey, ez), float(row["u_mm"])
            errors.append(error)
            uncertainties.append(u)
            if "--tests" in sys.argv:
                print(f"  {test['id']} {head}: error {1000 * error:6.2f} um, "
                      f"u {1000 * u:6.2f} um ({row['u_largest_term']})")
    n = len(errors)
    if n == 0:
        sys.exit(f"{report}: no scored test point")
    rms = math.sqrt(sum(e * e for e in errors) / n)
    within_u = sum(e <= u for e, u in zip(errors, uncertainties)) / n
    within_2u = sum(e <= 2 * u for e, u in zip(errors, uncertainties)) / n
    median_u = statistics.median(uncertainties)
    ok = within_2u >= 0.95 and within_u >= 0.60 and median_u <= 2 * rms
    print(f"| {label} | {n} | {1000 * rms:.2f} | {1000 * max(errors):.2f} | "
          f"{1000 * median_u:.2f} | {median_u / rms:.2f} | "
          f"{100 * within_u:.0f} % | {100 * within_2u:.0f} % | "
          f"{'yes' if ok else 'no'} |")


if __name__ == "__main__":
    main()
