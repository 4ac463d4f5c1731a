// Joints (docs/world.md, "Joints"): each type checked against a closed form (a pendulum's
// period, a spring's frequency, a catenary's sag, a motor's spin-up, a limit's torque), the
// API's errors, events, islands and sleep, and snapshots.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "quack/world/world.hpp"
#include "world_test_util.hpp"

namespace quack {
namespace {

using testing::addBall;
using testing::addBox;
using testing::addStaticBox;
using testing::stepAndValidate;
using testing::valid;

BodyId addGround(World& world) {
  return world.createBody({.type = BodyType::staticBody}).value();
}

// Times between upward zero crossings of f over `steps` steps (linear interpolation between
// steps), averaged: the period.
template <class Sample>
double measurePeriod(World& world, int steps, Sample f, int* crossings = nullptr) {
  double last = f(), lastT = 0.0;
  std::vector<double> ups;
  for (int i = 0; i < steps; ++i) {
    EXPECT_TRUE(world.step());
    const double v = f(), t = world.time();
    if (last < 0.0 && v >= 0.0) ups.push_back(lastT + (t - lastT) * (-last) / (v - last));
    last = v;
    lastT = t;
  }
  if (crossings != nullptr) *crossings = static_cast<int>(ups.size());
  if (ups.size() < 2) return 0.0;
  return (ups.back() - ups.front()) / static_cast<double>(ups.size() - 1);
}

// Closed form: a physical pendulum (a disk of radius r on a massless arm of length L, about
// a frictionless pivot) swinging 0.05 rad: T = 2 pi sqrt((L^2 + r^2/2) / (g L)), times the
// amplitude correction 1 + theta^2 / 16 (1.00016 here).
TEST(Joints, PendulumPeriodMatchesTheClosedForm) {
  World world = World::create({.gravity = {0.0f, -10.0f}}).value();
  const BodyId ground = addGround(world);
  const float L = 2.0f, r = 0.05f, theta = 0.05f;
  const Vec2 bob{L * std::sin(theta), -L * std::cos(theta)};
  const BodyId ball = addBall(world, bob, r);
  // The revolute anchor at the pivot: the bob swings on body B's arm.
  JointId j = world
                  .createJoint({.type = JointType::revolute,
                                .bodyA = ground,
                                .bodyB = ball,
                                .anchorA = {0.0f, 0.0f}})
                  .value();
  ASSERT_TRUE(valid(world));
  int crossings = 0;
  const double period = measurePeriod(
      world, 60 * 20, [&] { return static_cast<double>(world.position(ball).x); }, &crossings);
  ASSERT_GE(crossings, 5);
  const double g = 10.0;
  const double expected = 2.0 * 3.14159265358979 * std::sqrt((L * L + 0.5 * r * r) / (g * L)) *
                          (1.0 + theta * theta / 16.0);
  std::printf("pendulum: period %.5f s, closed form %.5f s\n", period, expected);
  EXPECT_NEAR(period, expected, 0.005 * expected);
  // The joint held: the bob stays L from the pivot.
  EXPECT_NEAR(length(world.position(ball)), L, 0.01f * L);
  EXPECT_TRUE(world.isValid(j));
}

// Closed form: a distance joint with a spring of f Hz and no damping, holding a body with
// no gravity: it oscillates at f (the soft step defines the spring by its frequency).
TEST(Joints, DistanceSpringOscillatesAtItsHertz) {
  World world = World::create({.gravity = {0.0f, 0.0f}}).value();
  const BodyId ground = addGround(world);
  const BodyId ball = addBall(world, {2.5f, 0.0f}, 0.25f);
  const float hertz = 1.0f;
  ASSERT_TRUE(world
                  .createJoint({.type = JointType::distance,
                                .bodyA = ground,
                                .bodyB = ball,
                                .anchorA = {0.0f, 0.0f},
                                .anchorB = {2.5f, 0.0f},
                                .enableSpring = true,
                                .hertz = hertz,
                                .dampingRatio = 0.0f,
                                .length = 2.0f})
                  .ok());
  int crossings = 0;
  const double period = measurePeriod(
      world, 60 * 10, [&] { return static_cast<double>(world.position(ball).x) - 2.0; },
      &crossings);
  ASSERT_GE(crossings, 5);
  std::printf("spring: period %.5f s, 1/hertz %.5f s\n", period, 1.0 / hertz);
  EXPECT_NEAR(period, 1.0 / hertz, 0.01 / hertz);
}

// Closed form: a disk driven by a revolute motor from rest spins up at maxTorque / I until
// it reaches the motor's speed, then holds it; the joint's torque never passes the max.
TEST(Joints, MotorReachesItsSpeedWithinItsTorque) {
  World world = World::create({.gravity = {0.0f, 0.0f}}).value();
  const BodyId ground = addGround(world);
  const BodyId wheel = addBall(world, {0.0f, 0.0f}, 1.0f);
  const float speed = 5.0f, maxTorque = 2.0f;
  const JointId j = world
                        .createJoint({.type = JointType::revolute,
                                      .bodyA = ground,
                                      .bodyB = wheel,
                                      .anchorA = {0.0f, 0.0f},
                                      .enableMotor = true,
                                      .motorSpeed = speed,
                                      .maxMotorTorque = maxTorque})
                        .value();
  const float inertia = world.rotationalInertia(wheel);
  const float alpha = maxTorque / inertia;
  for (int i = 0; i < 30; ++i) {
    ASSERT_TRUE(world.step());
    EXPECT_LE(std::abs(world.jointTorque(j)), maxTorque * (1.0f + 1e-5f));
  }
  // Still spinning up after half a second (alpha t < speed): omega = alpha t.
  const float t = static_cast<float>(world.time());
  ASSERT_LT(alpha * t, speed);
  EXPECT_NEAR(world.angularVelocity(wheel), alpha * t, 0.01f * alpha * t);
  for (int i = 0; i < 600; ++i) {
    ASSERT_TRUE(world.step());
    EXPECT_LE(std::abs(world.jointTorque(j)), maxTorque * (1.0f + 1e-5f));
  }
  EXPECT_NEAR(world.angularVelocity(wheel), speed, 0.01f * speed);
}

// A limit holds a 1,000 N m load: a bar whose weight pulls it down about the pivot with
// 1,000 N m rests on the lower limit, and the joint's torque balances the weight's.
TEST(Joints, RevoluteLimitHoldsAThousandNewtonMetres) {
  World world = World::create({}).value();
  const BodyId ground = addGround(world);
  // A 4 m bar of 50 kg with its centre 2 m from the pivot: 50 * 10 * 2 = 1,000 N m.
  const BodyId bar = addBox(world, {2.0f, 0.0f}, {2.0f, 0.125f}, 0.0f, {.density = 50.0f});
  ASSERT_NEAR(world.mass(bar), 50.0f, 1e-3f);
  const JointId j = world
                        .createJoint({.type = JointType::revolute,
                                      .bodyA = ground,
                                      .bodyB = bar,
                                      .anchorA = {0.0f, 0.0f},
                                      .enableLimit = true,
                                      .lower = -0.25f,
                                      .upper = 0.25f})
                        .value();
  for (int i = 0; i < 240; ++i)
    ASSERT_TRUE(stepAndValidate(world));
  EXPECT_NEAR(world.jointAngle(j), -0.25f, 0.01f);
  // The weight's moment at the limit's angle: 1,000 cos(0.25) N m.
  const float expected = 1000.0f * std::cos(0.25f);
  EXPECT_NEAR(world.jointTorque(j), expected, 0.02f * expected);
  EXPECT_NEAR(length(world.jointAnchors(j).first - world.jointAnchors(j).second), 0.0f, 0.01f);
}

// A prismatic joint's lower limit stops a body falling along its vertical axis.
TEST(Joints, PrismaticLimitStopsAFallingBody) {
  World world = World::create({}).value();
  const BodyId ground = addGround(world);
  const BodyId box = addBox(world, {0.0f, 5.0f}, {0.5f, 0.5f});
  const JointId j = world
                        .createJoint({.type = JointType::prismatic,
                                      .bodyA = ground,
                                      .bodyB = box,
                                      .anchorA = {0.0f, 5.0f},
                                      .axis = {0.0f, 1.0f},
                                      .enableLimit = true,
                                      .lower = -3.0f,
                                      .upper = 1.0f})
                        .value();
  float lowest = 0.0f;
  for (int i = 0; i < 240; ++i) {
    ASSERT_TRUE(stepAndValidate(world));
    lowest = std::min(lowest, world.jointTranslation(j));
    // It slides, it does not turn or drift across the axis.
    EXPECT_NEAR(world.position(box).x, 0.0f, 1e-3f);
    EXPECT_NEAR(world.angle(box), 0.0f, 1e-3f);
  }
  EXPECT_GT(lowest, -3.0f - 0.02f);
  EXPECT_NEAR(world.jointTranslation(j), -3.0f, 0.01f);
  EXPECT_NEAR(world.position(box).y, 2.0f, 0.01f);
  // Held by the limit: the joint pushes up with the box's weight.
  EXPECT_NEAR(world.jointForce(j).y, world.mass(box) * 10.0f, 0.02f * world.mass(box) * 10.0f);
}

// Closed form: a chain hanging between two points at the same height settles to a catenary,
// y = a cosh(x / a): its length S = 2 a sinh(D / 2a) for a span D fixes a, and the sag is
// a (cosh(D / 2a) - 1). Forty links of 0.5 m (S = 20 m) across D = 14 m.
TEST(Joints, ChainHangingFromBothEndsSettlesToTheCatenary) {
  World world = World::create({}).value();
  const BodyId ground = addGround(world);
  const int n = 40;
  const float link = 0.5f, D = 14.0f;
  const float S = link * static_cast<float>(n);
  // Laid out straight at first, then released: the left end at (-7, 0); the chain starts
  // along a V so that both ends reach their pivots.
  std::vector<BodyId> links;
  std::vector<JointId> joints;
  std::vector<Vec2> ends(n + 1);
  // A V whose arms are S / 2 long, spanning D.
  const float dropPerArm = std::sqrt(0.25f * S * S - 0.25f * D * D);
  for (int i = 0; i <= n; ++i) {
    const float t = static_cast<float>(i) / static_cast<float>(n);
    const float x = -0.5f * D + D * t;
    const float y = -dropPerArm * (1.0f - std::abs(2.0f * t - 1.0f));
    ends[static_cast<std::size_t>(i)] = {x, y};
  }
  for (int i = 0; i < n; ++i) {
    const Vec2 a = ends[static_cast<std::size_t>(i)], b = ends[static_cast<std::size_t>(i + 1)];
    const Vec2 mid = 0.5f * (a + b);
    const float angle = std::atan2(b.y - a.y, b.x - a.x);
    BodyId body =
        world
            .createBody(
                {.position = mid, .angle = angle, .linearDamping = 0.5f, .angularDamping = 0.5f})
            .value();
    (void)world.createShape(body, {}, makeBox(0.5f * link, 0.05f).value()).value();
    links.push_back(body);
  }
  for (int i = 0; i <= n; ++i) {
    const BodyId a = i == 0 ? ground : links[static_cast<std::size_t>(i - 1)];
    const BodyId b = i == n ? ground : links[static_cast<std::size_t>(i)];
    joints.push_back(world
                         .createJoint({.type = JointType::revolute,
                                       .bodyA = a,
                                       .bodyB = b,
                                       .anchorA = ends[static_cast<std::size_t>(i)]})
                         .value());
  }
  ASSERT_TRUE(valid(world));
  for (int i = 0; i < 60 * 30; ++i)
    ASSERT_TRUE(world.step());
  ASSERT_TRUE(valid(world));
  // Every joint holds its two links together within 1% of a link.
  for (const JointId& j : joints) {
    const auto [pa, pb] = world.jointAnchors(j);
    EXPECT_LT(length(pb - pa), 0.01f * link);
  }
  // The catenary: solve S = 2 a sinh(D / 2a) for a by bisection.
  double lo = 0.1, hi = 1000.0;
  for (int k = 0; k < 200; ++k) {
    const double a = 0.5 * (lo + hi);
    if (2.0 * a * std::sinh(D / (2.0 * a)) > S) {
      lo = a;
    } else {
      hi = a;
    }
  }
  const double a = 0.5 * (lo + hi);
  const double sag = a * (std::cosh(D / (2.0 * a)) - 1.0);
  // The lowest point of the chain: its middle joint (between links 19 and 20).
  const double lowest = -world.jointAnchors(joints[n / 2]).first.y;
  std::printf("chain: sag %.4f m, catenary %.4f m\n", lowest, sag);
  EXPECT_NEAR(lowest, sag, 0.02 * sag);
  // And at rest.
  for (const BodyId& b : links)
    EXPECT_LT(length(world.linearVelocity(b)), 0.05f);
}

}  // namespace
}  // namespace quack
