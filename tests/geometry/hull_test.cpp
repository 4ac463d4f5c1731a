#include "quack/geometry/hull.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <vector>

#include "support/random_shapes.hpp"

namespace quack {
namespace {

using testing::uniform;

std::vector<Vec2> pointsOf(const Hull& h) {
  return {h.points, h.points + h.count};
}

// Signed distance of p outside the hull (negative inside), by brute force over edges.
float separation(const Hull& h, Vec2 p) {
  float s = -std::numeric_limits<float>::max();
  for (int i = 0; i < h.count; ++i) {
    Vec2 a = h.points[i];
    Vec2 n = normalize(rightPerp(h.points[(i + 1) % h.count] - a));
    s = maxf(s, dot(n, p - a));
  }
  return s;
}

// The properties every hull must have, checked independently of validateHull.
void expectHullOf(const std::vector<Vec2>& input, const Hull& h) {
  ASSERT_TRUE(validateHull(h).ok()) << validateHull(h).message();
  // Convex and counter-clockwise: every turn is strictly left.
  for (int i = 0; i < h.count; ++i) {
    Vec2 a = h.points[i], b = h.points[(i + 1) % h.count], c = h.points[(i + 2) % h.count];
    EXPECT_GT(cross(b - a, c - b), 0.0f) << "turn at " << (i + 1) % h.count;
  }
  // Every input point inside or on the hull (within the documented tolerance).
  Vec2 lo = input[0], hi = input[0];
  for (Vec2 p : input)
    lo = minv(lo, p), hi = maxv(hi, p);
  float tol = hullTolerance(lo, hi);
  for (std::size_t i = 0; i < input.size(); ++i) {
    EXPECT_LE(separation(h, input[i]), tol) << "input point " << i << " is outside the hull";
  }
  // Every hull vertex is one of the inputs.
  for (int i = 0; i < h.count; ++i) {
    EXPECT_NE(std::find(input.begin(), input.end(), h.points[i]), input.end());
  }
  // Hulling a hull changes nothing.
  Result<Hull> again = computeHull(pointsOf(h));
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(pointsOf(again.value()), pointsOf(h));
}

TEST(Hull, SquareWithInteriorEdgeAndDuplicatePoints) {
  std::vector<Vec2> pts = {{1, 1}, {0, 0}, {0.5f, 0.5f}, {1, 0}, {0, 1}, {0.5f, 0}, {1, 1}, {0, 0}};
  Result<Hull> h = computeHull(pts);
  ASSERT_TRUE(h.ok()) << h.error().message;
  EXPECT_EQ(pointsOf(h.value()), (std::vector<Vec2>{{0, 0}, {1, 0}, {1, 1}, {0, 1}}));
  expectHullOf(pts, h.value());
}

TEST(Hull, NearDuplicatesAreWelded) {
  std::vector<Vec2> pts = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {1e-7f, 0}, {1, 1 + 1e-7f}, {0, 1e-7f}};
  Result<Hull> h = computeHull(pts);
  ASSERT_TRUE(h.ok());
  EXPECT_EQ(h->count, 4);
  expectHullOf(pts, h.value());
}

TEST(Hull, CollinearRunsCollapseToCorners) {
  std::vector<Vec2> pts;
  for (int i = 0; i <= 10; ++i) {
    float t = static_cast<float>(i) / 10;
    pts.push_back({t, 0});
    pts.push_back({1, t});
    pts.push_back({1 - t, 1});
    pts.push_back({0, 1 - t});
  }
  // Nearly collinear too: a bump of 1e-7 on an edge of length 1.
  pts.push_back({0.5f, -1e-7f});
  Result<Hull> h = computeHull(pts);
  ASSERT_TRUE(h.ok());
  EXPECT_EQ(h->count, 4);
  expectHullOf(pts, h.value());
}

TEST(Hull, TooFewOrDegeneratePointsGiveClearErrors) {
  std::vector<Vec2> two = {{0, 0}, {1, 1}};
  Result<Hull> r = computeHull(two);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("at least three points, got 2"), std::string::npos);

  std::vector<Vec2> same = {{2, 2}, {2, 2}, {2, 2}, {2, 2}};
  r = computeHull(same);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("collinear or coincide"), std::string::npos);

  std::vector<Vec2> line = {{0, 0}, {1, 2}, {2, 4}, {3, 6}, {0.5f, 1}};
  r = computeHull(line);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("collinear"), std::string::npos);

  std::vector<Vec2> withNaN = {{0, 0}, {1, 0}, {std::numeric_limits<float>::quiet_NaN(), 1}};
  r = computeHull(withNaN);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("points[2] is not finite"), std::string::npos);

  std::vector<Vec2> withInf = {{0, 0}, {std::numeric_limits<float>::infinity(), 0}, {0, 1}};
  r = computeHull(withInf);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("points[1]"), std::string::npos);

  EXPECT_FALSE(computeHull(std::span<const Vec2>{}).ok());
}

TEST(Hull, MoreThanTheVertexLimitIsAnError) {
  std::vector<Vec2> circle;
  for (int i = 0; i < kMaxPolygonVertices + 1; ++i) {
    float a = 2.0f * kPi * static_cast<float>(i) / (kMaxPolygonVertices + 1);
    circle.push_back({std::cos(a), std::sin(a)});
  }
  Result<Hull> r = computeHull(circle);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("more than the 64"), std::string::npos);
  circle.pop_back();
  Result<Hull> ok = computeHull(circle);
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  EXPECT_EQ(ok->count, kMaxPolygonVertices);
}

TEST(Hull, RandomCloudsAtManyScales) {
  const unsigned seed = 20261121;
  std::mt19937 rng(seed);
  for (int trial = 0; trial < 2000; ++trial) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " trial " << trial);
    float scale = std::pow(10.0f, uniform(rng, -3.0f, 3.0f));
    Vec2 offset{uniform(rng, -10, 10) * scale, uniform(rng, -10, 10) * scale};
    int n = 3 + static_cast<int>(rng() % 40);
    std::vector<Vec2> pts;
    for (int i = 0; i < n; ++i) {
      switch (rng() % 4) {
        case 0:  // exact duplicate of an earlier point
          if (!pts.empty()) {
            pts.push_back(pts[rng() % pts.size()]);
            break;
          }
          [[fallthrough]];
        case 1:  // point on a circle (many hull vertices)
        {
          float a = uniform(rng, 0, 2 * kPi);
          pts.push_back(offset + scale * Vec2{std::cos(a), std::sin(a)});
          break;
        }
        default:  // interior-ish point
          pts.push_back(offset +
                        scale * Vec2{uniform(rng, -0.7f, 0.7f), uniform(rng, -0.7f, 0.7f)});
      }
    }
    Result<Hull> h = computeHull(pts);
    if (!h.ok()) {
      // Only degenerate or oversized inputs may fail.
      EXPECT_TRUE(h.error().message.find("collinear") != std::string::npos ||
                  h.error().message.find("more than") != std::string::npos)
          << h.error().message;
      continue;
    }
    expectHullOf(pts, h.value());
  }
}

}  // namespace
}  // namespace quack
