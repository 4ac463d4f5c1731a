"""quack.World's joints: create_joint with the scene files' rules and its errors (each naming
its argument), JointHandle's readings and setters, stale handles, breaking joints and their
events, the docs' pendulum against the closed form, and joints in state files."""

import json
import math
import os
import re
import subprocess
import sys
import threading

import pytest

import quack


def _docs_block(source_dir):
    """The Python block of docs/python.md's "### Joints" section."""
    with open(os.path.join(source_dir, "docs", "python.md")) as f:
        text = f.read()
    section = text[text.index("### Joints"):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_the_docs_pendulum_swings_with_the_period_of_the_closed_form(source_dir):
    run = subprocess.run([sys.executable, "-c", _docs_block(source_dir)], capture_output=True,
                         text=True, check=False)
    assert run.returncode == 0, run.stderr
    m = re.search(r"period (\d\.\d+) s; 2 pi sqrt\(L/g\) = (\d\.\d+) s", run.stdout)
    assert m, run.stdout
    period, closed = float(m.group(1)), float(m.group(2))
    assert closed == pytest.approx(2 * math.pi * math.sqrt(1.0 / 10.0), abs=1e-4)
    # The swing is 0.1 rad: the small-angle formula is 0.06% short of the true period.
    assert period == pytest.approx(closed, rel=0.005)
    m = re.search(r"rod length (\d\.\d+) m, tension (\d\.\d+) N", run.stdout)
    assert m, run.stdout
    assert float(m.group(1)) == pytest.approx(1.0, abs=2e-3)
    # At the bottom of a small swing the rod carries about the bob's weight, m g.
    assert float(m.group(2)) == pytest.approx(math.pi * 0.05 ** 2 * 10.0, rel=0.05)


def test_mypy_strict_accepts_the_docs_pendulum(source_dir, tmp_path):
    pytest.importorskip("mypy", reason="mypy is not installed (Debian python3-mypy)")
    block = tmp_path / "pendulum.py"
    block.write_text(_docs_block(source_dir))
    stubs = os.path.join(source_dir, "python", "stubs")
    run = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental",
                          "--cache-dir", str(tmp_path / "cache"), str(block)],
                         capture_output=True, text=True, env=dict(os.environ, MYPYPATH=stubs),
                         check=False)
    assert run.returncode == 0, run.stdout + run.stderr


def two_boxes(gap=1.0):
    """A static post at the origin and a dynamic 1 kg box `gap` metres to its right."""
    w = quack.World()
    post = w.create_body(type="static", name="post")
    w.create_shape(post, quack.box(half=(0.1, 0.1)))
    box = w.create_body(pos=(gap, 0), name="box")
    w.create_shape(box, quack.box(half=(0.5, 0.5)), density=1.0)  # 1 kg
    return w, post, box


def test_a_revolute_joint_holds_its_point_and_reads_back():
    w, post, box = two_boxes()
    j = w.create_joint("revolute", post, box, anchor=(0, 0))
    assert j.valid and j.type == "revolute" and j.world is w
    assert j.body_a == post and j.body_b == box
    assert w.joint_count == 1 and w.joints == [j] and hash(j) == hash(w.joints[0])
    for _ in range(30):  # under a quarter swing (a physical pendulum of 2.5 s from level)
        w.step()
    (ax, ay), (bx, by) = j.anchors
    assert math.hypot(bx - ax, by - ay) < 0.01
    # It swung down about the post: the box's centre stays 1 m from it, turning with it.
    assert math.hypot(*box.position) == pytest.approx(1.0, abs=0.01)
    assert box.position[1] < -0.5 and j.angle < -0.5
    assert j.angle == pytest.approx(math.atan2(box.position[1], box.position[0]), abs=0.01)
    assert math.hypot(*j.force) > 0 and j.translation == 0.0


def test_a_limit_is_on_when_lower_and_upper_are_given():
    w, post, box = two_boxes()
    j = w.create_joint("revolute", post, box, anchor=(0, 0), lower=-0.25, upper=0.25)
    for _ in range(120):
        w.step()
    assert j.angle == pytest.approx(-0.25, abs=0.02)  # hangs on the lower limit
    j.set_limits()  # neither: off
    for _ in range(60):
        w.step()
    assert j.angle < -0.6
    j.set_limits(-0.1, 0.1)
    with pytest.raises(ValueError, match=r"^upper: a limit needs both lower and upper"):
        j.set_limits(lower=0.5)
    with pytest.raises(ValueError, match=r"^lower: must be at most upper"):
        j.set_limits(1.0, 0.5)
    with pytest.raises(ValueError, match=r"^set_limits: a revolute joint's limits must be within"):
        j.set_limits(-4.0, 0.0)


