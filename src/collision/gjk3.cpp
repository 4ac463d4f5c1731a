// GJK in 3D (see gjk3.hpp). The simplex solve is in double; everything else in float.

#include "quack/collision/gjk3.hpp"
#include "quack/math/detail/vec3d.hpp"

#include <cmath>
#include <limits>

#include "gjk3_internal.hpp"

namespace quack {
namespace detail {
namespace {

// A fall of |v|^2 (computed in double) smaller than this fraction of the simplex's squared
// size is rounding, not progress: about 8 double ulps of the squared coordinates.
constexpr double kGjk3StallRelativeTolerance = 8.0 * std::numeric_limits<double>::epsilon();

using D3 = detail::Vec3d;
using detail::toDouble;

// The nearest point of a sub-simplex to the origin: which vertices (by index into the
// simplex) carry it and with what weights.
struct Solution {
  int count = 0;
  int index[4] = {};
  double weight[4] = {};
  double distanceSquared = std::numeric_limits<double>::infinity();
};

Solution single(int i, D3 p) {
  Solution s;
  s.count = 1;
  s.index[0] = i;
  s.weight[0] = 1.0;
  s.distanceSquared = detail::dot(p, p);
  return s;
}

Solution pair(int i, int j, D3 a, D3 b, double t) {  // (1 - t) a + t b
  Solution s;
  s.count = 2;
  s.index[0] = i;
  s.index[1] = j;
  s.weight[0] = 1.0 - t;
  s.weight[1] = t;
  D3 q = a + t * (b - a);
  s.distanceSquared = detail::dot(q, q);
  return s;
}

// Nearest point of segment ab to the origin.
Solution solveSegment(int i, int j, D3 a, D3 b) {
  D3 ab = b - a;
  double t = -detail::dot(a, ab);
  if (t <= 0.0) return single(i, a);
  double len2 = detail::dot(ab, ab);
  if (t >= len2) return single(j, b);
  return pair(i, j, a, b, t / len2);
}

// Nearest point of triangle abc to the origin, by its Voronoi regions (Ericson 5.1.5 with
// p = 0).
Solution solveTriangle(int i, int j, int k, D3 a, D3 b, D3 c) {
  D3 ab = b - a, ac = c - a;
  D3 ap = -1.0 * a;
  double d1 = detail::dot(ab, ap), d2 = detail::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return single(i, a);
  D3 bp = -1.0 * b;
  double d3 = detail::dot(ab, bp), d4 = detail::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return single(j, b);
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return pair(i, j, a, b, d1 / (d1 - d3));
  D3 cp = -1.0 * c;
  double d5 = detail::dot(ab, cp), d6 = detail::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return single(k, c);
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return pair(i, k, a, c, d2 / (d2 - d6));
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return pair(j, k, b, c, (d4 - d3) / ((d4 - d3) + (d5 - d6)));
  double sum = va + vb + vc;
  if (!(sum > 0)) {
    // Degenerate (collinear) triangle: the best of its edges.
    Solution best = solveSegment(i, j, a, b);
    Solution s2 = solveSegment(j, k, b, c);
    if (s2.distanceSquared < best.distanceSquared) best = s2;
    Solution s3 = solveSegment(i, k, a, c);
    if (s3.distanceSquared < best.distanceSquared) best = s3;
    return best;
  }
  double v = vb / sum, w = vc / sum;
  Solution s;
  s.count = 3;
  s.index[0] = i;
  s.index[1] = j;
  s.index[2] = k;
  s.weight[0] = 1.0 - v - w;
  s.weight[1] = v;
  s.weight[2] = w;
  D3 q = a + v * ab + w * ac;
  s.distanceSquared = detail::dot(q, q);
  return s;
}

// Nearest point of tetrahedron abcd to the origin: inside (count 4, distance 0), or the
// nearest of the faces the origin is outside of (Ericson 5.1.6). A face whose opposite
// vertex is (nearly) on its plane is also tried, so a flat tetrahedron still gives its
// nearest face rather than a false "inside".
Solution solveTetrahedron(const D3 p[4]) {
  double scale = 0;
  for (int i = 1; i < 4; ++i)
    scale = std::max(scale, detail::dot(p[i] - p[0], p[i] - p[0]));
  Solution best;
  bool inside = true;
  // Face i, j, k with opposite vertex l; written out per face (constant indices) so that
  // the points stay in registers.
  auto tryFace = [&](int i, int j, int k, int l) {
    const D3 a = p[i], b = p[j], c = p[k];
    const D3 n = detail::cross(b - a, c - a);
    const double signO = -detail::dot(n, a);  // origin's side
    const double signD = detail::dot(n, p[l] - a);
    // Flat when the opposite vertex's height is within double rounding of the face.
    const bool flat = signD * signD <= 1e-24 * detail::dot(n, n) * scale;
    if (!flat && signO * signD >= 0) return;  // origin on the inner side of this face
    inside = false;
    Solution s = solveTriangle(i, j, k, a, b, c);
    if (s.distanceSquared < best.distanceSquared) best = s;
  };
  tryFace(0, 1, 2, 3);
  tryFace(0, 2, 3, 1);
  tryFace(0, 3, 1, 2);
  tryFace(1, 3, 2, 0);
  if (inside) {
    Solution s;
    s.count = 4;
    for (int i = 0; i < 4; ++i) {
      s.index[i] = i;
      s.weight[i] = 0.25;
    }
    s.distanceSquared = 0.0;
    return s;
  }
  return best;
}

// The simplex's point nearest the origin: which vertices carry it, their weights, the
// point and its squared length, in double. The simplex is left as it is.
Solution solveSimplex(const Simplex3& s, D3& closest) noexcept {
  // All four slots, used or not (they always hold finite points or zeros): a loop of fixed
  // length has no branch to mispredict.
  const D3 p[4] = {toDouble(s.v[0].w), toDouble(s.v[1].w), toDouble(s.v[2].w), toDouble(s.v[3].w)};
  Solution sol;
  switch (s.count) {
    case 1:
      sol = single(0, p[0]);
      break;
    case 2:
      sol = solveSegment(0, 1, p[0], p[1]);
      break;
    case 3:
      sol = solveTriangle(0, 1, 2, p[0], p[1], p[2]);
      break;
    default:
      sol = solveTetrahedron(p);
      break;
  }
  D3 q{};
  for (int i = 0; i < sol.count; ++i)
    q = q + sol.weight[i] * p[sol.index[i]];
  closest = q;
  sol.distanceSquared = sol.count == 4 ? 0.0 : detail::dot(q, q);
  return sol;
}

// Keeps the vertices that carry the solution, in its order, with their weights. In place
// when its indices ascend (a segment's or a triangle's always do; a tetrahedron's face may
// not), else through a copy.
void reduceSimplex(Simplex3& s, const Solution& sol) noexcept {
  bool ascending = true;
  for (int i = 1; i < sol.count; ++i)
    ascending = ascending && sol.index[i - 1] < sol.index[i];
  if (ascending) {
    for (int i = 0; i < sol.count; ++i) {
      if (sol.index[i] != i) s.v[i] = s.v[sol.index[i]];
    }
  } else {
    SupportPoint3 kept[4];
    for (int i = 0; i < sol.count; ++i)
      kept[i] = s.v[sol.index[i]];
    for (int i = 0; i < sol.count; ++i)
      s.v[i] = kept[i];
  }
  for (int i = 0; i < sol.count; ++i)
    s.weights[i] = static_cast<float>(sol.weight[i]);
  s.count = sol.count;
}

Vec3 toFloat(D3 q) noexcept {
  return {static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z)};
}

}  // namespace

GjkCore3 runGjk3(const MinkowskiPair3& pair, GjkCache3* cache, float separationRadius,
                 Simplex3& simplex, Gjk3Trace* trace) noexcept {
  const ShapeProxy3& a = pair.a;
  const ShapeProxy3& b = pair.b;
  GjkCore3 out;
  // The pass's record (null when not tracing): the simplex and v after the solve, then the
  // support point if one is taken.
  Gjk3IterationRecord* record = nullptr;
  Simplex3& s = simplex;
  s.count = 0;
  bool warm = false;
  if (cache != nullptr && cache->count >= 1 && cache->count <= 4) {
    warm = true;
    for (int i = 0; i < cache->count; ++i) {
      if (cache->indexA[i] >= a.count() || cache->indexB[i] >= b.count()) warm = false;
    }
    if (warm) {
      for (int i = 0; i < cache->count; ++i)
        s.v[i] = pair.make(cache->indexA[i], cache->indexB[i]);
      s.count = cache->count;
    }
  }
  if (!warm) {
    Vec3 d = pair.rotation * b.center() + pair.translation - a.center();
    if (lengthSquared(d) == 0.0f) d = {1, 0, 0};
    s.v[0] = pair.support(-d);
    s.count = 1;
    out.iterations = 1;
  }

  double previous = std::numeric_limits<double>::infinity();
  Vec3 v;
  GjkStatus status = GjkStatus::maxIterations;
  for (int iter = 0; iter < kGjk3MaxIterations; ++iter) {
    D3 q;
    const Solution sol = solveSimplex(s, q);
    float scale = 0.0f;
    for (int i = 0; i < sol.count; ++i)
      scale = maxf(scale, lengthSquared(s.v[sol.index[i]].w));
    const Vec3 closest = toFloat(q);
    const float contact = kGjk3ContactRelativeTolerance * kGjk3ContactRelativeTolerance * scale;
    const bool overlap = sol.count == 4 || lengthSquared(closest) <= contact;
    // Progress is judged on |v|^2 in double: the last steps turn v by angles whose effect
    // on |v|^2 (the square of the angle) is far below float's resolution, and stopping
    // there would leave the normal off by ~1e-4 (found by the brute-force oracle).
    const double vvD = sol.distanceSquared;
    const bool stalled =
        !overlap && vvD >= previous - kGjk3StallRelativeTolerance * static_cast<double>(scale);
    if (stalled && vvD > previous) {
      // Worse than before: keep the simplex that gave v, the last pass's, which is this one
      // without the new support point (the last vertex); its weights are still in place.
      --s.count;
    } else {
      reduceSimplex(s, sol);
      v = closest;
    }
    if (overlap) v = {};
    if (trace != nullptr && trace->capacity > 0) {
      record = claimTraceRecord3(*trace);
      *record = {};
      record->simplex = s;
      record->closest = v;
    }
    if (overlap) {
      status = GjkStatus::overlap;
      break;
    }
    if (stalled) {
      status = GjkStatus::stalled;
      break;
    }
    previous = vvD;
    const float vv = lengthSquared(v);
    SupportPoint3 w = pair.support(-v);
    ++out.iterations;
    if (record != nullptr) {
      record->hasSupport = true;
      record->direction = normalize(v);
      record->support = w;
    }
    // Every slot compared, the unused ones masked out: no branch per vertex.
    bool repeated = false;
    for (int i = 0; i < 4; ++i)
      repeated |= (i < s.count) & (s.v[i].indexA == w.indexA) & (s.v[i].indexB == w.indexB);
    if (repeated) {
      status = GjkStatus::repeatedSupport;
      break;
    }
    float vw = dot(v, w.w);
    // Early out for the overlap test: the lower bound on the core distance, v.w / |v|,
    // already exceeds the radii.
    if (separationRadius >= 0.0f && vw > 0.0f &&
        vw * vw > separationRadius * separationRadius * vv) {
      status = GjkStatus::converged;
      out.separated = true;
      break;
    }
    if (vv - vw <= 0.0f) {
      status = GjkStatus::converged;
      break;
    }
    s.v[s.count++] = w;
  }
  out.status = status;
  out.closest = v;
  if (cache != nullptr) {
    cache->count = s.count;
    for (int i = 0; i < s.count; ++i) {
      cache->indexA[i] = static_cast<std::uint8_t>(s.v[i].indexA);
      cache->indexB[i] = static_cast<std::uint8_t>(s.v[i].indexB);
    }
  }
  return out;
}

void closestPoints3(const Simplex3& s, Vec3& pointA, Vec3& pointB) noexcept {
  pointA = {};
  pointB = {};
  for (int i = 0; i < s.count; ++i) {
    pointA += s.weights[i] * s.v[i].pointA;
    pointB += s.weights[i] * s.v[i].pointB;
  }
}

}  // namespace detail

