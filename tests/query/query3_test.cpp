// `quack query` in 3D: hand-worked answers, the 3D shape and pose parsing, the errors, and
// the program's output compared with the library called directly.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "quack/collision/epa3.hpp"
#include "quack/collision/gjk3.hpp"
#include "quack/collision/manifold3.hpp"
#include "quack/collision/mesh3.hpp"
#include "quack/collision/toi3.hpp"
#include "quack/geometry/raycast3.hpp"
#include "quack/io/answer_json.hpp"
#include "quack/io/shape_json.hpp"
#include "query.hpp"

namespace quack::app {
namespace {

using nlohmann::json;

json answerOk(const std::string& line) {
  QueryAnswer a = answerQuery(line);
  EXPECT_TRUE(a.ok) << line << " -> " << a.answer;
  return json::parse(a.answer);
}

std::string errorOf(const std::string& line) {
  QueryAnswer a = answerQuery(line);
  EXPECT_FALSE(a.ok) << line << " -> " << a.answer;
  json j = json::parse(a.answer);
  return j["error"].is_string() ? j["error"].get<std::string>() : "";
}

void expectVec3(const json& v, double x, double y, double z, double tolerance) {
  ASSERT_TRUE(v.is_array()) << v;
  ASSERT_EQ(v.size(), 3u) << v;
  EXPECT_NEAR(v[0].get<double>(), x, tolerance) << v;
  EXPECT_NEAR(v[1].get<double>(), y, tolerance) << v;
  EXPECT_NEAR(v[2].get<double>(), z, tolerance) << v;
}

TEST(ShapeJson3, DimensionOfEachShape) {
  EXPECT_EQ(shapeDimension(json::parse(R"({"type":"sphere","radius":1})")), 3);
  EXPECT_EQ(shapeDimension(json::parse(R"({"type":"hull","points":[]})")), 3);
  EXPECT_EQ(shapeDimension(json::parse(R"({"type":"triangle"})")), 3);
  EXPECT_EQ(shapeDimension(json::parse(R"({"type":"box","half":[1,1,1]})")), 3);
  EXPECT_EQ(shapeDimension(json::parse(R"({"type":"box","half":[1,1]})")), 2);
  EXPECT_EQ(shapeDimension(json::parse(R"({"type":"capsule","p1":[0,0,0]})")), 3);
  EXPECT_EQ(shapeDimension(json::parse(R"({"type":"capsule","p1":[0,0]})")), 2);
  EXPECT_EQ(shapeDimension(json::parse(R"({"type":"circle","radius":1})")), 2);
  EXPECT_EQ(shapeDimension(json::parse(R"({"type":"torus"})")), 0);
  EXPECT_EQ(shapeDimension(json::parse("[1, 2]")), 0);
}

TEST(ShapeJson3, ShapesAndPosesAreParsed) {
  Result<ShapeGeometry3> sphere =
      parseShape3(json::parse(R"({"type":"sphere","center":[1,2,3],"radius":0.5})"), "a");
  ASSERT_TRUE(sphere.ok()) << sphere.error().message;
  ASSERT_EQ(shapeType(*sphere), ShapeType3::sphere);
  EXPECT_EQ(std::get<Sphere>(*sphere).center, (Vec3{1, 2, 3}));
  EXPECT_EQ(std::get<Sphere>(*sphere).radius, 0.5f);

  Result<ShapeGeometry3> box = parseShape3(json::parse(R"({"type":"box","half":[1,2,3]})"), "a");
  ASSERT_TRUE(box.ok()) << box.error().message;
  ASSERT_EQ(shapeType(*box), ShapeType3::hull);
  EXPECT_EQ(std::get<Hull3>(*box).vertexCount, 8);

  // A cube's corners with its centre and a duplicate: a hull of 8 vertices.
  Result<ShapeGeometry3> hull = parseShape3(
      json::parse(
          R"({"type":"hull","points":[[0,0,0],[1,0,0],[0,1,0],[1,1,0],[0,0,1],[1,0,1],[0,1,1],[1,1,1],[0.5,0.5,0.5],[1,1,1]],"radius":0})"),
      "b");
  ASSERT_TRUE(hull.ok()) << hull.error().message;
  EXPECT_EQ(std::get<Hull3>(*hull).vertexCount, 8);

  // Rounded: the radius is kept; a box's too.
  Result<ShapeGeometry3> rounded = parseShape3(
      json::parse(R"({"type":"hull","points":[[0,0,0],[1,0,0],[0,1,0],[0,0,1]],"radius":0.25})"),
      "b");
  ASSERT_TRUE(rounded.ok()) << rounded.error().message;
  EXPECT_EQ(std::get<Hull3>(*rounded).radius, 0.25f);
  EXPECT_EQ(std::get<Hull3>(*hull).radius, 0.0f);
  Result<ShapeGeometry3> roundedBox =
      parseShape3(json::parse(R"({"type":"box","half":[1,2,3],"radius":0.5})"), "a");
  ASSERT_TRUE(roundedBox.ok()) << roundedBox.error().message;
  EXPECT_EQ(std::get<Hull3>(*roundedBox).radius, 0.5f);

  Result<ShapeGeometry3> triangle =
      parseShape3(json::parse(R"({"type":"triangle","points":[[0,0,0],[1,0,0],[0,0,-1]]})"), "b");
  ASSERT_TRUE(triangle.ok()) << triangle.error().message;
  EXPECT_EQ(triangleNormal(std::get<Triangle3>(*triangle)), (Vec3{0, 1, 0}));

  // The quaternion is normalised: [0, 0, 2, 2] is 90 degrees about z.
  Result<Transform3> pose = parsePose3(json::parse(R"({"pos":[1,2,3],"quat":[0,0,2,2]})"), "pa");
  ASSERT_TRUE(pose.ok()) << pose.error().message;
  EXPECT_EQ(pose->p, (Vec3{1, 2, 3}));
  EXPECT_NEAR(pose->q.z, std::sqrt(0.5), 1e-7);
  EXPECT_NEAR(pose->q.w, std::sqrt(0.5), 1e-7);
  Vec3 turned = rotate(pose->q, Vec3{1, 0, 0});
  EXPECT_NEAR(turned.x, 0.0, 1e-6);
  EXPECT_NEAR(turned.y, 1.0, 1e-6);
  // A tiny but non-zero quaternion normalises too (in double).
  Result<Transform3> tiny = parsePose3(json::parse(R"({"quat":[0,0,0,1e-40]})"), "pa");
  ASSERT_TRUE(tiny.ok()) << tiny.error().message;
  EXPECT_EQ(tiny->q, (Quat{0, 0, 0, 1}));
  Result<Transform3> identity = parsePose3(json::parse("{}"), "pa");
  ASSERT_TRUE(identity.ok());
  EXPECT_EQ(*identity, Transform3{});
}

TEST(ShapeJson3, ErrorsNameTheField) {
  auto shapeError = [](const std::string& text) {
    Result<ShapeGeometry3> s = parseShape3(json::parse(text), "a");
    EXPECT_FALSE(s.ok()) << text;
    return s.ok() ? std::string() : s.error().message;
  };
  EXPECT_EQ(shapeError(R"({"type":"sphere"})"), "a.radius: missing");
  EXPECT_EQ(shapeError(R"({"type":"sphere","radius":0})"), "a.radius: must be > 0");
  EXPECT_EQ(shapeError(R"({"type":"sphere","radius":1,"center":[0,0]})"),
            "a.center: must be [x, y, z]");
  EXPECT_EQ(shapeError(R"({"type":"sphere","radius":1,"colour":1})"), "a.colour: unknown key");
  EXPECT_EQ(shapeError(R"({"type":"box","half":[1,1,1e300]})"),
            "a.half[2]: must be finite (as a float)");
  EXPECT_EQ(shapeError(R"({"type":"box","half":[1,-1,1]})"), "a.half: must be > 0");
  EXPECT_EQ(shapeError(R"({"type":"box","half":[1,1,2e19]})"),
            "a.half[2]: 2e+19 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(shapeError(R"({"type":"box","half":[1,1,1],"angle":1})"),
            "a.angle: a 3D box turns by \"quat\": [x, y, z, w], not by an angle");
  EXPECT_EQ(shapeError(R"({"type":"hull","points":[[0,0,0],[1,0,0],[0,1,0]]})"),
            "a.points: needs at least 4 points");
  const std::string tetra = R"("type":"hull","points":[[0,0,0],[1,0,0],[0,1,0],[0,0,1]])";
  EXPECT_EQ(shapeError("{" + tetra + R"(,"radius":-0.1})"), "a.radius: must be >= 0");
  EXPECT_EQ(shapeError("{" + tetra + R"(,"radius":1e300})"),
            "a.radius: must be finite (as a float)");
  EXPECT_EQ(shapeError("{" + tetra + R"(,"radius":"0.1"})"), "a.radius: must be a number");
  EXPECT_EQ(shapeError("{" + tetra + R"(,"radius":2e9})"),
            "a.radius: 2e+09 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(shapeError(R"({"type":"box","half":[1,1,1],"radius":-1})"), "a.radius: must be >= 0");
  EXPECT_EQ(shapeError(R"({"type":"hull","points":[[0,0,0],[1,0,0],[0,1,0],[0,0,1,4]]})"),
            "a.points[3]: must be [x, y, z]");
  // Coplanar points: the quickhull's own message, labelled with the field.
  const std::string flat =
      shapeError(R"({"type":"hull","points":[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]})");
  EXPECT_EQ(flat.rfind("a: ", 0), 0u) << flat;
  EXPECT_EQ(shapeError(R"({"type":"triangle","points":[[0,0,0],[1,0,0]]})"),
            "a.points: needs exactly 3 points");
  const std::string collinear =
      shapeError(R"({"type":"triangle","points":[[0,0,0],[1,0,0],[2,0,0]]})");
  EXPECT_EQ(collinear.rfind("a: triangle", 0), 0u) << collinear;
  EXPECT_EQ(shapeError(R"({"type":"circle","radius":1})"),
            "a.type: \"circle\" is a 2D shape (in 3D: sphere, capsule, box, hull, triangle)");
  EXPECT_EQ(shapeError(R"({"type":"cone"})"),
            "a.type: unknown shape type \"cone\" (expected sphere, capsule, box, hull, triangle in "
            "3D)");

  auto poseError = [](const char* text) {
    Result<Transform3> p = parsePose3(json::parse(text), "pb");
    EXPECT_FALSE(p.ok()) << text;
    return p.ok() ? std::string() : p.error().message;
  };
  EXPECT_EQ(poseError(R"({"quat":[0,0,0,0]})"),
            "pb.quat: [0, 0, 0, 0] is not a rotation (the zero quaternion; the identity is "
            "[0, 0, 0, 1])");
  EXPECT_EQ(poseError(R"({"quat":[0,0,1e300,1]})"), "pb.quat[2]: must be finite (as a float)");
  EXPECT_EQ(poseError(R"({"quat":[0,0,1]})"), "pb.quat: must be [x, y, z, w] (scalar last)");
  EXPECT_EQ(poseError(R"({"quat":[0,0,"1",1]})"), "pb.quat[2]: must be a number");
  EXPECT_EQ(poseError(R"({"pos":[0,0]})"), "pb.pos: must be [x, y, z]");
  EXPECT_EQ(poseError(R"({"angle":1})"),
            "pb.angle: a 3D pose turns by \"quat\": [x, y, z, w], not by an angle");
  EXPECT_EQ(poseError(R"({"pos":[0,0,0],"spin":1})"), "pb.spin: unknown key");
  EXPECT_EQ(poseError("[0,0,0]"), "pb: must be an object {\"pos\", \"quat\"}");
}

// Two spheres, radii 1 and 0.5, centres 5 m apart along (0.6, 0.8, 0): 3.5 m apart, the
// closest points on the line of centres.
TEST(Query3, DistanceOfTwoSpheres) {
  json j = answerOk(
      R"({"id":"s","op":"distance","a":{"type":"sphere","radius":1},"b":{"type":"sphere","center":[0,0,0],"radius":0.5},"pb":{"pos":[3,4,0]}})");
  EXPECT_EQ(j["id"], "s");
  EXPECT_NEAR(j["distance"].get<double>(), 3.5, 1e-6);
  expectVec3(j["pointA"], 0.6, 0.8, 0.0, 1e-6);
  expectVec3(j["pointB"], 2.7, 3.6, 0.0, 1e-6);
  expectVec3(j["normal"], 0.6, 0.8, 0.0, 1e-6);
  EXPECT_TRUE(j["iterations"].is_number_integer());
  EXPECT_TRUE(j["status"].is_string());
  // Far from the origin, turned: the same answer moved.
  json far = answerOk(
      R"({"op":"distance","a":{"type":"sphere","radius":1},"pa":{"pos":[1e4,0,0],"quat":[0.3,0.1,0.2,0.9]},"b":{"type":"sphere","radius":0.5},"pb":{"pos":[10003,4,0]}})");
  EXPECT_NEAR(far["distance"].get<double>(), 3.5, 1e-3);
  // Overlapping: distance 0; penetration 0.5 deep along the same line.
  json over = answerOk(
      R"({"op":"penetration","a":{"type":"sphere","radius":1},"b":{"type":"sphere","radius":0.5},"pb":{"pos":[0.6,0.8,0]}})");
  EXPECT_EQ(over["overlap"], true);
  EXPECT_NEAR(over["depth"].get<double>(), 0.5, 1e-6);
  expectVec3(over["normal"], 0.6, 0.8, 0.0, 1e-6);
  expectVec3(over["pointA"], 0.6, 0.8, 0.0, 1e-6);
  expectVec3(over["pointB"], 0.3, 0.4, 0.0, 1e-6);
  EXPECT_EQ(
      answerOk(
          R"({"op":"overlap","a":{"type":"sphere","radius":1},"b":{"type":"sphere","radius":0.5},"pb":{"pos":[0,1.4,0]}})")
          ["overlap"],
      true);
  EXPECT_EQ(
      answerOk(
          R"({"op":"overlap","a":{"type":"sphere","radius":1},"b":{"type":"sphere","radius":0.5},"pb":{"pos":[0,1.6,0]}})")
          ["overlap"],
      false);
}

// A unit cube resting 0.01 m deep on a 4 x 1 x 4 slab: four points at the cube's bottom
// corners, each 0.01 deep, midway between the surfaces (y = 0.495), normal up.
TEST(Query3, ManifoldOfABoxOnABox) {
  json j = answerOk(
      R"({"id":7,"op":"manifold","a":{"type":"box","half":[2,0.5,2]},"b":{"type":"box","half":[0.5,0.5,0.5]},"pb":{"pos":[0.3,0.99,-0.2]}})");
  EXPECT_EQ(j["id"], 7);
  expectVec3(j["normal"], 0.0, 1.0, 0.0, 1e-6);
  ASSERT_EQ(j["points"].size(), 4u);
  std::vector<std::uint32_t> ids;
  for (const json& p : j["points"]) {
    EXPECT_NEAR(p["separation"].get<double>(), -0.01, 1e-5);
    EXPECT_NEAR(p["point"][1].get<double>(), 0.495, 1e-5);
    EXPECT_NEAR(std::abs(p["point"][0].get<double>() - 0.3), 0.5, 1e-5);
    EXPECT_NEAR(std::abs(p["point"][2].get<double>() + 0.2), 0.5, 1e-5);
    ids.push_back(p["id"].get<std::uint32_t>());
  }
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(std::unique(ids.begin(), ids.end()), ids.end()) << "feature ids must differ";
  // 1 m apart: no points at the default speculative distance, four with a 2 m one.
  const std::string apart =
      R"("a":{"type":"box","half":[2,0.5,2]},"b":{"type":"box","half":[0.5,0.5,0.5]},"pb":{"pos":[0,2,0]})";
  EXPECT_EQ(answerOk(R"({"op":"manifold",)" + apart + "}")["points"].size(), 0u);
  json wide = answerOk(R"({"op":"manifold","speculative":2,)" + apart + "}");
  ASSERT_EQ(wide["points"].size(), 4u);
  EXPECT_NEAR(wide["points"][0]["separation"].get<double>(), 1.0, 1e-5);
  // The slab turned a quarter turn about y is the same slab.
  json turned = answerOk(
      R"({"op":"manifold","a":{"type":"box","half":[2,0.5,2]},"pa":{"quat":[0,0.7071067811865476,0,0.7071067811865476]},"b":{"type":"box","half":[0.5,0.5,0.5]},"pb":{"pos":[0,0.99,0]}})");
  expectVec3(turned["normal"], 0.0, 1.0, 0.0, 1e-6);
  EXPECT_EQ(turned["points"].size(), 4u);
}

// A 2 m cube centred at z = 5, turned a quarter turn about y: the ray from the origin along
// +z enters its face z = 4 at fraction 0.4, normal -z.
TEST(Query3, RayHitsABoxFace) {
  json j = answerOk(
      R"({"id":3,"op":"raycast","a":{"type":"box","half":[1,1,1]},"pa":{"pos":[0,0,5],"quat":[0,0.7071067811865476,0,0.7071067811865476]},"ray":{"origin":[0.2,-0.3,0],"translation":[0,0,10]}})");
  EXPECT_EQ(j["id"], 3);
  EXPECT_EQ(j["hit"], true);
  EXPECT_NEAR(j["fraction"].get<double>(), 0.4, 1e-6);
  expectVec3(j["point"], 0.2, -0.3, 4.0, 1e-5);
  expectVec3(j["normal"], 0.0, 0.0, -1.0, 1e-6);
  // Too short, or starting inside: no hit, every number 0.
  for (const char* ray : {R"({"origin":[0,0,0],"translation":[0,0,3]})",
                          R"({"origin":[0,0,5],"translation":[0,0,3]})"}) {
    json miss = answerOk(
        std::string(
            R"({"op":"raycast","a":{"type":"box","half":[1,1,1]},"pa":{"pos":[0,0,5]},"ray":)") +
        ray + "}");
    EXPECT_EQ(miss["hit"], false);
    EXPECT_EQ(miss["fraction"], 0.0);
    expectVec3(miss["point"], 0, 0, 0, 0);
    expectVec3(miss["normal"], 0, 0, 0, 0);
  }
}

// A sphere of radius 0.5 falling from y = 5 to y = -5 onto a slab whose top is y = 0.5: its
// centre reaches y = 1 after 4 of the 10 m, and toi stops a linear slop short (0.005 m).
// The slab turns a quarter turn about y meanwhile, which leaves its top where it was.
TEST(Query3, ToiOfASphereFallingOnABox) {
  json j = answerOk(
      R"({"id":30,"op":"toi","a":{"type":"box","half":[5,0.5,5]},"b":{"type":"sphere","radius":0.5},"sweepA":{"from":{},"to":{"quat":[0,0.7071067811865476,0,0.7071067811865476]}},"sweepB":{"from":{"pos":[0,5,0]},"to":{"pos":[0,-5,0]}}})");
  EXPECT_EQ(j["id"], 30);
  EXPECT_EQ(j["status"], "hit");
  EXPECT_NEAR(j["t"].get<double>(), (4.0 - 0.005) / 10.0, 2e-4);
  json touching = answerOk(
      R"({"op":"toi","target":0,"a":{"type":"box","half":[5,0.5,5]},"b":{"type":"sphere","radius":0.5},"sweepA":{"from":{},"to":{}},"sweepB":{"from":{"pos":[0,5,0]},"to":{"pos":[0,-5,0]}}})");
  EXPECT_EQ(touching["status"], "hit");
  // Within the time-of-impact tolerance (kToiTolerance) short of touching.
  EXPECT_LE(touching["t"].get<double>(), 0.4);
  EXPECT_GE(touching["t"].get<double>(), 0.4 - kToiTolerance / 10.0);
  json past = answerOk(
      R"({"op":"toi","a":{"type":"box","half":[5,0.5,5]},"b":{"type":"sphere","radius":0.5},"sweepA":{"from":{},"to":{}},"sweepB":{"from":{"pos":[6,5,0]},"to":{"pos":[6,-5,0]}}})");
  EXPECT_EQ(past["status"], "separated");
  EXPECT_EQ(past["t"], 1.0);
  // The same fall as a shape cast: B moves by the translation.
  json cast = answerOk(
      R"({"op":"shapecast","a":{"type":"box","half":[5,0.5,5]},"b":{"type":"sphere","radius":0.5},"pb":{"pos":[0,5,0]},"translation":[0,-10,0]})");
  EXPECT_EQ(cast["status"], "hit");
  EXPECT_EQ(cast["hit"], true);
  EXPECT_NEAR(cast["fraction"].get<double>(), 0.4, 2e-4);
  expectVec3(cast["normal"], 0.0, 1.0, 0.0, 1e-5);
  expectVec3(cast["point"], 0.0, 0.5, 0.0, 2e-3);
}

// A unit cube [0, 1]^3 rounded by 0.25: a sphere of radius 0.5 centred 2 m above its top
// face's middle is 2 - 0.25 - 0.5 = 1.25 m away; a ray down its middle enters at
// y = 1.25; a rounded box resting 0.01 m deep on a rounded slab has four points midway.
TEST(Query3, RoundedHullHandWorked) {
  const std::string cube =
      R"({"type":"hull","points":[[0,0,0],[1,0,0],[0,1,0],[1,1,0],[0,0,1],[1,0,1],[0,1,1],[1,1,1]],"radius":0.25})";
  json d = answerOk(R"({"op":"distance","a":)" + cube +
                    R"(,"b":{"type":"sphere","radius":0.5},"pb":{"pos":[0.5,3,0.5]}})");
  EXPECT_NEAR(d["distance"].get<double>(), 1.25, 1e-6);
  expectVec3(d["pointA"], 0.5, 1.25, 0.5, 1e-6);
  expectVec3(d["normal"], 0.0, 1.0, 0.0, 1e-6);
  json r = answerOk(R"({"op":"raycast","a":)" + cube +
                    R"(,"ray":{"origin":[0.5,5,0.5],"translation":[0,-10,0]}})");
  EXPECT_EQ(r["hit"], true);
  EXPECT_NEAR(r["fraction"].get<double>(), 0.375, 1e-6);
  json p = answerOk(R"({"op":"penetration","a":)" + cube +
                    R"(,"b":{"type":"sphere","radius":0.5},"pb":{"pos":[0.5,1.7,0.5]}})");
  EXPECT_NEAR(p["depth"].get<double>(), 0.05, 1e-6);
  json m = answerOk(
      R"({"op":"manifold","a":{"type":"box","half":[2,0.5,2],"radius":0.1},"b":{"type":"box","half":[0.5,0.5,0.5],"radius":0.05},"pb":{"pos":[0.3,1.14,-0.2]}})");
  expectVec3(m["normal"], 0.0, 1.0, 0.0, 1e-6);
  ASSERT_EQ(m["points"].size(), 4u);
  for (const json& q : m["points"]) {
    EXPECT_NEAR(q["separation"].get<double>(), -0.01, 1e-5);
    EXPECT_NEAR(q["point"][1].get<double>(), 0.595, 1e-5);
  }
}

TEST(Query3, EveryShapeKindAnswersEveryOp) {
  const std::vector<std::string> shapes = {
      R"({"type":"sphere","center":[0.1,0,0],"radius":0.5})",
      R"({"type":"capsule","p1":[0,-0.5,0],"p2":[0,0.5,0],"radius":0.3})",
      R"({"type":"box","half":[0.5,0.4,0.3],"center":[0,0.1,0],"quat":[0,0,0.2,1]})",
      R"({"type":"box","half":[0.3,0.2,0.3],"radius":0.15})",
      R"({"type":"hull","points":[[0,0,0],[1,0,0],[0,1,0],[0,0,1],[0.2,0.2,0.2]]})",
      R"({"type":"hull","points":[[0,0,0],[1,0,0],[0,1,0],[0,0,1]],"radius":0.2})",
      R"({"type":"triangle","points":[[-1,0,-1],[1,0,-1],[0,0,1]]})"};
  for (const std::string& a : shapes) {
    for (const std::string& b : shapes) {
      const std::string pair = R"("a":)" + a + R"(,"pa":{"quat":[0.1,0.2,0.3,0.9]},"b":)" + b +
                               R"(,"pb":{"pos":[0.3,0.2,0.1]})";
      // The ops agree with each other: overlap, distance 0, penetration and a shape cast
      // that starts overlapped, or none of them.
      const bool overlap = answerOk(R"({"op":"overlap",)" + pair + "}")["overlap"].get<bool>();
      json distance = answerOk(R"({"op":"distance",)" + pair + "}");
      EXPECT_EQ(distance["distance"].get<double>() == 0.0, overlap) << a << " " << b;
      json penetration = answerOk(R"({"op":"penetration",)" + pair + "}");
      EXPECT_EQ(penetration["overlap"].get<bool>(), overlap) << a << " " << b;
      json manifold = answerOk(R"({"op":"manifold",)" + pair + "}");
      if (overlap) {
        EXPECT_GE(manifold["points"].size(), 1u) << a << " " << b;
      }
      json cast = answerOk(R"({"op":"shapecast","translation":[3,0,0],)" + pair + "}");
      EXPECT_EQ(cast["status"] == "overlapped", overlap) << a << " " << b;
      json toi = answerOk(
          R"({"op":"toi","a":)" + a + R"(,"b":)" + b +
          R"(,"sweepA":{"from":{},"to":{"quat":[0,1,0,1]}},"sweepB":{"from":{"pos":[4,0,0]},"to":{"pos":[-4,0,0],"quat":[1,0,0,1]}}})");
      EXPECT_EQ(toi["status"], "hit") << a << " " << b << " " << toi;
    }
    json ray = answerOk(R"({"op":"raycast","a":)" + a +
                        R"(,"ray":{"origin":[0.05,5,0.05],"translation":[0,-10,0]}})");
    EXPECT_EQ(ray["hit"], true) << a;
    EXPECT_GT(ray["normal"][1].get<double>(), 0.0) << a;
  }
}

TEST(Query3, ErrorsNameTheField) {
  const std::string spheres =
      R"("a":{"type":"sphere","radius":1},"b":{"type":"sphere","radius":1})";
  // Mixing dimensions, either way round, and 2D-only fields on 3D lines.
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"distance","a":{"type":"sphere","radius":1},"b":{"type":"circle","radius":1}})"),
      "b: a 2D shape in one query with the 3D shape a (both shapes must be 2D, or both 3D)");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"distance","a":{"type":"box","half":[1,1]},"b":{"type":"box","half":[1,1,1]}})"),
      "a: a 2D shape in one query with the 3D shape b (both shapes must be 2D, or both 3D)");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"distance","a":{"type":"capsule","p1":[0,0,0],"p2":[1,0],"radius":1},"b":{"type":"sphere","radius":1}})"),
      "a.p2: must be [x, y, z]");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"distance","pa":{"angle":1},)" + spheres + "}"),
            "pa.angle: a 3D pose turns by \"quat\": [x, y, z, w], not by an angle");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"distance","pb":{"pos":[1,2]},)" + spheres + "}"),
            "pb.pos: must be [x, y, z]");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"distance","pb":{"quat":[0,0,0,0]},)" + spheres + "}"),
            "pb.quat: [0, 0, 0, 0] is not a rotation (the zero quaternion; the identity is "
            "[0, 0, 0, 1])");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"distance","pa":{"pos":[0,0,1e19]},)" + spheres + "}"),
            "pa.pos[2]: 1e+19 m is beyond the coordinate limit 1e9 m");
  // A 2D line with a quaternion says so.
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"distance","a":{"type":"circle","radius":1},"pa":{"quat":[0,0,0,1]},"b":{"type":"circle","radius":1}})"),
      "pa.quat: a 2D pose turns by \"angle\" (radians); \"quat\" is for 3D shapes");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"distance","a":{"type":"sphere","radius":1}})"), "b: missing");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"shapecast","translation":[1,0],)" + spheres + "}"),
            "translation: must be [x, y, z]");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"shapecast",)" + spheres + "}"), "translation: missing");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"raycast","a":{"type":"sphere","radius":1},"ray":{"origin":[0,0,0]}})"),
      "ray.translation: missing");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"raycast","a":{"type":"sphere","radius":1},"ray":{"origin":[0,0],"translation":[1,0,0]}})"),
      "ray.origin: must be [x, y, z]");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"toi","sweepA":{"from":{},"to":{"quat":[0,0,0,0]}},"sweepB":{"from":{},"to":{}},)" +
          spheres + "}"),
      "sweepA.to.quat: [0, 0, 0, 0] is not a rotation (the zero quaternion; the identity "
      "is [0, 0, 0, 1])");
  EXPECT_EQ(
      errorOf(
          R"({"id":1,"op":"toi","sweepA":{"from":{},"to":{}},"sweepB":{"from":{"angle":0},"to":{}},)" +
          spheres + "}"),
      "sweepB.from.angle: a 3D pose turns by \"quat\": [x, y, z, w], not by an angle");
  EXPECT_EQ(errorOf(R"({"id":1,"op":"toi","sweepA":{"from":{},"to":{}},)" + spheres + "}"),
            "sweepB: missing");
  EXPECT_EQ(
      errorOf(R"({"id":1,"op":"distance","a":{"type":"sphere","radius":1},"b":{"type":"cone"}})"),
      "b.type: unknown shape type \"cone\" (expected sphere, capsule, box, hull, triangle in "
      "3D)");
  // Huge coordinates that pass the parser but make non-finite answers are refused, not null.
  QueryAnswer huge = answerQuery(
      R"({"id":2,"op":"distance","a":{"type":"sphere","radius":1e9},"pa":{"pos":[-1e9,-1e9,-1e9]},"b":{"type":"sphere","radius":1e9},"pb":{"pos":[1e9,1e9,1e9]}})");
  const json h = json::parse(huge.answer);
  if (huge.ok) {
    EXPECT_TRUE(std::isfinite(h["distance"].get<double>())) << h;
  } else {
    EXPECT_NE(h["error"].get<std::string>().find("not finite"), std::string::npos) << h;
  }
}

