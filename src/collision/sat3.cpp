// SAT for two hulls with Gauss-map edge pruning (see sat3.hpp).

#include "quack/collision/sat3.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace quack {
namespace {

// Edges whose cross product is below this fraction of their lengths' product (the sine of
// a 1e-6 radian angle) are parallel: their axis has no direction a float can trust, and
// the face of B - A they would span is a face axis of A or B, tested already.
constexpr float kParallelEdgesRelative = 1e-6f;

// A face or an edge is skipped when an upper bound on every separation it can give is
// below the best already known by more than this fraction of the pair's scale (the hulls'
// size and their centroids' distance from A's origin). What the bounds assume holds only
// within the hull's tolerance (a vertex may stand kHull3RelativeTolerance, 1e-5 of the
// size, outside a face plane), the bound and the separation are rounded differently
// (about 1e-6 of the scale each), and an edge pair that passes the Gauss-map test only by
// rounding (arcs crossing within 1e-6 of an end) exceeds its bound by about as much. Ten
// times the sum still skips nearly every feature the bounds rule out, whose bounds fall
// short by a good part of the size.
constexpr float kBoundSlackRelative = 1e-4f;

// Four lanes: SSE2's, or four scalars that compute the same bits.
constexpr int kLanes = 4;
static_assert(kMaxHullVertices3 % kLanes == 0, "vertex columns pad within the array");

// Least projection of the vertices on `direction` (the hull's frame), each product formed
// as dot() forms it, so the value is the one a loop over dot() gives.
float minProjection(const HullSatData3& c, Vec3 direction) noexcept {
#if defined(__SSE2__)
  const __m128 dx = _mm_set1_ps(direction.x);
  const __m128 dy = _mm_set1_ps(direction.y);
  const __m128 dz = _mm_set1_ps(direction.z);
  __m128 best = _mm_set1_ps(std::numeric_limits<float>::infinity());
  for (int i = 0; i < c.columnCount; i += kLanes) {
    const __m128 p = _mm_add_ps(
        _mm_add_ps(_mm_mul_ps(_mm_load_ps(c.x + i), dx), _mm_mul_ps(_mm_load_ps(c.y + i), dy)),
        _mm_mul_ps(_mm_load_ps(c.z + i), dz));
    best = _mm_min_ps(best, p);
  }
  best = _mm_min_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(1, 0, 3, 2)));
  best = _mm_min_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(2, 3, 0, 1)));
  return _mm_cvtss_f32(best);
#else
  float best = std::numeric_limits<float>::infinity();
  for (int i = 0; i < c.columnCount; ++i)
    best = minf(best, c.x[i] * direction.x + c.y[i] * direction.y + c.z[i] * direction.z);
  return best;
#endif
}

// Whether an edge of a hull, between its faces f1 and f2 (unit normals n1, n2), can give a
// separation of at least `needs`, given its faces' bounds (faceBounds[f] = dot(n_f, x) -
// radius - offset_f, x the other hull's centroid in this hull's frame). On the arc from n1
// to n2 (angle t from n1, arc angle theta), dot(n, x - p) for the edge's point p is
// (sin(theta - t) p1 + sin(t) p2) / sin(theta), where p_i = dot(n_i, x - p) = faceBounds +
// radius; the weights add up to between 1 and 1 / cos(theta / 2). So the greatest is at
// most P / cos(theta / 2) when P = max(p1, p2) is positive, else P; compared squared,
// with cos^2(theta / 2) = (1 + dot(n1, n2)) / 2, without a root.
bool edgeCanReach(const float* faceBounds, int f1, int f2, Vec3 n1, Vec3 n2, float radius,
                  float needs) noexcept {
  const float p = maxf(faceBounds[f1], faceBounds[f2]) + radius;
  const float target = needs + radius;
  // Joined with & and |, not && and ||: the outcome is close to a coin toss, a branch on
  // it mispredicted half the time.
  const bool positive = p > 0.0f;
  return (!positive & (p >= target)) |
         (positive & ((target <= 0.0f) | (2.0f * p * p >= target * target * (1.0f + dot(n1, n2)))));
}

