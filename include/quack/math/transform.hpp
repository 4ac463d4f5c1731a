#pragma once
/// `Transform`: a rigid motion (rotation then translation). Name a transform by its
/// frames, `worldFromBody`, so that `worldFromBody * bodyFromShape` reads right and
/// `transformPoint(worldFromBody, pBody)` gives a point in the world frame.

#include "quack/math/rot.hpp"

namespace quack {

struct Transform {
  Vec2 p;  ///< translation: the origin of the inner frame, in the outer frame
  Rot q;   ///< rotation of the inner frame relative to the outer frame

  friend constexpr bool operator==(Transform, Transform) noexcept = default;
};

/// Point p (in the inner frame) expressed in the outer frame.
constexpr Vec2 transformPoint(Transform outerFromInner, Vec2 p) noexcept {
  return rotate(outerFromInner.q, p) + outerFromInner.p;
}
/// Point p (in the outer frame) expressed in the inner frame.
constexpr Vec2 invTransformPoint(Transform outerFromInner, Vec2 p) noexcept {
  return invRotate(outerFromInner.q, p - outerFromInner.p);
}
/// Direction v (in the inner frame) expressed in the outer frame.
constexpr Vec2 transformVector(Transform outerFromInner, Vec2 v) noexcept {
  return rotate(outerFromInner.q, v);
}
/// Composition: `aFromC = aFromB * bFromC`.
constexpr Transform operator*(Transform aFromB, Transform bFromC) noexcept {
  return {transformPoint(aFromB, bFromC.p), mulRot(aFromB.q, bFromC.q)};
}
/// `bFromA` given `aFromB`.
constexpr Transform inverse(Transform aFromB) noexcept {
  Rot qi = inverse(aFromB.q);
  return {rotate(qi, -aFromB.p), qi};
}
/// `bFromC = inverse(aFromB) * aFromC`, without forming the inverse.
constexpr Transform invMul(Transform aFromB, Transform aFromC) noexcept {
  return {invRotate(aFromB.q, aFromC.p - aFromB.p), invMulRot(aFromB.q, aFromC.q)};
}
/// Transform from a position and an angle in radians.
inline Transform makeTransform(Vec2 p, float radians) noexcept {
  return {p, Rot::fromAngle(radians)};
}

}  // namespace quack
