#pragma once
// The continuous phase: one part of the world. Swept boxes for fast bodies, time of impact
// between sweeps (against static and kinematic shapes, and between moving bodies), and the
// time-ordered handling of the impacts (the execution phase of docs/background.md).
// docs/continuous.md, "In the world", explains the choices.

#include <cstdint>
#include <span>
#include <vector>

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
  // What one search gathers before it tests: shapes and participants near the sweep.
  struct SearchScratch {
    std::vector<std::uint32_t> candidates;  // shapes near one sweep
    std::vector<std::uint32_t> near;        // participants near one sweep
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
  // A participant's swept box changed (or it is new): it leaves the sorted index for the
  // short list that queries scan in full.
  void markMoved(std::uint32_t index);

  // Two dynamic bodies, neither a bullet, that touch at the start of the step (a manifold
  // with points, from the contact set), or of which one is anchored by a joint: the
  // contact solver holds them (see findImpactWith).
  bool heldBySolver(const BodyStore& store, std::uint32_t shapeA, std::uint32_t shapeB) const;
  // The body has a joint to a static or kinematic body, or a mouse joint.
  bool anchoredByJoint(const BodyStore& store, std::uint32_t body) const;
  const ContactSet* contacts_ = nullptr;  // during run
  const JointSet* joints_ = nullptr;      // during run
  std::vector<FastBody> fast_;
  std::vector<std::uint32_t> participantOf_;  // per body index: its FastBody, or kNoParticipant
  // The participants' swept boxes, indexed for overlap queries: sorted by lower x at the
  // start of the phase (a query scans the lower-x window [lower - widest, upper]); those
  // whose boxes changed since are in moved_ and scanned one by one. A tree would spend a
  // large share of the phase on inserts (1,000 bullets); one sort is cheap.
  std::vector<std::uint32_t> sorted_;
  std::vector<float> sortedLower_;  // lower x of sorted_'s boxes, for the binary search
  std::vector<Aabb> sortedBoxes_;   // sorted_'s boxes as they were sorted, scanned in place
  std::vector<std::uint32_t> moved_;
  std::vector<std::uint8_t> inMoved_;
  float widest_ = 0.0f;                    // widest box in sorted_, metres
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
  static constexpr std::uint32_t kMaxListedShapes = 64;
  std::vector<ListedShape> listedShapes_;
  bool listed_ = false;
};

}  // namespace quack::detail
