#include "quack/io/render.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

namespace quack {
namespace {

SceneWorld smallScene() {
  Result<Scene> scene = parseScene(R"({"bodies": [
      {"name": "g", "type": "static", "shapes": [{"type": "box", "half": [5, 0.5], "center": [0, -0.5]}]},
      {"name": "s", "type": "static", "shapes": [{"type": "segment", "p1": [-5, 3], "p2": [5, 3]}]},
      {"name": "c", "pos": [0, 1], "shapes": [{"type": "circle", "radius": 0.5}]},
      {"name": "k", "pos": [2, 1], "shapes": [{"type": "capsule", "p1": [-0.5, 0], "p2": [0.5, 0], "radius": 0.25}]},
      {"name": "r", "pos": [-2, 1], "shapes": [{"type": "box", "half": [0.5, 0.5], "radius": 0.1}]}]})",
                                   "r");
  return buildWorld(scene.value()).value();
}

TEST(Render, OutlinesFollowTheShapes) {
  Outline circle = outlineOf(makeCircle({1, 0}, 2).value());
  ASSERT_GE(circle.points.size(), 24u);
  for (Vec2 p : circle.points)
    EXPECT_NEAR(distance(p, {1, 0}), 2.0f, 1e-5f);
  Outline segment = outlineOf(makeSegment({0, 0}, {1, 0}).value());
  EXPECT_FALSE(segment.closed);
  EXPECT_EQ(segment.points.size(), 2u);
  Polygon rounded = makeBox(1, 1, {}, 0, 0.5f).value();
  for (Vec2 p : outlineOf(rounded).points) {
    // Every outline point is on the rounded box's boundary: 0.5 from the core.
    Vec2 q = clampf(p.x, -1, 1) == p.x && clampf(p.y, -1, 1) == p.y
                 ? p
                 : Vec2{clampf(p.x, -1, 1), clampf(p.y, -1, 1)};
    EXPECT_NEAR(distance(p, q), 0.5f, 1e-4f);
  }
}

TEST(Render, SvgHasEveryShapeAndContact) {
  SceneWorld sw = smallScene();
  for (int i = 0; i < 30; ++i)
    ASSERT_TRUE(sw.world.step().ok());
  std::string svg = renderSvg(sw, "small <scene>");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("<title>small &lt;scene&gt;</title>"), std::string::npos);
  std::size_t paths = 0;
  for (std::size_t at = svg.find("<path"); at != std::string::npos; at = svg.find("<path", at + 1))
    ++paths;
  EXPECT_EQ(paths, 5u);
  EXPECT_NE(svg.find("<circle"), std::string::npos);  // resting bodies have contact points
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

// Joints are drawn: in the SVG one teal polyline per live joint, through its anchors; in the
// replay's frames, eight numbers per joint (centre A, anchor A, anchor B, centre B).
TEST(Render, JointsAreDrawnInTheSvgAndTheReplay) {
  Result<Scene> scene = parseScene(R"({"bodies": [
      {"name": "pivot", "type": "static"},
      {"name": "a", "pos": [1, 0], "shapes": [{"type": "circle", "radius": 0.2}]},
      {"name": "b", "pos": [2, 0], "shapes": [{"type": "circle", "radius": 0.2}]}],
      "joints": [{"type": "revolute", "a": "pivot", "b": "a", "anchor": [0, 0]},
                 {"type": "distance", "a": "a", "b": "b", "anchors": [[1, 0], [2, 0]]}]})",
                                   "j");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  SceneWorld sw = buildWorld(scene.value()).value();
  ReplayRecorder replay(sw, 3);
  replay.record(sw);
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(sw.world.step().ok());
    replay.record(sw);
  }
  const std::string svg = renderSvg(sw, "joints");
  std::size_t lines = 0;
  for (std::size_t at = svg.find("<polyline"); at != std::string::npos;
       at = svg.find("<polyline", at + 1))
    ++lines;
  EXPECT_EQ(lines, 2u);
  EXPECT_NE(svg.find("stroke=\"#2a9d8f\""), std::string::npos);
  // The revolute joint's polyline starts at the static pivot's centre, (0, 0).
  EXPECT_NE(svg.find("<polyline points=\"0,0 0,"), std::string::npos) << svg;
  const std::string html = replay.html("joints");
  const std::size_t frame = html.find("\"j\":[");
  ASSERT_NE(frame, std::string::npos);
  const std::size_t end = html.find(']', frame);
  const std::string numbers = html.substr(frame + 5, end - frame - 5);
  EXPECT_EQ(std::count(numbers.begin(), numbers.end(), ',') + 1, 16);
}

TEST(Render, ReplayKeepsAtMostItsFrameBudget) {
  SceneWorld sw = smallScene();
  ReplayOptions options;
  options.maxFrames = 50;
  options.broadPhaseBoxes = true;
  ReplayRecorder replay(sw, 201, options);
  replay.record(sw);
  for (int i = 0; i < 200; ++i) {
    ASSERT_TRUE(sw.world.step().ok());
    replay.record(sw);
  }
  EXPECT_LE(replay.frameCount(), 50);
  EXPECT_GE(replay.frameCount(), 40);
  std::string html = replay.html("a </script> title");
  EXPECT_EQ(html.find("@DATA@"), std::string::npos);
  EXPECT_NE(html.find("\"frames\":["), std::string::npos);
  EXPECT_NE(html.find("\"a\":["), std::string::npos);  // broad-phase boxes recorded
  // The title cannot close the data script early.
  std::size_t dataStart = html.find("id=\"quack-data\">");
  std::size_t dataEnd = html.find("</script>", dataStart);
  EXPECT_EQ(html.substr(dataStart, dataEnd - dataStart).find("</"), std::string::npos);
  EXPECT_EQ(html.find("http://"), std::string::npos);  // no network
  EXPECT_EQ(html.find("https://"), std::string::npos);
}

