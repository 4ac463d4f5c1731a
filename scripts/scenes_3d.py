#!/usr/bin/env python3
"""Writes the 3D sample scenes (docs/scenes.md, "3D scenes"):

    scripts/scenes_3d.py scenes/

  pyramid-3d.json   a square pyramid of 55 unit boxes (5 x 5 at the bottom) on a box ground
  hulls-3d.json     48 random convex hulls (some rounded) dropped into a walled bin
  ramp-3d.json      spheres (and a capsule) rolling down a curved triangle-mesh valley
  cards-3d.json     a house of 15 cards: leaned pairs, with flat cards on top, three storeys

The files are checked in, so every build reads the same text; this script (fixed seed,
Python's Mersenne Twister, whose random() sequence Python guarantees for a given seed) says
how they were made and writes them again byte for byte. Numbers have at most five decimals.
"""
import math
import os
import random
import sys


def num(x):
    text = f"{x:.5f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def vec(*xs):
    return "[" + ", ".join(num(x) for x in xs) + "]"


def quat_z(angle):
    """The rotation by `angle` radians about z, [x, y, z, w]."""
    return (0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2))


def body(name, shapes, type_="dynamic", pos=(0, 0, 0), quat=None, extra=""):
    text = f'{{"name": "{name}", "type": "{type_}", "pos": {vec(*pos)}'
    if quat is not None:
        text += f', "quat": {vec(*quat)}'
    text += extra
    return text + ', "shapes": [' + ", ".join(shapes) + "]}"


def scene(bodies, world='"dim": 3'):
    return '{"world": {' + world + '},\n "bodies": [\n  ' + ",\n  ".join(bodies) + "\n ]}\n"


def ground(half=(20, 0.5, 20), friction=0.6):
    box = f'{{"type": "box", "half": {vec(*half)}, "friction": {num(friction)}}}'
    return body("ground", [box], "static", (0, -half[1], 0))


def pyramid():
    bodies = [ground()]
    base, half = 5, 0.5
    for level in range(base):
        n = base - level
        for i in range(n):
            for k in range(n):
                x = (i - (n - 1) / 2) * 2 * half
                z = (k - (n - 1) / 2) * 2 * half
                y = half + level * 2 * half
                box = f'{{"type": "box", "half": {vec(half, half, half)}}}'
                bodies.append(body(f"box{level}_{i}_{k}", [box], pos=(x, y, z)))
    return scene(bodies)


