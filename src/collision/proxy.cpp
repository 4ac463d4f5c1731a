#include "quack/collision/proxy.hpp"

namespace quack {

ShapeProxy ShapeProxy::fromPoints(const Vec2* points, int count, float radius) noexcept {
  Vec2 sum;
  for (int i = 0; i < count; ++i)
    sum += points[i];
  return fromPoints(points, count, radius, (1.0f / static_cast<float>(count)) * sum);
}

ShapeProxy makeProxy(const Circle& circle) noexcept {
  return ShapeProxy::fromPoints(&circle.center, 1, circle.radius);
}

ShapeProxy makeProxy(const Capsule& capsule) noexcept {
  const Vec2 points[2] = {capsule.p1, capsule.p2};
  return ShapeProxy::fromPoints(points, 2, capsule.radius);
}

ShapeProxy makeProxy(const Segment& segment) noexcept {
  const Vec2 points[2] = {segment.p1, segment.p2};
  return ShapeProxy::fromPoints(points, 2, 0.0f);
}

ShapeProxy makeProxy(const ShapeGeometry& geometry) noexcept {
  return std::visit([](const auto& shape) { return makeProxy(shape); }, geometry);
}

}  // namespace quack
