#pragma once
/// Proxies, filters and pairs: the vocabulary shared by every broad-phase structure.
///
/// A proxy is the broad phase's record of one bounding box (usually one shape). The
/// structures (`DynamicTree`, `Quadtree`, `SweepAndPrune`, `SpatialHash`, `BruteForce`)
/// work on bare proxy indices; `BroadPhase` hands out `ProxyId`s, which add a generation so
/// that a handle kept after `destroyProxy` is reported as stale instead of reaching a reused
/// slot.

#include <cstdint>

namespace quack {

/// Index meaning "no proxy" (and "no node" inside the structures).
inline constexpr std::uint32_t kNullIndex = 0xffffffffu;

/// Handle to a proxy of a `BroadPhase`: the slot index and the slot's generation when the
/// proxy was created. The default handle is null.
struct ProxyId {
  std::uint32_t index = kNullIndex;
  std::uint32_t generation = 0;

  friend constexpr bool operator==(ProxyId, ProxyId) noexcept = default;
};

/// Whether a proxy can move. Pairs of two static proxies are never reported (the proximity
/// phase of docs/background.md): static geometry cannot start touching other static
/// geometry. Kinematic bodies are `dynamicProxy` at this layer; the world applies body-type
/// rules on top.
enum class ProxyKind : std::uint8_t { dynamicProxy, staticProxy };

/// Collision filter of a proxy (the proximity phase), 64 categories wide.
struct Filter {
  /// The categories this proxy belongs to (one bit per category, usually one bit set).
  std::uint64_t category = 1;
  /// The categories this proxy collides with.
  std::uint64_t mask = ~std::uint64_t{0};
  /// Two proxies with the same non-zero group always collide when the group is positive and
  /// never collide when it is negative, whatever their categories and masks say.
  std::int32_t group = 0;

  friend constexpr bool operator==(Filter, Filter) noexcept = default;
};

/// The filter rule: same non-zero group decides (positive collides, negative never);
/// otherwise each proxy's category must be in the other's mask.
constexpr bool shouldCollide(Filter a, Filter b) noexcept {
  if (a.group == b.group && a.group != 0) return a.group > 0;
  return (a.category & b.mask) != 0 && (b.category & a.mask) != 0;
}

/// A candidate pair reported by `BroadPhase::updatePairs`: `a.index < b.index`.
struct ProxyPair {
  ProxyId a;
  ProxyId b;

  friend constexpr bool operator==(ProxyPair, ProxyPair) noexcept = default;
};

}  // namespace quack
