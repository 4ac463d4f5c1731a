// `quack query` op raycast: hand-worked answers, its errors, and agreement with the geometry
// layer's rayCast on random shapes, poses and rays.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "quack/geometry/raycast.hpp"
#include "quack/io/shape_json.hpp"
#include "query.hpp"

namespace quack::app {
namespace {

using nlohmann::json;

json answerOf(const json& query) {
  QueryAnswer a = answerQuery(query.dump());
  EXPECT_TRUE(a.ok) << query.dump() << " -> " << a.answer;
  return json::parse(a.answer);
}

std::string errorOf(const std::string& line) {
  QueryAnswer a = answerQuery(line);
  EXPECT_FALSE(a.ok) << line << " -> " << a.answer;
  json j = json::parse(a.answer);
  return j["error"].is_string() ? j["error"].get<std::string>() : "";
}

Vec2 vecOf(const json& j) {
  return {j[0].get<float>(), j[1].get<float>()};
}

json rayQuery(const json& shape, const json& pose, Vec2 origin, Vec2 translation) {
  return {
      {"id", 1},
      {"op", "raycast"},
      {"a", shape},
      {"pa", pose},
      {"ray", {{"origin", {origin.x, origin.y}}, {"translation", {translation.x, translation.y}}}}};
}

TEST(QueryRayCast, HandWorkedHitsAndMisses) {
  // A unit circle at (5, 0), ray along +x from the origin: enters at x = 4, t = 0.4.
  json circle = {{"type", "circle"}, {"radius", 1}};
  json hit = answerOf(rayQuery(circle, {{"pos", {5, 0}}}, {0, 0}, {10, 0}));
  EXPECT_TRUE(hit["hit"].get<bool>());
  EXPECT_FLOAT_EQ(hit["fraction"].get<float>(), 0.4f);
  EXPECT_EQ(vecOf(hit["point"]), (Vec2{4, 0}));
  EXPECT_EQ(vecOf(hit["normal"]), (Vec2{-1, 0}));
  // Passing above it: no hit, and every number of the answer is 0.
  json miss = answerOf(rayQuery(circle, {{"pos", {5, 0}}}, {0, 2}, {10, 0}));
  EXPECT_FALSE(miss["hit"].get<bool>());
  EXPECT_EQ(miss["fraction"].get<float>(), 0.0f);
  EXPECT_EQ(vecOf(miss["point"]), (Vec2{}));
  EXPECT_EQ(vecOf(miss["normal"]), (Vec2{}));
  // Starting inside a solid shape is not entering it.
  EXPECT_FALSE(answerOf(rayQuery(circle, json::object(), {0.5f, 0}, {10, 0}))["hit"].get<bool>());
  // A capsule from (-1, 0) to (1, 0), radius 0.5, turned a quarter turn about (0, 3): it
  // stands from y = 2 to y = 4, and a ray up the y axis from the origin enters its bottom cap
  // at y = 1.5, t = 0.15, normal straight down (world frame).
  json capsule = {{"type", "capsule"}, {"p1", {-1, 0}}, {"p2", {1, 0}}, {"radius", 0.5}};
  json up = answerOf(rayQuery(capsule, {{"pos", {0, 3}}, {"angle", kPi / 2}}, {0, 0}, {0, 10}));
  EXPECT_TRUE(up["hit"].get<bool>());
  EXPECT_NEAR(up["fraction"].get<float>(), 0.15f, 1e-6f);
  EXPECT_NEAR(vecOf(up["point"]).x, 0.0f, 1e-6f);
  EXPECT_NEAR(vecOf(up["point"]).y, 1.5f, 1e-6f);
  EXPECT_NEAR(vecOf(up["normal"]).x, 0.0f, 1e-6f);
  EXPECT_NEAR(vecOf(up["normal"]).y, -1.0f, 1e-6f);
  // Segments are two-sided: the normal faces the ray's origin.
  json segment = {{"type", "segment"}, {"p1", {0, -1}}, {"p2", {0, 1}}};
  json left = answerOf(rayQuery(segment, json::object(), {2, 0}, {-4, 0}));
  EXPECT_FLOAT_EQ(left["fraction"].get<float>(), 0.5f);
  EXPECT_EQ(vecOf(left["normal"]), (Vec2{1, 0}));
  json right = answerOf(rayQuery(segment, json::object(), {-2, 0}, {4, 0}));
  EXPECT_EQ(vecOf(right["normal"]), (Vec2{-1, 0}));
}

TEST(QueryRayCast, ConcaveShapeAnswersItsNearestPiece) {
  // An L: the square [0, 2] x [0, 2] without the quarter [1, 2] x [1, 2].
  json l = {{"type", "concave"}, {"points", {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}}};
  json side = answerOf(rayQuery(l, json::object(), {-1, 0.5f}, {4, 0}));
  EXPECT_TRUE(side["hit"].get<bool>());
  EXPECT_FLOAT_EQ(side["fraction"].get<float>(), 0.25f);
  EXPECT_EQ(vecOf(side["normal"]), (Vec2{-1, 0}));
  // From the notch, leftwards: the inner edge x = 1.
  json notch = answerOf(rayQuery(l, json::object(), {1.5f, 1.5f}, {-2, 0}));
  EXPECT_TRUE(notch["hit"].get<bool>());
  EXPECT_FLOAT_EQ(notch["fraction"].get<float>(), 0.25f);
  EXPECT_EQ(vecOf(notch["point"]), (Vec2{1, 1.5f}));
  EXPECT_EQ(vecOf(notch["normal"]), (Vec2{1, 0}));
  // From inside, across the seams between pieces: no hit (it never enters the shape).
  for (Vec2 o : {Vec2{0.5f, 0.5f}, Vec2{0.5f, 1.5f}, Vec2{1.5f, 0.5f}}) {
    for (Vec2 d : {Vec2{3, 0}, Vec2{0, 3}, Vec2{-3, 0}, Vec2{0, -3}, Vec2{2, 2}})
      EXPECT_FALSE(answerOf(rayQuery(l, json::object(), o, d))["hit"].get<bool>());
  }
  // The same as the nearest of the pieces' own ray casts, from outside.
  Result<std::vector<ShapeGeometry>> pieces = parseShapePieces(l, "a");
  ASSERT_TRUE(pieces.ok());
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int trial = 0; trial < 500; ++trial) {
    const float angle = kPi * u(rng);
    const Vec2 origin = Vec2{1, 1} + 3.0f * Vec2{std::cos(angle), std::sin(angle)};
    const Vec2 translation = Vec2{1, 1} + Vec2{u(rng), u(rng)} - origin;
    RayHit best;
    for (const ShapeGeometry& g : *pieces) {
      RayHit h = rayCast(g, RayCastInput{origin, translation, 1.0f});
      if (h.hit && (!best.hit || h.fraction < best.fraction)) best = h;
    }
    json a = answerOf(rayQuery(l, json::object(), origin, translation));
    ASSERT_EQ(a["hit"].get<bool>(), best.hit) << trial;
    if (!best.hit) continue;
    EXPECT_FLOAT_EQ(a["fraction"].get<float>(), best.fraction) << trial;
    EXPECT_EQ(vecOf(a["point"]), best.point) << trial;
    EXPECT_EQ(vecOf(a["normal"]), best.normal) << trial;
  }
}

// A random shape of every JSON type but concave, about the origin, about `size` across.
json randomShapeJson(std::mt19937& rng, int type, float size) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  auto point = [&](float extent) {
    return json::array({extent * (2.0f * u(rng) - 1.0f), extent * (2.0f * u(rng) - 1.0f)});
  };
  switch (type) {
    case 0:
      return {
          {"type", "circle"}, {"center", point(0.3f * size)}, {"radius", size * (0.1f + u(rng))}};
    case 1:
      return {{"type", "capsule"},
              {"p1", point(size)},
              {"p2", point(size)},
              {"radius", size * (0.05f + 0.4f * u(rng))}};
    case 2:
      return {{"type", "segment"}, {"p1", point(size)}, {"p2", point(size)}};
    case 3:
      return {{"type", "box"},
              {"half", {size * (0.1f + u(rng)), size * (0.1f + u(rng))}},
              {"center", point(0.3f * size)},
              {"angle", kPi * (2.0f * u(rng) - 1.0f)},
              {"radius", u(rng) < 0.3f ? 0.2f * size * u(rng) : 0.0f}};
    default: {
      // Points on a circle in angle order: convex.
      const int n = 3 + static_cast<int>(u(rng) * 10.0f);
      std::vector<float> angles;
      for (int i = 0; i < n; ++i)
        angles.push_back(2.0f * kPi * u(rng));
      std::sort(angles.begin(), angles.end());
      json points = json::array();
      for (float a : angles)
        points.push_back({size * std::cos(a), size * std::sin(a)});
      return {
          {"type", "polygon"}, {"points", points}, {"radius", u(rng) < 0.3f ? 0.1f * size : 0.0f}};
    }
  }
}

