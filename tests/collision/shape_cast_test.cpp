// Shape cast: hand-worked cases, initial overlap, dense sampling of the distance along the
// translation, swapping A and B, and rigid motion of the whole query.

#include "quack/collision/shape_cast.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "quack/collision/epa.hpp"
#include "test_shapes.hpp"

namespace quack {
namespace {

TEST(ShapeCast, CircleOntoCircle) {
  ShapeProxy a = makeProxy(makeCircle({}, 1.0f).value());
  ShapeProxy b = makeProxy(makeCircle({}, 0.5f).value());
  ShapeCastOutput out = castShape(a, {}, b, makeTransform({5, 0}, 0), {-10, 0});
  ASSERT_EQ(out.status, ShapeCastStatus::hit);
  EXPECT_TRUE(out.hit);
  // Touching when B's centre is at x = 1.5: fraction 3.5 / 10.
  EXPECT_NEAR(out.fraction, 0.35f, kShapeCastTolerance / 10.0f);
  EXPECT_NEAR(out.normal.x, 1.0f, 1e-6f);
  EXPECT_NEAR(out.normal.y, 0.0f, 1e-6f);
  EXPECT_NEAR(out.point.x, 1.0f, 1e-5f);
  EXPECT_LE(out.iterations, 6);
}

TEST(ShapeCast, BoxFaceOntoBoxFaceInOneStep) {
  Polygon boxA = makeBox(1.0f, 1.0f).value();
  Polygon boxB = makeBox(0.5f, 0.5f).value();
  ShapeCastOutput out =
      castShape(makeProxy(boxA), {}, makeProxy(boxB), makeTransform({0.2f, 5}, 0), {0, -10});
  ASSERT_EQ(out.status, ShapeCastStatus::hit);
  EXPECT_NEAR(out.fraction, 0.35f, kShapeCastTolerance / 10.0f);
  EXPECT_NEAR(out.normal.y, 1.0f, 1e-6f);
  EXPECT_LE(out.iterations, 3);
}

TEST(ShapeCast, MissesWhenMovingAwayOrPastOrShort) {
  ShapeProxy a = makeProxy(makeCircle({}, 1.0f).value());
  ShapeProxy b = makeProxy(makeCircle({}, 0.5f).value());
  Transform at5 = makeTransform({5, 0}, 0);
  EXPECT_EQ(castShape(a, {}, b, at5, {10, 0}).status, ShapeCastStatus::missed);
  EXPECT_EQ(castShape(a, {}, b, at5, {0, 10}).status, ShapeCastStatus::missed);
  EXPECT_EQ(castShape(a, {}, b, at5, {-3, 0}).status, ShapeCastStatus::missed);
  EXPECT_EQ(castShape(a, {}, b, at5, {-10, 0}, 0.3f).status, ShapeCastStatus::missed);
  EXPECT_EQ(castShape(a, {}, b, at5, {-10, 0}, 0.3f).fraction, 0.3f);
  EXPECT_FALSE(castShape(a, {}, b, at5, {10, 0}).hit);
}

TEST(ShapeCast, TouchingAndLeavingIsAMiss) {
  Polygon ground = makeBox(5.0f, 0.5f).value();
  Polygon box = makeBox(0.5f, 0.5f).value();
  ShapeCastOutput up =
      castShape(makeProxy(ground), {}, makeProxy(box), makeTransform({0, 1.00005f}, 0), {0, 3});
  EXPECT_EQ(up.status, ShapeCastStatus::missed);
  ShapeCastOutput down =
      castShape(makeProxy(ground), {}, makeProxy(box), makeTransform({0, 1.00005f}, 0), {0, -3});
  EXPECT_EQ(down.status, ShapeCastStatus::hit);
  EXPECT_EQ(down.fraction, 0.0f);
}

TEST(ShapeCast, InitialOverlapGivesDepenetrationNeverAZeroNormal) {
  Polygon boxA = makeBox(1.0f, 1.0f).value();
  Polygon boxB = makeBox(0.5f, 0.5f).value();
  Transform xb = makeTransform({1.2f, 0.1f}, 0);
  ShapeCastOutput out = castShape(makeProxy(boxA), {}, makeProxy(boxB), xb, {-1, 0});
  ASSERT_EQ(out.status, ShapeCastStatus::overlapped);
  EXPECT_TRUE(out.hit);
  EXPECT_EQ(out.fraction, 0.0f);
  EXPECT_NEAR(out.normal.x, 1.0f, 1e-6f);
  EXPECT_NEAR(out.depth, 0.3f, 1e-5f);
  // Identical circles on the same centre: EPA's degenerate case still gives a direction.
  ShapeProxy c = makeProxy(makeCircle({}, 1.0f).value());
  for (Vec2 motion : {Vec2{1, 0}, Vec2{0, 0}, Vec2{-3, 4}}) {
    ShapeCastOutput same = castShape(c, {}, c, {}, motion);
    ASSERT_EQ(same.status, ShapeCastStatus::overlapped);
    EXPECT_NEAR(length(same.normal), 1.0f, 1e-5f);
    EXPECT_NEAR(same.depth, 2.0f, 1e-5f);
  }
}

TEST(ShapeCast, BadInputIsReportedNotGuessed) {
  ShapeProxy c = makeProxy(makeCircle({}, 1.0f).value());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(castShape(c, {}, c, makeTransform({5, 0}, 0), {nan, 0}).status,
            ShapeCastStatus::invalidInput);
  EXPECT_EQ(castShape(c, {{nan, 0}, {}}, c, makeTransform({5, 0}, 0), {-1, 0}).status,
            ShapeCastStatus::invalidInput);
  EXPECT_EQ(castShape(c, {}, c, makeTransform({5, 0}, 0), {-10, 0}, 1.5f).status,
            ShapeCastStatus::invalidInput);
  EXPECT_STREQ(toString(ShapeCastStatus::maxIterations), "max_iterations");
}

// Random pairs of every kind: the cast against the distance sampled densely along the
// translation. Before the reported fraction no sample overlaps; at it the shapes are within
// the tolerance; a miss means no sample overlaps at all.
TEST(ShapeCast, AgreesWithDenseSampling) {
  const unsigned seed = 7001;
  std::mt19937 rng(seed);
  const ShapeType kinds[] = {ShapeType::circle, ShapeType::capsule, ShapeType::segment,
                             ShapeType::polygon};
  constexpr int kSamples = 1000;
  int hits = 0, misses = 0, overlaps = 0;
  for (int trial = 0; trial < 400; ++trial) {
    ShapeGeometry sa = testing::randomShape(rng, kinds[trial % 4], 1.0f);
    ShapeGeometry sb = testing::randomShape(rng, kinds[(trial / 4) % 4], 1.0f);
    ShapeProxy a = makeProxy(sa), b = makeProxy(sb);
    Transform xa = testing::randomTransform(rng, 1.0f);
    Transform xb = testing::randomTransform(rng, 4.0f);
    // Aim roughly at A most of the time, so that hits are common.
    Vec2 target =
        xa.p + Vec2{testing::uniform(rng, -1.5f, 1.5f), testing::uniform(rng, -1.5f, 1.5f)};
    Vec2 translation = 2.0f * (target - xb.p);
    ShapeCastOutput out = castShape(a, xa, b, xb, translation);
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    auto distanceAt = [&](float s) {
      return computeDistance(a, xa, b, {xb.p + s * translation, xb.q}).distance;
    };
    ASSERT_NE(out.status, ShapeCastStatus::maxIterations);
    ASSERT_NE(out.status, ShapeCastStatus::invalidInput);
    const float pathLength = length(translation);
    if (out.status == ShapeCastStatus::overlapped) {
      ++overlaps;
      EXPECT_EQ(distanceAt(0.0f), 0.0f);
      EXPECT_NEAR(length(out.normal), 1.0f, 1e-4f);
      continue;
    }
    if (out.status == ShapeCastStatus::hit) {
      ++hits;
      EXPECT_NEAR(length(out.normal), 1.0f, 1e-4f);
      const float d = distanceAt(out.fraction);
      EXPECT_LE(d, kShapeCastTolerance + 1e-5f);
      EXPECT_GT(d, 0.0f);
    } else {
      ++misses;
    }
    // Samples strictly before the fraction (by more than one sample's travel) are apart.
    for (int k = 0; k <= kSamples; ++k) {
      const float s = static_cast<float>(k) / kSamples;
      const float d = distanceAt(s);
      if (s < out.fraction - 1e-6f) {
        ASSERT_GT(d, 0.0f) << "overlap at s = " << s << " before fraction " << out.fraction;
      }
      if (out.status == ShapeCastStatus::missed) {
        ASSERT_GT(d, 0.0f) << "missed, but overlap at s = " << s;
      }
      if (d == 0.0f) {
        // The first overlapping sample bounds the hit from above.
        ASSERT_LE(out.fraction, s + 2e-5f / pathLength);
        break;
      }
    }
  }
  RecordProperty("hits", hits);
  RecordProperty("misses", misses);
  RecordProperty("overlaps", overlaps);
  EXPECT_GT(hits, 100);
  EXPECT_GT(misses, 20);
}

TEST(ShapeCast, SwapAndRigidMotion) {
  const unsigned seed = 7002;
  std::mt19937 rng(seed);
  const ShapeType kinds[] = {ShapeType::circle, ShapeType::capsule, ShapeType::segment,
                             ShapeType::polygon};
  for (int trial = 0; trial < 300; ++trial) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
    ShapeGeometry sa = testing::randomShape(rng, kinds[trial % 4], 1.0f);
    ShapeGeometry sb = testing::randomShape(rng, kinds[(trial / 4) % 4], 1.0f);
    ShapeProxy a = makeProxy(sa), b = makeProxy(sb);
    Transform xa = testing::randomTransform(rng, 1.0f);
    Transform xb = testing::randomTransform(rng, 4.0f);
    Vec2 translation =
        2.0f * (xa.p - xb.p) + Vec2{testing::uniform(rng, -2, 2), testing::uniform(rng, -2, 2)};
    ShapeCastOutput out = castShape(a, xa, b, xb, translation);
    if (out.status == ShapeCastStatus::overlapped) continue;
    // Swapped: A moves by -translation against B; the same fraction, the normal flipped.
    ShapeCastOutput swapped = castShape(b, xb, a, xa, -translation);
    ASSERT_EQ(swapped.status, out.status);
    const float fractionSlack = 2.0f * kShapeCastTolerance / length(translation) + 1e-5f;
    if (out.hit) {
      EXPECT_NEAR(swapped.fraction, out.fraction, fractionSlack);
      EXPECT_NEAR(dot(swapped.normal, out.normal), -1.0f, 1e-2f);
    }
    // Rigid motion of everything: the same fraction, the normal rotated.
    Transform motion = testing::randomTransform(rng, 10.0f);
    ShapeCastOutput moved =
        castShape(a, motion * xa, b, motion * xb, rotate(motion.q, translation));
    ASSERT_EQ(moved.status, out.status);
    if (out.hit) {
      EXPECT_NEAR(moved.fraction, out.fraction, fractionSlack);
      EXPECT_NEAR(dot(moved.normal, rotate(motion.q, out.normal)), 1.0f, 1e-2f);
    }
  }
}

}  // namespace
}  // namespace quack
