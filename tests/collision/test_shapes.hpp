#pragma once
// Random shapes of every kind, and how to print one, for the collision tests.

#include <algorithm>  // random_shapes.hpp uses std::sort without including it
#include <cstdio>
#include <random>
#include <string>

#include "quack/collision/manifold.hpp"
#include "quack/collision/proxy.hpp"
#include "support/random_shapes.hpp"

namespace quack::testing {

// The shape for a failure message: its type, radius and core points.
inline std::string describe(const ShapeGeometry& shape) {
  char buf[256];
  ShapeProxy p = makeProxy(shape);
  std::string s = toString(shapeType(shape));
  std::snprintf(buf, sizeof buf, " r=%.9g pts:", static_cast<double>(p.radius()));
  s += buf;
  for (int i = 0; i < p.count(); ++i) {
    std::snprintf(buf, sizeof buf, " (%.9g,%.9g)", static_cast<double>(p.points()[i].x),
                  static_cast<double>(p.points()[i].y));
    s += buf;
  }
  return s;
}

// A random shape of `kind` about the origin with size `size` (metres). Rounded kinds get
// a radius up to a third of the size; polygons 3 to 32 vertices, sometimes rounded.
inline ShapeGeometry randomShape(std::mt19937& rng, ShapeType kind, float size) {
  switch (kind) {
    case ShapeType::circle:
      return ShapeGeometry(makeCircle({}, size * uniform(rng, 0.1f, 1.0f)).value());
    case ShapeType::capsule: {
      float h = size * uniform(rng, 0.2f, 1.0f);
      float a = uniform(rng, -kPi, kPi);
      Vec2 d = h * Vec2{std::cos(a), std::sin(a)};
      return ShapeGeometry(makeCapsule(-d, d, size * uniform(rng, 0.05f, 0.4f)).value());
    }
    case ShapeType::segment: {
      float h = size * uniform(rng, 0.2f, 1.0f);
      float a = uniform(rng, -kPi, kPi);
      Vec2 d = h * Vec2{std::cos(a), std::sin(a)};
      return ShapeGeometry(makeSegment(-d, d).value());
    }
    case ShapeType::polygon: {
      int n = std::uniform_int_distribution<int>(3, 32)(rng);
      float r = uniform(rng, 0.0f, 1.0f) < 0.3f ? size * uniform(rng, 0.0f, 0.2f) : 0.0f;
      return ShapeGeometry(randomPolygon(rng, n, size, {}, r));
    }
  }
  return {};
}

inline Transform randomTransform(std::mt19937& rng, float extent) {
  return makeTransform({uniform(rng, -extent, extent), uniform(rng, -extent, extent)},
                       uniform(rng, -kPi, kPi));
}

}  // namespace quack::testing
