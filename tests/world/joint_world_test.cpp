// Joints in the world: the API's errors and handles, collideConnected, events, islands and
// sleep, breaking, the remaining joint types against closed forms, energy, snapshots and
// the same bits on any number of workers and lanes.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "quack/world/tasks.hpp"
#include "quack/world/world.hpp"
#include "world_test_util.hpp"

namespace quack {
namespace {

using testing::addBall;
using testing::addBox;
using testing::addPyramid;
using testing::addStaticBox;
using testing::stepAndValidate;
using testing::valid;

BodyId addGround(World& world) {
  return world.createBody({.type = BodyType::staticBody}).value();
}

JointDef revolute(BodyId a, BodyId b, Vec2 anchor) {
  return {.type = JointType::revolute, .bodyA = a, .bodyB = b, .anchorA = anchor};
}

std::string errorOf(World& world, const JointDef& def) {
  Result<JointId> r = world.createJoint(def);
  return r ? std::string("(accepted)") : r.error().message;
}

TEST(JointApi, BadDefinitionsAreRefusedByName) {
  World world = World::create({}).value();
  const BodyId ground = addGround(world);
  const BodyId box = addBox(world, {0.0f, 2.0f}, {0.5f, 0.5f});
  const BodyId other = addBox(world, {3.0f, 2.0f}, {0.5f, 0.5f});
  const BodyId wall = addStaticBox(world, {5.0f, 0.0f}, {1.0f, 1.0f});
  EXPECT_NE(errorOf(world, revolute(BodyId{}, box, {})).find("JointDef.bodyA"), std::string::npos);
  EXPECT_NE(errorOf(world, revolute(box, box, {})).find("same body"), std::string::npos);
  // Two static bodies may be joined: the joint acts once one of them is made dynamic.
  EXPECT_TRUE(world.createJoint(revolute(ground, wall, {})).ok());
  JointDef d = revolute(ground, box, {0.0f, 2.0f});
  d.anchorA.x = std::nanf("");
  EXPECT_NE(errorOf(world, d).find("JointDef.anchorA"), std::string::npos);
  d = revolute(ground, box, {0.0f, 2.0f});
  d.enableLimit = true;
  d.lower = 1.0f;
  d.upper = -1.0f;
  EXPECT_NE(errorOf(world, d).find("JointDef.lower"), std::string::npos);
  d.lower = -4.0f;
  d.upper = 1.0f;
  EXPECT_NE(errorOf(world, d).find("[-pi, pi]"), std::string::npos);
  d = revolute(ground, box, {0.0f, 2.0f});
  d.hertz = -1.0f;
  EXPECT_NE(errorOf(world, d).find("JointDef.hertz"), std::string::npos);
  d = revolute(ground, box, {0.0f, 2.0f});
  d.maxMotorTorque = -1.0f;
  EXPECT_NE(errorOf(world, d).find("JointDef.maxMotorTorque"), std::string::npos);
  d = revolute(ground, box, {0.0f, 2.0f});
  d.breakForce = std::nanf("");
  EXPECT_NE(errorOf(world, d).find("JointDef.breakForce"), std::string::npos);
  JointDef p{.type = JointType::prismatic, .bodyA = ground, .bodyB = box, .axis = {0.0f, 0.0f}};
  EXPECT_NE(errorOf(world, p).find("JointDef.axis"), std::string::npos);
  JointDef dist{.type = JointType::distance,
                .bodyA = box,
                .bodyB = other,
                .anchorA = {0.0f, 2.0f},
                .anchorB = {0.0f, 2.0f}};
  EXPECT_NE(errorOf(world, dist).find("at least kLinearSlop"), std::string::npos);
  dist.anchorB = {3.0f, 2.0f};
  dist.minLength = 2.0f;
  dist.maxLength = 1.0f;
  EXPECT_NE(errorOf(world, dist).find("JointDef.minLength"), std::string::npos);
  JointDef mouse{.type = JointType::mouse, .bodyA = ground, .bodyB = box, .maxForce = 100.0f};
  EXPECT_NE(errorOf(world, mouse).find("must be null"), std::string::npos);
  mouse.bodyA = {};
  mouse.hertz = 0.0f;
  EXPECT_NE(errorOf(world, mouse).find("JointDef.hertz"), std::string::npos);
  mouse.hertz = 5.0f;
  mouse.maxForce = 0.0f;
  EXPECT_NE(errorOf(world, mouse).find("JointDef.maxForce of a mouse joint"), std::string::npos);
  JointDef motor{.type = JointType::motor, .bodyA = ground, .bodyB = box};
  EXPECT_NE(errorOf(world, motor).find("maxForce or maxTorque"), std::string::npos);
  // Nothing was created by any of the bad ones.
  EXPECT_EQ(world.jointCount(), 1u);
  EXPECT_TRUE(valid(world));
}

TEST(JointApi, HandlesAreCheckedAndTheRangeListsTheLiveJoints) {
  World world = World::create({}).value();
  const BodyId ground = addGround(world);
  const BodyId a = addBall(world, {0.0f, 1.0f}, 0.25f);
  const BodyId b = addBall(world, {1.0f, 1.0f}, 0.25f);
  const JointId ja = world.createJoint(revolute(ground, a, {0.0f, 1.0f})).value();
  const JointId jb = world.createJoint(revolute(a, b, {0.5f, 1.0f})).value();
  EXPECT_EQ(world.jointCount(), 2u);
  std::vector<JointId> listed(world.joints().begin(), world.joints().end());
  EXPECT_EQ(listed, (std::vector<JointId>{ja, jb}));
  ASSERT_TRUE(world.destroyJoint(ja).ok());
  EXPECT_FALSE(world.isValid(ja));
  const Status again = world.destroyJoint(ja);
  ASSERT_FALSE(again.ok());
  EXPECT_NE(again.message().find("stale"), std::string::npos);
  World other = World::create({}).value();
  const Status foreign = other.destroyJoint(jb);
  ASSERT_FALSE(foreign.ok());
  EXPECT_NE(foreign.message().find("another world"), std::string::npos);
  EXPECT_EQ(world.jointCount(), 1u);
  EXPECT_EQ(world.jointDef(jb).type, JointType::revolute);
  EXPECT_FALSE(world.setMouseTarget(jb, {}).ok());
  EXPECT_FALSE(world.setJointMotor(jb, true, 1.0f, -1.0f).ok());
  EXPECT_TRUE(world.setJointMotor(jb, true, 1.0f, 5.0f).ok());
  EXPECT_TRUE(valid(world));
}

// Two overlapping boxes: a joint keeps them from colliding unless collideConnected, and
// destroying it lets them collide again.
TEST(JointApi, JointedBodiesCollideOnlyWhenAsked) {
  for (bool collide : {false, true}) {
    SCOPED_TRACE(collide ? "collideConnected" : "not collideConnected");
    World world = World::create({.gravity = {0.0f, 0.0f}}).value();
    const BodyId a = addBox(world, {0.0f, 0.0f}, {0.5f, 0.5f});
    const BodyId b = addBox(world, {0.6f, 0.0f}, {0.5f, 0.5f});
    ASSERT_TRUE(stepAndValidate(world));
    ASSERT_EQ(world.touchingContactCount(), 1u);  // they overlap
    JointDef d = revolute(a, b, {0.3f, 0.0f});
    d.collideConnected = collide;
    const JointId j = world.createJoint(d).value();
    ASSERT_TRUE(valid(world));
    ASSERT_TRUE(stepAndValidate(world));
    EXPECT_EQ(world.touchingContactCount(), collide ? 1u : 0u);
    if (!collide) {
      // The contact that was there ended, with its event.
      EXPECT_EQ(world.events().end.size(), 1u);
      ASSERT_TRUE(world.destroyJoint(j).ok());
      ASSERT_TRUE(stepAndValidate(world));
      EXPECT_EQ(world.touchingContactCount(), 1u);
      EXPECT_EQ(world.events().begin.size(), 1u);
    }
  }
}

// The continuous phase keeps the same rule: a rod spun fast about a pin on a static post
// passes through the post it is pinned to (not collideConnected), turn after turn, rather
// than being stopped at the post's top by a swept impact. With collideConnected it is.
TEST(JointApi, JointedBodiesAreNotSweptAgainstEachOther) {
  for (bool collide : {false, true}) {
    SCOPED_TRACE(collide ? "collideConnected" : "not collideConnected");
    World world = World::create({.gravity = {0.0f, 0.0f}}).value();
    // The post's top 0.2 m below the pin, so that the rod (0.05 m thick) starts clear of it.
    const BodyId post = addStaticBox(world, {0.0f, -2.2f}, {0.5f, 2.0f});
    const BodyId rod = addBox(world, {2.0f, 0.0f}, {2.0f, 0.05f});
    JointDef d = revolute(post, rod, {0.0f, 0.0f});
    d.collideConnected = collide;
    ASSERT_TRUE(world.createJoint(d).ok());
    // Spun about its centre; the pin leaves it a quarter of that about the pin (5 rad/s,
    // half a turn in 0.6 s: fast, a third of a radian a step at the rod's 4 m).
    ASSERT_TRUE(world.setAngularVelocity(rod, -20.0f).ok());  // clockwise: down into the post
    ASSERT_TRUE(stepAndValidate(world));
    // Closed form: the pin conserves angular momentum about itself, so the spin becomes
    // 20 I / (I + m d^2), with I = m (4^2 + 0.1^2) / 12 about the centre and d = 2 m.
    const double inertia = (16.0 + 0.01) / 12.0;
    const double expected = 20.0 * inertia / (inertia + 4.0);  // 5.0023 rad/s
    const float start = std::fabs(world.angularVelocity(rod));
    ASSERT_NEAR(start, expected, 0.01 * expected);
    float slowest = start, fastest = start;
    for (int i = 0; i < 120; ++i) {  // two seconds: the rod meets the post about twice
      ASSERT_TRUE(stepAndValidate(world));
      slowest = std::min(slowest, std::fabs(world.angularVelocity(rod)));
      fastest = std::max(fastest, std::fabs(world.angularVelocity(rod)));
    }
    if (collide) {
      EXPECT_LT(slowest, 0.5f * start);  // stopped at the post
    } else {
      // Untouched by the post: no sweep stopped it (when the sweeps ignored the joint,
      // impacts took it as low as 3.7 rad/s and as high as 6.1).
      EXPECT_GT(slowest, 0.99f * start);
      EXPECT_LT(fastest, 1.01f * start);
    }
  }
}

TEST(JointEvents, DestroyingABodyEndsItsJointsWithAnEvent) {
  World world = World::create({}).value();
  const BodyId ground = addGround(world);
  const BodyId a = addBall(world, {0.0f, 1.0f}, 0.25f);
  const BodyId b = addBall(world, {1.0f, 1.0f}, 0.25f);
  JointDef d = revolute(ground, a, {0.0f, 1.0f});
  d.userData = 7;
  const JointId ja = world.createJoint(d).value();
  const JointId jb = world.createJoint(revolute(a, b, {0.5f, 1.0f})).value();
  std::vector<JointEndEvent> called;
  world.onJointEnd([&](World&, const JointEndEvent& e) { called.push_back(e); });
  ASSERT_TRUE(world.destroyBody(a).ok());
  EXPECT_FALSE(world.isValid(ja));
  EXPECT_FALSE(world.isValid(jb));
  EXPECT_EQ(world.jointCount(), 0u);
  ASSERT_TRUE(valid(world));
  ASSERT_TRUE(stepAndValidate(world));
  const std::vector<JointEndEvent>& ends = world.events().jointEnd;
  ASSERT_EQ(ends.size(), 2u);
  ASSERT_EQ(called.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(ends[k].reason, JointEndReason::bodyDestroyed);
    EXPECT_EQ(called[k].joint, ends[k].joint);
  }
  // Highest joint first (a body's list runs from its newest joint).
  EXPECT_EQ(ends[0].joint, jb);
  EXPECT_EQ(ends[1].joint, ja);
  EXPECT_EQ(ends[1].userData, 7u);
  ASSERT_TRUE(stepAndValidate(world));
  EXPECT_TRUE(world.events().jointEnd.empty());
}

// A game's sticky bomb: on contact, weld the two bodies together from the callback. The
// contact between them ends (reported with the next step), the weld holds them, and
// destroying the joint from a callback waits until the callbacks are done.
TEST(JointEvents, JointsMadeAndDestroyedFromCallbacks) {
  World world = World::create({}).value();
  addStaticBox(world, {0.0f, -0.5f}, {20.0f, 0.5f});
  const BodyId base = addBox(world, {0.0f, 0.5f}, {2.0f, 0.5f});
  const BodyId bomb = addBall(world, {1.0f, 3.0f}, 0.25f);
  JointId weld;
  world.onContactBegin(~0ull, ~0ull, [&](World& w, ShapeId a, ShapeId b) {
    const BodyId ba = w.body(a), bb = w.body(b);
    if ((ba == bomb || bb == bomb) && !w.isValid(weld)) {
      const BodyId other = ba == bomb ? bb : ba;
      weld = w.createJoint({.type = JointType::weld,
                            .bodyA = other,
                            .bodyB = bomb,
                            .anchorA = w.position(bomb)})
                 .value();
    }
  });
  int steps = 0;
  while (!world.isValid(weld) && steps < 120) {
    ASSERT_TRUE(stepAndValidate(world));
    ++steps;
  }
  ASSERT_TRUE(world.isValid(weld));
  ASSERT_TRUE(stepAndValidate(world));
  // The bomb's contact with the base ended when the weld was made.
  bool ended = false;
  for (const ContactEndEvent& e : world.events().end)
    ended = ended || world.body(e.shapeA) == bomb || world.body(e.shapeB) == bomb;
  EXPECT_TRUE(ended);
  world.onJointEnd([](World&, const JointEndEvent&) {});
  world.onContactBegin(~0ull, ~0ull, [&](World& w, ShapeId, ShapeId) {
    if (w.isValid(weld)) {
      EXPECT_TRUE(w.destroyJoint(weld).ok());
      EXPECT_TRUE(w.isValid(weld));  // until the callbacks are done
    }
  });
  // Something else lands on the base: its begin event destroys the weld.
  addBall(world, {-1.0f, 2.0f}, 0.25f);
  for (int i = 0; i < 60 && world.isValid(weld); ++i)
    ASSERT_TRUE(stepAndValidate(world));
  EXPECT_FALSE(world.isValid(weld));
  (void)base;
}

// A joint holding a 10 kg ball against gravity carries 100 N: a break force of 50 N breaks
// it in the first step, reported in that step's events and to the callback; 150 N holds.
// A 10 kg ball hangs 1 m under the ground's origin on a distance joint, and on a revolute
// joint (plain: solved in lanes, which finish its force themselves): 98 N.
TEST(JointEvents, ABreakForceBreaksTheJointAndSaysSo) {
  for (const JointType type : {JointType::distance, JointType::revolute})
    for (float breakForce : {50.0f, 150.0f}) {
      SCOPED_TRACE(std::to_string(breakForce) +
                   (type == JointType::distance ? " distance" : " revolute"));
      World world = World::create({}).value();
      const BodyId ground = addGround(world);
      const BodyId ball = world.createBody({.position = {0.0f, -1.0f}}).value();
      (void)world.createShape(ball, {.density = 10.0f / (kPi * 0.25f)},
                              makeCircle({}, 0.5f).value());
      ASSERT_NEAR(world.mass(ball), 10.0f, 1e-3f);
      JointDef d{.type = type,
                 .bodyA = ground,
                 .bodyB = ball,
                 .anchorA = {0.0f, 0.0f},
                 .anchorB = {0.0f, -1.0f}};
      d.breakForce = breakForce;
      const JointId j = world.createJoint(d).value();
      int calls = 0;
      world.onJointEnd([&](World&, const JointEndEvent& e) {
        ++calls;
        EXPECT_EQ(e.reason, JointEndReason::broken);
        EXPECT_GT(length(e.force), breakForce);
      });
      for (int i = 0; i < 30; ++i)
        ASSERT_TRUE(stepAndValidate(world));
      if (breakForce < 100.0f) {
        EXPECT_FALSE(world.isValid(j));
        EXPECT_EQ(calls, 1);
        EXPECT_LT(world.position(ball).y, -1.5f);  // falling
      } else {
        EXPECT_TRUE(world.isValid(j));
        EXPECT_EQ(calls, 0);
        EXPECT_NEAR(length(world.jointForce(j)), 100.0f, 1.0f);
        EXPECT_NEAR(world.position(ball).y, -1.0f, 0.01f);
      }
    }
}

// Two bodies joined by a joint and touching nothing share an island: they sleep together,
// and waking one wakes the other.
TEST(JointIslands, JointedBodiesSleepAndWakeTogether) {
  World world = World::create({}).value();
  addStaticBox(world, {0.0f, -0.5f}, {20.0f, 0.5f});
  const BodyId a = addBox(world, {-3.0f, 0.5f}, {0.5f, 0.5f});
  const BodyId b = addBox(world, {3.0f, 0.5f}, {0.5f, 0.5f});
  const std::size_t before = world.islandCount();
  ASSERT_TRUE(world
                  .createJoint({.type = JointType::distance,
                                .bodyA = a,
                                .bodyB = b,
                                .anchorA = {-3.0f, 0.5f},
                                .anchorB = {3.0f, 0.5f}})
                  .ok());
  EXPECT_EQ(world.islandCount(), before - 1);
  for (int i = 0; i < 120 && world.isAwake(a); ++i)
    ASSERT_TRUE(stepAndValidate(world));
  EXPECT_FALSE(world.isAwake(a));
  EXPECT_FALSE(world.isAwake(b));
  ASSERT_TRUE(world.setAwake(b, true).ok());
  EXPECT_TRUE(world.isAwake(a));
  ASSERT_TRUE(valid(world));
}

// Changing a jointed body's type keeps the islands right (World::validate checks that
// jointed dynamic bodies share an island), and a kinematic body drives what is jointed to it.
TEST(JointIslands, BodyTypeChangesAndKinematicDrivers) {
  World world = World::create({}).value();
  const BodyId a = addBox(world, {0.0f, 5.0f}, {0.5f, 0.5f});
  const BodyId b = addBox(world, {2.0f, 5.0f}, {0.5f, 0.5f});
  const JointId j = world.createJoint(revolute(a, b, {1.0f, 5.0f})).value();
  for (BodyType t : {BodyType::staticBody, BodyType::kinematicBody, BodyType::dynamicBody}) {
    ASSERT_TRUE(world.setBodyType(a, t).ok());
    ASSERT_TRUE(valid(world));
    ASSERT_TRUE(stepAndValidate(world));
  }
  EXPECT_TRUE(world.isValid(j));
  // A kinematic body turning about its centre carries b around on the joint.
  ASSERT_TRUE(world.setBodyType(a, BodyType::kinematicBody).ok());
  ASSERT_TRUE(world.setAngularVelocity(a, 1.0f).ok());
  for (int i = 0; i < 90; ++i)
    ASSERT_TRUE(stepAndValidate(world));
  const auto [onA, onB] = world.jointAnchors(j);
  EXPECT_LT(length(onB - onA), 0.02f);
  EXPECT_TRUE(world.isAwake(b));
  // a turned 1.5 rad: the joint's point on a is now above a's centre and to the left.
  EXPECT_NEAR(world.angle(a), 1.5f, 1e-3f);
  EXPECT_GT(onA.y, world.position(a).y + 0.9f);
}

// Closed form: a weld with a spring of f Hz on its angle holding a bar; with a rigid weld the
// bar does not sag at all beyond the joint's softness.
TEST(JointTypes, WeldHoldsABarOutRigidly) {
  World world = World::create({}).value();
  const BodyId ground = addGround(world);
  const BodyId bar = addBox(world, {1.0f, 0.0f}, {1.0f, 0.1f});
  const JointId j =
      world
          .createJoint(
              {.type = JointType::weld, .bodyA = ground, .bodyB = bar, .anchorA = {0.0f, 0.0f}})
          .value();
  for (int i = 0; i < 120; ++i)
    ASSERT_TRUE(stepAndValidate(world));
  EXPECT_LT(std::abs(world.angle(bar)), 0.01f);
  EXPECT_LT(length(world.position(bar) - Vec2{1.0f, 0.0f}), 0.01f);
  // It carries the bar's weight (20 * 0.2 * 10 N... the mass times g) and its moment.
  const float weight = world.mass(bar) * 10.0f;
  EXPECT_NEAR(world.jointForce(j).y, weight, 0.02f * weight);
  EXPECT_NEAR(world.jointTorque(j), weight * 1.0f, 0.02f * weight);
}

// Closed form: a wheel joint's suspension of f Hz holding a body on a vertical axis sags
// g / (2 pi f)^2 (the soft spring is defined by its frequency, whatever the mass).
TEST(JointTypes, WheelSuspensionSagsAsItsSpringSays) {
  World world = World::create({}).value();
  const BodyId ground = addGround(world);
  const BodyId wheel = addBall(world, {0.0f, 0.0f}, 0.5f);
  const float hertz = 2.0f;
  const JointId j = world
                        .createJoint({.type = JointType::wheel,
                                      .bodyA = ground,
                                      .bodyB = wheel,
                                      .anchorA = {0.0f, 0.0f},
                                      .axis = {0.0f, 1.0f},
                                      .enableMotor = true,
                                      .motorSpeed = 3.0f,
                                      .maxMotorTorque = 100.0f,
                                      .enableSpring = true,
                                      .hertz = hertz,
                                      .dampingRatio = 0.7f})
                        .value();
  for (int i = 0; i < 300; ++i)
    ASSERT_TRUE(stepAndValidate(world));
  const float omega = 2.0f * kPi * hertz;
  const float sag = 10.0f / (omega * omega);
  EXPECT_NEAR(world.jointTranslation(j), -sag, 0.02f * sag);
  EXPECT_NEAR(world.position(wheel).x, 0.0f, 1e-3f);
  EXPECT_NEAR(world.angularVelocity(wheel), 3.0f, 0.03f);
}

TEST(JointTypes, MotorJointDrivesBToItsTarget) {
  World world = World::create({.gravity = {0.0f, 0.0f}}).value();
  const BodyId ground = addGround(world);
  const BodyId box = addBox(world, {0.0f, 0.0f}, {0.5f, 0.5f});
  const JointId j = world
                        .createJoint({.type = JointType::motor,
                                      .bodyA = ground,
                                      .bodyB = box,
                                      .linearOffset = {2.0f, 1.0f},
                                      .angularOffset = 0.5f,
                                      .maxForce = 500.0f,
                                      .maxTorque = 500.0f})
                        .value();
  for (int i = 0; i < 240; ++i) {
    ASSERT_TRUE(stepAndValidate(world));
    EXPECT_LE(length(world.jointForce(j)), 500.0f * (1.0f + 1e-5f));
  }
  EXPECT_LT(length(world.position(box) - Vec2{2.0f, 1.0f}), 0.01f);
  EXPECT_NEAR(world.angle(box), 0.5f, 0.01f);
  ASSERT_TRUE(world.setMotorTarget(j, {-1.0f, 0.0f}, 0.0f).ok());
  for (int i = 0; i < 240; ++i)
    ASSERT_TRUE(stepAndValidate(world));
  EXPECT_LT(length(world.position(box) - Vec2{-1.0f, 0.0f}), 0.01f);
}

TEST(JointTypes, MouseJointPullsAPointToItsTargetWithinItsForce) {
  World world = World::create({}).value();
  addStaticBox(world, {0.0f, -0.5f}, {20.0f, 0.5f});
  const BodyId box = addBox(world, {0.0f, 0.5f}, {0.5f, 0.5f});
  const float maxForce = 1000.0f * world.mass(box);
  const JointId j = world
                        .createJoint({.type = JointType::mouse,
                                      .bodyB = box,
                                      .anchorA = {0.25f, 0.75f},
                                      .hertz = 5.0f,
                                      .dampingRatio = 0.7f,
                                      .maxForce = maxForce,
                                      .target = {0.25f, 0.75f}})
                        .value();
  ASSERT_TRUE(world.setMouseTarget(j, {3.0f, 4.0f}).ok());
  for (int i = 0; i < 360; ++i) {
    ASSERT_TRUE(stepAndValidate(world));
    EXPECT_LE(length(world.jointForce(j)), maxForce * (1.0f + 1e-5f));
  }
  const auto [target, grabbed] = world.jointAnchors(j);
  EXPECT_EQ(target, (Vec2{3.0f, 4.0f}));
  // Closed form: hanging from the grabbed point, the spring of 5 Hz carries the weight, so
  // the point sits g / omega^2 (1.01 cm) below the target.
  const float omega = 2.0f * kPi * 5.0f;
  const Vec2 expected = target - Vec2{0.0f, 10.0f / (omega * omega)};
  EXPECT_LT(length(grabbed - expected), 0.002f);
}

// A ten-part ragdoll (Box2D v3's human, read for the proportions: a torso, a head, upper
// and lower arms and legs, joined by revolute joints with limits and joint friction).
std::vector<BodyId> addRagdoll(World& world, Vec2 at, float scale = 1.0f) {
  struct Part {
    Vec2 center;
    Vec2 half;
  };
  const float s = scale;
  // Parts around the hip at `at`: torso, head, upper arms, lower arms, upper legs, lower legs.
  const Part parts[10] = {{{0.0f, 0.35f}, {0.12f, 0.35f}},   {{0.0f, 0.85f}, {0.1f, 0.12f}},
                          {{-0.2f, 0.45f}, {0.05f, 0.15f}},  {{0.2f, 0.45f}, {0.05f, 0.15f}},
                          {{-0.2f, 0.15f}, {0.045f, 0.15f}}, {{0.2f, 0.15f}, {0.045f, 0.15f}},
                          {{-0.08f, -0.2f}, {0.06f, 0.2f}},  {{0.08f, -0.2f}, {0.06f, 0.2f}},
                          {{-0.08f, -0.6f}, {0.05f, 0.2f}},  {{0.08f, -0.6f}, {0.05f, 0.2f}}};
  std::vector<BodyId> bodies;
  for (const Part& p : parts)
    bodies.push_back(addBox(world, at + s * p.center, s * p.half, 0.0f, {.friction = 0.6f}));
  struct Link {
    int a, b;
    Vec2 anchor;
    float lower, upper;
  };
  const Link links[9] = {{0, 1, {0.0f, 0.72f}, -0.5f, 0.5f}, {0, 2, {-0.2f, 0.6f}, -3.0f, 1.0f},
                         {0, 3, {0.2f, 0.6f}, -1.0f, 3.0f},  {2, 4, {-0.2f, 0.3f}, -2.5f, 0.0f},
                         {3, 5, {0.2f, 0.3f}, 0.0f, 2.5f},   {0, 6, {-0.08f, 0.0f}, -1.5f, 1.0f},
                         {0, 7, {0.08f, 0.0f}, -1.0f, 1.5f}, {6, 8, {-0.08f, -0.4f}, 0.0f, 2.5f},
                         {7, 9, {0.08f, -0.4f}, -2.5f, 0.0f}};
  for (const Link& l : links) {
    JointDef d = revolute(bodies[static_cast<std::size_t>(l.a)],
                          bodies[static_cast<std::size_t>(l.b)], at + s * l.anchor);
    d.enableLimit = true;
    d.lower = l.lower;
    d.upper = l.upper;
    // Joint friction, as Box2D v3's human has: a motor held at rest with a small torque, so
    // that a dangling limb does not swing for ever (a frictionless pendulum would).
    d.enableMotor = true;
    d.motorSpeed = 0.0f;
    d.maxMotorTorque = 0.05f * s * s;
    EXPECT_TRUE(world.createJoint(d).ok());
  }
  return bodies;
}

double energy(const World& world, float g) {
  double e = 0.0;
  for (BodyId b : world.bodies()) {
    if (world.bodyType(b) != BodyType::dynamicBody) continue;
    const double m = world.mass(b), i = world.rotationalInertia(b);
    const Vec2 v = world.linearVelocity(b);
    const double w = world.angularVelocity(b);
    e += 0.5 * m * (v.x * v.x + v.y * v.y) + 0.5 * i * w * w +
         m * static_cast<double>(g) * world.worldCenterOfMass(b).y;
  }
  return e;
}

// Checked against energy conservation: a ragdoll dropped from 20 m onto a pyramid never has
// more energy (kinetic plus potential, every dynamic body) than it started with, beyond
// the pyramid's own settling, and everything comes to rest.
TEST(JointScenes, RagdollDroppedOnAPyramidNeverGainsEnergyAndRests) {
  World world = World::create({}).value();
  addStaticBox(world, {0.0f, -0.5f}, {40.0f, 0.5f});
  addPyramid(world, 8);
  const std::vector<BodyId> doll = addRagdoll(world, {0.3f, 20.0f});
  ASSERT_TRUE(valid(world));
  const double start = energy(world, 10.0f);
  const double dollMass = [&] {
    double m = 0.0;
    for (BodyId b : doll)
      m += world.mass(b);
    return m;
  }();
  double most = start;
  int steps = 0;
  for (; steps < 60 * 20 && world.awakeBodyCount() > 0; ++steps) {
    ASSERT_TRUE(stepAndValidate(world));
    most = std::max(most, energy(world, 10.0f));
  }
  std::printf("ragdoll: start %.2f J, most %.2f J, asleep after %d steps\n", start, most, steps);
  // The pyramid's contacts push out their slop when it settles: a few millijoules; the drop
  // is worth dollMass * g * 20 m (hundreds of joules).
  EXPECT_LE(most, start + 1e-3 * dollMass * 10.0 * 20.0);
  EXPECT_EQ(world.awakeBodyCount(), 0u);
  // The doll's joints held: within 3 cm at rest. Its limbs (40 to 170 g) lie wedged
  // between boxes of 1 kg, and the joints' softness (WorldDef::jointHertz) yields a little
  // to that weight; 2 cm is what this scene shows.
  for (JointId j : world.joints()) {
    const auto [pa, pb] = world.jointAnchors(j);
    EXPECT_LT(length(pb - pa), 0.03f);
  }
}

// Box2D v3's joint_grid (its layout, read for understanding): n x n circles of 0.4 m,
// 1 m apart, each pinned to the one above and the one to its left by a revolute joint,
// hanging from the 7 circles in the middle of the top row, which are static.
void addJointGrid(World& world, int n) {
  std::vector<BodyId> grid(static_cast<std::size_t>(n * n));
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < n; ++i) {
      const bool fixed = i == 0 && k >= n / 2 - 3 && k <= n / 2 + 3;
      BodyId b = world
                     .createBody({.type = fixed ? BodyType::staticBody : BodyType::dynamicBody,
                                  .position = {static_cast<float>(k), -static_cast<float>(i)}})
                     .value();
      (void)world.createShape(b, {.density = 1.0f}, makeCircle({}, 0.4f).value());
      grid[static_cast<std::size_t>(k * n + i)] = b;
      if (i > 0) {
        ASSERT_TRUE(
            world
                .createJoint(revolute(grid[static_cast<std::size_t>(k * n + i - 1)], b,
                                      {static_cast<float>(k), 0.5f - static_cast<float>(i)}))
                .ok());
      }
      if (k > 0) {
        ASSERT_TRUE(
            world
                .createJoint(revolute(grid[static_cast<std::size_t>((k - 1) * n + i)], b,
                                      {static_cast<float>(k) - 0.5f, -static_cast<float>(i)}))
                .ok());
      }
    }
  }
}

