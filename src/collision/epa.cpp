// The 2D expanding polytope: a counter-clockwise polygon of support points of B - A.

#include "quack/collision/epa.hpp"
#include "gjk_internal.hpp"

namespace quack {

const char* toString(EpaStatus status) noexcept {
  switch (status) {
    case EpaStatus::separated:
      return "separated";
    case EpaStatus::coresSeparated:
      return "cores_separated";
    case EpaStatus::converged:
      return "converged";
    case EpaStatus::repeatedSupport:
      return "repeated_support";
    case EpaStatus::maxIterations:
      return "max_iterations";
    case EpaStatus::degenerate:
      return "degenerate";
  }
  return "unknown";
}

namespace {

// Counter-clockwise polygon; edge i runs from vertex i to vertex i + 1 (mod count).
struct Polytope2 {
  SupportPoint vertices[kEpaMaxVertices];
  Vec2 normals[kEpaMaxVertices];     // outward unit normal of edge i
  float distances[kEpaMaxVertices];  // signed distance of edge i's line from the origin
  int count = 0;
  float size = 0.0f;  // largest |w|: the scale of the relative tolerances
};

void updateEdge(Polytope2& p, int i) noexcept {
  Vec2 a = p.vertices[i].w;
  Vec2 b = p.vertices[(i + 1) % p.count].w;
  Vec2 e = b - a;
  float len = length(e);
  if (!(len > 0.0f)) {
    // A zero-length edge has no normal; it can never be the nearest.
    p.normals[i] = {};
    p.distances[i] = std::numeric_limits<float>::infinity();
    return;
  }
  Vec2 n = (1.0f / len) * rightPerp(e);
  p.normals[i] = n;
  p.distances[i] = dot(n, a);
}

bool sameSupport(const SupportPoint& x, const SupportPoint& y) noexcept {
  return x.indexA == y.indexA && x.indexB == y.indexB;
}

// The nearest edge, ties broken towards the normal (A to B, i.e. minus the edge normal)
// most along the centre direction c.
[[gnu::always_inline]] inline int findNearestEdge(const Polytope2& p, Vec2 c) noexcept {
  int best = 0;
  for (int i = 1; i < p.count; ++i) {
    if (p.distances[i] < p.distances[best]) best = i;
  }
  float tie = p.distances[best] + kEpaTieRelativeTolerance * p.size;
  float bestAlign = dot(p.normals[best], c);
  // A tying edge counts only if the origin projects onto it: next to the nearest edge, a
  // neighbour at almost the same distance has its foot just past the shared vertex, and its
  // witness points would not agree with its normal (regression test
  // Epa.TieBreakKeepsWitnessesOnTheEdge).
  auto projectsInside = [&](int i) {
    Vec2 v0 = p.vertices[i].w;
    Vec2 e = p.vertices[(i + 1) % p.count].w - v0;
    float ee = dot(e, e);
    float t = ee > 0.0f ? -dot(v0, e) / ee : 0.0f;
    return t >= 0.0f && t <= 1.0f;
  };
  for (int i = 0; i < p.count; ++i) {
    if (i == best || p.distances[i] > tie || !projectsInside(i)) continue;
    float align = dot(p.normals[i], c);
    if (align < bestAlign) {
      best = i;
      bestAlign = align;
    }
  }
  return best;
}

struct Degenerate {
  bool flat = false;
  Vec2 normal;  // A frame, A to B, when flat
};

// Grows GJK's simplex (which holds the origin, possibly on its boundary) into a
// counter-clockwise triangle. Returns flat when B - A has no area near the origin.
[[gnu::always_inline]] inline Degenerate buildTriangle(Polytope2& p, const Simplex2& s,
                                                       const ShapeProxy& a, const ShapeProxy& b,
                                                       Transform aFromB, Vec2 c,
                                                       int& iterations) noexcept {
  p.count = s.count;
  for (int i = 0; i < s.count; ++i)
    p.vertices[i] = s.vertices[i].support;
  for (int i = 0; i < p.count; ++i)
    p.size = maxf(p.size, length(p.vertices[i].w));
  if (p.count == 1) {
    const Vec2 axes[4] = {{1.0f, 0.0f}, {-1.0f, 0.0f}, {0.0f, 1.0f}, {0.0f, -1.0f}};
    for (Vec2 d : axes) {
      SupportPoint w = supportMinkowski(a, b, aFromB, d);
      ++iterations;
      if (!sameSupport(w, p.vertices[0]) && !(w.w == p.vertices[0].w)) {
        p.vertices[1] = w;
        p.count = 2;
        p.size = maxf(p.size, length(w.w));
        break;
      }
    }
    if (p.count == 1) {
      // B - A is a single point (two circle cores on the same centre, say).
      Vec2 n = normalize(c);
      return {true, n == Vec2{} ? Vec2{0.0f, 1.0f} : n};
    }
  }
  if (p.count == 2) {
    Vec2 e = p.vertices[1].w - p.vertices[0].w;
    Vec2 n = normalize(leftPerp(e));
    for (float sign : {1.0f, -1.0f}) {
      SupportPoint w = supportMinkowski(a, b, aFromB, sign * n);
      ++iterations;
      if (sign * dot(n, w.w - p.vertices[0].w) > kEpaRelativeTolerance * p.size) {
        p.vertices[2] = w;
        p.count = 3;
        p.size = maxf(p.size, length(w.w));
        break;
      }
    }
    if (p.count == 2) {
      // B - A is a segment through the origin (collinear segment or capsule cores): any
      // sideways push separates the cores, so the core depth is zero. Side from the centres.
      if (dot(n, c) < 0.0f) n = -n;
      return {true, n};
    }
  }
  if (cross(p.vertices[1].w - p.vertices[0].w, p.vertices[2].w - p.vertices[0].w) < 0.0f) {
    SupportPoint t = p.vertices[1];
    p.vertices[1] = p.vertices[2];
    p.vertices[2] = t;
  }
  for (int i = 0; i < 3; ++i)
    updateEdge(p, i);
  return {};
}

// The answer from the polytope's nearest edge (the final one, or any pass's, for the
// trace): depth, normal and the deepest points, world frame.
[[gnu::always_inline]] inline void finishFromEdge(const Polytope2& poly, int edge,
                                                  const ShapeProxy& a, const ShapeProxy& b,
                                                  Transform worldFromA,
                                                  PenetrationOutput& out) noexcept {
  const float radii = a.radius() + b.radius();
  const SupportPoint& v0 = poly.vertices[edge];
  const SupportPoint& v1 = poly.vertices[(edge + 1) % poly.count];
  Vec2 e = v1.w - v0.w;
  float ee = dot(e, e);
  // Barycentric weight of the origin's projection onto the nearest edge.
  float t = ee > 0.0f ? clampf(-dot(v0.w, e) / ee, 0.0f, 1.0f) : 0.0f;
  Vec2 coreA = lerp(v0.pointA, v1.pointA, t);
  Vec2 coreB = lerp(v0.pointB, v1.pointB, t);
  Vec2 n = -poly.normals[edge];
  float coreDepth = maxf(poly.distances[edge], 0.0f);
  out.depth = coreDepth + radii;
  out.normal = rotate(worldFromA.q, n);
  out.pointA = transformPoint(worldFromA, coreA + a.radius() * n);
  out.pointB = transformPoint(worldFromA, coreB - b.radius() * n);
}

// The EPA observers, as for GJK (gjk_internal.hpp): onStart gets the support points spent
// on the first triangle, onPass the polytope of each pass, its nearest edge and the pass's
// support point (null when the polytope was full).
struct NoEpaObserver {
  void onStart(int) noexcept {}
  void onPass(const Polytope2&, int, const SupportPoint*) noexcept {}
};

struct EpaRecorder {
  const ShapeProxy& a;
  const ShapeProxy& b;
  Transform worldFromA;
  EpaTrace* trace;

