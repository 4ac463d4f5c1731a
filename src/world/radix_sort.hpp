#pragma once
// A stable least-significant-digit radix sort on an unsigned key, for the world's lists that
// are sorted every step or every rebuild and are long enough that comparisons dominate
// (the step's new pairs, the ghost-edge grid's entries).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace quack::detail {

/// Sorts `items` by key(item), a std::uint64_t of at most `bits` significant bits, kDigit bits
/// a pass; items with equal keys keep their order. `scratch` is the second buffer. Shorter
/// digits suit short lists, where clearing and summing the counts would dominate.
template <int kDigit = 11, class T, class Key>
void radixSortByKey(std::vector<T>& items, std::vector<T>& scratch, int bits, Key key) {
  constexpr std::size_t kBuckets = std::size_t{1} << kDigit;
  scratch.resize(items.size());
  std::size_t count[kBuckets];
  for (int shift = 0; shift < bits; shift += kDigit) {
    std::fill(count, count + kBuckets, std::size_t{0});
    for (const T& item : items)
      ++count[(key(item) >> shift) & (kBuckets - 1)];
    std::size_t at = 0;
    for (std::size_t& c : count) {
      const std::size_t n = c;
      c = at;
      at += n;
    }
    for (const T& item : items)
      scratch[count[(key(item) >> shift) & (kBuckets - 1)]++] = item;
    items.swap(scratch);
  }
}

}  // namespace quack::detail
