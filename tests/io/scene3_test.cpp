// 3D scene files: every key reaches the world, every bad field is refused by name, a 2D
// scene stays 2D, and the sample scenes do what docs/scenes.md says they do.

#include "quack/io/scene3.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "quack/geometry/mass3.hpp"
#include "quack/math/trig.hpp"

namespace quack {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = QUACK_SOURCE_DIR;

Scene3 parseOk(const std::string& text) {
  Result<Scene3> scene = parseScene3(text, "s.json");
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  return scene.ok() ? std::move(scene).value() : Scene3{};
}

// Every key given a value other than its default reaches the scene and then the world.
TEST(Scene3, EveryKeyReachesTheWorld) {
  const Scene3 scene = parseOk(R"({
    "world": {"dim": 3, "gravity": [1, -9, 0.5], "dt": 0.01, "substeps": 6, "sleep": false,
              "contactHertz": 40, "contactDampingRatio": 5, "contactPushMaxSpeed": 2,
              "restitutionThreshold": 0.5, "speculativeDistance": 0.03, "aabbMargin": 0.2,
              "contactRecycleDistance": 0.02, "continuous": false},
    "categories": ["ground", "prop"],
    "bodies": [
      {"name": "floor", "type": "static", "pos": [0, -1, 0],
       "shapes": [{"type": "mesh", "vertices": [[-5, 0, -5], [5, 0, -5], [5, 0, 5], [-5, 0, 5]],
                   "triangles": [[0, 3, 2], [0, 2, 1]], "friction": 0.3,
                   "filter": {"category": "ground", "mask": "prop"}}]},
      {"name": "crate", "type": "kinematic", "pos": [1, 2, 3], "quat": [0, 0, 2, 0],
       "vel": [1, 0, 0], "angvel": [0, 0.5, 0], "linearDamping": 0.1, "angularDamping": 0.2,
       "gravityScale": 2, "sleepThreshold": 0.1, "sleep": false,
       "shapes": [{"type": "box", "half": [0.5, 0.25, 1], "density": 300, "friction": 0.4,
                   "restitution": 0.3, "rollingResistance": 0.02,
                   "filter": {"category": "prop", "group": -2}},
                  {"type": "sphere", "center": [0, 1, 0], "radius": 0.5}]},
      {"shapes": [{"type": "capsule", "p1": [0, 0, -1], "p2": [0, 0, 1], "radius": 0.2},
                  {"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], "radius": 0.1},
                  {"type": "triangle", "points": [[0, 0, 0], [1, 0, 0], [0, 0, -1]]}]}]})");
  ASSERT_EQ(scene.bodies.size(), 3u);
  const WorldDef3& w = scene.world;
  EXPECT_EQ(w.gravity, (Vec3{1, -9, 0.5f}));
  EXPECT_EQ(w.timeStep, 0.01f);
  EXPECT_EQ(w.substeps, 6);
  EXPECT_FALSE(w.enableSleep);
  EXPECT_EQ(w.contactHertz, 40.0f);
  EXPECT_EQ(w.contactDampingRatio, 5.0f);
  EXPECT_EQ(w.contactPushMaxSpeed, 2.0f);
  EXPECT_EQ(w.restitutionThreshold, 0.5f);
  EXPECT_EQ(w.speculativeDistance, 0.03f);
  EXPECT_EQ(w.aabbMargin, 0.2f);
  EXPECT_EQ(w.contactRecycleDistance, 0.02f);
  EXPECT_FALSE(w.enableContinuous);
  EXPECT_EQ(scene.categories, (std::vector<std::string>{"ground", "prop"}));

  const SceneBody3& floor = scene.bodies[0];
  EXPECT_EQ(floor.def.type, BodyType::staticBody);
  ASSERT_EQ(floor.shapes.size(), 1u);
  ASSERT_TRUE(std::holds_alternative<Mesh3>(floor.shapes[0].geometry));
  EXPECT_EQ(std::get<Mesh3>(floor.shapes[0].geometry).triangleCount(), 2);
  EXPECT_EQ(floor.shapes[0].def.friction, 0.3f);
  EXPECT_EQ(floor.shapes[0].def.filter.category, 1u);
  EXPECT_EQ(floor.shapes[0].def.filter.mask, 2u);

  const SceneBody3& crate = scene.bodies[1];
  EXPECT_EQ(crate.name, "crate");
  EXPECT_EQ(crate.path, "bodies[1]");
  const BodyDef3& d = crate.def;
  EXPECT_EQ(d.type, BodyType::kinematicBody);
  EXPECT_EQ(d.position, (Vec3{1, 2, 3}));
  EXPECT_EQ(d.rotation, (Quat{0, 0, 1, 0}));  // normalised
  EXPECT_EQ(d.linearVelocity, (Vec3{1, 0, 0}));
  EXPECT_EQ(d.angularVelocity, (Vec3{0, 0.5f, 0}));
  EXPECT_EQ(d.linearDamping, 0.1f);
  EXPECT_EQ(d.angularDamping, 0.2f);
  EXPECT_EQ(d.gravityScale, 2.0f);
  EXPECT_EQ(d.sleepThreshold, 0.1f);
  EXPECT_FALSE(d.enableSleep);
  const ShapeDef3& m = crate.shapes[0].def;
  EXPECT_EQ(m.density, 300.0f);
  EXPECT_EQ(m.friction, 0.4f);
  EXPECT_EQ(m.restitution, 0.3f);
  EXPECT_EQ(m.rollingResistance, 0.02f);
  EXPECT_EQ(m.filter.category, 2u);
  EXPECT_EQ(m.filter.mask, ~std::uint64_t{0});
  EXPECT_EQ(m.filter.group, -2);
  // Defaults: a shape without keys is ShapeDef3's, with a filter that takes everything.
  const ShapeDef3& plain = crate.shapes[1].def;
  EXPECT_EQ(plain.density, ShapeDef3{}.density);
  EXPECT_EQ(plain.filter.category, ~std::uint64_t{0});
  EXPECT_EQ(scene.bodies[2].name, "body2");
  EXPECT_EQ(scene.bodies[2].def.type, BodyType::dynamicBody);
  EXPECT_EQ(scene.bodies[2].shapes[2].path, "bodies[2].shapes[2]");

  Result<SceneWorld3> built = buildWorld3(scene);
  ASSERT_TRUE(built.ok()) << built.error().message;
  const SceneWorld3& sw = built.value();
  EXPECT_EQ(sw.names, (std::vector<std::string>{"floor", "crate", "body2"}));
  EXPECT_EQ(sw.world.def().substeps, 6);
  EXPECT_EQ(sw.world.shapeCount(), 6u);
  ASSERT_EQ(sw.shapes.size(), 3u);
  EXPECT_EQ(sw.shapes[1].size(), 2u);
  const BodyId3 c = sw.bodies[1];
  EXPECT_EQ(sw.world.bodyType(c), BodyType::kinematicBody);
  EXPECT_EQ(sw.world.position(c), (Vec3{1, 2, 3}));
  EXPECT_EQ(sw.world.rotation(c), (Quat{0, 0, 1, 0}));
  EXPECT_EQ(sw.world.linearVelocity(c), (Vec3{1, 0, 0}));
  // A dynamic body's mass is the sum of its shapes' (density 1 by default): the closed
  // forms of computeMass, independently of the parser.
  const Capsule3 capsule{{0, 0, -1}, {0, 0, 1}, 0.2f};
  const float capsuleMass = computeMass(capsule, 1.0f).mass;
  EXPECT_NEAR(capsuleMass, kPi * 0.04f * (2.0f + 4.0f / 3.0f * 0.2f), 1e-5f);
  EXPECT_GT(sw.world.mass(sw.bodies[2]), capsuleMass);
}

// The 2D format is untouched: no "dim" or "dim": 2 parse as before; parseAnyScene picks
// the dimension; each parser refuses the other dimension by name.
TEST(Scene3, DimensionChoosesTheParser) {
  const std::string body2 = R"("bodies": [{"shapes": [{"type": "circle", "radius": 1}]}])";
  Result<Scene> none = parseScene("{" + body2 + "}", "a.json");
  ASSERT_TRUE(none.ok()) << none.error().message;
  Result<Scene> two = parseScene(R"({"world": {"dim": 2}, )" + body2 + "}", "a.json");
  ASSERT_TRUE(two.ok()) << two.error().message;
  EXPECT_EQ(two->bodies.size(), 1u);

  Result<AnyScene> any2 = parseAnyScene(R"({"world": {"dim": 2}, )" + body2 + "}", "a.json");
  ASSERT_TRUE(any2.ok());
  EXPECT_TRUE(std::holds_alternative<Scene>(*any2));
  const std::string scene3 =
      R"({"world": {"dim": 3}, "bodies": [{"shapes": [{"type": "sphere", "radius": 1}]}]})";
  Result<AnyScene> any3 = parseAnyScene(scene3, "b.json");
  ASSERT_TRUE(any3.ok()) << any3.error().message;
  ASSERT_TRUE(std::holds_alternative<Scene3>(*any3));
  EXPECT_EQ(std::get<Scene3>(*any3).bodies.size(), 1u);

  Result<Scene> wrong2 = parseScene(scene3, "b.json");
  ASSERT_FALSE(wrong2.ok());
  EXPECT_EQ(wrong2.error().message.rfind("b.json: world.dim: 3 is a 3D scene", 0), 0u)
      << wrong2.error().message;
  Result<Scene3> wrong3 = parseScene3("{" + body2 + "}", "a.json");
  ASSERT_FALSE(wrong3.ok());
  EXPECT_EQ(wrong3.error().message.rfind("a.json: world.dim: a 3D scene needs \"dim\": 3", 0), 0u)
      << wrong3.error().message;
  for (const char* dim : {"4", "0", "\"3\"", "3.0", "null"}) {
    const std::string text = std::string(R"({"world": {"dim": )") + dim + "}}";
    for (const Error& e :
         {parseAnyScene(text, "c.json").error(), parseScene(text, "c.json").error(),
          parseScene3(text, "c.json").error()}) {
      EXPECT_EQ(e.message.rfind("c.json: world.dim: must be 2 or 3", 0), 0u) << e.message;
    }
  }
  Result<AnyScene> missing = loadAnyScene("/no/such/scene-3d.json");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message,
            "/no/such/scene-3d.json: cannot open the file (No such file or directory)");
}

