#pragma once
/// Convex hull of a point set, the ground every polygon stands on.
///
/// Andrew's monotone chain (A. M. Andrew, "Another efficient algorithm for convex hulls in
/// two dimensions", 1979), followed by a clean-up pass that welds near-duplicates and drops
/// near-collinear vertices so that every edge of the result has a well-defined normal.

#include <span>

#include "quack/core/result.hpp"
#include "quack/math/vec2.hpp"

namespace quack {

/// Most vertices a hull or polygon may have. Fixed so that polygons are plain values and
/// the narrow phase never allocates; 64 covers "any sort of convex polygon" a game uses.
inline constexpr int kMaxPolygonVertices = 64;

/// Relative tolerance of the hull clean-up: a vertex closer than this fraction of the
/// point set's size to the segment joining its neighbours is dropped. About 100 float ulps
/// of the shape's size: above rounding noise of the cross products, far below any feature
/// a user draws on purpose.
inline constexpr float kHullRelativeTolerance = 1e-5f;

/// Smallest extent a shape may have, metres. Below it the squares and cross products the
/// collision routines form (~1e-18 and less) run into float's underflow, and answers stop
/// being finite; a nanometre is far below anything a game or a simulation in metres draws.
inline constexpr float kMinShapeSize = 1e-9f;

/// A convex hull: counter-clockwise, no three vertices collinear (within the tolerance),
/// no duplicates, starting at the lexicographically smallest vertex (least x, then least y).
struct Hull {
  Vec2 points[kMaxPolygonVertices];
  int count = 0;
};

/// Tolerance used for a point set whose bounding box is `lower`..`upper`: relative to
/// its size, but never below the float resolution of its coordinates.
float hullTolerance(Vec2 lower, Vec2 upper) noexcept;

/// Convex hull of `points` (any order, duplicates allowed). Errors, naming the problem:
/// a non-finite coordinate (with its index), fewer than three distinct points, all points
/// collinear, or a hull of more than kMaxPolygonVertices vertices.
Result<Hull> computeHull(std::span<const Vec2> points);

/// Checks every invariant a `Hull` promises (count in range, finite, counter-clockwise and
/// strictly convex within the tolerance, no duplicates). Tests call it after every hull.
Status validateHull(const Hull& hull);

}  // namespace quack
