// World3 against closed forms: free fall, rolling without slipping, restitution, an elastic
// swap, Coulomb friction on a slope, a stack that stands and sleeps, determinism.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "quack/world/world3.hpp"

namespace quack {
namespace {

constexpr float kG = 10.0f;

BodyId3 addGround(World3& world, float friction = 0.6f, float restitution = 0.0f) {
  const BodyId3 ground = world.createBody({.type = BodyType::staticBody}).value();
  (void)world
      .createShape(ground, {.friction = friction, .restitution = restitution},
                   makeBox3({20, 0.5f, 20}, {{0, -0.5f, 0}, {}}).value())
      .value();
  return ground;
}

// A static slab turned by `angle` about z (its top face rises towards -x); returns the
// unit normal of the top face. The top face passes through the origin.
Vec3 addSlope(World3& world, float angle, float friction) {
  const Quat q = Quat::fromAxisAngle({0, 0, 1}, angle);
  const Vec3 n = rotate(q, {0, 1, 0});
  const BodyId3 slope =
      world.createBody({.type = BodyType::staticBody, .position = -0.5f * n, .rotation = q})
          .value();
  (void)world.createShape(slope, {.friction = friction}, makeBox3({30, 0.5f, 5}).value()).value();
  return n;
}

TEST(World3Motion, FreeFallAndSpinMatchTheirClosedForms) {
  World3 world = World3::create().value();
  const BodyId3 ball =
      world.createBody({.position = {0, 100, 0}, .angularVelocity = {0, 2, 0}}).value();
  ASSERT_TRUE(world.createShape(ball, {}, makeBox3({0.5f, 0.5f, 0.5f}).value()).ok());
  const int steps = 60;
  for (int i = 0; i < steps; ++i)
    ASSERT_TRUE(world.step().ok());
  // Semi-implicit Euler in sub-steps of h: y = y0 - g h^2 n (n + 1) / 2 after n sub-steps,
  // within g h t / 2 of the closed form.
  const double h = 1.0 / 240.0;
  const double n = 4.0 * steps;
  EXPECT_NEAR(world.position(ball).y, 100.0 - kG * h * h * n * (n + 1.0) / 2.0, 1e-3);
  EXPECT_NEAR(world.linearVelocity(ball).y, -kG * 1.0, 1e-3);
  // A cube spins about y at a steady rate (its inertia is isotropic): 2 rad in 1 s.
  const Quat expected = Quat::fromAxisAngle({0, 1, 0}, 2.0f);
  EXPECT_GT(std::fabs(dot(world.rotation(ball), expected)), 1.0f - 1e-5f);
  EXPECT_NEAR(world.angularVelocity(ball).y, 2.0f, 1e-6f);
}

// A solid sphere rolling without slipping down a slope of angle theta accelerates at
// 5/7 g sin(theta) (a sliding one, without friction, at g sin(theta)).
TEST(World3Motion, SphereRollsDownASlopeAtFiveSeventhsGSinTheta) {
  const float theta = 20.0f * kPi / 180.0f;
  World3 world = World3::create({.enableSleep = false}).value();
  const Vec3 n = addSlope(world, theta, 0.6f);
  const float r = 0.5f;
  const BodyId3 ball = world.createBody({.position = (r + 0.001f) * n}).value();
  ASSERT_TRUE(world.createShape(ball, {.density = 100.0f, .friction = 0.6f}, Sphere{{}, r}).ok());
  const Vec3 downhill = -rotate(Quat::fromAxisAngle({0, 0, 1}, theta), {1, 0, 0});
  const float t = 1.5f;
  for (int i = 0; i < 90; ++i)
    ASSERT_TRUE(world.step().ok());
  const float a = 5.0f / 7.0f * kG * std::sin(theta);
  const float speed = dot(world.linearVelocity(ball), downhill);
  EXPECT_NEAR(speed, a * t, 0.01f * a * t);
  // Rolling: the contact point is at rest, v = w x (r n).
  const Vec3 slip = world.linearVelocity(ball) + cross(world.angularVelocity(ball), -r * n);
  EXPECT_LT(length(slip), 0.01f * speed);
  // It stays on the slope.
  EXPECT_NEAR(dot(world.position(ball), n), r, 0.01f);
}

// Dropped from height H onto the ground, a sphere of restitution e leaves at e times the
// speed it approached with, so it rises to e^2 H. The solver takes the approach speed at the
// start of the step in which it reaches the ground (speculative contact), which is up to
// g dt short of the speed at impact: the rebound lies within that.
TEST(World3Motion, RestitutionReboundHeight) {
  World3 world = World3::create({.enableSleep = false}).value();
  addGround(world);
  const float r = 0.25f, drop = 2.0f, e = 0.5f, dt = 1.0f / 60.0f;
  const BodyId3 ball = world.createBody({.position = {0, r + drop, 0}}).value();
  ASSERT_TRUE(world.createShape(ball, {.restitution = e}, Sphere{{}, r}).ok());
  bool bounced = false;
  float top = 0.0f;
  for (int i = 0; i < 120; ++i) {
    ASSERT_TRUE(world.step().ok());
    const float vy = world.linearVelocity(ball).y;
    if (!bounced && vy > 0.0f) bounced = true;
    if (bounced) top = std::max(top, world.position(ball).y - r);
  }
  ASSERT_TRUE(bounced);
  const float impact = std::sqrt(2.0f * kG * drop);
  const float lowest = e * (impact - kG * dt);
  // (0.01 m: the top is sampled once a step.)
  EXPECT_LE(top, e * e * drop + 0.01f);
  EXPECT_GE(top, lowest * lowest / (2.0f * kG) - 0.01f);
}

// Two equal spheres, restitution 1, head on: the moving one stops, the other leaves with its
// velocity (momentum and energy conserved).
TEST(World3Motion, ElasticCollisionSwapsTheVelocitiesOfEqualSpheres) {
  World3 world = World3::create({.gravity = {0, 0, 0}, .enableSleep = false}).value();
  const BodyId3 a = world.createBody({.position = {0, 0, 0}, .linearVelocity = {5, 0, 0}}).value();
  const BodyId3 b = world.createBody({.position = {2, 0, 0}}).value();
  ASSERT_TRUE(world.createShape(a, {.restitution = 1.0f}, Sphere{{}, 0.5f}).ok());
  ASSERT_TRUE(world.createShape(b, {.restitution = 1.0f}, Sphere{{}, 0.5f}).ok());
  for (int i = 0; i < 60; ++i)
    ASSERT_TRUE(world.step().ok());
  EXPECT_NEAR(world.linearVelocity(a).x, 0.0f, 0.05f);
  EXPECT_NEAR(world.linearVelocity(b).x, 5.0f, 0.05f);
  EXPECT_NEAR(world.linearVelocity(a).x + world.linearVelocity(b).x, 5.0f, 1e-4f);
}

struct SlopeRun {
  float along;  // metres slid downhill
  float speed;  // m/s downhill at the end
  float tilt;   // 1 - |cos| of the turn from the slope's rotation
};

SlopeRun slideBox(float degrees, float friction, int steps) {
  const float theta = degrees * kPi / 180.0f;
  World3 world = World3::create({.enableSleep = false}).value();
  const Vec3 n = addSlope(world, theta, friction);
  const Quat q = Quat::fromAxisAngle({0, 0, 1}, theta);
  const Vec3 start = 0.5f * n;
  const BodyId3 box = world.createBody({.position = start, .rotation = q}).value();
  (void)world.createShape(box, {.friction = friction}, makeBox3({0.5f, 0.5f, 0.5f}).value());
  for (int i = 0; i < steps; ++i)
    (void)world.step();
  const Vec3 downhill = -rotate(q, {1, 0, 0});
  return {dot(world.position(box) - start, downhill), dot(world.linearVelocity(box), downhill),
          1.0f - std::fabs(dot(world.rotation(box), q))};
}

// Coulomb: a box holds on a slope while tan(theta) <= mu (30 degrees, mu 0.6 > 0.577), and
// slides at g (sin - mu cos) beyond (40 degrees).
TEST(World3Motion, BoxHoldsOnThirtyDegreesAndSlidesOnFortyWithCoulombAcceleration) {
  const SlopeRun hold = slideBox(30.0f, 0.6f, 120);
  EXPECT_LT(std::fabs(hold.along), 0.01f);
  EXPECT_LT(std::fabs(hold.speed), 0.01f);
  EXPECT_LT(hold.tilt, 1e-4f);

  const float theta = 40.0f * kPi / 180.0f;
  const float a = kG * (std::sin(theta) - 0.6f * std::cos(theta));
  const SlopeRun slide = slideBox(40.0f, 0.6f, 60);
  EXPECT_NEAR(slide.speed, a * 1.0f, 0.02f * a);
  EXPECT_NEAR(slide.along, 0.5f * a, 0.03f * 0.5f * a);
  EXPECT_LT(slide.tilt, 1e-4f);
}

// Ten unit cubes on the ground stand for 10 s, upright and in place, and fall asleep.
TEST(World3Motion, TenBoxColumnStandsTenSecondsAndSleeps) {
  World3 world = World3::create().value();
  addGround(world);
  std::vector<BodyId3> boxes;
  for (int i = 0; i < 10; ++i) {
    boxes.push_back(world.createBody({.position = {0, 0.5f + 1.0f * float(i), 0}}).value());
    ASSERT_TRUE(world.createShape(boxes.back(), {}, makeBox3({0.5f, 0.5f, 0.5f}).value()).ok());
  }
  int asleepAt = -1;
  for (int i = 0; i < 600; ++i) {
    ASSERT_TRUE(world.step().ok());
    if (asleepAt < 0 && world.awakeBodyCount() == 0) asleepAt = i;
  }
  for (int i = 0; i < 10; ++i) {
    const Vec3 p = world.position(boxes[static_cast<std::size_t>(i)]);
    EXPECT_LT(std::fabs(p.x), 0.01f) << i;
    EXPECT_LT(std::fabs(p.z), 0.01f) << i;
    // Each soft contact rests a little deep, as a spring of the contact's stiffness under
    // the weight above it: m_above g / (omega^2 m_eff), omega = 2 pi 30 Hz and m_eff = m / 2
    // between two boxes, 2 pi 60 Hz and m against the ground (WorldDef3's contactHertz,
    // doubled against static bodies). Box k (0 at the bottom) sinks by the sum below it.
    const double w1 = 2.0 * 3.14159265358979 * 30.0, w2 = 2.0 * w1;
    double sink = 10.0 * kG / (w2 * w2);
    for (int k = 1; k <= i; ++k)
      sink += (10.0 - k) * kG / (w1 * w1 * 0.5);
    EXPECT_NEAR(p.y, 0.5 + i - sink, 1e-3) << i;
    EXPECT_GT(std::fabs(world.rotation(boxes[static_cast<std::size_t>(i)]).w), 1.0f - 1e-4f) << i;
  }
  EXPECT_GE(asleepAt, 0) << "the column never fell asleep";
  EXPECT_LT(asleepAt, 300);
  // A push on the top box wakes the whole island.
  ASSERT_TRUE(
      world.applyLinearImpulse(boxes.back(), {0.1f, 0, 0}, world.position(boxes.back())).ok());
  ASSERT_TRUE(world.step().ok());
  EXPECT_EQ(world.awakeBodyCount(), 10u);
}

// A box resting across the shared diagonal of a two-triangle mesh floor: flat, at its
// height, with no sideways drift (no ghost normals).
TEST(World3Motion, BoxRestsOnAMeshFloor) {
  World3 world = World3::create({.enableSleep = false}).value();
  const std::array<Vec3, 4> vertices = {Vec3{-5, 0, -5}, Vec3{-5, 0, 5}, Vec3{5, 0, 5},
                                        Vec3{5, 0, -5}};
  const std::array<std::array<std::int32_t, 3>, 2> triangles = {{{0, 1, 2}, {0, 2, 3}}};
  const BodyId3 ground = world.createBody({.type = BodyType::staticBody}).value();
  ASSERT_TRUE(world.createShape(ground, {}, makeMesh3(vertices, triangles).value()).ok());
  const BodyId3 box = world
                          .createBody({.position = {0.1f, 0.6f, -0.2f},
                                       .rotation = Quat::fromAxisAngle({0, 1, 0}, 0.3f)})
                          .value();
  ASSERT_TRUE(world.createShape(box, {}, makeBox3({0.5f, 0.5f, 0.5f}).value()).ok());
  for (int i = 0; i < 120; ++i)
    ASSERT_TRUE(world.step().ok());
  const Vec3 p = world.position(box);
  EXPECT_NEAR(p.y, 0.5f, 0.01f);
  EXPECT_NEAR(p.x, 0.1f, 1e-3f);
  EXPECT_NEAR(p.z, -0.2f, 1e-3f);
  EXPECT_GT(std::fabs(dot(world.rotation(box), Quat::fromAxisAngle({0, 1, 0}, 0.3f))),
            1.0f - 1e-5f);
}

// A mixed pile on the ground, twice: the same bits. (The same pile on a mesh floor:
// world3_stacking_test.cpp.)
std::vector<float> runPile() {
  World3 world = World3::create().value();
  addGround(world);
  std::vector<BodyId3> bodies;
  for (int i = 0; i < 24; ++i) {
    const float fi = float(i);
    const BodyId3 b =
        world
            .createBody({.position = {1.2f * float(i % 3) - 1.2f, 0.6f + 0.9f * float(i / 6),
                                      1.1f * float((i / 3) % 2) + 0.1f * fi},
                         .rotation = Quat::fromAxisAngle({0, 1, 0}, 0.4f * fi)})
            .value();
    if (i % 3 == 0) (void)world.createShape(b, {}, Sphere{{}, 0.35f});
    if (i % 3 == 1) (void)world.createShape(b, {}, makeBox3({0.4f, 0.3f, 0.35f}).value());
    if (i % 3 == 2) (void)world.createShape(b, {}, Capsule3{{-0.3f, 0, 0}, {0.3f, 0, 0}, 0.2f});
    bodies.push_back(b);
  }
  for (int i = 0; i < 180; ++i)
    (void)world.step();
  std::vector<float> out;
  for (BodyId3 b : bodies) {
    const Transform3 xf = world.transform(b);
    out.insert(out.end(), {xf.p.x, xf.p.y, xf.p.z, xf.q.x, xf.q.y, xf.q.z, xf.q.w});
  }
  return out;
}

TEST(World3Motion, SameBitsOnTwoRuns) {
  const std::vector<float> first = runPile();
  const std::vector<float> second = runPile();
  ASSERT_EQ(first.size(), second.size());
  EXPECT_EQ(std::memcmp(first.data(), second.data(), first.size() * sizeof(float)), 0);
  // And the pile settled on the floor rather than falling through or flying off.
  for (std::size_t i = 0; i < first.size(); i += 7) {
    EXPECT_GT(first[i + 1], 0.0f);
    EXPECT_LT(first[i + 1], 10.0f);
  }
}

// Twist friction: a unit cube spinning about the vertical on the floor is slowed by
// friction at its four corner points, each carrying m g / 4 at lever sqrt(0.5) from the
// centre: torque mu m g sqrt(0.5) over I = m / 6, so it loses mu g sqrt(0.5) 6 = 25.46 rad/s
// each second (the four-point contact's closed form; a pressure spread over the face would
// give 0.383 instead of sqrt(0.5)), and once stopped it stays stopped.
TEST(World3Motion, ASpinningCubeIsStoppedByTwistFriction) {
  World3 world = World3::create({.enableSleep = false}).value();
  addGround(world, 0.6f);
  const BodyId3 cube =
      world.createBody({.position = {0, 0.5f, 0}, .angularVelocity = {0, 5, 0}}).value();
  ASSERT_TRUE(
      world.createShape(cube, {.friction = 0.6f}, makeBox3({0.5f, 0.5f, 0.5f}).value()).ok());
  for (int i = 0; i < 6; ++i)
    ASSERT_TRUE(world.step().ok());
  const double loss = 0.6 * kG * std::sqrt(0.5) * 6.0;
  EXPECT_NEAR(world.angularVelocity(cube).y, 5.0 - loss * 0.1, 0.05 * loss * 0.1);
  for (int i = 0; i < 60; ++i)
    ASSERT_TRUE(world.step().ok());
  EXPECT_LT(std::fabs(world.angularVelocity(cube).y), 1e-3f);
  EXPECT_LT(length(world.linearVelocity(cube)), 1e-3f);
  EXPECT_NEAR(world.position(cube).y, 0.5f, 0.01f);
}

}  // namespace
}  // namespace quack