// The program's output for 3D lines is the library's answer, to the byte: each line is
// answered here by the collision functions called directly and written by toJson.
// A 2 x 2 m floor at y = 0 as two triangles (fronts up) sharing the diagonal (0, 2).
const std::string kFloorJson =
    R"({"type":"mesh","vertices":[[-1,0,-1],[1,0,-1],[1,0,1],[-1,0,1]],"triangles":[[0,3,2],[0,2,1]]})";

TEST(Query3, MeshAnswersItsOps) {
  // Straight down onto the floor from 5 m: fraction 0.5 of the 10 m ray, normal up.
  json r = answerOk(R"({"op":"raycast","a":)" + kFloorJson +
                    R"(,"ray":{"origin":[0.5,5,-0.25],"translation":[0,-10,0]}})");
  EXPECT_TRUE(r["hit"].get<bool>());
  EXPECT_NEAR(r["fraction"].get<double>(), 0.5, 1e-7);
  expectVec3(r["point"], 0.5, 0, -0.25, 1e-6);
  expectVec3(r["normal"], 0, 1, 0, 0);
  EXPECT_EQ(r["triangle"].get<int>(), 1);  // x > -z: the triangle (0, 2, 1)
  // From below: one-sided, no hit, every number 0 and triangle -1.
  r = answerOk(R"({"op":"raycast","a":)" + kFloorJson +
               R"(,"ray":{"origin":[0.5,-5,-0.25],"translation":[0,10,0]}})");
  EXPECT_FALSE(r["hit"].get<bool>());
  EXPECT_EQ(r["triangle"].get<int>(), -1);

  // A unit cube 0.01 m deep across the diagonal: one manifold per triangle, each along the
  // face normal (no ghost bump at the shared edge), points 0.01 deep.
  const std::string cube = R"(,"b":{"type":"box","half":[0.5,0.5,0.5]},"pb":{"pos":[0,0.49,0]})";
  json m = answerOk(R"({"op":"manifold","a":)" + kFloorJson + cube + "}");
  ASSERT_EQ(m["manifolds"].size(), 2u) << m;
  for (int i = 0; i < 2; ++i) {
    const json& one = m["manifolds"][static_cast<std::size_t>(i)];
    EXPECT_EQ(one["triangle"].get<int>(), i);
    expectVec3(one["normal"], 0, 1, 0, 1e-6);
    ASSERT_GE(one["points"].size(), 1u);
    for (const json& p : one["points"])
      EXPECT_NEAR(p["separation"].get<double>(), -0.01, 1e-5);
  }
  EXPECT_TRUE(answerOk(R"({"op":"overlap","a":)" + kFloorJson + cube + "}")["overlap"].get<bool>());
  // Above the floor by 0.3 m: apart, the closest triangle is the lower index of the two.
  const std::string above = R"(,"b":{"type":"sphere","radius":0.2},"pb":{"pos":[0.1,0.5,0.1]})";
  EXPECT_FALSE(
      answerOk(R"({"op":"overlap","a":)" + kFloorJson + above + "}")["overlap"].get<bool>());
  json d = answerOk(R"({"op":"distance","a":)" + kFloorJson + above + "}");
  EXPECT_NEAR(d["distance"].get<double>(), 0.3, 1e-6);
  expectVec3(d["normal"], 0, 1, 0, 1e-6);
  EXPECT_EQ(d["triangle"].get<int>(), 0);
  // Dropped 1 m, the sphere lands after 0.3 m.
  json c =
      answerOk(R"({"op":"shapecast","a":)" + kFloorJson + above + R"(,"translation":[0,-1,0]})");
  EXPECT_EQ(c["status"], "hit");
  EXPECT_NEAR(c["fraction"].get<double>(), 0.3, 1e-4);
  EXPECT_GE(c["triangle"].get<int>(), 0);
}

