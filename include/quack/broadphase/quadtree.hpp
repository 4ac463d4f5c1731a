#pragma once
/// `Quadtree`: a loose quadtree that needs no world bounds.
///
/// Cells live on an unbounded implicit grid hierarchy: level L has square cells of side
/// `s = smallestCellSize * 2^L`, indexed by integers. A box of largest side w goes to the
/// lowest level with w <= s, into the cell holding its centre. Each cell's *loose* box is
/// the cell grown by 0.625 s on every side, so it contains every box stored in it (half a
/// cell for the box's half-width, an eighth of a cell of slack for rounding), and a child's
/// loose box lies inside its parent's. A box straddling cell boundaries is therefore never a
/// special case: it simply belongs to one cell whose loose box contains it.
///
/// The root is whatever cell is the lowest common ancestor of the stored boxes: inserting
/// outside it adds parents on top, removing the last box of a branch prunes it, and a root
/// left with a single child and no boxes hands over to that child. Cells and boxes live in
/// index-linked arrays with free lists; a box is in a doubly linked list of its cell, so
/// every update is O(depth).
///
/// Learned from (for understanding): T. Ulrich, "Loose octrees", Game Programming Gems
/// (2000). Preconditions as for `DynamicTree`; boxes within +-`kMaxCoordinate` metres.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "quack/broadphase/detail/traversal_stack.hpp"
#include "quack/broadphase/proxy.hpp"
#include "quack/core/assert.hpp"
#include "quack/core/result.hpp"
#include "quack/math/aabb.hpp"

namespace quack {

class Quadtree {
 public:
  /// `smallestCellSize`: side of a level-0 cell in metres, > 0 and finite; boxes smaller than
  /// it share level 0. Near the smallest typical box size is best.
  explicit Quadtree(float smallestCellSize = 1.0f);

  /// Adds proxy `proxy` with box `box` (world frame, metres).
  void insert(std::uint32_t proxy, Aabb box);
  /// Removes a present proxy.
  void remove(std::uint32_t proxy);
  /// Replaces the box of a present proxy; relinks it only when its cell changes.
  void move(std::uint32_t proxy, Aabb box);
  /// True when `proxy` is present.
  bool contains(std::uint32_t proxy) const noexcept {
    return proxy < items_.size() && items_[proxy].cell != kNullIndex;
  }
  /// The box stored for a present proxy.
  Aabb box(std::uint32_t proxy) const {
    QUACK_ASSERT(contains(proxy));
    return items_[proxy].box;
  }
  /// Number of proxies present.
  std::uint32_t proxyCount() const noexcept { return count_; }
  /// Levels from the root to the deepest cell, 0 when empty.
  int depth() const;
  /// Number of live cells.
  std::uint32_t cellCount() const noexcept { return cellCount_; }

  /// Calls `visit(proxy)` for every proxy whose box overlaps `query`; false stops.
  template <class Visit>
  void query(Aabb query, Visit&& visit) const;

  /// As `DynamicTree::rayCast` (cells are visited in depth-first order, not nearest first).
  template <class Visit>
  void rayCast(Vec2 origin, Vec2 translation, float maxFraction, Vec2 inflation,
               Visit&& visit) const;

  /// Re-inserts every box into fresh arrays (compacts memory after heavy churn).
  void rebuild();
  /// Bytes of memory held (capacity).
  std::size_t bytesUsed() const noexcept;
  /// Checks links, levels, cell coordinates, loose boxes and that every box is in the cell
  /// its size and centre select; no empty leaf cell may remain.
  Status validate() const;

 private:
  struct Key {
    std::int64_t x;
    std::int64_t y;
    std::int32_t level;
  };
  struct Cell {
    Aabb loose;
    std::int64_t x;
    std::int64_t y;
    std::int32_t level;      // -1 when free
    std::uint32_t parent;    // free list link when free
    std::uint32_t child[4];  // slot = (y & 1) << 1 | (x & 1) of the child
    std::uint32_t firstItem;
  };
  struct Item {
    Aabb box;
    std::uint32_t cell;  // kNullIndex when absent
    std::uint32_t next;
    std::uint32_t prev;
  };

  Key keyOf(Aabb b) const noexcept;
  Aabb looseBoxOf(Key k) const noexcept;
  std::uint32_t newCell(Key k, std::uint32_t parent);
  void freeCell(std::uint32_t cell) noexcept;
  std::uint32_t findOrCreateCell(Key k);
  void link(std::uint32_t proxy, std::uint32_t cell) noexcept;
  void unlink(std::uint32_t proxy) noexcept;
  void prune(std::uint32_t cell) noexcept;

  float base_;
  std::vector<Cell> cells_;
  std::vector<Item> items_;  // per proxy
  std::uint32_t root_ = kNullIndex;
  std::uint32_t freeCells_ = kNullIndex;
  std::uint32_t cellCount_ = 0;
  std::uint32_t count_ = 0;
};

template <class Visit>
void Quadtree::query(Aabb q, Visit&& visit) const {
  if (root_ == kNullIndex || !overlaps(cells_[root_].loose, q)) return;
  detail::TraversalStack stack;
  stack.push(root_);
  while (!stack.empty()) {
    const Cell& c = cells_[stack.pop()];
    for (std::uint32_t i = c.firstItem; i != kNullIndex; i = items_[i].next) {
      if (overlaps(items_[i].box, q) && !visit(i)) return;
    }
    for (std::uint32_t child : c.child) {
      if (child != kNullIndex && overlaps(cells_[child].loose, q)) stack.push(child);
    }
  }
}

template <class Visit>
void Quadtree::rayCast(Vec2 origin, Vec2 translation, float maxFraction, Vec2 inflation,
                       Visit&& visit) const {
  if (root_ == kNullIndex) return;
  auto reaches = [&](Aabb b) {
    return quack::rayCast(Aabb{b.lower - inflation, b.upper + inflation}, origin, translation,
                          maxFraction)
        .hit;
  };
  if (!reaches(cells_[root_].loose)) return;
  detail::TraversalStack stack;
  stack.push(root_);
  while (!stack.empty()) {
    const Cell& c = cells_[stack.pop()];
    // The ray may have been clipped since this cell was pushed.
    if (!reaches(c.loose)) continue;
    for (std::uint32_t i = c.firstItem; i != kNullIndex; i = items_[i].next) {
      if (!reaches(items_[i].box)) continue;
      const float clip = visit(i, maxFraction);
      if (clip == 0.0f) return;
      if (clip > 0.0f && clip < maxFraction) maxFraction = clip;
    }
    for (std::uint32_t child : c.child) {
      if (child != kNullIndex && reaches(cells_[child].loose)) stack.push(child);
    }
  }
}

}  // namespace quack
