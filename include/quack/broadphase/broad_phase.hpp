#pragma once
/// `BroadPhase`: one interface over the five broad-phase structures, with the move buffer,
/// pair finding, filters and queries that the world, the tests and the benchmarks share.
///
/// ```
/// Result<BroadPhase> made = BroadPhase::create({.kind = BroadPhaseKind::tree});
/// BroadPhase& bp = made.value();
/// ProxyId a = bp.createProxy(box, shapeIndex).value();
/// ... each step: bp.moveProxy(a, newBox, displacement);
/// std::vector<ProxyPair> pairs;
/// bp.updatePairs(pairs);  // candidate pairs of this step
/// ```
///
/// Enlarged ("fat") boxes: a proxy's structure box is its tight box grown by its margin on
/// every side (`BroadPhaseConfig::margin`, or the proxy's own, given to `createProxy`) and
/// stretched by `displacementScale` times its last displacement. `moveProxy`
/// re-inserts the proxy only when the tight box leaves the fat box (or the fat box has grown
/// much larger than needed), so slowly moving proxies cost one containment test a step.
///
/// Pairs: `updatePairs` reports every pair {a, b} such that at least one of a and b was
/// created, re-inserted or touched since the last call, their fat boxes overlap (and, with
/// `checkTightBoxes`, their tight boxes too), they are not both static, their filters
/// accept each other and the user pair filter, if any, agrees. Each pair once, `a.index <
/// b.index`, in an order that depends on the structure (sort them for cross-structure
/// determinism). This is Box2D's contract: pairs that stayed in contact without re-insertion
/// are not reported again; the world keeps its contacts until their fat boxes part.
///
/// Dispatch: the structure is a `std::variant` member, selected once by name; each public
/// operation does one `std::visit` (a jump through a table, the cost of a virtual call), and
/// the per-pair and per-hit work inside is templated and inlined: no indirect call per pair
/// except the optional user pair filter.
///
/// Error policy: bad input at this boundary — a NaN, infinite, inverted or out-of-range box
/// (any coordinate beyond +-`kMaxCoordinate`), a null, unknown or stale `ProxyId` (the slot
/// was destroyed and maybe reused: the generation differs) — is rejected with an `Error`
/// that names the argument, and nothing changes. Queries given NaN input report no hits.
/// Internal invariants are `QUACK_ASSERT`s; `validate()` checks the whole structure.
///
/// Frames and units: all boxes, points and translations are in the world frame, metres.
/// Not thread-safe; queries may run concurrently with each other only when no change is
/// pending (after `updatePairs`), because sweep-and-prune sorts lazily.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "quack/broadphase/brute_force.hpp"
#include "quack/broadphase/dynamic_tree.hpp"
#include "quack/broadphase/proxy.hpp"
#include "quack/broadphase/quadtree.hpp"
#include "quack/broadphase/spatial_hash.hpp"
#include "quack/broadphase/sweep_and_prune.hpp"
#include "quack/core/id_pool.hpp"
#include "quack/core/result.hpp"
#include "quack/math/aabb.hpp"

