// The query answers and the shape/pose parsing behind them.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <streambuf>

#include "quack/geometry/mass.hpp"
#include "quack/io/shape_json.hpp"
#include "query.hpp"

namespace quack::app {
namespace {

using nlohmann::json;

TEST(ShapeJson, DefaultsAndErrorsNameTheField) {
  Result<ShapeGeometry> c = parseShape(json::parse(R"({"type":"circle","radius":2})"), "a");
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(std::get<Circle>(*c).radius, 2.0f);
  Result<ShapeGeometry> bad =
      parseShape(json::parse(R"({"type":"capsule","p1":[0,0],"p2":[1,0]})"), "b");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "b.radius: missing");
  Result<Transform> pose = parsePose(json::parse(R"({"angle":1.5})"), "pa");
  ASSERT_TRUE(pose.ok());
  EXPECT_EQ(pose->p, (Vec2{0, 0}));
  Result<Transform> badPose = parsePose(json::parse(R"({"pos":[0,0],"spin":1})"), "pa");
  ASSERT_FALSE(badPose.ok());
  EXPECT_EQ(badPose.error().message, "pa.spin: unknown key");
  Result<ShapeGeometry> nan = parseShape(json::parse(R"({"type":"box","half":[1,1e300]})"), "a");
  ASSERT_FALSE(nan.ok());
  EXPECT_EQ(nan.error().message, "a.half[1]: must be finite (as a float)");
}

TEST(ShapeJson, ConcaveShapesAreReadAsPieces) {
  const json l =
      json::parse(R"({"type":"concave","points":[[0,0],[2,0],[2,1],[1,1],[1,2],[0,2]]})");
  Result<ShapeGeometry> one = parseShape(l, "a");
  ASSERT_FALSE(one.ok());
  EXPECT_EQ(one.error().message,
            "a.type: a concave shape is several convex pieces; read it with parseShapePieces");
  Result<std::vector<ShapeGeometry>> pieces = parseShapePieces(l, "a");
  ASSERT_TRUE(pieces.ok());
  ASSERT_GE(pieces->size(), 2u);
  float area = 0.0f;
  for (const ShapeGeometry& g : *pieces) {
    ASSERT_EQ(shapeType(g), ShapeType::polygon);
    EXPECT_TRUE(validateShape(g).ok());
    area += computeMass(g, 1.0f).area;
  }
  EXPECT_NEAR(area, 3.0f, 1e-5f);
  Result<std::vector<ShapeGeometry>> box =
      parseShapePieces(json::parse(R"({"type":"box","half":[1,2]})"), "b");
  ASSERT_TRUE(box.ok());
  ASSERT_EQ(box->size(), 1u);
  EXPECT_EQ(shapeType(box->front()), ShapeType::polygon);
  Result<std::vector<ShapeGeometry>> unknown =
      parseShapePieces(json::parse(R"({"type":"ellipse"})"), "b");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().message,
            "b.type: unknown shape type \"ellipse\" (expected circle, capsule, segment, box, "
            "polygon, concave)");
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
  EXPECT_EQ(runQueries(in, out), 2);
  EXPECT_EQ(out.str(),
            "{\"id\":1,\"overlap\":true}\n{\"error\":\"a: missing\",\"id\":2}\n"
            "{\"error\":\"line 3 is blank\",\"id\":null}\n{\"id\":3,\"overlap\":false}\n");
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
  EXPECT_EQ(json::parse(bad.answer)["error"],
            "speculative: must be a number >= 0 within the coordinate limit 1e9 m");
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
      "target: must be a number >= 0 within the coordinate limit 1e9 m");
  EXPECT_EQ(
      error(
          R"({"id":1,"op":"toi","pa":{},"sweepA":{"from":{},"to":{}},"sweepB":{"from":{},"to":{}},)" +
          circles + "}"),
      "pa: not used by op toi (give sweepA and sweepB)");
  EXPECT_EQ(error(R"({"id":1,"op":"overlap","sweepB":{},)" + circles + "}"),
            "sweepB: only for op toi");
}

// ---- Hardening (the hardening issue): each test is named after the defect it pins down.

std::string errorOf(const std::string& line) {
  QueryAnswer a = answerQuery(line);
  EXPECT_FALSE(a.ok) << line << " -> " << a.answer;
  json j = json::parse(a.answer);
  return j["error"].is_string() ? j["error"].get<std::string>() : "";
}

const std::string kCircles = R"("a":{"type":"circle","radius":1},"b":{"type":"circle","radius":1})";

