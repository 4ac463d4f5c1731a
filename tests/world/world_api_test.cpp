// The public API a game programmer expects: handles that catch misuse in every build, forces
// and torques, body types changed on the fly, a world shape cast, iteration without
// allocating, and a step that reads plainly in a game loop. Each physical check is against
// a closed form; each query against brute force.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "quack/collision/gjk.hpp"
#include "quack/world/world.hpp"
#include "world_test_util.hpp"

namespace quack {
namespace {

using testing::addBall;
using testing::addBox;
using testing::addStaticBox;
using testing::stepAndValidate;
using testing::valid;

TEST(WorldApi, BodyTypeNamesAreTheSceneFileNames) {
  EXPECT_STREQ(toString(BodyType::staticBody), "static");
  EXPECT_STREQ(toString(BodyType::kinematicBody), "kinematic");
  EXPECT_STREQ(toString(BodyType::dynamicBody), "dynamic");
}

// Shapes of one polygon share a stored copy, validated once (docs/world.md, "Shapes' geometry,
// stored once"): a copy
// that differs in one normal is still validated and refused, one body's density is not
// another's (a closed form: a 1 x 2 box weighs 2 kg per unit density), and a polygon whose
// shapes were all destroyed can come back.
TEST(WorldApi, SharedPolygonsAreStillValidatedAndWeighedPerShape) {
  World world = World::create({}).value();
  const Polygon box = makeBox(0.5f, 1.0f).value();
  const BodyId a = world.createBody({.type = BodyType::dynamicBody}).value();
  const ShapeId first = world.createShape(a, {.density = 1.0f}, box).value();
  Polygon bent = box;
  bent.normals[0].x = -bent.normals[0].x + 0.5f;  // no longer a unit normal
  const BodyId b = world.createBody({.type = BodyType::dynamicBody, .position = {3, 0}}).value();
  Result<ShapeId> refused = world.createShape(b, {}, bent);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("geometry"), std::string::npos) << refused.error().message;
  ASSERT_TRUE(world.createShape(b, {.density = 3.0f}, box).ok());
  EXPECT_NEAR(world.mass(a), 2.0f, 1e-5f);
  EXPECT_NEAR(world.mass(b), 6.0f, 1e-5f);
  ASSERT_TRUE(world.destroyShape(first).ok());
  ASSERT_TRUE(world.destroyBody(b).ok());
  ASSERT_TRUE(world.step().ok());
  ASSERT_TRUE(world.createShape(a, {.density = 2.0f}, box).ok());
  EXPECT_NEAR(world.mass(a), 4.0f, 1e-5f);
  ASSERT_TRUE(world.step().ok());
}

TEST(WorldApi, HandleFromAnotherWorldIsRefused) {
  World a = World::create({}).value();
  World b = World::create({}).value();
  EXPECT_NE(a.id(), b.id());
  EXPECT_NE(a.id(), 0u);
  BodyId inA = addBall(a, {1, 2}, 0.5f);
  BodyId inB = addBall(b, {7, 8}, 0.5f);
  ASSERT_EQ(inA.index, inB.index);  // same slot, same generation: only the world differs
  ASSERT_EQ(inA.generation, inB.generation);
  EXPECT_FALSE(b.isValid(inA));
  Status s = b.setTransform(inA, {0, 0}, 0);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("another world"), std::string::npos) << s.message();
  EXPECT_EQ(b.position(inA), (Vec2{0, 0}));  // neutral, not world b's body at that slot
  EXPECT_EQ(b.position(inB), (Vec2{7, 8}));
  EXPECT_FALSE(b.destroyBody(inA).ok());
  EXPECT_FALSE(b.createShape(inA, {}, makeCircle({}, 1).value()).ok());
  ShapeId shapeA = a.shapes(inA)[0];
  EXPECT_FALSE(b.isValid(shapeA));
  EXPECT_FALSE(b.destroyShape(shapeA).ok());
  EXPECT_EQ(b.body(shapeA), BodyId{});
  EXPECT_TRUE(valid(a));
  EXPECT_TRUE(valid(b));
}

