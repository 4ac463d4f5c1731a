"""The single-pair queries: cases worked by hand, symmetry, errors, and agreement with
`quack query` on random pairs (the same numbers must come out, bit for bit)."""

import math
import random

import pytest

import quack
from conftest import random_pose, random_shape_dict, run_queries

CIRCLE = quack.circle(radius=0.5)
BOX = quack.box(half=(1, 0.5))
ORIGIN = (0, 0, 0)


def test_distance_between_circles_by_hand():
    r = quack.distance(CIRCLE, ORIGIN, CIRCLE, (3, 0, 0))
    assert r.distance == pytest.approx(2.0)
    assert r.pointA == pytest.approx((0.5, 0.0))
    assert r.pointB == pytest.approx((2.5, 0.0))
    assert r.normal == pytest.approx((1.0, 0.0))
    assert r.point_a == r.pointA and r.point_b == r.pointB
    assert r.status in quack.GJK_STATUSES
    assert r.iterations >= 1
    assert set(r.to_dict()) == {"distance", "pointA", "pointB", "normal", "iterations", "status"}


def test_distance_is_zero_when_overlapping_and_swapping_flips_the_normal():
    assert quack.distance(CIRCLE, ORIGIN, BOX, (0.5, 0, 0)).distance == 0.0
    ab = quack.distance(BOX, (0, 0, 0.2), CIRCLE, (3, 1, 0))
    ba = quack.distance(CIRCLE, (3, 1, 0), BOX, (0, 0, 0.2))
    assert ab.distance == pytest.approx(ba.distance, abs=1e-6)
    assert ab.normal == pytest.approx((-ba.normal[0], -ba.normal[1]), abs=1e-6)
    assert ab.pointA == pytest.approx(ba.pointB, abs=1e-6)


def test_overlap_by_hand():
    assert quack.overlap(CIRCLE, ORIGIN, CIRCLE, (0.9, 0, 0)).overlap
    assert bool(quack.overlap(CIRCLE, ORIGIN, BOX, (1.4, 0, 0)))
    assert not quack.overlap(CIRCLE, ORIGIN, BOX, (1.6, 0, 0))
    # The box turned a quarter turn is 0.5 wide: apart at 1.1.
    assert not quack.overlap(CIRCLE, ORIGIN, BOX, (1.1, 0, math.pi / 2)).overlap


def test_penetration_by_hand():
    r = quack.penetration(CIRCLE, ORIGIN, CIRCLE, (0.6, 0, 0))
    assert r.overlap
    assert r.depth == pytest.approx(0.4, abs=1e-6)
    assert r.normal == pytest.approx((1.0, 0.0), abs=1e-6)
    assert r.pointA == pytest.approx((0.5, 0.0), abs=1e-6)
    assert r.pointB == pytest.approx((0.1, 0.0), abs=1e-6)
    apart = quack.penetration(CIRCLE, ORIGIN, CIRCLE, (3, 0, 0))
    assert not apart.overlap and apart.depth == 0.0
    assert r.status in quack.EPA_STATUSES


def test_manifold_by_hand():
    # Box resting on a wide box, overlapping by 0.01: two points along the shared face.
    ground = quack.box(half=(5, 0.5))
    m = quack.manifold(ground, ORIGIN, BOX, (0, 0.99, 0))
    assert m.normal == pytest.approx((0.0, 1.0), abs=1e-6)
    assert len(m.points) == 2
    for p in m.points:
        assert p.separation == pytest.approx(-0.01, abs=1e-5)
        assert abs(p.point[0]) == pytest.approx(1.0, abs=1e-5)
    assert quack.manifold(ground, ORIGIN, BOX, (0, 3, 0)).points == []
    # Within the speculative distance asked for, points appear.
    assert len(quack.manifold(ground, ORIGIN, BOX, (0, 1.5, 0), speculative=1.0).points) == 2


def test_raycast_by_hand():
    r = quack.raycast(BOX, ORIGIN, (-5, 0), (10, 0))
    assert r.hit
    assert r.fraction == pytest.approx(0.4)
    assert r.point == pytest.approx((-1.0, 0.0))
    assert r.normal == pytest.approx((-1.0, 0.0))
    miss = quack.raycast(BOX, ORIGIN, (-5, 2), (10, 0))
    assert not miss.hit and miss.point == (0.0, 0.0)
    # Moved and turned: the box at (10, 0) turned a quarter turn is 0.5 wide in x.
    r = quack.raycast(BOX, (10, 0, math.pi / 2), (0, 0), (20, 0))
    assert r.point == pytest.approx((9.5, 0.0), abs=1e-5)


