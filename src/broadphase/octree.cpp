#include "quack/broadphase/octree.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace quack {

namespace {

// Loose boxes extend this many cell sides past the cell: 0.5 for the half-width of a box as
// large as the cell, plus 0.125 of slack for float rounding of box centres.
constexpr double kLooseness = 0.625;
// The slack (s / 8) must exceed the rounding of a centre coordinate, a few ulps of the
// largest coordinate, so a cell is never smaller than this many ulps.
constexpr float kMinCellInUlps = 64.0f;
// Cell indices are offset so that they are never negative and every cell has the single
// level-kTopLevel cell 0 as an ancestor, with the parent of index i always i >> 1: at level L
// the index is floor((x + O) / s) with O = (4/3) * smallestCellSize * 2^61 (as in the
// quadtree). The offset is a third of a cell off every level's grid, so the origin, where
// scenes tend to sit, is never on a cell boundary of any level: with O = 0 the cells on
// either side of x = 0 would share only the top cell, and every query would walk a 60-cell
// chain. Valid while |x| < smallestCellSize * 2^61 / 3, far beyond kMaxCoordinate.
constexpr std::int32_t kTopLevel = 62;

// O / s at level L = (2^(63 - L)) / 3: its integer part...
std::int64_t offsetCells(std::int32_t level) noexcept {
  return static_cast<std::int64_t>((std::uint64_t{1} << (63 - level)) / 3u);
}
// ...and its fractional part (1/3 or 2/3).
double offsetPhase(std::int32_t level) noexcept {
  return static_cast<double>((std::uint64_t{1} << (63 - level)) % 3u) / 3.0;
}

int slotOf(std::int64_t x, std::int64_t y, std::int64_t z) noexcept {
  return static_cast<int>(((z & 1) << 2) | ((y & 1) << 1) | (x & 1));
}

float maxAbs(Aabb3 b) noexcept {
  const Vec3 lo = absv(b.lower);
  const Vec3 hi = absv(b.upper);
  return maxf(maxf(maxf(lo.x, hi.x), maxf(lo.y, hi.y)), maxf(lo.z, hi.z));
}

}  // namespace

Octree::Octree(float smallestCellSize) : base_(smallestCellSize) {
  static_assert(kTopCellLevel == kTopLevel, "octree.hpp and octree.cpp agree on the top level");
  for (std::int32_t level = 1; level <= kTopLevel; ++level)
    childSide_[level] = std::ldexp(smallestCellSize, level - 1);
  QUACK_ASSERT(smallestCellSize > 0.0f && std::isfinite(smallestCellSize));
}

Octree::Key Octree::keyOf(Aabb3 b) const noexcept {
  const Vec3 size = b.upper - b.lower;
  const float w = maxf(maxf(size.x, size.y), size.z);
  const double w64 = static_cast<double>(w);
  const double minSize =
      static_cast<double>(kMinCellInUlps * maxAbs(b) * std::numeric_limits<float>::epsilon());
  std::int32_t level = 0;
  double s = static_cast<double>(base_);
  while ((s < w64 || s < minSize) && level < kTopLevel - 1) {
    s *= 2.0;
    ++level;
  }
  const Vec3 c = center(b);
  const double phase = offsetPhase(level);
  const std::int64_t off = offsetCells(level);
  auto index = [&](float v) {
    return static_cast<std::int64_t>(std::floor(static_cast<double>(v) / s + phase)) + off;
  };
  return {index(c.x), index(c.y), index(c.z), level};
}

Aabb3 Octree::looseBoxOf(Key k) const noexcept {
  if (k.level >= kTopLevel) {
    const float big = std::numeric_limits<float>::max();
    return {{-big, -big, -big}, {big, big, big}};
  }
  const double s = std::ldexp(static_cast<double>(base_), k.level);
  const double phase = offsetPhase(k.level);
  const std::int64_t off = offsetCells(k.level);
  auto lower = [&](std::int64_t i) {
    const double x = static_cast<double>(i - off) - phase;
    return static_cast<float>(x * s - kLooseness * s);
  };
  auto upper = [&](std::int64_t i) {
    const double x = static_cast<double>(i - off) - phase;
    return static_cast<float>((x + 1.0) * s + kLooseness * s);
  };
  return {{lower(k.x), lower(k.y), lower(k.z)}, {upper(k.x), upper(k.y), upper(k.z)}};
}

