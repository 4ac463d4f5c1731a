#pragma once
/// `Vec3` and `Aabb3`, the value types of the 3D layer (the 2D ones are `Vec2` and `Aabb`).
/// Units are metres unless a declaration says otherwise. Everything is constexpr and
/// noexcept except what needs `std::sqrt`, which is noexcept.

#include <cmath>

#include "quack/math/vec2.hpp"

namespace quack {

/// 3D vector or point; zero by default. Whether it is a point or a direction, and in which
/// frame, is said by the declaration that uses it. Right-handed, y up by convention.
struct Vec3 {
  float x = 0.0f;
  float y = 0.0f;
  float z = 0.0f;

  constexpr Vec3& operator+=(Vec3 v) noexcept {
    x += v.x;
    y += v.y;
    z += v.z;
    return *this;
  }
  constexpr Vec3& operator-=(Vec3 v) noexcept {
    x -= v.x;
    y -= v.y;
    z -= v.z;
    return *this;
  }
  constexpr Vec3& operator*=(float s) noexcept {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  friend constexpr bool operator==(Vec3, Vec3) noexcept = default;
};

constexpr Vec3 operator+(Vec3 a, Vec3 b) noexcept {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
constexpr Vec3 operator-(Vec3 a, Vec3 b) noexcept {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
constexpr Vec3 operator-(Vec3 a) noexcept {
  return {-a.x, -a.y, -a.z};
}
constexpr Vec3 operator*(float s, Vec3 v) noexcept {
  return {s * v.x, s * v.y, s * v.z};
}
constexpr Vec3 operator*(Vec3 v, float s) noexcept {
  return {s * v.x, s * v.y, s * v.z};
}

constexpr float dot(Vec3 a, Vec3 b) noexcept {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
/// Right-handed cross product.
constexpr Vec3 cross(Vec3 a, Vec3 b) noexcept {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr float lengthSquared(Vec3 v) noexcept {
  return dot(v, v);
}
inline float length(Vec3 v) noexcept {
  return std::sqrt(lengthSquared(v));
}
constexpr float distanceSquared(Vec3 a, Vec3 b) noexcept {
  return lengthSquared(b - a);
}
inline float distance(Vec3 a, Vec3 b) noexcept {
  return length(b - a);
}
constexpr Vec3 minv(Vec3 a, Vec3 b) noexcept {
  return {minf(a.x, b.x), minf(a.y, b.y), minf(a.z, b.z)};
}
constexpr Vec3 maxv(Vec3 a, Vec3 b) noexcept {
  return {maxf(a.x, b.x), maxf(a.y, b.y), maxf(a.z, b.z)};
}
constexpr Vec3 absv(Vec3 a) noexcept {
  return {absf(a.x), absf(a.y), absf(a.z)};
}
constexpr Vec3 lerp(Vec3 a, Vec3 b, float t) noexcept {
  return a + t * (b - a);
}
inline bool isFinite(Vec3 v) noexcept {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
/// Unit vector along v, or the zero vector when |v| is below `kNormalizeEpsilon`.
inline Vec3 normalize(Vec3 v) noexcept {
  float len = length(v);
  if (len < kNormalizeEpsilon) return {};
  float inv = 1.0f / len;
  return {inv * v.x, inv * v.y, inv * v.z};
}

/// Axis-aligned box in 3D, by its lower and upper corners (frame said by the user).
/// Empty when any lower component exceeds the upper one.
struct Aabb3 {
  Vec3 lower;
  Vec3 upper;
  friend constexpr bool operator==(Aabb3, Aabb3) noexcept = default;
};

constexpr bool overlaps(Aabb3 a, Aabb3 b) noexcept {
  return !(b.lower.x > a.upper.x || b.lower.y > a.upper.y || b.lower.z > a.upper.z ||
           a.lower.x > b.upper.x || a.lower.y > b.upper.y || a.lower.z > b.upper.z);
}
constexpr bool contains(Aabb3 outer, Aabb3 inner) noexcept {
  return outer.lower.x <= inner.lower.x && outer.lower.y <= inner.lower.y &&
         outer.lower.z <= inner.lower.z && inner.upper.x <= outer.upper.x &&
         inner.upper.y <= outer.upper.y && inner.upper.z <= outer.upper.z;
}
constexpr Aabb3 merge(Aabb3 a, Aabb3 b) noexcept {
  return {minv(a.lower, b.lower), maxv(a.upper, b.upper)};
}
/// Surface area (the surface-area heuristic's cost of a node).
constexpr float surfaceArea(Aabb3 a) noexcept {
  Vec3 d = a.upper - a.lower;
  return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
}
constexpr Vec3 center(Aabb3 a) noexcept {
  return 0.5f * (a.lower + a.upper);
}
constexpr Vec3 extents(Aabb3 a) noexcept {
  return 0.5f * (a.upper - a.lower);
}
inline bool isValid(Aabb3 a) noexcept {
  return isFinite(a.lower) && isFinite(a.upper) && a.lower.x <= a.upper.x &&
         a.lower.y <= a.upper.y && a.lower.z <= a.upper.z;
}

}  // namespace quack
