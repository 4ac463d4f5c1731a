#pragma once
// The joint set: one part of the world (docs/world.md, "Joints"). It owns the joints (their
// settings fixed to the bodies' frames, and the impulses they accumulated, kept between
// steps for warm starting) and, per body, the list of its joints. The solver solves them
// with the contacts (joint_solver.hpp); the islands take them as edges; the contact set
// asks it which pairs of bodies must not collide.

#include <cstdint>
#include <vector>

#include "quack/core/id_pool.hpp"
#include "quack/core/result.hpp"
#include "quack/math/transform.hpp"
#include "quack/world/types.hpp"

namespace quack::detail {

class BodyStore;

inline constexpr std::uint32_t kNoJoint = 0xffffffffu;
/// A mouse joint's missing body A.
inline constexpr std::uint32_t kNoBody = 0xffffffffu;

struct Joint {
  JointDef def;  // as created (world frame then), with the setters' changes since
  bool alive = false;
  bool pendingDestroy = false;  // destroyJoint from a callback: done after the callbacks
  std::uint32_t bodyA = kNoBody, bodyB = 0;
  // Fixed to the bodies at creation: each anchor from its body's origin (body frame), the
  // axis in A's frame (unit), B's angle less A's.
  Vec2 localAnchorA, localAnchorB;
  Vec2 localAxisA{1.0f, 0.0f};
  float referenceAngle = 0.0f;
  float length = 0.0f;  // a distance joint's rest length (resolved from def.length)
  // Accumulated impulses of the last sub-step (N s), for warm starting. `linear` is the
  // point constraint (revolute, weld, motor, mouse), or a prismatic joint's pair (across
  // the axis, angular).
  Vec2 linearImpulse;
  float angularImpulse = 0.0f;  // weld, motor
  float perpImpulse = 0.0f;     // wheel: across the axis
  float axialImpulse = 0.0f;    // distance: the rigid length
  float springImpulse = 0.0f, motorImpulse = 0.0f, lowerImpulse = 0.0f, upperImpulse = 0.0f;
  // What the last step applied (World::jointForce, jointTorque), on B, world frame.
  Vec2 force;
  float torque = 0.0f;
  // The next joint in body A's and in body B's list.
  std::uint32_t next[2] = {kNoJoint, kNoJoint};
};

class JointSet {
 public:
  std::vector<Joint> joints;  // by JointId::index; live where Joint::alive
  IdPool ids;
  /// Joints taken by bodies destroyed between steps: reported with the next step's events.
  std::vector<JointEndEvent> endsSinceStep;

  /// A new joint (its fields filled but `alive` and `next`), listed with its bodies.
  std::uint32_t create(const Joint& joint);
  /// Unlists and frees it.
  void release(std::uint32_t joint);
  std::size_t count() const noexcept { return ids.liveCount(); }
  bool empty() const noexcept { return ids.liveCount() == 0; }

  /// Calls f(joint index) for every joint of `body`, highest index first.
  template <class F>
  void forEachOf(std::uint32_t body, F f) const {
    if (body >= head_.size()) return;
    for (std::uint32_t j = head_[body]; j != kNoJoint;) {
      const Joint& joint = joints[j];
      const std::uint32_t next = joint.next[joint.bodyA == body ? 0 : 1];
      f(j);
      j = next;
    }
  }
  /// The other body of a joint of `body` (kNoBody: a mouse joint's missing body).
  std::uint32_t other(std::uint32_t joint, std::uint32_t body) const noexcept {
    const Joint& j = joints[joint];
    return j.bodyA == body ? j.bodyB : j.bodyA;
  }
  std::uint32_t jointCountOf(std::uint32_t body) const noexcept {
    return body < counts_.size() ? counts_[body] : 0;
  }
  /// Is there a joint between bodies a and b that keeps their shapes from colliding (not
  /// collideConnected)? Walks the shorter of their lists.
  bool blocksCollision(std::uint32_t a, std::uint32_t b) const noexcept;

  /// Rebuilds the per-body lists from the joints (after a snapshot is restored): the same
  /// lists as the ones kept while creating and releasing, which are in index order.
  void rebuildLists(std::size_t bodySlots);
  /// Every live joint's bodies are live and list it; the lists hold only live joints, in
  /// order; counts agree.
  Status validate(const BodyStore& store) const;

 private:
  void link(std::uint32_t joint, int side);
  void unlink(std::uint32_t joint, int side);
  std::vector<std::uint32_t> head_;    // by body index: its first joint
  std::vector<std::uint32_t> counts_;  // by body index: its joints
};

}  // namespace quack::detail
