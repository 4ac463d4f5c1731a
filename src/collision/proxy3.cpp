#include "quack/collision/proxy3.hpp"

namespace quack {

ShapeProxy3 ShapeProxy3::fromPoints(const Vec3* points, int count, float radius,
                                    Vec3 center) noexcept {
  QUACK_ASSERT(count >= 1 && count <= kMaxHullVertices3);
  ShapeProxy3 proxy;
  proxy.count_ = count;
  proxy.radius_ = radius;
  if (count <= 3) {
    for (int i = 0; i < count; ++i)
      proxy.local_[i] = points[i];
  } else {
    proxy.external_ = points;
  }
  proxy.center_ = center;
  return proxy;
}

ShapeProxy3 ShapeProxy3::fromPoints(const Vec3* points, int count, float radius) noexcept {
  Vec3 sum;
  for (int i = 0; i < count; ++i)
    sum += points[i];
  return fromPoints(points, count, radius, (1.0f / static_cast<float>(count)) * sum);
}

ShapeProxy3 makeProxy(const Sphere& sphere) noexcept {
  return ShapeProxy3::fromPoints(&sphere.center, 1, sphere.radius);
}

ShapeProxy3 makeProxy(const Capsule3& capsule) noexcept {
  const Vec3 points[2] = {capsule.p1, capsule.p2};
  return ShapeProxy3::fromPoints(points, 2, capsule.radius);
}

ShapeProxy3 makeProxy(const Triangle3& triangle) noexcept {
  return ShapeProxy3::fromPoints(triangle.v, 3, 0.0f);
}

ShapeProxy3 makeProxy(const Hull3& hull) noexcept {
  return ShapeProxy3::fromPoints(hull.vertices, hull.vertexCount, hull.radius, hull.centroid);
}

ShapeProxy3 makeProxy(const ShapeGeometry3& geometry) noexcept {
  return std::visit([](const auto& shape) { return makeProxy(shape); }, geometry);
}

}  // namespace quack
