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
  StateFile state = captureState(sw, {12, 3, 5, 1}, {0.25, 22.5});
  ASSERT_EQ(state.bodies.size(), 41u);
  EXPECT_EQ(state.steps, 90u);
  std::string text = writeState(state);
  Result<StateFile> back = parseState(text, "state.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back.value(), state);  // every float bit for bit, names with quotes
  EXPECT_EQ(writeState(back.value()), text);
}

TEST(State, BadStateFilesAreNamed) {
  EXPECT_FALSE(parseState("[]", "s").ok());
  Result<StateFile> r = parseState(R"({"time": 1, "steps": 2, "bodies": [{"name": "a", "pos": [0]}],
      "events": {"begin": 0, "end": 0, "hit": 0, "sensor": 0}, "timing": {"ms_per_step": 1, "total_ms": 2}})",
                                   "s.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "s.json: bodies[0].pos: must be [x, y]");
  Result<StateFile> u = parseState(R"({"time": 1, "extra": 2})", "s.json");
  ASSERT_FALSE(u.ok());
  EXPECT_EQ(u.error().message, "s.json: extra: unknown key");
}

}  // namespace
}  // namespace quack