// Box2D v3's joint_grid, scaled down to 40 x 40: circles joined to their left and upper
// neighbours, hanging from a few static ones in the top row; it holds together as well as
// v3's does (v3's own grid keeps its circles from colliding; here they may: v3 measured
// the same gap both ways).
TEST(JointScenes, JointGridHoldsTogether) {
  World world = World::create({}).value();
  const int n = 40;
  addJointGrid(world, n);
  ASSERT_TRUE(valid(world));
  float worst = 0.0f;
  for (int s = 0; s < 120; ++s)
    ASSERT_TRUE(world.step());
  ASSERT_TRUE(valid(world));
  for (JointId j : world.joints()) {
    const auto [pa, pb] = world.jointAnchors(j);
    worst = std::max(worst, length(pb - pa));
  }
  std::printf("joint grid %dx%d: widest joint gap %.4f m, %d colours\n", n, n, worst,
              world.solverStats().colors);
  // Against Box2D v3 on the same 40 x 40 grid and steps: 0.0840 m (within 5%).
  EXPECT_LT(worst, 1.05f * 0.0840f);
}

// The web sandbox's chain (web/glue/glue.cpp, addChain): 20 capsule links 0.3 m long on
// pivots 0.25 m apart, so neighbours overlap at each pivot, hung level from a static pin
// and let swing down past the sandbox's static obstacles. Its fast links are swept against
// each other and against what they pass; after two seconds every joint still holds (the
// anchors within 1 cm; the sandbox saw 0.2 mm, and 9.7 cm open when the continuous phase
// once tested such pairs from one side only).
TEST(JointScenes, AChainOfOverlappingLinksSwingsDownAndHolds) {
  World world = World::create({}).value();
  addStaticBox(world, {0.0f, -3.8f}, {5.5f, 0.25f});
  addStaticBox(world, {-5.5f, -1.0f}, {0.25f, 3.0f});
  addStaticBox(world, {5.5f, -1.0f}, {0.25f, 3.0f});
  const BodyId obstacle =
      world.createBody({.type = BodyType::staticBody, .position = {-2.0f, -1.2f}, .angle = -0.25f})
          .value();
  (void)world.createShape(obstacle, {}, makeSegment({-1.5f, 0.0f}, {1.5f, 0.0f}).value()).value();
  const Vec2 at{-2.5f, 4.4f};
  BodyId previous = world.createBody({.type = BodyType::staticBody, .position = at}).value();
  (void)world.createShape(previous, {}, makeCircle({}, 0.08f).value()).value();
  const Capsule link = makeCapsule({-0.1f, 0.0f}, {0.1f, 0.0f}, 0.05f).value();
  std::vector<JointId> joints;
  for (int i = 0; i < 20; ++i) {
    const float x = at.x + 0.25f * static_cast<float>(i);
    const BodyId b = world.createBody({.position = {x + 0.125f, at.y}}).value();
    (void)world.createShape(b, {.friction = 0.4f}, link).value();
    JointDef d;
    d.type = JointType::revolute;
    d.bodyA = previous;
    d.bodyB = b;
    d.anchorA = {x, at.y};
    joints.push_back(world.createJoint(d).value());
    previous = b;
  }
  for (int s = 0; s < 120; ++s)
    ASSERT_TRUE(world.step(1.0f / 60.0f, world.def().substeps));
  ASSERT_TRUE(valid(world));
  float worst = 0.0f;
  for (JointId j : joints) {
    const auto [pa, pb] = world.jointAnchors(j);
    worst = std::max(worst, length(pb - pa));
  }
  std::printf("sandbox chain: widest joint gap %.4f m\n", worst);
  EXPECT_LT(worst, 0.01f);
  // It swung down: the last link's far pivot is well below the pin.
  EXPECT_LT(world.position(previous).y, at.y - 2.0f);
}

