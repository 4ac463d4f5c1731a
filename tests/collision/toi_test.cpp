// Time of impact: hand-worked cases, the thin-wall cases (a bullet at 1,000 m/s
// and a fast-spinning rod), dense sampling of the distance along random sweeps, swapping A
// and B, rigid motion of both sweeps, and bad input.

#include "quack/collision/toi.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "test_shapes.hpp"

namespace quack {
namespace {

Sweep still(Vec2 position, float angle) {
  return {{}, position, position, angle, angle};
}
Sweep moving(Vec2 from, float angleFrom, Vec2 to, float angleTo) {
  return {{}, from, to, angleFrom, angleTo};
}

float distanceAt(const ShapeProxy& a, const Sweep& sa, const ShapeProxy& b, const Sweep& sb,
                 float t) {
  return computeDistance(a, transformAt(sa, t), b, transformAt(sb, t)).distance;
}

// The answer against `samples` + 1 samples of the exact distance along the sweeps: never
// closer than the target before out.t, and not `separated` when a sample is closer.
void expectAgreesWithSampling(const ShapeProxy& a, const Sweep& sa, const ShapeProxy& b,
                              const Sweep& sb, const ToiOutput& out, int samples) {
  for (int k = 0; k <= samples; ++k) {
    const float t = static_cast<float>(k) / static_cast<float>(samples);
    const float d = distanceAt(a, sa, b, sb, t);
    if (t < out.t) {
      ASSERT_GT(d, kToiTargetSeparation - 1e-4f)
          << "closer than the target at t = " << t << " before " << out.t;
    } else if (d < kToiTargetSeparation - 1e-4f) {
      ASSERT_NE(out.status, ToiStatus::separated) << "separated, but close at t = " << t;
      return;
    }
  }
}

TEST(Toi, CircleThroughABox) {
  Polygon box = makeBox(1.0f, 1.0f).value();
  ShapeProxy a = makeProxy(box);
  ShapeProxy b = makeProxy(makeCircle({}, 0.5f).value());
  Sweep sb = moving({-5, 0.3f}, 0, {5, 0.3f}, 0);
  ToiOutput out = computeToi(a, still({}, 0), b, sb);
  ASSERT_EQ(out.status, ToiStatus::hit);
  // The circle's centre reaches x = -1.5 - target at t = (3.5 - target) / 10.
  EXPECT_NEAR(out.t, (3.5f - kToiTargetSeparation) / 10.0f, kToiTolerance / 10.0f);
  EXPECT_GE(out.distance, kToiTargetSeparation - 1e-6f);
  EXPECT_LT(out.distance, kToiTargetSeparation + kToiTolerance);
  EXPECT_NEAR(out.normal.x, -1.0f, 1e-6f);
  EXPECT_NEAR(out.point.x, -1.0f, 1e-5f);
  // The search starts where the circle first comes within the aim of the face's line, and
  // along the face's normal it is in the band there: the face settles it (the centre meets
  // the face square), with no evaluation.
  EXPECT_EQ(out.iterations, 0);
  // Target 0: touching.
  ToiOutput touch = computeToi(a, still({}, 0), b, sb, 1.0f, 0.0f);
  ASSERT_EQ(touch.status, ToiStatus::hit);
  EXPECT_NEAR(touch.t, 0.35f, kToiTolerance / 10.0f);
}

TEST(Toi, SeparatedOverlappedAndShort) {
  ShapeProxy a = makeProxy(makeCircle({}, 1.0f).value());
  ShapeProxy b = makeProxy(makeCircle({}, 0.5f).value());
  ToiOutput past = computeToi(a, still({}, 0), b, moving({-5, 2}, 0, {5, 2}, 3));
  EXPECT_EQ(past.status, ToiStatus::separated);
  EXPECT_EQ(past.t, 1.0f);
  ToiOutput shortSweep = computeToi(a, still({}, 0), b, moving({-5, 0}, 0, {5, 0}, 0), 0.3f);
  EXPECT_EQ(shortSweep.status, ToiStatus::separated);
  EXPECT_EQ(shortSweep.t, 0.3f);
  ToiOutput overlapped = computeToi(a, still({}, 0), b, moving({1, 0}, 0, {5, 0}, 0));
  EXPECT_EQ(overlapped.status, ToiStatus::overlapped);
  EXPECT_EQ(overlapped.t, 0.0f);
  EXPECT_NEAR(overlapped.normal.x, 1.0f, 1e-6f);
  EXPECT_NEAR(overlapped.distance, -0.5f, 1e-6f);
  // Both moving, head on: they meet in the middle.
  ToiOutput headOn =
      computeToi(a, moving({-5, 0}, 0, {5, 0}, 0), b, moving({5, 0}, 0, {-5, 0}, 0), 1.0f, 0.0f);
  ASSERT_EQ(headOn.status, ToiStatus::hit);
  EXPECT_NEAR(headOn.t, (10.0f - 1.5f) / 20.0f, 1e-4f);
}

TEST(Toi, BadInputGetsAStatusAndANamedError) {
  ShapeProxy a = makeProxy(makeCircle({}, 1.0f).value());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  Sweep bad = moving({0, 0}, 0, {nan, 0}, 0);
  EXPECT_EQ(computeToi(a, still({}, 0), a, bad).status, ToiStatus::invalidInput);
  EXPECT_EQ(computeToi(a, moving({0, 0}, inf, {5, 0}, 0), a, still({3, 0}, 0)).status,
            ToiStatus::invalidInput);
  EXPECT_EQ(computeToi(a, still({}, 0), a, still({5, 0}, 0), 1.5f).status, ToiStatus::invalidInput);
  EXPECT_EQ(computeToi(a, still({}, 0), a, still({5, 0}, 0), 1.0f, -1.0f).status,
            ToiStatus::invalidInput);
  EXPECT_EQ(computeToi(a, still({}, 0), a, still({5, 0}, 0), 1.0f, nan).status,
            ToiStatus::invalidInput);
  Status s = checkSweep(bad, "sweepB");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message(), "sweepB.c2.x is not finite: nan");
  EXPECT_TRUE(checkSweep(still({1, 2}, 3), "sweepA").ok());
  EXPECT_STREQ(toString(ToiStatus::separated), "separated");
  EXPECT_STREQ(toString(ToiStatus::invalidInput), "invalid_input");
}

// Issue 7: a 1 cm thick wall and a small bullet at 1,000 m/s over a 60 Hz step, over many
// angles and offsets: the bullet never gets through, and it stops just short.
TEST(Toi, BulletAtAThousandMetresPerSecondNeverPassesAThinWall) {
  const unsigned seed = 7003;
  std::mt19937 rng(seed);
  Polygon wall = makeBox(0.005f, 2.0f).value();  // 1 cm thick, 4 m tall, at x = 0
  ShapeProxy a = makeProxy(wall);
  Polygon bulletBox = makeBox(0.01f, 0.004f).value();
  Circle bulletBall = makeCircle({}, 0.01f).value();
  const float step = 1000.0f / 60.0f;  // metres per step
  int maxIterations = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    ShapeProxy b = trial % 2 == 0 ? makeProxy(bulletBox) : makeProxy(bulletBall);
    float heading = testing::uniform(rng, -1.4f, 1.4f);  // up to 80 degrees off the normal
    Vec2 dir{std::cos(heading), std::sin(heading)};
    Vec2 crossing{0.0f, testing::uniform(rng, -1.9f, 1.9f)};
    // The wall crossing happens somewhere in the step.
    float before = testing::uniform(rng, 0.05f, 0.95f) * step;
    Vec2 start = crossing - before * dir;
    float spin = testing::uniform(rng, -20.0f, 20.0f);
    float angle0 = testing::uniform(rng, -kPi, kPi);
    Sweep sb = moving(start, angle0, start + step * dir, angle0 + spin);
    ToiOutput out = computeToi(a, still({}, 0), b, sb);
    ASSERT_EQ(out.status, ToiStatus::hit) << toString(out.status);
    maxIterations = std::max(maxIterations, out.iterations);
    // Stopped on the near side, apart from the wall.
    Transform at = transformAt(sb, out.t);
    EXPECT_LT(at.p.x, 0.0f);
    EXPECT_GE(distanceAt(a, still({}, 0), b, sb, out.t), kToiTargetSeparation - 1e-4f);
    // Dense samples before t never touch.
    for (int k = 0; k < 200; ++k) {
      float t = out.t * static_cast<float>(k) / 200.0f;
      ASSERT_GT(distanceAt(a, still({}, 0), b, sb, t), 0.0f) << "t = " << t;
    }
  }
  RecordProperty("max_iterations", maxIterations);
}

