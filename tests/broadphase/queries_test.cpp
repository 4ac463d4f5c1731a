// Queries of every structure against brute force over the tight boxes.

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <optional>
#include <string>

#include "broadphase/oracle.hpp"
#include "quack/broadphase/broad_phase.hpp"

namespace quack {
namespace {

struct Live {
  ProxyId id;
  Aabb box;
};

// A broad phase of one kind filled by a fixed seed, after some churn so that the structures
// are not in their freshly built state.
BroadPhase makeScene(BroadPhaseKind kind, std::uint32_t seed, std::vector<Live>& live) {
  std::mt19937 rng(seed);
  BroadPhaseConfig config;
  config.kind = kind;
  BroadPhase bp = BroadPhase::create(config).value();
  for (int i = 0; i < 400; ++i) {
    const Aabb b = i % 20 == 0 ? test::randomBox(rng, 20.0f, 1.0f, 4.0f)
                               : test::randomBox(rng, 20.0f, 0.05f, 0.6f);
    live.push_back({bp.createProxy(b, static_cast<std::uint64_t>(i) * 3).value(), b});
  }
  std::uniform_real_distribution<float> step(-0.3f, 0.3f);
  for (int round = 0; round < 5; ++round) {
    for (Live& l : live) {
      const Vec2 d{step(rng), step(rng)};
      l.box = {l.box.lower + d, l.box.upper + d};
      EXPECT_TRUE(bp.moveProxy(l.id, l.box, d).ok());
    }
    std::vector<ProxyPair> pairs;
    bp.updatePairs(pairs);
  }
  for (std::size_t i = 0; i < live.size(); i += 9)
    EXPECT_TRUE(bp.destroyProxy(live[i].id).ok());
  for (std::size_t i = live.size(); i-- > 0;) {
    if (i % 9 == 0) live.erase(live.begin() + static_cast<std::ptrdiff_t>(i));
  }
  return bp;
}

class Queries : public ::testing::TestWithParam<BroadPhaseKind> {};

TEST_P(Queries, AabbAndPointQueriesMatchBruteForce) {
  const std::uint32_t seed = 41;
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::vector<Live> live;
  const BroadPhase bp = makeScene(GetParam(), seed, live);
  std::mt19937 rng(seed + 1);
  std::size_t totalHits = 0;
  for (int i = 0; i < 300; ++i) {
    const Aabb q = i % 3 == 0 ? Aabb{center(test::randomBox(rng, 22.0f, 0, 0)),
                                     center(test::randomBox(rng, 22.0f, 0, 0))}
                              : test::randomBox(rng, 22.0f, 0.1f, 3.0f);
    if (!isValid(q)) continue;
    std::vector<std::uint32_t> got;
    bp.queryAabb(q, [&](ProxyId id, std::uint64_t user) {
      EXPECT_EQ(user, bp.userData(id));
      got.push_back(id.index);
      return true;
    });
    std::vector<std::uint32_t> expected;
    for (const Live& l : live) {
      if (overlaps(l.box, q)) expected.push_back(l.id.index);
    }
    std::sort(got.begin(), got.end());
    std::sort(expected.begin(), expected.end());
    ASSERT_EQ(got, expected) << "query " << i;
    totalHits += got.size();

    const Vec2 p = center(test::randomBox(rng, 22.0f, 0, 0));
    got.clear();
    bp.queryPoint(p, [&](ProxyId id, std::uint64_t) {
      got.push_back(id.index);
      return true;
    });
    expected.clear();
    for (const Live& l : live) {
      if (contains(l.box, p)) expected.push_back(l.id.index);
    }
    std::sort(got.begin(), got.end());
    std::sort(expected.begin(), expected.end());
    ASSERT_EQ(got, expected) << "point " << i;
  }
  EXPECT_GT(totalHits, 300u);
  // A visitor returning false stops the query at the first hit.
  int calls = 0;
  bp.queryAabb({{-30, -30}, {30, 30}}, [&](ProxyId, std::uint64_t) {
    ++calls;
    return false;
  });
  EXPECT_EQ(calls, 1);
}

TEST_P(Queries, RayCastsMatchBruteForce) {
  const std::uint32_t seed = 43;
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::vector<Live> live;
  const BroadPhase bp = makeScene(GetParam(), seed, live);
  std::mt19937 rng(seed + 1);
  std::size_t hitsSeen = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec2 origin = center(test::randomBox(rng, 24.0f, 0, 0));
    const Vec2 target = center(test::randomBox(rng, 24.0f, 0, 0));
    const Vec2 translation = i % 10 == 0 ? Vec2{target.x - origin.x, 0} : target - origin;
    std::vector<std::pair<float, std::uint32_t>> expected;
    for (const Live& l : live) {
      const AabbRayHit h = rayCast(l.box, origin, translation, 1.0f);
      if (h.hit) expected.emplace_back(h.fraction, l.id.index);
    }
    std::sort(expected.begin(), expected.end());
    const std::vector<BroadPhaseHit> all = bp.rayCastAll(origin, translation);
    ASSERT_EQ(all.size(), expected.size()) << "ray " << i;
    for (std::size_t k = 0; k < all.size(); ++k) {
      ASSERT_EQ(all[k].proxy.index, expected[k].second) << "ray " << i;
      ASSERT_EQ(all[k].fraction, expected[k].first) << "ray " << i;
      ASSERT_EQ(all[k].userData, bp.userData(all[k].proxy));
    }
    const std::optional<BroadPhaseHit> closest = bp.rayCastClosest(origin, translation);
    ASSERT_EQ(closest.has_value(), !expected.empty()) << "ray " << i;
    if (closest) {
      // Ties (several boxes holding the origin, at fraction 0) may go to any of them.
      ASSERT_EQ(closest->fraction, expected.front().first) << "ray " << i;
      ASSERT_EQ(rayCast(bp.tightBox(closest->proxy), origin, translation, 1.0f).fraction,
                closest->fraction)
          << "ray " << i;
    }
    hitsSeen += all.size();
  }
  EXPECT_GT(hitsSeen, 300u);
}

TEST_P(Queries, BoxCastsMatchBruteForce) {
  const std::uint32_t seed = 47;
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::vector<Live> live;
  const BroadPhase bp = makeScene(GetParam(), seed, live);
  std::mt19937 rng(seed + 1);
  int hits = 0;
  for (int i = 0; i < 200; ++i) {
    const Aabb box = test::randomBox(rng, 24.0f, 0.1f, 1.0f);
    const Vec2 translation = center(test::randomBox(rng, 24.0f, 0, 0)) - center(box);
    const Vec2 h = extents(box);
    std::optional<std::pair<float, std::uint32_t>> expected;
    for (const Live& l : live) {
      const Aabb grown{l.box.lower - h, l.box.upper + h};
      const AabbRayHit r = rayCast(grown, center(box), translation, 1.0f);
      if (r.hit && (!expected || std::make_pair(r.fraction, l.id.index) < *expected)) {
        expected = std::make_pair(r.fraction, l.id.index);
      }
    }
    const std::optional<BroadPhaseHit> got = bp.boxCastClosest(box, translation);
    ASSERT_EQ(got.has_value(), expected.has_value()) << "cast " << i;
    if (got) {
      ++hits;
      ASSERT_EQ(got->fraction, expected->first) << "cast " << i;
      const Aabb t = bp.tightBox(got->proxy);
      ASSERT_EQ(rayCast({t.lower - h, t.upper + h}, center(box), translation, 1.0f).fraction,
                got->fraction)
          << "cast " << i;
    }
  }
  EXPECT_GT(hits, 50);
}

TEST_P(Queries, CallbackReturningZeroStopsTheCast) {
  std::vector<Live> live;
  const BroadPhase bp = makeScene(GetParam(), 53, live);
  int calls = 0;
  bp.rayCast({-25, 0}, {50, 0.5f}, [&](ProxyId, std::uint64_t, float) {
    ++calls;
    return 0.0f;
  });
  EXPECT_EQ(calls, 1);
}

// ---- Hardening: any finite query (box, point, ray, box cast), however huge, is answered in
// bounded time and exactly. The spatial hash looped over a cell-count product that
// overflowed (a box of +-2e9 m, a ray of 1e19 m, a shape of half-size 1e10 hung it) and
// cast huge floats to integers (undefined behaviour).

class BroadPhaseHardening : public ::testing::TestWithParam<BroadPhaseKind> {};

// The scene of makeScene plus proxies at the corners and edges of the coordinate range.
BroadPhase makeWideScene(BroadPhaseKind kind, std::vector<Live>& live, float cellSize = 1.0f) {
  BroadPhaseConfig config;
  config.kind = kind;
  config.cellSize = cellSize;
  BroadPhase bp = BroadPhase::create(config).value();
  std::mt19937 rng(59);
  for (int i = 0; i < 200; ++i) {
    const Aabb b = test::randomBox(rng, 20.0f, 0.05f, 0.6f);
    live.push_back({bp.createProxy(b, static_cast<std::uint64_t>(i)).value(), b});
  }
  const float m = kMaxCoordinate;
  const Aabb far[] = {{{m - 1, m - 1}, {m, m}},
                      {{-m, -m}, {-m + 1, -m + 1}},
                      {{-m, m - 5}, {-m + 3, m}},
                      {{m - 2, -m}, {m, -m + 2}},
                      {{-m, -0.5f}, {m, 0.5f}},  // a band across the whole range
                      {{1e8f, -3e8f}, {1e8f + 1, -3e8f + 1}}};
  for (const Aabb& b : far)
    live.push_back({bp.createProxy(b, 7).value(), b});
  return bp;
}

std::vector<std::uint32_t> boxHits(const BroadPhase& bp, Aabb q) {
  std::vector<std::uint32_t> got;
  bp.queryAabb(q, [&](ProxyId id, std::uint64_t) {
    got.push_back(id.index);
    return true;
  });
  std::sort(got.begin(), got.end());
  return got;
}

std::vector<std::uint32_t> bruteBoxHits(const std::vector<Live>& live, Aabb q) {
  std::vector<std::uint32_t> expected;
  for (const Live& l : live) {
    if (overlaps(l.box, q)) expected.push_back(l.id.index);
  }
  std::sort(expected.begin(), expected.end());
  return expected;
}

void expectHugeQueriesMatchBruteForce(const BroadPhase& bp, const std::vector<Live>& live) {
  const float big = std::numeric_limits<float>::max();
  const Aabb boxes[] = {{{-2e9f, -2e9f}, {2e9f, 2e9f}},
                        {{-big, -big}, {big, big}},
                        {{-1e10f + 3, -1e10f - 2}, {1e10f + 3, 1e10f - 2}},
                        {{-1e19f, 0.1f}, {1e19f, 0.2f}},
                        {{5e8f, -big}, {big, 2e9f}},
                        {{2e9f, 2e9f}, {3e9f, 3e9f}},  // beyond every proxy
                        {{-big, -big}, {-big, -big}},  // a point at the far corner
                        {{1e8f, -3e8f}, {1e8f, -3e8f}}};
  for (const Aabb& q : boxes) {
    EXPECT_EQ(boxHits(bp, q), bruteBoxHits(live, q))
        << "box " << q.lower.x << " " << q.lower.y << " " << q.upper.x << " " << q.upper.y;
  }
  struct Ray {
    Vec2 origin, translation;
  };
  const Ray rays[] = {{{0, 0}, {1e19f, 1e19f}},       {{-1e19f, 0.25f}, {2e19f, 0}},
                      {{0.5f, -1e19f}, {0, 2e19f}},   {{3e38f, 0.3f}, {-3.4e38f, 0}},
                      {{-2e9f, -2e9f}, {4e9f, 4e9f}}, {{1e8f + 0.5f, 1e19f}, {0, -2e19f}}};
  for (const Ray& r : rays) {
    std::vector<std::pair<float, std::uint32_t>> expected;
    for (const Live& l : live) {
      const AabbRayHit h = rayCast(l.box, r.origin, r.translation, 1.0f);
      if (h.hit) expected.emplace_back(h.fraction, l.id.index);
    }
    std::sort(expected.begin(), expected.end());
    const std::vector<BroadPhaseHit> all = bp.rayCastAll(r.origin, r.translation);
    ASSERT_EQ(all.size(), expected.size()) << "ray from " << r.origin.x << " " << r.origin.y;
    for (std::size_t k = 0; k < all.size(); ++k) {
      EXPECT_EQ(all[k].proxy.index, expected[k].second);
      EXPECT_EQ(all[k].fraction, expected[k].first);
    }
  }
  // A box of half-size 1e10 cast 1e19 m.
  const Aabb shape{{-1e10f, -1e10f}, {1e10f, 1e10f}};
  const Vec2 h = extents(shape);
  for (const Vec2 t : {Vec2{1e19f, 0}, Vec2{-1e19f, 1e19f}, Vec2{0, 0}}) {
    std::optional<float> expected;
    for (const Live& l : live) {
      const AabbRayHit r = rayCast({l.box.lower - h, l.box.upper + h}, center(shape), t, 1.0f);
      if (r.hit && (!expected || r.fraction < *expected)) expected = r.fraction;
    }
    const std::optional<BroadPhaseHit> got = bp.boxCastClosest(shape, t);
    ASSERT_EQ(got.has_value(), expected.has_value());
    if (got) {
      EXPECT_EQ(got->fraction, *expected);
    }
  }
}

TEST_P(BroadPhaseHardening, HugeFiniteQueriesAnswerInBoundedTimeAndMatchBruteForce) {
  std::vector<Live> live;
  const BroadPhase bp = makeWideScene(GetParam(), live);
  ASSERT_TRUE(bp.validate().ok());
  expectHugeQueriesMatchBruteForce(bp, live);
}

TEST_P(BroadPhaseHardening, ExtremeCellSizesAreRefusedOrAnswerExactly) {
  // Cell sizes at either end of what BroadPhase::create accepts still give exact answers.
  for (float cell : {kMinCellSize, 1e-3f, 1e6f, kMaxCoordinate}) {
    SCOPED_TRACE("cellSize=" + std::to_string(cell));
    std::vector<Live> live;
    const BroadPhase bp = makeWideScene(GetParam(), live, cell);
    ASSERT_TRUE(bp.validate().ok()) << bp.validate().message();
    expectHugeQueriesMatchBruteForce(bp, live);
  }
  BroadPhaseConfig config;
  config.kind = GetParam();
  config.cellSize = 1e-30f;
  EXPECT_FALSE(BroadPhase::create(config).ok());
  config.cellSize = 1e30f;
  EXPECT_FALSE(BroadPhase::create(config).ok());
}

INSTANTIATE_TEST_SUITE_P(BroadPhase, BroadPhaseHardening, ::testing::ValuesIn(kAllBroadPhaseKinds),
                         [](const ::testing::TestParamInfo<BroadPhaseKind>& param) {
                           return std::string(toString(param.param));
                         });

INSTANTIATE_TEST_SUITE_P(BroadPhase, Queries, ::testing::ValuesIn(kAllBroadPhaseKinds),
                         [](const ::testing::TestParamInfo<BroadPhaseKind>& param) {
                           return std::string(toString(param.param));
                         });

}  // namespace
}  // namespace quack
