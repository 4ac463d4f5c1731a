#include "quack/broadphase/brute_force.hpp"

#include <string>

namespace quack {

void BruteForce::insert(std::uint32_t proxy, Aabb b) {
  QUACK_ASSERT(isValid(b));
  QUACK_ASSERT(proxy != kNullIndex);
  if (proxy >= slot_.size()) slot_.resize(std::size_t{proxy} + 1, kNullIndex);
  QUACK_ASSERT_MSG(slot_[proxy] == kNullIndex, "BruteForce::insert: proxy already present");
  slot_[proxy] = static_cast<std::uint32_t>(boxes_.size());
  boxes_.push_back(b);
  proxies_.push_back(proxy);
}

void BruteForce::remove(std::uint32_t proxy) {
  QUACK_ASSERT_MSG(contains(proxy), "BruteForce::remove: proxy not present");
  const std::uint32_t s = slot_[proxy];
  const std::uint32_t last = proxies_.back();
  boxes_[s] = boxes_.back();
  proxies_[s] = last;
  slot_[last] = s;
  boxes_.pop_back();
  proxies_.pop_back();
  slot_[proxy] = kNullIndex;
}

void BruteForce::move(std::uint32_t proxy, Aabb b) {
  QUACK_ASSERT(isValid(b));
  QUACK_ASSERT_MSG(contains(proxy), "BruteForce::move: proxy not present");
  boxes_[slot_[proxy]] = b;
}

void BruteForce::rebuild() {
  boxes_.shrink_to_fit();
  proxies_.shrink_to_fit();
}

std::size_t BruteForce::bytesUsed() const noexcept {
  return boxes_.capacity() * sizeof(Aabb) +
         (proxies_.capacity() + slot_.capacity()) * sizeof(std::uint32_t);
}

Status BruteForce::validate() const {
  if (boxes_.size() != proxies_.size()) return fail("dense arrays differ in length");
  std::size_t present = 0;
  for (std::uint32_t p = 0; p < slot_.size(); ++p) {
    if (slot_[p] == kNullIndex) continue;
    ++present;
    if (slot_[p] >= proxies_.size() || proxies_[slot_[p]] != p) {
      return fail("slot table and dense array disagree at proxy " + std::to_string(p));
    }
  }
  if (present != proxies_.size()) return fail("dense array holds proxies not in the slot table");
  for (const Aabb& b : boxes_) {
    if (!isValid(b)) return fail("a stored box is not valid");
  }
  return {};
}

}  // namespace quack
