#pragma once
/// Support proxies: every convex shape seen by GJK and EPA as "the convex hull of a few
/// points, grown by a radius".
///
/// A circle is one point plus its radius, a capsule two points plus its radius, a segment
/// two points and radius 0, a polygon its vertices plus its rounding radius. GJK and EPA
/// work on the hull of the points (the "core") and add the radius at the end, the approach
/// of van den Bergen ("Collision Detection in Interactive 3D Environments", 2003, sec. 4.3)
/// and of Catto's GDC 2010 GJK talk.

#include <bit>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "quack/core/assert.hpp"
#include "quack/geometry/shapes.hpp"

namespace quack {

/// Points plus radius, in the shape frame. The points of a polygon proxy are a view into
/// the polygon's vertex array (no copy), so the polygon must outlive the proxy; circles,
/// capsules and segments copy their one or two points into the proxy itself, so a proxy is
/// safe to copy. Precondition of every use: 1 <= count() <= kMaxPolygonVertices, the points
/// in convex position or fewer than three, radius >= 0, all finite (the make* functions
/// and `makeProxy` guarantee this).
class ShapeProxy {
 public:
  ShapeProxy() = default;

  /// A proxy of `count` points (shape frame) and `radius` metres. With count <= 2 the
  /// points are copied; with more, the proxy views `points`, which must outlive it.
  static ShapeProxy fromPoints(const Vec2* points, int count, float radius) noexcept;
  /// As above with a given `center` (shape frame), a point inside the core. Inline, as is
  /// the polygon's makeProxy: the narrow phase makes two proxies a query, and out of line
  /// the calls cost as much as the work.
  static ShapeProxy fromPoints(const Vec2* points, int count, float radius, Vec2 center) noexcept {
    QUACK_ASSERT(count >= 1 && count <= kMaxPolygonVertices);
    ShapeProxy proxy;
    proxy.count_ = count;
    proxy.radius_ = radius;
    if (count <= 2) {
      for (int i = 0; i < count; ++i)
        proxy.local_[i] = points[i];
    } else {
      proxy.external_ = points;
    }
    proxy.center_ = center;
    return proxy;
  }

  /// The core points, shape frame.
  const Vec2* points() const noexcept { return external_ != nullptr ? external_ : local_; }
  int count() const noexcept { return count_; }
  /// Rounding radius, metres.
  float radius() const noexcept { return radius_; }
  /// A point inside the core (the mean of the points; the centroid for polygons), shape
  /// frame. GJK starts its search from it and EPA breaks ties with it.
  Vec2 center() const noexcept { return center_; }

 private:
  Vec2 local_[2];
  const Vec2* external_ = nullptr;
  Vec2 center_;
  int count_ = 0;
  float radius_ = 0.0f;
};

/// The proxy of each shape (shape frame). The polygon overload views `polygon`.
ShapeProxy makeProxy(const Circle& circle) noexcept;
ShapeProxy makeProxy(const Capsule& capsule) noexcept;
ShapeProxy makeProxy(const Segment& segment) noexcept;
inline ShapeProxy makeProxy(const Polygon& polygon) noexcept {
  return ShapeProxy::fromPoints(polygon.vertices, polygon.count, polygon.radius, polygon.centroid);
}
/// The proxy of a shape of any kind; it views the polygon a polygon geometry holds, so keep
/// `geometry` alive and unmoved while the proxy is in use.
ShapeProxy makeProxy(const ShapeGeometry& geometry) noexcept;

namespace detail {

#if defined(__SSE2__)
// Index of the first maximum over two groups of four products, the second group starting
// at point `last` (overlapping the first when there are fewer than eight points: a point
// seen twice changes neither the maximum nor the first index that attains it).
[[gnu::always_inline]] inline int firstMaxOfTwoGroups(__m128 first, __m128 second,
                                                      int last) noexcept {
  __m128 best = _mm_max_ps(second, first);
  best = _mm_max_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(2, 3, 0, 1)));
  best = _mm_max_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(1, 0, 3, 2)));
  const unsigned hits =
      (static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(second, best))) << last) |
      static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(first, best)));
  return hits == 0 ? 0 : std::countr_zero(hits);
}
#endif

// Index of the first maximum of dot(points[i], direction) over `count` points: the same
// answer as scanning with a strict `>`, computed branch-free. A scan's `value > best` is
// taken at random places for random directions, and its mispredictions cost more than
// the arithmetic (callgrind's branch simulation on the narrow-phase benchmark). The dot
// products are formed exactly as dot() forms them (x * dx + y * dy, no fused multiply-add),
// so the values, and therefore the index, are the scalar loop's. NaN values (outside the
// preconditions) still give an index in range.
inline int findFirstMaxDot(const Vec2* points, int count, Vec2 direction) noexcept {
#if defined(__SSE2__)
  static_assert(sizeof(Vec2) == 2 * sizeof(float));
  if (count >= 4) {
    const __m128 dx = _mm_set1_ps(direction.x);
    const __m128 dy = _mm_set1_ps(direction.y);
    auto dots = [&](int i) {
      __m128 lo = _mm_loadu_ps(&points[i].x);      // x0 y0 x1 y1
      __m128 hi = _mm_loadu_ps(&points[i + 2].x);  // x2 y2 x3 y3
      __m128 xs = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));
      __m128 ys = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1));
      return _mm_add_ps(_mm_mul_ps(xs, dx), _mm_mul_ps(ys, dy));
    };
    // Groups of four; a count that is not a multiple of four ends with a group that
    // overlaps the one before (a point seen twice changes neither the maximum nor the
    // first index that attains it).
    const int last = count - 4;
    if (count <= 8) {
      // Boxes and the usual polygons: one or two groups, each formed once, no loop (the
      // same maximum, compared in the same order, as the loop below).
      return firstMaxOfTwoGroups(dots(0), dots(last), last);
    }
    __m128 best = dots(last);
    for (int i = 0; i < last; i += 4)
      best = _mm_max_ps(best, dots(i));
    best = _mm_max_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(2, 3, 0, 1)));
    best = _mm_max_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(1, 0, 3, 2)));
    std::uint64_t hits = static_cast<std::uint64_t>(_mm_movemask_ps(_mm_cmpeq_ps(dots(last), best)))
                         << last;
    for (int i = 0; i < last; i += 4)
      hits |= static_cast<std::uint64_t>(_mm_movemask_ps(_mm_cmpeq_ps(dots(i), best))) << i;
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

