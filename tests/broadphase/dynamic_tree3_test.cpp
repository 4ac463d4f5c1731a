// DynamicTree3: hand-checked small trees, balance under adversarial insertion orders, long
// random sequences checked against brute force (structure3_checks.hpp), the binned rebuild,
// memory per proxy, and the 3D slab test against a double-precision one.

#include "quack/broadphase/dynamic_tree3.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "broadphase/structure3_checks.hpp"
#include "quack/broadphase/detail/node_stack.hpp"

namespace quack {
namespace {

using test::queryAll3;

TEST(DynamicTree3, ThreeLeavesByHand) {
  DynamicTree3 t;
  EXPECT_EQ(t.height(), 0);
  EXPECT_EQ(t.areaRatio(), 0.0f);
  t.insert(0, {{0, 0, 0}, {1, 1, 1}});
  EXPECT_EQ(t.height(), 0);
  t.insert(1, {{10, 0, 0}, {11, 1, 1}});
  EXPECT_EQ(t.height(), 1);
  // Next to leaf 0: the SAH pairs it with 0, not with the far leaf.
  t.insert(2, {{1.5f, 0, 0}, {2.5f, 1, 1}});
  EXPECT_EQ(t.height(), 2);
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
  EXPECT_EQ(queryAll3(t, {{0.5f, 0.5f, 0.5f}, {2, 0.6f, 0.6f}}),
            (std::vector<std::uint32_t>{0, 2}));
  EXPECT_EQ(queryAll3(t, {{11, 1, 1}, {12, 2, 2}}), (std::vector<std::uint32_t>{1}));  // touching
  EXPECT_TRUE(queryAll3(t, {{5, 5, 5}, {6, 6, 6}}).empty());
  EXPECT_TRUE(queryAll3(t, {{0, 0, 1.001f}, {11, 1, 2}}).empty());  // above every box in z
  // Root 11 x 1 x 1: area 2 (11 + 1 + 11) = 46; inner node 2.5 x 1 x 1: 2 (2.5 + 1 + 2.5) = 12.
  EXPECT_FLOAT_EQ(t.areaRatio(), (46.0f + 12.0f) / 46.0f);
  t.remove(1);
  EXPECT_EQ(t.height(), 1);
  t.remove(0);
  t.remove(2);
  EXPECT_EQ(t.proxyCount(), 0u);
  ASSERT_TRUE(t.validate().ok());
}

TEST(DynamicTree3, RotationsKeepSortedInsertionsBalanced) {
  // Boxes along a line, and along a diagonal of a grid, are the classic worst case of an
  // unbalanced tree (height n - 1); with rotations it stays logarithmic.
  DynamicTree3 line;
  DynamicTree3 grid;
  const int n = 1024;
  for (int i = 0; i < n; ++i) {
    const float x = static_cast<float>(i);
    line.insert(static_cast<std::uint32_t>(i), {{x, 0, 0}, {x + 0.5f, 0.5f, 0.5f}});
    const Vec3 c{static_cast<float>(i % 8), static_cast<float>((i / 8) % 8),
                 static_cast<float>(i / 64)};
    grid.insert(static_cast<std::uint32_t>(i), {c, c + Vec3{0.5f, 0.5f, 0.5f}});
  }
  ASSERT_TRUE(line.validate().ok()) << line.validate().message();
  ASSERT_TRUE(grid.validate().ok()) << grid.validate().message();
  // The 2D tree's bound, 2 log2(n) + 2 (an AVL tree would be within 1.44 log2(n)).
  EXPECT_LE(line.height(), 22) << line.height();
  EXPECT_LE(grid.height(), 22) << grid.height();
  // Removing every other one keeps it valid and shallow.
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); i += 2) {
    line.remove(i);
    ASSERT_TRUE(line.validate().ok()) << line.validate().message();
  }
  EXPECT_LE(line.height(), 20) << line.height();
}

TEST(DynamicTree3, RandomOperationsMatchBruteForce) {
  for (std::uint32_t seed : {301u, 302u, 303u}) {
    test::randomSequence<DynamicTree3>([] { return DynamicTree3{}; }, seed, 3000, 250);
    if (HasFatalFailure()) return;
  }
}

