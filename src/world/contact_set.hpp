#pragma once
// The contact set: one part of the world. It owns the contacts (pairs of shapes whose fat
// boxes overlap), finds new ones from the broad phase's pairs, updates their manifolds and
// touching state each step (with warm-start impulses matched by feature id), and reports
// begin and end to the event dispatcher.

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "pair_map.hpp"
#include "quack/broadphase/broad_phase.hpp"
#include "quack/collision/manifold.hpp"

namespace quack {
struct WorldDef;
}

namespace quack::detail {

class BodyStore;
class EventDispatcher;
class GhostEdges;
class TaskRunner;
struct StepContext;

/// Two bodies, by index.
struct BodyPair {
  std::uint32_t a, b;
};

/// What the contact set's work changed for the islands (IslandSet::apply consumes it):
/// bodies whose contact began or stopped touching (not sensors), and sleeping bodies a new
/// contact found with nothing awake in it (static geometry created or moved onto them),
/// to be woken.
struct ContactChanges {
  std::vector<BodyPair> began, ended;
  std::vector<std::uint32_t> toWake;
};

struct Contact {
  bool alive = false;
  bool touching = false;
  bool sensor = false;  // shapeA is the sensor
  std::uint32_t shapeA = 0, shapeB = 0;
  std::uint32_t bodyA = 0, bodyB = 0;  // the shapes' bodies, so the step's walks skip the shapes
  // The shapes' proxies (fixed for the contact's life: a shape's proxy is made again only
  // after its contacts are destroyed), so that the narrow phase tests the fat boxes and
  // keeps a recycled manifold without reading the shape records.
  ProxyId proxyA, proxyB;
  ManifoldFn fn = nullptr;
  float friction = 0.0f, restitution = 0.0f;
  Manifold manifold;
  // The accumulated impulses are in ContactSet::impulses.
  // Contact recycling (docs/world.md, "Contact recycling and point order"). When the manifold was
  // last computed: the bodies' transforms, and each point as a point fixed on A and one
  // fixed on B (body frames, from each body's origin) with its separation then. While the
  // bodies stay near that relative pose the manifold is kept: the normal as it was (world
  // frame), the points where those body points have moved, the separation updated by the
  // points' relative motion along the normal.
  // The solver then uses the points' arms as they were when the manifold was computed
  // (Contact::recycled), not as the bodies have turned since.
  bool recycleValid = false;
  bool recycled = false;  // this step's manifold is the recycled one
  Transform cachedA, cachedB;
  Vec2 localA[kMaxManifoldPoints], localB[kMaxManifoldPoints];
  float baseSeparation[kMaxManifoldPoints] = {};
};

/// Sorts pairs by (a.index, b.index), the order the contact set creates contacts in
/// whichever broad phase found them. Equal to std::sort by that key; by radix when there
/// are many (`scratch` is its second buffer).
void sortPairs(std::vector<ProxyPair>& pairs, std::vector<ProxyPair>& scratch);

/// What preparing a touching contact's constraint reads, written by the narrow phase in
/// contact order while it has the contact and both bodies at hand: the solver then reads
/// this short record (two cache lines) for each lane instead of the contact record and both
/// body records (nine lines, in no order: a fifth of a pyramid step went to waiting for
/// them). Arms run from each centre of mass to the point (world axes); baseSeparation is
/// the separation less the arms' offset along the normal. Valid in the step whose narrow
/// phase wrote it (`stamp`, ContactSet::simStamp); a contact the narrow phase skipped
/// (asleep until its island woke after the narrow phase, or restored from a snapshot) is
/// prepared from its records through the same function, so the two paths give the same bits.
struct ContactSim {
  std::uint64_t stamp = 0;
  Vec2 normal;
  float friction = 0.0f, restitution = 0.0f;
  int pointCount = 0;
  struct Point {
    Vec2 rA, rB;
    float baseSeparation = 0.0f;
    float normalImpulse = 0.0f, tangentImpulse = 0.0f;
  };
  Point points[kMaxManifoldPoints];
};

/// A contact's accumulated impulses per manifold point, for warm starting (matched by id).
/// Kept beside the contact records, by contact index: the solver writes them back every
/// step in lane order, and 16 bytes a contact stay in cache where the 200-byte records do
/// not (many pyramids, 58,000 contacts: 0.9 MB against 12 MB).
struct ContactImpulses {
  float normal[kMaxManifoldPoints] = {};
  float tangent[kMaxManifoldPoints] = {};
};

/// Fills `sim` from the contact, its impulses and its bodies (centres of mass where the
/// step begins).
void fillContactSim(ContactSim& sim, const Contact& c, const ContactImpulses& impulses,
                    Vec2 centerA, Vec2 localCenterA, Vec2 centerB, Vec2 localCenterB);

/// The recycling reference of a freshly computed manifold (localA, localB, baseSeparation)
/// from the manifold and the poses it was computed at (cachedA, cachedB): the narrow phase
/// sets it so, and a snapshot re-derives it so (snapshot.cpp), bit for bit.
void deriveRecycleReference(Contact& c);

/// What the step's walks over every contact read (which contacts the narrow phase and the
/// solver take): 12 bytes of a contact's 200, kept beside the contacts so that the walks
/// read a few hundred kilobytes, not the whole set twice a step.
struct ContactHead {
  std::uint32_t bodyA = 0, bodyB = 0;
  bool alive = false, touching = false, sensor = false;
};

class ContactSet {
 public:
  std::vector<Contact> contacts;          // live where Contact::alive
  std::vector<ContactImpulses> impulses;  // by contact index (ContactImpulses)
  /// The narrow phase's sims (ContactSim), where simIndex says: a contact that the
  /// solver's last step put in lane L writes lane L's record, so that preparing, which
  /// walks the lanes in order, reads this array nearly in order (the lanes change little
  /// from step to step); any other contact writes past the lanes, by its index.
  std::vector<ContactSim> sims;
  /// Where contact `ci`'s sim lies in `sims`.
  std::size_t simIndex(std::uint32_t ci) const noexcept {
    const std::uint32_t lane = ci < simLane_.size() ? simLane_[ci] : kNoSimLane;
    return lane != kNoSimLane ? lane : simLanes_ + ci;
  }
  /// The solver's lanes of this step, for the next step's narrow phase: touching[k] went to
  /// lane lanes[k] of laneCount. Any assignment works (the stamp says whether a sim is
  /// current); each lane holds one contact, so no two contacts share a record.
  void placeSims(std::span<const std::uint32_t> touching, std::span<const std::uint32_t> lanes,
                 std::size_t laneCount);
  /// By contact index: each contact's ContactHead, kept equal to the contact's fields.
  const std::vector<ContactHead>& heads() const noexcept { return heads_; }
  /// Rebuilds the heads from the contacts (after a snapshot is restored).
  void rebuildHeads();
  /// The stamp of this step's narrow phase: a sim with it is current.
  std::uint64_t simStamp() const noexcept { return simStamp_; }

