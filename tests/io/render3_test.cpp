// The 3D replay page: the recording it carries (every shape once, with its geometry; every
// moving body's pose per frame, as the world had it) and its size budgets.

#include "quack/io/render3.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <string>

namespace quack {
namespace {

using nlohmann::json;

// The JSON the page carries.
json pageData(const std::string& html) {
  const std::string open = "id=\"quack-data\">";
  const std::size_t start = html.find(open) + open.size();
  const std::size_t end = html.find("</script>", start);
  return json::parse(html.substr(start, end - start));
}

Scene3 everyShapeScene() {
  Result<Scene3> scene = parseScene3(R"({"world": {"dim": 3}, "bodies": [
      {"name": "floor", "type": "static",
       "shapes": [{"type": "mesh", "vertices": [[-5, 0, -5], [5, 0, -5], [5, 0, 5], [-5, 0, 5]],
                   "triangles": [[0, 3, 2], [0, 2, 1]]},
                  {"type": "triangle", "points": [[6, 0, 0], [7, 0, 0], [6, 0, -1]]}]},
      {"name": "box", "pos": [0, 1, 0], "quat": [0, 0.3, 0, 1], "shapes": [{"type": "box", "half": [0.5, 0.25, 0.4]}]},
      {"name": "ball", "pos": [2, 2, 0], "vel": [0, 0, 1], "shapes": [{"type": "sphere", "radius": 0.3}]},
      {"name": "pill", "pos": [-2, 1, 1], "angvel": [0, 2, 0],
       "shapes": [{"type": "capsule", "p1": [-0.4, 0, 0], "p2": [0.4, 0, 0], "radius": 0.2}]},
      {"name": "gem", "pos": [0, 3, 2],
       "shapes": [{"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.6, 0.6, 0.6]], "radius": 0.02}]}]})",
                                     "every.json");
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  return std::move(scene).value();
}

TEST(Render3, ReplayCarriesEveryShapeAndTheWorldsPoses) {
  const Scene3 scene = everyShapeScene();
  SceneWorld3 sw = buildWorld3(scene).value();
  ReplayOptions3 options;
  options.maxFrames = 20;
  ReplayRecorder3 replay(scene, sw, 121, options);
  replay.record(sw);
  for (int i = 0; i < 120; ++i) {
    ASSERT_TRUE(sw.world.step().ok());
    replay.record(sw);
  }
  EXPECT_LE(replay.frameCount(), 20);
  EXPECT_GE(replay.frameCount(), 15);
  EXPECT_EQ(replay.shapesDrawn(), 6u);
  EXPECT_EQ(replay.shapesTotal(), 6u);
  const std::string html = replay.html("a </script> title");
  EXPECT_EQ(html.find("@DATA@"), std::string::npos);
  EXPECT_EQ(html.find("http://"), std::string::npos);  // nothing fetched
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_NE(html.find("getContext(\"webgl\""), std::string::npos);
  const json data = pageData(html);
  EXPECT_EQ(data["title"], "a </script> title");
  const json& shapes = data["shapes"];
  ASSERT_EQ(shapes.size(), 6u);
  EXPECT_EQ(shapes[0]["g"]["t"], "mesh");
  EXPECT_EQ(shapes[0]["g"]["i"].size(), 6u);  // two triangles
  EXPECT_EQ(shapes[0]["b"], -1);              // static: drawn where it is
  EXPECT_EQ(shapes[1]["g"]["t"], "mesh");     // a triangle is a one-triangle mesh
  EXPECT_EQ(shapes[1]["g"]["i"].size(), 3u);
  EXPECT_EQ(shapes[2]["g"]["t"], "hull");  // a box is a hull: 8 vertices, 6 faces of 4
  EXPECT_EQ(shapes[2]["g"]["v"].size(), 24u);
  ASSERT_EQ(shapes[2]["g"]["f"].size(), 6u);
  for (const json& face : shapes[2]["g"]["f"])
    EXPECT_EQ(face.size(), 4u);
  EXPECT_EQ(shapes[3]["g"]["t"], "sphere");
  EXPECT_EQ(shapes[3]["g"]["r"], 0.3);
  EXPECT_EQ(shapes[4]["g"]["t"], "capsule");
  const Hull3& gem = std::get<Hull3>(std::get<ShapeGeometry3>(scene.bodies[4].shapes[0].geometry));
  EXPECT_EQ(shapes[5]["g"]["f"].size(), static_cast<std::size_t>(gem.faceCount));
  EXPECT_EQ(shapes[5]["g"]["r"], 0.02);
  // The moving bodies are numbered in scene order; the last frame is the last step and
  // every pose is the world's, to the 4 decimals the page keeps.
  for (std::size_t k = 1; k < shapes.size(); ++k)
    EXPECT_EQ(shapes[k]["b"], k < 2 ? -1 : static_cast<int>(k) - 2);
  const json& last = data["frames"].back();
  EXPECT_NEAR(last["t"].get<double>(), 2.0, 1e-4);
  ASSERT_EQ(last["p"].size(), 4u * 7u);
  for (int b = 0; b < 4; ++b) {
    const Transform3 xf = sw.world.transform(sw.bodies[static_cast<std::size_t>(b) + 1]);
    const float want[7] = {xf.p.x, xf.p.y, xf.p.z, xf.q.x, xf.q.y, xf.q.z, xf.q.w};
    for (int k = 0; k < 7; ++k)
      EXPECT_NEAR(last["p"][7 * b + k].get<double>(), want[k], 5.1e-5) << b << " " << k;
  }
  // Contacts: the box rests on the floor by the end, so some points, six numbers each.
  EXPECT_GT(last["c"].size(), 0u);
  EXPECT_EQ(last["c"].size() % 6, 0u);
  // The first frame is the scene as written.
  const json& first = data["frames"].front();
  EXPECT_EQ(first["t"], 0);
  EXPECT_NEAR(first["p"][7 * 1 + 0].get<double>(), 2.0, 1e-9);  // the ball's x
  // Bounds hold every moving body over the run and the static shapes; focus the movers.
  const json& bounds = data["bounds"];
  EXPECT_LE(bounds[0].get<double>(), -5.0);
  EXPECT_GE(bounds[3].get<double>(), 7.0);
  const json& focus = data["focus"];
  EXPECT_GT(focus[0].get<double>(), -5.0);
}

// A huge mesh does not fit the shapes' quarter of the budget: it is left out and the page
// says so; the frames are thinned to fit the rest, and the page keeps to the budget.
TEST(Render3, ReplayKeepsToItsSizeBudget) {
  std::string vertices, triangles;
  const int n = 60;  // a 60 x 60 grid: 7,200 triangles, about 100 kB of text
  for (int i = 0; i <= n; ++i) {
    for (int k = 0; k <= n; ++k) {
      vertices += (vertices.empty() ? "" : ",") + std::string("[") + std::to_string(i - n / 2) +
                  ", 0, " + std::to_string(k - n / 2) + "]";
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < n; ++k) {
      const int a = i * (n + 1) + k, b = a + 1, c = a + n + 2, d = a + n + 1;
      triangles += (triangles.empty() ? "" : ",") + std::string("[") + std::to_string(a) + "," +
                   std::to_string(b) + "," + std::to_string(c) + "],[" + std::to_string(a) + "," +
                   std::to_string(c) + "," + std::to_string(d) + "]";
    }
  }
  std::string bodies;
  for (int i = 0; i < 16; ++i) {
    bodies += R"(, {"pos": [)" + std::to_string(i % 8 - 4) + ", " + std::to_string(2 + i / 8) +
              R"(, 0], "shapes": [{"type": "sphere", "radius": 0.4}]})";
  }
  Result<Scene3> scene = parseScene3(
      R"({"world": {"dim": 3}, "bodies": [{"type": "static", "shapes": [{"type": "mesh", "vertices": [)" +
          vertices + R"(], "triangles": [)" + triangles + "]}]}" + bodies + "]}",
      "big.json");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  SceneWorld3 sw = buildWorld3(scene.value()).value();
  ReplayOptions3 options;
  options.maxBytes = 96 * 1024;
  ReplayRecorder3 replay(scene.value(), sw, 241, options);
  replay.record(sw);
  for (int i = 0; i < 240; ++i) {
    ASSERT_TRUE(sw.world.step().ok());
    replay.record(sw);
  }
  EXPECT_EQ(replay.shapesTotal(), 17u);
  EXPECT_EQ(replay.shapesDrawn(), 16u);  // the spheres, not the mesh
  const std::string html = replay.html("big");
  EXPECT_LE(html.size(), options.maxBytes);
  EXPECT_LT(replay.frameCount(), 241);
  EXPECT_GE(replay.frameCount(), 2);
  const json data = pageData(html);
  EXPECT_EQ(data["drawn"], 16);
  EXPECT_EQ(data["total"], 17);
  EXPECT_NEAR(data["frames"].back()["t"].get<double>(), 4.0, 1e-4);  // the last step is kept
}

}  // namespace
}  // namespace quack