namespace quack {

/// The five structures, named `tree`, `quadtree`, `sap`, `hash`, `brute`.
enum class BroadPhaseKind : std::uint8_t { tree, quadtree, sap, hash, brute };

/// Every kind, in declaration order (for tests and benchmarks that try them all).
inline constexpr BroadPhaseKind kAllBroadPhaseKinds[] = {
    BroadPhaseKind::tree, BroadPhaseKind::quadtree, BroadPhaseKind::sap, BroadPhaseKind::hash,
    BroadPhaseKind::brute};

/// The short name of a kind ("tree", "quadtree", "sap", "hash", "brute").
const char* toString(BroadPhaseKind kind) noexcept;
/// The kind with that short name, or an error listing the valid names.
Result<BroadPhaseKind> parseBroadPhaseKind(std::string_view name);

/// Boxes must lie within +-kMaxCoordinate metres of the origin (1e9 m, defined in
/// quack/math/aabb.hpp so the geometry layer shares it). Queries take any finite box, ray
/// or translation and answer in time bounded by the proxy count (docs/broad-phase.md).

/// Smallest `BroadPhaseConfig::cellSize`, metres. The quadtree's integer cell grid covers
/// +-cellSize * 2^61 / 3 metres, which must hold the coordinate range with room to spare;
/// a micrometre covers 7.7e11 m.
inline constexpr float kMinCellSize = 1e-6f;

/// How a `BroadPhase` is made. Every field has a default that suits boxes of about 1 m.
struct BroadPhaseConfig {
  BroadPhaseKind kind = BroadPhaseKind::tree;
  /// Metres added to every side of a tight box to make its fat box (>= 0). Larger means fewer
  /// re-insertions but more candidate pairs. 0.1 m is Box2D's value for metre-sized bodies.
  float margin = 0.1f;
  /// The fat box is also stretched by this times the displacement passed to `moveProxy`
  /// (>= 0), so a steadily moving proxy stays inside it longer.
  float displacementScale = 1.0f;
  /// Report a pair only when the tight boxes overlap as well as the fat boxes.
  bool checkTightBoxes = false;
  /// Cell side of the hash and smallest cell side of the quadtree, metres, in
  /// [kMinCellSize, kMaxCoordinate]: about the typical fat box size.
  float cellSize = 1.0f;
};

/// The user pair filter: called for each candidate pair that passed the built-in rules
/// (static-static, groups, categories and masks, tight boxes); return false to drop it.
/// `context` is the pointer given to `setPairFilter`.
using PairFilterFn = bool (*)(void* context, ProxyId a, std::uint64_t userA, ProxyId b,
                              std::uint64_t userB);

/// One hit of a ray or box cast against the tight boxes.
struct BroadPhaseHit {
  ProxyId proxy;
  std::uint64_t userData = 0;
  /// Fraction of the translation at which the ray (or moving box) first touches the tight
  /// box; 0 when it starts inside (or overlapping).
  float fraction = 1.0f;
};

/// Size and shape figures of a `BroadPhase`.
struct BroadPhaseStats {
  std::uint32_t proxyCount = 0;
  /// Bytes held by the structure itself (nodes, cells, buckets, sorted arrays).
  std::size_t structureBytes = 0;
  /// Bytes held by the shared per-proxy records (tight and fat boxes, filters, user data,
  /// generations, move buffer), the same for every structure.
  std::size_t recordBytes = 0;
  /// Tree height, or quadtree depth; 0 for the others.
  int height = 0;
  /// Tree only: sum of internal node perimeters over the root's; 0 for the others.
  float areaRatio = 0.0f;
};

/// Every record of a `BroadPhase` that decides what it reports from now on, slot by slot
/// (index = ProxyId::index): the proxies' generations and free slots, boxes, kinds, filters,
/// user data and the move buffer. The structure's own shape (tree nodes, cells, sorted
/// arrays) is not part of it: pairs, boxes and every query's hits depend only on these
/// records; only the order in which a structure visits its hits does (docs/determinism.md,
/// "Snapshots"). Entries of free slots are ignored.
struct BroadPhaseRecords {
  std::vector<std::uint32_t> generations;  ///< per slot, never 0
  std::vector<std::uint32_t> freeSlots;    ///< in release order (IdPool::freeSlots)
  std::vector<Aabb> tight, fat;            ///< per slot, world frame
  /// Per slot, metres (finite, >= 0): each proxy's margin. Empty in `fromRecords` means
  /// the config's margin for every proxy.
  std::vector<float> margins;
  std::vector<ProxyKind> kinds;           ///< per slot
  std::vector<std::uint8_t> buffered;     ///< per slot: 1 while in the move buffer
  std::vector<Filter> filters;            ///< per slot
  std::vector<std::uint64_t> userData;    ///< per slot
  std::vector<std::uint32_t> moveBuffer;  ///< slots, in order (may hold stale entries)
};

class BroadPhase {
 public:
  /// A broad phase using `config`; fails on a non-finite or negative margin or displacement
  /// scale, or a non-positive cell size, naming the field.
  static Result<BroadPhase> create(BroadPhaseConfig config = {});

  BroadPhaseKind kind() const noexcept { return config_.kind; }
  const BroadPhaseConfig& config() const noexcept { return config_; }