  /// What findNew, update and destroy changed since clearChanges (the world hands it to
  /// the islands, then clears it; kept between steps, so a warm step allocates nothing).
  const ContactChanges& changes() const noexcept { return changes_; }
  void clearChanges() noexcept {
    changes_.began.clear();
    changes_.ended.clear();
    changes_.toWake.clear();
  }

  std::size_t count() const noexcept { return count_; }

  /// The contacts with an awake body in them (the only ones the narrow phase and the
  /// solver look at), from the awake bodies' bits (IslandSet::awakeBits). When most bodies
  /// are awake it is simply every contact, which is cheaper than marking them.
  void markAwake(const BodyStore& store, const std::vector<std::uint64_t>& awakeBodies,
                 std::size_t awakeCount, std::size_t bodyCount);
  /// Calls f(index) for every contact markAwake chose, in index order (some may be dead).
  template <class F>
  void forEachAwake(F f) const {
    if (allAwake_) {
      for (std::uint32_t i = 0; i < contacts.size(); ++i)
        f(i);
      return;
    }
    for (std::size_t w = 0; w < awake_.size(); ++w)
      for (std::uint64_t bits = awake_[w]; bits != 0; bits &= bits - 1)
        f(static_cast<std::uint32_t>(w * 64 + static_cast<std::size_t>(__builtin_ctzll(bits))));
  }
  /// forEachAwake in words of 64 contact indices: the words to split among workers, and
  /// f(index) for the chosen contacts of words [first, last), in index order.
  int awakeWordCount() const noexcept {
    return static_cast<int>(allAwake_ ? (contacts.size() + 63) / 64 : awake_.size());
  }
  template <class F>
  void forEachAwakeIn(int first, int last, F f) const {
    for (auto w = static_cast<std::size_t>(first); w < static_cast<std::size_t>(last); ++w) {
      if (allAwake_) {
        const std::size_t end = std::min(contacts.size(), (w + 1) * 64);
        for (std::size_t i = w * 64; i < end; ++i)
          f(static_cast<std::uint32_t>(i));
      } else {
        for (std::uint64_t bits = awake_[w]; bits != 0; bits &= bits - 1)
          f(static_cast<std::uint32_t>(w * 64 + static_cast<std::size_t>(__builtin_ctzll(bits))));
      }
    }
  }
  std::size_t touchingCount() const noexcept;
  /// The contact of a pair of shapes, if any (index into `contacts`).
  const std::uint32_t* find(std::uint32_t shapeA, std::uint32_t shapeB) const;

