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
/// lower bound v.w / |v| reaches |v|, when a support point comes back (the "simplex seen
/// before" of the seeds), when |v| stops decreasing, or at the iteration cap. Radii are
/// added at the end (Catto, "Computing Distance", GDC 2010). Ericson, "Real-Time Collision
/// Detection", 2005, ch. 9, is a readable account of all of it.

#include <cstdint>

#include "quack/collision/proxy.hpp"

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

/// Distance and closest points between proxy A placed by `worldFromA` and proxy B placed by
/// `worldFromB`. `cache` (may be null) warm-starts the search and is updated. No
/// allocation. Preconditions: valid proxies (see ShapeProxy) and finite transforms.
DistanceOutput computeDistance(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                               Transform worldFromB, GjkCache* cache = nullptr) noexcept;

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
