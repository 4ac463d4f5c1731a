// World3 stacks: a column and a pyramid of unit cubes standing for a simulated minute, a
// heavy-on-light column, a mixed pile on a mesh floor. Sleeping is off, so what is measured
// is the solver holding the pile up every step. The reference is the symmetric start: a
// symmetric stack must stay where it was built, less the soft contacts' compression.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "quack/world/world3.hpp"

namespace quack {
namespace {

constexpr int kMinuteSteps = 60 * 60;

void addGround(World3& world) {
  const BodyId3 ground = world.createBody({.type = BodyType::staticBody}).value();
  ASSERT_TRUE(
      world.createShape(ground, {}, makeBox3({50, 0.5f, 50}, {{0, -0.5f, 0}, {}}).value()).ok());
}

struct Stack {
  std::vector<BodyId3> bodies;
  std::vector<Vec3> start;
};

BodyId3 addCube(World3& world, Stack& stack, Vec3 p, float density = 1.0f) {
  const BodyId3 b = world.createBody({.position = p}).value();
  EXPECT_TRUE(
      world.createShape(b, {.density = density}, makeBox3({0.5f, 0.5f, 0.5f}).value()).ok());
  stack.bodies.push_back(b);
  stack.start.push_back(p);
  return b;
}

// How far any body moved sideways (x and z) from where it was built, and the largest turn
// of any body (radians).
struct Drift {
  float sideways = 0.0f;
  float turn = 0.0f;
};

Drift measure(const World3& world, const Stack& stack) {
  Drift d;
  for (std::size_t i = 0; i < stack.bodies.size(); ++i) {
    const Vec3 p = world.position(stack.bodies[i]);
    d.sideways = std::max(d.sideways, std::hypot(p.x - stack.start[i].x, p.z - stack.start[i].z));
    const Quat q = world.rotation(stack.bodies[i]);
    d.turn = std::max(d.turn, 2.0f * std::asin(std::min(1.0f, length(q.vector()))));
  }
  return d;
}

// Twenty unit cubes on top of each other stand a minute: every box within 5 cm of its
// column (the 2D column test's bound; measured 1.9 cm, a wander that does not grow), none
// turned more than 0.02 rad. Before contact recycling (docs/world3.md) the
// column leaned from the tenth second and fell; before faces were preferred to edges within
// kLinearSlop, flush boxes got one-point edge contacts and fell sooner.
TEST(World3Stacking, TwentyBoxColumnStandsAMinute) {
  World3 world = World3::create({.enableSleep = false}).value();
  addGround(world);
  Stack stack;
  for (int i = 0; i < 20; ++i)
    addCube(world, stack, {0, 0.5f + float(i), 0});
  for (int s = 0; s < kMinuteSteps; ++s)
    ASSERT_TRUE(world.step().ok());
  const Drift d = measure(world, stack);
  EXPECT_LT(d.sideways, 0.05f);
  EXPECT_LT(d.turn, 0.02f);
  // Still a column: the top box above the 19 others (sunk by the soft contacts, not fallen).
  EXPECT_GT(world.position(stack.bodies.back()).y, 19.0f);
}

// A 20-row pyramid of unit cubes (210, a single layer as Box2D's pyramid, half a cube
// apart in z from nothing: it could fall either way) stands a minute.
TEST(World3Stacking, TwentyRowPyramidStandsAMinute) {
  World3 world = World3::create({.enableSleep = false}).value();
  addGround(world);
  Stack stack;
  const int rows = 20;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < rows - r; ++c)
      addCube(world, stack, {float(c) - 0.5f * float(rows - r - 1), 0.5f + float(r), 0});
  for (int s = 0; s < kMinuteSteps; ++s)
    ASSERT_TRUE(world.step().ok());
  const Drift d = measure(world, stack);
  EXPECT_LT(d.sideways, 0.02f);
  EXPECT_LT(d.turn, 0.02f);
  EXPECT_GT(world.position(stack.bodies.back()).y, float(rows) - 1.0f);
}

// Heavy on light: ten cubes alternating density 1 and 10 (a 10:1 mass ratio at every
// contact) stand 20 s, and each contact's compression is what the soft contacts predict
// within a factor of two (the bottom contact carries the most: no contact gives way).
TEST(World3Stacking, TenToOneMassRatioColumnStands) {
  World3 world = World3::create({.enableSleep = false}).value();
  addGround(world);
  Stack stack;
  for (int i = 0; i < 10; ++i)
    addCube(world, stack, {0, 0.5f + float(i), 0}, (i % 2) ? 10.0f : 1.0f);
  for (int s = 0; s < 20 * 60; ++s)
    ASSERT_TRUE(world.step().ok());
  const Drift d = measure(world, stack);
  EXPECT_LT(d.sideways, 0.01f);
  EXPECT_LT(d.turn, 0.01f);
  // Every box above the one under it, by at least 0.97 m: overlap at most 3 cm at the
  // bottom, under 5 x 11 kg.
  for (std::size_t i = 1; i < stack.bodies.size(); ++i) {
    const float gap = world.position(stack.bodies[i]).y - world.position(stack.bodies[i - 1]).y;
    EXPECT_GT(gap, 0.97f) << "box " << i;
    EXPECT_LT(gap, 1.0f + 1e-3f) << "box " << i;
  }
}

// A pile of 24 spheres, boxes and capsules dropped on a two-triangle mesh floor 40 m
// across: nothing passes through the triangles, and the pile settles (every body asleep
// within 10 s, none below the floor).
TEST(World3Stacking, MixedPileSettlesOnAMeshFloor) {
  World3 world = World3::create().value();
  const std::array<Vec3, 4> vertices = {Vec3{-20, 0, -20}, Vec3{-20, 0, 20}, Vec3{20, 0, 20},
                                        Vec3{20, 0, -20}};
  const std::array<std::array<std::int32_t, 3>, 2> triangles = {{{0, 1, 2}, {0, 2, 3}}};
  const BodyId3 ground = world.createBody({.type = BodyType::staticBody}).value();
  ASSERT_TRUE(world.createShape(ground, {}, makeMesh3(vertices, triangles).value()).ok());
  std::vector<BodyId3> bodies;
  for (int i = 0; i < 24; ++i) {
    const float fi = float(i);
    const BodyId3 b =
        world
            .createBody({.position = {1.2f * float(i % 3) - 1.2f, 0.6f + 0.9f * float(i / 6),
                                      1.1f * float((i / 3) % 2) + 0.1f * fi},
                         .rotation = Quat::fromAxisAngle({0, 1, 0}, 0.4f * fi)})
            .value();
    // Rolling resistance: a capsule rolls on otherwise, and that floor ends.
    if (i % 3 == 0) (void)world.createShape(b, {.rollingResistance = 0.1f}, Sphere{{}, 0.35f});
    if (i % 3 == 1) (void)world.createShape(b, {}, makeBox3({0.4f, 0.3f, 0.35f}).value());
    if (i % 3 == 2)
      (void)world.createShape(b, {.rollingResistance = 0.1f},
                              Capsule3{{-0.3f, 0, 0}, {0.3f, 0, 0}, 0.2f});
    bodies.push_back(b);
  }
  float lowest = 1e9f;
  for (int s = 0; s < 600; ++s) {
    ASSERT_TRUE(world.step().ok());
    for (BodyId3 b : bodies)
      lowest = std::min(lowest, world.position(b).y);
  }
  // The thinnest body lying flat has its centre 0.2 m up; 1 cm of soft overlap allowed.
  EXPECT_GT(lowest, 0.19f);
  EXPECT_EQ(world.awakeBodyCount(), 0u);
}

}  // namespace
}  // namespace quack
