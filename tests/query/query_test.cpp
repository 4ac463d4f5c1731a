// The query answers and the shape/pose parsing behind them.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "quack/io/shape_json.hpp"
#include "query.hpp"

namespace quack::app {
namespace {

using nlohmann::json;

TEST(ShapeJson, DefaultsAndErrorsNameTheField) {
  Result<ParsedShape> c = parseShape(json::parse(R"({"type":"circle","radius":2})"), "a");
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c->circle.radius, 2.0f);
  Result<ParsedShape> bad =
      parseShape(json::parse(R"({"type":"capsule","p1":[0,0],"p2":[1,0]})"), "b");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "b.radius: missing");
  Result<Transform> pose = parsePose(json::parse(R"({"angle":1.5})"), "pa");
  ASSERT_TRUE(pose.ok());
  EXPECT_EQ(pose->p, (Vec2{0, 0}));
  Result<Transform> badPose = parsePose(json::parse(R"({"pos":[0,0],"spin":1})"), "pa");
  ASSERT_FALSE(badPose.ok());
  EXPECT_EQ(badPose.error().message, "pa.spin: unknown key");
  Result<ParsedShape> nan = parseShape(json::parse(R"({"type":"box","half":[1,1e300]})"), "a");
  ASSERT_FALSE(nan.ok());
  EXPECT_EQ(nan.error().message, "a.half[1]: must be finite (as a float)");
}

TEST(Query, DistanceAnswerCarriesTheId) {
  QueryAnswer a = answerQuery(
      R"({"id":"x","op":"distance","a":{"type":"circle","radius":1},"b":{"type":"circle","radius":1},"pb":{"pos":[5,0]}})");
  ASSERT_TRUE(a.ok);
  json j = json::parse(a.answer);
  EXPECT_EQ(j["id"], "x");
  EXPECT_NEAR(j["distance"].get<double>(), 3.0, 1e-6);
  EXPECT_EQ(j["status"], "repeated_support");
}

TEST(Query, BadLinesGetAnErrorAndTheBatchGoesOn) {
  std::istringstream in(
      "{\"id\":1,\"op\":\"overlap\",\"a\":{\"type\":\"circle\",\"radius\":1},\"b\":{\"type\":"
      "\"circle\",\"radius\":1}}\n"
      "{\"id\":2,\"op\":\"overlap\"}\n"
      "\n"
      "{\"id\":3,\"op\":\"overlap\",\"a\":{\"type\":\"circle\",\"radius\":1},\"b\":{\"type\":"
      "\"circle\",\"radius\":1},\"pb\":{\"pos\":[3,0]}}\n");
  std::ostringstream out;
  EXPECT_EQ(runQueries(in, out), 1);
  EXPECT_EQ(out.str(),
            "{\"id\":1,\"overlap\":true}\n{\"error\":\"a: missing\",\"id\":2}\n"
            "{\"id\":3,\"overlap\":false}\n");
}