// Box2D v3's joint_grid at its own size, 100 x 100 (slow): it holds together under gravity.
TEST(JointScenes, HundredByHundredJointGridHoldsTogether) {
  World world = World::create({}).value();
  const int n = 100;
  addJointGrid(world, n);
  for (int s = 0; s < 120; ++s)
    ASSERT_TRUE(world.step());
  ASSERT_TRUE(valid(world));
  float worst = 0.0f;
  for (JointId j : world.joints()) {
    const auto [pa, pb] = world.jointAnchors(j);
    worst = std::max(worst, length(pb - pa));
  }
  std::printf("joint grid %dx%d: widest joint gap %.4f m after 2 s\n", n, n, worst);
  for (BodyId b : world.bodies())
    ASSERT_TRUE(isFinite(world.position(b)));
  // Against the best peer on the same scene: ten thousand half-kilogram bodies hang from
  // seven, and the top joints stretch. Box2D v3 (617d32a, its own joint_grid built with the
  // same layout, 120 steps of 1/60 s, 4 sub-steps) ends with its widest joint gap at
  // 0.5913 m; Quack must do at least as well, within 5%.
  EXPECT_LT(worst, 1.05f * 0.5913f);
}

// Continuous collision and joints: a paddle pinned at its centre and turned by a motor at
// 5 rad/s (its tips at 100 m/s) sweeps into a heavy box. An impact's response knows nothing
// of joints; were the pair swept, the paddle was knocked off its pivot (the pivot opened by
// 7 cm). A jointed body meets other dynamic bodies through the solver: the pivot holds as
// with continuous collision off (within 1.3 cm, measured), and the box is still struck.
TEST(JointScenes, AMotorPaddleHittingABoxStaysOnItsPivot) {
  for (bool continuous : {true, false}) {
    SCOPED_TRACE(continuous ? "continuous" : "discrete");
    World world = World::create({.gravity = {0.0f, 0.0f}, .enableContinuous = continuous}).value();
    const BodyId ground = addGround(world);
    const BodyId paddle = addBox(world, {0.0f, 0.0f}, {0.4f, 20.0f});
    const JointId j = world
                          .createJoint({.type = JointType::revolute,
                                        .bodyA = ground,
                                        .bodyB = paddle,
                                        .anchorA = {0.0f, 0.0f},
                                        .enableMotor = true,
                                        .motorSpeed = 5.0f,
                                        .maxMotorTorque = 1e30f})
                          .value();
    const BodyId box = addBox(world, {-15.0f, 1.0f}, {0.35f, 0.35f}, 0.0f, {.density = 40.0f});
    float widest = 0.0f;
    for (int i = 0; i < 30; ++i) {
      ASSERT_TRUE(stepAndValidate(world));
      const auto [a, b] = world.jointAnchors(j);
      widest = std::max(widest, length(b - a));
    }
    std::printf("paddle (%s): widest pivot gap %.4f m\n", continuous ? "continuous" : "discrete",
                widest);
    EXPECT_LT(widest, 0.02f);
    EXPECT_GT(length(world.linearVelocity(box)), 10.0f);  // struck
  }
}

