#pragma once
/// `Octree`: a loose octree that needs no world bounds, the 3D counterpart of `Quadtree`
/// with the same interface (`Aabb3` and `Vec3` for `Aabb` and `Vec2`).
///
/// Cells live on an unbounded implicit grid hierarchy: level L has cubic cells of side
/// `s = smallestCellSize * 2^L`, indexed by integers. A box of largest side w goes to the
/// lowest level with w <= s, into the cell holding its centre. Each cell's *loose* box is
/// the cell grown by 0.625 s on every side, so it contains every box stored in it (half a
/// cell for the box's half-width, an eighth of a cell of slack for rounding), and a child's
/// loose box lies inside its parent's. A box straddling cell boundaries is never a special
/// case: it belongs to the one cell whose loose box contains it.
///
/// The root is whatever cell is the lowest common ancestor of the stored boxes: inserting
/// outside it adds parents on top, removing the last box of a branch prunes it, and a root
/// left with a single child and no boxes hands over to that child. So the tree has no
/// predefined bounds and grows and shrinks with the scene. Cells and boxes live in
/// index-linked arrays with free lists; a box is in a doubly linked list of its cell, so
/// every update is O(depth), and a move that keeps its cell only stores the new box.
///
/// Learned from (for understanding): T. Ulrich, "Loose octrees", Game Programming Gems
/// (2000), and this library's 2D `Quadtree`, of which this is a port. Preconditions as for
/// `DynamicTree3`; boxes within +-`kMaxCoordinate` metres.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "quack/broadphase/detail/aabb3_ops.hpp"
#include "quack/broadphase/detail/node_stack.hpp"
#include "quack/broadphase/proxy.hpp"
#include "quack/core/assert.hpp"
#include "quack/core/result.hpp"
#include "quack/math/vec3.hpp"

namespace quack {

/// The loose octree (see the top of this file).
class Octree {
 public:
  /// `smallestCellSize`: side of a level-0 cell in metres, > 0 and finite; boxes smaller than
  /// it share level 0. Near the smallest typical box size is best.
  explicit Octree(float smallestCellSize = 1.0f);

  /// Adds proxy `proxy` with box `box` (world frame, metres).
  void insert(std::uint32_t proxy, Aabb3 box);
  /// Removes a present proxy.
  void remove(std::uint32_t proxy);
  /// Replaces the box of a present proxy; relinks it only when its cell changes.
  void move(std::uint32_t proxy, Aabb3 box);
  /// True when `proxy` is present.
  bool contains(std::uint32_t proxy) const noexcept {
    return proxy < items_.size() && items_[proxy].cell != kNullIndex;
  }
  /// The box stored for a present proxy.
  Aabb3 box(std::uint32_t proxy) const {
    QUACK_ASSERT(contains(proxy));
    return items_[proxy].box;
  }
  /// Number of proxies present.
  std::uint32_t proxyCount() const noexcept { return count_; }
  /// Levels from the root to the deepest cell, 0 when empty.
  int depth() const;
  /// Number of live cells.
  std::uint32_t cellCount() const noexcept { return cellCount_; }
  /// Level of the root cell (cell side = smallestCellSize * 2^level); -1 when empty.
  int rootLevel() const noexcept { return root_ == kNullIndex ? -1 : cells_[root_].level; }

  /// Calls `visit(proxy)` for every proxy whose box overlaps `query` (touching counts);
  /// false stops.
  template <class Visit>
  void query(Aabb3 query, Visit&& visit) const;

  /// As `DynamicTree3::rayCast` (cells are visited depth first, not nearest first).
  template <class Visit>
  void rayCast(Vec3 origin, Vec3 translation, float maxFraction, Vec3 inflation,
               Visit&& visit) const;

  /// Re-inserts every box into fresh arrays (compacts memory after heavy churn).
  void rebuild();
  /// Bytes of memory held (capacity).
  std::size_t bytesUsed() const noexcept;
  /// Checks links, levels, cell coordinates, loose boxes and that every box is in the cell
  /// its size and centre select; no empty leaf cell may remain, nor a root with one child
  /// and no boxes.
  Status validate() const;

 private:
  struct Key {
    std::int64_t x;
    std::int64_t y;
    std::int64_t z;
    std::int32_t level;
  };
  struct Cell {
    Aabb3 loose;
    std::int64_t x;
    std::int64_t y;
    std::int64_t z;
    std::int32_t level;      // -1 when free
    std::uint32_t parent;    // free list link when free
    std::uint32_t child[8];  // slot = (z & 1) << 2 | (y & 1) << 1 | (x & 1) of the child
    std::uint32_t firstItem;
    std::uint8_t childMask;  // bit s set when child[s] is present
  };
  struct Item {
    Aabb3 box;
    std::uint32_t cell;  // kNullIndex when absent
    std::uint32_t next;
    std::uint32_t prev;
  };

