#pragma once
/// Decomposition of a simple polygon, with or without holes, into few convex pieces.
///
/// The outline is cleaned (duplicates, collinear runs and zero-width spikes dropped),
/// checked (no two edges may cross or touch, holes must lie inside the outline and outside
/// each other), its holes are bridged into the outline (Eberly, "Triangulation by Ear
/// Clipping", 2002, sec. 3), the result is triangulated by ear clipping, and the triangles
/// are merged greedily by Hertel and Mehlhorn's rule ("Fast triangulation of simple
/// polygons", 1983): a diagonal is removed when both its ends stay convex, longest
/// diagonals first. Hertel-Mehlhorn gives at most 4 times the fewest convex pieces (without
/// holes); `ConvexDecomposition::lowerBound` reports a lower bound on the fewest so a caller
/// can see how close a result is. Geometry is computed in double precision. docs/concave.md
/// has the details and measured figures.

#include <span>
#include <vector>

#include "quack/core/result.hpp"
#include "quack/geometry/shapes.hpp"

namespace quack {

/// Most points (outline plus holes) a concave shape may have. The simplicity check and ear
/// clipping are quadratic, so the bound keeps a decomposition a load-time cost, never a
/// frame's (docs/concave.md, "Measured", has the times and the command that measures them).
inline constexpr int kMaxConcaveVertices = 1024;

/// A polygon split into convex pieces. Shape frame (the frame of the input points).
struct ConvexDecomposition {
  /// Counter-clockwise convex polygons (each at most kMaxPolygonVertices vertices, radius 0)
  /// whose union is the input polygon and whose interiors do not overlap.
  std::vector<Polygon> pieces;
  /// Area of the cleaned polygon (outline minus holes), m^2, computed in double.
  double area = 0.0;
  /// Reflex vertices of the cleaned polygon (hole vertices count from the solid's side).
  int reflexCount = 0;
  /// No convex decomposition has fewer pieces than this: max(1, ceil(r / 2) + 1 - holes),
  /// r = reflexCount (Chazelle's bound: each cut resolves at most two reflex vertices).
  int lowerBound = 1;
  /// Triangles the ear clipping produced before merging.
  int triangleCount = 0;
  /// Ears cut without passing the ear test because none did (float trouble on nearly
  /// degenerate input; always 0 on the tested corpus). Pieces are still checked convex.
  int forcedEars = 0;
};

/// Splits the simple polygon `outline` (either orientation) minus `holes` (each a simple
/// polygon strictly inside the outline, outside the other holes, either orientation) into
/// convex pieces. Points in the shape frame, metres.
///
/// Errors, naming what is wrong: fewer than 3 points, a non-finite coordinate (with its
/// index), more than kMaxConcaveVertices points, an outline or hole of zero area after
/// clean-up, two edges that cross or touch ("edges 3 and 7 cross": edge i joins point i
/// to point i + 1 of the input; hole edges are named "holes[k] edge i"), a hole outside the
/// outline or inside another hole.
Result<ConvexDecomposition> decomposePolygon(std::span<const Vec2> outline,
                                             std::span<const std::vector<Vec2>> holes = {});

}  // namespace quack
