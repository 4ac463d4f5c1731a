"""quack.d3.World: the 3D world from Python. Free fall against the integrator's closed form,
a ball and a box at rest on a box and on a mesh (heights from the geometry), mass and
impulses against the formulas for a ball, stale and foreign handles, every bad argument
named, the same bits on two runs, begin and end events, the bulk state, and the GIL
released while a world steps; queries (rays, boxes, shape overlaps and casts) against
hand-worked answers and against a loop over each shape's own quack.d3 query; snapshots
restored to the same bits, and bad ones refused with World3's message; docs/python.md's
example run and typed."""

import math
import os
import re
import subprocess
import sys
import threading

import numpy as np
import pytest

import quack
from quack import d3

G = 10.0
DT = 1 / 60


def ground_world(**world_args):
    """A static box ground, top face at y = 0."""
    w = d3.World(**world_args)
    ground = w.create_body(type="static", position=(0, -0.5, 0))
    ground_shape = w.create_shape(ground, d3.box(half=(10, 0.5, 10)))
    return w, ground, ground_shape


def test_free_fall_matches_the_closed_form():
    """Semi-implicit Euler over n sub-steps of h from rest (each sub-step moves by the new
    velocity): v = -g n h and y = y0 - g h^2 n (n + 1) / 2, which is the exact fall
    -g t^2 / 2 and g h t / 2 further: halving h halves the gap."""
    gaps = []
    for substeps in (4, 8):
        w = d3.World(gravity=(0, -G, 0), dt=DT, substeps=substeps)
        ball = w.create_body(position=(1, 100, -2))
        w.create_shape(ball, d3.sphere(radius=0.5), density=1000)
        steps = 90
        for _ in range(steps):
            w.step()
        n = steps * substeps
        h = np.float32(DT) / substeps
        t = steps * float(np.float32(DT))
        x, y, z = ball.position
        assert (x, z) == (1.0, -2.0)
        assert ball.linear_velocity[0] == 0 and ball.linear_velocity[2] == 0
        assert ball.linear_velocity[1] == pytest.approx(-G * n * h, rel=1e-5)
        assert y == pytest.approx(100 - G * h * h * n * (n + 1) / 2, abs=2e-4)
        exact = 100 - G * t * t / 2
        assert exact - y == pytest.approx(G * h * t / 2, rel=0.02)
        gaps.append(y - exact)
        assert ball.angular_velocity == (0.0, 0.0, 0.0)
        assert ball.rotation == (0.0, 0.0, 0.0, 1.0)
    assert gaps[1] == pytest.approx(gaps[0] / 2, rel=0.02)


def test_mass_and_inertia_of_a_ball():
    w = d3.World()
    ball = w.create_body(position=(0, 1, 0))
    w.create_shape(ball, d3.sphere(radius=0.25), density=1000)
    m = 1000 * 4 / 3 * math.pi * 0.25**3
    assert ball.mass == pytest.approx(m, rel=1e-5)
    inertia = np.array(ball.inertia)
    assert inertia == pytest.approx(np.eye(3) * 0.4 * m * 0.25**2, rel=1e-5, abs=1e-9)
    assert ball.center_of_mass == (0.0, 1.0, 0.0)
    assert ball.type == "dynamic"
    ground = w.create_body(type="static")
    assert ground.mass == 0 and ground.type == "static"


def test_a_ball_comes_to_rest_on_a_box_ground():
    w, ground, ground_shape = ground_world()
    ball = w.create_body(position=(0.3, 2, -0.2))
    ball_shape = w.create_shape(ball, d3.sphere(radius=0.25), density=1000)
    assert w.body_count == 2 and w.shape_count == 2 and w.contact_count == 0
    for _ in range(120):
        w.step()
    # Resting: the centre one radius above the top face (within the solver's slop, 5 mm).
    x, y, z = ball.position
    assert y == pytest.approx(0.25, abs=0.005)
    assert (x, z) == pytest.approx((0.3, -0.2), abs=1e-4)
    assert np.linalg.norm(ball.linear_velocity) < 0.01
    assert w.contact_count == 1
    [contact] = w.touching_contacts()
    assert (contact.shape_a, contact.shape_b) == (ground_shape, ball_shape)
    [manifold] = contact.manifolds
    assert manifold.normal == pytest.approx((0, 1, 0), abs=1e-6)
    [point] = manifold.points
    assert point.point == pytest.approx((0.3, 0, -0.2), abs=0.005)
    assert abs(point.separation) < 0.005
    # Then it falls asleep (enable_sleep is on by default), and a write wakes it.
    for _ in range(120):
        w.step()
    assert not ball.awake and w.awake_body_count == 0
    ball.linear_velocity = (1, 0, 0)
    assert ball.awake and w.awake_body_count == 1
    ball.awake = False
    assert not ball.awake and ball.linear_velocity == (0.0, 0.0, 0.0)


def test_a_box_rests_flat_and_a_ball_rests_on_a_mesh():
    w = d3.World()
    tilted = (0, math.sin(0.3), 0, math.cos(0.3))  # 0.6 rad about y: still face down
    box = w.create_body(position=(0, 1, 0), rotation=tilted)
    w.create_shape(box, d3.box(half=(0.5, 0.25, 0.5)))
    floor = w.create_body(type="static")
    mesh = d3.mesh(np.array([[-5, 0, -5], [5, 0, -5], [5, 0, 5], [-5, 0, 5]], float),
                   np.array([[0, 2, 1], [0, 3, 2]]))
    floor_shape = w.create_shape(floor, mesh)
    ball = w.create_body(position=(3, 1, 3))
    ball_shape = w.create_shape(ball, d3.sphere(radius=0.5))
    for _ in range(150):
        w.step()
    assert box.position[1] == pytest.approx(0.25, abs=0.005)
    assert np.array(box.rotation) == pytest.approx(tilted, abs=1e-3)
    assert ball.position[1] == pytest.approx(0.5, abs=0.005)
    pairs = {(c.shape_a, c.shape_b) for c in w.touching_contacts()}
    assert (floor_shape, ball_shape) in pairs  # the mesh is shape a