// Every bad field is refused with the file, its JSON path and what is wrong.
TEST(Scene3, EveryBadFieldIsRefusedByName) {
  struct Case {
    const char* world;   // the "world" object's keys after "dim": 3
    const char* body;    // one body (empty: none)
    const char* top;     // more top-level keys
    const char* wanted;  // the message's start, after "f.json: "
  };
  const std::vector<Case> cases = {
      {R"(, "gravity": [0, -10])", "", "", "world.gravity: must be [x, y, z]"},
      {R"(, "gravity": [0, -1e5, 0])", "", "", "world.gravity: must be at most 10000 m/s^2"},
      {R"(, "broadphase": "sap")", "", "", "world.broadphase: the 3D world has one broad phase"},
      {R"(, "dt": 0)", "", "", "world.dt: must be > 0"},
      {R"(, "dt": 2)", "", "", "world.dt: must be at most 1 s, got 2"},
      {R"(, "substeps": 0)", "", "", "world.substeps: must be in 1..64"},
      {R"(, "sleep": 1)", "", "", "world.sleep: must be true or false"},
      {R"(, "contactHertz": 0)", "", "", "world.contactHertz: must be > 0"},
      {R"(, "contactDampingRatio": -1)", "", "", "world.contactDampingRatio: must be >= 0"},
      {R"(, "contactPushMaxSpeed": 0)", "", "", "world.contactPushMaxSpeed: must be > 0"},
      {R"(, "restitutionThreshold": -1)", "", "", "world.restitutionThreshold: must be >= 0"},
      {R"(, "speculativeDistance": 2)", "", "", "world.speculativeDistance: must be at most 1 m"},
      {R"(, "speculativeDistance": 0.5, "aabbMargin": 0.1)", "", "",
       "world.aabbMargin: must be >= speculativeDistance (0.5 m), got 0.1"},
      {R"(, "contactRecycleDistance": 2)", "", "", "world.contactRecycleDistance: must be at most"},
      {R"(, "continuous": 1)", "", "", "world.continuous: must be"},
      {R"(, "hertz": 3)", "", "", "world.hertz: unknown key"},
      {"", "", R"(, "generate": [])", "generate: the 3D scene format has no generators yet"},
      {"", "", R"(, "joints": [])", "joints: the 3D world has no joints yet"},
      {"", "", R"(, "categories": ["a", "a"])", "categories[1]: \"a\" is declared twice"},
      {"", "", R"(, "bodies": {})", "bodies: must be an array"},
      {"", R"({"angle": 1})", "", "bodies[0].angle: a 3D body turns by \"quat\""},
      {"", R"({"bullet": true})", "", "bodies[0].bullet: the 3D world has no bullets"},
      {"", R"({"spin": 1})", "", "bodies[0].spin: unknown key"},
      {"", R"({"name": 5})", "", "bodies[0].name: must be a string"},
      {"", R"({"type": "rigid"})", "", "bodies[0].type: must be \"static\", \"kinematic\""},
      {"", R"({"pos": [0, 1]})", "", "bodies[0].pos: must be [x, y, z]"},
      {"", R"({"pos": [0, 6e8, 0]})", "", "bodies[0].pos: [0, 6e+08, 0] is beyond +-5e+08 m"},
      {"", R"({"pos": [0, 1e39, 0]})", "", "bodies[0].pos[1]: must be finite (as a float)"},
      {"", R"({"quat": [0, 0, 0, 0]})", "", "bodies[0].quat: [0, 0, 0, 0] is not a rotation"},
      {"", R"({"quat": [0, 0, 1]})", "", "bodies[0].quat: must be [x, y, z, w]"},
      {"", R"({"vel": [2e5, 0, 0]})", "", "bodies[0].vel: must be at most 100000 m/s in speed"},
      {"", R"({"angvel": [0, 0, -2e5]})", "",
       "bodies[0].angvel: must be at most 100000 rad/s in size"},
      {"", R"({"linearDamping": -1})", "", "bodies[0].linearDamping: must be >= 0"},
      {"", R"({"angularDamping": -0.5})", "", "bodies[0].angularDamping: must be >= 0"},
      {"", R"({"gravityScale": 1e4})", "", "bodies[0].gravityScale: must be at most 1000 in size"},
      {"", R"({"sleepThreshold": -1})", "", "bodies[0].sleepThreshold: must be >= 0"},
      {"", R"({"sleep": "yes"})", "", "bodies[0].sleep: must be true or false"},
      {"", R"({"awake": false, "sleep": false})", "", "bodies[0].awake: false needs \"sleep\""},
      {R"(, "sleep": false)", R"({"awake": false})", "",
       "bodies[0].awake: false needs sleeping on"},
      {"", R"({"shapes": {}})", "", "bodies[0].shapes: must be an array"},
      {"", R"({"shapes": [5]})", "", "bodies[0].shapes[0]: must be an object with a \"type\""},
      {"", R"({"shapes": [{"type": "circle", "radius": 1}]})", "",
       "bodies[0].shapes[0].type: a 2D shape in a 3D scene"},
      {"", R"({"shapes": [{"type": "box", "half": [1, 1]}]})", "",
       "bodies[0].shapes[0].type: a 2D shape in a 3D scene"},
      {"", R"({"shapes": [{"type": "sphere", "radius": -1}]})", "",
       "bodies[0].shapes[0].radius: must be > 0"},
      {"", R"({"shapes": [{"type": "cone", "radius": 1}]})", "",
       "bodies[0].shapes[0].type: unknown shape type \"cone\""},
      {"", R"({"shapes": [{"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}]})", "",
       "bodies[0].shapes[0].points: needs at least 4 points"},
      {"", R"({"shapes": [{"type": "sphere", "radius": 1, "color": "red"}]})", "",
       "bodies[0].shapes[0].color: unknown key"},
      {"", R"({"shapes": [{"type": "sphere", "radius": 1, "sensor": true}]})", "",
       "bodies[0].shapes[0].sensor: the 3D world has no sensors yet"},
      {"", R"({"shapes": [{"type": "sphere", "radius": 1, "density": -1}]})", "",
       "bodies[0].shapes[0].density: must be >= 0"},
      {"", R"({"shapes": [{"type": "sphere", "radius": 1, "density": 1e10}]})", "",
       "bodies[0].shapes[0].density: must be at most 1e+09 kg/m^3"},
      {"", R"({"shapes": [{"type": "sphere", "radius": 1, "friction": 2000}]})", "",
       "bodies[0].shapes[0].friction: must be at most 1000"},
      {"", R"({"shapes": [{"type": "sphere", "radius": 1, "restitution": 20}]})", "",
       "bodies[0].shapes[0].restitution: must be at most 10"},
      {"", R"({"shapes": [{"type": "sphere", "radius": 1, "rollingResistance": -1}]})", "",
       "bodies[0].shapes[0].rollingResistance: must be >= 0"},
      {"", R"({"shapes": [{"type": "sphere", "radius": 1, "filter": {"category": "x"}}]})", "",
       "bodies[0].shapes[0].filter.category: unknown category \"x\""},
      {"", R"({"shapes": [{"type": "sphere", "radius": 1e4, "density": 1e9}]})", "",
       "bodies[0].shapes[0].density: the shape's mass"},
      {"",
       R"({"pos": [4e8, 0, 0], "shapes": [{"type": "sphere", "center": [7e8, 0, 0], "radius": 1}]})",
       "",
       "bodies[0].shapes[0]: reaches [1.1e+09, -1, -1]..[1.1e+09, 1, 1], beyond the coordinate"},
      {"",
       R"({"shapes": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 0, -1]], "triangles": [[0, 1, 2]]}]})",
       "", "bodies[0].shapes[0].type: a mesh needs a static body"},
      {"",
       R"({"type": "static", "shapes": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 0, -1]], "triangles": [[0, 1, 9]]}]})",
       "", "bodies[0].shapes[0].triangles[0][2]: vertex index 9 is out of range (0 to 2)"},
      {"",
       R"({"type": "static", "shapes": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [2, 0, 0]], "triangles": [[0, 1, 2]]}]})",
       "", "bodies[0].shapes[0].triangles[0]: "},
      {"",
       R"({"type": "static", "shapes": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 0, -1]], "triangles": [[0, 1, 2]], "sensor": false}]})",
       "", "bodies[0].shapes[0].sensor: the 3D world has no sensors yet"},
  };
  int checked = 0;
  for (const Case& c : cases) {
    std::string text = std::string(R"({"world": {"dim": 3)") + c.world + "}";
    if (*c.body != '\0') text += std::string(R"(, "bodies": [)") + c.body + "]";
    text += std::string(c.top) + "}";
    SCOPED_TRACE(text);
    Result<Scene3> scene = parseScene3(text, "f.json");
    ASSERT_FALSE(scene.ok()) << "accepted a bad scene";
    const std::string wanted = std::string("f.json: ") + c.wanted;
    EXPECT_EQ(scene.error().message.rfind(wanted, 0), 0u)
        << "got: " << scene.error().message << "\nwanted: " << wanted;
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(cases.size()));
}

