// EPA in 3D (see epa3.hpp).

#include "quack/collision/epa3.hpp"

#include <cmath>
#include <limits>

#include "gjk3_internal.hpp"

namespace quack {

const char* toString(Epa3Status status) noexcept {
  switch (status) {
    case Epa3Status::separated:
      return "separated";
    case Epa3Status::coresSeparated:
      return "cores_separated";
    case Epa3Status::converged:
      return "converged";
    case Epa3Status::repeatedSupport:
      return "repeated_support";
    case Epa3Status::bufferFull:
      return "buffer_full";
    case Epa3Status::gaveUp:
      return "gave_up";
    case Epa3Status::degenerate:
      return "degenerate";
  }
  return "unknown";
}

namespace {

struct Face {
  int v[3];
  Vec3 normal;     // outward unit normal, A frame
  float distance;  // signed distance of the plane from the origin (positive: origin inside)
  int adj[3];      // the face across edge k (v[k] -> v[k + 1])
  int adjEdge[3];  // that edge's index in the face across
  int seenPass;    // the last pass whose new point saw this face (0: none)
  bool live;
};

// A fixed array whose elements are left uninitialised on construction: the polytope's
// buffers (about 45 kB) are written before they are read, and zeroing them cost a fifth of
// EPA's instructions on 16-vertex hulls.
template <typename T, int N>
struct UninitializedArray {
  UninitializedArray() noexcept {}
  T& operator[](int i) noexcept { return items[i]; }
  const T& operator[](int i) const noexcept { return items[i]; }
  union {
    T items[N];
  };
};

// A polytope in fixed buffers. Faces live in slots; removed slots are reused through a
// free list, so the adjacency indices stay valid. A released slot's distance is +inf, so
// the search for the nearest face needs no test of `live`.
struct Polytope {
  UninitializedArray<SupportPoint3, kEpa3MaxVertices> vertices;
  UninitializedArray<Face, kEpa3MaxFaces> faces;
  UninitializedArray<int, kEpa3MaxFaces> freeSlots;
  int vertexCount = 0;
  int slotCount = 0;  // slots ever used
  int freeCount = 0;
  int liveCount = 0;