def test_impulses_against_the_formulas():
    w = d3.World(gravity=(0, 0, 0))
    ball = w.create_body()
    w.create_shape(ball, d3.sphere(radius=0.5), density=2)
    m = ball.mass
    ball.apply_impulse((3, 0, 0))
    assert ball.linear_velocity == pytest.approx((3 / m, 0, 0), rel=1e-6)
    assert ball.angular_velocity == (0.0, 0.0, 0.0)
    # Off the centre: w = I^-1 (r x J) with I = 2/5 m r^2 for a solid ball.
    ball.apply_impulse((0, 0, 1), point=(0, 0.5, 0))
    i = 0.4 * m * 0.25
    assert ball.angular_velocity == pytest.approx((0.5 / i, 0, 0), rel=1e-5)
    assert ball.linear_velocity == pytest.approx((3 / m, 0, 1 / m), rel=1e-6)
    ball.set_transform((1, 2, 3), (0, 0, 2, 0))  # normalised: half a turn about z
    assert ball.position == (1.0, 2.0, 3.0) and ball.rotation == (0.0, 0.0, 1.0, 0.0)
    ball.angular_velocity = (0, 1, 0)
    assert ball.angular_velocity == (0.0, 1.0, 0.0)


def test_continuous_collision_stops_a_fast_ball_at_a_mesh_floor():
    # 100 m/s from 1.1 m above a one-sided floor (beyond the 1 m speculative reach): it
    # falls through without continuous collision and stops on the floor with it.
    floor = d3.mesh(np.array([[-20, 0, -20], [-20, 0, 20], [20, 0, 20], [20, 0, -20]], float),
                    np.array([[0, 1, 2], [0, 2, 3]]))
    lowest = {}
    for continuous in (False, True):
        w = d3.World(enable_continuous=continuous)
        w.create_shape(w.create_body(type="static"), floor)
        ball = w.create_body(position=(0.3, 1.35, -0.2), linear_velocity=(0, -100, 0))
        w.create_shape(ball, d3.sphere(radius=0.25))
        low = ball.position[1]
        for _ in range(60):
            w.step()
            low = min(low, ball.position[1])
        lowest[continuous] = low
    assert lowest[False] < -1.0
    assert lowest[True] > 0.24


def test_a_stale_handle_raises():
    w, ground, ground_shape = ground_world()
    ball = w.create_body(position=(0, 2, 0))
    shape = w.create_shape(ball, d3.sphere(radius=0.25))
    assert ball.valid and shape.valid and shape.body == ball
    w.destroy_body(ball)
    assert not ball.valid and not shape.valid
    assert "stale" in repr(ball) and "stale" in repr(shape)
    assert w.body_count == 1 and w.bodies == [ground]
    for read in (lambda: ball.position, lambda: ball.rotation, lambda: ball.mass,
                 lambda: ball.awake, lambda: ball.linear_velocity):
        with pytest.raises(ValueError,
                           match=r"^stale quack.d3.BodyHandle \(the body was destroyed\)$"):
            read()
    with pytest.raises(ValueError, match="stale quack.d3.BodyHandle"):
        ball.linear_velocity = (1, 0, 0)
    with pytest.raises(ValueError, match="stale quack.d3.BodyHandle"):
        ball.apply_impulse((1, 0, 0))
    with pytest.raises(ValueError, match="stale quack.d3.ShapeHandle"):
        shape.body  # noqa: B018
    with pytest.raises(ValueError, match=r"^body: stale handle \(the body was destroyed\)"):
        w.destroy_body(ball)
    with pytest.raises(ValueError, match=r"^body: stale handle"):
        w.create_shape(ball, d3.sphere(radius=0.25))
    with pytest.raises(ValueError, match=r"^shape: stale handle \(the shape was destroyed\)"):
        w.destroy_shape(shape)
    # A new body may take the slot: the old handle stays stale (the generation moved on).
    again = w.create_body()
    assert not ball.valid and again.valid and again != ball
    other = d3.World()
    with pytest.raises(ValueError, match=r"^body: a body of another world"):
        other.create_shape(again, d3.sphere(radius=1))
    with pytest.raises(ValueError, match=r"^shape: a shape of another world"):
        other.destroy_shape(ground_shape)
    with pytest.raises(ValueError, match=r"^body: must be a quack.d3.BodyHandle"):
        w.create_shape("ground", d3.sphere(radius=1))


