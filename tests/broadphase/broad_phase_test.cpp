// Every structure, driven through BroadPhase by long random sequences, must report exactly
// the pairs a brute-force model predicts, and stay valid after every operation.

#include "quack/broadphase/broad_phase.hpp"

#include <gtest/gtest.h>

#include <string>

#include "broadphase/oracle.hpp"

namespace quack {
namespace {

using test::IndexPair;
using test::ModelProxy;

struct Scenario {
  BroadPhaseKind kind;
  std::uint32_t seed;
  bool checkTight;
  bool withFilters;
};

std::string describe(const Scenario& s) {
  return std::string(toString(s.kind)) + " seed=" + std::to_string(s.seed) +
         (s.checkTight ? " tight" : "") + (s.withFilters ? " filters" : "");
}

// The user filter of the tests: drops pairs whose index sum is a multiple of 7.
bool dropSevens(void*, ProxyId a, std::uint64_t, ProxyId b, std::uint64_t) {
  return (a.index + b.index) % 7 != 0;
}

void runScenario(const Scenario& sc, int steps) {
  SCOPED_TRACE(describe(sc));
  std::mt19937 rng(sc.seed);
  BroadPhaseConfig config;
  config.kind = sc.kind;
  config.checkTightBoxes = sc.checkTight;
  config.cellSize = 1.0f;
  Result<BroadPhase> made = BroadPhase::create(config);
  ASSERT_TRUE(made.ok());
  BroadPhase bp = std::move(made).value();
  if (sc.withFilters) bp.setPairFilter(dropSevens, nullptr);

  const float world = 12.0f;
  std::map<std::uint32_t, ModelProxy> live;
  std::vector<bool> buffered;
  std::vector<ProxyPair> pairs;
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_real_distribution<float> step(-0.08f, 0.08f);
  std::uniform_int_distribution<int> groupDist(-2, 2);
  std::size_t totalPairs = 0;

  auto pickLive = [&]() {
    auto it = live.begin();
    std::advance(it, std::uniform_int_distribution<std::size_t>(0, live.size() - 1)(rng));
    return it;
  };
  auto randomFilter = [&]() {
    Filter f;
    if (!sc.withFilters) return f;
    f.category = std::uint64_t{1} << std::uniform_int_distribution<int>(0, 63)(rng);
    f.mask = unit(rng) < 0.5f ? ~std::uint64_t{0} : (rng() | (std::uint64_t{rng()} << 32));
    f.group = groupDist(rng);
    return f;
  };
  auto markBuffered = [&](std::uint32_t index) {
    if (buffered.size() <= index) buffered.resize(index + 1, false);
    buffered[index] = true;
  };

  for (int i = 0; i < steps; ++i) {
    SCOPED_TRACE("step " + std::to_string(i));
    const float op = unit(rng);
    if (live.size() < 8 || (op < 0.25f && live.size() < 160)) {
      ModelProxy m;
      // Mostly small boxes, some larger ones spanning many cells.
      m.tight = unit(rng) < 0.9f ? test::randomBox(rng, world, 0.05f, 0.6f)
                                 : test::randomBox(rng, world, 1.0f, 6.0f);
      m.filter = randomFilter();
      m.kind =
          sc.withFilters && unit(rng) < 0.3f ? ProxyKind::staticProxy : ProxyKind::dynamicProxy;
      m.user = rng();
      // Half the proxies have their own margin (as the world's shapes do), from none to
      // three times the config's.
      std::optional<float> margin;
      if (unit(rng) < 0.5f) margin = 0.3f * unit(rng);
      m.margin = margin ? *margin : config.margin;
      Result<ProxyId> id = bp.createProxy(m.tight, m.user, m.filter, m.kind, margin);
      ASSERT_TRUE(id.ok()) << id.error().message;
      m.id = id.value();
      m.fat = bp.fatBox(m.id);
      ASSERT_EQ(m.fat, inflate(m.tight, m.margin));
      ASSERT_FALSE(live.count(m.id.index));
      live[m.id.index] = m;
      markBuffered(m.id.index);
    } else if (op < 0.35f) {
      auto it = pickLive();
      ASSERT_TRUE(bp.destroyProxy(it->second.id).ok());
      buffered[it->first] = false;
      live.erase(it);
    } else if (op < 0.85f) {
      auto it = pickLive();
      ModelProxy& m = it->second;
      const Vec2 d{step(rng), step(rng)};
      m.tight = {m.tight.lower + d, m.tight.upper + d};
      Result<bool> moved = bp.moveProxy(m.id, m.tight, d);
      ASSERT_TRUE(moved.ok()) << moved.error().message;
      if (moved.value()) markBuffered(it->first);
      m.fat = bp.fatBox(m.id);
      ASSERT_TRUE(contains(m.fat, m.tight));
      // Re-inserted with its own margin, stretched along the move.
      if (moved.value()) {
        ASSERT_EQ(m.fat, sweep(inflate(m.tight, m.margin), config.displacementScale * d));
      }
    } else if (op < 0.90f) {
      auto it = pickLive();
      ModelProxy& m = it->second;
      const Aabb to = test::randomBox(rng, world, 0.05f, 0.6f);
      const Vec2 jump = center(to) - center(m.tight);
      m.tight = to;
      // Half the teleports pass the jump as displacement (a huge stretched box).
      Result<bool> moved = bp.moveProxy(m.id, m.tight, unit(rng) < 0.5f ? jump : Vec2{});
      ASSERT_TRUE(moved.ok());
      if (moved.value()) markBuffered(it->first);
      m.fat = bp.fatBox(m.id);
    } else if (op < 0.92f && sc.withFilters) {
      auto it = pickLive();
      it->second.filter = randomFilter();
      ASSERT_TRUE(bp.setFilter(it->second.id, it->second.filter).ok());
      markBuffered(it->first);
    } else if (op < 0.93f) {
      bp.rebuild();
    } else {
      bp.updatePairs(pairs);
      auto user = [&](std::uint32_t a, std::uint32_t b) {
        return !sc.withFilters || (a + b) % 7 != 0;
      };
      buffered.resize(std::max<std::size_t>(buffered.size(), 1), false);
      for (auto& [index, m] : live) {
        if (buffered.size() <= index) buffered.resize(index + 1, false);
      }
      const std::vector<IndexPair> expected =
          test::expectedPairs(live, buffered, sc.checkTight, user);
      ASSERT_EQ(test::sortedPairs(pairs), expected);
      for (const ProxyPair& p : pairs) {
        ASSERT_LT(p.a.index, p.b.index);
        ASSERT_EQ(p.a, live[p.a.index].id);
        ASSERT_EQ(p.b, live[p.b.index].id);
      }
      totalPairs += pairs.size();
      std::fill(buffered.begin(), buffered.end(), false);
    }
    const Status valid = bp.validate();
    ASSERT_TRUE(valid.ok()) << valid.message();
    ASSERT_EQ(bp.proxyCount(), live.size());
  }
  // The sequence must have exercised pair finding for real.
  EXPECT_GT(totalPairs, 100u);
}

class EveryStructure : public ::testing::TestWithParam<BroadPhaseKind> {};

TEST_P(EveryStructure, RandomSequencesMatchBruteForce) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    runScenario({GetParam(), seed, false, false}, 2500);
  }
}

