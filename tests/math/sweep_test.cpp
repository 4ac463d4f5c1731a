#include "quack/math/sweep.hpp"

#include <gtest/gtest.h>

namespace quack {
namespace {

TEST(Sweep, EndpointsReproducePosesAndMidpointInterpolates) {
  Vec2 localCenter{0.5f, 0};
  Transform start = makeTransform({0, 0}, 0);
  Transform end = makeTransform({4, 2}, 0.5f * kPi);
  Sweep s = makeSweep(localCenter, start, end);
  Transform t0 = transformAt(s, 0);
  Transform t1 = transformAt(s, 1);
  EXPECT_NEAR(t0.p.x, 0, 1e-6f);
  EXPECT_NEAR(t0.p.y, 0, 1e-6f);
  EXPECT_NEAR(t1.p.x, 4, 1e-5f);
  EXPECT_NEAR(t1.p.y, 2, 1e-5f);
  EXPECT_NEAR(t1.q.angle(), 0.5f * kPi, 1e-6f);
  // The centre of mass moves on a straight line: halfway is the midpoint of c1 and c2.
  Transform mid = transformAt(s, 0.5f);
  Vec2 c = transformPoint(mid, localCenter);
  Vec2 expected = 0.5f * (s.c1 + s.c2);
  EXPECT_NEAR(c.x, expected.x, 1e-5f);
  EXPECT_NEAR(c.y, expected.y, 1e-5f);
  EXPECT_NEAR(mid.q.angle(), 0.25f * kPi, 1e-6f);
}

TEST(Sweep, ShortWayRoundAndAdvance) {
  Sweep s = makeSweep({}, makeTransform({}, 3.0f), makeTransform({}, -3.0f));
  // 3 to -3 radians the short way is 0.283 radians through pi, not 6 radians back.
  EXPECT_NEAR(s.a2 - s.a1, 2.0f * kPi - 6.0f, 1e-5f);
  Sweep a = advance(Sweep{{}, {0, 0}, {10, 0}, 0, 1}, 0.3f);
  EXPECT_FLOAT_EQ(a.c1.x, 3.0f);
  EXPECT_FLOAT_EQ(a.a1, 0.3f);
  EXPECT_EQ(a.c2, (Vec2{10, 0}));
}

}  // namespace
}  // namespace quack
