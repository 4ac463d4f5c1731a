// Continuous collision in the world: bullets at 1,000 m/s against a 1 cm wall, a
// thin fast-spinning rod against a thin wall, time-of-impact events in time order, hundreds
// of simultaneous impacts, bullets against dynamic bodies, determinism.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "quack/collision/toi.hpp"
#include "quack/world/world.hpp"
#include "world_test_util.hpp"

namespace quack {
namespace {

float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

// A 1 cm thick wall, 4 m tall, centred on x = 0.
BodyId addWall(World& world, float halfHeight = 2.0f) {
  return testing::addStaticBox(world, {0, 0}, {0.005f, halfHeight});
}

void expectSortedEvents(const World& world) {
  const auto& toi = world.events().toi;
  for (std::size_t i = 0; i < toi.size(); ++i) {
    EXPECT_GE(toi[i].time, 0.0f);
    EXPECT_LE(toi[i].time, 1.0f);
    EXPECT_NEAR(length(toi[i].normal), 1.0f, 1e-4f);
    if (i > 0) {
      EXPECT_LE(toi[i - 1].time, toi[i].time) << "event " << i;
    }
  }
}

TEST(Ccd, BulletAtAThousandMetresPerSecondNeverPassesAThinWall) {
  const unsigned seed = 7101;
  std::mt19937 rng(seed);
  int events = 0;
  for (int trial = 0; trial < 120; ++trial) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    World world = World::create({.gravity = {0, 0}}).value();
    addWall(world);
    const float heading = uniform(rng, -1.2f, 1.2f);  // up to about 70 degrees off normal
    const Vec2 dir{std::cos(heading), std::sin(heading)};
    const Vec2 crossing{0.0f, uniform(rng, -1.8f, 1.8f)};
    const float speed = 1000.0f;
    // Half of them are bullets; the others are caught as fast bodies by their motion.
    const bool bullet = trial % 2 == 0;
    const float before = uniform(rng, 0.1f, 1.9f) * speed / 60.0f;
    BodyId b = world
                   .createBody({.position = crossing - before * dir,
                                .angle = uniform(rng, -kPi, kPi),
                                .linearVelocity = speed * dir,
                                .angularVelocity = uniform(rng, -30.0f, 30.0f),
                                .bullet = bullet})
                   .value();
    if (trial % 4 < 2) {
      (void)world.createShape(b, {}, makeCircle({}, 0.01f).value());
    } else {
      (void)world.createShape(b, {}, makeBox(0.01f, 0.004f).value());
    }
    for (int step = 0; step < 10; ++step) {
      const Vec2 from = world.position(b);
      ASSERT_TRUE(testing::stepAndValidate(world));
      // Through the wall: on its far side while level with it, or crossing x = 0 between
      // its ends. A bullet that slid off an end (it hit at a glancing angle and kept its
      // speed along the wall, restitution 0) may go round it, beyond |y| = 2.
      const Vec2 to = world.position(b);
      if (to.x >= 0.0f) {
        ASSERT_GT(std::abs(to.y), 2.0f) << "through the wall at step " << step;
        if (from.x < 0.0f) {
          const float y = from.y + (to.y - from.y) * (-from.x / (to.x - from.x));
          ASSERT_GT(std::abs(y), 2.0f) << "crossed x = 0 at y = " << y << ", step " << step;
        }
      }
      events += static_cast<int>(world.events().toi.size());
      expectSortedEvents(world);
    }
  }
  RecordProperty("toi_events", events);
  EXPECT_GE(events, 120);
}

TEST(Ccd, WithoutContinuousCollisionTheBulletTunnels) {
  // The control for the test above: the same shot with the continuous phase off.
  World world = World::create({.gravity = {0, 0}, .enableContinuous = false}).value();
  addWall(world);
  BodyId b = world.createBody({.position = {-5, 0}, .linearVelocity = {1000, 0}}).value();
  (void)world.createShape(b, {}, makeCircle({}, 0.01f).value());
  for (int step = 0; step < 10; ++step)
    ASSERT_TRUE(testing::stepAndValidate(world));
  EXPECT_GT(world.position(b).x, 0.0f);
}

TEST(Ccd, ThinFastSpinningRodNeverPassesAThinWall) {
  const unsigned seed = 7102;
  std::mt19937 rng(seed);
  for (int trial = 0; trial < 40; ++trial) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    World world = World::create({.gravity = {0, 0}}).value();
    addWall(world, 3.0f);
    const float spin = uniform(rng, 60.0f, 200.0f) * (trial % 2 == 0 ? 1.0f : -1.0f);
    BodyId rod =
        world
            .createBody({.position = {uniform(rng, -1.5f, -0.6f), uniform(rng, -1, 1)},
                         .angle = uniform(rng, -kPi, kPi),
                         .linearVelocity = {uniform(rng, 1.0f, 30.0f), uniform(rng, -3, 3)},
                         .angularVelocity = spin,
                         .bullet = trial % 3 == 0})
            .value();
    Polygon thin = makeBox(0.5f, 0.004f).value();
    (void)world.createShape(rod, {}, thin);
    for (int step = 0; step < 120; ++step) {
      ASSERT_TRUE(testing::stepAndValidate(world));
      const Transform xf = world.transform(rod);
      ASSERT_LT(xf.p.x, 0.0f) << "centre through the wall at step " << step;
      for (Vec2 end : {Vec2{0.5f, 0}, Vec2{-0.5f, 0}}) {
        // Either end may press into the wall a little (the solver's slop), never past it.
        ASSERT_LT(transformPoint(xf, end).x, 0.005f + 0.05f) << "end through at step " << step;
      }
      expectSortedEvents(world);
    }
  }
}

