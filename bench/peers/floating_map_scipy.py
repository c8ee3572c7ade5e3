#!/usr/bin/python3
"""Peer for BM_Map/Floating3125: the floating-mechanism workspace map (0-6 psi
in 1.5 psi steps, 3125 configurations) solved the textbook way, with SciPy's
fsolve per configuration, warm-started from the previous configuration, with
the same small-angle model and geometry as softbench (shared/spec/model.md).

Uses Debian's python3-scipy; run with /usr/bin/python3. Prints the median wall
time over --repeats runs and the extents, so the answer can be compared.
"""
import argparse
import itertools
import math
import statistics
import time

import numpy as np
from scipy.optimize import fsolve

MPA_PER_PSI = 0.006894757
A_Z, W_Y, K_S, K_THETA = 157.0, 105.2, 2.71, 19.31
Y, Z, A0 = 26.98, 15.58, 39.70
HEADS = [np.array([0.0, 0.0]), np.array([0.0, A0])]
# (fixed anchor or head index, head index); R from the rest axis as softbench.
LINKS = [((-Y, -Z), 0), ((Y, -Z), 0), ((Y, Z + A0), 1), ((-Y, Z + A0), 1),
         (0, 1)]


def rest_anchor(anchor):
    return HEADS[anchor] if isinstance(anchor, int) else np.array(anchor)


GEOMETRY = []
for anchor, head in LINKS:
    axis = HEADS[head] - rest_anchor(anchor)
    phi = math.atan2(-axis[0], axis[1])
    c, s = math.cos(phi), math.sin(phi)
    GEOMETRY.append((np.array([[c, -s], [s, c]]), np.linalg.norm(axis)))


def residual(x, pressures):
    heads = [HEADS[h] + x[2 * h:2 * h + 2] for h in range(2)]
    r = np.zeros(4)
    for (anchor, head), (rot, rest), p in zip(LINKS, GEOMETRY, pressures):
        a = heads[anchor] if isinstance(anchor, int) else np.array(anchor)
        v = rot.T @ (heads[head] - a)
        dl = math.hypot(v[0], v[1]) - rest
        theta = math.atan2(-v[0], v[1])
        fz = p * A_Z - K_S * dl + K_THETA * theta * theta
        fy = -p * W_Y * theta + K_S * dl * theta + K_THETA * theta
        f = rot @ np.array([fy, fz])
        r[2 * head:2 * head + 2] += f
        if isinstance(anchor, int):
            r[2 * anchor:2 * anchor + 2] -= f
    return r


def solve_map():
    levels = [i * 1.5 * MPA_PER_PSI for i in range(5)]
    x = np.zeros(4)
    out = []
    for combo in itertools.product(levels, repeat=5):
        x, _, ok, _ = fsolve(residual, x, args=(combo,), xtol=1e-12,
                             full_output=True)
        if ok != 1:
            x = fsolve(residual, np.zeros(4), args=(combo,), xtol=1e-12)
        out.append(x.copy())
    return np.array(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    times = []
    for _ in range(args.repeats):
        start = time.perf_counter()
        result = solve_map()
        times.append(time.perf_counter() - start)
    print(f"points {len(result)}")
    print(f"median_s {statistics.median(times):.4f}")
    print("left z {:.4f} .. {:.4f}, y {:.4f} .. {:.4f}".format(
        result[:, 1].min(), result[:, 1].max(), result[:, 0].min(),
        result[:, 0].max()))
    print("right z {:.4f} .. {:.4f}, y {:.4f} .. {:.4f}".format(
        result[:, 3].min(), result[:, 3].max(), result[:, 2].min(),
        result[:, 2].max()))


if __name__ == "__main__":
    main()
