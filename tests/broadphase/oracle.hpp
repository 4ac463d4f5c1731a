#pragma once
// A model of a BroadPhase kept by the tests, and brute-force answers computed from it with
// no code shared with the library except the box primitives of quack/math.

#include <algorithm>
#include <cstdint>
#include <map>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "quack/broadphase/broad_phase.hpp"

namespace quack::test {

struct ModelProxy {
  ProxyId id;
  Aabb tight;
  Aabb fat;
  Filter filter;
  ProxyKind kind = ProxyKind::dynamicProxy;
  std::uint64_t user = 0;
  float margin = 0.0f;  // the proxy's fat-box margin (its own, or the config's)
};

// The filter rule written out independently of shouldCollide().
inline bool modelCollide(const Filter& a, const Filter& b) {
  if (a.group != 0 && a.group == b.group) return a.group > 0;
  const bool aAcceptsB = (a.mask & b.category) != 0;
  const bool bAcceptsA = (b.mask & a.category) != 0;
  return aAcceptsB && bAcceptsA;
}

using IndexPair = std::pair<std::uint32_t, std::uint32_t>;

inline std::vector<IndexPair> sortedPairs(const std::vector<ProxyPair>& pairs) {
  std::vector<IndexPair> out;
  for (const ProxyPair& p : pairs)
    out.emplace_back(p.a.index, p.b.index);
  std::sort(out.begin(), out.end());
  return out;
}

// Expected pairs: at least one buffered, fat boxes overlap, not both static, filters agree,
// tight boxes overlap when asked, and the user filter (a predicate on indices) agrees.
template <class UserFilter>
std::vector<IndexPair> expectedPairs(const std::map<std::uint32_t, ModelProxy>& live,
                                     const std::vector<bool>& buffered, bool tight,
                                     UserFilter&& user) {
  std::vector<IndexPair> out;
  for (auto a = live.begin(); a != live.end(); ++a) {
    for (auto b = std::next(a); b != live.end(); ++b) {
      const ModelProxy& pa = a->second;
      const ModelProxy& pb = b->second;
      const bool moved = buffered[a->first] || buffered[b->first];
      if (!moved) continue;
      if (!overlaps(pa.fat, pb.fat)) continue;
      if (pa.kind == ProxyKind::staticProxy && pb.kind == ProxyKind::staticProxy) continue;
      if (!modelCollide(pa.filter, pb.filter)) continue;
      if (tight && !overlaps(pa.tight, pb.tight)) continue;
      if (!user(a->first, b->first)) continue;
      out.emplace_back(a->first, b->first);
    }
  }
  return out;
}

inline Aabb randomBox(std::mt19937& rng, float world, float minHalf, float maxHalf) {
  std::uniform_real_distribution<float> pos(-world, world);
  std::uniform_real_distribution<float> half(minHalf, maxHalf);
  const Vec2 c{pos(rng), pos(rng)};
  const Vec2 h{half(rng), half(rng)};
  return {c - h, c + h};
}

}  // namespace quack::test
