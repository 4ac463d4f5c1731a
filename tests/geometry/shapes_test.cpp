#include "quack/geometry/shapes.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <string>
#include <vector>

#include "quack/geometry/bounds.hpp"
#include "quack/geometry/mass.hpp"
#include "quack/geometry/raycast.hpp"
#include "support/random_shapes.hpp"

namespace quack {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

template <class T>
void expectError(const Result<T>& r, const std::string& fragment) {
  ASSERT_FALSE(r.ok()) << "expected an error containing '" << fragment << "'";
  EXPECT_NE(r.error().message.find(fragment), std::string::npos) << r.error().message;
}

// Hardening: shapes beyond the coordinate limit (1e9 m) are refused for their size, naming
// the argument, before any arithmetic (a box of half-size 1e19 used to be reported as "hull
// is not strictly convex" further down the line, and 3e38 gave NaN answers).
TEST(ShapesHardening, ShapesBeyondTheCoordinateLimitAreRefused) {
  expectError(makeBox(1e19f, 1e19f),
              "box half-extents (1e+19, 1e+19) m are beyond the coordinate "
              "limit 1e9 m");
  expectError(makeBox(1, 3e38f), "beyond the coordinate limit 1e9 m");
  expectError(makeBox(1, 1, {2e9f, 0}), "box center (2e+09, 0) is beyond the coordinate limit");
  expectError(makeBox(1, 1, {}, 0, 2e9f), "box radius 2e+09 m is beyond the coordinate limit");
  expectError(makeCircle({0, -3e38f}, 1), "circle center (0, -3e+38) is beyond");
  expectError(makeCircle({}, 1e10f), "circle radius 1e+10 m is beyond the coordinate limit");
  expectError(makeCapsule({0, 0}, {1e19f, 0}, 1), "capsule p2 (1e+19, 0) is beyond");
  expectError(makeCapsule({0, 0}, {1, 0}, 1e19f), "capsule radius 1e+19 m is beyond");
  expectError(makeSegment({-2e19f, 0}, {0, 0}), "segment p1 (-2e+19, 0) is beyond");
  const Vec2 huge[] = {{0, 0}, {1e19f, 0}, {0, 1e19f}};
  expectError(makePolygon(huge), "polygon points[1] (1e+19, 0) is beyond the coordinate limit");
  const Vec2 tri[] = {{0, 0}, {1, 0}, {0, 1}};
  expectError(makePolygon(tri, 5e9f), "polygon radius 5e+09 m is beyond");
  Hull h = computeHull(tri).value();
  h.points[2] = {0, 4e9f};
  expectError(makePolygon(h), "hull point 2 (0, 4e+09) is beyond");
  // At the limit is fine.
  EXPECT_TRUE(makeBox(kMaxCoordinate, kMaxCoordinate).ok());
  EXPECT_TRUE(makeCircle({kMaxCoordinate, -kMaxCoordinate}, kMaxCoordinate).ok());
}

// Hardening: the nanometre floor (kMinShapeSize) now covers boxes, circles and capsules
// too; a box of half-size 1e-25 used to be accepted and answered queries.
TEST(ShapesHardening, BoxesCirclesAndCapsulesBelowANanometreAreRefused) {
  expectError(makeBox(1e-25f, 1e-25f), "box side 2e-25 m is below the smallest size");
  expectError(makeBox(1, 1e-12f), "box side");
  expectError(makeCircle({}, 1e-25f), "circle diameter 2e-25 m is below the smallest size");
  expectError(makeCapsule({0, 0}, {1e-20f, 0}, 1e-20f), "capsule size");
  EXPECT_TRUE(makeBox(1e-9f, 1e-9f).ok());
  EXPECT_TRUE(makeCircle({}, 1e-9f).ok());
  EXPECT_TRUE(makeCapsule({0, 0}, {1, 0}, 1e-12f).ok());  // thin but a metre long
}

TEST(Shapes, BadNumbersAreNamed) {
  expectError(makeCircle({kNaN, 0}, 1), "circle center is not finite");
  expectError(makeCircle({}, -1), "circle radius must be > 0, got -1");
  expectError(makeCircle({}, 0), "circle radius must be > 0");
  expectError(makeCircle({}, kInf), "circle radius is not finite");
  expectError(makeCapsule({0, 0}, {1, kInf}, 1), "capsule p2 is not finite");
  expectError(makeCapsule({0, 0}, {1, 0}, -0.5f), "capsule radius must be > 0");
  expectError(makeCapsule({0, 0}, {1, 0}, 0), "a capsule of radius 0 is a segment");
  expectError(makeCapsule({1, 1}, {1, 1}, 0.5f), "use a circle");
  expectError(makeSegment({kNaN, 0}, {1, 0}), "segment p1 is not finite");
  expectError(makeSegment({1, 2}, {1, 2}), "zero length");
  // Regression (the narrow-phase fuzzer): shapes of 1e-23 m made EPA's squares underflow.
  expectError(makeSegment({3e-23f, 3e-23f}, {3.2e-23f, 3.8e-23f}),
              "below the smallest size Quack resolves");
  const Vec2 speck[] = {{0, 0}, {1e-12f, 0}, {0, 1e-12f}};
  expectError(makePolygon(speck), "less than the smallest size Quack resolves");
  expectError(makeBox(0, 1), "half-extents must be finite and > 0");
  expectError(makeBox(1, kNaN), "half-extents");
  expectError(makeBox(1, 1, {}, kNaN), "box angle is not finite");
  expectError(makeBox(1, 1, {}, 0, -1), "box radius must be >= 0");
  const Vec2 tri[] = {{0, 0}, {1, 0}, {0, 1}};
  expectError(makePolygon(tri, -0.1f), "polygon radius must be >= 0");
  expectError(makePolygon(tri, kNaN), "polygon radius is not finite");
  const Vec2 flat[] = {{0, 0}, {1, 0}, {2, 0}};
  expectError(makePolygon(flat), "collinear");
  const Vec2 nan[] = {{0, 0}, {1, 0}, {0, kNaN}};
  expectError(makePolygon(nan), "points[2] is not finite");
}

TEST(Shapes, ConcavePointSetIsRejectedWithAHint) {
  // An L: the inner corner (1, 1) lies inside the hull.
  const Vec2 ell[] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  expectError(makePolygon(ell),
              "points[3] (1, 1) lies inside the hull of the others (use a concave");
}

TEST(Shapes, ConvexPointSetInAnyOrderGivesCounterClockwisePolygon) {
  // Clockwise, with an extra point on an edge and a duplicate.
  const Vec2 cw[] = {{0, 0}, {0, 1}, {1, 1}, {1, 0.5f}, {1, 0}, {0, 0}};
  Result<Polygon> p = makePolygon(cw, 0.1f);
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_EQ(p->count, 4);
  EXPECT_FLOAT_EQ(p->radius, 0.1f);
  EXPECT_TRUE(validatePolygon(p.value()).ok()) << validatePolygon(p.value()).message();
  EXPECT_FLOAT_EQ(p->centroid.x, 0.5f);
  EXPECT_FLOAT_EQ(p->centroid.y, 0.5f);
  EXPECT_EQ(p->normals[0], (Vec2{0, -1}));  // bottom edge from (0,0) to (1,0)
}

TEST(Shapes, BoxByHand) {
  Result<Polygon> b = makeBox(2, 1, {5, 5}, 0.5f * kPi);
  ASSERT_TRUE(b.ok());
  EXPECT_TRUE(validatePolygon(b.value()).ok()) << validatePolygon(b.value()).message();
  EXPECT_EQ(b->count, 4);
  // Turned a quarter: the first corner (-2, -1) goes to (1, -2) + (5, 5).
  EXPECT_NEAR(b->vertices[0].x, 6.0f, 1e-5f);
  EXPECT_NEAR(b->vertices[0].y, 3.0f, 1e-5f);
  EXPECT_EQ(b->centroid, (Vec2{5, 5}));
}

TEST(Shapes, ValidatePolygonCatchesBrokenInvariants) {
  Polygon p = makeBox(1, 1).value();
  Polygon flipped = p;
  flipped.normals[1] = -flipped.normals[1];
  EXPECT_FALSE(validatePolygon(flipped).ok());
  Polygon clockwise = p;
  std::swap(clockwise.vertices[1], clockwise.vertices[3]);
  EXPECT_FALSE(validatePolygon(clockwise).ok());
  Polygon negative = p;
  negative.radius = -1;
  EXPECT_FALSE(validatePolygon(negative).ok());
  Polygon outside = p;
  outside.centroid = {5, 5};
  EXPECT_FALSE(validatePolygon(outside).ok());
  Polygon tooMany = p;
  tooMany.count = kMaxPolygonVertices + 1;
  EXPECT_FALSE(validatePolygon(tooMany).ok());
}

TEST(Shapes, SixtyFourVertexPolygon) {
  std::vector<Vec2> pts;
  for (int i = 0; i < kMaxPolygonVertices; ++i) {
    float a = 2.0f * kPi * static_cast<float>(i) / kMaxPolygonVertices;
    pts.push_back({3 * std::cos(a), 3 * std::sin(a)});
  }
  Result<Polygon> p = makePolygon(pts, 0.05f);
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_EQ(p->count, kMaxPolygonVertices);
  EXPECT_TRUE(validatePolygon(p.value()).ok());
}

TEST(Shapes, RandomPolygonsValidate) {
  const unsigned seed = 99;
  std::mt19937 rng(seed);
  for (int i = 0; i < 500; ++i) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " i " << i);
    int n = 3 + static_cast<int>(rng() % 30);
    float size = std::pow(10.0f, testing::uniform(rng, -3, 3));
    Polygon p = testing::randomPolygon(rng, n, size, {size * 5, -size * 3});
    EXPECT_TRUE(validatePolygon(p).ok()) << validatePolygon(p).message();
  }
}

