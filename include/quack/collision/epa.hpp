#pragma once
/// EPA: the penetration depth of two overlapping convex shapes, the normal to separate them
/// along, and the deepest point of each in the other.
///
/// The expanding polytope algorithm (G. van den Bergen, "Proximity queries and penetration
/// depth computation on 3D game objects", GDC 2001; Ericson, "Real-Time Collision
/// Detection", 2005, sec. 9.5): starting from GJK's final simplex, which holds the origin,
/// repeatedly take the polytope edge nearest the origin and push it out to the support
/// point of B - A along its outward normal, until the support point lies on the edge. The
/// nearest edge is then an edge of B - A, its distance the depth, and the barycentric
/// weights of the origin's projection on it rebuild the contact point on each shape
/// (docs/background.md, "Narrow phase"). The 2D polytope lives in epa.cpp; a 3D one would
/// be a sibling epa3.
///
/// Winding: the starting triangle is made counter-clockwise whatever order GJK left it in,
/// and insertion keeps it so, so outward normals are always the right-hand perpendiculars.
///
/// Tie-break: when two edges are equally near the origin (within kEpaTieRelativeTolerance,
/// e.g. two equal boxes exactly on top of each other), the one whose normal points most
/// along the direction from A's centre to B's centre wins (docs/background.md). When the
/// centres coincide too, the first edge in polytope order wins; that answer is
/// deterministic but not antisymmetric under swapping A and B.

#include <cstdint>

#include "quack/collision/gjk.hpp"

namespace quack {

/// Most polytope vertices. The core of B - A has at most n + m vertices (n, m <= 64), and
/// every polytope vertex is one of them, so this never fills before EPA ends.
inline constexpr int kEpaMaxVertices = 2 * kMaxPolygonVertices + 4;

/// EPA stops when the support point along the nearest edge's normal is within this
/// fraction of the polytope's size of the edge. For polygon cores the support point lands
/// exactly on the edge at the end, so this only absorbs rounding (about 80 float ulps of
/// the size: more than the rounding of the distance, far below any real feature).
inline constexpr float kEpaRelativeTolerance = 1e-5f;

/// Two edges whose distances to the origin differ by less than this fraction of the
/// polytope's size count as equally near, and the tie-break above decides. About 8 float
/// ulps: just above the rounding of the distances, so a tie is a real tie (the chosen
/// depth is at most this much above the least one).
inline constexpr float kEpaTieRelativeTolerance = 1e-6f;

/// How computePenetration reached its answer.
enum class EpaStatus : std::uint8_t {
  separated,        ///< no overlap: GJK's distance answer, depth 0
  coresSeparated,   ///< only the radii overlap: depth from GJK's core distance, exact
  converged,        ///< EPA's support point met the nearest edge
  repeatedSupport,  ///< EPA's support point was an end of the nearest edge
  maxIterations,    ///< the polytope filled; the answer is the best found
  degenerate,       ///< B - A's core has no area (points or collinear segments); normal
                    ///< from the centres, depth the radii
};

/// Name of a status for output ("converged", "cores_separated", ...).
const char* toString(EpaStatus status) noexcept;

/// Result of computePenetration. Points and normal are in the world frame.
struct PenetrationOutput {
  bool overlap = false;  ///< the closed shapes share a point
  float depth = 0.0f;    ///< metres to move B along `normal` to separate them; 0 when apart
  Vec2 normal;           ///< unit, from A to B (when apart: GJK's normal)
  Vec2 pointA;           ///< A's surface point deepest in B (when apart: closest point on A)
  Vec2 pointB;           ///< B's surface point deepest in A (pointB = pointA - depth * normal)
  int iterations = 0;    ///< GJK plus EPA support-point evaluations
  EpaStatus status = EpaStatus::separated;
};

/// One pass of EPA's loop, as an observer sees it: the polytope, its edge nearest the
/// origin, and (unless the polytope was full) the support point along that edge's normal.
struct EpaIterationRecord {
  /// The polytope at the start of the pass, counter-clockwise, A frame; edge i runs from
  /// vertex i to vertex (i + 1) % polytopeCount.
  SupportPoint polytope[kEpaMaxVertices];
  int polytopeCount = 0;
  int edge = 0;               ///< the nearest edge (after the tie-break)
  Vec2 edgeNormal;            ///< its outward unit normal, A frame
  float edgeDistance = 0.0f;  ///< its line's signed distance from the origin (the core depth)
  bool hasSupport = false;    ///< a support point was taken in this pass
  SupportPoint support;       ///< the support point of B - A along edgeNormal when hasSupport

  /// The answer computePenetration would return had EPA stopped at this pass, world frame
  /// (the last record's are the returned answer, bit for bit).
  float depth = 0.0f;
  Vec2 normal;
  Vec2 pointA;
  Vec2 pointB;
};

/// Enough EPA records for any run: every pass but the last adds a vertex to a polytope that
/// starts with 3 and holds at most kEpaMaxVertices.
inline constexpr int kEpaMaxTraceRecords = kEpaMaxVertices - 2;

/// A caller-owned buffer that computePenetration fills with one record per pass of EPA's
/// loop; the same contract as GjkTrace (the first `capacity - 1` passes and the final one
/// are kept, `truncated` says some were dropped). `count` is 0 when EPA did not run
/// (separated, coresSeparated, degenerate). An EpaIterationRecord is about 4 kB.
struct EpaTrace {
  EpaIterationRecord* records = nullptr;  ///< caller-owned array of `capacity` records
  int capacity = 0;
  int count = 0;           ///< records written: min(passes, capacity), 0 when records is null
  int passes = 0;          ///< passes the run made
  bool truncated = false;  ///< passes > capacity: middle passes were dropped
  /// Support points taken to grow GJK's final simplex into EPA's first triangle (counted in
  /// PenetrationOutput::iterations, not in any record).
  int triangleSupports = 0;
};

/// Penetration of proxy B (placed by `worldFromB`) into proxy A (placed by `worldFromA`):
/// GJK first; when the cores overlap, EPA on the cores plus both radii. `cache` as for
/// computeDistance. No allocation (the polytope is a fixed array on the stack).
PenetrationOutput computePenetration(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                                     Transform worldFromB, GjkCache* cache = nullptr) noexcept;
/// The same for shapes of any kind, through their proxies.
inline PenetrationOutput computePenetration(const ShapeGeometry& a, Transform worldFromA,
                                            const ShapeGeometry& b, Transform worldFromB,
                                            GjkCache* cache = nullptr) noexcept {
  return computePenetration(makeProxy(a), worldFromA, makeProxy(b), worldFromB, cache);
}

/// computePenetration that also records every pass of GJK into `gjkTrace` and of EPA into
/// `epaTrace` (either may be null; see GjkTrace, EpaTrace). The answer is the same, bit for
/// bit.
PenetrationOutput computePenetration(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                                     Transform worldFromB, GjkCache* cache, GjkTrace* gjkTrace,
                                     EpaTrace* epaTrace) noexcept;

}  // namespace quack
