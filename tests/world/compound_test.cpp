// A concave body built from its convex pieces: the world's mass properties must be those of
// the whole outline.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "quack/geometry/decompose.hpp"
#include "quack/world/world.hpp"

namespace quack {
namespace {

// Area, centroid and polar moment about the centroid of a polygon with holes (each ring a
// signed-triangle sum in double; holes taken with the opposite sign of the outline).
struct RefMass {
  double area = 0, cx = 0, cy = 0, inertia = 0;
};

RefMass triangleSum(const std::vector<std::vector<Vec2>>& rings) {
  double a = 0, mx = 0, my = 0, i0 = 0;
  for (std::size_t r = 0; r < rings.size(); ++r) {
    const std::vector<Vec2>& o = rings[r];
    double ra = 0, rmx = 0, rmy = 0, ri = 0;
    for (std::size_t k = 0; k < o.size(); ++k) {
      double x1 = o[k].x, y1 = o[k].y;
      double x2 = o[(k + 1) % o.size()].x, y2 = o[(k + 1) % o.size()].y;
      double c = x1 * y2 - x2 * y1;
      ra += c / 2;
      rmx += c * (x1 + x2) / 6;
      rmy += c * (y1 + y2) / 6;
      ri += c * (x1 * x1 + x1 * x2 + x2 * x2 + y1 * y1 + y1 * y2 + y2 * y2) / 12;
    }
    // The outline counts positive, holes negative, whatever their orientation.
    double sign = (r == 0) == (ra > 0) ? 1.0 : -1.0;
    a += sign * ra;
    mx += sign * rmx;
    my += sign * rmy;
    i0 += sign * ri;
  }
  RefMass m;
  m.area = a;
  m.cx = mx / a;
  m.cy = my / a;
  m.inertia = i0 - a * (m.cx * m.cx + m.cy * m.cy);
  return m;
}

void checkBody(const std::vector<Vec2>& outline, const std::vector<std::vector<Vec2>>& holes,
               float density, const std::string& what) {
  SCOPED_TRACE(what);
  ConvexDecomposition d = decomposePolygon(outline, holes).value();
  World world = World::create({}).value();
  // Off the origin and turned, so the body frame and the world frame differ.
  BodyId body = world.createBody({.position = {3, -2}, .angle = 0.7f}).value();
  for (const Polygon& p : d.pieces)
    ASSERT_TRUE(world.createShape(body, {.density = density}, p).ok());
  std::vector<std::vector<Vec2>> rings = {outline};
  rings.insert(rings.end(), holes.begin(), holes.end());
  RefMass ref = triangleSum(rings);
  EXPECT_NEAR(world.mass(body), density * ref.area, 1e-4 * density * ref.area);
  Vec2 c = invTransformPoint(world.transform(body), world.worldCenterOfMass(body));
  double size = std::sqrt(ref.area);
  EXPECT_NEAR(c.x, ref.cx, 1e-4 * size);
  EXPECT_NEAR(c.y, ref.cy, 1e-4 * size);
  EXPECT_NEAR(world.rotationalInertia(body), density * ref.inertia, 2e-4 * density * ref.inertia);
}

TEST(Compound, ConcaveBodyMassMatchesTheOutline) {
  // The L of the README: area 7, centroid and inertia by hand from two rectangles.
  std::vector<Vec2> l = {{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 4}, {0, 4}};
  checkBody(l, {}, 2.0f, "L");
  ConvexDecomposition d = decomposePolygon(l).value();
  World world = World::create({}).value();
  BodyId body = world.createBody({}).value();
  for (const Polygon& p : d.pieces)
    ASSERT_TRUE(world.createShape(body, {}, p).ok());
  // Rectangles [0,4]x[0,1] (area 4, centre (2, 0.5)) and [0,1]x[1,4] (area 3, (0.5, 2.5)).
  EXPECT_NEAR(world.mass(body), 7.0f, 1e-5f);
  Vec2 c = world.worldCenterOfMass(body);
  EXPECT_NEAR(c.x, (4 * 2.0 + 3 * 0.5) / 7, 1e-5);
  EXPECT_NEAR(c.y, (4 * 0.5 + 3 * 2.5) / 7, 1e-5);
  double cx = 9.5 / 7, cy = 9.5 / 7;
  double i1 = 4 * (16 + 1) / 12.0 + 4 * ((2 - cx) * (2 - cx) + (0.5 - cy) * (0.5 - cy));
  double i2 = 3 * (1 + 9) / 12.0 + 3 * ((0.5 - cx) * (0.5 - cx) + (2.5 - cy) * (2.5 - cy));
  EXPECT_NEAR(world.rotationalInertia(body), i1 + i2, 1e-4 * (i1 + i2));
}

TEST(Compound, RandomOutlinesAndHoles) {
  for (std::uint32_t seed = 1; seed <= 30; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> ur(0.4f, 1.0f);
    int count = 6 + static_cast<int>(rng() % 80);
    std::vector<Vec2> star;
    for (int i = 0; i < count; ++i) {
      float a = 2.0f * kPi * static_cast<float>(i) / static_cast<float>(count);
      float r = 3.0f * ur(rng);
      star.push_back({1.0f + r * std::cos(a), -0.5f + r * std::sin(a)});
    }
    std::vector<std::vector<Vec2>> holes;
    if (seed % 3 == 0) {
      holes.push_back({{0.6f, -0.9f}, {1.4f, -0.9f}, {1.4f, -0.1f}, {0.6f, -0.1f}});
    }
    checkBody(star, holes, 0.5f + static_cast<float>(seed % 4), "seed " + std::to_string(seed));
  }
}

}  // namespace
}  // namespace quack
