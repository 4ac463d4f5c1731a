// World3's queries against hand-worked cases and against brute force over every shape
// (the collision layer's own routines called shape by shape, with no broad phase).

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "quack/collision/epa3.hpp"
#include "quack/collision/gjk3.hpp"
#include "quack/collision/toi3.hpp"
#include "quack/geometry/raycast3.hpp"
#include "quack/world/world3.hpp"

namespace quack {
namespace {

// A unit-half-extent box ground at y in [-1, 0], a one-sided mesh square at y = 5 facing
// up, and a sphere of radius 0.5 at (3, 1, 0).
struct Scene {
  World3 world = World3::create().value();
  ShapeId3 ground, mesh, ball;
  Scene() {
    const BodyId3 g = world.createBody({.type = BodyType::staticBody}).value();
    ground =
        world.createShape(g, {}, makeBox3({10, 0.5f, 10}, {{0, -0.5f, 0}, {}}).value()).value();
    const std::array<Vec3, 4> v = {Vec3{-2, 5, -2}, Vec3{-2, 5, 2}, Vec3{2, 5, 2}, Vec3{2, 5, -2}};
    const std::array<std::array<std::int32_t, 3>, 2> t = {{{0, 1, 2}, {0, 2, 3}}};
    const BodyId3 m = world.createBody({.type = BodyType::staticBody}).value();
    mesh = world.createShape(m, {}, makeMesh3(v, t).value()).value();
    const BodyId3 b = world.createBody({.position = {3, 1, 0}}).value();
    ball = world.createShape(b, {.filter = {.category = 2}}, Sphere{{}, 0.5f}).value();
  }
};

TEST(World3Query, RaysMeetTheNearestShapeAtTheHandWorkedPoint) {
  Scene s;
  // Straight down from y = 10 at x = 0: the mesh's front at y = 5 (fraction 0.25).
  auto hit = s.world.rayCastClosest({0, 10, 0}, {0, -20, 0});
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->shape, s.mesh);
  EXPECT_NEAR(hit->fraction, 0.25f, 1e-6f);
  EXPECT_NEAR(hit->normal.y, 1.0f, 1e-6f);
  EXPECT_GE(hit->triangle, 0);
  // From below the mesh, upwards: its back lets the ray through, and nothing else is there.
  EXPECT_FALSE(s.world.rayCastClosest({0, 3, 0}, {0, 10, 0}).has_value());
  // Down at x = 3: the ball's top at y = 1.5, then the ground at y = 0.
  auto all = s.world.rayCastAll({3, 10, 0}, {0, -20, 0});
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].shape, s.ball);
  EXPECT_NEAR(all[0].point.y, 1.5f, 1e-5f);
  EXPECT_EQ(all[1].shape, s.ground);
  EXPECT_NEAR(all[1].point.y, 0.0f, 1e-5f);
  // A filter that does not see category 2 skips the ball.
  auto ground = s.world.rayCastClosest({3, 10, 0}, {0, -20, 0}, {.mask = ~std::uint64_t{2}});
  ASSERT_TRUE(ground.has_value());
  EXPECT_EQ(ground->shape, s.ground);
  // A zero or non-finite ray meets nothing.
  EXPECT_FALSE(s.world.rayCastClosest({0, 10, 0}, {0, 0, 0}).has_value());
  EXPECT_FALSE(s.world.rayCastClosest({0, 10, 0}, {0, std::nanf(""), 0}).has_value());
}

TEST(World3Query, OverlapsAndCastsOnTheHandWorkedScene) {
  Scene s;
  auto boxes = s.world.overlapAabb({{2, 0.9f, -0.1f}, {4, 1.1f, 0.1f}});
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0], s.ball);
  // A 1 m cube at (3, 0.4, 0) overlaps the ground (by 0.1 m) and the ball (0.6 m deep
  // along y: the ball's bottom at 0.5, the cube's top at 0.9... the least push is EPA's).
  auto over = s.world.overlapShape(makeBox3({0.5f, 0.5f, 0.5f}).value(), {{3, 0.4f, 0}, {}});
  ASSERT_TRUE(over.ok());
  ASSERT_EQ(over.value().size(), 2u);
  EXPECT_EQ(over.value()[0].shape, s.ground);
  EXPECT_NEAR(over.value()[0].depth, 0.1f, 1e-4f);
  EXPECT_NEAR(over.value()[0].depenetration.y, 0.1f, 1e-4f);  // up, out of the ground
  // Moving the cube by each depenetration separates it from that shape.
  for (const ShapeOverlap3& o : over.value()) {
    const Transform3 moved{Vec3{3, 0.4f, 0} + 1.001f * o.depenetration, {}};
    auto again = s.world.overlapShape(makeBox3({0.5f, 0.5f, 0.5f}).value(), moved);
    ASSERT_TRUE(again.ok());
    for (const ShapeOverlap3& a : again.value())
      EXPECT_FALSE(a.shape == o.shape && a.depth > 1e-4f);
  }
  // A sphere of radius 0.25 dropped from y = 4 at x = -3 meets the ground when its centre
  // is at 0.25: fraction 3.75 / 10.
  auto cast = s.world.castShape(Sphere{{}, 0.25f}, {{-3, 4, 0}, {}}, {0, -10, 0});
  ASSERT_TRUE(cast.ok());
  ASSERT_TRUE(cast.value().has_value());
  EXPECT_EQ(cast.value()->shape, s.ground);
  EXPECT_NEAR(cast.value()->fraction, 0.375f, 2e-3f);
  EXPECT_NEAR(cast.value()->normal.y, 1.0f, 1e-3f);
  // Bad input is refused by name.
  auto bad = s.world.castShape(Sphere{{}, -1.0f}, {}, {0, -1, 0});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("castShape: geometry"), std::string::npos);
  EXPECT_FALSE(s.world.overlapShape(Sphere{{}, 1.0f}, {{0, std::nanf(""), 0}, {}}).ok());
}

