// Snapshots of every sample scene (docs/determinism.md, "Snapshots"): after 40 steps, a
// full and a dynamic snapshot; 40 more steps recorded; then a new world from the full
// snapshot, and the world itself restored from the dynamic one after it moved on, each give
// the same state hash and events at every one of the 40 steps.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "quack/io/scene.hpp"

namespace quack {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = QUACK_SOURCE_DIR;

struct Step {
  std::uint64_t hash;
  std::size_t begin, end, hit, sensor, toi;
  friend bool operator==(const Step&, const Step&) = default;
};

std::vector<Step> run(World& world, int steps) {
  std::vector<Step> out;
  for (int i = 0; i < steps; ++i) {
    EXPECT_TRUE(world.step().ok());
    const StepEvents& e = world.events();
    out.push_back({world.stateHash(), e.begin.size(), e.end.size(), e.hit.size(),
                   e.sensorBegin.size(), e.toi.size()});
  }
  return out;
}

class SnapshotScenes : public ::testing::TestWithParam<std::string> {};

TEST_P(SnapshotScenes, ContinueBitIdentically) {
  Result<Scene> scene = loadScene((kSource / "scenes" / (GetParam() + ".json")).string());
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  Result<SceneWorld> built = buildWorld(scene.value());
  ASSERT_TRUE(built.ok()) << built.error().message;
  World& world = built.value().world;
  run(world, 40);
  const std::vector<std::uint8_t> full = world.snapshot().value();
  const std::vector<std::uint8_t> dynamic = world.snapshot(SnapshotKind::dynamic).value();
  const std::vector<Step> reference = run(world, 40);
  ASSERT_FALSE(reference.empty());

  Result<World> copy = World::fromSnapshot(full);
  ASSERT_TRUE(copy.ok()) << copy.error().message;
  EXPECT_EQ(run(copy.value(), 40), reference);

  run(world, 7);
  Status restored = world.restore(dynamic);
  ASSERT_TRUE(restored.ok()) << restored.message();
  EXPECT_TRUE(world.validate().ok());
  EXPECT_EQ(run(world, 40), reference);
}

INSTANTIATE_TEST_SUITE_P(Scenes, SnapshotScenes,
                         ::testing::Values("broadphase-brute", "broadphase-hash",
                                           "broadphase-quadtree", "broadphase-sap",
                                           "broadphase-tree", "bullets", "concave", "players",
                                           "pyramid", "rain", "sensor", "tiles"),
                         [](const auto& param) {
                           std::string name = param.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace quack