namespace {

DistanceOutput3 distance3(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                          Transform3 worldFromB, GjkCache3* cache, Gjk3Trace* trace) noexcept {
  // A's rotation as a matrix: four rotations below (B's offset into A's frame, the normal
  // and the two points out of it) cost less so than by the quaternion.
  const Mat3 worldFromARotation = toMat3(worldFromA.q);
  auto toWorld = [&](Vec3 p) { return worldFromARotation * p + worldFromA.p; };
  const Transform3 aFromB{mulTranspose(worldFromARotation, worldFromB.p - worldFromA.p),
                          invMul(worldFromA.q, worldFromB.q)};
  const detail::MinkowskiPair3 pair(a, b, aFromB);
  DistanceOutput3 out;
  detail::GjkCore3 core = detail::runGjk3(pair, cache, -1.0f, out.simplex, trace);
  out.iterations = core.iterations;
  out.status = core.status;
  Vec3 pA, pB;
  detail::closestPoints3(out.simplex, pA, pB);
  float ra = a.radius(), rb = b.radius();
  if (core.status == GjkStatus::overlap) {
    // The cores share a point: report it (the weights place it on both cores).
    Vec3 p = toWorld(0.5f * (pA + pB));
    out.pointA = out.pointB = p;
    return out;
  }
  // The separating direction from the solved v (more accurate than pB - pA, which
  // subtracts two rebuilt points).
  float len = length(core.closest);
  Vec3 n = (1.0f / len) * core.closest;
  out.coreDistance = len;
  out.normal = worldFromARotation * n;
  if (len > ra + rb) {
    out.distance = len - ra - rb;
    out.pointA = toWorld(pA + ra * n);
    out.pointB = toWorld(pB - rb * n);
  } else {
    // Only the radii overlap: the shared point halfway between the surfaces.
    Vec3 p = 0.5f * ((pA + ra * n) + (pB - rb * n));
    out.pointA = out.pointB = toWorld(p);
  }
  return out;
}

}  // namespace

DistanceOutput3 computeDistance(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                                Transform3 worldFromB, GjkCache3* cache) noexcept {
  return distance3(a, worldFromA, b, worldFromB, cache, nullptr);
}

DistanceOutput3 computeDistance(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                                Transform3 worldFromB, GjkCache3* cache,
                                Gjk3Trace& trace) noexcept {
  detail::resetTrace3(trace);
  return distance3(a, worldFromA, b, worldFromB, cache, &trace);
}

bool testOverlap(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                 Transform3 worldFromB, GjkCache3* cache) noexcept {
  const detail::MinkowskiPair3 pair(a, b, invMul(worldFromA, worldFromB));
  float radii = a.radius() + b.radius();
  Simplex3 simplex;
  detail::GjkCore3 core = detail::runGjk3(pair, cache, radii, simplex);
  if (core.separated) return false;
  if (core.status == GjkStatus::overlap) return true;
  return length(core.closest) <= radii;
}

}  // namespace quack