// Issue 7: a thin rod spinning fast (up to two turns a step) next to a thin wall.
TEST(Toi, ThinFastSpinningRodNeverPassesAThinWall) {
  const unsigned seed = 7004;
  std::mt19937 rng(seed);
  Polygon wall = makeBox(0.005f, 3.0f).value();
  ShapeProxy a = makeProxy(wall);
  Capsule rod = makeCapsule({-0.5f, 0}, {0.5f, 0}, 0.005f).value();
  ShapeProxy b = makeProxy(rod);
  int hits = 0, failed = 0, maxIterations = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    Vec2 c1{testing::uniform(rng, -1.5f, -0.52f), testing::uniform(rng, -1.0f, 1.0f)};
    Vec2 c2 = c1 + Vec2{testing::uniform(rng, 0.0f, 1.0f), testing::uniform(rng, -0.5f, 0.5f)};
    float a1 = testing::uniform(rng, -kPi, kPi);
    // Up to two turns a step (a world with 4 sub-steps turns at most half a turn).
    float spin = testing::uniform(rng, -4.0f * kPi, 4.0f * kPi);
    Sweep sb = moving(c1, a1, c2, a1 + spin);
    ToiOutput out = computeToi(a, still({}, 0), b, sb);
    maxIterations = std::max(maxIterations, out.iterations);
    ASSERT_NE(out.status, ToiStatus::invalidInput);
    if (out.status == ToiStatus::overlapped) continue;
    hits += out.status == ToiStatus::hit;
    failed += out.status == ToiStatus::failed;
    // Nothing before t comes within the target (the answer is never late).
    for (int k = 0; k <= 2000; ++k) {
      float t = out.t * static_cast<float>(k) / 2000.0f;
      ASSERT_GT(distanceAt(a, still({}, 0), b, sb, t), kToiTargetSeparation - 1e-4f)
          << "t = " << t << " of " << out.t << " " << toString(out.status);
    }
    if (out.status == ToiStatus::hit) {
      EXPECT_LT(out.distance, kToiTargetSeparation + kToiTolerance);
    }
  }
  RecordProperty("hits", hits);
  RecordProperty("failed", failed);
  RecordProperty("max_iterations", maxIterations);
  EXPECT_GT(hits, 300);
  EXPECT_LE(failed, 10);
}

