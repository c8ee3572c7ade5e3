#!/usr/bin/env python3
"""Peer of `softbench fit` (bench/fit_benchmark.cc): the same fits written the
way a NumPy/SciPy user would write them, on the same files.

pandas.read_csv reads every test's CSV (C parser, only the needed columns),
all rows are stacked into one design matrix per model (the thesis's
24-million-row matrix, Algorithm 1) and solved with scipy.linalg.lstsq; R^2,
RMSE and RMSE as % of the full-scale range per direction, as softbench prints.

Usage: fit_numpy.py MANIFEST.yaml [--repeats N]
"""
import argparse
import math
import os
import resource
import time

import numpy as np
import pandas as pd
import scipy.linalg
import yaml

MPA_PER_UNIT = {"psi": 0.006894757, "kpa": 0.001, "mpa": 1.0}
NATURAL_LENGTH_MM = 18.5


def design(model, p, dl, th):
    """Axial and shear design columns (A_z, W_y, k_s, k_theta) of one test."""
    n = p.size
    one = np.ones(n)
    zero = np.zeros(n)
    if model == "full-trig":
        c, s = math.cos(th), math.sin(th)
    else:
        c, s = 1.0, th
    g = 1.0 / (1.0 + dl / NATURAL_LENGTH_MM) if model == "variable-arm" else 1.0
    axial = np.column_stack([p, zero, -dl * c * one, g * th * s * one])
    shear = np.column_stack([zero, -p * th, dl * s * one, g * th * c * one])
    if model == "pressurized-spring":
        return axial[:, [0, 2]], shear[:, [0, 2]]
    return axial, shear


def signed(name):
    return (name[1:], -1.0) if name.startswith("-") else (name.lstrip("+"), 1.0)


def run(manifest_path):
    with open(manifest_path) as f:
        manifest = yaml.safe_load(f)
    base = os.path.dirname(manifest_path)
    unit = manifest["pressure_unit"]
    cols = manifest.get("columns", {})
    p_col = cols.get("pressure", "pressure_" + unit)
    axes = manifest.get("axes", {})
    a_col, a_sign = signed(axes.get("axial", "+fz_n"))
    s_col, s_sign = signed(axes.get("shear", "+fy_n"))
    tests = []
    for t in manifest["tests"]:
        frame = pd.read_csv(os.path.join(base, t["file"]),
                            usecols=[p_col, a_col, s_col])
        frame = frame[np.isfinite(frame).all(axis=1)]
        dl = t.get("measured_delta_length_mm", t["delta_length_mm"])
        th = math.radians(t.get("measured_theta_deg", t["theta_deg"]))
        tests.append((frame[p_col].to_numpy() * MPA_PER_UNIT[unit],
                      a_sign * frame[a_col].to_numpy(),
                      s_sign * frame[s_col].to_numpy(), dl, th))
    fa = np.concatenate([t[1] for t in tests])
    fs = np.concatenate([t[2] for t in tests])
    results = {}
    for model in ("small-angle", "full-trig", "variable-arm",
                  "pressurized-spring"):
        blocks = [design(model, p, dl, th) for p, _, _, dl, th in tests]
        a_axial = np.vstack([b[0] for b in blocks])
        a_shear = np.vstack([b[1] for b in blocks])
        matrix = np.vstack([a_axial, a_shear])
        constants = scipy.linalg.lstsq(matrix, np.concatenate([fa, fs]),
                                       lapack_driver="gelsy")[0]
        fit = []
        for a, f in ((a_axial, fa), (a_shear, fs)):
            r = f - a @ constants
            rmse = math.sqrt(np.mean(r * r))
            r2 = 1.0 - np.sum(r * r) / np.sum((f - f.mean()) ** 2)
            fsr = f.max() - f.min()
            fit.append((r2, rmse, 100.0 * rmse / fsr))
        results[model] = (constants, fit)
    return fa.size, results


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("manifest")
    parser.add_argument("--repeats", type=int, default=1)
    args = parser.parse_args()
    times = []
    for _ in range(args.repeats):
        start = time.perf_counter()
        rows, results = run(args.manifest)
        times.append(time.perf_counter() - start)
    for model, (constants, fit) in results.items():
        print(f"{model:<19} {np.array2string(constants, precision=4)} "
              f"axial R2 {fit[0][0]:.4f} RMSE {fit[0][1]:.3f} N; "
              f"shear R2 {fit[1][0]:.4f} RMSE {fit[1][1]:.3f} N")
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(f"peer numpy/scipy: {rows} rows, median {np.median(times):.2f} s over "
          f"{len(times)} runs, peak memory {peak_mb:.0f} MB")


if __name__ == "__main__":
    main()
