#pragma once
/// The 3D convex shapes: sphere, capsule, box (a hull), convex hull and triangle.
///
/// Names: a 3D type carries a `3` where a 2D type has the same name (`Capsule3`, `Hull3`,
/// `Triangle3`, `Transform3`); `Sphere` has no 2D namesake. Shapes are plain values in their
/// own frame ("shape frame"); a `Transform3` `worldFromShape` places them. Conventions:
/// right-handed, y up, metres. Build them with the `make*` functions, which check every
/// number and return an error naming what is wrong; the structs themselves do not check.

#include <span>
#include <variant>

#include "quack/core/result.hpp"
#include "quack/geometry/hull3.hpp"
#include "quack/math/transform3.hpp"

namespace quack {

/// Solid ball. Shape frame.
struct Sphere {
  Vec3 center;
  float radius = 0.0f;
};

/// Solid capsule: the points within `radius` of the segment p1-p2. Shape frame.
struct Capsule3 {
  Vec3 p1, p2;
  float radius = 0.0f;
};

/// Triangle with no thickness and no volume (terrain, meshes); one-sided for ray casts
/// only in that its `normal` is cross(v[1] - v[0], v[2] - v[0]) normalised (counter-clockwise
/// seen from the front). Shape frame.
struct Triangle3 {
  Vec3 v[3];
};

/// Errors: non-finite centre or radius, radius <= 0.
Result<Sphere> makeSphere(Vec3 center, float radius);
/// Errors: non-finite numbers, radius <= 0, p1 and p2 closer than kHull3RelativeTolerance
/// of the radius (use a sphere).
Result<Capsule3> makeCapsule3(Vec3 p1, Vec3 p2, float radius);
/// Errors: non-finite numbers, collinear vertices (zero area, relative to the longest edge
/// by kHull3RelativeTolerance).
Result<Triangle3> makeTriangle3(Vec3 a, Vec3 b, Vec3 c);
/// Convex hull of `points` (see computeHull3, which also reports what was dropped), rounded
/// by `radius` metres (the points within `radius` of the hull). Errors: computeHull3's, a
/// radius that is not finite, negative or beyond kMaxCoordinate.
Result<Hull3> makeHull3(std::span<const Vec3> points, float radius = 0.0f);
/// Box with half-extents `half`, placed in the shape frame by `shapeFromBox` (identity: centred
/// at the origin, axis-aligned), as a Hull3 of 8 vertices and 6 faces, rounded by `radius`
/// (the half-extents are the core's: the rounded box reaches half + radius). Errors:
/// non-finite numbers, a half-extent below kMinShapeSize, a bad radius (as makeHull3).
Result<Hull3> makeBox3(Vec3 half, Transform3 shapeFromBox = {}, float radius = 0.0f);

/// The kinds of 3D shape, in the order of ShapeGeometry3's alternatives. A box is a hull.
enum class ShapeType3 { sphere, capsule, hull, triangle };

/// A 3D shape of any kind, shape frame (the 2D ShapeGeometry's counterpart). The
/// alternatives are in ShapeType3 order, so `shapeType(g)` is the index of the one held.
using ShapeGeometry3 = std::variant<Sphere, Capsule3, Hull3, Triangle3>;

/// The type of the shape `geometry` holds.
inline ShapeType3 shapeType(const ShapeGeometry3& geometry) noexcept {
  return static_cast<ShapeType3>(geometry.index());
}

/// The kind's name as in the JSON formats: "sphere", "capsule", "hull", "triangle".
constexpr const char* toString(ShapeType3 type) noexcept {
  switch (type) {
    case ShapeType3::sphere:
      return "sphere";
    case ShapeType3::capsule:
      return "capsule";
    case ShapeType3::hull:
      return "hull";
    case ShapeType3::triangle:
      return "triangle";
  }
  return "unknown";
}

/// Checks a 3D shape of any kind as the make* functions check their arguments (a hull with
/// validateHull3), so a hand-built struct cannot pass a NaN or a zero radius; the error is
/// the make* function's message.
Status validateShape(const ShapeGeometry3& geometry);

/// The triangle's unit normal, cross(v1 - v0, v2 - v0) normalised. Shape frame.
inline Vec3 triangleNormal(const Triangle3& t) noexcept {
  return normalize(cross(t.v[1] - t.v[0], t.v[2] - t.v[0]));
}

}  // namespace quack
