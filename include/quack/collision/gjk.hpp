#pragma once
/// GJK: the distance between two convex shapes, their closest points, and an overlap test.
///
/// Gilbert, Johnson and Keerthi (IEEE J. Robotics and Automation 4(2), 1988), run on the
/// proxies' cores in A's frame: each iteration takes the support point of B - A along
/// -v, where v is the point of the current simplex closest to the origin, and re-solves
/// the simplex with signed volumes (simplex2.hpp). The search direction is always -v, so
/// no triple product is ever formed and no direction can vanish while the shapes are apart.
/// Termination follows van den Bergen ("A fast and robust GJK implementation for
/// collision detection of convex objects", J. Graphics Tools 4(2), 1999): stop when the
/// lower bound v.w / |v| reaches |v|, when a support point comes back (a "simplex seen
/// before"), when |v| stops decreasing, or at the iteration cap. Radii are
/// added at the end (Catto, "Computing Distance", GDC 2010). Ericson, "Real-Time Collision
/// Detection", 2005, ch. 9, is a readable account of all of it.

#include <cstdint>

#include "quack/collision/simplex2.hpp"

namespace quack {

/// Most GJK iterations. 2D GJK on cores of n and m points ends in about n + m iterations
/// at worst (each iteration adds a new vertex of B - A, which has at most n + m); twice the
/// largest possible n + m is a cap that only a bug or NaN input reaches.
inline constexpr int kGjkMaxIterations = 4 * kMaxPolygonVertices;

// No relative tolerance on van den Bergen's stopping test |v|^2 - v.w <= tol |v|^2: the
// direction of v (the normal) is only good to about sqrt(tol) when GJK stops there, so any
// tol a float can see (>= 1e-7) would give normals off by 3e-4. The cores are polytopes,
// so GJK ends exactly (repeated support point, or v.w >= |v|^2) in a few iterations, and
// the stall test below catches rounding.

/// The cores touch when |v| is below this fraction of the largest simplex vertex: the
/// rounding error of v computed from support points of that size is a few float ulps of
/// it, so a smaller |v| is indistinguishable from zero.
inline constexpr float kGjkContactRelativeTolerance = 1e-6f;

/// How GJK stopped.
enum class GjkStatus : std::uint8_t {
  converged,        ///< the lower and upper distance bounds met: v.w >= |v|^2
  repeatedSupport,  ///< a support point already in the simplex came back: the simplex is final
  stalled,          ///< |v| stopped decreasing (float rounding): the best simplex is kept
  overlap,          ///< the cores overlap or touch: the simplex holds the origin
  maxIterations,    ///< hit kGjkMaxIterations; the answer is the best found
};

/// Name of a status for output ("converged", "repeated_support", ...).
const char* toString(GjkStatus status) noexcept;

/// Warm start for GJK, owned by the caller: the proxy-point indices of the last simplex.
/// Zero-initialise it (count 0) for a cold start; pass the same cache for the same pair on
/// the next query and GJK starts from where it ended. Only valid for the same two proxies.
struct GjkCache {
  int count = 0;
  std::uint8_t indexA[3] = {};
  std::uint8_t indexB[3] = {};
};

/// Result of `computeDistance`. Points and normal are in the world frame.
struct DistanceOutput {
  float distance = 0.0f;      ///< between the rounded shapes, metres; 0 when they overlap
  float coreDistance = 0.0f;  ///< between the cores (radii ignored), metres
  Vec2 pointA;         ///< closest point on A's surface (when overlapping: a point both share)
  Vec2 pointB;         ///< closest point on B's surface (when overlapping: equal to pointA)
  Vec2 normal;         ///< unit, from A to B; zero when the cores overlap (use computePenetration)
  int iterations = 0;  ///< support-point evaluations
  GjkStatus status = GjkStatus::converged;
};

/// One pass of GJK's loop, as an observer sees it: the simplex solve, then (unless the loop
/// stops first) the support point along the new search direction. `DistanceOutput::iterations`
/// counts the support points, so a run has as many records with `hasSupport` as iterations,
/// and one more record, without a support point, when it stopped before taking one (overlap,
/// stall, cap).
struct GjkIterationRecord {
  /// The simplex after the solve (reduced, weights set), A frame; on a stall, the previous
  /// simplex, which GJK keeps. Each vertex carries its points on A and B (SupportPoint).
  Simplex2 simplex;
  Vec2 closest;             ///< the simplex point nearest the origin (v), A frame; zero on overlap
  bool hasSupport = false;  ///< a support point was taken in this pass
  Vec2 direction;           ///< unit, A frame: v's direction; the support is taken along -direction
  SupportPoint support;     ///< the new support point of B - A (A frame) when hasSupport

