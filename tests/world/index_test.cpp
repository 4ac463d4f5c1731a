// The world's internal indexes against brute-force oracles: the contact set's pair map
// (against std::unordered_map) and the continuous phase's grid of swept boxes (against a
// scan of every box).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <unordered_map>
#include <vector>

#include "../../src/world/contact_set.hpp"
#include "../../src/world/continuous.hpp"
#include "../../src/world/ghost_edges.hpp"
#include "../../src/world/pair_map.hpp"

namespace quack::detail {
namespace {

TEST(PairMap, AgreesWithAStandardMapThroughInsertsAndErases) {
  std::mt19937 rng(7);
  PairMap map;
  std::unordered_map<std::uint64_t, std::uint32_t> oracle;
  // Few distinct shapes, so that keys collide in the table and erases shift chains back.
  std::uniform_int_distribution<std::uint32_t> shape(0, 300);
  std::uniform_int_distribution<int> op(0, 9);
  auto key = [](std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) | b;
  };
  for (int i = 0; i < 200000; ++i) {
    const std::uint32_t a = shape(rng);
    std::uint32_t b = shape(rng);
    if (a == b) b = a + 1;
    const std::uint64_t k = key(a, b);
    const int o = op(rng);
    if (o < 5) {
      map.set(k, static_cast<std::uint32_t>(i));
      oracle[k] = static_cast<std::uint32_t>(i);
    } else if (o < 9) {
      map.erase(k);
      oracle.erase(k);
    } else {
      const std::uint32_t* v = map.find(k);
      const auto it = oracle.find(k);
      ASSERT_EQ(v != nullptr, it != oracle.end()) << "step " << i;
      if (v != nullptr) {
        ASSERT_EQ(*v, it->second) << "step " << i;
      }
    }
    ASSERT_EQ(map.size(), oracle.size()) << "step " << i;
  }
  // Every key the oracle holds is found with its value, and a sample of others is not.
  for (const auto& [k, v] : oracle) {
    const std::uint32_t* found = map.find(k);
    ASSERT_NE(found, nullptr);
    EXPECT_EQ(*found, v);
  }
  std::size_t absent = 0;
  for (std::uint32_t a = 0; a < 300; ++a) {
    const std::uint64_t k = key(a, a + 1);
    EXPECT_EQ(map.contains(k), oracle.count(k) != 0);
    absent += oracle.count(k) == 0 ? 1 : 0;
  }
  EXPECT_GT(absent, 0u);
  EXPECT_GT(oracle.size(), 1000u);  // the table grew and shrank through many sizes' worth
  map.clear();
  EXPECT_EQ(map.size(), 0u);
  EXPECT_FALSE(map.contains(oracle.begin()->first));
}

TEST(BoxGrid, QueriesReportEveryOverlappingBoxOnceAsAScanDoes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> pos(-30.0f, 30.0f);
  std::uniform_real_distribution<float> size(0.05f, 1.5f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int round = 0; round < 20; ++round) {
    std::vector<BoxGrid::Item> items;
    const int n = 50 + 100 * round;
    for (int i = 0; i < n; ++i) {
      const Vec2 c{pos(rng), pos(rng)};
      // Mostly small boxes; a few long ones (a paddle's sweep) that go to the large list,
      // and a few far away (the edge of the world) and degenerate (a point).
      Vec2 h{size(rng), size(rng)};
      const float r = unit(rng);
      if (r < 0.03f) h = {40.0f, 2.0f};
      Vec2 at = c;
      if (r > 0.98f) at = {9.0e8f * (unit(rng) - 0.5f), -9.0e8f};
      if (r > 0.96f && r <= 0.98f) h = {};
      items.push_back({Aabb{at - h, at + h}, static_cast<std::uint32_t>(i)});
    }
    BoxGrid grid;
    grid.build(items);
    ASSERT_EQ(grid.size(), items.size());
    for (int q = 0; q < 200; ++q) {
      const Vec2 c{pos(rng), pos(rng)};
      Vec2 h{2.0f * size(rng), 2.0f * size(rng)};
      if (q % 50 == 0) h = {100.0f, 100.0f};  // more cells than entries: the scan
      if (q % 50 == 1) h = {1.0e9f, 1.0e9f};  // the whole world
      if (q % 50 == 2) h = {};                // a point
      const Aabb box{c - h, c + h};
      std::vector<std::uint32_t> got, want;
      grid.query(box, [&](std::uint32_t id) { got.push_back(id); });
      for (const BoxGrid::Item& item : items)
        if (overlaps(item.box, box)) want.push_back(item.id);
      std::sort(got.begin(), got.end());
      ASSERT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end())
          << "an item reported twice, round " << round << " query " << q;
      ASSERT_EQ(got, want) << "round " << round << " query " << q;
    }
  }
}

