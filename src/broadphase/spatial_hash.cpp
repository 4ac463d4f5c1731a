#include "quack/broadphase/spatial_hash.hpp"

#include <algorithm>
#include <string>

namespace quack {

namespace {
// Buckets per proxy: each box of about the cell size touches about four cells, so four
// buckets per proxy keep the load near one entry per bucket.
constexpr std::size_t kBucketsPerProxy = 4;
constexpr std::size_t kMinBuckets = 64;
}  // namespace

SpatialHash::SpatialHash(float cellSize) : cellSize_(cellSize), inverse_(1.0f / cellSize) {
  QUACK_ASSERT(cellSize > 0.0f && isFinite(cellSize));
}

void SpatialHash::insert(std::uint32_t proxy, Aabb b) {
  QUACK_ASSERT(isValid(b));
  QUACK_ASSERT(proxy != kNullIndex);
  if (proxy >= dense_.size()) {
    dense_.resize(std::size_t{proxy} + 1, kNullIndex);
    boxes_.resize(std::size_t{proxy} + 1);
  }
  QUACK_ASSERT_MSG(dense_[proxy] == kNullIndex, "SpatialHash::insert: proxy already present");
  dense_[proxy] = static_cast<std::uint32_t>(list_.size());
  list_.push_back(proxy);
  boxes_[proxy] = b;
  if (list_.size() * kBucketsPerProxy > buckets_.size()) {
    resize(std::max(kMinBuckets, buckets_.size() * 2));  // re-hashes proxy too
  } else {
    addToCells(proxy, rangeOf(b));
  }
}

void SpatialHash::remove(std::uint32_t proxy) {
  QUACK_ASSERT_MSG(contains(proxy), "SpatialHash::remove: proxy not present");
  removeFromCells(proxy, rangeOf(boxes_[proxy]));
  const std::uint32_t i = dense_[proxy];
  list_[i] = list_.back();
  dense_[list_[i]] = i;
  list_.pop_back();
  dense_[proxy] = kNullIndex;
}

void SpatialHash::move(std::uint32_t proxy, Aabb b) {
  QUACK_ASSERT(isValid(b));
  QUACK_ASSERT_MSG(contains(proxy), "SpatialHash::move: proxy not present");
  const Range before = rangeOf(boxes_[proxy]);
  const Range after = rangeOf(b);
  boxes_[proxy] = b;
  if (before.x0 == after.x0 && before.y0 == after.y0 && before.x1 == after.x1 &&
      before.y1 == after.y1) {
    return;
  }
  removeFromCells(proxy, before);
  addToCells(proxy, after);
}

void SpatialHash::addToCells(std::uint32_t proxy, Range r) {
  if (r.cells() > kMaxCellsPerProxy) {
    oversized_.push_back(proxy);
    return;
  }
  for (std::int64_t y = r.y0; y <= r.y1; ++y) {
    for (std::int64_t x = r.x0; x <= r.x1; ++x) {
      std::vector<std::uint32_t>& bucket = buckets_[bucketOf(x, y)];
      // Two cells of one box may share a bucket; listing the proxy once keeps queries exact.
      if (std::find(bucket.begin(), bucket.end(), proxy) == bucket.end()) bucket.push_back(proxy);
    }
  }
}

void SpatialHash::removeFromCells(std::uint32_t proxy, Range r) {
  if (r.cells() > kMaxCellsPerProxy) {
    auto it = std::find(oversized_.begin(), oversized_.end(), proxy);
    QUACK_ASSERT(it != oversized_.end());
    *it = oversized_.back();
    oversized_.pop_back();
    return;
  }
  for (std::int64_t y = r.y0; y <= r.y1; ++y) {
    for (std::int64_t x = r.x0; x <= r.x1; ++x) {
      std::vector<std::uint32_t>& bucket = buckets_[bucketOf(x, y)];
      auto it = std::find(bucket.begin(), bucket.end(), proxy);
      if (it == bucket.end()) continue;  // already removed through another cell of the bucket
      *it = bucket.back();
      bucket.pop_back();
    }
  }
}

void SpatialHash::resize(std::size_t bucketCount) {
  buckets_.assign(bucketCount, {});
  oversized_.clear();
  for (std::uint32_t p : list_)
    addToCells(p, rangeOf(boxes_[p]));
}

void SpatialHash::rebuild() {
  std::size_t n = kMinBuckets;
  while (n < list_.size() * kBucketsPerProxy)
    n *= 2;
  buckets_.clear();
  buckets_.shrink_to_fit();
  resize(n);
}

std::size_t SpatialHash::bytesUsed() const noexcept {
  std::size_t bytes =
      boxes_.capacity() * sizeof(Aabb) +
      (dense_.capacity() + list_.capacity() + oversized_.capacity()) * sizeof(std::uint32_t) +
      buckets_.capacity() * sizeof(std::vector<std::uint32_t>);
  for (const auto& b : buckets_)
    bytes += b.capacity() * sizeof(std::uint32_t);
  return bytes;
}

Status SpatialHash::validate() const {
  for (std::size_t i = 0; i < list_.size(); ++i) {
    const std::uint32_t p = list_[i];
    if (p >= dense_.size() || dense_[p] != i) {
      return fail("dense table disagrees at list entry " + std::to_string(i));
    }
    if (!isValid(boxes_[p])) return fail("a stored box is not valid");
  }
  std::size_t present = 0;
  for (std::uint32_t d : dense_)
    present += d != kNullIndex ? 1 : 0;
  if (present != list_.size()) return fail("dense table holds stale proxies");
  if (buckets_.empty()) {
    if (!list_.empty()) return fail("proxies present but no table");
    return {};
  }
  // Every listed entry must belong (its cells hash there), and every cell must list it.
  std::size_t entries = 0;
  for (std::size_t b = 0; b < buckets_.size(); ++b) {
    for (std::uint32_t p : buckets_[b]) {
      ++entries;
      if (!contains(p)) return fail("bucket lists an absent proxy " + std::to_string(p));
      const Range r = rangeOf(boxes_[p]);
      if (r.cells() > kMaxCellsPerProxy) return fail("oversized proxy listed in a bucket");
      bool belongs = false;
      for (std::int64_t y = r.y0; y <= r.y1 && !belongs; ++y) {
        for (std::int64_t x = r.x0; x <= r.x1 && !belongs; ++x)
          belongs = bucketOf(x, y) == b;
      }
      if (!belongs) return fail("proxy " + std::to_string(p) + " listed in a foreign bucket");
      if (std::count(buckets_[b].begin(), buckets_[b].end(), p) != 1) {
        return fail("proxy " + std::to_string(p) + " listed twice in one bucket");
      }
    }
  }
  std::size_t expected = 0;
  std::size_t oversized = 0;
  for (std::uint32_t p : list_) {
    const Range r = rangeOf(boxes_[p]);
    if (r.cells() > kMaxCellsPerProxy) {
      ++oversized;
      continue;
    }
    std::vector<std::size_t> distinct;
    for (std::int64_t y = r.y0; y <= r.y1; ++y) {
      for (std::int64_t x = r.x0; x <= r.x1; ++x) {
        const std::size_t b = bucketOf(x, y);
        if (std::find(distinct.begin(), distinct.end(), b) != distinct.end()) continue;
        distinct.push_back(b);
        if (std::find(buckets_[b].begin(), buckets_[b].end(), p) == buckets_[b].end()) {
          return fail("proxy " + std::to_string(p) + " missing from one of its cells");
        }
      }
    }
    expected += distinct.size();
  }
  if (entries != expected) return fail("bucket entry count differs from the cells covered");
  if (oversized != oversized_.size()) return fail("side list does not match oversized boxes");
  return {};
}

}  // namespace quack
