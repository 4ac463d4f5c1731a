#pragma once
/// The Minkowski difference B - A = {b - a : a in A, b in B} of two proxies' cores, through
/// its support function (what GJK and EPA use) and, for tests and the demo, explicitly.
///
/// The shapes overlap exactly when B - A holds the origin, and the distance between them is
/// the distance from the origin to B - A (Gilbert, Johnson and Keerthi, "A fast procedure
/// for computing the distance between complex objects in three-dimensional space", IEEE J.
/// Robotics and Automation 4(2), 1988). Quack takes B - A, not A - B, so that the point of
/// B - A closest to the origin points from A to B.

#include "quack/collision/proxy.hpp"
#include "quack/core/result.hpp"
#include "quack/geometry/hull.hpp"

namespace quack {

/// One support point of B - A with the two proxy points that make it. All three points
/// are in A's shape frame.
struct SupportPoint {
  Vec2 pointA;     ///< a point of A's core, A frame
  Vec2 pointB;     ///< a point of B's core, A frame
  Vec2 w;          ///< pointB - pointA, A frame
  int indexA = 0;  ///< index of pointA in proxy A
  int indexB = 0;  ///< index of pointB in proxy B
};

/// The support point of B - A furthest along `direction` (A frame, any length), with B
/// placed in A's frame by `aFromB`: support_B(d) - support_A(-d).
inline SupportPoint supportMinkowski(const ShapeProxy& a, const ShapeProxy& b, Transform aFromB,
                                     Vec2 direction) noexcept {
  SupportPoint s;
  s.indexA = findSupport(a, -direction);
  s.indexB = findSupport(b, invRotate(aFromB.q, direction));
  s.pointA = a.points()[s.indexA];
  s.pointB = transformPoint(aFromB, b.points()[s.indexB]);
  s.w = s.pointB - s.pointA;
  return s;
}

/// The core of B - A explicitly, in the world frame: the convex hull of all pairwise
/// differences of the proxies' points placed by `worldFromA` and `worldFromB` (the radii
/// are not included: the full difference is this hull grown by rA + rB). Allocates; for
/// tests and the demo, not the narrow phase. Errors: a difference with no area (both cores
/// points or parallel segments) or more than kMaxPolygonVertices hull vertices.
Result<Hull> computeMinkowskiDifference(const ShapeProxy& a, Transform worldFromA,
                                        const ShapeProxy& b, Transform worldFromB);

}  // namespace quack
