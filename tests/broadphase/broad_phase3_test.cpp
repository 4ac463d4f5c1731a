// BroadPhase3 over both 3D structures, driven by long random sequences, must report exactly
// the pairs, box-query hits and ray hits that brute force over a model predicts, stay valid
// after every operation, and reject bad input as the 2D BroadPhase does.

#include "quack/broadphase/broad_phase3.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <map>
#include <random>
#include <string>

#include "broadphase/oracle3.hpp"

namespace quack {
namespace {

using test::IndexPair;
using test::ModelProxy3;

struct Scenario3 {
  BroadPhase3Kind kind;
  std::uint32_t seed;
  bool checkTight;
  bool withFilters;
};

bool dropSevens(void*, ProxyId a, std::uint64_t, ProxyId b, std::uint64_t) {
  return (a.index + b.index) % 7 != 0;
}

// Brute-force answers of the queries on the tight boxes of the model.
void checkQueries(const BroadPhase3& bp, const std::map<std::uint32_t, ModelProxy3>& live,
                  std::mt19937& rng, float world) {
  const Aabb3 q = test::randomBox3(rng, world, 0.2f, 4.0f);
  std::vector<std::uint32_t> expected;
  for (const auto& [index, m] : live) {
    if (overlaps(m.tight, q)) expected.push_back(index);
  }
  std::vector<std::uint32_t> got;
  bp.queryAabb(q, [&](ProxyId id, std::uint64_t user) {
    EXPECT_EQ(user, live.at(id.index).user);
    got.push_back(id.index);
    return true;
  });
  std::sort(got.begin(), got.end());
  ASSERT_EQ(got, expected) << "queryAabb";

  const Vec3 origin = test::randomVec3(rng, -world, world);
  const Vec3 translation = test::randomVec3(rng, -2.0f * world, 2.0f * world);
  std::vector<std::pair<float, std::uint32_t>> hits;
  for (const auto& [index, m] : live) {
    const AabbRayHit h = detail::rayCast3(m.tight, origin, translation, 1.0f);
    if (h.hit) hits.emplace_back(h.fraction, index);
  }
  std::sort(hits.begin(), hits.end());
  const std::vector<BroadPhaseHit> all = bp.rayCastAll(origin, translation);
  ASSERT_EQ(all.size(), hits.size()) << "rayCastAll";
  for (std::size_t k = 0; k < all.size(); ++k) {
    EXPECT_EQ(all[k].proxy.index, hits[k].second);
    EXPECT_EQ(all[k].fraction, hits[k].first);
  }
  const std::optional<BroadPhaseHit> closest = bp.rayCastClosest(origin, translation);
  ASSERT_EQ(closest.has_value(), !hits.empty()) << "rayCastClosest";
  if (closest) {
    EXPECT_EQ(closest->fraction, hits.front().first);
  }

  // A box cast: the moving box touches a tight box when its centre's ray meets the tight box
  // grown by the moving box's half-extents.
  const Aabb3 moving = test::randomBox3(rng, world, 0.1f, 1.0f);
  float first = 2.0f;
  for (const auto& [index, m] : live) {
    const AabbRayHit h = detail::rayCast3(detail::grow3(m.tight, extents(moving)), center(moving),
                                          translation, 1.0f);
    if (h.hit) first = std::min(first, h.fraction);
  }
  float got3 = 2.0f;
  bp.boxCast(moving, translation, [&](ProxyId, std::uint64_t, float fraction) {
    got3 = std::min(got3, fraction);
    return fraction;
  });
  ASSERT_EQ(got3, first) << "boxCast";
}

void runScenario(const Scenario3& sc, int steps) {
  SCOPED_TRACE(std::string(toString(sc.kind)) + " seed=" + std::to_string(sc.seed) +
               (sc.checkTight ? " tight" : "") + (sc.withFilters ? " filters" : ""));
  std::mt19937 rng(sc.seed);
  BroadPhase3Config config;
  config.kind = sc.kind;
  config.checkTightBoxes = sc.checkTight;
  config.cellSize = 0.5f;
  BroadPhase3 bp = BroadPhase3::create(config).value();
  if (sc.withFilters) bp.setPairFilter(dropSevens, nullptr);

  const float world = 6.0f;
  std::map<std::uint32_t, ModelProxy3> live;
  std::vector<bool> buffered;
  std::vector<ProxyPair> pairs;
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_int_distribution<int> groupDist(-2, 2);
  std::size_t totalPairs = 0;
  std::size_t reinserted = 0;

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
    if (live.size() < 8 || (op < 0.25f && live.size() < 150)) {
      ModelProxy3 m;
      m.tight = unit(rng) < 0.9f ? test::randomBox3(rng, world, 0.05f, 0.6f)
                                 : test::randomBox3(rng, world, 1.0f, 4.0f);
      m.filter = randomFilter();
      m.kind =
          sc.withFilters && unit(rng) < 0.3f ? ProxyKind::staticProxy : ProxyKind::dynamicProxy;
      m.user = rng();
      Result<ProxyId> id = bp.createProxy(m.tight, m.user, m.filter, m.kind);
      ASSERT_TRUE(id.ok()) << id.error().message;
      m.id = id.value();
      m.fat = bp.fatBox(m.id);
      ASSERT_TRUE(contains(m.fat, m.tight));
      ASSERT_FALSE(live.count(m.id.index));
      live[m.id.index] = m;
      markBuffered(m.id.index);
    } else if (op < 0.33f) {
      auto it = pickLive();
      ASSERT_TRUE(bp.destroyProxy(it->second.id).ok());
      buffered[it->first] = false;
      live.erase(it);
    } else if (op < 0.83f) {
      auto it = pickLive();
      ModelProxy3& m = it->second;
      const Vec3 d = test::randomVec3(rng, -0.08f, 0.08f);
      m.tight = {m.tight.lower + d, m.tight.upper + d};
      Result<bool> moved = bp.moveProxy(m.id, m.tight, d);
      ASSERT_TRUE(moved.ok()) << moved.error().message;
      if (moved.value()) {
        markBuffered(it->first);
        ++reinserted;
      } else {
        ASSERT_EQ(bp.fatBox(m.id), m.fat) << "a move that stays in place keeps the fat box";
      }
      m.fat = bp.fatBox(m.id);
      ASSERT_TRUE(contains(m.fat, m.tight));
      // The fat box is stretched ahead of the motion.
      if (moved.value()) {
        ASSERT_TRUE(contains(m.fat, Aabb3{m.tight.lower + d, m.tight.upper + d}));
      }
    } else if (op < 0.88f) {
      auto it = pickLive();
      ModelProxy3& m = it->second;
      const Aabb3 to = test::randomBox3(rng, world, 0.05f, 0.6f);
      const Vec3 jump = center(to) - center(m.tight);
      m.tight = to;
      // Half the teleports pass the jump as displacement (a huge stretched box).
      Result<bool> moved = bp.moveProxy(m.id, m.tight, unit(rng) < 0.5f ? jump : Vec3{});
      ASSERT_TRUE(moved.ok());
      if (moved.value()) markBuffered(it->first);
      m.fat = bp.fatBox(m.id);
    } else if (op < 0.90f && sc.withFilters) {
      auto it = pickLive();
      it->second.filter = randomFilter();
      ASSERT_TRUE(bp.setFilter(it->second.id, it->second.filter).ok());
      markBuffered(it->first);
    } else if (op < 0.91f) {
      bp.rebuild();
    } else if (op < 0.94f) {
      checkQueries(bp, live, rng, world);
      if (testing::Test::HasFatalFailure()) return;
    } else {
      bp.updatePairs(pairs);
      auto user = [&](std::uint32_t a, std::uint32_t b) {
        return !sc.withFilters || (a + b) % 7 != 0;
      };
      for (auto& [index, m] : live) {
        if (buffered.size() <= index) buffered.resize(index + 1, false);
      }
      const std::vector<IndexPair> expected =
          test::expectedPairs3(live, buffered, sc.checkTight, user);
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
  // The sequence must have exercised pair finding and re-insertion for real.
  EXPECT_GT(totalPairs, 100u);
  EXPECT_GT(reinserted, 50u);
}

class Every3DStructure : public ::testing::TestWithParam<BroadPhase3Kind> {};

TEST_P(Every3DStructure, RandomSequencesMatchBruteForce) {
  for (std::uint32_t seed : {1u, 2u}) {
    runScenario({GetParam(), seed, false, false}, 2500);
    if (HasFatalFailure()) return;
  }
}

TEST_P(Every3DStructure, RandomSequencesWithFiltersAndTightCheckMatchBruteForce) {
  runScenario({GetParam(), 11u, true, true}, 2500);
  runScenario({GetParam(), 12u, false, true}, 1500);
}

TEST_P(Every3DStructure, ABufferedPairIsReportedOnceAndThenNotAgain) {
  BroadPhase3Config config;
  config.kind = GetParam();
  BroadPhase3 bp = BroadPhase3::create(config).value();
  const ProxyId a = bp.createProxy({{0, 0, 0}, {1, 1, 1}}, 10).value();
  const ProxyId b = bp.createProxy({{0.5f, 0.5f, 0.5f}, {1.5f, 1.5f, 1.5f}}, 20).value();
  bp.createProxy({{5, 5, 5}, {6, 6, 6}}).value();
  std::vector<ProxyPair> pairs;
  bp.updatePairs(pairs);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].a, a);
  EXPECT_EQ(pairs[0].b, b);
  bp.updatePairs(pairs);
  EXPECT_TRUE(pairs.empty());
  // A move inside the fat box is not a re-insertion, so nothing is reported.
  EXPECT_FALSE(bp.moveProxy(a, {{0.01f, 0, 0}, {1.01f, 1, 1}}, {0.01f, 0, 0}).value());
  bp.updatePairs(pairs);
  EXPECT_TRUE(pairs.empty());
  // Out along z by more than the margin: re-inserted, the pair is reported again.
  EXPECT_TRUE(bp.moveProxy(a, {{0, 0, 0.3f}, {1, 1, 1.3f}}, {0, 0, 0.3f}).value());
  bp.updatePairs(pairs);
  ASSERT_EQ(pairs.size(), 1u);
  ASSERT_TRUE(bp.touchProxy(b).ok());
  bp.updatePairs(pairs);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].a, a);
}