TEST(Query, ManifoldOfABoxRestingOnABox) {
  QueryAnswer a = answerQuery(
      R"({"id":7,"op":"manifold","a":{"type":"box","half":[5,0.5]},"b":{"type":"box","half":[0.5,0.5]},"pb":{"pos":[1,0.99]}})");
  ASSERT_TRUE(a.ok) << a.answer;
  json j = json::parse(a.answer);
  EXPECT_EQ(j["id"], 7);
  EXPECT_NEAR(j["normal"][0].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(j["normal"][1].get<double>(), 1.0, 1e-6);
  ASSERT_EQ(j["points"].size(), 2u);
  for (const json& p : j["points"]) {
    EXPECT_NEAR(p["separation"].get<double>(), -0.01, 1e-5);
    EXPECT_NEAR(p["point"][1].get<double>(), 0.495, 1e-5);
    EXPECT_TRUE(p["id"].is_number_unsigned());
  }
  // Apart by more than the speculative distance: no points; a wider one finds them.
  QueryAnswer apart = answerQuery(
      R"({"id":8,"op":"manifold","a":{"type":"circle","radius":1},"b":{"type":"circle","radius":1},"pb":{"pos":[2.5,0]}})");
  ASSERT_TRUE(apart.ok);
  EXPECT_EQ(json::parse(apart.answer)["points"].size(), 0u);
  QueryAnswer wide = answerQuery(
      R"({"id":9,"op":"manifold","speculative":1,"a":{"type":"circle","radius":1},"b":{"type":"circle","radius":1},"pb":{"pos":[2.5,0]}})");
  ASSERT_TRUE(wide.ok);
  json w = json::parse(wide.answer);
  ASSERT_EQ(w["points"].size(), 1u);
  EXPECT_NEAR(w["points"][0]["separation"].get<double>(), 0.5, 1e-6);
  QueryAnswer bad = answerQuery(
      R"({"id":10,"op":"manifold","speculative":-1,"a":{"type":"circle","radius":1},"b":{"type":"circle","radius":1}})");
  EXPECT_FALSE(bad.ok);
  EXPECT_EQ(json::parse(bad.answer)["error"], "speculative: must be a finite number >= 0");
  QueryAnswer misplaced = answerQuery(
      R"({"id":11,"op":"distance","speculative":1,"a":{"type":"circle","radius":1},"b":{"type":"circle","radius":1}})");
  EXPECT_FALSE(misplaced.ok);
}

TEST(Query, ShapeCastHitMissAndOverlap) {
  QueryAnswer a = answerQuery(
      R"({"id":20,"op":"shapecast","a":{"type":"circle","radius":1},"b":{"type":"circle","radius":0.5},"pb":{"pos":[5,0]},"translation":[-10,0]})");
  ASSERT_TRUE(a.ok) << a.answer;
  json j = json::parse(a.answer);
  EXPECT_EQ(j["status"], "hit");
  EXPECT_EQ(j["hit"], true);
  EXPECT_NEAR(j["fraction"].get<double>(), 0.35, 1e-4);
  EXPECT_NEAR(j["normal"][0].get<double>(), 1.0, 1e-6);
  EXPECT_NEAR(j["point"][0].get<double>(), 1.0, 1e-4);
  QueryAnswer miss = answerQuery(
      R"({"id":21,"op":"shapecast","a":{"type":"circle","radius":1},"b":{"type":"circle","radius":0.5},"pb":{"pos":[5,0]},"translation":[10,0]})");
  ASSERT_TRUE(miss.ok);
  EXPECT_EQ(json::parse(miss.answer)["status"], "missed");
  EXPECT_EQ(json::parse(miss.answer)["hit"], false);
  // Overlapping from the start: a defined answer, with a unit normal and the depth.
  QueryAnswer over = answerQuery(
      R"({"id":22,"op":"shapecast","a":{"type":"box","half":[1,1]},"b":{"type":"box","half":[0.5,0.5]},"pb":{"pos":[1.2,0.1]},"translation":[-1,0]})");
  ASSERT_TRUE(over.ok);
  json o = json::parse(over.answer);
  EXPECT_EQ(o["status"], "overlapped");
  EXPECT_NEAR(o["normal"][0].get<double>(), 1.0, 1e-6);
  EXPECT_NEAR(o["depth"].get<double>(), 0.3, 1e-5);
}

TEST(Query, ToiOfACircleThroughABox) {
  QueryAnswer a = answerQuery(
      R"({"id":30,"op":"toi","a":{"type":"box","half":[1,1]},"b":{"type":"circle","radius":0.5},"sweepA":{"from":{"pos":[0,0]},"to":{"pos":[0,0]}},"sweepB":{"from":{"pos":[-5,0.3]},"to":{"pos":[5,0.3],"angle":1}}})");
  ASSERT_TRUE(a.ok) << a.answer;
  json j = json::parse(a.answer);
  EXPECT_EQ(j["status"], "hit");
  EXPECT_NEAR(j["t"].get<double>(), (3.5 - 0.005) / 10.0, 2e-4);
  QueryAnswer touching = answerQuery(
      R"({"id":31,"op":"toi","target":0,"a":{"type":"box","half":[1,1]},"b":{"type":"circle","radius":0.5},"sweepA":{"from":{"pos":[0,0]},"to":{"pos":[0,0]}},"sweepB":{"from":{"pos":[-5,0.3]},"to":{"pos":[5,0.3]}}})");
  ASSERT_TRUE(touching.ok) << touching.answer;
  EXPECT_NEAR(json::parse(touching.answer)["t"].get<double>(), 0.35, 2e-5);
  QueryAnswer apart = answerQuery(
      R"({"id":32,"op":"toi","a":{"type":"circle","radius":1},"b":{"type":"circle","radius":1},"sweepA":{"from":{"pos":[0,0]},"to":{"pos":[0,0]}},"sweepB":{"from":{"pos":[-5,3]},"to":{"pos":[5,3]}}})");
  ASSERT_TRUE(apart.ok);
  EXPECT_EQ(json::parse(apart.answer)["status"], "separated");
  EXPECT_EQ(json::parse(apart.answer)["t"], 1.0);
}

TEST(Query, ShapeCastAndToiErrorsNameTheField) {
  auto error = [](const std::string& line) {
    QueryAnswer a = answerQuery(line);
    EXPECT_FALSE(a.ok) << line;
    return json::parse(a.answer)["error"].get<std::string>();
  };
  const std::string circles =
      R"("a":{"type":"circle","radius":1},"b":{"type":"circle","radius":1})";
  EXPECT_EQ(error(R"({"id":1,"op":"shapecast",)" + circles + "}"), "translation: missing");
  EXPECT_EQ(error(R"({"id":1,"op":"shapecast","translation":[1],)" + circles + "}"),
            "translation: must be [x, y]");
  EXPECT_EQ(error(R"({"id":1,"op":"distance","translation":[1,0],)" + circles + "}"),
            "translation: only for op shapecast");
  EXPECT_EQ(error(R"({"id":1,"op":"toi",)" + circles + "}"), "sweepA: missing");
  EXPECT_EQ(error(R"({"id":1,"op":"toi","sweepA":{"from":{}},)" + circles + "}"),
            "sweepA.to: missing");
  EXPECT_EQ(error(R"({"id":1,"op":"toi","sweepA":{"from":{},"to":{},"via":{}},)" + circles + "}"),
            "sweepA.via: unknown key");
  EXPECT_EQ(
      error(
          R"({"id":1,"op":"toi","sweepA":{"from":{},"to":{}},"sweepB":{"from":{"pos":[1e300,0]},"to":{}},)" +
          circles + "}"),
      "sweepB.from.pos[0]: must be finite (as a float)");
  EXPECT_EQ(
      error(
          R"({"id":1,"op":"toi","target":-1,"sweepA":{"from":{},"to":{}},"sweepB":{"from":{},"to":{}},)" +
          circles + "}"),
      "target: must be a finite number >= 0");
  EXPECT_EQ(
      error(
          R"({"id":1,"op":"toi","pa":{},"sweepA":{"from":{},"to":{}},"sweepB":{"from":{},"to":{}},)" +
          circles + "}"),
      "pa: not used by op toi (give sweepA and sweepB)");
  EXPECT_EQ(error(R"({"id":1,"op":"overlap","sweepB":{},)" + circles + "}"),
            "sweepB: only for op toi");
}

}  // namespace
}  // namespace quack::app