// A hit against GJK at its time: the distance in the band, the reported distance no less
// than it, the normal GJK's (to 2.6 degrees), the point on A no further from B than the
// distance reported. Hits the face settles (with or without an evaluation before) report
// the face's numbers, the others the search's last evaluation.
void expectHitAgreesWithGjk(const ShapeProxy& a, const Sweep& sa, const ShapeProxy& b,
                            const Sweep& sb, const ToiOutput& out) {
  const DistanceOutput d = computeDistance(a, transformAt(sa, out.t), b, transformAt(sb, out.t));
  EXPECT_GE(d.distance, kToiTargetSeparation - 1e-5f);
  EXPECT_LT(d.distance, kToiTargetSeparation + kToiTolerance + 1e-5f);
  EXPECT_GE(out.distance, d.distance - 1e-5f);
  EXPECT_GT(dot(out.normal, d.normal), 0.999f);
  const ShapeProxy point = ShapeProxy::fromPoints(&out.point, 1, 0.0f);
  const float fromPoint = computeDistance(point, Transform{}, b, transformAt(sb, out.t)).distance;
  EXPECT_LE(fromPoint, out.distance + 1e-5f);
  EXPECT_GE(fromPoint, kToiTargetSeparation - 1e-5f);
}

// Random pairs of every kind with random sweeps (translation and up to two turns): the
// answer against the distance sampled densely along the sweeps.
TEST(Toi, AgreesWithDenseSampling) {
  const unsigned seed = 7005;
  std::mt19937 rng(seed);
  const ShapeType kinds[] = {ShapeType::circle, ShapeType::capsule, ShapeType::segment,
                             ShapeType::polygon};
  constexpr int kSamples = 1000;
  int counts[5] = {};
  for (int trial = 0; trial < 600; ++trial) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    ShapeGeometry sa = testing::randomShape(rng, kinds[trial % 4], 1.0f);
    ShapeGeometry sb = testing::randomShape(rng, kinds[(trial / 4) % 4], 1.0f);
    ShapeProxy a = makeProxy(sa), b = makeProxy(sb);
    auto randomSweep = [&](float extent) {
      Vec2 c1{testing::uniform(rng, -extent, extent), testing::uniform(rng, -extent, extent)};
      Vec2 c2{testing::uniform(rng, -extent, extent), testing::uniform(rng, -extent, extent)};
      float a1 = testing::uniform(rng, -kPi, kPi);
      Vec2 lc{testing::uniform(rng, -0.3f, 0.3f), testing::uniform(rng, -0.3f, 0.3f)};
      return Sweep{lc, c1, c2, a1,
                   a1 + testing::uniform(rng, -4 * kPi, 4 * kPi) * (trial % 3 == 0 ? 0.0f : 1.0f)};
    };
    Sweep sweepA = randomSweep(1.0f);
    Sweep sweepB = randomSweep(5.0f);
    ToiOutput out = computeToi(a, sweepA, b, sweepB);
    counts[static_cast<int>(out.status)]++;
    ASSERT_NE(out.status, ToiStatus::invalidInput);
    if (out.status == ToiStatus::overlapped) {
      EXPECT_EQ(distanceAt(a, sweepA, b, sweepB, 0.0f), 0.0f);
      EXPECT_NEAR(length(out.normal), 1.0f, 1e-4f);
      continue;
    }
    if (out.status == ToiStatus::hit) {
      EXPECT_NEAR(length(out.normal), 1.0f, 1e-4f);
      const float d = distanceAt(a, sweepA, b, sweepB, out.t);
      EXPECT_GE(d, kToiTargetSeparation - 1e-4f);
      EXPECT_LT(d, kToiTargetSeparation + kToiTolerance + 1e-4f);
      expectHitAgreesWithGjk(a, sweepA, b, sweepB, out);
    }
    expectAgreesWithSampling(a, sweepA, b, sweepB, out, kSamples);
    if (::testing::Test::HasFatalFailure()) return;
  }
  RecordProperty("hit", counts[0]);
  RecordProperty("separated", counts[1]);
  RecordProperty("overlapped", counts[2]);
  RecordProperty("failed", counts[3]);
  EXPECT_GT(counts[0], 100);
  EXPECT_GT(counts[1], 50);
  EXPECT_LE(counts[3], 6);  // failures are allowed, but rare; they are never late
}

