// The joint set (joint_set.hpp; docs/world.md, "Joints").

#include "joint_set.hpp"

#include <string>

#include "body_store.hpp"

namespace quack {

const char* toString(JointType type) noexcept {
  switch (type) {
    case JointType::revolute:
      return "revolute";
    case JointType::prismatic:
      return "prismatic";
    case JointType::distance:
      return "distance";
    case JointType::weld:
      return "weld";
    case JointType::wheel:
      return "wheel";
    case JointType::motor:
      return "motor";
    case JointType::mouse:
      return "mouse";
  }
  return "unknown";
}

}  // namespace quack

namespace quack::detail {

// A body's list runs from its highest joint index down, so that a snapshot rebuilds it as it
// was (rebuildLists): the order a list is walked decides the order islands are split in.
// A new joint usually has the highest index of its bodies' joints and goes first in O(1).
void JointSet::link(std::uint32_t joint, int side) {
  Joint& j = joints[joint];
  const std::uint32_t body = side == 0 ? j.bodyA : j.bodyB;
  if (body == kNoBody) return;
  if (body >= head_.size()) {
    head_.resize(body + 1, kNoJoint);
    counts_.resize(body + 1, 0);
  }
  ++counts_[body];
  std::uint32_t* at = &head_[body];
  while (*at != kNoJoint && *at > joint) {
    Joint& k = joints[*at];
    at = &k.next[k.bodyA == body ? 0 : 1];
  }
  j.next[side] = *at;
  *at = joint;
}

void JointSet::unlink(std::uint32_t joint, int side) {
  Joint& j = joints[joint];
  const std::uint32_t body = side == 0 ? j.bodyA : j.bodyB;
  if (body == kNoBody) return;
  --counts_[body];
  std::uint32_t* at = &head_[body];
  while (*at != joint) {
    Joint& k = joints[*at];
    at = &k.next[k.bodyA == body ? 0 : 1];
  }
  *at = j.next[side];
  j.next[side] = kNoJoint;
}

std::uint32_t JointSet::create(const Joint& joint) {
  const std::uint32_t index = ids.allocate();
  if (index >= joints.size()) joints.resize(index + 1);
  joints[index] = joint;
  joints[index].alive = true;
  joints[index].next[0] = joints[index].next[1] = kNoJoint;
  link(index, 0);
  link(index, 1);
  return index;
}

void JointSet::release(std::uint32_t joint) {
  unlink(joint, 0);
  unlink(joint, 1);
  joints[joint] = Joint{};
  ids.release(joint);
}

bool JointSet::blocksCollision(std::uint32_t a, std::uint32_t b) const noexcept {
  if (jointCountOf(a) == 0 || jointCountOf(b) == 0) return false;
  if (jointCountOf(b) < jointCountOf(a)) std::swap(a, b);
  bool blocked = false;
  forEachOf(a, [&](std::uint32_t j) {
    if (!joints[j].def.collideConnected && other(j, a) == b) blocked = true;
  });
  return blocked;
}

void JointSet::rebuildLists(std::size_t bodySlots) {
  head_.assign(bodySlots, kNoJoint);
  counts_.assign(bodySlots, 0);
  for (std::uint32_t j = 0; j < joints.size(); ++j) {
    if (!joints[j].alive) continue;
    joints[j].next[0] = joints[j].next[1] = kNoJoint;
    link(j, 0);
    link(j, 1);
  }
}

Status JointSet::validate(const BodyStore& store) const {
  std::vector<std::uint32_t> seen(store.bodies.size(), 0);
  for (std::uint32_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const std::string name = "joint " + std::to_string(j);
    if (joint.alive != ids.isAlive(j)) return fail(name + ": alive flag disagrees with its handle");
    if (!joint.alive) continue;
    if (joint.bodyA == joint.bodyB) return fail(name + ": joins a body to itself");
    for (std::uint32_t body : {joint.bodyA, joint.bodyB}) {
      if (body == kNoBody && body == joint.bodyA && joint.def.type == JointType::mouse) continue;
      if (!store.bodyAlive(body))
        return fail(name + ": body " + std::to_string(body) + " is not live");
      ++seen[body];
    }
  }
  for (std::uint32_t body = 0; body < head_.size(); ++body) {
    std::uint32_t n = 0;
    std::uint32_t last = kNoJoint;
    for (std::uint32_t j = head_[body]; j != kNoJoint;) {
      if (j >= joints.size() || !joints[j].alive)
        return fail("body " + std::to_string(body) + " lists joint " + std::to_string(j) +
                    ", which is not live");
      const Joint& joint = joints[j];
      if (joint.bodyA != body && joint.bodyB != body)
        return fail("body " + std::to_string(body) + " lists joint " + std::to_string(j) +
                    ", which is not its");
      if (last != kNoJoint && j >= last)
        return fail("body " + std::to_string(body) + ": joints out of order");
      last = j;
      ++n;
      if (n > joints.size()) return fail("body " + std::to_string(body) + ": joint list loops");
      j = joint.next[joint.bodyA == body ? 0 : 1];
    }
    if (n != counts_[body] || (body < seen.size() ? seen[body] : 0) != n)
      return fail("body " + std::to_string(body) + ": joint count disagrees with its list");
  }
  for (std::uint32_t body = static_cast<std::uint32_t>(head_.size()); body < seen.size(); ++body)
    if (seen[body] != 0) return fail("body " + std::to_string(body) + ": joints not listed");
  return {};
}

}  // namespace quack::detail