// In a long list the message names the body by its index.
TEST(Scene3, ErrorsNameTheBodyIndex) {
  std::string text = R"({"world": {"dim": 3}, "bodies": [)";
  for (int i = 0; i < 40; ++i)
    text += R"({"shapes": [{"type": "sphere", "radius": 1}]},)";
  text += R"({"shapes": [{"type": "sphere", "radius": 0}]}]})";
  Result<Scene3> scene = parseScene3(text, "long.json");
  ASSERT_FALSE(scene.ok());
  EXPECT_EQ(scene.error().message, "long.json: bodies[40].shapes[0].radius: must be > 0");
}

// A body listed asleep starts asleep and stays where it is until touched.
TEST(Scene3, AwakeFalseStartsAsleep) {
  const Scene3 scene = parseOk(R"({"world": {"dim": 3}, "bodies": [
      {"name": "hung", "pos": [0, 5, 0], "awake": false, "shapes": [{"type": "sphere", "radius": 0.5}]},
      {"name": "falling", "pos": [3, 5, 0], "shapes": [{"type": "sphere", "radius": 0.5}]}]})");
  SceneWorld3 sw = buildWorld3(scene).value();
  EXPECT_FALSE(sw.world.isAwake(sw.bodies[0]));
  EXPECT_TRUE(sw.world.isAwake(sw.bodies[1]));
  for (int i = 0; i < 30; ++i)
    ASSERT_TRUE(sw.world.step().ok());
  EXPECT_EQ(sw.world.position(sw.bodies[0]), (Vec3{0, 5, 0}));
  EXPECT_LT(sw.world.position(sw.bodies[1]).y, 4.0f);
}

