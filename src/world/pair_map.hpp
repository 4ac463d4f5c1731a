#pragma once
// PairMap: the contact set's map from a pair of shapes to its contact. An open-addressing
// hash table (linear probing, deletion by shifting back, at most half full) in one array:
// a lookup is a hash and usually one cache line, where std::unordered_map allocated a node
// per contact and chased a pointer per lookup (a churning pile of 8,000 boxes creates and
// destroys thousands of contacts a step, and looks up every pair the broad phase reports
// and every pair the continuous phase tests). Nothing iterates it, so its order never
// reaches a result.

#include <cstdint>
#include <vector>

namespace quack::detail {

class PairMap {
 public:
  // A key no pair has: shape indices are below 0xffffffff, and a pair's two differ.
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  std::size_t size() const noexcept { return count_; }

  const std::uint32_t* find(std::uint64_t key) const noexcept {
    if (count_ == 0) return nullptr;
    for (std::size_t i = home(key);; i = (i + 1) & mask_) {
      const Slot& s = slots_[i];
      if (s.key == key) return &s.value;
      if (s.key == kEmpty) return nullptr;
    }
  }
  bool contains(std::uint64_t key) const noexcept { return find(key) != nullptr; }

  // Inserts the key with `value`, or gives an existing key `value`.
  void set(std::uint64_t key, std::uint32_t value) {
    if (2 * (count_ + 1) > slots_.size()) grow();
    for (std::size_t i = home(key);; i = (i + 1) & mask_) {
      Slot& s = slots_[i];
      if (s.key == key) {
        s.value = value;
        return;
      }
      if (s.key == kEmpty) {
        s = {key, value};
        ++count_;
        return;
      }
    }
  }

  // Removes the key if present.
  void erase(std::uint64_t key) noexcept {
    if (count_ == 0) return;
    std::size_t i = home(key);
    for (;; i = (i + 1) & mask_) {
      if (slots_[i].key == key) break;
      if (slots_[i].key == kEmpty) return;
    }
    // Shift back the entries after the hole that may move into it (Knuth's algorithm R).
    std::size_t hole = i;
    for (std::size_t j = (i + 1) & mask_; slots_[j].key != kEmpty; j = (j + 1) & mask_) {
      const std::size_t h = home(slots_[j].key);
      // j's entry may fill the hole unless its home lies cyclically in (hole, j].
      const bool stays = hole <= j ? (hole < h && h <= j) : (hole < h || h <= j);
      if (stays) continue;
      slots_[hole] = slots_[j];
      hole = j;
    }
    slots_[hole].key = kEmpty;
    --count_;
  }

  void clear() noexcept {
    for (Slot& s : slots_)
      s.key = kEmpty;
    count_ = 0;
  }

 private:
  struct Slot {
    std::uint64_t key = kEmpty;
    std::uint32_t value = 0;
  };
  std::size_t home(std::uint64_t key) const noexcept {
    // A 64-bit mix (the finaliser of MurmurHash3), so that neighbouring shape indices spread.
    key ^= key >> 33;
    key *= 0xff51afd7ed558ccdull;
    key ^= key >> 33;
    key *= 0xc4ceb9fe1a85ec53ull;
    key ^= key >> 33;
    return static_cast<std::size_t>(key) & mask_;
  }
  void grow() {
    std::vector<Slot> old;
    old.swap(slots_);
    slots_.assign(old.empty() ? 64 : 2 * old.size(), Slot{});
    mask_ = slots_.size() - 1;
    count_ = 0;
    for (const Slot& s : old)
      if (s.key != kEmpty) set(s.key, s.value);
  }
  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  std::size_t count_ = 0;
};

}  // namespace quack::detail
