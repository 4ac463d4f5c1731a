#include "quack/io/render.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace quack
