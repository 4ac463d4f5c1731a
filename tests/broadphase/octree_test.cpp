// Octree: cells chosen by size and centre, growth and shrinking without predefined bounds,
// long random sequences checked against brute force (structure3_checks.hpp).

#include "quack/broadphase/octree.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "broadphase/structure3_checks.hpp"

namespace quack {
namespace {

using test::queryAll3;

TEST(Octree, SmallSceneByHand) {
  Octree o(1.0f);
  EXPECT_EQ(o.depth(), 0);
  EXPECT_EQ(o.rootLevel(), -1);
  o.insert(0, {{0, 0, 0}, {0.5f, 0.5f, 0.5f}});
  EXPECT_EQ(o.depth(), 1);
  EXPECT_EQ(o.cellCount(), 1u);
  EXPECT_EQ(o.rootLevel(), 0);  // a box smaller than a cell sits at level 0
  o.insert(1, {{10, 0, 0}, {10.5f, 0.5f, 0.5f}});
  o.insert(2, {{-3, -3, -3}, {3, 3, 3}});  // 6 m: level 3 (8 m cells)
  ASSERT_TRUE(o.validate().ok()) << o.validate().message();
  EXPECT_EQ(queryAll3(o, {{0.25f, 0.25f, 0.25f}, {0.3f, 0.3f, 0.3f}}),
            (std::vector<std::uint32_t>{0, 2}));
  EXPECT_EQ(queryAll3(o, {{10.5f, 0.5f, 0.5f}, {11, 1, 1}}), (std::vector<std::uint32_t>{1}));
  EXPECT_TRUE(queryAll3(o, {{5, 5, 5}, {6, 6, 6}}).empty());
  // Moving within its cell only stores the new box.
  const std::uint32_t cells = o.cellCount();
  o.move(0, {{0.01f, 0, 0}, {0.51f, 0.5f, 0.5f}});
  EXPECT_EQ(o.cellCount(), cells);
  ASSERT_TRUE(o.validate().ok()) << o.validate().message();
  o.remove(1);
  o.remove(2);
  ASSERT_TRUE(o.validate().ok()) << o.validate().message();
  // One box left: the root is its cell again.
  EXPECT_EQ(o.cellCount(), 1u);
  EXPECT_EQ(o.rootLevel(), 0);
  o.remove(0);
  EXPECT_EQ(o.cellCount(), 0u);
  ASSERT_TRUE(o.validate().ok());
}

TEST(Octree, GrowsWithoutBoundsAndShrinksBack) {
  // Boxes ever further out, in every octant: the root climbs; removing them, it comes back.
  Octree o(0.5f);
  o.insert(0, {{-0.1f, -0.1f, -0.1f}, {0.1f, 0.1f, 0.1f}});
  const int start = o.rootLevel();
  std::uint32_t next = 1;
  for (float r = 10.0f; r < 2e8f; r *= 10.0f) {
    for (int octant = 0; octant < 8; ++octant) {
      const Vec3 c{(octant & 1) ? r : -r, (octant & 2) ? r : -r, (octant & 4) ? r : -r};
      o.insert(next++, {c - Vec3{0.2f, 0.2f, 0.2f}, c + Vec3{0.2f, 0.2f, 0.2f}});
      ASSERT_TRUE(o.validate().ok()) << o.validate().message();
    }
  }
  EXPECT_GT(o.rootLevel(), start + 25);  // 2e8 m / 0.5 m is about 2^28.6
  // Every far box is found by a point query, and only it.
  EXPECT_EQ(queryAll3(o, {{1e8f, 1e8f, 1e8f}, {1e8f, 1e8f, 1e8f}}),
            (std::vector<std::uint32_t>{next - 1}));
  for (std::uint32_t p = 1; p < next; ++p) {
    o.remove(p);
    ASSERT_TRUE(o.validate().ok()) << o.validate().message();
  }
  EXPECT_EQ(o.rootLevel(), start);
  EXPECT_EQ(o.cellCount(), 1u);
}

TEST(Octree, BoxesOnCellBoundariesAndAtTheOrigin) {
  // Boxes straddling the boundaries of many levels, and many around the origin: each goes to
  // exactly one cell whose loose box holds it (validate), and queries stay exact.
  Octree o(1.0f);
  std::vector<Aabb3> boxes;
  std::uint32_t p = 0;
  for (int i = -4; i <= 4; ++i) {
    for (int j = -4; j <= 4; ++j) {
      const float x = static_cast<float>(i) * 4.0f;
      const float y = static_cast<float>(j) * 2.0f;
      boxes.push_back({{x - 0.3f, y - 0.3f, -0.3f}, {x + 0.3f, y + 0.3f, 0.3f}});
      o.insert(p++, boxes.back());
    }
  }
  ASSERT_TRUE(o.validate().ok()) << o.validate().message();
  // A root far above the scene would mean a long chain of cells: the offset grid keeps the
  // origin off every level's boundaries.
  EXPECT_LE(o.depth(), 8);
  for (std::uint32_t k = 0; k < boxes.size(); ++k) {
    const std::vector<std::uint32_t> hit = queryAll3(o, boxes[k]);
    EXPECT_EQ(hit, (std::vector<std::uint32_t>{k}));
  }
}

TEST(Octree, RandomOperationsMatchBruteForce) {
  for (std::uint32_t seed : {401u, 402u, 403u}) {
    test::randomSequence<Octree>([] { return Octree{0.5f}; }, seed, 3000, 250);
    if (HasFatalFailure()) return;
  }
}

TEST(Octree, RandomOperationsWithLargeCellsMatchBruteForce) {
  // Cells larger than every box: all at level 0, many per cell.
  test::randomSequence<Octree>([] { return Octree{16.0f}; }, 404u, 2000, 200);
}

TEST(Octree, RebuildCompactsAndKeepsBoxes) {
  Octree o(1.0f);
  std::mt19937 rng(8);
  std::vector<Aabb3> boxes;
  for (std::uint32_t i = 0; i < 3000; ++i) {
    boxes.push_back(test::randomBox3(rng, 100.0f, 0.1f, 2.0f));
    o.insert(i, boxes.back());
  }
  for (std::uint32_t i = 0; i < 3000; i += 2)
    o.remove(i);
  const std::size_t before = o.bytesUsed();
  o.rebuild();
  ASSERT_TRUE(o.validate().ok()) << o.validate().message();
  EXPECT_LT(o.bytesUsed(), before);
  EXPECT_EQ(o.proxyCount(), 1500u);
  for (std::uint32_t i = 1; i < 3000; i += 2)
    ASSERT_EQ(o.box(i), boxes[i]);
}

}  // namespace
}  // namespace quack
