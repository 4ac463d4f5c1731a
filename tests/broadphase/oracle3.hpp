#pragma once
// The 3D counterpart of oracle.hpp: a model of a BroadPhase3 kept by the tests, random
// boxes and rays, and brute-force answers computed from the model with no code shared with
// the library except the box primitives (overlaps, and detail::rayCast3, whose own test
// compares it with a double-precision slab test).

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "broadphase/oracle.hpp"
#include "quack/broadphase/broad_phase3.hpp"

namespace quack::test {

struct ModelProxy3 {
  ProxyId id;
  Aabb3 tight;
  Aabb3 fat;
  Filter filter;
  ProxyKind kind = ProxyKind::dynamicProxy;
  std::uint64_t user = 0;
};

inline Aabb3 randomBox3(std::mt19937& rng, float world, float minHalf, float maxHalf) {
  std::uniform_real_distribution<float> pos(-world, world);
  std::uniform_real_distribution<float> half(minHalf, maxHalf);
  const Vec3 c{pos(rng), pos(rng), pos(rng)};
  const Vec3 h{half(rng), half(rng), half(rng)};
  return {c - h, c + h};
}

inline Vec3 randomVec3(std::mt19937& rng, float lo, float hi) {
  std::uniform_real_distribution<float> u(lo, hi);
  return {u(rng), u(rng), u(rng)};
}

// Expected pairs of a BroadPhase3: at least one buffered, fat boxes overlap, not both
// static, filters agree (modelCollide of oracle.hpp), tight boxes overlap when asked, and
// the user filter (a predicate on indices) agrees.
template <class UserFilter>
std::vector<IndexPair> expectedPairs3(const std::map<std::uint32_t, ModelProxy3>& live,
                                      const std::vector<bool>& buffered, bool tight,
                                      UserFilter&& user) {
  std::vector<IndexPair> out;
  for (auto a = live.begin(); a != live.end(); ++a) {
    for (auto b = std::next(a); b != live.end(); ++b) {
      const ModelProxy3& pa = a->second;
      const ModelProxy3& pb = b->second;
      if (!buffered[a->first] && !buffered[b->first]) continue;
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

// Every pair of overlapping boxes among `boxes` (index = proxy; absent entries skipped).
inline std::vector<IndexPair> allOverlappingPairs(
    const std::vector<std::pair<bool, Aabb3>>& boxes) {
  std::vector<IndexPair> out;
  for (std::uint32_t a = 0; a < boxes.size(); ++a) {
    if (!boxes[a].first) continue;
    for (std::uint32_t b = a + 1; b < boxes.size(); ++b) {
      if (boxes[b].first && overlaps(boxes[a].second, boxes[b].second)) out.emplace_back(a, b);
    }
  }
  return out;
}

}  // namespace quack::test
