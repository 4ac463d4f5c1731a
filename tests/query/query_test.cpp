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

}  // namespace
}  // namespace quack::app
