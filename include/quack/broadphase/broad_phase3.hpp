#pragma once
/// `BroadPhase3`: the 3D broad phase, `BroadPhase`'s counterpart over the two 3D structures
/// (`DynamicTree3` and the loose `Octree`), with the same contract: fat boxes, the move
/// buffer, pair finding, filters, the user pair filter and box and ray queries.
///
/// ```
/// Result<BroadPhase3> made = BroadPhase3::create({.kind = BroadPhase3Kind::tree});
/// BroadPhase3& bp = made.value();
/// ProxyId a = bp.createProxy(box, shapeIndex).value();
/// ... each step: bp.moveProxy(a, newBox, displacement);
/// std::vector<ProxyPair> pairs;
/// bp.updatePairs(pairs);  // candidate pairs of this step
/// ```
///
/// Fat boxes: a proxy's structure box is its tight box grown by `margin` on every side and
/// stretched by `displacementScale` times its last displacement (a prediction of the next
/// one). `moveProxy` re-inserts the proxy only when the tight box leaves the fat box (or the
/// fat box has grown much larger than needed), so a slowly moving proxy costs one
/// containment test a step.
///
/// Pairs: `updatePairs` reports every pair {a, b} such that at least one of a and b was
/// created, re-inserted or touched since the last call, their fat boxes overlap (and, with
/// `checkTightBoxes`, their tight boxes too), they are not both static, their filters
/// accept each other (`shouldCollide`, the 2D filter: it has no dimension) and the user
/// pair filter, if any, agrees. Each pair once, `a.index < b.index`, in an order that
/// depends on the structure. This is Box2D's (and the 2D `BroadPhase`'s) contract: pairs
/// that stayed in contact without re-insertion are not reported again.
///
/// Error policy (as in 2D): a NaN, infinite, inverted or out-of-range box (beyond
/// +-`kMaxCoordinate`), a non-finite displacement, or a null, unknown or stale `ProxyId` is
/// rejected with an `Error` naming the argument, and nothing changes. Queries given NaN input
/// report no hits. Internal invariants are `QUACK_ASSERT`s; `validate()` checks everything.
///
/// Frames and units: all boxes, points and translations are in the world frame, metres.
/// Not thread-safe; queries may run concurrently with each other.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <variant>
#include <vector>

#include "quack/broadphase/broad_phase.hpp"
#include "quack/broadphase/detail/aabb3_ops.hpp"
#include "quack/broadphase/dynamic_tree3.hpp"
#include "quack/broadphase/octree.hpp"
#include "quack/broadphase/proxy.hpp"
#include "quack/core/id_pool.hpp"
#include "quack/core/result.hpp"
#include "quack/math/vec3.hpp"