  void onStart(int triangleSupports) noexcept {
    if (trace != nullptr) trace->triangleSupports = triangleSupports;
  }

  void onPass(const Polytope2& poly, int edge, const SupportPoint* support) noexcept {
    if (trace == nullptr) return;
    EpaIterationRecord* record = detail::claimTraceRecord(*trace);
    if (record == nullptr) return;
    for (int i = 0; i < poly.count; ++i)
      record->polytope[i] = poly.vertices[i];
    record->polytopeCount = poly.count;
    record->edge = edge;
    record->edgeNormal = poly.normals[edge];
    record->edgeDistance = poly.distances[edge];
    record->hasSupport = support != nullptr;
    record->support = support != nullptr ? *support : SupportPoint{};
    PenetrationOutput answer;
    finishFromEdge(poly, edge, a, b, worldFromA, answer);
    record->depth = answer.depth;
    record->normal = answer.normal;
    record->pointA = answer.pointA;
    record->pointB = answer.pointB;
  }
};

// Instantiated unobserved and observed. The helpers above are always inlined, so that the
// unobserved copy is compiled as if it were the only one: with two callers each the
// compiler would call them instead, and every query would pay for the calls.
template <class GjkObserver, class EpaObserver>
PenetrationOutput penetrate(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                            Transform worldFromB, GjkCache* cache, GjkObserver& gjkObserver,
                            EpaObserver& epaObserver) noexcept {
  Transform aFromB = invMul(worldFromA, worldFromB);
  detail::GjkRun run = detail::runGjk(a, b, aFromB, cache, -1.0f, gjkObserver);
  PenetrationOutput out;
  out.iterations = run.iterations;
  const float radii = a.radius() + b.radius();

  if (run.status != GjkStatus::overlap) {
    WitnessPoints witness = detail::witnessPoints(run, a, b, aFromB);
    float core = length(run.closest);
    Vec2 n = detail::closestDirection(run);
    out.normal = rotate(worldFromA.q, n);
    out.pointA = transformPoint(worldFromA, witness.pointA + a.radius() * n);
    out.pointB = transformPoint(worldFromA, witness.pointB - b.radius() * n);
    if (core > radii) {
      out.status = EpaStatus::separated;
      return out;
    }
    out.overlap = true;
    out.depth = radii - core;
    out.status = EpaStatus::coresSeparated;
    return out;
  }

  out.overlap = true;
  const Vec2 c = transformPoint(aFromB, b.center()) - a.center();
  Polytope2 poly;
  const Simplex2 simplex = detail::toSimplex2(run, a, b, aFromB);
  Degenerate flat = buildTriangle(poly, simplex, a, b, aFromB, c, out.iterations);
  epaObserver.onStart(out.iterations - run.iterations);
  if (flat.flat) {
    // The cores meet but B - A has no area: the witness point of GJK is shared by both cores.
    WitnessPoints witness = computeWitnessPoints(simplex);
    out.depth = radii;
    out.normal = rotate(worldFromA.q, flat.normal);
    out.pointA = transformPoint(worldFromA, witness.pointA + a.radius() * flat.normal);
    out.pointB = transformPoint(worldFromA, witness.pointB - b.radius() * flat.normal);
    out.status = EpaStatus::degenerate;
    return out;
  }

  int edge = 0;
  out.status = EpaStatus::maxIterations;
  for (;;) {
    edge = findNearestEdge(poly, c);
    if (poly.count >= kEpaMaxVertices) {
      epaObserver.onPass(poly, edge, nullptr);
      break;
    }
    Vec2 n = poly.normals[edge];
    SupportPoint w = supportMinkowski(a, b, aFromB, n);
    ++out.iterations;
    // Seen before the stopping tests: if one ends the loop, this pass's edge is the answer.
    epaObserver.onPass(poly, edge, &w);
    const SupportPoint& e0 = poly.vertices[edge];
    const SupportPoint& e1 = poly.vertices[(edge + 1) % poly.count];
    if (sameSupport(w, e0) || sameSupport(w, e1)) {
      out.status = EpaStatus::repeatedSupport;
      break;
    }
    poly.size = maxf(poly.size, length(w.w));
    if (dot(n, w.w) - poly.distances[edge] <= kEpaRelativeTolerance * poly.size) {
      out.status = EpaStatus::converged;
      break;
    }
    // Insert w between the edge's ends; w lies strictly outside the edge, so the polygon
    // stays convex and counter-clockwise.
    for (int i = poly.count; i > edge + 1; --i) {
      poly.vertices[i] = poly.vertices[i - 1];
      poly.normals[i] = poly.normals[i - 1];
      poly.distances[i] = poly.distances[i - 1];
    }
    poly.vertices[edge + 1] = w;
    ++poly.count;
    updateEdge(poly, edge);
    updateEdge(poly, edge + 1);
  }

  finishFromEdge(poly, edge, a, b, worldFromA, out);
  return out;
}

}  // namespace

PenetrationOutput computePenetration(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                                     Transform worldFromB, GjkCache* cache) noexcept {
  detail::NoGjkObserver noGjk;
  NoEpaObserver noEpa;
  return penetrate(a, worldFromA, b, worldFromB, cache, noGjk, noEpa);
}

PenetrationOutput computePenetration(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                                     Transform worldFromB, GjkCache* cache, GjkTrace* gjkTrace,
                                     EpaTrace* epaTrace) noexcept {
  if (gjkTrace != nullptr) detail::resetTrace(*gjkTrace);
  if (epaTrace != nullptr) {
    detail::resetTrace(*epaTrace);
    epaTrace->triangleSupports = 0;
  }
  detail::GjkRecorder gjkRecorder{a, b, worldFromA, gjkTrace};
  EpaRecorder epaRecorder{a, b, worldFromA, epaTrace};
  return penetrate(a, worldFromA, b, worldFromB, cache, gjkRecorder, epaRecorder);
}

}  // namespace quack