TEST(ShapeGeometry, ShapeTypeNamesTheHeldShape) {
  EXPECT_EQ(shapeType(ShapeGeometry{makeCircle({}, 1).value()}), ShapeType::circle);
  EXPECT_EQ(shapeType(ShapeGeometry{makeCapsule({-1, 0}, {1, 0}, 0.5f).value()}),
            ShapeType::capsule);
  EXPECT_EQ(shapeType(ShapeGeometry{makeSegment({-1, 0}, {1, 0}).value()}), ShapeType::segment);
  EXPECT_EQ(shapeType(ShapeGeometry{makeBox(1, 2).value()}), ShapeType::polygon);
}

TEST(ShapeGeometry, ValidateShapeGivesTheMakeFunctionsMessages) {
  EXPECT_TRUE(validateShape(makeCircle({}, 1).value()).ok());
  EXPECT_TRUE(validateShape(makeBox(1, 2, {3, 4}, 0.5f, 0.1f).value()).ok());
  const struct {
    ShapeGeometry shape;
    Status expected;
  } bad[] = {
      {Circle{{0, 0}, -1.0f}, Status{makeCircle({0, 0}, -1.0f).error()}},
      {Capsule{{0, 0}, {0, 0}, 1.0f}, Status{makeCapsule({0, 0}, {0, 0}, 1.0f).error()}},
      {Segment{{1, 1}, {1, 1}}, Status{makeSegment({1, 1}, {1, 1}).error()}},
      {Polygon{}, validatePolygon(Polygon{})},
  };
  for (const auto& b : bad) {
    Status s = validateShape(b.shape);
    ASSERT_FALSE(s.ok());
    ASSERT_FALSE(b.expected.ok());
    EXPECT_EQ(s.message(), b.expected.message());
  }
}

