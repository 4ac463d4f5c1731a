#pragma once
// Random shapes for tests, from a caller-owned engine so every test fixes its seed.

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "quack/geometry/shapes.hpp"

namespace quack::testing {

inline float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

// A convex polygon of `count` vertices: sorted random angles on an ellipse of radii
// (rx, ry) around `center`, rotated by a random angle. Retries until the hull keeps all
// vertices (angles too close would be welded).
inline Polygon randomPolygon(std::mt19937& rng, int count, float size, Vec2 center = {},
                             float radius = 0.0f) {
  for (;;) {
    std::vector<float> angles(static_cast<std::size_t>(count));
    for (float& a : angles)
      a = uniform(rng, 0.0f, 2.0f * kPi);
    std::sort(angles.begin(), angles.end());
    float rx = size * uniform(rng, 0.3f, 1.0f);
    float ry = size * uniform(rng, 0.3f, 1.0f);
    Rot q = Rot::fromAngle(uniform(rng, -kPi, kPi));
    std::vector<Vec2> points;
    for (float a : angles) {
      points.push_back(center + rotate(q, Vec2{rx * std::cos(a), ry * std::sin(a)}));
    }
    Result<Polygon> p = makePolygon(points, radius);
    if (p && p->count == count) return p.value();
  }
}

}  // namespace quack::testing
