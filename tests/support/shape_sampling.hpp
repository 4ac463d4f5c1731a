#pragma once
// Boundary samples of shapes, for brute-force checks of bounds and casts.

#include <cmath>
#include <vector>

#include "quack/geometry/shapes.hpp"

namespace quack::testing {

// Points on the boundary of a rounded convex outline (core points plus radius), shape frame.
inline std::vector<Vec2> sampleRounded(const std::vector<Vec2>& core, float radius, int perTurn) {
  std::vector<Vec2> out;
  if (radius == 0.0f) {
    for (std::size_t i = 0; i < core.size(); ++i) {
      Vec2 a = core[i], b = core[(i + 1) % core.size()];
      for (int k = 0; k < 64; ++k)
        out.push_back(lerp(a, b, static_cast<float>(k) / 64));
    }
    return out;
  }
  for (Vec2 c : core) {
    for (int k = 0; k < perTurn; ++k) {
      float a = 2.0f * kPi * static_cast<float>(k) / static_cast<float>(perTurn);
      out.push_back(c + radius * Vec2{std::cos(a), std::sin(a)});
    }
  }
  return out;
}

inline std::vector<Vec2> sampleBoundary(const Circle& s) {
  return sampleRounded({s.center}, s.radius, 4096);
}
inline std::vector<Vec2> sampleBoundary(const Capsule& s) {
  return sampleRounded({s.p1, s.p2}, s.radius, 4096);
}
inline std::vector<Vec2> sampleBoundary(const Segment& s) {
  return sampleRounded({s.p1, s.p2}, 0.0f, 0);
}
inline std::vector<Vec2> sampleBoundary(const Polygon& s) {
  return sampleRounded({s.vertices, s.vertices + s.count}, s.radius, 4096);
}

}  // namespace quack::testing
