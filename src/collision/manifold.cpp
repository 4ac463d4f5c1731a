#include "quack/collision/manifold.hpp"

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <new>
#include <variant>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/core/assert.hpp"

namespace quack {
namespace {

// A convex core of `count` points (count 2 for capsules and segments: the two sides of
// the segment are its "edges", with normals n and -n) plus a radius. All in one frame.
struct PolyView {
  const Vec2* vertices;
  const Vec2* normals;
  int count;
  float radius;
};

int nextIndex(int i, int count) {
  return i + 1 == count ? 0 : i + 1;
}
int prevIndex(int i, int count) {
  return i == 0 ? count - 1 : i - 1;
}

// Feature ids: bit 16 says B's face was the reference; bit 17 marks a vertex-vertex or
// vertex-disk contact; bits 8-15 the reference feature; bits 0-7 the incident vertex.
constexpr std::uint32_t kFlipBit = kManifoldIdReferenceOnB;
constexpr std::uint32_t kVertexBit = 1u << 17;
constexpr std::uint32_t makeId(bool flip, bool vertex, int reference, int incident) {
  return (flip ? kFlipBit : 0u) | (vertex ? kVertexBit : 0u) |
         (static_cast<std::uint32_t>(reference) << 8) | static_cast<std::uint32_t>(incident);
}

// Adds a point given in A's frame; the normal is set by the caller.
void addPoint(Manifold& m, const Transform& worldFromA, const Transform& worldFromB, Vec2 pointInA,
              float separation, std::uint32_t id) {
  ManifoldPoint& p = m.points[m.pointCount++];
  p.point = transformPoint(worldFromA, pointInA);
  p.anchorA = p.point - worldFromA.p;
  p.anchorB = p.point - worldFromB.p;
  p.separation = separation;
  p.id = id;
}

struct EdgeSeparation {
  float separation;  // least signed distance of q's core from the edge's line
  int edge;          // edge of p
  int support;       // vertex of q that attains it, or kSupportLater
};

// EdgeSeparation::support not found yet: the first vertex of q with the least product with
// the edge's normal, detail::findFirstMaxDot(q, -n), is.
constexpr int kSupportLater = -1;

// The edge of p whose outward normal separates q most, by walking q. q is in p's frame.
//
// As the edge normals of p turn counter-clockwise, the vertex of q deepest against them
// (the support of q along -n) moves counter-clockwise too, so it is found by walking
// forward from the previous one: n + 2m dot products instead of n m (rotating calipers,
// Shamos 1978; the same monotonicity that makes the Minkowski sum of convex polygons a
// merge of their edge lists).
EdgeSeparation walkMaxSeparation(const PolyView& p, const PolyView& q) {
  const int m = q.count;
  Vec2 n = p.normals[0];
  int j = 0;
  float dj = dot(n, q.vertices[0]);
  for (int k = 1; k < m; ++k) {
    float dk = dot(n, q.vertices[k]);
    if (dk < dj) {
      j = k;
      dj = dk;
    }
  }
  EdgeSeparation best{dj - dot(n, p.vertices[0]), 0, j};
  for (int i = 1; i < p.count; ++i) {
    n = p.normals[i];
    dj = dot(n, q.vertices[j]);
    // Descend; the sequence is unimodal around a convex polygon, and m steps bound it.
    // Equal values are crossed: a two-point p turns its normal by exactly pi, which starts
    // the walk at q's maximum, where an edge of q square to n is a plateau.
    for (int step = 1; step < m; ++step) {
      int k = nextIndex(j, m);
      float dk = dot(n, q.vertices[k]);
      if (!(dk <= dj)) break;
      j = k;
      dj = dk;
    }
    float s = dj - dot(n, p.vertices[i]);
    if (s > best.separation) best = {s, i, j};
  }
  return best;
}

#if defined(__SSE2__)
// Polygons up to this many vertices take every edge against every vertex (n m products
// four at a time, no data-dependent branch) instead of the walk below. The walk's
// branches go at random places for random pairs, and their mispredictions cost more than
// the products (callgrind's branch simulation on bench/narrowphase's 8-gon pairs). Past 16
// vertices the products grow as n m and the walk wins.
constexpr int kAllPairsMaxVertices = 16;
static_assert(kAllPairsMaxVertices <= 16, "separationsOfGroups is instantiated for up to 4 groups");

// Four consecutive points (from v) as a column of x and a column of y.
void loadColumns(const Vec2* v, __m128& xs, __m128& ys) {
  __m128 lo = _mm_loadu_ps(&v[0].x);  // x0 y0 x1 y1
  __m128 hi = _mm_loadu_ps(&v[2].x);  // x2 y2 x3 y3
  xs = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));
  ys = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1));
}

