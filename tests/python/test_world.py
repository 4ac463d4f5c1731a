"""quack.World: bodies and shapes, stepping, bulk state, events, callbacks, stale handles,
world queries, scene and state files, agreement with C++, and reference counting."""

import gc
import math
import os
import re
import subprocess
import sys
import threading
import time
import tracemalloc

import numpy as np
import pytest

import quack


def ball_world(**world_args):
    """Ground (top at y = 0) and a ball of radius 0.5 dropped from y = 3."""
    w = quack.World(**world_args)
    ground = w.create_body(type="static", name="ground", pos=(0, -0.5))
    w.create_shape(ground, quack.box(half=(20, 0.5)), category=1)
    ball = w.create_body(pos=(0, 3), name="ball")
    w.create_shape(ball, quack.circle(radius=0.5), category=2)
    return w, ground, ball


def test_a_ball_falls_and_rests_on_the_ground():
    w, ground, ball = ball_world()
    assert w.body_count == 2 and w.shape_count == 2
    assert ball.type == "dynamic" and ground.type == "static"
    assert ball.name == "ball" and w.body("ground") == ground
    assert ball.mass == pytest.approx(math.pi * 0.25, rel=1e-5)
    w.step()
    assert ball.position[1] < 3 and ball.velocity[1] < 0
    for _ in range(179):
        w.step()
    w.validate()
    assert w.step_count == 180 and w.time == pytest.approx(3.0, rel=1e-5)
    assert ball.position[1] == pytest.approx(0.5, abs=0.01)
    assert abs(ball.velocity[1]) < 0.05
    assert w.contact_count == 1


def test_step_with_its_own_dt_and_substeps():
    w, _, ball = ball_world()
    w.step(0.1, 8)
    assert w.time == pytest.approx(0.1)
    # Free fall for 0.1 s: v = -1 m/s.
    assert ball.velocity[1] == pytest.approx(-1.0, rel=1e-4)
    with pytest.raises(ValueError, match="dt"):
        w.step(-1.0, 4)


def test_bulk_reads_match_the_handles():
    w, ground, ball = ball_world()
    for _ in range(10):
        w.step()
    positions = w.get_positions()
    assert positions.shape == (2, 2)
    assert tuple(positions[1]) == ball.position and tuple(positions[0]) == ground.position
    assert tuple(w.get_velocities([ball])[0]) == ball.velocity
    assert w.get_angles().shape == (2,)
    assert w.get_angular_velocities([ball, ground]).tolist() == [ball.angular_velocity, 0.0]


def test_bulk_writes_move_many_bodies():
    w = quack.World(gravity=(0, 0))
    bodies = [w.create_body(pos=(i * 3.0, 0)) for i in range(50)]
    for b in bodies:
        w.create_shape(b, quack.box(half=(0.5, 0.5)))
    targets = np.column_stack([np.arange(50) * 3.0, np.full(50, 7.0)])
    w.set_positions(targets, bodies)
    assert np.array_equal(w.get_positions(bodies), targets)
    w.set_angles(np.full(50, 0.25))
    assert np.allclose(w.get_angles(), 0.25)
    w.set_velocities(np.tile([1.0, 0.0], (50, 1)))
    w.set_angular_velocities(np.linspace(0, 1, 50))
    w.step(0.5, 4)
    assert np.allclose(w.get_positions(bodies)[:, 0], targets[:, 0] + 0.5, atol=1e-5)
    # The solver turns a body by normalising (cos, sin) + dt w (-sin, cos) each sub-step,
    # which falls short of dt w by about (dt w)^3 / 3: 0.4974 rad for 0.5 s at 1 rad/s.
    turned = w.get_angles() - 0.25
    assert np.allclose(turned, 0.5 * np.linspace(0, 1, 50), rtol=0.01, atol=1e-6)
    w.validate()


def test_a_refused_bulk_write_changes_nothing():
    w = quack.World(gravity=(0, 0))
    bodies = [w.create_body(pos=(i, 0)) for i in range(3)]
    before = w.get_positions()
    bad = np.array([[5.0, 5.0], [6.0, 6.0], [np.nan, 0.0]])
    with pytest.raises(ValueError, match=r"positions\[2\]\[0\]: must be finite"):
        w.set_positions(bad)
    with pytest.raises(ValueError, match=r"positions\[1\]\[1\]: 2e\+09 m is beyond"):
        w.set_positions(np.array([[0.0, 0.0], [0.0, 2e9], [0.0, 0.0]]))
    with pytest.raises(ValueError, match=r"velocities: must be a numpy array of shape \(3, 2\)"):
        w.set_velocities(np.zeros((2, 2)))
    with pytest.raises(ValueError, match=r"bodies\[1\]\]?: .*kMaxLinearSpeed"):
        w.set_velocities(np.array([[0.0, 0.0], [2e5, 0.0], [0.0, 0.0]]))
    assert np.array_equal(w.get_positions(), before)
    assert np.array_equal(w.get_velocities(), np.zeros((3, 2)))
    with pytest.raises(ValueError, match=r"bodies: must be a list"):
        w.get_positions("all")
    w.destroy_body(bodies[1])
    with pytest.raises(ValueError, match=r"bodies\[0\]: stale handle"):
        w.get_positions([bodies[1]])


