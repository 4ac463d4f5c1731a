#pragma once
/// `SweepAndPrune`: boxes sorted by their lower x bound; a sweep along x finds every
/// overlapping pair in O(n + pairs), and a query scans the window of boxes that can reach
/// it.
///
/// Moving a proxy only rewrites its box; the order is restored lazily, by insertion sort
/// (near-linear for coherent motion), before the next query or sweep. New proxies are sorted
/// on their own and merged in; removed proxies leave tombstones compacted at the same time.
/// Because of that lazy step, the `const` queries may reorganise internal (mutable) state: do
/// not query one `SweepAndPrune` from several threads while changes are pending (after
/// `BroadPhase::updatePairs()` none are).
///
/// Learned from (for understanding): D. Baraff, "Dynamic simulation of non-penetrating rigid
/// bodies" (1992), and P. Terdiman, "Sweep-and-prune" notes (2007). Preconditions as for
/// `DynamicTree`.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "quack/broadphase/proxy.hpp"
#include "quack/core/assert.hpp"
#include "quack/core/result.hpp"
#include "quack/math/aabb.hpp"

namespace quack {

class SweepAndPrune {
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
    return entries_[slot_[proxy]].box;
  }
  /// Number of proxies present.
  std::uint32_t proxyCount() const noexcept { return count_; }

  /// Calls `visit(proxy)` for every proxy whose box overlaps `query`; false stops.
  template <class Visit>
  void query(Aabb query, Visit&& visit) const {
    flush();
    // The slack covers the rounding of the widths and of this subtraction (a few ulps).
    const float start = query.lower.x - maxWidth_ - 1e-6f * (absf(query.lower.x) + maxWidth_);
    auto it = std::lower_bound(entries_.begin(), entries_.end(), start,
                               [](const Entry& e, float x) { return e.box.lower.x < x; });
    for (; it != entries_.end() && it->box.lower.x <= query.upper.x; ++it) {
      if (overlaps(it->box, query) && !visit(it->proxy)) return;
    }
  }

  /// As `DynamicTree::rayCast`; candidates are the boxes in the segment's bounding box, in x
  /// order.
  template <class Visit>
  void rayCast(Vec2 origin, Vec2 translation, float maxFraction, Vec2 inflation,
               Visit&& visit) const {
    const Aabb swept =
        sweep(Aabb{origin - inflation, origin + inflation}, maxFraction * translation);
    query(swept, [&](std::uint32_t proxy) {
      const Aabb b = entries_[slot_[proxy]].box;
      const Aabb grown{b.lower - inflation, b.upper + inflation};
      if (!quack::rayCast(grown, origin, translation, maxFraction).hit) return true;
      const float clip = visit(proxy, maxFraction);
      if (clip == 0.0f) return false;
      if (clip > 0.0f && clip < maxFraction) maxFraction = clip;
      return true;
    });
  }

  /// True when one sweep over all proxies is expected to beat one query per moved proxy.
  bool prefersSweep(std::size_t movedCount) const noexcept {
    // A windowed query costs a binary search plus the window; the sweep costs about two
    // window lengths per proxy. Measured crossover (bench/broadphase) is near 1 in 16.
    return movedCount * 16 > count_;
  }

  /// Calls `onPair(a, b)` once for every pair of overlapping boxes with `isMoved(a) ||
  /// isMoved(b)`.
  template <class IsMoved, class OnPair>
  void sweepPairs(IsMoved&& isMoved, OnPair&& onPair) const {
    flush();
    const std::size_t n = entries_.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Entry& a = entries_[i];
      const bool aMoved = isMoved(a.proxy);
      for (std::size_t j = i + 1; j < n && entries_[j].box.lower.x <= a.box.upper.x; ++j) {
        const Entry& b = entries_[j];
        if (b.box.lower.y > a.box.upper.y || a.box.lower.y > b.box.upper.y) continue;
        if (aMoved || isMoved(b.proxy)) onPair(a.proxy, b.proxy);
      }
    }
  }

  /// Sorts from scratch and releases unused capacity.
  void rebuild();
  /// Bytes of memory held (capacity).
  std::size_t bytesUsed() const noexcept;
  /// Checks the order, the slot table and the widest-box bound (after restoring the order).
  Status validate() const;

 private:
  struct Entry {
    Aabb box;
    std::uint32_t proxy;  // kNullIndex for a tombstone
  };
  void flush() const;

  mutable std::vector<Entry> entries_;
  mutable std::vector<std::uint32_t> slot_;  // per proxy: index in entries_, or null
  mutable std::size_t sortedEnd_ = 0;        // entries_[sortedEnd_..] were appended unsorted
  mutable std::size_t tombstones_ = 0;
  mutable bool dirty_ = false;
  mutable float maxWidth_ = 0.0f;  // an upper bound of every box's x width
  std::uint32_t count_ = 0;
};

}  // namespace quack
