// The 3D state file: every number reads back to the same bits, the file is a pure
// function of the run, bad files are named, and each dimension's reader refuses the other's.

#include <gtest/gtest.h>

#include <bit>
#include <cfloat>
#include <cstdint>
#include <limits>
#include <random>

#include "quack/io/scene3.hpp"
#include "quack/io/state.hpp"

namespace quack {
namespace {

std::uint32_t bits(float f) {
  return std::bit_cast<std::uint32_t>(f);
}

// Bit for bit, so that -0 and 0 (equal as floats) differ here.
void expectSameBits(const StateFile3& a, const StateFile3& b) {
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.time), std::bit_cast<std::uint64_t>(b.time));
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.events, b.events);
  ASSERT_EQ(a.bodies.size(), b.bodies.size());
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const BodyState3 &x = a.bodies[i], &y = b.bodies[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.awake, y.awake);
    const float fx[] = {x.pos.x, x.pos.y, x.pos.z, x.quat.x,   x.quat.y,   x.quat.z,  x.quat.w,
                        x.vel.x, x.vel.y, x.vel.z, x.angvel.x, x.angvel.y, x.angvel.z};
    const float fy[] = {y.pos.x, y.pos.y, y.pos.z, y.quat.x,   y.quat.y,   y.quat.z,  y.quat.w,
                        y.vel.x, y.vel.y, y.vel.z, y.angvel.x, y.angvel.y, y.angvel.z};
    for (int k = 0; k < 13; ++k)
      EXPECT_EQ(bits(fx[k]), bits(fy[k])) << "body " << i << " number " << k;
  }
}

// Floats of every kind (random bit patterns over the finite range, the extremes, signed
// zeros, subnormals) written and read back give the same bits.
TEST(State3, NumbersReadBackToTheSameBits) {
  std::mt19937 rng(12);
  std::uniform_int_distribution<std::uint32_t> any;
  auto randomFinite = [&] {
    for (;;) {
      const float f = std::bit_cast<float>(any(rng));
      if (std::isfinite(f)) return f;
    }
  };
  const float special[] = {0.0f,
                           -0.0f,
                           std::numeric_limits<float>::denorm_min(),
                           -std::numeric_limits<float>::denorm_min(),
                           FLT_MIN,
                           FLT_MAX,
                           -FLT_MAX,
                           1.0f / 3.0f,
                           0.1f,
                           16777217.0f,
                           1e-30f};
  StateFile3 state;
  state.time = 1.0 / 3.0;
  state.steps = 12345678901234ull;
  state.events = {7, 3, 0, 0};
  for (int i = 0; i < 400; ++i) {
    BodyState3 b;
    b.name = "b\"" + std::to_string(i);  // a name that needs escaping
    float* f[] = {&b.pos.x, &b.pos.y, &b.pos.z, &b.quat.x,   &b.quat.y,   &b.quat.z,  &b.quat.w,
                  &b.vel.x, &b.vel.y, &b.vel.z, &b.angvel.x, &b.angvel.y, &b.angvel.z};
    for (int k = 0; k < 13; ++k)
      *f[k] = i < 11 ? special[(i + k) % 11] : randomFinite();
    b.awake = i % 3 != 0;
    state.bodies.push_back(b);
  }
  const std::string text = writeState3(state);
  Result<StateFile3> back = parseState3(text, "s.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  expectSameBits(state, back.value());
  EXPECT_EQ(writeState3(back.value()), text);  // and writes the same bytes again
}

// A run's state: captured from the world, written, read back to the same bits; the same
// run twice writes the same bytes; a static body is never awake, a settled one sleeps.
TEST(State3, ARunsStateRoundTripsAndRepeats) {
  auto run = [] {
    Result<Scene3> scene = parseScene3(R"({"world": {"dim": 3}, "bodies": [
        {"name": "ground", "type": "static", "pos": [0, -0.5, 0], "shapes": [{"type": "box", "half": [5, 0.5, 5]}]},
        {"name": "die", "pos": [0, 2, 0], "quat": [0.3, 0.2, 0.1, 1], "angvel": [3, 1, 2],
         "shapes": [{"type": "box", "half": [0.3, 0.3, 0.3]}]},
        {"name": "ball", "pos": [2, 1, 1], "vel": [-1, 0, 0], "shapes": [{"type": "sphere", "radius": 0.4}]}]})",
                                       "run.json");
    EXPECT_TRUE(scene.ok()) << scene.error().message;
    SceneWorld3 sw = buildWorld3(scene.value()).value();
    EventTotals totals;
    for (int i = 0; i < 240; ++i) {
      EXPECT_TRUE(sw.world.step().ok());
      totals.begin += sw.world.events().begin.size();
      totals.end += sw.world.events().end.size();
    }
    return captureState3(sw, totals);
  };
  const StateFile3 state = run();
  ASSERT_EQ(state.bodies.size(), 3u);
  EXPECT_EQ(state.steps, 240u);
  EXPECT_EQ(state.time, 240.0 * static_cast<double>(1.0f / 60.0f));
  EXPECT_FALSE(state.bodies[0].awake);  // static
  EXPECT_EQ(state.bodies[1].name, "die");
  EXPECT_GE(state.events.begin, 2u);  // the die and the ball land
  const std::string text = writeState3(state);
  EXPECT_EQ(text.rfind("{\"dim\": 3,\n \"time\": ", 0), 0u) << text;
  EXPECT_NE(
      text.find(R"({"name": "ground", "pos": [0.0, -0.5, 0.0], "quat": [0.0, 0.0, 0.0, 1.0], )"
                R"("vel": [0.0, 0.0, 0.0], "angvel": [0.0, 0.0, 0.0], "awake": false})"),
      std::string::npos)
      << text;
  Result<StateFile3> back = parseState3(text, "s.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  expectSameBits(state, back.value());
  EXPECT_EQ(writeState3(run()), text);
}

