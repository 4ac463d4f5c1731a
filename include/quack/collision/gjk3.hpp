#pragma once
/// GJK in 3D: distance, closest points and overlap of two convex shapes, with the
/// tetrahedron simplex and a warm-start cache.
///
/// The same algorithm as the 2D gjk.hpp (Gilbert, Johnson and Keerthi 1988; termination as
/// van den Bergen 1999; radii added at the end, Catto GDC 2010), on the proxies' cores in
/// A's frame (B is brought in by the relative pose, so two shapes 1e4 m from the origin
/// lose nothing to their world coordinates). Each pass solves the simplex (1 to 4 support
/// points of B - A) for its point nearest the origin by Voronoi regions (Ericson, "Real-Time
/// Collision Detection", 2005, 5.1.5-5.1.6), in double: the solve is a few dozen operations
/// on at most four points, and double removes the float cancellation that makes 3D GJK
/// cycle on nearly flat tetrahedra (a known failure in the peers' trackers). Written from the
/// published descriptions cited here; no peer's code was consulted.

#include <cstdint>

#include "quack/collision/gjk.hpp"
#include "quack/collision/proxy3.hpp"

namespace quack {

/// Most GJK iterations in 3D. Each iteration adds a support point of B - A, which has at
/// most 64 x 64 distinct ones, but GJK on polytopes ends in a few dozen; a repeated support
/// point or a stall ends it before this, which only a bug or NaN input reaches.
inline constexpr int kGjk3MaxIterations = 4 * kMaxHullVertices3;

/// The cores touch when |v| is below this fraction of the largest simplex vertex (as in 2D,
/// kGjkContactRelativeTolerance: a few float ulps of the support points' size).
inline constexpr float kGjk3ContactRelativeTolerance = 1e-6f;

/// One support point of B - A, A frame: w = pointB - pointA, with the proxies' indices.
struct SupportPoint3 {
  Vec3 pointA;
  Vec3 pointB;
  Vec3 w;
  int indexA = 0;
  int indexB = 0;
};

/// GJK's simplex: 1 to 4 support points and the barycentric weights of the point nearest
/// the origin (summing to 1).
struct Simplex3 {
  SupportPoint3 v[4];
  float weights[4] = {};
  int count = 0;
};

/// Warm start, owned by the caller: the proxy indices of the last simplex. Zero-initialise
/// it for a cold start; only valid for the same two proxies.
struct GjkCache3 {
  int count = 0;
  std::uint8_t indexA[4] = {};
  std::uint8_t indexB[4] = {};
};

/// Result of computeDistance for 3D proxies. Points and normal in the world frame.
struct DistanceOutput3 {
  float distance = 0.0f;      ///< between the rounded shapes, metres; 0 when they overlap
  float coreDistance = 0.0f;  ///< between the cores (radii ignored), metres
  Vec3 pointA;         ///< closest point on A's surface (when overlapping: a point both share)
  Vec3 pointB;         ///< closest point on B's surface (when overlapping: equal to pointA)
  Vec3 normal;         ///< unit, from A to B; zero when the cores overlap (use computePenetration)
  int iterations = 0;  ///< support-point evaluations
  GjkStatus status = GjkStatus::converged;
  Simplex3 simplex;  ///< the final simplex, A frame (EPA starts from it)
};

/// One pass of GJK's 3D loop, as an observer sees it (the 3D GjkIterationRecord, gjk.hpp):
/// the simplex solve, then (unless the loop stops first) the support point along the new
/// search direction. A run has as many records with `hasSupport` as support points taken
/// in the loop, and one more, without one, when it stopped before taking one.
struct Gjk3IterationRecord {
  /// The simplex after the solve (reduced, weights set), A frame; on a stall, the previous
  /// simplex, which GJK keeps.
  Simplex3 simplex;
  Vec3 closest;             ///< the simplex point nearest the origin (v), A frame; zero on overlap
  bool hasSupport = false;  ///< a support point was taken in this pass
  Vec3 direction;           ///< unit, A frame: v's direction; the support is taken along -direction
  SupportPoint3 support;    ///< the new support point of B - A (A frame) when hasSupport
};

/// Enough 3D GJK records for any run.
inline constexpr int kGjk3MaxTraceRecords = kGjk3MaxIterations + 1;

/// A caller-owned buffer that the traced computeDistance and computePenetration fill with
/// one record per pass of GJK's loop; the contract of GjkTrace (gjk.hpp): set `records` and
/// `capacity`, the call resets the rest; when the run has more passes than `capacity`, the
/// first `capacity - 1` are kept and the last slot holds the final pass. Observing never
/// changes the answer.
struct Gjk3Trace {
  Gjk3IterationRecord* records = nullptr;  ///< caller-owned array of `capacity` records
  int capacity = 0;
  int count = 0;           ///< records written: min(passes, capacity)
  int passes = 0;          ///< passes the run made
  bool truncated = false;  ///< passes > capacity: middle passes were dropped
};

/// Distance and closest points between proxy A placed by `worldFromA` and proxy B placed
/// by `worldFromB`. `cache` (may be null) warm-starts the search and is updated. No
/// allocation. Preconditions: valid proxies and finite transforms with unit quaternions.
DistanceOutput3 computeDistance(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                                Transform3 worldFromB, GjkCache3* cache = nullptr) noexcept;

/// computeDistance that also records every pass of GJK into `trace` (see Gjk3Trace). The
/// answer is the same, bit for bit.
DistanceOutput3 computeDistance(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                                Transform3 worldFromB, GjkCache3* cache, Gjk3Trace& trace) noexcept;

/// True when the closed rounded shapes share a point (touching counts, to the tolerance
/// above). `cache` as for computeDistance.
bool testOverlap(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                 Transform3 worldFromB, GjkCache3* cache = nullptr) noexcept;

/// The same for 3D shapes of any kind, through their proxies.
inline DistanceOutput3 computeDistance(const ShapeGeometry3& a, Transform3 worldFromA,
                                       const ShapeGeometry3& b, Transform3 worldFromB,
                                       GjkCache3* cache = nullptr) noexcept {
  return computeDistance(makeProxy(a), worldFromA, makeProxy(b), worldFromB, cache);
}
inline bool testOverlap(const ShapeGeometry3& a, Transform3 worldFromA, const ShapeGeometry3& b,
                        Transform3 worldFromB, GjkCache3* cache = nullptr) noexcept {
  return testOverlap(makeProxy(a), worldFromA, makeProxy(b), worldFromB, cache);
}

}  // namespace quack