@pytest.mark.parametrize("call, message", [
    (lambda: d3.World(dt=0), r"^dt: must be in \(0, kMaxTimeStep\], got 0"),
    (lambda: d3.World(dt=2), r"^dt: must be in \(0, kMaxTimeStep\]"),
    (lambda: d3.World(substeps=0), r"^substeps: must be an integer in 1\.\.64, got 0"),
    (lambda: d3.World(contact_hertz=-1), r"^contact_hertz: must be finite and > 0"),
    (lambda: d3.World(contact_damping_ratio=-1), r"^contact_damping_ratio: must be"),
    (lambda: d3.World(contact_push_max_speed=0), r"^contact_push_max_speed: must be"),
    (lambda: d3.World(restitution_threshold=-1), r"^restitution_threshold: must be"),
    (lambda: d3.World(speculative_distance=2), r"^speculative_distance: must be in \[0, 1\]"),
    (lambda: d3.World(aabb_margin=0), r"^aabb_margin: must be finite and >= speculative"),
    (lambda: d3.World(contact_recycle_distance=-1),
     r"^contact_recycle_distance: must be in \[0, 1\] m"),
    (lambda: d3.World(gravity=(0, math.nan, 0)), r"^gravity\[1\]: must be finite"),
    (lambda: d3.World(gravity=(0, -10)), r"^gravity: must be a vector \(x, y, z\)"),
    (lambda: d3.World(gravity=(0, 1e5, 0)), r"^gravity: must be finite, each component"),
    (lambda: d3.World(enable_sleep=1), r"^enable_sleep: must be True or False, not a int"),
    (lambda: d3.World(enable_continuous=0),
     r"^enable_continuous: must be True or False, not a int"),
    (lambda: d3.World(dt="fast"), r"^dt: must be a number, not a str"),
])
def test_a_bad_world_argument_is_named(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_a_bad_body_or_shape_argument_is_named():
    w, ground, _ = ground_world()
    ball = w.create_body()
    for kwargs, message in [
        ({"type": "wobbly"}, r'^type: unknown body type "wobbly"'),
        ({"position": (0, math.inf, 0)}, r"^position\[1\]: must be finite"),
        ({"position": (6e8, 0, 0)}, r"^position: must be finite and within kMaxCoordinate / 2"),
        ({"rotation": (0, 0, 0, 0)}, r"^rotation: the quaternion \(qx, qy, qz, qw\) is zero"),
        ({"rotation": (0, 0, 1)}, r"^rotation: must be a quaternion \(qx, qy, qz, qw\)"),
        ({"linear_velocity": (1e6, 0, 0)}, r"^linear_velocity: must be finite, at most"),
        ({"angular_velocity": (0, 0, 2e9)}, r"^angular_velocity\[2\]: 2e\+09 rad/s is beyond"),
        ({"linear_damping": -1}, r"^linear_damping: must be finite and >= 0"),
        ({"angular_damping": True}, r"^angular_damping: must be a number, not a bool"),
        ({"gravity_scale": 1e4}, r"^gravity_scale: must be finite, within"),
        ({"sleep_threshold": -1}, r"^sleep_threshold: must be finite and >= 0"),
        ({"enable_sleep": None}, r"^enable_sleep: must be True or False"),
    ]:
        with pytest.raises(ValueError, match=message):
            w.create_body(**kwargs)
    for kwargs, message in [
        ({"density": -1}, r"^density: must be finite and >= 0, got -1"),
        ({"friction": math.nan}, r"^friction: must be finite and >= 0"),
        ({"restitution": 11}, r"^restitution: must be in \[0, kMaxRestitution\]"),
        ({"rolling_resistance": -0.5}, r"^rolling_resistance: must be finite and >= 0"),
    ]:
        with pytest.raises(ValueError, match=message):
            w.create_shape(ball, d3.sphere(radius=1), **kwargs)
    assert w.shape_count == 1  # nothing was made
    mesh = d3.mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 0, 1]], float), np.array([[0, 2, 1]]))
    with pytest.raises(ValueError, match="^createShape: mesh: a triangle mesh may only be put "
                                         "on a static body"):
        w.create_shape(ball, mesh)
    with pytest.raises(ValueError, match=r"^shape: a 2D quack.Shape in a 3D world"):
        w.create_shape(ball, quack.circle(radius=1))
    with pytest.raises(ValueError, match=r"^shape: must be a quack.d3.Shape or a quack.d3.Mesh"):
        w.create_shape(ball, {"type": "sphere", "radius": 1})
    with pytest.raises(ValueError, match=r"^step: dt: must be in \(0, kMaxTimeStep\]"):
        w.step(-1.0, 4)
    with pytest.raises(ValueError, match=r"^substeps: must be an integer in 1\.\.64, got 65"):
        w.step(substeps=65)
    with pytest.raises(ValueError, match=r"^setLinearVelocity: body: a static body"):
        ground.linear_velocity = (1, 0, 0)
    with pytest.raises(ValueError, match=r"^applyLinearImpulse: body: not dynamic"):
        ground.apply_impulse((1, 0, 0))
    with pytest.raises(ValueError, match=r"^awake: must be True or False, not a int"):
        ball.awake = 1
    with pytest.raises(ValueError, match=r"^impulse\[0\]: must be finite"):
        ball.apply_impulse((math.nan, 0, 0))
    with pytest.raises(ValueError, match=r"^setTransform: position: must be finite and within"):
        ball.position = (0, 7e8, 0)
    with pytest.raises(ValueError, match=r"^rotation\[3\]: must be finite"):
        ball.rotation = (0, 0, 0, math.inf)
    assert w.step_count == 0  # the refused steps did not count
    # Nothing changed through all of that.
    assert ball.position == (0.0, 0.0, 0.0) and ball.rotation == (0.0, 0.0, 0.0, 1.0)
    assert ball.linear_velocity == (0.0, 0.0, 0.0)


def test_huge_quaternion_components_are_normalised():
    """Read as floats and normalised in double (as quack.d3 poses are): 1e30 squared would
    overflow a float."""
    w = d3.World()
    b = w.create_body(rotation=(0, 1e30, 0, 1e30))
    h = math.sqrt(0.5)
    assert b.rotation == pytest.approx((0, h, 0, h), rel=1e-6)


def pile(seed, **world_args):
    """Ground and a pile of spheres, boxes, capsules and hulls at random poses."""
    rng = np.random.default_rng(seed)
    w, _, _ = ground_world(**world_args)
    shapes = [d3.sphere(radius=0.3), d3.box(half=(0.3, 0.2, 0.25)),
              d3.capsule((0, -0.2, 0), (0, 0.2, 0), 0.2),
              d3.hull(rng.normal(size=(12, 3)) * 0.3)]
    for i in range(24):
        q = rng.normal(size=4)
        b = w.create_body(position=(rng.uniform(-1, 1), 0.6 + 0.5 * i, rng.uniform(-1, 1)),
                          rotation=q, angular_velocity=rng.uniform(-2, 2, size=3))
        w.create_shape(b, shapes[i % 4], friction=0.5, restitution=0.1,
                       rolling_resistance=0.02)
    return w