// Issue 16: the replay records which bodies sleep in each frame, as run lengths over the
// moving bodies (awake first): all awake at the start, and a settled pyramid (with a ball
// still falling beside it, listed first) is one awake body and then the rest asleep.
TEST(Render, ReplayRecordsSleepingBodiesAsRunLengths) {
  Result<Scene> scene = parseScene(R"({"bodies": [
      {"name": "ground", "type": "static", "pos": [0, -0.5], "shapes": [{"type": "box", "half": [20, 0.5]}]},
      {"name": "ball", "pos": [15, 1000], "shapes": [{"type": "circle", "radius": 0.5}]}],
      "generate": [{"kind": "pyramid", "rows": 4}]})",
                                   "zz");
  SceneWorld sw = buildWorld(scene.value()).value();
  ReplayRecorder replay(sw, 181, {});
  replay.record(sw);
  for (int i = 0; i < 180; ++i) {
    ASSERT_TRUE(sw.world.step().ok());
    replay.record(sw);
  }
  ASSERT_FALSE(sw.world.isAwake(sw.bodies[2]));  // the pyramid slept
  std::string html = replay.html("sleep");
  std::size_t first = html.find("\"w\":");
  ASSERT_NE(first, std::string::npos);
  EXPECT_EQ(html.substr(first, 9), "\"w\":[11],");
  std::size_t last = html.rfind("\"w\":");
  EXPECT_EQ(html.substr(last, 11), "\"w\":[1,10],");
  // A body asleep first in scene order starts with an empty awake run.
  ASSERT_TRUE(sw.world.setAwake(sw.bodies[1], false).ok());
  ReplayRecorder again(sw, 1, {});
  again.record(sw);
  std::string page = again.html("sleep");
  EXPECT_NE(page.find("\"w\":[0,11],"), std::string::npos);
}

}  // namespace
}  // namespace quack

namespace quack {
namespace {

// A pile of 3,000 mixed shapes on a floor: many shapes, many contacts.
SceneWorld pile() {
  Result<Scene> scene = parseScene(R"({
      "bodies": [{"name": "ground", "type": "static", "shapes": [{"type": "box", "half": [60, 0.5], "center": [0, -0.5]}]}],
      "generate": [{"kind": "rain", "count": 3000, "pos": [0, 20], "size": [55, 19]}]})",
                                   "pile");
  return buildWorld(scene.value()).value();
}

// Issue 15: a million bodies made a 424 MB SVG and replay. Each has a size budget; a
// scene beyond it draws an even sample of its shapes and says so.
TEST(Render, LargeSceneSvgAndReplayStayWithinTheirSizeBudgets) {
  SceneWorld sw = pile();
  for (int i = 0; i < 5; ++i)
    ASSERT_TRUE(sw.world.step().ok());
  SvgOptions svgOptions;
  svgOptions.maxShapes = 500;
  svgOptions.maxContacts = 100;
  svgOptions.maxBytes = 100000;
  std::string svg = renderSvg(sw, "pile", svgOptions);
  EXPECT_LE(svg.size(), svgOptions.maxBytes);
  EXPECT_NE(svg.find("shapes and "), std::string::npos);
  EXPECT_NE(svg.find("(the SVG size budget)"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  // Unlimited, the same picture is far bigger: the budget did the work.
  SvgOptions unlimited;
  unlimited.maxShapes = unlimited.maxContacts = unlimited.maxBytes = std::size_t{1} << 40;
  std::string full = renderSvg(sw, "pile", unlimited);
  EXPECT_GT(full.size(), 4 * svgOptions.maxBytes);
  EXPECT_EQ(full.find("size budget"), std::string::npos);

  ReplayOptions options;
  options.maxBytes = 400000;
  options.maxShapes = 1000000;  // the byte budget alone limits the shapes here
  options.maxContactsPerFrame = 200;
  options.maxBoxesPerFrame = 300;
  options.broadPhaseBoxes = true;
  const int steps = 40;
  ReplayRecorder replay(sw, steps + 1, options);
  replay.record(sw);
  for (int i = 0; i < steps; ++i) {
    ASSERT_TRUE(sw.world.step().ok());
    replay.record(sw);
  }
  std::string html = replay.html("pile");
  EXPECT_LE(html.size(), options.maxBytes);
  EXPECT_LT(replay.shapesDrawn(), replay.shapesTotal());
  EXPECT_GT(replay.shapesDrawn(), 100u);
  EXPECT_GE(replay.frameCount(), 2);
  EXPECT_LT(replay.frameCount(), steps + 1);  // thinned to fit
  // The page says what it left out, and the last frame is the end of the run.
  EXPECT_NE(html.find("\"drawn\":" + std::to_string(replay.shapesDrawn())), std::string::npos);
  EXPECT_NE(html.find("\"capped\":true"), std::string::npos);
  EXPECT_NE(html.find("(size budget)"), std::string::npos);
  std::size_t last = html.rfind("{\"t\":");
  ASSERT_NE(last, std::string::npos);
  EXPECT_NEAR(std::strtod(html.c_str() + last + 5, nullptr), sw.world.time(), 1e-4);
}

}  // namespace
}  // namespace quack
