// Contact manifolds: hand-worked cases, swap and rigid-motion symmetry, feature-id
// stability, agreement with SAT, EPA and GJK, and the dispatch table.

#include "quack/collision/manifold.hpp"

#include <gtest/gtest.h>

#include <random>

#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/sat.hpp"
#include "test_shapes.hpp"

namespace quack {
namespace {

using testing::uniform;

void expectNear(Vec2 a, Vec2 b, float tol, const char* what = "") {
  EXPECT_NEAR(a.x, b.x, tol) << what;
  EXPECT_NEAR(a.y, b.y, tol) << what;
}

const ManifoldPoint* findId(const Manifold& m, std::uint32_t id) {
  for (int i = 0; i < m.pointCount; ++i)
    if (m.points[i].id == id) return &m.points[i];
  return nullptr;
}

// How far B must move along unit n (world) to stop overlapping A: the support of A along n
// plus the support of B along -n, radii included.
float supportValue(const ShapeGeometry& s, Transform xf, Vec2 n) {
  ShapeProxy p = makeProxy(s);
  float best = -1e30f;
  for (int i = 0; i < p.count(); ++i)
    best = maxf(best, dot(transformPoint(xf, p.points()[i]), n));
  return best + p.radius();
}
float depthAlong(const ShapeGeometry& a, Transform xa, const ShapeGeometry& b, Transform xb,
                 Vec2 n) {
  return supportValue(a, xa, n) + supportValue(b, xb, -n);
}

TEST(Manifold, BoxRestingFlatOnBoxGivesTwoPointsAtTheRightDepth) {
  Polygon ground = makeBox(5, 0.5f).value();
  Polygon box = makeBox(0.5f, 0.5f).value();
  // B's bottom at y = 0.49: 1 cm into the ground's top face at y = 0.5.
  Manifold m = collidePolygons(ground, Transform{}, box, makeTransform({1, 0.99f}, 0));
  ASSERT_EQ(m.pointCount, 2);
  expectNear(m.normal, {0, 1}, 1e-6f);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(m.points[i].separation, -0.01f, 1e-5f);
    EXPECT_NEAR(m.points[i].point.y, 0.495f, 1e-5f);  // midway between the surfaces
  }
  float xs[2] = {m.points[0].point.x, m.points[1].point.x};
  EXPECT_NEAR(minf(xs[0], xs[1]), 0.5f, 1e-5f);
  EXPECT_NEAR(maxf(xs[0], xs[1]), 1.5f, 1e-5f);
  EXPECT_NE(m.points[0].id, m.points[1].id);
  // Anchors are the point relative to each body's origin.
  expectNear(m.points[0].anchorB, m.points[0].point - Vec2{1, 0.99f}, 1e-6f);
}

TEST(Manifold, BoxOnItsCornerGivesOnePoint) {
  Polygon ground = makeBox(5, 0.5f).value();
  Polygon box = makeBox(0.5f, 0.5f).value();
  // Turned 45 degrees, its lowest corner 2 cm below the ground's top face.
  float h = 0.5f * std::sqrt(2.0f);
  Manifold m =
      collidePolygons(ground, Transform{}, box, makeTransform({0, 0.5f + h - 0.02f}, kPi / 4));
  ASSERT_EQ(m.pointCount, 1);
  expectNear(m.normal, {0, 1}, 1e-6f);
  EXPECT_NEAR(m.points[0].separation, -0.02f, 1e-5f);
  expectNear(m.points[0].point, {0, 0.49f}, 1e-5f);
}

TEST(Manifold, RoundedAndCurvedPairsByHand) {
  Circle unit = makeCircle({}, 1).value();
  Manifold m = collideCircles(unit, Transform{}, unit, makeTransform({1.5f, 0}, 0));
  ASSERT_EQ(m.pointCount, 1);
  expectNear(m.normal, {1, 0}, 1e-6f);
  EXPECT_NEAR(m.points[0].separation, -0.5f, 1e-6f);
  expectNear(m.points[0].point, {0.75f, 0}, 1e-6f);

  // Circle above the middle of a capsule's side, and beyond its end cap.
  Capsule cap = makeCapsule({-1, 0}, {1, 0}, 0.25f).value();
  Circle small = makeCircle({}, 0.5f).value();
  m = collideCapsuleAndCircle(cap, Transform{}, small, makeTransform({0.3f, 0.7f}, 0));
  ASSERT_EQ(m.pointCount, 1);
  expectNear(m.normal, {0, 1}, 1e-6f);
  EXPECT_NEAR(m.points[0].separation, -0.05f, 1e-6f);
  m = collideCapsuleAndCircle(cap, Transform{}, small, makeTransform({1.3f, 0.4f}, 0));
  ASSERT_EQ(m.pointCount, 1);
  expectNear(m.normal, {0.6f, 0.8f}, 1e-6f);
  EXPECT_NEAR(m.points[0].separation, 0.5f - 0.75f, 1e-6f);
  // The same circle further out along that direction, 0.25 apart: beyond the speculative
  // distance, so nothing.
  EXPECT_EQ(
      collideCapsuleAndCircle(cap, Transform{}, small, makeTransform({1.6f, 0.8f}, 0)).pointCount,
      0);
}

TEST(Manifold, SpeculativeDistanceDecidesWhetherApartShapesReport) {
  Polygon a = makeBox(1, 1).value();
  Manifold near = collidePolygons(a, Transform{}, a, makeTransform({2.01f, 0}, 0));
  ASSERT_EQ(near.pointCount, 2);
  EXPECT_NEAR(near.points[0].separation, 0.01f, 1e-5f);
  Manifold far = collidePolygons(a, Transform{}, a, makeTransform({2.03f, 0}, 0));
  EXPECT_EQ(far.pointCount, 0);
  Manifold wide = collidePolygons(a, Transform{}, a, makeTransform({2.03f, 0}, 0), 0.05f);
  EXPECT_EQ(wide.pointCount, 2);
  Manifold none = collidePolygons(a, Transform{}, a, makeTransform({2.01f, 0}, 0), 0.0f);
  EXPECT_EQ(none.pointCount, 0);
}

TEST(Manifold, ParallelCapsulesGiveTwoPointsAndCrossingOnesOne) {
  Capsule c = makeCapsule({-1, 0}, {1, 0}, 0.1f).value();
  Manifold m = collideCapsules(c, Transform{}, c, makeTransform({0.5f, 0.15f}, 0));
  ASSERT_EQ(m.pointCount, 2);
  expectNear(m.normal, {0, 1}, 1e-6f);
  EXPECT_NEAR(m.points[0].separation, -0.05f, 1e-6f);
  EXPECT_NEAR(m.points[1].separation, -0.05f, 1e-6f);
  Manifold x = collideCapsules(c, Transform{}, c, makeTransform({0, 0.15f}, kPi / 2));
  ASSERT_GE(x.pointCount, 1);
  EXPECT_NEAR(deepestPoint(x).separation, -(1.0f + 0.2f - 0.15f), 1e-5f);
}

TEST(Manifold, CollinearDisjointSegmentsDoNotTouch) {
  Segment s = makeSegment({0, 0}, {1, 0}).value();
  EXPECT_EQ(collideSegments(s, Transform{}, s, makeTransform({2, 0}, 0)).pointCount, 0);
  // End to end within the speculative distance: one point along the line.
  Manifold m = collideSegments(s, Transform{}, s, makeTransform({1.01f, 0}, 0));
  ASSERT_EQ(m.pointCount, 1);
  expectNear(m.normal, {1, 0}, 1e-6f);
  EXPECT_NEAR(m.points[0].separation, 0.01f, 1e-6f);
}

TEST(Manifold, RoundedCornersUseTheVertexDirection) {
  // Two boxes rounded by 0.1, corner to corner on the diagonal with the cores 0.25 apart
  // along it: the rounded surfaces are 0.05 apart; face normals would say 0.177 - 0.2 < 0.
  Polygon r = makeBox(1, 1, {}, 0, 0.1f).value();
  float off = 2 + 0.25f / std::sqrt(2.0f);
  Manifold m = collidePolygons(r, Transform{}, r, makeTransform({off, off}, 0), 0.1f);
  ASSERT_EQ(m.pointCount, 1);
  expectNear(m.normal, {1 / std::sqrt(2.0f), 1 / std::sqrt(2.0f)}, 1e-5f);
  EXPECT_NEAR(m.points[0].separation, 0.05f, 1e-5f);
}

TEST(Manifold, PolygonAndCircleFaceAndVertexRegions) {
  Polygon box = makeBox(1, 1).value();
  Circle c = makeCircle({}, 0.5f).value();
  Manifold face = collidePolygonAndCircle(box, Transform{}, c, makeTransform({0.2f, 1.4f}, 0));
  ASSERT_EQ(face.pointCount, 1);
  expectNear(face.normal, {0, 1}, 1e-6f);
  EXPECT_NEAR(face.points[0].separation, -0.1f, 1e-6f);
  Manifold corner = collidePolygonAndCircle(box, Transform{}, c, makeTransform({1.3f, 1.4f}, 0));
  ASSERT_EQ(corner.pointCount, 1);
  expectNear(corner.normal, {0.6f, 0.8f}, 1e-6f);
  EXPECT_NEAR(corner.points[0].separation, 0.0f, 1e-6f);
  // Centre inside the box: pushed out through the nearest face.
  Manifold inside = collidePolygonAndCircle(box, Transform{}, c, makeTransform({0.8f, 0}, 0));
  ASSERT_EQ(inside.pointCount, 1);
  expectNear(inside.normal, {1, 0}, 1e-6f);
  EXPECT_NEAR(inside.points[0].separation, -0.7f, 1e-6f);
}

TEST(Manifold, DispatchTableCoversEveryPair) {
  Circle circle = makeCircle({}, 0.5f).value();
  Capsule capsule = makeCapsule({-0.5f, 0}, {0.5f, 0}, 0.25f).value();
  Segment segment = makeSegment({-0.5f, 0}, {0.5f, 0}).value();
  Polygon box = makeBox(0.5f, 0.5f).value();
  const ShapeGeometry shapes[4] = {circle, capsule, segment, box};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      SCOPED_TRACE(::testing::Message() << "pair " << i << ", " << j);
      ASSERT_NE(findManifoldFn(shapeType(shapes[i]), shapeType(shapes[j])), nullptr);
      Manifold m = collide(shapes[i], Transform{}, shapes[j], makeTransform({0.1f, 0.2f}, 0));
      if (i == 2 && j == 2) {
        EXPECT_EQ(m.pointCount, 0);  // parallel segments 0.2 apart
        continue;
      }
      // B above A, overlapping: the normal points up from A to B.
      ASSERT_GE(m.pointCount, 1);
      EXPECT_GT(m.normal.y, 0.5f);
      EXPECT_LT(deepestPoint(m).separation, 0.0f);
    }
  }
}