def test_events_after_a_step():
    w, ground, ball = ball_world()
    began = []
    for _ in range(120):
        w.step()
        began.extend(w.events().begin)
    assert len(began) == 1
    a, b = began[0]
    assert {a.body, b.body} == {ground, ball}
    ev = w.events()
    assert ev.end == [] and isinstance(ev.hit, list) and isinstance(ev.toi, list)


def test_hit_events_carry_point_normal_and_speed():
    w, ground, ball = ball_world()
    hits = []
    for _ in range(120):
        w.step()
        hits.extend(w.events().hit)
    assert hits, "a ball falling 2.5 m hits the ground faster than 1 m/s"
    h = hits[0]
    assert h.approach_speed > 1.0
    assert h.point[1] == pytest.approx(0.0, abs=0.05)
    assert abs(h.normal[1]) == pytest.approx(1.0, abs=1e-3)


def test_contact_callbacks_by_category():
    w, ground, ball = ball_world()
    seen, never = [], []
    # Category 2 is the ball, 1 the ground: shapes come in the order asked for.
    w.on_contact_begin(lambda a, b: seen.append((a.body, b.body)), 2, 1)
    w.on_contact_begin(lambda a, b: never.append(1), 4, 1)
    ended = []
    w.on_contact_end(lambda a, b: ended.append(1))
    events = 0
    for _ in range(120):
        w.step()
        events += len(w.events().begin)
    assert events == 1
    assert seen == [(ball, ground)]
    assert never == []
    ball.position = (0, 10)
    w.step()
    assert ended == [1]


def test_hit_and_sensor_callbacks():
    w, ground, ball = ball_world()
    zone = w.create_body(type="static", pos=(0, 1.5))
    w.create_shape(zone, quack.box(half=(2, 0.5)), sensor=True, category=4)
    entered, hits = [], []
    w.on_sensor_begin(lambda s, v: entered.append((s.body, v.body)), 4, 2)
    w.on_hit(lambda hit, swapped: hits.append((hit.approach_speed, swapped)), 2, 1)
    for _ in range(120):
        w.step()
    assert entered == [(zone, ball)]
    assert len(hits) >= 1 and hits[0][0] > 1.0



def test_impacts_between_bullets_come_as_events_and_callbacks():
    """Two bullets fired head-on at 500 m/s each (the C++ CcdDynamic test's closed form, here
    only what the binding must carry): one impact, approach speed 1,000 m/s along the line of
    centres, the same event through Events.toi and on_impact, and they never pass."""
    w = quack.World(gravity=(0, 0))
    a = w.create_body(pos=(-5, 0), vel=(500, 0), bullet=True)
    b = w.create_body(pos=(5, 0), vel=(-500, 0), bullet=True)
    w.create_shape(a, quack.circle(radius=0.05), restitution=1.0, friction=0.0, category=2)
    w.create_shape(b, quack.circle(radius=0.05), restitution=1.0, friction=0.0, category=4)
    called, tois = [], []
    w.on_impact(lambda impact, swapped: called.append((impact, swapped)), 2, 4)
    for _ in range(2):
        w.step()
        ev = w.events()
        tois.extend(ev.toi)
        assert ev.toi_capped == []
    assert len(tois) == 1
    t = tois[0]
    assert 0.0 <= t.time <= 1.0
    assert t.approach_speed == pytest.approx(1000.0, rel=1e-3)
    assert abs(t.normal[0]) == pytest.approx(1.0, abs=1e-3)
    assert [c[0] for c in called] == tois
    assert a.position[0] < b.position[0]
    assert a.velocity[0] < 0 < b.velocity[0]


def test_dynamic_pairs_off_sweeps_fast_bodies_against_static_shapes_only():
    """dynamic_pairs=False is Box2D v3's rule (the C++ test
    CcdDynamic.WithoutDynamicPairsOnlyStaticShapesAndBulletsAreSwept has the rest): a disc at
    600 m/s passes a thin plank at rest untouched, which the default world stops it at."""
    ends = {}
    for pairs in (True, False):
        w = quack.World(gravity=(0, 0), dynamic_pairs=pairs)
        plank = w.create_body(pos=(5, 0))
        w.create_shape(plank, quack.box(half=(0.01, 1.0)))
        disc = w.create_body(pos=(-2.95, 0), vel=(600, 0))
        w.create_shape(disc, quack.circle(radius=0.05), friction=0.0)
        tois = []
        for _ in range(3):
            w.step()
            tois.extend(w.events().toi)
        ends[pairs] = (len(tois), disc.position[0] - plank.position[0], disc.velocity[0])
    assert ends[True][0] >= 1 and ends[True][1] < 0.0  # still behind the plank it met
    assert ends[False][0] == 0 and ends[False][1] > 15.0 and ends[False][2] == 600.0
    with pytest.raises(TypeError):
        quack.World(dynamic_pairs="no")


class Boom(Exception):
    pass


def test_an_exception_in_a_callback_comes_out_of_step_after_the_step():
    w, ground, ball = ball_world()
    calls = []

    def explode(a, b):
        calls.append(1)
        raise Boom("from the callback")

    w.on_contact_begin(explode)
    w.on_contact_begin(lambda a, b: calls.append(2))
    steps = 0
    with pytest.raises(Boom, match="from the callback"):
        for _ in range(120):
            w.step()
            steps += 1
    # The step that raised was completed (the counter moved on); the second callback of that
    # step was skipped once the first raised.
    assert w.step_count == steps + 1
    assert calls == [1]
    w.validate()
    # The world goes on.
    w.step()
    assert w.step_count == steps + 2


