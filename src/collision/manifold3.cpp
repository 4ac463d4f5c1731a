// 3D contact manifolds (see manifold3.hpp).

#include "quack/collision/manifold3.hpp"

#include "manifold3_internal.hpp"

#include <cmath>
#include <limits>
#include <variant>

#include "quack/collision/epa3.hpp"
#include "quack/collision/gjk3.hpp"
#include "quack/collision/sat3.hpp"

namespace quack {
namespace {

// A clip whose deepest point is above SAT's separation by more than this fraction of the
// reference hull's size has lost SAT's support vertex (rounding of the clipped points is
// about 1e-7 of the size; a lost vertex is a real feature away).
constexpr float kClipLostSupportRelative = 1e-5f;

// Capacity of the clipping buffers: an incident face of at most 64 vertices clipped by at
// most 64 side planes gains at most one vertex per plane.
constexpr int kClipCapacity = 2 * kMaxHullVertices3 + 2;

// Room for N values of T, left uninitialised: T's zeroing default members would cost a
// memset of the whole buffer (about 10 kB for the clipping's three) on every call. Every
// element is assigned before it is read.
template <class T, int N>
union Uninitialized {
  Uninitialized() noexcept {}
  T items[N];
};

struct ClipVertex {
  Vec3 p;
  std::uint32_t id = 0;      // the point's feature id (without the reference face)
  std::uint32_t edgeId = 0;  // the id of the polygon edge leaving this vertex
};

ManifoldPoint3 makePoint(Vec3 point, float separation, std::uint32_t id, Transform3 worldFromA,
                         Transform3 worldFromB) noexcept {
  ManifoldPoint3 mp;
  mp.point = point;
  mp.anchorA = point - worldFromA.p;
  mp.anchorB = point - worldFromB.p;
  mp.separation = separation;
  mp.id = id;
  return mp;
}

// Keeps at most four of `count` points: the deepest, the furthest from it, the one making
// the largest triangle with those two, and the one furthest outside that triangle (largest
// area added). `normal` orients the areas.
int reduceToFour(ManifoldPoint3* pts, int count, Vec3 normal) noexcept {
  if (count <= kMaxManifoldPoints3) return count;
  int i0 = 0;
  for (int i = 1; i < count; ++i)
    if (pts[i].separation < pts[i0].separation) i0 = i;
  int i1 = -1;
  float best = -1.0f;
  for (int i = 0; i < count; ++i) {
    float d = distanceSquared(pts[i].point, pts[i0].point);
    if (i != i0 && d > best) {
      best = d;
      i1 = i;
    }
  }
  int i2 = -1;
  float bestArea = -1.0f;
  for (int i = 0; i < count; ++i) {
    if (i == i0 || i == i1) continue;
    float area =
        absf(dot(cross(pts[i1].point - pts[i0].point, pts[i].point - pts[i0].point), normal));
    if (area > bestArea) {
      bestArea = area;
      i2 = i;
    }
  }
  // Orient the triangle counter-clockwise about the normal, then take the point with the
  // most negative area against one of its edges (furthest outside).
  if (dot(cross(pts[i1].point - pts[i0].point, pts[i2].point - pts[i0].point), normal) < 0.0f) {
    int t = i1;
    i1 = i2;
    i2 = t;
  }
  const int tri[3] = {i0, i1, i2};
  int i3 = -1;
  float most = 0.0f;
  for (int i = 0; i < count; ++i) {
    if (i == i0 || i == i1 || i == i2) continue;
    for (int e = 0; e < 3; ++e) {
      Vec3 u = pts[tri[e]].point, v = pts[tri[(e + 1) % 3]].point;
      float area = dot(cross(v - u, pts[i].point - u), normal);
      if (area < most) {
        most = area;
        i3 = i;
      }
    }
  }
  ManifoldPoint3 kept[4] = {pts[i0], pts[i1], pts[i2], {}};
  int n = 3;
  if (i3 >= 0) kept[n++] = pts[i3];
  for (int i = 0; i < n; ++i)
    pts[i] = kept[i];
  return n;
}

// A hull's core, its radius left out (collideHulls adds it).
ShapeProxy3 coreProxy(const Hull3& hull) noexcept {
  return ShapeProxy3::fromPoints(hull.vertices, hull.vertexCount, 0.0f, hull.centroid);
}

// Closest points of segments p1q1 and p2q2 (Ericson 5.1.9).
void closestSegmentPoints(Vec3 p1, Vec3 q1, Vec3 p2, Vec3 q2, Vec3& c1, Vec3& c2) noexcept {
  Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  float a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  float s = 0.0f, t = 0.0f;
  float c = dot(d1, r);
  float b = dot(d1, d2), denom = a * e - b * b;
  s = denom > 0.0f ? clampf((b * f - c * e) / denom, 0.0f, 1.0f) : 0.0f;
  t = (b * s + f) / e;
  if (t < 0.0f) {
    t = 0.0f;
    s = clampf(-c / a, 0.0f, 1.0f);
  } else if (t > 1.0f) {
    t = 1.0f;
    s = clampf((b - c) / a, 0.0f, 1.0f);
  }
  c1 = p1 + s * d1;
  c2 = p2 + t * d2;
}

}  // namespace

Manifold3 collideGeneral(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                         Transform3 worldFromB, float speculativeDistance) noexcept {
  Manifold3 m;
  DistanceOutput3 d = computeDistance(a, worldFromA, b, worldFromB);
  if (d.distance > speculativeDistance) return m;
  if (d.distance > 0.0f) {
    m.normal = d.normal;
    m.points[0] = makePoint(0.5f * (d.pointA + d.pointB), d.distance, 0, worldFromA, worldFromB);
  } else {
    PenetrationOutput3 p = computePenetration(a, worldFromA, b, worldFromB);
    m.normal = p.normal;
    m.points[0] = makePoint(0.5f * (p.pointA + p.pointB), -p.depth, 0, worldFromA, worldFromB);
  }
  m.pointCount = 1;
  return m;
}

Manifold3 collideSpheres(const Sphere& a, Transform3 worldFromA, const Sphere& b,
                         Transform3 worldFromB, float speculativeDistance) noexcept {
  return collideGeneral(makeProxy(a), worldFromA, makeProxy(b), worldFromB, speculativeDistance);
}

Manifold3 collideCapsuleAndSphere(const Capsule3& a, Transform3 worldFromA, const Sphere& b,
                                  Transform3 worldFromB, float speculativeDistance) noexcept {
  return collideGeneral(makeProxy(a), worldFromA, makeProxy(b), worldFromB, speculativeDistance);
}

Manifold3 collideHullAndSphere(const Hull3& a, Transform3 worldFromA, const Sphere& b,
                               Transform3 worldFromB, float speculativeDistance) noexcept {
  return collideGeneral(makeProxy(a), worldFromA, makeProxy(b), worldFromB, speculativeDistance);
}

Manifold3 collideCapsules(const Capsule3& a, Transform3 worldFromA, const Capsule3& b,
                          Transform3 worldFromB, float speculativeDistance) noexcept {
  Manifold3 m =
      collideGeneral(makeProxy(a), worldFromA, makeProxy(b), worldFromB, speculativeDistance);
  if (m.pointCount == 0) return m;
  // In A's frame: B's segment, A's axis.
  Transform3 aFromB = invMul(worldFromA, worldFromB);
  Vec3 b1 = transformPoint(aFromB, b.p1), b2 = transformPoint(aFromB, b.p2);
  Vec3 axisA = a.p2 - a.p1;
  float lenA = length(axisA);
  Vec3 uA = (1.0f / lenA) * axisA;
  Vec3 n = invRotate(worldFromA.q, m.normal);
  // Parallel enough: the ends' heights along the normal differ by less than the slop.
  float t1 = dot(b1 - a.p1, uA), t2 = dot(b2 - a.p1, uA);
  if (absf(dot(b2 - b1, n)) >= kLinearSlop || absf(t2 - t1) <= 0.0f) return m;
  float lo = maxf(minf(t1, t2), 0.0f), hi = minf(maxf(t1, t2), lenA);
  if (hi - lo <= kLinearSlop) return m;
  // And parallel: across the common stretch B drifts sideways from A's axis by less than
  // the slop (crossed segments both lie across the normal, so the height test alone passes).
  Vec3 uB = normalize(b2 - b1);
  if (length(cross(uA, uB)) * (hi - lo) >= kLinearSlop) return m;
  Manifold3 two;
  two.normal = m.normal;
  const float ts[2] = {lo, hi};
  for (int k = 0; k < 2; ++k) {
    float s = (ts[k] - t1) / (t2 - t1);
    Vec3 pb = b1 + s * (b2 - b1);
    Vec3 pa = a.p1 + ts[k] * uA;
    float sep = dot(pb - pa, n) - a.radius - b.radius;
    if (sep > speculativeDistance) continue;
    Vec3 mid = 0.5f * ((pa + a.radius * n) + (pb - b.radius * n));
    two.points[two.pointCount++] = makePoint(transformPoint(worldFromA, mid), sep,
                                             static_cast<std::uint32_t>(k), worldFromA, worldFromB);
  }
  return two.pointCount == 2 ? two : m;
}

Manifold3 collideHullAndCapsule(const Hull3& a, Transform3 worldFromA, const Capsule3& b,
                                Transform3 worldFromB, float speculativeDistance) noexcept {
  Manifold3 m =
      collideGeneral(makeProxy(a), worldFromA, makeProxy(b), worldFromB, speculativeDistance);
  if (m.pointCount == 0) return m;
  Transform3 aFromB = invMul(worldFromA, worldFromB);
  Vec3 n = invRotate(worldFromA.q, m.normal);
  int face = 0;
  for (int f = 1; f < a.faceCount; ++f)
    if (dot(a.faces[f].normal, n) > dot(a.faces[face].normal, n)) face = f;
  const HullFace3& hf = a.faces[face];
  Vec3 p[2] = {transformPoint(aFromB, b.p1), transformPoint(aFromB, b.p2)};
  if (absf(dot(hf.normal, p[1] - p[0])) >= kLinearSlop) return m;
  // Clip the segment to the face's side planes.
  float lo = 0.0f, hi = 1.0f;
  Vec3 d = p[1] - p[0];
  for (int k = 0; k < hf.count; ++k) {
    Vec3 v0 = a.vertices[a.faceVertices[hf.first + k]];
    Vec3 v1 = a.vertices[a.faceVertices[hf.first + (k + 1) % hf.count]];
    Vec3 side = cross(v1 - v0, hf.normal);
    float num = dot(side, v0 - p[0]), den = dot(side, d);
    if (den == 0.0f) {
      if (num < 0.0f) return m;
      continue;
    }
    float t = num / den;
    if (den > 0.0f)
      hi = minf(hi, t);
    else
      lo = maxf(lo, t);
  }
  if (hi - lo <= 0.0f || (hi - lo) * length(d) <= kLinearSlop) return m;
  Manifold3 two;
  two.normal = transformVector(worldFromA, hf.normal);
  const float ts[2] = {lo, hi};
  for (int k = 0; k < 2; ++k) {
    Vec3 q = p[0] + ts[k] * d;
    float sep = dot(hf.normal, q) - hf.offset - a.radius - b.radius;
    if (sep > speculativeDistance) continue;
    Vec3 mid = q - (b.radius + 0.5f * sep) * hf.normal;
    std::uint32_t id = (static_cast<std::uint32_t>(face) << 16) | static_cast<std::uint32_t>(k);
    two.points[two.pointCount++] =
        makePoint(transformPoint(worldFromA, mid), sep, id, worldFromA, worldFromB);
  }
  return two.pointCount == 2 ? two : m;
}

namespace {

// The face contact of reference face `faceIndex` (of B when refOnB, else of A) whose axis
// separation is `faceSeparation`: the incident face clipped to the reference face's sides.
// False, and `result` untouched, when the clipped points lost the deepest vertex.
bool faceContact(const Hull3& a, Transform3 worldFromA, const Hull3& b, Transform3 worldFromB,
                 const HullSatData3& dataA, const HullSatData3& dataB, bool refOnB, int faceIndex,
                 float faceSeparation, float speculativeDistance, Manifold3& result) noexcept {
  const Hull3& ref = refOnB ? b : a;
  const Hull3& inc = refOnB ? a : b;
  const Transform3 worldFromRef = refOnB ? worldFromB : worldFromA;
  const Transform3 worldFromInc = refOnB ? worldFromA : worldFromB;
  const Transform3 refFromInc = invMul(worldFromRef, worldFromInc);
  const HullFace3& rf = ref.faces[faceIndex];
  const Vec3 n = rf.normal;

  // The incident face: of the faces around the other hull's deepest vertex (its support
  // along -n), the one most against the reference normal. Taking the most opposed face of
  // the whole hull can miss that vertex on a sliver, whose thin side face can be more
  // opposed than the big face that holds the deepest corner (found by the random test).
  Vec3 nInc = invRotate(refFromInc.q, n);
  int deep = 0;
  for (int i = 1; i < inc.vertexCount; ++i)
    if (dot(inc.vertices[i], nInc) < dot(inc.vertices[deep], nInc)) deep = i;
  int incFace = -1;
  for (int f = 0; f < inc.faceCount; ++f) {
    const HullFace3& face = inc.faces[f];
    bool around = false;
    for (int k = 0; k < face.count && !around; ++k)
      around = inc.faceVertices[face.first + k] == deep;
    if (around && (incFace < 0 || dot(face.normal, nInc) < dot(inc.faces[incFace].normal, nInc)))
      incFace = f;
  }
  const HullFace3& ifc = inc.faces[incFace];

  Uninitialized<ClipVertex, kClipCapacity> bufA, bufB;
  ClipVertex* poly = bufA.items;
  ClipVertex* next = bufB.items;
  int count = ifc.count;
  for (int k = 0; k < ifc.count; ++k) {
    std::uint32_t v = inc.faceVertices[ifc.first + k];
    poly[k] = {transformPoint(refFromInc, inc.vertices[v]), v, v};
  }
  // Sutherland-Hodgman against each side plane of the reference face.
  for (int k = 0; k < rf.count && count > 0; ++k) {
    Vec3 v0 = ref.vertices[ref.faceVertices[rf.first + k]];
    Vec3 v1 = ref.vertices[ref.faceVertices[rf.first + (k + 1 == rf.count ? 0 : k + 1)]];
    Vec3 side = cross(v1 - v0, n);
    int out = 0;
    for (int i = 0; i < count && out + 2 <= kClipCapacity; ++i) {
      const ClipVertex& p = poly[i];
      const ClipVertex& q = poly[i + 1 == count ? 0 : i + 1];
      float dp = dot(side, p.p - v0), dq = dot(side, q.p - v0);
      if (dp <= 0.0f) next[out++] = p;
      if ((dp <= 0.0f) != (dq <= 0.0f)) {
        float t = dp / (dp - dq);
        ClipVertex c;
        c.p = p.p + t * (q.p - p.p);
        c.id = kManifold3IdClip | (static_cast<std::uint32_t>(k) << 8) | (p.edgeId & 0xFFu);
        // Leaving the clip point: along the side plane when p was inside, else q's edge.
        c.edgeId = dp <= 0.0f ? (0x80u | static_cast<std::uint32_t>(k)) : p.edgeId;
        next[out++] = c;
      }
    }
    ClipVertex* t = poly;
    poly = next;
    next = t;
    count = out;
  }

  Uninitialized<ManifoldPoint3, kClipCapacity> kept;
  ManifoldPoint3* pts = kept.items;
  int n2 = 0;
  const Vec3 normalWorld =
      refOnB ? -transformVector(worldFromRef, n) : transformVector(worldFromRef, n);
  for (int i = 0; i < count; ++i) {
    float sep = dot(n, poly[i].p) - rf.offset;
    if (sep > speculativeDistance) continue;
    Vec3 mid = poly[i].p - (0.5f * sep) * n;
    std::uint32_t id = (static_cast<std::uint32_t>(faceIndex) << 16) | poly[i].id;
    if (refOnB) id |= kManifold3IdReferenceOnB;
    pts[n2++] = makePoint(transformPoint(worldFromRef, mid), sep, id, worldFromA, worldFromB);
  }
  // The deepest clipped point should be SAT's support vertex. When clipping lost it (the
  // faces only graze: the incident face lies outside the reference face's sides, or, apart,
  // the nearest features are not over the reference face), the clipped points are further
  // than the shapes are: one point from GJK / EPA instead (found by the slow random run).
  float minSep = std::numeric_limits<float>::infinity();
  for (int i = 0; i < n2; ++i)
    minSep = minf(minSep, pts[i].separation);
  // The reference hull's largest vertex distance from its centroid.
  const float size = std::sqrt((refOnB ? dataB : dataA).size2);
  if (n2 == 0 || minSep > faceSeparation + kClipLostSupportRelative * size) return false;
  n2 = reduceToFour(pts, n2, normalWorld);
  Manifold3& m = result;
  m.normal = normalWorld;
  for (int i = 0; i < n2; ++i)
    m.points[i] = pts[i];
  m.pointCount = n2;
  return true;
}

// The hulls' cores (their radii ignored), points whose core separation is at most
// `speculativeDistance`; collideHulls adds the radii (their sum: `radii`).
// With `cache`, a pair found apart leaves its separating axis there.
Manifold3 collideHullCores(const Hull3& a, Transform3 worldFromA, const Hull3& b,
                           Transform3 worldFromB, const HullSatData3& dataA,
                           const HullSatData3& dataB, float speculativeDistance, float radii,
                           HullPairCache3* cache) noexcept {
  Manifold3 m;
  SatOutput3 sat = computeSat(a, dataA, worldFromA, b, dataB, worldFromB, speculativeDistance);
  if (sat.separation > speculativeDistance) {
    if (cache != nullptr) {
      cache->axis = invRotate(worldFromA.q, sat.normal);
      float maxA = dot(a.vertices[0], cache->axis);
      for (int i = 1; i < a.vertexCount; ++i)
        maxA = maxf(maxA, dot(a.vertices[i], cache->axis));
      cache->maxA = maxA;
      cache->valid = true;
    }
    return m;
  }
  if (cache != nullptr) cache->valid = false;

  if (sat.feature == SatFeature3::edges && sat.faceSeparation + kLinearSlop >= sat.separation &&
      (sat.separation <= radii || sat.faceSeparation >= radii)) {
    // Face contact within kLinearSlop of the edge axis wins, as Box3D's manifold does: two
    // boxes resting flush have edge axes as good as the face one to within rounding and
    // tilt, and one edge point instead of four rocks a column of boxes. Its depth is then
    // up to kLinearSlop more than the true one; hulls that are apart get no face points
    // that overlap (the face's own separation must not be below the radii).
    Manifold3 face;
    if (faceContact(a, worldFromA, b, worldFromB, dataA, dataB,
                    sat.faceFeature == SatFeature3::faceB, sat.faceIndex, sat.faceSeparation,
                    speculativeDistance, face)) {
      float minSep = std::numeric_limits<float>::infinity();
      for (int i = 0; i < face.pointCount; ++i)
        minSep = minf(minSep, face.points[i].separation);
      if (minSep + kLinearSlop >= sat.separation) return face;
    }
  }
  if (sat.feature == SatFeature3::edges && sat.separation > 0.0f) {
    // Apart on an edge axis: the closest features need not be those edges (the separation
    // is only a lower bound), so GJK gives the one point, exactly.
    Manifold3 g =
        collideGeneral(coreProxy(a), worldFromA, coreProxy(b), worldFromB, speculativeDistance);
    for (int i = 0; i < g.pointCount; ++i)
      g.points[i].id = kManifold3IdEdges | (static_cast<std::uint32_t>(sat.edgeA) << 8) |
                       static_cast<std::uint32_t>(sat.edgeB);
    return g;
  }
  if (sat.feature == SatFeature3::edges) {
    Transform3 aFromB = invMul(worldFromA, worldFromB);
    const HullEdge3& ea = a.edges[sat.edgeA];
    const HullEdge3& eb = b.edges[sat.edgeB];
    Vec3 c1, c2;
    closestSegmentPoints(a.vertices[ea.v0], a.vertices[ea.v1],
                         transformPoint(aFromB, b.vertices[eb.v0]),
                         transformPoint(aFromB, b.vertices[eb.v1]), c1, c2);
    m.normal = sat.normal;
    std::uint32_t id = kManifold3IdEdges | (static_cast<std::uint32_t>(sat.edgeA) << 8) |
                       static_cast<std::uint32_t>(sat.edgeB);
    m.points[0] = makePoint(transformPoint(worldFromA, 0.5f * (c1 + c2)), sat.separation, id,
                            worldFromA, worldFromB);
    m.pointCount = 1;
    return m;
  }

  if (!faceContact(a, worldFromA, b, worldFromB, dataA, dataB, sat.feature == SatFeature3::faceB,
                   sat.faceIndex, sat.separation, speculativeDistance, m))
    return collideGeneral(coreProxy(a), worldFromA, coreProxy(b), worldFromB, speculativeDistance);
  return m;
}

}  // namespace

namespace {

Manifold3 collideHullsWith(const Hull3& a, Transform3 worldFromA, const Hull3& b,
                           Transform3 worldFromB, const HullSatData3& dataA,
                           const HullSatData3& dataB, float speculativeDistance,
                           HullPairCache3* cache) noexcept {
  const float radii = a.radius + b.radius;
  if (cache != nullptr && cache->valid) {
    // B's least projection on the cached axis (B's vertices in A's frame, as dot() forms
    // each product) less A's greatest: a gap beyond the speculative distance proves there
    // is no contact.
    const Transform3 aFromB = invMul(worldFromA, worldFromB);
    const Vec3 axisInB = invRotate(aFromB.q, cache->axis);
    float minB = dot(b.vertices[0], axisInB);
    for (int i = 1; i < b.vertexCount; ++i)
      minB = minf(minB, dot(b.vertices[i], axisInB));
    const float gap = minB + dot(cache->axis, aFromB.p) - cache->maxA;
    // A margin of rounding (the SAT's own numbers differ from these in the last bits) so
    // that a pair SAT would find touching is never skipped.
    const float size = a.vertexCount > 0 ? length(a.vertices[0] - a.centroid) : 0.0f;
    if (gap > speculativeDistance + radii + 1e-5f * (size + length(aFromB.p))) return {};
  }
  if (radii == 0.0f)
    return collideHullCores(a, worldFromA, b, worldFromB, dataA, dataB, speculativeDistance, 0.0f,
                            cache);
  // Rounded hulls: the cores' manifold with the radii added to the speculative distance,
  // each point's separation less the radii and the point moved from midway between the
  // cores to midway between the rounded surfaces (A's surface is ra further along the
  // normal, B's rb back), as the capsules' points are; as Box2D's rounded polygons do.
  const Manifold3 core = collideHullCores(a, worldFromA, b, worldFromB, dataA, dataB,
                                          speculativeDistance + radii, radii, cache);
  Manifold3 m;
  m.normal = core.normal;
  const Vec3 shift = (0.5f * (a.radius - b.radius)) * core.normal;
  for (int i = 0; i < core.pointCount; ++i) {
    const float sep = core.points[i].separation - radii;
    if (sep > speculativeDistance) continue;
    m.points[m.pointCount++] =
        makePoint(core.points[i].point + shift, sep, core.points[i].id, worldFromA, worldFromB);
  }
  return m;
}

}  // namespace

Manifold3 collideHulls(const Hull3& a, Transform3 worldFromA, const Hull3& b, Transform3 worldFromB,
                       float speculativeDistance) noexcept {
  return collideHullsWith(a, worldFromA, b, worldFromB, makeHullSatData3(a), makeHullSatData3(b),
                          speculativeDistance, nullptr);
}

Manifold3 collideHulls(const Hull3& a, Transform3 worldFromA, const Hull3& b, Transform3 worldFromB,
                       float speculativeDistance, HullPairCache3& cache) noexcept {
  return collideHullsWith(a, worldFromA, b, worldFromB, makeHullSatData3(a), makeHullSatData3(b),
                          speculativeDistance, &cache);
}

Manifold3 collideHulls(const Hull3& a, const HullSatData3& dataA, Transform3 worldFromA,
                       const Hull3& b, const HullSatData3& dataB, Transform3 worldFromB,
                       float speculativeDistance, HullPairCache3& cache) noexcept {
  return collideHullsWith(a, worldFromA, b, worldFromB, dataA, dataB, speculativeDistance, &cache);
}

namespace {

// The routine for shapes in the order (a, b) when one exists, else an empty optional-like
// flag; `collide` tries both orders.
bool collideOrdered(const ShapeGeometry3& a, Transform3 worldFromA, const ShapeGeometry3& b,
                    Transform3 worldFromB, float spec, Manifold3& out) noexcept {
  const Sphere* sa = std::get_if<Sphere>(&a);
  const Capsule3* ca = std::get_if<Capsule3>(&a);
  const Hull3* ha = std::get_if<Hull3>(&a);
  const Sphere* sb = std::get_if<Sphere>(&b);
  const Capsule3* cb = std::get_if<Capsule3>(&b);
  const Hull3* hb = std::get_if<Hull3>(&b);
  if (ha && hb) {
    out = collideHulls(*ha, worldFromA, *hb, worldFromB, spec);
  } else if (ha && cb) {
    out = collideHullAndCapsule(*ha, worldFromA, *cb, worldFromB, spec);
  } else if (ha && sb) {
    out = collideHullAndSphere(*ha, worldFromA, *sb, worldFromB, spec);
  } else if (ca && cb) {
    out = collideCapsules(*ca, worldFromA, *cb, worldFromB, spec);
  } else if (ca && sb) {
    out = collideCapsuleAndSphere(*ca, worldFromA, *sb, worldFromB, spec);
  } else if (sa && sb) {
    out = collideSpheres(*sa, worldFromA, *sb, worldFromB, spec);
  } else {
    return false;
  }
  return true;
}

}  // namespace

namespace detail {

ManifoldPoint3 makeManifoldPoint3(Vec3 point, float separation, std::uint32_t id,
                                  Transform3 worldFromA, Transform3 worldFromB) noexcept {
  return makePoint(point, separation, id, worldFromA, worldFromB);
}

int reduceManifoldPoints3(ManifoldPoint3* points, int count, Vec3 normal) noexcept {
  return reduceToFour(points, count, normal);
}

}  // namespace detail

namespace {

// B-versus-A's manifold as A-versus-B's: the normal flipped, the anchors swapped, ids kept.
Manifold3 swapped(Manifold3 m) noexcept {
  m.normal = -m.normal;
  for (int i = 0; i < m.pointCount; ++i) {
    const Vec3 t = m.points[i].anchorA;
    m.points[i].anchorA = m.points[i].anchorB;
    m.points[i].anchorB = t;
  }
  return m;
}

}  // namespace

Manifold3 collide(const ShapeGeometry3& a, Transform3 worldFromA, const ShapeGeometry3& b,
                  Transform3 worldFromB, float speculativeDistance) noexcept {
  Manifold3 m;
  if (collideOrdered(a, worldFromA, b, worldFromB, speculativeDistance, m)) return m;
  if (collideOrdered(b, worldFromB, a, worldFromA, speculativeDistance, m)) return swapped(m);
  // Triangles (mesh3.cpp): a lone triangle is a two-sided mesh triangle.
  if (const Triangle3* t = std::get_if<Triangle3>(&a))
    return collideTriangle(*t, worldFromA, b, worldFromB, speculativeDistance);
  if (const Triangle3* t = std::get_if<Triangle3>(&b))
    return swapped(collideTriangle(*t, worldFromB, a, worldFromA, speculativeDistance));
  return collideGeneral(makeProxy(a), worldFromA, makeProxy(b), worldFromB, speculativeDistance);
}

}  // namespace quack