TEST_P(EveryStructure, RandomSequencesWithFiltersAndTightCheckMatchBruteForce) {
  for (std::uint32_t seed : {11u, 12u}) {
    runScenario({GetParam(), seed, true, true}, 2500);
    runScenario({GetParam(), seed + 100, false, true}, 1500);
  }
}

TEST_P(EveryStructure, MovingEveryProxyEachStepMatchesBruteForce) {
  // The benchmark's workload in miniature: everything random-walks, pairs every step.
  const std::uint32_t seed = 77;
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937 rng(seed);
  BroadPhaseConfig config;
  config.kind = GetParam();
  BroadPhase bp = BroadPhase::create(config).value();
  std::map<std::uint32_t, ModelProxy> live;
  for (int i = 0; i < 300; ++i) {
    ModelProxy m;
    m.tight = test::randomBox(rng, 9.0f, 0.25f, 0.5f);
    m.id = bp.createProxy(m.tight).value();
    live[m.id.index] = m;
  }
  std::vector<ProxyPair> pairs;
  std::uniform_real_distribution<float> step(-0.05f, 0.05f);
  std::size_t total = 0;
  for (int frame = 0; frame < 60; ++frame) {
    std::vector<bool> buffered(300, frame == 0);
    for (auto& [index, m] : live) {
      const Vec2 d{step(rng), step(rng)};
      m.tight = {m.tight.lower + d, m.tight.upper + d};
      if (bp.moveProxy(m.id, m.tight, d).value()) buffered[index] = true;
      m.fat = bp.fatBox(m.id);
    }
    bp.updatePairs(pairs);
    ASSERT_EQ(test::sortedPairs(pairs),
              test::expectedPairs(live, buffered, false, [](auto, auto) { return true; }))
        << "frame " << frame;
    total += pairs.size();
    ASSERT_TRUE(bp.validate().ok()) << bp.validate().message();
  }
  EXPECT_GT(total, 300u);
}

