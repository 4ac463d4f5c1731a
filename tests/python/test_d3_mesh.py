"""quack.d3 meshes: building one from numpy arrays and its errors, every query against a mesh
equal to `quack query`'s answer bit for bit, the mesh's answers against a loop over its
triangles as lone shapes (brute force), a sphere falling onto a flat grid against its closed
form, and raycast_many against the single ray casts."""

import math
import os
import random
import subprocess
import sys

import numpy as np
import pytest

from quack import d3
from conftest import run_queries

TURN = (0.1, 0.2, 0.3, 0.9)


def wavy_grid(n=6, s=3.0):
    """An n x n height field over [-s, s]^2 (fronts up), diagonals alternating."""
    xs = np.linspace(-s, s, n + 1)
    vertices = np.array([(x, 0.4 * math.sin(1.3 * x + z), z) for x in xs for z in xs])
    triangles = []
    for i in range(n):
        for j in range(n):
            a, b, c, d = i * (n + 1) + j, (i + 1) * (n + 1) + j, (i + 1) * (n + 1) + j + 1, \
                i * (n + 1) + j + 1
            triangles += [(a, d, c), (a, c, b)] if (i + j) % 2 == 0 else [(a, d, b), (d, c, b)]
    return vertices, np.array(triangles)


FLOOR_V = np.array([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]], dtype=float)
FLOOR_T = np.array([[0, 3, 2], [0, 2, 1]])
FLOOR_JSON = {"type": "mesh", "vertices": FLOOR_V.tolist(), "triangles": FLOOR_T.tolist()}
FLOOR = d3.mesh(FLOOR_V, FLOOR_T)
GRID_V, GRID_T = wavy_grid()
GRID = d3.mesh(GRID_V, GRID_T)


def lone_triangles(mesh):
    """Each triangle of the mesh as a quack.d3.triangle (the same float32 corners)."""
    return [d3.triangle(mesh.vertices[t].tolist()) for t in mesh.triangles]


def test_mesh_by_hand():
    assert FLOOR.vertex_count == 4 and FLOOR.triangle_count == 2
    assert FLOOR.vertices.shape == (4, 3) and FLOOR.vertices.tolist() == FLOOR_V.tolist()
    assert FLOOR.triangles.tolist() == FLOOR_T.tolist()
    assert FLOOR.normals.tolist() == [[0, 1, 0], [0, 1, 0]]
    assert repr(FLOOR) == "quack.d3.Mesh(4 vertices, 2 triangles)"
    # Lists and other integer dtypes are taken too.
    assert d3.mesh(FLOOR_V.tolist(), FLOOR_T.astype(np.uint16)).triangle_count == 2
    assert GRID.triangle_count == 72


@pytest.mark.parametrize("vertices, triangles, message", [
    (FLOOR_V, FLOOR_T.astype(float), "triangles: must be a numpy array (M, 3) of integer vertex "
                                     "indices, not of dtype float64"),
    (FLOOR_V, [[0, 1], [1, 2]], "triangles: must be a numpy array (M, 3) of integer vertex "
                                "indices, not (2, 2)"),
    (FLOOR_V, [[True, False, True]], "not of dtype bool"),
    (FLOOR_V, [[0, 3, 9]], "triangles[0][2]: vertex index 9 is out of range (0 to 3)"),
    (FLOOR_V, [[0, 3, 2], [0, -1, 2]], "triangles[1][1]: vertex index -1 is out of range (0 to 3)"),
    (FLOOR_V, [[0, 0, 1]], "triangles[0]: a vertex index is repeated"),
    (FLOOR_V, np.zeros((0, 3), dtype=int), "triangles: no triangles"),
    ([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 2, 1]], "triangles[0]: "),
    ([[0, 0, 0], [1, 0, 0], [0, 0, float("nan")]], [[0, 2, 1]],
     "vertices[2][2]: must be finite (as a float)"),
    ([[0, 0, 0], [1e19, 0, 0], [0, 0, 1]], [[0, 2, 1]],
     "vertices[1][0]: 1e+19 m is beyond the coordinate limit 1e9 m"),
    ([[0, 0], [1, 0], [0, 1]], [[0, 2, 1]], "vertices: must be a numpy array (N, 3) of x, y, z"),
    # Two triangles along their shared edge the same way: their fronts disagree.
    (FLOOR_V, [[0, 3, 2], [0, 1, 2]], "triangles"),
])
def test_mesh_errors_name_the_field(vertices, triangles, message):
    with pytest.raises(ValueError) as e:
        d3.mesh(vertices, triangles)
    assert message in str(e.value)