// Swapping A and B flips the normal and nothing else; a rigid motion of both moves the
// answer with them. Over random pairs of every kind, through the table.
TEST(Manifold, SwapAndRigidMotionSymmetry) {
  const unsigned seed = 2718;
  std::mt19937 rng(seed);
  const ShapeType kinds[4] = {ShapeType::circle, ShapeType::capsule, ShapeType::segment,
                              ShapeType::polygon};
  int withPoints = 0;
  int nearTies = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " trial " << trial);
    ShapeGeometry a = testing::randomShape(rng, kinds[rng() % 4], 1.0f);
    ShapeGeometry b = testing::randomShape(rng, kinds[rng() % 4], 1.0f);
    Transform xa = testing::randomTransform(rng, 0.5f);
    Transform xb = testing::randomTransform(rng, 0.5f);
    Manifold ab = collide(a, xa, b, xb);
    Manifold ba = collide(b, xb, a, xa);
    ASSERT_EQ(ab.pointCount, ba.pointCount)
        << testing::describe(a) << " | " << testing::describe(b);
    if (ab.pointCount == 0) continue;
    ++withPoints;
    if (shapeType(a) != shapeType(b)) {
      // Different kinds: the table runs the same routine both ways, so the answers are
      // identical but for the normal's sign and the anchors' order.
      EXPECT_EQ(ab.normal, -ba.normal);
      for (int k = 0; k < ab.pointCount; ++k) {
        EXPECT_EQ(ab.points[k].id, ba.points[k].id);
        EXPECT_EQ(ab.points[k].point, ba.points[k].point);
        EXPECT_EQ(ab.points[k].separation, ba.points[k].separation);
        EXPECT_EQ(ab.points[k].anchorA, ba.points[k].anchorB);
      }
    } else {
      // Same kind: computed in the other shape's frame, so equal to rounding; the ids
      // differ only in the bit that says which argument holds the reference face. The
      // exception is a near-tie between a face of each, where the first argument's face is
      // preferred (for coherence between steps): then both normals must be equally good.
      if (length(ab.normal + ba.normal) > 1e-5f) {
        EXPECT_NEAR(depthAlong(a, xa, b, xb, ab.normal), depthAlong(a, xa, b, xb, -ba.normal),
                    0.1f * kLinearSlop + 1e-5f);
        ++nearTies;
        continue;
      }
      expectNear(ab.normal, -ba.normal, 1e-5f, "normal");
      for (int k = 0; k < ab.pointCount; ++k) {
        const ManifoldPoint* q = findId(ba, ab.points[k].id ^ kManifoldIdReferenceOnB);
        if (shapeType(a) == ShapeType::circle) q = findId(ba, ab.points[k].id);  // no faces: id 0
        ASSERT_NE(q, nullptr) << "id " << ab.points[k].id;
        expectNear(ab.points[k].point, q->point, 1e-5f, "point");
        EXPECT_NEAR(ab.points[k].separation, q->separation, 1e-5f);
        expectNear(ab.points[k].anchorA, q->anchorB, 1e-5f, "anchor");
      }
    }
    Transform motion = testing::randomTransform(rng, 100.0f);
    Manifold moved = collide(a, motion * xa, b, motion * xb);
    // Rounding at |p| ~ 100 m: a few float ulps of 100.
    if (moved.pointCount != ab.pointCount) {
      // Only a point at the speculative boundary may appear or vanish.
      bool borderline = false;
      for (int k = 0; k < ab.pointCount; ++k)
        borderline |= std::abs(ab.points[k].separation - kSpeculativeDistance) < 1e-4f;
      for (int k = 0; k < moved.pointCount; ++k)
        borderline |= std::abs(moved.points[k].separation - kSpeculativeDistance) < 1e-4f;
      EXPECT_TRUE(borderline);
      continue;
    }
    expectNear(moved.normal, rotate(motion.q, ab.normal), 2e-3f, "normal");
    for (int k = 0; k < ab.pointCount; ++k) {
      const ManifoldPoint* p = findId(moved, ab.points[k].id);
      ASSERT_NE(p, nullptr) << "id " << ab.points[k].id << " lost under a rigid motion";
      expectNear(p->point, transformPoint(motion, ab.points[k].point), 2e-3f, "point");
      EXPECT_NEAR(p->separation, ab.points[k].separation, 2e-3f);
    }
  }
  EXPECT_GT(withPoints, 1000);
  EXPECT_LT(nearTies, withPoints / 100);
}

