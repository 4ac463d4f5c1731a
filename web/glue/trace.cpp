#include "trace.hpp"

#include <limits>

namespace quack::web {
namespace {

// Same as the library's closestDirection (src/collision/gjk.cpp): for a segment simplex,
// the exact edge normal on v's side; otherwise v / |v|.
Vec2 findClosestDirection(const Simplex2& simplex, Vec2 v) noexcept {
  if (simplex.count == 2) {
    Vec2 a = simplex.vertices[0].support.w;
    Vec2 n = normalize(leftPerp(simplex.vertices[1].support.w - a));
    float side = dot(n, a);
    if (side < 0.0f) return -n;
    if (side > 0.0f) return n;
  }
  return normalize(v);
}

bool sameSupport(const SupportPoint& x, const SupportPoint& y) noexcept {
  return x.indexA == y.indexA && x.indexB == y.indexB;
}

// The EPA polytope of src/collision/epa2.cpp, in a vector (display only).
struct Polytope {
  std::vector<SupportPoint> vertices;
  std::vector<Vec2> normals;
  std::vector<float> distances;
  float size = 0.0f;

  int count() const { return static_cast<int>(vertices.size()); }

  void updateEdge(int i) {
    Vec2 a = vertices[i].w;
    Vec2 b = vertices[(i + 1) % count()].w;
    Vec2 e = b - a;
    float len = length(e);
    if (!(len > 0.0f)) {
      normals[i] = {};
      distances[i] = std::numeric_limits<float>::infinity();
      return;
    }
    normals[i] = (1.0f / len) * rightPerp(e);
    distances[i] = dot(normals[i], a);
  }

