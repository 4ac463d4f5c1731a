#!/usr/bin/env python3
"""Writes scenes/random-2000.json: 2,000 random dynamic shapes of every kind falling into a
box of twenty bins with static segments in the way, sleeping on (the determinism scene; see
docs/determinism.md, "Builds").

    scripts/random_scene.py > scenes/random-2000.json

The scene is checked in, so every build reads the same text; this script (fixed seed,
Python's Mersenne Twister, whose random() sequence Python guarantees for a given seed)
says how it was made and regenerates it byte for byte. Every number has at most three
decimals. Bodies: circles, boxes (some rounded), convex polygons of 3 to 8 points (some
rounded), capsules, and compound bodies (a box with a segment across it: a segment has no
area, so it rides on a body that has some).
"""
import math
import random
import sys

COUNT = 2000
SEED = 19


def num(x):
    text = f"{x:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def vec(x, y):
    return f"[{num(x)}, {num(y)}]"


def main():
    rng = random.Random(SEED)
    out = []
    out.append("{")
    out.append('  "world": {"sleep": true, "broadphase": "tree"},')
    out.append('  "bodies": [')
    statics = [
        '{"type": "box", "half": [80, 0.5]}',
        '{"type": "box", "half": [0.5, 20], "center": [-80.5, 20]}',
        '{"type": "box", "half": [0.5, 20], "center": [80.5, 20]}',
    ]
    # Nineteen dividers make twenty bins, so that the piles are separate islands that can
    # fall asleep within the run.
    for k in range(1, 20):
        statics.append(f'{{"type": "box", "half": [0.2, 4], "center": {vec(-80 + 8 * k, 4.5)}}}')
    for i in range(24):  # ramps above the bins: static segments, alternately tilted
        x = -74 + i * (148 / 23)
        y = 11 + (i % 3) * 1.5
        tilt = 0.35 if i % 2 == 0 else -0.35
        dx, dy = 2.2 * math.cos(tilt), 2.2 * math.sin(tilt)
        statics.append(f'{{"type": "segment", "p1": {vec(x - dx, y - dy)}, "p2": {vec(x + dx, y + dy)}}}')
    out.append('    {"name": "ground", "type": "static", "pos": [0, -0.5],')
    out.append('     "shapes": [' + ",\n                ".join(statics) + "]},")
    lines = []
    kinds = ["circle", "box", "rounded-box", "polygon", "rounded-polygon", "capsule", "compound"]
    shapes = 0
    i = 0
    while shapes < COUNT:
        kind = kinds[rng.randrange(len(kinds))]
        if kind == "compound" and shapes + 2 > COUNT:
            kind = "circle"
        s = rng.uniform(0.18, 0.42)
        # A jittered grid (112 columns, rows 1.2 m apart) above the ramps.
        col, row = i % 112, i // 112
        x = -77.7 + col * 1.4 + rng.uniform(-0.1, 0.1)
        y = 16 + row * 1.2 + rng.uniform(-0.1, 0.1)
        angle = rng.uniform(-math.pi, math.pi)
        vel = vec(rng.uniform(-2, 2), rng.uniform(-2, 0))
        angvel = num(rng.uniform(-3, 3))
        if kind == "circle":
            shape = [f'{{"type": "circle", "radius": {num(s)}}}']
        elif kind in ("box", "rounded-box"):
            radius = f', "radius": {num(0.2 * s)}' if kind == "rounded-box" else ""
            shape = [f'{{"type": "box", "half": {vec(s, s * rng.uniform(0.4, 1.0))}{radius}}}']
        elif kind in ("polygon", "rounded-polygon"):
            n = rng.randrange(3, 9)
            pts = []
            for k in range(n):
                a = 2 * math.pi * (k + 0.6 * rng.random()) / n
                pts.append(vec(s * math.cos(a), s * math.sin(a)))
            radius = f', "radius": {num(0.15 * s)}' if kind == "rounded-polygon" else ""
            shape = [f'{{"type": "polygon", "points": [{", ".join(pts)}]{radius}}}']
        elif kind == "capsule":
            shape = [f'{{"type": "capsule", "p1": {vec(-s, 0)}, "p2": {vec(s, 0)}, "radius": {num(0.45 * s)}}}']
        else:
            shape = [f'{{"type": "box", "half": {vec(0.6 * s, 0.6 * s)}}}',
                     f'{{"type": "segment", "p1": {vec(-1.2 * s, 0)}, "p2": {vec(1.2 * s, 0)}}}']
        shapes += len(shape)
        lines.append(f'    {{"name": "r{i}", "pos": {vec(x, y)}, "angle": {num(angle)}, "vel": {vel}, '
                     f'"angvel": {angvel},\n     "shapes": [{", ".join(shape)}]}}')
        i += 1
    out.append(",\n".join(lines))
    out.append("  ]")
    out.append("}")
    sys.stdout.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
