"""Shapes: every constructor, the JSON dict form, and the errors (the io layer's messages)."""

import math

import numpy as np
import pytest

import quack

L_OUTLINE = [[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]]


def test_each_kind_by_keywords_and_by_dict():
    made = {
        "circle": quack.circle(radius=0.5, center=(1, 2)),
        "capsule": quack.capsule(p1=(-1, 0), p2=(1, 0), radius=0.25),
        "segment": quack.segment(p1=(0, 0), p2=(4, 0)),
        "box": quack.box(half=(1, 0.5), center=(0, 1), angle=0.3, radius=0.1),
        "polygon": quack.polygon(points=[[0, 0], [1, 0], [0, 1]], radius=0),
        "concave": quack.concave(points=L_OUTLINE),
    }
    for kind, shape in made.items():
        assert isinstance(shape, quack.Shape)
        assert shape.type == kind
        d = shape.to_dict()
        assert d["type"] == kind
        again = quack.shape(d)
        assert again.to_dict() == d
        assert again.area() == shape.area()
    assert made["concave"].concave and made["concave"].piece_count >= 2
    assert not made["box"].concave and made["box"].piece_count == 1


def test_positional_arguments_follow_the_documented_order():
    assert quack.circle(0.5).to_dict() == {"type": "circle", "radius": 0.5}
    assert quack.capsule((0, 0), (1, 0), 0.5).to_dict()["radius"] == 0.5
    assert quack.box((2, 1)).to_dict() == {"type": "box", "half": [2, 1]}


def test_areas_worked_by_hand():
    assert quack.circle(radius=0.5).area() == pytest.approx(math.pi * 0.25, rel=1e-6)
    assert quack.box(half=(1, 0.5)).area() == pytest.approx(2.0, rel=1e-6)
    assert quack.polygon(points=[[0, 0], [1, 0], [0, 1]]).area() == pytest.approx(0.5, rel=1e-6)
    # Rectangle 2 x 0.5 plus a disk of radius 0.25.
    assert quack.capsule(p1=(-1, 0), p2=(1, 0), radius=0.25).area() == pytest.approx(
        1.0 + math.pi * 0.0625, rel=1e-6)
    assert quack.segment(p1=(0, 0), p2=(1, 0)).area() == 0.0
    assert quack.concave(points=L_OUTLINE).area() == pytest.approx(7.0, rel=1e-6)
    holed = quack.concave(points=[[0, 0], [4, 0], [4, 4], [0, 4]],
                          holes=[[[1, 1], [3, 1], [3, 3], [1, 3]]])
    assert holed.area() == pytest.approx(12.0, rel=1e-6)


def test_contains_uses_the_pose():
    box = quack.box(half=(1, 0.5))
    assert box.contains((0.9, 0.0))
    assert not box.contains((0.0, 0.9))
    # Turned a quarter turn, the box is tall.
    assert box.contains((0.0, 0.9), (0, 0, math.pi / 2))
    assert box.contains((10.0, 10.9), (10, 10, math.pi / 2))
    ell = quack.concave(points=L_OUTLINE)
    assert ell.contains((3.5, 0.5)) and ell.contains((0.5, 3.5)) and not ell.contains((3, 3))


def test_numpy_values_are_accepted():
    c = quack.circle(radius=np.float32(0.5), center=np.array([1.0, 2.0]))
    assert c.to_dict() == {"type": "circle", "radius": 0.5, "center": [1.0, 2.0]}
    p = quack.polygon(points=np.array([[0, 0], [1, 0], [0, 1]]))
    assert p.area() == pytest.approx(0.5)