// kGroups groups of four of p's normals (starting at starts[g]) against every vertex of
// q: the least of dot(n, q_j) minus dot(n, p_i), with the products formed as dot() forms
// them, so the values are the walk's. Vertex-major, so each vertex of q is broadcast once
// and the kGroups accumulators stay in registers.
template <int kGroups>
void separationsOfGroups(const PolyView& p, const int* starts, const PolyView& q,
                         __m128* separations) {
  __m128 nx[kGroups], ny[kGroups], least[kGroups];
  for (int g = 0; g < kGroups; ++g)
    loadColumns(p.normals + starts[g], nx[g], ny[g]);
  auto products = [&](int g, Vec2 v) {
    return _mm_add_ps(_mm_mul_ps(nx[g], _mm_set1_ps(v.x)), _mm_mul_ps(ny[g], _mm_set1_ps(v.y)));
  };
  for (int g = 0; g < kGroups; ++g)
    least[g] = products(g, q.vertices[0]);
  for (int j = 1; j < q.count; ++j) {
    for (int g = 0; g < kGroups; ++g)
      least[g] = _mm_min_ps(least[g], products(g, q.vertices[j]));
  }
  for (int g = 0; g < kGroups; ++g) {
    __m128 px, py;
    loadColumns(p.vertices + starts[g], px, py);
    separations[g] = _mm_sub_ps(least[g], _mm_add_ps(_mm_mul_ps(nx[g], px), _mm_mul_ps(ny[g], py)));
  }
}

// findMaxSeparation for 4 <= p.count <= kAllPairsMaxVertices: the same edge (the first
// attaining the largest separation); its support is kSupportLater, for which the caller takes
// the first vertex of q attaining the least product (the walk takes the last of a run of
// equal ones, which is the other end of an edge of q square to the normal: the incident
// edge chosen from either is that edge).
// allPairsMaxSeparation with the number of groups known at compile time, so that the
// groups stay in registers and the loops over them unroll.
template <int kGroups>
EdgeSeparation maxSeparationOfGroups(const PolyView& p, const int* starts, const PolyView& q) {
  __m128 groups[kGroups];
  separationsOfGroups<kGroups>(p, starts, q, groups);
  __m128 best = groups[0];
  for (int g = 1; g < kGroups; ++g)
    best = _mm_max_ps(best, groups[g]);
  best = _mm_max_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(2, 3, 0, 1)));
  best = _mm_max_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(1, 0, 3, 2)));
  std::uint32_t hits = 0;
  for (int g = 0; g < kGroups; ++g) {
    hits |= static_cast<std::uint32_t>(_mm_movemask_ps(_mm_cmpeq_ps(groups[g], best))) << starts[g];
  }
  // No hit only with NaN input (outside the preconditions): the walk answers then.
  if (hits == 0) return walkMaxSeparation(p, q);
  // The support vertex is left to the caller (kSupportLater), which needs it for the
  // reference face only: one search a query instead of two.
  return {_mm_cvtss_f32(best), std::countr_zero(hits), kSupportLater};
}

EdgeSeparation allPairsMaxSeparation(const PolyView& p, const PolyView& q) {
  // Groups of four normals; a count that is not a multiple of four ends with a group that
  // overlaps the one before, which changes neither the largest value nor its first index.
  const int last = p.count - 4;
  int starts[kAllPairsMaxVertices / 4];
  int groupCount = 0;
  for (int i = 0; i < last; i += 4)
    starts[groupCount++] = i;
  starts[groupCount++] = last;
  switch (groupCount) {
    case 1:
      return maxSeparationOfGroups<1>(p, starts, q);
    case 2:
      return maxSeparationOfGroups<2>(p, starts, q);
    case 3:
      return maxSeparationOfGroups<3>(p, starts, q);
    default:
      return maxSeparationOfGroups<4>(p, starts, q);
  }
}
#endif

