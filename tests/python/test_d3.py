"""quack.d3: 3D shapes and queries. Cases worked by hand, errors, the batch forms against the
single queries, agreement with `quack query` on 3D lines (the same numbers, bit for bit),
and the stubs under `mypy --strict`."""

import math
import os
import random
import subprocess
import sys

import numpy as np
import pytest

import quack
from quack import d3
from conftest import run_queries

BALL = d3.sphere(radius=1)
SMALL = d3.sphere(0.5)
SLAB = d3.box(half=(5, 0.5, 5))
CUBE = d3.box(half=(0.5, 0.5, 0.5))
QUARTER_Y = (0, math.sqrt(0.5), 0, math.sqrt(0.5))  # a quarter turn about y


def test_import_forms():
    import quack.d3 as imported
    assert imported is d3 is quack.d3
    assert d3.Shape is type(BALL)


def test_shapes_by_hand():
    assert BALL.type == "sphere" and BALL.vertex_count == 1
    assert BALL.volume() == pytest.approx(4 / 3 * math.pi, rel=1e-6)
    assert CUBE.type == "box" and CUBE.vertex_count == 8
    assert CUBE.volume() == pytest.approx(1.0, rel=1e-6)
    assert d3.capsule((0, -1, 0), (0, 1, 0), 0.5).volume() == pytest.approx(
        math.pi * 0.25 * 2 + 4 / 3 * math.pi * 0.125, rel=1e-6)
    # A cube's corners, its centre and a duplicate corner: 8 vertices, volume 1.
    corners = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    h = d3.hull(np.vstack([corners, [[0.5, 0.5, 0.5], [1, 1, 1]]]))
    assert h.vertex_count == 8 and h.volume() == pytest.approx(1.0, rel=1e-6)
    t = d3.triangle([(0, 0, 0), (1, 0, 0), (0, 0, -1)])
    assert t.type == "triangle" and t.volume() == 0.0
    assert d3.shape(CUBE.to_dict()).to_dict() == {"type": "box", "half": [0.5, 0.5, 0.5]}
    assert "quack.d3.shape(" in repr(BALL)
    # Rounded: a 2 x 1 x 1 box rounded by 0.1, Steiner's V + A r + (edges x angle) r^2 / 2
    # + 4/3 pi r^3: 2 + 10 * 0.1 + 16 * (pi / 2) * 0.01 / 2 + 4/3 pi 0.001.
    rounded = d3.box(half=(1, 0.5, 0.5), radius=0.1)
    assert rounded.to_dict() == {"type": "box", "half": [1, 0.5, 0.5], "radius": 0.1}
    assert rounded.volume() == pytest.approx(
        2 + 10 * 0.1 + 16 * math.pi / 2 * 0.01 / 2 + 4 / 3 * math.pi * 0.001, rel=1e-6)
    rh = d3.hull(corners, radius=0.25)
    assert rh.vertex_count == 8 and rh.to_dict()["radius"] == 0.25
    assert rh.volume() == pytest.approx(
        1 + 6 * 0.25 + 12 * math.pi / 2 * 0.25**2 / 2 + 4 / 3 * math.pi * 0.25**3, rel=1e-6)
    assert d3.shape(rh.to_dict()).volume() == rh.volume()