def test_a_motor_turns_and_a_prismatic_motor_slides():
    w = quack.World(gravity=(0, 0))
    hub = w.create_body(type="static")
    wheel = w.create_body(pos=(0, 0))
    w.create_shape(wheel, quack.circle(radius=0.5))
    motor = w.create_joint("revolute", hub, wheel, anchor=(0, 0), motor_speed=2.0,
                           max_motor_torque=100)
    slider = w.create_body(pos=(3, 0))
    w.create_shape(slider, quack.box(half=(0.2, 0.2)))
    rail = w.create_joint("prismatic", hub, slider, anchor=(3, 0), axis=(0, 1),
                          motor_speed=0.5, max_motor_force=100)
    for _ in range(60):
        w.step()
    assert wheel.angular_velocity == pytest.approx(2.0, rel=1e-3)
    assert slider.velocity[1] == pytest.approx(0.5, rel=1e-3)
    assert rail.translation == pytest.approx(0.5, rel=0.05)
    motor.set_motor(speed=-1.0)  # keeps its most torque
    rail.set_motor(enable=False)
    for _ in range(30):
        w.step()
    assert wheel.angular_velocity == pytest.approx(-1.0, rel=1e-3)
    with pytest.raises(ValueError, match=r"^max_force: a revolute joint's motor takes max_torque"):
        motor.set_motor(1.0, max_force=5)
    with pytest.raises(ValueError, match=r"^max_torque: a prismatic joint's motor takes max_force"):
        rail.set_motor(1.0, max_torque=5)
    with pytest.raises(ValueError, match=r"^max_torque: must be finite and >= 0"):
        motor.set_motor(1.0, max_torque=-1)
    with pytest.raises(ValueError, match=r"^speed: must be finite"):
        motor.set_motor(math.inf)


def test_a_mouse_joint_pulls_its_body_to_the_target():
    w, post, box = two_boxes()
    mouse = w.create_joint("mouse", None, box, anchor=(1, 0), target=(1, 2), max_force=1000)
    assert mouse.body_a is None and mouse.type == "mouse"
    assert mouse.anchors[0] == (1.0, 2.0)
    for _ in range(120):
        w.step()
    assert box.position[1] == pytest.approx(2.0, abs=0.05)
    mouse.set_target((3, 2))
    for _ in range(120):
        w.step()
    assert box.position[0] == pytest.approx(3.0, abs=0.05)
    with pytest.raises(ValueError, match=r"^set_target: a revolute joint has no target"):
        w.create_joint("revolute", post, box, anchor=(0, 0)).set_target((0, 0))
    with pytest.raises(ValueError, match=r"^target\[0\]: must be finite"):
        mouse.set_target((math.nan, 0))


def test_other_types_distance_weld_wheel_motor():
    w = quack.World()
    ground = w.create_body(type="static")
    w.create_shape(ground, quack.box(half=(20, 0.5)), friction=1.0)
    bodies = []
    for x in (-6, -2, 2, 6):
        b = w.create_body(pos=(x, 4))
        w.create_shape(b, quack.box(half=(0.3, 0.3)))
        bodies.append(b)
    rope = w.create_joint("distance", ground, bodies[0], anchors=((-6, 6), (-6, 4)),
                          max_length=3)
    spring = w.create_joint("distance", ground, bodies[1], anchors=((-2, 6), (-2, 4)),
                            hertz=2, damping_ratio=1)
    weld = w.create_joint("weld", ground, bodies[2], anchor=(2, 4))
    push = w.create_joint("motor", ground, bodies[3], linear_offset=(6, 3), max_force=500,
                          max_torque=100)
    for _ in range(240):
        w.step()
    assert rope.translation == pytest.approx(3.0, abs=0.02)  # a rope: taut at its most
    # The spring's rest length is 2 m; 0.072 kg on 1 / (2 pi 2 Hz)^2... it sags a little.
    assert 2.0 < spring.translation < 2.2
    assert bodies[2].position == pytest.approx((2, 4), abs=0.01)
    assert bodies[3].position == pytest.approx((6, 3), abs=0.01)
    push.set_offsets((5, 2), 0.5)
    for _ in range(240):
        w.step()
    assert bodies[3].position == pytest.approx((5, 2), abs=0.02)
    assert bodies[3].angle == pytest.approx(0.5, abs=0.02)
    assert weld.angle == pytest.approx(0.0, abs=0.01)
    with pytest.raises(ValueError, match=r"^set_offsets: a weld joint has no offsets"):
        weld.set_offsets((0, 0))
    with pytest.raises(ValueError, match=r"^set_motor: a weld joint has no motor"):
        weld.set_motor(1.0)
    with pytest.raises(ValueError, match=r"^set_limits: a weld joint has no limits"):
        weld.set_limits(0, 1)


