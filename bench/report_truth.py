"""A `validate` report beside its render's truth, for the scoring scripts.

bench/score_coverage.py and bench/score_lift.py read the same three files:
the truth CSV, REPORT/summary.json (the windows) and REPORT/results.csv.
"""
import csv
import json
import statistics
import sys


class ReportTruth:
    """Command-line arguments TRUTH.csv REPORT_DIR LABEL [--FLAG...] read."""

    def __init__(self, usage, flags=("--tests",)):
        args = [a for a in sys.argv[1:] if not a.startswith("--")]
        self.flags = [a for a in sys.argv[1:] if a.startswith("--")]
        unknown = [f for f in self.flags if f.split("=")[0] not in flags]
        if len(args) != 3 or unknown:
            sys.exit(usage)
        truth_path, self.report, self.label = args
        self.verbose = "--tests" in self.flags
        self.truth = list(csv.DictReader(open(truth_path)))
        self.summary = json.load(open(f"{self.report}/summary.json"))
        self.rows = list(csv.DictReader(open(f"{self.report}/results.csv")))
        self.heads = list(dict.fromkeys(r["head"] for r in self.rows))

    def median(self, window, column):
        """The truth's median of `column` over a summary.json window."""
        return statistics.median(
            float(t[column]) for t in self.truth
            if window["start_s"] <= float(t["time_s"]) < window["end_s"])

    def change(self, test, column):
        """The truth's change of `column`, actuated less initial window."""
        return (self.median(test["windows"]["actuated"], column) -
                self.median(test["windows"]["initial"], column))

    def row(self, test, head):
        """results.csv's row of a summary.json test and a head's name."""
        return next(r for r in self.rows
                    if r["test_id"] == test["id"] and r["head"] == head)
