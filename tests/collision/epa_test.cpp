// EPA and SAT: hand-worked cases, the tie-break, swap and rigid-motion invariance, and
// agreement of EPA with SAT and with a brute-force depth from the explicit Minkowski
// difference.

#include <gtest/gtest.h>

#include "quack/collision/epa.hpp"
#include "quack/collision/minkowski.hpp"
#include "quack/collision/sat.hpp"
#include "test_shapes.hpp"

namespace quack {
namespace {

using testing::AnyShape;
using testing::Kind;

constexpr float kTol = 1e-5f;

Polygon box(float hx, float hy, Vec2 c = {}, float angle = 0.0f, float r = 0.0f) {
  return makeBox(hx, hy, c, angle, r).value();
}
void expectNear(Vec2 a, Vec2 b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
}

TEST(Epa, OverlappingBoxes) {
  Polygon a = box(1, 1);
  PenetrationOutput p =
      computePenetration(makeProxy(a), Transform{}, makeProxy(a), makeTransform({1.5f, 0.2f}, 0));
  EXPECT_TRUE(p.overlap);
  EXPECT_NEAR(p.depth, 0.5f, kTol);
  expectNear(p.normal, {1, 0}, kTol);
  EXPECT_NEAR(p.pointA.x, 1.0f, kTol);
  EXPECT_NEAR(p.pointB.x, 0.5f, kTol);
  expectNear(p.pointB, p.pointA - p.depth * p.normal, kTol);
  EXPECT_TRUE(p.status == EpaStatus::converged || p.status == EpaStatus::repeatedSupport);
  PenetrationOutput q =
      computePenetration(makeProxy(a), makeTransform({1.5f, 0.2f}, 0), makeProxy(a), Transform{});
  EXPECT_NEAR(q.depth, 0.5f, kTol);
  expectNear(q.normal, {-1, 0}, kTol);
}

TEST(Epa, RoundedBoxesAddTheRadii) {
  Polygon a = box(1, 1, {}, 0, 0.1f);
  Polygon b = box(1, 1, {}, 0, 0.2f);
  PenetrationOutput p =
      computePenetration(makeProxy(a), Transform{}, makeProxy(b), makeTransform({0, 1.5f}, 0));
  EXPECT_NEAR(p.depth, 0.5f + 0.3f, kTol);
  expectNear(p.normal, {0, 1}, kTol);
  EXPECT_NEAR(p.pointA.y, 1.1f, kTol);
  EXPECT_NEAR(p.pointB.y, 0.3f, kTol);
}

TEST(Epa, CirclesWithSeparateCores) {
  Circle c = makeCircle({0, 0}, 1).value();
  PenetrationOutput p =
      computePenetration(makeProxy(c), Transform{}, makeProxy(c), makeTransform({0, 1.5f}, 0));
  EXPECT_EQ(p.status, EpaStatus::coresSeparated);
  EXPECT_NEAR(p.depth, 0.5f, kTol);
  expectNear(p.normal, {0, 1}, kTol);
  expectNear(p.pointA, {0, 1}, kTol);
  expectNear(p.pointB, {0, 0.5f}, kTol);
}

TEST(Epa, ApartGivesDepthZeroAndTheClosestPoints) {
  Polygon a = box(1, 1);
  PenetrationOutput p =
      computePenetration(makeProxy(a), Transform{}, makeProxy(a), makeTransform({3, 0}, 0));
  EXPECT_FALSE(p.overlap);
  EXPECT_EQ(p.depth, 0.0f);
  EXPECT_EQ(p.status, EpaStatus::separated);
  expectNear(p.normal, {1, 0}, kTol);
}

TEST(Epa, ConcentricCirclesAreDegenerateButFinite) {
  Circle c = makeCircle({0, 0}, 1).value();
  PenetrationOutput p = computePenetration(makeProxy(c), Transform{}, makeProxy(c), Transform{});
  EXPECT_TRUE(p.overlap);
  EXPECT_NEAR(p.depth, 2.0f, kTol);
  EXPECT_EQ(p.status, EpaStatus::degenerate);
  EXPECT_NEAR(length(p.normal), 1.0f, kTol);
}

TEST(Epa, CollinearCapsulesPushSideways) {
  Capsule c = makeCapsule({-1, 0}, {1, 0}, 0.25f).value();
  PenetrationOutput p =
      computePenetration(makeProxy(c), Transform{}, makeProxy(c), makeTransform({1, 0}, 0));
  EXPECT_NEAR(p.depth, 0.5f, kTol);
  EXPECT_NEAR(absf(p.normal.y), 1.0f, kTol);
}

TEST(Epa, TouchingCoresHaveZeroCoreDepth) {
  Polygon a = box(1, 1, {}, 0, 0.1f);
  PenetrationOutput p =
      computePenetration(makeProxy(a), Transform{}, makeProxy(a), makeTransform({2, 0.5f}, 0));
  EXPECT_TRUE(p.overlap);
  EXPECT_NEAR(p.depth, 0.2f, kTol);
  expectNear(p.normal, {1, 0}, kTol);
}

// Two edges equally near: the normal most along the centre-to-centre direction wins, and
// swapping the shapes flips it.
TEST(Epa, TieBreakFollowsTheCentres) {
  Polygon a = box(1, 1);
  Polygon b = box(1, 2);
  Transform xb = makeTransform({1.5f, 2.5f}, 0);
  PenetrationOutput p = computePenetration(makeProxy(a), Transform{}, makeProxy(b), xb);
  EXPECT_NEAR(p.depth, 0.5f, kTol);
  expectNear(p.normal, {0, 1}, kTol);
  PenetrationOutput q = computePenetration(makeProxy(b), xb, makeProxy(a), Transform{});
  EXPECT_NEAR(q.depth, 0.5f, kTol);
  expectNear(q.normal, {0, -1}, kTol);
  SatOutput s = computeSat(a, Transform{}, b, xb);
  EXPECT_NEAR(s.separation, -0.5f, kTol);
}

TEST(Sat, HandWorked) {
  Polygon a = box(1, 1);
  SatOutput s = computeSat(a, Transform{}, a, makeTransform({1.5f, 0}, 0));
  EXPECT_NEAR(s.separation, -0.5f, kTol);
  expectNear(s.normal, {1, 0}, kTol);
  s = computeSat(a, Transform{}, a, makeTransform({0, -3}, 0));
  EXPECT_NEAR(s.separation, 1.0f, kTol);
  expectNear(s.normal, {0, -1}, kTol);
  // A diamond against a box: B's edge normal gives the answer.
  s = computeSat(a, Transform{}, box(1, 1, {}, kPi / 4), makeTransform({2.0f, 0}, 0));
  EXPECT_NEAR(s.separation, 1.0f - std::sqrt(2.0f), kTol);
}

// Brute-force penetration depth from the explicit Minkowski difference (world frame):
// distance from the origin to the boundary of the core hull, plus the radii.
float bruteForceDepth(const Hull& m, float radii) {
  float inside = std::numeric_limits<float>::infinity();
  for (int i = 0; i < m.count; ++i) {
    Vec2 p = m.points[i], q = m.points[(i + 1) % m.count];
    Vec2 n = normalize(rightPerp(q - p));
    inside = minf(inside, dot(n, p));
  }
  return inside + radii;  // inside < 0 means the origin is outside the core hull
}

TEST(Epa, AgreesWithSatAndBruteForceOnRandomPolygons) {
  const unsigned seed = 777;
  std::mt19937 rng(seed);
  int compared = 0;
  for (int k = 0; k < 5000; ++k) {
    int n = std::uniform_int_distribution<int>(3, 32)(rng);
    int m = std::uniform_int_distribution<int>(3, 32)(rng);
    float ra = testing::uniform(rng, 0, 1) < 0.3f ? testing::uniform(rng, 0, 0.2f) : 0.0f;
    Polygon a = testing::randomPolygon(rng, n, 1.0f, {}, ra);
    Polygon b = testing::randomPolygon(rng, m, testing::uniform(rng, 0.2f, 2.0f));
    Transform xa = testing::randomTransform(rng, 0.5f);
    Transform xb = testing::randomTransform(rng, 1.0f);
    PenetrationOutput p = computePenetration(makeProxy(a), xa, makeProxy(b), xb);
    SatOutput s = computeSat(a, xa, b, xb);
    Result<Hull> mh = computeMinkowskiDifference(makeProxy(a), xa, makeProxy(b), xb);
    ASSERT_TRUE(mh.ok());
    float brute = bruteForceDepth(mh.value(), a.radius + b.radius);
    SCOPED_TRACE("seed " + std::to_string(seed) + " pair " + std::to_string(k));
    ASSERT_TRUE(std::isfinite(p.depth) && isFinite(p.normal));
    if (p.status == EpaStatus::converged || p.status == EpaStatus::repeatedSupport) {
      // Cores overlap: all three are exact.
      EXPECT_NEAR(p.depth, -s.separation, 1e-4f);
      EXPECT_NEAR(p.depth, brute, 1e-4f);
      expectNear(p.pointB, p.pointA - p.depth * p.normal, 1e-4f);
      ++compared;
    }
    EXPECT_EQ(p.overlap, p.depth > 0.0f || p.status != EpaStatus::separated);
  }
  EXPECT_GT(compared, 1000);
}

TEST(Epa, SwapAndRigidMotionInvariance) {
  const unsigned seed = 4242;
  std::mt19937 rng(seed);
  const Kind kinds[4] = {Kind::circle, Kind::capsule, Kind::segment, Kind::polygon};
  for (int k = 0; k < 4000; ++k) {
    AnyShape sa = testing::randomShape(rng, kinds[k % 4], 1.0f);
    AnyShape sb = testing::randomShape(rng, kinds[(k / 4) % 4], 1.0f);
    Transform xa = testing::randomTransform(rng, 0.7f);
    Transform xb = testing::randomTransform(rng, 0.7f);
    ShapeProxy pa = sa.proxy(), pb = sb.proxy();
    PenetrationOutput ab = computePenetration(pa, xa, pb, xb);
    PenetrationOutput ba = computePenetration(pb, xb, pa, xa);
    SCOPED_TRACE("seed " + std::to_string(seed) + " pair " + std::to_string(k) + ": " +
                 sa.describe() + " | " + sb.describe());
    const float tol = 2e-4f;
    EXPECT_EQ(ab.overlap, ba.overlap);
    EXPECT_NEAR(ab.depth, ba.depth, tol);
    // A unique answer only when the depth is well above rounding and not a tie.
    if (ab.depth > 1e-3f && ab.status != EpaStatus::degenerate) {
      expectNear(ab.normal, -ba.normal, 1e-3f);
    }
    Transform motion = testing::randomTransform(rng, 10.0f);
    PenetrationOutput moved = computePenetration(pa, motion * xa, pb, motion * xb);
    EXPECT_NEAR(ab.depth, moved.depth, tol);
    if (ab.depth > 1e-3f && ab.status != EpaStatus::degenerate) {
      expectNear(transformVector(motion, ab.normal), moved.normal, 1e-3f);
    }
  }
}

}  // namespace
}  // namespace quack
