#pragma once
/// A double-precision 3D vector for the few computations of the 3D layer that must not lose
/// float's bits to cancellation (quickhull's planes, GJK's simplex solve). Internal: not part
/// of the public API.

#include <cmath>

#include "quack/math/vec3.hpp"

namespace quack::detail {

struct Vec3d {
  double x = 0, y = 0, z = 0;
};

inline Vec3d toDouble(Vec3 v) noexcept {
  return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}
inline Vec3d operator-(Vec3d a, Vec3d b) noexcept {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3d operator+(Vec3d a, Vec3d b) noexcept {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3d operator*(double s, Vec3d a) noexcept {
  return {s * a.x, s * a.y, s * a.z};
}
inline double dot(Vec3d a, Vec3d b) noexcept {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3d cross(Vec3d a, Vec3d b) noexcept {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(Vec3d a) noexcept {
  return std::sqrt(dot(a, a));
}

}  // namespace quack::detail
