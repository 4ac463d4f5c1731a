#pragma once
/// The convex shapes: circle, capsule, segment and convex polygon with a rounding radius.
///
/// Shapes are plain values in their own frame ("shape frame"); a `Transform`
/// `worldFromShape` places them. Build them with the `make*` functions, which check every
/// number and return an error naming what is wrong; the structs themselves do not check.
/// `ShapeGeometry` is a shape of any kind; the geometry, collision and world functions that
/// take one dispatch on its type. To add a shape, see docs/ARCHITECTURE.md.

#include <span>
#include <variant>

#include "quack/core/result.hpp"
#include "quack/geometry/hull.hpp"
#include "quack/math/aabb.hpp"
#include "quack/math/transform.hpp"

namespace quack {

enum class ShapeType { circle, capsule, segment, polygon };

/// Solid disk. Shape frame.
struct Circle {
  Vec2 center;
  float radius = 0.0f;
};

/// Solid stadium: the points within `radius` of the segment p1-p2. Shape frame.
struct Capsule {
  Vec2 p1, p2;
  float radius = 0.0f;
};

/// Line segment with no thickness and no area (for terrain and rays). Shape frame.
struct Segment {
  Vec2 p1, p2;
};

/// Solid convex polygon, optionally rounded: the points within `radius` of the convex
/// polygon `vertices`. Vertices are counter-clockwise; `normals[i]` is the outward unit
/// normal of the edge from vertices[i] to vertices[i + 1]. `centroid` is the centroid of
/// the core polygon (for a rounded polygon, see computeMass for the true centre of mass).
/// Shape frame.
struct Polygon {
  Vec2 vertices[kMaxPolygonVertices];
  Vec2 normals[kMaxPolygonVertices];
  Vec2 centroid;
  float radius = 0.0f;
  int count = 0;
};

/// Errors: non-finite centre or radius, radius <= 0.
Result<Circle> makeCircle(Vec2 center, float radius);
/// Errors: non-finite numbers, radius <= 0 (use a segment), p1 and p2 closer than
/// kHullRelativeTolerance of the radius (use a circle).
Result<Capsule> makeCapsule(Vec2 p1, Vec2 p2, float radius);
/// Errors: non-finite numbers, zero length.
Result<Segment> makeSegment(Vec2 p1, Vec2 p2);

/// Convex polygon from a convex point set, in any order; points on an edge and duplicates
/// are dropped. Errors: non-finite numbers, negative or non-finite radius, fewer than three
/// distinct non-collinear points (zero area), more than kMaxPolygonVertices hull vertices,
/// and a point set that is not convex (a point strictly inside the hull of the others: such
/// an outline is a concave shape and must be decomposed).
Result<Polygon> makePolygon(std::span<const Vec2> points, float radius = 0.0f);
/// Polygon from an existing hull. Errors: an invalid hull, a bad radius.
Result<Polygon> makePolygon(const Hull& hull, float radius = 0.0f);
/// Rectangle with half-extents (halfWidth, halfHeight), centred at `center`, rotated by
/// `angle` radians, rounded by `radius`. Errors: non-finite numbers, half-extents <= 0,
/// negative radius.
Result<Polygon> makeBox(float halfWidth, float halfHeight, Vec2 center = {}, float angle = 0.0f,
                        float radius = 0.0f);

/// Checks every invariant of a `Polygon` (count, finite values, unit normals that match the
/// edges, counter-clockwise strict convexity, centroid inside, radius >= 0).
Status validatePolygon(const Polygon& polygon);

/// A shape of any kind, shape frame. The alternatives are in ShapeType order, so
/// `shapeType(g)` is the index of the one held.
using ShapeGeometry = std::variant<Circle, Capsule, Segment, Polygon>;

/// The type of the shape `geometry` holds.
inline ShapeType shapeType(const ShapeGeometry& geometry) noexcept {
  return static_cast<ShapeType>(geometry.index());
}

/// The shape kind's name as in the JSON formats: "circle", "capsule", "segment", "polygon".
constexpr const char* toString(ShapeType type) noexcept {
  switch (type) {
    case ShapeType::circle:
      return "circle";
    case ShapeType::capsule:
      return "capsule";
    case ShapeType::segment:
      return "segment";
    case ShapeType::polygon:
      return "polygon";
  }
  return "unknown";
}

/// Checks a shape of any kind as the make* functions check their arguments (a polygon with
/// validatePolygon), so a hand-built struct cannot pass a NaN, a zero radius or a concave
/// polygon; the error is the make* function's message.
Status validateShape(const ShapeGeometry& geometry);

}  // namespace quack
