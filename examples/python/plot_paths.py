#!/usr/bin/env python3
"""Runs a Quack scene, plots the path of every moving body to a PNG and draws the world at
the end as an SVG (World.to_svg, the picture a Jupyter notebook shows for a world).

    python3 examples/python/plot_paths.py [SCENE] [--steps N] [--out FILE] [--svg FILE]

Defaults: scenes/bullets.json, 240 steps, out/paths.png, out/paths.svg. Needs the quack
module (pip install .; or built: PYTHONPATH=build/debug/python) and matplotlib (Debian
python3-matplotlib); draws off-screen, no display needed. Typed: `mypy --strict` checks it
(tests/python/test_typing.py).
"""

import argparse
import os
import sys
from typing import List, Optional, Tuple

import matplotlib  # type: ignore[import]

matplotlib.use("Agg")  # files only: works without a display
import matplotlib.pyplot as plt  # type: ignore[import]  # noqa: E402
import numpy as np  # noqa: E402
import numpy.typing as npt  # noqa: E402

import quack  # noqa: E402

Paths = npt.NDArray[np.float64]

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def run(scene: str, steps: int) -> Tuple[List[str], Paths, Paths, quack.World]:
    """Steps the scene; returns the moving bodies' names and their positions, (steps + 1,
    bodies, 2), read from the world's state array (World.body_state: one array per step,
    no copy per read) once per step."""
    world = quack.load_scene(scene)
    moving = np.array([b.type != "static" for b in world.bodies], dtype=bool)
    state = world.body_state()
    statics = state[~moving, 0:2].copy()
    paths = np.empty((steps + 1, int(moving.sum()), 2))
    paths[0] = state[moving, 0:2]
    for i in range(steps):
        world.step()
        paths[i + 1] = world.body_state()[moving, 0:2]
    return [b.name for b, m in zip(world.bodies, moving) if m], paths, statics, world


def plot(names: List[str], paths: Paths, statics: Paths, title: str, out: str) -> None:
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


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default=os.path.join(ROOT, "scenes", "bullets.json"))
    parser.add_argument("--steps", type=int, default=240)
    parser.add_argument("--out", default=os.path.join("out", "paths.png"))
    parser.add_argument("--svg", default=os.path.join("out", "paths.svg"),
                        help="the world after the last step, drawn by World.to_svg")
    args = parser.parse_args(argv)
    if args.steps < 1:
        parser.error("--steps must be at least 1")
    names, paths, statics, world = run(args.scene, args.steps)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    plot(names, paths, statics, os.path.basename(args.scene), args.out)
    os.makedirs(os.path.dirname(os.path.abspath(args.svg)), exist_ok=True)
    with open(args.svg, "w", encoding="utf-8") as f:
        f.write(world.to_svg(title=f"{os.path.basename(args.scene)} after {args.steps} steps"))
    print(f"{args.out}, {args.svg}: {paths.shape[1]} bodies, {args.steps} steps, state hash "
          f"{world.state_hash():#018x}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
