#include "quack/math/vec2.hpp"

#include <gtest/gtest.h>

#include "quack/math/rot.hpp"

namespace quack {
namespace {

// Value types are usable at compile time.
static_assert(dot(Vec2{1, 2}, Vec2{3, 4}) == 11.0f);
static_assert(cross(Vec2{1, 0}, Vec2{0, 1}) == 1.0f);
static_assert(leftPerp(Vec2{1, 0}) == Vec2{0, 1});
static_assert(rightPerp(Vec2{1, 0}) == Vec2{0, -1});
static_assert(Vec2{} == Vec2{0, 0});
static_assert(rotate(Rot{}, Vec2{3, 4}) == Vec2{3, 4});

TEST(Vec2, ArithmeticByHand) {
  Vec2 a{1, 2}, b{3, -1};
  EXPECT_EQ(a + b, (Vec2{4, 1}));
  EXPECT_EQ(a - b, (Vec2{-2, 3}));
  EXPECT_EQ(2.0f * a, (Vec2{2, 4}));
  EXPECT_EQ(-a, (Vec2{-1, -2}));
  EXPECT_FLOAT_EQ(cross(a, b), 1 * -1 - 2 * 3);
  EXPECT_EQ(cross(a, 2.0f), (Vec2{4, -2}));
  EXPECT_EQ(cross(2.0f, a), (Vec2{-4, 2}));
  EXPECT_FLOAT_EQ(length(Vec2{3, 4}), 5.0f);
  EXPECT_FLOAT_EQ(distance(Vec2{1, 1}, Vec2{4, 5}), 5.0f);
  EXPECT_EQ(lerp(Vec2{0, 0}, Vec2{2, 4}, 0.25f), (Vec2{0.5f, 1}));
}

TEST(Vec2, NormalizeDegenerateGivesZeroNotNaN) {
  EXPECT_EQ(normalize(Vec2{}), (Vec2{}));
  Vec2 n = normalize(Vec2{0, -7});
  EXPECT_EQ(n, (Vec2{0, -1}));
}

TEST(Vec2, FinitenessCatchesNaNAndInfinity) {
  EXPECT_TRUE(isFinite(Vec2{1, 2}));
  EXPECT_FALSE(isFinite(Vec2{std::numeric_limits<float>::quiet_NaN(), 0}));
  EXPECT_FALSE(isFinite(Vec2{0, std::numeric_limits<float>::infinity()}));
}

TEST(Rot, QuarterTurnByHand) {
  Rot q = Rot::fromAngle(0.5f * kPi);
  Vec2 v = rotate(q, Vec2{1, 0});
  EXPECT_NEAR(v.x, 0.0f, 1e-6f);
  EXPECT_NEAR(v.y, 1.0f, 1e-6f);
  Vec2 back = invRotate(q, v);
  EXPECT_NEAR(back.x, 1.0f, 1e-6f);
  EXPECT_NEAR(back.y, 0.0f, 1e-6f);
  Rot half = mulRot(q, q);  // a half turn: angle() may say pi or -pi, cosine is -1
  EXPECT_NEAR(half.c, -1.0f, 1e-6f);
  EXPECT_NEAR(half.s, 0.0f, 1e-6f);
  EXPECT_NEAR(invMulRot(q, Rot{}).angle(), -0.5f * kPi, 1e-6f);
  EXPECT_EQ(normalizeRot(Rot{0, 0}), Rot{});
  Rot n = normalizeRot(Rot{3, 4});
  EXPECT_FLOAT_EQ(n.c, 0.6f);
  EXPECT_FLOAT_EQ(n.s, 0.8f);
}

}  // namespace
}  // namespace quack
