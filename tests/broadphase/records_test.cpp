// BroadPhase::records and fromRecords (used by World::snapshot and restore): a broad phase
// rebuilt from its records reports the same pairs, boxes and hits as the original from then
// on, for every structure; bad records are refused by name. IdPool::fromSlots likewise.

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "quack/broadphase/broad_phase.hpp"

namespace quack {
namespace {

std::vector<ProxyPair> sortedPairs(BroadPhase& bp) {
  std::vector<ProxyPair> pairs;
  bp.updatePairs(pairs);
  std::sort(pairs.begin(), pairs.end(), [](ProxyPair x, ProxyPair y) {
    return x.a.index != y.a.index ? x.a.index < y.a.index : x.b.index < y.b.index;
  });
  return pairs;
}

Aabb boxAt(float x, float y, float h) {
  return {{x - h, y - h}, {x + h, y + h}};
}

class RecordsAllKinds : public ::testing::TestWithParam<BroadPhaseKind> {};

TEST_P(RecordsAllKinds, RebuiltBroadPhaseBehavesTheSame) {
  BroadPhase bp = BroadPhase::create({.kind = GetParam()}).value();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-20.0f, 20.0f);
  std::vector<ProxyId> ids;
  for (int i = 0; i < 200; ++i) {
    const ProxyKind kind = i % 7 == 0 ? ProxyKind::staticProxy : ProxyKind::dynamicProxy;
    ids.push_back(bp.createProxy(boxAt(pos(rng), pos(rng), 0.5f), 1000u + static_cast<unsigned>(i),
                                 {.category = 1u << (i % 3), .mask = ~0ull}, kind)
                      .value());
  }
  (void)sortedPairs(bp);
  // Churn: destroyed slots (free list, bumped generations), moves (some re-inserted, so in
  // the move buffer), and a stale move-buffer entry of a destroyed proxy.
  for (int i = 0; i < 200; i += 9) {
    ASSERT_TRUE(bp.moveProxy(ids[static_cast<std::size_t>(i)], boxAt(pos(rng), pos(rng), 0.5f),
                             {0.1f, 0.0f})
                    .ok());
  }
  for (int i = 3; i < 200; i += 17)
    ASSERT_TRUE(bp.destroyProxy(ids[static_cast<std::size_t>(i)]).ok());