def test_a_car_on_wheel_joints_drives():
    w = quack.World()
    ground = w.create_body(type="static", pos=(0, -0.5))
    w.create_shape(ground, quack.box(half=(50, 0.5)), friction=0.9)
    chassis = w.create_body(pos=(0, 1.3))
    w.create_shape(chassis, quack.box(half=(1.4, 0.3)))
    wheels = []
    for x in (-1, 1):
        wheel = w.create_body(pos=(x, 0.6))
        w.create_shape(wheel, quack.circle(radius=0.45), friction=0.9)
        wheels.append(w.create_joint("wheel", chassis, wheel, anchor=(x, 0.6), axis=(0, 1),
                                     hertz=5, damping_ratio=0.7, lower=-0.25, upper=0.25,
                                     motor_speed=0, max_motor_torque=40))
    for _ in range(60):
        w.step()
    still = chassis.position[0]
    assert abs(still) < 0.05  # held by its braked wheels
    for j in wheels:
        j.set_motor(speed=-8)  # clockwise: forwards, to the right
    for _ in range(120):
        w.step()
    assert chassis.position[0] > still + 3.0
    for j in wheels:
        assert -0.26 < j.translation < 0.26


# Each bad argument names itself: (type, keyword arguments, the message's start).
BAD = [
    ("revolute", dict(anchor=(0, 0), hertz=-1), "hertz: must be >= 0"),
    ("revolute", dict(anchor=(0, 0), damping_ratio=0.5), 'damping_ratio: a spring needs its "hertz"'),
    ("revolute", dict(anchor=(0, 0), max_motor_torque=-2), "max_motor_torque: must be >= 0"),
    ("revolute", dict(anchor=(0, 0), motor_speed=3),
     'motor_speed: a motor needs its most torque or force ("max_motor_torque")'),
    ("prismatic", dict(anchor=(0, 0), axis=(1, 0), motor_speed=3),
     'motor_speed: a motor needs its most torque or force ("max_motor_force")'),
    ("revolute", dict(anchor=(0, 0), lower=-1), 'upper: a limit needs both "lower" and "upper"'),
    ("revolute", dict(anchor=(0, 0), upper=1), 'lower: a limit needs both "lower" and "upper"'),
    ("revolute", dict(anchor=(0, 0), lower=1, upper=-1), 'lower: must be at most "upper"'),
    ("revolute", dict(anchor=(0, 0), lower=-4, upper=1),
     "lower: a revolute joint's limits must be within [-pi, pi]"),
    ("revolute", dict(anchor=(0, 0), axis=(1, 0)), "axis: not an argument of a revolute joint"),
    ("revolute", dict(anchor=(0, 0), max_motor_force=1),
     "max_motor_force: not an argument of a revolute joint"),
    ("revolute", dict(), "anchor: the joint's point [x, y] is required"),
    ("revolute", dict(anchor=(0, math.inf)), "anchor"),
    ("revolute", dict(anchor=(0, 0), break_force=-1), "break_force: must be >= 0"),
    ("revolute", dict(anchor=(0, 0), break_torque=math.nan), "break_torque: must be finite"),
    ("revolute", dict(anchor=(0, 0), hertz="5"), "hertz: must be a number"),
    ("revolute", dict(anchor=(0, 0), hertz=True), "hertz: must be a number, not a bool"),
    ("prismatic", dict(anchor=(0, 0)), "axis: the direction [x, y] is required"),
    ("prismatic", dict(anchor=(0, 0), axis=(0, 0)), "axis: must not be zero"),
    ("wheel", dict(anchor=(0, 0), axis=(0, 1), max_motor_force=1),
     "max_motor_force: not an argument of a wheel joint"),
    ("distance", dict(anchor=(0, 0)), "anchor: not an argument of a distance joint"),
    ("distance", dict(anchors=((0, 0),)), "anchors: must be two points"),
    ("distance", dict(anchors=((0, 0), (1, 0)), length=-1), "length: must be >= 0"),
    ("distance", dict(anchors=((0, 0), (1, 0)), min_length=2, max_length=1),
     'min_length: must be at most "max_length"'),
    ("weld", dict(anchor=(0, 0), linear_hertz=-1), "linear_hertz: must be >= 0"),
    ("weld", dict(anchor=(0, 0), angular_damping_ratio=-1), "angular_damping_ratio: must be >= 0"),
    ("motor", dict(correction_factor=2), "correction_factor: must be in [0, 1]"),
    ("motor", dict(max_torque=-1), "max_torque: must be >= 0"),
    ("motor", dict(linear_offset=(1, 2, 3)), "linear_offset: must be [x, y]"),
    ("motor", dict(angular_offset=math.inf), "angular_offset: must be finite"),
    ("mouse", dict(anchor=(0, 0)), "target: the point [x, y] it pulls to is required"),
    ("mouse", dict(anchor=(0, 0), target=(1, 1), hertz=0),
     "hertz: a mouse joint's spring must be > 0 Hz"),
    ("mouse", dict(anchor=(0, 0), target=(1, 1), max_force=-5), "max_force: must be >= 0"),
    ("mouse", dict(anchor=(0, 0), target=(1, 1), lower=0, upper=1),
     "lower: not an argument of a mouse joint"),
    ("hinge", dict(anchor=(0, 0)), 'type: "hinge" is not a joint type'),
]


