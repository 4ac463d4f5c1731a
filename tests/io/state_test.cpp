#include "quack/io/state.hpp"

#include <gtest/gtest.h>

#include "quack/io/scene.hpp"

namespace quack {
namespace {

TEST(State, RoundTripsExactly) {
  Result<Scene> scene = parseScene(R"({"generate": [{"kind": "rain", "count": 40, "seed": 9}],
      "bodies": [{"name": "ground \"floor\"", "type": "static", "shapes": [{"type": "box", "half": [20, 0.5]}]}]})",
                                   "rt");
  ASSERT_TRUE(scene.ok());
  SceneWorld sw = buildWorld(scene.value()).value();
  for (int i = 0; i < 90; ++i)
    ASSERT_TRUE(sw.world.step().ok());
  StateFile state = captureState(sw, {12, 3, 5, 1});
  ASSERT_EQ(state.bodies.size(), 41u);
  EXPECT_EQ(state.steps, 90u);
  std::string text = writeState(state);
  Result<StateFile> back = parseState(text, "state.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back.value(), state);  // every float bit for bit, names with quotes
  EXPECT_EQ(writeState(back.value()), text);
}

// A scene with joints: the state file lists the live ones in scene order with their force
// and torque, and reads back bit for bit; a scene without joints writes no "joints" key.
TEST(State, JointsRoundTripExactly) {
  Result<Scene> scene = parseScene(R"({"bodies": [
      {"name": "pivot", "type": "static"},
      {"name": "bob", "pos": [1, -1], "shapes": [{"type": "circle", "radius": 0.2}]},
      {"name": "tail", "pos": [2, -1], "shapes": [{"type": "circle", "radius": 0.2}]}],
      "joints": [{"type": "revolute", "a": "pivot", "b": "bob", "anchor": [0, 0]},
                 {"type": "distance", "a": "bob", "b": "tail", "anchors": [[1, -1], [2, -1]],
                  "breakForce": 0.001}]})",
                                   "joints");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  SceneWorld sw = buildWorld(scene.value()).value();
  for (int i = 0; i < 10; ++i)
    ASSERT_TRUE(sw.world.step().ok());
  StateFile state = captureState(sw, {});
  // The distance joint broke at once (1 mN): only the revolute one is left.
  ASSERT_EQ(state.joints.size(), 1u);
  EXPECT_EQ(state.joints[0].type, "revolute");
  EXPECT_EQ(state.joints[0].a, "pivot");
  EXPECT_EQ(state.joints[0].b, "bob");
  EXPECT_GT(length(state.joints[0].force), 1.0f);
  const std::string text = writeState(state);
  EXPECT_NE(text.find("\"joints\": ["), std::string::npos);
  Result<StateFile> back = parseState(text, "state.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back.value(), state);
  EXPECT_EQ(writeState(back.value()), text);
  SceneWorld none = buildWorld(parseScene(R"({"bodies": []})", "none").value()).value();
  EXPECT_EQ(writeState(captureState(none, {})).find("joints"), std::string::npos);
}

// The event list's lines, worked out by hand: every kind, in the documented order, numbers
// as state files print them.
TEST(State, EventLinesByHand) {
  StepEvents e;
  e.hit.push_back({ShapeId{4, 1, 1}, ShapeId{9, 1, 1}, Vec2{0.5f, -1.0f}, Vec2{0.0f, 1.0f}, 2.25f});
  e.begin.push_back({ShapeId{4, 1, 1}, ShapeId{9, 1, 1}});
  e.end.push_back({ShapeId{1, 3, 1}, ShapeId{2, 1, 1}});
  e.sensorBegin.push_back({ShapeId{2, 1, 1}, ShapeId{7, 1, 1}});
  e.sensorEnd.push_back({ShapeId{2, 1, 1}, ShapeId{8, 1, 1}});
  e.toi.push_back({0.25f, ShapeId{5, 1, 1}, ShapeId{0, 1, 1}, Vec2{0.1f, 3.0f}, Vec2{-1.0f, 0.0f}});
  e.outOfBounds.push_back(BodyId{6, 1, 1});
  e.jointEnd.push_back({JointId{2, 1, 1}, BodyId{3, 1, 1}, BodyId{4, 1, 1}, JointEndReason::broken,
                        Vec2{1.5f, -2.0f}, 0.5f, 0});
  e.jointEnd.push_back({JointId{0, 1, 1}, BodyId{3, 1, 1}, BodyId{5, 1, 1},
                        JointEndReason::bodyDestroyed, Vec2{}, 0.0f, 0});
  std::string out = "before\n";
  appendEventLines(out, 3, e);
  EXPECT_EQ(out,
            "before\n"
            "{\"step\": 3, \"event\": \"begin\", \"a\": 4, \"b\": 9}\n"
            "{\"step\": 3, \"event\": \"end\", \"a\": 1, \"b\": 2}\n"
            "{\"step\": 3, \"event\": \"hit\", \"a\": 4, \"b\": 9, \"point\": [0.5, -1.0], "
            "\"normal\": [0.0, 1.0], \"speed\": 2.25}\n"
            "{\"step\": 3, \"event\": \"sensor-begin\", \"sensor\": 2, \"visitor\": 7}\n"
            "{\"step\": 3, \"event\": \"sensor-end\", \"sensor\": 2, \"visitor\": 8}\n"
            "{\"step\": 3, \"event\": \"toi\", \"time\": 0.25, \"a\": 5, \"b\": 0, "
            "\"point\": [0.10000000149011612, 3.0], \"normal\": [-1.0, 0.0]}\n"
            "{\"step\": 3, \"event\": \"out-of-bounds\", \"body\": 6}\n"
            "{\"step\": 3, \"event\": \"joint-end\", \"joint\": 2, \"reason\": \"broken\", "
            "\"force\": [1.5, -2.0], \"torque\": 0.5}\n"
            "{\"step\": 3, \"event\": \"joint-end\", \"joint\": 0, \"reason\": "
            "\"body-destroyed\", \"force\": [0.0, 0.0], \"torque\": 0.0}\n");
  std::string none;
  appendEventLines(none, 4, StepEvents{});
  EXPECT_EQ(none, "");
}

