"""Shared fixtures for the Python module's tests (run by ctest: see python/CMakeLists.txt,
which sets the environment variables below)."""

import json
import math
import os
import random
import subprocess

import pytest


def _path_from_env(name, what):
    path = os.environ.get(name)
    if not path or not os.path.exists(path):
        pytest.fail(f"{name} must name {what} (ctest sets it; see python/CMakeLists.txt)")
    return path


@pytest.fixture(scope="session")
def quack_bin():
    return _path_from_env("QUACK_BIN", "the built quack program")


@pytest.fixture(scope="session")
def scene_hash_bin():
    return _path_from_env("QUACK_SCENE_HASH", "the built quack_python_scene_hash helper")


@pytest.fixture(scope="session")
def source_dir():
    return _path_from_env("QUACK_SOURCE_DIR", "the source tree")


def run_queries(quack_bin, lines):
    """Answers of `quack query` to JSON Lines (a list of dicts), in order."""
    text = "".join(json.dumps(line) + "\n" for line in lines)
    out = subprocess.run([quack_bin, "query", "-"], input=text, capture_output=True, text=True,
                         check=False)
    answers = [json.loads(line) for line in out.stdout.splitlines()]
    assert len(answers) == len(lines), out.stderr
    return answers


def random_convex_points(rng, n, radius):
    """n points on a circle at distinct random angles: a strictly convex point set."""
    angles = sorted(rng.sample(range(0, 360, 7), n))
    return [[radius * math.cos(math.radians(a)), radius * math.sin(math.radians(a))]
            for a in angles]


def random_shape_dict(rng, kinds=("circle", "capsule", "segment", "box", "polygon", "concave")):
    kind = rng.choice(kinds)
    s = rng.uniform(0.3, 1.5)
    if kind == "circle":
        return {"type": "circle", "center": [rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)],
                "radius": s}
    if kind == "capsule":
        return {"type": "capsule", "p1": [-s, rng.uniform(-0.2, 0.2)], "p2": [s, 0],
                "radius": rng.uniform(0.1, 0.5)}
    if kind == "segment":
        return {"type": "segment", "p1": [-s, 0], "p2": [s, rng.uniform(-0.5, 0.5)]}
    if kind == "box":
        return {"type": "box", "half": [s, rng.uniform(0.2, 1.0)], "angle": rng.uniform(-1, 1),
                "radius": rng.choice([0, 0.1])}
    if kind == "polygon":
        return {"type": "polygon", "points": random_convex_points(rng, rng.randint(3, 8), s),
                "radius": rng.choice([0, 0.05])}
    # An L, scaled: two convex pieces.
    return {"type": "concave",
            "points": [[0, 0], [2 * s, 0], [2 * s, s / 2], [s / 2, s / 2], [s / 2, 2 * s],
                       [0, 2 * s]]}


def random_pose(rng, spread=3.0):
    return (rng.uniform(-spread, spread), rng.uniform(-spread, spread), rng.uniform(-4, 4))


@pytest.fixture
def rng():
    return random.Random(20)