def test_the_same_bits_on_two_runs():
    runs = []
    for _ in range(2):
        w = pile(7)
        for _ in range(150):
            w.step()
        runs.append(w.body_state().copy())
    assert runs[0].tobytes() == runs[1].tobytes()
    # The pile really moved and settled on the ground (not a trivially equal state). A random
    # hull need not hold its body's origin, so an origin may sit a little below the ground
    # (measured: 4.5 mm below, the hull's lowest vertex 0.3 mm above); one that fell through
    # would be metres down.
    assert runs[0][1:, 1].max() < 6 and runs[0][1:, 1].min() > -0.1
    # step(dt, substeps) with the world's own values is step().
    w = pile(7)
    for _ in range(150):
        w.step(np.float32(DT), 4)
    assert w.body_state().tobytes() == runs[0].tobytes()
    # A control: another pile differs.
    w = pile(8)
    for _ in range(150):
        w.step()
    assert w.body_state().tobytes() != runs[0].tobytes()


def test_begin_and_end_events():
    w, ground, ground_shape = ground_world()
    ball = w.create_body(position=(0, 1, 0))
    ball_shape = w.create_shape(ball, d3.sphere(radius=0.25))
    events = d3.World().events()
    assert events == d3.Events([], []) and isinstance(events, tuple)
    began_at = None
    for step in range(60):
        w.step()
        e = w.events()
        assert e.end == []
        if e.begin:
            assert began_at is None  # once: no bounce without restitution
            assert e.begin == [(ground_shape, ball_shape)]
            began_at = step
            # A contact begins when it gains points: within the speculative distance
            # (which grows with the closing speed) of the ground, at most a step's fall.
            assert 0.25 - 0.005 <= ball.position[1] <= 0.25 + 0.02 - ball.linear_velocity[1] * DT
    assert began_at is not None and 20 < began_at < 40  # a 0.75 m fall takes 0.39 s
    # Thrown up, it leaves: the contact ends once the gap passes the speculative distance
    # (0.02 m) and the closing allowance of the step (the speed times dt).
    ball.linear_velocity = (0, 5, 0)
    ends = []
    for step in range(10):
        w.step()
        if w.events().end:
            ends.append(step)
            assert w.events().end == [(ground_shape, ball_shape)] and w.contact_count == 0
            gap = ball.position[1] - 0.25
            assert gap > 0.02 + 4 * DT
            assert gap < 0.02 + 2 * 5 * DT + 5 * DT  # within a step of passing the allowance
    assert len(ends) == 1 and ends[0] <= 3
    # Back down, then its shape is destroyed while touching: an end with a stale handle.
    for _ in range(120):
        w.step()
    assert w.contact_count == 1
    w.destroy_shape(ball_shape)
    w.step()
    [(a, b)] = w.events().end
    assert a == ground_shape and b == ball_shape and not b.valid
    assert w.contact_count == 0 and w.shape_count == 1


def test_body_state_matches_the_handles_and_writes_all_or_none():
    w = pile(3)
    for _ in range(30):
        w.step()
    state = w.body_state()
    assert state.shape == (w.body_count, 13) and state.dtype == np.float64
    assert d3.BODY_STATE_COLUMNS == ("x", "y", "z", "qx", "qy", "qz", "qw", "vx", "vy", "vz",
                                     "wx", "wy", "wz")
    assert not state.flags.writeable
    assert w.body_state() is state  # shared until the next step or write
    for row, b in zip(state, w.bodies):
        assert tuple(row[0:3]) == b.position and tuple(row[3:7]) == b.rotation
        assert tuple(row[7:10]) == b.linear_velocity and tuple(row[10:13]) == b.angular_velocity
    w.bodies[2].linear_velocity = (0, 1, 0)
    fresh = w.body_state()
    assert fresh is not state and fresh[2, 8] == 1.0 and state[2, 8] != 1.0

    # A round trip, bit for bit: World3 keeps a rotation that is already unit to rounding.
    def same_state(a, b):
        return np.array_equal(a, b)

    saved = fresh.copy()
    w.set_body_state(saved)
    assert same_state(w.body_state(), saved)
    # A written row read back.
    new = saved.copy()
    new[1, 0:3] = (4, 5, 6)
    new[1, 3:7] = (0, 0, 0, 3)  # normalised
    new[1, 7:13] = (1, 2, 3, 0.5, 0, 0)
    new[0, 7:13] = 9  # the static ground keeps zero velocities
    w.set_body_state(new)
    got = w.body_state()
    assert tuple(got[1]) == (4, 5, 6, 0, 0, 0, 1, 1, 2, 3, 0.5, 0, 0)
    assert np.all(got[0, 7:13] == 0)
    assert same_state(got[2:], new[2:])

    # A row World3 refuses (6e8 m: within the coordinate limit, beyond World3's half of it):
    # nothing is written.
    bad = saved.copy()
    bad[5, 1] = 6e8
    with pytest.raises(ValueError, match=r"^state\[5\]: setTransform: position: must be"):
        w.set_body_state(bad)
    assert same_state(w.body_state(), got)
    bad = saved.copy()
    bad[3, 3:7] = 0
    with pytest.raises(ValueError, match=r"^state\[3\]: the quaternion .* is zero"):
        w.set_body_state(bad)
    bad = saved.copy()
    bad[4, 12] = math.nan
    with pytest.raises(ValueError, match=r"^state\[4\]\[12\]: must be finite"):
        w.set_body_state(bad)
    with pytest.raises(ValueError, match=r"^state: must be a numpy array of shape \(25, 13\)"):
        w.set_body_state(saved[:, :7])
    assert same_state(w.body_state(), got)


def test_the_gil_is_released_while_a_world_steps():
    """Another thread runs while a world steps, and its calls on that world are refused."""
    w = pile(5)
    done = threading.Event()
    refused = []
    spins = 0

    def stepper():
        for _ in range(60):
            w.step()
        done.set()

    t = threading.Thread(target=stepper)
    t.start()
    while not done.is_set():
        spins += 1
        try:
            w.body_count  # noqa: B018
        except RuntimeError as e:
            refused.append(str(e))
    t.join()
    assert spins > 60 and refused
    assert refused[0] == "quack.d3.World: the world is stepping (in another thread)"
    assert w.step_count == 60 and w.body_count == 25


