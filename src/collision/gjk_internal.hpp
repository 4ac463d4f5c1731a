#pragma once
// GJK's inner loop, shared by computeDistance, testOverlap and EPA (which starts from the
// final simplex).

#include "quack/collision/gjk.hpp"
#include "quack/collision/simplex2.hpp"

namespace quack::detail {

struct GjkRun {
  Simplex2 simplex;  // final simplex, A frame, weights set
  Vec2 closest;      // the point of B - A closest to the origin (zero on overlap), A frame
  // closestDirection(simplex, closest) when the loop already formed it (hasDirection), so
  // computeDistance does not normalise the same vector twice.
  Vec2 direction;
  bool hasDirection = false;
  int iterations = 0;
  GjkStatus status = GjkStatus::converged;
  bool separatedEarly = false;  // earlyOutRadius was given and a separating axis found
};

// The direction from the origin to the closest point of a solved simplex: along v for a
// point; for a segment the unit normal of the segment on v's side, which is exact to the
// rounding of the segment's own direction however small |v| is (v / |v| is not: its
// direction error grows like size / |v|). Zero when v is zero.
Vec2 closestDirection(const Simplex2& simplex, Vec2 v) noexcept;

// With earlyOutRadius >= 0 the loop also stops as soon as the distance is proven above
// it (separatedEarly) or below it (status overlap with a non-zero closest point).
GjkRun runGjk(const ShapeProxy& a, const ShapeProxy& b, Transform aFromB, GjkCache* cache,
              float earlyOutRadius) noexcept;

}  // namespace quack::detail
