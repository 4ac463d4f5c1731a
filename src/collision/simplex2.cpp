#include "quack/collision/simplex2.hpp"

namespace quack {
namespace {

// True when a and b are both positive or both negative (zero matches nothing): a weight
// of exactly zero drops its vertex, so a point on an edge is solved on that edge.
inline bool sameSign(float a, float b) noexcept {
  return (a > 0.0f && b > 0.0f) || (a < 0.0f && b < 0.0f);
}

// Montanari et al.'s S1D in the plane: the origin projected onto the line through a and b,
// and its barycentric coordinates measured along the axis where the segment is longest
// (the best conditioned of the two ratios). Returns which vertices keep a weight.
struct Segment1D {
  float weightA = 0.0f;
  float weightB = 0.0f;
  Vec2 closest;
};

Segment1D solveSegment(Vec2 a, Vec2 b) noexcept {
  Vec2 e = b - a;
  float ee = dot(e, e);
  if (ee == 0.0f) return {1.0f, 0.0f, a};
  Vec2 p0 = a - (dot(a, e) / ee) * e;
  bool useX = absf(e.x) >= absf(e.y);
  float mu = useX ? a.x - b.x : a.y - b.y;
  float c1 = useX ? p0.x - b.x : p0.y - b.y;  // weight of a times mu
  float c2 = useX ? a.x - p0.x : a.y - p0.y;  // weight of b times mu
  if (sameSign(mu, c1) && sameSign(mu, c2)) return {c1 / mu, c2 / mu, p0};
  // The projection falls outside (or on an end of) the segment: the nearer end is closest.
  if (sameSign(mu, c1)) return {1.0f, 0.0f, a};
  return {0.0f, 1.0f, b};
}

void keepSegment(Simplex2& s, int i, int j, const Segment1D& r) noexcept {
  SimplexVertex vi = s.vertices[i];
  SimplexVertex vj = s.vertices[j];
  if (r.weightA > 0.0f && r.weightB > 0.0f) {
    s.vertices[0] = vi;
    s.vertices[1] = vj;
    s.vertices[0].weight = r.weightA;
    s.vertices[1].weight = r.weightB;
    s.count = 2;
  } else {
    s.vertices[0] = r.weightA > 0.0f ? vi : vj;
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
    Segment1D r = solveSegment(s.vertices[0].support.w, s.vertices[1].support.w);
    keepSegment(s, 0, 1, r);
    return {r.closest, false};
  }
  Vec2 a = s.vertices[0].support.w;
  Vec2 b = s.vertices[1].support.w;
  Vec2 c = s.vertices[2].support.w;
  // Twice the signed area of abc, and of the three triangles with the origin in place of
  // one vertex; they sum to mu, so c_i / mu are the origin's barycentric coordinates.
  float mu = cross(b - a, c - a);
  float ca = cross(b, c);
  float cb = cross(c, a);
  float cc = cross(a, b);
  if (sameSign(mu, ca) && sameSign(mu, cb) && sameSign(mu, cc)) {
    s.vertices[0].weight = ca / mu;
    s.vertices[1].weight = cb / mu;
    s.vertices[2].weight = cc / mu;
    return {Vec2{}, true};
  }
  // The origin is outside (or on the boundary of, or the triangle is flat): the closest
  // point lies on an edge facing the origin, that is an edge whose opposite vertex's
  // sub-area has the wrong sign. Try each such edge and keep the nearest.
  const float sub[3] = {ca, cb, cc};
  const int edge[3][2] = {{1, 2}, {2, 0}, {0, 1}};  // the edge opposite vertex k
  float bestDistance = std::numeric_limits<float>::infinity();
  int bestEdge = -1;
  Segment1D best;
  for (int k = 0; k < 3; ++k) {
    if (sameSign(mu, sub[k])) continue;
    int i = edge[k][0];
    int j = edge[k][1];
    // Keep the older vertex first so that the order stays the insertion order.
    if (i > j) {
      int t = i;
      i = j;
      j = t;
    }
    Segment1D r = solveSegment(s.vertices[i].support.w, s.vertices[j].support.w);
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
  int i = edge[bestEdge][0];
  int j = edge[bestEdge][1];
  if (i > j) {
    int t = i;
    i = j;
    j = t;
  }
  keepSegment(s, i, j, best);
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