def test_what_callbacks_may_and_may_not_do():
    w, ground, ball = ball_world()
    errors = []

    def destroy_and_step(a, b):
        w.destroy_body(ball)  # deferred until the callbacks are done
        assert a.valid and b.valid
        try:
            w.step()
        except ValueError as e:
            errors.append(str(e))

    w.on_contact_begin(destroy_and_step)
    for _ in range(120):
        w.step()
        if not ball.valid:
            break
    assert not ball.valid
    assert errors == ["step: called from a callback"]
    assert w.body_count == 1 and w.bodies == [ground]


def test_stale_handles_say_so():
    w, ground, ball = ball_world()
    shape = ball.shapes[0]
    assert ball.valid and shape.valid and shape.body == ball and shape.type == "circle"
    w.destroy_body(ball)
    assert not ball.valid and not shape.valid
    assert "stale" in repr(ball)
    for get in (lambda: ball.position, lambda: ball.velocity, lambda: ball.mass,
                lambda: ball.shapes, lambda: ball.name):
        with pytest.raises(ValueError, match=r"stale quack.BodyHandle \(the body was destroyed\)"):
            get()
    with pytest.raises(ValueError, match="stale quack.ShapeHandle"):
        shape.body
    with pytest.raises(ValueError, match="body: stale handle"):
        w.destroy_body(ball)
    with pytest.raises(ValueError, match="body: stale handle"):
        w.create_shape(ball, quack.circle(radius=1))
    other, _, other_ball = ball_world()
    with pytest.raises(ValueError, match="body: a body of another world"):
        w.destroy_body(other_ball)
    # A new body may reuse the slot; the old handle stays stale.
    again = w.create_body()
    assert again.valid and not ball.valid and again != ball


def test_bad_definitions_raise_value_error():
    w = quack.World()
    with pytest.raises(ValueError, match='type: unknown body type "wobbly"'):
        w.create_body(type="wobbly")
    with pytest.raises(ValueError, match=r"pos\[0\]: must be finite"):
        w.create_body(pos=(math.nan, 0))
    b = w.create_body()
    with pytest.raises(ValueError, match="density"):
        w.create_shape(b, quack.circle(radius=1), density=-1)
    with pytest.raises(ValueError, match='broadphase: unknown broad phase "octree"'):
        quack.World(broadphase="octree")
    with pytest.raises(ValueError, match="substeps"):
        quack.World(substeps=0)


def test_concave_shapes_go_on_as_their_pieces():
    w = quack.World()
    b = w.create_body(type="static")
    pieces = w.create_shape(b, quack.concave(points=[[0, 0], [4, 0], [4, 1], [1, 1], [1, 4],
                                                     [0, 4]]))
    assert isinstance(pieces, list) and len(pieces) >= 2
    assert w.shape_count == len(pieces)
    assert all(p.type == "polygon" for p in pieces)


def test_world_queries():
    w, ground, ball = ball_world()
    hit = w.ray_cast_closest((0, 10), (0, -20), mask=quack.ALL_CATEGORIES)
    assert hit.body == ball and hit.point[1] == pytest.approx(3.5, abs=1e-5)
    assert hit.normal == pytest.approx((0, 1), abs=1e-5)
    assert hit.fraction == pytest.approx(6.5 / 20, abs=1e-5)
    everything = w.ray_cast_all((0, 10), (0, -20))
    assert [h.body for h in everything] == [ball, ground]
    assert w.ray_cast_closest((30, 10), (0, -20)) is None
    assert w.overlap_aabb((-1, 2), (1, 4)) == [ball.shapes[0]]
    overlaps = w.overlap_shape(quack.box(half=(0.5, 0.5)), (0, 0.25, 0))
    assert [o.body for o in overlaps] == [ground]
    assert overlaps[0].depth == pytest.approx(0.25, abs=1e-5)
    assert overlaps[0].depenetration == pytest.approx((0, 0.25), abs=1e-5)
    cast = w.cast_shape(quack.circle(radius=0.25), (5, 5, 0), (0, -10))
    assert cast.body == ground and cast.fraction == pytest.approx(4.75 / 10, abs=1e-3)
    with pytest.raises(ValueError, match="shape: a concave shape cannot be a query shape"):
        w.overlap_shape(quack.concave(points=[[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]]),
                        (0, 0, 0))
    with pytest.raises(ValueError, match=r"translation\[1\]: must be finite"):
        w.ray_cast_closest((0, 0), (0, math.inf))


def _scene(source_dir, name):
    return os.path.join(source_dir, "scenes", name)


@pytest.mark.parametrize("scene, steps", [("sensor.json", 150), ("players.json", 100),
                                          ("concave.json", 100)])
def test_a_scene_matches_the_cpp_world(source_dir, quack_bin, scene_hash_bin, tmp_path, scene,
                                       steps):
    """The same scene and steps: the state hash equals C++'s World::stateHash, and the state
    file equals `quack run`'s byte for byte (event totals included)."""
    path = _scene(source_dir, scene)
    w = quack.load_scene(path)
    for _ in range(steps):
        w.step()
    expected = int(subprocess.run([scene_hash_bin, path, str(steps)], capture_output=True,
                                  text=True, check=True).stdout)
    assert w.state_hash() == expected
    mine, theirs = tmp_path / "python.json", tmp_path / "quack.json"
    w.write_state(str(mine))
    subprocess.run([quack_bin, "run", path, "--steps", str(steps), "--out", str(theirs)],
                   capture_output=True, check=True)
    assert mine.read_bytes() == theirs.read_bytes()
    if scene == "sensor.json":
        # The event totals compared above are not all zero.
        assert b'"sensor": 0' not in theirs.read_bytes()


