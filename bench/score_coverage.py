#!/usr/bin/env python3
"""Scores a `validate` report's uncertainties against a render's truth.

For each scored test point and head: the error of the measured displacement
(REPORT/results.csv) against the truth's median over the same windows
(REPORT/summary.json), and whether it lies within the report's u_mm and
within U = 2 u_mm. Issue 26's targets: at least 95 % within U, at least 60 %
within u, median u at most 2x the RMS error.
  bench/score_coverage.py TRUTH.csv REPORT_DIR LABEL [--tests]
      [--without=TERM[,TERM...]]
Prints one table row (markdown); --tests prints each test point first.
--without takes the named terms (summary.json's: dots, scale, codec, ...)
out of each u, to show what a term carries.
"""
import math
import statistics
import sys

from report_truth import ReportTruth


def budget_without(test, head, names):
    """A head's u (mm) from summary.json's terms, less the named ones."""
    budget = next(b for b in test["uncertainty"] if b["head"] == head)
    terms = budget["displacement"]["terms"]
    kept = [t for t in terms if t["term"] not in names]
    return math.hypot(math.sqrt(sum(t["u_dy_mm"] ** 2 for t in kept)),
                      math.sqrt(sum(t["u_dz_mm"] ** 2 for t in kept)))


def main():
    r = ReportTruth(__doc__, flags=("--tests", "--without"))
    without = next((f.split("=", 1)[1].split(",") for f in r.flags
                    if f.startswith("--without=")), [])
    errors, uncertainties = [], []
    for test in r.summary["tests"]:
        for h, head in enumerate(r.heads, start=1):
            row = r.row(test, head)
            if not row["u_mm"]:
                continue  # not scored
            ey = float(row["measured_dy_mm"]) - r.change(test, f"y{h}_mm")
            ez = float(row["measured_dz_mm"]) - r.change(test, f"z{h}_mm")
            error, u = math.hypot(ey, ez), float(row["u_mm"])
            if without:
                u = budget_without(test, head, without)
            errors.append(error)
            uncertainties.append(u)
            if r.verbose:
                print(f"  {test['id']} {head}: error {1000 * error:6.2f} um, "
                      f"u {1000 * u:6.2f} um ({row['u_largest_term']})")
    named = {t["term"] for test in r.summary["tests"]
             for b in test["uncertainty"] for t in b["displacement"]["terms"]}
    if set(without) - named:
        sys.exit(f"--without: no term {', '.join(set(without) - named)} "
                 f"in {r.report} (its terms: {', '.join(sorted(named))})")
    n = len(errors)
    if n == 0:
        sys.exit(f"{r.report}: no scored test point")
    rms = math.sqrt(sum(e * e for e in errors) / n)
    within_u = sum(e <= u for e, u in zip(errors, uncertainties)) / n
    within_2u = sum(e <= 2 * u for e, u in zip(errors, uncertainties)) / n
    median_u = statistics.median(uncertainties)
    ok = within_2u >= 0.95 and within_u >= 0.60 and median_u <= 2 * rms
    print(f"| {r.label} | {n} | {1000 * rms:.2f} | {1000 * max(errors):.2f} | "
          f"{1000 * median_u:.2f} | {median_u / rms:.2f} | "
          f"{100 * within_u:.0f} % | {100 * within_2u:.0f} % | "
          f"{'yes' if ok else 'no'} |")


if __name__ == "__main__":
    main()
