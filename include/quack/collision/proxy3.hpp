#pragma once
/// Support proxies for the 3D shapes: "the convex hull of a few points, grown by a radius",
/// as in 2D (proxy.hpp). A sphere is one point plus its radius, a capsule two points plus
/// its radius, a triangle its three points, a hull (a box included) its vertices plus its
/// rounding radius.

#include <bit>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "quack/geometry/shapes3.hpp"

namespace quack {

/// Points plus radius, shape frame. Up to three points are copied into the proxy (spheres,
/// capsules, triangles: safe to copy); a hull proxy views the hull's vertex array, so the
/// hull must outlive it. Precondition of every use: 1 <= count() <= kMaxHullVertices3,
/// radius >= 0, all finite (the make* functions and makeProxy guarantee it).
class ShapeProxy3 {
 public:
  ShapeProxy3() = default;

  /// A proxy of `count` points (shape frame) and `radius` metres; with count <= 3 the points
  /// are copied, with more the proxy views `points`, which must outlive it. `center` is a
  /// point inside the core (GJK starts its search from the centres' difference).
  static ShapeProxy3 fromPoints(const Vec3* points, int count, float radius, Vec3 center) noexcept;
  /// As above with the mean of the points as the centre.
  static ShapeProxy3 fromPoints(const Vec3* points, int count, float radius) noexcept;

  /// The core points, shape frame.
  const Vec3* points() const noexcept { return external_ != nullptr ? external_ : local_; }
  int count() const noexcept { return count_; }
  /// Rounding radius, metres.
  float radius() const noexcept { return radius_; }
  /// A point inside the core, shape frame.
  Vec3 center() const noexcept { return center_; }

 private:
  Vec3 local_[3];
  const Vec3* external_ = nullptr;
  Vec3 center_;
  int count_ = 0;
  float radius_ = 0.0f;
};

/// The proxy of each 3D shape (shape frame). The hull overload views `hull`.
ShapeProxy3 makeProxy(const Sphere& sphere) noexcept;
ShapeProxy3 makeProxy(const Capsule3& capsule) noexcept;
ShapeProxy3 makeProxy(const Triangle3& triangle) noexcept;
ShapeProxy3 makeProxy(const Hull3& hull) noexcept;
/// The proxy of a 3D shape of any kind; it views the hull a hull geometry holds, so keep
/// `geometry` alive and unmoved while the proxy is in use.
ShapeProxy3 makeProxy(const ShapeGeometry3& geometry) noexcept;

namespace detail {

// Index of the first maximum of dot(points[i], direction) over `count` points: the same
// answer as scanning with a strict `>`, four points at a time and branch-free (the 3D twin
// of proxy.hpp's findFirstMaxDot). Each group of four points is loaded as three rows and
// turned into x, y and z lanes in registers; the dot products are formed as dot() forms
// them (x * dx + y * dy + z * dz, no fused multiply-add), so the values, and therefore the
// index, are the scalar loop's.
inline int findFirstMaxDot3(const Vec3* points, int count, Vec3 direction) noexcept {
#if defined(__SSE2__)
  static_assert(sizeof(Vec3) == 3 * sizeof(float));
  if (count >= 4) {
    const __m128 dx = _mm_set1_ps(direction.x);
    const __m128 dy = _mm_set1_ps(direction.y);
    const __m128 dz = _mm_set1_ps(direction.z);
    auto dots = [&](int i) {
      const float* f = &points[i].x;
      const __m128 r0 = _mm_loadu_ps(f);                                   // x0 y0 z0 x1
      const __m128 r1 = _mm_loadu_ps(f + 4);                               // y1 z1 x2 y2
      const __m128 r2 = _mm_loadu_ps(f + 8);                               // z2 x3 y3 z3
      const __m128 x23 = _mm_shuffle_ps(r1, r2, _MM_SHUFFLE(1, 1, 2, 2));  // x2 x2 x3 x3
      const __m128 xs = _mm_shuffle_ps(r0, x23, _MM_SHUFFLE(2, 0, 3, 0));
      const __m128 y01 = _mm_shuffle_ps(r0, r1, _MM_SHUFFLE(0, 0, 1, 1));  // y0 y0 y1 y1
      const __m128 y23 = _mm_shuffle_ps(r1, r2, _MM_SHUFFLE(2, 2, 3, 3));  // y2 y2 y3 y3
      const __m128 ys = _mm_shuffle_ps(y01, y23, _MM_SHUFFLE(2, 0, 2, 0));
      const __m128 z01 = _mm_shuffle_ps(r0, r1, _MM_SHUFFLE(1, 1, 2, 2));  // z0 z0 z1 z1
      const __m128 z23 = _mm_shuffle_ps(r2, r2, _MM_SHUFFLE(3, 3, 0, 0));  // z2 z2 z3 z3
      const __m128 zs = _mm_shuffle_ps(z01, z23, _MM_SHUFFLE(2, 0, 2, 0));
      return _mm_add_ps(_mm_add_ps(_mm_mul_ps(xs, dx), _mm_mul_ps(ys, dy)), _mm_mul_ps(zs, dz));
    };
    auto spread = [](__m128 m) {  // every lane the maximum of the four
      m = _mm_max_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(2, 3, 0, 1)));
      return _mm_max_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
    };
    // Groups of four; a count that is not a multiple of four ends with a group that
    // overlaps the one before (a point seen twice changes neither the maximum nor the
    // first index that attains it).
    const int last = count - 4;
    if (count <= 8) {
      const __m128 first = dots(0);
      const __m128 second = dots(last);
      const __m128 best = spread(_mm_max_ps(second, first));
      const unsigned hits =
          (static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(second, best))) << last) |
          static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(first, best)));
      return hits == 0 ? 0 : std::countr_zero(hits);
    }
    // Larger hulls: each group's products kept for the second pass.
    __m128 value[(kMaxHullVertices3 + 3) / 4];
    const int groups = (count + 3) / 4;
    __m128 best = value[groups - 1] = dots(last);
    for (int g = 0; g < groups - 1; ++g) {
      value[g] = dots(4 * g);
      best = _mm_max_ps(best, value[g]);
    }
    best = spread(best);
    std::uint64_t hits =
        static_cast<std::uint64_t>(_mm_movemask_ps(_mm_cmpeq_ps(value[groups - 1], best))) << last;
    for (int g = 0; g < groups - 1; ++g)
      hits |= static_cast<std::uint64_t>(_mm_movemask_ps(_mm_cmpeq_ps(value[g], best))) << (4 * g);
    return hits == 0 ? 0 : std::countr_zero(hits);
  }
#endif
  int best = 0;
  float bestValue = dot(points[0], direction);
  for (int i = 1; i < count; ++i) {
    float value = dot(points[i], direction);
    if (value > bestValue) {
      best = i;
      bestValue = value;
    }
  }
  return best;
}

}  // namespace detail

/// Index of the proxy point furthest along `direction` (shape frame, any length); the lowest
/// such index on a tie, so the answer is deterministic. A zero direction gives 0.
inline int findSupport(const ShapeProxy3& proxy, Vec3 direction) noexcept {
  return detail::findFirstMaxDot3(proxy.points(), proxy.count(), direction);
}

}  // namespace quack
