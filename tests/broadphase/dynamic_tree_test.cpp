#include "quack/broadphase/dynamic_tree.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "broadphase/oracle.hpp"

namespace quack {
namespace {

std::vector<std::uint32_t> queryAll(const DynamicTree& t, Aabb q) {
  std::vector<std::uint32_t> out;
  t.query(q, [&](std::uint32_t p) {
    out.push_back(p);
    return true;
  });
  std::sort(out.begin(), out.end());
  return out;
}

TEST(DynamicTree, ThreeLeavesByHand) {
  DynamicTree t;
  EXPECT_EQ(t.height(), 0);
  t.insert(0, {{0, 0}, {1, 1}});
  EXPECT_EQ(t.height(), 0);
  t.insert(1, {{10, 0}, {11, 1}});
  EXPECT_EQ(t.height(), 1);
  // Next to leaf 0: the SAH pairs it with 0, not with the far leaf.
  t.insert(2, {{1.5f, 0}, {2.5f, 1}});
  EXPECT_EQ(t.height(), 2);
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
  EXPECT_EQ(queryAll(t, {{0.5f, 0.5f}, {2, 0.6f}}), (std::vector<std::uint32_t>{0, 2}));
  EXPECT_EQ(queryAll(t, {{11, 1}, {12, 2}}), (std::vector<std::uint32_t>{1}));  // touching
  EXPECT_TRUE(queryAll(t, {{5, 5}, {6, 6}}).empty());
  // Root perimeter 2 * (11 + 1) = 24, inner node {0..2.5, 0..1}: 7.
  EXPECT_FLOAT_EQ(t.areaRatio(), (24.0f + 7.0f) / 24.0f);
  t.remove(1);
  EXPECT_EQ(t.height(), 1);
  t.remove(0);
  t.remove(2);
  EXPECT_EQ(t.proxyCount(), 0u);
  ASSERT_TRUE(t.validate().ok());
}

TEST(DynamicTree, RotationsKeepSortedInsertionsShallow) {
  // Inserting boxes along a line is the classic worst case for an unbalanced tree (height
  // n - 1); with rotations it stays logarithmic.
  DynamicTree t;
  const int n = 1024;
  for (int i = 0; i < n; ++i) {
    const float x = static_cast<float>(i);
    t.insert(static_cast<std::uint32_t>(i), {{x, 0}, {x + 0.5f, 0.5f}});
  }
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
  EXPECT_LE(t.height(), 2 * 10 + 2);
}

TEST(DynamicTree, RandomInsertRemoveMoveStaysValidAndMatchesBruteForce) {
  for (std::uint32_t seed : {21u, 22u}) {
    SCOPED_TRACE("seed=" + std::to_string(seed));
    std::mt19937 rng(seed);
    DynamicTree t;
    std::vector<std::optional<Aabb>> model(300);
    std::uniform_int_distribution<std::uint32_t> pick(0, 299);
    std::uniform_real_distribution<float> unit(0, 1);
    for (int i = 0; i < 4000; ++i) {
      const std::uint32_t p = pick(rng);
      const Aabb b = test::randomBox(rng, 30.0f, 0.1f, 2.0f);
      if (!model[p]) {
        t.insert(p, b);
        model[p] = b;
      } else if (unit(rng) < 0.4f) {
        t.remove(p);
        model[p].reset();
      } else {
        t.move(p, b);
        model[p] = b;
      }
      if (i % 500 == 250) t.rebuild();
      const Status v = t.validate();
      ASSERT_TRUE(v.ok()) << "step " << i << ": " << v.message();
      if (i % 20 == 0) {
        const Aabb q = test::randomBox(rng, 30.0f, 0.5f, 5.0f);
        std::vector<std::uint32_t> expected;
        for (std::uint32_t k = 0; k < model.size(); ++k) {
          if (model[k] && overlaps(*model[k], q)) expected.push_back(k);
        }
        ASSERT_EQ(queryAll(t, q), expected) << "step " << i;
      }
    }
    // AVL-style rotations bound the height near 1.44 log2(n); allow 2 log2(n) + 2.
    const double bound = 2.0 * std::log2(std::max<double>(2.0, t.proxyCount())) + 2.0;
    EXPECT_LE(t.height(), bound);
  }
}

// enlarge grows a moved leaf's ancestors in place; queries must stay exact both in that
// state and after rebuildEnlarged, and insert/remove in between must rebuild first. The
// brute-force model is the oracle; validate() checks the enlarged nodes' invariants
// (their boxes hold their children, their ancestors are enlarged too).
TEST(DynamicTree, EnlargeAndPartialRebuildMatchBruteForce) {
  for (std::uint32_t seed : {41u, 42u}) {
    SCOPED_TRACE("seed=" + std::to_string(seed));
    std::mt19937 rng(seed);
    DynamicTree t;
    std::vector<std::optional<Aabb>> model(400);
    for (std::uint32_t p = 0; p < 300; ++p) {
      model[p] = test::randomBox(rng, 40.0f, 0.1f, 2.0f);
      t.insert(p, *model[p]);
    }
    std::uniform_int_distribution<std::uint32_t> pick(0, 399);
    std::uniform_real_distribution<float> unit(0, 1);
    auto checkQueries = [&](int round) {
      for (int k = 0; k < 5; ++k) {
        const Aabb q = test::randomBox(rng, 40.0f, 0.5f, 6.0f);
        std::vector<std::uint32_t> expected;
        for (std::uint32_t i = 0; i < model.size(); ++i)
          if (model[i] && overlaps(*model[i], q)) expected.push_back(i);
        ASSERT_EQ(queryAll(t, q), expected) << "round " << round;
      }
    };
    for (int round = 0; round < 60; ++round) {
      // A step's worth of moves: nearby (a drift) or far (a teleport), some shrinking.
      const int moves = 1 + static_cast<int>(unit(rng) * 120.0f);
      for (int m = 0; m < moves; ++m) {
        const std::uint32_t p = pick(rng);
        if (!model[p]) continue;
        Aabb b = test::randomBox(rng, 40.0f, 0.1f, 2.0f);
        if (unit(rng) < 0.8f) {
          const Vec2 c = center(*model[p]) + Vec2{unit(rng) - 0.5f, unit(rng) - 0.5f};
          const Vec2 h = extents(b);
          b = {c - h, c + h};
        }
        t.enlarge(p, b);
        model[p] = b;
        ASSERT_TRUE(t.hasEnlarged());
        ASSERT_EQ(t.box(p), b);
      }
      Status v = t.validate();
      ASSERT_TRUE(v.ok()) << "round " << round << ", enlarged: " << v.message();
      checkQueries(round);
      if (round % 3 == 0) {
        // An insertion or removal while enlarged rebuilds first.
        const std::uint32_t p = pick(rng);
        if (model[p]) {
          t.remove(p);
          model[p].reset();
        } else {
          model[p] = test::randomBox(rng, 40.0f, 0.1f, 2.0f);
          t.insert(p, *model[p]);
        }
        EXPECT_FALSE(t.hasEnlarged());
      } else {
        t.rebuildEnlarged();
        EXPECT_FALSE(t.hasEnlarged());
      }
      v = t.validate();
      ASSERT_TRUE(v.ok()) << "round " << round << ", rebuilt: " << v.message();
      checkQueries(round);
    }
    // Partial rebuilds keep the tree shallow: within twice a balanced tree's height.
    const double bound = 2.0 * std::log2(std::max<double>(2.0, t.proxyCount())) + 2.0;
    EXPECT_LE(t.height(), bound);
  }
}

// One moved leaf rebuilds only its path: the rest of the hierarchy keeps its quality, and a
// step in which every leaf moved rebuilds the whole tree as well as the full build does
// (midpoint against binned SAH, within 25% by the area ratio).
TEST(DynamicTree, PartialRebuildKeepsQuality) {
  std::mt19937 rng(43);
  DynamicTree t;
  std::vector<Aabb> boxes;
  for (std::uint32_t i = 0; i < 2000; ++i) {
    boxes.push_back(test::randomBox(rng, 100.0f, 0.25f, 1.0f));
    t.insert(i, boxes.back());
  }
  t.rebuild();
  const float built = t.areaRatio();
  const int height = t.height();
  t.enlarge(7, boxes[7]);  // same box: only the marks
  t.rebuildEnlarged();
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
  EXPECT_LE(t.areaRatio(), built * 1.01f);
  EXPECT_LE(t.height(), height + 1);
  for (std::uint32_t i = 0; i < 2000; ++i) {
    const Vec2 shift{0.3f, -0.2f};
    boxes[i] = {boxes[i].lower + shift, boxes[i].upper + shift};
    t.enlarge(i, boxes[i]);
  }
  t.rebuildEnlarged();
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
  EXPECT_LE(t.areaRatio(), built * 1.25f);
  for (std::uint32_t i = 0; i < 2000; ++i)
    ASSERT_EQ(t.box(i), boxes[i]);
}

// Every centre equal: the midpoint cannot split, the median must (a balanced tree).
TEST(DynamicTree, PartialRebuildOfIdenticalBoxesIsBalanced) {
  DynamicTree t;
  for (std::uint32_t i = 0; i < 1024; ++i)
    t.insert(i, {{static_cast<float>(i), 0}, {static_cast<float>(i) + 1, 1}});
  for (std::uint32_t i = 0; i < 1024; ++i)
    t.enlarge(i, {{0, 0}, {1, 1}});
  t.rebuildEnlarged();
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
  EXPECT_EQ(t.height(), 10);
  EXPECT_EQ(queryAll(t, {{0.5f, 0.5f}, {0.5f, 0.5f}}).size(), 1024u);
}

TEST(DynamicTree, RebuildKeepsProxiesAndImprovesOrKeepsQuality) {
  std::mt19937 rng(31);
  DynamicTree t;
  // Clustered input inserted in a bad order.
  std::vector<Aabb> boxes;
  for (int i = 0; i < 2000; ++i) {
    const float cx = static_cast<float>(i % 10) * 100.0f;
    const Aabb b = test::randomBox(rng, 3.0f, 0.25f, 0.5f);
    boxes.push_back({b.lower + Vec2{cx, 0}, b.upper + Vec2{cx, 0}});
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
}

TEST(DynamicTree, RebuildOfIdenticalBoxesIsBalanced) {
  // Every centroid equal: the SAH cannot split, the median split must.
  DynamicTree t;
  for (std::uint32_t i = 0; i < 1000; ++i)
    t.insert(i, {{0, 0}, {1, 1}});
  t.rebuild();
  ASSERT_TRUE(t.validate().ok()) << t.validate().message();
  EXPECT_EQ(t.height(), 10);
  EXPECT_EQ(queryAll(t, {{0.5f, 0.5f}, {0.5f, 0.5f}}).size(), 1000u);
}

TEST(DynamicTree, BytesPerProxyAtMost64) {
  DynamicTree t;
  std::mt19937 rng(4);
  for (std::uint32_t i = 0; i < 10000; ++i)
    t.insert(i, test::randomBox(rng, 100.0f, 0.25f, 0.5f));
  t.rebuild();  // exact capacity
  const double perProxy = static_cast<double>(t.bytesUsed()) / 10000.0;
  EXPECT_LE(perProxy, 64.0);
  EXPECT_GE(perProxy, 52.0 - 0.01);
}

TEST(DynamicTree, RayCastVisitsNearestFirstAndClips) {
  DynamicTree t;
  for (std::uint32_t i = 0; i < 50; ++i) {
    const float x = static_cast<float>(i) * 2.0f;
    t.insert(i, {{x, -0.5f}, {x + 1.0f, 0.5f}});
  }
  std::vector<std::uint32_t> seen;
  // Clip at each hit: the ray visits only the first box's leaf (others start beyond it).
  t.rayCast({-1, 0}, {200, 0}, 1.0f, {}, [&](std::uint32_t p, float maxFraction) {
    seen.push_back(p);
    const AabbRayHit h = rayCast(t.box(p), {-1, 0}, {200, 0}, maxFraction);
    return h.hit ? h.fraction : maxFraction;
  });
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.front(), 0u);
  EXPECT_LE(seen.size(), 3u);
}

}  // namespace
}  // namespace quack

