// The query answers and the shape/pose parsing behind them.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "query.hpp"
#include "shape_json.hpp"

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

}  // namespace
}  // namespace quack::app
