#pragma once
/// SAT: the separating axis test for two convex polygons over every edge normal of both.
///
/// Two convex polygons are apart exactly when some edge normal of one separates them
/// (Ericson, "Real-Time Collision Detection", 2005, sec. 5.2.1; Gottschalk's separating
/// axis theorem), and when they overlap the smallest push that separates them is along one
/// of those normals, because the edges of B - A are exactly the edges of A and of -B. So
/// the largest separation over the n + m normals is the signed
/// distance when the cores overlap; when they are apart it is a lower bound on the
/// distance (exact only if the closest features are an edge and a vertex; GJK gives the
/// true distance). This is the "project onto each edge" test, and the method of
/// Catto's b2CollidePolygons before clipping.

#include "quack/geometry/shapes.hpp"

namespace quack {

/// Result of computeSat. Normal in the world frame.
struct SatOutput {
  /// Largest separation over the axes minus both radii, metres: negative is the
  /// penetration depth (exact), positive a lower bound on the distance.
  float separation = 0.0f;
  Vec2 normal;          ///< unit, from A to B: the axis that gave `separation`
  int edge = 0;         ///< index of the edge whose normal it is
  bool edgeOnA = true;  ///< whether that edge belongs to A (else to B)
};

/// SAT over every edge normal of both polygons (shape frames, placed by the transforms).
/// On a tie between an axis of A and one of B within float rounding, A's axis wins.
/// No allocation. Preconditions: valid polygons, finite transforms.
SatOutput computeSat(const Polygon& a, Transform worldFromA, const Polygon& b,
                     Transform worldFromB) noexcept;

}  // namespace quack
