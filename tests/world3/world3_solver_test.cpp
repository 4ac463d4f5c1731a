// World3's solver: colours, SIMD lanes and workers change nothing. A mixed pile (boxes,
// hulls, spheres and capsules with rolling resistance, bouncy shapes, a kinematic paddle)
// on a plate lying across a fine mesh floor (the plate touches more triangles than there
// are colours, so its manifolds overflow), with fast balls shot into it and at each other
// (continuous collision), is stepped with the build's lanes, with the
// one-lane path and on 2 and 3 workers; the snapshots, which hold every body's state and
// every contact's impulses bit for bit, must be equal byte for byte. The second method
// here is the one-lane, one-worker solve: it solves each manifold on its own, in order.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "quack/world/world3.hpp"

namespace quack {
namespace {

struct Pile {
  World3 world;
  std::vector<BodyId3> bodies;
  BodyId3 paddle;
};

Pile makePile(const WorldDef3& def) {
  Pile pile{World3::create(def).value(), {}, {}};
  World3& world = pile.world;
  // A 20 m square floor of 0.5 m cells, two triangles each.
  std::vector<Vec3> vertices;
  std::vector<std::array<std::int32_t, 3>> triangles;
  constexpr int kCells = 40;
  for (int i = 0; i <= kCells; ++i)
    for (int k = 0; k <= kCells; ++k)
      vertices.push_back({-10.0f + 0.5f * float(i), 0.0f, -10.0f + 0.5f * float(k)});
  for (int i = 0; i < kCells; ++i) {
    for (int k = 0; k < kCells; ++k) {
      const std::int32_t a = i * (kCells + 1) + k, b = a + 1, c = a + kCells + 1, d = c + 1;
      triangles.push_back({a, b, d});
      triangles.push_back({a, d, c});
    }
  }
  const BodyId3 ground = world.createBody({.type = BodyType::staticBody}).value();
  EXPECT_TRUE(world.createShape(ground, {}, makeMesh3(vertices, triangles).value()).ok());
  // The plate: 4 m square, on about 130 triangles.
  const BodyId3 plate = world.createBody({.position = {0, 0.1f, 0}}).value();
  EXPECT_TRUE(world.createShape(plate, {}, makeBox3({2, 0.1f, 2}).value()).ok());
  pile.bodies.push_back(plate);
  const std::array<Vec3, 7> hullPoints = {
      Vec3{0.3f, 0, 0},  Vec3{-0.25f, 0.1f, 0.05f}, Vec3{0, 0.3f, 0},      Vec3{0.05f, -0.3f, 0.1f},
      Vec3{0, 0, 0.35f}, Vec3{0.1f, 0.05f, -0.3f},  Vec3{0.2f, 0.2f, 0.2f}};
  const Hull3 hull = makeHull3(hullPoints).value();
  for (int i = 0; i < 48; ++i) {
    const float fi = float(i);
    const BodyId3 b =
        world
            .createBody({.position = {-1.5f + 1.0f * float(i % 4), 0.6f + 0.75f * float(i / 8),
                                      -1.2f + 0.8f * float((i / 4) % 2) + 0.05f * fi},
                         .rotation = Quat::fromAxisAngle(normalize(Vec3{1, 2, 0.5f}), 0.37f * fi),
                         .angularVelocity = {0, 0.5f * float(i % 3), 0}})
            .value();
    switch (i % 4) {
      case 0:
        EXPECT_TRUE(
            world
                .createShape(b, {.restitution = 0.4f, .rollingResistance = 0.05f}, Sphere{{}, 0.3f})
                .ok());
        break;
      case 1:
        EXPECT_TRUE(
            world.createShape(b, {.friction = 0.4f}, makeBox3({0.35f, 0.25f, 0.3f}).value()).ok());
        break;
      case 2:
        EXPECT_TRUE(world
                        .createShape(b, {.rollingResistance = 0.1f},
                                     Capsule3{{-0.25f, 0, 0}, {0.25f, 0, 0}, 0.2f})
                        .ok());
        break;
      default:
        EXPECT_TRUE(world.createShape(b, {.restitution = 0.2f}, hull).ok());
        break;
    }
    pile.bodies.push_back(b);
  }
  // Fast balls for the continuous phase: four shot down into the pile, and two pairs shot
  // at each other above it.
  for (int i = 0; i < 8; ++i) {
    const float fi = float(i);
    const bool down = i < 4;
    const Vec3 p = down ? Vec3{-1.2f + 0.8f * fi, 4.0f, 0.3f}
                        : Vec3{(i % 2 == 0 ? -3.0f : 3.0f), 2.5f + 0.5f * float(i / 6), 0.5f};
    const Vec3 v = down ? Vec3{0, -40, 0} : Vec3{(i % 2 == 0 ? 40.0f : -40.0f), 0, 0};
    const BodyId3 b = world.createBody({.position = p, .linearVelocity = v}).value();
    EXPECT_TRUE(world.createShape(b, {.density = 500}, Sphere{{}, 0.1f}).ok());
    pile.bodies.push_back(b);
  }
  // A kinematic paddle sweeping through the pile's edge.
  pile.paddle = world
                    .createBody({.type = BodyType::kinematicBody,
                                 .position = {3.0f, 0.6f, 0},
                                 .angularVelocity = {0, 0.8f, 0}})
                    .value();
  EXPECT_TRUE(world.createShape(pile.paddle, {}, makeBox3({2.5f, 0.3f, 0.1f}).value()).ok());
  return pile;
}

struct Outcome {
  std::vector<std::vector<std::uint8_t>> snapshots;  // after steps 40, 80, 120
  int mostColors = 0;
  std::size_t mostOverflow = 0, mostConstraints = 0;
  float lowest = 1e9f;
};

Outcome run(const WorldDef3& def) {
  Pile pile = makePile(def);
  Outcome out;
  for (int step = 1; step <= 120; ++step) {
    EXPECT_TRUE(pile.world.step().ok());
    const World3::SolverStats stats = pile.world.solverStats();
    out.mostColors = std::max(out.mostColors, stats.colors);
    out.mostOverflow = std::max(out.mostOverflow, stats.overflow);
    out.mostConstraints = std::max(out.mostConstraints, stats.constraints);
    // Over the floor (a fast ball can be knocked off its edge).
    for (BodyId3 b : pile.bodies) {
      const Vec3 p = pile.world.position(b);
      if (std::fabs(p.x) < 9.5f && std::fabs(p.z) < 9.5f) out.lowest = std::min(out.lowest, p.y);
    }
    if (step % 40 == 0) out.snapshots.push_back(pile.world.snapshot());
  }
  return out;
}

TEST(World3Solver, LanesAndWorkersGiveTheSameBits) {
  const Outcome reference = run({.enableSleep = false, .scalarSolver = true});
  // The scene exercises what the layout has to get right: several colours, an overflow set,
  // and well over a block of manifolds in each.
  EXPECT_GE(reference.mostColors, 4);
  EXPECT_GT(reference.mostOverflow, 0u);
  EXPECT_GT(reference.mostConstraints, 150u);
  // Nothing fell through the floor: no centre over it below 5 cm (the plate's is 0.1 m up, and
  // the lowest-lying body, a hull on a face near its centroid, rests at 0.076 m).
  EXPECT_GT(reference.lowest, 0.05f);
  ASSERT_EQ(reference.snapshots.size(), 3u);
  for (int workers : {1, 2, 3}) {
    for (bool scalar : {false, true}) {
      if (workers == 1 && scalar) continue;  // the reference
      const Outcome other =
          run({.enableSleep = false, .scalarSolver = scalar, .workerCount = workers});
      ASSERT_EQ(other.snapshots.size(), 3u);
      for (std::size_t k = 0; k < 3; ++k)
        EXPECT_TRUE(other.snapshots[k] == reference.snapshots[k])
            << "workers " << workers << (scalar ? ", one lane" : ", lanes")
            << ": differs after step " << 40 * (k + 1);
    }
  }
}

// A restored world keeps the workers it was made with; fromSnapshot runs on one.
TEST(World3Solver, RestoreKeepsTheWorldsWorkers) {
  Pile pile = makePile({.workerCount = 2});
  for (int i = 0; i < 10; ++i)
    ASSERT_TRUE(pile.world.step().ok());
  const std::vector<std::uint8_t> bytes = pile.world.snapshot();
  Pile other = makePile({.workerCount = 3});
  ASSERT_TRUE(other.world.restore(bytes).ok());
  EXPECT_EQ(other.world.def().workerCount, 3);
  World3 fresh = World3::fromSnapshot(bytes).value();
  EXPECT_EQ(fresh.def().workerCount, 1);
  for (int i = 0; i < 20; ++i) {
    ASSERT_TRUE(pile.world.step().ok());
    ASSERT_TRUE(other.world.step().ok());
    ASSERT_TRUE(fresh.step().ok());
  }
  EXPECT_TRUE(other.world.snapshot() == pile.world.snapshot());
  EXPECT_TRUE(fresh.snapshot() == pile.world.snapshot());
}

TEST(World3Solver, BadWorkerSettingsAreRefused) {
  auto message = [](const WorldDef3& def) {
    auto w = World3::create(def);
    return w ? std::string() : w.error().message;
  };
  EXPECT_NE(message({.workerCount = 0}).find("WorldDef3::workerCount"), std::string::npos);
  EXPECT_NE(message({.workerCount = 65}).find("WorldDef3::workerCount"), std::string::npos);
  EXPECT_NE(message({.finishTask = [](void*, void*) {}}).find("enqueueTask"), std::string::npos);
}

}  // namespace
}  // namespace quack
