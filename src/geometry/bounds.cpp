#include "quack/geometry/bounds.hpp"

#include <limits>

namespace quack {

Aabb computeAabb(const Circle& circle, Transform worldFromShape) noexcept {
  Vec2 c = transformPoint(worldFromShape, circle.center);
  Vec2 r{circle.radius, circle.radius};
  return {c - r, c + r};
}

Aabb computeAabb(const Capsule& capsule, Transform worldFromShape) noexcept {
  Vec2 a = transformPoint(worldFromShape, capsule.p1);
  Vec2 b = transformPoint(worldFromShape, capsule.p2);
  Vec2 r{capsule.radius, capsule.radius};
  return {minv(a, b) - r, maxv(a, b) + r};
}

Aabb computeAabb(const Segment& segment, Transform worldFromShape) noexcept {
  Vec2 a = transformPoint(worldFromShape, segment.p1);
  Vec2 b = transformPoint(worldFromShape, segment.p2);
  return {minv(a, b), maxv(a, b)};
}

Aabb computeAabb(const Polygon& polygon, Transform worldFromShape) noexcept {
  Vec2 lower = transformPoint(worldFromShape, polygon.vertices[0]);
  Vec2 upper = lower;
  for (int i = 1; i < polygon.count; ++i) {
    Vec2 v = transformPoint(worldFromShape, polygon.vertices[i]);
    lower = minv(lower, v);
    upper = maxv(upper, v);
  }
  Vec2 r{polygon.radius, polygon.radius};
  return {lower - r, upper + r};
}

bool containsPoint(const Circle& circle, Vec2 point) noexcept {
  return distanceSquared(circle.center, point) <= circle.radius * circle.radius;
}

bool containsPoint(const Capsule& capsule, Vec2 point) noexcept {
  Vec2 axis = capsule.p2 - capsule.p1;
  float t = clampf(dot(point - capsule.p1, axis) / lengthSquared(axis), 0.0f, 1.0f);
  return distanceSquared(capsule.p1 + t * axis, point) <= capsule.radius * capsule.radius;
}

bool containsPoint(const Segment&, Vec2) noexcept {
  return false;
}

bool containsPoint(const Polygon& polygon, Vec2 point) noexcept {
  // Largest signed distance to an edge line: <= 0 inside the core polygon.
  float maxSeparation = -std::numeric_limits<float>::max();
  for (int i = 0; i < polygon.count; ++i) {
    maxSeparation = maxf(maxSeparation, dot(polygon.normals[i], point - polygon.vertices[i]));
  }
  if (maxSeparation <= 0.0f) return true;
  if (polygon.radius == 0.0f) return false;
  // Outside the core: within the radius of some edge. Checking every edge is cheap and
  // has no special cases.
  float r2 = polygon.radius * polygon.radius;
  for (int i = 0; i < polygon.count; ++i) {
    Vec2 a = polygon.vertices[i];
    Vec2 ab = polygon.vertices[(i + 1) % polygon.count] - a;
    float t = clampf(dot(point - a, ab) / lengthSquared(ab), 0.0f, 1.0f);
    if (distanceSquared(a + t * ab, point) <= r2) return true;
  }
  return false;
}

Aabb computeAabb(const ShapeGeometry& geometry, Transform worldFromShape) noexcept {
  return std::visit([&](const auto& shape) { return computeAabb(shape, worldFromShape); },
                    geometry);
}

bool containsPoint(const ShapeGeometry& geometry, Vec2 point) noexcept {
  return std::visit([&](const auto& shape) { return containsPoint(shape, point); }, geometry);
}

}  // namespace quack
