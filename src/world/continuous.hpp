#pragma once
// The continuous phase: one part of the world. Swept boxes for fast bodies, time of impact
// between sweeps (against static and kinematic shapes, and between moving bodies), and the
// time-ordered handling of the impacts (the execution phase of docs/background.md).
// docs/continuous.md, "In the world", explains the choices.

#include <cstdint>
#include <span>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "quack/math/aabb.hpp"
#include "quack/math/sweep.hpp"

namespace quack {
struct WorldDef;
class BroadPhase;
}  // namespace quack

namespace quack::detail {

class BodyStore;
class ContactSet;
class JointSet;
class EventDispatcher;
class GhostEdges;
class TaskRunner;
struct StepContext;

inline constexpr std::uint32_t kNoParticipant = 0xffffffffu;

// A body whose motion the phase follows: a fast body from the start, or a dynamic body from
// the time an impact set it moving. What remains of its motion is `sweep`, which covers the
// step's fractions [t0, 1].
struct FastBody {
  std::uint32_t body = 0;
  Sweep sweep;
  float t0 = 0.0f;
  int events = 0;
  bool searching = true;    // looks for impacts along its sweep (fast bodies, and bodies set
                            // moving by an impact, until stopped or capped)
  std::uint32_t stamp = 0;  // bumped whenever the sweep changes; older queue entries are stale
  Aabb box;                 // sweptBox of the sweep
  float bestTime = 2.0f;    // time of its queued impact (2: none)
  std::uint32_t bestBody = 0xffffffffu;  // the body that impact is with
  // The velocity already in the sweep's end pose: zero for a fast body (its sweep is its
  // motion); for a body that stood at its end-of-step pose, the solver's velocity, so that
  // only what impacts add moves it further.
  Vec2 baseV;
  float baseW = 0.0f;
  bool anchored = false;  // anchoredByJoint, found once when it joins the phase
};

// The earliest impact found along a participant's sweep.
struct ToiCandidate {
  float time = 0.0f;  // fraction of the step
  std::uint32_t fast = 0, stamp = 0;
  // The other body's participant and its stamp when that body is followed too, else
  // kNoParticipant (it stands still: static, kinematic, or not yet set moving).
  std::uint32_t other = kNoParticipant, otherStamp = 0;
  std::uint32_t shapeA = 0, shapeB = 0;  // the participant's shape, the other
  Vec2 point, normal;
  bool stop = false;  // already touching at the start of a continued sweep: stop there
};

// Boxes with ids, indexed for overlap queries: a uniform grid of square cells hashed into
// buckets (one array, filled by counting), rebuilt rather than updated. A box covering more
// than kMaxCells cells is kept in a list that every query scans. The cell side is about the
// typical box, so a box covers a few cells. Queries report each overlapping box once, in no
// particular order (callers must not depend on it).
class BoxGrid {
 public:
  static constexpr std::int64_t kMaxCells = 16;
  struct Item {
    Aabb box;
    std::uint32_t id;
  };
  void build(std::span<const Item> items);
  std::size_t size() const noexcept { return count_; }
  // visit(id) for every item whose box overlaps `box`, once each.
  template <class Visit>
  void query(Aabb box, Visit&& visit) const {
    const std::int32_t x0 = cellOf(box.lower.x), x1 = cellOf(box.upper.x);
    const std::int32_t y0 = cellOf(box.lower.y), y1 = cellOf(box.upper.y);
    const std::int64_t cells = (std::int64_t{x1} - x0 + 1) * (std::int64_t{y1} - y0 + 1);
    if (cells > static_cast<std::int64_t>(entryCount_ / 2 + 16)) {
      // More cells than entries: scan the items instead (each once).
      for (const Item& item : all_)
        if (overlaps(item.box, box)) visit(item.id);
      return;
    }
    for (const Item& item : large_)
      if (overlaps(item.box, box)) visit(item.id);
    for (std::int32_t y = y0; y <= y1; ++y) {
      for (std::int32_t x = x0; x <= x1; ++x) {
        const std::uint32_t b = bucketOf(x, y);
        // The tests as one mask: an entry is another cell in the same bucket, a repeat of
        // a box (each item is taken once, from the first cell that both its box and the
        // query cover) or a box that misses the query in proportions no branch predicts.
        // Dense piles scan several entries a cell (the spinner's about 43 a query, to
        // report 9): as branches, this scan took about a tenth of the spinner's step. Four
        // entries at a time where SSE2 is there, reported in the order of a scan.
        const std::uint32_t repeat = (x != x0 ? 1u : 0u) | (y != y0 ? 2u : 0u);
        std::uint32_t k = bucketStart_[b];
        const std::uint32_t end = bucketStart_[b + 1];  // a multiple of four past k
#if defined(__SSE2__)
        const __m128 qlx = _mm_set1_ps(box.lower.x), qly = _mm_set1_ps(box.lower.y);
        const __m128 qux = _mm_set1_ps(box.upper.x), quy = _mm_set1_ps(box.upper.y);
        const __m128i cx = _mm_set1_epi32(x), cy = _mm_set1_epi32(y);
        const __m128i rep = _mm_set1_epi32(static_cast<std::int32_t>(repeat));
        for (; k + 4 <= end; k += 4) {
          const __m128 apart = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(_mm_loadu_ps(&lowerX_[k]), qux),
                                                   _mm_cmpgt_ps(_mm_loadu_ps(&lowerY_[k]), quy)),
                                         _mm_or_ps(_mm_cmpgt_ps(qlx, _mm_loadu_ps(&upperX_[k])),
                                                   _mm_cmpgt_ps(qly, _mm_loadu_ps(&upperY_[k]))));
          const __m128i sameCell = _mm_and_si128(
              _mm_cmpeq_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(&cellX_[k])), cx),
              _mm_cmpeq_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(&cellY_[k])), cy));
          const __m128i firstHere = _mm_cmpeq_epi32(
              _mm_andnot_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(&first_[k])), rep),
              _mm_setzero_si128());
          const __m128 keep =
              _mm_andnot_ps(apart, _mm_castsi128_ps(_mm_and_si128(sameCell, firstHere)));
          for (auto m = static_cast<std::uint32_t>(_mm_movemask_ps(keep)); m != 0; m &= m - 1)
            visit(ids_[k + static_cast<std::uint32_t>(__builtin_ctz(m))]);
        }