  int allocate() noexcept {
    int slot = freeCount > 0 ? freeSlots[--freeCount] : slotCount++;
    ++liveCount;
    return slot;
  }
  void release(int slot) noexcept {
    faces[slot].live = false;
    faces[slot].distance = std::numeric_limits<float>::infinity();
    freeSlots[freeCount++] = slot;
    --liveCount;
  }
  // The live face nearest the origin (the first such slot on a tie); -1 when none has a
  // distance below +inf (no live face, or NaN input).
  int nearestFace() const noexcept {
    int best = -1;
    float bestDistance = std::numeric_limits<float>::infinity();
    for (int f = 0; f < slotCount; ++f) {
      if (faces[f].distance < bestDistance) {
        best = f;
        bestDistance = faces[f].distance;
      }
    }
    return best;
  }
};

// A face has no normal when its doubled area squared is below this fraction of the size
// to the fourth: an area of 1e-12 of the size squared, the float rounding of the cross
// product of two edges of that size.
constexpr float kFaceAreaRelative2 = 1e-24f;

// A support point grows the start simplex only if it leaves its point, line or plane by
// more than this fraction of the size: about 8 float ulps, above the rounding of the
// support points.
constexpr float kGrowRelativeTolerance = 1e-6f;

// Face a, b, c (counter-clockwise seen from outside); false when it has no normal.
bool makeFace(const Polytope& p, int a, int b, int c, float sizeSquared, Face& out) noexcept {
  Vec3 pa = p.vertices[a].w, pb = p.vertices[b].w, pc = p.vertices[c].w;
  Vec3 n = cross(pb - pa, pc - pa);
  float len2 = lengthSquared(n);
  if (!(len2 > kFaceAreaRelative2 * sizeSquared * sizeSquared)) return false;
  n = (1.0f / std::sqrt(len2)) * n;
  // The distance from the three vertices' mean: less rounding than from one vertex.
  out.v[0] = a;
  out.v[1] = b;
  out.v[2] = c;
  out.normal = n;
  out.distance = dot(n, (1.0f / 3.0f) * (pa + pb + pc));
  out.seenPass = 0;
  out.live = true;
  return true;
}

// The same direction from A's centre to B's centre, or +y when they coincide.
Vec3 centreDirection(const ShapeProxy3& a, const ShapeProxy3& b, Transform3 aFromB) noexcept {
  Vec3 d = normalize(transformPoint(aFromB, b.center()) - a.center());
  return lengthSquared(d) > 0.0f ? d : Vec3{0, 1, 0};
}

// Records one pass of EPA: the polytope's vertices and live faces, the nearest face and the
// support point along its normal.
void recordPass(Epa3Trace& trace, const Polytope& poly, int best,
                const SupportPoint3& support) noexcept {
  Epa3IterationRecord* record = detail::claimTraceRecord3(trace);
  record->vertexCount = poly.vertexCount;
  for (int i = 0; i < poly.vertexCount; ++i)
    record->vertices[i] = poly.vertices[i];
  record->faceCount = 0;
  for (int f = 0; f < poly.slotCount; ++f) {
    if (!poly.faces[f].live) continue;
    if (f == best) record->nearest = record->faceCount;
    for (int k = 0; k < 3; ++k)
      record->faces[record->faceCount][k] = poly.faces[f].v[k];
    ++record->faceCount;
  }
  record->faceNormal = poly.faces[best].normal;
  record->faceDistance = poly.faces[best].distance;
  record->hasSupport = true;
  record->support = support;
}

PenetrationOutput3 penetration3(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                                Transform3 worldFromB, GjkCache3* cache, Gjk3Trace* gjkTrace,
                                Epa3Trace* epaTrace) noexcept {
  Transform3 aFromB = invMul(worldFromA, worldFromB);
  const detail::MinkowskiPair3 pair(a, b, aFromB);
  Simplex3 simplex;
  detail::GjkCore3 gjk = detail::runGjk3(pair, cache, -1.0f, simplex, gjkTrace);
  PenetrationOutput3 out;
  out.iterations = gjk.iterations;
  const float ra = a.radius(), rb = b.radius();
  auto finish = [&](Vec3 pA, Vec3 pB, Vec3 normalA, float depth) {
    // pA, pB: core points, A frame; normalA from A to B, A frame; depth including radii.
    out.normal = transformVector(worldFromA, normalA);
    out.depth = depth;
    out.pointA = transformPoint(worldFromA, pA + ra * normalA);
    out.pointB = transformPoint(worldFromA, pB - rb * normalA);
  };

  if (gjk.status != GjkStatus::overlap) {
    Vec3 pA, pB;
    detail::closestPoints3(simplex, pA, pB);
    float len = length(gjk.closest);
    Vec3 n = (1.0f / len) * gjk.closest;
    if (len > ra + rb) {
      out.status = Epa3Status::separated;
      finish(pA, pB, n, 0.0f);
      return out;
    }
    out.overlap = true;
    out.status = Epa3Status::coresSeparated;
    finish(pA, pB, n, ra + rb - len);
    return out;
  }
  out.overlap = true;

  Polytope poly;
  float size2 = 0.0f;
  auto addVertex = [&](const SupportPoint3& s) {
    poly.vertices[poly.vertexCount++] = s;
    size2 = maxf(size2, lengthSquared(s.w));
  };
  for (int i = 0; i < simplex.count; ++i)
    addVertex(simplex.v[i]);

  // Grow GJK's simplex to a tetrahedron by support points along directions that leave the
  // current point, line or plane.
  auto sameIndices = [&](const SupportPoint3& s) {
    for (int i = 0; i < poly.vertexCount; ++i) {
      if (poly.vertices[i].indexA == s.indexA && poly.vertices[i].indexB == s.indexB) return true;
    }
    return false;
  };
  const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int pass = 0; pass < 3 && poly.vertexCount < 4; ++pass) {
    Vec3 dirs[6];
    int dirCount = 0;
    Vec3 p0 = poly.vertices[0].w;
    if (poly.vertexCount == 1) {
      for (Vec3 e : axes) {
        dirs[dirCount++] = e;
        dirs[dirCount++] = -e;
      }
    } else if (poly.vertexCount == 2) {
      Vec3 d = poly.vertices[1].w - p0;
      Vec3 ad = absv(d);
      Vec3 e = ad.x <= ad.y && ad.x <= ad.z ? axes[0] : (ad.y <= ad.z ? axes[1] : axes[2]);
      Vec3 u = normalize(cross(d, e));
      Vec3 v = normalize(cross(d, u));
      dirs[dirCount++] = u;
      dirs[dirCount++] = -u;
      dirs[dirCount++] = v;
      dirs[dirCount++] = -v;
    } else {
      Vec3 n = normalize(cross(poly.vertices[1].w - p0, poly.vertices[2].w - p0));
      dirs[dirCount++] = n;
      dirs[dirCount++] = -n;
    }
    bool grown = false;
    for (int k = 0; k < dirCount && !grown; ++k) {
      SupportPoint3 s = pair.support(dirs[k]);
      ++out.iterations;
      if (sameIndices(s)) continue;
      // Accept it only if it leaves the current affine hull by more than rounding.
      float size = std::sqrt(maxf(size2, lengthSquared(s.w)));
      float eps = kGrowRelativeTolerance * size;
      float off = 0.0f;
      if (poly.vertexCount == 1) {
        off = length(s.w - p0);
      } else if (poly.vertexCount == 2) {
        Vec3 d = poly.vertices[1].w - p0;
        off = length(cross(d, s.w - p0)) / maxf(length(d), kNormalizeEpsilon);
      } else {
        Vec3 n = normalize(cross(poly.vertices[1].w - p0, poly.vertices[2].w - p0));
        off = absf(dot(n, s.w - p0));
      }
      if (off > eps) {
        addVertex(s);
        grown = true;
      }
    }
    if (!grown) break;
  }
  if (poly.vertexCount < 4) {
    // B - A's core is flat (or a segment, or a point): its depth is the radii alone.
    Vec3 n = centreDirection(a, b, aFromB);
    if (poly.vertexCount == 3) {
      Vec3 p0 = poly.vertices[0].w;
      Vec3 fn = normalize(cross(poly.vertices[1].w - p0, poly.vertices[2].w - p0));
      if (lengthSquared(fn) > 0.0f) n = dot(fn, n) >= 0.0f ? fn : -fn;
    }
    Vec3 pA, pB;
    detail::closestPoints3(simplex, pA, pB);
    out.status = Epa3Status::degenerate;
    finish(pA, pB, n, ra + rb);
    return out;
  }