def test_shapecast_and_toi_by_hand():
    # The circle (radius 0.5) moves from x = 5 towards the box (half-width 1): touching at
    # x = 1.5, after 3.5 of its 10 m.
    c = quack.shapecast(BOX, ORIGIN, CIRCLE, (5, 0, 0), (-10, 0))
    assert c.hit and c.status == "hit"
    assert c.fraction == pytest.approx(0.35, abs=1e-4)
    assert c.normal == pytest.approx((1.0, 0.0), abs=1e-5)
    assert c.point == pytest.approx((1.0, 0.0), abs=1e-4)
    t = quack.toi(BOX, (ORIGIN, ORIGIN), CIRCLE, ((5, 0, 0), (-5, 0, 0)))
    assert t.status == "hit"
    # Stops at the target separation (0.005 m by default) short of touching.
    assert t.t == pytest.approx((3.5 - 0.005) / 10, abs=1e-4)
    t = quack.toi(BOX, (ORIGIN, ORIGIN), CIRCLE, ((5, 0, 0), (-5, 0, 0)), target=0.5)
    assert t.t == pytest.approx(3.0 / 10, abs=1e-4)
    assert quack.toi(BOX, (ORIGIN, ORIGIN), CIRCLE, ((5, 0, 0), (5, 3, 0))).status == "separated"


def test_concave_shapes_in_the_ops_that_take_them():
    ell = quack.concave(points=[[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]])
    # The circle sits in the L's elbow, clear of both arms.
    assert not quack.overlap(ell, ORIGIN, CIRCLE, (2.5, 2.5, 0)).overlap
    assert quack.distance(ell, ORIGIN, CIRCLE, (2.5, 2.5, 0)).distance == pytest.approx(1.0)
    assert quack.penetration(ell, ORIGIN, CIRCLE, (3, 1.2, 0)).depth == pytest.approx(0.3)
    assert quack.raycast(ell, ORIGIN, (3, 3), (-3, -3)).point == pytest.approx((1, 1))


@pytest.mark.parametrize("call, message", [
    (lambda e: quack.manifold(e, ORIGIN, BOX, ORIGIN),
     "a: a concave shape supports ops overlap, distance and penetration only, not manifold"),
    (lambda e: quack.shapecast(BOX, ORIGIN, e, ORIGIN, (1, 0)),
     "b: a concave shape supports ops overlap, distance and penetration only, not shapecast"),
    (lambda e: quack.toi(e, (ORIGIN, ORIGIN), BOX, (ORIGIN, ORIGIN)),
     "a: a concave shape supports ops overlap, distance and penetration only, not toi"),
])
def test_concave_where_a_convex_shape_is_needed(call, message):
    ell = quack.concave(points=[[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]])
    with pytest.raises(ValueError, match=message):
        call(ell)