def test_handles_compare_and_hash():
    w = d3.World()
    a = w.create_body()
    assert w.bodies[0] == a and hash(w.bodies[0]) == hash(a) and a.world is w
    assert len({a, w.bodies[0]}) == 1
    assert repr(a) == "quack.d3.BodyHandle(index=0, generation=1)"
    assert repr(w) == "quack.d3.World(bodies=1, shapes=0, steps=0)"


# ---- queries ----------------------------------------------------------------------------

def square_mesh():
    """The square -1..1 in x and z at y = 0, fronts up: triangle 0 holds z > x, 1 z < x.
    (b - a) x (c - a) for triangle 0, (-1, 0, -1) (-1, 0, 1) (1, 0, 1): (0, 4, 0), up."""
    v = np.array([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]], float)
    return d3.mesh(v, np.array([[0, 3, 2], [0, 2, 1]]))


def test_a_ray_down_onto_the_ground_at_the_hand_worked_fraction():
    w, ground, ground_shape = ground_world()
    # From y = 3 down by 4: the top face y = 0 after 3 of the 4 metres.
    hit = w.ray_cast_closest((1, 3, 2), (0, -4, 0))
    assert isinstance(hit, d3.RayHit)
    assert hit.shape == ground_shape and hit.body == ground
    assert hit.fraction == pytest.approx(0.75, abs=1e-6)
    assert hit.point == pytest.approx((1, 0, 2), abs=1e-5)
    assert hit.normal == pytest.approx((0, 1, 0), abs=1e-6)
    assert hit.triangle == -1
    # Slanted: (0, 2, 0) + t (2, -4, 0) meets y = 0 at t = 1/2, x = 1.
    hit = w.ray_cast_closest((0, 2, 0), (2, -4, 0))
    assert hit.fraction == pytest.approx(0.5, abs=1e-6)
    assert hit.point == pytest.approx((1, 0, 0), abs=1e-5)
    # Short of the ground, a zero translation, from inside, and all of them in ray_cast_all.
    assert w.ray_cast_closest((1, 3, 2), (0, -2.9, 0)) is None
    assert w.ray_cast_closest((1, 3, 2), (0, 0, 0)) is None
    assert w.ray_cast_closest((0, -0.5, 0), (0, 5, 0)) is None
    assert w.ray_cast_all((1, 3, 2), (0, -2.9, 0)) == []
    # A ball above the ground: the closest is the ball (top at y = 1.5), all gives both.
    ball = w.create_body(position=(0, 1, 0))
    ball_shape = w.create_shape(ball, d3.sphere(radius=0.5))
    hits = w.ray_cast_all((0, 3, 0), (0, -4, 0))
    assert [h.shape for h in hits] == [ball_shape, ground_shape]
    assert [h.fraction for h in hits] == pytest.approx([1.5 / 4, 3 / 4], abs=1e-6)
    assert w.ray_cast_closest((0, 3, 0), (0, -4, 0)) == hits[0]


def test_a_one_sided_mesh_is_hit_from_the_front_and_passed_from_behind():
    w = d3.World()
    body = w.create_body(type="static", position=(0, 1, 0))
    mesh = w.create_shape(body, square_mesh())
    # Down from y = 3 by 4 onto the front at y = 1: fraction 1/2, in triangle 1 (z < x).
    hit = w.ray_cast_closest((0.5, 3, 0.2), (0, -4, 0))
    assert hit.shape == mesh and hit.body == body
    assert hit.fraction == pytest.approx(0.5, abs=1e-6)
    assert hit.point == pytest.approx((0.5, 1, 0.2), abs=1e-5)
    assert hit.normal == pytest.approx((0, 1, 0), abs=1e-6)
    assert hit.triangle == 1
    assert w.ray_cast_closest((-0.5, 3, 0.2), (0, -4, 0)).triangle == 0  # z > x
    # From behind (below, going up) the same line passes through.
    assert w.ray_cast_closest((0.5, -1, 0.2), (0, 4, 0)) is None
    assert w.ray_cast_all((0.5, -1, 0.2), (0, 4, 0)) == []
    # Beside the square: nothing.
    assert w.ray_cast_closest((1.5, 3, 0.2), (0, -4, 0)) is None


def test_filters_keep_and_skip_shapes_as_their_categories_and_masks_say():
    """A shape is met when its category is in the query's mask and the query's category in
    its mask (each side's bits in the other's)."""
    w, ground, ground_shape = ground_world()  # category 1, mask all
    crate = w.create_body(type="static", position=(0, 1, 0))
    all_but_4 = quack.ALL_CATEGORIES & ~4
    crate_shape = w.create_shape(crate, d3.box(half=(0.5, 0.5, 0.5)), category=2,
                                 mask=all_but_4)
    origin, down = (0, 3, 0), (0, -4, 0)
    # Top down: the crate (y 0.5..1.5), then the ground (top at 0).
    filters = ((crate_shape, 2, all_but_4), (ground_shape, 1, quack.ALL_CATEGORIES))

    def met(category, mask):
        return [h.shape for h in w.ray_cast_all(origin, down, category=category, mask=mask)]

    for category, mask in [(1, quack.ALL_CATEGORIES), (1, 1), (1, 2), (4, 3), (8, 6), (4, 0),
                           (2, 1), (5, 2)]:
        expected = [s for s, cat, msk in filters if cat & mask and category & msk]
        assert met(category, mask) == expected, (category, mask)
        closest = w.ray_cast_closest(origin, down, category=category, mask=mask)
        assert (closest.shape if closest else None) == (expected[0] if expected else None)
        boxes = w.overlap_aabb((-1, -2, -1), (1, 3, 1), category=category, mask=mask)
        assert boxes == [s for s in (ground_shape, crate_shape) if s in expected]  # by index
        overlaps = w.overlap_shape(d3.box(half=(2, 2, 2)), (0, 0, 0), category=category,
                                   mask=mask)
        assert {o.shape for o in overlaps} == set(expected)
        cast = w.cast_shape(d3.sphere(radius=0.25), (0, 3, 0), down, category=category,
                            mask=mask)
        assert (cast.shape if cast else None) == (expected[0] if expected else None)
    assert met(1, 2) == [crate_shape] and met(4, 3) == [ground_shape]