#endif
        for (; k < end; ++k) {
          const auto sameCell =
              static_cast<unsigned>(cellX_[k] == x) & static_cast<unsigned>(cellY_[k] == y);
          const auto firstHere = static_cast<unsigned>((repeat & ~first_[k]) == 0);
          const auto apart = static_cast<unsigned>(lowerX_[k] > box.upper.x) |
                             static_cast<unsigned>(lowerY_[k] > box.upper.y) |
                             static_cast<unsigned>(box.lower.x > upperX_[k]) |
                             static_cast<unsigned>(box.lower.y > upperY_[k]);
          if ((sameCell & firstHere & ~apart) != 0) visit(ids_[k]);
        }
      }
    }
  }

 private:
  std::int32_t cellOf(float v) const noexcept {
    // floor(v / cell), clamped well inside int32 so that a range's size always fits in 64
    // bits. Clamping first gives the same integer (the bounds are integers and floor is
    // monotonic), and a clamped value floors by truncation and one correction: about a third
    // of std::floor's instructions without SSE4.1, for four calls a query and a box.
    float c = v * inverseCell_;
    c = c < -1.0e9f ? -1.0e9f : (c > 1.0e9f ? 1.0e9f : c);
    const auto t = static_cast<std::int32_t>(c);
    return t - static_cast<std::int32_t>(c < static_cast<float>(t));
  }
  std::uint32_t bucketOf(std::int32_t x, std::int32_t y) const noexcept {
    return ((static_cast<std::uint32_t>(x) * 0x9E3779B1u) ^
            (static_cast<std::uint32_t>(y) * 0x85EBCA77u)) &
           bucketMask_;
  }
  struct CellRange {
    std::int32_t x0, x1, y0, y1;  // x1 < x0: in large_ (no cells)
  };
  std::vector<CellRange> ranges_;  // build's per-item cells, found once
  // Bucket b's entries: [start[b], start[b + 1]), padded to a multiple of four (see build).
  std::vector<std::uint32_t> bucketStart_;
  std::vector<std::uint32_t> cursor_;  // build's filling position per bucket
  std::size_t entryCount_ = 0;         // entries, not counting the padding
  // The entries, one per cell a box covers, as columns (four at a time in a query): the
  // box, its item's id, the cell, and bit 0 / bit 1 set when the cell is in the box's first
  // column / row.
  std::vector<float> lowerX_, lowerY_, upperX_, upperY_;
  std::vector<std::uint32_t> ids_;
  std::vector<std::int32_t> cellX_, cellY_;
  std::vector<std::uint32_t> first_;
  std::vector<Item> large_;
  std::vector<Item> all_;
  std::uint32_t bucketMask_ = 0;
  std::size_t count_ = 0;
  float inverseCell_ = 1.0f;
};