// The edge of p whose outward normal separates q most. q is in p's frame.
EdgeSeparation findMaxSeparation(const PolyView& p, const PolyView& q) {
#if defined(__SSE2__)
  if (p.count >= 4 && p.count <= kAllPairsMaxVertices && q.count <= kAllPairsMaxVertices) {
    return allPairsMaxSeparation(p, q);
  }
#endif
  return walkMaxSeparation(p, q);
}

// Room for a core's points that is not filled first: a Vec2 array would be zeroed (Vec2's
// members have initialisers), which for two 64-point arrays costs more than the transform
// that then overwrites them.
struct Vec2Buffer {
  alignas(Vec2) std::byte bytes[kMaxPolygonVertices * sizeof(Vec2)];
  // A byte array implicitly creates the Vec2 objects that are then written (C++20).
  Vec2* data() noexcept { return std::launder(reinterpret_cast<Vec2*>(bytes)); }
};

// out[i] = transformPoint(xf, in[i]) (translate = true) or rotate(xf.q, in[i]), with
// the same arithmetic, two points per SSE register.
[[gnu::always_inline]] inline void transformArray(Transform xf, const Vec2* in, int count,
                                                  Vec2* out, bool translate) {
  int i = 0;
#if defined(__SSE2__)
  // rotate(q, v) = (c x - s y, s x + c y) = c (x, y) + (-s, s) (y, x): the same products and
  // sums as the scalar form (negation is exact and addition commutes).
  const __m128 c = _mm_set1_ps(xf.q.c);
  const __m128 s = _mm_setr_ps(-xf.q.s, xf.q.s, -xf.q.s, xf.q.s);
  const __m128 t = translate ? _mm_setr_ps(xf.p.x, xf.p.y, xf.p.x, xf.p.y) : _mm_setzero_ps();
  for (; i + 2 <= count; i += 2) {
    __m128 v = _mm_loadu_ps(&in[i].x);
    __m128 swapped = _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1));
    __m128 r = _mm_add_ps(_mm_mul_ps(c, v), _mm_mul_ps(s, swapped));
    // Adding zero would turn a rotated -0 into +0; only translate when asked.
    if (translate) r = _mm_add_ps(r, t);
    _mm_storeu_ps(&out[i].x, r);
  }
#endif
  for (; i < count; ++i)
    out[i] = translate ? transformPoint(xf, in[i]) : rotate(xf.q, in[i]);
}

void transformPoints(Transform xf, const Vec2* in, int count, Vec2* out) {
  transformArray(xf, in, count, out, true);
}
void rotateVectors(Rot q, const Vec2* in, int count, Vec2* out) {
  transformArray({Vec2{}, q}, in, count, out, false);
}

// Size of a core, for scale-aware tolerances.
float extentOf(const PolyView& p) {
  Vec2 lo = p.vertices[0], hi = p.vertices[0];
  for (int i = 1; i < p.count; ++i) {
    lo = minv(lo, p.vertices[i]);
    hi = maxv(hi, p.vertices[i]);
  }
  return maxf(hi.x - lo.x, hi.y - lo.y);
}

// A vertex-to-vertex direction replaces the face normal only when it makes the distance
// longer than the face separation by more than this fraction: equal means parallel faces.
constexpr float kVertexContactTolerance = 1e-4f;

struct SegmentClosest {
  Vec2 p1, p2;     // closest points on the first and second segment
  float f1, f2;    // their fractions along each segment, in [0, 1]
  float distance;  // |p2 - p1|
};