  /// New contacts from the broad phase's new pairs, in an order that does not depend on
  /// the structure.
  void findNew(StepContext& step);
  /// The narrow phase: manifolds and touching state of every contact; contacts whose fat
  /// boxes parted are destroyed. Begin and end events go to `events`. The manifolds are
  /// computed on the workers; what follows from them is applied in contact order.
  /// `awakeBodies`: a bit per body index for the awake bodies (IslandSet::awakeBits).
  void update(StepContext& step, const GhostEdges& edges,
              const std::vector<std::uint64_t>& awakeBodies);
  /// A body was moved by hand (setTransform): its contacts compute their manifolds anew.
  void forgetPoses(const BodyStore& store, std::uint32_t body);
  /// Every contact computes its manifold anew in the next update.
  void forgetAllPoses() noexcept {
    for (Contact& c : contacts)
      c.recycleValid = false;
  }
  /// Removes a contact (from its shapes' lists too); a touching one reports its end to
  /// `events` when `emitEnd`, reported in this step (`inStep`) or the next.
  void destroy(std::uint32_t contact, BodyStore& store, EventDispatcher& events, bool emitEnd,
               bool inStep);

  /// Every contact's shapes are live and list it; the pair map agrees; counts add up.
  Status validate(const BodyStore& store) const;

 private:
  friend class SnapshotCodec;  // snapshot.cpp reads and rebuilds every field
  // What the narrow phase found for one contact, applied after the parallel part.
  enum class Outcome : std::uint8_t { kept, apart, sensorBegan, sensorEnded, began, ended };
  static Outcome updateOne(Contact& c, ContactImpulses& impulses, ContactSim& sim,
                           std::uint64_t stamp, const WorldDef& def, const BroadPhase& broadPhase,
                           const BodyStore& store, const GhostEdges& edges);
  // Smallest share of the narrow phase handed to a worker.
  static constexpr int kMinContactsPerTask = 64;
  static constexpr int kMinWordsPerTask = 8;  // of 64 contacts, for the gathers
  static constexpr int kMinProxiesPerTask = 64;
  std::vector<std::vector<ProxyPair>> pairParts_;  // per worker: pairs found

  std::vector<std::uint32_t> updateList_;                // this step's contacts to update
  std::vector<std::vector<std::uint32_t>> updateParts_;  // updateList_ gathered per range
  std::vector<Outcome> updateOutcome_;                   // and what each found
  std::vector<std::uint32_t> free_;
  PairMap byPair_;
  std::vector<ProxyPair> pairScratch_;
  std::vector<ProxyPair> pairSortScratch_;  // sortPairs' other buffer
  ContactChanges changes_;
  std::vector<ContactHead> heads_;
  std::size_t count_ = 0;
  std::uint64_t simStamp_ = 0;  // bumped by each update; 0 marks no sim current
  static constexpr std::uint32_t kNoSimLane = 0xffffffffu;
  std::vector<std::uint32_t> simLane_;    // by contact index: its lane (placeSims) or none
  std::vector<std::uint32_t> simPlaced_;  // the contacts that have one
  std::size_t simLanes_ = 0;              // lanes of the last placeSims; past them, by index
  std::vector<std::uint64_t> awake_;
  bool allAwake_ = true;
};

}  // namespace quack::detail
