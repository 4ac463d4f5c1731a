#pragma once
// Independent oracles for the 3D narrow phase, in double precision:
//  - bruteCoreDistance: the distance between two disjoint convex cores as the least
//    distance over every pair of features (vertex-vertex, vertex-edge, vertex-triangle,
//    edge-edge, both ways), the closest points of two disjoint polytopes lying on such a
//    pair. Exact up to double rounding; needs no GJK, no hull of the difference.
//  - minkowskiDepth (qhull, when present): the hull of every vertex difference b - a; the
//    origin is inside it exactly when the cores overlap, and then the core penetration
//    depth is the least distance from the origin to its facet planes.
// Random 3D test shapes (sphere, capsule, triangle, box, hull) live here too.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "quack/collision/proxy3.hpp"

#if QUACK_HAVE_QHULL
extern "C" {
#include <libqhull_r/qhull_ra.h>
}
#endif

namespace quack::testing3 {

struct D3 {
  double x = 0, y = 0, z = 0;
};
inline D3 operator-(D3 a, D3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline D3 operator+(D3 a, D3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline D3 operator*(double s, D3 a) {
  return {s * a.x, s * a.y, s * a.z};
}
inline double dotD(D3 a, D3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline D3 crossD(D3 a, D3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double lenD(D3 a) {
  return std::sqrt(dotD(a, a));
}
inline D3 toD(Vec3 v) {
  return {v.x, v.y, v.z};
}

// Rotation of v by q in double (q's float components taken exactly, renormalised).
inline D3 rotateD(Quat q, D3 v) {
  double n =
      std::sqrt(double(q.x) * q.x + double(q.y) * q.y + double(q.z) * q.z + double(q.w) * q.w);
  D3 u{q.x / n, q.y / n, q.z / n};
  double w = q.w / n;
  D3 t = 2.0 * crossD(u, v);
  return v + w * t + crossD(u, t);
}
inline D3 transformD(Transform3 t, Vec3 p) {
  return rotateD(t.q, toD(p)) + toD(t.p);
}

// Closest point on segment ab to p.
inline D3 closestOnSegment(D3 p, D3 a, D3 b) {
  D3 ab = b - a;
  double l2 = dotD(ab, ab);
  double t = l2 > 0 ? std::clamp(dotD(p - a, ab) / l2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}
// Closest point on triangle abc to p (Ericson 5.1.5).
inline D3 closestOnTriangle(D3 p, D3 a, D3 b, D3 c) {
  D3 ab = b - a, ac = c - a, ap = p - a;
  double d1 = dotD(ab, ap), d2 = dotD(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  D3 bp = p - b;
  double d3 = dotD(ab, bp), d4 = dotD(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  D3 cp = p - c;
  double d5 = dotD(ab, cp), d6 = dotD(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  double sum = va + vb + vc;
  if (!(sum > 0)) return closestOnSegment(p, a, b);
  return a + (vb / sum) * ab + (vc / sum) * ac;
}
// Distance between segments p1q1 and p2q2 (Ericson 5.1.9), with the degenerate cases.
inline double segmentSegmentDistance(D3 p1, D3 q1, D3 p2, D3 q2) {
  D3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  double a = dotD(d1, d1), e = dotD(d2, d2), f = dotD(d2, r);
  double s = 0, t = 0;
  if (a <= 0 && e <= 0) return lenD(r);
  if (a <= 0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    double c = dotD(d1, r);
    if (e <= 0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      double b = dotD(d1, d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return lenD((p1 + s * d1) - (p2 + t * d2));
}

// A convex core as features, world frame, double.
struct Features {
  std::vector<D3> v;
  std::vector<std::pair<int, int>> e;
  std::vector<std::array<int, 3>> t;
  double radius = 0;
};

// Least feature-pair distance: the core distance when the cores are disjoint.
inline double bruteCoreDistance(const Features& A, const Features& B) {
  double best = 1e300;
  auto pointTo = [&](D3 p, const Features& F) {
    for (D3 q : F.v)
      best = std::min(best, lenD(p - q));
    for (auto [i, j] : F.e)
      best = std::min(best, lenD(p - closestOnSegment(p, F.v[i], F.v[j])));
    for (auto [i, j, k] : F.t)
      best = std::min(best, lenD(p - closestOnTriangle(p, F.v[i], F.v[j], F.v[k])));
  };
  for (D3 p : A.v)
    pointTo(p, B);
  for (D3 p : B.v)
    pointTo(p, A);
  for (auto [i, j] : A.e)
    for (auto [k, l] : B.e)
      best = std::min(best, segmentSegmentDistance(A.v[i], A.v[j], B.v[k], B.v[l]));
  return best;
}

// The Minkowski difference's answer: whether the origin is strictly inside the hull of all
// b - a, and if so the least distance to a facet plane (the core depth).
struct MinkowskiAnswer {
  bool ok = false;  // qhull built a full-dimensional hull
  bool inside = false;
  double depth = 0;  // least facet distance when inside; minus the largest when outside
};

#if QUACK_HAVE_QHULL
inline MinkowskiAnswer minkowskiDepth(const Features& A, const Features& B) {
  std::vector<coordT> coords;
  for (D3 b : B.v)
    for (D3 a : A.v) {
      D3 d = b - a;
      coords.push_back(d.x);
      coords.push_back(d.y);
      coords.push_back(d.z);
    }
  MinkowskiAnswer out;
  qhT qhStorage;
  qhT* qh = &qhStorage;
  qh_zero(qh, stderr);
  char flags[] = "qhull Qt";
  FILE* quiet = fopen("/dev/null", "w");
  int code = qh_new_qhull(qh, 3, static_cast<int>(coords.size() / 3), coords.data(), False, flags,
                          nullptr, quiet);
  if (code == 0) {
    out.ok = true;
    double least = 1e300, most = -1e300;
    facetT* facet;
    FORALLfacets {
      // Plane: normal . x + offset = 0, outward normal; the origin's signed distance is offset.
      least = std::min(least, -facet->offset);
      most = std::max(most, facet->offset);
    }
    out.inside = least > 0;
    out.depth = out.inside ? least : -most;
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong, totlong;
  qh_memfreeshort(qh, &curlong, &totlong);
  if (quiet) fclose(quiet);
  return out;
}
#endif

// How many times the random-pair loops run their default count: QUACK_TEST_SCALE (1 to
// 1000, default 1). The ctest entry collision3_slow (label `slow`) runs them at 10.
inline int testScale() {
  const char* text = std::getenv("QUACK_TEST_SCALE");
  int scale = text != nullptr ? std::atoi(text) : 1;
  return std::clamp(scale, 1, 1000);
}

// A 3D test shape of any kind.
enum class Kind3 { sphere, capsule, triangle, box, hull };
inline const char* name(Kind3 k) {
  switch (k) {
    case Kind3::sphere:
      return "sphere";
    case Kind3::capsule:
      return "capsule";
    case Kind3::triangle:
      return "triangle";
    case Kind3::box:
      return "box";
    case Kind3::hull:
      return "hull";
  }
  return "?";
}

struct Shape3 {
  Kind3 kind = Kind3::sphere;
  Sphere sphere;
  Capsule3 capsule;
  Triangle3 triangle;
  Hull3 hull;

  ShapeProxy3 proxy() const {
    switch (kind) {
      case Kind3::sphere:
        return makeProxy(sphere);
      case Kind3::capsule:
        return makeProxy(capsule);
      case Kind3::triangle:
        return makeProxy(triangle);
      default:
        return makeProxy(hull);
    }
  }
  Features features(Transform3 t) const {
    Features f;
    switch (kind) {
      case Kind3::sphere:
        f.v = {transformD(t, sphere.center)};
        f.radius = sphere.radius;
        break;
      case Kind3::capsule:
        f.v = {transformD(t, capsule.p1), transformD(t, capsule.p2)};
        f.e = {{0, 1}};
        f.radius = capsule.radius;
        break;
      case Kind3::triangle:
        f.v = {transformD(t, triangle.v[0]), transformD(t, triangle.v[1]),
               transformD(t, triangle.v[2])};
        f.e = {{0, 1}, {1, 2}, {2, 0}};
        f.t = {{0, 1, 2}};
        break;
      default:
        f.radius = hull.radius;
        for (int i = 0; i < hull.vertexCount; ++i)
          f.v.push_back(transformD(t, hull.vertices[i]));
        for (int i = 0; i < hull.edgeCount; ++i)
          f.e.push_back({hull.edges[i].v0, hull.edges[i].v1});
        for (int k = 0; k < hull.faceCount; ++k) {
          const HullFace3& face = hull.faces[k];
          for (int j = 1; j + 1 < face.count; ++j) {
            f.t.push_back({hull.faceVertices[face.first], hull.faceVertices[face.first + j],
                           hull.faceVertices[face.first + j + 1]});
          }
        }
        break;
    }
    return f;
  }
  // Largest distance of a core point from the shape-frame origin plus the radius.
  float extent() const {
    ShapeProxy3 p = proxy();
    float e = 0;
    for (int i = 0; i < p.count(); ++i)
      e = std::max(e, length(p.points()[i]));
    return e + p.radius();
  }
};

inline float uni(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}
inline Quat randomQuat(std::mt19937& rng) {
  std::normal_distribution<float> n(0, 1);
  return normalize(Quat{n(rng), n(rng), n(rng), n(rng)});
}
inline Vec3 randomVec(std::mt19937& rng, float s) {
  return {uni(rng, -s, s), uni(rng, -s, s), uni(rng, -s, s)};
}

// A random shape of `kind` about the origin, size about `size`. Hulls have 4 to maxHull
// vertices (points in a box, on an ellipsoid, or a flat sliver).
inline Shape3 randomShape3(std::mt19937& rng, Kind3 kind, float size, int maxHull = 16) {
  Shape3 s;
  s.kind = kind;
  switch (kind) {
    case Kind3::sphere:
      s.sphere = makeSphere(randomVec(rng, 0.2f * size), size * uni(rng, 0.2f, 1.0f)).value();
      break;
    case Kind3::capsule: {
      Vec3 d = size * uni(rng, 0.2f, 1.0f) * normalize(randomVec(rng, 1) + Vec3{0, 0, 1e-3f});
      s.capsule = makeCapsule3(-d, d, size * uni(rng, 0.05f, 0.5f)).value();
      break;
    }
    case Kind3::triangle:
      while (true) {
        Result<Triangle3> t =
            makeTriangle3(randomVec(rng, size), randomVec(rng, size), randomVec(rng, size));
        if (t.ok() && length(cross(t->v[1] - t->v[0], t->v[2] - t->v[0])) > 0.05f * size * size) {
          s.triangle = *t;
          break;
        }
      }
      break;
    case Kind3::box:
      s.hull = makeBox3({size * uni(rng, 0.1f, 1.0f), size * uni(rng, 0.1f, 1.0f),
                         size * uni(rng, 0.1f, 1.0f)})
                   .value();
      break;
    case Kind3::hull:
      while (true) {
        int n = std::uniform_int_distribution<int>(4, maxHull)(rng);
        int style = std::uniform_int_distribution<int>(0, 2)(rng);
        Vec3 axes{size * uni(rng, 0.3f, 1.0f), size * uni(rng, 0.3f, 1.0f),
                  size * uni(rng, 0.3f, 1.0f)};
        if (style == 2) axes.z = size * uni(rng, 0.01f, 0.05f);  // sliver
        std::vector<Vec3> pts;
        std::normal_distribution<float> g(0, 1);
        for (int i = 0; i < n; ++i) {
          Vec3 p = style == 1 ? normalize(Vec3{g(rng), g(rng), g(rng)}) : randomVec(rng, 1);
          pts.push_back({p.x * axes.x, p.y * axes.y, p.z * axes.z});
        }
        Result<Hull3> h = makeHull3(pts);
        if (h.ok()) {
          s.hull = *h;
          break;
        }
      }
      break;
  }
  return s;
}

inline std::string describe(const Shape3& s) {
  std::string out = name(s.kind);
  ShapeProxy3 p = s.proxy();
  char buf[128];
  std::snprintf(buf, sizeof buf, " r=%.9g:", double(p.radius()));
  out += buf;
  for (int i = 0; i < p.count(); ++i) {
    std::snprintf(buf, sizeof buf, " (%.9g,%.9g,%.9g)", double(p.points()[i].x),
                  double(p.points()[i].y), double(p.points()[i].z));
    out += buf;
  }
  return out;
}

}  // namespace quack::testing3