def test_overlap_aabb_gives_the_shapes_whose_boxes_meet_the_box():
    w, ground, ground_shape = ground_world()  # box -10..10, -1..0, -10..10
    ball = w.create_body(type="static", position=(3, 2, 0))
    ball_shape = w.create_shape(ball, d3.sphere(radius=0.5))  # box 2.5..3.5, 1.5..2.5
    assert w.overlap_aabb((-1, -1, -1), (1, 1, 1)) == [ground_shape]
    assert w.overlap_aabb((2, 1, -1), (4, 3, 1)) == [ball_shape]
    assert w.overlap_aabb((-20, -20, -20), (20, 20, 20)) == [ground_shape, ball_shape]
    assert w.overlap_aabb((0, 5, 0), (1, 6, 1)) == []


def test_overlap_shape_depth_and_depenetration_by_hand():
    w, ground, ground_shape = ground_world()
    # A sphere of radius 0.5 centred 0.3 above the top face reaches 0.2 below it: out by
    # moving 0.2 up.
    over = w.overlap_shape(d3.sphere(radius=0.5), (2, 0.3, -1))
    assert len(over) == 1 and isinstance(over[0], d3.ShapeOverlap)
    assert over[0].shape == ground_shape and over[0].body == ground
    assert over[0].depth == pytest.approx(0.2, abs=1e-4)
    assert over[0].depenetration == pytest.approx((0, 0.2, 0), abs=1e-4)
    # Two spheres: radii 1 and 0.5, centres 1.2 apart along z: 0.3 deep, out along +z.
    ball = w.create_body(position=(5, 5, 5))
    ball_shape = w.create_shape(ball, d3.sphere(radius=1))
    over = w.overlap_shape(d3.sphere(radius=0.5), (5, 5, 6.2, 0, 0, 0, 1))
    assert [o.shape for o in over] == [ball_shape] and over[0].body == ball
    assert over[0].depth == pytest.approx(0.3, abs=1e-4)
    assert over[0].depenetration == pytest.approx((0, 0, 0.3), abs=1e-4)
    # A turned query box (45 degrees about z) standing on an edge 0.1 into the ground: its
    # lowest edge is half * sqrt(2) below its centre.
    half = 0.5
    s = math.sin(math.pi / 8)
    y = half * math.sqrt(2) - 0.1
    over = w.overlap_shape(d3.box(half=(half, half, half)), (-3, y, 0, 0, 0, s,
                                                            math.cos(math.pi / 8)))
    assert [o.shape for o in over] == [ground_shape]
    assert over[0].depth == pytest.approx(0.1, abs=1e-4)
    assert over[0].depenetration == pytest.approx((0, 0.1, 0), abs=1e-4)
    # Apart: nothing.
    assert w.overlap_shape(d3.sphere(radius=0.5), (0, 0.6, 0)) == []


def test_overlap_shape_on_a_mesh_gives_its_deepest_triangle():
    w = d3.World()
    body = w.create_body(type="static")
    mesh = w.create_shape(body, square_mesh())
    over = w.overlap_shape(d3.sphere(radius=0.5), (0.2, 0.35, -0.3))
    assert [o.shape for o in over] == [mesh]
    assert over[0].depth == pytest.approx(0.15, abs=1e-4)
    assert over[0].depenetration == pytest.approx((0, 0.15, 0), abs=1e-4)


def test_cast_shape_fraction_by_hand():
    w, ground, ground_shape = ground_world()
    # A ball of radius 0.5 from y = 3 down by 4 touches the top face when its centre is at
    # y = 0.5: after 2.5 of the 4 metres. A hit is within 1e-4 m of touching
    # (kShapeCastTolerance), so at most 1e-4 / 4 early.
    hit = w.cast_shape(d3.sphere(radius=0.5), (1, 3, 1), (0, -4, 0))
    assert isinstance(hit, d3.ShapeCastHit)
    assert hit.shape == ground_shape and hit.body == ground
    assert 0.625 - 1e-4 / 4 - 1e-6 <= hit.fraction <= 0.625 + 1e-6
    assert hit.point == pytest.approx((1, 0, 1), abs=1e-3)
    assert hit.normal == pytest.approx((0, 1, 0), abs=1e-4)
    # A box (half height 0.25) sliding diagonally: its bottom reaches y = 0 when it has come
    # down 1.75 of the 3.5: fraction 1/2, whatever it does sideways.
    hit = w.cast_shape(d3.box(half=(0.3, 0.25, 0.3)), (0, 2, 0), (2, -3.5, 1))
    assert 0.5 - 1e-4 / 3.5 - 1e-6 <= hit.fraction <= 0.5 + 1e-6
    # Starting in the ground: fraction 0. Going up, or falling short: None.
    assert w.cast_shape(d3.sphere(radius=0.5), (0, 0.2, 0), (0, 1, 0)).fraction == 0
    assert w.cast_shape(d3.sphere(radius=0.5), (0, 3, 0), (0, 4, 0)) is None
    assert w.cast_shape(d3.sphere(radius=0.5), (0, 3, 0), (0, -2, 0)) is None


def random_scene(seed):
    """Static bodies with every kind of shape at random poses, and a mesh; no steps."""
    rng = np.random.default_rng(seed)
    w = d3.World()
    shapes = [d3.sphere(radius=0.4), d3.box(half=(0.5, 0.2, 0.3)),
              d3.capsule((0, -0.3, 0), (0, 0.3, 0), 0.2),
              d3.hull(rng.normal(size=(10, 3)) * 0.4),
              d3.triangle([(0, 0, 0), (0.8, 0, 0), (0, 0.6, 0.3)])]
    placed = []
    for i in range(30):
        body = w.create_body(type="static" if i % 3 else "dynamic",
                             position=rng.uniform(-3, 3, size=3), rotation=rng.normal(size=4))
        shape = shapes[i % len(shapes)]
        placed.append((w.create_shape(body, shape), shape, body))
    floor = w.create_body(type="static", position=(0, -3.5, 0), rotation=(0.1, 0, 0, 1))
    mesh = d3.mesh(np.array([[-4, 0, -4], [4, 0, -4], [4, 0, 4], [-4, 0, 4]], float),
                   np.array([[0, 3, 2], [0, 2, 1]]))
    placed.append((w.create_shape(floor, mesh), mesh, floor))
    return w, placed, rng