// The second-order search along an axis runs when one shape turns much more than
// the other: a spinning shape against a still one, its answer checked against 2,001 samples
// of the exact distance, and the answer's distance against the band.
TEST(Toi, OneShapeTurningAgreesWithDenseSampling) {
  const unsigned seed = 7018;
  std::mt19937 rng(seed);
  const ShapeType kinds[] = {ShapeType::circle, ShapeType::capsule, ShapeType::segment,
                             ShapeType::polygon};
  constexpr int kSamples = 2000;
  int counts[5] = {};
  for (int trial = 0; trial < 400; ++trial) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    ShapeGeometry sa = testing::randomShape(rng, kinds[trial % 4], 1.5f);
    ShapeGeometry sb = testing::randomShape(rng, kinds[(trial / 4) % 4], 1.0f);
    ShapeProxy a = makeProxy(sa), b = makeProxy(sb);
    const float angleA = testing::uniform(rng, -kPi, kPi);
    const Vec2 cA{testing::uniform(rng, -0.5f, 0.5f), testing::uniform(rng, -0.5f, 0.5f)};
    // A still, or turning a little (below the search's share of the spin).
    const float turnA = trial % 2 == 0 ? 0.0f : testing::uniform(rng, -0.05f, 0.05f);
    Sweep sweepA{{}, cA, cA, angleA, angleA + turnA};
    const Vec2 c1{testing::uniform(rng, -4.0f, -1.0f), testing::uniform(rng, -2.0f, 2.0f)};
    const Vec2 c2 = c1 + Vec2{testing::uniform(rng, 0.0f, 5.0f), testing::uniform(rng, -2, 2)};
    const float a1 = testing::uniform(rng, -kPi, kPi);
    Vec2 lc{testing::uniform(rng, -0.3f, 0.3f), testing::uniform(rng, -0.3f, 0.3f)};
    Sweep sweepB{lc, c1, c2, a1, a1 + testing::uniform(rng, -4 * kPi, 4 * kPi)};
    ToiOutput out = computeToi(a, sweepA, b, sweepB);
    counts[static_cast<int>(out.status)]++;
    ASSERT_NE(out.status, ToiStatus::invalidInput);
    if (out.status == ToiStatus::overlapped) continue;
    // A pair that starts within the target is a hit at t = 0 at whatever distance it has.
    if (out.status == ToiStatus::hit && out.t > 0.0f) {
      const float d = distanceAt(a, sweepA, b, sweepB, out.t);
      EXPECT_GE(d, kToiTargetSeparation - 1e-4f);
      EXPECT_LT(d, kToiTargetSeparation + kToiTolerance + 1e-4f);
      expectHitAgreesWithGjk(a, sweepA, b, sweepB, out);
    }
    expectAgreesWithSampling(a, sweepA, b, sweepB, out, kSamples);
    if (::testing::Test::HasFatalFailure()) return;
  }
  RecordProperty("hit", counts[0]);
  RecordProperty("separated", counts[1]);
  RecordProperty("failed", counts[3]);
  EXPECT_GT(counts[0], 100);
  EXPECT_GT(counts[1], 30);
  EXPECT_LE(counts[3], 4);
}