  int findNearestEdge(Vec2 c) const {
    int best = 0;
    for (int i = 1; i < count(); ++i) {
      if (distances[i] < distances[best]) best = i;
    }
    float tie = distances[best] + kEpaTieRelativeTolerance * size;
    float bestAlign = dot(normals[best], c);
    for (int i = 0; i < count(); ++i) {
      if (i == best || distances[i] > tie) continue;
      float align = dot(normals[i], c);
      if (align < bestAlign) {
        best = i;
        bestAlign = align;
      }
    }
    return best;
  }
};

}  // namespace

GjkTrace traceGjk(const ShapeProxy& a, const ShapeProxy& b, Transform aFromB) {
  GjkTrace trace;
  Simplex2 s;
  Vec2 c = transformPoint(aFromB, b.center()) - a.center();
  if (c == Vec2{}) c = {1.0f, 0.0f};
  s.vertices[0].support = supportMinkowski(a, b, aFromB, -c);
  s.count = 1;

  Simplex2 previous;
  Vec2 previousClosest;
  float previousVV = std::numeric_limits<float>::infinity();
  int unchangedSteps = 0;
  for (;;) {
    SimplexSolution solution = solveSimplex2(s);
    GjkStep step;
    step.simplex = s;
    step.closest = solution.closest;
    if (solution.holdsOrigin) {
      trace.steps.push_back(step);
      trace.closest = {};
      trace.status = GjkStatus::overlap;
      break;
    }
    Vec2 v = solution.closest;
    float vv = lengthSquared(v);
    float maxWW = 0.0f;
    for (int i = 0; i < s.count; ++i)
      maxWW = maxf(maxWW, lengthSquared(s.vertices[i].support.w));
    if (vv <= kGjkContactRelativeTolerance * kGjkContactRelativeTolerance * maxWW) {
      trace.steps.push_back(step);
      trace.closest = {};
      trace.status = GjkStatus::overlap;
      break;
    }
    if (vv == previousVV && ++unchangedSteps <= 2) {
      // As the library: an unchanged |v| goes on (the direction may still be improving).
    } else if (!(vv < previousVV)) {
      trace.steps.push_back(step);
      if (previous.count > 0) {
        s = previous;
        trace.closest = previousClosest;
      }
      trace.status = GjkStatus::stalled;
      break;
    }
    trace.closest = v;
    if (trace.iterations >= kGjkMaxIterations) {
      trace.steps.push_back(step);
      trace.status = GjkStatus::maxIterations;
      break;
    }
    previous = s;
    previousClosest = v;
    previousVV = vv;

    Vec2 dir = findClosestDirection(s, v);
    SupportPoint w = supportMinkowski(a, b, aFromB, -dir);
    ++trace.iterations;
    step.hasSupport = true;
    step.direction = dir;
    step.support = w;
    trace.steps.push_back(step);
    float vw = length(v) * dot(dir, w.w);
    bool repeated = false;
    for (int i = 0; i < s.count; ++i)
      repeated |= sameSupport(s.vertices[i].support, w);
    if (repeated) {
      trace.status = GjkStatus::repeatedSupport;
      break;
    }
    if (vw >= vv) {
      trace.status = GjkStatus::converged;
      break;
    }
    s.vertices[s.count].support = w;
    ++s.count;
  }
  trace.finalSimplex = s;
  if (trace.status != GjkStatus::overlap) {
    float core = length(trace.closest);
    float radii = a.radius() + b.radius();
    trace.distance = core > radii ? core - radii : 0.0f;
  }
  return trace;
}

EpaTrace traceEpa(const ShapeProxy& a, const ShapeProxy& b, Transform aFromB, const GjkTrace& gjk) {
  EpaTrace trace;
  trace.iterations = gjk.iterations;
  const float radii = a.radius() + b.radius();
  if (gjk.status != GjkStatus::overlap) {
    float core = length(gjk.closest);
    trace.status = core > radii ? EpaStatus::separated : EpaStatus::coresSeparated;
    trace.depth = core > radii ? 0.0f : radii - core;
    return trace;
  }
  const Vec2 c = transformPoint(aFromB, b.center()) - a.center();
  const Simplex2& s = gjk.finalSimplex;
  Polytope p;
  for (int i = 0; i < s.count; ++i) {
    p.vertices.push_back(s.vertices[i].support);
    p.size = maxf(p.size, length(s.vertices[i].support.w));
  }
  // The start triangle, grown as epa2.cpp's buildTriangle grows it.
  if (p.count() == 1) {
    const Vec2 axes[4] = {{1.0f, 0.0f}, {-1.0f, 0.0f}, {0.0f, 1.0f}, {0.0f, -1.0f}};
    for (Vec2 d : axes) {
      SupportPoint w = supportMinkowski(a, b, aFromB, d);
      ++trace.iterations;
      if (!sameSupport(w, p.vertices[0]) && !(w.w == p.vertices[0].w)) {
        p.vertices.push_back(w);
        p.size = maxf(p.size, length(w.w));
        break;
      }
    }
  }
  if (p.count() == 2) {
    Vec2 n = normalize(leftPerp(p.vertices[1].w - p.vertices[0].w));
    for (float sign : {1.0f, -1.0f}) {
      SupportPoint w = supportMinkowski(a, b, aFromB, sign * n);
      ++trace.iterations;
      if (sign * dot(n, w.w - p.vertices[0].w) > kEpaRelativeTolerance * p.size) {
        p.vertices.push_back(w);
        p.size = maxf(p.size, length(w.w));
        break;
      }
    }
  }
  if (p.count() < 3) {
    trace.status = EpaStatus::degenerate;
    trace.depth = radii;
    return trace;
  }
  trace.ran = true;
  if (cross(p.vertices[1].w - p.vertices[0].w, p.vertices[2].w - p.vertices[0].w) < 0.0f) {
    std::swap(p.vertices[1], p.vertices[2]);
  }
  p.normals.assign(3, Vec2{});
  p.distances.assign(3, 0.0f);
  for (int i = 0; i < 3; ++i)
    p.updateEdge(i);

  int edge = 0;
  trace.status = EpaStatus::maxIterations;
  for (;;) {
    edge = p.findNearestEdge(c);
    EpaStep step;
    step.polytope = p.vertices;
    step.nearestEdge = edge;
    step.normal = p.normals[edge];
    step.distance = p.distances[edge];
    if (p.count() >= kEpaMaxVertices) {
      trace.steps.push_back(step);
      break;
    }
    Vec2 n = p.normals[edge];
    SupportPoint w = supportMinkowski(a, b, aFromB, n);
    ++trace.iterations;
    step.hasSupport = true;
    step.support = w;
    trace.steps.push_back(step);
    if (sameSupport(w, p.vertices[edge]) || sameSupport(w, p.vertices[(edge + 1) % p.count()])) {
      trace.status = EpaStatus::repeatedSupport;
      break;
    }
    p.size = maxf(p.size, length(w.w));
    if (dot(n, w.w) - p.distances[edge] <= kEpaRelativeTolerance * p.size) {
      trace.status = EpaStatus::converged;
      break;
    }
    p.vertices.insert(p.vertices.begin() + edge + 1, w);
    p.normals.insert(p.normals.begin() + edge + 1, Vec2{});
    p.distances.insert(p.distances.begin() + edge + 1, 0.0f);
    p.updateEdge(edge);
    p.updateEdge(edge + 1);
  }
  trace.depth = maxf(p.distances[edge], 0.0f) + radii;
  return trace;
}

}  // namespace quack::web