TEST_P(Every3DStructure, StaleIdsAndReusedSlots) {
  BroadPhase3Config config;
  config.kind = GetParam();
  BroadPhase3 bp = BroadPhase3::create(config).value();
  const ProxyId a = bp.createProxy({{0, 0, 0}, {1, 1, 1}}).value();
  const ProxyId b = bp.createProxy({{0, 0, 0}, {1, 1, 1}}).value();
  ASSERT_TRUE(bp.destroyProxy(b).ok());
  const ProxyId c = bp.createProxy({{0.5f, 0, 0}, {1.5f, 1, 1}}).value();
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

TEST_P(Every3DStructure, FarApartAndHugeBoxesNeedNoWorldBounds) {
  BroadPhase3Config config;
  config.kind = GetParam();
  BroadPhase3 bp = BroadPhase3::create(config).value();
  const ProxyId far1 =
      bp.createProxy({{-9e8f, -9e8f, -9e8f}, {-9e8f + 64, -9e8f + 64, -9e8f + 64}}).value();
  const ProxyId far2 =
      bp.createProxy({{9e8f, 9e8f, 9e8f}, {9e8f + 64, 9e8f + 64, 9e8f + 64}}).value();
  const ProxyId huge = bp.createProxy({{-1e6f, -1e6f, -1e6f}, {1e6f, 1e6f, 1e6f}}).value();
  const ProxyId small = bp.createProxy({{0, 0, 0}, {0.5f, 0.5f, 0.5f}}).value();
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

INSTANTIATE_TEST_SUITE_P(BroadPhase3, Every3DStructure, ::testing::ValuesIn(kAllBroadPhase3Kinds),
                         [](const ::testing::TestParamInfo<BroadPhase3Kind>& param) {
                           return std::string(toString(param.param));
                         });

TEST(BroadPhase3Pairs, TreeAndOctreeReportTheSamePairsFrameAfterFrame) {
  // The benchmark's workload in miniature: 400 boxes random-walk, pairs every frame; both
  // structures, fed the same moves, report the same pairs, and those of brute force. A
  // third, the tree again, pairs through the overload that splits the moved proxies'
  // queries into parts (ranges of 7, taken last first, dealt to 3 parts in turn, as
  // workers might take them).
  std::mt19937 rng(77);
  BroadPhase3Config tc;
  BroadPhase3Config oc;
  oc.kind = BroadPhase3Kind::octree;
  BroadPhase3 tree = BroadPhase3::create(tc).value();
  BroadPhase3 octree = BroadPhase3::create(oc).value();
  BroadPhase3 split = BroadPhase3::create(tc).value();
  std::map<std::uint32_t, ModelProxy3> live;
  for (int i = 0; i < 400; ++i) {
    ModelProxy3 m;
    m.tight = test::randomBox3(rng, 5.0f, 0.25f, 0.5f);
    m.id = tree.createProxy(m.tight).value();
    ASSERT_EQ(octree.createProxy(m.tight).value(), m.id);
    ASSERT_EQ(split.createProxy(m.tight).value(), m.id);
    live[m.id.index] = m;
  }
  std::vector<ProxyPair> treePairs;
  std::vector<ProxyPair> octreePairs;
  std::vector<ProxyPair> splitPairs;
  std::vector<std::vector<ProxyPair>> parts(3);
  std::size_t total = 0;
  for (int frame = 0; frame < 40; ++frame) {
    std::vector<bool> buffered(400, frame == 0);
    for (auto& [index, m] : live) {
      const Vec3 d = test::randomVec3(rng, -0.05f, 0.05f);
      m.tight = {m.tight.lower + d, m.tight.upper + d};
      const bool t = tree.moveProxy(m.id, m.tight, d).value();
      const bool o = octree.moveProxy(m.id, m.tight, d).value();
      ASSERT_EQ(t, o);
      ASSERT_EQ(split.moveProxy(m.id, m.tight, d).value(), t);
      if (t) buffered[index] = true;
      m.fat = tree.fatBox(m.id);
      ASSERT_EQ(octree.fatBox(m.id), m.fat);
    }
    tree.updatePairs(treePairs);
    octree.updatePairs(octreePairs);
    split.updatePairs(splitPairs, parts, [](std::size_t count, auto&& body) {
      const std::size_t ranges = (count + 6) / 7;
      for (std::size_t r = ranges; r-- > 0;)
        body(7 * r, std::min(count, 7 * r + 7), r % 3);
    });
    const std::vector<IndexPair> expected =
        test::expectedPairs3(live, buffered, false, [](auto, auto) { return true; });
    ASSERT_EQ(test::sortedPairs(treePairs), expected) << "frame " << frame;
    ASSERT_EQ(test::sortedPairs(octreePairs), expected) << "frame " << frame;
    ASSERT_EQ(test::sortedPairs(splitPairs), expected) << "frame " << frame;
    ASSERT_EQ(splitPairs.size(), expected.size()) << "frame " << frame;
    total += expected.size();
    ASSERT_TRUE(tree.validate().ok()) << tree.validate().message();
    ASSERT_TRUE(octree.validate().ok()) << octree.validate().message();
  }
  EXPECT_GT(total, 400u);
}

TEST(BroadPhase3Names, RoundTripAndRejectUnknown) {
  for (BroadPhase3Kind k : kAllBroadPhase3Kinds) {
    Result<BroadPhase3Kind> parsed = parseBroadPhase3Kind(toString(k));
    ASSERT_TRUE(parsed.ok());
    EXPECT_EQ(parsed.value(), k);
  }
  Result<BroadPhase3Kind> bad = parseBroadPhase3Kind("quadtree");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("quadtree"), std::string::npos);
}

TEST(BroadPhase3Input, BadConfigIsRejectedNamingTheField) {
  BroadPhase3Config c;
  c.margin = -1.0f;
  Result<BroadPhase3> r = BroadPhase3::create(c);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("margin"), std::string::npos);
  c = {};
  c.displacementScale = std::numeric_limits<float>::infinity();
  r = BroadPhase3::create(c);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("displacementScale"), std::string::npos);
  c = {};
  c.cellSize = 0.0f;
  r = BroadPhase3::create(c);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("cellSize"), std::string::npos);
}