// The bounds that answer before any distance evaluation, or say where the search starts:
// the shapes' circles about their centres of mass, and a still shape's edge
// lines against the other's circle.
// They may settle only pairs that stay beyond the aim (target + half the tolerance)
// throughout; what they
// settle is checked against 1,001 samples of the exact distance, with the still shape's
// points given counter-clockwise, clockwise and shuffled (a proxy's points may come in any
// order; an edge's line is taken through the support along its normal, so any order gives
// true bounds, if fewer of them).
// The kinds a still shape with edges can be, and every kind, for the random sweeps.
constexpr ShapeType kStillKinds[] = {ShapeType::capsule, ShapeType::segment, ShapeType::polygon};
constexpr ShapeType kMovingKinds[] = {ShapeType::circle, ShapeType::capsule, ShapeType::segment,
                                      ShapeType::polygon};

// A still shape's proxy with its points as given (counter-clockwise), reversed or shuffled
// (`order` 0, 1, 2; the bounds must hold whatever the order). It views `points`.
ShapeProxy reorderedProxy(const ShapeProxy& given, int order, std::mt19937& rng,
                          Vec2 (&points)[kMaxPolygonVertices]) {
  const int count = given.count();
  std::copy(given.points(), given.points() + count, points);
  if (order == 1) std::reverse(points, points + count);
  if (order == 2) std::shuffle(points, points + count, rng);
  return ShapeProxy::fromPoints(points, count, given.radius());
}