  /// Adds a proxy for the tight box `box` (world frame). `userData` is returned with pairs and
  /// hits. `margin` (metres, finite and >= 0) replaces the config's margin for this proxy,
  /// for the life of the proxy. The new proxy is in the move buffer: its pairs come out of
  /// the next `updatePairs`. Fails on an invalid or out-of-range box or a bad margin.
  Result<ProxyId> createProxy(Aabb box, std::uint64_t userData = 0, Filter filter = {},
                              ProxyKind kind = ProxyKind::dynamicProxy,
                              std::optional<float> margin = std::nullopt);
  /// Removes a proxy. Fails on a null, unknown or stale id.
  Status destroyProxy(ProxyId id);
  /// Gives a proxy its new tight box (world frame) and the displacement since the last
  /// move (metres, used to stretch the fat box ahead of the motion; pass zero for a
  /// teleport). Returns whether the proxy was re-inserted (and so buffered for pairs).
  /// Fails on a bad id, box or displacement.
  Result<bool> moveProxy(ProxyId id, Aabb box, Vec2 displacement) {
    // The per-proxy-per-step path is inline; every rejection goes out of line.
    if (!isAcceptableMove(id, box, displacement)) return rejectMove(id, box, displacement);
    const std::uint32_t p = id.index;
    tight_[p] = box;
    if (staysInPlace(p, box, displacement)) return false;
    reinsert(p, wantedBox(p, box, displacement));
    return true;
  }
  /// moveProxy's common case, for many proxies moved from several threads at once (each
  /// proxy by one thread, nothing else changing meanwhile): it records the tight box and
  /// returns false when the fat box still holds it; true means moveProxy must follow (on one
  /// thread) to re-insert the proxy. Rejects what moveProxy rejects.
  Result<bool> moveProxyInPlace(ProxyId id, Aabb box, Vec2 displacement) {
    if (!isAcceptableMove(id, box, displacement)) return rejectMove(id, box, displacement);
    const std::uint32_t p = id.index;
    tight_[p] = box;
    return !staysInPlace(p, box, displacement);
  }
  /// Replaces a proxy's filter and buffers it, so the next `updatePairs` re-reports its
  /// pairs under the new rules.
  Status setFilter(ProxyId id, Filter filter);
  /// Buffers a proxy as if it had moved (its pairs come out of the next `updatePairs`).
  Status touchProxy(ProxyId id);

  /// True when `id` names a live proxy.
  bool isValid(ProxyId id) const noexcept { return ids_.isValid(id.index, id.generation); }
  /// Precondition `isValid(id)` (asserted): the user data given at creation.
  std::uint64_t userData(ProxyId id) const;
  /// Precondition `isValid(id)` (asserted): the proxy's filter.
  Filter filter(ProxyId id) const;
  /// Precondition `isValid(id)` (asserted): the last tight box given.
  Aabb tightBox(ProxyId id) const;
  /// Precondition `isValid(id)` (asserted): the enlarged box stored in the structure.
  Aabb fatBox(ProxyId id) const;
  /// Number of live proxies.
  std::uint32_t proxyCount() const noexcept { return ids_.liveCount(); }

  /// Installs the user pair filter (null removes it).
  void setPairFilter(PairFilterFn userFilter, void* context) noexcept {
    pairFilter_ = userFilter;
    pairFilterContext_ = context;
  }

  /// Replaces the contents of `pairs` with this step's candidate pairs (see the contract
  /// above) and empties the move buffer.
  void updatePairs(std::vector<ProxyPair>& pairs);
  /// updatePairs with the moved proxies' queries spread over threads. `parallelFor(count,
  /// body)` must call body(begin, end, part) for ranges covering [0, count) once, each
  /// with a `part` below parts.size(), no two at once with the same part; each part's pairs
  /// go to parts[part] and then, part after part, to `pairs`. The pairs are those of
  /// updatePairs, in an order that depends on the split (sort them for determinism), and
  /// the user pair filter may be called from several threads at once. Sweep-and-prune,
  /// whose queries sort lazily, runs on the calling thread.
  template <class ParallelFor>
  void updatePairs(std::vector<ProxyPair>& pairs, std::vector<std::vector<ProxyPair>>& parts,
                   ParallelFor&& parallelFor);