// ---- the sample scenes ------------------------------------------------------------------

SceneWorld3 loadSample(const char* name, Scene3& scene) {
  Result<Scene3> loaded = loadScene3((kSource / "scenes" / name).string());
  EXPECT_TRUE(loaded.ok()) << loaded.error().message;
  scene = std::move(loaded).value();
  Result<SceneWorld3> built = buildWorld3(scene);
  EXPECT_TRUE(built.ok()) << built.error().message;
  return std::move(built).value();
}

// Every scenes/*-3d.json is a 3D scene that builds and steps with finite state.
TEST(Scene3, EverySample3DSceneRuns) {
  int scenes = 0;
  for (const auto& entry : fs::directory_iterator(kSource / "scenes")) {
    const std::string file = entry.path().filename().string();
    if (file.size() < 8 || file.substr(file.size() - 8) != "-3d.json") continue;
    SCOPED_TRACE(file);
    ++scenes;
    Result<AnyScene> any = loadAnyScene(entry.path().string());
    ASSERT_TRUE(any.ok()) << any.error().message;
    ASSERT_TRUE(std::holds_alternative<Scene3>(*any));
    SceneWorld3 sw = buildWorld3(std::get<Scene3>(*any)).value();
    for (int s = 0; s < 10; ++s)
      ASSERT_TRUE(sw.world.step().ok());
    for (BodyId3 b : sw.bodies) {
      EXPECT_TRUE(isFinite(sw.world.position(b)));
      EXPECT_TRUE(isFinite(sw.world.linearVelocity(b)));
    }
  }
  EXPECT_GE(scenes, 4);
}

