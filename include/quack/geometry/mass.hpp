#pragma once
/// Mass properties of shapes of uniform density.

#include "quack/geometry/shapes.hpp"

namespace quack {

/// Mass properties of a shape. Shape frame.
struct MassProperties {
  float mass = 0.0f;     ///< kg: density times area
  float area = 0.0f;     ///< m^2
  Vec2 centroid;         ///< centre of mass, shape frame
  float inertia = 0.0f;  ///< rotational inertia about `centroid`, kg m^2
};

/// Precondition (asserted): density finite and >= 0, in kg/m^2.
MassProperties computeMass(const Circle& circle, float density);
/// Exact for the stadium (rectangle plus two half-disks).
MassProperties computeMass(const Capsule& capsule, float density);
/// A segment has no area: mass, area and inertia are 0; the centroid is its midpoint.
MassProperties computeMass(const Segment& segment, float density);
/// Exact for rounded polygons too: the core polygon, a rectangle along each edge and a
/// circular sector at each vertex (the sectors add up to one disk).
MassProperties computeMass(const Polygon& polygon, float density);
/// Any shape, by its type.
MassProperties computeMass(const ShapeGeometry& geometry, float density);

}  // namespace quack
