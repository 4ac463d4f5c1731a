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
// `trace` (may be null) records every pass (Gjk3Trace); it changes nothing else.
GjkCore3 runGjk3(const ShapeProxy3& a, const ShapeProxy3& b, Transform3 aFromB, GjkCache3* cache,
                 float separationRadius, Gjk3Trace* trace = nullptr) noexcept;

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