def test_query_errors_name_the_argument():
    ball = d3.sphere(0.2)
    cases = [
        (lambda: d3.manifold(ball, None, FLOOR, None),
         "b: a quack.d3.Mesh must be shape a for manifold (as shape b it serves overlap, "
         "distance, penetration, toi)"),
        (lambda: d3.shapecast(ball, None, FLOOR, None, (0, 1, 0)),
         "b: a quack.d3.Mesh must be shape a for shapecast"),
        (lambda: d3.distance(FLOOR, None, FLOOR, None), "b: a mesh against a mesh"),
        (lambda: d3.toi(FLOOR, ((0, 0, 0), (0, 1, 0)), ball, ((0, 1, 0), (0, 0, 0))),
         "sweepA[1]: a mesh is static: its pose must be sweepA[0]'s"),
        (lambda: d3.toi(FLOOR, (0, 0, 0), ball, ((0, 1, 0), (0, 0, 0))),
         "sweepA: must be None (the mesh at the origin) or (pose, pose)"),
        (lambda: d3.toi(FLOOR, None, ball, ((0, 1, 0), (0, 0, 0)), target=-1), "target"),
        (lambda: d3.distance(FLOOR, (0, 0, math.inf), ball, None), "pa[2]"),
        (lambda: d3.penetration(ball, None, FLOOR, (0, 0, 0, 0, 0, 0, 0)), "pb: the quaternion"),
        (lambda: d3.overlap_many(FLOOR, np.zeros(7), ball, np.zeros(7)),
         "shapes_a: a quack.d3.Mesh is taken by raycast_many only"),
        (lambda: d3.hull([FLOOR]), "hull"),
        (lambda: d3.raycast_many(FLOOR, np.array([0, 0, 0, 0, 0, 0, 1.0]),
                                 np.array([[0, 1, 0, 0, -2, 0], [0, 1, 0, 0, math.nan, 0]])),
         "rays[1][4]"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError) as e:
            call()
        assert message in str(e.value)


def _pose(rng):
    q = [rng.uniform(-1, 1) for _ in range(3)] + [rng.uniform(0.1, 1)]
    return tuple([rng.uniform(-0.5, 0.5) for _ in range(3)] + q)


def _json_pose(p):
    return {"pos": list(p[:3]), "quat": list(p[3:])}


def test_answers_equal_quack_query_bit_for_bit(quack_bin):
    rng = random.Random(41)
    grid_json = {"type": "mesh", "vertices": GRID_V.tolist(), "triangles": GRID_T.tolist()}
    shapes = [{"type": "sphere", "radius": 0.3}, {"type": "box", "half": [0.3, 0.2, 0.25]},
              {"type": "capsule", "p1": [-0.4, 0, 0], "p2": [0.4, 0, 0], "radius": 0.15}]
    ops = ["overlap", "distance", "penetration", "manifold", "raycast", "shapecast", "toi",
           "distance-b", "penetration-b", "toi-b", "overlap-b"]
    lines, calls = [], []
    for i in range(110):
        op = ops[i % len(ops)]
        b = shapes[i % len(shapes)]
        sb = d3.shape(b)
        pm = _pose(rng)
        pb = tuple([rng.uniform(-2.5, 2.5), rng.uniform(-0.8, 1.2), rng.uniform(-2.5, 2.5)]) + \
            tuple(_pose(rng)[3:])
        pb = tuple(pm[k] + pb[k] for k in range(3)) + pb[3:]
        if op == "raycast":
            o = [rng.uniform(-2, 2), 3, rng.uniform(-2, 2)]
            t = [rng.uniform(-1, 1), -6, rng.uniform(-1, 1)]
            lines.append({"id": i, "op": op, "a": grid_json, "pa": _json_pose(pm),
                          "ray": {"origin": o, "translation": t}})
            calls.append(d3.raycast(GRID, pm, o, t))
        elif op in ("toi", "toi-b"):
            end = (pb[0] + rng.uniform(-1, 1), pb[1] - 2, pb[2] + rng.uniform(-1, 1)) + \
                tuple(_pose(rng)[3:])
            mesh_sweep = {"from": _json_pose(pm), "to": _json_pose(pm)}
            convex_sweep = {"from": _json_pose(pb), "to": _json_pose(end)}
            if op == "toi":
                lines.append({"id": i, "op": "toi", "a": grid_json, "sweepA": mesh_sweep,
                              "b": b, "sweepB": convex_sweep})
                calls.append(d3.toi(GRID, (pm, pm), sb, (pb, end)))
            else:
                lines.append({"id": i, "op": "toi", "a": b, "sweepA": convex_sweep,
                              "b": grid_json, "sweepB": mesh_sweep})
                calls.append(d3.toi(sb, (pb, end), GRID, (pm, pm)))
        elif op.endswith("-b"):
            name = op[:-2]
            lines.append({"id": i, "op": name, "a": b, "pa": _json_pose(pb), "b": grid_json,
                          "pb": _json_pose(pm)})
            calls.append(getattr(d3, name)(sb, pb, GRID, pm))
        else:
            line = {"id": i, "op": op, "a": grid_json, "pa": _json_pose(pm), "b": b,
                    "pb": _json_pose(pb)}
            if op == "shapecast":
                t = [rng.uniform(-1, 1), -2, rng.uniform(-1, 1)]
                line["translation"] = t
                calls.append(d3.shapecast(GRID, pm, sb, pb, t))
            else:
                calls.append(getattr(d3, op)(GRID, pm, sb, pb))
            lines.append(line)
    answers = run_queries(quack_bin, lines)
    hits = 0
    for line, answer, call in zip(lines, answers, calls):
        assert "error" not in answer, (line, answer)
        del answer["id"]
        assert call.to_dict() == answer, line
        hits += answer.get("status") == "hit"
    assert hits > 3


def test_penetration_distance_and_raycast_against_every_triangle():
    rng = random.Random(43)
    lone = lone_triangles(GRID)
    ball, cube = d3.sphere(0.3), d3.box((0.3, 0.2, 0.25))
    overlaps = 0
    for i in range(60):
        b = ball if i % 2 == 0 else cube
        pb = (rng.uniform(-3, 3), rng.uniform(-0.6, 0.8), rng.uniform(-3, 3)) + \
            tuple(_pose(rng)[3:])
        each = [d3.penetration(t, None, b, pb) for t in lone]
        got = d3.penetration(GRID, None, b, pb)
        deep = [k for k, p in enumerate(each) if p.overlap]
        if deep:
            overlaps += 1
            best = max(deep, key=lambda k: (each[k].depth, -k))
            assert got.triangle == best
            assert got.depth == each[best].depth and got.normal == each[best].normal
            assert d3.overlap(GRID, None, b, pb)
        else:
            assert not got.overlap and got.depth == 0
            dists = [d3.distance(t, None, b, pb).distance for t in lone]
            closest = min(range(len(lone)), key=lambda k: (dists[k], k))
            assert got.triangle == closest
            assert d3.distance(GRID, None, b, pb).distance == dists[closest]
            assert not d3.overlap(GRID, None, b, pb)
        # A ray straight down through the shape's place: the first front hit over the
        # triangles (a lone triangle is two-sided; the mesh's face normals are up here).
        o, t = (pb[0], 3.0, pb[2]), (0.1, -6.0, -0.05)
        hits = [(d3.raycast(tri, None, o, t), k) for k, tri in enumerate(lone)]
        front = [(h.fraction, k) for h, k in hits if h.hit and
                 np.dot(h.normal, GRID.normals[k]) > 0]
        ray = d3.raycast(GRID, None, o, t)
        assert ray.hit == bool(front)
        if front:
            assert (ray.fraction, ray.triangle) == min(front)
    assert 10 < overlaps < 50


def test_sphere_falling_onto_a_flat_grid_hits_at_its_closed_form():
    # A sphere of radius 0.5 falling from y = 2 to y = -1, spinning, over a flat grid: its
    # centre is 0.5 + target above the floor at t = (1.5 - target) / 3 (target 0.005; the
    # hit band kToiTolerance = 0.00125 is 3 times shorter in t).
    vertices, triangles = wavy_grid(4, 2.0)
    vertices[:, 1] = 0
    flat = d3.mesh(vertices, triangles)
    ball = d3.sphere(0.5)
    late, early = (1.5 - 0.005) / 3, (1.5 - 0.005 - 0.00125) / 3
    for x, z in [(0.3, -0.7), (0.0, 0.0), (-1.6, 1.2)]:
        start, end = (x, 2, z), (x, -1, z, 0.3, 0.2, 0.1, 0.9)
        r = d3.toi(flat, None, ball, (start, end))
        assert r.status == "hit" and early - 1e-6 <= r.t <= late + 1e-6
        # The same, turned round, and the lone triangles' earliest time agrees.
        assert d3.toi(ball, (start, end), flat, None).to_dict() == r.to_dict()
        each = [d3.toi(t, (None, None), ball, (start, end)) for t in lone_triangles(flat)]
        first = min(e.t for e in each if e.status == "hit")
        assert abs(first - r.t) < 1e-6
    # Rising through the floor from below: one-sided, no hit.
    up = d3.toi(flat, None, ball, ((0.3, -2, 0.1), (0.3, 2, 0.1)))
    assert up.status == "separated" and up.t == 1 and up.triangle == -1


def test_raycast_many_equals_the_single_ray_casts():
    rng = np.random.default_rng(7)
    n = 400
    rays = np.column_stack([rng.uniform(-3, 3, n), rng.uniform(1, 3, n), rng.uniform(-3, 3, n),
                            rng.uniform(-2, 2, n), rng.uniform(-6, -1, n), rng.uniform(-2, 2, n)])
    rays[::5, 4] *= -1  # some rays go up: they miss (one-sided, or nothing above)
    poses = np.tile(np.array([0.2, -0.1, 0.3] + list(TURN)), (n, 1))
    poses[:, 0] += rng.uniform(-0.2, 0.2, n)
    r = d3.raycast_many(GRID, poses, rays)
    assert r.triangle.dtype == np.int32 and r.triangle.shape == (n,)
    for i in range(n):
        one = d3.raycast(GRID, tuple(poses[i]), tuple(rays[i, :3]), tuple(rays[i, 3:]))
        assert bool(r.hit[i]) == one.hit and r.triangle[i] == one.triangle
        assert r.fraction[i] == one.fraction
        assert tuple(r.point[i]) == one.point and tuple(r.normal[i]) == one.normal
    assert 100 < r.hit.sum() < n - 40
    # One pose for every ray.
    single = d3.raycast_many(GRID, poses[0], rays)
    assert single.hit.shape == (n,)


def test_mypy_strict_types_a_mesh_program(tmp_path):
    pytest.importorskip("mypy", reason="mypy is not installed (Debian python3-mypy)")
    stubs = os.path.join(os.environ["QUACK_SOURCE_DIR"], "python", "stubs")
    good = tmp_path / "good.py"
    good.write_text(
        "import numpy as np\nfrom quack import d3\n"
        "m = d3.mesh(np.zeros((3, 3)), np.array([[0, 1, 2]]))\nb = d3.sphere(0.5)\n"
        "i: int = d3.distance(m, None, b, (0, 1, 0)).triangle\n"
        "j: int = d3.penetration(b, None, m, None).triangle\n"
        "k: int = d3.toi(m, None, b, ((0, 5, 0), (0, -5, 0))).triangle\n"
        "ids = [c.triangle for c in d3.manifold(m, None, b, None).manifolds]\n"
        "r = d3.raycast_many(m, np.zeros(7), np.zeros((2, 6)))\n")
    bad = tmp_path / "bad.py"
    bad.write_text("from quack import d3\nm = d3.mesh([[0, 0, 0]], [[0, 0, 0]])\n"
                   "d3.manifold(d3.sphere(1), None, m, None)\n")
    env = dict(os.environ, MYPYPATH=stubs)
    for path, code in ((good, 0), (bad, 1)):
        run = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental",
                              "--cache-dir", str(tmp_path / "cache"), str(path)],
                             capture_output=True, text=True, env=env, check=False)
        assert run.returncode == code, run.stdout + run.stderr
    assert 'bad.py:3: error: No overload variant of "manifold" matches' in run.stdout