def test_ray_cast_closest_and_all_agree_with_each_shapes_own_raycast():
    """The world's answer against a loop over every shape with quack.d3.raycast at the
    body's pose: the least fraction (closest) and every shape entered (all)."""
    w, placed, rng = random_scene(11)
    hits = several = 0
    for _ in range(300):
        # Most rays aimed through a body's origin, some anywhere.
        origin = rng.uniform(-5, 5, size=3)
        aim = np.array(placed[rng.integers(len(placed))][2].position) + rng.normal(size=3) * 0.3
        translation = (aim - origin) * 1.5 if rng.uniform() < 0.8 else rng.normal(size=3) * 6
        brute = []
        for shape, geometry, body in placed:
            r = d3.raycast(geometry, body.position + body.rotation, origin, translation)
            if r.hit:
                brute.append((r.fraction, shape, r))
        brute.sort(key=lambda b: b[0])
        closest = w.ray_cast_closest(origin, translation)
        every = w.ray_cast_all(origin, translation)
        assert [h.shape for h in every] == [b[1] for b in brute]
        for h, (fraction, shape, r) in zip(every, brute):
            assert h.fraction == pytest.approx(fraction, abs=1e-5)
            assert h.point == pytest.approx(r.point, abs=1e-4)
            assert h.normal == pytest.approx(r.normal, abs=1e-4)
            assert h.triangle == getattr(r, "triangle", -1)
            assert h.body == shape.body
        if not brute:
            assert closest is None
            continue
        hits += 1
        several += len(brute) > 1
        assert closest == every[0]
    # Most rays met something, many several things: the lists compared are not empty.
    assert hits > 150 and several > 30


def test_cast_shape_agrees_with_each_shapes_own_shapecast():
    w, placed, rng = random_scene(12)
    query = d3.box(half=(0.2, 0.3, 0.1))
    hits = 0
    for _ in range(60):
        start = rng.uniform(-5, 5, size=3)
        pose = tuple(start) + tuple(rng.normal(size=4))
        aim = np.array(placed[rng.integers(len(placed))][2].position) + rng.normal(size=3) * 0.3
        translation = (aim - start) * 1.5 if rng.uniform() < 0.8 else rng.normal(size=3) * 4
        first = None
        for shape, geometry, body in placed:
            r = d3.shapecast(geometry, body.position + body.rotation, query, pose, translation)
            if r.hit and (first is None or r.fraction < first[0]):
                first = (r.fraction, shape)
        got = w.cast_shape(query, pose, translation)
        if first is None:
            assert got is None
            continue
        hits += 1
        assert got.shape == first[1] and got.fraction == pytest.approx(first[0], abs=1e-5)
    assert hits > 30


def test_a_bad_query_argument_is_named():
    w, _, _ = ground_world()
    mesh = square_mesh()
    for call, message in [
        (lambda: w.ray_cast_closest((0, math.nan, 0), (0, -1, 0)), r"^origin\[1\]: must be finite"),
        (lambda: w.ray_cast_all((0, 0, 0), (0, -1)), r"^translation: must be a vector \(x, y, z\)"),
        (lambda: w.ray_cast_closest((0, 0, 0), (0, 2e9, 0)),
         r"^translation\[1\]: 2e\+09 m is beyond the coordinate limit"),
        (lambda: w.overlap_aabb((0, 0, 0), (1, -1, 1)), r"^upper\[1\]: -1 is below lower\[1\] 0"),
        (lambda: w.overlap_aabb("box", (1, 1, 1)), r"^lower: must be a vector"),
        (lambda: w.overlap_shape(mesh, None), r"^shape: a quack.d3.Mesh cannot be a query shape"),
        (lambda: w.overlap_shape(quack.circle(radius=1), None), r"^shape: a 2D quack.Shape"),
        (lambda: w.cast_shape({"type": "sphere"}, None, (0, 1, 0)),
         r"^shape: must be a quack.d3.Shape, not a dict"),
        (lambda: w.overlap_shape(d3.sphere(radius=1), (0, 0, 0, 0, 0, 0, 0)),
         r"^pose: the quaternion \(qx, qy, qz, qw\) is zero"),
        (lambda: w.cast_shape(d3.sphere(radius=1), (0, 0), (0, 1, 0)),
         r"^pose: must be a pose \(x, y, z\) or \(x, y, z, qx, qy, qz, qw\)"),
        (lambda: w.cast_shape(d3.sphere(radius=1), None, (0, math.inf, 0)),
         r"^translation\[1\]: must be finite"),
    ]:
        with pytest.raises(ValueError, match=message):
            call()


def test_queries_skip_destroyed_shapes_and_hand_out_live_handles():
    w, ground, ground_shape = ground_world()
    ball = w.create_body(type="static", position=(0, 1, 0))
    ball_shape = w.create_shape(ball, d3.sphere(radius=0.5))
    assert w.ray_cast_closest((0, 3, 0), (0, -4, 0)).shape == ball_shape
    w.destroy_body(ball)
    hit = w.ray_cast_closest((0, 3, 0), (0, -4, 0))
    assert hit.shape == ground_shape and hit.shape.valid and hit.body.world is w
    assert w.overlap_aabb((-1, 0.6, -1), (1, 2, 1)) == []


# ---- snapshots --------------------------------------------------------------------------

