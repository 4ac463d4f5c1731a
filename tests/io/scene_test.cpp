// Scene files: every sample scene runs; every kind of bad file gets its message; the
// generators make what they say.

#include "quack/io/scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace quack {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = QUACK_SOURCE_DIR;

TEST(Scene, EverySampleSceneRuns) {
  int scenes = 0;
  for (const auto& entry : fs::directory_iterator(kSource / "scenes")) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    ++scenes;
    Result<Scene> scene = loadScene(entry.path().string());
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    Result<SceneWorld> built = buildWorld(scene.value());
    ASSERT_TRUE(built.ok()) << built.error().message;
    SceneWorld& sw = built.value();
    EXPECT_EQ(sw.bodies.size(), scene->bodies.size());
    for (int s = 0; s < 60; ++s)
      ASSERT_TRUE(sw.world.step().ok());
    for (BodyId b : sw.bodies) {
      if (!sw.world.isValid(b)) continue;
      EXPECT_TRUE(isFinite(sw.world.position(b)));
      EXPECT_TRUE(isFinite(sw.world.linearVelocity(b)));
    }
  }
  EXPECT_GE(scenes, 10);
}

TEST(Scene, EveryBroadPhaseHasASampleScene) {
  for (BroadPhaseKind kind : kAllBroadPhaseKinds) {
    fs::path file = kSource / "scenes" / ("broadphase-" + std::string(nameOf(kind)) + ".json");
    Result<Scene> scene = loadScene(file.string());
    ASSERT_TRUE(scene.ok()) << file;
    EXPECT_EQ(scene->world.broadPhase, kind);
  }
}

TEST(Scene, BadFilesGetMessagesNamingFileAndPath) {
  std::ifstream cases(kSource / "tests/io/bad_scenes/cases.txt");
  ASSERT_TRUE(cases);
  std::string line;
  int checked = 0;
  while (std::getline(cases, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::size_t bar = line.find('|');
    ASSERT_NE(bar, std::string::npos) << line;
    std::string file = line.substr(0, bar), expected = line.substr(bar + 1);
    SCOPED_TRACE(file);
    std::ifstream in(kSource / "tests/io/bad_scenes" / file);
    ASSERT_TRUE(in) << "missing case file";
    std::stringstream text;
    text << in.rdbuf();
    Result<Scene> scene = parseScene(text.str(), file);
    ASSERT_FALSE(scene.ok()) << "accepted a bad scene";
    EXPECT_NE(scene.error().message.find(expected), std::string::npos)
        << "got: " << scene.error().message << "\nwanted: " << expected;
    ++checked;
  }
  EXPECT_GE(checked, 15);
  Result<Scene> missing = loadScene("/no/such/scene.json");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, "/no/such/scene.json: cannot open the file");
}

TEST(Scene, DefaultsAndExplicitValues) {
  Result<Scene> s = parseScene(R"({
    "categories": ["terrain", "player"],
    "bodies": [{"shapes": [{"type": "circle", "radius": 0.5}]},
               {"name": "p", "type": "kinematic", "pos": [1, 2], "angle": 0.5, "vel": [3, 4], "angvel": 1,
                "bullet": true,
                "shapes": [{"type": "box", "half": [1, 1], "density": 2, "friction": 0.1, "restitution": 0.7,
                            "sensor": true, "filter": {"category": "player", "mask": ["terrain"], "group": -3}}]}]})",
                               "inline");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Scene& scene = s.value();
  EXPECT_EQ(scene.world.gravity, (Vec2{0, -10}));
  EXPECT_EQ(scene.world.substeps, 4);
  EXPECT_EQ(scene.world.broadPhase, BroadPhaseKind::kTree);
  ASSERT_EQ(scene.bodies.size(), 2u);
  const SceneBody& a = scene.bodies[0];
  EXPECT_EQ(a.name, "body0");
  EXPECT_EQ(a.def.type, BodyType::dynamicBody);
  EXPECT_EQ(a.shapes[0].def.density, 1.0f);
  EXPECT_EQ(a.shapes[0].def.friction, 0.6f);
  EXPECT_EQ(a.shapes[0].def.filter.category,
            ~std::uint64_t{0});  // no filter: collides with everything
  const SceneBody& b = scene.bodies[1];
  EXPECT_EQ(b.name, "p");
  EXPECT_EQ(b.def.type, BodyType::kinematicBody);
  EXPECT_EQ(b.def.position, (Vec2{1, 2}));
  EXPECT_EQ(b.def.linearVelocity, (Vec2{3, 4}));
  EXPECT_TRUE(b.def.bullet);
  const ShapeDef& d = b.shapes[0].def;
  EXPECT_EQ(d.density, 2.0f);
  EXPECT_EQ(d.restitution, 0.7f);
  EXPECT_TRUE(d.sensor);
  EXPECT_EQ(d.filter.category, 2u);
  EXPECT_EQ(d.filter.mask, 1u);
  EXPECT_EQ(d.filter.group, -3);
}

