#include "quack/geometry/mass.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "support/random_shapes.hpp"

namespace quack {
namespace {

// Independent reference: area, centroid and polar moment about the centroid of a simple
// polygon outline, by a signed-triangle sum in double precision.
struct RefMass {
  double area = 0, cx = 0, cy = 0, inertia = 0;
};

RefMass triangleSum(const std::vector<Vec2>& outline) {
  double a = 0, mx = 0, my = 0, i0 = 0;
  for (std::size_t k = 0; k < outline.size(); ++k) {
    double x1 = outline[k].x, y1 = outline[k].y;
    double x2 = outline[(k + 1) % outline.size()].x, y2 = outline[(k + 1) % outline.size()].y;
    double c = x1 * y2 - x2 * y1;
    a += c / 2;
    mx += c * (x1 + x2) / 6;
    my += c * (y1 + y2) / 6;
    i0 += c * (x1 * x1 + x1 * x2 + x2 * x2 + y1 * y1 + y1 * y2 + y2 * y2) / 12;
  }
  RefMass r;
  r.area = a;
  r.cx = mx / a;
  r.cy = my / a;
  r.inertia = i0 - a * (r.cx * r.cx + r.cy * r.cy);
  return r;
}

// Outline of a rounded convex polygon (or capsule: two vertices), arcs cut into fine steps.
std::vector<Vec2> roundedOutline(const std::vector<Vec2>& core, float radius, int stepsPerTurn) {
  std::vector<Vec2> out;
  const std::size_t n = core.size();
  for (std::size_t i = 0; i < n; ++i) {
    Vec2 prev = core[(i + n - 1) % n], v = core[i], next = core[(i + 1) % n];
    Vec2 nIn = normalize(rightPerp(v - prev));
    Vec2 nOut = normalize(rightPerp(next - v));
    double a0 = std::atan2(nIn.y, nIn.x);
    double sweep = std::atan2(cross(nIn, nOut), dot(nIn, nOut));
    if (sweep <= 0) sweep += 2 * M_PI;  // a capsule end turns by exactly pi: atan2 may say -pi
    int steps = std::max(1, static_cast<int>(stepsPerTurn * sweep / (2 * M_PI)));
    for (int s = 0; s <= steps; ++s) {
      double a = a0 + sweep * s / steps;
      out.push_back(v + radius *
                            Vec2{static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a))});
    }
  }
  return out;
}

void expectMatches(const MassProperties& m, const RefMass& ref, float density, double relTol) {
  double scale = std::sqrt(std::abs(ref.area));
  EXPECT_NEAR(m.area, ref.area, relTol * std::abs(ref.area));
  EXPECT_NEAR(m.mass, density * ref.area, relTol * density * std::abs(ref.area));
  EXPECT_NEAR(m.centroid.x, ref.cx, relTol * scale + 1e-6 * std::abs(ref.cx));
  EXPECT_NEAR(m.centroid.y, ref.cy, relTol * scale + 1e-6 * std::abs(ref.cy));
  EXPECT_NEAR(m.inertia, density * ref.inertia, relTol * density * ref.inertia);
}