  // The tetrahedron, each face turned to face away from the fourth vertex, and its
  // adjacency by matching each directed edge with its reverse.
  static constexpr int kTet[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {1, 3, 2, 0}, {2, 3, 0, 1}};
  for (const auto& t : kTet) {
    Face f;
    if (!makeFace(poly, t[0], t[1], t[2], size2, f)) {
      out.status = Epa3Status::gaveUp;
      break;
    }
    if (dot(f.normal, poly.vertices[t[3]].w) > f.distance)
      makeFace(poly, t[0], t[2], t[1], size2, f);
    poly.faces[poly.allocate()] = f;
  }
  if (out.status != Epa3Status::gaveUp) {
    // Face f (slot f) lacks vertex kTet[f][3]; the face across f's edge k lacks the vertex of
    // f that is not on that edge, and holds the edge reversed.
    static constexpr int kFaceWithout[4] = {2, 3, 1, 0};
    for (int f = 0; f < 4; ++f) {
      Face& face = poly.faces[f];
      for (int k = 0; k < 3; ++k) {
        const int g = kFaceWithout[face.v[(k + 2) % 3]];
        const int w = face.v[(k + 1) % 3];
        const Face& across = poly.faces[g];
        face.adj[k] = g;
        face.adjEdge[k] = across.v[0] == w ? 0 : (across.v[1] == w ? 1 : 2);
      }
    }
  }

