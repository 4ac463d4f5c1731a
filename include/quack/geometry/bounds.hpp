#pragma once
/// Bounding boxes and point containment for every shape.

#include "quack/geometry/shapes.hpp"
#include "quack/math/aabb.hpp"

namespace quack {

/// Tight world-frame box of the shape placed by `worldFromShape`.
Aabb computeAabb(const Circle& circle, Transform worldFromShape) noexcept;
Aabb computeAabb(const Capsule& capsule, Transform worldFromShape) noexcept;
Aabb computeAabb(const Segment& segment, Transform worldFromShape) noexcept;
Aabb computeAabb(const Polygon& polygon, Transform worldFromShape) noexcept;
Aabb computeAabb(const ShapeGeometry& geometry, Transform worldFromShape) noexcept;

/// True when `point` (shape frame) lies in the closed shape (the boundary counts).
bool containsPoint(const Circle& circle, Vec2 point) noexcept;
bool containsPoint(const Capsule& capsule, Vec2 point) noexcept;
/// A segment has no interior: always false.
bool containsPoint(const Segment& segment, Vec2 point) noexcept;
bool containsPoint(const Polygon& polygon, Vec2 point) noexcept;
bool containsPoint(const ShapeGeometry& geometry, Vec2 point) noexcept;

}  // namespace quack