  Key keyOf(Aabb3 b) const noexcept;
  Aabb3 looseBoxOf(Key k) const noexcept;
  std::uint32_t newCell(Key k, std::uint32_t parent);
  void freeCell(std::uint32_t cell) noexcept;
  std::uint32_t findOrCreateCell(Key k);
  std::uint32_t childrenOverlapping(const Cell& c, Aabb3 q) const noexcept;
  void link(std::uint32_t proxy, std::uint32_t cell) noexcept;
  void unlink(std::uint32_t proxy) noexcept;
  void prune(std::uint32_t cell) noexcept;

  // Level of the topmost cell (every cell's ancestor), whose loose box is the float range;
  // octree.cpp explains the integer grid.
  static constexpr std::int32_t kTopCellLevel = 62;

  float base_;
  // childSide_[L]: side of a level L - 1 cell (base_ * 2^(L - 1)), formed once (ldexpf is a
  // library call, too slow for every cell a query visits).
  float childSide_[kTopCellLevel + 1] = {};
  std::vector<Cell> cells_;
  std::vector<Item> items_;  // per proxy
  std::uint32_t root_ = kNullIndex;
  std::uint32_t freeCells_ = kNullIndex;
  std::uint32_t cellCount_ = 0;
  std::uint32_t count_ = 0;
};

template <class Visit>
void Octree::query(Aabb3 q, Visit&& visit) const {
  if (root_ == kNullIndex || !overlaps(cells_[root_].loose, q)) return;
  detail::NodeStack stack;
  stack.push(root_);
  while (!stack.empty()) {
    const Cell& c = cells_[stack.pop()];
    for (std::uint32_t i = c.firstItem; i != kNullIndex; i = items_[i].next) {
      if (overlaps(items_[i].box, q) && !visit(i)) return;
    }
    for (std::uint32_t m = childrenOverlapping(c, q); m != 0; m &= m - 1) {
      stack.push(c.child[std::countr_zero(m)]);
    }
  }
}

inline std::uint32_t Octree::childrenOverlapping(const Cell& c, Aabb3 q) const noexcept {
  // The children's loose boxes follow from the parent's: with h the child's side and L, U
  // the parent's loose bounds on an axis (U = L + 4.5 h), the lower child spans
  // [L + 0.625 h, L + 2.875 h] and the upper one [L + 1.625 h, U - 0.625 h]. Testing those
  // ranges, grown by kChildPad h against float rounding, picks the children to visit with
  // six comparisons and without reading the children's cells; a child picked whose stored
  // loose box misses the query costs one visit, and none is missed: h is at least 64 ulps
  // of the coordinates (keyOf's kMinCellInUlps), and the rounding of these sums is a few.
  // The topmost cell's loose box is the whole float range, so its children are read.
  if (c.childMask == 0) return 0;
  if (c.level >= kTopCellLevel) {
    std::uint32_t m = 0;
    for (int s = 0; s < 8; ++s) {
      if (c.child[s] != kNullIndex && overlaps(cells_[c.child[s]].loose, q)) m |= 1u << s;
    }
    return m;
  }
  constexpr float kChildPad = 1.0f / 16.0f;
  const float h = childSide_[c.level];
  const float lo0 = (0.625f - kChildPad) * h;
  const float hi0 = (2.875f + kChildPad) * h;
  const float lo1 = (1.625f - kChildPad) * h;
  const float hi1 = (0.625f - kChildPad) * h;
  auto axis = [&](float l, float u, float ql, float qu, std::uint32_t lowBits,
                  std::uint32_t highBits) {
    std::uint32_t m = 0;
    if (ql <= l + hi0 && qu >= l + lo0) m |= lowBits;
    if (ql <= u - hi1 && qu >= l + lo1) m |= highBits;
    return m;
  };
  return c.childMask & axis(c.loose.lower.x, c.loose.upper.x, q.lower.x, q.upper.x, 0x55u, 0xaau) &
         axis(c.loose.lower.y, c.loose.upper.y, q.lower.y, q.upper.y, 0x33u, 0xccu) &
         axis(c.loose.lower.z, c.loose.upper.z, q.lower.z, q.upper.z, 0x0fu, 0xf0u);
}

template <class Visit>
void Octree::rayCast(Vec3 origin, Vec3 translation, float maxFraction, Vec3 inflation,
                     Visit&& visit) const {
  if (root_ == kNullIndex) return;
  const detail::Ray3 ray(origin, translation);
  auto reaches = [&](Aabb3 b) {
    return detail::rayCast3(detail::grow3(b, inflation), ray, maxFraction).hit;
  };
  if (!reaches(cells_[root_].loose)) return;
  detail::NodeStack stack;
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