std::uint32_t Octree::newCell(Key k, std::uint32_t parent) {
  std::uint32_t c;
  if (freeCells_ != kNullIndex) {
    c = freeCells_;
    freeCells_ = cells_[c].parent;
  } else {
    c = static_cast<std::uint32_t>(cells_.size());
    cells_.push_back({});
  }
  Cell& cell = cells_[c];
  cell.loose = looseBoxOf(k);
  cell.x = k.x;
  cell.y = k.y;
  cell.z = k.z;
  cell.level = k.level;
  cell.parent = parent;
  for (std::uint32_t& ch : cell.child)
    ch = kNullIndex;
  cell.childMask = 0;
  cell.firstItem = kNullIndex;
  ++cellCount_;
  return c;
}

void Octree::freeCell(std::uint32_t c) noexcept {
  cells_[c].level = -1;
  cells_[c].parent = freeCells_;
  freeCells_ = c;
  --cellCount_;
}

std::uint32_t Octree::findOrCreateCell(Key k) {
  if (root_ == kNullIndex) {
    root_ = newCell(k, kNullIndex);
    return root_;
  }
  // Grow upwards until the root is an ancestor of (or is) the target cell.
  for (;;) {
    const Cell& r = cells_[root_];
    if (r.level >= k.level) {
      const int shift = r.level - k.level;
      if ((k.x >> shift) == r.x && (k.y >> shift) == r.y && (k.z >> shift) == r.z) break;
    }
    QUACK_ASSERT_MSG(r.level < kTopLevel, "Octree: coordinates out of range");
    const Key up{r.x >> 1, r.y >> 1, r.z >> 1, r.level + 1};
    const int slot = slotOf(r.x, r.y, r.z);
    const std::uint32_t old = root_;
    root_ = newCell(up, kNullIndex);
    cells_[root_].child[slot] = old;
    cells_[root_].childMask = static_cast<std::uint8_t>(1u << slot);
    cells_[old].parent = root_;
  }
  // Walk down, creating the missing cells.
  std::uint32_t c = root_;
  while (cells_[c].level > k.level) {
    const int shift = cells_[c].level - 1 - k.level;
    const std::int64_t cx = k.x >> shift;
    const std::int64_t cy = k.y >> shift;
    const std::int64_t cz = k.z >> shift;
    const int slot = slotOf(cx, cy, cz);
    std::uint32_t next = cells_[c].child[slot];
    if (next == kNullIndex) {
      next = newCell({cx, cy, cz, cells_[c].level - 1}, c);
      cells_[c].child[slot] = next;
      cells_[c].childMask = static_cast<std::uint8_t>(cells_[c].childMask | (1u << slot));
    }
    c = next;
  }
  return c;
}

void Octree::link(std::uint32_t proxy, std::uint32_t cell) noexcept {
  Item& it = items_[proxy];
  it.cell = cell;
  it.prev = kNullIndex;
  it.next = cells_[cell].firstItem;
  if (it.next != kNullIndex) items_[it.next].prev = proxy;
  cells_[cell].firstItem = proxy;
}

void Octree::unlink(std::uint32_t proxy) noexcept {
  Item& it = items_[proxy];
  if (it.prev != kNullIndex) {
    items_[it.prev].next = it.next;
  } else {
    cells_[it.cell].firstItem = it.next;
  }
  if (it.next != kNullIndex) items_[it.next].prev = it.prev;
  it.cell = kNullIndex;
  it.next = kNullIndex;
  it.prev = kNullIndex;
}

