#pragma once
/// `DynamicTree`: a dynamic bounding-volume hierarchy of axis-aligned boxes.
///
/// Leaves are proxies (indices chosen by the caller, dense from 0); internal nodes have two
/// children and store *both children's boxes* (so a descent or a query reads one node per
/// level instead of three), their parent and their height. A leaf stores only where it hangs
/// (its parent node and slot). Nodes live in one array with a free list threaded through
/// it; there are no pointers. 48 bytes per internal node plus 4 per leaf: 52 bytes a proxy.
///
/// Insertion descends by the surface-area heuristic (in 2D the "area" is the perimeter);
/// every node on the way back up is re-balanced by a rotation when its children's heights
/// differ by more than one. `rebuild()` throws the hierarchy away and builds it top-down with
/// a binned surface-area heuristic, for bulk loads.
///
/// Learned from (read for understanding, not copied): E. Catto, "Dynamic Bounding Volume
/// Hierarchies", GDC 2019, and Box2D's b2DynamicTree (greedy SAH descent and AVL-style
/// rotations); I. Wald, "On fast construction of SAH-based BVHs", 2007 (binned SAH).
///
/// The structure is written against the box operations of `quack/math/aabb.hpp` only
/// (`merge`, `perimeter` as the surface area, `overlaps`, `contains`, `rayCast`), so a 3D box
/// type with the same operations needs no change to the algorithms.
///
/// Preconditions (checked by `QUACK_ASSERT`; `BroadPhase` checks them for its users): boxes
/// are valid (finite, lower <= upper); a proxy is inserted at most once and removed or moved
/// only while present.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "quack/broadphase/detail/traversal_stack.hpp"
#include "quack/broadphase/proxy.hpp"
#include "quack/core/assert.hpp"
#include "quack/core/result.hpp"
#include "quack/math/aabb.hpp"

namespace quack {

class DynamicTree {
 public:
  /// Adds proxy `proxy` with box `box` (world frame, metres). Grows the leaf table as needed.
  void insert(std::uint32_t proxy, Aabb box);
  /// Removes a present proxy.
  void remove(std::uint32_t proxy);
  /// Replaces the box of a present proxy (removes and re-inserts its leaf).
  void move(std::uint32_t proxy, Aabb box);
  /// Replaces the box of a present proxy without re-inserting it: the leaf keeps its place,
  /// its ancestors' boxes grow to hold the new box and are marked enlarged. Queries stay
  /// exact (every box still holds what is below it) but look at more nodes, until
  /// `rebuildEnlarged()` rebuilds the enlarged part of the hierarchy. For many proxies
  /// moved at once (a world step), this with one rebuild costs a fraction of `move` each.
  void enlarge(std::uint32_t proxy, Aabb box);
  /// Rebuilds the part of the hierarchy that `enlarge` marked: every enlarged node is
  /// dropped and the subtrees and leaves hanging from them are joined again top down, by
  /// splitting at the middle of their centres along the wider axis. Untouched subtrees are
  /// kept whole. Does nothing when nothing was enlarged. `insert`, `remove` and `move` call
  /// it first; `rebuild` builds everything anew.
  void rebuildEnlarged();
  /// True when `enlarge` has marked nodes that `rebuildEnlarged` has not rebuilt yet.
  bool hasEnlarged() const noexcept { return enlarged_; }
  /// True when `proxy` is in the tree.
  bool contains(std::uint32_t proxy) const noexcept {
    return proxy < leafParent_.size() && leafParent_[proxy] != kAbsent;
  }
  /// The box stored for a present proxy.
  Aabb box(std::uint32_t proxy) const;
  /// Number of proxies in the tree.
  std::uint32_t proxyCount() const noexcept { return leafCount_; }

  /// Calls `visit(proxy)` for every proxy whose box overlaps `query` (touching counts), in
  /// no particular order; `visit` returns false to stop the query.
  template <class Visit>
  void query(Aabb query, Visit&& visit) const;