def test_shape_errors_name_the_field():
    with pytest.raises(ValueError, match=r"^sphere.radius: must be > 0$"):
        d3.sphere(radius=0)
    with pytest.raises(ValueError, match=r"^box.half: must be \[x, y, z\]$"):
        d3.box(half=(1, 1))
    with pytest.raises(ValueError, match=r"^box.quat: \[0, 0, 0, 0\] is not a rotation"):
        d3.box(half=(1, 1, 1), quat=(0, 0, 0, 0))
    with pytest.raises(ValueError, match=r"^hull.points: needs at least 4 points$"):
        d3.hull([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    with pytest.raises(ValueError, match=r"^hull: "):  # coplanar: quickhull's message
        d3.hull([(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)])
    with pytest.raises(ValueError, match=r"^hull.radius: must be >= 0$"):
        d3.hull([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], radius=-0.1)
    with pytest.raises(ValueError, match=r"^hull.radius: must be finite"):
        d3.hull([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], radius=float("nan"))
    with pytest.raises(ValueError, match=r"^box.radius: must be >= 0$"):
        d3.box(half=(1, 1, 1), radius=-1)
    with pytest.raises(ValueError, match=r"^triangle.points: needs exactly 3 points$"):
        d3.triangle([(0, 0, 0), (1, 0, 0)])
    with pytest.raises(ValueError, match=r"is a 2D shape"):
        d3.shape({"type": "circle", "radius": 1})
    with pytest.raises(ValueError, match=r"^capsule.p1\[0\]: must be finite \(as a float\)$"):
        d3.capsule((1e300, 0, 0), (0, 1, 0), 1)


def test_distance_of_two_spheres_by_hand():
    r = d3.distance(BALL, None, SMALL, (3, 4, 0))
    assert r.distance == pytest.approx(3.5, abs=1e-6)
    assert r.pointA == pytest.approx((0.6, 0.8, 0.0), abs=1e-6)
    assert r.pointB == pytest.approx((2.7, 3.6, 0.0), abs=1e-6)
    assert r.normal == pytest.approx((0.6, 0.8, 0.0), abs=1e-6)
    assert r.point_a == r.pointA and r.point_b == r.pointB
    assert r.status in quack.GJK_STATUSES and r.iterations >= 1
    assert set(r.to_dict()) == {"distance", "pointA", "pointB", "normal", "iterations", "status"}
    # The same with a 7-number pose (a turn does not move a sphere's centre).
    turned = d3.distance(BALL, (0, 0, 0) + QUARTER_Y, SMALL, (3, 4, 0, 0, 0, 0, 2))
    assert turned.distance == pytest.approx(3.5, abs=1e-6)


def test_overlap_and_penetration_by_hand():
    assert d3.overlap(BALL, None, SMALL, (0, 1.4, 0)).overlap
    assert not d3.overlap(BALL, None, SMALL, (0, 1.6, 0))
    p = d3.penetration(BALL, None, SMALL, (0.6, 0.8, 0))
    assert p.overlap and p.depth == pytest.approx(0.5, abs=1e-6)
    assert p.normal == pytest.approx((0.6, 0.8, 0.0), abs=1e-6)
    assert p.pointA == pytest.approx((0.6, 0.8, 0.0), abs=1e-6)
    assert p.pointB == pytest.approx((0.3, 0.4, 0.0), abs=1e-6)
    assert p.status in d3.EPA_STATUSES


def test_manifold_of_a_cube_resting_on_a_slab():
    m = d3.manifold(SLAB, None, CUBE, (0.3, 0.99, -0.2))
    assert m.normal == pytest.approx((0.0, 1.0, 0.0), abs=1e-6)
    assert len(m.points) == 4
    corners = sorted((round(p.point[0], 4), round(p.point[2], 4)) for p in m.points)
    assert corners == [(-0.2, -0.7), (-0.2, 0.3), (0.8, -0.7), (0.8, 0.3)]
    for p in m.points:
        assert p.separation == pytest.approx(-0.01, abs=1e-5)
        assert p.point[1] == pytest.approx(0.495, abs=1e-5)
    assert len({p.id for p in m.points}) == 4
    assert len(d3.manifold(SLAB, None, CUBE, (0, 2, 0)).points) == 0
    assert len(d3.manifold(SLAB, None, CUBE, (0, 2, 0), speculative=2).points) == 4


def test_raycast_into_a_turned_cube_face():
    cube = d3.box(half=(1, 1, 1))
    r = d3.raycast(cube, (0, 0, 5) + QUARTER_Y, (0.2, -0.3, 0), (0, 0, 10))
    assert r.hit and bool(r)
    assert r.fraction == pytest.approx(0.4, abs=1e-6)
    assert r.point == pytest.approx((0.2, -0.3, 4.0), abs=1e-5)
    assert r.normal == pytest.approx((0.0, 0.0, -1.0), abs=1e-6)
    miss = d3.raycast(cube, (0, 0, 5), (0, 0, 0), (0, 0, 3))
    assert not miss.hit and miss.fraction == 0.0 and miss.point == (0.0, 0.0, 0.0)


def test_toi_and_shapecast_of_a_sphere_falling_on_a_slab():
    # The centre reaches y = 1 after 4 of the 10 m; toi stops a linear slop (0.005 m) short.
    t = d3.toi(SLAB, (None, (0, 0, 0) + QUARTER_Y), SMALL,
               ((0, 5, 0), (0, -5, 0)))
    assert t.status == "hit"
    assert t.t == pytest.approx((4 - 0.005) / 10, abs=2e-4)
    assert d3.toi(SLAB, (None, None), SMALL, ((6, 5, 0), (6, -5, 0))).status == "separated"
    c = d3.shapecast(SLAB, None, SMALL, (0, 5, 0), (0, -10, 0))
    assert c.hit and c.status == "hit"
    assert c.fraction == pytest.approx(0.4, abs=2e-4)
    assert c.normal == pytest.approx((0.0, 1.0, 0.0), abs=1e-5)


def test_query_errors_name_the_argument():
    with pytest.raises(ValueError, match=r"^pa: the quaternion \(qx, qy, qz, qw\) is zero"):
        d3.distance(BALL, (0, 0, 0, 0, 0, 0, 0), SMALL, None)
    with pytest.raises(ValueError, match=r"^pb: must be a pose \(x, y, z\) or"):
        d3.distance(BALL, None, SMALL, (1, 2))
    with pytest.raises(ValueError, match=r"^pb\[2\]: 2e\+19 m is beyond the coordinate limit"):
        d3.distance(BALL, None, SMALL, (0, 0, 2e19))
    with pytest.raises(ValueError, match=r"^pa\[6\]: must be finite \(as a float\)$"):
        d3.overlap(BALL, (0, 0, 0, 0, 0, 0, math.inf), SMALL, None)
    with pytest.raises(ValueError, match=r"^b: a 2D quack.Shape in a 3D query"):
        d3.distance(BALL, None, quack.circle(radius=1), None)
    with pytest.raises(ValueError, match=r"^a: a 3D quack.d3.Shape in a 2D query"):
        quack.distance(BALL, None, quack.circle(radius=1), None)
    with pytest.raises(ValueError, match=r"^a: must be a quack.d3.Shape .* not str$"):
        d3.overlap("ball", None, SMALL, None)
    with pytest.raises(ValueError, match=r"^translation: must be a vector \(x, y, z\)$"):
        d3.shapecast(BALL, None, SMALL, None, (1, 0))
    with pytest.raises(ValueError, match=r"^sweepB: must be \(pose_from, pose_to\)"):
        d3.toi(BALL, (None, None), SMALL, (None,))
    with pytest.raises(ValueError, match=r"^speculative: must be a number >= 0"):
        d3.manifold(BALL, None, SMALL, None, speculative=-1)


def _random_shape(rng):
    kind = rng.choice(["sphere", "capsule", "box", "hull", "triangle"])
    s = rng.uniform(0.3, 1.2)
    if kind == "sphere":
        return {"type": "sphere", "center": [rng.uniform(-0.2, 0.2), 0, 0], "radius": s}
    if kind == "capsule":
        return {"type": "capsule", "p1": [0, -s, 0], "p2": [0, s, rng.uniform(-0.3, 0.3)],
                "radius": rng.uniform(0.1, 0.5)}
    # Boxes and hulls are rounded half the time.
    if kind == "box":
        box = {"type": "box", "half": [s, rng.uniform(0.2, 1.0), rng.uniform(0.2, 1.0)]}
        if rng.random() < 0.5:
            box["radius"] = rng.uniform(0.01, 0.3)
        return box
    if kind == "hull":
        hull = {"type": "hull", "points": [[rng.uniform(-s, s) for _ in range(3)]
                                           for _ in range(rng.randint(6, 20))]}
        if rng.random() < 0.5:
            hull["radius"] = rng.uniform(0.01, 0.3)
        return hull
    return {"type": "triangle", "points": [[-s, 0, -s], [s, 0, -s], [0, rng.uniform(-0.5, 0.5), s]]}


def _random_pose(rng):
    q = [rng.uniform(-1, 1) for _ in range(4)]
    return [rng.uniform(-2, 2) for _ in range(3)] + q


def _json_pose(p):
    return {"pos": list(p[:3]), "quat": list(p[3:])}


def test_answers_equal_quack_query_bit_for_bit(quack_bin):
    rng = random.Random(33)
    lines, calls = [], []
    for i in range(150):
        a, b = _random_shape(rng), _random_shape(rng)
        pa, pb = _random_pose(rng), _random_pose(rng)
        sa, sb = d3.shape(a), d3.shape(b)
        op = ["overlap", "distance", "penetration", "manifold", "raycast", "shapecast", "toi"][i % 7]
        line = {"id": i, "op": op, "a": a}
        if op == "raycast":
            o, t = [rng.uniform(-3, 3) for _ in range(3)], [rng.uniform(-6, 6) for _ in range(3)]
            line.update(pa=_json_pose(pa), ray={"origin": o, "translation": t})
            calls.append(d3.raycast(sa, pa, o, t))
        elif op == "toi":
            pa2, pb2 = _random_pose(rng), _random_pose(rng)
            line.update(b=b, sweepA={"from": _json_pose(pa), "to": _json_pose(pa2)},
                        sweepB={"from": _json_pose(pb), "to": _json_pose(pb2)})
            calls.append(d3.toi(sa, (pa, pa2), sb, (pb, pb2)))
        else:
            line.update(pa=_json_pose(pa), b=b, pb=_json_pose(pb))
            if op == "shapecast":
                t = [rng.uniform(-4, 4) for _ in range(3)]
                line["translation"] = t
                calls.append(d3.shapecast(sa, pa, sb, pb, t))
            else:
                calls.append(getattr(d3, op)(sa, pa, sb, pb))
        lines.append(line)
    answers = run_queries(quack_bin, lines)
    for line, answer, call in zip(lines, answers, calls):
        assert "error" not in answer, (line, answer)
        del answer["id"]
        assert call.to_dict() == answer, line


def test_batch_equals_the_single_queries():
    rng = random.Random(7)
    shapes_a = [d3.shape(_random_shape(rng)) for _ in range(60)]
    shapes_b = [d3.shape(_random_shape(rng)) for _ in range(60)]
    poses_a = np.array([_random_pose(rng) for _ in range(60)])
    poses_b = np.array([_random_pose(rng) for _ in range(60)])
    d = d3.distance_many(shapes_a, poses_a, shapes_b, poses_b)
    p = d3.penetration_many(shapes_a, poses_a, shapes_b, poses_b)
    o = d3.overlap_many(shapes_a, poses_a, shapes_b, poses_b)
    assert d.pointA.shape == (60, 3) and p.normal.shape == (60, 3) and o.overlap.dtype == bool
    for i in range(60):
        one = d3.distance(shapes_a[i], poses_a[i], shapes_b[i], poses_b[i])
        assert d.distance[i] == one.distance and tuple(d.pointA[i]) == one.pointA
        assert tuple(d.normal[i]) == one.normal and quack.GJK_STATUSES[d.status[i]] == one.status
        pen = d3.penetration(shapes_a[i], poses_a[i], shapes_b[i], poses_b[i])
        assert p.depth[i] == pen.depth and tuple(p.pointB[i]) == pen.pointB
        assert d3.EPA_STATUSES[p.status[i]] == pen.status
        assert o.overlap[i] == d3.overlap(shapes_a[i], poses_a[i], shapes_b[i], poses_b[i]).overlap
    rays = np.array([[rng.uniform(-3, 3) for _ in range(3)] + [rng.uniform(-6, 6) for _ in range(3)]
                     for _ in range(60)])
    r = d3.raycast_many(shapes_a, poses_a, rays)
    for i in range(60):
        one = d3.raycast(shapes_a[i], poses_a[i], rays[i, :3], rays[i, 3:])
        assert r.hit[i] == one.hit and r.fraction[i] == one.fraction
        assert tuple(r.point[i]) == one.point


def test_batch_by_hand_and_errors():
    # A small sphere at x = 2..6 from a unit ball: distances 0.5 to 4.5.
    poses = np.zeros((5, 7))
    poses[:, 0] = np.linspace(2, 6, 5)
    poses[:, 6] = 1
    d = d3.distance_many(BALL, np.array([0, 0, 0, 0, 0, 0, 1.0]), SMALL, poses)
    assert d.distance == pytest.approx([0.5, 1.5, 2.5, 3.5, 4.5], abs=1e-6)
    assert d.normal == pytest.approx(np.tile([1.0, 0, 0], (5, 1)), abs=1e-6)
    bad = poses.copy()
    bad[3, 3:] = 0
    with pytest.raises(ValueError, match=r"^poses_b\[3\]: the quaternion .* is zero"):
        d3.distance_many(BALL, poses[0], SMALL, bad)
    with pytest.raises(ValueError, match=r"^poses_b: must be a numpy array of shape \(N, 7\)"):
        d3.distance_many(BALL, poses[0], SMALL, np.zeros((5, 3)))
    with pytest.raises(ValueError, match=r"^poses_b: 4 rows, but shapes_a has 5"):
        d3.distance_many([BALL] * 5, poses, SMALL, poses[:4])
    with pytest.raises(ValueError, match=r"^rays\[1\]\[2\]: must be finite"):
        d3.raycast_many(BALL, poses[0], np.array([[0, 0, 0, 1, 0, 0], [0, 0, np.nan, 1, 0, 0]]))


def test_mypy_strict_types_a_3d_program(source_dir, tmp_path):
    pytest.importorskip("mypy", reason="mypy is not installed (Debian python3-mypy)")
    good = tmp_path / "good.py"
    good.write_text(
        "import numpy as np\nfrom quack import d3\n"
        "a = d3.box(half=(1, 1, 1), quat=(0, 0, 0, 1))\nb = d3.sphere(radius=0.5)\n"
        "r = d3.distance(a, None, b, (3, 0, 0, 0, 0, 0, 1))\nd: float = r.distance\n"
        "n: tuple[float, float, float] = r.normal\n"
        "m = d3.manifold(a, (0, 0, 0), b, (0, 1.2, 0))\nids = [p.id for p in m.points]\n"
        "many = d3.distance_many(a, np.zeros(7), [b, b], np.zeros((2, 7)))\n"
        "t: str = d3.toi(a, (None, None), b, ((0, 5, 0), (0, -5, 0))).status\n")
    bad = tmp_path / "bad.py"
    bad.write_text("from quack import d3\nx: str = d3.sphere(radius=1).volume()\n"
                   "d3.distance(d3.sphere(1), None, d3.sphere(1))\n")
    env = dict(os.environ, MYPYPATH=os.path.join(source_dir, "python", "stubs"))
    for path, code in ((good, 0), (bad, 1)):
        run = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental",
                              "--cache-dir", str(tmp_path / "cache"), str(path)],
                             capture_output=True, text=True, env=env, check=False)
        assert run.returncode == code, run.stdout + run.stderr
    assert "bad.py:2: error: Incompatible types in assignment" in run.stdout
    assert 'bad.py:3: error: No overload variant of "distance" matches' in run.stdout