TEST(Toi, BoundsSettleOnlyPairsThatStayApart) {
  // Hand-worked: a 1 m rod (half-extent 0.500016 m about its centre) beside a wall whose
  // face is at x = -0.005, its centre moving from x = -0.6 to -0.55 while it makes half a
  // turn. Its circle stays 0.544984 - 0.5 = 0.044984 m from the face line at the end: the
  // edge bound settles it, with no GJK call, and that is the distance reported.
  const Polygon wallBox = makeBox(0.005f, 2.0f).value(), rodBox = makeBox(0.5f, 0.004f).value();
  const ShapeProxy wall = makeProxy(wallBox), rod = makeProxy(rodBox);  // they view the boxes
  const ToiOutput apart =
      computeToi(wall, still({}, 0), rod, moving({-0.6f, 0.3f}, 0.3f, {-0.55f, 0.3f}, 0.3f + kPi));
  EXPECT_EQ(apart.status, ToiStatus::separated);
  EXPECT_EQ(apart.iterations, 0);
  EXPECT_EQ(apart.t, 1.0f);
  const float extent = std::sqrt(0.5f * 0.5f + 0.004f * 0.004f);
  EXPECT_NEAR(apart.distance, 0.545f - extent, 1e-6f);
  // Its centre 0.45 m from the wall, turning from upright to level: the tip reaches past
  // the face (to x = 0.05), so nothing may settle it; the search finds the impact.
  const Sweep turning = moving({-0.45f, 0.3f}, 0.5f * kPi, {-0.45f, 0.3f}, kPi);
  const ToiOutput close = computeToi(wall, still({}, 0), rod, turning);
  ASSERT_EQ(close.status, ToiStatus::hit);
  // Its circle is within reach of the face from the start, so the edge bound says nothing;
  // the search along the face's normal follows the tip in (the gap 0.0058 m at t = 0.6776
  // by hand), and the tip lands on the face: the face settles it with no GJK call.
  EXPECT_EQ(close.iterations, 0);
  const float closeGap = distanceAt(wall, still({}, 0), rod, turning, close.t);
  EXPECT_GE(closeGap, kToiTargetSeparation - 1e-5f);
  EXPECT_LT(closeGap, kToiTargetSeparation + kToiTolerance + 1e-5f);
  EXPECT_GT(close.t, 0.0f);
  EXPECT_LT(close.t, 1.0f);
  expectAgreesWithSampling(wall, still({}, 0), rod, turning, close, 1000);
  // From 3 m away, turning half a turn on the way in: the search starts where the rod's
  // circle first comes within the aim (target + tolerance / 2 = 5.625 mm) of the face's
  // line, t = (3 - 0.005 - 0.500016 - 0.005625) / 2.7 = 0.92199; every time before is free
  // without an evaluation. The rod is level to 3 degrees by then, its tip in the band and
  // on the face: the face settles it, with no evaluation.
  const Sweep approaching = moving({-3.0f, 0.3f}, 0.2f, {-0.3f, 0.3f}, 0.2f + kPi);
  const ToiOutput far = computeToi(wall, still({}, 0), rod, approaching);
  ASSERT_EQ(far.status, ToiStatus::hit);
  EXPECT_NEAR(far.t, 0.92199f, 2e-5f);
  EXPECT_EQ(far.iterations, 0);
  expectAgreesWithSampling(wall, still({}, 0), rod, approaching, far, 2000);
  // Circles: a disc passing 2 m from a unit disc's centre.
  const ShapeProxy unit = makeProxy(makeCircle({}, 1.0f).value());
  const ShapeProxy half = makeProxy(makeCircle({}, 0.5f).value());
  const ToiOutput past = computeToi(unit, still({}, 0), half, moving({-5, 2}, 0, {5, 2}, 3));
  EXPECT_EQ(past.status, ToiStatus::separated);
  EXPECT_EQ(past.iterations, 0);
  EXPECT_NEAR(past.distance, std::sqrt(29.0f) - 1.5f, 1e-5f);  // at t = 1, centre (5, 2)

  const unsigned seed = 7019;
  std::mt19937 rng(seed);
  int settled = 0, byEdges = 0, searched = 0;
  for (int trial = 0; trial < 600; ++trial) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    const ShapeGeometry sa = testing::randomShape(rng, kStillKinds[trial % 3], 2.0f);
    const ShapeGeometry sb = testing::randomShape(rng, kMovingKinds[(trial / 3) % 4], 0.7f);
    Vec2 points[kMaxPolygonVertices];
    const ShapeProxy a = reorderedProxy(makeProxy(sa), (trial / 12) % 3, rng, points);
    const ShapeProxy b = makeProxy(sb);
    const float angleA = testing::uniform(rng, -kPi, kPi);
    const Sweep sweepA = still({testing::uniform(rng, -0.3f, 0.3f), 0.0f}, angleA);
    const float heading = testing::uniform(rng, -kPi, kPi);
    const Vec2 c1 = testing::uniform(rng, 1.0f, 4.0f) * Vec2{std::cos(heading), std::sin(heading)};
    const Vec2 c2 =
        c1 + Vec2{testing::uniform(rng, -0.5f, 0.5f), testing::uniform(rng, -0.5f, 0.5f)};
    const float a1 = testing::uniform(rng, -kPi, kPi);
    const Vec2 lc{testing::uniform(rng, -0.2f, 0.2f), testing::uniform(rng, -0.2f, 0.2f)};
    const Sweep sweepB{lc, c1, c2, a1, a1 + testing::uniform(rng, -2 * kPi, 2 * kPi)};
    const ToiOutput out = computeToi(a, sweepA, b, sweepB);
    ASSERT_NE(out.status, ToiStatus::invalidInput);
    expectAgreesWithSampling(a, sweepA, b, sweepB, out, 1000);
    if (::testing::Test::HasFatalFailure()) return;
    if (out.iterations > 0 || out.status != ToiStatus::separated) {
      ++searched;
      continue;
    }
    ++settled;
    // Settled: at least the aim (target + half the tolerance) at every sample, and the
    // distance a lower bound at t = 1.
    float least = std::numeric_limits<float>::infinity();
    for (int k = 0; k <= 1000; ++k)
      least = std::min(least, distanceAt(a, sweepA, b, sweepB, static_cast<float>(k) / 1000.0f));
    EXPECT_GE(least, kToiTargetSeparation + 0.5f * kToiTolerance);
    EXPECT_GE(out.distance, kToiTargetSeparation);
    EXPECT_LE(out.distance, distanceAt(a, sweepA, b, sweepB, 1.0f) + 1e-4f);
    // Which bound settled it: the circles could not when they come within reach.
    const float reach = computeMaxExtent(a, sweepA.localCenter) +
                        computeMaxExtent(b, sweepB.localCenter) + kToiTargetSeparation +
                        2.0f * kToiTolerance;
    bool circlesMeet = false;
    for (int k = 0; k <= 1000 && !circlesMeet; ++k) {
      const float t = static_cast<float>(k) / 1000.0f;
      circlesMeet =
          length((1.0f - t) * (sweepB.c1 - sweepA.c1) + t * (sweepB.c2 - sweepA.c2)) < reach;
    }
    if (circlesMeet) ++byEdges;
  }
  RecordProperty("settled", settled);
  RecordProperty("settled_by_edges", byEdges);
  RecordProperty("searched", searched);
  EXPECT_GT(byEdges, 30);
  EXPECT_GT(settled - byEdges, 30);
  EXPECT_GT(searched, 100);
}