  /// Calls `visit(ProxyId, userData) -> bool` for each proxy whose tight box overlaps `box`
  /// (touching counts); return false to stop.
  template <class Visit>
  void queryAabb(Aabb box, Visit&& visit) const;
  /// Calls `visit(ProxyId, userData) -> bool` for each proxy whose tight box contains `point`.
  template <class Visit>
  void queryPoint(Vec2 point, Visit&& visit) const {
    queryAabb(Aabb{point, point}, visit);
  }
  /// Casts the ray `origin + t * translation`, t in [0, 1], against the tight boxes. Calls
  /// `callback(ProxyId, userData, fraction) -> float` for boxes it reaches (fraction 0 when
  /// it starts inside), and the return value steers the cast: a value in (0, current max)
  /// clips the ray there, 0 stops, anything else (1, or -1 to ignore the proxy) goes on
  /// unclipped. Return `fraction` for the closest hit, 1 for all hits.
  template <class Callback>
  void rayCast(Vec2 origin, Vec2 translation, Callback&& callback) const {
    castImpl(origin, translation, Vec2{}, callback);
  }
  /// As `rayCast` for the box `box` moving by `translation` (a sweep of a box, no
  /// rotation): `fraction` is when it first touches a tight box.
  template <class Callback>
  void boxCast(Aabb box, Vec2 translation, Callback&& callback) const {
    if (!quack::isValid(box)) return;
    castImpl(center(box), translation, extents(box), callback);
  }
  /// The first tight box the ray meets, if any (of boxes met at the same fraction, any one).
  std::optional<BroadPhaseHit> rayCastClosest(Vec2 origin, Vec2 translation) const;
  /// Every tight box the ray meets, sorted by fraction (then by index).
  std::vector<BroadPhaseHit> rayCastAll(Vec2 origin, Vec2 translation) const;
  /// The first tight box the moving box meets, if any (ties: any one).
  std::optional<BroadPhaseHit> boxCastClosest(Aabb box, Vec2 translation) const;

  /// A copy of every record (see BroadPhaseRecords), for saving.
  BroadPhaseRecords records() const;
  /// A broad phase with `config` holding exactly `records`: the same proxies (ids and
  /// generations), boxes, filters and move buffer, the live proxies inserted into a new
  /// structure in index order. Fails, naming the slot and the field, on arrays of different
  /// lengths, a bad free list, an invalid box, a tight box outside its fat box, a buffered
  /// flag that disagrees with the move buffer or a move-buffer entry beyond the slots.
  static Result<BroadPhase> fromRecords(BroadPhaseConfig config, BroadPhaseRecords records);

  /// Rebuilds the structure from scratch (the tree by binned SAH): after a bulk load.
  void rebuild();
  /// Sizes and quality figures.
  BroadPhaseStats stats() const;
  /// Checks the structure's invariants and that it agrees with the proxy records.
  Status validate() const;

  /// The structure, for tests and tools that need its own interface.
  const DynamicTree* tree() const noexcept { return std::get_if<DynamicTree>(&index_); }

 private:
  using Index = std::variant<DynamicTree, Quadtree, SweepAndPrune, SpatialHash, BruteForce>;
  static constexpr std::uint8_t kStatic = 2;
  static constexpr std::uint8_t kBuffered = 4;  // in the move buffer
  static constexpr std::uint8_t kInPass = 8;    // being paired by the current updatePairs

  struct Record {
    Filter filter;
    std::uint64_t userData = 0;
  };

  // Re-insert a proxy whose fat box has grown past its wanted fat box plus this many margins
  // on a side (after a fast move or a teleport), so stale huge boxes do not linger.
  static constexpr float kShrinkMargins = 4.0f;
  // Displacements are only required to be finite (FLT_MAX passes, NaN and inf fail).
  static constexpr float kMaxDisplacement = 3.402823466e38f;

  // Finite, not inverted and within kMaxCoordinate: six comparisons, all false for NaN.
  bool isAcceptableMove(ProxyId id, Aabb box, Vec2 displacement) const noexcept {
    return isValid(id) && isAcceptableBox(box) && absf(displacement.x) <= kMaxDisplacement &&
           absf(displacement.y) <= kMaxDisplacement;
  }
  static bool isAcceptableBox(Aabb b) noexcept {
    return b.lower.x <= b.upper.x && b.lower.y <= b.upper.y && b.lower.x >= -kMaxCoordinate &&
           b.lower.y >= -kMaxCoordinate && b.upper.x <= kMaxCoordinate &&
           b.upper.y <= kMaxCoordinate;
  }