TEST(Query3, MeshToiAndPenetrationAndMeshAsShapeB) {
  // A sphere of radius 0.2 dropped from 1 m to -1 m over the floor: it comes within the
  // target of the floor when its centre is at 0.2 + target, t = (0.8 - target) / 2.
  const std::string ball = R"({"type":"sphere","radius":0.2})";
  const std::string drop = R"({"from":{"pos":[0.1,1,0.1]},"to":{"pos":[0.1,-1,0.1]}})";
  const double late = (0.8 - kToiTargetSeparation) / 2, band = kToiTolerance / 2;
  json t = answerOk(R"({"op":"toi","a":)" + kFloorJson + R"(,"b":)" + ball + R"(,"sweepB":)" +
                    drop + "}");
  EXPECT_EQ(t["status"], "hit");
  EXPECT_LE(t["t"].get<double>(), late + 1e-6);
  EXPECT_GE(t["t"].get<double>(), late - band - 1e-6);
  EXPECT_GE(t["triangle"].get<int>(), 0);
  // The same with the mesh as shape b (its sweep held still), and with the floor's sweep
  // given as the origin twice; the target moves the hit.
  json tb = answerOk(R"({"op":"toi","a":)" + ball + R"(,"b":)" + kFloorJson + R"(,"sweepA":)" +
                     drop + R"(,"sweepB":{"from":{},"to":{}}})");
  EXPECT_EQ(tb, t);
  json far = answerOk(R"({"op":"toi","a":)" + kFloorJson + R"(,"b":)" + ball + R"(,"sweepB":)" +
                      drop + R"(,"target":0.2})");
  EXPECT_NEAR(far["t"].get<double>(), 0.3, band + 1e-6);
  // Rising from below: one-sided, separated at t = 1 with no triangle.
  json up = answerOk(R"({"op":"toi","a":)" + kFloorJson + R"(,"b":)" + ball +
                     R"(,"sweepB":{"from":{"pos":[0.1,-1,0.1]},"to":{"pos":[0.1,1,0.1]}}})");
  EXPECT_EQ(up["status"], "separated");
  EXPECT_EQ(up["triangle"].get<int>(), -1);

  // The sphere 0.05 m into the floor: 0.05 m deep, straight up; as shape b the normal
  // points from the sphere to the floor and the points swap.
  const std::string sunk = R"({"type":"sphere","radius":0.2})";
  json p = answerOk(R"({"op":"penetration","a":)" + kFloorJson + R"(,"b":)" + sunk +
                    R"(,"pb":{"pos":[0.1,0.15,-0.3]}})");
  EXPECT_TRUE(p["overlap"].get<bool>());
  EXPECT_NEAR(p["depth"].get<double>(), 0.05, 1e-6);
  expectVec3(p["normal"], 0, 1, 0, 1e-6);
  expectVec3(p["pointA"], 0.1, 0, -0.3, 1e-6);
  expectVec3(p["pointB"], 0.1, -0.05, -0.3, 1e-6);
  EXPECT_EQ(p["triangle"].get<int>(), 1);  // z < x: the triangle (0, 2, 1)
  json pb = answerOk(R"({"op":"penetration","a":)" + sunk +
                     R"(,"pa":{"pos":[0.1,0.15,-0.3]},"b":)" + kFloorJson + "}");
  EXPECT_EQ(pb["depth"], p["depth"]);
  EXPECT_EQ(pb["triangle"], p["triangle"]);
  expectVec3(pb["normal"], 0, -1, 0, 1e-6);
  EXPECT_EQ(pb["pointA"], p["pointB"]);
  EXPECT_EQ(pb["pointB"], p["pointA"]);
  // Distance and overlap as shape b, the same numbers turned round.
  const std::string above = R"({"pos":[0.1,0.5,0.1]})";
  json d = answerOk(R"({"op":"distance","a":)" + kFloorJson + R"(,"b":)" + ball + R"(,"pb":)" +
                    above + "}");
  json db = answerOk(R"({"op":"distance","a":)" + ball + R"(,"pa":)" + above + R"(,"b":)" +
                     kFloorJson + "}");
  EXPECT_EQ(db["distance"], d["distance"]);
  EXPECT_EQ(db["pointA"], d["pointB"]);
  EXPECT_EQ(db["pointB"], d["pointA"]);
  expectVec3(db["normal"], 0, -1, 0, 1e-6);
  EXPECT_FALSE(answerOk(R"({"op":"overlap","a":)" + ball + R"(,"pa":)" + above + R"(,"b":)" +
                        kFloorJson + "}")["overlap"]
                   .get<bool>());
}

