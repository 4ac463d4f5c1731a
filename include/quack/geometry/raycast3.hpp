#pragma once
/// Ray casts against the 3D shapes.

#include "quack/geometry/shapes3.hpp"

namespace quack {

/// The ray `origin + t * translation`, t in [0, maxFraction]. Shape frame.
struct RayCastInput3 {
  Vec3 origin;
  Vec3 translation;
  float maxFraction = 1.0f;
};

/// Where a ray first enters a shape. Shape frame.
struct RayHit3 {
  bool hit = false;
  float fraction = 0.0f;  ///< t of the entry point, in [0, maxFraction]
  Vec3 point;             ///< entry point
  Vec3 normal;            ///< outward unit normal of the surface at the entry point
};

/// First entry of the ray into the shape. As in 2D: a ray that starts inside or on the
/// boundary of a solid reports no hit (it is not entering); so does a zero or non-finite
/// translation. A triangle is two-sided: the normal faces the ray's origin; a ray in its
/// plane misses. The hull cast clips the ray against each face plane (Cyrus-Beck; Ericson,
/// "Real-Time Collision Detection", 5.3.8), the triangle cast is Moller-Trumbore (1997),
/// the capsule is the nearer of its cylinder and its two end spheres. A rounded hull (radius
/// > 0) is exact for the rounded solid: the nearest entry among its faces lifted by the
/// radius (each hit kept when it lies over its face), its edges' cylinders and its vertices'
/// spheres; a ray from within the radius of the core (found by the distance to each face
/// and edge) reports no hit. O(faces x face size + edges + vertices).
RayHit3 rayCast(const Sphere& sphere, const RayCastInput3& ray) noexcept;
RayHit3 rayCast(const Capsule3& capsule, const RayCastInput3& ray) noexcept;
RayHit3 rayCast(const Hull3& hull, const RayCastInput3& ray) noexcept;
RayHit3 rayCast(const Triangle3& triangle, const RayCastInput3& ray) noexcept;
/// Any 3D shape, by its type.
RayHit3 rayCast(const ShapeGeometry3& geometry, const RayCastInput3& ray) noexcept;

}  // namespace quack
