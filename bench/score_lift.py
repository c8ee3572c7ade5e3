#!/usr/bin/env python3
"""Scores a `validate` report's lifts and displacements against a render's truth.

For each measured test point and head (issue 27): the measured lift
(REPORT/results.csv lift_mm, actuated less initial) against the truth's
median lift over the same windows (REPORT/summary.json), whether it lies
within U = 2 u_lift_mm, and the in-plane displacement's error against the
truth. Targets: every lift within 0.05 mm, every displacement within
0.005 mm.
  bench/score_lift.py TRUTH.csv REPORT_DIR LABEL [--tests]
Prints one table row (markdown); --tests prints each test point first.
"""
import math
import sys

from report_truth import ReportTruth


def main():
    r = ReportTruth(__doc__)
    lift_errors, within, errors, true_lifts = [], [], [], []
    for test in r.summary["tests"]:
        for h, head in enumerate(r.heads, start=1):
            row = r.row(test, head)
            if not row["lift_mm"] or not row["measured_dy_mm"]:
                continue  # not measured
            true_lift = r.change(test, f"lift{h}_mm")
            lift_error = float(row["lift_mm"]) - true_lift
            u_lift = float(row["u_lift_mm"])
            error = math.hypot(
                float(row["measured_dy_mm"]) - r.change(test, f"y{h}_mm"),
                float(row["measured_dz_mm"]) - r.change(test, f"z{h}_mm"))
            lift_errors.append(abs(lift_error))
            within.append(abs(lift_error) <= 2 * u_lift)
            errors.append(error)
            true_lifts.append(true_lift)
            if r.verbose:
                print(f"  {test['id']} {head}: lift {true_lift:.3f} mm, error "
                      f"{1000 * lift_error:7.2f} um (U {2000 * u_lift:.1f}); "
                      f"displacement error {1000 * error:.2f} um "
                      f"(shift {row['lift_shift_mm']} mm)")
    n = len(errors)
    if n == 0:
        sys.exit(f"{r.report}: no measured test point")
    ok = max(lift_errors) <= 0.05 and max(errors) <= 0.005
    print(f"| {r.label} | {n} | {max(true_lifts):.2f} | "
          f"{1000 * math.sqrt(sum(e * e for e in lift_errors) / n):.1f} | "
          f"{1000 * max(lift_errors):.1f} | {100 * sum(within) / n:.0f} % | "
          f"{1000 * math.sqrt(sum(e * e for e in errors) / n):.2f} | "
          f"{1000 * max(errors):.2f} | {'yes' if ok else 'no'} |")


if __name__ == "__main__":
    main()
