"""distance_many on pentagon pairs at three kinds of angle, for comparing two builds.

Usage: python3 python/bench/distance_angles.py BUILD_DIR/python [--n N] [--repeats R]

Prints the best time per pair (ns) of `quack.distance_many` over `repeats` calls, for both
poses at angle 0, both at angle 0.3, and random angles. The pairs are bench_batch.py's
pentagons with centres uniform in [-2, 2] m (about a third overlap); the module is imported
from the directory given, so two builds (before and after a change) can be run by turns.
"""
import argparse
import math
import os
import sys
import time

import numpy as np


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("module_dir", help="the directory holding the built quack module")
    parser.add_argument("--n", type=int, default=100_000)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    sys.path.insert(0, args.module_dir)
    import quack  # noqa: E402  (from the directory given)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from bench_batch import PENTAGON  # noqa: E402

    rng = np.random.default_rng(20)
    n = args.n
    xy_a = np.column_stack([rng.uniform(-2, 2, n), rng.uniform(-2, 2, n)])
    xy_b = np.column_stack([rng.uniform(-2, 2, n), rng.uniform(-2, 2, n)])
    random_a = rng.uniform(-math.pi, math.pi, n)
    random_b = rng.uniform(-math.pi, math.pi, n)
    pentagon = quack.shape(PENTAGON)
    figures = []
    for name, angle_a, angle_b in [("angle 0", np.zeros(n), np.zeros(n)),
                                   ("angle 0.3", np.full(n, 0.3), np.full(n, 0.3)),
                                   ("random angles", random_a, random_b)]:
        poses_a = np.column_stack([xy_a, angle_a])
        poses_b = np.column_stack([xy_b, angle_b])
        best = math.inf
        for _ in range(args.repeats):
            start = time.perf_counter()
            quack.distance_many(pentagon, poses_a, pentagon, poses_b)
            best = min(best, time.perf_counter() - start)
        figures.append(f"{name}: {best / n * 1e9:.0f} ns")
    print(" | ".join(figures))


if __name__ == "__main__":
    main()