  /// Casts the segment `origin + t * translation`, t in [0, maxFraction], against the boxes
  /// grown by `inflation` (half-extents, >= 0; zero for a ray, the moving box's half-extents
  /// for a box cast). Calls `visit(proxy, maxFraction)` for proxies whose grown box the
  /// segment reaches, nearest subtrees first; `visit` returns the new `maxFraction` (return
  /// the value passed in to go on unclipped, a smaller one to clip, 0 to stop).
  template <class Visit>
  void rayCast(Vec2 origin, Vec2 translation, float maxFraction, Vec2 inflation,
               Visit&& visit) const;

  /// Rebuilds the whole hierarchy with a binned surface-area heuristic (top down). Proxies
  /// and their boxes are unchanged; only the shape of the tree changes.
  void rebuild();

  /// Calls `visit(Aabb box, int depth)` for every internal node, the root at depth 0, with
  /// the node's box (the union of its children's): the hierarchy, for drawing and tools.
  /// Leaves are the proxies' own boxes and are not visited.
  template <class Visit>
  void visitInternalNodes(Visit&& visit) const;

  /// Height of the tree: 0 for empty or a single leaf, else 1 + the taller child.
  int height() const noexcept;
  /// Sum of the perimeters of all internal nodes divided by the root's perimeter: 0 when
  /// empty, lower is a tighter tree (a quality measure, as in Box2D).
  float areaRatio() const noexcept;
  /// Bytes of memory held (capacity, not size).
  std::size_t bytesUsed() const noexcept;
  /// Checks every invariant: parent links, child boxes equal to the merge of their children,
  /// heights, leaf and node counts, the free list. The message names the first failure.
  Status validate() const;

 private:
  static constexpr std::uint32_t kLeafBit = 0x80000000u;
  // Parent reference of a leaf not in the tree. Node indices stay below 2^30 (asserted), so
  // no real reference (node << 1 | slot) takes this value.
  static constexpr std::uint32_t kAbsent = 0xfffffffeu;

  struct Node {
    Aabb childBox[2];
    std::uint32_t child[2];  // node index, or proxy | kLeafBit
    std::uint32_t parent;    // (node << 1) | slot, kNullIndex at the root; free list link
    std::int16_t height;     // -1 when free
    // Set by enlarge on every ancestor of a moved leaf (so every ancestor of an enlarged
    // node is enlarged); its box in the parent holds its children's boxes, not equals
    // their merge. Cleared by rebuildEnlarged, which drops these nodes.
    std::uint16_t enlarged;
  };

  struct Built {
    std::uint32_t ref;
    Aabb box;
    std::int32_t height;
  };
  struct BuildItem {
    Aabb box;
    Vec2 centroid;
    std::uint32_t ref;  // proxy | kLeafBit, or a kept subtree's node
  };

  static bool isLeaf(std::uint32_t ref) noexcept { return (ref & kLeafBit) != 0; }
  std::int32_t heightOf(std::uint32_t ref) const noexcept {
    return isLeaf(ref) ? 0 : nodes_[ref].height;
  }
  void setParent(std::uint32_t ref, std::uint32_t parentRef) noexcept;
  void link(std::uint32_t parentRef, std::uint32_t ref, Aabb box) noexcept;
  std::uint32_t allocateNode();
  void freeNode(std::uint32_t node) noexcept;
  void insertLeaf(std::uint32_t proxy, Aabb box);
  void removeLeaf(std::uint32_t proxy);
  void fixUpward(std::uint32_t node);
  std::uint32_t balance(std::uint32_t node);
  Built build(BuildItem* items, std::size_t count, std::uint32_t parentRef, int depth);
  Built buildMidpoint(BuildItem* items, std::size_t count, std::uint32_t parentRef, int depth);
  Built join(std::uint32_t node, const Built& left, const Built& right);