def hulls():
    rng = random.Random(7)
    walls = [
        f'{{"type": "box", "half": [4, 0.5, 4], "center": [0, -0.5, 0]}}',
        f'{{"type": "box", "half": [0.25, 0.75, 4], "center": [-4.25, 0.25, 0]}}',
        f'{{"type": "box", "half": [0.25, 0.75, 4], "center": [4.25, 0.25, 0]}}',
        f'{{"type": "box", "half": [4.5, 0.75, 0.25], "center": [0, 0.25, -4.25]}}',
        f'{{"type": "box", "half": [4.5, 0.75, 0.25], "center": [0, 0.25, 4.25]}}',
    ]
    bodies = [body("bin", walls, "static")]
    count = 48
    for n in range(count):
        # Points on an ellipsoid of radii 0.3 to 0.6 m: their hull is convex and solid.
        radii = [0.3 + 0.3 * rng.random() for _ in range(3)]
        points = []
        for _ in range(8 + rng.randrange(9)):
            u, v = 2 * rng.random() - 1, 2 * math.pi * rng.random()
            s = math.sqrt(1 - u * u)
            points.append(vec(radii[0] * s * math.cos(v), radii[1] * u, radii[2] * s * math.sin(v)))
        rounded = f', "radius": {num(0.05)}' if n % 4 == 0 else ""
        hull = f'{{"type": "hull", "points": [{", ".join(points)}]{rounded}, "friction": 0.5}}'
        layer, slot = divmod(n, 16)
        x = (slot % 4 - 1.5) * 1.6 + 0.2 * (rng.random() - 0.5)
        z = (slot // 4 - 1.5) * 1.6 + 0.2 * (rng.random() - 0.5)
        axis = [rng.random() - 0.5 for _ in range(3)]
        length = math.sqrt(sum(a * a for a in axis))
        angle = math.pi * rng.random()
        q = [a / length * math.sin(angle / 2) for a in axis] + [math.cos(angle / 2)]
        bodies.append(body(f"hull{n}", [hull], pos=(x, 2.0 + 1.4 * layer, z), quat=q))
    return scene(bodies)


def ramp():
    # A valley: y = 4 (1 - x / 12)^2 for x in [0, 24] (down from 4 m, up to 4 m again on
    # the far side), 6 m wide (z in [-3, 3]) with a lip along each side; triangles
    # counter-clockwise seen from above (their fronts up).
    columns, width = 25, 3.0
    xs = [24 * i / (columns - 1) for i in range(columns)]
    profile = [(x, 4 * (1 - x / 12) ** 2) for x in xs]
    zs = [-width - 1.0, -width, width, width + 1.0]
    lift = [1.2, 0.0, 0.0, 1.2]  # the lips rise 1.2 m over 1 m at the sides
    vertices, triangles = [], []
    for x, y in profile:
        for z, dy in zip(zs, lift):
            vertices.append(vec(x, y + dy, z))
    rows = len(zs)
    for i in range(columns - 1):
        for k in range(rows - 1):
            a, b = i * rows + k, i * rows + k + 1
            c, d = (i + 1) * rows + k + 1, (i + 1) * rows + k
            # (b - a) x (c - a) = z x x = +y: a, b, c and a, c, d face up.
            triangles.append(f"[{a}, {b}, {c}]")
            triangles.append(f"[{a}, {c}, {d}]")
    mesh = (f'{{"type": "mesh", "vertices": [{", ".join(vertices)}], '
            f'"triangles": [{", ".join(triangles)}], "friction": 0.8}}')
    bodies = [body("ramp", [mesh], "static")]
    for n, z in enumerate([-2.0, -1.0, 0.0, 1.0, 2.0]):
        r = 0.25 + 0.1 * n
        rolling = 0.0 if n % 2 == 0 else 0.05
        sphere = (f'{{"type": "sphere", "radius": {num(r)}, "density": 500, "friction": 0.8, '
                  f'"rollingResistance": {num(rolling)}}}')
        bodies.append(body(f"ball{n}", [sphere], pos=(0.3 + 0.4 * n, 4.0 + r + 0.5, z)))
    capsule = ('{"type": "capsule", "p1": [0, 0, -0.6], "p2": [0, 0, 0.6], "radius": 0.2, '
               '"density": 500, "friction": 0.8}')
    bodies.append(body("log", [capsule], pos=(1.0, 4.2, 0.0)))
    return scene(bodies)


def cards():
    # A card is 1.0 m tall, 0.7 m wide and 4 cm thick (scaled up from a playing card so
    # that it is thicker than the contact slop, docs/world.md "Limits"); friction 0.9.
    h, w, t, lean = 1.0, 0.7, 0.04, math.radians(18)
    spacing = 0.72  # between the A-frames of one storey
    card = (f'{{"type": "box", "half": {vec(t / 2, h / 2, w / 2)}, "density": 200, '
            f'"friction": 0.9}}')
    flat = (f'{{"type": "box", "half": {vec(h / 2, t / 2, w / 2)}, "density": 200, '
            f'"friction": 0.9}}')
    bodies = [ground(friction=0.9)]
    gap = 0.001

    def a_frame(name, x0, y0):
        # Two cards leaned on each other above (x0, y0): each turned by `lean` about z so
        # that its top leans inwards; the bottom corner rests `gap` above y0, the top inner
        # corners meet at x0.
        s, c = math.sin(lean), math.cos(lean)
        for side, sign in (("l", -1), ("r", 1)):
            angle = sign * lean  # the left card turns clockwise (its top to +x)
            # Corners of the card in its frame, turned, relative to its centre.
            corners = [(dx * t / 2, dy * h / 2) for dx in (-1, 1) for dy in (-1, 1)]
            turned = [(x * math.cos(angle) - y * math.sin(angle),
                       x * math.sin(angle) + y * math.cos(angle)) for x, y in corners]
            low = min(y for _, y in turned)
            inner = max(-sign * x for x, _ in turned)  # the corner nearest the middle
            cx = x0 + sign * (inner + gap / 2)
            cy = y0 + gap - low
            bodies.append(body(f"{name}{side}", [card], pos=(cx, cy, 0), quat=quat_z(angle)))
        return y0 + gap + h * c + t * s  # the top of the frame

    def flat_card(name, x, y):
        bodies.append(body(name, [flat], pos=(x, y + gap + t / 2, 0)))
        return y + gap + t

    y = 0.0
    top = 0.0
    for storey, frames in enumerate([3, 2, 1]):
        xs = [(i - (frames - 1) / 2) * spacing for i in range(frames)]
        for i, x in enumerate(xs):
            top = a_frame(f"card{storey}_{i}", x, y)
        if frames > 1:
            for i in range(frames - 1):
                level = flat_card(f"flat{storey}_{i}", (xs[i] + xs[i + 1]) / 2, top)
            y = level
    return scene(bodies, '"dim": 3, "substeps": 8')


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "scenes"
    for name, make in (("pyramid-3d", pyramid), ("hulls-3d", hulls), ("ramp-3d", ramp),
                       ("cards-3d", cards)):
        with open(os.path.join(folder, name + ".json"), "w") as f:
            f.write(make())


if __name__ == "__main__":
    main()
