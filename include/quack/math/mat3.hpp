#pragma once
/// `Mat3`: a 3x3 matrix of floats, stored by columns (inertia tensors, rotation matrices,
/// small linear solves in the 3D layer). Plain constexpr value type; zero by default.

#include "quack/math/vec3.hpp"

namespace quack {

/// 3x3 matrix by columns: `m * v = cx * v.x + cy * v.y + cz * v.z`. The frame of its
/// inputs and outputs is said by the declaration that uses it.
struct Mat3 {
  Vec3 cx;  ///< first column
  Vec3 cy;  ///< second column
  Vec3 cz;  ///< third column

  /// The identity.
  static constexpr Mat3 identity() noexcept { return {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; }
  /// diag(d.x, d.y, d.z).
  static constexpr Mat3 diagonal(Vec3 d) noexcept {
    return {{d.x, 0, 0}, {0, d.y, 0}, {0, 0, d.z}};
  }
  /// The matrix with rows r0, r1, r2 (reads like the written matrix).
  static constexpr Mat3 fromRows(Vec3 r0, Vec3 r1, Vec3 r2) noexcept {
    return {{r0.x, r1.x, r2.x}, {r0.y, r1.y, r2.y}, {r0.z, r1.z, r2.z}};
  }
  friend constexpr bool operator==(Mat3, Mat3) noexcept = default;
};

/// m v.
constexpr Vec3 operator*(Mat3 m, Vec3 v) noexcept {
  return m.cx * v.x + m.cy * v.y + m.cz * v.z;
}
/// a b (b first, then a).
constexpr Mat3 operator*(Mat3 a, Mat3 b) noexcept {
  return {a * b.cx, a * b.cy, a * b.cz};
}
/// Sum, entry by entry.
constexpr Mat3 operator+(Mat3 a, Mat3 b) noexcept {
  return {a.cx + b.cx, a.cy + b.cy, a.cz + b.cz};
}
/// Difference, entry by entry.
constexpr Mat3 operator-(Mat3 a, Mat3 b) noexcept {
  return {a.cx - b.cx, a.cy - b.cy, a.cz - b.cz};
}
/// Every entry times s.
constexpr Mat3 operator*(float s, Mat3 m) noexcept {
  return {s * m.cx, s * m.cy, s * m.cz};
}
/// The transpose (for a rotation, its inverse).
constexpr Mat3 transpose(Mat3 m) noexcept {
  return {{m.cx.x, m.cy.x, m.cz.x}, {m.cx.y, m.cy.y, m.cz.y}, {m.cx.z, m.cy.z, m.cz.z}};
}
/// mᵀ v, without forming the transpose.
constexpr Vec3 mulTranspose(Mat3 m, Vec3 v) noexcept {
  return {dot(m.cx, v), dot(m.cy, v), dot(m.cz, v)};
}
/// The determinant: the triple product of the columns.
constexpr float determinant(Mat3 m) noexcept {
  return dot(m.cx, cross(m.cy, m.cz));
}
/// The inverse, by the adjugate over the determinant; the zero matrix when the
/// determinant is exactly zero (a singular matrix has none; the caller decides what a
/// nearly singular one means, from `determinant`).
constexpr Mat3 inverse(Mat3 m) noexcept {
  float det = determinant(m);
  if (det == 0.0f) return {};
  float inv = 1.0f / det;
  // Rows of the inverse are the cross products of the columns (Cramer's rule).
  Vec3 r0 = inv * cross(m.cy, m.cz);
  Vec3 r1 = inv * cross(m.cz, m.cx);
  Vec3 r2 = inv * cross(m.cx, m.cy);
  return Mat3::fromRows(r0, r1, r2);
}
/// The matrix of `cross(v, ·)`: skew(v) w = cross(v, w).
constexpr Mat3 skew(Vec3 v) noexcept {
  return {{0, v.z, -v.y}, {-v.z, 0, v.x}, {v.y, -v.x, 0}};
}
/// The outer product a bᵀ.
constexpr Mat3 outer(Vec3 a, Vec3 b) noexcept {
  return {a * b.x, a * b.y, a * b.z};
}
/// The trace.
constexpr float trace(Mat3 m) noexcept {
  return m.cx.x + m.cy.y + m.cz.z;
}

}  // namespace quack