TEST(DynamicTree3, HeightStaysLogarithmicUnderChurn) {
  std::mt19937 rng(77);
  DynamicTree3 t;
  const std::uint32_t n = 2000;
  std::vector<Aabb3> boxes(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    boxes[i] = test::randomBox3(rng, 50.0f, 0.2f, 1.0f);
    t.insert(i, boxes[i]);
  }
  std::uniform_int_distribution<std::uint32_t> pick(0, n - 1);
  for (int k = 0; k < 20000; ++k) {
    const std::uint32_t p = pick(rng);
    const Vec3 d = test::randomVec3(rng, -0.5f, 0.5f);
    boxes[p] = {boxes[p].lower + d, boxes[p].upper + d};
    t.move(p, boxes[p]);
  }
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
  EXPECT_LE(t.height(), static_cast<int>(2.0 * std::log2(n) + 2)) << t.height();
  // Churn degrades the SAH quality a little; a rebuild restores it.
  const float churned = t.areaRatio();
  t.rebuild();
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
  EXPECT_LE(t.areaRatio(), churned);
}

TEST(DynamicTree3, RebuildKeepsProxiesAndImprovesQuality) {
  std::mt19937 rng(31);
  DynamicTree3 t;
  // Ten clusters inserted round robin: a bad order for greedy insertion.
  std::vector<Aabb3> boxes;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 shift{static_cast<float>(i % 10) * 100.0f, 0.0f, static_cast<float>(i % 3) * 50.0f};
    const Aabb3 b = test::randomBox3(rng, 3.0f, 0.25f, 0.5f);
    boxes.push_back({b.lower + shift, b.upper + shift});
    t.insert(static_cast<std::uint32_t>(i), boxes.back());
  }
  const float before = t.areaRatio();
  t.rebuild();
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
  EXPECT_EQ(t.proxyCount(), 2000u);
  for (std::uint32_t i = 0; i < 2000; ++i)
    ASSERT_EQ(t.box(i), boxes[i]);
  EXPECT_LE(t.areaRatio(), before * 1.05f);
  EXPECT_LE(t.height(), 40);
  // Incremental updates after a rebuild keep the tree valid.
  for (std::uint32_t i = 0; i < 2000; i += 3) {
    t.move(i, boxes[(i * 7) % 2000]);
    boxes[i] = boxes[(i * 7) % 2000];
  }
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
}

TEST(DynamicTree3, RebuildOfIdenticalBoxesIsBalanced) {
  // Every centroid equal: the SAH cannot split, the median split must.
  DynamicTree3 t;
  for (std::uint32_t i = 0; i < 1000; ++i)
    t.insert(i, {{0, 0, 0}, {1, 1, 1}});
  t.rebuild();
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
  EXPECT_EQ(t.height(), 10);
  EXPECT_EQ(queryAll3(t, {{0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}}).size(), 1000u);
}

TEST(DynamicTree3, BytesPerProxyAre68AfterRebuild) {
  DynamicTree3 t;
  std::mt19937 rng(4);
  for (std::uint32_t i = 0; i < 10000; ++i)
    t.insert(i, test::randomBox3(rng, 100.0f, 0.25f, 0.5f));
  t.rebuild();  // exact capacity: n - 1 nodes of 64 bytes and n leaf links of 4
  EXPECT_EQ(t.bytesUsed(), 9999u * 64u + 10000u * 4u);
}

TEST(DynamicTree3, RayCastVisitsNearestFirstAndClips) {
  DynamicTree3 t;
  for (std::uint32_t i = 0; i < 50; ++i) {
    const float z = static_cast<float>(i) * 2.0f;
    t.insert(i, {{-0.5f, -0.5f, z}, {0.5f, 0.5f, z + 1.0f}});
  }
  std::vector<std::uint32_t> seen;
  const Vec3 origin{0, 0, -1};
  const Vec3 translation{0, 0, 200};
  // Clip at each hit: the ray visits only the first box's leaf and maybe its sibling.
  t.rayCast(origin, translation, 1.0f, {}, [&](std::uint32_t p, float maxFraction) {
    seen.push_back(p);
    const AabbRayHit h = detail::rayCast3(t.box(p), origin, translation, maxFraction);
    return h.hit ? h.fraction : maxFraction;
  });
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.front(), 0u);
  EXPECT_LE(seen.size(), 3u);
  // Returning 0 stops at once.
  int calls = 0;
  t.rayCast(origin, translation, 1.0f, {}, [&](std::uint32_t, float) {
    ++calls;
    return 0.0f;
  });
  EXPECT_EQ(calls, 1);
}

