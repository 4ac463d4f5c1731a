#pragma once
/// `DynamicTree3`: a dynamic bounding-volume hierarchy of 3D axis-aligned boxes, the 3D
/// counterpart of `DynamicTree` with the same interface (`Aabb3` and `Vec3` for `Aabb` and
/// `Vec2`).
///
/// Leaves are proxies (indices chosen by the caller, dense from 0); internal nodes have two
/// children and store *both children's boxes*, their parent and their height, so a descent
/// or a query reads one node per level. A node is 64 bytes and aligned to 64, one cache line;
/// a leaf stores only where it hangs (its parent node and slot). Nodes live in one array with
/// a free list threaded through it; there are no pointers. 68 bytes a proxy.
///
/// Insertion descends by the surface-area heuristic (the true surface area in 3D); every node
/// on the way back up is re-balanced by a rotation when its children's heights differ by more
/// than one. `rebuild()` throws the hierarchy away and builds it top-down with a binned
/// surface-area heuristic over the longest axis of the centroids, for bulk loads.
///
/// Learned from (read for understanding, not copied): E. Catto, "Dynamic Bounding Volume
/// Hierarchies", GDC 2019, and Box2D's b2DynamicTree (greedy SAH descent with a lower bound
/// on the cost below, AVL-style rotations); I. Wald, "On fast construction of SAH-based
/// BVHs", 2007 (binned SAH); and this library's 2D `DynamicTree`, of which this is a port.
///
/// Preconditions (checked by `QUACK_ASSERT`; `BroadPhase3` checks them for its users): boxes
/// are valid (finite, lower <= upper); a proxy is inserted at most once and removed or moved
/// only while present; proxy indices are below 2^31.

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

/// The 3D dynamic AABB tree (see the top of this file).
class DynamicTree3 {
 public:
  /// Adds proxy `proxy` with box `box` (world frame, metres). Grows the leaf table as needed.
  void insert(std::uint32_t proxy, Aabb3 box);
  /// Removes a present proxy.
  void remove(std::uint32_t proxy);
  /// Replaces the box of a present proxy (removes and re-inserts its leaf).
  void move(std::uint32_t proxy, Aabb3 box);
  /// True when `proxy` is in the tree.
  bool contains(std::uint32_t proxy) const noexcept {
    return proxy < leafParent_.size() && leafParent_[proxy] != kAbsent;
  }
  /// The box stored for a present proxy.
  Aabb3 box(std::uint32_t proxy) const;
  /// Number of proxies in the tree.
  std::uint32_t proxyCount() const noexcept { return leafCount_; }

  /// Calls `visit(proxy)` for every proxy whose box overlaps `query` (touching counts), in
  /// no particular order; `visit` returns false to stop the query.
  template <class Visit>
  void query(Aabb3 query, Visit&& visit) const;

  /// Casts the segment `origin + t * translation`, t in [0, maxFraction], against the boxes
  /// grown by `inflation` (half-extents, >= 0; zero for a ray, the moving box's half-extents
  /// for a box cast). Calls `visit(proxy, maxFraction)` for proxies whose grown box the
  /// segment reaches, nearer subtrees first; `visit` returns the new `maxFraction` (return
  /// the value passed in to go on unclipped, a smaller one to clip, 0 to stop).
  template <class Visit>
  void rayCast(Vec3 origin, Vec3 translation, float maxFraction, Vec3 inflation,
               Visit&& visit) const;

  /// Rebuilds the whole hierarchy with a binned surface-area heuristic (top down). Proxies
  /// and their boxes are unchanged; only the shape of the tree changes.
  void rebuild();

  /// Calls `visit(Aabb3 box, int depth)` for every internal node, the root at depth 0, with
  /// the node's box (the union of its children's). Leaves are not visited.
  template <class Visit>
  void visitInternalNodes(Visit&& visit) const;

  /// Height of the tree: 0 for empty or a single leaf, else 1 + the taller child.
  int height() const noexcept;
  /// Sum of the surface areas of all internal nodes divided by the root's: 0 when empty,
  /// lower is a tighter tree (the quality measure of Box2D and Box3D).
  float areaRatio() const noexcept;
  /// Bytes of memory held (capacity, not size).
  std::size_t bytesUsed() const noexcept;
  /// Checks every invariant: parent links, child boxes equal to the merge of their children,
  /// heights, leaf and node counts, the free list. The message names the first failure.
  /// (Balance is not an invariant: the SAH may hang a new leaf beside a whole subtree, and a
  /// rotation repairs a height difference of two only. The tests bound the height instead.)
  Status validate() const;

 private:
  static constexpr std::uint32_t kLeafBit = 0x80000000u;
  // Parent reference of a leaf not in the tree. Node indices stay below 2^30 (asserted), so
  // no real reference (node << 1 | slot) takes this value.
  static constexpr std::uint32_t kAbsent = 0xfffffffeu;