class ContinuousPhase {
 public:
  /// Handles the impacts of the bodies the solver flagged fast, in time order.
  /// `awake`: a bit per body index for the bodies that moved (IslandSet::awakeBits).
  /// The first search of every fast body runs on the workers (each reads the step's state
  /// and writes only its own result); the queue is filled in participant order.
  /// `contacts`: the step's contacts, whose touching state (from the start of the step)
  /// says which pairs of dynamic bodies the contact solver already holds.
  /// Returns the dynamic bodies an impact set moving (some may be asleep: the world wakes
  /// them), valid until the next run.
  std::span<const std::uint32_t> run(StepContext& step, const std::vector<std::uint64_t>& awake,
                                     const GhostEdges& edges, const ContactSet& contacts);

  /// Figures of the last run (World::ContinuousStats).
  struct Stats {
    std::size_t fastBodies = 0;
    std::size_t toiSearches = 0;
  };
  const Stats& stats() const noexcept { return stats_; }

 private:
  Aabb sweptBox(const BodyStore& store, const FastBody& f) const;
  std::uint32_t addParticipant(BodyStore& store, std::uint32_t body, bool searching);
  // A participant near a sweep that passed the pair rules, and both sweeps over the part
  // of the step they share (from `from` on).
  struct NearSweep {
    std::uint32_t participant;
    float from;
    Sweep mine, theirs;
  };
  // What one search gathers before it tests: shapes and participants near the sweep.
  struct SearchScratch {
    std::vector<std::uint32_t> candidates;  // shapes near one sweep
    std::vector<std::uint32_t> near;        // participants near one sweep
    std::vector<NearSweep> passing;         // those of `near` that pass the pair rules
    std::size_t toiSearches = 0;            // computeToi calls, for stats_
  };
  Stats stats_;
  std::vector<std::uint32_t> pushed_;  // what run returns
  bool findImpact(const BodyStore& store, const BroadPhase& broadPhase, const GhostEdges& edges,
                  std::uint32_t fast, bool continuation, ToiCandidate& best,
                  std::uint32_t onlyBody = 0xffffffffu) {
    return findImpactWith(scratch_[0], store, broadPhase, edges, fast, continuation, best,
                          onlyBody);
  }
  bool findImpactWith(SearchScratch& scratch, const BodyStore& store, const BroadPhase& broadPhase,
                      const GhostEdges& edges, std::uint32_t fast, bool continuation,
                      ToiCandidate& best, std::uint32_t onlyBody) const;

  // The participants whose swept boxes overlap `box` (not in any order).
  template <class Visit>
  void queryParticipants(Aabb box, Visit&& visit) const;
  // A participant's swept box changed (or it is new): it leaves the grid for the short
  // list that queries scan in full.
  void markMoved(std::uint32_t index);

