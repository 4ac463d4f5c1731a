"""Batch queries: equal to the single-pair answers, broadcasting, errors, and the GIL
released while they run."""

import math
import random
import threading
import time

import numpy as np
import pytest

import quack
from conftest import random_pose, random_shape_dict

N = 400


def _inputs(seed, kinds=("circle", "capsule", "segment", "box", "polygon", "concave")):
    rng = random.Random(seed)
    shapes_a = [quack.shape(random_shape_dict(rng, kinds)) for _ in range(N)]
    shapes_b = [quack.shape(random_shape_dict(rng, kinds)) for _ in range(N)]
    poses_a = np.array([random_pose(rng) for _ in range(N)])
    poses_b = np.array([random_pose(rng) for _ in range(N)])
    return shapes_a, poses_a, shapes_b, poses_b


def _check_fields(batch, singles, fields):
    for name in fields:
        column = getattr(batch, name)
        assert len(column) == len(singles)
        for i, single in enumerate(singles):
            value = getattr(single, name)
            if name == "status":
                value = (quack.GJK_STATUSES if batch.kind == "distance"
                         else quack.EPA_STATUSES).index(value)
            # Bit for bit: the same float, widened to double on both sides.
            assert np.array_equal(column[i], np.asarray(value)), (name, i)


def test_distance_many_equals_distance():
    a, pa, b, pb = _inputs(1)
    batch = quack.distance_many(a, pa, b, pb)
    singles = [quack.distance(a[i], tuple(pa[i]), b[i], tuple(pb[i])) for i in range(N)]
    _check_fields(batch, singles, ["distance", "pointA", "pointB", "normal", "iterations", "status"])
    assert batch.distance.shape == (N,) and batch.pointA.shape == (N, 2)
    assert batch.point_a is batch.pointA and batch.point_b is batch.pointB
    assert (batch.distance == 0).any() and (batch.distance > 0).any()


def test_overlap_many_equals_overlap():
    a, pa, b, pb = _inputs(2)
    batch = quack.overlap_many(a, pa, b, pb)
    assert batch.overlap.dtype == np.bool_
    singles = [quack.overlap(a[i], tuple(pa[i]), b[i], tuple(pb[i])) for i in range(N)]
    _check_fields(batch, singles, ["overlap"])
    assert batch.overlap.any() and not batch.overlap.all()


def test_penetration_many_equals_penetration():
    a, pa, b, pb = _inputs(3)
    batch = quack.penetration_many(a, pa, b, pb)
    singles = [quack.penetration(a[i], tuple(pa[i]), b[i], tuple(pb[i])) for i in range(N)]
    _check_fields(batch, singles,
                  ["overlap", "depth", "normal", "pointA", "pointB", "iterations", "status"])


def test_batches_of_convex_shapes_equal_the_single_queries():
    # Every shape one convex piece on both sides: the batch forms each row's proxy once and
    # queries the proxies (the lists above hold concave shapes, which take the pieces path).
    a, pa, b, pb = _inputs(5, kinds=("circle", "capsule", "segment", "box", "polygon"))
    distance = quack.distance_many(a, pa, b, pb)
    _check_fields(distance, [quack.distance(a[i], tuple(pa[i]), b[i], tuple(pb[i]))
                             for i in range(N)],
                  ["distance", "pointA", "pointB", "normal", "iterations", "status"])
    overlap = quack.overlap_many(a, pa, b, pb)
    _check_fields(overlap, [quack.overlap(a[i], tuple(pa[i]), b[i], tuple(pb[i]))
                            for i in range(N)], ["overlap"])
    assert overlap.overlap.any() and not overlap.overlap.all()
    penetration = quack.penetration_many(a, pa, b, pb)
    _check_fields(penetration, [quack.penetration(a[i], tuple(pa[i]), b[i], tuple(pb[i]))
                                for i in range(N)],
                  ["overlap", "depth", "normal", "pointA", "pointB", "iterations", "status"])
    # One convex shape against a list, both ways round.
    one = quack.distance_many(a[0], pa, b, pb)
    singles = [quack.distance(a[0], tuple(pa[i]), b[i], tuple(pb[i])) for i in range(N)]
    _check_fields(one, singles, ["distance", "pointA", "pointB", "normal"])
    one = quack.distance_many(a, pa, b[0], pb)
    singles = [quack.distance(a[i], tuple(pa[i]), b[0], tuple(pb[i])) for i in range(N)]
    _check_fields(one, singles, ["distance", "pointA", "pointB", "normal"])


