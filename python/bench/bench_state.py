#!/usr/bin/env python3
"""Reading and writing every body's state each frame: World.body_state() (one array per
step, shared by every read until the next step) against the per-quantity copies
(get_positions, get_angles, get_velocities, get_angular_velocities: a new array each call),
and set_body_state against the four setters.

    python3 python/bench/bench_state.py [--bodies N ...] [--reads K] [--repeats R] [--json FILE]

`scripts/python.sh bench-state` runs it on the release build. The module must be importable
(PYTHONPATH). The world is N circles in a grid without gravity or contacts, so a step costs
little; only the reads and writes are timed, the step between frames is not. Figures are
microseconds per frame (best of R runs of 200 frames), and per body.
"""

import argparse
import json
import math
import time

import numpy as np

import quack

FRAMES = 200


def make_world(n):
    w = quack.World(gravity=(0, 0))
    side = int(math.ceil(math.sqrt(n)))
    circle = quack.circle(radius=0.4)
    for i in range(n):
        b = w.create_body(pos=(float(i % side), float(i // side)), vel=(0.1, 0.0))
        w.create_shape(b, circle)
    return w


def per_frame(w, read, repeats):
    """Best over `repeats` of the mean time of `read(w)` per frame, the step excluded."""
    best = math.inf
    for _ in range(repeats):
        total = 0.0
        for _ in range(FRAMES):
            w.step()
            t0 = time.perf_counter()
            read(w)
            total += time.perf_counter() - t0
        best = min(best, total / FRAMES)
    return best


def copies(k):
    def read(w):
        for _ in range(k):
            p = w.get_positions()
            a = w.get_angles()
            v = w.get_velocities()
            av = w.get_angular_velocities()
            p[0, 0] + a[0] + v[0, 0] + av[0]  # use them
    return read


def shared(k):
    def read(w):
        for _ in range(k):
            s = w.body_state()
            p, a, v, av = s[:, 0:2], s[:, 2], s[:, 3:5], s[:, 5]
            p[0, 0] + a[0] + v[0, 0] + av[0]
    return read


def write_four(w):
    n = w.body_count
    w.set_positions(POS[:n])
    w.set_angles(ANG[:n])
    w.set_velocities(VEL[:n])
    w.set_angular_velocities(ANG[:n])


def write_state(w):
    w.set_body_state(STATE[:w.body_count])


def main():
    global POS, ANG, VEL, STATE
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", type=int, nargs="+", default=[100, 1000, 10000])
    parser.add_argument("--reads", type=int, default=3,
                        help="reads of the whole state per frame (a game's systems each read)")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--json", help="also write the figures here")
    args = parser.parse_args()
    rows = []
    print(f"{'bodies':>7} {'case':<34} {'us/frame':>10} {'ns/body':>8} {'vs copies':>9}")
    for n in args.bodies:
        side = int(math.ceil(math.sqrt(n)))
        POS = np.column_stack([np.arange(n) % side, np.arange(n) // side]).astype(float)
        ANG = np.zeros(n)
        VEL = np.tile([0.1, 0.0], (n, 1))
        STATE = np.column_stack([POS, ANG, VEL, ANG])
        w = make_world(n)
        cases = [
            ("read once: 4 get_* copies", copies(1)),
            ("read once: body_state()", shared(1)),
            (f"read {args.reads}x: 4 get_* copies", copies(args.reads)),
            (f"read {args.reads}x: body_state()", shared(args.reads)),
            ("write: 4 set_* calls", write_four),
            ("write: set_body_state()", write_state),
        ]
        base = None
        for i, (name, fn) in enumerate(cases):
            t = per_frame(w, fn, args.repeats)
            if i % 2 == 0:
                base = t
            ratio = base / t
            rows.append({"bodies": n, "case": name, "us_per_frame": t * 1e6,
                         "ns_per_body": t * 1e9 / n, "speedup_vs_copies": ratio})
            print(f"{n:>7} {name:<34} {t * 1e6:>10.1f} {t * 1e9 / n:>8.1f} {ratio:>8.2f}x")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