// A scene with every joint type, contacts and sleeping, for the bit-for-bit tests.
void buildJointScene(World& world) {
  addStaticBox(world, {0.0f, -0.5f}, {30.0f, 0.5f});
  const BodyId ground = addGround(world);
  addPyramid(world, 6);
  addRagdoll(world, {0.2f, 8.0f});
  // A chain of 12 links from a pivot, swinging down into the pyramid's side.
  BodyId prev = ground;
  for (int i = 0; i < 12; ++i) {
    const Vec2 c{-14.0f + 0.5f * static_cast<float>(i) + 0.25f, 9.0f};
    const BodyId link = addBox(world, c, {0.25f, 0.06f});
    EXPECT_TRUE(world.createJoint(revolute(prev, link, c - Vec2{0.25f, 0.0f})).ok());
    prev = link;
  }
  const BodyId wheel = addBall(world, {8.0f, 1.0f}, 0.5f);
  const BodyId car = addBox(world, {8.0f, 2.0f}, {1.0f, 0.25f});
  EXPECT_TRUE(world
                  .createJoint({.type = JointType::wheel,
                                .bodyA = car,
                                .bodyB = wheel,
                                .anchorA = {8.0f, 1.0f},
                                .axis = {0.0f, 1.0f},
                                .enableMotor = true,
                                .motorSpeed = -4.0f,
                                .maxMotorTorque = 50.0f,
                                .enableSpring = true,
                                .hertz = 4.0f})
                  .ok());
  const BodyId slider = addBox(world, {12.0f, 3.0f}, {0.3f, 0.3f});
  EXPECT_TRUE(world
                  .createJoint({.type = JointType::prismatic,
                                .bodyA = ground,
                                .bodyB = slider,
                                .anchorA = {12.0f, 3.0f},
                                .axis = {1.0f, 1.0f},
                                .enableLimit = true,
                                .lower = -2.0f,
                                .upper = 0.5f,
                                .enableMotor = true,
                                .motorSpeed = 1.0f,
                                .maxMotorForce = 20.0f})
                  .ok());
  const BodyId welded = addBox(world, {13.0f, 3.5f}, {0.2f, 0.2f});
  EXPECT_TRUE(world
                  .createJoint({.type = JointType::weld,
                                .bodyA = slider,
                                .bodyB = welded,
                                .anchorA = {12.8f, 3.2f},
                                .linearHertz = 5.0f,
                                .angularHertz = 2.0f})
                  .ok());
  const BodyId swing = addBall(world, {-6.0f, 6.0f}, 0.3f);
  EXPECT_TRUE(world
                  .createJoint({.type = JointType::distance,
                                .bodyA = ground,
                                .bodyB = swing,
                                .anchorA = {-8.0f, 8.0f},
                                .anchorB = {-6.0f, 6.0f},
                                .enableLimit = true,
                                .enableSpring = true,
                                .hertz = 0.0f,
                                .maxLength = 3.5f})
                  .ok());
  const BodyId pushed = addBox(world, {-10.0f, 0.5f}, {0.5f, 0.5f});
  EXPECT_TRUE(world
                  .createJoint({.type = JointType::motor,
                                .bodyA = ground,
                                .bodyB = pushed,
                                .linearOffset = {-8.0f, 0.6f},
                                .maxForce = 30.0f,
                                .maxTorque = 5.0f})
                  .ok());
  const BodyId grabbed = addBox(world, {4.0f, 0.5f}, {0.4f, 0.4f});
  EXPECT_TRUE(world
                  .createJoint({.type = JointType::mouse,
                                .bodyB = grabbed,
                                .anchorA = {4.2f, 0.7f},
                                .maxForce = 200.0f,
                                .target = {5.0f, 3.0f}})
                  .ok());
}