TEST(Scene, Generators) {
  Result<Scene> s = parseScene(R"({"generate": [
      {"kind": "pyramid", "rows": 4, "half": 0.25, "pos": [1, 0.25]},
      {"kind": "tiles", "count": 5, "half": [0.5, 0.1], "pos": [0, -0.1]},
      {"kind": "rain", "count": 30, "seed": 4},
      {"kind": "field", "count": 7, "shapes": ["circle"], "min": 0.3, "max": 0.3}]})",
                               "gen");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const auto& bodies = s->bodies;
  ASSERT_EQ(bodies.size(), 10u + 5u + 30u + 7u);
  // Pyramid: 4 + 3 + 2 + 1 boxes; the bottom row centred on x = 1, resting on y = 0.
  EXPECT_EQ(bodies[0].name, "pyramid0_0");
  EXPECT_FLOAT_EQ(bodies[0].def.position.x, 1.0f - 0.75f);
  EXPECT_FLOAT_EQ(bodies[0].def.position.y, 0.25f);
  EXPECT_FLOAT_EQ(bodies[9].def.position.y, 0.25f + 3 * 0.5f);
  // Tiles: separate static bodies laid flush, edge on edge.
  for (int i = 10; i < 14; ++i) {
    EXPECT_EQ(bodies[static_cast<std::size_t>(i)].def.type, BodyType::staticBody);
    EXPECT_FLOAT_EQ(bodies[static_cast<std::size_t>(i + 1)].def.position.x -
                        bodies[static_cast<std::size_t>(i)].def.position.x,
                    1.0f);
  }
  // Rain is dynamic and repeatable by seed; the field is static by default.
  EXPECT_EQ(bodies[15].def.type, BodyType::dynamicBody);
  EXPECT_EQ(bodies[45].def.type, BodyType::staticBody);
  Result<Scene> again =
      parseScene(R"({"generate": [{"kind": "rain", "count": 30, "seed": 4}]})", "gen");
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->bodies[3].def.position, bodies[18].def.position);
  EXPECT_EQ(std::get<Circle>(bodies[47].shapes[0].geometry).radius, 0.3f);
}

}  // namespace
}  // namespace quack

namespace quack {
namespace {

TEST(Scene, BoxSlidesOverTheTilesGeneratorsFloor) {
  // The `tiles` generator's 100 separate static bodies: a frictionless box keeps its speed
  // and never hops (ghost-collision removal, docs/concave.md); and a chain holds a ball.
  Result<Scene> s = parseScene(R"({
      "bodies": [
        {"name": "box", "pos": [-49, 0.5], "vel": [8, 0],
         "shapes": [{"type": "box", "half": [0.5, 0.5], "friction": 0}]},
        {"name": "rail", "type": "static", "pos": [0, 4],
         "shapes": [{"type": "chain", "points": [[50, 0], [0, 0], [-50, 0]]}]},
        {"name": "ball", "pos": [-45, 4.5], "shapes": [{"type": "circle", "radius": 0.5}]}],
      "generate": [{"kind": "tiles", "count": 100, "friction": 0}]})",
                               "tiles");
  ASSERT_TRUE(s.ok()) << s.error().message;
  ASSERT_EQ(s->bodies[1].chains.size(), 1u);
  Result<SceneWorld> w = buildWorld(*s);
  ASSERT_TRUE(w.ok()) << w.error().message;
  World& world = w->world;
  BodyId box = w->bodies[0];
  float minV = 8, maxV = 8, maxVy = 0;
  for (int step = 0; step < 900 && world.position(box).x < 48.0f; ++step) {
    ASSERT_TRUE(world.step().ok());
    minV = std::min(minV, world.linearVelocity(box).x);
    maxV = std::max(maxV, world.linearVelocity(box).x);
    maxVy = std::max(maxVy, std::fabs(world.linearVelocity(box).y));
  }
  EXPECT_GT(world.position(box).x, 47.0f);
  EXPECT_GT(minV, 0.98f * 8);
  EXPECT_LT(maxV, 1.02f * 8);
  EXPECT_LT(maxVy, 0.05f);
  EXPECT_NEAR(world.position(w->bodies[2]).y, 4.5f, 0.01f);
}

}  // namespace
}  // namespace quack