@pytest.mark.parametrize("kind,kwargs,message", BAD,
                         ids=[f"{t}-{m.split(':')[0]}" for t, _, m in BAD])
def test_each_bad_argument_names_itself(kind, kwargs, message):
    w, post, box = two_boxes()
    a = None if kind == "mouse" else post
    with pytest.raises(ValueError) as e:
        w.create_joint(kind, a, box, **kwargs)
    assert str(e.value).startswith(message), str(e.value)
    assert w.joint_count == 0


def test_bad_bodies_name_a_and_b():
    w, post, box = two_boxes()
    other = quack.World().create_body()
    cases = [
        (("revolute", None, box), "a: a revolute joint needs body a"),
        (("mouse", post, box), "a: must be None for a mouse joint"),
        (("revolute", post, post), "b: the same body as a"),
        (("revolute", post, "box"), "b: must be a quack.BodyHandle"),
        (("revolute", other, box), "a: a body of another world"),
    ]
    for args, message in cases:
        with pytest.raises(ValueError, match="^" + re.escape(message)):
            w.create_joint(*args, anchor=(0, 0), target=(0, 0))
    with pytest.raises(TypeError):
        w.create_joint("revolute", post, box, (0, 0))  # the settings are keyword-only
    assert w.joint_count == 0


def test_handles_go_stale_when_a_body_is_destroyed():
    w, post, box = two_boxes()
    j = w.create_joint("revolute", post, box, anchor=(0, 0))
    other = w.create_joint("mouse", None, box, anchor=(1, 0), target=(1, 1))
    ended = []
    w.on_joint_end(ended.append)
    w.destroy_body(box)
    assert not j.valid and not other.valid
    assert w.joint_count == 0 and w.joints == []
    assert "stale" in repr(j)
    for read in (lambda: j.type, lambda: j.anchors, lambda: j.force, lambda: j.torque,
                 lambda: j.angle, lambda: j.translation, lambda: j.body_a, lambda: j.body_b,
                 lambda: j.set_motor(1.0), lambda: j.set_limits(), j.destroy,
                 lambda: other.set_target((0, 0))):
        with pytest.raises(ValueError, match=r"^stale quack.JointHandle"):
            read()
    with pytest.raises(ValueError, match=r"^joint: stale handle"):
        w.destroy_joint(j)
    # The ends are reported with the next step.
    w.step()
    events = {e.joint: e for e in w.events().joint_end}
    assert set(events) == {j, other}
    assert all(e.reason == "body-destroyed" for e in events.values())
    assert events[j].body_a == post and not events[j].body_b.valid
    assert events[other].body_a is None and events[other].body_b == box
    assert ended == w.events().joint_end
    # A joint made in the slot again is a new joint: the old handle stays stale.
    box2 = w.create_body(pos=(1, 0))
    w.create_shape(box2, quack.circle(radius=0.2))
    j2 = w.create_joint("revolute", post, box2, anchor=(0, 0))
    assert j2 != j and not j.valid and j2.valid


