#pragma once
/// Internal: the 3D box operations the 3D broad phase needs beyond those of
/// `quack/math/vec3.hpp` (growing, sweeping and ray-casting an `Aabb3`). Not part of the
/// public interface; names end in 3 so that they never collide, through argument-dependent
/// lookup, with operations the math layer may add on `Aabb3` later.

#include "quack/math/aabb.hpp"
#include "quack/math/vec3.hpp"

namespace quack::detail {

/// `a` grown by `margin` metres on every side (margin >= 0).
constexpr Aabb3 inflate3(Aabb3 a, float margin) noexcept {
  const Vec3 m{margin, margin, margin};
  return {a.lower - m, a.upper + m};
}

/// `a` grown by the half-extents `h` (each >= 0): the box a moving box of half-extents `h`
/// must reach with its centre to touch `a`.
constexpr Aabb3 grow3(Aabb3 a, Vec3 h) noexcept {
  return {a.lower - h, a.upper + h};
}

/// The box swept by `a` moving by `d` (the union of a and a + d).
constexpr Aabb3 sweep3(Aabb3 a, Vec3 d) noexcept {
  return {minv(a.lower, a.lower + d), maxv(a.upper, a.upper + d)};
}

/// A ray `origin + t * translation` prepared for many slab tests: the reciprocal of each
/// translation component is formed once (it is the same float as `1.0f / d` formed in each
/// test, so the answers are those of a test that divides every time).
struct Ray3 {
  Vec3 origin;
  Vec3 translation;
  Vec3 inverse;  ///< 1 / translation per axis; unused where the component is 0

  /// The ray from `o` along `t` (any finite values; a zero component is handled apart).
  Ray3(Vec3 o, Vec3 t) noexcept
      : origin(o),
        translation(t),
        inverse{t.x != 0.0f ? 1.0f / t.x : 0.0f, t.y != 0.0f ? 1.0f / t.y : 0.0f,
                t.z != 0.0f ? 1.0f / t.z : 0.0f} {}
};

/// Slab test of `ray`, t in [0, maxFraction], against `a` (the 3D `rayCast` of
/// quack/math/aabb.hpp, axis by axis the same arithmetic). A ray starting inside hits at 0.
///
/// Monotone under containment: every rounding step (a subtraction, a product by the fixed
/// reciprocal, min, max) is monotone, so when `a` holds `b` the entry interval found for `a`
/// holds the one found for `b`. A tree that prunes with this test therefore never drops a
/// box that the same test, run on the box alone, reports as hit.
inline AabbRayHit rayCast3(Aabb3 a, const Ray3& ray, float maxFraction) noexcept {
  float tmin = 0.0f;
  float tmax = maxFraction;
  const float o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
  const float d[3] = {ray.translation.x, ray.translation.y, ray.translation.z};
  const float inv[3] = {ray.inverse.x, ray.inverse.y, ray.inverse.z};
  const float lo[3] = {a.lower.x, a.lower.y, a.lower.z};
  const float hi[3] = {a.upper.x, a.upper.y, a.upper.z};
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0f) {
      if (o[i] < lo[i] || o[i] > hi[i]) return {};
      continue;
    }
    float t1 = (lo[i] - o[i]) * inv[i];
    float t2 = (hi[i] - o[i]) * inv[i];
    if (t1 > t2) {
      const float tmp = t1;
      t1 = t2;
      t2 = tmp;
    }
    tmin = maxf(tmin, t1);
    tmax = minf(tmax, t2);
    if (tmin > tmax) return {};
  }
  return {true, tmin};
}

/// The same test for a ray given by origin and translation.
inline AabbRayHit rayCast3(Aabb3 a, Vec3 origin, Vec3 translation,
                           float maxFraction = 1.0f) noexcept {
  return rayCast3(a, Ray3(origin, translation), maxFraction);
}

}  // namespace quack::detail
