// SAT for two hulls with Gauss-map edge pruning (see sat3.hpp).

#include "quack/collision/sat3.hpp"

#include <cmath>

#include "quack/collision/proxy3.hpp"

namespace quack {
namespace {

// Edges whose cross product is below this fraction of their lengths' product (the sine of
// a 1e-6 radian angle) are parallel: their axis has no direction a float can trust, and
// the face of B - A they would span is a face axis of A or B, tested already.
constexpr float kParallelEdgesRelative = 1e-6f;

// Least projection of the hull's vertices on `direction` (hull frame).
float minProjection(const Hull3& h, Vec3 direction) noexcept {
  float best = dot(h.vertices[0], direction);
  for (int i = 1; i < h.vertexCount; ++i)
    best = minf(best, dot(h.vertices[i], direction));
  return best;
}

// B's edge in A's frame, for the edge-pair loop: the arc of its two face normals, negated
// (c, d, with the arc's plane normal dxc = cross(d, c), parallel to the edge), and its
// first vertex and direction. Computed once per edge rather than once per edge pair.
struct EdgeArc {
  Vec3 c, d, dxc;
  Vec3 p, direction;
};

}  // namespace

SatOutput3 computeSat(const Hull3& a, Transform3 worldFromA, const Hull3& b, Transform3 worldFromB,
                      float stopAbove) noexcept {
  Transform3 aFromB = invMul(worldFromA, worldFromB);
  SatOutput3 out;
  float size = 0.0f;
  for (int i = 0; i < a.vertexCount; ++i)
    size = maxf(size, length(a.vertices[i] - a.centroid));
  for (int i = 0; i < b.vertexCount; ++i)
    size = maxf(size, length(b.vertices[i] - b.centroid));

  // Faces of A: B's least projection on the normal minus the face's offset.
  float bestFace = -std::numeric_limits<float>::infinity();
  Vec3 bestNormal;
  for (int f = 0; f < a.faceCount; ++f) {
    const HullFace3& face = a.faces[f];
    Vec3 nB = invRotate(aFromB.q, face.normal);
    float s = minProjection(b, nB) + dot(face.normal, aFromB.p) - face.offset;
    if (s > bestFace) {
      bestFace = s;
      bestNormal = face.normal;
      out.feature = SatFeature3::faceA;
      out.faceIndex = f;
      if (s > stopAbove) break;
    }
  }
  // Faces of B (in B's frame): A's least projection on the normal.
  Transform3 bFromA = inverse(aFromB);
  for (int f = 0; f < b.faceCount && !(bestFace > stopAbove); ++f) {
    const HullFace3& face = b.faces[f];
    Vec3 nA = rotate(aFromB.q, face.normal);
    float s = minProjection(a, invRotate(bFromA.q, face.normal)) + dot(face.normal, bFromA.p) -
              face.offset;
    if (s > bestFace) {
      bestFace = s;
      bestNormal = -nA;
      out.feature = SatFeature3::faceB;
      out.faceIndex = f;
      if (s > stopAbove) break;
    }
  }
  // A face axis beyond stopAbove: the final separation (this face's, or an edge's larger
  // by the bias) exceeds it whatever the edges say.
  if (bestFace > stopAbove) {
    out.separation = bestFace;
    out.normal = transformVector(worldFromA, bestNormal);
    return out;
  }

  // Edge pairs that are faces of the Minkowski difference: arcs ab (an edge of A: its two
  // face normals) and cd (an edge of B: its normals negated) that cross on the unit sphere
  // (Gregorius 2013). B's arcs are brought into A's frame once (about 11 kB on the stack).
  EdgeArc arcs[kMaxHullEdges3];
  for (int j = 0; j < b.edgeCount; ++j) {
    const HullEdge3& eb = b.edges[j];
    EdgeArc& arc = arcs[j];
    arc.c = -rotate(aFromB.q, b.faces[eb.faceLeft].normal);
    arc.d = -rotate(aFromB.q, b.faces[eb.faceRight].normal);
    arc.dxc = cross(arc.d, arc.c);
    arc.p = transformPoint(aFromB, b.vertices[eb.v0]);
    arc.direction = transformPoint(aFromB, b.vertices[eb.v1]) - arc.p;
  }
  float bestEdge = -std::numeric_limits<float>::infinity();
  Vec3 bestEdgeNormal;
  int bestEdgeA = 0, bestEdgeB = 0;
  bool stop = false;
  for (int i = 0; i < a.edgeCount && !stop; ++i) {
    const HullEdge3& ea = a.edges[i];
    Vec3 pa = a.vertices[ea.v0], qa = a.vertices[ea.v1];
    Vec3 na1 = a.faces[ea.faceLeft].normal, na2 = a.faces[ea.faceRight].normal;
    Vec3 bxa = cross(na2, na1);
    Vec3 da = qa - pa;
    for (int j = 0; j < b.edgeCount; ++j) {
      const EdgeArc& arc = arcs[j];
      // c and d on opposite sides of the plane of ab (most pairs fail here), a and b on
      // opposite sides of the plane of cd, and both arcs on the same hemisphere.
      const float cba = dot(arc.c, bxa);
      const float dba = dot(arc.d, bxa);
      if (!(cba * dba < 0.0f)) continue;
      const float adc = dot(na1, arc.dxc);
      const float bdc = dot(na2, arc.dxc);
      if (!(adc * bdc < 0.0f && cba * bdc > 0.0f)) continue;
      ++out.edgePairsTested;
      const Vec3 pb = arc.p;
      const Vec3 db = arc.direction;
      Vec3 axis = cross(da, db);
      float len = length(axis);
      if (len < kParallelEdgesRelative * length(da) * length(db)) continue;
      axis = (1.0f / len) * axis;
      if (dot(axis, pa - a.centroid) < 0.0f) axis = -axis;
      float s = dot(axis, pb - pa);
      if (s > bestEdge) {
        bestEdge = s;
        bestEdgeNormal = axis;
        bestEdgeA = i;
        bestEdgeB = j;
        // This edge axis wins over every face, and so does any larger one: the answer's
        // separation exceeds stopAbove.
        if (s > stopAbove && s > bestFace + kSat3FaceBiasRelative * size) {
          stop = true;
          break;
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