// The pyramid of 55 boxes as shipped: all asleep within a second, every box within 5 mm of
// where it started and square to the axes.
TEST(Scene3, SamplePyramidStandsAndSleeps) {
  Scene3 scene;
  SceneWorld3 sw = loadSample("pyramid-3d.json", scene);
  for (int s = 0; s < 60; ++s)
    ASSERT_TRUE(sw.world.step().ok());
  EXPECT_EQ(sw.world.awakeBodyCount(), 0u);
  ASSERT_EQ(sw.bodies.size(), 56u);
  for (std::size_t i = 1; i < sw.bodies.size(); ++i) {
    SCOPED_TRACE(sw.names[i]);
    EXPECT_LT(length(sw.world.position(sw.bodies[i]) - scene.bodies[i].def.position), 5e-3f);
    EXPECT_GT(std::fabs(sw.world.rotation(sw.bodies[i]).w), 0.9999f);  // within 1.6 degrees
  }
}

// The pyramid stands on its own, without sleeping's help: with sleep off, after 5 s every
// box is within 5 mm of where it started (measured: 0.7 mm, the same after 30 s) and square
// to the axes. Slow (4 to 8 s in the debug build: every box awake every step).
TEST(Scene3, SamplePyramidStandsWithoutSleeping) {
  Scene3 scene;
  loadSample("pyramid-3d.json", scene);
  scene.world.enableSleep = false;
  SceneWorld3 sw = buildWorld3(scene).value();
  for (int s = 0; s < 300; ++s)
    ASSERT_TRUE(sw.world.step().ok());
  for (std::size_t i = 1; i < sw.bodies.size(); ++i) {
    SCOPED_TRACE(sw.names[i]);
    EXPECT_LT(length(sw.world.position(sw.bodies[i]) - scene.bodies[i].def.position), 5e-3f);
    EXPECT_GT(std::fabs(sw.world.rotation(sw.bodies[i]).w), 0.9999f);
  }
}