TEST(QueryRayCast, AgreesWithTheGeometryLayerOnRandomShapesAndPoses) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int compared = 0, hits = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    json shape = randomShapeJson(rng, trial % 5, 1.0f);
    Result<ShapeGeometry> g = parseShape(shape, "a");
    if (!g) continue;  // a degenerate random outline (collinear points, say)
    const Vec2 pos{20.0f * u(rng), 20.0f * u(rng)};
    const float angle = kPi * u(rng);
    const Transform worldFromA = makeTransform(pos, angle);
    const Vec2 origin = pos + Vec2{4.0f * u(rng), 4.0f * u(rng)};
    // Aimed near the shape, long enough to reach it or to stop short: hits, misses, starts
    // inside.
    const Vec2 target = pos + Vec2{u(rng), u(rng)};
    const Vec2 translation = (1.0f + 0.8f * u(rng)) * (target - origin);
    json a =
        answerOf(rayQuery(shape, {{"pos", {pos.x, pos.y}}, {"angle", angle}}, origin, translation));
    // The reference: the ray taken into A's frame, cast there, the hit brought back.
    RayHit h = rayCast(*g, RayCastInput{invTransformPoint(worldFromA, origin),
                                        invRotate(worldFromA.q, translation), 1.0f});
    ++compared;
    ASSERT_EQ(a["hit"].get<bool>(), h.hit) << shape.dump() << " trial " << trial;
    if (!h.hit) continue;
    ++hits;
    const Vec2 point = transformPoint(worldFromA, h.point);
    const Vec2 normal = rotate(worldFromA.q, h.normal);
    EXPECT_NEAR(a["fraction"].get<float>(), h.fraction, 1e-6f) << trial;
    EXPECT_NEAR(vecOf(a["point"]).x, point.x, 1e-5f) << trial;
    EXPECT_NEAR(vecOf(a["point"]).y, point.y, 1e-5f) << trial;
    EXPECT_NEAR(vecOf(a["normal"]).x, normal.x, 1e-6f) << trial;
    EXPECT_NEAR(vecOf(a["normal"]).y, normal.y, 1e-6f) << trial;
    // The hit point is where the ray says, and on the surface (the normal is a unit vector).
    EXPECT_NEAR(length(point - (origin + h.fraction * translation)), 0.0f, 1e-4f) << trial;
    EXPECT_NEAR(length(normal), 1.0f, 1e-5f) << trial;
  }
  EXPECT_GT(compared, 3500);
  EXPECT_GT(hits, 1000);
  EXPECT_LT(hits, compared - 500);
}