void Octree::prune(std::uint32_t c) noexcept {
  auto isEmptyLeaf = [this](std::uint32_t i) {
    const Cell& cell = cells_[i];
    return cell.firstItem == kNullIndex &&
           std::all_of(std::begin(cell.child), std::end(cell.child),
                       [](std::uint32_t ch) { return ch == kNullIndex; });
  };
  while (c != kNullIndex && isEmptyLeaf(c)) {
    const std::uint32_t parent = cells_[c].parent;
    if (parent == kNullIndex) {
      root_ = kNullIndex;
    } else {
      const int slot = slotOf(cells_[c].x, cells_[c].y, cells_[c].z);
      cells_[parent].child[slot] = kNullIndex;
      cells_[parent].childMask =
          static_cast<std::uint8_t>(cells_[parent].childMask & ~(1u << slot));
    }
    freeCell(c);
    c = parent;
  }
  // A root with no boxes and one child is just a longer path to that child.
  while (root_ != kNullIndex && cells_[root_].firstItem == kNullIndex) {
    std::uint32_t only = kNullIndex;
    int children = 0;
    for (std::uint32_t ch : cells_[root_].child) {
      if (ch != kNullIndex) {
        only = ch;
        ++children;
      }
    }
    if (children != 1) break;
    freeCell(root_);
    root_ = only;
    cells_[only].parent = kNullIndex;
  }
}

void Octree::insert(std::uint32_t proxy, Aabb3 b) {
  QUACK_ASSERT(isValid(b));
  QUACK_ASSERT(proxy != kNullIndex);
  if (proxy >= items_.size()) {
    items_.resize(std::size_t{proxy} + 1, Item{{}, kNullIndex, kNullIndex, kNullIndex});
  }
  QUACK_ASSERT_MSG(items_[proxy].cell == kNullIndex, "Octree::insert: proxy already present");
  items_[proxy].box = b;
  link(proxy, findOrCreateCell(keyOf(b)));
  ++count_;
}

void Octree::remove(std::uint32_t proxy) {
  QUACK_ASSERT_MSG(contains(proxy), "Octree::remove: proxy not present");
  const std::uint32_t cell = items_[proxy].cell;
  unlink(proxy);
  prune(cell);
  --count_;
}

void Octree::move(std::uint32_t proxy, Aabb3 b) {
  QUACK_ASSERT(isValid(b));
  QUACK_ASSERT_MSG(contains(proxy), "Octree::move: proxy not present");
  const Key k = keyOf(b);
  const std::uint32_t cell = items_[proxy].cell;
  items_[proxy].box = b;
  const Cell& c = cells_[cell];
  if (c.x == k.x && c.y == k.y && c.z == k.z && c.level == k.level) return;
  unlink(proxy);
  prune(cell);
  link(proxy, findOrCreateCell(k));
}

void Octree::rebuild() {
  std::vector<Item> old;
  old.swap(items_);
  cells_.clear();
  cells_.shrink_to_fit();
  root_ = kNullIndex;
  freeCells_ = kNullIndex;
  cellCount_ = 0;
  count_ = 0;
  items_.assign(old.size(), Item{{}, kNullIndex, kNullIndex, kNullIndex});
  for (std::uint32_t p = 0; p < old.size(); ++p) {
    if (old[p].cell != kNullIndex) insert(p, old[p].box);
  }
}

int Octree::depth() const {
  if (root_ == kNullIndex) return 0;
  int deepest = 0;
  std::vector<std::pair<std::uint32_t, int>> stack{{root_, 1}};
  while (!stack.empty()) {
    const auto [c, d] = stack.back();
    stack.pop_back();
    deepest = std::max(deepest, d);
    for (std::uint32_t ch : cells_[c].child) {
      if (ch != kNullIndex) stack.push_back({ch, d + 1});
    }
  }
  return deepest;
}

std::size_t Octree::bytesUsed() const noexcept {
  return cells_.capacity() * sizeof(Cell) + items_.capacity() * sizeof(Item);
}

