// World3's continuous collision against static geometry, against the plain fact that a
// body must not pass through a floor or a wall: 100 m/s onto a one-sided mesh, onto a thin
// slab and into a thin wall; and a body sliding fast along a floor is not held back (the
// frictionless closed form x = v t); two fast bodies meet (head on, and one meeting two in
// one step in time order, against positions worked by hand). Each fall-through case is also
// run with continuous collision off, to show the scene needs it.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <variant>
#include <vector>

#include "../../src/world/continuous3.hpp"
#include "quack/world/world3.hpp"

namespace quack {
namespace {

void addMeshFloor(World3& world) {
  const std::array<Vec3, 4> vertices = {Vec3{-20, 0, -20}, Vec3{-20, 0, 20}, Vec3{20, 0, 20},
                                        Vec3{20, 0, -20}};
  const std::array<std::array<std::int32_t, 3>, 2> triangles = {{{0, 1, 2}, {0, 2, 3}}};
  const BodyId3 ground = world.createBody({.type = BodyType::staticBody}).value();
  ASSERT_TRUE(world.createShape(ground, {}, makeMesh3(vertices, triangles).value()).ok());
}

// The lowest height the body's centre reaches over `steps` steps.
float lowestOver(World3& world, BodyId3 body, int steps) {
  float lowest = world.position(body).y;
  for (int s = 0; s < steps; ++s) {
    EXPECT_TRUE(world.step().ok());
    lowest = std::min(lowest, world.position(body).y);
  }
  return lowest;
}

float dropBallOnMesh(bool continuous) {
  World3 world = World3::create({.enableContinuous = continuous}).value();
  addMeshFloor(world);
  const BodyId3 ball =
      world.createBody({.position = {0.3f, 1.35f, -0.2f}, .linearVelocity = {0, -100, 0}}).value();
  EXPECT_TRUE(world.createShape(ball, {}, Sphere{{}, 0.25f}).ok());
  return lowestOver(world, ball, 60);
}

TEST(World3Continuous, BallAtAHundredMetresASecondStopsOnAMeshFloor) {
  // 1.67 m a step from 1.1 m above the floor (beyond the speculative reach of 1 m) ends
  // below the one-sided floor: without continuous collision it falls through.
  EXPECT_LT(dropBallOnMesh(false), -1.0f);
  // Its centre never goes below the floor by more than the soft contact's give (1 cm).
  EXPECT_GT(dropBallOnMesh(true), 0.24f);
}

float dropBoxOnSlab(bool continuous) {
  World3 world = World3::create({.enableContinuous = continuous}).value();
  const BodyId3 slab = world.createBody({.type = BodyType::staticBody}).value();
  EXPECT_TRUE(
      world.createShape(slab, {}, makeBox3({10, 0.025f, 10}, {{0, -0.025f, 0}, {}}).value()).ok());
  const BodyId3 box = world
                          .createBody({.position = {0, 3.0f, 0},
                                       .rotation = Quat::fromAxisAngle({1, 0, 0}, 0.3f),
                                       .linearVelocity = {0, -100, 0}})
                          .value();
  EXPECT_TRUE(world.createShape(box, {}, makeBox3({0.2f, 0.2f, 0.2f}).value()).ok());
  return lowestOver(world, box, 60);
}

TEST(World3Continuous, BoxAtAHundredMetresASecondStopsOnAThinSlab) {
  EXPECT_LT(dropBoxOnSlab(false), -0.1f);
  // The slab is 5 cm thick; the box's centre stays above its top face less 1 cm.
  EXPECT_GT(dropBoxOnSlab(true), 0.19f);
}

TEST(World3Continuous, BallFiredAtAThinWallStaysOnItsSide) {
  for (bool continuous : {false, true}) {
    World3 world = World3::create({.gravity = {0, 0, 0}, .enableContinuous = continuous}).value();
    const BodyId3 wall = world.createBody({.type = BodyType::staticBody}).value();
    ASSERT_TRUE(
        world.createShape(wall, {}, makeBox3({0.02f, 5, 5}, {{10, 0, 0}, {}}).value()).ok());
    const BodyId3 ball =
        world.createBody({.position = {0, 0.1f, 0}, .linearVelocity = {100, 0, 0}}).value();
    ASSERT_TRUE(world.createShape(ball, {}, Sphere{{}, 0.1f}).ok());
    float furthest = 0.0f;
    for (int s = 0; s < 30; ++s) {
      ASSERT_TRUE(world.step().ok());
      furthest = std::max(furthest, world.position(ball).x);
    }
    if (continuous) {
      EXPECT_LT(furthest, 10.0f - 0.02f - 0.1f + 0.01f);  // the wall's near face, less r
    } else {
      EXPECT_GT(furthest, 10.5f);  // passed through
    }
  }
}

// A box sliding at 30 m/s on a frictionless floor is fast (half a metre a step, its
// thinnest half-extent 0.25 m), touches the floor at the start of every sweep, and must not
// be held there: x = v t after 1 s within 1%.
TEST(World3Continuous, FastSlidingBoxIsNotHeldByTheFloorItTouches) {
  World3 world = World3::create({.enableSleep = false}).value();
  const BodyId3 ground = world.createBody({.type = BodyType::staticBody}).value();
  ASSERT_TRUE(world
                  .createShape(ground, {.friction = 0.0f},
                               makeBox3({100, 0.5f, 5}, {{0, -0.5f, 0}, {}}).value())
                  .ok());
  const BodyId3 box =
      world.createBody({.position = {-40, 0.25f, 0}, .linearVelocity = {30, 0, 0}}).value();
  ASSERT_TRUE(
      world.createShape(box, {.friction = 0.0f}, makeBox3({0.25f, 0.25f, 0.25f}).value()).ok());
  for (int s = 0; s < 60; ++s)
    ASSERT_TRUE(world.step().ok());
  EXPECT_NEAR(world.position(box).x, -40.0f + 30.0f, 0.3f);
  EXPECT_NEAR(world.position(box).y, 0.25f, 0.01f);
}

// A 0.1 m ball at 100 m/s fired at a 4 cm dynamic slab floating in zero gravity: swept
// against the slab (held where the solver left it), it stops at its face and the two then
// share the ball's momentum (m v before = the sum after, within 1%); without continuous
// collision it passes through and the slab never moves.
TEST(World3Continuous, BallFiredAtAThinDynamicSlabHitsIt) {
  for (bool continuous : {false, true}) {
    World3 world = World3::create({.gravity = {0, 0, 0}, .enableContinuous = continuous}).value();
    const BodyId3 slab = world.createBody({.position = {10, 0, 0}}).value();
    ASSERT_TRUE(world.createShape(slab, {.density = 100}, makeBox3({0.02f, 2, 2}).value()).ok());
    const BodyId3 ball =
        world.createBody({.position = {0, 0.1f, 0}, .linearVelocity = {100, 0, 0}}).value();
    ASSERT_TRUE(world.createShape(ball, {}, Sphere{{}, 0.1f}).ok());
    float furthest = -1e9f;  // the ball's lead over the slab's centre
    for (int s = 0; s < 12; ++s) {
      ASSERT_TRUE(world.step().ok());
      furthest = std::max(furthest, world.position(ball).x - world.position(slab).x);
    }
    const float momentum = world.mass(ball) * world.linearVelocity(ball).x +
                           world.mass(slab) * world.linearVelocity(slab).x;
    EXPECT_NEAR(momentum, world.mass(ball) * 100.0f, 0.01f * world.mass(ball) * 100.0f);
    if (continuous) {
      EXPECT_LT(furthest, -0.02f - 0.1f + 0.01f);     // never past the slab's near face
      EXPECT_GT(world.linearVelocity(slab).x, 0.0f);  // struck
    } else {
      EXPECT_GT(furthest, 0.5f);  // passed through
      EXPECT_EQ(world.linearVelocity(slab).x, 0.0f);
    }
  }
}

// Two bodies flying at each other in zero gravity along x, centres on one line: A from
// x = -1.5 at vA, B from x = 1.5 at vB (3.33 m a step closing at 100 m/s each; the gap is
// 2.95 m, past the speculative reach, so without continuous collision they never meet).
struct HeadOn {
  World3 world;
  BodyId3 a, b;
};

HeadOn fireHeadOn(bool continuous, const ShapeGeometry3& shape, float vA, float vB,
                  Filter filterB = {}) {
  HeadOn h{World3::create({.gravity = {0, 0, 0}, .enableContinuous = continuous}).value(), {}, {}};
  h.a = h.world.createBody({.position = {-1.5f, 0, 0}, .linearVelocity = {vA, 0, 0}}).value();
  EXPECT_TRUE(h.world.createShape(h.a, {}, shape).ok());
  h.b = h.world.createBody({.position = {1.5f, 0, 0}, .linearVelocity = {vB, 0, 0}}).value();
  EXPECT_TRUE(h.world.createShape(h.b, {.filter = filterB}, shape).ok());
  return h;
}

// Whether A stayed on its side of B (left) at every one of 30 steps.
bool staysApart(HeadOn& h) {
  bool apart = true;
  for (int s = 0; s < 30; ++s) {
    EXPECT_TRUE(h.world.step().ok());
    apart = apart && h.world.position(h.a).x < h.world.position(h.b).x;
  }
  return apart;
}

const ShapeGeometry3 kSlab = makeBox3({0.025f, 1, 1}).value();  // 5 cm thick
const ShapeGeometry3 kBall = Sphere{{}, 0.05f};                 // 10 cm across

// The first step puts both back to where their faces are the time of impact's target gap
// (kLinearSlop, within its quarter-slop tolerance) apart, at t = (gap - s) / 3.33 of the
// step, velocities kept; after that A never gets past B, and the momentum (0) is kept
// within 1% of one body's. The slabs part again at 12.5 m/s each (the solver's answer to
// a 200 m/s meeting of two faces, as when a slab at 200 m/s strikes a resting one: not this
// phase's), so the velocities are not held to the inelastic closed form here; the balls'
// single point is, below.
void expectHeadOnMeeting(const ShapeGeometry3& shape, float thickness) {
  HeadOn off = fireHeadOn(false, shape, 100, -100);
  EXPECT_FALSE(staysApart(off));  // passed through each other
  HeadOn on = fireHeadOn(true, shape, 100, -100);
  ASSERT_TRUE(on.world.step().ok());
  const float gap = 3.0f - thickness;
  const float t = (gap - kLinearSlop) / (200.0f / 60.0f);
  EXPECT_NEAR(on.world.position(on.a).x, -1.5f + 100.0f / 60.0f * t, 1e-3f);
  EXPECT_NEAR(on.world.position(on.b).x, 1.5f - 100.0f / 60.0f * t, 1e-3f);
  EXPECT_EQ(on.world.linearVelocity(on.a).x, 100.0f);
  EXPECT_EQ(on.world.linearVelocity(on.b).x, -100.0f);
  EXPECT_TRUE(staysApart(on));
  const float m = on.world.mass(on.a);
  EXPECT_NEAR(
      m * on.world.linearVelocity(on.a).x + on.world.mass(on.b) * on.world.linearVelocity(on.b).x,
      0.0f, 0.01f * m * 100.0f);
}

TEST(World3Continuous, TwoFastSlabsHeadOnCollide) {
  expectHeadOnMeeting(kSlab, 0.05f);
}

TEST(World3Continuous, TwoFastBallsHeadOnCollide) {
  expectHeadOnMeeting(kBall, 0.1f);
}

// The same meeting, but B's mask leaves out A's category: the filter holds in the sweep too.
TEST(World3Continuous, TwoFastBodiesWhoseFiltersExcludeEachOtherPass) {
  HeadOn h = fireHeadOn(true, kBall, 100, -100, Filter{.category = 2, .mask = ~std::uint64_t{1}});
  EXPECT_FALSE(staysApart(h));
}

// A at 100 m/s meets B at 50 m/s coming the other way; equal masses: the momentum
// m (vA + vB) = 50 m is kept within 1%, and the balls (restitution 0, one contact point)
// end at the inelastic closed form (100 - 50) / 2 = 25 m/s each, within 1%.
TEST(World3Continuous, TwoFastBodiesMeetingKeepTheirMomentum) {
  for (const ShapeGeometry3& shape : {kSlab, kBall}) {
    HeadOn h = fireHeadOn(true, shape, 100, -50);
    ASSERT_EQ(h.world.mass(h.a), h.world.mass(h.b));
    EXPECT_TRUE(staysApart(h));
    const float vA = h.world.linearVelocity(h.a).x, vB = h.world.linearVelocity(h.b).x;
    EXPECT_NEAR(vA + vB, 50.0f, 0.5f);
    if (std::holds_alternative<Sphere>(shape)) {
      EXPECT_NEAR(vA, 25.0f, 0.25f);
      EXPECT_NEAR(vB, 25.0f, 0.25f);
    }
  }
}

// Two runs of the same scene give the same bits.
TEST(World3Continuous, FastPairsAreDeterministic) {
  auto run = [] {
    HeadOn h = fireHeadOn(true, kSlab, 100, -50);
    std::vector<float> xs;
    for (int s = 0; s < 20; ++s) {
      EXPECT_TRUE(h.world.step().ok());
      xs.push_back(h.world.position(h.a).x);
      xs.push_back(h.world.position(h.b).x);
    }
    return xs;
  };
  EXPECT_EQ(run(), run());
}

// One step, balls of radius r = 0.05 on the x axis, zero gravity, 1/60 s: A from 0 at
// +100 m/s, B from 1.0 and C from 1.5 both at -100 m/s (1.667 m a step each). Worked by
// hand, in step fractions, with the time of impact's target gap s = kLinearSlop:
// A meets B first, at t1 = (1.0 - 2r - s) / 3.333 = 0.2685: A at 0.4475, B at 0.5525. A
// would meet C at 0.4185 (A at 0.6975): later, and not at all once A is put back. C then
// meets B where B was put back: its centre reaches 0.5525 + 2r + s = 0.6575 (at t = 0.5055).
// Bodies put back keep their velocities. Any creation order gives the same positions.
TEST(World3Continuous, AFastBodyMeetsTheEarlierOfTwoFastBodiesFirst) {
  const float s = kLinearSlop;
  const float t1 = (1.0f - 0.1f - s) / (200.0f / 60.0f);
  const float xA = 100.0f / 60.0f * t1, xB = 1.0f - xA, xC = xB + 0.1f + s;
  std::array<int, 3> order = {0, 1, 2};  // A, B, C
  do {
    World3 world = World3::create({.gravity = {0, 0, 0}}).value();
    const std::array<Vec3, 3> start = {Vec3{0, 0, 0}, Vec3{1.0f, 0, 0}, Vec3{1.5f, 0, 0}};
    const std::array<float, 3> speed = {100, -100, -100};
    std::array<BodyId3, 3> body;
    for (int i : order) {
      body[i] =
          world.createBody({.position = start[i], .linearVelocity = {speed[i], 0, 0}}).value();
      ASSERT_TRUE(world.createShape(body[i], {}, kBall).ok());
    }
    ASSERT_TRUE(world.step().ok());
    SCOPED_TRACE(testing::Message() << "order " << order[0] << order[1] << order[2]);
    // The time of impact stops within its tolerance (a quarter slop) past the target gap.
    EXPECT_NEAR(world.position(body[0]).x, xA, 1e-3f);
    EXPECT_NEAR(world.position(body[1]).x, xB, 1e-3f);
    EXPECT_NEAR(world.position(body[2]).x, xC, 2e-3f);
    for (int i = 0; i < 3; ++i)
      EXPECT_EQ(world.linearVelocity(body[i]).x, speed[i]);
    // Then the three stay in order, and their momentum m (100 - 200) is kept within 1%.
    for (int step = 0; step < 40; ++step) {
      ASSERT_TRUE(world.step().ok());
      EXPECT_LT(world.position(body[0]).x, world.position(body[1]).x);
      EXPECT_LT(world.position(body[1]).x, world.position(body[2]).x);
    }
    float sum = 0.0f;
    for (int i = 0; i < 3; ++i)
      sum += world.linearVelocity(body[i]).x;
    EXPECT_NEAR(sum, -100.0f, 1.0f);
  } while (std::next_permutation(order.begin(), order.end()));
}

// The phase's cap, on its own store: three 0.3 m balls 0.7 m apart on x that each moved
// 1 m (fast) toward +x in a step, all their swept boxes meeting, make three pairs; with the
// cap at one pair it checks one and says so. None meets another (they moved together).
TEST(World3Continuous, FastPairsPastTheCapAreCountedAndSaid) {
  for (int cap : {1, detail::kMaxFastPairs3}) {
    detail::BodyStore3 store(BroadPhase3::create({.margin = 0.1f}).value());
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t b = store.addBody({.position = {0.7f * float(i), 0, 0}});
      ASSERT_TRUE(store
                      .addShape(b, {},
                                {std::make_shared<const ShapeGeometry3>(Sphere{{}, 0.3f}), nullptr},
                                nullptr)
                      .ok());
    }
    detail::Continuous3 continuous;
    continuous.recordStarts(store);
    for (std::uint32_t b = 0; b < 3; ++b) {
      detail::Body3& body = store.bodies[b];
      body.origin = body.origin + Vec3{1, 0, 0};
      body.center = body.center + Vec3{1, 0, 0};
      store.moveProxies(b, {1, 0, 0});
    }
    detail::TaskRunner tasks;
    const detail::Continuous3Result r = continuous.solve(store, tasks, cap);
    EXPECT_EQ(r.fastBodies, 3);
    EXPECT_EQ(r.putBack, 0);
    if (cap == 1) {
      EXPECT_EQ(r.fastPairs, 1);
      EXPECT_EQ(r.status, detail::Continuous3Status::pairsCapped);
    } else {
      EXPECT_EQ(r.fastPairs, 3);
      EXPECT_EQ(r.status, detail::Continuous3Status::complete);
    }
  }
}

}  // namespace
}  // namespace quack