  explicit BroadPhase(BroadPhaseConfig config);
  Error rejectMove(ProxyId id, Aabb box, Vec2 displacement) const;
  void reinsert(std::uint32_t proxy, Aabb wanted);
  Aabb wantedBox(std::uint32_t p, Aabb box, Vec2 displacement) const noexcept {
    return sweep(inflate(box, margins_[p]), config_.displacementScale * displacement);
  }
  // The fat box still holds the tight box and is not much larger than needed.
  bool staysInPlace(std::uint32_t p, Aabb box, Vec2 displacement) const noexcept {
    const Aabb fat = fat_[p];
    return contains(fat, box) &&
           contains(inflate(wantedBox(p, box, displacement), kShrinkMargins * margins_[p]), fat);
  }
  Status checkId(ProxyId id, const char* function) const;
  void buffer(std::uint32_t proxy);
  void addPair(std::uint32_t a, std::uint32_t b, std::vector<ProxyPair>& pairs) const;
  // updatePairs in parts: the move buffer deduplicated and flagged; the pairs by a sweep
  // (true) or nothing (false: query the moved proxies); the pairs of moved proxies
  // [first, last); the flags cleared.
  void beginPairPass();
  bool sweepPairPass(std::vector<ProxyPair>& pairs);
  void queryMoved(std::size_t first, std::size_t last, std::vector<ProxyPair>& pairs) const;
  void endPairPass();
  ProxyId idOf(std::uint32_t proxy) const noexcept { return {proxy, ids_.generation(proxy)}; }

  template <class Callback>
  void castImpl(Vec2 origin, Vec2 translation, Vec2 inflation, Callback& callback) const;

  BroadPhaseConfig config_;
  Index index_;
  std::vector<Aabb> fat_;
  std::vector<Aabb> tight_;
  std::vector<float> margins_;  // per slot: the proxy's margin
  std::vector<std::uint8_t> flags_;
  std::vector<Record> records_;
  IdPool ids_;  // slots, generations and the free list of proxies
  std::vector<std::uint32_t> moveBuffer_;
  PairFilterFn pairFilter_ = nullptr;
  void* pairFilterContext_ = nullptr;
  bool enlargeMoves_ = false;  // the tree enlarges instead of re-inserting (beginPairPass)
};

template <class ParallelFor>
void BroadPhase::updatePairs(std::vector<ProxyPair>& pairs,
                             std::vector<std::vector<ProxyPair>>& parts,
                             ParallelFor&& parallelFor) {
  pairs.clear();
  beginPairPass();
  if (!sweepPairPass(pairs)) {
    for (std::vector<ProxyPair>& part : parts)
      part.clear();
    parallelFor(moveBuffer_.size(), [&](std::size_t begin, std::size_t end, std::size_t part) {
      queryMoved(begin, end, parts[part]);
    });
    for (const std::vector<ProxyPair>& part : parts)
      pairs.insert(pairs.end(), part.begin(), part.end());
  }
  endPairPass();
}

template <class Visit>
void BroadPhase::queryAabb(Aabb box, Visit&& visit) const {
  if (!quack::isValid(box)) return;
  std::visit(
      [&](const auto& index) {
        index.query(box, [&](std::uint32_t p) {
          if (!overlaps(tight_[p], box)) return true;
          return static_cast<bool>(visit(idOf(p), records_[p].userData));
        });
      },
      index_);
}

template <class Callback>
void BroadPhase::castImpl(Vec2 origin, Vec2 translation, Vec2 inflation, Callback& callback) const {
  if (!isFinite(origin) || !isFinite(translation) || !isFinite(inflation)) return;
  std::visit(
      [&](const auto& index) {
        index.rayCast(
            origin, translation, 1.0f, inflation, [&](std::uint32_t p, float maxFraction) -> float {
              const Aabb grown{tight_[p].lower - inflation, tight_[p].upper + inflation};
              const AabbRayHit h = quack::rayCast(grown, origin, translation, maxFraction);
              if (!h.hit) return maxFraction;
              return static_cast<float>(callback(idOf(p), records_[p].userData, h.fraction));
            });
      },
      index_);
}

}  // namespace quack
