#!/usr/bin/env python3
"""Runs a Quack scene and plots the path of every moving body to a PNG.

    python3 examples/python/plot_paths.py [SCENE] [--steps N] [--out FILE]

Defaults: scenes/bullets.json, 240 steps, out/paths.png. Needs the quack module (built:
PYTHONPATH=build/debug/python; installed: scripts/python.sh install) and matplotlib
(Debian python3-matplotlib); draws off-screen, no display needed.
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only: works without a display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import quack  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def run(scene, steps):
    """Steps the scene; returns the moving bodies' names and their positions, (steps + 1,
    bodies, 2), read in one call per step."""
    world = quack.load_scene(scene)
    moving = [b for b in world.bodies if b.type != "static"]
    statics = world.get_positions([b for b in world.bodies if b.type == "static"])
    paths = np.empty((steps + 1, len(moving), 2))
    paths[0] = world.get_positions(moving)
    for i in range(steps):
        world.step()
        paths[i + 1] = world.get_positions(moving)
    return [b.name for b in moving], paths, statics, world


def plot(names, paths, statics, title, out):
    fig, ax = plt.subplots(figsize=(8, 6), dpi=100)
    for k in range(paths.shape[1]):
        line, = ax.plot(paths[:, k, 0], paths[:, k, 1], linewidth=1)
        ax.plot(paths[-1, k, 0], paths[-1, k, 1], "o", color=line.get_color(), markersize=3)
    if len(statics):
        ax.plot(statics[:, 0], statics[:, 1], "ks", markersize=4, label="static bodies")
        ax.legend(loc="upper right")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"{title}: paths of {paths.shape[1]} bodies over {paths.shape[0] - 1} steps")
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default=os.path.join(ROOT, "scenes", "bullets.json"))
    parser.add_argument("--steps", type=int, default=240)
    parser.add_argument("--out", default=os.path.join("out", "paths.png"))
    args = parser.parse_args(argv)
    if args.steps < 1:
        parser.error("--steps must be at least 1")
    names, paths, statics, world = run(args.scene, args.steps)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    plot(names, paths, statics, os.path.basename(args.scene), args.out)
    print(f"{args.out}: {paths.shape[1]} bodies, {args.steps} steps, state hash "
          f"{world.state_hash():#018x}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