// Closest points of segments a1-a2 and b1-b2 (Ericson, RTCD sec. 5.1.9), with the end
// cases resolved by clamping so that a fraction is exactly 0 or 1 at a vertex.
SegmentClosest closestOnSegments(Vec2 a1, Vec2 a2, Vec2 b1, Vec2 b2) {
  Vec2 d1 = a2 - a1, d2 = b2 - b1, r = a1 - b1;
  float dd1 = dot(d1, d1), dd2 = dot(d2, d2), rd1 = dot(r, d1), rd2 = dot(r, d2);
  float f1 = 0.0f, f2 = 0.0f;
  float d12 = dot(d1, d2);
  float denominator = dd1 * dd2 - d12 * d12;
  // Parallel (or degenerate) segments: any pair of closest points will do; start at a1.
  if (denominator > 0.0f) f1 = clampf((d12 * rd2 - rd1 * dd2) / denominator, 0.0f, 1.0f);
  f2 = (d12 * f1 + rd2) / dd2;
  if (f2 < 0.0f) {
    f2 = 0.0f;
    f1 = clampf(-rd1 / dd1, 0.0f, 1.0f);
  } else if (f2 > 1.0f) {
    f2 = 1.0f;
    f1 = clampf((d12 - rd1) / dd1, 0.0f, 1.0f);
  }
  SegmentClosest out;
  out.p1 = a1 + f1 * d1;
  out.p2 = b1 + f2 * d2;
  out.f1 = f1;
  out.f2 = f2;
  out.distance = distance(out.p1, out.p2);
  return out;
}