// The house of cards stands at least 3 s on its own (sleep off): no card moves more than
// 3 cm (they settle by 2.5 cm at the feet; a falling card moves tens of centimetres), and
// the top pair is still at its height within 2 cm.
TEST(Scene3, SampleCardHouseStandsThreeSeconds) {
  Scene3 scene;
  loadSample("cards-3d.json", scene);
  scene.world.enableSleep = false;
  SceneWorld3 sw = buildWorld3(scene).value();
  for (int s = 0; s < 180; ++s)
    ASSERT_TRUE(sw.world.step().ok());
  float top = -1.0f, topNow = -1.0f;
  for (std::size_t i = 1; i < sw.bodies.size(); ++i) {
    SCOPED_TRACE(sw.names[i]);
    const Vec3 start = scene.bodies[i].def.position, now = sw.world.position(sw.bodies[i]);
    EXPECT_LT(length(now - start), 0.03f);
    if (start.y > top) {
      top = start.y;
      topNow = now.y;
    }
  }
  EXPECT_GT(top, 2.3f);  // three storeys
  EXPECT_NEAR(topNow, top, 0.02f);
}

// Spheres and a capsule roll down the mesh valley and stay on it: after 2 s each has moved
// down the slope (x grows by over 2 m), and at every step of 6 s each sphere's centre is at
// least its radius above the curve y = 4 (1 - x / 12)^2 (less 2 cm: the mesh is the curve's
// chords, above it as the curve is convex), and every body is within the valley.
TEST(Scene3, SampleRampSpheresRollAndStayOnTheMesh) {
  Scene3 scene;
  SceneWorld3 sw = loadSample("ramp-3d.json", scene);
  std::vector<float> radius(sw.bodies.size(), 0.0f);
  for (std::size_t i = 1; i < sw.bodies.size(); ++i) {
    const auto* g = std::get_if<ShapeGeometry3>(&scene.bodies[i].shapes[0].geometry);
    ASSERT_NE(g, nullptr);
    if (const auto* s = std::get_if<Sphere>(g)) radius[i] = s->radius;
  }
  for (int s = 1; s <= 360; ++s) {
    ASSERT_TRUE(sw.world.step().ok());
    for (std::size_t i = 1; i < sw.bodies.size(); ++i) {
      const Vec3 p = sw.world.position(sw.bodies[i]);
      ASSERT_TRUE(p.x > -0.5f && p.x < 24.5f && std::fabs(p.z) < 4.0f) << sw.names[i] << " left";
      if (radius[i] == 0.0f) continue;
      const float surface = 4.0f * (1.0f - p.x / 12.0f) * (1.0f - p.x / 12.0f);
      ASSERT_GT(p.y, surface + radius[i] - 0.02f) << sw.names[i] << " at step " << s;
      if (s == 120) {
        EXPECT_GT(p.x - scene.bodies[i].def.position.x, 2.0f) << sw.names[i];
      }
    }
  }
}

