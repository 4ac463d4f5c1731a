#pragma once
/// `Vec2` and the scalar helpers the rest of Quack uses. Units are metres unless a
/// declaration says otherwise. All functions are constexpr and noexcept except those that
/// need `std::sqrt`, which are noexcept.

#include <cmath>
#include <limits>

namespace quack {

/// 2D vector or point; zero by default. Whether it is a point or a direction, and in
/// which frame, is said by the declaration that uses it.
struct Vec2 {
  float x = 0.0f;
  float y = 0.0f;

  constexpr Vec2& operator+=(Vec2 v) noexcept {
    x += v.x;
    y += v.y;
    return *this;
  }
  constexpr Vec2& operator-=(Vec2 v) noexcept {
    x -= v.x;
    y -= v.y;
    return *this;
  }
  constexpr Vec2& operator*=(float s) noexcept {
    x *= s;
    y *= s;
    return *this;
  }
  friend constexpr bool operator==(Vec2, Vec2) noexcept = default;
};

constexpr float kPi = 3.14159265358979323846f;

constexpr Vec2 operator+(Vec2 a, Vec2 b) noexcept {
  return {a.x + b.x, a.y + b.y};
}
constexpr Vec2 operator-(Vec2 a, Vec2 b) noexcept {
  return {a.x - b.x, a.y - b.y};
}
constexpr Vec2 operator-(Vec2 a) noexcept {
  return {-a.x, -a.y};
}
constexpr Vec2 operator*(float s, Vec2 v) noexcept {
  return {s * v.x, s * v.y};
}
constexpr Vec2 operator*(Vec2 v, float s) noexcept {
  return {s * v.x, s * v.y};
}

constexpr float dot(Vec2 a, Vec2 b) noexcept {
  return a.x * b.x + a.y * b.y;
}
/// z-component of the 3D cross product: positive when b is counter-clockwise from a.
constexpr float cross(Vec2 a, Vec2 b) noexcept {
  return a.x * b.y - a.y * b.x;
}
/// cross(v, s): v rotated clockwise by 90 degrees and scaled by s.
constexpr Vec2 cross(Vec2 v, float s) noexcept {
  return {s * v.y, -s * v.x};
}
/// cross(s, v): v rotated counter-clockwise by 90 degrees and scaled by s.
constexpr Vec2 cross(float s, Vec2 v) noexcept {
  return {-s * v.y, s * v.x};
}
/// v rotated counter-clockwise by 90 degrees.
constexpr Vec2 leftPerp(Vec2 v) noexcept {
  return {-v.y, v.x};
}
/// v rotated clockwise by 90 degrees.
constexpr Vec2 rightPerp(Vec2 v) noexcept {
  return {v.y, -v.x};
}

constexpr float lengthSquared(Vec2 v) noexcept {
  return v.x * v.x + v.y * v.y;
}
inline float length(Vec2 v) noexcept {
  return std::sqrt(lengthSquared(v));
}
constexpr float distanceSquared(Vec2 a, Vec2 b) noexcept {
  return lengthSquared(b - a);
}
inline float distance(Vec2 a, Vec2 b) noexcept {
  return length(b - a);
}

constexpr float minf(float a, float b) noexcept {
  return a < b ? a : b;
}
constexpr float maxf(float a, float b) noexcept {
  return a > b ? a : b;
}
constexpr float absf(float a) noexcept {
  return a < 0.0f ? -a : a;
}
constexpr float clampf(float a, float lo, float hi) noexcept {
  return a < lo ? lo : (a > hi ? hi : a);
}
constexpr Vec2 minv(Vec2 a, Vec2 b) noexcept {
  return {minf(a.x, b.x), minf(a.y, b.y)};
}
constexpr Vec2 maxv(Vec2 a, Vec2 b) noexcept {
  return {maxf(a.x, b.x), maxf(a.y, b.y)};
}
constexpr Vec2 absv(Vec2 a) noexcept {
  return {absf(a.x), absf(a.y)};
}
constexpr Vec2 lerp(Vec2 a, Vec2 b, float t) noexcept {
  return a + t * (b - a);
}

/// True when x is neither NaN nor infinite.
inline bool isFinite(float x) noexcept {
  return std::isfinite(x);
}
inline bool isFinite(Vec2 v) noexcept {
  return std::isfinite(v.x) && std::isfinite(v.y);
}

/// Unit vector along v, or the zero vector when |v| is below `kNormalizeEpsilon` (so a
/// caller can test for the degenerate case instead of receiving NaN).
constexpr float kNormalizeEpsilon = 1e-30f;
inline Vec2 normalize(Vec2 v) noexcept {
  float len = length(v);
  if (len < kNormalizeEpsilon) return {};
  float inv = 1.0f / len;
  return {inv * v.x, inv * v.y};
}

}  // namespace quack
