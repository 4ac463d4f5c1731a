#pragma once
/// `BruteForce`: every query tests every proxy. The reference the other structures are
/// checked against, and the fastest choice below a few dozen proxies.
///
/// Proxies are kept in a dense array (removal swaps the last one in), so a query is one
/// linear pass over contiguous boxes. Preconditions as for `DynamicTree`.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "quack/broadphase/proxy.hpp"
#include "quack/core/assert.hpp"
#include "quack/core/result.hpp"
#include "quack/math/aabb.hpp"

namespace quack {

class BruteForce {
 public:
  /// Adds proxy `proxy` with box `box` (world frame, metres).
  void insert(std::uint32_t proxy, Aabb box);
  /// Removes a present proxy.
  void remove(std::uint32_t proxy);
  /// Replaces the box of a present proxy.
  void move(std::uint32_t proxy, Aabb box);
  /// True when `proxy` is present.
  bool contains(std::uint32_t proxy) const noexcept {
    return proxy < slot_.size() && slot_[proxy] != kNullIndex;
  }
  /// The box stored for a present proxy.
  Aabb box(std::uint32_t proxy) const {
    QUACK_ASSERT(contains(proxy));
    return boxes_[slot_[proxy]];
  }
  /// Number of proxies present.
  std::uint32_t proxyCount() const noexcept { return static_cast<std::uint32_t>(boxes_.size()); }

  /// Calls `visit(proxy)` for every proxy whose box overlaps `query`; false stops.
  template <class Visit>
  void query(Aabb query, Visit&& visit) const {
    for (std::size_t i = 0; i < boxes_.size(); ++i) {
      if (overlaps(boxes_[i], query) && !visit(proxies_[i])) return;
    }
  }
  /// As `DynamicTree::rayCast`: every proxy is tested, in storage order.
  template <class Visit>
  void rayCast(Vec2 origin, Vec2 translation, float maxFraction, Vec2 inflation,
               Visit&& visit) const {
    for (std::size_t i = 0; i < boxes_.size(); ++i) {
      const Aabb grown{boxes_[i].lower - inflation, boxes_[i].upper + inflation};
      if (!quack::rayCast(grown, origin, translation, maxFraction).hit) continue;
      const float clip = visit(proxies_[i], maxFraction);
      if (clip == 0.0f) return;
      if (clip > 0.0f && clip < maxFraction) maxFraction = clip;
    }
  }
  /// Nothing to rebuild; releases unused capacity.
  void rebuild();
  /// Bytes of memory held (capacity).
  std::size_t bytesUsed() const noexcept;
  /// Checks that the dense array and the slot table agree.
  Status validate() const;

 private:
  std::vector<Aabb> boxes_;             // dense
  std::vector<std::uint32_t> proxies_;  // dense, parallel to boxes_
  std::vector<std::uint32_t> slot_;     // per proxy: position in the dense arrays, or null
};

}  // namespace quack
