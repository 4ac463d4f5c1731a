#pragma once
// The continuous phase: one part of the world. Swept boxes for fast bodies, time of impact
// against what they sweep past, and the time-ordered handling of the impacts (the seeds'
// execution phase). docs/world.md, "Continuous collision", explains the choices.

#include <cstdint>
#include <vector>

#include "quack/math/aabb.hpp"
#include "quack/math/sweep.hpp"

namespace quack {
struct WorldDef;
class BroadPhase;
}  // namespace quack

namespace quack::detail {

class BodyStore;
class EventDispatcher;
class GhostEdges;

// One fast body: what remains of its motion is `sweep`, which covers the step's fractions
// [t0, 1].
struct FastBody {
  std::uint32_t body = 0;
  Sweep sweep;
  float t0 = 0.0f;
  int events = 0;
  std::uint32_t stamp = 0;  // bumped whenever the sweep changes; older queue entries are stale
  Aabb box;                 // sweptBox of the sweep
  float bestTime = 2.0f;    // time of its queued impact (2: none)
  std::uint32_t bestBody = 0xffffffffu;  // the body that impact is with
};

// The earliest impact found along a fast body's sweep.
struct ToiCandidate {
  float time = 0.0f;  // fraction of the step
  std::uint32_t fast = 0, stamp = 0;
  std::uint32_t shapeA = 0, shapeB = 0;  // fast body's shape, the other
  Vec2 point, normal;
  bool stop = false;  // already touching at the start of a continued sweep: stop there
};

class ContinuousPhase {
 public:
  /// Handles the impacts of the bodies the solver flagged fast, in time order.
  /// `awake`: a bit per body index for the bodies that moved (IslandSet::awakeBits).
  void run(const WorldDef& def, BodyStore& store, const std::vector<std::uint64_t>& awake,
           BroadPhase& broadPhase, const GhostEdges& edges, EventDispatcher& events, float dt);

  /// Dynamic bodies a bullet pushed in the last run (some may be asleep: the world wakes
  /// them).
  std::vector<std::uint32_t> pushed;

 private:
  Aabb sweptBox(const BodyStore& store, const FastBody& f) const;
  bool findImpact(const BodyStore& store, const BroadPhase& broadPhase, const GhostEdges& edges,
                  std::uint32_t fast, bool continuation, ToiCandidate& best,
                  std::uint32_t onlyBody = 0xffffffffu);

  std::vector<FastBody> fast_;
  std::vector<ToiCandidate> queue_;        // a binary heap, earliest on top
  std::vector<std::uint32_t> candidates_;  // shapes near one sweep
};

}  // namespace quack::detail
