#pragma once
/// Support proxies for the 3D shapes: "the convex hull of a few points, grown by a radius",
/// as in 2D (proxy.hpp). A sphere is one point plus its radius, a capsule two points plus
/// its radius, a triangle its three points, a hull (a box included) its vertices plus its
/// rounding radius.

#include <cstdint>

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

/// Index of the proxy point furthest along `direction` (shape frame, any length); the lowest
/// such index on a tie, so the answer is deterministic. A zero direction gives 0.
inline int findSupport(const ShapeProxy3& proxy, Vec3 direction) noexcept {
  const Vec3* p = proxy.points();
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