TEST(Query3, MeshErrorsNameTheFieldAndTheOp) {
  const std::string b = R"(,"b":{"type":"sphere","radius":0.2})";
  const std::string ball = R"({"type":"sphere","radius":0.2})";
  EXPECT_EQ(errorOf(R"({"op":"manifold","a":)" + ball + R"(,"b":)" + kFloorJson + "}"),
            "b: a mesh must be shape a for op manifold (as shape b it supports ops overlap, "
            "distance, penetration, toi)");
  EXPECT_EQ(errorOf(R"({"op":"shapecast","a":)" + ball + R"(,"b":)" + kFloorJson +
                    R"(,"translation":[0,1,0]})"),
            "b: a mesh must be shape a for op shapecast (as shape b it supports ops overlap, "
            "distance, penetration, toi)");
  EXPECT_EQ(errorOf(R"({"op":"distance","a":)" + kFloorJson + R"(,"b":)" + kFloorJson + "}"),
            "b: a mesh against a mesh is not supported (shape b must be convex)");
  // Op toi: the mesh's sweep must stand still; the convex sweep is checked as always.
  const std::string toi = R"({"op":"toi","a":)" + kFloorJson + b;
  EXPECT_EQ(
      errorOf(toi + R"(,"sweepA":{"from":{},"to":{"pos":[0,1,0]}},"sweepB":{"from":{},"to":{}}})"),
      "sweepA.to: a mesh is static: its pose must be sweepA.from's (or leave sweepA out: "
      "the mesh at the origin)");
  EXPECT_EQ(errorOf(toi + R"(,"sweepA":{"from":{}},"sweepB":{"from":{},"to":{}}})"),
            "sweepA.to: missing");
  EXPECT_EQ(errorOf(toi + "}"), "sweepB: missing");
  EXPECT_EQ(
      errorOf(toi + R"(,"sweepB":{"from":{},"to":{"pos":[0,"x",0]}}})").rfind("sweepB.to.pos", 0),
      0u);
  EXPECT_EQ(errorOf(toi + R"(,"sweepB":{"from":{},"to":{}},"target":-1})"),
            "target: must be a number >= 0 within the coordinate limit 1e9 m");
  EXPECT_EQ(errorOf(toi + R"(,"pa":{},"sweepB":{"from":{},"to":{}}})"),
            "pa: not used by op toi (give sweepA and sweepB)");
  EXPECT_EQ(
      errorOf(
          R"({"op":"toi","a":)" + ball + R"(,"b":)" + kFloorJson +
          R"(,"sweepB":{"from":{"pos":[1,0,0]},"to":{"pos":[1,0,0],"quat":[0,1,0,0]}},"sweepA":{"from":{},"to":{}}})"),
      "sweepB.to: a mesh is static: its pose must be sweepB.from's (or leave sweepB out: "
      "the mesh at the origin)");
  EXPECT_EQ(errorOf(R"({"op":"penetration","a":)" + kFloorJson + R"(,"b":{"type":"sphere"}})")
                .rfind("b.radius", 0),
            0u);
  auto meshError = [&](const std::string& mesh) {
    return errorOf(R"({"op":"distance","a":)" + mesh + b + "}");
  };
  EXPECT_EQ(
      meshError(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,0,1]],"triangles":[[0,2,3]]})"),
      "a.triangles[0][2]: vertex index 3 is out of range (0 to 2)");
  EXPECT_EQ(
      meshError(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,0,1]],"triangles":[[0,-1,2]]})"),
      "a.triangles[0][1]: vertex index -1 is out of range (0 to 2)");
  EXPECT_EQ(
      meshError(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,0,1]],"triangles":[[0,1.5,2]]})"),
      "a.triangles[0][1]: must be an integer vertex index");
  EXPECT_EQ(
      meshError(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,0,1]],"triangles":[[0,2]]})"),
      "a.triangles[0]: must be [i, j, k] (three vertex indices)");
  EXPECT_EQ(meshError(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,0,1]],"triangles":[]})"),
            "a.triangles: needs at least 1 triangle");
  EXPECT_EQ(meshError(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,0,1]]})"),
            "a.triangles: missing");
  EXPECT_EQ(
      meshError(
          R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,0,1]],"triangles":[[0,2,1]],"radius":0})")
          .rfind("a.radius: ", 0),
      0u);
  // A degenerate triangle (three points on a line) and a repeated index: makeMesh3's
  // errors, said as the triangle's field.
  const std::string line = meshError(
      R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[2,0,0],[0,0,1]],"triangles":[[0,3,1],[0,1,2]]})");
  EXPECT_EQ(line.rfind("a.triangles[1]: ", 0), 0u) << line;
  EXPECT_EQ(
      meshError(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,0,1]],"triangles":[[0,0,1]]})"),
      "a.triangles[0]: a vertex index is repeated");
  // Vertices: beyond the coordinate limit, not a triple.
  EXPECT_EQ(
      meshError(R"({"type":"mesh","vertices":[[0,0,0],[1e19,0,0],[0,0,1]],"triangles":[[0,2,1]]})"),
      "a.vertices[1][0]: 1e+19 m is beyond the coordinate limit 1e9 m");
  EXPECT_EQ(meshError(R"({"type":"mesh","vertices":[[0,0,0],[1,0],[0,0,1]],"triangles":[[0,2,1]]})")
                .rfind("a.vertices[1]", 0),
            0u);
}