// The polygon-style routine for any two cores with two or more points (polygons, capsules
// and segments). `a` is in A's frame, `bLocal` in B's frame.
// The transforms by reference: by value each comes in two vector registers that are taken
// apart again (about 30 moves a call).
Manifold collidePolygonal(const PolyView& a, const Transform& worldFromA, const PolyView& bLocal,
                          const Transform& worldFromB, float speculativeDistance) {
  // Work in A's frame: B's core is moved once, its normals only when A's faces did not
  // already separate the cores.
  Transform aFromB = invMul(worldFromA, worldFromB);
  Vec2Buffer bVertices, bNormals;
  transformPoints(aFromB, bLocal.vertices, bLocal.count, bVertices.data());
  const PolyView b{bVertices.data(), bNormals.data(), bLocal.count, bLocal.radius};
  const float radius = a.radius + b.radius;
  const float limit = speculativeDistance + radius;

  EdgeSeparation onA = findMaxSeparation(a, b);
  if (onA.separation > limit) return {};
  rotateVectors(aFromB.q, bLocal.normals, bLocal.count, bNormals.data());
  EdgeSeparation onB = findMaxSeparation(b, a);
  if (onB.separation > limit) return {};

  // Prefer A's face unless B's separates clearly more: the hysteresis keeps the reference
  // face, and so the ids, steady while two faces are nearly parallel. A tenth of the slop
  // for game-sized shapes, a thousandth of the size for tiny ones.
  bool flip = false;
  float gap = onB.separation - onA.separation;
  if (gap > 0.0f) {
    float tolerance = 0.1f * kLinearSlop;
    if (gap <= tolerance) tolerance = minf(tolerance, 1e-3f * minf(extentOf(a), extentOf(b)));
    flip = gap > tolerance;
  }
  const PolyView& ref = flip ? b : a;
  const PolyView& inc = flip ? a : b;
  const EdgeSeparation& axis = flip ? onB : onA;
  const int i1 = axis.edge;
  const int i2 = nextIndex(i1, ref.count);
  const Vec2 n = ref.normals[i1];
  // The incident edge is one of the two at the support vertex: the one facing n most.
  // The least dot(n, q_j) is the largest dot(-n, q_j), negated exactly.
  const int s = axis.support != kSupportLater
                    ? axis.support
                    : detail::findFirstMaxDot(inc.vertices, inc.count, -n);
  int j1 = dot(n, inc.normals[prevIndex(s, inc.count)]) < dot(n, inc.normals[s])
               ? prevIndex(s, inc.count)
               : s;
  int j2 = nextIndex(j1, inc.count);
  const Vec2 v11 = ref.vertices[i1], v12 = ref.vertices[i2];
  const Vec2 v21 = inc.vertices[j1], v22 = inc.vertices[j2];

  Manifold m;
  m.normal = rotate(worldFromA.q, flip ? -n : n);
  // One point between the closest points of the two cores, normal along them.
  auto addVertexContact = [&](const SegmentClosest& c, bool flipped, int refVertex, int incVertex) {
    Vec2 d = (1.0f / c.distance) * (c.p2 - c.p1);
    Vec2 mid = 0.5f * ((c.p1 + ref.radius * d) + (c.p2 - inc.radius * d));
    m.normal = rotate(worldFromA.q, flipped ? -d : d);
    addPoint(m, worldFromA, worldFromB, mid, c.distance - radius,
             makeId(flipped, true, refVertex, incVertex));
  };

  // Cores apart: when their closest features are two vertices, the face normal
  // understates the distance (rounded corners); use the vertex-to-vertex direction. Only
  // when that distance really exceeds the face separation: parallel faces also have
  // closest points at vertices, and there the face is right.
  if (axis.separation > 0.0f) {
    SegmentClosest c = closestOnSegments(v11, v12, v21, v22);
    bool refAtVertex = c.f1 == 0.0f || c.f1 == 1.0f;
    bool incAtVertex = c.f2 == 0.0f || c.f2 == 1.0f;
    if (refAtVertex && incAtVertex &&
        c.distance > (1.0f + kVertexContactTolerance) * axis.separation) {
      if (c.distance > limit) return {};
      addVertexContact(c, flip, c.f1 == 0.0f ? i1 : i2, c.f2 == 0.0f ? j1 : j2);
      return m;
    }
  }

  // Clip the incident edge to the strip over the reference face: with tangent t along
  // v11 -> v12, keep the part with 0 <= t.(x - v11) <= |v12 - v11|.
  const Vec2 tangent = leftPerp(n);
  const float faceLength = dot(v12 - v11, tangent);
  const float t1 = dot(v21 - v11, tangent);
  const float t2 = dot(v22 - v11, tangent);
  float sLo = 0.0f, sHi = 1.0f;  // fractions along v21 -> v22
  if (t1 != t2) {
    float sa = (0.0f - t1) / (t2 - t1);
    float sb = (faceLength - t1) / (t2 - t1);
    sLo = maxf(0.0f, minf(sa, sb));
    sHi = minf(1.0f, maxf(sa, sb));
  } else if (t1 < 0.0f || t1 > faceLength) {
    sLo = 1.0f;  // an edge square to the face and beside it: empty, handled below
    sHi = 0.0f;
  }
  if (sLo > sHi) {
    // The incident edge lies beside the reference face. Cores apart or touching: the
    // closest features decide, as above (collinear segments end to end land here).
    if (axis.separation >= 0.0f) {
      SegmentClosest c = closestOnSegments(v11, v12, v21, v22);
      if (c.distance > limit) return {};
      if (c.distance > 0.0f) {
        addVertexContact(c, flip, c.f1 < 0.5f ? i1 : i2, c.f2 < 0.5f ? j1 : j2);
        return m;
      }
    }
    // Cores overlapping at a corner of the reference shape: one point at the incident
    // vertex deepest along n.
    float d1 = dot(v21 - v11, n), d2 = dot(v22 - v11, n);
    Vec2 v = d1 <= d2 ? v21 : v22;
    float d = minf(d1, d2);
    if (d - radius > speculativeDistance) return {};
    addPoint(m, worldFromA, worldFromB, v + (0.5f * (ref.radius - inc.radius - d)) * n, d - radius,
             makeId(flip, false, i1, d1 <= d2 ? j1 : j2));
    return m;
  }
  const Vec2 clipped[2] = {lerp(v21, v22, sLo), lerp(v21, v22, sHi)};
  const int from[2] = {sLo < 1.0f ? j1 : j2, sHi > 0.0f ? j2 : j1};
  for (int k = 0; k < 2; ++k) {
    float d = dot(clipped[k] - v11, n);
    if (d - radius > speculativeDistance) continue;
    // Midway between the reference surface and the incident surface.
    Vec2 point = clipped[k] + (0.5f * (ref.radius - inc.radius - d)) * n;
    addPoint(m, worldFromA, worldFromB, point, d - radius, makeId(flip, false, i1, from[k]));
  }
  if (m.pointCount == 2 && m.points[0].id == m.points[1].id) {
    // Clipped to a single vertex (an edge square to the face): keep the deeper copy.
    if (m.points[1].separation < m.points[0].separation) m.points[0] = m.points[1];
    m.pointCount = 1;
  }
  return m;
}

