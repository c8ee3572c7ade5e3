#!/usr/bin/env python3
"""What a first touch of fresh memory costs per 4 KB page on this machine.

The tag fit's cost (docs/benchmarks.md, "fourth pass") is partly the pages
its images and Jacobian touch for the first time: each costs a fault and
the kernel's zeroing. This maps 64 MB of anonymous memory and writes one
byte per page, three ways: plain (a fault per page), with MAP_POPULATE (the
kernel fills the mapping up front) and with MADV_HUGEPAGE (2 MB pages where
the kernel grants them). The loop's own cost (a Python store, ~0.05 us) is
small against a fault's.

Usage: bench/peers/page_fault_cost.py [ROUNDS]   (default 5; prints medians)
"""
import mmap
import statistics
import sys
import time

MEGABYTES = 64
PAGE = mmap.PAGESIZE


def touch_us_per_page(flags=0, hugepage=False):
    size = MEGABYTES << 20
    start = time.perf_counter()  # MAP_POPULATE faults inside mmap itself
    memory = mmap.mmap(-1, size, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS
                       | flags)
    if hugepage:
        memory.madvise(mmap.MADV_HUGEPAGE)
    for offset in range(0, size, PAGE):
        memory[offset] = 1
    elapsed = time.perf_counter() - start
    memory.close()
    return elapsed * 1e6 / (size // PAGE)


def main():
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    ways = {
        "touch": {},
        "MAP_POPULATE": {"flags": mmap.MAP_POPULATE},
        "MADV_HUGEPAGE": {"hugepage": True},
    }
    figures = {name: [] for name in ways}
    for _ in range(rounds):  # interleaved, so load drifts hit every way
        for name, kwargs in ways.items():
            figures[name].append(touch_us_per_page(**kwargs))
    print(f"first write per {PAGE}-byte page of {MEGABYTES} MB, "
          f"{rounds} rounds: median (min-max) us")
    for name, values in figures.items():
        print(f"{name:14s} {statistics.median(values):6.2f} "
              f"({min(values):.2f}-{max(values):.2f})")


if __name__ == "__main__":
    main()
