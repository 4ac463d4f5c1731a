#pragma once
/// `Aabb`: an axis-aligned bounding box, closed on all sides.

#include "quack/math/vec2.hpp"

namespace quack {

/// The coordinate limit, metres: shapes (geometry), broad-phase boxes and `quack query`
/// inputs must lie within +-kMaxCoordinate of the origin. Beyond it a float cannot tell
/// centimetres apart anyway (its spacing is 64 m at 1e9), the squares the collision
/// routines form stay far from overflow (1e18 << 3.4e38), and cell indices of the quadtree
/// and hash stay well inside their integers.
inline constexpr float kMaxCoordinate = 1.0e9f;
/// True when both coordinates of p lie within +-kMaxCoordinate (false for NaN).
constexpr bool withinCoordinateLimit(Vec2 p) noexcept {
  return p.x >= -kMaxCoordinate && p.x <= kMaxCoordinate && p.y >= -kMaxCoordinate &&
         p.y <= kMaxCoordinate;
}

/// Axis-aligned box [lower, upper]. A valid box has lower <= upper on both axes; the
/// default box is the degenerate box at the origin.
struct Aabb {
  Vec2 lower;
  Vec2 upper;

  friend constexpr bool operator==(Aabb, Aabb) noexcept = default;
};

/// lower <= upper on both axes and every coordinate finite (NaN fails the comparison).
inline bool isValid(Aabb a) noexcept {
  return isFinite(a.lower) && isFinite(a.upper) && a.lower.x <= a.upper.x && a.lower.y <= a.upper.y;
}
/// True when the closed boxes share at least one point (touching counts).
constexpr bool overlaps(Aabb a, Aabb b) noexcept {
  return !(b.lower.x > a.upper.x || b.lower.y > a.upper.y || a.lower.x > b.upper.x ||
           a.lower.y > b.upper.y);
}
/// True when `inner` lies inside `outer` (boundaries may coincide).
constexpr bool contains(Aabb outer, Aabb inner) noexcept {
  return outer.lower.x <= inner.lower.x && outer.lower.y <= inner.lower.y &&
         inner.upper.x <= outer.upper.x && inner.upper.y <= outer.upper.y;
}
/// True when point p lies in the closed box.
constexpr bool contains(Aabb a, Vec2 p) noexcept {
  return a.lower.x <= p.x && p.x <= a.upper.x && a.lower.y <= p.y && p.y <= a.upper.y;
}
/// The smallest box holding both.
constexpr Aabb merge(Aabb a, Aabb b) noexcept {
  return {minv(a.lower, b.lower), maxv(a.upper, b.upper)};
}
/// The smallest box holding a and p.
constexpr Aabb merge(Aabb a, Vec2 p) noexcept {
  return {minv(a.lower, p), maxv(a.upper, p)};
}
constexpr Vec2 center(Aabb a) noexcept {
  return 0.5f * (a.lower + a.upper);
}
constexpr Vec2 extents(Aabb a) noexcept {
  return 0.5f * (a.upper - a.lower);
}
/// Perimeter: the 2D "surface area" used by the surface-area heuristic.
constexpr float perimeter(Aabb a) noexcept {
  return 2.0f * ((a.upper.x - a.lower.x) + (a.upper.y - a.lower.y));
}
constexpr float area(Aabb a) noexcept {
  return (a.upper.x - a.lower.x) * (a.upper.y - a.lower.y);
}
/// a grown by `margin` on every side.
constexpr Aabb inflate(Aabb a, float margin) noexcept {
  return {{a.lower.x - margin, a.lower.y - margin}, {a.upper.x + margin, a.upper.y + margin}};
}
/// The box swept by a moving by `d` (the union of a and a + d).
constexpr Aabb sweep(Aabb a, Vec2 d) noexcept {
  return {minv(a.lower, a.lower + d), maxv(a.upper, a.upper + d)};
}
/// The intersection; invalid (lower > upper) when the boxes are apart.
constexpr Aabb intersect(Aabb a, Aabb b) noexcept {
  return {maxv(a.lower, b.lower), minv(a.upper, b.upper)};
}

/// Result of a ray against a box: the entry fraction along the ray.
struct AabbRayHit {
  bool hit = false;
  float fraction = 0.0f;  ///< in [0, maxFraction]; 0 when the origin is inside
};

/// Slab test of the ray `origin + t * translation`, t in [0, maxFraction], against a.
/// A ray starting inside the box hits at fraction 0.
inline AabbRayHit rayCast(Aabb a, Vec2 origin, Vec2 translation,
                          float maxFraction = 1.0f) noexcept {
  float tmin = 0.0f;
  float tmax = maxFraction;
  const float o[2] = {origin.x, origin.y};
  const float d[2] = {translation.x, translation.y};
  const float lo[2] = {a.lower.x, a.lower.y};
  const float hi[2] = {a.upper.x, a.upper.y};
  for (int i = 0; i < 2; ++i) {
    if (d[i] == 0.0f) {
      if (o[i] < lo[i] || o[i] > hi[i]) return {};
      continue;
    }
    float inv = 1.0f / d[i];
    float t1 = (lo[i] - o[i]) * inv;
    float t2 = (hi[i] - o[i]) * inv;
    if (t1 > t2) {
      float tmp = t1;
      t1 = t2;
      t2 = tmp;
    }
    tmin = maxf(tmin, t1);
    tmax = minf(tmax, t2);
    if (tmin > tmax) return {};
  }
  return {true, tmin};
}

}  // namespace quack