TEST(Manifold, IdsStableUnderSmallMotionsAndChangeWithFeatures) {
  Polygon ground = makeBox(2, 0.5f).value();
  Polygon box = makeBox(0.5f, 0.5f).value();
  Manifold base = collidePolygons(ground, Transform{}, box, makeTransform({0, 0.99f}, 0.01f));
  ASSERT_EQ(base.pointCount, 2);
  const unsigned seed = 161;
  std::mt19937 rng(seed);
  for (int i = 0; i < 200; ++i) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " i " << i);
    Transform jiggle =
        makeTransform({uniform(rng, -0.01f, 0.01f), 0.99f + uniform(rng, -0.002f, 0.002f)},
                      0.01f + uniform(rng, -0.005f, 0.005f));
    Manifold m = collidePolygons(ground, Transform{}, box, jiggle);
    ASSERT_EQ(m.pointCount, 2);
    EXPECT_NE(findId(m, base.points[0].id), nullptr);
    EXPECT_NE(findId(m, base.points[1].id), nullptr);
  }
  // Tipped onto its other corner, a different vertex of the box touches.
  Manifold left = collidePolygons(ground, Transform{}, box, makeTransform({0, 1.1f}, 0.5f));
  Manifold right = collidePolygons(ground, Transform{}, box, makeTransform({0, 1.1f}, -0.5f));
  ASSERT_EQ(left.pointCount, 1);
  ASSERT_EQ(right.pointCount, 1);
  EXPECT_NE(left.points[0].id, right.points[0].id);
}