TEST(State, BadStateFilesAreNamed) {
  EXPECT_FALSE(parseState("[]", "s").ok());
  Result<StateFile> r = parseState(R"({"time": 1, "steps": 2, "bodies": [{"name": "a", "pos": [0]}],
      "events": {"begin": 0, "end": 0, "hit": 0, "sensor": 0}})",
                                   "s.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "s.json: bodies[0].pos: must be [x, y]");
  Result<StateFile> u = parseState(R"({"time": 1, "extra": 2})", "s.json");
  ASSERT_FALSE(u.ok());
  EXPECT_EQ(u.error().message, "s.json: extra: unknown key");
}

// Issue 16: each body says whether it is awake. A settled pyramid writes "awake": false for
// every box (and for the ground: static bodies are never awake); a falling ball, true. The
// flag reads back; a file from before sleeping, with no "awake", reads as awake.
TEST(State, AwakeIsWrittenPerBodyAndReadsBack) {
  Result<Scene> scene = parseScene(R"({"generate": [{"kind": "pyramid", "rows": 4}],
      "bodies": [{"name": "ground", "type": "static", "pos": [0, -0.5], "shapes": [{"type": "box", "half": [20, 0.5]}]},
                 {"name": "ball", "pos": [15, 1000], "shapes": [{"type": "circle", "radius": 0.5}]}]})",
                                   "aw");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  SceneWorld sw = buildWorld(scene.value()).value();
  StateFile start = captureState(sw, {});
  ASSERT_EQ(start.bodies.size(), 12u);
  EXPECT_FALSE(start.bodies[0].awake);
  for (std::size_t i = 1; i < start.bodies.size(); ++i)
    EXPECT_TRUE(start.bodies[i].awake) << start.bodies[i].name;
  for (int i = 0; i < 180; ++i)
    ASSERT_TRUE(sw.world.step().ok());
  StateFile state = captureState(sw, {});
  EXPECT_TRUE(state.bodies[1].awake);  // the ball is still falling
  std::size_t asleep = 0;
  for (std::size_t i = 2; i < state.bodies.size(); ++i)
    asleep += state.bodies[i].awake ? 0 : 1;
  EXPECT_EQ(asleep, 10u);
  std::string text = writeState(state);
  EXPECT_NE(
      text.find(
          R"("name": "ground", "pos": [0.0, -0.5], "angle": 0.0, "vel": [0.0, 0.0], "angvel": 0.0, "awake": false})"),
      std::string::npos)
      << text;
  EXPECT_NE(text.find(R"("awake": true})"), std::string::npos);
  Result<StateFile> back = parseState(text, "aw.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back.value(), state);

  Result<StateFile> bad =
      parseState(R"({"time": 1, "steps": 2, "bodies": [{"name": "a", "pos": [0, 0],
      "angle": 0, "vel": [0, 0], "angvel": 0, "awake": 1}], "events": {"begin": 0, "end": 0, "hit": 0, "sensor": 0}})",
                 "s.json");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "s.json: bodies[0].awake: must be true or false");
  Result<StateFile> old =
      parseState(R"({"time": 1, "steps": 2, "bodies": [{"name": "a", "pos": [0, 0],
      "angle": 0, "vel": [0, 0], "angvel": 0}], "events": {"begin": 0, "end": 0, "hit": 0, "sensor": 0}})",
                 "old.json");
  ASSERT_TRUE(old.ok()) << old.error().message;
  EXPECT_TRUE(old->bodies[0].awake);
}

// Issue 14: timing made two identical runs' state files differ. A state file is now a pure
// function of the world: no timing in it, and the same world writes the same bytes.
TEST(State, TimingIsNotInTheStateFileSoIdenticalRunsWriteIdenticalBytes) {
  auto run = [] {
    Result<Scene> scene = parseScene(R"({"generate": [{"kind": "rain", "count": 60, "seed": 3}],
        "bodies": [{"type": "static", "shapes": [{"type": "box", "half": [20, 0.5]}]}]})",
                                     "pure");
    SceneWorld sw = buildWorld(scene.value()).value();
    for (int i = 0; i < 40; ++i)
      EXPECT_TRUE(sw.world.step().ok());
    return writeState(captureState(sw, {1, 2, 3, 4}));
  };
  std::string a = run(), b = run();
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.find("timing"), std::string::npos);
  EXPECT_EQ(a.find("ms"), std::string::npos);
  // A file from an older Quack, with its "timing", still reads.
  Result<StateFile> old = parseState(R"({"time": 1, "steps": 2, "bodies": [],
      "events": {"begin": 0, "end": 0, "hit": 0, "sensor": 0}, "timing": {"ms_per_step": 1, "total_ms": 2}})",
                                     "old.json");
  EXPECT_TRUE(old.ok()) << old.error().message;
}

}  // namespace
}  // namespace quack