  std::vector<Node> nodes_;
  std::vector<std::uint32_t> leafParent_;  // per proxy: (node << 1) | slot, or kAbsent
  std::uint32_t root_ = kNullIndex;        // node index or proxy | kLeafBit
  Aabb rootBox_;
  std::uint32_t freeList_ = kNullIndex;
  std::uint32_t nodeCount_ = 0;
  std::uint32_t leafCount_ = 0;
  bool enlarged_ = false;
  std::vector<BuildItem> rebuildItems_;  // rebuildEnlarged's scratch, kept for its capacity
  std::vector<std::uint32_t> rebuildStack_;
};

template <class Visit>
void DynamicTree::query(Aabb q, Visit&& visit) const {
  if (root_ == kNullIndex || !overlaps(rootBox_, q)) return;
  if (isLeaf(root_)) {
    visit(root_ & ~kLeafBit);
    return;
  }
  detail::TraversalStack stack;
  stack.push(root_);
  while (!stack.empty()) {
    const Node& node = nodes_[stack.pop()];
    for (int s = 0; s < 2; ++s) {
      if (!overlaps(node.childBox[s], q)) continue;
      std::uint32_t c = node.child[s];
      if (isLeaf(c)) {
        if (!visit(c & ~kLeafBit)) return;
      } else {
        stack.push(c);
      }
    }
  }
}

template <class Visit>
void DynamicTree::rayCast(Vec2 origin, Vec2 translation, float maxFraction, Vec2 inflation,
                          Visit&& visit) const {
  if (root_ == kNullIndex) return;
  auto grow = [inflation](Aabb b) { return Aabb{b.lower - inflation, b.upper + inflation}; };
  if (!quack::rayCast(grow(rootBox_), origin, translation, maxFraction).hit) return;
  if (isLeaf(root_)) {
    visit(root_ & ~kLeafBit, maxFraction);
    return;
  }
  detail::TraversalStack stack;
  stack.push(root_);
  while (!stack.empty()) {
    const Node& node = nodes_[stack.pop()];
    AabbRayHit h0 = quack::rayCast(grow(node.childBox[0]), origin, translation, maxFraction);
    AabbRayHit h1 = quack::rayCast(grow(node.childBox[1]), origin, translation, maxFraction);
    // Visit the nearer child first so that a closest-hit callback clips the ray early.
    int first = (h1.hit && (!h0.hit || h1.fraction < h0.fraction)) ? 1 : 0;
    AabbRayHit hits[2] = {h0, h1};
    std::uint32_t deferred = kNullIndex;
    for (int k = 0; k < 2; ++k) {
      int s = k == 0 ? first : 1 - first;
      if (!hits[s].hit || hits[s].fraction > maxFraction) continue;
      std::uint32_t c = node.child[s];
      if (isLeaf(c)) {
        float clip = visit(c & ~kLeafBit, maxFraction);
        if (clip == 0.0f) return;
        if (clip > 0.0f && clip < maxFraction) maxFraction = clip;
      } else if (k == 0) {
        deferred = c;
      } else {
        stack.push(c);
      }
    }
    // The nearer internal child goes on top so it is popped first.
    if (deferred != kNullIndex) stack.push(deferred);
  }
}

template <class Visit>
void DynamicTree::visitInternalNodes(Visit&& visit) const {
  if (root_ == kNullIndex || isLeaf(root_)) return;
  struct Item {
    std::uint32_t node;
    int depth;
    Aabb box;
  };
  std::vector<Item> stack{{root_, 0, rootBox_}};
  while (!stack.empty()) {
    Item item = stack.back();
    stack.pop_back();
    visit(item.box, item.depth);
    const Node& n = nodes_[item.node];
    for (int i = 0; i < 2; ++i) {
      if (!isLeaf(n.child[i])) stack.push_back({n.child[i], item.depth + 1, n.childBox[i]});
    }
  }
}

}  // namespace quack