TEST(ShapeGeometry, OverloadsAgreeWithThePerShapeFunctions) {
  const Transform xf = makeTransform({1, -2}, 0.7f);
  const RayCastInput ray{{-5, 0.3f}, {10, 0.1f}, 1.0f};
  auto check = [&](const auto& shape) {
    const ShapeGeometry g = shape;
    const Aabb a = computeAabb(g, xf), b = computeAabb(shape, xf);
    EXPECT_EQ(a.lower, b.lower);
    EXPECT_EQ(a.upper, b.upper);
    EXPECT_EQ(containsPoint(g, {0.1f, 0.2f}), containsPoint(shape, Vec2{0.1f, 0.2f}));
    EXPECT_EQ(computeMass(g, 2.0f).inertia, computeMass(shape, 2.0f).inertia);
    EXPECT_EQ(rayCast(g, ray).fraction, rayCast(shape, ray).fraction);
    EXPECT_EQ(rayCast(g, ray).hit, rayCast(shape, ray).hit);
  };
  check(makeCircle({0.5f, 0}, 1).value());
  check(makeCapsule({-1, 0}, {1, 0.5f}, 0.25f).value());
  check(makeSegment({-1, 0}, {1, 0.5f}).value());
  check(makeBox(1, 0.5f, {0.2f, 0}, 0.3f, 0.05f).value());
}

}  // namespace
}  // namespace quack
