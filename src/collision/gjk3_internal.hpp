#pragma once
// GJK's 3D loop, shared by computeDistance, testOverlap and EPA (internal to the collision
// layer).

#include "quack/collision/gjk3.hpp"
#include "quack/math/mat3.hpp"

namespace quack::detail {

struct GjkCore3 {
  Vec3 closest;  // the final simplex's point nearest the origin (zero on overlap), A frame
  int iterations = 0;
  GjkStatus status = GjkStatus::converged;
  bool separated = false;  // the overlap test's early out fired
};

// B - A in A's frame: the two proxies and B's pose in A's frame, its rotation as a matrix.
// Every support point rotates twice (the direction into B's frame, B's point out of it);
// the matrix does each in 9 products where the quaternion takes 18, and costs 18 to form,
// once per query.
struct MinkowskiPair3 {
  MinkowskiPair3(const ShapeProxy3& proxyA, const ShapeProxy3& proxyB, Transform3 aFromB) noexcept
      : a(proxyA), b(proxyB), rotation(toMat3(aFromB.q)), translation(aFromB.p) {}

  // The support point along `direction` (A frame, any length).
  SupportPoint3 support(Vec3 direction) const noexcept {
    return make(findSupport(a, -direction), findSupport(b, mulTranspose(rotation, direction)));
  }
  // The support point of the proxies' points indexA and indexB.
  SupportPoint3 make(int indexA, int indexB) const noexcept {
    SupportPoint3 s;
    s.indexA = indexA;
    s.indexB = indexB;
    s.pointA = a.points()[indexA];
    s.pointB = rotation * b.points()[indexB] + translation;
    s.w = s.pointB - s.pointA;
    return s;
  }

  const ShapeProxy3& a;
  const ShapeProxy3& b;
  Mat3 rotation;     // aFromB's
  Vec3 translation;  // aFromB's
};

// GJK on the cores in A's frame. separationRadius >= 0 enables the overlap test's early out.
// `simplex` receives the final simplex (A frame, weights set): the caller's own, such as
// DistanceOutput3's, so that the simplex is neither zeroed nor copied twice per query.
// `trace` (may be null) records every pass (Gjk3Trace); it changes nothing else.
GjkCore3 runGjk3(const MinkowskiPair3& pair, GjkCache3* cache, float separationRadius,
                 Simplex3& simplex, Gjk3Trace* trace = nullptr) noexcept;

// The record slot for the next pass of a trace (the contract of Gjk3Trace and Epa3Trace):
// the first capacity - 1 passes keep their slots, later ones share the last.
template <typename Trace>
auto* claimTraceRecord3(Trace& trace) noexcept {
  int slot = trace.passes < trace.capacity ? trace.passes : trace.capacity - 1;
  ++trace.passes;
  if (trace.passes > trace.capacity) trace.truncated = true;
  trace.count = trace.passes < trace.capacity ? trace.passes : trace.capacity;
  return &trace.records[slot];
}
template <typename Trace>
void resetTrace3(Trace& trace) noexcept {
  trace.count = 0;
  trace.passes = 0;
  trace.truncated = false;
  if (trace.records == nullptr) trace.capacity = 0;
}
// The weighted points of the simplex on A and on B (A frame).
void closestPoints3(const Simplex3& s, Vec3& pointA, Vec3& pointB) noexcept;

}  // namespace quack::detail
