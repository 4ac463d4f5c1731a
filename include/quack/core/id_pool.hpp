#pragma once
/// `IdPool`: slots with generations, for handles that catch use after destruction.
///
/// A handle is a slot index plus the slot's generation when it was handed out. Releasing a
/// slot bumps its generation, so every handle to the old occupant is stale from then on,
/// whoever takes the slot next. Freed slots are reused last-in first-out, so the same
/// sequence of allocations and releases always gives the same indices (determinism).
/// Generation 0 is never live: a zero-initialised handle is always invalid.
///
/// ```
/// IdPool pool;
/// std::uint32_t a = pool.allocate();        // slot 0, generation 1
/// std::uint32_t g = pool.generation(a);
/// pool.release(a);
/// bool stale = !pool.isValid(a, g);          // true
/// ```
///
/// Used by the world (bodies, shapes) and the broad phase (proxies).

#include <cstdint>
#include <string>
#include <vector>

#include "quack/core/assert.hpp"
#include "quack/core/result.hpp"

namespace quack {

class IdPool {
 public:
  /// A free slot (the most recently released one, else a new one), now live.
  std::uint32_t allocate() {
    std::uint32_t index;
    if (!free_.empty()) {
      index = free_.back();
      free_.pop_back();
    } else {
      index = static_cast<std::uint32_t>(generations_.size());
      generations_.push_back(1);
      alive_.push_back(0);
    }
    alive_[index] = 1;
    ++liveCount_;
    return index;
  }

  /// The index the next `allocate` will return.
  std::uint32_t nextIndex() const noexcept {
    return free_.empty() ? static_cast<std::uint32_t>(generations_.size()) : free_.back();
  }

  /// Precondition: `isAlive(index)` (asserted). The slot's handles become stale.
  void release(std::uint32_t index) {
    QUACK_ASSERT(isAlive(index));
    alive_[index] = 0;
    // Skip 0 on wrap-around (after 2^32 reuses of one slot): 0 is never live.
    if (++generations_[index] == 0) generations_[index] = 1;
    free_.push_back(index);
    --liveCount_;
  }

  bool isAlive(std::uint32_t index) const noexcept {
    return index < alive_.size() && alive_[index] != 0;
  }
  /// True when (index, generation) names the slot's present occupant.
  bool isValid(std::uint32_t index, std::uint32_t generation) const noexcept {
    return isAlive(index) && generations_[index] == generation;
  }
  /// The slot's present generation (of its occupant, or of the next one if free).
  std::uint32_t generation(std::uint32_t index) const noexcept {
    return index < generations_.size() ? generations_[index] : 0;
  }
  /// Slots ever made: indices are below this.
  std::uint32_t capacity() const noexcept {
    return static_cast<std::uint32_t>(generations_.size());
  }
  std::uint32_t liveCount() const noexcept { return liveCount_; }
  /// Bytes held, for memory statistics.
  std::size_t memoryBytes() const noexcept {
    return generations_.capacity() * sizeof(std::uint32_t) + alive_.capacity() +
           free_.capacity() * sizeof(std::uint32_t);
  }

  /// The free slots, in the order `release` freed them (the last is reused first).
  const std::vector<std::uint32_t>& freeSlots() const noexcept { return free_; }

  /// The pool whose slots have these generations and whose free list is `freeSlots` (in
  /// release order); every other slot is live. For restoring a saved pool (World::restore):
  /// fails, naming the problem, on a generation of 0, a free slot out of range or listed
  /// twice.
  static Result<IdPool> fromSlots(std::vector<std::uint32_t> generations,
                                  std::vector<std::uint32_t> freeSlots) {
    IdPool pool;
    pool.alive_.assign(generations.size(), 1);
    for (std::size_t i = 0; i < generations.size(); ++i) {
      if (generations[i] == 0) return fail("slot " + std::to_string(i) + " has generation 0");
    }
    for (std::uint32_t i : freeSlots) {
      if (i >= generations.size())
        return fail("free slot " + std::to_string(i) + " is beyond the " +
                    std::to_string(generations.size()) + " slots");
      if (pool.alive_[i] == 0) return fail("free slot " + std::to_string(i) + " is listed twice");
      pool.alive_[i] = 0;
    }
    pool.liveCount_ = static_cast<std::uint32_t>(generations.size() - freeSlots.size());
    pool.generations_ = std::move(generations);
    pool.free_ = std::move(freeSlots);
    return pool;
  }

  /// Every free slot is dead and listed once, live + free = capacity.
  Status validate() const {
    std::uint32_t live = 0;
    for (std::uint8_t a : alive_)
      live += a;
    if (live != liveCount_) return fail("IdPool: live count is wrong");
    std::vector<std::uint8_t> seen(alive_.size(), 0);
    for (std::uint32_t i : free_) {
      if (i >= alive_.size() || alive_[i] != 0 || seen[i] != 0)
        return fail("IdPool: free slot " + std::to_string(i) + " is live or listed twice");
      seen[i] = 1;
    }
    if (free_.size() + liveCount_ != alive_.size()) return fail("IdPool: free + live != slots");
    for (std::uint32_t g : generations_) {
      if (g == 0) return fail("IdPool: a slot has generation 0");
    }
    return {};
  }

 private:
  std::vector<std::uint32_t> generations_;
  std::vector<std::uint8_t> alive_;
  std::vector<std::uint32_t> free_;
  std::uint32_t liveCount_ = 0;
};

}  // namespace quack
