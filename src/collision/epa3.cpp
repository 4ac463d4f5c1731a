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
};

// A polytope in fixed buffers.
struct Polytope {
  SupportPoint3 vertices[kEpa3MaxVertices];
  Face faces[kEpa3MaxFaces];
  int vertexCount = 0;
  int faceCount = 0;
};

// Face a, b, c (counter-clockwise seen from outside); false when it has no normal.
bool makeFace(const Polytope& p, int a, int b, int c, float sizeSquared, Face& out) noexcept {
  Vec3 pa = p.vertices[a].w, pb = p.vertices[b].w, pc = p.vertices[c].w;
  Vec3 n = cross(pb - pa, pc - pa);
  float len2 = lengthSquared(n);
  // No normal when the doubled area is at the float rounding of the size squared.
  if (!(len2 > 1e-24f * sizeSquared * sizeSquared)) return false;
  n = (1.0f / std::sqrt(len2)) * n;
  // The distance from the three vertices' mean: less rounding than from one vertex.
  out = {{a, b, c}, n, dot(n, (1.0f / 3.0f) * (pa + pb + pc))};
  return true;
}

// The same direction from A's centre to B's centre, or +y when they coincide.
Vec3 centreDirection(const ShapeProxy3& a, const ShapeProxy3& b, Transform3 aFromB) noexcept {
  Vec3 d = normalize(transformPoint(aFromB, b.center()) - a.center());
  return lengthSquared(d) > 0.0f ? d : Vec3{0, 1, 0};
}

}  // namespace

PenetrationOutput3 computePenetration(const ShapeProxy3& a, Transform3 worldFromA,
                                      const ShapeProxy3& b, Transform3 worldFromB,
                                      GjkCache3* cache) noexcept {
  Transform3 aFromB = invMul(worldFromA, worldFromB);
  detail::GjkCore3 gjk = detail::runGjk3(a, b, aFromB, cache, -1.0f);
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
    detail::closestPoints3(gjk.simplex, pA, pB);
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
  for (int i = 0; i < gjk.simplex.count; ++i)
    addVertex(gjk.simplex.v[i]);

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
      SupportPoint3 s = detail::support3(a, b, aFromB, dirs[k]);
      ++out.iterations;
      if (sameIndices(s)) continue;
      // Accept it only if it leaves the current affine hull by more than rounding.
      float size = std::sqrt(maxf(size2, lengthSquared(s.w)));
      float eps = 1e-6f * size;
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
    detail::closestPoints3(gjk.simplex, pA, pB);
    out.status = Epa3Status::degenerate;
    finish(pA, pB, n, ra + rb);
    return out;
  }

  // The tetrahedron, each face turned to face away from the fourth vertex.
  static constexpr int kTet[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {1, 3, 2, 0}, {2, 3, 0, 1}};
  for (const auto& t : kTet) {
    Face f;
    if (!makeFace(poly, t[0], t[1], t[2], size2, f)) {
      out.status = Epa3Status::gaveUp;
      break;
    }
    if (dot(f.normal, poly.vertices[t[3]].w) > f.distance) {
      makeFace(poly, t[0], t[2], t[1], size2, f);
    }
    poly.faces[poly.faceCount++] = f;
  }

  int best = 0;
  if (out.status != Epa3Status::gaveUp) {
    out.status = Epa3Status::bufferFull;
    // Cap: each pass adds one vertex or stops, so there are fewer passes than vertices.
    for (int pass = 0; pass < kEpa3MaxVertices; ++pass) {
      best = 0;
      for (int f = 1; f < poly.faceCount; ++f) {
        if (poly.faces[f].distance < poly.faces[best].distance) best = f;
      }
      const Face nearest = poly.faces[best];
      SupportPoint3 s = detail::support3(a, b, aFromB, nearest.normal);
      ++out.iterations;
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

      // Faces the new point sees, and their horizon: the directed edges of seen faces whose
      // reverse belongs to no seen face.
      int newIndex = poly.vertexCount;
      bool seen[kEpa3MaxFaces];
      int seenCount = 0;
      for (int f = 0; f < poly.faceCount; ++f) {
        const Face& face = poly.faces[f];
        seen[f] = f == best || dot(face.normal, s.w) - face.distance > 0.0f;
        seenCount += seen[f] ? 1 : 0;
      }
      int horizon[kEpa3MaxFaces][2];
      int horizonCount = 0;
      for (int f = 0; f < poly.faceCount; ++f) {
        if (!seen[f]) continue;
        for (int k = 0; k < 3; ++k) {
          int u = poly.faces[f].v[k], w = poly.faces[f].v[(k + 1) % 3];
          bool inner = false;
          for (int g = 0; g < poly.faceCount && !inner; ++g) {
            if (!seen[g]) continue;
            for (int j = 0; j < 3; ++j) {
              if (poly.faces[g].v[j] == w && poly.faces[g].v[(j + 1) % 3] == u) inner = true;
            }
          }
          if (!inner) {
            if (horizonCount == kEpa3MaxFaces) {
              horizonCount = -1;
              break;
            }
            horizon[horizonCount][0] = u;
            horizon[horizonCount][1] = w;
            ++horizonCount;
          }
        }
        if (horizonCount < 0) break;
      }
      // The horizon must be one loop: each vertex starts exactly one edge, and following
      // the edges from the first comes back after all of them.
      bool loop = horizonCount >= 3;
      if (loop) {
        int start = horizon[0][0], at = horizon[0][1], steps = 1;
        while (at != start && steps <= horizonCount) {
          int next = -1;
          for (int e = 0; e < horizonCount; ++e) {
            if (horizon[e][0] == at) {
              if (next >= 0)
                next = -2;  // two edges leave one vertex
              else
                next = e;
            }
          }
          if (next < 0) break;
          at = horizon[next][1];
          ++steps;
        }
        loop = at == start && steps == horizonCount;
      }
      if (!loop || poly.faceCount - seenCount + horizonCount > kEpa3MaxFaces) {
        out.status = loop ? Epa3Status::bufferFull : Epa3Status::gaveUp;
        break;
      }
      // Build the cone first (into spare slots), so a face with no normal leaves the
      // polytope as it was.
      poly.vertices[newIndex] = s;
      Face cone[kEpa3MaxFaces];
      bool ok = true;
      float size2New = maxf(size2, lengthSquared(s.w));
      for (int e = 0; e < horizonCount && ok; ++e)
        ok = makeFace(poly, horizon[e][0], horizon[e][1], newIndex, size2New, cone[e]);
      if (!ok) {
        out.status = Epa3Status::gaveUp;
        break;
      }
      ++poly.vertexCount;
      size2 = size2New;
      int kept = 0;
      for (int f = 0; f < poly.faceCount; ++f) {
        if (!seen[f]) poly.faces[kept++] = poly.faces[f];
      }
      for (int e = 0; e < horizonCount; ++e)
        poly.faces[kept++] = cone[e];
      poly.faceCount = kept;
    }
  }

  // The answer: the nearest face, the origin's projection on it in barycentric weights.
  best = 0;
  for (int f = 1; f < poly.faceCount; ++f) {
    if (poly.faces[f].distance < poly.faces[best].distance) best = f;
  }
  if (poly.faceCount == 0) {
    Vec3 pA, pB;
    detail::closestPoints3(gjk.simplex, pA, pB);
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

}  // namespace quack