  // Two dynamic bodies, neither a bullet, that touch at the start of the step (a manifold
  // with points, from the contact set), or of which one is anchored by a joint: the
  // contact solver holds them (see findImpactWith). Shape A's body is participant `fastA`;
  // shape B's is participant `fastB`, or kNoParticipant.
  bool heldBySolver(const BodyStore& store, std::uint32_t shapeA, std::uint32_t shapeB,
                    std::uint32_t fastA, std::uint32_t fastB) const;
  // The body has a joint to a static or kinematic body, or a mouse joint.
  bool anchoredByJoint(const BodyStore& store, std::uint32_t body) const;
  const ContactSet* contacts_ = nullptr;  // during run
  const JointSet* joints_ = nullptr;      // during run
  bool sweepDynamicPairs_ = true;         // WorldDef::sweepDynamicPairs, during run
  std::vector<FastBody> fast_;
  std::vector<std::uint32_t> participantOf_;  // per body index: its FastBody, or kNoParticipant
  // The participants' swept boxes, indexed for overlap queries: a BoxGrid built at the
  // start of the phase and again whenever many boxes have changed since (buildIndex); those
  // in moved_ (changed since the last build) are scanned one by one. An index sorted along x
  // scanned a window as wide as the widest box (a 40 m paddle's sweep: every participant)
  // and a whole column of falling bodies.
  void buildIndex();
  std::vector<std::uint32_t> sorted_;  // participants by swept box lower x (first searches)
  std::vector<std::uint64_t> sortKeys_, sortScratch_;  // sortByLowerX's keys, buffer
  void sortByLowerX();
  BoxGrid grid_;  // participants [0, indexed_) as they were at the last build
  std::vector<BoxGrid::Item> gridItems_;
  std::uint32_t indexed_ = 0;
  bool indexBuilt_ = false;
  std::vector<BoxGrid::Item> moved_;       // changed since the build: their boxes now
  std::vector<std::uint32_t> movedSlot_;   // per participant: 1 + its place in moved_, or 0
  std::vector<ToiCandidate> queue_;        // a binary heap, earliest on top
  std::vector<SearchScratch> scratch_{1};  // per worker
  std::vector<ToiCandidate> first_;        // the first searches' results, per participant
  std::vector<std::uint8_t> firstFound_;   // and whether each found one
  std::vector<std::uint32_t> recheck_;     // participants to re-check after an impact
  // Who waits on whom: for each dynamic body, a list (through waitNodes_, newest first) of
  // the participants whose queued impact was with it when queued. An impact that changes the
  // body re-searches those still waiting on it (bestBody) instead of scanning every
  // participant; entries whose participant has since queued another impact are skipped.
  struct WaitNode {
    std::uint32_t participant, body, next;
  };
  std::vector<std::uint32_t> waitHead_;  // per body index: first node, or kNoParticipant
  std::vector<WaitNode> waitNodes_;
  // The shapes of everything that is not a participant when the phase starts (static,
  // kinematic, sleeping and slow bodies) with their broad-phase boxes, when there are at
  // most kMaxListedShapes of them: a search then scans them instead of querying the broad
  // phase, whose tree holds the participants too (a thousand bullets in a walled box spent
  // most of the phase walking tree nodes to find four walls). Empty with listed_ false:
  // the broad phase is queried.
  struct ListedShape {
    std::uint32_t shape;
    Aabb box;
  };
  static constexpr std::uint32_t kMaxListedShapes = 16;
  std::vector<ListedShape> listedShapes_;
  bool listed_ = false;
  // When the participants hold at least half the broad phase's proxies (a churning pile,
  // where nearly every body is fast), the shapes outside them are put in a grid of their
  // tight boxes at the start of the phase, and searches query it instead of the broad
  // phase: the tree's query would find the participants' own neighbours, every one of them
  // skipped. It finds what the tree's query finds (the same tight boxes, the same overlap
  // test), so the answers are the same bits.
  BoxGrid stillGrid_;
  bool stillGridded_ = false;
};

}  // namespace quack::detail