// The deepest point's separation is the penetration depth: it agrees with SAT (polygons),
// with EPA, and with GJK's distance when apart; the normal agrees with EPA's.
TEST(Manifold, DepthAgreesWithSatEpaAndGjk) {
  const unsigned seed = 31415;
  std::mt19937 rng(seed);
  const ShapeType kinds[4] = {ShapeType::circle, ShapeType::capsule, ShapeType::segment,
                              ShapeType::polygon};
  int compared = 0;
  int otherNormal = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " trial " << trial);
    ShapeGeometry a = testing::randomShape(rng, kinds[rng() % 4], 1.0f);
    ShapeGeometry b = testing::randomShape(rng, kinds[rng() % 4], 1.0f);
    if (shapeType(a) == ShapeType::segment && shapeType(b) == ShapeType::segment)
      continue;  // no interior
    Transform xa = testing::randomTransform(rng, 0.6f);
    Transform xb = testing::randomTransform(rng, 0.6f);
    Manifold m = collide(a, xa, b, xb);
    PenetrationOutput pen = computePenetration(makeProxy(a), xa, makeProxy(b), xb);
    if (!pen.overlap) {
      DistanceOutput d = computeDistance(makeProxy(a), xa, makeProxy(b), xb);
      if (d.distance > kSpeculativeDistance + 1e-4f) {
        EXPECT_EQ(m.pointCount, 0) << "reported at distance " << d.distance;
      } else if (d.distance < kSpeculativeDistance - 1e-4f) {
        ASSERT_GE(m.pointCount, 1) << "missed at distance " << d.distance;
        // Face separations may understate the distance when the closest features are a
        // vertex and a face off its end; never overstate it.
        EXPECT_LE(deepestPoint(m).separation, d.distance + 1e-4f);
      }
      continue;
    }
    ASSERT_GE(m.pointCount, 1) << testing::describe(a) << " | " << testing::describe(b);
    ++compared;
    float depth = -deepestPoint(m).separation;
    EXPECT_NEAR(depth, pen.depth, 2e-3f) << testing::describe(a) << " | " << testing::describe(b);
    if (shapeType(a) == ShapeType::polygon && shapeType(b) == ShapeType::polygon) {
      SatOutput sat = computeSat(std::get<Polygon>(a), xa, std::get<Polygon>(b), xb);
      EXPECT_NEAR(depth, -sat.separation, 2e-3f);
    }
    // The manifold's normal is a least-depth direction: pushing B along it by EPA's depth
    // separates the shapes (near-ties may pick another normal than EPA, never a worse one).
    EXPECT_NEAR(depthAlong(a, xa, b, xb, m.normal), pen.depth, 2e-3f);
    if (dot(m.normal, pen.normal) < 0.99f) ++otherNormal;
  }
  EXPECT_GT(compared, 1000);
  EXPECT_LT(otherNormal, compared / 100) << "near-ties should be rare";
}