TEST(Query3, ProgramOutputMatchesTheLibrary) {
  const Hull3 slab = makeBox3({2, 0.5f, 2}).value();
  const Hull3 cube = makeBox3({0.5f, 0.5f, 0.5f}).value();
  const Sphere ball = makeSphere({0, 0, 0}, 0.5f).value();
  const Capsule3 rod = makeCapsule3({0, -1, 0}, {0, 1, 0}, 0.25f).value();
  // [0.1, 0.2, 0.3, 0.9] read as floats and normalised in double, as the parser does.
  const double q[4] = {0.1f, 0.2f, 0.3f, 0.9f};
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const Quat turn{static_cast<float>(q[0] / norm), static_cast<float>(q[1] / norm),
                  static_cast<float>(q[2] / norm), static_cast<float>(q[3] / norm)};
  const Transform3 slabPose{{0, 0, 0}, turn};
  const Transform3 cubePose{{0.3f, 0.95f, -0.2f}, {}};
  const Transform3 ballPose{{1, 2, 3}, {}};

  std::vector<std::pair<std::string, json>> cases;
  auto add = [&](const std::string& line, json expected, const char* id) {
    expected["id"] = id;
    cases.emplace_back(line, expected);
  };
  const std::string slabJson = R"({"type":"box","half":[2,0.5,2]})";
  const std::string cubeJson = R"({"type":"box","half":[0.5,0.5,0.5]})";
  const std::string turnJson = R"({"quat":[0.1,0.2,0.3,0.9]})";
  const std::string pair = R"("a":)" + slabJson + R"(,"pa":)" + turnJson + R"(,"b":)" + cubeJson +
                           R"(,"pb":{"pos":[0.3,0.95,-0.2]})";
  add(R"({"id":"d","op":"distance",)" + pair + "}",
      toJson(computeDistance(makeProxy(slab), slabPose, makeProxy(cube), cubePose)), "d");
  add(R"({"id":"p","op":"penetration",)" + pair + "}",
      toJson(computePenetration(makeProxy(slab), slabPose, makeProxy(cube), cubePose)), "p");
  add(R"({"id":"m","op":"manifold",)" + pair + "}",
      toJson(collideHulls(slab, slabPose, cube, cubePose, kSpeculativeDistance)), "m");
  json overlap = {{"overlap", testOverlap(makeProxy(slab), slabPose, makeProxy(cube), cubePose)}};
  add(R"({"id":"o","op":"overlap",)" + pair + "}", overlap, "o");
  add(R"({"id":"s","op":"shapecast","a":{"type":"sphere","radius":0.5},"pa":{"pos":[1,2,3]},"b":{"type":"capsule","p1":[0,-1,0],"p2":[0,1,0],"radius":0.25},"pb":{"pos":[5,2,3]},"translation":[-8,0.5,0]})",
      toJson(castShape(makeProxy(ball), ballPose, makeProxy(rod), Transform3{{5, 2, 3}, {}},
                       {-8, 0.5f, 0})),
      "s");
  const Transform3 from{{0, 3, 0}, {}};
  const Transform3 to{
      {0, -3, 0},
      {static_cast<float>(1 / std::sqrt(2.0)), 0, 0, static_cast<float>(1 / std::sqrt(2.0))}};
  const ShapeProxy3 rodProxy = makeProxy(rod);
  add(R"({"id":"t","op":"toi","a":)" + slabJson +
          R"(,"b":{"type":"capsule","p1":[0,-1,0],"p2":[0,1,0],"radius":0.25},"sweepA":{"from":)" +
          turnJson + R"(,"to":)" + turnJson +
          R"(},"sweepB":{"from":{"pos":[0,3,0]},"to":{"pos":[0,-3,0],"quat":[1,0,0,1]}}})",
      toJson(computeToi(makeProxy(slab), makeSweep3(makeProxy(slab).center(), slabPose, slabPose),
                        rodProxy, makeSweep3(rodProxy.center(), from, to), 1.0f,
                        kToiTargetSeparation)),
      "t");
  RayHit3 hit = rayCast(slab, {invTransformPoint(slabPose, {0.1f, 5, 0.2f}),
                               invTransformVector(slabPose, {0, -10, 0}), 1.0f});
  ASSERT_TRUE(hit.hit);
  hit.point = transformPoint(slabPose, hit.point);
  hit.normal = transformVector(slabPose, hit.normal);
  add(R"({"id":"r","op":"raycast","a":)" + slabJson + R"(,"pa":)" + turnJson +
          R"(,"ray":{"origin":[0.1,5,0.2],"translation":[0,-10,0]}})",
      toJson(hit), "r");

  // Rounded: the slab rounded by 0.05 (the cube 0.05 deeper), its manifold and a ray.
  const Hull3 roundSlab = makeBox3({2, 0.5f, 2}, {}, 0.05f).value();
  const std::string roundSlabJson = R"({"type":"box","half":[2,0.5,2],"radius":0.05})";
  add(R"({"id":"rm","op":"manifold","a":)" + roundSlabJson + R"(,"pa":)" + turnJson + R"(,"b":)" +
          cubeJson + R"(,"pb":{"pos":[0.3,0.95,-0.2]}})",
      toJson(collideHulls(roundSlab, slabPose, cube, cubePose, kSpeculativeDistance)), "rm");
  add(R"({"id":"rd","op":"distance","a":)" + roundSlabJson + R"(,"pa":)" + turnJson +
          R"(,"b":{"type":"sphere","radius":0.5},"pb":{"pos":[1,2,3]}})",
      toJson(computeDistance(makeProxy(roundSlab), slabPose, makeProxy(ball), ballPose)), "rd");
  RayHit3 roundHit = rayCast(roundSlab, {invTransformPoint(slabPose, {0.1f, 5, 0.2f}),
                                         invTransformVector(slabPose, {0, -10, 0}), 1.0f});
  ASSERT_TRUE(roundHit.hit);
  roundHit.point = transformPoint(slabPose, roundHit.point);
  roundHit.normal = transformVector(slabPose, roundHit.normal);
  add(R"({"id":"rr","op":"raycast","a":)" + roundSlabJson + R"(,"pa":)" + turnJson +
          R"(,"ray":{"origin":[0.1,5,0.2],"translation":[0,-10,0]}})",
      toJson(roundHit), "rr");

  // A mesh as shape a: the floor turned by the same quaternion.
  const std::vector<Vec3> floorVertices = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
  const std::vector<std::array<std::int32_t, 3>> floorTriangles = {{0, 3, 2}, {0, 2, 1}};
  const Mesh3 floor = makeMesh3(floorVertices, floorTriangles).value();
  const std::string floorPair = R"("a":)" + kFloorJson + R"(,"pa":)" + turnJson + R"(,"b":)" +
                                cubeJson + R"(,"pb":{"pos":[0.3,0.95,-0.2]})";
  add(R"({"id":"mr","op":"raycast","a":)" + kFloorJson + R"(,"pa":)" + turnJson +
          R"(,"ray":{"origin":[0.1,5,0.2],"translation":[0,-10,0]}})",
      toJson(rayCastMesh(floor, slabPose, {{0.1f, 5, 0.2f}, {0, -10, 0}, 1.0f})), "mr");
  std::vector<MeshContact3> contacts;
  collideMesh(floor, slabPose, cube, Transform3{{0.3f, 0.2f, -0.2f}, {}}, contacts);
  EXPECT_FALSE(contacts.empty());
  add(R"({"id":"mm","op":"manifold","a":)" + kFloorJson + R"(,"pa":)" + turnJson + R"(,"b":)" +
          cubeJson + R"(,"pb":{"pos":[0.3,0.2,-0.2]}})",
      toJson(contacts), "mm");
  add(R"({"id":"md","op":"distance",)" + floorPair + "}",
      toJson(computeDistanceMesh(floor, slabPose, makeProxy(cube), cubePose)), "md");
  add(R"({"id":"mo","op":"overlap",)" + floorPair + "}",
      json{{"overlap", testOverlapMesh(floor, slabPose, makeProxy(cube), cubePose)}}, "mo");
  add(R"({"id":"ms","op":"shapecast",)" + floorPair + R"(,"translation":[0,-2,0.1]})",
      toJson(castShapeMesh(floor, slabPose, makeProxy(cube), cubePose, {0, -2, 0.1f})), "ms");
  const Transform3 sunkPose{{0.3f, 0.2f, -0.2f}, {}};
  add(R"({"id":"mp","op":"penetration","a":)" + kFloorJson + R"(,"pa":)" + turnJson + R"(,"b":)" +
          cubeJson + R"(,"pb":{"pos":[0.3,0.2,-0.2]}})",
      toJson(computePenetrationMesh(floor, slabPose, makeProxy(cube), sunkPose)), "mp");
  const ShapeProxy3 cubeProxy = makeProxy(cube);
  add(R"({"id":"mt","op":"toi","a":)" + kFloorJson + R"(,"sweepA":{"from":)" + turnJson +
          R"(,"to":)" + turnJson + R"(},"b":)" + cubeJson +
          R"(,"sweepB":{"from":{"pos":[0,3,0]},"to":{"pos":[0,-3,0],"quat":[1,0,0,1]}}})",
      toJson(computeToiMesh(floor, slabPose, cubeProxy, makeSweep3(cubeProxy.center(), from, to),
                            1.0f, kToiTargetSeparation)),
      "mt");

  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  const std::filesystem::path in = dir / ("quack_query3_in_" + std::to_string(::getpid()));
  const std::filesystem::path out = dir / ("quack_query3_out_" + std::to_string(::getpid()));
  {
    std::ofstream file(in);
    for (const auto& c : cases)
      file << c.first << '\n';
  }
  const std::string command =
      std::string("\"") + QUACK_EXE + "\" query \"" + in.string() + "\" > \"" + out.string() + "\"";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream answers(out);
  std::string line;
  std::size_t n = 0;
  while (std::getline(answers, line)) {
    ASSERT_LT(n, cases.size());
    EXPECT_EQ(line, cases[n].second.dump()) << cases[n].first;
    ++n;
  }
  EXPECT_EQ(n, cases.size());
  std::filesystem::remove(in);
  std::filesystem::remove(out);
}

}  // namespace
}  // namespace quack::app
