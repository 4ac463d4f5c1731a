// The proximity-phase rules as a truth table, on shouldCollide() and through updatePairs().

#include <gtest/gtest.h>

#include <string>

#include "quack/broadphase/broad_phase.hpp"

namespace quack {
namespace {

struct FilterRow {
  const char* name;
  Filter a;
  Filter b;
  bool collide;
};

constexpr std::uint64_t kAll = ~std::uint64_t{0};
constexpr std::uint64_t kBit0 = 1;
constexpr std::uint64_t kBit1 = 2;
constexpr std::uint64_t kBit63 = std::uint64_t{1} << 63;

const FilterRow kRows[] = {
    {"defaults collide", {}, {}, true},
    {"a's mask excludes b", {kBit0, kBit0, 0}, {kBit1, kAll, 0}, false},
    {"b's mask excludes a", {kBit0, kAll, 0}, {kBit1, kBit1, 0}, false},
    {"both masks accept", {kBit0, kBit1, 0}, {kBit1, kBit0, 0}, true},
    {"category 63 is honoured", {kBit63, kAll, 0}, {kBit0, ~kBit63, 0}, false},
    {"category 63 accepted", {kBit63, kAll, 0}, {kBit0, kBit63, 0}, true},
    {"same negative group never", {kBit0, kAll, -3}, {kBit0, kAll, -3}, false},
    {"same positive group always", {kBit0, 0, 4}, {kBit1, 0, 4}, true},
    {"different groups fall back to masks", {kBit0, kAll, 4}, {kBit1, kAll, -4}, true},
    {"different groups, masks refuse", {kBit0, 0, 4}, {kBit1, kAll, 5}, false},
    {"group 0 is no group", {kBit0, 0, 0}, {kBit1, 0, 0}, false},
    {"one in a group, other not", {kBit0, kAll, -1}, {kBit0, kAll, 0}, true},
};

TEST(Filter, TruthTableAndSymmetry) {
  for (const FilterRow& row : kRows) {
    SCOPED_TRACE(row.name);
    EXPECT_EQ(shouldCollide(row.a, row.b), row.collide);
    EXPECT_EQ(shouldCollide(row.b, row.a), row.collide);
  }
}

struct UserVeto {
  std::uint64_t vetoed = 0;
  int calls = 0;
};

bool vetoUser(void* context, ProxyId, std::uint64_t userA, ProxyId, std::uint64_t userB) {
  auto* v = static_cast<UserVeto*>(context);
  ++v->calls;
  return userA != v->vetoed && userB != v->vetoed;
}

TEST(Filter, PairsObeyTheTableStaticRuleAndUserCallbackInEveryStructure) {
  for (BroadPhaseKind kind : kAllBroadPhaseKinds) {
    SCOPED_TRACE(std::string(toString(kind)));
    for (const FilterRow& row : kRows) {
      SCOPED_TRACE(row.name);
      // kinds: dynamic/dynamic, static/dynamic, static/static; user veto on and off.
      for (int kinds = 0; kinds < 3; ++kinds) {
        for (bool veto : {false, true}) {
          BroadPhaseConfig config;
          config.kind = kind;
          BroadPhase bp = BroadPhase::create(config).value();
          UserVeto user{veto ? std::uint64_t{2} : std::uint64_t{99}, 0};
          bp.setPairFilter(vetoUser, &user);
          const ProxyKind ka = kinds == 2 ? ProxyKind::staticProxy : ProxyKind::dynamicProxy;
          const ProxyKind kb = kinds >= 1 ? ProxyKind::staticProxy : ProxyKind::dynamicProxy;
          bp.createProxy({{0, 0}, {1, 1}}, 1, row.a, ka).value();
          bp.createProxy({{0.5f, 0.5f}, {2, 2}}, 2, row.b, kb).value();
          std::vector<ProxyPair> pairs;
          bp.updatePairs(pairs);
          const bool builtIn = row.collide && kinds != 2;
          EXPECT_EQ(pairs.size(), builtIn && !veto ? 1u : 0u)
              << "kinds=" << kinds << " veto=" << veto;
          // The user callback sees only pairs the built-in rules accepted.
          EXPECT_EQ(user.calls, builtIn ? 1 : 0);
        }
      }
    }
  }
}

TEST(Filter, ChangingAFilterReReportsThePairUnderTheNewRule) {
  BroadPhase bp = BroadPhase::create().value();
  const ProxyId a = bp.createProxy({{0, 0}, {1, 1}}, 0, {kBit0, kAll, -1}).value();
  bp.createProxy({{0, 0}, {1, 1}}, 0, {kBit0, kAll, -1}).value();
  std::vector<ProxyPair> pairs;
  bp.updatePairs(pairs);
  EXPECT_TRUE(pairs.empty());
  ASSERT_TRUE(bp.setFilter(a, {kBit0, kAll, 0}).ok());
  EXPECT_EQ(bp.filter(a).group, 0);
  bp.updatePairs(pairs);
  EXPECT_EQ(pairs.size(), 1u);
}

}  // namespace
}  // namespace quack