// The general GJK/EPA path agrees with the special routines on the deepest point, and on
// whether there is a point at all. They may disagree on that only near the speculative
// distance, where a tolerance decides (checked against GJK's distance, which neither path's
// point count decides): the general path reports exactly when the distance is below
// kSpeculativeDistance; a special routine's face separation may understate the distance
// (a vertex against a face off its end: see DepthAgreesWithSatEpaAndGjk) but never
// overstates it, so it may report a pair the general path leaves out, never miss one the
// general path finds clearly inside the margin.
TEST(Manifold, GeneralPathAgreesWithSpecialRoutines) {
  const unsigned seed = 1618;
  std::mt19937 rng(seed);
  const ShapeType kinds[4] = {ShapeType::circle, ShapeType::capsule, ShapeType::segment,
                              ShapeType::polygon};
  int compared = 0;
  int disagreements = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " trial " << trial);
    ShapeGeometry a = testing::randomShape(rng, kinds[rng() % 4], 1.0f);
    ShapeGeometry b = testing::randomShape(rng, kinds[rng() % 4], 1.0f);
    if (shapeType(a) == ShapeType::segment && shapeType(b) == ShapeType::segment) continue;
    Transform xa = testing::randomTransform(rng, 0.6f);
    Transform xb = testing::randomTransform(rng, 0.6f);
    Manifold special = collide(a, xa, b, xb);
    Manifold general = collideGeneral(makeProxy(a), xa, makeProxy(b), xb);
    if ((general.pointCount == 0) != (special.pointCount == 0)) {
      ++disagreements;
      const float d = computeDistance(makeProxy(a), xa, makeProxy(b), xb).distance;
      // Neither path reports a pair clearly inside the margin as apart.
      EXPECT_GT(d, kSpeculativeDistance - 1e-4f)
          << testing::describe(a) << " | " << testing::describe(b);
      const Manifold& reported = general.pointCount > 0 ? general : special;
      const float separation = deepestPoint(reported).separation;
      EXPECT_LT(separation, kSpeculativeDistance);
      EXPECT_LE(separation, d + 1e-4f);  // understated at most, never overstated
      if (general.pointCount > 0) {
        // The special routine's separation understates the distance, so it can only be
        // the one that reports when the distance is on the boundary itself.
        EXPECT_NEAR(d, kSpeculativeDistance, 1e-4f);
      }
      continue;
    }
    if (general.pointCount == 0) continue;
    ++compared;
    EXPECT_NEAR(deepestPoint(general).separation, deepestPoint(special).separation, 2e-3f)
        << testing::describe(a) << " | " << testing::describe(b);
  }
  EXPECT_GT(compared, 1000);
  EXPECT_LT(disagreements, compared / 100);
}

}  // namespace
}  // namespace quack