TEST(Toi, StillFaceSettlesHitsOnlyWhereTheTipMeetsIt) {
  // Hand-worked, refused: a disc of radius 0.5, its centre at y = 1.3, moving right from
  // x = -3 to 0 past the top corner (-1, 1) of a 2 m box. The left face is the one it
  // starts furthest beyond; along its normal the gap reaches the aim at x = -1.505625
  // (t = 0.4981), but there the centre is 0.588 m from the face's segment (its corner): the
  // face cannot settle it, GJK goes on to the corner, where the distance is at the aim:
  // x = -1 - sqrt(0.505625^2 - 0.3^2) = -1.407021, t = 0.530993.
  const Polygon boxShape = makeBox(1.0f, 1.0f).value();
  const ShapeProxy box = makeProxy(boxShape);  // views boxShape
  const ShapeProxy disc = makeProxy(makeCircle({}, 0.5f).value());
  const Sweep past = moving({-3.0f, 1.3f}, 0, {0.0f, 1.3f}, 0);
  const ToiOutput corner = computeToi(box, still({}, 0), disc, past);
  ASSERT_EQ(corner.status, ToiStatus::hit);
  EXPECT_GE(corner.iterations, 1);
  EXPECT_NEAR(corner.t, 0.530993f, 1e-4f);
  expectAgreesWithSampling(box, still({}, 0), disc, past, corner, 2000);
  // The same disc 0.2 m lower meets the face itself at x = -1.505625: settled.
  const Sweep square = moving({-3.0f, 0.8f}, 0, {0.0f, 0.8f}, 0);
  const ToiOutput face = computeToi(box, still({}, 0), disc, square);
  ASSERT_EQ(face.status, ToiStatus::hit);
  EXPECT_EQ(face.iterations, 0);
  EXPECT_NEAR(face.t, (3.0f - 1.505625f) / 3.0f, 2e-4f);
  expectHitAgreesWithGjk(box, still({}, 0), disc, square, face);
  // Swapped (the still box as B): the same time, the normal reversed.
  const ToiOutput swapped = computeToi(disc, square, box, still({}, 0));
  ASSERT_EQ(swapped.status, ToiStatus::hit);
  EXPECT_EQ(swapped.iterations, 0);
  EXPECT_NEAR(swapped.t, face.t, 1e-6f);
  EXPECT_NEAR(swapped.normal.x, 1.0f, 1e-6f);
  expectHitAgreesWithGjk(disc, square, box, still({}, 0), swapped);

  // Random: a still shape (points in order, reversed or shuffled: a face that is not at the
  // support must be refused) against any shape moving and turning, as either A or B. Every
  // answer against dense sampling; every settled hit against GJK at its time.
  const unsigned seed = 7023;
  std::mt19937 rng(seed);
  int settled = 0, searched = 0;
  for (int trial = 0; trial < 600; ++trial) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    const ShapeGeometry gs = testing::randomShape(rng, kStillKinds[trial % 3], 2.0f);
    const ShapeGeometry gm = testing::randomShape(rng, kMovingKinds[(trial / 3) % 4], 0.7f);
    Vec2 points[kMaxPolygonVertices];
    const ShapeProxy fixed = reorderedProxy(makeProxy(gs), (trial / 12) % 3, rng, points);
    const ShapeProxy mover = makeProxy(gm);
    const Sweep fixedSweep =
        still({testing::uniform(rng, -0.3f, 0.3f), 0.0f}, testing::uniform(rng, -kPi, kPi));
    const float heading = testing::uniform(rng, -kPi, kPi);
    const Vec2 c1 = testing::uniform(rng, 1.5f, 4.0f) * Vec2{std::cos(heading), std::sin(heading)};
    const Vec2 c2 = testing::uniform(rng, 0.0f, 1.0f) * c1;  // towards the still shape
    const float a1 = testing::uniform(rng, -kPi, kPi);
    const float turn = (trial / 36) % 2 == 0 ? 0.0f : testing::uniform(rng, -1.0f, 1.0f);
    const Sweep moverSweep{{}, c1, c2, a1, a1 + turn};
    const bool fixedIsA = trial % 2 == 0;
    const ShapeProxy& a = fixedIsA ? fixed : mover;
    const ShapeProxy& b = fixedIsA ? mover : fixed;
    const Sweep& sa = fixedIsA ? fixedSweep : moverSweep;
    const Sweep& sb = fixedIsA ? moverSweep : fixedSweep;
    const ToiOutput out = computeToi(a, sa, b, sb);
    ASSERT_NE(out.status, ToiStatus::invalidInput);
    expectAgreesWithSampling(a, sa, b, sb, out, 1000);
    if (::testing::Test::HasFatalFailure()) return;
    if (out.status != ToiStatus::hit) continue;
    expectHitAgreesWithGjk(a, sa, b, sb, out);
    ++(out.iterations > 0 ? searched : settled);
  }
  RecordProperty("settled", settled);
  RecordProperty("searched", searched);
  // 91 settled and 165 searched of 256 hits at this seed.
  EXPECT_GT(settled, 60);
  EXPECT_GT(searched, 100);
}