def test_destroy_ends_a_joint_without_an_event():
    w, post, box = two_boxes()
    j = w.create_joint("revolute", post, box, anchor=(0, 0))
    k = w.create_joint("distance", post, box, anchors=((0, 0), (1, 0)))
    j.destroy()
    w.destroy_joint(k)
    assert not j.valid and not k.valid and w.joint_count == 0
    w.step()
    assert w.events().joint_end == []
    with pytest.raises(ValueError, match=r"^joint: must be a quack.JointHandle"):
        w.destroy_joint(post)
    with pytest.raises(ValueError, match=r"^joint: a joint of another world"):
        w2, p2, b2 = two_boxes()
        w.destroy_joint(w2.create_joint("weld", p2, b2, anchor=(0, 0)))


def test_a_joint_breaks_past_its_break_force():
    """A 1 kg box hangs from a weld (10 N of weight); a 200 kg box lands on it."""
    w, post, box = two_boxes()
    weld = w.create_joint("weld", post, box, anchor=(0.5, 0), break_force=150)
    seen = []
    w.on_joint_end(lambda e: seen.append((e.joint, e.reason, math.hypot(*e.force))))
    for _ in range(30):
        w.step()
    assert weld.valid and math.hypot(*weld.force) == pytest.approx(10.0, rel=0.05)
    weight = w.create_body(pos=(1, 2))
    w.create_shape(weight, quack.box(half=(0.5, 0.5)), density=200)
    steps = 0
    while weld.valid and steps < 120:
        w.step()
        steps += 1
    assert not weld.valid, "the weld held 200 kg"
    (joint, reason, force), = seen
    assert joint == weld and reason == "broken" and force > 150
    (event,) = w.events().joint_end
    assert event.joint == weld and event.body_a == post and event.body_b == box
    assert event.body_b.valid  # the body stays; only the joint went
    for _ in range(30):
        w.step()
    assert box.position[1] < -0.5  # falling, now free


def test_joints_of_a_scene_file_and_the_state_file(source_dir, tmp_path):
    path = os.path.join(source_dir, "scenes", "joints.json")
    with open(path) as f:
        listed = json.load(f)["joints"]
    w = quack.load_scene(path)
    assert [j.type for j in w.joints] == [j["type"] for j in listed]
    # A joint made in Python is written like the scene's own.
    post, lift = w.body("pivot"), w.body("link19")
    w.create_joint("distance", post, lift, anchors=(post.position, lift.position))
    w.step()
    out = tmp_path / "state.json"
    w.write_state(str(out))
    written = json.loads(out.read_text())["joints"]
    assert len(written) == len(listed) + 1
    assert written[-1]["type"] == "distance"
    assert written[-1]["a"] == "pivot" and written[-1]["b"] == "link19"


def test_snapshots_bring_joints_back():
    w, post, box = two_boxes()
    j = w.create_joint("revolute", post, box, anchor=(0, 0))
    saved = w.snapshot()
    for _ in range(30):
        w.step()
    angle = j.angle
    j.destroy()
    w.restore(saved)
    assert j.valid and w.joint_count == 1
    for _ in range(30):
        w.step()
    assert j.angle == angle


def test_joint_calls_refuse_while_another_thread_steps():
    w, post, box = two_boxes(gap=0.55)  # on the post: a contact begins in the first step
    j = w.create_joint("mouse", None, box, anchor=(0.55, 0), target=(0.55, 0))
    in_step, done = threading.Event(), threading.Event()

    def hold_the_step(a, b):
        in_step.set()
        done.wait(30)

    w.on_contact_begin(hold_the_step)
    calls = {
        "create_joint": lambda: w.create_joint("revolute", post, box, anchor=(0, 0)),
        "destroy_joint": lambda: w.destroy_joint(j),
        "joints": lambda: w.joints,
        "joint_count": lambda: w.joint_count,
        "on_joint_end": lambda: w.on_joint_end(lambda e: None),
        "valid": lambda: j.valid,
        "type": lambda: j.type,
        "anchors": lambda: j.anchors,
        "force": lambda: j.force,
        "set_target": lambda: j.set_target((0, 0)),
        "destroy": j.destroy,
    }
    t = threading.Thread(target=w.step)
    t.start()
    refused = []
    try:
        assert in_step.wait(30), "the step's callback never ran"
        for name, call in calls.items():
            with pytest.raises(RuntimeError, match="the world is stepping"):
                call()
            refused.append(name)
        assert re.fullmatch(r"JointHandle\(index=0, generation=\d+\)", repr(j))
    finally:
        done.set()
        t.join()
    assert refused == list(calls)
    assert j.valid and w.joint_count == 1