  Result<BroadPhase> copy = BroadPhase::fromRecords(bp.config(), bp.records());
  ASSERT_TRUE(copy.ok()) << copy.error().message;
  BroadPhase& rebuilt = copy.value();
  ASSERT_TRUE(rebuilt.validate().ok());
  EXPECT_EQ(rebuilt.proxyCount(), bp.proxyCount());
  for (ProxyId id : ids) {
    ASSERT_EQ(rebuilt.isValid(id), bp.isValid(id));
    if (!bp.isValid(id)) continue;
    EXPECT_EQ(rebuilt.fatBox(id).lower, bp.fatBox(id).lower);
    EXPECT_EQ(rebuilt.fatBox(id).upper, bp.fatBox(id).upper);
    EXPECT_EQ(rebuilt.userData(id), bp.userData(id));
    EXPECT_EQ(rebuilt.filter(id), bp.filter(id));
  }
  // The pending pairs, then ten rounds of the same moves: the same pairs each time.
  const std::vector<ProxyPair> first = sortedPairs(bp);
  EXPECT_FALSE(first.empty());
  EXPECT_EQ(sortedPairs(rebuilt), first);
  for (int round = 0; round < 10; ++round) {
    for (std::size_t i = 0; i < ids.size(); i += 3) {
      if (!bp.isValid(ids[i])) continue;
      const Aabb b = boxAt(pos(rng), pos(rng), 0.5f);
      ASSERT_EQ(bp.moveProxy(ids[i], b, {0.0f, 0.0f}).value(),
                rebuilt.moveProxy(ids[i], b, {0.0f, 0.0f}).value());
    }
    EXPECT_EQ(sortedPairs(rebuilt), sortedPairs(bp)) << "round " << round;
  }
  // New proxies take the same slots and generations.
  const ProxyId a = bp.createProxy(boxAt(0, 0, 1)).value();
  const ProxyId b = rebuilt.createProxy(boxAt(0, 0, 1)).value();
  EXPECT_EQ(a, b);
  // Hits: the same set (the order of a structure's visits may differ; sorted here).
  EXPECT_EQ(rebuilt.rayCastAll({-30, 0}, {60, 1}).size(), bp.rayCastAll({-30, 0}, {60, 1}).size());
}

INSTANTIATE_TEST_SUITE_P(BroadPhaseRecords, RecordsAllKinds,
                         ::testing::ValuesIn(kAllBroadPhaseKinds),
                         [](const auto& param) { return std::string(toString(param.param)); });

TEST(BroadPhaseRecords, BadRecordsAreRefusedByName) {
  BroadPhase bp = BroadPhase::create({}).value();
  for (int i = 0; i < 4; ++i)
    (void)bp.createProxy(boxAt(static_cast<float>(i), 0, 0.5f)).value();
  const BroadPhaseRecords good = bp.records();
  auto refused = [&](BroadPhaseRecords r, const char* expected) {
    Result<BroadPhase> made = BroadPhase::fromRecords({}, std::move(r));
    ASSERT_FALSE(made.ok()) << "accepted; expected " << expected;
    EXPECT_NE(made.error().message.find(expected), std::string::npos) << made.error().message;
  };
  BroadPhaseRecords r = good;
  r.fat.pop_back();
  refused(r, "differ in length");
  r = good;
  r.freeSlots = {9};
  refused(r, "free slot 9 is beyond");
  r = good;
  r.freeSlots = {1, 1};
  refused(r, "listed twice");
  r = good;
  r.generations[2] = 0;
  refused(r, "slot 2 has generation 0");
  r = good;
  r.tight[1] = boxAt(50, 0, 0.5f);
  refused(r, "proxy 1 tight box is outside its fat box");
  r = good;
  r.fat[0].lower.x = std::numeric_limits<float>::quiet_NaN();
  refused(r, "proxy 0 fat box has a NaN");
  r = good;
  r.buffered[3] = 1;
  r.moveBuffer.clear();
  refused(r, "is buffered but not in the move buffer");
  r = good;
  r.moveBuffer.push_back(99);
  refused(r, "move buffer entry 99 is beyond");
  r = good;
  r.margins.pop_back();
  refused(r, "differ in length");
  r = good;
  r.margins[2] = std::numeric_limits<float>::quiet_NaN();
  refused(r, "proxy 2 margin must be finite and >= 0");
  r = good;
  r.margins[1] = -0.01f;
  refused(r, "proxy 1 margin must be finite and >= 0");
}

// A proxy's own margin outlives a round trip through the records: a move that leaves the
// fat box re-inserts it with its margin, not the config's. Empty margins mean the config's.
TEST(BroadPhaseRecords, ProxyMarginsSurviveTheRoundTrip) {
  BroadPhaseConfig config;
  config.margin = 0.1f;
  config.displacementScale = 0.0f;
  BroadPhase bp = BroadPhase::create(config).value();
  const ProxyId own =
      bp.createProxy(boxAt(0, 0, 0.5f), 0, {}, ProxyKind::dynamicProxy, 0.01f).value();
  const ProxyId plain = bp.createProxy(boxAt(5, 0, 0.5f)).value();
  EXPECT_EQ(bp.records().margins, (std::vector<float>{0.01f, 0.1f}));
  BroadPhase rebuilt = BroadPhase::fromRecords(config, bp.records()).value();
  ASSERT_TRUE(rebuilt.moveProxy(own, boxAt(1, 0, 0.5f), {}).value());
  ASSERT_TRUE(rebuilt.moveProxy(plain, boxAt(6, 0, 0.5f), {}).value());
  EXPECT_EQ(rebuilt.fatBox(own), inflate(boxAt(1, 0, 0.5f), 0.01f));
  EXPECT_EQ(rebuilt.fatBox(plain), inflate(boxAt(6, 0, 0.5f), 0.1f));
  BroadPhaseRecords r = bp.records();
  r.margins.clear();
  BroadPhase defaulted = BroadPhase::fromRecords(config, std::move(r)).value();
  ASSERT_TRUE(defaulted.moveProxy(own, boxAt(1, 0, 0.5f), {}).value());
  EXPECT_EQ(defaulted.fatBox(own), inflate(boxAt(1, 0, 0.5f), 0.1f));
}

}  // namespace
}  // namespace quack
