#pragma once
// The 3D world's contact set: one contact per pair of shapes whose fat boxes overlap, its
// manifolds (one for two convex shapes, one per touching triangle of a mesh), warm-start
// impulses carried from step to step point by point through feature ids, and the begin and
// end events. Private to the world layer.

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "body_store3.hpp"
#include "task_runner.hpp"

namespace quack::detail {

// A manifold and the solver's impulses at its points, kept between steps for warm starting.
struct ContactManifold3 {
  int triangle = -1;  // the mesh triangle (A is the mesh), or -1
  Manifold3 manifold;
  float normalImpulse[kMaxManifoldPoints3] = {};
  float maxNormalImpulse[kMaxManifoldPoints3] = {};
  // The friction at the manifold's centre: its linear impulse (world frame, so a turned
  // tangent basis keeps it) and its twist about the normal.
  Vec3 frictionImpulse;
  float twistImpulse = 0.0f;
  Vec3 rollingImpulse;  // angular, world frame
  // As computed (for recycling and the solver): each point fixed in A's and in B's body
  // frame, its separation then, and the arms from the centres of mass then (world axes).
  Vec3 localA[kMaxManifoldPoints3], localB[kMaxManifoldPoints3];
  float computedSeparation[kMaxManifoldPoints3] = {};
  Vec3 armA[kMaxManifoldPoints3], armB[kMaxManifoldPoints3];
};

struct Contact3 {
  std::uint32_t shapeA = 0, shapeB = 0;  // A: the mesh, else the lower shape index
  std::vector<ContactManifold3> manifolds;
  float friction = 0.0f, restitution = 0.0f;
  float rollingResistance = 0.0f;  // rolling coefficient times the rolling radius, m
  bool touching = false;
  bool flat = false;         // B is a hull (A a hull or a mesh): the manifolds may be recycled
  HullPairCache3 hullCache;  // two hulls: the axis that last kept them apart
  // The poses (and bodies' pose versions) the manifolds were computed at.
  bool recycleValid = false;
  Transform3 cachedA, cachedB;
  std::uint32_t versionA = 0, versionB = 0;
};

// The most a contact looks ahead (metres): the speculative distance grown by how far the
// bodies can close in one step, up to this.
inline constexpr float kMaxSpeculativeReach3 = 1.0f;

class ContactSet3 {
 public:
  explicit ContactSet3(std::uint32_t worldId) : worldId_(worldId) {}

  // Creates a contact for each new broad-phase pair the world's rules accept (two bodies,
  // at least one dynamic), in sorted pair order.
  void findNew(BodyStore3& store, TaskRunner& tasks);
  // For every contact with an awake body: destroys it when the fat boxes parted; else
  // recycles its manifolds (a resting flat pair near the pose they were computed at), or
  // computes them at the speculative distance plus how far the bodies can close in dt and
  // carries the impulses over by triangle and feature id (or position). Begin and end
  // events in contact order.
  // The manifolds are made on `tasks`' workers; the result is the same for any number.
  void update(const BodyStore3& store, const WorldDef3& def, float dt, StepEvents3& events,
              TaskRunner& tasks);
  // Destroys the contacts of a shape about to go (end events for the touching ones).
  void removeShape(const BodyStore3& store, std::uint32_t shape, StepEvents3& events);

  // Replaces every contact (a snapshot's), in their order, and the lookup built from them.
  void restore(std::vector<Contact3> contacts);
  const std::vector<Contact3>& contacts() const noexcept { return contacts_; }
  std::vector<Contact3>& contacts() noexcept { return contacts_; }
  std::size_t touchingCount() const noexcept;
  ShapeId3 shapeId(const BodyStore3& store, std::uint32_t shape) const noexcept {
    return {shape, store.shapeIds.generation(shape), worldId_};
  }
  // The event of a contact between live shapes a and b.
  ContactEvent3 event(const BodyStore3& store, std::uint32_t a, std::uint32_t b) const noexcept {
    return {shapeId(store, a), shapeId(store, b), store.shapes[a].def.filter.category,
            store.shapes[b].def.filter.category};
  }

 private:
  static std::uint64_t key(std::uint32_t a, std::uint32_t b) noexcept {
    return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
  }
  void destroy(std::uint32_t index);
  enum class Outcome : std::uint8_t { same, parted, began, ended };
  struct Scratch {  // per worker, reused
    std::vector<ContactManifold3> fresh;
    std::vector<MeshContact3> mesh;
  };
  static Outcome updateOne(Contact3& c, const BodyStore3& store, const WorldDef3& def, float dt,
                           Scratch& scratch);
  std::vector<Scratch> scratch_;
  std::vector<Outcome> outcomes_;
  std::vector<Contact3> contacts_;
  // Lookup only, never iterated: the contacts' order is the vector's.
  std::unordered_map<std::uint64_t, std::uint32_t> index_;
  std::vector<ProxyPair> pairs_;
  std::vector<std::vector<ProxyPair>> pairParts_;  // per worker
  std::vector<std::uint8_t> wanted_;               // per pair: a contact is to be made
  std::uint32_t worldId_;
};

}  // namespace quack::detail