TEST(Ccd, EventsComeOutSortedByTime) {
  World world = World::create({.gravity = {0, 0}}).value();
  addWall(world, 20.0f);
  // Bullets at different distances: they reach the wall at different times of the step.
  for (int i = 0; i < 30; ++i) {
    BodyId b = world
                   .createBody({.position = {-1.0f - 0.5f * static_cast<float>((i * 7) % 30),
                                             -15.0f + static_cast<float>(i)},
                                .linearVelocity = {1000, 0},
                                .bullet = true})
                   .value();
    (void)world.createShape(b, {}, makeCircle({}, 0.05f).value());
  }
  ASSERT_TRUE(testing::stepAndValidate(world));
  const auto& toi = world.events().toi;
  ASSERT_EQ(toi.size(), 30u);
  expectSortedEvents(world);
  EXPECT_LT(toi.front().time, toi.back().time);
  for (const ToiEvent& e : toi) {
    EXPECT_NEAR(e.normal.x, 1.0f, 1e-4f);  // from the bullet to the wall
    EXPECT_NEAR(e.point.x, -0.005f - kToiTargetSeparation, 2.0f * kToiTolerance);
  }
}

TEST(Ccd, HundredsOfSimultaneousImpactsFinish) {
  // 400 bullets inside a box of 1 cm walls, every one hitting a wall in the first step and
  // then bouncing about (restitution 1): the phase must finish and keep every one inside.
  World world = World::create({.gravity = {0, 0}}).value();
  testing::addStaticBox(world, {-10, 0}, {0.005f, 10.0f});
  testing::addStaticBox(world, {10, 0}, {0.005f, 10.0f});
  testing::addStaticBox(world, {0, -10}, {10.0f, 0.005f});
  testing::addStaticBox(world, {0, 10}, {10.0f, 0.005f});
  std::mt19937 rng(7103);
  std::vector<BodyId> bullets;
  for (int i = 0; i < 400; ++i) {
    const float heading = uniform(rng, -kPi, kPi);
    BodyId b =
        world
            .createBody({.position = {uniform(rng, -9, 9), uniform(rng, -9, 9)},
                         .linearVelocity = 2000.0f * Vec2{std::cos(heading), std::sin(heading)},
                         .bullet = i % 2 == 0})
            .value();
    (void)world.createShape(b, {.restitution = 1.0f}, makeCircle({}, 0.02f).value());
    bullets.push_back(b);
  }
  std::size_t maxEvents = 0;
  for (int step = 0; step < 10; ++step) {
    ASSERT_TRUE(testing::stepAndValidate(world));
    expectSortedEvents(world);
    maxEvents = std::max(maxEvents, world.events().toi.size());
    for (BodyId b : bullets) {
      Vec2 p = world.position(b);
      ASSERT_TRUE(std::abs(p.x) < 10.0f && std::abs(p.y) < 10.0f)
          << "escaped at step " << step << ": " << p.x << ", " << p.y;
    }
  }
  RecordProperty("max_toi_events_per_step", static_cast<int>(maxEvents));
  EXPECT_GE(maxEvents, 400u);
}