// The contact set's pair sort against std::sort by the same key, on both of its paths (a
// plain sort under 1,024 pairs, radix above) and index ranges from a few bits to 31.
TEST(SortPairs, GivesStdSortsOrderOnBothPaths) {
  std::mt19937 rng(4242);
  std::vector<ProxyPair> scratch;
  for (std::uint32_t maxIndex : {40u, 5000u, 70000u, 0x7ffffff0u}) {
    for (std::size_t n : {10u, 1023u, 1024u, 30000u}) {
      std::uniform_int_distribution<std::uint32_t> index(0, maxIndex);
      std::vector<ProxyPair> pairs;
      for (std::size_t k = 0; k < n; ++k) {
        std::uint32_t a = index(rng), b = index(rng);
        if (a > b) std::swap(a, b);
        pairs.push_back({ProxyId{a, 1}, ProxyId{b, 1}});
      }
      // Some pairs twice, as a broad phase may report them.
      for (std::size_t k = 0; k < n / 10; ++k)
        pairs.push_back(pairs[k * 7 % pairs.size()]);
      std::shuffle(pairs.begin(), pairs.end(), rng);
      std::vector<ProxyPair> expected = pairs;
      std::sort(expected.begin(), expected.end(), [](const ProxyPair& x, const ProxyPair& y) {
        return x.a.index != y.a.index ? x.a.index < y.a.index : x.b.index < y.b.index;
      });
      sortPairs(pairs, scratch);
      EXPECT_EQ(pairs, expected) << "max index " << maxIndex << ", " << n << " pairs";
    }
  }
}

// The static-edge search's grid: entries added edge by edge, each edge in a few cells
// around its own, sorted by cell and then edge. The radix path (256 entries or more, cells
// spanning up to 64 bits) and std::sort's must agree, negative cells and shared cells
// included; spans past 64 bits take std::sort.
TEST(SortCellEntries, GivesStdSortsOrderOnBothPaths) {
  std::mt19937 rng(77);
  std::vector<CellEntry> scratch;
  for (long long span : {3LL, 200LL, 70000LL, 1LL << 40, 1000000000000000LL}) {
    for (std::size_t edges : {20u, 255u, 4000u}) {
      std::uniform_int_distribution<long long> cell(-span, span);
      std::uniform_int_distribution<int> extra(0, 2);
      std::vector<CellEntry> entries;
      for (std::size_t k = 0; k < edges; ++k) {
        const long long x0 = cell(rng), y0 = cell(rng);
        const int nx = extra(rng), ny = extra(rng);
        for (long long x = x0; x <= x0 + nx; ++x)
          for (long long y = y0; y <= y0 + ny; ++y)
            entries.push_back({x, y, k});
      }
      std::vector<CellEntry> expected = entries;
      std::sort(expected.begin(), expected.end(), [](const CellEntry& a, const CellEntry& b) {
        if (a.x != b.x) return a.x < b.x;
        if (a.y != b.y) return a.y < b.y;
        return a.edge < b.edge;
      });
      sortCellEntries(entries, scratch);
      ASSERT_EQ(entries.size(), expected.size());
      for (std::size_t k = 0; k < entries.size(); ++k) {
        ASSERT_TRUE(entries[k].x == expected[k].x && entries[k].y == expected[k].y &&
                    entries[k].edge == expected[k].edge)
            << "span " << span << ", " << edges << " edges, entry " << k;
      }
    }
  }
}

}  // namespace
}  // namespace quack::detail
