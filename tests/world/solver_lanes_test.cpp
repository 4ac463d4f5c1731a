// The contact solver's lanes (docs/world.md, "The solver's data"). The build's SIMD path
// (SSE2, AVX2 or NEON) solves a colour's constraints several at a time; the scalar path one
// at a time. Both must give the same bits, step after step: that shows each lane does the
// scalar operations in the scalar order, and that no two constraints in a block touch the
// same dynamic body (a lost write-back would change the answer at once). In a build whose
// lanes are the scalar path (QUACK_SIMD=scalar, WebAssembly) the comparison is of a path
// with itself; the other builds in CI make it real. The golden hash
// ties every build to one answer: CI checks it with g++ and clang, debug and optimised,
// SSE2 and AVX2.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "quack/world/world.hpp"
#include "world_test_util.hpp"

namespace quack {
namespace {

using testing::addBox;
using testing::addPyramid;
using testing::addStaticBox;

// Everything the solver treats differently: boxes stacked (two-point manifolds), circles,
// capsules and rounded triangles (one point), restitution, friction from 0 to 1, a
// kinematic platform carrying bodies, a turning body, a heavy plank with more small boxes
// on it than there are colours (its constraints overflow), and bodies falling on top.
void buildLaneScene(World& world) {
  addStaticBox(world, {0, -0.5f}, {60, 0.5f});
  addStaticBox(world, {-30, 5}, {8, 0.3f}, -0.3f);  // a slope
  (void)addPyramid(world, 8);
  // The plank and its load: 40 small boxes side by side.
  BodyId plank = world.createBody({.position = {25, 0.5f}}).value();
  (void)world.createShape(plank, {.density = 50}, makeBox(14, 0.5f).value()).value();
  for (int i = 0; i < 40; ++i)
    addBox(world, {11.3f + 0.7f * static_cast<float>(i), 1.3f}, {0.3f, 0.3f});
  // A kinematic platform moving sideways with two boxes on it.
  BodyId platform =
      world.createBody({.type = BodyType::kinematicBody, .position = {-12, 3}}).value();
  (void)world.createShape(platform, {}, makeBox(3, 0.25f).value()).value();
  (void)world.setLinearVelocity(platform, {1.5f, 0});
  addBox(world, {-13, 3.75f}, {0.5f, 0.5f});
  addBox(world, {-11, 3.75f}, {0.5f, 0.5f});
  // A spinning box dropped on the pyramid.
  BodyId spinner = addBox(world, {0.3f, 12}, {0.6f, 0.2f}, 0.4f);
  (void)world.setAngularVelocity(spinner, 8);
  // A rain of mixed shapes over the slope and the plank.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0, 1);
  const Vec2 tri[] = {{-0.5f, -0.3f}, {0.5f, -0.3f}, {0, 0.5f}};
  const Polygon roundedTriangle = makePolygon(tri, 0.05f).value();
  for (int i = 0; i < 60; ++i) {
    const Vec2 p{-35 + 70 * u(rng), 6 + 10 * u(rng)};
    BodyId b = world.createBody({.position = p, .angle = 3 * u(rng)}).value();
    const ShapeDef def{.friction = u(rng), .restitution = i % 3 == 0 ? 0.5f : 0.0f};
    testing::addMixedShape(
        world, b, def, i, [&] { return u(rng); }, roundedTriangle);
  }
}

struct LaneRun {
  std::vector<std::uint64_t> hashes;  // after every step
  World::SolverStats largest;         // the step with the most overflow
  std::size_t mostConstraints = 0;    // over all steps
  std::size_t awake = 0, bodies = 0;  // at the end
};

LaneRun runScene(bool scalar, int steps, BroadPhaseKind kind = BroadPhaseKind::tree,
                 bool sleep = true) {
  World world =
      World::create({.broadPhase = kind, .scalarSolver = scalar, .enableSleep = sleep}).value();
  buildLaneScene(world);
  LaneRun r;
  for (int s = 0; s < steps; ++s) {
    EXPECT_TRUE(world.step().ok());
    r.hashes.push_back(world.stateHash());
    const World::SolverStats st = world.solverStats();
    if (st.overflow >= r.largest.overflow) r.largest = st;
    r.mostConstraints = std::max(r.mostConstraints, st.constraints);
  }
  EXPECT_TRUE(testing::valid(world));
  r.awake = world.awakeBodyCount();
  r.bodies = world.bodyCount();
  return r;
}

TEST(SolverLanes, SimdAndScalarGiveTheSameBitsEveryStep) {
  // Sleeping off, so that every body is solved every step.
  constexpr int kSteps = 360;
  const LaneRun simd = runScene(false, kSteps, BroadPhaseKind::tree, false);
  const LaneRun scalar = runScene(true, kSteps, BroadPhaseKind::tree, false);
  std::printf("lanes: %s; colours %d, constraints %zu, overflow %zu\n", World::simdPath(),
              simd.largest.colors, simd.largest.constraints, simd.largest.overflow);
  // The scene exercises what it is meant to: several colours, and an overflow set.
  EXPECT_GT(simd.largest.colors, 3);
  // (The most constraints of any step: the count at the step of most overflow depends on
  // how the rain lands, which the continuous phase between moving bodies changed.)
  EXPECT_GT(simd.mostConstraints, 200u);
  EXPECT_GT(simd.largest.overflow, 0u);
  EXPECT_EQ(simd.largest.overflow, scalar.largest.overflow);
  for (int s = 0; s < kSteps; ++s)
    ASSERT_EQ(simd.hashes[s], scalar.hashes[s]) << "the paths part at step " << s + 1;
  // And the world did move: the hashes change from step to step.
  EXPECT_NE(simd.hashes.front(), simd.hashes.back());
  // With sleeping on, sleeping bodies read the resting slot as static ones do. 900 steps:
  // by then 41 of the 143 bodies sleep. (When they start to sleep swings with any change to
  // the physics: a change to the time of impact took the sleepers at 360 steps from more
  // than 20 to 17; the world's smaller fat boxes took those at 600 steps from 33 to 19, and
  // from step 750 on more sleep than before: 37 and 41 at 900.)
  constexpr int kSleepSteps = 900;
  const LaneRun simdSleep = runScene(false, kSleepSteps);
  const LaneRun scalarSleep = runScene(true, kSleepSteps);
  for (int s = 0; s < kSleepSteps; ++s)
    ASSERT_EQ(simdSleep.hashes[s], scalarSleep.hashes[s]) << "sleeping on: step " << s + 1;
  EXPECT_LT(simdSleep.awake + 20, simdSleep.bodies);
}

// The solver prepares a contact from the narrow phase's compact record (ContactSim) when
// that step's narrow phase wrote it, else from the contact and body records (an island
// woken by a contact that began in the step, a restored snapshot). Both paths must give
// the same bits: the lane scene with sleeping on, every contact prepared each way.
TEST(SolverLanes, CompactContactRecordGivesTheSameBitsAsTheFullRecords) {
  constexpr int kSteps = 600;
  const LaneRun compact = runScene(false, kSteps);
  detail::setTestSolverReadsRecords(true);
  const LaneRun records = runScene(false, kSteps);
  detail::setTestSolverReadsRecords(false);
  for (int s = 0; s < kSteps; ++s)
    ASSERT_EQ(compact.hashes[s], records.hashes[s]) << "the paths part at step " << s + 1;
  EXPECT_NE(compact.hashes.front(), compact.hashes.back());
}

TEST(SolverLanes, SameBitsWhateverTheBroadPhase) {
  constexpr int kSteps = 120;
  const std::uint64_t expected = runScene(false, kSteps).hashes.back();
  for (BroadPhaseKind kind : kAllBroadPhaseKinds) {
    SCOPED_TRACE(std::string(toString(kind)));
    EXPECT_EQ(runScene(false, kSteps, kind).hashes.back(), expected);
    EXPECT_EQ(runScene(true, kSteps, kind).hashes.back(), expected);
  }
}

// The state hash after 900 steps of the lane scene, sleeping on (some of it falls asleep).
// Every build must give this value:
// g++ and clang, -O0 and -O3, asserts on or off, sanitizers, and every QUACK_SIMD path
// (the library is built with -ffp-contract=off; docs/world.md, "Determinism"). A change
// that alters the physics on purpose changes it too: QUACK_PRINT_GOLDEN=1 prints the new
// value, to be put here with the reason in the commit message.
constexpr std::uint64_t kGoldenHash = 0x207a06f31e29c9e9;

TEST(SolverLanes, GoldenHashOnEveryBuild) {
  const LaneRun r = runScene(false, 900);
  const std::uint64_t hash = r.hashes.back();
  // Part of the scene sleeps by then, part is awake: both are in the hash.
  EXPECT_GT(r.awake, 0u);
  EXPECT_LT(r.awake + 20, r.bodies);
  std::printf("after 900 steps: %zu of %zu bodies awake\n", r.awake, r.bodies);
  if (std::getenv("QUACK_PRINT_GOLDEN") != nullptr)
    std::printf("golden hash: 0x%016llx\n", static_cast<unsigned long long>(hash));
  EXPECT_EQ(hash, kGoldenHash) << "lanes: " << World::simdPath();
}

}  // namespace
}  // namespace quack