def test_the_hash_changes_when_the_world_does(source_dir, scene_hash_bin):
    path = _scene(source_dir, "sensor.json")
    w = quack.load_scene(path)
    w.step()
    one = int(subprocess.run([scene_hash_bin, path, "1"], capture_output=True, text=True,
                             check=True).stdout)
    two = int(subprocess.run([scene_hash_bin, path, "2"], capture_output=True, text=True,
                             check=True).stdout)
    assert w.state_hash() == one != two


def test_scene_names_and_categories(source_dir):
    w = quack.load_scene(_scene(source_dir, "sensor.json"))
    assert w.categories == ["terrain", "ball", "zone"]
    assert w.bodies[0].name == "ground" and w.body("zone").type == "static"
    assert len(w.bodies) == w.body_count


def test_scene_errors(tmp_path):
    with pytest.raises(ValueError, match="nothing.json"):
        quack.load_scene(str(tmp_path / "nothing.json"))
    bad = tmp_path / "bad.json"
    bad.write_text('{"bodies": [{"shapes": [{"type": "circle", "radius": -1}]}]}')
    with pytest.raises(ValueError, match=r"bodies\[0\].shapes\[0\].radius: must be > 0"):
        quack.load_scene(str(bad))
    w = quack.World()
    with pytest.raises(ValueError, match="write_state: cannot open"):
        w.write_state(str(tmp_path / "no" / "such" / "dir.json"))


def test_the_gil_is_released_during_step(source_dir):
    from test_batch import _check_gil_released
    w = quack.load_scene(_scene(source_dir, "rain.json"))
    _check_gil_released(lambda: [w.step() for _ in range(400)])


def test_another_thread_cannot_use_the_world_while_it_steps(source_dir):
    w = quack.load_scene(_scene(source_dir, "rain.json"))
    refused = []
    stop = threading.Event()

    def stepper():
        # Steps until this thread has been refused once (10 steps were sometimes over before
        # this thread ran).
        for _ in range(5000):
            if stop.is_set():
                break
            w.step()

    t = threading.Thread(target=stepper)
    t.start()
    while t.is_alive():
        try:
            w.get_positions()
        except RuntimeError as e:
            refused.append(str(e))
            break
    stop.set()
    t.join()
    assert refused == ["quack.World: the world is stepping (in another thread)"]


def _rss_kib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise AssertionError("no VmRSS")


def test_no_leaks_over_100000_create_destroy_cycles():
    """Bodies, shapes and handles made and dropped 100,000 times: Python's allocations
    (tracemalloc), the process's memory (RSS) and the world's reference count all come back
    to where they were after a warm-up."""
    w = quack.World()
    circle = quack.circle(radius=0.5)

    def cycles(n):
        for i in range(n):
            b = w.create_body(pos=(i % 100, 0))
            s = w.create_shape(b, circle)
            assert s.body == b
            if i % 1000 == 0:
                w.step()
            w.destroy_body(b)

    cycles(5000)  # warm-up: the world's pools and Python's free lists reach their size
    gc.collect()
    world_refs = len(gc.get_referrers(w))
    rss_before = _rss_kib()
    tracemalloc.start()
    snapshot_before = tracemalloc.take_snapshot()
    cycles(100_000)
    gc.collect()
    grown = sum(stat.size_diff for stat in
                tracemalloc.take_snapshot().compare_to(snapshot_before, "filename"))
    tracemalloc.stop()
    rss_after = _rss_kib()
    assert w.body_count == 0 and w.shape_count == 0 and w.bodies == []
    assert len(gc.get_referrers(w)) == world_refs
    # A leak of one handle (about 50 bytes) per cycle would be 5 MB.
    assert grown < 100_000, f"Python allocations grew by {grown} bytes"
    assert rss_after - rss_before < 2048, f"RSS grew by {rss_after - rss_before} KiB"


def test_dropping_a_world_frees_it():
    import weakref
    w, ground, ball = ball_world()
    w.on_contact_begin(lambda a, b: None)
    ref = weakref.ref(w)
    del w, ground, ball
    gc.collect()
    assert ref() is None


def test_a_world_in_a_cycle_with_its_callbacks_is_collected():
    """Callbacks that refer to their world, directly or through a handle, make cycles the
    collector must see through the module's objects to free."""
    import weakref
    w, ground, ball = ball_world()
    w.on_contact_begin(lambda a, b: w.step_count)
    w.on_hit(lambda hit, swapped: ball.position)
    w.step()
    ref = weakref.ref(w)
    del w, ground, ball
    gc.collect()
    assert ref() is None



