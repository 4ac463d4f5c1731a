#include "quack/geometry/bounds.hpp"

#include <gtest/gtest.h>

#include <random>

#include "support/random_shapes.hpp"
#include "support/shape_sampling.hpp"

namespace quack {
namespace {

using testing::uniform;

// The box holds every boundary sample and each side is touched by one (tightness).
template <class Shape>
void expectTightBox(const Shape& shape, Transform xf, float tol) {
  Aabb box = computeAabb(shape, xf);
  ASSERT_TRUE(isValid(box));
  Aabb sampled{{1e30f, 1e30f}, {-1e30f, -1e30f}};
  for (Vec2 p : testing::sampleBoundary(shape))
    sampled = merge(sampled, transformPoint(xf, p));
  EXPECT_LE(box.lower.x, sampled.lower.x + tol);
  EXPECT_LE(box.lower.y, sampled.lower.y + tol);
  EXPECT_GE(box.upper.x, sampled.upper.x - tol);
  EXPECT_GE(box.upper.y, sampled.upper.y - tol);
  EXPECT_NEAR(box.lower.x, sampled.lower.x, tol);
  EXPECT_NEAR(box.lower.y, sampled.lower.y, tol);
  EXPECT_NEAR(box.upper.x, sampled.upper.x, tol);
  EXPECT_NEAR(box.upper.y, sampled.upper.y, tol);
}

TEST(Bounds, AabbByHand) {
  Transform xf = makeTransform({10, 0}, 0.5f * kPi);
  Aabb b = computeAabb(makeBox(1, 0.5f).value(), xf);
  EXPECT_NEAR(b.lower.x, 9.5f, 1e-5f);
  EXPECT_NEAR(b.upper.x, 10.5f, 1e-5f);
  EXPECT_NEAR(b.lower.y, -1.0f, 1e-5f);
  EXPECT_NEAR(b.upper.y, 1.0f, 1e-5f);
  Aabb c = computeAabb(makeCircle({1, 0}, 2).value(), xf);
  EXPECT_NEAR(c.lower.x, 8.0f, 1e-5f);
  EXPECT_NEAR(c.upper.y, 3.0f, 1e-5f);
  Aabb s = computeAabb(makeSegment({0, 0}, {2, 0}).value(), Transform{});
  EXPECT_EQ(s, (Aabb{{0, 0}, {2, 0}}));
}

TEST(Bounds, AabbAgreesWithBoundarySamples) {
  const unsigned seed = 31337;
  std::mt19937 rng(seed);
  for (int i = 0; i < 200; ++i) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " i " << i);
    Transform xf =
        makeTransform({uniform(rng, -50, 50), uniform(rng, -50, 50)}, uniform(rng, -kPi, kPi));
    float r = uniform(rng, 0.05f, 1.0f);
    // Sampling a circle of radius r with 4096 points misses its extreme by at most
    // r (1 - cos(pi / 4096)) < 3e-7 r; add float noise at |p| ~ 50.
    const float tol = 1e-4f;
    expectTightBox(makeCircle({uniform(rng, -1, 1), 0}, r).value(), xf, tol);
    expectTightBox(makeCapsule({-1, 0}, {uniform(rng, 0, 2), 1}, r).value(), xf, tol);
    expectTightBox(makeSegment({-1, 0}, {uniform(rng, 0, 2), 1}).value(), xf, tol);
    expectTightBox(testing::randomPolygon(rng, 3 + static_cast<int>(rng() % 10), 1.0f, {},
                                          rng() % 2 ? r : 0.0f),
                   xf, tol);
  }
}

TEST(Bounds, ContainsPointByHand) {
  Circle c = makeCircle({0, 0}, 1).value();
  EXPECT_TRUE(containsPoint(c, {1, 0}));  // boundary counts
  EXPECT_FALSE(containsPoint(c, {1.001f, 0}));
  Capsule k = makeCapsule({-1, 0}, {1, 0}, 0.5f).value();
  EXPECT_TRUE(containsPoint(k, {1.4f, 0}));
  EXPECT_TRUE(containsPoint(k, {0, -0.5f}));
  EXPECT_FALSE(containsPoint(k, {1.4f, 0.4f}));  // outside the end cap
  EXPECT_FALSE(containsPoint(makeSegment({0, 0}, {1, 0}).value(), {0.5f, 0}));
  Polygon box = makeBox(1, 1).value();
  EXPECT_TRUE(containsPoint(box, {1, 1}));
  EXPECT_FALSE(containsPoint(box, {1.01f, 0}));
  Polygon rounded = makeBox(1, 1, {}, 0, 0.5f).value();
  EXPECT_TRUE(containsPoint(rounded, {1.49f, 0}));
  EXPECT_TRUE(containsPoint(rounded, {1.3f, 1.3f}));   // |(0.3,0.3)| = 0.42 < 0.5
  EXPECT_FALSE(containsPoint(rounded, {1.4f, 1.4f}));  // |(0.4,0.4)| = 0.57 > 0.5
}

// Independent containment: crossing-number test on the core, then distance to the core's
// edges computed in double.
bool referenceContains(const Polygon& p, Vec2 q) {
  bool inside = false;
  for (int i = 0, j = p.count - 1; i < p.count; j = i++) {
    Vec2 a = p.vertices[i], b = p.vertices[j];
    if ((a.y > q.y) != (b.y > q.y)) {
      double x =
          a.x + (static_cast<double>(q.y) - a.y) * (b.x - a.x) / (static_cast<double>(b.y) - a.y);
      if (q.x < x) inside = !inside;
    }
  }
  if (inside) return true;
  double best = 1e300;
  for (int i = 0; i < p.count; ++i) {
    double ax = p.vertices[i].x, ay = p.vertices[i].y;
    double bx = p.vertices[(i + 1) % p.count].x, by = p.vertices[(i + 1) % p.count].y;
    double ex = bx - ax, ey = by - ay;
    double t = std::clamp(((q.x - ax) * ex + (q.y - ay) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
    best = std::min(best, std::hypot(ax + t * ex - q.x, ay + t * ey - q.y));
  }
  return best <= p.radius;
}

TEST(Bounds, PolygonContainmentAgreesWithReference) {
  const unsigned seed = 5150;
  std::mt19937 rng(seed);
  int checked = 0;
  for (int i = 0; i < 200; ++i) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " i " << i);
    float r = rng() % 2 ? uniform(rng, 0.01f, 0.5f) : 0.0f;
    Polygon p = testing::randomPolygon(rng, 3 + static_cast<int>(rng() % 16), 1.0f, {}, r);
    for (int k = 0; k < 200; ++k) {
      Vec2 q{uniform(rng, -1.8f, 1.8f), uniform(rng, -1.8f, 1.8f)};
      // Skip points within rounding distance of the boundary, where either answer is right.
      bool near = false;
      for (Vec2 d : {Vec2{1e-4f, 0}, Vec2{-1e-4f, 0}, Vec2{0, 1e-4f}, Vec2{0, -1e-4f}}) {
        near = near || referenceContains(p, q + d) != referenceContains(p, q);
      }
      if (near) continue;
      EXPECT_EQ(containsPoint(p, q), referenceContains(p, q)) << q.x << ", " << q.y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 30000);
}

}  // namespace
}  // namespace quack