// The hulls fall into the bin and come to rest in it: after 20 s every hull is asleep, its
// lowest vertex on or above the floor (1 cm) and inside the walls. All but five are asleep
// after 4 s; those five lean on each other and rock at up to 0.4 rad/s until 16 s
// (docs/world3.md, "Not yet": solved in contact order instead of by colour, the same pile
// slept at 4.7 s; with the colours taken in the other order, at 4.5 s).
TEST(Scene3, SampleHullsSettleInTheBin) {
  Scene3 scene;
  SceneWorld3 sw = loadSample("hulls-3d.json", scene);
  for (int s = 0; s < 1200; ++s)
    ASSERT_TRUE(sw.world.step().ok());
  for (std::size_t i = 1; i < sw.bodies.size(); ++i) {
    SCOPED_TRACE(sw.names[i]);
    const Hull3& hull =
        std::get<Hull3>(std::get<ShapeGeometry3>(scene.bodies[i].shapes[0].geometry));
    const Transform3 xf = sw.world.transform(sw.bodies[i]);
    float low = 1e9f;
    for (int k = 0; k < hull.vertexCount; ++k) {
      const Vec3 w = transformPoint(xf, hull.vertices[k]);
      low = minf(low, w.y - hull.radius);
      EXPECT_LT(std::fabs(w.x), 4.01f);  // the walls' inner faces are at 4
      EXPECT_LT(std::fabs(w.z), 4.01f);
    }
    EXPECT_GT(low, -0.01f);
    EXPECT_FALSE(sw.world.isAwake(sw.bodies[i]));
  }
}

}  // namespace
}  // namespace quack
