#include "quack/broadphase/sweep_and_prune.hpp"

#include <string>

namespace quack {

void SweepAndPrune::insert(std::uint32_t proxy, Aabb b) {
  QUACK_ASSERT(isValid(b));
  QUACK_ASSERT(proxy != kNullIndex);
  if (proxy >= slot_.size()) slot_.resize(std::size_t{proxy} + 1, kNullIndex);
  QUACK_ASSERT_MSG(slot_[proxy] == kNullIndex, "SweepAndPrune::insert: proxy already present");
  slot_[proxy] = static_cast<std::uint32_t>(entries_.size());
  entries_.push_back({b, proxy});
  maxWidth_ = maxf(maxWidth_, b.upper.x - b.lower.x);
  dirty_ = true;
  ++count_;
}

void SweepAndPrune::remove(std::uint32_t proxy) {
  QUACK_ASSERT_MSG(contains(proxy), "SweepAndPrune::remove: proxy not present");
  entries_[slot_[proxy]].proxy = kNullIndex;
  slot_[proxy] = kNullIndex;
  ++tombstones_;
  dirty_ = true;
  --count_;
}

void SweepAndPrune::move(std::uint32_t proxy, Aabb b) {
  QUACK_ASSERT(isValid(b));
  QUACK_ASSERT_MSG(contains(proxy), "SweepAndPrune::move: proxy not present");
  entries_[slot_[proxy]].box = b;
  maxWidth_ = maxf(maxWidth_, b.upper.x - b.lower.x);
  dirty_ = true;
}

void SweepAndPrune::flush() const {
  if (!dirty_) return;
  auto byLower = [](const Entry& a, const Entry& b) { return a.box.lower.x < b.box.lower.x; };
  if (tombstones_ > 0) {
    std::size_t out = 0;
    std::size_t newSortedEnd = 0;
    for (std::size_t i = 0; i < entries_.size(); ++i) {
      if (i == sortedEnd_) newSortedEnd = out;
      if (entries_[i].proxy != kNullIndex) entries_[out++] = entries_[i];
    }
    if (sortedEnd_ >= entries_.size()) newSortedEnd = out;
    entries_.resize(out);
    sortedEnd_ = newSortedEnd;
    tombstones_ = 0;
  }
  // Insertion sort of the old part: coherent motion leaves it nearly sorted. A teleport can
  // make it quadratic, so past a budget of shifts it gives up and sorts from scratch.
  const std::size_t budget = 8 * sortedEnd_ + 1024;
  std::size_t shifts = 0;
  bool gaveUp = false;
  for (std::size_t i = 1; i < sortedEnd_ && !gaveUp; ++i) {
    const Entry e = entries_[i];
    std::size_t j = i;
    while (j > 0 && entries_[j - 1].box.lower.x > e.box.lower.x) {
      entries_[j] = entries_[j - 1];
      --j;
      if (++shifts > budget) {
        gaveUp = true;
        break;
      }
    }
    entries_[j] = e;
  }
  if (gaveUp) {
    std::sort(entries_.begin(), entries_.end(), byLower);
  } else if (sortedEnd_ < entries_.size()) {
    const auto mid = entries_.begin() + static_cast<std::ptrdiff_t>(sortedEnd_);
    std::sort(mid, entries_.end(), byLower);
    std::inplace_merge(entries_.begin(), mid, entries_.end(), byLower);
  }
  sortedEnd_ = entries_.size();
  float width = 0.0f;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    slot_[entries_[i].proxy] = static_cast<std::uint32_t>(i);
    width = maxf(width, entries_[i].box.upper.x - entries_[i].box.lower.x);
  }
  maxWidth_ = width;
  dirty_ = false;
}

void SweepAndPrune::rebuild() {
  dirty_ = true;
  sortedEnd_ = 0;
  flush();
  entries_.shrink_to_fit();
}

std::size_t SweepAndPrune::bytesUsed() const noexcept {
  return entries_.capacity() * sizeof(Entry) + slot_.capacity() * sizeof(std::uint32_t);
}

Status SweepAndPrune::validate() const {
  flush();
  if (entries_.size() != count_) return fail("entry count != proxy count");
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const Entry& e = entries_[i];
    if (!isValid(e.box)) return fail("a stored box is not valid");
    if (e.proxy >= slot_.size() || slot_[e.proxy] != i) {
      return fail("slot table disagrees at entry " + std::to_string(i));
    }
    if (i > 0 && entries_[i - 1].box.lower.x > e.box.lower.x) {
      return fail("entries out of order at " + std::to_string(i));
    }
    if (e.box.upper.x - e.box.lower.x > maxWidth_) return fail("widest-box bound too small");
  }
  std::size_t present = 0;
  for (std::uint32_t s : slot_)
    present += s != kNullIndex ? 1 : 0;
  if (present != count_) return fail("slot table holds stale proxies");
  return {};
}

}  // namespace quack
