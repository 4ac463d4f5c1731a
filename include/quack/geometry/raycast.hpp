#pragma once
/// Ray casts against every shape.

#include "quack/geometry/shapes.hpp"

namespace quack {

/// The ray `origin + t * translation`, t in [0, maxFraction]. Shape frame.
struct RayCastInput {
  Vec2 origin;
  Vec2 translation;
  float maxFraction = 1.0f;
};

/// Where a ray first enters a shape. Shape frame.
struct RayHit {
  bool hit = false;
  float fraction = 0.0f;  ///< t of the entry point, in [0, maxFraction]
  Vec2 point;             ///< entry point
  Vec2 normal;            ///< outward unit normal of the surface at the entry point
};

/// First entry of the ray into the shape. A ray that starts inside or on the boundary of a
/// solid shape reports no hit (it is not entering); so does a zero or non-finite
/// translation. Segments are two-sided: the normal faces the ray's origin.
RayHit rayCast(const Circle& circle, const RayCastInput& ray) noexcept;
RayHit rayCast(const Capsule& capsule, const RayCastInput& ray) noexcept;
RayHit rayCast(const Segment& segment, const RayCastInput& ray) noexcept;
RayHit rayCast(const Polygon& polygon, const RayCastInput& ray) noexcept;
RayHit rayCast(const ShapeGeometry& geometry, const RayCastInput& ray) noexcept;

}  // namespace quack
