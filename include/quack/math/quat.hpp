#pragma once
/// `Quat`: a rotation in 3D as a unit quaternion, stored scalar last (x, y, z, w) as the
/// JSON pose `{"quat": [x, y, z, w]}` and most engines do (Jolt, Box3D, Bullet's storage
/// order). q and -q are the same rotation. Right-handed: a positive angle about an axis
/// turns counter-clockwise when the axis points at the viewer.
///
/// Formulas: Shoemake, "Animating rotation with quaternion curves", SIGGRAPH 1985, and the
/// rotation v' = v + 2w (u x v) + 2 u x (u x v) with u = (x, y, z), which needs no matrix.

#include "quack/math/mat3.hpp"
#include "quack/math/trig.hpp"

namespace quack {

/// Unit quaternion (x, y, z, w) = (sin(a/2) axis, cos(a/2)); identity by default. The
/// functions that rotate assume unit length (`normalize` restores it after drift).
struct Quat {
  float x = 0.0f;
  float y = 0.0f;
  float z = 0.0f;
  float w = 1.0f;

  /// Rotation by `radians` about `axis`. Precondition: `axis` of unit length (use
  /// `normalize(axis)`). Quack's portable sine and cosine, so the same bits everywhere.
  static Quat fromAxisAngle(Vec3 axis, float radians) noexcept {
    float s = portableSin(0.5f * radians);
    return {s * axis.x, s * axis.y, s * axis.z, portableCos(0.5f * radians)};
  }
  /// The vector part (x, y, z).
  constexpr Vec3 vector() const noexcept { return {x, y, z}; }
  friend constexpr bool operator==(Quat, Quat) noexcept = default;
};

/// The rotation q then r: (r * q) v = r (q v). Hamilton product.
constexpr Quat operator*(Quat r, Quat q) noexcept {
  return {
      r.w * q.x + r.x * q.w + r.y * q.z - r.z * q.y, r.w * q.y - r.x * q.z + r.y * q.w + r.z * q.x,
      r.w * q.z + r.x * q.y - r.y * q.x + r.z * q.w, r.w * q.w - r.x * q.x - r.y * q.y - r.z * q.z};
}
/// The conjugate; for a unit quaternion, the inverse rotation.
constexpr Quat conjugate(Quat q) noexcept {
  return {-q.x, -q.y, -q.z, q.w};
}
/// The 4D dot product (the cosine of half the angle between two unit rotations, up to sign).
constexpr float dot(Quat a, Quat b) noexcept {
  return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
}
/// |q|^2 (1 for a unit quaternion).
constexpr float lengthSquared(Quat q) noexcept {
  return dot(q, q);
}
/// q scaled to unit length; the identity when |q| is below `kNormalizeEpsilon` (a zero
/// quaternion is no rotation; input checks refuse it before it gets here).
inline Quat normalize(Quat q) noexcept {
  float len = std::sqrt(lengthSquared(q));
  if (len < kNormalizeEpsilon) return {};
  float inv = 1.0f / len;
  return {inv * q.x, inv * q.y, inv * q.z, inv * q.w};
}
/// True when all four components are finite.
inline bool isFinite(Quat q) noexcept {
  return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
}
/// v rotated by q (unit).
constexpr Vec3 rotate(Quat q, Vec3 v) noexcept {
  Vec3 u = q.vector();
  Vec3 t = 2.0f * cross(u, v);
  return v + q.w * t + cross(u, t);
}
/// v rotated by the inverse of q (unit).
constexpr Vec3 invRotate(Quat q, Vec3 v) noexcept {
  return rotate(conjugate(q), v);
}
/// conjugate(r) * q: the rotation from r to q, without forming the conjugate first.
constexpr Quat invMul(Quat r, Quat q) noexcept {
  return conjugate(r) * q;
}
/// The rotation matrix of q (unit): `toMat3(q) * v == rotate(q, v)` up to rounding.
constexpr Mat3 toMat3(Quat q) noexcept {
  float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
  float wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  return {{1.0f - 2.0f * (yy + zz), 2.0f * (xy + wz), 2.0f * (xz - wy)},
          {2.0f * (xy - wz), 1.0f - 2.0f * (xx + zz), 2.0f * (yz + wx)},
          {2.0f * (xz + wy), 2.0f * (yz - wx), 1.0f - 2.0f * (xx + yy)}};
}
/// The rotation q advanced by angular velocity `omega` (rad/s, outer frame) over `dt`
/// seconds, to first order and renormalised: q + dt/2 (omega, 0) * q (the usual
/// integration; exact enough for small omega dt, the rotating sweeps of time of impact).
inline Quat integrateRotation(Quat q, Vec3 omega, float dt) noexcept {
  Quat w{omega.x, omega.y, omega.z, 0.0f};
  Quat d = w * q;
  float h = 0.5f * dt;
  return normalize({q.x + h * d.x, q.y + h * d.y, q.z + h * d.z, q.w + h * d.w});
}

}  // namespace quack