def test_raycast_many_equals_raycast():
    rng = random.Random(4)
    shapes = [quack.shape(random_shape_dict(rng)) for _ in range(N)]
    poses = np.array([random_pose(rng) for _ in range(N)])
    rays = np.array([[rng.uniform(-6, 6), rng.uniform(-6, 6), rng.uniform(-8, 8),
                      rng.uniform(-8, 8)] for _ in range(N)])
    batch = quack.raycast_many(shapes, poses, rays)
    singles = [quack.raycast(shapes[i], tuple(poses[i]), rays[i, :2], rays[i, 2:])
               for i in range(N)]
    _check_fields(batch, singles, ["hit", "fraction", "point", "normal"])
    assert batch.hit.any() and not batch.hit.all()


def test_one_shape_and_one_pose_serve_every_pair():
    circle, box = quack.circle(radius=0.5), quack.box(half=(1, 0.5))
    xs = np.linspace(1, 5, 9)
    poses_b = np.column_stack([xs, np.zeros_like(xs), np.zeros_like(xs)])
    batch = quack.distance_many(circle, np.zeros(3), box, poses_b)
    assert batch.distance == pytest.approx(np.maximum(xs - 1.5, 0))
    assert batch.to_dict().keys() >= {"distance", "pointA", "pointB", "normal"}
    # Broadcast rows equal explicit rows.
    explicit = quack.distance_many([circle] * 9, np.zeros((9, 3)), box, poses_b)
    assert np.array_equal(batch.distance, explicit.distance)
    rays = quack.raycast_many(box, poses_b, np.array([-10.0, 0.0, 20.0, 0.0]))
    assert rays.fraction == pytest.approx((xs - 1 + 10) / 20)


def test_float32_and_non_contiguous_arrays_are_read_as_given():
    box = quack.box(half=(1, 0.5))
    wide = np.zeros((5, 6))
    wide[:, 0] = np.arange(5) + 3.0
    poses = wide[:, ::2]  # (5, 3), not contiguous
    d64 = quack.distance_many(box, np.zeros(3), box, poses).distance
    d32 = quack.distance_many(box, np.zeros(3), box, poses.astype(np.float32)).distance
    assert d64 == pytest.approx(np.arange(5) + 1.0)
    assert np.array_equal(d32, d64)


@pytest.mark.parametrize("call, message", [
    (lambda c: quack.distance_many(c, np.zeros((3, 2)), c, np.zeros((3, 3))),
     r"poses_a: must be a numpy array of shape \(N, 3\) or \(3,\) .*, not \(3, 2\)"),
    (lambda c: quack.distance_many(c, np.zeros((3, 3)), c, np.zeros((4, 3))),
     r"poses_b: 4 rows, but poses_a has 3"),
    (lambda c: quack.distance_many([c, c], np.zeros((3, 3)), c, np.zeros((3, 3))),
     r"poses_a: 3 rows, but shapes_a has 2"),
    (lambda c: quack.overlap_many(c, "poses", c, np.zeros(3)), r"poses_a: must be a numpy array"),
    (lambda c: quack.overlap_many([c, 5], np.zeros((2, 3)), c, np.zeros(3)),
     r"shapes_a\[1\]: must be a quack.Shape"),
    (lambda c: quack.overlap_many([], np.zeros((2, 3)), c, np.zeros(3)),
     r"shapes_a: the list of shapes is empty"),
    (lambda c: quack.overlap_many(c, np.array([[0, 0, 0], [0, 0, np.nan]]), c, np.zeros(3)),
     r"poses_a\[1\]\[2\]: must be finite \(as a float\)"),
    (lambda c: quack.penetration_many(c, np.zeros(3), c, np.array([0, 3e9, 0])),
     r"poses_b\[1\]: 3e\+09 m is beyond the coordinate limit"),
    (lambda c: quack.raycast_many(c, np.zeros(3), np.zeros((2, 3))),
     r"rays: must be a numpy array of shape \(N, 4\)"),
    (lambda c: quack.raycast_many(c, np.zeros(3), np.array([[0, 0, 1, 0], [0, 0, np.inf, 0]])),
     r"rays\[1\]\[2\]: must be finite"),
])
def test_bad_batches_raise_value_error(call, message):
    with pytest.raises(ValueError, match=message):
        call(quack.circle(radius=0.5))