TEST(QueryRayCast, ErrorsNameTheField) {
  const std::string a = R"("a":{"type":"circle","radius":1})";
  const std::string ray = R"("ray":{"origin":[0,0],"translation":[1,0]})";
  EXPECT_EQ(errorOf(R"({"id":1,"op":"raycast",)" + ray + "}"), "a: missing");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"raycast",)" + a + "}"), "ray: missing");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"raycast","ray":[0,0],)" + a + "}"),
            R"(ray: must be an object {"origin", "translation"})");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"raycast","ray":{"translation":[1,0]},)" + a + "}"),
            "ray.origin: missing");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"raycast","ray":{"origin":[1,0]},)" + a + "}"),
            "ray.translation: missing");
  EXPECT_EQ(
      errorOf(R"({"id":1,"op":"raycast","ray":{"origin":[0,0],"translation":[1,0],"dir":1},)" + a +
              "}"),
      "ray.dir: unknown key");
  EXPECT_EQ(
      errorOf(R"({"id":1,"op":"raycast","ray":{"origin":[1e19,0],"translation":[1,0]},)" + a + "}"),
      "ray.origin[0]: 1e+19 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(
      errorOf(R"({"id":1,"op":"raycast","ray":{"origin":[0,0],"translation":[1,2e9]},)" + a + "}"),
      "ray.translation[1]: 2e+09 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(
      errorOf(R"({"id":1,"op":"raycast","ray":{"origin":[0,"x"],"translation":[1,0]},)" + a + "}"),
      "ray.origin[1]: must be a number");
  EXPECT_EQ(
      errorOf(R"({"id":1,"op":"raycast","b":{"type":"circle","radius":1},)" + ray + "," + a + "}"),
      "b: not used by op raycast (the ray meets a only)");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"raycast","pb":{},)" + ray + "," + a + "}"),
            "pb: not used by op raycast (the ray meets a only)");
  EXPECT_EQ(
      errorOf(R"({"id":1,"op":"distance","b":{"type":"circle","radius":1},)" + ray + "," + a + "}"),
      "ray: only for op raycast");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"raycast","translation":[1,0],)" + ray + "," + a + "}"),
            "translation: only for op shapecast");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"raycast","pa":{"pos":[2e9,0]},)" + ray + "," + a + "}"),
            "pa.pos[0]: 2e+09 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"raycast","a":{"type":"circle","radius":-1},)" + ray + "}"),
            "a.radius: must be > 0");
}

TEST(QueryRayCast, AFarShapeAndRayGiveFiniteAnswers) {
  // At the coordinate limit: a hit, and every number finite (finished() refuses otherwise).
  json circle = {{"type", "circle"}, {"radius", 1}};
  QueryAnswer a = answerQuery(rayQuery(circle, {{"pos", {1e9, 1e9}}}, {0, 0}, {1e9f, 1e9f}).dump());
  ASSERT_TRUE(a.ok) << a.answer;
  EXPECT_TRUE(json::parse(a.answer)["hit"].get<bool>());
  EXPECT_TRUE(firstNonFiniteField(json::parse(a.answer)).empty());
}

}  // namespace
}  // namespace quack::app
