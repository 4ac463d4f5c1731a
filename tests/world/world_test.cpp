// The world: stacking, bouncing, friction, filters, events, callbacks, queries, determinism
// and bad input.

#include "quack/world/world.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "quack/collision/gjk.hpp"
#include "quack/geometry/bounds.hpp"
#include "quack/geometry/raycast.hpp"
#include "world_test_util.hpp"

namespace quack {
namespace {

using testing::addBall;
using testing::addBox;
using testing::addPyramid;
using testing::addStaticBox;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

World makeWorld(WorldDef def = {}) {
  return World::create(def).value();
}

// The world's fat boxes (docs/world.md, "Fat boxes"), worked by hand: a dynamic shape's
// margin is the speculative distance (2 cm) plus an eighth of its extent, at most 5 cm; a
// static shape's is twice the speculative distance. Two shapes have a contact (touching or
// not) once their fat boxes overlap, so at a gap below the sum of their margins.
TEST(World, FatBoxMarginsFollowEachShapesSize) {
  auto contactsAtGap = [](float halfA, float halfB, bool staticB, float gap) {
    World world = makeWorld({.gravity = {0.0f, 0.0f}});
    const BodyId a = world.createBody({.position = {0.0f, 0.0f}}).value();
    (void)world.createShape(a, {}, makeBox(halfA, halfA).value());
    const BodyId b =
        world
            .createBody({.type = staticB ? BodyType::staticBody : BodyType::dynamicBody,
                         .position = {halfA + gap + halfB, 0.0f}})
            .value();
    (void)world.createShape(b, {}, makeBox(halfB, halfB).value());
    EXPECT_TRUE(world.step(1.0f / 60.0f, 4).ok());
    return world.contactCount();
  };
  // Boxes of 0.1 m half-size: extent 0.1 sqrt 2 = 0.1414 m, margin 0.02 + 0.0177 m; a pair
  // within 0.0754 m.
  EXPECT_EQ(contactsAtGap(0.1f, 0.1f, false, 0.070f), 1u);
  EXPECT_EQ(contactsAtGap(0.1f, 0.1f, false, 0.080f), 0u);
  // Boxes of 0.5 m: an eighth of 0.707 m is past the 5 cm cap, margin 0.07 m; within 0.14 m.
  EXPECT_EQ(contactsAtGap(0.5f, 0.5f, false, 0.135f), 1u);
  EXPECT_EQ(contactsAtGap(0.5f, 0.5f, false, 0.145f), 0u);
  // A 0.1 m box beside a static one (margin 0.04 m): within 0.0777 m.
  EXPECT_EQ(contactsAtGap(0.1f, 0.5f, true, 0.074f), 1u);
  EXPECT_EQ(contactsAtGap(0.1f, 0.5f, true, 0.082f), 0u);
}

// Documented in docs/world.md: after 10 s no box of a 20-row pyramid has moved more than
// this from where it was placed (a tenth of a box's half-size).
constexpr float kPyramidDrift = 0.05f;

TEST(World, TwentyRowPyramidStandsTenSeconds) {
  for (BroadPhaseKind kind : {BroadPhaseKind::tree, BroadPhaseKind::sap}) {
    SCOPED_TRACE(std::string(toString(kind)));
    World world = makeWorld({.broadPhase = kind});
    addStaticBox(world, {0, -0.5f}, {40, 0.5f});
    std::vector<BodyId> boxes = addPyramid(world, 20);
    ASSERT_EQ(boxes.size(), 210u);
    std::vector<Vec2> start;
    for (BodyId b : boxes)
      start.push_back(world.position(b));
    for (int s = 0; s < 600; ++s)
      ASSERT_TRUE(testing::stepAndValidate(world));
    float maxDrift = 0.0f, maxAngle = 0.0f;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      maxDrift = maxf(maxDrift, distance(world.position(boxes[i]), start[i]));
      maxAngle = maxf(maxAngle, absf(world.angle(boxes[i])));
    }
    EXPECT_LT(maxDrift, kPyramidDrift);
    EXPECT_LT(maxAngle, 0.01f);
    RecordProperty("max_drift_m", std::to_string(maxDrift));
  }
}

// Highest point of the ball after each bounce.
std::vector<float> bounceApexes(float restitution, int steps) {
  World world = makeWorld();
  addStaticBox(world, {0, -0.5f}, {10, 0.5f}, 0.0f, {.restitution = restitution});
  BodyId ball = addBall(world, {0, 5.5f}, 0.5f, {.restitution = restitution});
  std::vector<float> apexes;
  float prevVy = 0.0f;
  for (int s = 0; s < steps; ++s) {
    EXPECT_TRUE(testing::stepAndValidate(world));
    float vy = world.linearVelocity(ball).y;
    if (prevVy > 0.0f && vy <= 0.0f) apexes.push_back(world.position(ball).y - 0.5f);
    prevVy = vy;
  }
  return apexes;
}

TEST(World, BallWithRestitutionOneKeepsNinetyPercentOfItsHeight) {
  std::vector<float> apexes = bounceApexes(1.0f, 60 * 12);
  ASSERT_GE(apexes.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i)
    RecordProperty("apex_" + std::to_string(i), std::to_string(apexes[i]));
  for (std::size_t i = 0; i < 4; ++i) {
    SCOPED_TRACE(i);
    EXPECT_GT(apexes[i], 0.9f * 5.0f);   // dropped from 5 m above the ground
    EXPECT_LT(apexes[i], 1.05f * 5.0f);  // and never gains energy
  }
}

TEST(World, BallWithRestitutionZeroDoesNotBounce) {
  std::vector<float> apexes = bounceApexes(0.0f, 60 * 4);
  for (float a : apexes)
    EXPECT_LT(a, 0.01f);
}

// A box on a slope of `degrees`, friction 0.6: how far it moves in 2 s.
float slide(float degrees) {
  World world = makeWorld();
  float a = degrees * kPi / 180.0f;
  addStaticBox(world, {0, 0}, {20, 0.5f}, a, {.friction = 0.6f});
  // Resting on the slope's top face, at its middle.
  Vec2 up{-std::sin(a), std::cos(a)};
  BodyId box = addBox(world, 1.0f * up, {0.5f, 0.5f}, a, {.friction = 0.6f});
  for (int s = 0; s < 30; ++s)
    EXPECT_TRUE(testing::stepAndValidate(world));  // settle
  Vec2 p0 = world.position(box);
  for (int s = 0; s < 120; ++s)
    EXPECT_TRUE(testing::stepAndValidate(world));
  return distance(p0, world.position(box));
}

TEST(World, FrictionHoldsAtTwentyDegreesAndSlidesAtForty) {
  float at20 = slide(20.0f), at40 = slide(40.0f);
  RecordProperty("slide_20_m", std::to_string(at20));
  RecordProperty("slide_40_m", std::to_string(at40));
  EXPECT_LT(at20, 0.01f);  // tan 20 = 0.36 < 0.6
  EXPECT_GT(at40, 1.0f);   // tan 40 = 0.84 > 0.6: a = g (sin - 0.6 cos) = 1.8 m/s^2
}

TEST(World, MassOfACompoundBody) {
  World world = makeWorld();
  BodyId b = world.createBody({.position = {1, 1}}).value();
  ASSERT_TRUE(world.createShape(b, {.density = 2}, makeBox(1, 0.5f, {-1, 0}).value()).ok());
  ASSERT_TRUE(world.createShape(b, {.density = 2}, makeBox(1, 0.5f, {1, 0}).value()).ok());
  // Two 2 x 1 boxes side by side make a 4 x 1 box: mass 8, inertia m (16 + 1) / 12.
  EXPECT_FLOAT_EQ(world.mass(b), 8.0f);
  EXPECT_NEAR(world.rotationalInertia(b), 8.0f * 17.0f / 12.0f, 1e-4f);
  EXPECT_NEAR(world.worldCenterOfMass(b).x, 1.0f, 1e-6f);
}

// Filters in a live world: two overlapping dynamic boxes touch exactly when the filter rule
// says so (categories, masks, groups), and a player never touches its own weapon.
TEST(World, FiltersAsATruthTable) {
  struct Row {
    Filter a, b;
    bool collide;
  };
  const std::uint64_t terrain = 1, player = 2, weapon = 4;
  const Row rows[] = {
      {{player, terrain | player, 0}, {player, terrain | player, 0}, true},
      {{player, terrain | player, 0}, {weapon, terrain, 0}, false},  // weapon ignores players
      {{player, terrain | weapon, 0}, {weapon, terrain | player, 0}, true},
      {{player, terrain | weapon, -1}, {weapon, terrain | player, -1}, false},  // own weapon
      {{player, terrain, 3}, {weapon, terrain, 3}, true},  // positive group wins
      {{player, terrain | weapon, -1}, {weapon, terrain | player, -2}, true},  // other groups
      {{player, 0, 0}, {player, ~0ull, 0}, false},
  };
  for (const Row& row : rows) {
    World world = makeWorld({.gravity = {0, 0}});
    BodyId a = addBox(world, {0, 0}, {0.5f, 0.5f}, 0, {.filter = row.a});
    BodyId b = addBox(world, {0.5f, 0.2f}, {0.5f, 0.5f}, 0, {.filter = row.b});
    ASSERT_TRUE(testing::stepAndValidate(world));
    bool touching = world.touchingContactCount() > 0;
    EXPECT_EQ(touching, row.collide) << "category " << row.a.category << "/" << row.b.category;
    EXPECT_EQ(touching, shouldCollide(row.a, row.b));
    // Touching boxes are pushed apart; filtered ones stay where they are.
    for (int s = 0; s < 30; ++s)
      ASSERT_TRUE(testing::stepAndValidate(world));
    EXPECT_EQ(distance(world.position(a), world.position(b)) > 0.9f, row.collide);
  }
}

TEST(World, EventsOfABallDroppedOnTheGroundThroughASensor) {
  World world = makeWorld();
  BodyId ground = addStaticBox(world, {0, -0.5f}, {10, 0.5f});
  BodyId zone = world.createBody({.type = BodyType::staticBody, .position = {0, 3}}).value();
  ShapeId sensor = world.createShape(zone, {.sensor = true}, makeBox(2, 0.5f).value()).value();
  BodyId ball = addBall(world, {0, 5}, 0.5f);
  int begins = 0, ends = 0, hits = 0, sensorBegins = 0, sensorEnds = 0;
  float hitSpeed = 0.0f;
  for (int s = 0; s < 120; ++s) {
    ASSERT_TRUE(testing::stepAndValidate(world));
    const StepEvents& e = world.events();
    begins += static_cast<int>(e.begin.size());
    ends += static_cast<int>(e.end.size());
    hits += static_cast<int>(e.hit.size());
    for (const ContactHitEvent& h : e.hit)
      hitSpeed = h.approachSpeed;
    for (const SensorEvent& se : e.sensorBegin) {
      EXPECT_EQ(se.sensor, sensor);
      ++sensorBegins;
    }
    sensorEnds += static_cast<int>(e.sensorEnd.size());
  }
  EXPECT_EQ(begins, 1);
  EXPECT_EQ(ends, 0);
  EXPECT_EQ(hits, 1);
  // Free fall of 4.5 m: sqrt(2 g h) = 9.49 m/s, to within a step of gravity.
  EXPECT_NEAR(hitSpeed, std::sqrt(2.0f * 10.0f * 4.5f), 0.3f);
  EXPECT_EQ(sensorBegins, 1);
  EXPECT_EQ(sensorEnds, 1);
  // Lift the ball off: the contact ends on the next step.
  ASSERT_TRUE(world.setTransform(ball, {0, 8}, 0).ok());
  ASSERT_TRUE(testing::stepAndValidate(world));
  EXPECT_EQ(world.events().end.size(), 1u);
  (void)ground;
}

TEST(World, CallbacksByCategoryAndRemovalInsideThem) {
  const std::uint64_t terrain = 1, bullet = 2, target = 4;
  World world = makeWorld();
  addStaticBox(world, {0, -0.5f}, {10, 0.5f}, 0, {.filter = {terrain, ~0ull, 0}});
  BodyId shot = addBall(world, {0, 2}, 0.25f, {.filter = {bullet, ~0ull, 0}});
  BodyId crate = addBox(world, {3, 0.5f}, {0.5f, 0.5f}, 0, {.filter = {target, ~0ull, 0}});
  int bulletHits = 0, otherCalls = 0, created = 0;
  BodyId spawned;
  world.onContactBegin(bullet, terrain, [&](World& w, ShapeId a, ShapeId b) {
    ++bulletHits;
    EXPECT_EQ(w.shapeDef(a).filter.category, bullet);  // passed in the asked order
    EXPECT_EQ(w.shapeDef(b).filter.category, terrain);
    EXPECT_TRUE(w.destroyBody(w.body(a)).ok());  // deferred
    EXPECT_TRUE(w.isValid(w.body(a)));           // still valid until callbacks end
    spawned = w.createBody({.position = {-3, 1}}).value();
    EXPECT_TRUE(w.createShape(spawned, {}, makeCircle({}, 0.2f).value()).ok());
    ++created;
  });
  // Runs for the same begin event, after the first callback asked to destroy the bullet:
  // the callbacks and the event list agree, so it runs too, and the handle is still valid.
  world.onContactBegin(bullet, ~0ull, [&](World& w, ShapeId a, ShapeId) {
    EXPECT_TRUE(w.isValid(a));
    ++otherCalls;
  });
  ASSERT_TRUE(testing::stepAndValidate(world));
  for (int s = 0; s < 90; ++s)
    ASSERT_TRUE(testing::stepAndValidate(world));
  EXPECT_EQ(bulletHits, 1);
  EXPECT_EQ(otherCalls, 1);
  EXPECT_EQ(created, 1);
  EXPECT_FALSE(world.isValid(shot));
  EXPECT_TRUE(world.isValid(spawned));
  EXPECT_TRUE(world.isValid(crate));
  EXPECT_FALSE(world.destroyBody(shot).ok());  // stale
  // step() from inside a callback is refused. The only new contact: the ball dropped on the
  // ground (the crate and the spawned body settled long ago, nothing bounces).
  int refused = 0;
  world.onContactBegin(~0ull, ~0ull, [&](World& w, ShapeId, ShapeId) {
    EXPECT_FALSE(w.step().ok());
    ++refused;
  });
  addBall(world, {5, 1}, 0.25f);
  for (int s = 0; s < 60; ++s)
    ASSERT_TRUE(testing::stepAndValidate(world));
  EXPECT_EQ(refused, 1);
}

// Callbacks of each kind, counted after the steps. A ball (category 2) dropped 4.5 m onto
// the ground (category 1), left to rest, then lifted: one begin, one hit at the free-fall
// speed sqrt(2 g h), one end. Callbacks whose masks match no pair are never called.
TEST(World, ContactBeginHitAndEndCallbacksOfABallLandedAndLifted) {
  const std::uint64_t terrain = 1, ballCategory = 2, nobody = 8;
  World world = makeWorld();
  addStaticBox(world, {0, -0.5f}, {10, 0.5f}, 0, {.filter = {terrain, ~0ull, 0}});
  BodyId ball = addBall(world, {0, 5}, 0.5f, {.filter = {ballCategory, ~0ull, 0}});
  const ShapeId ballShape = world.shapes(ball)[0];
  int begins = 0, hits = 0, ends = 0, unmatched = 0;
  float approach = 0.0f;
  world.onContactBegin(ballCategory, terrain, [&](World&, ShapeId a, ShapeId) {
    EXPECT_EQ(a, ballShape);  // passed in the asked order
    ++begins;
  });
  world.onHit(ballCategory, terrain, [&](World&, const ContactHitEvent& hit, bool swapped) {
    EXPECT_EQ(swapped ? hit.shapeB : hit.shapeA, ballShape);
    approach = hit.approachSpeed;
    ++hits;
  });
  world.onContactEnd(ballCategory, terrain, [&](World&, ShapeId a, ShapeId) {
    EXPECT_EQ(a, ballShape);
    ++ends;
  });
  // Masks that must not match: a category no shape has, and terrain with terrain.
  world.onContactBegin(nobody, ~0ull, [&](World&, ShapeId, ShapeId) { ++unmatched; });
  world.onContactBegin(terrain, terrain, [&](World&, ShapeId, ShapeId) { ++unmatched; });
  world.onHit(nobody, ~0ull, [&](World&, const ContactHitEvent&, bool) { ++unmatched; });
  world.onHit(ballCategory, ballCategory,
              [&](World&, const ContactHitEvent&, bool) { ++unmatched; });
  world.onContactEnd(nobody, ~0ull, [&](World&, ShapeId, ShapeId) { ++unmatched; });
  world.onContactEnd(terrain, terrain, [&](World&, ShapeId, ShapeId) { ++unmatched; });
  for (int s = 0; s < 120; ++s)
    ASSERT_TRUE(testing::stepAndValidate(world));
  EXPECT_EQ(begins, 1);
  EXPECT_EQ(hits, 1);
  EXPECT_EQ(ends, 0);
  // Free fall of 4.5 m: sqrt(2 g h) = 9.49 m/s, to within a step of gravity.
  EXPECT_NEAR(approach, std::sqrt(2.0f * 10.0f * 4.5f), 0.3f);
  ASSERT_TRUE(world.setTransform(ball, {0, 8}, 0).ok());
  ASSERT_TRUE(testing::stepAndValidate(world));
  EXPECT_EQ(ends, 1);
  for (int s = 0; s < 10; ++s)
    ASSERT_TRUE(testing::stepAndValidate(world));
  EXPECT_EQ(begins, 1);  // still in the air
  EXPECT_EQ(hits, 1);
  EXPECT_EQ(ends, 1);
  EXPECT_EQ(unmatched, 0);
}

// A ball falling through a sensor band: one sensor begin then one sensor end, each with the
// sensor passed first; callbacks whose masks exclude the pair are never called.
TEST(World, SensorCallbacksOfABallFallingThroughASensor) {
  const std::uint64_t terrain = 1, ballCategory = 2, zoneCategory = 4;
  World world = makeWorld();
  addStaticBox(world, {0, -0.5f}, {10, 0.5f}, 0, {.filter = {terrain, ~0ull, 0}});
  BodyId zone = world.createBody({.type = BodyType::staticBody, .position = {0, 3}}).value();
  const ShapeId sensor =
      world
          .createShape(zone, {.sensor = true, .filter = {zoneCategory, ~0ull, 0}},
                       makeBox(2, 0.5f).value())
          .value();
  BodyId ball = addBall(world, {0, 5}, 0.5f, {.filter = {ballCategory, ~0ull, 0}});
  const ShapeId ballShape = world.shapes(ball)[0];
  int begins = 0, ends = 0, unmatched = 0;
  std::uint64_t beganAt = 0, endedAt = 0;
  world.onSensorBegin(zoneCategory, ballCategory, [&](World& w, ShapeId s, ShapeId v) {
    EXPECT_EQ(s, sensor);
    EXPECT_EQ(v, ballShape);
    beganAt = w.stepCount();
    ++begins;
  });
  world.onSensorEnd(zoneCategory, ballCategory, [&](World& w, ShapeId s, ShapeId v) {
    EXPECT_EQ(s, sensor);
    EXPECT_EQ(v, ballShape);
    endedAt = w.stepCount();
    ++ends;
  });
  // The roles swapped (the ball is no sensor), a visitor mask without the ball, and a
  // category nobody has.
  world.onSensorBegin(ballCategory, zoneCategory, [&](World&, ShapeId, ShapeId) { ++unmatched; });
  world.onSensorBegin(zoneCategory, ~ballCategory, [&](World&, ShapeId, ShapeId) { ++unmatched; });
  world.onSensorEnd(ballCategory, zoneCategory, [&](World&, ShapeId, ShapeId) { ++unmatched; });
  world.onSensorEnd(8, ~0ull, [&](World&, ShapeId, ShapeId) { ++unmatched; });
  for (int s = 0; s < 120; ++s)
    ASSERT_TRUE(testing::stepAndValidate(world));
  EXPECT_EQ(begins, 1);
  EXPECT_EQ(ends, 1);
  EXPECT_LT(beganAt, endedAt);
  EXPECT_EQ(unmatched, 0);
  EXPECT_NEAR(world.position(ball).y, 0.5f, 0.05f);  // it went on through to the ground
}

void buildMixedScene(World& world) {
  addStaticBox(world, {0, -0.5f}, {30, 0.5f});
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  for (int i = 0; i < 120; ++i) {
    Vec2 p{-10 + 20 * u(rng), 1 + 15 * u(rng)};
    BodyId b = world.createBody({.position = p, .angle = u(rng) * 3}).value();
    switch (i % 4) {
      case 0:
        (void)world.createShape(b, {}, makeCircle({}, 0.3f + 0.3f * u(rng)).value());
        break;
      case 1:
        (void)world.createShape(b, {}, makeBox(0.3f + 0.3f * u(rng), 0.3f).value());
        break;
      case 2:
        (void)world.createShape(b, {}, makeCapsule({-0.4f, 0}, {0.4f, 0}, 0.2f).value());
        break;
      default: {
        const Vec2 tri[] = {{-0.5f, -0.3f}, {0.5f, -0.3f}, {0, 0.5f}};
        (void)world.createShape(b, {.restitution = 0.3f}, makePolygon(tri, 0.05f).value());
      }
    }
  }
}

TEST(World, DeterministicStateHash) {
  std::uint64_t first = 0;
  for (BroadPhaseKind kind : kAllBroadPhaseKinds) {
    SCOPED_TRACE(std::string(toString(kind)));
    for (int run = 0; run < 2; ++run) {
      World world = makeWorld({.broadPhase = kind});
      buildMixedScene(world);
      for (int s = 0; s < 300; ++s)
        ASSERT_TRUE(testing::stepAndValidate(world));
      if (first == 0) first = world.stateHash();
      // The same scene, whatever the structure: pairs are sorted before contacts are made.
      EXPECT_EQ(world.stateHash(), first);
    }
  }
}

TEST(World, RayCastsAgreeWithBruteForce) {
  World world = makeWorld({.gravity = {0, 0}});
  buildMixedScene(world);
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> u(-15, 15);
  int hits = 0;
  for (int i = 0; i < 300; ++i) {
    Vec2 o{u(rng), u(rng) + 10}, d{u(rng), u(rng)};
    // Brute force: every shape cast in its own frame.
    float best = 2.0f;
    std::size_t all = 0;
    for (BodyId b : world.bodies()) {
      for (ShapeId s : world.shapes(b)) {
        Transform xf = world.transform(b);
        RayCastInput in{invTransformPoint(xf, o), invRotate(xf.q, d), 1.0f};
        RayHit h = std::visit([&](const auto& g) { return rayCast(g, in); }, world.geometry(s));
        if (h.hit) {
          best = minf(best, h.fraction);
          ++all;
        }
      }
    }
    std::optional<RayHitResult> closest = world.rayCastClosest(o, d);
    ASSERT_EQ(closest.has_value(), best <= 1.0f);
    if (closest) {
      ++hits;
      EXPECT_FLOAT_EQ(closest->fraction, best);
      EXPECT_NEAR(length(closest->normal), 1.0f, 1e-4f);
    }
    std::vector<RayHitResult> every = world.rayCastAll(o, d);
    EXPECT_EQ(every.size(), all);
    for (std::size_t k = 1; k < every.size(); ++k)
      EXPECT_LE(every[k - 1].fraction, every[k].fraction);
  }
  EXPECT_GT(hits, 50);
}

TEST(World, OverlapQueries) {
  World world = makeWorld({.gravity = {0, 0}});
  buildMixedScene(world);
  Aabb box{{-3, 2}, {3, 6}};
  std::vector<ShapeId> found = world.overlapAabb(box);
  std::size_t expected = 0;
  for (BodyId b : world.bodies()) {
    for (ShapeId s : world.shapes(b)) {
      Aabb sb = std::visit([&](const auto& g) { return computeAabb(g, world.transform(b)); },
                           world.geometry(s));
      expected += overlaps(sb, box) ? 1 : 0;
    }
  }
  EXPECT_EQ(found.size(), expected);

  // Overlap with depenetration: moving the query shape by each vector frees it from that shape.
  Circle probe = makeCircle({}, 1.5f).value();
  int checked = 0;
  for (float x = -8; x <= 8; x += 2) {
    Transform xf = makeTransform({x, 4}, 0);
    auto overlapsNow = world.overlapShape(probe, xf);
    ASSERT_TRUE(overlapsNow.ok());
    for (const ShapeOverlap& o : overlapsNow.value()) {
      ++checked;
      EXPECT_GT(o.depth, 0.0f);
      EXPECT_NEAR(length(o.depenetration), o.depth, 1e-4f);
      Transform moved =
          makeTransform(xf.p + o.depenetration * 1.001f + 1e-4f * normalize(o.depenetration), 0);
      Transform other = world.transform(world.body(o.shape));
      bool still = std::visit(
          [&](const auto& g) { return testOverlap(makeProxy(probe), moved, makeProxy(g), other); },
          world.geometry(o.shape));
      EXPECT_FALSE(still);
    }
  }
  EXPECT_GT(checked, 5);
  EXPECT_FALSE(world.overlapShape(probe, Transform{{kNaN, 0}, {}}).ok());
}

TEST(World, BadInputGetsClearErrorsAndChangesNothing) {
  EXPECT_FALSE(World::create({.timeStep = 0}).ok());
  EXPECT_FALSE(World::create({.substeps = 0}).ok());
  EXPECT_FALSE(World::create({.gravity = {kNaN, 0}}).ok());
  World world = makeWorld();
  auto r = world.createBody({.position = {kNaN, 0}});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("BodyDef.position"), std::string::npos);
  EXPECT_FALSE(world.createBody({.linearDamping = -1}).ok());
  BodyId b = world.createBody({}).value();
  auto s = world.createShape(b, {.density = -1}, makeCircle({}, 1).value());
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("ShapeDef.density"), std::string::npos);
  EXPECT_FALSE(world.createShape(b, {.friction = kNaN}, makeCircle({}, 1).value()).ok());
  Circle bad;
  bad.radius = -1;
  auto g = world.createShape(b, {}, bad);
  ASSERT_FALSE(g.ok());
  EXPECT_NE(g.error().message.find("circle radius"), std::string::npos);
  EXPECT_EQ(world.shapeCount(), 0u);  // nothing was added
  EXPECT_FALSE(world.createShape(BodyId{}, {}, makeCircle({}, 1).value()).ok());
  EXPECT_FALSE(world.step(0.0f, 4).ok());
  EXPECT_FALSE(world.step(kNaN, 4).ok());
  EXPECT_FALSE(world.step(1.0f / 60, 0).ok());
  EXPECT_FALSE(world.setTransform(b, {kNaN, 0}, 0).ok());
  EXPECT_FALSE(world.setLinearVelocity(b, {0, kNaN}).ok());
  EXPECT_FALSE(world.applyLinearImpulse(b, {kNaN, 0}, {}).ok());
  ShapeId sh = world.createShape(b, {}, makeCircle({}, 1).value()).value();
  ASSERT_TRUE(world.destroyShape(sh).ok());
  auto again = world.destroyShape(sh);
  ASSERT_FALSE(again.ok());
  EXPECT_NE(again.message().find("stale"), std::string::npos);
  ASSERT_TRUE(world.destroyBody(b).ok());
  EXPECT_FALSE(world.destroyBody(b).ok());
  EXPECT_FALSE(world.setAngularVelocity(b, 1).ok());
  EXPECT_EQ(world.bodyCount(), 0u);
  EXPECT_TRUE(testing::stepAndValidate(world));
}