TEST(Ccd, BulletDoesNotPassThroughADynamicBox) {
  World world = World::create({}).value();
  testing::addStaticBox(world, {0, -0.5f}, {20, 0.5f});
  BodyId box = testing::addBox(world, {0, 0.5f}, {0.1f, 0.5f});
  BodyId bullet =
      world.createBody({.position = {-5, 0.5f}, .linearVelocity = {600, 0}, .bullet = true})
          .value();
  (void)world.createShape(bullet, {.density = 0.1f}, makeCircle({}, 0.01f).value());
  bool hit = false;
  for (int step = 0; step < 3; ++step) {
    ASSERT_TRUE(testing::stepAndValidate(world));
    for (const ToiEvent& e : world.events().toi)
      hit = hit || world.body(e.shapeB) == box;
    ASSERT_LT(world.position(bullet).x, world.position(box).x) << "step " << step;
  }
  EXPECT_TRUE(hit);
  EXPECT_GT(world.linearVelocity(box).x, 0.0f);  // the box took the impact
}

// The re-check of the event phase: a fast box is stopped by a wall early in the step; a
// bullet crossing the spot where the box now ends the step (but not where it would have
// ended) must meet it, in time order after the box's own event.
TEST(Ccd, BulletIsRecheckedAgainstABodyThatAnEarlierEventMoved) {
  World world = World::create({.gravity = {0, 0}}).value();
  BodyId wall = addWall(world);
  BodyId box = world.createBody({.position = {-3, 0}, .linearVelocity = {600, 0}}).value();
  ShapeId boxShape = world.createShape(box, {}, makeBox(0.1f, 0.1f).value()).value();
  BodyId bullet =
      world.createBody({.position = {-0.12f, 5}, .linearVelocity = {0, -600}, .bullet = true})
          .value();
  ShapeId bulletShape = world.createShape(bullet, {}, makeCircle({}, 0.01f).value()).value();
  ASSERT_TRUE(testing::stepAndValidate(world));
  const auto& toi = world.events().toi;
  // The box at the wall, then the bullet and the box (found by either sweep: both are
  // followed now), then possibly the box, set moving by the bullet, at the wall
  // again.
  ASSERT_GE(toi.size(), 2u);
  EXPECT_EQ(toi[0].shapeA, boxShape);
  EXPECT_EQ(world.body(toi[0].shapeB), wall);
  const bool boxFirst = toi[1].shapeA == boxShape;
  EXPECT_EQ(boxFirst ? toi[1].shapeB : toi[1].shapeA, bulletShape);
  EXPECT_EQ(boxFirst ? toi[1].shapeA : toi[1].shapeB, boxShape);
  for (std::size_t i = 1; i < toi.size(); ++i)
    EXPECT_LE(toi[i - 1].time, toi[i].time);
  EXPECT_LT(toi[0].time, toi[1].time);
  EXPECT_LT(world.position(box).x, 0.0f);
  EXPECT_GT(world.position(bullet).y, world.position(box).y);
}

TEST(Ccd, DeterministicAcrossRunsAndBroadPhases) {
  auto run = [](BroadPhaseKind kind) {
    World world = World::create({.broadPhase = kind}).value();
    testing::addStaticBox(world, {0, -0.5f}, {20, 0.5f});
    testing::addStaticBox(world, {5, 3}, {0.005f, 3});
    std::mt19937 rng(7104);
    for (int i = 0; i < 60; ++i) {
      BodyId b = world
                     .createBody({.position = {uniform(rng, -10, 0), uniform(rng, 0.5f, 5)},
                                  .linearVelocity = {uniform(rng, 100, 800), uniform(rng, -50, 50)},
                                  .angularVelocity = uniform(rng, -50, 50),
                                  .bullet = i % 3 == 0})
                     .value();
      (void)world.createShape(b, {.restitution = 0.3f}, makeBox(0.05f, 0.02f).value());
    }
    for (int step = 0; step < 60; ++step)
      EXPECT_TRUE(testing::stepAndValidate(world));
    return world.stateHash();
  };
  const std::uint64_t first = run(BroadPhaseKind::tree);
  EXPECT_EQ(run(BroadPhaseKind::tree), first);
  for (BroadPhaseKind kind : {BroadPhaseKind::quadtree, BroadPhaseKind::sap, BroadPhaseKind::hash,
                              BroadPhaseKind::brute}) {
    EXPECT_EQ(run(kind), first) << "broad phase " << static_cast<int>(kind);
  }
}

}  // namespace
}  // namespace quack
