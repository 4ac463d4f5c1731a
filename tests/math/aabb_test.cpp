#include "quack/math/aabb.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace quack {
namespace {

constexpr Aabb kUnit{{0, 0}, {1, 1}};
static_assert(perimeter(kUnit) == 4.0f);
static_assert(overlaps(kUnit, Aabb{{1, 1}, {2, 2}}));  // touching corners overlap
static_assert(!overlaps(kUnit, Aabb{{1.5f, 0}, {2, 1}}));

TEST(Aabb, ByHand) {
  Aabb a{{0, 0}, {2, 1}};
  Aabb b{{1, -1}, {3, 0.5f}};
  EXPECT_TRUE(overlaps(a, b));
  EXPECT_EQ(merge(a, b), (Aabb{{0, -1}, {3, 1}}));
  EXPECT_EQ(intersect(a, b), (Aabb{{1, 0}, {2, 0.5f}}));
  EXPECT_EQ(center(a), (Vec2{1, 0.5f}));
  EXPECT_EQ(extents(a), (Vec2{1, 0.5f}));
  EXPECT_FLOAT_EQ(area(a), 2.0f);
  EXPECT_FLOAT_EQ(perimeter(a), 6.0f);
  EXPECT_EQ(inflate(a, 0.5f), (Aabb{{-0.5f, -0.5f}, {2.5f, 1.5f}}));
  EXPECT_EQ(sweep(a, {1, -2}), (Aabb{{0, -2}, {3, 1}}));
  EXPECT_TRUE(contains(merge(a, b), a));
  EXPECT_FALSE(contains(a, b));
  EXPECT_TRUE(contains(a, Vec2{2, 1}));
  EXPECT_TRUE(isValid(a));
  EXPECT_FALSE(isValid(Aabb{{1, 0}, {0, 1}}));
  EXPECT_FALSE(isValid(Aabb{{std::numeric_limits<float>::quiet_NaN(), 0}, {1, 1}}));
}

TEST(Aabb, RayCastByHand) {
  Aabb box{{1, -1}, {3, 1}};
  AabbRayHit h = rayCast(box, {0, 0}, {4, 0});
  ASSERT_TRUE(h.hit);
  EXPECT_FLOAT_EQ(h.fraction, 0.25f);
  EXPECT_FALSE(rayCast(box, {0, 2}, {4, 0}).hit);          // passes above
  EXPECT_FALSE(rayCast(box, {0, 0}, {0.5f, 0}).hit);       // stops short
  EXPECT_EQ(rayCast(box, {2, 0}, {1, 0}).fraction, 0.0f);  // starts inside
  EXPECT_TRUE(rayCast(box, {2, 5}, {0, -10}).hit);         // axis-parallel, inside the slab
}

TEST(Aabb, RayCastAgreesWithSampling) {
  const unsigned seed = 777;
  SCOPED_TRACE(seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-5, 5);
  Aabb box{{-1, -0.5f}, {2, 1.5f}};
  for (int i = 0; i < 2000; ++i) {
    Vec2 o{u(rng), u(rng)}, d{u(rng), u(rng)};
    AabbRayHit h = rayCast(box, o, d);
    // First sample inside the box along the ray.
    const int kSamples = 4000;
    float first = -1.0f;
    for (int k = 0; k <= kSamples; ++k) {
      float t = static_cast<float>(k) / kSamples;
      if (contains(box, o + t * d)) {
        first = t;
        break;
      }
    }
    if (first >= 0.0f) {
      ASSERT_TRUE(h.hit) << "i=" << i;
      EXPECT_LE(h.fraction, first + 1e-5f);
      EXPECT_GE(h.fraction, first - 1.0f / kSamples - 1e-5f);
    } else if (h.hit) {
      // A hit the sampling missed must be a graze thinner than the sample spacing.
      EXPECT_LE(h.fraction, 1.0f);
    }
  }
}

}  // namespace
}  // namespace quack