TEST(Toi, SwapAndRigidMotion) {
  const unsigned seed = 7006;
  std::mt19937 rng(seed);
  const ShapeType kinds[] = {ShapeType::circle, ShapeType::capsule, ShapeType::segment,
                             ShapeType::polygon};
  for (int trial = 0; trial < 300; ++trial) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    ShapeGeometry sa = testing::randomShape(rng, kinds[trial % 4], 1.0f);
    ShapeGeometry sb = testing::randomShape(rng, kinds[(trial / 4) % 4], 1.0f);
    ShapeProxy a = makeProxy(sa), b = makeProxy(sb);
    Sweep sweepA = moving({0, 0}, 0.3f, {0.5f, 0.2f}, 0.3f + testing::uniform(rng, -1, 1));
    Vec2 c1{testing::uniform(rng, -6, -3), testing::uniform(rng, -2, 2)};
    Sweep sweepB =
        moving(c1, 0, c1 + Vec2{testing::uniform(rng, 4, 9), testing::uniform(rng, -2, 2)},
               testing::uniform(rng, -2, 2));
    ToiOutput out = computeToi(a, sweepA, b, sweepB);
    if (out.status != ToiStatus::hit) continue;
    ToiOutput swapped = computeToi(b, sweepB, a, sweepA);
    ASSERT_EQ(swapped.status, ToiStatus::hit);
    // Both stop inside the same band; the band is crossed in a short time.
    EXPECT_NEAR(swapped.t, out.t, 2e-3f);
    EXPECT_NEAR(dot(swapped.normal, out.normal), -1.0f, 0.05f);
    // A rigid motion of the whole scene (both sweeps) changes nothing but the frame.
    const float turn = testing::uniform(rng, -kPi, kPi);
    const Transform m = makeTransform({testing::uniform(rng, -10, 10), 3}, turn);
    auto moveSweep = [&](Sweep s) {
      s.c1 = transformPoint(m, s.c1);
      s.c2 = transformPoint(m, s.c2);
      s.a1 += turn;
      s.a2 += turn;
      return s;
    };
    ToiOutput moved = computeToi(a, moveSweep(sweepA), b, moveSweep(sweepB));
    ASSERT_EQ(moved.status, ToiStatus::hit);
    EXPECT_NEAR(moved.t, out.t, 2e-3f);
    EXPECT_NEAR(dot(moved.normal, rotate(m.q, out.normal)), 1.0f, 0.05f);
  }
}

}  // namespace
}  // namespace quack
