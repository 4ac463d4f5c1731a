// A committed corpus of adversarial pairs: identical shapes, concentric, edge-on-edge,
// vertex-on-vertex, slivers, huge aspect ratios, tiny and huge scales. Every query must
// return a finite answer and a status, within its iteration cap: no NaN, no hang. Each
// case runs at several rotations, and with A and B swapped.

#include <gtest/gtest.h>

#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/manifold.hpp"
#include "quack/collision/sat.hpp"
#include "test_shapes.hpp"

namespace quack {
namespace {

struct Case {
  const char* name;
  ShapeGeometry a;
  Transform xa;
  ShapeGeometry b;
  Transform xb;
};

Polygon box(float hx, float hy, float r = 0.0f) {
  return makeBox(hx, hy, {}, 0.0f, r).value();
}
Polygon poly(std::initializer_list<Vec2> pts, float r = 0.0f) {
  return makePolygon(std::span<const Vec2>(pts.begin(), pts.size()), r).value();
}

std::vector<Case> corpus() {
  std::vector<Case> c;
  Transform id{};
  auto at = [](float x, float y, float a = 0.0f) { return makeTransform({x, y}, a); };
  c.push_back({"identical boxes", box(1, 1), id, box(1, 1), id});
  c.push_back({"identical circles", makeCircle({}, 1).value(), id, makeCircle({}, 1).value(), id});
  c.push_back({"concentric circle in box", box(2, 2), id, makeCircle({}, 0.5f).value(), id});
  c.push_back({"concentric rotated squares", box(1, 1), id, box(1, 1), at(0, 0, kPi / 4)});
  c.push_back({"identical segments", makeSegment({-1, 0}, {1, 0}).value(), id,
               makeSegment({-1, 0}, {1, 0}).value(), id});
  c.push_back({"collinear capsules", makeCapsule({-1, 0}, {1, 0}, 0.1f).value(), id,
               makeCapsule({-1, 0}, {1, 0}, 0.1f).value(), at(0.5f, 0)});
  c.push_back({"edge on edge", box(1, 1), id, box(1, 1), at(2, 0)});
  c.push_back({"edge on edge shifted", box(1, 1), id, box(1, 1), at(2, 1.3f)});
  c.push_back({"vertex on vertex", box(1, 1), id, box(1, 1), at(2, 2)});
  c.push_back({"vertex on edge", box(1, 1), id, box(1, 1), at(1 + std::sqrt(2.0f), 0, kPi / 4)});
  c.push_back({"sliver triangles", poly({{0, 0}, {10, 0}, {5, 1e-3f}}), id,
               poly({{0, 0}, {10, 0}, {5, 1e-3f}}), at(0.5f, 5e-4f)});
  c.push_back({"crossing slivers", poly({{-5, 0}, {5, 0}, {0, 1e-3f}}), id,
               poly({{-5, 0}, {5, 0}, {0, 1e-3f}}), at(0, 0, 1e-3f)});
  c.push_back({"huge aspect box", box(1e3f, 1e-3f), id, box(1e3f, 1e-3f), at(0, 1.5e-3f, 1e-4f)});
  c.push_back({"needle vs circle", makeCapsule({-1e3f, 0}, {1e3f, 0}, 1e-3f).value(), id,
               makeCircle({}, 1e-3f).value(), at(500, 1.9e-3f)});
  c.push_back({"tiny boxes", box(1e-3f, 1e-3f), id, box(1e-3f, 1e-3f), at(1.5e-3f, 1e-4f)});
  c.push_back({"huge boxes", box(1e3f, 1e3f), id, box(1e3f, 1e3f), at(1.5e3f, 10)});
  c.push_back({"tiny far from origin", box(1e-3f, 1e-3f), at(1e4f, 1e4f), box(1e-3f, 1e-3f),
               at(1e4f + 1.5e-3f, 1e4f)});
  c.push_back({"huge vs tiny", box(1e3f, 1e3f), id, makeCircle({}, 1e-3f).value(), at(1e3f, 0)});
  c.push_back({"rounded boxes touching cores", box(1, 1, 0.5f), id, box(1, 1, 0.5f), at(2, 0)});
  c.push_back({"point-like polygon", poly({{0, 0}, {1e-4f, 0}, {0, 1e-4f}}), id,
               poly({{0, 0}, {1e-4f, 0}, {0, 1e-4f}}), at(0, 0, kPi)});
  c.push_back({"segment on polygon edge", box(1, 1), id, makeSegment({-3, 1}, {3, 1}).value(), id});
  c.push_back(
      {"64-gons concentric", makeBox(1, 1).value(), id, makeBox(1, 1).value(), at(0, 0, kPi / 2)});
  return c;
}

void expectFinite(Vec2 v, const std::string& what) {
  EXPECT_TRUE(isFinite(v)) << what;
}

TEST(Adversarial, EveryQueryIsFiniteAndEnds) {
  std::vector<Case> cases = corpus();
  // A 64-gon circle approximation, concentric with itself rotated.
  std::vector<Vec2> ring;
  for (int i = 0; i < kMaxPolygonVertices; ++i) {
    float a = 2.0f * kPi * static_cast<float>(i) / kMaxPolygonVertices;
    ring.push_back({std::cos(a), std::sin(a)});
  }
  Polygon big = makePolygon(ring).value();
  cases.push_back({"64-gon vs itself rotated", big, {}, big, makeTransform({0, 0}, 0.01f)});
  for (const Case& c : cases) {
    for (float turn : {0.0f, 0.3f, kPi / 2, 2.0f}) {
      Transform spin = makeTransform({0.0f, 0.0f}, turn);
      for (int swap = 0; swap < 2; ++swap) {
        const ShapeGeometry& sa = swap ? c.b : c.a;
        const ShapeGeometry& sb = swap ? c.a : c.b;
        Transform xa = spin * (swap ? c.xb : c.xa);
        Transform xb = spin * (swap ? c.xa : c.xb);
        ShapeProxy pa = makeProxy(sa), pb = makeProxy(sb);
        std::string what =
            std::string(c.name) + " turn " + std::to_string(turn) + (swap ? " swapped" : "");
        DistanceOutput d = computeDistance(pa, xa, pb, xb);
        EXPECT_TRUE(std::isfinite(d.distance)) << what;
        EXPECT_GE(d.distance, 0.0f) << what;
        expectFinite(d.pointA, what);
        expectFinite(d.pointB, what);
        expectFinite(d.normal, what);
        EXPECT_NE(d.status, GjkStatus::maxIterations) << what;
        PenetrationOutput p = computePenetration(pa, xa, pb, xb);
        EXPECT_TRUE(std::isfinite(p.depth)) << what;
        EXPECT_GE(p.depth, 0.0f) << what;
        expectFinite(p.pointA, what);
        expectFinite(p.pointB, what);
        expectFinite(p.normal, what);
        EXPECT_NEAR(length(p.normal), 1.0f, 1e-3f) << what;
        EXPECT_NE(p.status, EpaStatus::maxIterations) << what;
        (void)testOverlap(pa, xa, pb, xb);
        // Every manifold routine, through the table and through the general path.
        for (const Manifold& m : {collide(sa, xa, sb, xb), collideGeneral(pa, xa, pb, xb)}) {
          ASSERT_GE(m.pointCount, 0) << what;
          ASSERT_LE(m.pointCount, kMaxManifoldPoints) << what;
          if (m.pointCount > 0) {
            EXPECT_NEAR(length(m.normal), 1.0f, 1e-3f) << what;
          }
          for (int k = 0; k < m.pointCount; ++k) {
            expectFinite(m.points[k].point, what);
            expectFinite(m.points[k].anchorA, what);
            EXPECT_TRUE(std::isfinite(m.points[k].separation)) << what;
            EXPECT_LE(m.points[k].separation, kSpeculativeDistance + 1e-3f) << what;
          }
          // Overlapping shapes always get a manifold.
          if (p.overlap) {
            EXPECT_GE(m.pointCount, 1) << what;
          }
        }
        if (shapeType(sa) == ShapeType::polygon && shapeType(sb) == ShapeType::polygon) {
          SatOutput s = computeSat(std::get<Polygon>(sa), xa, std::get<Polygon>(sb), xb);
          EXPECT_TRUE(std::isfinite(s.separation)) << what;
          if (p.status == EpaStatus::converged || p.status == EpaStatus::repeatedSupport) {
            float scale = 1e-5f * (1.0f + length(xa.p) + length(xb.p) + 2e3f);
            EXPECT_NEAR(p.depth, -s.separation, scale) << what;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace quack
