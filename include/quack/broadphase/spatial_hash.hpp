#pragma once
/// `SpatialHash`: an unbounded uniform grid of square cells, stored in a hash table.
///
/// A proxy is listed in every cell its box touches. Cells hash into a power-of-two table of
/// buckets; two cells sharing a bucket only cost extra candidates, never wrong answers. A
/// query visits the cells of its box and reports a proxy only from the first cell the proxy
/// and the query share (the lowest x and y of both cell ranges), so each proxy is reported
/// once without any per-query "seen" marks, and queries are truly `const`. Boxes that would
/// cover more than `kMaxCellsPerProxy` cells are kept in a side list tested by every query,
/// so one huge box costs neither memory nor time per cell.
///
/// Pick the cell size near the typical box size (each box then touches about four cells).
/// Learned from (for understanding): Chipmunk's cpSpaceHash and M. Teschner et al.,
/// "Optimized spatial hashing for collision detection of deformable objects" (2003).
/// Preconditions as for `DynamicTree`; boxes within +-`kMaxCoordinate` of the origin so that
/// cell indices fit their integers (`BroadPhase` checks this).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "quack/broadphase/proxy.hpp"
#include "quack/core/assert.hpp"
#include "quack/core/result.hpp"
#include "quack/math/aabb.hpp"

namespace quack {

class SpatialHash {
 public:
  /// A box touching more cells than this goes to the side list instead.
  static constexpr std::int64_t kMaxCellsPerProxy = 64;

  /// `cellSize`: side of a cell in metres, > 0 and finite.
  explicit SpatialHash(float cellSize = 1.0f);

  /// Adds proxy `proxy` with box `box` (world frame, metres).
  void insert(std::uint32_t proxy, Aabb box);
  /// Removes a present proxy.
  void remove(std::uint32_t proxy);
  /// Replaces the box of a present proxy; touches the table only when its cells change.
  void move(std::uint32_t proxy, Aabb box);
  /// True when `proxy` is present.
  bool contains(std::uint32_t proxy) const noexcept {
    return proxy < dense_.size() && dense_[proxy] != kNullIndex;
  }
  /// The box stored for a present proxy.
  Aabb box(std::uint32_t proxy) const {
    QUACK_ASSERT(contains(proxy));
    return boxes_[proxy];
  }
  /// Number of proxies present.
  std::uint32_t proxyCount() const noexcept { return static_cast<std::uint32_t>(list_.size()); }
  /// Side of a cell, metres.
  float cellSize() const noexcept { return cellSize_; }

  /// Calls `visit(proxy)` for every proxy whose box overlaps `query`; false stops.
  template <class Visit>
  void query(Aabb query, Visit&& visit) const;

  /// As `DynamicTree::rayCast`; candidates are the proxies in the segment's bounding box.
  template <class Visit>
  void rayCast(Vec2 origin, Vec2 translation, float maxFraction, Vec2 inflation,
               Visit&& visit) const {
    const Aabb swept =
        sweep(Aabb{origin - inflation, origin + inflation}, maxFraction * translation);
    query(swept, [&](std::uint32_t proxy) {
      const Aabb grown{boxes_[proxy].lower - inflation, boxes_[proxy].upper + inflation};
      if (!quack::rayCast(grown, origin, translation, maxFraction).hit) return true;
      const float clip = visit(proxy, maxFraction);
      if (clip == 0.0f) return false;
      if (clip > 0.0f && clip < maxFraction) maxFraction = clip;
      return true;
    });
  }

  /// Re-sizes the table to the proxy count and re-hashes everything.
  void rebuild();
  /// Bytes of memory held (capacity, including every bucket's).
  std::size_t bytesUsed() const noexcept;
  /// Checks that every proxy is listed exactly in its cells' buckets (or the side list) and
  /// nowhere else.
  Status validate() const;

 private:
  // Cell indices are clamped to +-2^60: a query may be any finite box (a float can reach
  // 3.4e38, and x / cellSize more), and a float-to-integer cast out of range is undefined.
  // Clamping is monotonic, so boxes that overlap still share a cell.
  static constexpr float kCellLimit = 1152921504606846976.0f;  // 2^60
  struct Range {
    std::int64_t x0, y0, x1, y1;
    // The number of cells, saturating: each side is at most 2^61 + 1 cells, and the product
    // of two such would overflow.
    std::int64_t cells() const noexcept {
      const std::int64_t w = x1 - x0 + 1;
      const std::int64_t h = y1 - y0 + 1;
      return w > std::numeric_limits<std::int64_t>::max() / h
                 ? std::numeric_limits<std::int64_t>::max()
                 : w * h;
    }
  };
  std::int64_t cellOf(float x) const noexcept {
    const float c = std::floor(x * inverse_);
    if (c >= kCellLimit) return static_cast<std::int64_t>(kCellLimit);
    if (c <= -kCellLimit) return -static_cast<std::int64_t>(kCellLimit);
    return c == c ? static_cast<std::int64_t>(c) : 0;  // NaN (never from a valid box): 0
  }
  Range rangeOf(Aabb b) const noexcept {
    return {cellOf(b.lower.x), cellOf(b.lower.y), cellOf(b.upper.x), cellOf(b.upper.y)};
  }
  std::size_t bucketOf(std::int64_t x, std::int64_t y) const noexcept {
    std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull ^
                      static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full;
    h ^= h >> 31;
    return static_cast<std::size_t>(h) & (buckets_.size() - 1);
  }
  void addToCells(std::uint32_t proxy, Range r);
  void removeFromCells(std::uint32_t proxy, Range r);
  void resize(std::size_t bucketCount);

  float cellSize_;
  float inverse_;
  std::vector<Aabb> boxes_;                          // per proxy
  std::vector<std::uint32_t> dense_;                 // per proxy: index in list_, or null
  std::vector<std::uint32_t> list_;                  // the present proxies
  std::vector<std::vector<std::uint32_t>> buckets_;  // power-of-two count
  std::vector<std::uint32_t> oversized_;
};

template <class Visit>
void SpatialHash::query(Aabb q, Visit&& visit) const {
  for (std::uint32_t p : oversized_) {
    if (overlaps(boxes_[p], q) && !visit(p)) return;
  }
  if (buckets_.empty()) return;
  const Range r = rangeOf(q);
  // A query larger than the table would visit buckets many times over: scan instead. This
  // also bounds a huge query (+-1e19 m, a long ray's box) by the proxy count.
  if (r.cells() > static_cast<std::int64_t>(buckets_.size())) {
    for (std::uint32_t p : list_) {
      if (overlaps(boxes_[p], q) && rangeOf(boxes_[p]).cells() <= kMaxCellsPerProxy && !visit(p)) {
        return;
      }
    }
    return;
  }
  for (std::int64_t y = r.y0; y <= r.y1; ++y) {
    for (std::int64_t x = r.x0; x <= r.x1; ++x) {
      for (std::uint32_t p : buckets_[bucketOf(x, y)]) {
        const Aabb b = boxes_[p];
        if (!overlaps(b, q)) continue;
        // Report from the first shared cell only (this also skips other cells' proxies
        // that merely share the bucket).
        const std::int64_t cx = std::max(cellOf(b.lower.x), r.x0);
        const std::int64_t cy = std::max(cellOf(b.lower.y), r.y0);
        if (cx != x || cy != y) continue;
        if (!visit(p)) return;
      }
    }
  }
}

}  // namespace quack