TEST(DynamicTree3, VisitInternalNodesCoversTheHierarchy) {
  DynamicTree3 tree;
  std::mt19937 rng(404);
  std::vector<Aabb3> boxes;
  for (std::uint32_t i = 0; i < 300; ++i) {
    boxes.push_back(test::randomBox3(rng, 50.0f, 0.5f, 0.5f));
    tree.insert(i, boxes.back());
  }
  int nodes = 0;
  int deepest = 0;
  Aabb3 root{};
  tree.visitInternalNodes([&](Aabb3 box, int depth) {
    if (depth == 0) root = box;
    ++nodes;
    deepest = std::max(deepest, depth);
  });
  EXPECT_EQ(nodes, 299);
  EXPECT_LT(deepest, tree.height());
  for (const Aabb3& b : boxes)
    EXPECT_TRUE(contains(root, b));
}

TEST(NodeStack, SpillsPastItsInlineCapacityAndKeepsTheOrder) {
  // 128 values fit inline; the rest go to the heap and come back last in, first out.
  detail::NodeStack stack;
  EXPECT_TRUE(stack.empty());
  for (std::uint32_t round = 0; round < 2; ++round) {
    for (std::uint32_t v = 0; v < 1000; ++v)
      stack.push(v * 3 + round);
    for (std::uint32_t v = 1000; v-- > 0;)
      ASSERT_EQ(stack.pop(), v * 3 + round);
    EXPECT_TRUE(stack.empty());
  }
}

// The slab test against the same test in double precision: they agree on every ray whose
// distance to the box's boundary is not within float rounding (kSlabTolerance).
TEST(RayCast3, AgreesWithADoublePrecisionSlabTest) {
  // Relative to the coordinates (|x| <= 20 m): a few float ulps of the inputs, carried
  // through one subtraction and one product.
  constexpr double kSlabTolerance = 1e-5;
  std::mt19937 rng(5);
  int hits = 0;
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    const Aabb3 b = test::randomBox3(rng, 10.0f, 0.1f, 5.0f);
    const Vec3 o = test::randomVec3(rng, -20.0f, 20.0f);
    // Half the rays are aimed near the box (so that many hit), half anywhere.
    const Vec3 aim = center(b) + test::randomVec3(rng, -6.0f, 6.0f) - o;
    const Vec3 d = (i % 2 == 0) ? 1.5f * aim : test::randomVec3(rng, -40.0f, 40.0f);
    const double od[3] = {o.x, o.y, o.z};
    const double dd[3] = {d.x, d.y, d.z};
    const double lo[3] = {b.lower.x, b.lower.y, b.lower.z};
    const double hi[3] = {b.upper.x, b.upper.y, b.upper.z};
    double tmin = 0.0;
    double tmax = 1.0;
    for (int k = 0; k < 3; ++k) {
      double t1 = (lo[k] - od[k]) / dd[k];
      double t2 = (hi[k] - od[k]) / dd[k];
      if (t1 > t2) std::swap(t1, t2);
      tmin = std::max(tmin, t1);
      tmax = std::min(tmax, t2);
    }
    // Skip rays that graze an edge or end at the box: either answer is right there.
    if (std::abs(tmax - tmin) < kSlabTolerance || std::abs(tmin - 1.0) < kSlabTolerance) continue;
    ++checked;
    const AabbRayHit h = detail::rayCast3(b, o, d, 1.0f);
    ASSERT_EQ(h.hit, tmin <= tmax) << "ray " << i;
    if (h.hit) {
      ++hits;
      EXPECT_NEAR(h.fraction, tmin, kSlabTolerance) << "ray " << i;
    }
  }
  EXPECT_GT(checked, 19000);
  EXPECT_GT(hits, 3000);
}

}  // namespace
}  // namespace quack