TEST(QueryHardening, DeeplyNestedIdIsRefused) {
  // An id nested 70,000 deep overflowed the stack when the answer echoed it. The line is
  // refused before parsing, naming the limit, and the next line is still answered.
  const std::string deep = "{\"id\":" + std::string(70000, '[') + std::string(70000, ']') +
                           ",\"op\":\"overlap\"," + kCircles + "}";
  const std::string ok = "{\"id\":2,\"op\":\"overlap\"," + kCircles + "}";
  std::istringstream in(deep + "\n" + ok + "\n");
  std::ostringstream out;
  EXPECT_EQ(runQueries(in, out), 1);
  EXPECT_EQ(out.str(),
            "{\"error\":\"line nests [ and { deeper than the limit of 64 levels\",\"id\":null}\n"
            "{\"id\":2,\"overlap\":true}\n");
  // Just past the limit is refused; at the limit (brackets inside strings do not count) the
  // line is answered, echoing its id.
  const std::string at =
      std::string(kMaxQueryNesting - 1, '[') + std::string(kMaxQueryNesting - 1, ']');
  QueryAnswer fine =
      answerQuery("{\"id\":" + at + ",\"op\":\"overlap\",\"x\":\"[[[[{{{{\"," + kCircles + "}");
  EXPECT_EQ(json::parse(fine.answer)["error"], "x: unknown key");
  EXPECT_EQ(errorOf("{\"id\":[" + at + "]" + ",\"op\":\"overlap\"," + kCircles + "}"),
            "line nests [ and { deeper than the limit of 64 levels");
}

TEST(QueryHardening, FarApartCirclesAreRefusedNotOverlapping) {
  // Two unit circles 2e19 m apart were reported overlapping with depth 2.
  EXPECT_EQ(errorOf(R"({"id":1,"op":"penetration",)" + kCircles +
                    R"(,"pa":{"pos":[-1e19,0]},"pb":{"pos":[1e19,0]}})"),
            "pa.pos[0]: -1e+19 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"overlap",)" + kCircles + R"(,"pb":{"pos":[0,2e9]}})"),
            "pb.pos[1]: 2e+09 m is beyond the coordinate limit 1e9 m");
  // At the limit it is answered.
  QueryAnswer edge = answerQuery(R"({"id":1,"op":"overlap",)" + kCircles +
                                 R"(,"pa":{"pos":[1e9,-1e9]},"pb":{"pos":[1e9,-1e9]}})");
  EXPECT_TRUE(edge.ok) << edge.answer;
}

TEST(QueryHardening, HugeShapesAreRefusedNamingTheField) {
  // Shapes at +-3e38 gave null witness points, a box of half-size 3e38 a null normal.
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"distance","a":{"type":"circle","radius":1,"center":[3e38,0]},"b":{"type":"circle","radius":1,"center":[-3e38,0]}})"),
      "a.center[0]: 3e+38 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"penetration","a":{"type":"box","half":[3e38,3e38]},"b":{"type":"circle","radius":1}})"),
      "a.half[0]: 3e+38 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"distance","a":{"type":"circle","radius":1},"b":{"type":"circle","radius":2e9}})"),
      "b.radius: 2e+09 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"distance","a":{"type":"polygon","points":[[0,0],[1,0],[0,-5e9]]},"b":{"type":"circle","radius":1}})"),
      "a.points[2][1]: -5e+09 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"distance","a":{"type":"capsule","p1":[0,0],"p2":[1e10,0],"radius":1},"b":{"type":"circle","radius":1}})"),
      "a.p2[0]: 1e+10 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"overlap","a":{"type":"concave","points":[[0,0],[4,0],[4,1],[1,1],[1,4e9],[0,4]]},"b":{"type":"circle","radius":1}})"),
      "a.points[4][1]: 4e+09 m is beyond the coordinate limit 1e9 m");
  // Translations and sweeps too.
  EXPECT_EQ(errorOf(R"({"id":1,"op":"shapecast","translation":[1e19,0],)" + kCircles + "}"),
            "translation[0]: 1e+19 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"toi","sweepA":{"from":{},"to":{"pos":[0,-3e38]}},"sweepB":{"from":{},"to":{}},)" +
          kCircles + "}"),
      "sweepA.to.pos[1]: -3e+38 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"manifold","speculative":1e30,)" + kCircles + "}"),
            "speculative: must be a number >= 0 within the coordinate limit 1e9 m");
}

TEST(QueryHardening, HugeBoxSaysTheCoordinateLimitNotConvexity) {
  // A box of half-size 1e19 said "hull is not strictly convex".
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"distance","a":{"type":"box","half":[1e19,1e19]},"b":{"type":"circle","radius":1}})"),
      "a.half[0]: 1e+19 m is beyond the coordinate limit 1e9 m");
}

TEST(QueryHardening, NanometreBoxIsRefused) {
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"distance","a":{"type":"box","half":[1e-25,1e-25]},"b":{"type":"circle","radius":1}})"),
      "a: box side 2e-25 m is below the smallest size Quack resolves (1e-09 m)");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"distance","a":{"type":"circle","radius":1e-25},"b":{"type":"circle","radius":1}})"),
      "a: circle diameter 2e-25 m is below the smallest size Quack resolves (1e-09 m)");
}