TEST(State3, BadStateFilesAreNamed) {
  const std::string good =
      R"({"dim": 3, "time": 1, "steps": 2, "bodies": [{"name": "a", "pos": [0, 0, 0],
      "quat": [0, 0, 0, 1], "vel": [0, 0, 0], "angvel": [0, 0, 0], "awake": true}],
      "events": {"begin": 0, "end": 0}})";
  ASSERT_TRUE(parseState3(good, "s.json").ok());
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    t.replace(t.find(from), from.size(), to);
    return parseState3(t, "s.json");
  };
  const std::pair<Result<StateFile3>, std::string> cases[] = {
      {parseState3("[]", "s.json"), "s.json: not a JSON object"},
      {replaced(R"("dim": 3, )", ""), "s.json: dim: missing (a 3D state file starts with"},
      {replaced(R"("dim": 3)", R"("dim": 2)"), "s.json: dim: must be 3"},
      {replaced(R"("time": 1)", R"("time": "1")"), "s.json: time: must be a number"},
      {replaced(R"("steps": 2)", R"("steps": -2)"), "s.json: steps: must be a count"},
      {replaced(R"("pos": [0, 0, 0])", R"("pos": [0, 0])"),
       "s.json: bodies[0].pos: must be [x, y, z]"},
      {replaced(R"("quat": [0, 0, 0, 1])", R"("quat": [0, 0, 1])"),
       "s.json: bodies[0].quat: must be [x, y, z, w]"},
      {replaced(R"("angvel": [0, 0, 0])", R"("angvel": [0, 0, 1e39])"),
       "s.json: bodies[0].angvel[2]: must be finite (as a float)"},
      {replaced(R"("vel": [0, 0, 0], )", ""), "s.json: bodies[0].vel: missing"},
      {replaced(R"("awake": true)", R"("awake": 1)"),
       "s.json: bodies[0].awake: must be true or false"},
      {replaced(R"("awake": true)", R"("awake": true, "angle": 0)"),
       "s.json: bodies[0].angle: unknown key"},
      {replaced(R"("events": {"begin": 0, "end": 0})", R"("events": {"begin": 0})"),
       "s.json: events.end: missing"},
      {replaced(R"("steps": 2)", R"("steps": 2, "joints": [])"), "s.json: joints: unknown key"},
  };
  for (const auto& [result, wanted] : cases) {
    ASSERT_FALSE(result.ok()) << wanted;
    EXPECT_EQ(result.error().message.rfind(wanted, 0), 0u)
        << "got: " << result.error().message << "\nwanted: " << wanted;
  }
  // Each dimension's reader refuses the other's file.
  Result<StateFile> as2 = parseState(good, "s.json");
  ASSERT_FALSE(as2.ok());
  EXPECT_EQ(as2.error().message, "s.json: dim: a 3D state file (parseState3 reads it)");
  Result<StateFile3> as3 = parseState3(
      R"({"time": 1, "steps": 2, "bodies": [], "events": {"begin": 0, "end": 0, "hit": 0, "sensor": 0}})",
      "t.json");
  ASSERT_FALSE(as3.ok());
  EXPECT_EQ(as3.error().message.rfind("t.json: dim: missing", 0), 0u);
}

TEST(State3, EventLinesByHand) {
  StepEvents3 events;
  events.begin.push_back({ShapeId3{4, 1, 1}, ShapeId3{9, 1, 1}});
  events.begin.push_back({ShapeId3{0, 1, 1}, ShapeId3{2, 1, 1}});
  events.end.push_back({ShapeId3{3, 1, 1}, ShapeId3{5, 1, 1}});
  std::string out;
  appendEventLines3(out, 17, events);
  EXPECT_EQ(out,
            "{\"step\": 17, \"event\": \"begin\", \"a\": 4, \"b\": 9}\n"
            "{\"step\": 17, \"event\": \"begin\", \"a\": 0, \"b\": 2}\n"
            "{\"step\": 17, \"event\": \"end\", \"a\": 3, \"b\": 5}\n");
}

}  // namespace
}  // namespace quack