std::vector<std::uint64_t> hashes(WorldDef def, int steps) {
  World world = World::create(def).value();
  buildJointScene(world);
  std::vector<std::uint64_t> out;
  for (int s = 0; s < steps; ++s) {
    EXPECT_TRUE(world.step().ok());
    out.push_back(world.stateHash());
  }
  EXPECT_TRUE(valid(world));
  return out;
}

TEST(JointDeterminism, SameBitsOnAnyNumberOfWorkersAndLanes) {
  constexpr int kSteps = 180;
  const std::vector<std::uint64_t> one = hashes({.workerCount = 1}, kSteps);
  for (int workers : {2, 3, 8}) {
    SCOPED_TRACE("workers " + std::to_string(workers));
    EXPECT_EQ(hashes({.workerCount = workers}, kSteps), one);
  }
  EXPECT_EQ(hashes({.scalarSolver = true}, kSteps), one);
}

// Revolute joints are solved a block of lanes at a time: the chain's twelve plain ones in
// blocks of their own, the ragdoll's with limits, springs and friction motors in others.
// Solving every joint one at a time must give the same bits, step by step, on one worker
// and on two, with the lanes of this build and with the one-lane path.
TEST(JointDeterminism, RevoluteJointsInLanesGiveTheOneAtATimeBits) {
  constexpr int kSteps = 240;
  for (const WorldDef& def :
       {WorldDef{.workerCount = 1}, WorldDef{.workerCount = 2}, WorldDef{.scalarSolver = true}}) {
    SCOPED_TRACE("workers " + std::to_string(def.workerCount) +
                 (def.scalarSolver ? ", one lane" : ""));
    const std::vector<std::uint64_t> lanes = hashes(def, kSteps);
    detail::setTestJointsOneAtATime(true);
    const std::vector<std::uint64_t> oneByOne = hashes(def, kSteps);
    detail::setTestJointsOneAtATime(false);
    ASSERT_EQ(lanes.size(), oneByOne.size());
    for (int s = 0; s < kSteps; ++s)
      ASSERT_EQ(lanes[s], oneByOne[s]) << "the paths part at step " << s + 1;
    EXPECT_NE(lanes.front(), lanes.back());
  }
}