@pytest.mark.parametrize("make, message", [
    (lambda: quack.circle(radius=-1), "circle.radius: must be > 0"),
    (lambda: quack.circle(radius=float("nan")), "circle.radius: must be finite (as a float)"),
    (lambda: quack.circle(radius=1e39), "circle.radius: must be finite (as a float)"),
    (lambda: quack.circle(radius="big"), "circle.radius: must be a number"),
    (lambda: quack.circle(radius=object()), "circle.radius: a object is not a JSON value"),
    (lambda: quack.capsule(p1=(0, 0), p2=(0, 0), radius=0.5), "capsule: capsule p1 and p2 coincide"),
    (lambda: quack.segment(p1=(0, 0), p2=(0, 0)), "segment: segment p1 and p2 coincide"),
    (lambda: quack.box(half=(1,)), "box.half: must be [x, y]"),
    (lambda: quack.box(half=(1, -1)), "box.half: must be > 0"),
    (lambda: quack.box(half=(1e10, 1)), "box.half[0]: 1e+10 m is beyond the coordinate limit"),
    (lambda: quack.polygon(points=[[0, 0], [1, 0]]), "polygon.points: needs at least 3 points"),
    (lambda: quack.polygon(points=L_OUTLINE), "(use a concave shape)"),
    (lambda: quack.concave(points=[[0, 0], [2, 2], [2, 0], [0, 2]]), "concave: edges 0 and 2 cross"),
    (lambda: quack.shape({"type": "blob"}), 'shape.type: unknown shape type "blob"'),
    (lambda: quack.shape({"type": "circle", "radius": 1, "colour": 2}),
     "shape.colour: unknown key"),
    (lambda: quack.shape({"radius": 1}), "shape.type: missing"),
    (lambda: quack.shape({"type": "circle"}), "shape.radius: missing"),
    (lambda: quack.shape([1, 2]), "shape: must be an object"),
    (lambda: quack.shape({1: 2}), "shape: dict keys must be strings, not int"),
])
def test_bad_shapes_raise_value_error_with_the_message(make, message):
    with pytest.raises(ValueError) as error:
        make()
    assert message in str(error.value)


def test_repr_shows_the_json():
    assert repr(quack.circle(radius=0.5)) == 'quack.shape({"radius":0.5,"type":"circle"})'


class _Index:
    """An integer-like object: __index__ only."""

    def __init__(self, value):
        self.value = value

    def __index__(self):
        return self.value


def test_a_self_referencing_or_very_deep_container_is_a_value_error():
    """Issue 28, item 1: the Python to JSON conversion followed a list or dict that contains
    itself (and a 200,000-deep list) until the C++ stack overflowed (SIGSEGV)."""
    looped = []
    looped.append(looped)
    with pytest.raises(ValueError, match=r"^polygon\.points: nested more than 64 levels deep"):
        quack.polygon(looped)
    d = {"type": "circle", "radius": 1}
    d["center"] = d
    with pytest.raises(ValueError, match=r"^shape: nested more than 64 levels deep"):
        quack.shape(d)
    deep = [0.0, 0.0]
    for _ in range(200_000):
        deep = [deep]
    with pytest.raises(ValueError, match=r"^circle\.center: nested more than 64 levels deep"):
        quack.circle(radius=1, center=deep)
    # A tuple in a tuple, and a dict in a list in a dict: the same limit.
    t = (1.0,)
    for _ in range(100):
        t = (t,)
    with pytest.raises(ValueError, match=r"^circle\.center: nested"):
        quack.circle(radius=1, center=t)
    # Shallow nesting is still read (and refused by the format, with its own message).
    with pytest.raises(ValueError, match=r"circle\.center"):
        quack.circle(radius=1, center=[[[0.0]]])


def test_out_of_range_integers_are_value_errors_naming_the_argument():
    """Issue 28, item 10: numpy uint64 beyond int64, and an __index__ returning 2**70, gave
    RuntimeError: Unable to cast ...; a complex number lost its imaginary part."""
    with pytest.raises(ValueError, match=r"^circle\.radius"):
        quack.circle(radius=np.uint64(2**64 - 1))
    with pytest.raises(ValueError, match=r"^circle\.radius"):
        quack.circle(radius=_Index(2**70))
    with pytest.raises(ValueError, match=r"^circle\.radius"):
        quack.circle(radius=10**400)
    with pytest.raises(ValueError, match=r"^circle\.radius: a complex number"):
        quack.circle(radius=np.complex128(1 + 2j))
    with pytest.raises(ValueError, match=r"^circle\.radius: a complex number"):
        quack.circle(radius=1j)
    # In range, the same objects are numbers.
    assert quack.circle(radius=_Index(2)).to_dict()["radius"] == 2
    assert quack.circle(radius=np.uint64(3)).to_dict()["radius"] == 3
    with pytest.raises(ValueError, match=r"^pa\[0\]: must be a real number"):
        quack.distance(quack.circle(1), (np.complex128(1 + 1j), 0, 0), quack.circle(1), None)
    with pytest.raises(ValueError, match=r"^pa\[0\]: must be a number, not a bool"):
        quack.distance(quack.circle(1), (True, 0, 0), quack.circle(1), None)