namespace quack {

/// The two 3D structures, named `tree` and `octree`.
enum class BroadPhase3Kind : std::uint8_t { tree, octree };

/// Every 3D kind, in declaration order.
inline constexpr BroadPhase3Kind kAllBroadPhase3Kinds[] = {BroadPhase3Kind::tree,
                                                           BroadPhase3Kind::octree};

/// The short name of a kind ("tree", "octree").
const char* toString(BroadPhase3Kind kind) noexcept;
/// The kind with that short name, or an error listing the valid names.
Result<BroadPhase3Kind> parseBroadPhase3Kind(std::string_view name);

/// How a `BroadPhase3` is made. Every field has a default that suits boxes of about 1 m.
struct BroadPhase3Config {
  /// The structure: the tree suits most scenes (docs/3d-broad-phase.md has the figures).
  BroadPhase3Kind kind = BroadPhase3Kind::tree;
  /// Metres added to every side of a tight box to make its fat box (>= 0). Larger means fewer
  /// re-insertions but more candidate pairs. 0.1 m, as in 2D, for metre-sized bodies.
  float margin = 0.1f;
  /// The fat box is also stretched by this times the displacement passed to `moveProxy`
  /// (>= 0), so a steadily moving proxy stays inside it longer.
  float displacementScale = 1.0f;
  /// Report a pair only when the tight boxes overlap as well as the fat boxes.
  bool checkTightBoxes = false;
  /// Smallest cell side of the octree, metres, in [kMinCellSize, kMaxCoordinate]: about the
  /// typical fat box size. Unused by the tree.
  float cellSize = 1.0f;
};

/// Size and shape figures of a `BroadPhase3`.
struct BroadPhase3Stats {
  /// Live proxies.
  std::uint32_t proxyCount = 0;
  /// Bytes held by the structure itself (nodes or cells and items).
  std::size_t structureBytes = 0;
  /// Bytes held by the per-proxy records (tight and fat boxes, filters, user data,
  /// generations, move buffer), the same for both structures.
  std::size_t recordBytes = 0;
  /// Tree height, or octree depth.
  int height = 0;
  /// Tree only: sum of internal node surface areas over the root's; 0 for the octree.
  float areaRatio = 0.0f;
};

/// The 3D broad phase (see the top of this file). A value: copies are independent.
/// Every record of a `BroadPhase3` that decides what it reports from now on, slot by slot,
/// as BroadPhaseRecords is for 2D: generations and free slots, tight and fat boxes, kinds,
/// filters, user data and the move buffer; not the structure's own shape, which changes
/// only the order of hits (World3's snapshots sort what depends on order).
struct BroadPhase3Records {
  std::vector<std::uint32_t> generations;  ///< per slot, never 0
  std::vector<std::uint32_t> freeSlots;    ///< in release order (IdPool::freeSlots)
  std::vector<Aabb3> tight, fat;           ///< per slot, world frame
  std::vector<ProxyKind> kinds;            ///< per slot
  std::vector<std::uint8_t> buffered;      ///< per slot: 1 while in the move buffer
  std::vector<Filter> filters;             ///< per slot
  std::vector<std::uint64_t> userData;     ///< per slot
  std::vector<std::uint32_t> moveBuffer;   ///< slots, in order (may hold stale entries)
};

class BroadPhase3 {
 public:
  /// A broad phase using `config`; fails on a non-finite or negative margin or displacement
  /// scale, or a cell size out of range, naming the field.
  static Result<BroadPhase3> create(BroadPhase3Config config = {});

  /// The structure chosen at creation.
  BroadPhase3Kind kind() const noexcept { return config_.kind; }
  /// The configuration given at creation (validated).
  const BroadPhase3Config& config() const noexcept { return config_; }