// Random scenes: every query's answer is brute force's over every shape in index order.
TEST(World3Query, RandomQueriesAgreeWithBruteForce) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  World3 world = World3::create().value();
  struct Placed {
    ShapeId3 id;
    ShapeGeometry3 geometry;
    Transform3 xf;
  };
  std::vector<Placed> shapes;
  for (int i = 0; i < 90; ++i) {
    const Vec3 p{6 * u(rng), 6 * u(rng), 6 * u(rng)};
    const Quat q = normalize(Quat{u(rng), u(rng), u(rng), u(rng) + 1.5f});
    const BodyId3 b =
        world.createBody({.type = BodyType::staticBody, .position = p, .rotation = q}).value();
    ShapeGeometry3 g;
    if (i % 3 == 0) g = Sphere{{}, 0.3f + 0.5f * std::fabs(u(rng))};
    if (i % 3 == 1) g = makeBox3({0.3f + 0.6f * std::fabs(u(rng)), 0.4f, 0.6f}).value();
    if (i % 3 == 2) g = Capsule3{{-0.5f, 0, 0}, {0.5f, 0, 0}, 0.3f};
    const ShapeId3 id = world.createShape(b, {}, g).value();
    shapes.push_back({id, g, world.transform(b)});
  }
  int rayHits = 0, overlaps = 0, castHits = 0;
  for (int k = 0; k < 200; ++k) {
    const Vec3 origin{10 * u(rng), 10 * u(rng), 10 * u(rng)};
    // Aimed through a point among the shapes, so that most rays and casts meet one.
    const Vec3 target{4 * u(rng), 4 * u(rng), 4 * u(rng)};
    const Vec3 translation = 1.5f * (target - origin);
    // Rays: the closest entry over every shape.
    float best = 2.0f;
    std::uint32_t bestShape = 0;
    for (const Placed& s : shapes) {
      const RayHit3 h = rayCast(
          s.geometry, {invTransformPoint(s.xf, origin), invRotate(s.xf.q, translation), 1.0f});
      if (h.hit && h.fraction < best) {
        best = h.fraction;
        bestShape = s.id.index;
      }
    }
    auto hit = world.rayCastClosest(origin, translation);
    ASSERT_EQ(hit.has_value(), best <= 1.0f) << k;
    if (hit) {
      ++rayHits;
      EXPECT_EQ(hit->shape.index, bestShape) << k;
      EXPECT_EQ(hit->fraction, best) << k;
    }
    // Overlaps: a sphere of radius 1 at the ray's target.
    const Sphere probe{{}, 1.0f};
    std::vector<std::uint32_t> expected;
    for (const Placed& s : shapes)
      if (testOverlap(ShapeGeometry3{probe}, {target, {}}, s.geometry, s.xf))
        expected.push_back(s.id.index);
    auto over = world.overlapShape(probe, {target, {}});
    ASSERT_TRUE(over.ok());
    // GJK's overlap and EPA's agree except within rounding of touching: none of those here.
    ASSERT_EQ(over.value().size(), expected.size()) << k;
    for (std::size_t i = 0; i < expected.size(); ++i)
      EXPECT_EQ(over.value()[i].shape.index, expected[i]) << k;
    overlaps += int(expected.size());
    // Shape casts: a 0.2 m ball along the ray, the earliest hit over every shape.
    const Sphere ball{{}, 0.2f};
    float first = 2.0f;
    std::uint32_t firstShape = 0;
    for (const Placed& s : shapes) {
      const ShapeCastOutput3 c =
          castShape(makeProxy(s.geometry), s.xf, makeProxy(ball), {origin, {}}, translation);
      if (c.hit && c.fraction < first) {
        first = c.fraction;
        firstShape = s.id.index;
      }
    }
    auto cast = world.castShape(ball, {origin, {}}, translation);
    ASSERT_TRUE(cast.ok());
    ASSERT_EQ(cast.value().has_value(), first <= 1.0f) << k;
    if (cast.value()) {
      ++castHits;
      EXPECT_EQ(cast.value()->shape.index, firstShape) << k;
      EXPECT_EQ(cast.value()->fraction, first) << k;
    }
  }
  // The random scene exercises every answer.
  EXPECT_GT(rayHits, 60);
  EXPECT_GT(overlaps, 100);
  EXPECT_GT(castHits, 100);
  std::printf("rays %d, overlaps %d, casts %d of 200\n", rayHits, overlaps, castHits);
}

}  // namespace
}  // namespace quack
