#pragma once
// GJK's 3D loop, shared by computeDistance, testOverlap and EPA (internal to the collision
// layer).

#include "quack/collision/gjk3.hpp"

namespace quack::detail {

struct GjkCore3 {
  Simplex3 simplex;  // final simplex, A frame, weights set
  Vec3 closest;      // its point nearest the origin (zero on overlap), A frame
  int iterations = 0;
  GjkStatus status = GjkStatus::converged;
  bool separated = false;  // the overlap test's early out fired
};

// The support point of B - A along `direction` (A frame).
SupportPoint3 support3(const ShapeProxy3& a, const ShapeProxy3& b, Transform3 aFromB,
                       Vec3 direction) noexcept;
SupportPoint3 makeSupport3(const ShapeProxy3& a, const ShapeProxy3& b, Transform3 aFromB,
                           int indexA, int indexB) noexcept;
// Reduces the simplex to the vertices that carry its point nearest the origin, sets the
// weights, `closest` and (when not null) its squared length in double; true when the simplex is a
// tetrahedron holding the origin.
bool solveSimplex3(Simplex3& s, Vec3& closest, double* distanceSquared) noexcept;
// GJK on the cores in A's frame. separationRadius >= 0 enables the overlap test's early out.
GjkCore3 runGjk3(const ShapeProxy3& a, const ShapeProxy3& b, Transform3 aFromB, GjkCache3* cache,
                 float separationRadius) noexcept;
// The weighted points of the simplex on A and on B (A frame).
void closestPoints3(const Simplex3& s, Vec3& pointA, Vec3& pointB) noexcept;

}  // namespace quack::detail