TEST(WorldApi, StaleAndWildHandlesReadNeutralValues) {
  World world = World::create({}).value();
  BodyId first = addBall(world, {1, 2}, 0.5f);
  const ShapeId firstShape = world.shapes(first)[0];
  ASSERT_TRUE(world.destroyBody(first).ok());
  ASSERT_TRUE(valid(world));
  BodyId second = addBox(world, {5, 6}, {0.5f, 0.5f}, 0.3f);
  ASSERT_EQ(second.index, first.index);  // the slot was reused
  // The stale handle does not read the slot's new occupant.
  EXPECT_FALSE(world.isValid(first));
  EXPECT_EQ(world.position(first), (Vec2{0, 0}));
  EXPECT_EQ(world.angle(first), 0.0f);
  EXPECT_EQ(world.mass(first), 0.0f);
  EXPECT_EQ(world.linearVelocity(first), (Vec2{0, 0}));
  EXPECT_EQ(world.bodyType(first), BodyType::staticBody);
  EXPECT_TRUE(world.shapes(first).empty());
  EXPECT_EQ(world.shapeDef(firstShape).density, ShapeDef{}.density);
  EXPECT_TRUE(std::holds_alternative<Circle>(world.geometry(firstShape)));
  EXPECT_EQ(world.position(second), (Vec2{5, 6}));
  // A wild index and the null handle.
  const BodyId wild{123456, 1, world.id()};
  EXPECT_EQ(world.position(wild), (Vec2{0, 0}));
  EXPECT_FALSE(world.setLinearVelocity(wild, {1, 0}).ok());
  EXPECT_EQ(world.userData(BodyId{}), 0u);
  Status s = world.applyForce(BodyId{}, {1, 0}, {0, 0});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("null"), std::string::npos) << s.message();
}

TEST(WorldApi, ConstantForceGivesUniformAcceleration) {
  // Closed form: with no gravity, F applied every step for T seconds gives v = F T / m.
  World world = World::create({.gravity = {0, 0}}).value();
  BodyId b = addBox(world, {0, 0}, {0.5f, 0.25f});
  const float m = world.mass(b);
  ASSERT_NEAR(m, 0.5f, 1e-6f);  // 1 x 0.5 m, density 1
  const Vec2 force{3.0f, -1.0f};
  for (int i = 0; i < 60; ++i) {
    ASSERT_TRUE(world.applyForce(b, force, world.worldCenterOfMass(b)).ok());
    ASSERT_TRUE(stepAndValidate(world));
  }
  const Vec2 v = world.linearVelocity(b);
  EXPECT_NEAR(v.x, force.x / m, 1e-3f);
  EXPECT_NEAR(v.y, force.y / m, 1e-3f);
  EXPECT_NEAR(world.angularVelocity(b), 0.0f, 1e-5f);  // through the centre: no spin
  // Forces are cleared after each step: one more step without it keeps the velocity.
  ASSERT_TRUE(stepAndValidate(world));
  EXPECT_NEAR(world.linearVelocity(b).x, force.x / m, 1e-3f);
}

TEST(WorldApi, TorqueAndAngularImpulseFollowTheInertia) {
  World world = World::create({.gravity = {0, 0}}).value();
  BodyId b = addBall(world, {0, 0}, 0.5f);
  const float inertia = world.rotationalInertia(b);
  // Disk: I = m r^2 / 2 with m = pi r^2.
  const float m = kPi * 0.25f;
  ASSERT_NEAR(inertia, 0.5f * m * 0.25f, 1e-5f);
  ASSERT_TRUE(world.applyAngularImpulse(b, 0.2f).ok());
  EXPECT_NEAR(world.angularVelocity(b), 0.2f / inertia, 1e-5f);
  ASSERT_TRUE(world.applyTorque(b, 0.5f).ok());
  ASSERT_TRUE(stepAndValidate(world));
  EXPECT_NEAR(world.angularVelocity(b), (0.2f + 0.5f / 60.0f) / inertia, 1e-4f);
  // An off-centre force turns the body: torque = r x F.
  World w2 = World::create({.gravity = {0, 0}}).value();
  BodyId c = addBall(w2, {0, 0}, 0.5f);
  ASSERT_TRUE(w2.applyForce(c, {0, 2}, {0.5f, 0}).ok());
  ASSERT_TRUE(stepAndValidate(w2));
  EXPECT_NEAR(w2.angularVelocity(c), (0.5f * 2.0f / 60.0f) / inertia, 1e-4f);
  EXPECT_FALSE(world.applyAngularImpulse(b, 1e30f).ok());
  EXPECT_FALSE(world.applyTorque(b, std::nanf("")).ok());
}