// Least distance from the centroid to a face plane: the radius of the ball about the
// centroid inside the hull.
float inradius(const Hull3& h) noexcept {
  float r = std::numeric_limits<float>::infinity();
  for (int f = 0; f < h.faceCount; ++f)
    r = minf(r, h.faces[f].offset - dot(h.faces[f].normal, h.centroid));
  return maxf(r, 0.0f);
}

// B's edges that the bounds keep, in A's frame, as columns for the Gauss-map test: the arc
// of the edge's two face normals, negated (c, d, with the arc's plane normal
// dxc = cross(d, c), parallel to the edge), padded to a multiple of kLanes with zeros
// (which fail the test); and, per kept edge, its index, first vertex and direction.
struct ArcColumns {
  alignas(16) float cx[kMaxHullEdges3 + kLanes];
  alignas(16) float cy[kMaxHullEdges3 + kLanes];
  alignas(16) float cz[kMaxHullEdges3 + kLanes];
  alignas(16) float dx[kMaxHullEdges3 + kLanes];
  alignas(16) float dy[kMaxHullEdges3 + kLanes];
  alignas(16) float dz[kMaxHullEdges3 + kLanes];
  alignas(16) float ex[kMaxHullEdges3 + kLanes];
  alignas(16) float ey[kMaxHullEdges3 + kLanes];
  alignas(16) float ez[kMaxHullEdges3 + kLanes];
  float point[kMaxHullEdges3][3];
  float direction[kMaxHullEdges3][3];
  std::uint8_t edge[kMaxHullEdges3];
  int count;
};

// A's edge in the Gauss-map test: its arc from a to b (its two face normals) and the arc's
// plane normal bxa = cross(b, a).
struct EdgeArcA {
  Vec3 a, b, bxa;
};

// Bit k set when kept arc `first + k` of B crosses A's arc: c and d on opposite sides of
// the plane of ab (most pairs fail here), a and b on opposite sides of the plane of cd,
// and both arcs on the same hemisphere (Gregorius 2013). Every product is dot()'s.
unsigned crossingLanes(const ArcColumns& arcs, int first, const EdgeArcA& e) noexcept {
#if defined(__SSE2__)
  const __m128 zero = _mm_setzero_ps();
  auto dot4 = [](__m128 x, __m128 y, __m128 z, Vec3 v) {
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, _mm_set1_ps(v.x)), _mm_mul_ps(y, _mm_set1_ps(v.y))),
                      _mm_mul_ps(z, _mm_set1_ps(v.z)));
  };
  const __m128 cba = dot4(_mm_load_ps(arcs.cx + first), _mm_load_ps(arcs.cy + first),
                          _mm_load_ps(arcs.cz + first), e.bxa);
  const __m128 dba = dot4(_mm_load_ps(arcs.dx + first), _mm_load_ps(arcs.dy + first),
                          _mm_load_ps(arcs.dz + first), e.bxa);
  const __m128 ex = _mm_load_ps(arcs.ex + first), ey = _mm_load_ps(arcs.ey + first),
               ez = _mm_load_ps(arcs.ez + first);
  const __m128 adc = dot4(ex, ey, ez, e.a);
  const __m128 bdc = dot4(ex, ey, ez, e.b);
  const __m128 cross1 = _mm_cmplt_ps(_mm_mul_ps(cba, dba), zero);
  const __m128 cross2 = _mm_cmplt_ps(_mm_mul_ps(adc, bdc), zero);
  const __m128 hemisphere = _mm_cmpgt_ps(_mm_mul_ps(cba, bdc), zero);
  return static_cast<unsigned>(_mm_movemask_ps(_mm_and_ps(_mm_and_ps(cross1, cross2), hemisphere)));
#else
  unsigned mask = 0;
  for (int k = 0; k < kLanes; ++k) {
    const int j = first + k;
    const Vec3 c{arcs.cx[j], arcs.cy[j], arcs.cz[j]};
    const Vec3 d{arcs.dx[j], arcs.dy[j], arcs.dz[j]};
    const Vec3 dxc{arcs.ex[j], arcs.ey[j], arcs.ez[j]};
    const float cba = dot(c, e.bxa), dba = dot(d, e.bxa);
    const float adc = dot(e.a, dxc), bdc = dot(e.b, dxc);
    if (cba * dba < 0.0f && adc * bdc < 0.0f && cba * bdc > 0.0f) mask |= 1u << k;
  }
  return mask;