def test_a_restored_world_steps_on_to_the_same_bits():
    w = pile(7)
    for _ in range(40):
        w.step()
    snap = w.snapshot()
    assert isinstance(snap, bytes) and snap[:8] == b"QUACK3SN"
    at_snapshot = w.body_state().copy()
    for _ in range(60):
        w.step()
    ahead = w.body_state().copy()
    assert ahead.tobytes() != at_snapshot.tobytes()  # it moved on: not a trivial equality

    # The same world, put back: the same rows, then the same 60 steps give the same bits.
    w.restore(snap)
    assert w.step_count == 40
    assert w.body_state().tobytes() == at_snapshot.tobytes()
    for _ in range(60):
        w.step()
    assert w.body_state().tobytes() == ahead.tobytes()

    # Another world built the same way (its bodies have the same handles) but stepped
    # differently, restored from it (as a bytearray): the same bits again.
    other = pile(7)
    for _ in range(5):
        other.step(1 / 30, 2)
    other.restore(bytearray(snap))
    assert other.body_state().tobytes() == at_snapshot.tobytes()
    for _ in range(60):
        other.step()
    assert other.body_state().tobytes() == ahead.tobytes()
    assert other.snapshot() == w.snapshot()


def test_restore_brings_back_destroyed_bodies_and_their_handles():
    w, ground, ground_shape = ground_world()
    a = w.create_body(position=(0, 1, 0))
    w.create_shape(a, d3.sphere(radius=0.25))
    b = w.create_body(position=(2, 1, 0))
    b_shape = w.create_shape(b, d3.box(half=(0.2, 0.2, 0.2)))
    snap = w.snapshot()
    before = w.body_state().copy()
    w.destroy_body(a)
    c = w.create_body(position=(-2, 1, 0))  # takes a's slot, a new generation
    w.step()
    assert not a.valid and w.bodies == [ground, b, c]
    w.restore(snap)
    assert a.valid and b.valid and b_shape.valid and not c.valid
    assert w.bodies == [ground, a, b] and w.body_count == 3
    assert w.body_state().tobytes() == before.tobytes()
    assert a.position == (0.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="stale quack.d3.BodyHandle"):
        c.position  # noqa: B018
    # A snapshot with bodies this world never made (one of another world) is refused, and
    # the world is left as it was.
    lone = d3.World()
    with pytest.raises(ValueError, match=r"^snapshot: holds bodies this quack.d3.World did "
                                         r"not make"):
        lone.restore(snap)
    assert lone.body_count == 0 and lone.bodies == [] and lone.body_state().shape == (0, 13)


def test_bad_snapshot_bytes_are_refused_with_world3s_message():
    """The messages of docs/world3.md's format: the header "QUACK3SN", the version (u32 at
    byte 8), the payload length (u64 at 12) and its checksum (u64 at 20)."""
    w = pile(2)
    for _ in range(10):
        w.step()
    state = w.body_state().copy()
    snap = w.snapshot()
    other_version = bytearray(snap)
    other_version[8] = 2
    corrupted = bytearray(snap)
    corrupted[-1] ^= 0x40
    payload = len(snap) - 28
    for data, message in [
        (b"junk", "restore: snapshot: not a 3D world snapshot (no QUACK3SN header)"),
        (quack.World().snapshot(), "restore: snapshot: not a 3D world snapshot"),
        (bytes(other_version), "restore: snapshot: format version 2, this build reads version 1"),
        (snap[:-1], f"restore: snapshot: payload of {payload - 1} bytes, the header says "
                    f"{payload} (truncated?)"),
        (bytes(corrupted), "restore: snapshot: checksum mismatch (corrupted)"),
    ]:
        with pytest.raises(ValueError) as e:
            w.restore(data)
        assert str(e.value).startswith(message), str(e.value)
        assert w.body_state().tobytes() == state.tobytes()  # unchanged
    with pytest.raises(ValueError, match=r"^snapshot: must be bytes .*, not a str"):
        w.restore("QUACK3SN")
    assert w.step_count == 10


def _doc_block(source_dir):
    """The first Python block of docs/python.md's "The 3D world" section."""
    with open(os.path.join(source_dir, "docs", "python.md")) as f:
        text = f.read()
    section = text[text.index("## The 3D world: `quack.d3.World`"):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_the_doc_example_runs_and_agrees_with_the_closed_forms(source_dir):
    run = subprocess.run([sys.executable, "-c", _doc_block(source_dir)], capture_output=True,
                         text=True, check=False)
    assert run.returncode == 0, run.stderr
    m = re.search(r"landed in the step ending at (\d\.\d+) s; sqrt\(2 h / g\) = (\d\.\d+) s",
                  run.stdout)
    landed, closed = float(m.group(1)), float(m.group(2))
    assert closed == pytest.approx(math.sqrt(2 * 1.75 / G), abs=1e-3)
    assert landed - DT < closed <= landed + 1e-3  # the closed-form touch within that step
    m = re.search(r"resting at y = (-?\d\.\d+) m, awake: (\w+), mass (\d+\.\d+) kg", run.stdout)
    assert float(m.group(1)) == pytest.approx(0.25, abs=0.005)
    assert m.group(2) == "False"
    assert float(m.group(3)) == pytest.approx(1000 * 4 / 3 * math.pi * 0.25**3, abs=0.01)
    assert run.stdout.splitlines()[-1] == "(2, 13)"


def test_mypy_strict_types_the_doc_example_and_catches_a_wrong_call(source_dir, tmp_path):
    pytest.importorskip("mypy", reason="mypy is not installed (Debian python3-mypy)")
    good = tmp_path / "good.py"
    good.write_text(_doc_block(source_dir))
    bad = tmp_path / "bad.py"
    bad.write_text("from quack import d3\nw = d3.World()\nw.step(substeps='4')\n"
                   "p: float = w.create_body().position\n")
    env = dict(os.environ, MYPYPATH=os.path.join(source_dir, "python", "stubs"))
    for path, code in ((good, 0), (bad, 1)):
        run = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental",
                              "--cache-dir", str(tmp_path / "cache"), str(path)],
                             capture_output=True, text=True, env=env, check=False)
        assert run.returncode == code, run.stdout + run.stderr
    assert 'bad.py:3: error: Argument "substeps"' in run.stdout
    assert "bad.py:4: error: Incompatible types in assignment" in run.stdout