namespace quack {
namespace {

// The node visitor sees every internal node once: a tree of n leaves has n - 1 of them,
// each box holds its children, and depths never exceed the height.
TEST(DynamicTree, VisitInternalNodesCoversTheHierarchy) {
  DynamicTree tree;
  std::mt19937 rng(404);
  std::uniform_real_distribution<float> u(-50, 50);
  std::vector<Aabb> boxes;
  for (std::uint32_t i = 0; i < 300; ++i) {
    Vec2 c{u(rng), u(rng)};
    boxes.push_back({c - Vec2{0.5f, 0.5f}, c + Vec2{0.5f, 0.5f}});
    tree.insert(i, boxes.back());
  }
  int nodes = 0, deepest = 0;
  Aabb root{};
  tree.visitInternalNodes([&](Aabb box, int depth) {
    if (depth == 0) root = box;
    ++nodes;
    deepest = std::max(deepest, depth);
  });
  EXPECT_EQ(nodes, 299);
  EXPECT_LT(deepest, tree.height());
  for (const Aabb& b : boxes)
    EXPECT_TRUE(contains(root, b));
  DynamicTree empty;
  int none = 0;
  empty.visitInternalNodes([&](Aabb, int) { ++none; });
  EXPECT_EQ(none, 0);
}

}  // namespace
}  // namespace quack