  // Per-pass scratch: the faces the new point sees, the horizon in order, and the cone
  // built before the polytope is touched.
  struct HorizonEdge {
    int a, b;     // the edge, as in the seen face (counter-clockwise)
    int outside;  // the unseen face across it
    int edge;     // the edge's index in that face
  };
  struct Frame {
    int face, edge, remaining;
  };
  UninitializedArray<int, kEpa3MaxFaces> seen;
  UninitializedArray<HorizonEdge, kEpa3MaxFaces> horizon;
  UninitializedArray<Face, kEpa3MaxFaces> cone;
  UninitializedArray<Frame, kEpa3MaxFaces> stack;

  if (out.status != Epa3Status::gaveUp) {
    out.status = Epa3Status::bufferFull;
    // Cap: each pass adds one vertex or stops, so there are fewer passes than vertices.
    for (int pass = 1; pass <= kEpa3MaxVertices; ++pass) {
      const int best = poly.nearestFace();
      if (best < 0) {
        out.status = Epa3Status::gaveUp;
        break;
      }
      const Face nearest = poly.faces[best];
      SupportPoint3 s = pair.support(nearest.normal);
      ++out.iterations;
      if (epaTrace != nullptr && epaTrace->capacity > 0) recordPass(*epaTrace, poly, best, s);
      bool repeated = false;
      for (int k = 0; k < 3; ++k) {
        const SupportPoint3& v = poly.vertices[nearest.v[k]];
        if (v.indexA == s.indexA && v.indexB == s.indexB) repeated = true;
      }
      if (repeated) {
        out.status = Epa3Status::repeatedSupport;
        break;
      }
      float size = std::sqrt(maxf(size2, lengthSquared(s.w)));
      float gap = dot(nearest.normal, s.w) - nearest.distance;
      if (gap <= kEpa3RelativeTolerance * size) {
        out.status = Epa3Status::converged;
        break;
      }
      if (poly.vertexCount == kEpa3MaxVertices) break;  // bufferFull

      // The faces the new point sees, grown from the nearest across edges to the faces that
      // see it too (Ericson 9.5's silhouette walk, with an explicit stack); the horizon
      // comes out in order around the seen region.
      int seenCount = 1, horizonCount = 0, top = 0;
      poly.faces[best].seenPass = pass;
      seen[0] = best;
      stack[top++] = {best, 0, 3};
      bool overflow = false;
      while (top > 0 && !overflow) {
        Frame& fr = stack[top - 1];
        if (fr.remaining == 0) {
          --top;
          continue;
        }
        int k = fr.edge;
        fr.edge = (k + 1) % 3;
        --fr.remaining;
        const Face& face = poly.faces[fr.face];
        int g = face.adj[k];
        Face& across = poly.faces[g];
        if (across.seenPass == pass) continue;
        if (dot(across.normal, s.w) - across.distance > 0.0f) {
          across.seenPass = pass;
          seen[seenCount++] = g;
          if (top == kEpa3MaxFaces) {
            overflow = true;
            break;
          }
          stack[top++] = {g, (face.adjEdge[k] + 1) % 3, 2};
        } else {
          if (horizonCount == kEpa3MaxFaces) {
            overflow = true;
            break;
          }
          horizon[horizonCount++] = {face.v[k], face.v[(k + 1) % 3], g, face.adjEdge[k]};
        }
      }
      // The horizon must be one loop in order (rounding can make the seen region other
      // than a disk), and the new faces must fit.
      bool loop = !overflow && horizonCount >= 3;
      for (int e = 0; e < horizonCount && loop; ++e)
        loop = horizon[e].b == horizon[(e + 1) % horizonCount].a;
      if (!loop || poly.liveCount - seenCount + horizonCount > kEpa3MaxFaces) {
        out.status = loop ? Epa3Status::bufferFull : Epa3Status::gaveUp;
        break;
      }
      // Build the cone first, so a face with no normal leaves the polytope as it was.
      int newIndex = poly.vertexCount;
      poly.vertices[newIndex] = s;
      float size2New = maxf(size2, lengthSquared(s.w));
      bool ok = true;
      for (int e = 0; e < horizonCount && ok; ++e)
        ok = makeFace(poly, horizon[e].a, horizon[e].b, newIndex, size2New, cone[e]);
      if (!ok) {
        out.status = Epa3Status::gaveUp;
        break;
      }
      ++poly.vertexCount;
      size2 = size2New;
      for (int k = 0; k < seenCount; ++k)
        poly.release(seen[k]);
      int slots[kEpa3MaxFaces];
      for (int e = 0; e < horizonCount; ++e)
        slots[e] = poly.allocate();
      for (int e = 0; e < horizonCount; ++e) {
        Face& f = poly.faces[slots[e]];
        f = cone[e];
        // Edge 0 (a -> b) faces the outside face; edge 1 (b -> new) the next cone face's
        // edge 2 (new -> b); edge 2 (new -> a) the previous cone face's edge 1.
        f.adj[0] = horizon[e].outside;
        f.adjEdge[0] = horizon[e].edge;
        f.adj[1] = slots[(e + 1) % horizonCount];
        f.adjEdge[1] = 2;
        f.adj[2] = slots[(e + horizonCount - 1) % horizonCount];
        f.adjEdge[2] = 1;
        Face& outside = poly.faces[horizon[e].outside];
        outside.adj[horizon[e].edge] = slots[e];
        outside.adjEdge[horizon[e].edge] = 0;
      }
    }
  }

