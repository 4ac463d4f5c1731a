// Continuous collision between moving bodies: sweeps against sweeps, one queue in
// time order, both bodies answered at the impact, impact callbacks. Each test fails without
// the phase (two bullets, or two fast bodies, pass through each other at end-of-step poses).

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "quack/world/world.hpp"
#include "world_test_util.hpp"

namespace quack {
namespace {

float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

BodyId addDisc(World& world, Vec2 position, Vec2 velocity, float radius, ShapeDef def,
               bool bullet) {
  BodyId b = world.createBody({.position = position, .linearVelocity = velocity, .bullet = bullet})
                 .value();
  (void)world.createShape(b, def, makeCircle({}, radius).value()).value();
  return b;
}

// Two bullets fired head-on at 500 m/s each, of different masses, restitution 0.5: they meet
// inside the first step (10 m apart, closing 16.7 m per step) and must come out with the
// velocities of a one-dimensional impact: v1' = (m1 v1 + m2 v2 - m2 e (v1 - v2)) / (m1 + m2),
// v2' = (m1 v1 + m2 v2 + m1 e (v1 - v2)) / (m1 + m2).
TEST(CcdDynamic, HeadOnBulletsNeverPassAndReboundAsMomentumAndRestitutionSay) {
  for (int trial = 0; trial < 8; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    World world = World::create({.gravity = {0, 0}}).value();
    const float e = 0.5f;
    const float density2 = 1.0f + static_cast<float>(trial);  // mass ratios 1 to 8
    const float offset = 0.013f * static_cast<float>(trial);  // where in the step they meet
    BodyId left = addDisc(world, {-5.0f - offset, 0}, {500, 0}, 0.05f,
                          {.density = 1.0f, .friction = 0.0f, .restitution = e}, true);
    BodyId right = addDisc(world, {5.0f, 0}, {-500, 0}, 0.05f,
                           {.density = density2, .friction = 0.0f, .restitution = e}, true);
    const float m1 = world.mass(left), m2 = world.mass(right);
    const float v1 = 500.0f, v2 = -500.0f;
    const float p = m1 * v1 + m2 * v2;
    const float expected1 = (p - m2 * e * (v1 - v2)) / (m1 + m2);
    const float expected2 = (p + m1 * e * (v1 - v2)) / (m1 + m2);
    int impacts = 0;
    for (int step = 0; step < 10; ++step) {
      ASSERT_TRUE(testing::stepAndValidate(world));
      for (const ToiEvent& ev : world.events().toi) {
        const bool pair = (world.body(ev.shapeA) == left && world.body(ev.shapeB) == right) ||
                          (world.body(ev.shapeA) == right && world.body(ev.shapeB) == left);
        if (!pair) continue;
        ++impacts;
        EXPECT_NEAR(ev.approachSpeed, 1000.0f, 1e-2f);
        EXPECT_NEAR(std::abs(ev.normal.x), 1.0f, 1e-5f);
      }
      ASSERT_LT(world.position(left).x, world.position(right).x) << "passed at step " << step;
    }
    EXPECT_EQ(impacts, 1);
    EXPECT_NEAR(world.linearVelocity(left).x, expected1, 1e-3f * 500.0f);
    EXPECT_NEAR(world.linearVelocity(right).x, expected2, 1e-3f * 500.0f);
    EXPECT_NEAR(world.linearVelocity(left).y, 0.0f, 1e-3f);
    EXPECT_NEAR(m1 * world.linearVelocity(left).x + m2 * world.linearVelocity(right).x, p,
                1e-4f * (m1 + m2) * 500.0f);
  }
}

// A bullet aimed at the pivot of a thin (2 cm) paddle that spins at 100 rad/s (1.7 rad per
// step): the paddle always covers its centre, so the bullet must meet it. Passing through
// would leave it on its way unchanged; a real impact sends it off the paddle's face, away
// from the paddle along the impact's normal (a glancing blow off a paddle nearly edge-on
// may still carry it on past the pivot: that is not passing through). Speeds 300 to
// 1,000 m/s, any phase of the spin; without the phase the bullet goes straight through.
TEST(CcdDynamic, BulletNeverPassesAThinPaddleSpinningAtAHundredRadiansPerSecond) {
  std::mt19937 rng(1800);
  int passedWithout = 0;
  for (int trial = 0; trial < 40; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const float speed = uniform(rng, 300.0f, 1000.0f);
    const float phase = uniform(rng, -kPi, kPi);
    const float aim = uniform(rng, -0.008f, 0.008f);
    const float start = -uniform(rng, 3.0f, 12.0f);
    for (bool continuous : {true, false}) {
      World world = World::create({.gravity = {0, 0}, .enableContinuous = continuous}).value();
      BodyId paddle =
          world.createBody({.position = {0, 0}, .angle = phase, .angularVelocity = 100.0f}).value();
      (void)world.createShape(paddle, {.density = 5.0f}, makeBox(0.01f, 1.0f).value()).value();
      BodyId bullet = addDisc(world, {start, aim}, {speed, 0}, 0.01f,
                              {.density = 1.0f, .restitution = 1.0f}, true);
      int met = 0;
      Vec2 away;  // the first impact's normal, from the paddle to the bullet
      for (int step = 0; step < 12; ++step) {
        ASSERT_TRUE(testing::stepAndValidate(world));
        for (const ToiEvent& ev : world.events().toi) {
          const bool paddleFirst = world.body(ev.shapeA) == paddle;
          if (!paddleFirst && world.body(ev.shapeB) != paddle) continue;
          if (met++ == 0) away = paddleFirst ? ev.normal : -ev.normal;
        }
      }
      const Vec2 v = world.linearVelocity(bullet);
      const bool unchanged = length(v - Vec2{speed, 0}) < 1.0f;
      if (continuous) {
        EXPECT_GE(met, 1);
        EXPECT_FALSE(unchanged);
        EXPECT_GT(dot(v - world.linearVelocity(paddle), away), 0.0f);
      } else {
        passedWithout += unchanged && world.position(bullet).x > 1.0f ? 1 : 0;
      }
    }
  }
  // The control: at these speeds the discrete solver alone lets most through untouched.
  RecordProperty("passed_without_continuous", passedWithout);
  EXPECT_GT(passedWithout, 20);
}

// Bodies that move together are the contact solver's, not the continuous phase's. A train
// of ten 0.2 m boxes at 60 m/s (1 m a step, 5x their thickness), the first five touching,
// the others 5 cm apart, on frictionless ice: all ten are fast, yet no pair of them can
// pass through the other (they move alike), so the first step, before the train reaches
// the wall, runs no time-of-impact search at all. Then the wall stops them, none passes it.
TEST(CcdDynamic, BodiesMovingTogetherAreLeftToTheContactSolver) {
  World world = World::create({.gravity = {0, 0}}).value();
  BodyId wall = world.createBody({.type = BodyType::staticBody, .position = {6, 0}}).value();
  (void)world.createShape(wall, {}, makeBox(0.5f, 2.0f).value()).value();
  std::vector<BodyId> train;
  float x = 0.0f;
  for (int i = 0; i < 10; ++i) {
    BodyId b = world.createBody({.position = {x, 0}, .linearVelocity = {60, 0}}).value();
    (void)world.createShape(b, {.friction = 0.0f}, makeBox(0.1f, 0.1f).value()).value();
    train.push_back(b);
    x -= i < 4 ? 0.2f : 0.25f;  // the first five touch, the rest 5 cm apart
  }
  ASSERT_TRUE(testing::stepAndValidate(world));
  EXPECT_EQ(world.continuousStats().fastBodies, 10u);
  EXPECT_EQ(world.continuousStats().toiSearches, 0u);
  EXPECT_TRUE(world.events().toi.empty());
  for (BodyId b : train)
    EXPECT_NEAR(world.linearVelocity(b).x, 60.0f, 1e-3f);
  for (int step = 0; step < 30; ++step)
    ASSERT_TRUE(testing::stepAndValidate(world));
  for (BodyId b : train)
    EXPECT_LT(world.position(b).x, 5.5f);
}

// A box that touches a still box at the start of the step (a manifold with points) and
// leaves it at 60 m/s: the contact solver has the pair, so the phase runs no search for it
// though the box is fast and the other is within its swept box. A bullet in the same place
// is still searched against it. Either way the box leaves and the other stays.
TEST(CcdDynamic, ATouchingPairOfDynamicBodiesIsTheSolversUnlessABulletIsInIt) {
  for (bool bullet : {false, true}) {
    SCOPED_TRACE(bullet ? "bullet" : "not a bullet");
    World world = World::create({.gravity = {0, 0}}).value();
    BodyId a = world.createBody({.position = {0, 0}, .linearVelocity = {-60, 0}, .bullet = bullet})
                   .value();
    (void)world.createShape(a, {.friction = 0.0f}, makeBox(0.1f, 0.1f).value()).value();
    BodyId b = world.createBody({.position = {0.2f, 0}}).value();
    (void)world.createShape(b, {.friction = 0.0f}, makeBox(0.1f, 0.1f).value()).value();
    ASSERT_TRUE(testing::stepAndValidate(world));
    EXPECT_EQ(world.continuousStats().fastBodies, 1u);
    if (bullet)
      EXPECT_GT(world.continuousStats().toiSearches, 0u);
    else
      EXPECT_EQ(world.continuousStats().toiSearches, 0u);
    EXPECT_NEAR(world.linearVelocity(a).x, -60.0f, 1e-3f);
    EXPECT_NEAR(world.position(a).x, -1.0f, 1e-3f);
    EXPECT_EQ(world.linearVelocity(b).x, 0.0f);
  }
}

// Two fast boxes (not bullets) whose paths cross at right angles, both reaching the crossing
// in the middle of a step: at end-of-step poses they never overlap (5 m apart on each side).
TEST(CcdDynamic, FastBoxCrossingAnotherFastBoxPathAtRightAnglesHitsIt) {
  for (int trial = 0; trial < 6; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    for (bool continuous : {true, false}) {
      World world = World::create({.gravity = {0, 0}, .enableContinuous = continuous}).value();
      const float lag = 0.05f * static_cast<float>(trial);  // B a little behind A
      BodyId a = world.createBody({.position = {-7.5f, 0}, .linearVelocity = {300, 0}}).value();
      ShapeId sa = world.createShape(a, {}, makeBox(0.2f, 0.2f).value()).value();
      BodyId b =
          world.createBody({.position = {0, -7.5f - lag}, .linearVelocity = {0, 300}}).value();
      ShapeId sb = world.createShape(b, {}, makeBox(0.2f, 0.2f).value()).value();
      int impacts = 0, mostInAStep = 0;
      for (int step = 0; step < 4; ++step) {
        ASSERT_TRUE(testing::stepAndValidate(world));
        int inStep = 0;
        for (const ToiEvent& ev : world.events().toi)
          inStep += (ev.shapeA == sa && ev.shapeB == sb) || (ev.shapeA == sb && ev.shapeB == sa);
        impacts += inStep;
        mostInAStep = std::max(mostInAStep, inStep);
      }
      const Vec2 va = world.linearVelocity(a), vb = world.linearVelocity(b);
      if (!continuous) {
        // The control: straight through, untouched.
        EXPECT_EQ(va.y, 0.0f);
        EXPECT_EQ(vb.x, 0.0f);
        continue;
      }
      // The first impact is at a corner: it sets both spinning, and the turning boxes meet
      // again a few times within the step, each time slower, up to the bound. The bound is
      // per body and step, and each event counts for at least one of the two (for both when
      // its impulse moves both), so one step has at most twice the bound for the pair.
      EXPECT_GE(impacts, 1);
      EXPECT_LE(mostInAStep, 2 * kMaxToiEventsPerBody);
      // They met: each turned the other, and momentum (equal masses) is kept.
      EXPECT_GT(std::abs(va.y) + std::abs(vb.x), 10.0f);
      EXPECT_NEAR(va.x + vb.x, 300.0f, 0.5f);
      EXPECT_NEAR(va.y + vb.y, 300.0f, 0.5f);
      // And neither is where its straight path would have taken it.
      EXPECT_LT(world.position(a).x, 12.0f);
    }
  }
}

struct BoxRun {
  std::uint64_t hash = 0;
  std::uint64_t bodiesHash = 0;  // the fast bodies' poses and velocities, bit for bit
  int steps = 0, escaped = 0, impacts = 0, callbacks = 0, capped = 0;
  bool sorted = true, callbacksMatch = true;
};

// `count` small fast bodies (discs and boxes, 60 to 200 m/s, restitution 1) in a closed box
// of 1 cm walls, 20 m across; `farStatics` static boxes far outside it, which nothing meets.
BoxRun runClosedBox(int count, int steps, BroadPhaseKind kind, unsigned seed, int farStatics = 0) {
  World world = World::create({.gravity = {0, 0}, .broadPhase = kind}).value();
  constexpr float kHalf = 10.0f, kWall = 0.005f;
  testing::addStaticBox(world, {0, -kHalf}, {kHalf + kWall, kWall});
  testing::addStaticBox(world, {0, kHalf}, {kHalf + kWall, kWall});
  testing::addStaticBox(world, {-kHalf, 0}, {kWall, kHalf + kWall});
  testing::addStaticBox(world, {kHalf, 0}, {kWall, kHalf + kWall});
  std::mt19937 rng(seed);
  std::vector<BodyId> bodies;
  for (int i = 0; i < count; ++i) {
    const Vec2 p{uniform(rng, -9.5f, 9.5f), uniform(rng, -9.5f, 9.5f)};
    const float heading = uniform(rng, -kPi, kPi);
    const float speed = uniform(rng, 60.0f, 200.0f);
    BodyId b =
        world
            .createBody({.position = p,
                         .angle = uniform(rng, -kPi, kPi),
                         .linearVelocity = speed * Vec2{std::cos(heading), std::sin(heading)},
                         .angularVelocity = uniform(rng, -30.0f, 30.0f),
                         .enableSleep = false})
            .value();
    const ShapeDef def{.friction = 0.0f, .restitution = 1.0f};
    if (i % 2 == 0) {
      (void)world.createShape(b, def, makeCircle({}, 0.04f).value()).value();
    } else {
      (void)world.createShape(b, def, makeBox(0.05f, 0.02f).value()).value();
    }
    bodies.push_back(b);
  }
  for (int i = 0; i < farStatics; ++i)
    testing::addStaticBox(world, {500.0f + 3.0f * static_cast<float>(i), 500.0f}, {1.0f, 1.0f});
  BoxRun run;
  std::vector<float> seen;  // callback times in this step
  world.onImpact(~0ull, ~0ull, [&](World&, const ToiEvent& e, bool) {
    ++run.callbacks;
    seen.push_back(e.time);
  });
  for (int step = 0; step < steps; ++step) {
    seen.clear();
    if (!world.step().ok()) break;
    ++run.steps;
    const auto& toi = world.events().toi;
    run.impacts += static_cast<int>(toi.size());
    run.capped += static_cast<int>(world.events().toiCapped.size());
    for (std::size_t i = 1; i < toi.size(); ++i)
      run.sorted = run.sorted && toi[i - 1].time <= toi[i].time;
    // Every impact of the step had its callback, in the list's order.
    run.callbacksMatch = run.callbacksMatch && seen.size() == toi.size();
    for (std::size_t i = 0; i < seen.size() && i < toi.size(); ++i)
      run.callbacksMatch = run.callbacksMatch && seen[i] == toi[i].time;
    for (BodyId b : bodies) {
      const Vec2 p = world.position(b);
      if (!(std::abs(p.x) < kHalf && std::abs(p.y) < kHalf)) {
        ++run.escaped;
      }
    }
  }
  run.hash = world.stateHash();
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a over the bits
  for (BodyId b : bodies) {
    const Vec2 p = world.position(b), v = world.linearVelocity(b);
    for (float x : {p.x, p.y, world.angle(b), v.x, v.y, world.angularVelocity(b)}) {
      std::uint32_t bits = 0;
      std::memcpy(&bits, &x, sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
    }
  }
  run.bodiesHash = h;
  return run;
}

// 1,000 small fast bodies in a closed box for 10 s (600 steps): none ever outside, impact
// events in time order, each with its callback. (About 10 s in a debug build.)
TEST(CcdDynamic, ThousandSmallFastBodiesStayInsideAClosedBoxForTenSeconds) {
  const BoxRun run = runClosedBox(1000, 600, BroadPhaseKind::tree, 18);
  EXPECT_EQ(run.steps, 600);
  EXPECT_EQ(run.escaped, 0);
  EXPECT_TRUE(run.sorted);
  EXPECT_TRUE(run.callbacksMatch);
  EXPECT_EQ(run.callbacks, run.impacts);
  EXPECT_GT(run.impacts, 10000);  // the phase had work to do
  RecordProperty("impacts", run.impacts);
  RecordProperty("capped", run.capped);
  std::printf("closed box: %d impacts in %d steps, %d capped\n", run.impacts, run.steps,
              run.capped);
}

// The same bits whatever the broad phase, with impacts between moving bodies.
TEST(CcdDynamic, SameBitsWhateverTheBroadPhase) {
  const BoxRun reference = runClosedBox(150, 60, BroadPhaseKind::tree, 19);
  EXPECT_GT(reference.impacts, 100);
  for (BroadPhaseKind kind : kAllBroadPhaseKinds) {
    SCOPED_TRACE(std::string(toString(kind)));
    const BoxRun run = runClosedBox(150, 60, kind, 19);
    EXPECT_EQ(run.hash, reference.hash);
    EXPECT_EQ(run.impacts, reference.impacts);
  }
}

// A search takes the shapes outside the fast bodies from a list when there are at most 16
// of them (continuous.hpp, kMaxListedShapes) and from a grid of them (or a broad-phase
// query) when there are more: the same impacts and the same bits either way. Here 150 fast
// bodies and 4 walls (listed) against the same with 100 static boxes far outside the walls,
// which nothing meets (gridded).
TEST(CcdDynamic, ListedAndQueriedStillShapesGiveTheSameBits) {
  const BoxRun listed = runClosedBox(150, 60, BroadPhaseKind::tree, 19);
  const BoxRun queried = runClosedBox(150, 60, BroadPhaseKind::tree, 19, 100);
  EXPECT_GT(listed.impacts, 100);
  EXPECT_EQ(listed.escaped, 0);
  EXPECT_EQ(queried.escaped, 0);
  EXPECT_EQ(listed.impacts, queried.impacts);
  EXPECT_EQ(listed.bodiesHash, queried.bodiesHash);
  EXPECT_NE(listed.hash, queried.hash);  // the far boxes are in the world's hash
}

// WorldDef::sweepDynamicPairs off is Box2D v3's rule: a fast body that is not a bullet is
// swept against static and kinematic shapes only. A disc at 600 m/s (10 m a step, 200 times
// its radius) aimed at a thin plank at rest passes it untouched, while with the default the
// phase meets the plank; a second disc still stops at a thin static wall; a bullet still
// meets the plank; and the setting survives a snapshot.
TEST(CcdDynamic, WithoutDynamicPairsOnlyStaticShapesAndBulletsAreSwept) {
  for (bool pairs : {true, false}) {
    SCOPED_TRACE(pairs ? "dynamic pairs swept" : "static only");
    WorldDef def{.gravity = {0, 0}};
    def.sweepDynamicPairs = pairs;
    World world = World::create(def).value();
    BodyId wall = world.createBody({.type = BodyType::staticBody, .position = {12, 10}}).value();
    (void)world.createShape(wall, {}, makeBox(0.01f, 1.0f).value()).value();
    BodyId plank = world.createBody({.position = {5, 0}}).value();
    (void)world.createShape(plank, {}, makeBox(0.01f, 1.0f).value()).value();
    BodyId plank2 = world.createBody({.position = {5, -20}}).value();
    (void)world.createShape(plank2, {}, makeBox(0.01f, 1.0f).value()).value();
    const ShapeDef disc{.friction = 0.0f, .restitution = 0.0f};
    BodyId toPlank = addDisc(world, {-2.95f, 0}, {600, 0}, 0.05f, disc, false);
    BodyId toWall = addDisc(world, {-2.95f, 10}, {600, 0}, 0.05f, disc, false);
    BodyId bullet = addDisc(world, {-2.95f, -20}, {600, 0}, 0.05f, disc, true);
    int plankImpacts = 0, wallImpacts = 0, bulletImpacts = 0;
    for (int step = 0; step < 3; ++step) {
      ASSERT_TRUE(testing::stepAndValidate(world));
      for (const ToiEvent& ev : world.events().toi) {
        const BodyId a = world.body(ev.shapeA), b = world.body(ev.shapeB);
        plankImpacts += (a == toPlank && b == plank) || (a == plank && b == toPlank) ? 1 : 0;
        wallImpacts += a == toWall && b == wall ? 1 : 0;
        bulletImpacts += (a == bullet && b == plank2) || (a == plank2 && b == bullet) ? 1 : 0;
      }
    }
    EXPECT_GE(wallImpacts, 1);
    EXPECT_LT(world.position(toWall).x, 12.0f);
    EXPECT_GE(bulletImpacts, 1);
    EXPECT_LT(world.position(bullet).x, world.position(plank2).x);
    if (pairs) {
      EXPECT_GE(plankImpacts, 1);
      EXPECT_LT(world.position(toPlank).x, world.position(plank).x);
    } else {
      // Through the plank untouched: three steps of 10 m at 600 m/s.
      EXPECT_EQ(plankImpacts, 0);
      EXPECT_FLOAT_EQ(world.linearVelocity(toPlank).x, 600.0f);
      EXPECT_GT(world.position(toPlank).x, 20.0f);
    }
    const std::vector<std::uint8_t> bytes = world.snapshot().value();
    EXPECT_EQ(World::fromSnapshot(bytes).value().def().sweepDynamicPairs, pairs);
  }
}

// Impact callbacks select by category, both ways round, like contact callbacks.
TEST(CcdDynamic, ImpactCallbacksSelectByCategory) {
  World world = World::create({.gravity = {0, 0}}).value();
  const ShapeDef red{.filter = {.category = 1}}, blue{.filter = {.category = 2}};
  BodyId a = addDisc(world, {-5, 0}, {500, 0}, 0.05f, red, true);
  BodyId b = addDisc(world, {5, 0}, {-500, 0}, 0.05f, blue, true);
  int redBlue = 0, blueRed = 0, swapped = 0, redRed = 0;
  world.onImpact(1, 2, [&](World& w, const ToiEvent& e, bool s) {
    ++redBlue;
    swapped += s ? 1 : 0;
    EXPECT_EQ(w.body(s ? e.shapeB : e.shapeA), a);
  });
  world.onImpact(2, 1, [&](World& w, const ToiEvent& e, bool s) {
    ++blueRed;
    EXPECT_EQ(w.body(s ? e.shapeB : e.shapeA), b);
  });
  world.onImpact(1, 1, [&](World&, const ToiEvent&, bool) { ++redRed; });
  ASSERT_TRUE(world.step().ok());
  ASSERT_EQ(world.events().toi.size(), 1u);
  EXPECT_EQ(redBlue, 1);
  EXPECT_EQ(blueRed, 1);
  EXPECT_EQ(redRed, 0);
}

}  // namespace
}  // namespace quack