TEST(BroadPhase3Input, BadBoxesAndIdsAreRejectedAndChangeNothing) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (BroadPhase3Kind k : kAllBroadPhase3Kinds) {
    SCOPED_TRACE(std::string(toString(k)));
    BroadPhase3Config config;
    config.kind = k;
    BroadPhase3 bp = BroadPhase3::create(config).value();
    const Aabb3 unit{{0, 0, 0}, {1, 1, 1}};
    const ProxyId good = bp.createProxy(unit).value();
    for (Aabb3 bad : {Aabb3{{0, 0, nan}, {1, 1, 1}}, Aabb3{{0, 0, 0}, {1, 1, inf}},
                      Aabb3{{0, 0, 1}, {1, 1, 0}}, Aabb3{{0, 0, 0}, {1, 1, 2e9f}}}) {
      Result<ProxyId> r = bp.createProxy(bad);
      ASSERT_FALSE(r.ok());
      EXPECT_NE(r.error().message.find("box"), std::string::npos);
      ASSERT_FALSE(bp.moveProxy(good, bad, {}).ok());
    }
    EXPECT_FALSE(bp.moveProxy(good, unit, {0, 0, nan}).ok());
    EXPECT_FALSE(bp.destroyProxy(ProxyId{}).ok());
    EXPECT_FALSE(bp.destroyProxy(ProxyId{99, 1}).ok());
    const Status stale = bp.touchProxy(ProxyId{good.index, good.generation + 1});
    ASSERT_FALSE(stale.ok());
    EXPECT_NE(stale.message().find("stale"), std::string::npos);
    EXPECT_EQ(bp.proxyCount(), 1u);
    EXPECT_EQ(bp.tightBox(good), unit);
    EXPECT_TRUE(bp.validate().ok()) << bp.validate().message();
    int hits = 0;
    bp.queryAabb({{nan, nan, nan}, {nan, nan, nan}}, [&](ProxyId, std::uint64_t) {
      ++hits;
      return true;
    });
    EXPECT_EQ(hits, 0);
    EXPECT_FALSE(bp.rayCastClosest({0, 0, nan}, {1, 0, 0}).has_value());
    EXPECT_TRUE(bp.rayCastClosest({-1, 0.5f, 0.5f}, {4, 0, 0}).has_value());
  }
}

TEST(BroadPhase3Stats, ReportsSizesAndQuality) {
  std::mt19937 rng(5);
  for (BroadPhase3Kind k : kAllBroadPhase3Kinds) {
    BroadPhase3Config config;
    config.kind = k;
    BroadPhase3 bp = BroadPhase3::create(config).value();
    for (int i = 0; i < 1000; ++i)
      bp.createProxy(test::randomBox3(rng, 50.0f, 0.25f, 0.5f)).value();
    const BroadPhase3Stats s = bp.stats();
    EXPECT_EQ(s.proxyCount, 1000u);
    EXPECT_GT(s.structureBytes, 1000u * 36u);
    EXPECT_GT(s.recordBytes, 1000u * 48u);
    if (k == BroadPhase3Kind::tree) {
      EXPECT_GE(s.height, 10);  // at least log2(1000)
      EXPECT_GT(s.areaRatio, 1.0f);
      ASSERT_NE(bp.tree(), nullptr);
    } else {
      EXPECT_GE(s.height, 2);
      ASSERT_NE(bp.octree(), nullptr);
    }
  }
}

}  // namespace
}  // namespace quack