TEST_P(EveryStructure, ABufferedPairIsReportedOnceAndThenNotAgain) {
  BroadPhaseConfig config;
  config.kind = GetParam();
  BroadPhase bp = BroadPhase::create(config).value();
  const ProxyId a = bp.createProxy({{0, 0}, {1, 1}}, 10).value();
  const ProxyId b = bp.createProxy({{0.5f, 0.5f}, {1.5f, 1.5f}}, 20).value();
  bp.createProxy({{5, 5}, {6, 6}}).value();
  std::vector<ProxyPair> pairs;
  bp.updatePairs(pairs);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].a, a);
  EXPECT_EQ(pairs[0].b, b);
  bp.updatePairs(pairs);
  EXPECT_TRUE(pairs.empty());
  // A move inside the fat box is not a re-insertion, so nothing is reported.
  EXPECT_FALSE(bp.moveProxy(a, {{0.01f, 0}, {1.01f, 1}}, {0.01f, 0}).value());
  bp.updatePairs(pairs);
  EXPECT_TRUE(pairs.empty());
  ASSERT_TRUE(bp.touchProxy(b).ok());
  bp.updatePairs(pairs);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].a, a);
}

TEST_P(EveryStructure, DestroyedBufferedProxyAndReusedSlotAreHandled) {
  BroadPhaseConfig config;
  config.kind = GetParam();
  BroadPhase bp = BroadPhase::create(config).value();
  const ProxyId a = bp.createProxy({{0, 0}, {1, 1}}).value();
  const ProxyId b = bp.createProxy({{0, 0}, {1, 1}}).value();
  ASSERT_TRUE(bp.destroyProxy(b).ok());
  // The slot is reused with a new generation; the old id is stale.
  const ProxyId c = bp.createProxy({{0.5f, 0}, {1.5f, 1}}).value();
  EXPECT_EQ(c.index, b.index);
  EXPECT_NE(c.generation, b.generation);
  EXPECT_FALSE(bp.isValid(b));
  EXPECT_FALSE(bp.destroyProxy(b).ok());
  std::vector<ProxyPair> pairs;
  bp.updatePairs(pairs);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].a, a);
  EXPECT_EQ(pairs[0].b, c);
  EXPECT_TRUE(bp.validate().ok()) << bp.validate().message();
}

TEST_P(EveryStructure, FarApartAndHugeBoxesNeedNoWorldBounds) {
  BroadPhaseConfig config;
  config.kind = GetParam();
  BroadPhase bp = BroadPhase::create(config).value();
  const ProxyId far1 = bp.createProxy({{-9e8f, -9e8f}, {-9e8f + 1, -9e8f + 1}}).value();
  const ProxyId far2 = bp.createProxy({{9e8f, 9e8f}, {9e8f + 64, 9e8f + 64}}).value();
  const ProxyId huge = bp.createProxy({{-1e6f, -1e6f}, {1e6f, 1e6f}}).value();
  const ProxyId small = bp.createProxy({{0, 0}, {0.5f, 0.5f}}).value();
  ASSERT_TRUE(bp.validate().ok()) << bp.validate().message();
  std::vector<ProxyPair> pairs;
  bp.updatePairs(pairs);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].a, huge);
  EXPECT_EQ(pairs[0].b, small);
  ASSERT_TRUE(bp.destroyProxy(far1).ok());
  ASSERT_TRUE(bp.destroyProxy(far2).ok());
  ASSERT_TRUE(bp.validate().ok()) << bp.validate().message();
}

INSTANTIATE_TEST_SUITE_P(BroadPhase, EveryStructure, ::testing::ValuesIn(kAllBroadPhaseKinds),
                         [](const ::testing::TestParamInfo<BroadPhaseKind>& param) {
                           return std::string(toString(param.param));
                         });