  /// The answer computeDistance would return had GJK stopped after this pass, world frame
  /// (the last record's are the returned answer, bit for bit).
  float distance = 0.0f;
  float coreDistance = 0.0f;
  Vec2 pointA;
  Vec2 pointB;
  Vec2 normal;
};

/// Enough GJK records for any run: at most kGjkMaxIterations support points, plus the last
/// pass that takes none.
inline constexpr int kGjkMaxTraceRecords = kGjkMaxIterations + 1;

/// A caller-owned buffer that computeDistance (and computePenetration) fill with one record
/// per pass of GJK's loop, for viewers, tests and teaching. Set `records` and `capacity`;
/// the call resets the rest. When the run has more passes than `capacity`, the first
/// `capacity - 1` are kept, the last slot holds the final pass (so `records[count - 1]` is
/// always where GJK ended) and `truncated` is set; nothing is written past `capacity`.
/// Observing never changes the answer; the overloads without a trace run the same loop with
/// the recording compiled out.
struct GjkTrace {
  GjkIterationRecord* records = nullptr;  ///< caller-owned array of `capacity` records
  int capacity = 0;
  int count = 0;           ///< records written: min(passes, capacity), 0 when records is null
  int passes = 0;          ///< passes the run made
  bool truncated = false;  ///< passes > capacity: middle passes were dropped
};

namespace detail {
// computeDistance with the transforms by reference: by value, each is handed over in two
// vector registers, which the function takes apart again (about 30 moves a query).
DistanceOutput computeDistanceOf(const ShapeProxy& a, const Transform& worldFromA,
                                 const ShapeProxy& b, const Transform& worldFromB,
                                 GjkCache* cache) noexcept;
}  // namespace detail

/// Distance and closest points between proxy A placed by `worldFromA` and proxy B placed by
/// `worldFromB`. `cache` (may be null) warm-starts the search and is updated. No
/// allocation. Preconditions: valid proxies (see ShapeProxy) and finite transforms.
inline DistanceOutput computeDistance(const ShapeProxy& a, Transform worldFromA,
                                      const ShapeProxy& b, Transform worldFromB,
                                      GjkCache* cache = nullptr) noexcept {
  return detail::computeDistanceOf(a, worldFromA, b, worldFromB, cache);
}

/// computeDistance that also records every pass of GJK into `trace` (see GjkTrace). The
/// answer is the same, bit for bit.
DistanceOutput computeDistance(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                               Transform worldFromB, GjkCache* cache, GjkTrace& trace) noexcept;

/// True when the closed rounded shapes share a point (touching counts, to the tolerances
/// above). Stops as soon as a separating direction is found, so it is cheaper than
/// computeDistance on pairs that are apart. `cache` as for computeDistance.
bool testOverlap(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                 Transform worldFromB, GjkCache* cache = nullptr) noexcept;

/// The same for shapes of any kind, through their proxies.
inline DistanceOutput computeDistance(const ShapeGeometry& a, Transform worldFromA,
                                      const ShapeGeometry& b, Transform worldFromB,
                                      GjkCache* cache = nullptr) noexcept {
  return computeDistance(makeProxy(a), worldFromA, makeProxy(b), worldFromB, cache);
}
inline bool testOverlap(const ShapeGeometry& a, Transform worldFromA, const ShapeGeometry& b,
                        Transform worldFromB, GjkCache* cache = nullptr) noexcept {
  return testOverlap(makeProxy(a), worldFromA, makeProxy(b), worldFromB, cache);
}

}  // namespace quack
