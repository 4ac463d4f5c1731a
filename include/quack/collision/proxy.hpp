#pragma once
/// Support proxies: every convex shape seen by GJK and EPA as "the convex hull of a few
/// points, grown by a radius".
///
/// A circle is one point plus its radius, a capsule two points plus its radius, a segment
/// two points and radius 0, a polygon its vertices plus its rounding radius. GJK and EPA
/// work on the hull of the points (the "core") and add the radius at the end, the approach
/// of van den Bergen ("Collision Detection in Interactive 3D Environments", 2003, sec. 4.3)
/// and of Catto's GDC 2010 GJK talk.

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
  /// As above with a given `center` (shape frame), a point inside the core.
  static ShapeProxy fromPoints(const Vec2* points, int count, float radius, Vec2 center) noexcept;

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
ShapeProxy makeProxy(const Polygon& polygon) noexcept;

/// Index of the proxy point furthest along `direction` (shape frame, any length); the
/// lowest such index on a tie, so the answer is deterministic. A zero direction gives 0.
inline int findSupport(const ShapeProxy& proxy, Vec2 direction) noexcept {
  const Vec2* p = proxy.points();
  int best = 0;
  float bestValue = dot(p[0], direction);
  for (int i = 1; i < proxy.count(); ++i) {
    float value = dot(p[i], direction);
    if (value > bestValue) {
      best = i;
      bestValue = value;
    }
  }
  return best;
}

}  // namespace quack
