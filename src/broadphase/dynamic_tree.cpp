#include "quack/broadphase/dynamic_tree.hpp"

#include <algorithm>
#include <string>

namespace quack {

namespace {

// Number of bins of the binned SAH build: Wald (2007) finds 8-32 bins within a few percent
// of the full sweep; 16 is the usual middle.
constexpr int kBinCount = 16;
// Below this depth the SAH decides; past it the build splits at the object median, which
// bounds the depth of a degenerate input at 64 + log2(n).
constexpr int kMaxSahDepth = 64;
// Node indices are stored shifted left by one (with the child slot), and kAbsent must stay
// out of reach.
[[maybe_unused]] constexpr std::uint32_t kMaxNodes = 0x3fffffffu;

std::string at(const char* what, std::uint32_t index) {
  return std::string(what) + " " + std::to_string(index);
}

}  // namespace

Aabb DynamicTree::box(std::uint32_t proxy) const {
  QUACK_ASSERT(contains(proxy));
  std::uint32_t ref = leafParent_[proxy];
  if (ref == kNullIndex) return rootBox_;
  return nodes_[ref >> 1].childBox[ref & 1];
}

void DynamicTree::setParent(std::uint32_t ref, std::uint32_t parentRef) noexcept {
  if (isLeaf(ref)) {
    leafParent_[ref & ~kLeafBit] = parentRef;
  } else {
    nodes_[ref].parent = parentRef;
  }
}

void DynamicTree::link(std::uint32_t parentRef, std::uint32_t ref, Aabb b) noexcept {
  if (parentRef == kNullIndex) {
    root_ = ref;
    rootBox_ = b;
  } else {
    Node& p = nodes_[parentRef >> 1];
    p.child[parentRef & 1] = ref;
    p.childBox[parentRef & 1] = b;
  }
  setParent(ref, parentRef);
}

std::uint32_t DynamicTree::allocateNode() {
  std::uint32_t n;
  if (freeList_ != kNullIndex) {
    n = freeList_;
    freeList_ = nodes_[n].parent;
  } else {
    QUACK_ASSERT_MSG(nodes_.size() < kMaxNodes, "DynamicTree: too many nodes");
    n = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
  }
  nodes_[n].height = 1;
  nodes_[n].enlarged = 0;
  ++nodeCount_;
  return n;
}

void DynamicTree::freeNode(std::uint32_t node) noexcept {
  nodes_[node].parent = freeList_;
  nodes_[node].height = -1;
  freeList_ = node;
  --nodeCount_;
}

void DynamicTree::insert(std::uint32_t proxy, Aabb b) {
  QUACK_ASSERT(isValid(b));
  QUACK_ASSERT(proxy < kLeafBit);
  if (proxy >= leafParent_.size()) leafParent_.resize(std::size_t{proxy} + 1, kAbsent);
  QUACK_ASSERT_MSG(leafParent_[proxy] == kAbsent, "DynamicTree::insert: proxy already present");
  rebuildEnlarged();
  insertLeaf(proxy, b);
  ++leafCount_;
}

void DynamicTree::remove(std::uint32_t proxy) {
  QUACK_ASSERT_MSG(contains(proxy), "DynamicTree::remove: proxy not present");
  rebuildEnlarged();
  removeLeaf(proxy);
  --leafCount_;
}

void DynamicTree::move(std::uint32_t proxy, Aabb b) {
  QUACK_ASSERT(isValid(b));
  QUACK_ASSERT_MSG(contains(proxy), "DynamicTree::move: proxy not present");
  // The incremental operations rotate nodes, which would leave enlarged nodes under ones
  // that are not: the enlarged part is rebuilt first.
  rebuildEnlarged();
  removeLeaf(proxy);
  insertLeaf(proxy, b);
}

// Learned from Box2D v3's b2DynamicTree_EnlargeProxy and b2DynamicTree_Rebuild (read for
// understanding, not copied): moving a leaf costs a walk up while the boxes grow, and the
// re-insertions of a whole step are replaced by one top-down build over the enlarged part.
void DynamicTree::enlarge(std::uint32_t proxy, Aabb b) {
  QUACK_ASSERT(isValid(b));
  QUACK_ASSERT_MSG(contains(proxy), "DynamicTree::enlarge: proxy not present");
  const std::uint32_t ref = leafParent_[proxy];
  if (ref == kNullIndex) {
    rootBox_ = b;  // the only leaf: nothing above it
    return;
  }
  // The leaf's own box is exact (it may shrink or move); the boxes above only grow.
  nodes_[ref >> 1].childBox[ref & 1] = b;
  std::uint32_t node = ref >> 1;
  bool growing = true;
  while (node != kNullIndex) {
    Node& n = nodes_[node];
    // Above a node that was enlarged before, every node is marked already.
    if (!growing && n.enlarged != 0) break;
    n.enlarged = 1;
    const std::uint32_t pref = n.parent;
    if (growing) {
      Aabb& slot = pref == kNullIndex ? rootBox_ : nodes_[pref >> 1].childBox[pref & 1];
      const Aabb grown = merge(slot, b);
      growing = !(grown == slot);
      slot = grown;
    }
    node = pref == kNullIndex ? kNullIndex : pref >> 1;
  }
  enlarged_ = true;
}

void DynamicTree::rebuildEnlarged() {
  if (!enlarged_) return;
  enlarged_ = false;
  if (root_ == kNullIndex || isLeaf(root_) || nodes_[root_].enlarged == 0) return;
  // Every enlarged node is dropped; what hangs from one and is not enlarged itself (a leaf,
  // or a subtree no moved leaf is under) becomes an item of the build. Enlarged nodes form
  // a connected top of the tree, so a walk down from the root finds them all.
  std::vector<BuildItem>& items = rebuildItems_;
  std::vector<std::uint32_t>& stack = rebuildStack_;
  items.clear();
  stack.clear();
  stack.push_back(root_);
  while (!stack.empty()) {
    const std::uint32_t node = stack.back();
    stack.pop_back();
    const Node n = nodes_[node];
    freeNode(node);
    for (int s = 0; s < 2; ++s) {
      const std::uint32_t child = n.child[s];
      if (!isLeaf(child) && nodes_[child].enlarged != 0) {
        stack.push_back(child);
      } else {
        items.push_back({n.childBox[s], center(n.childBox[s]), child});
      }
    }
  }
  const Built top = buildMidpoint(items.data(), items.size(), kNullIndex, 0);
  link(kNullIndex, top.ref, top.box);
}

// The node made by a top-down build over its two built halves.
DynamicTree::Built DynamicTree::join(std::uint32_t node, const Built& left, const Built& right) {
  Node& n = nodes_[node];
  n.child[0] = left.ref;
  n.childBox[0] = left.box;
  n.child[1] = right.ref;
  n.childBox[1] = right.box;
  n.height = static_cast<std::int16_t>(1 + std::max(left.height, right.height));
  return {node, merge(left.box, right.box), n.height};
}

// Top-down build over items (leaves and kept subtrees) by the middle of the centres' range
// along its wider axis: two passes over the items a level, against the binned SAH's
// binning, a sweep over the bins and a partition. Where every centre falls on one side
// (equal centres), the split is at the object median.
DynamicTree::Built DynamicTree::buildMidpoint(BuildItem* items, std::size_t count,
                                              std::uint32_t parentRef, int depth) {
  if (count == 1) {
    setParent(items[0].ref, parentRef);
    return {items[0].ref, items[0].box, heightOf(items[0].ref)};
  }
  std::size_t mid = count / 2;
  if (count > 2) {
    Aabb centroids{items[0].centroid, items[0].centroid};
    for (std::size_t i = 1; i < count; ++i)
      centroids = merge(centroids, items[i].centroid);
    const Vec2 extent = centroids.upper - centroids.lower;
    const bool alongX = extent.x >= extent.y;
    const float pivot = alongX ? 0.5f * (centroids.lower.x + centroids.upper.x)
                               : 0.5f * (centroids.lower.y + centroids.upper.y);
    BuildItem* m = alongX
                       ? std::partition(items, items + count,
                                        [&](const BuildItem& it) { return it.centroid.x < pivot; })
                       : std::partition(items, items + count,
                                        [&](const BuildItem& it) { return it.centroid.y < pivot; });
    mid = static_cast<std::size_t>(m - items);
    if (mid == 0 || mid == count || depth >= kMaxSahDepth) {
      mid = count / 2;
      std::nth_element(items, items + mid, items + count,
                       [&](const BuildItem& x, const BuildItem& y) {
                         return alongX ? x.centroid.x < y.centroid.x : x.centroid.y < y.centroid.y;
                       });
    }
  }
  const std::uint32_t node = allocateNode();
  nodes_[node].parent = parentRef;
  const Built left = buildMidpoint(items, mid, node << 1, depth + 1);
  const Built right = buildMidpoint(items + mid, count - mid, (node << 1) | 1u, depth + 1);
  return join(node, left, right);
}

void DynamicTree::insertLeaf(std::uint32_t proxy, Aabb b) {
  const std::uint32_t leaf = proxy | kLeafBit;
  if (root_ == kNullIndex) {
    link(kNullIndex, leaf, b);
    return;
  }
  // Greedy descent by the surface-area heuristic: at each node compare the cost of making the
  // new leaf the node's sibling with a lower bound of the cost of descending into a child.
  std::uint32_t siblingRef = kNullIndex;
  std::uint32_t sibling = root_;
  Aabb siblingBox = rootBox_;
  while (!isLeaf(sibling)) {
    const Node& n = nodes_[sibling];
    const float area = perimeter(siblingBox);
    const float combined = perimeter(merge(siblingBox, b));
    const float costHere = 2.0f * combined;
    const float inheritance = 2.0f * (combined - area);
    float cost[2];
    for (int s = 0; s < 2; ++s) {
      float grown = perimeter(merge(n.childBox[s], b));
      if (!isLeaf(n.child[s])) grown -= perimeter(n.childBox[s]);
      cost[s] = grown + inheritance;
    }
    if (costHere < cost[0] && costHere < cost[1]) break;
    const int s = cost[0] <= cost[1] ? 0 : 1;
    siblingRef = (sibling << 1) | static_cast<std::uint32_t>(s);
    siblingBox = n.childBox[s];
    sibling = n.child[s];
  }

  const std::uint32_t parent = allocateNode();
  Node& p = nodes_[parent];
  p.child[0] = sibling;
  p.childBox[0] = siblingBox;
  p.child[1] = leaf;
  p.childBox[1] = b;
  p.height = static_cast<std::int16_t>(heightOf(sibling) + 1);
  setParent(sibling, parent << 1);
  leafParent_[proxy] = (parent << 1) | 1u;
  link(siblingRef, parent, merge(siblingBox, b));
  if (siblingRef != kNullIndex) fixUpward(siblingRef >> 1);
}

void DynamicTree::removeLeaf(std::uint32_t proxy) {
  const std::uint32_t ref = leafParent_[proxy];
  leafParent_[proxy] = kAbsent;
  if (ref == kNullIndex) {
    root_ = kNullIndex;
    rootBox_ = {};
    return;
  }
  const std::uint32_t parent = ref >> 1;
  const std::uint32_t other = 1u - (ref & 1u);
  const std::uint32_t sibling = nodes_[parent].child[other];
  const Aabb siblingBox = nodes_[parent].childBox[other];
  const std::uint32_t grandRef = nodes_[parent].parent;
  link(grandRef, sibling, siblingBox);
  freeNode(parent);
  if (grandRef != kNullIndex) fixUpward(grandRef >> 1);
}

void DynamicTree::fixUpward(std::uint32_t node) {
  while (node != kNullIndex) {
    const std::uint32_t before = node;
    node = balance(node);
    Node& n = nodes_[node];
    const std::int32_t h = 1 + std::max(heightOf(n.child[0]), heightOf(n.child[1]));
    const Aabb b = merge(n.childBox[0], n.childBox[1]);
    const std::uint32_t pref = n.parent;
    Aabb& slot = pref == kNullIndex ? rootBox_ : nodes_[pref >> 1].childBox[pref & 1];
    // Nothing above can change when this node kept its height and box and did not rotate.
    const bool unchanged = before == node && h == n.height && slot == b;
    n.height = static_cast<std::int16_t>(h);
    slot = b;
    if (unchanged || pref == kNullIndex) return;
    node = pref >> 1;
  }
}

std::uint32_t DynamicTree::balance(std::uint32_t a) {
  Node& A = nodes_[a];
  const std::int32_t diff = heightOf(A.child[1]) - heightOf(A.child[0]);
  if (diff <= 1 && diff >= -1) return a;
  // Lift the taller child C above A; C keeps its taller child and hands its shorter one to
  // A, which takes C's old slot.
  const int tall = diff > 1 ? 1 : 0;
  const std::uint32_t c = A.child[tall];
  QUACK_ASSERT(!isLeaf(c));
  Node& C = nodes_[c];
  const int keep = heightOf(C.child[0]) > heightOf(C.child[1]) ? 0 : 1;
  const int give = 1 - keep;
  const std::uint32_t handed = C.child[give];
  const Aabb handedBox = C.childBox[give];

  const std::uint32_t aParent = A.parent;
  C.parent = aParent;
  if (aParent == kNullIndex) {
    root_ = c;
  } else {
    nodes_[aParent >> 1].child[aParent & 1] = c;
  }
  A.child[tall] = handed;
  A.childBox[tall] = handedBox;
  setParent(handed, (a << 1) | static_cast<std::uint32_t>(tall));
  A.height = static_cast<std::int16_t>(1 + std::max(heightOf(A.child[0]), heightOf(A.child[1])));
  C.child[give] = a;
  C.childBox[give] = merge(A.childBox[0], A.childBox[1]);
  A.parent = (c << 1) | static_cast<std::uint32_t>(give);
  return c;
}

void DynamicTree::rebuild() {
  std::vector<BuildItem> items;
  items.reserve(leafCount_);
  for (std::uint32_t p = 0; p < leafParent_.size(); ++p) {
    if (leafParent_[p] == kAbsent) continue;
    Aabb b = box(p);
    items.push_back({b, center(b), p | kLeafBit});
  }
  // Release the capacity left over from incremental growth: a bulk load ends up exact.
  std::vector<Node>().swap(nodes_);
  leafParent_.shrink_to_fit();
  freeList_ = kNullIndex;
  nodeCount_ = 0;
  root_ = kNullIndex;
  rootBox_ = {};
  enlarged_ = false;
  if (items.empty()) return;
  nodes_.reserve(items.size() - 1);
  Built top = build(items.data(), items.size(), kNullIndex, 0);
  link(kNullIndex, top.ref, top.box);
}

DynamicTree::Built DynamicTree::build(BuildItem* items, std::size_t count, std::uint32_t parentRef,
                                      int depth) {
  if (count == 1) {
    setParent(items[0].ref, parentRef);
    return {items[0].ref, items[0].box, heightOf(items[0].ref)};
  }
  Aabb centroids{items[0].centroid, items[0].centroid};
  for (std::size_t i = 1; i < count; ++i)
    centroids = merge(centroids, items[i].centroid);
  const Vec2 extent = centroids.upper - centroids.lower;
  const int axis = extent.x >= extent.y ? 0 : 1;
  auto coord = [axis](Vec2 v) { return axis == 0 ? v.x : v.y; };
  const float lo = coord(centroids.lower);
  const float width = coord(extent);

  std::size_t mid = count / 2;
  bool split = false;
  if (width > 0.0f && depth < kMaxSahDepth) {
    Aabb binBox[kBinCount];
    std::size_t binCount[kBinCount] = {};
    const float scale = static_cast<float>(kBinCount) / width;
    auto binOf = [&](const BuildItem& it) {
      int b = static_cast<int>((coord(it.centroid) - lo) * scale);
      return std::clamp(b, 0, kBinCount - 1);
    };
    for (std::size_t i = 0; i < count; ++i) {
      const int b = binOf(items[i]);
      binBox[b] = binCount[b] == 0 ? items[i].box : merge(binBox[b], items[i].box);
      ++binCount[b];
    }
    // Cost of splitting after bin k: perimeter(left) * |left| + perimeter(right) * |right|.
    float rightCost[kBinCount] = {};
    Aabb acc{};
    std::size_t n = 0;
    for (int k = kBinCount - 1; k > 0; --k) {
      if (binCount[k] > 0) acc = n == 0 ? binBox[k] : merge(acc, binBox[k]);
      n += binCount[k];
      rightCost[k] = n == 0 ? 0.0f : perimeter(acc) * static_cast<float>(n);
    }
    float best = 0.0f;
    int bestK = -1;
    n = 0;
    for (int k = 0; k < kBinCount - 1; ++k) {
      if (binCount[k] > 0) acc = n == 0 ? binBox[k] : merge(acc, binBox[k]);
      n += binCount[k];
      if (n == 0 || n == count) continue;
      const float cost = perimeter(acc) * static_cast<float>(n) + rightCost[k + 1];
      if (bestK < 0 || cost < best) {
        best = cost;
        bestK = k;
      }
    }
    if (bestK >= 0) {
      BuildItem* m = std::partition(items, items + count,
                                    [&](const BuildItem& it) { return binOf(it) <= bestK; });
      mid = static_cast<std::size_t>(m - items);
      split = mid > 0 && mid < count;
    }
  }
  if (!split) {
    mid = count / 2;
    std::nth_element(items, items + mid, items + count,
                     [&](const BuildItem& x, const BuildItem& y) {
                       return coord(x.centroid) < coord(y.centroid);
                     });
  }

  const std::uint32_t node = allocateNode();
  nodes_[node].parent = parentRef;
  const Built left = build(items, mid, node << 1, depth + 1);
  const Built right = build(items + mid, count - mid, (node << 1) | 1u, depth + 1);
  return join(node, left, right);
}

int DynamicTree::height() const noexcept {
  return root_ == kNullIndex ? 0 : heightOf(root_);
}

float DynamicTree::areaRatio() const noexcept {
  if (root_ == kNullIndex || isLeaf(root_)) return 0.0f;
  const float rootArea = perimeter(rootBox_);
  if (rootArea <= 0.0f) return 0.0f;
  // Every internal node but the root has its box in its parent's slot; the root's is rootBox_.
  float total = rootArea;
  for (const Node& n : nodes_) {
    if (n.height < 0) continue;
    for (int s = 0; s < 2; ++s) {
      if (!isLeaf(n.child[s])) total += perimeter(n.childBox[s]);
    }
  }
  return total / rootArea;
}

std::size_t DynamicTree::bytesUsed() const noexcept {
  return nodes_.capacity() * sizeof(Node) + leafParent_.capacity() * sizeof(std::uint32_t);
}

Status DynamicTree::validate() const {
  std::uint32_t freeCount = 0;
  for (std::uint32_t f = freeList_; f != kNullIndex; f = nodes_[f].parent) {
    if (f >= nodes_.size()) return fail(at("free list points outside the node array:", f));
    if (nodes_[f].height != -1) return fail(at("free-list node is not marked free:", f));
    if (++freeCount > nodes_.size()) return fail("free list has a cycle");
  }
  if (freeCount + nodeCount_ != nodes_.size()) {
    return fail("free nodes + live nodes != node array size");
  }
  std::uint32_t leaves = 0;
  for (std::uint32_t p = 0; p < leafParent_.size(); ++p) {
    if (leafParent_[p] != kAbsent) ++leaves;
  }
  if (leaves != leafCount_) return fail("leaf count does not match the leaf table");
  if (root_ == kNullIndex) {
    if (leafCount_ != 0 || nodeCount_ != 0) return fail("empty root but proxies present");
    return {};
  }
  if (leafCount_ == 0) return fail("root present but no proxies");
  if (nodeCount_ + 1 != leafCount_) return fail("internal nodes != leaves - 1");

  struct Item {
    std::uint32_t ref;
    std::uint32_t parentRef;
    Aabb box;
  };
  std::vector<Item> stack{{root_, kNullIndex, rootBox_}};
  std::uint32_t seenNodes = 0;
  std::uint32_t seenLeaves = 0;
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    if (!isValid(it.box)) return fail("a stored box is not valid (NaN or inverted)");
    if (isLeaf(it.ref)) {
      const std::uint32_t p = it.ref & ~kLeafBit;
      if (p >= leafParent_.size()) return fail(at("leaf refers to unknown proxy", p));
      if (leafParent_[p] != it.parentRef) return fail(at("wrong parent link of proxy", p));
      ++seenLeaves;
      continue;
    }
    if (it.ref >= nodes_.size()) return fail(at("child refers outside the node array:", it.ref));
    const Node& n = nodes_[it.ref];
    if (n.height < 1) return fail(at("free or leaf-height node reachable:", it.ref));
    if (n.parent != it.parentRef) return fail(at("wrong parent link of node", it.ref));
    if (++seenNodes > nodeCount_) return fail("more reachable nodes than live nodes (cycle?)");
    if (n.height != 1 + std::max(heightOf(n.child[0]), heightOf(n.child[1]))) {
      return fail(at("wrong height at node", it.ref));
    }
    const Aabb merged = merge(n.childBox[0], n.childBox[1]);
    if (n.enlarged != 0) {
      if (!quack::contains(it.box, merged)) {
        return fail(at("enlarged box does not hold its children at node", it.ref));
      }
      if (!enlarged_) return fail(at("enlarged node in a tree not marked so:", it.ref));
      if (n.parent != kNullIndex && nodes_[n.parent >> 1].enlarged == 0) {
        return fail(at("enlarged node under one that is not:", it.ref));
      }
    } else if (!(merge(n.childBox[0], n.childBox[1]) == it.box)) {
      return fail(at("box is not the merge of its children at node", it.ref));
    }
    for (std::uint32_t s = 0; s < 2; ++s) {
      stack.push_back({n.child[s], (it.ref << 1) | s, n.childBox[s]});
    }
  }
  if (seenNodes != nodeCount_) return fail("unreachable live nodes");
  if (seenLeaves != leafCount_) return fail("unreachable leaves");
  return {};
}

}  // namespace quack
