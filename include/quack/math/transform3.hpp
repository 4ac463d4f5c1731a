#pragma once
/// `Transform3`: a rigid motion in 3D (rotation then translation), the 3D `Transform`.
/// Name one by its frames, `worldFromBody`, so that `worldFromBody * bodyFromShape` reads
/// right and `transformPoint(worldFromBody, pBody)` gives a point in the world frame.

#include "quack/math/quat.hpp"

namespace quack {

/// Rigid motion: x_outer = rotate(q, x_inner) + p. Identity by default.
struct Transform3 {
  Vec3 p;  ///< translation: the origin of the inner frame, in the outer frame, metres
  Quat q;  ///< rotation of the inner frame relative to the outer frame (unit)

  friend constexpr bool operator==(Transform3, Transform3) noexcept = default;
};

/// Point p (inner frame) in the outer frame.
constexpr Vec3 transformPoint(Transform3 outerFromInner, Vec3 p) noexcept {
  return rotate(outerFromInner.q, p) + outerFromInner.p;
}
/// Point p (outer frame) in the inner frame.
constexpr Vec3 invTransformPoint(Transform3 outerFromInner, Vec3 p) noexcept {
  return invRotate(outerFromInner.q, p - outerFromInner.p);
}
/// Direction v (inner frame) in the outer frame.
constexpr Vec3 transformVector(Transform3 outerFromInner, Vec3 v) noexcept {
  return rotate(outerFromInner.q, v);
}
/// Direction v (outer frame) in the inner frame.
constexpr Vec3 invTransformVector(Transform3 outerFromInner, Vec3 v) noexcept {
  return invRotate(outerFromInner.q, v);
}
/// Composition: `aFromC = aFromB * bFromC`.
constexpr Transform3 operator*(Transform3 aFromB, Transform3 bFromC) noexcept {
  return {transformPoint(aFromB, bFromC.p), aFromB.q * bFromC.q};
}
/// `bFromA` given `aFromB`.
constexpr Transform3 inverse(Transform3 aFromB) noexcept {
  Quat qi = conjugate(aFromB.q);
  return {rotate(qi, -aFromB.p), qi};
}
/// `bFromC = inverse(aFromB) * aFromC`, without forming the inverse: the relative pose,
/// computed from the difference of the translations, so two poses far from the origin give
/// a relative pose with no large-coordinate rounding beyond that of their inputs.
constexpr Transform3 invMul(Transform3 aFromB, Transform3 aFromC) noexcept {
  return {invRotate(aFromB.q, aFromC.p - aFromB.p), invMul(aFromB.q, aFromC.q)};
}
/// Transform from a position and a rotation (normalised here, so a hand-written one is
/// safe; precondition: q not zero).
inline Transform3 makeTransform3(Vec3 p, Quat q) noexcept {
  return {p, normalize(q)};
}

}  // namespace quack