  struct alignas(64) Node {
    Aabb3 childBox[2];
    std::uint32_t child[2];  // node index, or proxy | kLeafBit
    std::uint32_t parent;    // (node << 1) | slot, kNullIndex at the root; free list link
    std::int32_t height;     // -1 when free
  };
  static_assert(sizeof(Node) == 64, "one node, one cache line");

  struct Built {
    std::uint32_t ref;
    Aabb3 box;
    std::int32_t height;
  };
  struct BuildItem {
    Aabb3 box;
    Vec3 centroid;
    std::uint32_t proxy;
  };

  static bool isLeaf(std::uint32_t ref) noexcept { return (ref & kLeafBit) != 0; }
  std::int32_t heightOf(std::uint32_t ref) const noexcept {
    return isLeaf(ref) ? 0 : nodes_[ref].height;
  }
  void setParent(std::uint32_t ref, std::uint32_t parentRef) noexcept;
  void link(std::uint32_t parentRef, std::uint32_t ref, Aabb3 box) noexcept;
  std::uint32_t allocateNode();
  void freeNode(std::uint32_t node) noexcept;
  void insertLeaf(std::uint32_t proxy, Aabb3 box);
  void removeLeaf(std::uint32_t proxy);
  void fixUpward(std::uint32_t node);
  std::uint32_t balance(std::uint32_t node);
  Built build(BuildItem* items, std::size_t count, std::uint32_t parentRef, int depth);

  std::vector<Node> nodes_;
  std::vector<std::uint32_t> leafParent_;  // per proxy: (node << 1) | slot, or kAbsent
  std::uint32_t root_ = kNullIndex;        // node index or proxy | kLeafBit
  Aabb3 rootBox_;
  std::uint32_t freeList_ = kNullIndex;
  std::uint32_t nodeCount_ = 0;
  std::uint32_t leafCount_ = 0;
};

template <class Visit>
void DynamicTree3::query(Aabb3 q, Visit&& visit) const {
  if (root_ == kNullIndex || !overlaps(rootBox_, q)) return;
  if (isLeaf(root_)) {
    visit(root_ & ~kLeafBit);
    return;
  }
  detail::NodeStack stack;
  stack.push(root_);
  while (!stack.empty()) {
    const Node& node = nodes_[stack.pop()];
    for (int s = 0; s < 2; ++s) {
      if (!overlaps(node.childBox[s], q)) continue;
      const std::uint32_t c = node.child[s];
      if (isLeaf(c)) {
        if (!visit(c & ~kLeafBit)) return;
      } else {
        stack.push(c);
      }
    }
  }
}

template <class Visit>
void DynamicTree3::rayCast(Vec3 origin, Vec3 translation, float maxFraction, Vec3 inflation,
                           Visit&& visit) const {
  if (root_ == kNullIndex) return;
  const detail::Ray3 ray(origin, translation);
  if (!detail::rayCast3(detail::grow3(rootBox_, inflation), ray, maxFraction).hit) return;
  if (isLeaf(root_)) {
    visit(root_ & ~kLeafBit, maxFraction);
    return;
  }
  detail::NodeStack stack;
  stack.push(root_);
  while (!stack.empty()) {
    const Node& node = nodes_[stack.pop()];
    const AabbRayHit hits[2] = {
        detail::rayCast3(detail::grow3(node.childBox[0], inflation), ray, maxFraction),
        detail::rayCast3(detail::grow3(node.childBox[1], inflation), ray, maxFraction)};
    // Visit the nearer child first so that a closest-hit callback clips the ray early.
    const int first =
        (hits[1].hit && (!hits[0].hit || hits[1].fraction < hits[0].fraction)) ? 1 : 0;
    std::uint32_t deferred = kNullIndex;
    for (int k = 0; k < 2; ++k) {
      const int s = k == 0 ? first : 1 - first;
      if (!hits[s].hit || hits[s].fraction > maxFraction) continue;
      const std::uint32_t c = node.child[s];
      if (isLeaf(c)) {
        const float clip = visit(c & ~kLeafBit, maxFraction);
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
void DynamicTree3::visitInternalNodes(Visit&& visit) const {
  if (root_ == kNullIndex || isLeaf(root_)) return;
  struct Item {
    std::uint32_t node;
    int depth;
    Aabb3 box;
  };
  std::vector<Item> stack{{root_, 0, rootBox_}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    visit(item.box, item.depth);
    const Node& n = nodes_[item.node];
    for (int i = 0; i < 2; ++i) {
      if (!isLeaf(n.child[i])) stack.push_back({n.child[i], item.depth + 1, n.childBox[i]});
    }
  }
}

}  // namespace quack