// A body's mass sums its shapes' (the first eight are computed once and kept for the
// inertia pass, the rest computed again): twelve unit boxes in a row, closed forms.
TEST(WorldApi, MassOfTwelveBoxesMatchesTheClosedForm) {
  World world = World::create({}).value();
  BodyId b = world.createBody({.position = {0, 5}}).value();
  for (int i = 0; i < 12; ++i)
    ASSERT_TRUE(
        world.createShape(b, {}, makeBox(0.5f, 0.5f, {static_cast<float>(i), 0}).value()).ok());
  EXPECT_NEAR(world.mass(b), 12.0f, 1e-4f);
  // Centre of mass at x = 5.5; each box: 1/6 about its own centre, plus (i - 5.5)^2.
  float inertia = 0.0f;
  for (int i = 0; i < 12; ++i)
    inertia += 1.0f / 6.0f + (static_cast<float>(i) - 5.5f) * (static_cast<float>(i) - 5.5f);
  EXPECT_NEAR(world.rotationalInertia(b), inertia, 1e-3f * inertia);
  EXPECT_NEAR(world.worldCenterOfMass(b).x, 5.5f, 1e-5f);
  EXPECT_NEAR(world.worldCenterOfMass(b).y, 5.0f, 1e-5f);
}

TEST(WorldApi, SetBodyTypeEndsContactsAndChangesTheMotion) {
  World world = World::create({}).value();
  addStaticBox(world, {0, -0.5f}, {10, 0.5f});
  BodyId box = addBox(world, {0, 0.5f}, {0.5f, 0.5f});
  BodyId top = addBox(world, {0, 1.5f}, {0.5f, 0.5f});
  for (int i = 0; i < 30; ++i)
    ASSERT_TRUE(stepAndValidate(world));
  ASSERT_EQ(world.touchingContactCount(), 2u);
  // The lower box becomes static: it stops, the stack keeps standing on it.
  ASSERT_TRUE(world.setBodyType(box, BodyType::staticBody).ok());
  ASSERT_TRUE(valid(world));
  EXPECT_EQ(world.mass(box), 0.0f);
  EXPECT_EQ(world.linearVelocity(box), (Vec2{0, 0}));
  ASSERT_TRUE(stepAndValidate(world));
  // Both of its contacts ended (end events) and the one with the top box came back; the
  // static-static one with the ground did not.
  EXPECT_EQ(world.events().end.size(), 2u);
  EXPECT_EQ(world.touchingContactCount(), 1u);
  for (int i = 0; i < 60; ++i)
    ASSERT_TRUE(stepAndValidate(world));
  EXPECT_NEAR(world.position(top).y, 1.5f, 0.02f);
  // The top box becomes kinematic and is moved; then the lower box dynamic again: it falls
  // onto the ground, and the kinematic box stays where it is, sliding on.
  ASSERT_TRUE(world.setBodyType(top, BodyType::kinematicBody).ok());
  ASSERT_TRUE(world.setLinearVelocity(top, {1, 0}).ok());
  const Vec2 topStart = world.position(top);
  ASSERT_TRUE(world.setTransform(box, {-4, 3}, 0).ok());
  ASSERT_TRUE(world.setBodyType(box, BodyType::dynamicBody).ok());
  EXPECT_NEAR(world.mass(box), 1.0f, 1e-6f);
  for (int i = 0; i < 120; ++i)
    ASSERT_TRUE(stepAndValidate(world));
  EXPECT_NEAR(world.position(box).y, 0.5f, 0.05f);  // fell 2.5 m and landed
  // 1 m/s for 120 steps of 1/60 s; a kinematic body is not pushed off its line.
  EXPECT_NEAR(world.position(top).x, topStart.x + 2.0f, 1e-3f);
  EXPECT_EQ(world.position(top).y, topStart.y);
  EXPECT_FALSE(world.setBodyType(box, static_cast<BodyType>(7)).ok());
}

