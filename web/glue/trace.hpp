#pragma once
// A display-only re-run of Quack's GJK and EPA that records every iteration, for the demo
// page. The library's own loops keep no history (they must not allocate), so this file
// follows them step by step through the public pieces (supportMinkowski, solveSimplex2,
// computeWitnessPoints) and the same constants. It is checked against the library on every
// call: glue.cpp compares the traced status, iteration count, distance and depth with
// computeDistance and computePenetration and reports any difference on the page.

#include <vector>

#include "quack/collision/epa.hpp"
#include "quack/collision/simplex2.hpp"

namespace quack::web {

/// One GJK iteration. Points in A's frame.
struct GjkStep {
  Simplex2 simplex;         ///< after the solve (reduced, weights set)
  Vec2 closest;             ///< point of the simplex closest to the origin
  bool hasSupport = false;  ///< a support point was taken in this iteration
  Vec2 direction;           ///< unit search direction (the support is taken along -direction)
  SupportPoint support;
};

struct GjkTrace {
  std::vector<GjkStep> steps;
  Simplex2 finalSimplex;
  Vec2 closest;
  int iterations = 0;
  GjkStatus status = GjkStatus::converged;
  float distance = 0.0f;  ///< rounded shapes, 0 when overlapping
};

/// One EPA iteration. Points in A's frame.
struct EpaStep {
  std::vector<SupportPoint> polytope;  ///< counter-clockwise
  int nearestEdge = 0;
  Vec2 normal;  ///< outward unit normal of the nearest edge
  float distance = 0.0f;
  bool hasSupport = false;
  SupportPoint support;
};

struct EpaTrace {
  bool ran = false;  ///< the cores overlapped and B - A has area
  std::vector<EpaStep> steps;
  EpaStatus status = EpaStatus::separated;
  float depth = 0.0f;  ///< rounded shapes
  int iterations = 0;  ///< GJK plus EPA support points
};

/// GJK from a cold start, as computeDistance runs it. `aFromB` places B in A's frame.
GjkTrace traceGjk(const ShapeProxy& a, const ShapeProxy& b, Transform aFromB);

/// EPA from GJK's final simplex, as computePenetration runs it.
EpaTrace traceEpa(const ShapeProxy& a, const ShapeProxy& b, Transform aFromB, const GjkTrace& gjk);

}  // namespace quack::web
