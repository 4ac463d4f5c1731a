#pragma once
// A committed corpus of adversarial pairs: identical shapes, concentric, edge-on-edge,
// vertex-on-vertex, slivers, huge aspect ratios, tiny and huge scales. Shared by the tests
// that must hold on all of them (adversarial_test.cpp, observer_test.cpp).

#include <cmath>
#include <initializer_list>
#include <span>
#include <vector>

#include "test_shapes.hpp"

namespace quack::testing {

struct AdversarialCase {
  const char* name;
  ShapeGeometry a;
  Transform xa;
  ShapeGeometry b;
  Transform xb;
};

inline Polygon box(float hx, float hy, float r = 0.0f) {
  return makeBox(hx, hy, {}, 0.0f, r).value();
}
inline Polygon poly(std::initializer_list<Vec2> pts, float r = 0.0f) {
  return makePolygon(std::span<const Vec2>(pts.begin(), pts.size()), r).value();
}

inline std::vector<AdversarialCase> adversarialCorpus() {
  std::vector<AdversarialCase> c;
  Transform id{};
  auto at = [](float x, float y, float a = 0.0f) { return makeTransform({x, y}, a); };
  c.push_back({"identical boxes", ShapeGeometry(box(1, 1)), id, ShapeGeometry(box(1, 1)), id});
  c.push_back({"identical circles", ShapeGeometry(makeCircle({}, 1).value()), id,
               ShapeGeometry(makeCircle({}, 1).value()), id});
  c.push_back({"concentric circle in box", ShapeGeometry(box(2, 2)), id,
               ShapeGeometry(makeCircle({}, 0.5f).value()), id});
  c.push_back({"concentric rotated squares", ShapeGeometry(box(1, 1)), id, ShapeGeometry(box(1, 1)),
               at(0, 0, kPi / 4)});
  c.push_back({"identical segments", ShapeGeometry(makeSegment({-1, 0}, {1, 0}).value()), id,
               ShapeGeometry(makeSegment({-1, 0}, {1, 0}).value()), id});
  c.push_back({"collinear capsules", ShapeGeometry(makeCapsule({-1, 0}, {1, 0}, 0.1f).value()), id,
               ShapeGeometry(makeCapsule({-1, 0}, {1, 0}, 0.1f).value()), at(0.5f, 0)});
  c.push_back({"edge on edge", ShapeGeometry(box(1, 1)), id, ShapeGeometry(box(1, 1)), at(2, 0)});
  c.push_back({"edge on edge shifted", ShapeGeometry(box(1, 1)), id, ShapeGeometry(box(1, 1)),
               at(2, 1.3f)});
  c.push_back(
      {"vertex on vertex", ShapeGeometry(box(1, 1)), id, ShapeGeometry(box(1, 1)), at(2, 2)});
  c.push_back({"vertex on edge", ShapeGeometry(box(1, 1)), id, ShapeGeometry(box(1, 1)),
               at(1 + std::sqrt(2.0f), 0, kPi / 4)});
  c.push_back({"sliver triangles", ShapeGeometry(poly({{0, 0}, {10, 0}, {5, 1e-3f}})), id,
               ShapeGeometry(poly({{0, 0}, {10, 0}, {5, 1e-3f}})), at(0.5f, 5e-4f)});
  c.push_back({"crossing slivers", ShapeGeometry(poly({{-5, 0}, {5, 0}, {0, 1e-3f}})), id,
               ShapeGeometry(poly({{-5, 0}, {5, 0}, {0, 1e-3f}})), at(0, 0, 1e-3f)});
  c.push_back({"huge aspect box", ShapeGeometry(box(1e3f, 1e-3f)), id,
               ShapeGeometry(box(1e3f, 1e-3f)), at(0, 1.5e-3f, 1e-4f)});
  c.push_back({"needle vs circle", ShapeGeometry(makeCapsule({-1e3f, 0}, {1e3f, 0}, 1e-3f).value()),
               id, ShapeGeometry(makeCircle({}, 1e-3f).value()), at(500, 1.9e-3f)});
  c.push_back({"tiny boxes", ShapeGeometry(box(1e-3f, 1e-3f)), id, ShapeGeometry(box(1e-3f, 1e-3f)),
               at(1.5e-3f, 1e-4f)});
  c.push_back({"huge boxes", ShapeGeometry(box(1e3f, 1e3f)), id, ShapeGeometry(box(1e3f, 1e3f)),
               at(1.5e3f, 10)});
  c.push_back({"tiny far from origin", ShapeGeometry(box(1e-3f, 1e-3f)), at(1e4f, 1e4f),
               ShapeGeometry(box(1e-3f, 1e-3f)), at(1e4f + 1.5e-3f, 1e4f)});
  c.push_back({"huge vs tiny", ShapeGeometry(box(1e3f, 1e3f)), id,
               ShapeGeometry(makeCircle({}, 1e-3f).value()), at(1e3f, 0)});
  c.push_back({"rounded boxes touching cores", ShapeGeometry(box(1, 1, 0.5f)), id,
               ShapeGeometry(box(1, 1, 0.5f)), at(2, 0)});
  c.push_back({"point-like polygon", ShapeGeometry(poly({{0, 0}, {1e-4f, 0}, {0, 1e-4f}})), id,
               ShapeGeometry(poly({{0, 0}, {1e-4f, 0}, {0, 1e-4f}})), at(0, 0, kPi)});
  c.push_back({"segment on polygon edge", ShapeGeometry(box(1, 1)), id,
               ShapeGeometry(makeSegment({-3, 1}, {3, 1}).value()), id});
  c.push_back({"64-gons concentric", ShapeGeometry(makeBox(1, 1).value()), id,
               ShapeGeometry(makeBox(1, 1).value()), at(0, 0, kPi / 2)});
  // A 64-gon circle approximation, concentric with itself rotated.
  std::vector<Vec2> ring;
  for (int i = 0; i < kMaxPolygonVertices; ++i) {
    float a = 2.0f * kPi * static_cast<float>(i) / kMaxPolygonVertices;
    ring.push_back({std::cos(a), std::sin(a)});
  }
  Polygon big = makePolygon(ring).value();
  c.push_back({"64-gon vs itself rotated",
               ShapeGeometry(big),
               {},
               ShapeGeometry(big),
               makeTransform({0, 0}, 0.01f)});
  return c;
}

// The rotations each case is run at (both shapes turned about the origin).
inline constexpr float kAdversarialTurns[] = {0.0f, 0.3f, kPi / 2, 2.0f};

}  // namespace quack::testing