TEST(WorldApi, WorldShapeCastAgreesWithClosedFormAndBruteForce) {
  World world = World::create({}).value();
  addStaticBox(world, {0, -0.5f}, {10, 0.5f});
  BodyId crate = addBox(world, {3, 1}, {1, 1});
  const Circle probe = makeCircle({}, 0.5f).value();
  // Straight down from y = 5 onto the ground's top at 0: contact after 4.5 of 10 m.
  Result<std::optional<ShapeCastResult>> down =
      world.castShape(probe, makeTransform({-3, 5}, 0), {0, -10});
  ASSERT_TRUE(down.ok());
  ASSERT_TRUE(down->has_value());
  EXPECT_NEAR((*down)->fraction, 0.45f, 1e-3f);
  EXPECT_NEAR((*down)->normal.y, 1.0f, 1e-4f);  // from the ground towards the probe
  EXPECT_NEAR((*down)->point.y, 0.0f, 1e-3f);
  // Sideways: the crate (its left face at x = 2) is met before the far wall of nothing.
  auto side = world.castShape(probe, makeTransform({-2, 1}, 0), {10, 0});
  ASSERT_TRUE(side.ok() && side->has_value());
  EXPECT_EQ((*side)->body, crate);
  EXPECT_NEAR((*side)->fraction, 0.35f, 1e-3f);  // 4 - 0.5 = 3.5 of 10 m
  // Brute force: random casts; the answer's fraction is the first sampled fraction at
  // which the probe overlaps anything, within the sampling step.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int k = 0; k < 40; ++k) {
    const Vec2 from{5 * u(rng), 3 + 2 * u(rng)};
    const Vec2 move{8 * u(rng), -6 + 2 * u(rng)};
    auto got = world.castShape(probe, makeTransform(from, 0), move);
    ASSERT_TRUE(got.ok());
    float first = 2.0f;
    for (int i = 0; i <= 1000 && first > 1.0f; ++i) {
      const float t = static_cast<float>(i) / 1000.0f;
      auto hits = world.overlapShape(probe, makeTransform(from + t * move, 0));
      ASSERT_TRUE(hits.ok());
      if (!hits->empty()) first = t;
    }
    if (first > 1.0f) {
      EXPECT_FALSE(got->has_value()) << "cast " << k;
    } else {
      ASSERT_TRUE(got->has_value()) << "cast " << k;
      EXPECT_NEAR((*got)->fraction, first, 2e-3f) << "cast " << k;
    }
  }
  EXPECT_FALSE(world.castShape(probe, makeTransform({0, 0}, 0), {std::nanf(""), 0}).ok());
}

TEST(WorldApi, RangesIterateWithoutCopies) {
  World world = World::create({}).value();
  addStaticBox(world, {0, -0.5f}, {10, 0.5f});
  std::vector<BodyId> made;
  for (int i = 0; i < 6; ++i)
    made.push_back(addBox(world, {static_cast<float>(2 * i) - 5.0f, 0.5f}, {0.5f, 0.5f}));
  ASSERT_TRUE(world.destroyBody(made[2]).ok());
  std::vector<BodyId> seen;
  for (BodyId b : world.bodies())
    seen.push_back(b);
  ASSERT_EQ(seen.size(), world.bodyCount());
  for (BodyId b : seen)
    EXPECT_TRUE(world.isValid(b));
  EXPECT_EQ(std::count(seen.begin(), seen.end(), made[2]), 0);
  // A body with two shapes lists them in creation order.
  BodyId two = world.createBody({.position = {0, 5}}).value();
  ShapeId s1 = world.createShape(two, {}, makeCircle({}, 0.3f).value()).value();
  ShapeId s2 = world.createShape(two, {}, makeCircle({1, 0}, 0.3f).value()).value();
  World::ShapeRange shapes = world.shapes(two);
  ASSERT_EQ(shapes.size(), 2u);
  EXPECT_EQ(shapes[0], s1);
  EXPECT_EQ(*std::next(shapes.begin()), s2);
  for (int i = 0; i < 5; ++i)
    world.step();  // ignoring the StepStatus compiles without a warning (-Werror)
  std::size_t contacts = 0;
  for (const World::ContactView& c : world.touchingContacts()) {
    EXPECT_GT(c.manifold.pointCount, 0);
    ++contacts;
  }
  EXPECT_EQ(contacts, world.touchingContactCount());
  EXPECT_EQ(contacts, 5u);
}

}  // namespace
}  // namespace quack
