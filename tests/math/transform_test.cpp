#include "quack/math/transform.hpp"

#include <gtest/gtest.h>

#include <random>

namespace quack {
namespace {

constexpr Transform kShift{{1, 2}, {}};
static_assert(transformPoint(kShift, Vec2{3, 4}) == Vec2{4, 6});
static_assert(invTransformPoint(kShift, Vec2{4, 6}) == Vec2{3, 4});

void expectNear(Vec2 a, Vec2 b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
}

TEST(Transform, ByHand) {
  Transform worldFromBody = makeTransform({10, 0}, 0.5f * kPi);
  expectNear(transformPoint(worldFromBody, {1, 0}), {10, 1}, 1e-6f);
  expectNear(invTransformPoint(worldFromBody, {10, 1}), {1, 0}, 1e-6f);
  expectNear(transformVector(worldFromBody, {1, 0}), {0, 1}, 1e-6f);
}

TEST(Transform, CompositionInverseAndInvMulAgree) {
  const unsigned seed = 12345;
  SCOPED_TRACE(seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-100, 100), ang(-kPi, kPi);
  for (int i = 0; i < 1000; ++i) {
    Transform aFromB = makeTransform({pos(rng), pos(rng)}, ang(rng));
    Transform bFromC = makeTransform({pos(rng), pos(rng)}, ang(rng));
    Vec2 pC{pos(rng), pos(rng)};
    Transform aFromC = aFromB * bFromC;
    expectNear(transformPoint(aFromC, pC), transformPoint(aFromB, transformPoint(bFromC, pC)),
               1e-3f);
    Transform bFromA = inverse(aFromB);
    expectNear(transformPoint(bFromA, transformPoint(aFromB, pC)), pC, 1e-3f);
    Transform viaInvMul = invMul(aFromB, aFromC);
    expectNear(viaInvMul.p, bFromC.p, 1e-3f);
    EXPECT_NEAR(viaInvMul.q.c, bFromC.q.c, 1e-5f);
    EXPECT_NEAR(viaInvMul.q.s, bFromC.q.s, 1e-5f);
  }
}

}  // namespace
}  // namespace quack
