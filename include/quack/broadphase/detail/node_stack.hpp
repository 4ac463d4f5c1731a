#pragma once
/// Internal: the stack of the 3D structures' traversals. Not part of the public interface.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace quack::detail {

/// A LIFO of node indices on the call stack for the common case (a tree of 10^5 leaves is
/// about 20 deep; a query holds at most a few nodes per level) that spills to the heap for
/// degenerate trees, so a query never overflows and never allocates in normal use. It does
/// what `TraversalStack` does, with the rare paths out of line, so that the compiler inlines
/// `push` and `pop` into the query loops (callgrind found `TraversalStack::push` called, not
/// inlined, in the 3D tree's queries: 6.5% of a frame's instructions).
class NodeStack {
 public:
  /// Adds `value` on top.
  void push(std::uint32_t value) {
    if (size_ < kInline) [[likely]] {
      inline_[size_++] = value;
    } else {
      spill(value);
    }
  }
  /// Removes and returns the top value; precondition: not empty.
  std::uint32_t pop() {
    if (size_ <= kInline) [[likely]] {
      return inline_[--size_];
    }
    return unspill();
  }
  /// True when nothing is on the stack.
  bool empty() const noexcept { return size_ == 0; }

 private:
  static constexpr std::size_t kInline = 128;

  [[gnu::noinline]] void spill(std::uint32_t value) {
    spill_.push_back(value);
    ++size_;
  }
  [[gnu::noinline]] std::uint32_t unspill() {
    --size_;
    const std::uint32_t v = spill_.back();
    spill_.pop_back();
    return v;
  }

  std::uint32_t inline_[kInline];
  std::size_t size_ = 0;
  std::vector<std::uint32_t> spill_;
};

}  // namespace quack::detail