#endif
}

}  // namespace

HullSatData3 makeHullSatData3(const Hull3& h) noexcept {
  HullSatData3 d;
  // The largest squared distance of a vertex from the centroid (computeSat takes the root
  // of the larger of two hulls': sqrt is monotonic, the root of the largest square is the
  // largest root).
  for (int i = 0; i < h.vertexCount; ++i)
    d.size2 = maxf(d.size2, lengthSquared(h.vertices[i] - h.centroid));
  d.inradius = inradius(h);
  const int n = (h.vertexCount + kLanes - 1) / kLanes * kLanes;
  for (int i = 0; i < n; ++i) {
    const Vec3 v = h.vertices[i < h.vertexCount ? i : 0];
    d.x[i] = v.x;
    d.y[i] = v.y;
    d.z[i] = v.z;
  }
  d.columnCount = n;
  return d;
}

SatOutput3 computeSat(const Hull3& a, Transform3 worldFromA, const Hull3& b, Transform3 worldFromB,
                      float stopAbove) noexcept {
  return computeSat(a, makeHullSatData3(a), worldFromA, b, makeHullSatData3(b), worldFromB,
                    stopAbove);
}

SatOutput3 computeSat(const Hull3& a, const HullSatData3& columnsA, Transform3 worldFromA,
                      const Hull3& b, const HullSatData3& columnsB, Transform3 worldFromB,
                      float stopAbove) noexcept {
  const Transform3 aFromB = invMul(worldFromA, worldFromB);
  const Transform3 bFromA = inverse(aFromB);
  SatOutput3 out;
  const float size = std::sqrt(maxf(columnsA.size2, columnsB.size2));
  // Each centroid in the other's frame, and the ball about it inside its hull (its radius
  // the least distance to a face plane), for the bounds: a hull's least projection on a
  // unit direction is at most its centroid's less that radius.
  const Vec3 centroidBInA = transformPoint(aFromB, b.centroid);
  const Vec3 centroidAInB = transformPoint(bFromA, a.centroid);
  const float inradiusA = columnsA.inradius, inradiusB = columnsB.inradius;
  const float slack = kBoundSlackRelative *
                      (2.0f * size + length(a.centroid) + length(b.centroid) + length(aFromB.p));

  // Faces of A: B's least projection on the normal minus the face's offset, at most the
  // bound dot(normal, B's centroid) - offset. Faces of B likewise, in B's frame.
  auto separationA = [&](int f) {
    const HullFace3& face = a.faces[f];
    return minProjection(columnsB, invRotate(aFromB.q, face.normal)) + dot(face.normal, aFromB.p) -
           face.offset;
  };
  auto separationB = [&](int f) {
    const HullFace3& face = b.faces[f];
    return minProjection(columnsA, invRotate(bFromA.q, face.normal)) + dot(face.normal, bFromA.p) -
           face.offset;
  };
  float boundA[kMaxHullFaces3], boundB[kMaxHullFaces3];
  int seedA = 0, seedB = 0;
  for (int f = 0; f < a.faceCount; ++f) {
    boundA[f] = dot(a.faces[f].normal, centroidBInA) - inradiusB - a.faces[f].offset;
    if (boundA[f] > boundA[seedA]) seedA = f;
  }
  for (int f = 0; f < b.faceCount; ++f) {
    boundB[f] = dot(b.faces[f].normal, centroidAInB) - inradiusA - b.faces[f].offset;
    if (boundB[f] > boundB[seedB]) seedB = f;
  }
  // The faces with the largest bounds give a separation the best face reaches at least;
  // the passes below skip every face whose bound is short of it. Beyond stopAbove, that
  // face is the answer.
  const float seedSeparationA = separationA(seedA);
  const float seedSeparationB = separationB(seedB);
  const float seed = maxf(seedSeparationA, seedSeparationB);
  if (seed > stopAbove) {
    const bool onA = seedSeparationA >= seedSeparationB;
    out.separation = seed;
    out.feature = onA ? SatFeature3::faceA : SatFeature3::faceB;
    out.faceIndex = onA ? seedA : seedB;
    out.normal = onA ? transformVector(worldFromA, a.faces[seedA].normal)
                     : -transformVector(worldFromB, b.faces[seedB].normal);
    out.faceFeature = out.feature;
    out.faceSeparation = seed;
    out.faceNormal = out.normal;
    return out;
  }

  // The passes in index order, so that ties go to the first face as before the bounds:
  // a skipped face is below the seed, so neither the best nor first to pass stopAbove.
  std::uint8_t facesA[kMaxHullFaces3], facesB[kMaxHullFaces3];
  int facesACount = 0, facesBCount = 0;
  for (int f = 0; f < a.faceCount; ++f) {
    facesA[facesACount] = static_cast<std::uint8_t>(f);
    facesACount += boundA[f] + slack >= seed;
  }
  for (int f = 0; f < b.faceCount; ++f) {
    facesB[facesBCount] = static_cast<std::uint8_t>(f);
    facesBCount += boundB[f] + slack >= seed;
  }
  float bestFace = -std::numeric_limits<float>::infinity();
  Vec3 bestNormal;
  for (int n = 0; n < facesACount; ++n) {
    const int f = facesA[n];
    if (boundA[f] + slack < bestFace) continue;
    const float s = f == seedA ? seedSeparationA : separationA(f);
    if (s > bestFace) {
      bestFace = s;
      bestNormal = a.faces[f].normal;
      out.feature = SatFeature3::faceA;
      out.faceIndex = f;
      if (s > stopAbove) break;
    }
  }
  for (int n = 0; n < facesBCount && !(bestFace > stopAbove); ++n) {
    const int f = facesB[n];
    if (boundB[f] + slack < bestFace) continue;
    const float s = f == seedB ? seedSeparationB : separationB(f);
    if (s > bestFace) {
      bestFace = s;
      bestNormal = -rotate(aFromB.q, b.faces[f].normal);
      out.feature = SatFeature3::faceB;
      out.faceIndex = f;
      if (s > stopAbove) break;
    }
  }
  // A face axis beyond stopAbove: the final separation (this face's, or an edge's larger
  // by the bias) exceeds it whatever the edges say.
  out.faceFeature = out.feature;
  out.faceSeparation = bestFace;
  out.faceNormal = transformVector(worldFromA, bestNormal);
  if (bestFace > stopAbove) {
    out.separation = bestFace;
    out.normal = out.faceNormal;
    return out;
  }

  // Edge pairs that are faces of the Minkowski difference: arcs ab (an edge of A: its two
  // face normals) and cd (an edge of B: its normals negated) that cross on the unit sphere
  // (Gregorius 2013). On such a pair's axis n (away from A), A's edge is A's support and
  // B's is B's least, so its separation is at most n . (B's centroid - A's edge point) -
  // B's inradius for n on A's arc, and n . (A's centroid - B's edge point) - A's inradius
  // for -n on B's arc: an edge whose greatest over its arc cannot beat the best face (by
  // the bias an edge needs) is dropped (edgeCanReach), and the pairs are the kept edges'.
  const float edgeNeeds = bestFace + kSat3FaceBiasRelative * size - slack;
  std::uint8_t keptB[kMaxHullEdges3];
  int keptBCount = 0;
  for (int j = 0; j < b.edgeCount; ++j) {
    const HullEdge3& eb = b.edges[j];
    keptB[keptBCount] = static_cast<std::uint8_t>(j);
    keptBCount += edgeCanReach(boundB, eb.faceLeft, eb.faceRight, b.faces[eb.faceLeft].normal,
                               b.faces[eb.faceRight].normal, inradiusA, edgeNeeds);
  }
  ArcColumns arcs;
  int kept = 0;
  for (int n = 0; n < keptBCount; ++n) {
    const int j = keptB[n];
    const HullEdge3& eb = b.edges[j];
    const Vec3 n1 = rotate(aFromB.q, b.faces[eb.faceLeft].normal);
    const Vec3 n2 = rotate(aFromB.q, b.faces[eb.faceRight].normal);
    const Vec3 p = transformPoint(aFromB, b.vertices[eb.v0]);
    const Vec3 c = -n1, d = -n2, dxc = cross(d, c);
    const Vec3 direction = transformPoint(aFromB, b.vertices[eb.v1]) - p;
    arcs.cx[kept] = c.x;
    arcs.cy[kept] = c.y;
    arcs.cz[kept] = c.z;
    arcs.dx[kept] = d.x;
    arcs.dy[kept] = d.y;
    arcs.dz[kept] = d.z;
    arcs.ex[kept] = dxc.x;
    arcs.ey[kept] = dxc.y;
    arcs.ez[kept] = dxc.z;
    arcs.point[kept][0] = p.x;
    arcs.point[kept][1] = p.y;
    arcs.point[kept][2] = p.z;
    arcs.direction[kept][0] = direction.x;
    arcs.direction[kept][1] = direction.y;
    arcs.direction[kept][2] = direction.z;
    arcs.edge[kept] = static_cast<std::uint8_t>(j);
    ++kept;
  }
  for (int k = kept; k % kLanes != 0; ++k) {
    arcs.cx[k] = arcs.cy[k] = arcs.cz[k] = 0.0f;
    arcs.dx[k] = arcs.dy[k] = arcs.dz[k] = 0.0f;
    arcs.ex[k] = arcs.ey[k] = arcs.ez[k] = 0.0f;
  }

  float bestEdge = -std::numeric_limits<float>::infinity();
  Vec3 bestEdgeNormal;
  int bestEdgeA = 0, bestEdgeB = 0;
  bool stop = false;
  std::uint8_t keptA[kMaxHullEdges3];
  int keptACount = 0;
  for (int i = 0; i < a.edgeCount && kept > 0; ++i) {
    const HullEdge3& ea = a.edges[i];
    keptA[keptACount] = static_cast<std::uint8_t>(i);
    keptACount += edgeCanReach(boundA, ea.faceLeft, ea.faceRight, a.faces[ea.faceLeft].normal,
                               a.faces[ea.faceRight].normal, inradiusB, edgeNeeds);
  }
  for (int n = 0; n < keptACount && !stop; ++n) {
    const int i = keptA[n];
    const HullEdge3& ea = a.edges[i];
    EdgeArcA arc;
    arc.a = a.faces[ea.faceLeft].normal;
    arc.b = a.faces[ea.faceRight].normal;
    const Vec3 pa = a.vertices[ea.v0];
    arc.bxa = cross(arc.b, arc.a);
    const Vec3 da = a.vertices[ea.v1] - pa;
    for (int first = 0; first < kept && !stop; first += kLanes) {
      for (unsigned lanes = crossingLanes(arcs, first, arc); lanes != 0; lanes &= lanes - 1) {
        const int k = first + std::countr_zero(lanes);
        ++out.edgePairsTested;
        const Vec3 pb{arcs.point[k][0], arcs.point[k][1], arcs.point[k][2]};
        const Vec3 db{arcs.direction[k][0], arcs.direction[k][1], arcs.direction[k][2]};
        Vec3 axis = cross(da, db);
        const float len = length(axis);
        if (len < kParallelEdgesRelative * length(da) * length(db)) continue;
        axis = (1.0f / len) * axis;
        if (dot(axis, pa - a.centroid) < 0.0f) axis = -axis;
        const float s = dot(axis, pb - pa);
        if (s > bestEdge) {
          bestEdge = s;
          bestEdgeNormal = axis;
          bestEdgeA = i;
          bestEdgeB = arcs.edge[k];
          // This edge axis wins over every face, and so does any larger one: the answer's
          // separation exceeds stopAbove.
          if (s > stopAbove && s > bestFace + kSat3FaceBiasRelative * size) {
            stop = true;
            break;
          }
        }
      }
    }
  }

  out.separation = bestFace;
  out.normal = bestNormal;
  if (bestEdge > bestFace + kSat3FaceBiasRelative * size) {
    out.separation = bestEdge;
    out.normal = bestEdgeNormal;
    out.feature = SatFeature3::edges;
    out.edgeA = bestEdgeA;
    out.edgeB = bestEdgeB;
  }
  out.normal = transformVector(worldFromA, out.normal);
  return out;
}

}  // namespace quack
