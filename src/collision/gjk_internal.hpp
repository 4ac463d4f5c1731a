#pragma once
// GJK's inner loop, shared by computeDistance, testOverlap and EPA (which starts from the
// final simplex), and the observer hook that records its passes.

#include <cstdint>

#include "quack/collision/gjk.hpp"
#include "quack/collision/simplex2.hpp"

namespace quack::detail {

// A vertex of GJK's simplex as the loop keeps it: w = pointB - pointA (all the solver
// reads), the two proxy indices in one key (the repeated-support test compares one number
// a vertex) and the barycentric weight. The points on A and B are formed again from the
// indices where they are needed, by the operations that formed them in the loop (so the
// same bits): the loop moves 16 bytes a vertex, not a 36-byte SimplexVertex.
struct GjkVertex {
  Vec2 w;  // A frame
  float weight = 0.0f;
  std::uint32_t key = 0;  // indexA | indexB << 16

  int indexA() const noexcept { return static_cast<int>(key & 0xFFFFu); }
  int indexB() const noexcept { return static_cast<int>(key >> 16); }
};

constexpr std::uint32_t packGjkIndices(int indexA, int indexB) noexcept {
  return static_cast<std::uint32_t>(indexA) | (static_cast<std::uint32_t>(indexB) << 16);
}

struct GjkRun {
  GjkVertex vertices[3];  // the final simplex, weights set
  int count = 0;
  Vec2 closest;  // the point of B - A closest to the origin (zero on overlap), A frame
  // closestDirection(run) when the loop already formed it (hasDirection), so
  // computeDistance does not normalise the same vector twice.
  Vec2 direction;
  bool hasDirection = false;
  int iterations = 0;
  GjkStatus status = GjkStatus::converged;
  bool separatedEarly = false;  // earlyOutRadius was given and a separating axis found
};

// A vertex of a run's simplex with its points on A and B (A frame), B placed by aFromB.
inline SupportPoint supportOf(const GjkVertex& v, const ShapeProxy& a, const ShapeProxy& b,
                              Transform aFromB) noexcept {
  SupportPoint s;
  s.indexA = v.indexA();
  s.indexB = v.indexB();
  s.pointA = a.points()[s.indexA];
  s.pointB = transformPoint(aFromB, b.points()[s.indexB]);
  s.w = s.pointB - s.pointA;
  return s;
}

// The run's simplex as a Simplex2 (for EPA and the trace).
Simplex2 toSimplex2(const GjkRun& run, const ShapeProxy& a, const ShapeProxy& b,
                    Transform aFromB) noexcept;

// computeWitnessPoints(toSimplex2(run, ...)), the same sums in the same order, without
// forming the Simplex2.
inline WitnessPoints witnessPoints(const GjkRun& run, const ShapeProxy& a, const ShapeProxy& b,
                                   Transform aFromB) noexcept {
  const Vec2* pointsA = a.points();
  const Vec2* pointsB = b.points();
  // Component by component (the operations of Vec2's += and *): written as Vec2 sums, the
  // compiler formed the sums twice, once in packed registers and once in scalar ones.
  float ax = 0.0f, ay = 0.0f, bx = 0.0f, by = 0.0f;
  for (int i = 0; i < run.count; ++i) {
    const GjkVertex& v = run.vertices[i];
    const Vec2 pa = pointsA[v.indexA()];
    const Vec2 pb = transformPoint(aFromB, pointsB[v.indexB()]);
    ax += v.weight * pa.x;
    ay += v.weight * pa.y;
    bx += v.weight * pb.x;
    by += v.weight * pb.y;
  }
  return {{ax, ay}, {bx, by}};
}

// The direction from the origin to the closest point v of a run's solved simplex: along v
// for a point; for a segment the unit normal of the segment on v's side, which is exact to
// the rounding of the segment's own direction however small |v| is (v / |v| is not: its
// direction error grows like size / |v|). Zero when v is zero.
Vec2 closestDirection(const GjkRun& run) noexcept;

// The slot for the next record of a trace (GjkTrace, EpaTrace): the first capacity - 1
// passes in order, then the last slot again and again, so it ends holding the final pass.
// Null when the buffer has no room at all (no records, or capacity <= 0).
template <class Trace>
auto* claimTraceRecord(Trace& trace) noexcept {
  const int pass = trace.passes++;
  const int capacity = trace.records == nullptr ? 0 : trace.capacity;
  // No slot of its own: this pass (no room at all) or the one the last slot held is lost.
  if (pass >= capacity) trace.truncated = true;
  if (capacity <= 0) return static_cast<decltype(trace.records)>(nullptr);
  const int slot = pass < capacity ? pass : capacity - 1;
  trace.count = slot + 1;
  return &trace.records[slot];
}

template <class Trace>
void resetTrace(Trace& trace) noexcept {
  trace.count = 0;
  trace.passes = 0;
  trace.truncated = false;
}

// The observers runGjk is instantiated with. onPass sees the run at the end of each pass
// (after the support search, or at the stop when there is none) with `support` the pass's
// support point or null, and the transform it runs under. The default does nothing and
// compiles away.
struct NoGjkObserver {
  void onPass(const GjkRun&, Transform, const SupportPoint*) noexcept {}
};

// Records each pass into a GjkTrace (may be null: then it records nothing).
struct GjkRecorder {
  const ShapeProxy& a;
  const ShapeProxy& b;
  Transform worldFromA;
  GjkTrace* trace;

  void onPass(const GjkRun& run, Transform aFromB, const SupportPoint* support) noexcept;
};

// With earlyOutRadius >= 0 the loop also stops as soon as the distance is proven above
// it (separatedEarly) or below it (status overlap with a non-zero closest point). aFromB
// by reference: by value it is packed into two vector registers at the call and unpacked
// again inside, about ten moves a query.
template <class Observer>
GjkRun runGjk(const ShapeProxy& a, const ShapeProxy& b, const Transform& aFromB, GjkCache* cache,
              float earlyOutRadius, Observer& observer) noexcept;

extern template GjkRun runGjk<NoGjkObserver>(const ShapeProxy&, const ShapeProxy&, const Transform&,
                                             GjkCache*, float, NoGjkObserver&) noexcept;
extern template GjkRun runGjk<GjkRecorder>(const ShapeProxy&, const ShapeProxy&, const Transform&,
                                           GjkCache*, float, GjkRecorder&) noexcept;

}  // namespace quack::detail
