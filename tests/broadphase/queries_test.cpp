// Queries of every structure against brute force over the tight boxes.

#include <gtest/gtest.h>

#include <algorithm>
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

INSTANTIATE_TEST_SUITE_P(BroadPhase, Queries, ::testing::ValuesIn(kAllBroadPhaseKinds),
                         [](const ::testing::TestParamInfo<BroadPhaseKind>& param) {
                           return std::string(nameOf(param.param));
                         });

}  // namespace
}  // namespace quack
