#pragma once
/// The 2D simplex solver of GJK: the point of a simplex (point, segment or triangle of
/// support points of B - A) closest to the origin, as barycentric weights on the smallest
/// sub-simplex that holds it.
///
/// Signed volumes, after M. Montanari, N. Petrinic and E. Barbieri, "Improving the GJK
/// algorithm for faster and more reliable distance queries between convex objects", ACM
/// Trans. Graph. 36(3), 2017: the weights are ratios of signed areas (lengths on a
/// segment), and a vertex whose sub-area has the wrong sign is dropped. This is Johnson's
/// sub-algorithm (Gilbert et al. 1988) without its recursion (docs/background.md,
/// "Narrow phase"). The 3D solver (tetrahedra) would be a sibling `simplex3`.

#include "quack/collision/minkowski.hpp"

namespace quack {

/// One vertex of the simplex: a support point and its barycentric weight.
struct SimplexVertex {
  SupportPoint support;  ///< A frame
  float weight = 0.0f;   ///< barycentric weight in [0, 1]; the weights sum to 1
};

/// Up to three support points of B - A (A frame).
struct Simplex2 {
  SimplexVertex vertices[3];
  int count = 0;
};

/// What `solveSimplex2` found.
struct SimplexSolution {
  Vec2 closest;              ///< the point of the simplex closest to the origin, A frame
  bool holdsOrigin = false;  ///< a full triangle holds the origin (closest is zero)
};

/// Reduces `simplex` (count 1 to 3) in place to the smallest sub-simplex whose hull holds
/// its point closest to the origin, sets the weights, and returns that point. The order of
/// the kept vertices is preserved. A degenerate simplex (coincident points, a flat
/// triangle) is reduced to an edge or a point, never divided by zero.
SimplexSolution solveSimplex2(Simplex2& simplex) noexcept;

/// Sum of weight * pointA and of weight * pointB over the simplex: the witness points on
/// each core, A frame.
struct WitnessPoints {
  Vec2 pointA;
  Vec2 pointB;
};
WitnessPoints computeWitnessPoints(const Simplex2& simplex) noexcept;

}  // namespace quack
