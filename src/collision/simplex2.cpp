#include "quack/collision/simplex2.hpp"

#include "simplex2_internal.hpp"

namespace quack {
namespace {

// The edge ij of s (i < j, so the kept vertices stay in insertion order) as the new
// simplex: both ends when both weights are positive, else the one that is.
void keepSegment(Simplex2& s, int i, int j, const detail::SegmentSolve& r) noexcept {
  const detail::SegmentWeights weights = detail::segmentWeights(r);
  SimplexVertex vi = s.vertices[i];
  SimplexVertex vj = s.vertices[j];
  if (weights.a > 0.0f && weights.b > 0.0f) {
    s.vertices[0] = vi;
    s.vertices[1] = vj;
    s.vertices[0].weight = weights.a;
    s.vertices[1].weight = weights.b;
    s.count = 2;
  } else {
    s.vertices[0] = weights.a > 0.0f ? vi : vj;
    s.vertices[0].weight = 1.0f;
    s.count = 1;
  }
}

}  // namespace

SimplexSolution solveSimplex2(Simplex2& s) noexcept {
  QUACK_ASSERT(s.count >= 1 && s.count <= 3);
  if (s.count == 1) {
    s.vertices[0].weight = 1.0f;
    return {s.vertices[0].support.w, false};
  }
  if (s.count == 2) {
    detail::SegmentSolve r = detail::solveSegment(s.vertices[0].support.w, s.vertices[1].support.w);
    keepSegment(s, 0, 1, r);
    return {r.closest, false};
  }
  const detail::TriangleAreas t = detail::triangleAreas(
      s.vertices[0].support.w, s.vertices[1].support.w, s.vertices[2].support.w);
  if (!t.faces[0] && !t.faces[1] && !t.faces[2]) {
    s.vertices[0].weight = t.sub[0] / t.mu;
    s.vertices[1].weight = t.sub[1] / t.mu;
    s.vertices[2].weight = t.sub[2] / t.mu;
    return {Vec2{}, true};
  }
  // The origin is outside (or on the boundary of, or the triangle is flat): the closest
  // point lies on an edge facing the origin. Try each such edge and keep the nearest.
  const int edge[3][2] = {{1, 2}, {0, 2}, {0, 1}};  // the edge opposite vertex k, in order
  float bestDistance = std::numeric_limits<float>::infinity();
  int bestEdge = -1;
  detail::SegmentSolve best;
  for (int k = 0; k < 3; ++k) {
    if (!t.faces[k]) continue;
    detail::SegmentSolve r =
        detail::solveSegment(s.vertices[edge[k][0]].support.w, s.vertices[edge[k][1]].support.w);
    float d = lengthSquared(r.closest);
    if (d < bestDistance) {
      bestDistance = d;
      bestEdge = k;
      best = r;
    }
  }
  if (bestEdge < 0) {
    // Only reachable with NaN coordinates: keep one vertex so the caller stops cleanly.
    s.count = 1;
    s.vertices[0].weight = 1.0f;
    return {s.vertices[0].support.w, false};
  }
  keepSegment(s, edge[bestEdge][0], edge[bestEdge][1], best);
  return {best.closest, false};
}

WitnessPoints computeWitnessPoints(const Simplex2& s) noexcept {
  WitnessPoints out;
  for (int i = 0; i < s.count; ++i) {
    out.pointA += s.vertices[i].weight * s.vertices[i].support.pointA;
    out.pointB += s.vertices[i].weight * s.vertices[i].support.pointB;
  }
  return out;
}

}  // namespace quack
