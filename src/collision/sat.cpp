#include "quack/collision/sat.hpp"

namespace quack {
namespace {

struct Axis {
  float separation;
  int edge;
};

// The largest over p's edge normals of the smallest signed distance of q's vertices from
// that edge; q is given in p's frame.
Axis findMaxSeparation(const Polygon& p, const Polygon& q, Transform pFromQ) noexcept {
  Vec2 qv[kMaxPolygonVertices];
  for (int j = 0; j < q.count; ++j)
    qv[j] = transformPoint(pFromQ, q.vertices[j]);
  Axis best{-std::numeric_limits<float>::infinity(), 0};
  for (int i = 0; i < p.count; ++i) {
    Vec2 n = p.normals[i];
    Vec2 v = p.vertices[i];
    float s = std::numeric_limits<float>::infinity();
    for (int j = 0; j < q.count; ++j)
      s = minf(s, dot(n, qv[j] - v));
    if (s > best.separation) best = {s, i};
  }
  return best;
}

}  // namespace

SatOutput computeSat(const Polygon& a, Transform worldFromA, const Polygon& b,
                     Transform worldFromB) noexcept {
  Transform aFromB = invMul(worldFromA, worldFromB);
  Axis onA = findMaxSeparation(a, b, aFromB);
  Axis onB = findMaxSeparation(b, a, inverse(aFromB));
  float radii = a.radius + b.radius;
  // Prefer A's axis unless B's is better by more than rounding, so a symmetric pair gives
  // a stable answer (about 10 float ulps of the separation's scale).
  constexpr float kSatRelativeTieTolerance = 1e-6f;
  float scale = maxf(absf(onA.separation), absf(onB.separation)) + 1e-30f;
  SatOutput out;
  if (onB.separation > onA.separation + kSatRelativeTieTolerance * scale) {
    out.separation = onB.separation - radii;
    out.normal = -rotate(worldFromB.q, b.normals[onB.edge]);
    out.edge = onB.edge;
    out.edgeOnA = false;
  } else {
    out.separation = onA.separation - radii;
    out.normal = rotate(worldFromA.q, a.normals[onA.edge]);
    out.edge = onA.edge;
    out.edgeOnA = true;
  }
  return out;
}

}  // namespace quack
