// The single-pair queries: the ops of `quack query` as functions of the same names, with
// results whose fields carry the JSON answer's names (and snake_case aliases).

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "quack/collision/manifold.hpp"
#include "quack/collision/pieces.hpp"
#include "quack/collision/shape_cast.hpp"
#include "quack/collision/toi.hpp"

namespace quack::python {

namespace {

struct OverlapResult {
  bool overlap = false;
};

struct DistanceResult {
  DistanceOutput d;
};

struct PenetrationResult {
  PenetrationOutput p;
};

struct ManifoldPointResult {
  ManifoldPoint p;
};

struct ManifoldResult {
  Manifold m;
};

struct RayCastResult {
  RayHit h;
};

struct ShapeCastResult {
  ShapeCastOutput c;
};

struct ToiResult {
  ToiOutput t;
};

double d(float f) {
  return static_cast<double>(f);
}

// The ops that want one convex shape refuse a concave one with `quack query`'s message.
void requireConvex(const PyShape& s, const char* which, const char* op) {
  if (s.concave) {
    raiseValue(std::string(which) +
               ": a concave shape supports ops overlap, distance and penetration only, not " + op);
  }
}

// A sweep (pose_from, pose_to) of a convex shape, turning about the shape's centre, the
// short way round (as `quack query` op toi).
Sweep toSweep(py::handle sweep, const PyShape& shape, const std::string& path) {
  if (!py::isinstance<py::sequence>(sweep) || py::isinstance<py::str>(sweep) ||
      py::len(sweep) != 2) {
    raiseValue(path + ": must be (pose_from, pose_to), each pose (x, y, angle)");
  }
  py::sequence s = py::reinterpret_borrow<py::sequence>(sweep);
  Transform from = toTransform(s[0], path + "[0]");
  Transform to = toTransform(s[1], path + "[1]");
  return makeSweep(makeProxy(shape.pieces.front()).center(), from, to);
}

}  // namespace

void registerQueries(py::module_& m) {
  py::class_<OverlapResult>(m, "OverlapResult", "Answer of quack.overlap.")
      .def_readonly("overlap", &OverlapResult::overlap, "The closed shapes share a point.")
      .def("__bool__", [](const OverlapResult& r) { return r.overlap; })
      .def(
          "to_dict",
          [](const OverlapResult& r) { return py::dict(py::arg("overlap") = r.overlap); },
          "The answer as `quack query` writes it (a dict).")
      .def("__repr__", [](const OverlapResult& r) {
        return std::string("OverlapResult(overlap=") + (r.overlap ? "True" : "False") + ")";
      });

  py::class_<DistanceResult>(m, "DistanceResult",
                             "Answer of quack.distance (world frame; normal from a to b).")
      .def_property_readonly(
          "distance", [](const DistanceResult& r) { return d(r.d.distance); },
          "Distance between the shapes, metres (0 when they overlap).")
      .def_property_readonly(
          "pointA", [](const DistanceResult& r) { return toTuple(r.d.pointA); },
          "Closest point on a, world frame.")
      .def_property_readonly(
          "pointB", [](const DistanceResult& r) { return toTuple(r.d.pointB); },
          "Closest point on b, world frame.")
      .def_property_readonly(
          "point_a", [](const DistanceResult& r) { return toTuple(r.d.pointA); },
          "pointA (PEP 8 name).")
      .def_property_readonly(
          "point_b", [](const DistanceResult& r) { return toTuple(r.d.pointB); },
          "pointB (PEP 8 name).")
      .def_property_readonly(
          "normal", [](const DistanceResult& r) { return toTuple(r.d.normal); },
          "Unit vector from a to b.")
      .def_property_readonly(
          "iterations", [](const DistanceResult& r) { return r.d.iterations; },
          "GJK iterations used.")
      .def_property_readonly(
          "status", [](const DistanceResult& r) { return toString(r.d.status); },
          "GJK status, one of quack.GJK_STATUSES.")
      .def(
          "to_dict",
          [](const DistanceResult& r) {
            return py::dict(
                py::arg("distance") = d(r.d.distance), py::arg("pointA") = toTuple(r.d.pointA),
                py::arg("pointB") = toTuple(r.d.pointB), py::arg("normal") = toTuple(r.d.normal),
                py::arg("iterations") = r.d.iterations, py::arg("status") = toString(r.d.status));
          },
          "The answer as `quack query` writes it (a dict).")
      .def("__repr__", [](const DistanceResult& r) {
        return "DistanceResult(distance=" + std::to_string(r.d.distance) +
               ", status=" + toString(r.d.status) + ")";
      });

  py::class_<PenetrationResult>(m, "PenetrationResult",
                                "Answer of quack.penetration (world frame; normal from a to b; "
                                "depth 0 when apart).")
      .def_property_readonly(
          "overlap", [](const PenetrationResult& r) { return r.p.overlap; }, "The shapes overlap.")
      .def_property_readonly(
          "depth", [](const PenetrationResult& r) { return d(r.p.depth); },
          "Penetration depth, metres (0 when apart).")
      .def_property_readonly(
          "normal", [](const PenetrationResult& r) { return toTuple(r.p.normal); },
          "Unit vector from a to b along which b moves out.")
      .def_property_readonly(
          "pointA", [](const PenetrationResult& r) { return toTuple(r.p.pointA); },
          "Deepest point of a inside b, world frame.")
      .def_property_readonly(
          "pointB", [](const PenetrationResult& r) { return toTuple(r.p.pointB); },
          "Deepest point of b inside a, world frame.")
      .def_property_readonly(
          "point_a", [](const PenetrationResult& r) { return toTuple(r.p.pointA); },
          "pointA (PEP 8 name).")
      .def_property_readonly(
          "point_b", [](const PenetrationResult& r) { return toTuple(r.p.pointB); },
          "pointB (PEP 8 name).")
      .def_property_readonly(
          "iterations", [](const PenetrationResult& r) { return r.p.iterations; },
          "EPA iterations used.")
      .def_property_readonly(
          "status", [](const PenetrationResult& r) { return toString(r.p.status); },
          "EPA status, one of quack.EPA_STATUSES.")
      .def(
          "to_dict",
          [](const PenetrationResult& r) {
            return py::dict(
                py::arg("overlap") = r.p.overlap, py::arg("depth") = d(r.p.depth),
                py::arg("normal") = toTuple(r.p.normal), py::arg("pointA") = toTuple(r.p.pointA),
                py::arg("pointB") = toTuple(r.p.pointB), py::arg("iterations") = r.p.iterations,
                py::arg("status") = toString(r.p.status));
          },
          "The answer as `quack query` writes it (a dict).")
      .def("__repr__", [](const PenetrationResult& r) {
        return std::string("PenetrationResult(overlap=") + (r.p.overlap ? "True" : "False") +
               ", depth=" + std::to_string(r.p.depth) + ")";
      });

  py::class_<ManifoldPointResult>(m, "ManifoldPoint", "One contact point (world frame).")
      .def_property_readonly(
          "point", [](const ManifoldPointResult& r) { return toTuple(r.p.point); },
          "The contact point, world frame.")
      .def_property_readonly(
          "separation", [](const ManifoldPointResult& r) { return d(r.p.separation); },
          "Signed separation, metres (negative: overlap).")
      .def_property_readonly(
          "id", [](const ManifoldPointResult& r) { return r.p.id; },
          "Feature id: the same for the same pair of features from step to step.")
      .def(
          "to_dict",
          [](const ManifoldPointResult& r) {
            return py::dict(py::arg("point") = toTuple(r.p.point),
                            py::arg("separation") = d(r.p.separation), py::arg("id") = r.p.id);
          },
          "The point as `quack query` writes it (a dict).");

  py::class_<ManifoldResult>(m, "ManifoldResult",
                             "Answer of quack.manifold: normal from a to b ((0, 0) without "
                             "points) and up to two points.")
      .def_property_readonly(
          "normal",
          [](const ManifoldResult& r) { return toTuple(r.m.pointCount > 0 ? r.m.normal : Vec2{}); },
          "Unit contact normal from a to b.")
      .def_property_readonly(
          "points",
          [](const ManifoldResult& r) {
            py::list out;
            for (int i = 0; i < r.m.pointCount; ++i)
              out.append(ManifoldPointResult{r.m.points[i]});
            return out;
          },
          "The contact points (quack.ManifoldPoint), 0 to 2.")
      .def(
          "to_dict",
          [](const ManifoldResult& r) {
            py::list points;
            for (int i = 0; i < r.m.pointCount; ++i)
              points.append(py::cast(ManifoldPointResult{r.m.points[i]}).attr("to_dict")());
            return py::dict(py::arg("normal") = toTuple(r.m.pointCount > 0 ? r.m.normal : Vec2{}),
                            py::arg("points") = points);
          },
          "The answer as `quack query` writes it (a dict).")
      .def("__repr__", [](const ManifoldResult& r) {
        return "ManifoldResult(points=" + std::to_string(r.m.pointCount) + ")";
      });

  py::class_<RayCastResult>(m, "RayCastResult",
                            "Answer of quack.raycast (world frame; point and normal (0, 0) "
                            "when missed).")
      .def_property_readonly(
          "hit", [](const RayCastResult& r) { return r.h.hit; }, "The ray enters the shape.")
      .def_property_readonly(
          "fraction", [](const RayCastResult& r) { return d(r.h.fraction); },
          "Where: origin + fraction * translation.")
      .def_property_readonly(
          "point", [](const RayCastResult& r) { return toTuple(r.h.point); },
          "Entry point, world frame.")
      .def_property_readonly(
          "normal", [](const RayCastResult& r) { return toTuple(r.h.normal); },
          "Surface normal at the entry point.")
      .def(
          "to_dict",
          [](const RayCastResult& r) {
            return py::dict(py::arg("hit") = r.h.hit, py::arg("fraction") = d(r.h.fraction),
                            py::arg("point") = toTuple(r.h.point),
                            py::arg("normal") = toTuple(r.h.normal));
          },
          "The answer as `quack query` writes it (a dict).")
      .def("__repr__", [](const RayCastResult& r) {
        return std::string("RayCastResult(hit=") + (r.h.hit ? "True" : "False") +
               ", fraction=" + std::to_string(r.h.fraction) + ")";
      });

  py::class_<ShapeCastResult>(m, "ShapeCastResult",
                              "Answer of quack.shapecast (world frame; b moves by translation).")
      .def_property_readonly(
          "hit", [](const ShapeCastResult& r) { return r.c.hit; },
          "b touches a along the translation.")
      .def_property_readonly(
          "fraction", [](const ShapeCastResult& r) { return d(r.c.fraction); },
          "Where b first touches: pose + fraction * translation.")
      .def_property_readonly(
          "point", [](const ShapeCastResult& r) { return toTuple(r.c.point); },
          "First contact point, world frame.")
      .def_property_readonly(
          "normal", [](const ShapeCastResult& r) { return toTuple(r.c.normal); },
          "Contact normal from a to b.")
      .def_property_readonly(
          "depth", [](const ShapeCastResult& r) { return d(r.c.depth); },
          "Overlap at the start, metres (the shapes already touch).")
      .def_property_readonly(
          "status", [](const ShapeCastResult& r) { return toString(r.c.status); }, "Cast status.")
      .def(
          "to_dict",
          [](const ShapeCastResult& r) {
            return py::dict(
                py::arg("hit") = r.c.hit, py::arg("fraction") = d(r.c.fraction),
                py::arg("point") = toTuple(r.c.point), py::arg("normal") = toTuple(r.c.normal),
                py::arg("depth") = d(r.c.depth), py::arg("status") = toString(r.c.status));
          },
          "The answer as `quack query` writes it (a dict).")
      .def("__repr__", [](const ShapeCastResult& r) {
        return std::string("ShapeCastResult(hit=") + (r.c.hit ? "True" : "False") +
               ", fraction=" + std::to_string(r.c.fraction) + ")";
      });

  py::class_<ToiResult>(m, "ToiResult", "Answer of quack.toi.")
      .def_property_readonly(
          "status", [](const ToiResult& r) { return toString(r.t.status); },
          "Time of impact status, as `quack query` answers it.")
      .def_property_readonly(
          "t", [](const ToiResult& r) { return d(r.t.t); },
          "Fraction of the sweep in [0, 1] at the impact (1 when none).")
      .def(
          "to_dict",
          [](const ToiResult& r) {
            return py::dict(py::arg("status") = toString(r.t.status), py::arg("t") = d(r.t.t));
          },
          "The answer as `quack query` writes it (a dict).")
      .def("__repr__", [](const ToiResult& r) {
        return std::string("ToiResult(status=") + toString(r.t.status) +
               ", t=" + std::to_string(r.t.t) + ")";
      });

  m.def(
      "overlap",
      [](py::handle a, py::handle pa, py::handle b, py::handle pb) {
        const PyShape& sa = toShape(a, "a");
        const PyShape& sb = toShape(b, "b");
        return OverlapResult{
            overlapPieces(sa.pieces, toTransform(pa, "pa"), sb.pieces, toTransform(pb, "pb"))};
      },
      py::arg("a"), py::arg("pa"), py::arg("b"), py::arg("pb"),
      "Whether shape a at pose pa (x, y, angle) and b at pb share a point.");
  m.def(
      "distance",
      [](py::handle a, py::handle pa, py::handle b, py::handle pb) {
        const PyShape& sa = toShape(a, "a");
        const PyShape& sb = toShape(b, "b");
        return DistanceResult{
            distancePieces(sa.pieces, toTransform(pa, "pa"), sb.pieces, toTransform(pb, "pb"))};
      },
      py::arg("a"), py::arg("pa"), py::arg("b"), py::arg("pb"),
      "Distance and witness points (GJK); distance 0 when they overlap.");
  m.def(
      "penetration",
      [](py::handle a, py::handle pa, py::handle b, py::handle pb) {
        const PyShape& sa = toShape(a, "a");
        const PyShape& sb = toShape(b, "b");
        return PenetrationResult{
            penetrationPieces(sa.pieces, toTransform(pa, "pa"), sb.pieces, toTransform(pb, "pb"))};
      },
      py::arg("a"), py::arg("pa"), py::arg("b"), py::arg("pb"),
      "Penetration depth, normal and deepest points (GJK, then EPA); depth 0 when apart.");
  m.def(
      "manifold",
      [](py::handle a, py::handle pa, py::handle b, py::handle pb, py::handle speculative) {
        const PyShape& sa = toShape(a, "a");
        const PyShape& sb = toShape(b, "b");
        requireConvex(sa, "a", "manifold");
        requireConvex(sb, "b", "manifold");
        const Transform ta = toTransform(pa, "pa");
        const Transform tb = toTransform(pb, "pb");
        const float s =
            speculative.is_none() ? kSpeculativeDistance : toLength(speculative, "speculative");
        return ManifoldResult{collide(sa.pieces.front(), ta, sb.pieces.front(), tb, s)};
      },
      py::arg("a"), py::arg("pa"), py::arg("b"), py::arg("pb"), py::arg("speculative") = py::none(),
      "Contact manifold of two convex shapes: points up to speculative metres apart (default "
      "0.02).");
  m.def(
      "raycast",
      [](py::handle a, py::handle pa, py::handle origin, py::handle translation) {
        const PyShape& sa = toShape(a, "a");
        return RayCastResult{rayCastPieces(sa.pieces, toTransform(pa, "pa"),
                                           toPosition(origin, "origin"),
                                           toPosition(translation, "translation"))};
      },
      py::arg("a"), py::arg("pa"), py::arg("origin"), py::arg("translation"),
      "The ray origin + t translation, t in [0, 1] (world frame), against shape a at pa: the "
      "first point where it enters.");
  m.def(
      "shapecast",
      [](py::handle a, py::handle pa, py::handle b, py::handle pb, py::handle translation) {
        const PyShape& sa = toShape(a, "a");
        const PyShape& sb = toShape(b, "b");
        requireConvex(sa, "a", "shapecast");
        requireConvex(sb, "b", "shapecast");
        const Transform ta = toTransform(pa, "pa");
        const Transform tb = toTransform(pb, "pb");
        return ShapeCastResult{castShape(sa.pieces.front(), ta, sb.pieces.front(), tb,
                                         toPosition(translation, "translation"))};
      },
      py::arg("a"), py::arg("pa"), py::arg("b"), py::arg("pb"), py::arg("translation"),
      "Moves b by translation (world frame) and reports where it first touches a.");
  m.def(
      "toi",
      [](py::handle a, py::handle sweepA, py::handle b, py::handle sweepB, py::handle target) {
        const PyShape& sa = toShape(a, "a");
        const PyShape& sb = toShape(b, "b");
        requireConvex(sa, "a", "toi");
        requireConvex(sb, "b", "toi");
        const Sweep wa = toSweep(sweepA, sa, "sweepA");
        const Sweep wb = toSweep(sweepB, sb, "sweepB");
        const float tgt = target.is_none() ? kToiTargetSeparation : toLength(target, "target");
        return ToiResult{computeToi(sa.pieces.front(), wa, sb.pieces.front(), wb, 1.0f, tgt)};
      },
      py::arg("a"), py::arg("sweepA"), py::arg("b"), py::arg("sweepB"),
      py::arg("target") = py::none(),
      "Time of impact: the first fraction t in [0, 1] at which a moving by sweepA and b "
      "moving by sweepB (each (pose_from, pose_to)) come within target metres (default "
      "0.005).");
}

}  // namespace quack::python