def test_handle_setters_impulses_and_forces():
    w = quack.World(gravity=(0, 0))
    b = w.create_body(pos=(1, 2), angle=0.5)
    shape = w.create_shape(b, quack.box(half=(0.5, 0.5)), density=2, friction=0.3, category=8)
    assert shape.category == 8 and shape.friction == pytest.approx(0.3) and not shape.sensor
    assert b.mass == pytest.approx(2.0)
    assert b.position == (1.0, 2.0) and b.angle == pytest.approx(0.5)
    b.angle = 1.0
    b.velocity = (3, 0)
    b.angular_velocity = 2.0
    assert (b.angle, b.velocity, b.angular_velocity) == (1.0, (3.0, 0.0), 2.0)
    b.velocity = (0, 0)
    b.angular_velocity = 0
    b.apply_impulse((4, 0))  # 4 N s on 2 kg at the centre: 2 m/s, no spin
    assert b.velocity == pytest.approx((2.0, 0.0)) and b.angular_velocity == 0.0
    b.apply_impulse((0, 2), point=(1.5, 2))  # off centre: spins too
    assert b.angular_velocity != 0.0
    b.velocity = (0, 0)
    b.apply_force((20, 0))  # 10 m/s^2 for one step
    w.step(0.1, 1)
    assert b.velocity[0] == pytest.approx(1.0, rel=1e-4)
    with pytest.raises(ValueError, match=r"velocity\[0\]: must be finite"):
        b.velocity = (math.nan, 0)
    with pytest.raises(ValueError, match="setAngularVelocity"):
        b.angular_velocity = 1e6
    w.destroy_shape(shape)
    assert not shape.valid and b.shapes == [] and w.shape_count == 0
    with pytest.raises(ValueError, match="shape: stale handle"):
        w.destroy_shape(shape)


def test_sensor_end_callback():
    w, ground, ball = ball_world()
    zone = w.create_body(type="static", pos=(0, 2))
    w.create_shape(zone, quack.box(half=(2, 0.2)), sensor=True, category=4)
    left = []
    w.on_sensor_end(lambda s, v: left.append(v.body), 4, 2)
    ended = 0
    for _ in range(120):
        w.step()
        ended += len(w.events().sensor_end)
    assert ended == 1 and left == [ball]


def _entry_points(w, ball, shape):
    """Every call that reads or writes the world, by name."""
    n = w.body_count
    return {
        "validate": w.validate,
        "state_hash": w.state_hash,
        "events": w.events,
        "body_count": lambda: w.body_count,
        "shape_count": lambda: w.shape_count,
        "contact_count": lambda: w.contact_count,
        "bodies": lambda: w.bodies,
        "time": lambda: w.time,
        "step_count": lambda: w.step_count,
        "body": lambda: w.body("ball"),
        "step": w.step,
        "create_body": w.create_body,
        "destroy_shape": lambda: w.destroy_shape(shape),
        "on_contact_end": lambda: w.on_contact_end(lambda a, b: None),
        "get_positions": w.get_positions,
        "get_angles": w.get_angles,
        "get_velocities": w.get_velocities,
        "get_angular_velocities": w.get_angular_velocities,
        "set_positions": lambda: w.set_positions(np.zeros((n, 2))),
        "set_angles": lambda: w.set_angles(np.zeros(n)),
        "body_state": w.body_state,
        "set_body_state": lambda: w.set_body_state(np.zeros((n, 6))),
        "to_svg": w.to_svg,
        "ray_cast_closest": lambda: w.ray_cast_closest((0, 5), (0, -10)),
        "ray_cast_all": lambda: w.ray_cast_all((0, 5), (0, -10)),
        "overlap_aabb": lambda: w.overlap_aabb((-1, -1), (1, 1)),
        "overlap_shape": lambda: w.overlap_shape(quack.circle(1), (0, 0, 0)),
        "cast_shape": lambda: w.cast_shape(quack.circle(1), (0, 5, 0), (0, -10)),
        "body.valid": lambda: ball.valid,
        "body.position": lambda: ball.position,
        "body.angle": lambda: ball.angle,
        "body.velocity": lambda: ball.velocity,
        "body.angular_velocity": lambda: ball.angular_velocity,
        "body.mass": lambda: ball.mass,
        "body.type": lambda: ball.type,
        "body.name": lambda: ball.name,
        "body.shapes": lambda: ball.shapes,
        "body.apply_impulse": lambda: ball.apply_impulse((0, 1)),
        "shape.valid": lambda: shape.valid,
        "shape.body": lambda: shape.body,
        "shape.type": lambda: shape.type,
        "shape.category": lambda: shape.category,
        "shape.sensor": lambda: shape.sensor,
        "shape.friction": lambda: shape.friction,
    }


def test_every_entry_point_refuses_while_another_thread_steps():
    """Issue 28, item 5: validate, state_hash, events, body_count, contact_count, bodies and a
    handle's position, angle, valid and shapes read the world while another thread stepped it
    (validate reported false corruption). A callback holds the step open until this thread
    has tried every entry point: each must raise RuntimeError."""
    w, ground, ball = ball_world()
    ball.position = (0, 0.45)  # touching the ground: a contact begins in the first step
    shape = ball.shapes[0]
    in_step, done = threading.Event(), threading.Event()
    held = []

    def hold_the_step(a, b):
        held.append(threading.get_ident())
        in_step.set()
        done.wait(60)

    w.on_contact_begin(hold_the_step)
    calls = _entry_points(w, ball, shape)
    t = threading.Thread(target=w.step)
    t.start()
    refused, accepted = [], []
    try:
        assert in_step.wait(60), "the step's callback never ran"
        for name, call in calls.items():
            try:
                call()
                accepted.append(name)
            except RuntimeError as e:
                assert str(e) == "quack.World: the world is stepping (in another thread)"
                refused.append(name)
        # The reprs say nothing of the world's state, and do not raise.
        assert repr(w) == "World(stepping)"
        assert re.fullmatch(r"BodyHandle\(index=1, generation=\d+\)", repr(ball))
    finally:
        done.set()
        t.join()
    assert held == [t.ident]
    assert accepted == []
    assert refused == list(calls)
    # Once the step is over every call is accepted again.
    w.validate()
    assert w.step_count == 1 and ball.valid and w.body_count == 2