TEST(QueryHardening, NonFiniteAnswersAreRefusedNotPrintedAsNull) {
  // The last check before printing: any NaN or infinity makes the line an error.
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(firstNonFiniteField(json{{"id", 1}, {"distance", 2.0}}), "");
  EXPECT_EQ(firstNonFiniteField(json{{"id", 1}, {"normal", {0.0, inf}}}), "normal[1]");
  EXPECT_EQ(
      firstNonFiniteField(json{{"points", json::array({json{{"separation", std::nan("")}}})}}),
      "points[0].separation");
  // And every answer to the committed cases is finite.
  std::istringstream in(
      R"({"id":1,"op":"penetration","a":{"type":"box","half":[1e9,1e9]},"b":{"type":"box","half":[1e9,1e9]},"pb":{"pos":[1e9,1e9],"angle":3e38}})"
      "\n"
      R"({"id":2,"op":"shapecast","a":{"type":"circle","radius":1e9},"b":{"type":"circle","radius":1e-9},"pb":{"pos":[-1e9,1e9]},"translation":[1e9,-1e9]})"
      "\n");
  std::ostringstream out;
  runQueries(in, out);
  std::istringstream lines(out.str());
  std::string line;
  while (std::getline(lines, line)) {
    EXPECT_EQ(line.find("null"), std::string::npos) << line;
    EXPECT_EQ(firstNonFiniteField(json::parse(line)), "") << line;
  }
}

TEST(QueryHardening, OutOfRangeNumberNamesTheFieldAndByte) {
  // 1e400 said only "line is not valid JSON".
  const std::string line = R"({"id":1,"op":"overlap",)" + kCircles + R"(,"pb":{"pos":[1e400,0]}})";
  EXPECT_EQ(errorOf(line), "pb.pos[0]: number 1e400 is out of range (beyond a double) at byte " +
                               std::to_string(line.find("1e400") + 1));
  // A syntax error gives the byte, the field being read and the parser's reason.
  const std::string broken = R"({"id":1,"op":"overlap","a":{"type":"circle" "radius":1}})";
  const std::string e = errorOf(broken);
  EXPECT_EQ(e.rfind("line is not valid JSON at byte 45 (near a.type): syntax error", 0), 0u) << e;
  EXPECT_EQ(errorOf("not json").rfind("line is not valid JSON at byte 1: syntax error", 0), 0u);
}

TEST(QueryHardening, InvalidUtf8InAnErrorIsReplacedNotThrown) {
  // The parser's "last read" bytes are echoed in the message; invalid UTF-8 there must not
  // make the serializer throw.
  QueryAnswer a = answerQuery("{\"id\":\"\xff\xfe\"}");
  EXPECT_FALSE(a.ok);
  EXPECT_TRUE(json::accept(a.answer)) << a.answer;
}

TEST(QueryHardening, BlankLinesAreAnsweredSoLineNAnswersLineN) {
  std::istringstream in("\n" + std::string("{\"id\":5,\"op\":\"overlap\",") + kCircles +
                        "}\n  \t\r\n");
  std::ostringstream out;
  EXPECT_EQ(runQueries(in, out), 2);
  EXPECT_EQ(out.str(),
            "{\"error\":\"line 1 is blank\",\"id\":null}\n{\"id\":5,\"overlap\":true}\n"
            "{\"error\":\"line 3 is blank\",\"id\":null}\n");
}

// A stream buffer that refuses every byte, as a full disk does.
class FullDisk : public std::streambuf {
 protected:
  int_type overflow(int_type) override { return traits_type::eof(); }
  std::streamsize xsputn(const char*, std::streamsize) override { return 0; }
};

TEST(QueryHardening, DirectoryArgumentIsAnError) {
  std::istringstream none;
  std::ostringstream out, err;
  EXPECT_EQ(runQueryCommand(QUACK_QUERY_TEST_DIR, none, out, err), 2);
  EXPECT_EQ(err.str(),
            std::string("quack query: cannot read ") + QUACK_QUERY_TEST_DIR + ": Is a directory\n");
  EXPECT_EQ(out.str(), "");
  std::ostringstream err2;
  EXPECT_EQ(runQueryCommand("/no/such/file.jsonl", none, out, err2), 2);
  EXPECT_EQ(err2.str(),
            "quack query: cannot open /no/such/file.jsonl: No such file or directory\n");
}

TEST(QueryHardening, WriteFailureIsAnError) {
  std::istringstream in("{\"id\":1,\"op\":\"overlap\"," + kCircles + "}\n");
  FullDisk full;
  std::ostream out(&full);
  std::ostringstream err;
  EXPECT_EQ(runQueryCommand("-", in, out, err), 2);
  EXPECT_EQ(err.str().rfind("quack query: cannot write the answers to standard output", 0), 0u)
      << err.str();
}

}  // namespace
}  // namespace quack::app