@pytest.mark.parametrize("call, message", [
    (lambda: quack.distance(CIRCLE, (math.nan, 0, 0), BOX, ORIGIN),
     r"pa\[0\]: must be finite \(as a float\)"),
    (lambda: quack.distance(CIRCLE, ORIGIN, BOX, (0, 0, math.inf)),
     r"pb\[2\]: must be finite \(as a float\)"),
    (lambda: quack.overlap(CIRCLE, (2e9, 0, 0), BOX, ORIGIN),
     r"pa\[0\]: 2e\+09 m is beyond the coordinate limit 1e9 m"),
    (lambda: quack.overlap(CIRCLE, (0, 0), BOX, ORIGIN), r"pa: must be a pose \(x, y, angle\)"),
    (lambda: quack.overlap(CIRCLE, "0 0 0", BOX, ORIGIN), r"pa: must be a pose"),
    (lambda: quack.overlap(CIRCLE, (0, "x", 0), BOX, ORIGIN), r"pa\[1\]: must be a number"),
    (lambda: quack.overlap({"type": "circle"}, ORIGIN, BOX, ORIGIN),
     r"a: must be a quack.Shape .* not dict"),
    (lambda: quack.raycast(BOX, ORIGIN, (0, math.nan), (1, 0)),
     r"origin\[1\]: must be finite"),
    (lambda: quack.shapecast(BOX, ORIGIN, CIRCLE, ORIGIN, (1,)),
     r"translation: must be a vector \(x, y\)"),
    (lambda: quack.manifold(BOX, ORIGIN, CIRCLE, ORIGIN, speculative=-1),
     r"speculative: must be a number >= 0"),
    (lambda: quack.toi(BOX, ORIGIN, CIRCLE, (ORIGIN, ORIGIN)),
     r"sweepA: must be \(pose_from, pose_to\)"),
    (lambda: quack.toi(BOX, (ORIGIN, ORIGIN), CIRCLE, (ORIGIN, ORIGIN), target=math.nan),
     r"target: must be a number >= 0"),
])
def test_bad_arguments_raise_value_error_naming_them(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def _pose_json(p):
    return {"pos": [p[0], p[1]], "angle": p[2]}


def test_agreement_with_quack_query_on_random_pairs(quack_bin):
    """Every op, 1,200 random pairs of every kind: the module's answer equals the program's,
    field by field, exactly (both read the same doubles and compute in float)."""
    rng = random.Random(7)
    lines, calls = [], []
    convex = ("circle", "capsule", "segment", "box", "polygon")
    for i in range(200):
        for op in ("overlap", "distance", "penetration", "manifold", "raycast", "shapecast"):
            kinds = convex if op in ("manifold", "shapecast") else convex + ("concave",)
            a, b = random_shape_dict(rng, kinds), random_shape_dict(rng, kinds)
            pa, pb = random_pose(rng), random_pose(rng)
            line = {"id": len(lines), "op": op, "a": a, "pa": _pose_json(pa)}
            sa, sb = quack.shape(a), quack.shape(b)
            if op == "raycast":
                origin = [rng.uniform(-6, 6), rng.uniform(-6, 6)]
                translation = [-origin[0] + rng.uniform(-1, 1), -origin[1] + rng.uniform(-1, 1)]
                line["ray"] = {"origin": origin, "translation": translation}
                calls.append(lambda sa=sa, pa=pa, o=origin, t=translation:
                             quack.raycast(sa, pa, o, t))
            else:
                line["b"], line["pb"] = b, _pose_json(pb)
                if op == "shapecast":
                    translation = [rng.uniform(-6, 6), rng.uniform(-6, 6)]
                    line["translation"] = translation
                    calls.append(lambda sa=sa, pa=pa, sb=sb, pb=pb, t=translation:
                                 quack.shapecast(sa, pa, sb, pb, t))
                else:
                    f = getattr(quack, op)
                    calls.append(lambda f=f, sa=sa, pa=pa, sb=sb, pb=pb: f(sa, pa, sb, pb))
            lines.append(line)
        # toi: sweeps between two random poses each.
        a, b = random_shape_dict(rng, convex), random_shape_dict(rng, convex)
        sweep_a, sweep_b = (random_pose(rng), random_pose(rng)), (random_pose(rng), random_pose(rng))
        lines.append({"id": len(lines), "op": "toi", "a": a, "b": b,
                      "sweepA": {"from": _pose_json(sweep_a[0]), "to": _pose_json(sweep_a[1])},
                      "sweepB": {"from": _pose_json(sweep_b[0]), "to": _pose_json(sweep_b[1])}})
        calls.append(lambda sa=quack.shape(a), sb=quack.shape(b), wa=sweep_a, wb=sweep_b:
                     quack.toi(sa, wa, sb, wb))
    answers = run_queries(quack_bin, lines)
    compared = 0
    for line, answer, call in zip(lines, answers, calls):
        assert "error" not in answer, (line, answer)
        mine = call().to_dict()
        expected = {k: v for k, v in answer.items() if k != "id"}
        normalised = _lists(mine)
        assert normalised == expected, (line, answer, mine)
        compared += 1
    assert compared == len(lines) == 1400


def _lists(value):
    """Tuples as lists, as JSON has them."""
    if isinstance(value, dict):
        return {k: _lists(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_lists(v) for v in value]
    return value


def test_bad_lines_fail_the_same_way_in_both(quack_bin):
    """The same bad shape gives the same message from the module and the program."""
    bad = [{"type": "circle", "radius": -1}, {"type": "polygon", "points": [[0, 0], [1, 0]]},
           {"type": "box", "half": [1, 0], "radius": 0}, {"type": "circle", "radius": 1, "x": 0}]
    answers = run_queries(quack_bin, [{"id": i, "op": "overlap", "a": s, "b": s}
                                      for i, s in enumerate(bad)])
    for shape, answer in zip(bad, answers):
        with pytest.raises(ValueError) as error:
            quack.shape(shape)
        # The program names the field under "a"; the module under "shape".
        assert answer["error"].replace("a.", "shape.", 1).replace("a:", "shape:", 1) == str(error.value)