  /// Adds a proxy for the tight box `box` (world frame). `userData` is returned with pairs
  /// and hits. The new proxy is in the move buffer: its pairs come out of the next
  /// `updatePairs`. Fails on an invalid or out-of-range box.
  Result<ProxyId> createProxy(Aabb3 box, std::uint64_t userData = 0, Filter filter = {},
                              ProxyKind kind = ProxyKind::dynamicProxy);
  /// Removes a proxy. Fails on a null, unknown or stale id.
  Status destroyProxy(ProxyId id);
  /// Gives a proxy its new tight box (world frame) and its displacement since the last move
  /// (metres; stretches the fat box ahead of the motion; zero for a teleport). Returns
  /// whether the proxy was re-inserted (and so buffered for pairs). Fails on a bad id, box or
  /// displacement.
  Result<bool> moveProxy(ProxyId id, Aabb3 box, Vec3 displacement) {
    // The per-proxy-per-step path is inline; every rejection goes out of line.
    if (!isAcceptableMove(id, box, displacement)) return rejectMove(id, box, displacement);
    const std::uint32_t p = id.index;
    tight_[p] = box;
    if (staysInPlace(p, box, displacement)) return false;
    reinsert(p, wantedBox(box, displacement));
    return true;
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
  Aabb3 tightBox(ProxyId id) const;
  /// Precondition `isValid(id)` (asserted): the enlarged box stored in the structure.
  Aabb3 fatBox(ProxyId id) const;
  /// Number of live proxies.
  std::uint32_t proxyCount() const noexcept { return ids_.liveCount(); }

  /// Installs the user pair filter (null removes it); `PairFilterFn` is the 2D one.
  void setPairFilter(PairFilterFn userFilter, void* context) noexcept {
    pairFilter_ = userFilter;
    pairFilterContext_ = context;
  }

  /// Replaces the contents of `pairs` with this step's candidate pairs (see the contract
  /// above) and empties the move buffer.
  void updatePairs(std::vector<ProxyPair>& pairs);
  /// The same pairs, the moved proxies' queries split over threads (as the 2D broad
  /// phase's): `parallelFor(count, body)` must call `body(first, last, part)` over ranges
  /// covering [0, count), with a `part` below parts.size(), no two at once with the same
  /// part; each part's pairs go to parts[part] and then, part after part, to `pairs`. The
  /// pairs are those of updatePairs, in an order that depends on the split (sort them for
  /// determinism), and the user pair filter may be called from several threads at once.
  template <class ParallelFor>
  void updatePairs(std::vector<ProxyPair>& pairs, std::vector<std::vector<ProxyPair>>& parts,
                   ParallelFor&& parallelFor) {
    pairs.clear();
    beginPass();
    for (std::vector<ProxyPair>& part : parts)
      part.clear();
    std::visit(
        [&](const auto& index) {
          parallelFor(moveBuffer_.size(),
                      [&](std::size_t first, std::size_t last, std::size_t part) {
                        queryMoved(index, first, last, parts[part]);
                      });
        },
        index_);
    for (const std::vector<ProxyPair>& part : parts)
      pairs.insert(pairs.end(), part.begin(), part.end());
    endPass();
  }

  /// Calls `visit(ProxyId, userData) -> bool` for each proxy whose tight box overlaps `box`
  /// (touching counts); return false to stop.
  template <class Visit>
  void queryAabb(Aabb3 box, Visit&& visit) const;
  /// Calls `visit(ProxyId, userData) -> bool` for each proxy whose tight box holds `point`.
  template <class Visit>
  void queryPoint(Vec3 point, Visit&& visit) const {
    queryAabb(Aabb3{point, point}, visit);
  }
  /// Casts the ray `origin + t * translation`, t in [0, 1], against the tight boxes. Calls
  /// `callback(ProxyId, userData, fraction) -> float` for boxes it reaches (fraction 0 when
  /// it starts inside), and the return value steers the cast: a value in (0, current max)
  /// clips the ray there, 0 stops, anything else (1, or -1 to ignore the proxy) goes on
  /// unclipped. Return `fraction` for the closest hit, 1 for all hits.
  template <class Callback>
  void rayCast(Vec3 origin, Vec3 translation, Callback&& callback) const {
    castImpl(origin, translation, Vec3{}, callback);
  }
  /// As `rayCast` for the box `box` moving by `translation` (a sweep of a box, no rotation):
  /// `fraction` is when it first touches a tight box.
  template <class Callback>
  void boxCast(Aabb3 box, Vec3 translation, Callback&& callback) const {
    if (!quack::isValid(box)) return;
    castImpl(center(box), translation, extents(box), callback);
  }
  /// The first tight box the ray meets, if any (of boxes met at the same fraction, any one).
  std::optional<BroadPhaseHit> rayCastClosest(Vec3 origin, Vec3 translation) const;
  /// Every tight box the ray meets, sorted by fraction (then by index).
  std::vector<BroadPhaseHit> rayCastAll(Vec3 origin, Vec3 translation) const;

  /// Rebuilds the structure from scratch (the tree by binned SAH): after a bulk load.
  void rebuild();
  /// Sizes and quality figures.
  BroadPhase3Stats stats() const;
  /// Checks the structure's invariants and that it agrees with the proxy records.
  Status validate() const;

  /// A copy of every record (see BroadPhase3Records), for saving.
  BroadPhase3Records records() const;
  /// A broad phase holding exactly these records (its structure built anew). Fails, naming
  /// the slot and the field, on records that do not make a valid broad phase.
  static Result<BroadPhase3> fromRecords(BroadPhase3Config config, BroadPhase3Records records);

  /// The tree, when that is the structure (for tests and tools).
  const DynamicTree3* tree() const noexcept { return std::get_if<DynamicTree3>(&index_); }
  /// The octree, when that is the structure.
  const Octree* octree() const noexcept { return std::get_if<Octree>(&index_); }

 private:
  using Index = std::variant<DynamicTree3, Octree>;
  static constexpr std::uint8_t kStatic = 2;
  static constexpr std::uint8_t kBuffered = 4;  // in the move buffer
  static constexpr std::uint8_t kInPass = 8;    // being paired by the current updatePairs

  struct Record {
    Filter filter;
    std::uint64_t userData = 0;
  };

  // updatePairs' steps: the move buffer deduplicated and marked, each moved proxy's query
  // (read-only: may run on several threads), the marks and the buffer cleared.
  void beginPass();
  void endPass();
  template <class Index>
  void queryMoved(const Index& index, std::size_t first, std::size_t last,
                  std::vector<ProxyPair>& pairs) const {
    for (std::size_t i = first; i < last; ++i) {
      const std::uint32_t m = moveBuffer_[i];
      index.query(fat_[m], [&](std::uint32_t o) {
        // When both moved, the pair is reported from the lower index only.
        if (o == m || ((flags_[o] & kInPass) != 0 && o < m)) return true;
        addPair(m, o, pairs);
        return true;
      });
    }
  }

  // Re-insert a proxy whose fat box has grown past its wanted fat box plus this many margins
  // on a side (after a fast move or a teleport), so stale huge boxes do not linger (2D's).
  static constexpr float kShrinkMargins = 4.0f;
  // Displacements are only required to be finite (FLT_MAX passes, NaN and inf fail).
  static constexpr float kMaxDisplacement = 3.402823466e38f;

  // Finite, not inverted and within kMaxCoordinate: nine comparisons, all false for NaN.
  bool isAcceptableMove(ProxyId id, Aabb3 box, Vec3 d) const noexcept {
    return isValid(id) && isAcceptableBox(box) && absf(d.x) <= kMaxDisplacement &&
           absf(d.y) <= kMaxDisplacement && absf(d.z) <= kMaxDisplacement;
  }
  static bool isAcceptableBox(Aabb3 b) noexcept {
    return b.lower.x <= b.upper.x && b.lower.y <= b.upper.y && b.lower.z <= b.upper.z &&
           b.lower.x >= -kMaxCoordinate && b.lower.y >= -kMaxCoordinate &&
           b.lower.z >= -kMaxCoordinate && b.upper.x <= kMaxCoordinate &&
           b.upper.y <= kMaxCoordinate && b.upper.z <= kMaxCoordinate;
  }

  explicit BroadPhase3(BroadPhase3Config config);
  Error rejectMove(ProxyId id, Aabb3 box, Vec3 displacement) const;
  void reinsert(std::uint32_t proxy, Aabb3 wanted);
  Aabb3 wantedBox(Aabb3 box, Vec3 displacement) const noexcept {
    return detail::sweep3(detail::inflate3(box, config_.margin),
                          config_.displacementScale * displacement);
  }
  // The fat box still holds the tight box and is not much larger than needed.
  bool staysInPlace(std::uint32_t p, Aabb3 box, Vec3 displacement) const noexcept {
    const Aabb3 fat = fat_[p];
    return contains(fat, box) &&
           contains(detail::inflate3(wantedBox(box, displacement), kShrinkMargins * config_.margin),
                    fat);
  }
  Status checkId(ProxyId id, const char* function) const;
  void buffer(std::uint32_t proxy);
  void addPair(std::uint32_t a, std::uint32_t b, std::vector<ProxyPair>& pairs) const;
  ProxyId idOf(std::uint32_t proxy) const noexcept { return {proxy, ids_.generation(proxy)}; }

  template <class Callback>
  void castImpl(Vec3 origin, Vec3 translation, Vec3 inflation, Callback& callback) const;

  BroadPhase3Config config_;
  Index index_;
  std::vector<Aabb3> fat_;
  std::vector<Aabb3> tight_;
  std::vector<std::uint8_t> flags_;
  std::vector<Record> records_;
  IdPool ids_;  // slots, generations and the free list of proxies
  std::vector<std::uint32_t> moveBuffer_;
  PairFilterFn pairFilter_ = nullptr;
  void* pairFilterContext_ = nullptr;
};

template <class Visit>
void BroadPhase3::queryAabb(Aabb3 box, Visit&& visit) const {
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
void BroadPhase3::castImpl(Vec3 origin, Vec3 translation, Vec3 inflation,
                           Callback& callback) const {
  if (!isFinite(origin) || !isFinite(translation) || !isFinite(inflation)) return;
  const detail::Ray3 ray(origin, translation);
  std::visit(
      [&](const auto& index) {
        index.rayCast(
            origin, translation, 1.0f, inflation, [&](std::uint32_t p, float maxFraction) -> float {
              const AabbRayHit h =
                  detail::rayCast3(detail::grow3(tight_[p], inflation), ray, maxFraction);
              if (!h.hit) return maxFraction;
              return static_cast<float>(callback(idOf(p), records_[p].userData, h.fraction));
            });
      },
      index_);
}

}  // namespace quack