Status Octree::validate() const {
  std::uint32_t freeCount = 0;
  for (std::uint32_t f = freeCells_; f != kNullIndex; f = cells_[f].parent) {
    if (f >= cells_.size() || cells_[f].level != -1) return fail("free list is broken");
    if (++freeCount > cells_.size()) return fail("free list has a cycle");
  }
  if (freeCount + cellCount_ != cells_.size()) return fail("free + live cells != cell array");
  std::uint32_t present = 0;
  for (const Item& it : items_)
    present += it.cell != kNullIndex ? 1 : 0;
  if (present != count_) return fail("item count does not match the item table");
  if (root_ == kNullIndex) {
    if (count_ != 0 || cellCount_ != 0) return fail("no root but cells or boxes present");
    return {};
  }
  if (cells_[root_].parent != kNullIndex) return fail("root has a parent");
  std::uint32_t seenCells = 0;
  std::uint32_t seenItems = 0;
  std::vector<std::uint32_t> stack{root_};
  while (!stack.empty()) {
    const std::uint32_t ci = stack.back();
    stack.pop_back();
    if (ci >= cells_.size()) return fail("cell index outside the cell array");
    const Cell& c = cells_[ci];
    const std::string where = " in cell " + std::to_string(ci);
    if (c.level < 0) return fail("free cell reachable" + where);
    if (++seenCells > cellCount_) return fail("more reachable cells than live cells (cycle?)");
    if (!(c.loose == looseBoxOf({c.x, c.y, c.z, c.level}))) return fail("wrong loose box" + where);
    bool hasChild = false;
    for (int s = 0; s < 8; ++s) {
      const std::uint32_t ch = c.child[s];
      if (ch == kNullIndex) continue;
      hasChild = true;
      if (ch >= cells_.size()) return fail("child index outside the cell array" + where);
      const Cell& k = cells_[ch];
      if (k.parent != ci) return fail("wrong parent link" + where);
      if (k.level != c.level - 1 || (k.x >> 1) != c.x || (k.y >> 1) != c.y || (k.z >> 1) != c.z ||
          slotOf(k.x, k.y, k.z) != s) {
        return fail("child coordinates do not nest" + where);
      }
      if (!quack::contains(c.loose, k.loose)) return fail("child's loose box sticks out" + where);
      stack.push_back(ch);
    }
    if (!hasChild && c.firstItem == kNullIndex) return fail("empty leaf cell" + where);
    for (int s = 0; s < 8; ++s) {
      if (((c.childMask >> s) & 1u) != (c.child[s] != kNullIndex ? 1u : 0u))
        return fail("child mask disagrees with the children" + where);
    }
    std::uint32_t prev = kNullIndex;
    for (std::uint32_t i = c.firstItem; i != kNullIndex; i = items_[i].next) {
      if (i >= items_.size()) return fail("item index outside the item table" + where);
      const Item& it = items_[i];
      if (it.cell != ci || it.prev != prev) return fail("broken item list" + where);
      if (++seenItems > count_) return fail("more listed boxes than proxies (cycle?)");
      if (!isValid(it.box)) return fail("a stored box is not valid" + where);
      if (!quack::contains(c.loose, it.box)) return fail("box outside its loose cell" + where);
      const Key k = keyOf(it.box);
      if (k.x != c.x || k.y != c.y || k.z != c.z || k.level != c.level)
        return fail("box in the wrong cell" + where);
      prev = i;
    }
  }
  if (seenCells != cellCount_) return fail("unreachable live cells");
  if (seenItems != count_) return fail("unreachable boxes");
  // The root may hold one child and no boxes only transiently: prune() hands it over.
  const Cell& r = cells_[root_];
  if (r.firstItem == kNullIndex &&
      std::count_if(std::begin(r.child), std::end(r.child),
                    [](std::uint32_t ch) { return ch != kNullIndex; }) == 1) {
    return fail("root with one child and no boxes");
  }
  return {};
}

}  // namespace quack
