#include "quack/geometry/raycast.hpp"

#include <cmath>

#include "quack/geometry/bounds.hpp"

namespace quack {
namespace {

bool isUsable(const RayCastInput& ray) {
  return isFinite(ray.origin) && isFinite(ray.translation) && isFinite(ray.maxFraction) &&
         ray.maxFraction >= 0.0f && lengthSquared(ray.translation) > 0.0f;
}

// Entry of the ray into the disk (center, radius), assuming the origin is outside it.
RayHit rayCastDisk(Vec2 center, float radius, const RayCastInput& ray) {
  // Solve |o + t d - c|^2 = r^2 for the smaller root, in the form that avoids cancellation:
  // project the centre onto the ray, then step back by the half-chord.
  Vec2 d = ray.translation;
  float dd = lengthSquared(d);
  Vec2 s = ray.origin - center;
  float tClosest = -dot(s, d) / dd;
  Vec2 closest = s + tClosest * d;
  float h2 = radius * radius - lengthSquared(closest);
  if (h2 < 0.0f) return {};
  float t = tClosest - std::sqrt(h2 / dd);
  if (t < 0.0f || t > ray.maxFraction) return {};
  RayHit hit;
  hit.hit = true;
  hit.fraction = t;
  hit.point = ray.origin + t * d;
  hit.normal = normalize(hit.point - center);
  return hit;
}

// Cyrus-Beck clipping of the ray against the half-planes of a convex polygon. The entering
// edge is the one whose plane clips the lower bound last. Origin inside: no entering edge.
RayHit rayCastCore(const Polygon& polygon, const RayCastInput& ray) {
  float lower = 0.0f;
  float upper = ray.maxFraction;
  int entering = -1;
  for (int i = 0; i < polygon.count; ++i) {
    // Ray is in the half-plane where dot(n, p - v) <= 0.
    float numerator = dot(polygon.normals[i], polygon.vertices[i] - ray.origin);
    float denominator = dot(polygon.normals[i], ray.translation);
    if (denominator == 0.0f) {
      if (numerator < 0.0f) return {};  // parallel and outside this edge
      continue;
    }
    float t = numerator / denominator;
    if (denominator < 0.0f) {
      if (t > lower) {
        lower = t;
        entering = i;
      }
    } else if (t < upper) {
      upper = t;
    }
    if (upper < lower) return {};
  }
  if (entering < 0) return {};
  RayHit hit;
  hit.hit = true;
  hit.fraction = lower;
  hit.point = ray.origin + lower * ray.translation;
  hit.normal = polygon.normals[entering];
  return hit;
}

// Entry into a rounded convex shape: edges offset outward by `radius` and a disk at every
// vertex. With two vertices (normals n and -n) this is a capsule.
RayHit rayCastRounded(const Vec2* vertices, const Vec2* normals, int count, float radius,
                      const RayCastInput& ray) {
  RayHit best;
  best.fraction = ray.maxFraction;
  for (int i = 0; i < count; ++i) {
    Vec2 n = normals[i];
    Vec2 a = vertices[i] + radius * n;
    Vec2 b = vertices[(i + 1) % count] + radius * n;
    float denominator = dot(n, ray.translation);
    if (denominator < 0.0f) {
      float t = dot(n, a - ray.origin) / denominator;
      if (t >= 0.0f && t <= best.fraction) {
        Vec2 p = ray.origin + t * ray.translation;
        Vec2 edge = b - a;
        float u = dot(p - a, edge);
        if (u >= 0.0f && u <= lengthSquared(edge)) {
          best = {true, t, p, n};
        }
      }
    }
    RayCastInput clipped = ray;
    clipped.maxFraction = best.fraction;
    RayHit corner = rayCastDisk(vertices[i], radius, clipped);
    if (corner.hit && corner.fraction <= best.fraction) best = corner;
  }
  return best.hit ? best : RayHit{};
}

}  // namespace

RayHit rayCast(const Circle& circle, const RayCastInput& ray) noexcept {
  if (!isUsable(ray) || containsPoint(circle, ray.origin)) return {};
  return rayCastDisk(circle.center, circle.radius, ray);
}

RayHit rayCast(const Capsule& capsule, const RayCastInput& ray) noexcept {
  if (!isUsable(ray) || containsPoint(capsule, ray.origin)) return {};
  Vec2 n = normalize(rightPerp(capsule.p2 - capsule.p1));
  const Vec2 vertices[2] = {capsule.p1, capsule.p2};
  const Vec2 normals[2] = {n, -n};
  return rayCastRounded(vertices, normals, 2, capsule.radius, ray);
}

RayHit rayCast(const Segment& segment, const RayCastInput& ray) noexcept {
  if (!isUsable(ray)) return {};
  Vec2 e = segment.p2 - segment.p1;
  Vec2 d = ray.translation;
  float denominator = cross(d, e);
  if (denominator == 0.0f) return {};  // parallel (or collinear): no crossing point
  Vec2 s = segment.p1 - ray.origin;
  float t = cross(s, e) / denominator;  // along the ray
  float u = cross(s, d) / denominator;  // along the segment
  if (t < 0.0f || t > ray.maxFraction || u < 0.0f || u > 1.0f) return {};
  Vec2 n = normalize(rightPerp(e));
  if (dot(n, d) > 0.0f) n = -n;  // two-sided: face the incoming ray
  return {true, t, ray.origin + t * d, n};
}

RayHit rayCast(const Polygon& polygon, const RayCastInput& ray) noexcept {
  if (!isUsable(ray) || containsPoint(polygon, ray.origin)) return {};
  if (polygon.radius == 0.0f) return rayCastCore(polygon, ray);
  return rayCastRounded(polygon.vertices, polygon.normals, polygon.count, polygon.radius, ray);
}

RayHit rayCast(const ShapeGeometry& geometry, const RayCastInput& ray) noexcept {
  return std::visit([&](const auto& shape) { return rayCast(shape, ray); }, geometry);
}

}  // namespace quack