def test_reads_from_another_thread_never_see_a_step_half_done(source_dir):
    """Issue 28, item 5, unheld: while a thread steps a scene, validate() and state_hash()
    from this thread either raise RuntimeError or see a whole world (never ValueError)."""
    w = quack.load_scene(_scene(source_dir, "rain.json"))
    stop = threading.Event()

    def stepper():
        for _ in range(3000):
            if stop.is_set():
                break
            w.step()

    t = threading.Thread(target=stepper)
    refused = accepted = 0
    t.start()
    while t.is_alive() and refused < 50:
        for call in (w.validate, w.state_hash, lambda: w.bodies[0].position):
            try:
                call()
                accepted += 1
            except RuntimeError:
                refused += 1
    stop.set()
    t.join()
    assert refused >= 50
    w.validate()


def test_a_memory_error_from_step_leaves_the_world_usable(tmp_path):
    """Issue 28, item 6 (the Python side): after a MemoryError from step (std::bad_alloc, here
    under an address-space limit: 600 circles in one spot make 179,700 contacts, far more
    than the 64 MB the limit leaves), every call said "the world is stepping (in another
    thread)" for good. The in-step mark is now cleared however step ends: reads work, step
    says why it refuses, and restoring a snapshot makes the world step again."""
    code = r"""
import resource, quack
w = quack.World(gravity=(0, 0))
for i in range(600):
    b = w.create_body(pos=(0, 0))
    w.create_shape(b, quack.circle(radius=1))
def vm_bytes():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
snap = w.snapshot()
soft, hard = resource.getrlimit(resource.RLIMIT_AS)
resource.setrlimit(resource.RLIMIT_AS, (vm_bytes() + (64 << 20), hard))
try:
    w.step()
    print("stepped")
except MemoryError:
    print("MemoryError")
resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
print(w.body_count, len(w.get_positions()), type(w.state_hash()).__name__)
import threading
seen = []
t = threading.Thread(target=lambda: seen.append(w.body_count))
t.start(); t.join()
print("another thread reads", seen)
try:
    w.step(substeps=1)
    print("stepped again")
except ValueError as e:
    print("ValueError:", e)
w.restore(snap)
w.step()
print("restored and stepped", w.body_count)
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300, check=False)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[0] == "MemoryError", out.stdout
    assert lines[1] == "600 600 int", out.stdout
    assert lines[2] == "another thread reads [600]", out.stdout + out.stderr
    # The C++ world refuses to go on from a half-done step (docs/world.md, "Exceptions")
    # until a snapshot is restored.
    assert lines[3].startswith("ValueError: step: step 1 ran out of memory"), out.stdout
    assert lines[4] == "restored and stepped 600", out.stdout


def test_arguments_out_of_range_are_value_errors_naming_them():
    """Issue 28, item 10: step(substeps=2**40) and an __index__ returning 2**70 raised
    RuntimeError: Unable to cast...; set_angles took 1e30 rad although scenes limit angles
    to 1e4; an oversized impulse was "1e+30 m"."""

    class Index:
        def __index__(self):
            return 2**70

    w, ground, ball = ball_world()
    with pytest.raises(ValueError, match=r"^substeps: must be an integer in 1\.\.64, got 1099"):
        w.step(substeps=2**40)
    with pytest.raises(ValueError, match=r"^substeps: must be an integer in 1\.\.64, got 1180"):
        w.step(substeps=Index())
    with pytest.raises(ValueError, match=r"^substeps: must be an integer in 1\.\.64, not a str"):
        w.step(substeps="4")
    with pytest.raises(ValueError, match=r"^dt: must be a number, not a str"):
        w.step(dt="0.1")
    with pytest.raises(ValueError, match=r"^dt: must be a real number"):
        w.step(dt=0.1 + 1j)
    with pytest.raises(ValueError, match=r"^substeps: must be an integer in 1\.\.64, got 1099"):
        quack.World(substeps=2**40)
    with pytest.raises(ValueError, match=r"^dt: must be a number, not a str"):
        quack.World(dt="0.1")
    assert quack.World(dt=np.float32(0.5), substeps=np.int8(3)).step_count == 0
    w.step(dt=np.float32(0.01), substeps=np.uint8(2))
    assert w.step_count == 1
    with pytest.raises(ValueError, match=r"^angles\[1\]: 1e\+30 rad is beyond the limit 1e4 rad"):
        w.set_angles(np.array([0.0, 1e30]))
    with pytest.raises(ValueError, match=r"^angle: -20000 rad is beyond the limit 1e4 rad"):
        ball.angle = -2e4
    with pytest.raises(ValueError, match=r"^angle: 1e\+30 rad"):
        w.create_body(angle=1e30)
    w.set_angles(np.full(2, 1e4))  # at the limit: accepted (and kept within +-pi)
    assert abs(ball.angle) <= math.pi
    with pytest.raises(ValueError, match=r"^impulse\[0\]: 1e\+30 N s is beyond the limit 1e9 N s"):
        ball.apply_impulse((1e30, 0))
    with pytest.raises(ValueError, match=r"^force\[1\]: 1e\+30 N is beyond"):
        ball.apply_force((0, 1e30))
    with pytest.raises(ValueError, match=r"^velocity\[0\]: 1e\+30 m/s is beyond"):
        ball.velocity = (1e30, 0)
    with pytest.raises(ValueError, match=r"^gravity\[1\]: 1e\+30 m/s\^2 is beyond"):
        quack.World(gravity=(0, 1e30))
    for bad, kind in ((np.zeros((2, 2), dtype=complex), "complex128"),
                      (np.zeros((2, 2), dtype=bool), "bool"),
                      (np.array([["0", "1"], ["2", "3"]]), "<U1")):
        with pytest.raises(ValueError, match=rf"^positions: must hold integers or floats, not {kind}"):
            w.set_positions(bad)
    w.set_positions(np.array([[0, -1], [0, 3]], dtype=np.int32))
    assert ball.position == (0.0, 3.0)
    # Scalar numbers everywhere: numpy complex (whose imaginary part pybind11's float
    # conversion dropped) and bool are refused, naming the argument.
    for call, name in ((lambda v: w.create_body(angle=v), "angle"),
                       (lambda v: w.create_body(angvel=v), "angvel"),
                       (lambda v: w.create_body(linear_damping=v), "linear_damping"),
                       (lambda v: w.create_body(gravity_scale=v), "gravity_scale"),
                       (lambda v: w.create_shape(ball, quack.circle(1), density=v), "density"),
                       (lambda v: w.create_shape(ball, quack.circle(1), friction=v), "friction"),
                       (lambda v: w.create_shape(ball, quack.circle(1), restitution=v),
                        "restitution"),
                       (lambda v: setattr(ball, "angle", v), "angle"),
                       (lambda v: setattr(ball, "angular_velocity", v), "angular_velocity")):
        count = w.body_count, w.shape_count
        with pytest.raises(ValueError, match=rf"^{name}: must be a real number"):
            call(np.complex128(0.5 + 1j))
        with pytest.raises(ValueError, match=rf"^{name}: must be a number, not a bool"):
            call(True)
        assert (w.body_count, w.shape_count) == count
    w.create_shape(w.create_body(angle=np.float32(0.5), angvel=np.int64(1)), quack.circle(1),
                   density=np.uint8(2), friction=np.float16(0.5))


def test_the_collector_may_run_while_a_world_is_made():
    """A garbage collection during World's constructor (here started by numpy's first import,
    which the argument checks trigger) traversed the world before its C++ value existed
    (SIGSEGV)."""
    code = ("import gc, quack\n"
            "gc.set_threshold(1)\n"
            "worlds = [quack.World(gravity=(0, -9.8)) for _ in range(20)]\n"
            "print(len(worlds), 'numpy' in __import__('sys').modules)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120, check=False)
    assert out.returncode == 0, out.stderr
    assert out.stdout == "20 True\n"


def test_body_state_is_one_array_shared_until_the_next_step():
    w, ground, ball = ball_world()
    ball.velocity = (1.5, 2.0)
    ball.angular_velocity = 0.25
    state = w.body_state()
    assert quack.BODY_STATE_COLUMNS == ("x", "y", "angle", "vx", "vy", "angular_velocity")
    assert state.shape == (2, 6) and state.dtype == np.float64
    assert not state.flags.writeable
    assert state[1].tolist() == [0.0, 3.0, 0.0, 1.5, 2.0, 0.25]
    assert state[0, 0:2].tolist() == [0.0, -0.5]
    # The same array for every read until the world changes: no copy per call, and slices are
    # views of it.
    assert w.body_state() is state
    positions = state[:, 0:2]
    assert positions.base is state or positions.base is state.base
    with pytest.raises(ValueError, match="read-only"):
        state[1, 0] = 5.0
    w.step()
    fresh = w.body_state()
    assert fresh is not state
    # The stale array keeps the values of its time (never freed, never rewritten).
    assert state[1].tolist() == [0.0, 3.0, 0.0, 1.5, 2.0, 0.25]
    assert positions[1].tolist() == [0.0, 3.0]
    assert np.array_equal(fresh[:, 0:2], w.get_positions())
    assert np.array_equal(fresh[:, 2], w.get_angles())
    assert np.array_equal(fresh[:, 3:5], w.get_velocities())
    assert np.array_equal(fresh[:, 5], w.get_angular_velocities())
    # Every write makes the next read a new array.
    for write in (lambda: setattr(ball, "position", (1, 3)),
                  lambda: setattr(ball, "angle", 0.5),
                  lambda: setattr(ball, "velocity", (0, 0)),
                  lambda: setattr(ball, "angular_velocity", 1.0),
                  lambda: ball.apply_impulse((0, 1)),
                  lambda: w.set_positions(np.array([[0, -0.5], [2, 3]])),
                  lambda: w.set_angles(np.zeros(2)),
                  lambda: w.set_velocities(np.zeros((2, 2))),
                  lambda: w.set_angular_velocities(np.zeros(2)),
                  lambda: w.create_body(pos=(5, 5)),
                  w.step):
        before = w.body_state()
        write()
        after = w.body_state()
        assert after is not before
        assert np.array_equal(after[:, 0:2], w.get_positions())
        assert np.array_equal(after[:, 3:5], w.get_velocities())
    assert w.body_state().shape == (3, 6)
    w.destroy_body(w.bodies[2])
    assert w.body_state().shape == (2, 6)


def test_a_stale_body_state_survives_its_world_and_many_bodies_made():
    """A view into memory that a step may reallocate would be a use-after-free: the array is
    the module's own, so it outlives new bodies (which reallocate the world's storage), steps
    and the world itself, with the values of its time."""
    w, ground, ball = ball_world()
    state = w.body_state()
    expected = state.copy()
    for i in range(2000):
        w.create_body(pos=(i % 40, 10 + i // 40))
    for _ in range(3):
        w.step()
    del w, ground, ball
    gc.collect()
    assert np.array_equal(state, expected)


def test_set_body_state_writes_every_body_or_none():
    w, ground, ball = ball_world()
    other = w.create_body(pos=(3, 3))
    w.create_shape(other, quack.box(half=(0.5, 0.5)))
    state = w.body_state().copy()
    state[1] = [1.0, 4.0, 0.5, 2.0, -1.0, 0.3]
    state[2] = [-2.0, 6.0, -0.5, 0.0, 1.0, -0.2]
    w.set_body_state(state)
    got = w.body_state()
    assert np.allclose(got[1:], state[1:], atol=1e-6)
    assert ground.position == (0.0, -0.5) and ground.velocity == (0.0, 0.0)
    assert ball.position == pytest.approx((1.0, 4.0)) and ball.angle == pytest.approx(0.5)
    before = w.body_state()
    for bad, message in (
            (np.zeros((2, 6)), r"^state: must be a numpy array of shape \(3, 6\) for 3 bodies"),
            (np.zeros((3, 5)), r"^state: must be a numpy array of shape \(3, 6\)"),
            (np.zeros((3, 6), dtype=complex), r"^state: must hold integers or floats"),
            (np.where(np.arange(18).reshape(3, 6) == 14, np.nan, 0.0),
             r"^state\[2\]\[2\]: must be finite"),
            (np.where(np.arange(18).reshape(3, 6) == 8, 1e30, 0.0),
             r"^state\[1\]\[2\]: 1e\+30 rad is beyond the limit 1e4 rad"),
            (np.where(np.arange(18).reshape(3, 6) == 12, 2e9, 0.0),
             r"^state\[2\]\[0\]: 2e\+09 m is beyond the coordinate limit")):
        with pytest.raises(ValueError, match=message):
            w.set_body_state(bad)
        assert w.body_state() is before  # nothing written
    # A speed the world refuses (its limit, 1e5 m/s) puts every body back.
    too_fast = state.copy()
    too_fast[2, 3] = 1e7
    with pytest.raises(ValueError, match=r"^bodies\[2\]"):
        w.set_body_state(too_fast)
    assert np.array_equal(w.body_state(), before)


def test_to_svg_draws_the_world():
    w, ground, ball = ball_world()
    svg = w.to_svg(title="a ball")
    assert svg.startswith("<svg") or svg.startswith("<?xml")
    assert svg.rstrip().endswith("</svg>")
    assert "a ball" in svg
    assert w._repr_svg_() == w.to_svg()
    # A big world: the notebook's picture keeps to its smaller budget and says so.
    for i in range(6000):
        b = w.create_body(type="static", pos=(i % 100, 5 + i // 100))
        w.create_shape(b, quack.circle(radius=0.3))
    small, full = w._repr_svg_(), w.to_svg()
    assert len(small) < 2 << 20 and len(small) < len(full)
    assert small.count("<circle") + small.count("<path") + small.count("<polygon") <= 5000 + 10
    # Two shapes: the ground's box and the ball.
    assert svg.count("<path") + svg.count("<polygon") + svg.count("<circle") >= 2


def test_snapshot_and_restore_round_trip_and_refuse_what_does_not_fit():
    """snapshot() and restore(): a world put back to a snapshot continues to the same bits;
    a snapshot that is not one, or is of another world's structure, is a ValueError naming
    the problem, and the world is left as it was."""
    w = quack.World()
    ground = w.create_body(pos=(0, 0), type="static")
    w.create_shape(ground, quack.box(half=(5, 0.5)))
    for i in range(5):
        b = w.create_body(pos=(0.3 * i, 1.0 + i))
        w.create_shape(b, quack.circle(radius=0.4))
    for _ in range(10):
        w.step()
    snap = w.snapshot()
    assert isinstance(snap, bytes) and len(snap) > 48
    for _ in range(20):
        w.step()
    later = w.state_hash()
    w.restore(snap)
    for _ in range(20):
        w.step()
    assert w.state_hash() == later
    with pytest.raises(ValueError, match="restore: not a Quack snapshot"):
        w.restore(b"junk")
    flipped = bytearray(snap)
    flipped[-1] ^= 1
    with pytest.raises(ValueError, match="checksum"):
        w.restore(bytes(flipped))
    assert w.state_hash() == later


def test_body_state_after_restore_is_the_restored_one():
    """Regression: restore() did not move the world's version on, so body_state() handed
    back the array of before the restore."""
    w = quack.World()
    w.create_body(type="static")
    ball = w.create_body(pos=(0, 5))
    w.create_shape(ball, quack.circle(radius=0.5))
    snap = w.snapshot()
    first = w.body_state().copy()
    for _ in range(30):
        w.step()
    assert w.body_state()[1, 1] < 5  # it fell
    w.restore(snap)
    assert ball.position == (0.0, 5.0)
    assert w.body_state().tobytes() == first.tobytes()