// Ties every build (scalar, SSE2, AVX2, NEON, clang, wasm) to the same bits with joints:
// print it with QUACK_PRINT_GOLDEN=1.
constexpr std::uint64_t kJointGoldenHash = 0x03f793a8bec8250b;

TEST(JointDeterminism, GoldenHashOnEveryBuild) {
  const std::uint64_t hash = hashes({}, 300).back();
  if (std::getenv("QUACK_PRINT_GOLDEN") != nullptr)
    std::printf("joint golden hash: 0x%016llx\n", static_cast<unsigned long long>(hash));
  EXPECT_EQ(hash, kJointGoldenHash) << "lanes: " << World::simdPath();
}

// A world restored mid-swing continues to the same bits, from a full and a dynamic
// snapshot.
TEST(JointDeterminism, RestoredMidSwingContinuesToTheSameBits) {
  for (SnapshotKind kind : {SnapshotKind::full, SnapshotKind::dynamic}) {
    SCOPED_TRACE(toString(kind));
    World world = World::create({}).value();
    buildJointScene(world);
    for (int s = 0; s < 45; ++s)
      ASSERT_TRUE(world.step());
    Result<std::vector<std::uint8_t>> taken = world.snapshot(kind);
    ASSERT_TRUE(taken.ok()) << taken.error().message;
    const std::vector<std::uint8_t> bytes = std::move(taken).value();
    std::vector<std::uint64_t> ahead;
    std::vector<Vec2> forces;
    for (int s = 0; s < 60; ++s) {
      ASSERT_TRUE(world.step());
      ahead.push_back(world.stateHash());
      for (JointId j : world.joints())
        forces.push_back(world.jointForce(j));
    }
    World restored = World::create({}).value();
    if (kind == SnapshotKind::full) {
      Result<World> made = World::fromSnapshot(bytes);
      ASSERT_TRUE(made.ok()) << made.error().message;
      restored = std::move(made).value();
    } else {
      // A dynamic snapshot goes back into the world it came from.
      restored = std::move(world);
      const Status st = restored.restore(bytes);
      ASSERT_TRUE(st.ok()) << st.message();
    }
    ASSERT_TRUE(valid(restored));
    std::vector<Vec2> again;
    for (int s = 0; s < 60; ++s) {
      ASSERT_TRUE(restored.step());
      ASSERT_EQ(restored.stateHash(), ahead[static_cast<std::size_t>(s)]) << "step " << s;
      for (JointId j : restored.joints())
        again.push_back(restored.jointForce(j));
    }
    EXPECT_EQ(again.size(), forces.size());
    EXPECT_TRUE(again == forces);
  }
}

}  // namespace
}  // namespace quack
