#pragma once
// Shapes of every kind behind one value, and random pairs of them, for the collision tests.

#include <algorithm>  // random_shapes.hpp uses std::sort without including it
#include <cstdio>
#include <random>
#include <string>

#include "quack/collision/manifold.hpp"
#include "quack/collision/proxy.hpp"
#include "support/random_shapes.hpp"

namespace quack::testing {

enum class Kind { circle, capsule, segment, polygon };
inline const char* toString(Kind k) {
  switch (k) {
    case Kind::circle:
      return "circle";
    case Kind::capsule:
      return "capsule";
    case Kind::segment:
      return "segment";
    case Kind::polygon:
      return "polygon";
  }
  return "?";
}

// One shape of any kind, shape frame. Holds its storage so a proxy into it stays valid
// while the AnyShape lives (do not copy an AnyShape while a proxy views it).
struct AnyShape {
  Kind kind = Kind::circle;
  Circle circle;
  Capsule capsule;
  Segment segment;
  Polygon polygon;

  ShapeProxy proxy() const {
    switch (kind) {
      case Kind::circle:
        return makeProxy(circle);
      case Kind::capsule:
        return makeProxy(capsule);
      case Kind::segment:
        return makeProxy(segment);
      case Kind::polygon:
        return makeProxy(polygon);
    }
    return {};
  }
  // The shape for the manifold dispatch table (refers to this object's storage).
  ShapeRef ref() const {
    switch (kind) {
      case Kind::circle:
        return circle;
      case Kind::capsule:
        return capsule;
      case Kind::segment:
        return segment;
      case Kind::polygon:
        return polygon;
    }
    return {};
  }
  float radius() const { return proxy().radius(); }
  std::string describe() const {
    char buf[256];
    ShapeProxy p = proxy();
    std::string s = toString(kind);
    std::snprintf(buf, sizeof buf, " r=%.9g pts:", static_cast<double>(p.radius()));
    s += buf;
    for (int i = 0; i < p.count(); ++i) {
      std::snprintf(buf, sizeof buf, " (%.9g,%.9g)", static_cast<double>(p.points()[i].x),
                    static_cast<double>(p.points()[i].y));
      s += buf;
    }
    return s;
  }
};

inline AnyShape makeAny(const Circle& c) {
  AnyShape s;
  s.kind = Kind::circle;
  s.circle = c;
  return s;
}
inline AnyShape makeAny(const Capsule& c) {
  AnyShape s;
  s.kind = Kind::capsule;
  s.capsule = c;
  return s;
}
inline AnyShape makeAny(const Segment& c) {
  AnyShape s;
  s.kind = Kind::segment;
  s.segment = c;
  return s;
}
inline AnyShape makeAny(const Polygon& c) {
  AnyShape s;
  s.kind = Kind::polygon;
  s.polygon = c;
  return s;
}

// A random shape of `kind` about the origin with size `size` (metres). Rounded kinds get
// a radius up to a third of the size; polygons 3 to 32 vertices, sometimes rounded.
inline AnyShape randomShape(std::mt19937& rng, Kind kind, float size) {
  switch (kind) {
    case Kind::circle:
      return makeAny(makeCircle({}, size * uniform(rng, 0.1f, 1.0f)).value());
    case Kind::capsule: {
      float h = size * uniform(rng, 0.2f, 1.0f);
      float a = uniform(rng, -kPi, kPi);
      Vec2 d = h * Vec2{std::cos(a), std::sin(a)};
      return makeAny(makeCapsule(-d, d, size * uniform(rng, 0.05f, 0.4f)).value());
    }
    case Kind::segment: {
      float h = size * uniform(rng, 0.2f, 1.0f);
      float a = uniform(rng, -kPi, kPi);
      Vec2 d = h * Vec2{std::cos(a), std::sin(a)};
      return makeAny(makeSegment(-d, d).value());
    }
    case Kind::polygon: {
      int n = std::uniform_int_distribution<int>(3, 32)(rng);
      float r = uniform(rng, 0.0f, 1.0f) < 0.3f ? size * uniform(rng, 0.0f, 0.2f) : 0.0f;
      return makeAny(randomPolygon(rng, n, size, {}, r));
    }
  }
  return {};
}

inline Transform randomTransform(std::mt19937& rng, float extent) {
  return makeTransform({uniform(rng, -extent, extent), uniform(rng, -extent, extent)},
                       uniform(rng, -kPi, kPi));
}

}  // namespace quack::testing