TEST(World, EveryBroadPhaseRunsTheSameScene) {
  for (BroadPhaseKind kind : kAllBroadPhaseKinds) {
    SCOPED_TRACE(std::string(toString(kind)));
    World world = makeWorld({.broadPhase = kind});
    buildMixedScene(world);
    for (int s = 0; s < 120; ++s)
      ASSERT_TRUE(testing::stepAndValidate(world));
    EXPECT_TRUE(world.broadPhase().validate().ok());
    EXPECT_GT(world.touchingContactCount(), 50u);
  }
}

// The step sorts its new pairs by radix when there are a thousand or more (contact_set.cpp);
// each broad phase reports them in its own order, so equal bits from all of them show that
// the order the contacts are made in does not depend on the structure on that path too.
// (That it is std::sort's order is SortPairs.GivesStdSortsOrderOnBothPaths.)
TEST(World, ManyNewPairsGiveTheSameBitsWhateverTheBroadPhase) {
  auto run = [](BroadPhaseKind kind, std::size_t& firstContacts) {
    World world = makeWorld({.broadPhase = kind});
    addStaticBox(world, {0.0f, -0.5f}, {30.0f, 0.5f});
    for (int row = 0; row < 24; ++row) {
      for (int col = 0; col < 30; ++col) {
        // Boxes 0.8 m wide, 0.9 m apart, a little shifted and turned: each overlaps its
        // neighbours' fat boxes, and the pile settles unevenly.
        const float shift = 0.01f * static_cast<float>((7 * row + 3 * col) % 5 - 2);
        const float turn = 0.02f * static_cast<float>((row + 2 * col) % 7 - 3);
        const Vec2 at{-13.0f + 0.9f * static_cast<float>(col) + shift,
                      0.5f + 0.9f * static_cast<float>(row)};
        const BodyId b = world.createBody({.position = at, .angle = turn}).value();
        (void)world.createShape(b, {}, makeBox(0.4f, 0.4f).value());
      }
    }
    EXPECT_TRUE(testing::stepAndValidate(world));
    firstContacts = world.contactCount();
    for (int s = 0; s < 20; ++s)
      EXPECT_TRUE(testing::stepAndValidate(world));
    return world.stateHash();
  };
  std::size_t contacts = 0;
  const std::uint64_t first = run(BroadPhaseKind::tree, contacts);
  // Every contact after the first step came from that step's new pairs: at least this many.
  EXPECT_GE(contacts, 1024u);
  for (BroadPhaseKind kind : kAllBroadPhaseKinds) {
    std::size_t count = 0;
    EXPECT_EQ(run(kind, count), first) << toString(kind);
    EXPECT_EQ(count, contacts) << toString(kind);
  }
}

}  // namespace
}  // namespace quack
