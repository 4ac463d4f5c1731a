#include "quack/geometry/raycast.hpp"

#include <gtest/gtest.h>

#include <random>

#include "quack/geometry/bounds.hpp"
#include "support/random_shapes.hpp"

namespace quack {
namespace {

using testing::uniform;

TEST(RayCast, ByHand) {
  Polygon box = makeBox(1, 0.5f).value();
  RayHit h = rayCast(box, {{-5, 0.25f}, {10, 0}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_FLOAT_EQ(h.fraction, 0.4f);
  EXPECT_EQ(h.point, (Vec2{-1, 0.25f}));
  EXPECT_EQ(h.normal, (Vec2{-1, 0}));
  EXPECT_FALSE(rayCast(box, {{-5, 0.25f}, {10, 0}, 0.3f}).hit);  // clipped by maxFraction
  EXPECT_FALSE(rayCast(box, {{0, 0}, {10, 0}, 1}).hit);          // starts inside

  Circle c = makeCircle({0, 0}, 1).value();
  h = rayCast(c, {{-3, 0}, {4, 0}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_FLOAT_EQ(h.fraction, 0.5f);
  EXPECT_EQ(h.normal, (Vec2{-1, 0}));

  Capsule k = makeCapsule({-1, 0}, {1, 0}, 0.5f).value();
  h = rayCast(k, {{0, 3}, {0, -3}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, 2.5f / 3.0f, 1e-6f);
  EXPECT_NEAR(h.normal.y, 1.0f, 1e-6f);
  h = rayCast(k, {{4, 0}, {-4, 0}, 1});  // into the end cap
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, 2.5f / 4.0f, 1e-6f);
  EXPECT_NEAR(h.normal.x, 1.0f, 1e-6f);

  Segment s = makeSegment({0, -1}, {0, 1}).value();
  h = rayCast(s, {{2, 0}, {-4, 0}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_FLOAT_EQ(h.fraction, 0.5f);
  EXPECT_EQ(h.normal, (Vec2{1, 0}));  // faces the incoming ray
  h = rayCast(s, {{-2, 0}, {4, 0}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.normal, (Vec2{-1, 0}));
  EXPECT_FALSE(rayCast(s, {{0, -3}, {0, 6}, 1}).hit);  // collinear: no crossing

  Polygon rounded = makeBox(1, 1, {}, 0, 0.5f).value();
  h = rayCast(rounded, {{-5, 0}, {10, 0}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_FLOAT_EQ(h.fraction, 0.35f);
  // Aimed at the corner arc along the diagonal: enters at (1, 1) + 0.5 (1, 1)/sqrt 2.
  h = rayCast(rounded, {{5, 5}, {-10, -10}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.point.x, 1 + 0.5f / std::sqrt(2.0f), 1e-5f);
  EXPECT_NEAR(h.normal.x, 1 / std::sqrt(2.0f), 1e-5f);
}

TEST(RayCast, DegenerateRaysDoNotHit) {
  Circle c = makeCircle({0, 0}, 1).value();
  EXPECT_FALSE(rayCast(c, {{-3, 0}, {0, 0}, 1}).hit);
  EXPECT_FALSE(rayCast(c, {{-3, 0}, {std::numeric_limits<float>::quiet_NaN(), 0}, 1}).hit);
  EXPECT_FALSE(rayCast(c, {{-3, 0}, {4, 0}, -1}).hit);
}

// Checks a cast against dense sampling of containment along the ray, and that the normal
// points out of the shape at the hit point.
template <class Shape>
void checkAgainstSampling(const Shape& shape, const RayCastInput& ray, int samples) {
  RayHit h = rayCast(shape, ray);
  if (containsPoint(shape, ray.origin)) {
    EXPECT_FALSE(h.hit) << "a ray starting inside must not hit";
    return;
  }
  float first = -1.0f;
  for (int k = 1; k <= samples; ++k) {
    float t = ray.maxFraction * static_cast<float>(k) / static_cast<float>(samples);
    if (containsPoint(shape, ray.origin + t * ray.translation)) {
      first = t;
      break;
    }
  }
  float step = ray.maxFraction / static_cast<float>(samples);
  float len = length(ray.translation);
  if (first >= 0.0f) {
    ASSERT_TRUE(h.hit) << "sampling found the shape at t = " << first;
    EXPECT_LE(h.fraction, first + 1e-5f);
    EXPECT_GE(h.fraction, first - step - 1e-5f);
  }
  if (h.hit) {
    EXPECT_GE(h.fraction, 0.0f);
    EXPECT_LE(h.fraction, ray.maxFraction);
    EXPECT_NEAR(length(h.normal), 1.0f, 1e-4f);
    // Just outside along the normal is outside (shapes here are far thicker than the probe).
    float probe = 1e-3f;
    EXPECT_FALSE(containsPoint(shape, h.point + probe * h.normal));
    EXPECT_LE(dot(h.normal, ray.translation), 1e-5f * len) << "normal faces along the ray";
    // The hit point is on the boundary: a step against the normal is inside. This also
    // covers grazes that the sampling stepped over.
    EXPECT_TRUE(containsPoint(shape, h.point - probe * h.normal));
  }
}

TEST(RayCast, EveryShapeAgreesWithDenseSampling) {
  const unsigned seed = 8086;
  std::mt19937 rng(seed);
  for (int i = 0; i < 400; ++i) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " i " << i);
    float r = uniform(rng, 0.05f, 0.8f);
    RayCastInput ray{{uniform(rng, -3, 3), uniform(rng, -3, 3)},
                     {uniform(rng, -6, 6), uniform(rng, -6, 6)},
                     uniform(rng, 0.2f, 1.0f)};
    checkAgainstSampling(makeCircle({uniform(rng, -1, 1), uniform(rng, -1, 1)}, r + 0.3f).value(),
                         ray, 4000);
    checkAgainstSampling(
        makeCapsule({-1, uniform(rng, -1, 1)}, {1, uniform(rng, -1, 1)}, r).value(), ray, 4000);
    checkAgainstSampling(testing::randomPolygon(rng, 3 + static_cast<int>(rng() % 12), 1.5f), ray,
                         4000);
    checkAgainstSampling(testing::randomPolygon(rng, 3 + static_cast<int>(rng() % 12), 1.0f, {}, r),
                         ray, 4000);
  }
}

// Segments have no interior; check against the crossing computed in double precision.
TEST(RayCast, SegmentAgreesWithDoubleIntersection) {
  const unsigned seed = 6502;
  std::mt19937 rng(seed);
  int hits = 0;
  for (int i = 0; i < 5000; ++i) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " i " << i);
    Segment s = makeSegment({uniform(rng, -2, 2), uniform(rng, -2, 2)},
                            {uniform(rng, -2, 2), uniform(rng, -2, 2)})
                    .value();
    RayCastInput ray{
        {uniform(rng, -3, 3), uniform(rng, -3, 3)}, {uniform(rng, -6, 6), uniform(rng, -6, 6)}, 1};
    double ex = s.p2.x - s.p1.x, ey = s.p2.y - s.p1.y, dx = ray.translation.x,
           dy = ray.translation.y;
    double den = dx * ey - dy * ex;
    double sx = s.p1.x - ray.origin.x, sy = s.p1.y - ray.origin.y;
    double t = (sx * ey - sy * ex) / den, u = (sx * dy - sy * dx) / den;
    bool expect = t >= 0 && t <= 1 && u >= 0 && u <= 1;
    // Skip crossings within rounding of an end of either segment.
    if (std::min({std::abs(t), std::abs(1 - t), std::abs(u), std::abs(1 - u)}) < 1e-4) continue;
    RayHit h = rayCast(s, ray);
    ASSERT_EQ(h.hit, expect);
    if (expect) {
      ++hits;
      EXPECT_NEAR(h.fraction, t, 1e-4);
    }
  }
  EXPECT_GT(hits, 200);
}

}  // namespace
}  // namespace quack