TEST(Mass, ClosedFormsByHand) {
  MassProperties c = computeMass(makeCircle({1, 2}, 0.5f).value(), 2.0f);
  EXPECT_FLOAT_EQ(c.area, kPi * 0.25f);
  EXPECT_FLOAT_EQ(c.mass, 2.0f * kPi * 0.25f);
  EXPECT_EQ(c.centroid, (Vec2{1, 2}));
  EXPECT_FLOAT_EQ(c.inertia, c.mass * 0.125f);

  MassProperties b = computeMass(makeBox(1.0f, 0.5f, {3, 4}, 0.3f).value(), 2.0f);
  EXPECT_FLOAT_EQ(b.area, 2.0f);
  EXPECT_FLOAT_EQ(b.mass, 4.0f);
  EXPECT_NEAR(b.centroid.x, 3.0f, 1e-5f);
  EXPECT_NEAR(b.centroid.y, 4.0f, 1e-5f);
  EXPECT_NEAR(b.inertia, 4.0f * (4.0f + 1.0f) / 12.0f, 1e-5f);

  const Vec2 tri[] = {{0, 0}, {3, 0}, {0, 3}};
  MassProperties t = computeMass(makePolygon(tri).value(), 2.0f);
  EXPECT_FLOAT_EQ(t.area, 4.5f);
  EXPECT_NEAR(t.centroid.x, 1.0f, 1e-6f);
  EXPECT_NEAR(t.centroid.y, 1.0f, 1e-6f);
  EXPECT_NEAR(t.inertia, 9.0f * 18.0f / 18.0f, 1e-4f);  // m (a^2 + b^2) / 18

  // Capsule, L = 2, r = 0.5: rectangle plus two half-disks, worked by hand.
  MassProperties k = computeMass(makeCapsule({-1, 0}, {1, 0}, 0.5f).value(), 2.0f);
  const double L = 2, r = 0.5, rho = 2;
  double rectMass = rho * 2 * r * L, halfMass = rho * M_PI * r * r / 2;
  double inertia = rectMass * (L * L + 4 * r * r) / 12 +
                   2 * halfMass * (r * r / 2 + L * L / 4 + L * 4 * r / (3 * M_PI));
  EXPECT_NEAR(k.area, 2 * r * L + M_PI * r * r, 1e-5);
  EXPECT_NEAR(k.inertia, inertia, 1e-5);
  EXPECT_NEAR(k.centroid.x, 0, 1e-6);

  // 2 x 2 box rounded by 0.25: area = core + perimeter r + pi r^2.
  MassProperties rb = computeMass(makeBox(1, 1, {}, 0, 0.25f).value(), 1.0f);
  EXPECT_NEAR(rb.area, 4 + 8 * 0.25 + M_PI / 16, 1e-5);
  EXPECT_NEAR(rb.centroid.x, 0, 1e-6);

  MassProperties s = computeMass(makeSegment({0, 0}, {2, 2}).value(), 5.0f);
  EXPECT_EQ(s.mass, 0.0f);
  EXPECT_EQ(s.inertia, 0.0f);
  EXPECT_EQ(s.centroid, (Vec2{1, 1}));
}

TEST(Mass, PolygonsAgreeWithTriangleSum) {
  const unsigned seed = 4242;
  std::mt19937 rng(seed);
  for (int i = 0; i < 300; ++i) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " i " << i);
    int n = 3 + static_cast<int>(rng() % 30);
    float size = std::pow(10.0f, testing::uniform(rng, -2, 2));
    Polygon p = testing::randomPolygon(rng, n, size, {2 * size, size});
    std::vector<Vec2> outline(p.vertices, p.vertices + p.count);
    expectMatches(computeMass(p, 3.0f), triangleSum(outline), 3.0f, 2e-4);
  }
}

TEST(Mass, RoundedShapesAgreeWithFineOutline) {
  const unsigned seed = 777;
  std::mt19937 rng(seed);
  for (int i = 0; i < 100; ++i) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " i " << i);
    int n = 3 + static_cast<int>(rng() % 12);
    float radius = testing::uniform(rng, 0.01f, 1.0f);
    Polygon p = testing::randomPolygon(rng, n, 1.0f, {0.5f, -0.25f}, radius);
    std::vector<Vec2> core(p.vertices, p.vertices + p.count);
    // 20000 steps a turn: the chord error of the arcs is far below the tolerance.
    expectMatches(computeMass(p, 1.5f), triangleSum(roundedOutline(core, radius, 20000)), 1.5f,
                  1e-3);
  }
  for (int i = 0; i < 100; ++i) {
    SCOPED_TRACE(::testing::Message() << "capsule seed " << seed << " i " << i);
    Vec2 a{testing::uniform(rng, -2, 2), testing::uniform(rng, -2, 2)};
    Vec2 b{testing::uniform(rng, -2, 2), testing::uniform(rng, -2, 2)};
    float radius = testing::uniform(rng, 0.05f, 1.0f);
    if (distance(a, b) < 0.1f) continue;
    Capsule c = makeCapsule(a, b, radius).value();
    expectMatches(computeMass(c, 0.5f), triangleSum(roundedOutline({a, b}, radius, 20000)), 0.5f,
                  1e-3);
  }
}

}  // namespace
}  // namespace quack