// A core (polygon, capsule or segment, in A's frame) against a disk centred at `centerB`
// (B's frame) of radius `radiusB`.
Manifold collideCoreAndDisk(const PolyView& a, Transform worldFromA, Vec2 centerB, float radiusB,
                            Transform worldFromB, float speculativeDistance) {
  Vec2 c = invTransformPoint(worldFromA, transformPoint(worldFromB, centerB));
  const float radius = a.radius + radiusB;
  int edge = 0;
  float s = -std::numeric_limits<float>::max();
  for (int i = 0; i < a.count; ++i) {
    float si = dot(a.normals[i], c - a.vertices[i]);
    if (si > s) {
      s = si;
      edge = i;
    }
  }
  if (s - radius > speculativeDistance) return {};
  Vec2 v1 = a.vertices[edge], v2 = a.vertices[nextIndex(edge, a.count)];
  Vec2 normal = a.normals[edge];
  Vec2 closest = c - s * normal;  // on the face's line
  float dist = s;
  std::uint32_t id = makeId(false, false, edge, 0);
  // Outside the core beyond an end of the best face: the closest feature is that vertex
  // (for a convex core, the face of greatest separation borders the closest feature).
  if (s > 0.0f) {
    Vec2 vertex = v1;
    int vertexIndex = edge;
    bool atVertex = dot(c - v1, v2 - v1) < 0.0f;
    if (!atVertex && dot(c - v2, v1 - v2) < 0.0f) {
      vertex = v2;
      vertexIndex = nextIndex(edge, a.count);
      atVertex = true;
    }
    if (atVertex) {
      Vec2 d = c - vertex;
      dist = length(d);
      if (dist - radius > speculativeDistance) return {};
      normal = (1.0f / dist) * d;  // dist >= s > 0
      closest = vertex;
      id = makeId(false, true, vertexIndex, 0);
    }
  }
  Manifold m;
  m.normal = rotate(worldFromA.q, normal);
  Vec2 mid = 0.5f * ((closest + a.radius * normal) + (c - radiusB * normal));
  addPoint(m, worldFromA, worldFromB, mid, dist - radius, id);
  return m;
}

// The two-point core of a capsule or segment: its sides are the edges.
struct SegmentCore {
  Vec2 vertices[2];
  Vec2 normals[2];
  PolyView view(float radius) const { return {vertices, normals, 2, radius}; }
};

SegmentCore makeSegmentCore(Vec2 p1, Vec2 p2) {
  Vec2 n = normalize(rightPerp(p2 - p1));
  return {{p1, p2}, {n, -n}};
}

PolyView viewOf(const Polygon& p) {
  return {p.vertices, p.normals, p.count, p.radius};
}

void flipManifold(Manifold& m) {
  m.normal = -m.normal;
  for (int i = 0; i < m.pointCount; ++i) {
    Vec2 t = m.points[i].anchorA;
    m.points[i].anchorA = m.points[i].anchorB;
    m.points[i].anchorB = t;
  }
}

// The shape of type S that `g` holds; the table entry was chosen by the types, so the
// check is an assertion (std::get_if checks the index, std::get would throw).
template <class S>
const S& held(const ShapeGeometry& g) noexcept {
  const S* s = std::get_if<S>(&g);
  QUACK_ASSERT(s != nullptr);
  return *s;
}

template <class A, class B,
          Manifold (*Fn)(const A&, Transform, const B&, Transform, float) noexcept>
Manifold callDirect(const ShapeGeometry& a, Transform worldFromA, const ShapeGeometry& b,
                    Transform worldFromB, float speculativeDistance) noexcept {
  return Fn(held<A>(a), worldFromA, held<B>(b), worldFromB, speculativeDistance);
}