def _longest_stall_while(work):
    """Runs `work` in another thread and returns (how long the call took, the longest time
    this thread went without running meanwhile). A call that holds the GIL stalls this
    thread for its whole length; one that releases it, for no more than a scheduler slice."""
    timing = {}
    go = threading.Event()

    def worker():
        go.wait()  # start only once this thread is watching
        begin = time.perf_counter()
        work()
        timing["call"] = time.perf_counter() - begin

    t = threading.Thread(target=worker)
    t.start()
    longest, last = 0.0, time.perf_counter()
    go.set()
    while t.is_alive():
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
    t.join()
    return timing["call"], longest


def _check_gil_released(work):
    call, stall = _longest_stall_while(work)
    assert call > 0.05, f"the call took {call:.3f} s: too quick to tell"
    assert stall < call / 2, f"this thread stalled {stall:.3f} s of a {call:.3f} s call"


def test_the_gil_is_released_during_a_batch():
    rng = random.Random(5)
    poly = quack.polygon(points=[[1, 0], [0.3, 0.9], [-0.8, 0.6], [-0.8, -0.6], [0.3, -0.9]])
    poses_a = np.array([random_pose(rng) for _ in range(1000)] * 400)
    poses_b = poses_a[::-1].copy()
    _check_gil_released(lambda: quack.distance_many(poly, poses_a, poly, poses_b))


def test_the_check_sees_a_call_that_holds_the_gil():
    """The check above can fail: sorting a big list holds the GIL throughout."""
    data = [random.random() for _ in range(1_000_000)]
    call, stall = _longest_stall_while(lambda: sorted(data))
    assert call > 0.05 and stall >= call / 2, (call, stall)


@pytest.mark.parametrize("bad, kind", [
    (np.zeros((3, 3), dtype=complex), "complex128"),
    (np.zeros((3, 3), dtype=np.complex64), "complex64"),
    (np.zeros((3, 3), dtype=bool), "bool"),
    (np.array([["0", "0", "0"]] * 3), "<U1"),
    (np.array([[0, 0, None]] * 3), "object"),
])
def test_batches_refuse_complex_bool_and_string_poses(bad, kind):
    """Issue 28, item 10: complex poses were taken with their imaginary part dropped, and
    bool and string arrays were converted to numbers."""
    c = quack.circle(radius=0.5)
    for call, name in ((lambda: quack.distance_many(c, bad, c, np.zeros(3)), "poses_a"),
                       (lambda: quack.overlap_many(c, np.zeros(3), c, bad), "poses_b"),
                       (lambda: quack.raycast_many(c, bad, np.zeros(4)), "poses")):
        with pytest.raises(ValueError, match=rf"^{name}: must hold integers or floats, not {kind}"):
            call()
    # Integers of any width are numbers.
    got = quack.distance_many(c, np.array([[0, 0, 0]] * 3, dtype=np.uint8), c,
                              np.array([3, 0, 0], dtype=np.int64))
    assert got.distance.tolist() == [2.0, 2.0, 2.0]