TEST(BroadPhaseNames, RoundTripAndRejectUnknown) {
  for (BroadPhaseKind k : kAllBroadPhaseKinds) {
    Result<BroadPhaseKind> parsed = parseBroadPhaseKind(toString(k));
    ASSERT_TRUE(parsed.ok());
    EXPECT_EQ(parsed.value(), k);
  }
  Result<BroadPhaseKind> bad = parseBroadPhaseKind("octree");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("octree"), std::string::npos);
}

TEST(BroadPhaseInput, BadConfigIsRejectedNamingTheField) {
  BroadPhaseConfig c;
  c.margin = -1.0f;
  Result<BroadPhase> r = BroadPhase::create(c);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("margin"), std::string::npos);
  c = {};
  c.cellSize = 0.0f;
  r = BroadPhase::create(c);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("cellSize"), std::string::npos);
}

TEST(BroadPhaseInput, BadProxyMarginIsRejectedNamingIt) {
  BroadPhase bp = BroadPhase::create({}).value();
  for (float bad :
       {-0.1f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    Result<ProxyId> r = bp.createProxy({{0, 0}, {1, 1}}, 0, {}, ProxyKind::dynamicProxy, bad);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("margin"), std::string::npos) << r.error().message;
  }
  EXPECT_EQ(bp.proxyCount(), 0u);
  EXPECT_TRUE(bp.validate().ok());
}

TEST(BroadPhaseInput, BadBoxesAndIdsAreRejectedAndChangeNothing) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (BroadPhaseKind k : kAllBroadPhaseKinds) {
    SCOPED_TRACE(std::string(toString(k)));
    BroadPhaseConfig config;
    config.kind = k;
    BroadPhase bp = BroadPhase::create(config).value();
    const ProxyId good = bp.createProxy({{0, 0}, {1, 1}}).value();
    for (Aabb bad : {Aabb{{nan, 0}, {1, 1}}, Aabb{{0, 0}, {inf, 1}}, Aabb{{1, 0}, {0, 1}},
                     Aabb{{0, 0}, {2e9f, 1}}}) {
      Result<ProxyId> r = bp.createProxy(bad);
      ASSERT_FALSE(r.ok());
      EXPECT_NE(r.error().message.find("box"), std::string::npos);
      Result<bool> m = bp.moveProxy(good, bad, {});
      ASSERT_FALSE(m.ok());
    }
    EXPECT_FALSE(bp.moveProxy(good, {{0, 0}, {1, 1}}, {nan, 0}).ok());
    EXPECT_FALSE(bp.destroyProxy(ProxyId{}).ok());
    EXPECT_FALSE(bp.destroyProxy(ProxyId{99, 1}).ok());
    EXPECT_FALSE(bp.destroyProxy(ProxyId{good.index, good.generation + 1}).ok());
    const Status stale = bp.touchProxy(ProxyId{good.index, good.generation + 1});
    ASSERT_FALSE(stale.ok());
    EXPECT_NE(stale.message().find("stale"), std::string::npos);
    EXPECT_EQ(bp.proxyCount(), 1u);
    EXPECT_EQ(bp.tightBox(good), (Aabb{{0, 0}, {1, 1}}));
    EXPECT_TRUE(bp.validate().ok()) << bp.validate().message();
    // NaN queries report nothing rather than everything.
    int hits = 0;
    bp.queryAabb({{nan, nan}, {nan, nan}}, [&](ProxyId, std::uint64_t) {
      ++hits;
      return true;
    });
    EXPECT_EQ(hits, 0);
    EXPECT_FALSE(bp.rayCastClosest({nan, 0}, {1, 0}).has_value());
  }
}

TEST(BroadPhaseStats, ReportsSizesAndTreeQuality) {
  BroadPhase bp = BroadPhase::create().value();
  std::mt19937 rng(5);
  for (int i = 0; i < 1000; ++i)
    bp.createProxy(test::randomBox(rng, 50.0f, 0.25f, 0.5f)).value();
  const BroadPhaseStats s = bp.stats();
  EXPECT_EQ(s.proxyCount, 1000u);
  EXPECT_GT(s.structureBytes, 1000u * 52u - 1);
  EXPECT_GT(s.recordBytes, 0u);
  EXPECT_GE(s.height, 10);  // at least log2(1000)
  EXPECT_GT(s.areaRatio, 1.0f);
}

}  // namespace
}  // namespace quack