// findFirstMaxDot over one point set searched many times (GJK's loop searches each proxy
// two to four times a query): a polygon of 4 to 8 points has its one or two groups of four
// split into x and y columns once, here, rather than at every search. The products, the
// maximum and the index are formed as findFirstMaxDot forms them, so the same answer.
class PointSearch {
 public:
  PointSearch(const Vec2* points, int count) noexcept : points_(points), count_(count) {
#if defined(__SSE2__)
    columns_ = count >= 4 && count <= 8;
    last_ = columns_ ? count - 4 : 0;
    if (columns_) {
      loadColumns(0, xs0_, ys0_);
      loadColumns(last_, xs1_, ys1_);
    } else {
      xs0_ = ys0_ = xs1_ = ys1_ = _mm_setzero_ps();  // unused
    }
#endif
  }

  [[gnu::always_inline]] int findFirstMaxDot(Vec2 direction) const noexcept {
#if defined(__SSE2__)
    if (columns_) {
      const __m128 dx = _mm_set1_ps(direction.x);
      const __m128 dy = _mm_set1_ps(direction.y);
      return firstMaxOfTwoGroups(_mm_add_ps(_mm_mul_ps(xs0_, dx), _mm_mul_ps(ys0_, dy)),
                                 _mm_add_ps(_mm_mul_ps(xs1_, dx), _mm_mul_ps(ys1_, dy)), last_);
    }
#endif
    return detail::findFirstMaxDot(points_, count_, direction);
  }

  /// True when the points are held as columns (4 to 8 points, SSE2): then
  /// findFirstMaxAndMinDot may be called.
  bool hasColumns() const noexcept {
#if defined(__SSE2__)
    return columns_;
#else
    return false;
#endif
  }

  /// findFirstMaxDot(direction) and findFirstMaxDot(-direction) from one set of products:
  /// the products along -direction are those along direction negated (exactly; a zero may
  /// change sign, which no comparison sees), so the first of the least is the second answer.
  /// Only with hasColumns().
  [[gnu::always_inline]] void findFirstMaxAndMinDot(Vec2 direction, int& maxIndex,
                                                    int& minIndex) const noexcept {
#if defined(__SSE2__)
    const __m128 dx = _mm_set1_ps(direction.x);
    const __m128 dy = _mm_set1_ps(direction.y);
    const __m128 first = _mm_add_ps(_mm_mul_ps(xs0_, dx), _mm_mul_ps(ys0_, dy));
    const __m128 second = _mm_add_ps(_mm_mul_ps(xs1_, dx), _mm_mul_ps(ys1_, dy));
    __m128 most = _mm_max_ps(second, first);
    __m128 least = _mm_min_ps(second, first);
    most = _mm_max_ps(most, _mm_shuffle_ps(most, most, _MM_SHUFFLE(2, 3, 0, 1)));
    least = _mm_min_ps(least, _mm_shuffle_ps(least, least, _MM_SHUFFLE(2, 3, 0, 1)));
    most = _mm_max_ps(most, _mm_shuffle_ps(most, most, _MM_SHUFFLE(1, 0, 3, 2)));
    least = _mm_min_ps(least, _mm_shuffle_ps(least, least, _MM_SHUFFLE(1, 0, 3, 2)));
    const unsigned mostHits =
        (static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(second, most))) << last_) |
        static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(first, most)));
    const unsigned leastHits =
        (static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(second, least))) << last_) |
        static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(first, least)));
    maxIndex = mostHits == 0 ? 0 : std::countr_zero(mostHits);
    minIndex = leastHits == 0 ? 0 : std::countr_zero(leastHits);
#else
    maxIndex = detail::findFirstMaxDot(points_, count_, direction);
    minIndex = detail::findFirstMaxDot(points_, count_, -direction);
#endif
  }

 private:
#if defined(__SSE2__)
  void loadColumns(int i, __m128& xs, __m128& ys) const noexcept {
    const __m128 lo = _mm_loadu_ps(&points_[i].x);      // x0 y0 x1 y1
    const __m128 hi = _mm_loadu_ps(&points_[i + 2].x);  // x2 y2 x3 y3
    xs = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));
    ys = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1));
  }

  // Set by the constructor (zeros unless columns_), not by initialisers, so that the
  // usual polygon stores each column once.
  __m128 xs0_, ys0_, xs1_, ys1_;
  int last_ = 0;
  bool columns_ = false;
#endif
  const Vec2* points_;
  int count_;
};

}  // namespace detail

/// Index of the proxy point furthest along `direction` (shape frame, any length); the
/// lowest such index on a tie, so the answer is deterministic. A zero direction gives 0.
inline int findSupport(const ShapeProxy& proxy, Vec2 direction) noexcept {
  return detail::findFirstMaxDot(proxy.points(), proxy.count(), direction);
}

}  // namespace quack