  // The answer: the nearest face, the origin's projection on it in barycentric weights.
  const int best = poly.nearestFace();
  if (best < 0) {
    Vec3 pA, pB;
    detail::closestPoints3(simplex, pA, pB);
    finish(pA, pB, centreDirection(a, b, aFromB), ra + rb);
    return out;
  }
  const Face& face = poly.faces[best];
  const SupportPoint3& s0 = poly.vertices[face.v[0]];
  const SupportPoint3& s1 = poly.vertices[face.v[1]];
  const SupportPoint3& s2 = poly.vertices[face.v[2]];
  Vec3 p = face.distance * face.normal;
  // Barycentric weights of p by the sub-triangle areas along the face normal.
  float w0 = dot(cross(s1.w - p, s2.w - p), face.normal);
  float w1 = dot(cross(s2.w - p, s0.w - p), face.normal);
  float w2 = dot(cross(s0.w - p, s1.w - p), face.normal);
  float sum = w0 + w1 + w2;
  if (!(sum > 0.0f)) {
    w0 = w1 = w2 = 1.0f;
    sum = 3.0f;
  }
  float inv = 1.0f / sum;
  Vec3 pA = (w0 * inv) * s0.pointA + (w1 * inv) * s1.pointA + (w2 * inv) * s2.pointA;
  Vec3 pB = (w0 * inv) * s0.pointB + (w1 * inv) * s1.pointB + (w2 * inv) * s2.pointB;
  float coreDepth = maxf(face.distance, 0.0f);
  finish(pA, pB, -face.normal, coreDepth + ra + rb);
  return out;
}

}  // namespace

PenetrationOutput3 computePenetration(const ShapeProxy3& a, Transform3 worldFromA,
                                      const ShapeProxy3& b, Transform3 worldFromB,
                                      GjkCache3* cache) noexcept {
  return penetration3(a, worldFromA, b, worldFromB, cache, nullptr, nullptr);
}

PenetrationOutput3 computePenetration(const ShapeProxy3& a, Transform3 worldFromA,
                                      const ShapeProxy3& b, Transform3 worldFromB, GjkCache3* cache,
                                      Gjk3Trace* gjkTrace, Epa3Trace* epaTrace) noexcept {
  if (gjkTrace != nullptr) detail::resetTrace3(*gjkTrace);
  if (epaTrace != nullptr) detail::resetTrace3(*epaTrace);
  return penetration3(a, worldFromA, b, worldFromB, cache, gjkTrace, epaTrace);
}

}  // namespace quack
