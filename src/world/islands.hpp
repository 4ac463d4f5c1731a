#pragma once
// Islands and sleep: one part of the world (docs/world.md, "Sleeping"). Dynamic bodies
// joined by touching contacts or joints (not sensors; static and kinematic bodies join nothing)
// form islands. Islands merge as contacts begin; a contact that stops touching only marks its
// island, which is split (its connected parts found again) when it wants to sleep, at most
// one island a step. An island whose every body has rested for kTimeToSleep sleeps as a
// whole: its bodies leave the awake set (the solver, the continuous phase and the narrow
// phase skip them) and keep their contacts. Box2D v3's island.c and solver_set.c showed the
// approach (read for understanding; the code is ours).

#include <cstdint>
#include <vector>

#include "quack/core/result.hpp"

namespace quack {
struct WorldDef;
class BroadPhase;
}  // namespace quack

namespace quack::detail {

class BodyStore;
class ContactSet;
class JointSet;
struct ContactChanges;
class TaskRunner;

inline constexpr std::uint32_t kNoIsland = 0xffffffffu;

struct Island {
  std::vector<std::uint32_t> bodies;  // in the order they joined
  bool alive = false;
  bool awake = true;
  bool dirty = false;  // a contact inside stopped touching since the island was last split
};

class IslandSet {
 public:
  /// A new body: a dynamic one gets an island of its own; asleep if `awake` is false (a
  /// kinematic body too).
  void addBody(BodyStore& store, std::uint32_t body, bool awake);
  /// Before a body is released: out of its island, whose other bodies wake.
  void removeBody(BodyStore& store, std::uint32_t body);
  /// Contacts that began or stopped touching since the last call (ContactSet::began and
  /// ended, which it empties): islands merge, waking a sleeping one, or are marked.
  /// The one place contact changes reach the islands: sleeping bodies a new contact found
  /// wake, contacts that began touching merge islands (or wake one touching a static or
  /// kinematic body), and those that ended mark their island for a split.
  void apply(BodyStore& store, const ContactChanges& changes);
  /// Wakes the body: a dynamic body's whole island, a kinematic body itself.
  void wake(BodyStore& store, std::uint32_t body);
  /// Wakes every body touching `body`, and their islands.
  void wakeTouching(BodyStore& store, const ContactSet& contacts, const JointSet& joints,
                    std::uint32_t body);
  /// A joint between bodies a and b (kNoBody: none) was created: both wake, and two dynamic
  /// bodies' islands merge (jointed bodies sleep and wake together).
  void link(BodyStore& store, std::uint32_t a, std::uint32_t b);
  /// A joint between them was destroyed: both wake and their island is marked for a split.
  void unlink(BodyStore& store, std::uint32_t a, std::uint32_t b);
  /// Wakes every body sharing a contact with `body`, touching or not (fat boxes overlap),
  /// and every body whose shapes' tight boxes meet its shapes' fat boxes where they are
  /// now: for a body moved by hand, which may now be inside them (a teleport lands where
  /// it has no contacts yet).
  void wakeNear(BodyStore& store, const BroadPhase& broadPhase, const ContactSet& contacts,
                std::uint32_t body);
  /// Puts the body's island (a kinematic body: the body) to sleep now (World::setAwake).
  void sleepNow(BodyStore& store, const ContactSet& contacts, const JointSet& joints,
                std::uint32_t body);
  /// The end of a step: each awake body's rest time, then islands that rested long enough
  /// go to sleep (splitting one marked island first, if one wants to).
  /// The bodies' rest times are updated on the workers (each writes its own body).
  void updateSleep(const WorldDef& def, BodyStore& store, const ContactSet& contacts,
                   const JointSet& joints, float dt, TaskRunner& tasks);

  /// The bodies that move this step (live, not static, awake), a bit per body index.
  const std::vector<std::uint64_t>& awakeBits() const noexcept { return awakeBits_; }
  bool isAwake(std::uint32_t body) const noexcept {
    return body / 64 < awakeBits_.size() && ((awakeBits_[body / 64] >> (body % 64)) & 1u) != 0;
  }
  std::size_t awakeCount() const noexcept;
  std::size_t islandCount() const noexcept { return islands_.size() - free_.size(); }

  /// Every dynamic body in the island it names, once; island and body agree on sleep; the
  /// awake bits agree with the bodies; bodies touching through a contact share an island.
  Status validate(const BodyStore& store, const ContactSet& contacts, const JointSet& joints) const;

 private:
  friend class SnapshotCodec;  // snapshot.cpp reads and rebuilds every field
  std::uint32_t newIsland();
  void freeIsland(std::uint32_t id);
  void setAwakeBit(std::uint32_t body, bool awake);
  void wakeIsland(BodyStore& store, std::uint32_t id);
  void sleepIsland(BodyStore& store, std::uint32_t id);
  void merge(BodyStore& store, std::uint32_t a, std::uint32_t b);
  /// Finds the island's connected parts again; returns their ids (the first keeps `id`).
  void split(BodyStore& store, const ContactSet& contacts, const JointSet& joints, std::uint32_t id,
             std::vector<std::uint32_t>& parts);

  std::vector<Island> islands_;
  std::vector<std::uint32_t> free_;
  std::vector<std::uint64_t> awakeBits_;
  // Scratch for updateSleep and split, kept to avoid allocating.
  std::vector<std::uint64_t> seenStep_;
  std::vector<float> minRest_, maxRest_;
  std::vector<std::uint32_t> candidates_, parts_, stack_, mark_;
  std::uint64_t step_ = 0;
};

}  // namespace quack::detail
