#include "quack/geometry/raycast3.hpp"

#include <cmath>
#include <limits>

namespace quack {
namespace {

// A ray is parallel to a triangle's plane (and misses it) when Moller-Trumbore's
// determinant is below this fraction of |e1||e2||d|: the sine of the angle between the ray
// and the plane, at about the float rounding of the determinant.
constexpr float kTriangleParallelRelative = 1e-7f;

bool validRay(const RayCastInput3& ray) {
  return isFinite(ray.origin) && isFinite(ray.translation) && std::isfinite(ray.maxFraction) &&
         ray.maxFraction >= 0.0f && lengthSquared(ray.translation) > 0.0f;
}

RayHit3 makeHit(const RayCastInput3& ray, float t, Vec3 normal) {
  return {true, t, ray.origin + t * ray.translation, normal};
}

// Entry fraction of the ray into the sphere (c, r), or -1. The origin is taken relative to
// the centre and the quadratic is solved in the stable form (Ericson 5.3.2, with the
// half-b trick), so far-away spheres lose no more than their coordinates' rounding.
float sphereEntry(Vec3 origin, Vec3 d, Vec3 c, float r, float maxFraction) {
  Vec3 m = origin - c;
  float a = dot(d, d);
  float b = dot(m, d);
  float cc = dot(m, m) - r * r;
  if (cc <= 0.0f) return -1.0f;  // inside or on the surface: not entering
  if (b >= 0.0f) return -1.0f;   // moving away
  float disc = b * b - a * cc;
  if (disc < 0.0f) return -1.0f;
  float t = cc / (-b + std::sqrt(disc));  // = (-b - sqrt(disc)) / a, without cancellation
  if (t < 0.0f || t > maxFraction) return -1.0f;
  return t;
}

// Entry fraction of the ray into the side of the cylinder of radius r about the segment
// c + s u, s in [0, len] (u unit), or -1; `normal` gets the outward normal there. Only the
// curved side: a ray entering through an end disk enters the end's sphere first.
float cylinderEntry(Vec3 origin, Vec3 d, Vec3 c, Vec3 u, float len, float r, float maxFraction,
                    Vec3& normal) {
  Vec3 m = origin - c;
  Vec3 dPerp = d - dot(d, u) * u;
  Vec3 mPerp = m - dot(m, u) * u;
  float a = dot(dPerp, dPerp);
  float b = dot(mPerp, dPerp);
  float cc = dot(mPerp, mPerp) - r * r;
  if (!(a > 0.0f && cc > 0.0f && b < 0.0f)) return -1.0f;
  float disc = b * b - a * cc;
  if (disc < 0.0f) return -1.0f;
  float t = cc / (-b + std::sqrt(disc));
  if (t < 0.0f || t > maxFraction) return -1.0f;
  Vec3 q = m + t * d;
  float along = dot(q, u);
  if (along < 0.0f || along > len) return -1.0f;
  normal = normalize(q - along * u);
  return t;
}

// Whether `p` (shape frame) lies inside the face `f`'s polygon seen along its normal (on its
// side planes counts as inside).
bool insideFace(const Hull3& hull, const HullFace3& f, Vec3 p) {
  for (int k = 0; k < f.count; ++k) {
    Vec3 v0 = hull.vertices[hull.faceVertices[f.first + k]];
    Vec3 v1 = hull.vertices[hull.faceVertices[f.first + (k + 1) % f.count]];
    if (dot(cross(v1 - v0, f.normal), p - v0) > 0.0f) return false;
  }
  return true;
}

// Squared distance from `p` to the hull's core (0 inside): outside, the nearest point is on
// a face, found over each face the point projects into and each edge.
float coreDistanceSquared(const Hull3& hull, Vec3 p) {
  bool inside = true;
  float best = std::numeric_limits<float>::infinity();
  for (int f = 0; f < hull.faceCount; ++f) {
    const HullFace3& face = hull.faces[f];
    float h = dot(face.normal, p) - face.offset;
    if (h <= 0.0f) continue;
    inside = false;
    if (insideFace(hull, face, p)) best = minf(best, h * h);
  }
  if (inside) return 0.0f;
  for (int e = 0; e < hull.edgeCount; ++e) {
    Vec3 a = hull.vertices[hull.edges[e].v0], b = hull.vertices[hull.edges[e].v1];
    Vec3 ab = b - a;
    float s = clampf(dot(p - a, ab) / dot(ab, ab), 0.0f, 1.0f);
    best = minf(best, lengthSquared(p - (a + s * ab)));
  }
  return best;
}

// A rounded hull: the nearest entry among the patches of its surface, each face's polygon
// lifted by the radius, each edge's cylinder, each vertex's sphere. Every point of those
// patches is within the radius of the core, and the surface is their union, so from an
// origin outside the solid the first patch hit is where the ray enters.
RayHit3 rayCastRounded(const Hull3& h, const RayCastInput3& ray) {
  const float r = h.radius;
  // Relative to the centroid, as the plain cast.
  const Vec3 c = h.centroid;
  const Vec3 o = ray.origin - c;
  const Vec3 d = ray.translation;
  if (coreDistanceSquared(h, ray.origin) <= r * r) return {};
  float best = -1.0f;
  Vec3 bestNormal;
  for (int f = 0; f < h.faceCount; ++f) {
    const HullFace3& face = h.faces[f];
    float den = dot(face.normal, d);
    if (den >= 0.0f) continue;
    float t = (face.offset - dot(face.normal, c) + r - dot(face.normal, o)) / den;
    if (t < 0.0f || t > ray.maxFraction || (best >= 0.0f && t >= best)) continue;
    if (!insideFace(h, face, ray.origin + t * d - r * face.normal)) continue;
    best = t;
    bestNormal = face.normal;
  }
  for (int e = 0; e < h.edgeCount; ++e) {
    Vec3 a = h.vertices[h.edges[e].v0] - c, b = h.vertices[h.edges[e].v1] - c;
    float len = length(b - a);
    Vec3 normal;
    float t = cylinderEntry(o, d, a, (1.0f / len) * (b - a), len, r, ray.maxFraction, normal);
    if (t >= 0.0f && (best < 0.0f || t < best)) {
      best = t;
      bestNormal = normal;
    }
  }
  for (int i = 0; i < h.vertexCount; ++i) {
    Vec3 v = h.vertices[i] - c;
    float t = sphereEntry(o, d, v, r, ray.maxFraction);
    if (t >= 0.0f && (best < 0.0f || t < best)) {
      best = t;
      bestNormal = normalize(o + t * d - v);
    }
  }
  if (best < 0.0f) return {};
  return makeHit(ray, best, bestNormal);
}

}  // namespace

RayHit3 rayCast(const Sphere& sphere, const RayCastInput3& ray) noexcept {
  if (!validRay(ray)) return {};
  float t = sphereEntry(ray.origin, ray.translation, sphere.center, sphere.radius, ray.maxFraction);
  if (t < 0.0f) return {};
  Vec3 p = ray.origin + t * ray.translation;
  return makeHit(ray, t, normalize(p - sphere.center));
}

RayHit3 rayCast(const Capsule3& capsule, const RayCastInput3& ray) noexcept {
  if (!validRay(ray)) return {};
  Vec3 axis = capsule.p2 - capsule.p1;
  float axisLen2 = dot(axis, axis);
  float r = capsule.radius;
  // Inside: distance from the origin to the segment at most r.
  Vec3 m = ray.origin - capsule.p1;
  float s = clampf(dot(m, axis) / axisLen2, 0.0f, 1.0f);
  if (lengthSquared(ray.origin - (capsule.p1 + s * axis)) <= r * r) return {};

  float best = -1.0f;
  Vec3 bestNormal;
  Vec3 d = ray.translation;
  float len = std::sqrt(axisLen2);
  float side = cylinderEntry(ray.origin, d, capsule.p1, (1.0f / len) * axis, len, r,
                             ray.maxFraction, bestNormal);
  if (side >= 0.0f) best = side;
  for (Vec3 end : {capsule.p1, capsule.p2}) {
    float t = sphereEntry(ray.origin, d, end, r, ray.maxFraction);
    if (t >= 0.0f && (best < 0.0f || t < best)) {
      best = t;
      bestNormal = normalize(ray.origin + t * d - end);
    }
  }
  if (best < 0.0f) return {};
  return makeHit(ray, best, bestNormal);
}

RayHit3 rayCast(const Hull3& hull, const RayCastInput3& ray) noexcept {
  if (!validRay(ray)) return {};
  if (hull.radius > 0.0f) return rayCastRounded(hull, ray);
  // Cyrus-Beck, relative to the centroid so far-away hulls keep their precision.
  Vec3 o = ray.origin - hull.centroid;
  float lower = 0.0f, upper = ray.maxFraction;
  int face = -1;
  for (int f = 0; f < hull.faceCount; ++f) {
    const HullFace3& hf = hull.faces[f];
    float num = hf.offset - dot(hf.normal, hull.centroid) - dot(hf.normal, o);
    float den = dot(hf.normal, ray.translation);
    if (den == 0.0f) {
      if (num < 0.0f) return {};
      continue;
    }
    float t = num / den;
    if (den < 0.0f) {
      if (t > lower) {
        lower = t;
        face = f;
      }
    } else if (t < upper) {
      upper = t;
    }
    if (upper < lower) return {};
  }
  if (face < 0) return {};  // the origin is inside or on the boundary
  return makeHit(ray, lower, hull.faces[face].normal);
}

RayHit3 rayCast(const Triangle3& triangle, const RayCastInput3& ray) noexcept {
  if (!validRay(ray)) return {};
  Vec3 e1 = triangle.v[1] - triangle.v[0];
  Vec3 e2 = triangle.v[2] - triangle.v[0];
  Vec3 d = ray.translation;
  Vec3 p = cross(d, e2);
  float det = dot(e1, p);
  // Parallel to the plane (relative test: det is |e1||e2||d| sin sin).
  float scale = length(e1) * length(e2) * length(d);
  if (absf(det) <= kTriangleParallelRelative * scale) return {};
  float inv = 1.0f / det;
  Vec3 s = ray.origin - triangle.v[0];
  float u = dot(s, p) * inv;
  if (u < 0.0f || u > 1.0f) return {};
  Vec3 q = cross(s, e1);
  float v = dot(d, q) * inv;
  if (v < 0.0f || u + v > 1.0f) return {};
  float t = dot(e2, q) * inv;
  if (t < 0.0f || t > ray.maxFraction) return {};
  Vec3 n = normalize(cross(e1, e2));
  if (dot(n, d) > 0.0f) n = -n;
  return makeHit(ray, t, n);
}

RayHit3 rayCast(const ShapeGeometry3& geometry, const RayCastInput3& ray) noexcept {
  return std::visit([&ray](const auto& shape) { return rayCast(shape, ray); }, geometry);
}

}  // namespace quack
