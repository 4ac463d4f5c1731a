#pragma once
/// `Rot`: a rotation stored as cosine and sine.

#include "quack/math/trig.hpp"
#include "quack/math/vec2.hpp"

namespace quack {

/// Rotation by an angle, stored as (cos, sin); identity by default.
struct Rot {
  float c = 1.0f;
  float s = 0.0f;

  /// Rotation by `radians`, counter-clockwise. Quack's own fast cosine and sine
  /// (portableCosSin, quack/math/trig.hpp): within 1 float ulp, the same bits on every
  /// platform.
  static Rot fromAngle(float radians) noexcept {
    const CosSin cs = portableCosSin(radians);
    return {cs.cosine, cs.sine};
  }
  /// Angle in (-pi, pi], by Quack's own atan2 (the same bits on every platform).
  float angle() const noexcept { return portableAtan2(s, c); }
  friend constexpr bool operator==(Rot, Rot) noexcept = default;
};

/// v rotated by q.
constexpr Vec2 rotate(Rot q, Vec2 v) noexcept {
  return {q.c * v.x - q.s * v.y, q.s * v.x + q.c * v.y};
}
/// v rotated by the inverse of q.
constexpr Vec2 invRotate(Rot q, Vec2 v) noexcept {
  return {q.c * v.x + q.s * v.y, -q.s * v.x + q.c * v.y};
}
/// The rotation q then r (r * q): angles add.
constexpr Rot mulRot(Rot r, Rot q) noexcept {
  return {r.c * q.c - r.s * q.s, r.s * q.c + r.c * q.s};
}
/// inverse(r) * q: the rotation from r to q.
constexpr Rot invMulRot(Rot r, Rot q) noexcept {
  return {r.c * q.c + r.s * q.s, r.c * q.s - r.s * q.c};
}
/// The inverse rotation.
constexpr Rot inverse(Rot q) noexcept {
  return {q.c, -q.s};
}
/// Re-normalizes q (after integration drift); identity when q is degenerate.
inline Rot normalizeRot(Rot q) noexcept {
  float len = std::sqrt(q.c * q.c + q.s * q.s);
  if (len < kNormalizeEpsilon) return {};
  return {q.c / len, q.s / len};
}

}  // namespace quack