// B-versus-A through the A-versus-B routine: same points and ids, normal flipped.
template <class A, class B,
          Manifold (*Fn)(const A&, Transform, const B&, Transform, float) noexcept>
Manifold callFlipped(const ShapeGeometry& b, Transform worldFromB, const ShapeGeometry& a,
                     Transform worldFromA, float speculativeDistance) noexcept {
  Manifold m = Fn(held<A>(a), worldFromA, held<B>(b), worldFromB, speculativeDistance);
  flipManifold(m);
  return m;
}

// Indexed [type of A][type of B] in ShapeType order: circle, capsule, segment, polygon.
constexpr ManifoldFn kManifoldTable[4][4] = {
    {callDirect<Circle, Circle, collideCircles>,
     callFlipped<Capsule, Circle, collideCapsuleAndCircle>,
     callFlipped<Segment, Circle, collideSegmentAndCircle>,
     callFlipped<Polygon, Circle, collidePolygonAndCircle>},
    {callDirect<Capsule, Circle, collideCapsuleAndCircle>,
     callDirect<Capsule, Capsule, collideCapsules>,
     callFlipped<Segment, Capsule, collideSegmentAndCapsule>,
     callFlipped<Polygon, Capsule, collidePolygonAndCapsule>},
    {callDirect<Segment, Circle, collideSegmentAndCircle>,
     callDirect<Segment, Capsule, collideSegmentAndCapsule>,
     callDirect<Segment, Segment, collideSegments>,
     callFlipped<Polygon, Segment, collidePolygonAndSegment>},
    {callDirect<Polygon, Circle, collidePolygonAndCircle>,
     callDirect<Polygon, Capsule, collidePolygonAndCapsule>,
     callDirect<Polygon, Segment, collidePolygonAndSegment>,
     callDirect<Polygon, Polygon, collidePolygons>},
};

}  // namespace

Manifold collideCircles(const Circle& a, Transform worldFromA, const Circle& b,
                        Transform worldFromB, float speculativeDistance) noexcept {
  Vec2 ca = transformPoint(worldFromA, a.center);
  Vec2 cb = transformPoint(worldFromB, b.center);
  Vec2 d = cb - ca;
  float dist = length(d);
  float radius = a.radius + b.radius;
  if (dist - radius > speculativeDistance) return {};
  // Coincident centres have no direction between them: use A's x axis (documented).
  Vec2 normal = dist > 0.0f ? (1.0f / dist) * d : rotate(worldFromA.q, Vec2{1.0f, 0.0f});
  Manifold m;
  m.normal = normal;
  ManifoldPoint& p = m.points[m.pointCount++];
  p.point = 0.5f * ((ca + a.radius * normal) + (cb - b.radius * normal));
  p.anchorA = p.point - worldFromA.p;
  p.anchorB = p.point - worldFromB.p;
  p.separation = dist - radius;
  p.id = 0;
  return m;
}

Manifold collideCapsuleAndCircle(const Capsule& a, Transform worldFromA, const Circle& b,
                                 Transform worldFromB, float speculativeDistance) noexcept {
  SegmentCore core = makeSegmentCore(a.p1, a.p2);
  return collideCoreAndDisk(core.view(a.radius), worldFromA, b.center, b.radius, worldFromB,
                            speculativeDistance);
}

Manifold collideSegmentAndCircle(const Segment& a, Transform worldFromA, const Circle& b,
                                 Transform worldFromB, float speculativeDistance) noexcept {
  SegmentCore core = makeSegmentCore(a.p1, a.p2);
  return collideCoreAndDisk(core.view(0.0f), worldFromA, b.center, b.radius, worldFromB,
                            speculativeDistance);
}

Manifold collidePolygonAndCircle(const Polygon& a, Transform worldFromA, const Circle& b,
                                 Transform worldFromB, float speculativeDistance) noexcept {
  return collideCoreAndDisk(viewOf(a), worldFromA, b.center, b.radius, worldFromB,
                            speculativeDistance);
}

