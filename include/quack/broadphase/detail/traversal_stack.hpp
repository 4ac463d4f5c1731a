#pragma once
/// Internal: the stack used by tree traversals. Not part of the public interface.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace quack::detail {

/// A LIFO of node indices that lives on the call stack for the common case (a balanced tree
/// of a billion leaves is about 45 deep) and spills to the heap for degenerate trees, so a
/// query never overflows and never allocates in normal use.
class TraversalStack {
 public:
  // The common case inline in the traversal loop, the spill out of line: with both in one
  // function g++ did not inline push, and the call cost 22 instructions a node (a quarter
  // of a churning pile's broad-phase queries).
  void push(std::uint32_t value) {
    if (size_ < kInline) [[likely]] {
      inline_[size_++] = value;
    } else {
      spill(value);
    }
  }
  std::uint32_t pop() {
    --size_;
    if (size_ < kInline) [[likely]]
      return inline_[size_];
    return unspill();
  }
  bool empty() const noexcept { return size_ == 0; }

 private:
  [[gnu::noinline]] void spill(std::uint32_t value) {
    spill_.push_back(value);
    ++size_;
  }
  [[gnu::noinline]] std::uint32_t unspill() {
    std::uint32_t v = spill_.back();
    spill_.pop_back();
    return v;
  }
  static constexpr std::size_t kInline = 128;
  std::uint32_t inline_[kInline];
  std::size_t size_ = 0;
  std::vector<std::uint32_t> spill_;
};

}  // namespace quack::detail