Manifold collideCapsules(const Capsule& a, Transform worldFromA, const Capsule& b,
                         Transform worldFromB, float speculativeDistance) noexcept {
  SegmentCore ca = makeSegmentCore(a.p1, a.p2), cb = makeSegmentCore(b.p1, b.p2);
  return collidePolygonal(ca.view(a.radius), worldFromA, cb.view(b.radius), worldFromB,
                          speculativeDistance);
}

Manifold collideSegmentAndCapsule(const Segment& a, Transform worldFromA, const Capsule& b,
                                  Transform worldFromB, float speculativeDistance) noexcept {
  SegmentCore ca = makeSegmentCore(a.p1, a.p2), cb = makeSegmentCore(b.p1, b.p2);
  return collidePolygonal(ca.view(0.0f), worldFromA, cb.view(b.radius), worldFromB,
                          speculativeDistance);
}

Manifold collideSegments(const Segment& a, Transform worldFromA, const Segment& b,
                         Transform worldFromB, float speculativeDistance) noexcept {
  SegmentCore ca = makeSegmentCore(a.p1, a.p2), cb = makeSegmentCore(b.p1, b.p2);
  return collidePolygonal(ca.view(0.0f), worldFromA, cb.view(0.0f), worldFromB,
                          speculativeDistance);
}

Manifold collidePolygonAndCapsule(const Polygon& a, Transform worldFromA, const Capsule& b,
                                  Transform worldFromB, float speculativeDistance) noexcept {
  SegmentCore cb = makeSegmentCore(b.p1, b.p2);
  return collidePolygonal(viewOf(a), worldFromA, cb.view(b.radius), worldFromB,
                          speculativeDistance);
}

Manifold collidePolygonAndSegment(const Polygon& a, Transform worldFromA, const Segment& b,
                                  Transform worldFromB, float speculativeDistance) noexcept {
  SegmentCore cb = makeSegmentCore(b.p1, b.p2);
  return collidePolygonal(viewOf(a), worldFromA, cb.view(0.0f), worldFromB, speculativeDistance);
}

Manifold collidePolygons(const Polygon& a, Transform worldFromA, const Polygon& b,
                         Transform worldFromB, float speculativeDistance) noexcept {
  return collidePolygonal(viewOf(a), worldFromA, viewOf(b), worldFromB, speculativeDistance);
}

ManifoldFn findManifoldFn(ShapeType a, ShapeType b) noexcept {
  return kManifoldTable[static_cast<int>(a)][static_cast<int>(b)];
}

Manifold collide(const ShapeGeometry& a, Transform worldFromA, const ShapeGeometry& b,
                 Transform worldFromB, float speculativeDistance) noexcept {
  return findManifoldFn(shapeType(a), shapeType(b))(a, worldFromA, b, worldFromB,
                                                    speculativeDistance);
}

Manifold collideGeneral(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                        Transform worldFromB, float speculativeDistance) noexcept {
  GjkCache cache;
  DistanceOutput d = computeDistance(a, worldFromA, b, worldFromB, &cache);
  Manifold m;
  if (d.distance > speculativeDistance) return m;
  Vec2 point;
  float separation;
  if (d.distance > 0.0f) {
    m.normal = d.normal;
    point = 0.5f * (d.pointA + d.pointB);
    separation = d.distance;
  } else {
    PenetrationOutput p = computePenetration(a, worldFromA, b, worldFromB, &cache);
    m.normal = p.normal;
    point = 0.5f * (p.pointA + p.pointB);
    separation = -p.depth;
  }
  ManifoldPoint& mp = m.points[m.pointCount++];
  mp.point = point;
  mp.anchorA = point - worldFromA.p;
  mp.anchorB = point - worldFromB.p;
  mp.separation = separation;
  mp.id = 0;
  return m;
}

const ManifoldPoint& deepestPoint(const Manifold& manifold) noexcept {
  QUACK_ASSERT(manifold.pointCount > 0);
  const ManifoldPoint* best = &manifold.points[0];
  for (int i = 1; i < manifold.pointCount; ++i) {
    if (manifold.points[i].separation < best->separation) best = &manifold.points[i];
  }
  return *best;
}

}  // namespace quack
