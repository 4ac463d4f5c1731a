#include "islands3.hpp"

#include <algorithm>

#include "quack/world/world.hpp"

namespace quack::detail {

std::uint32_t Islands3::find(std::uint32_t i) noexcept {
  while (parent_[i] != i) {
    parent_[i] = parent_[parent_[i]];  // path halving
    i = parent_[i];
  }
  return i;
}

void Islands3::wakeTouched(BodyStore3& store, const ContactSet3& contacts) {
  const auto n = static_cast<std::uint32_t>(store.bodies.size());
  parent_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i)
    parent_[i] = i;
  for (const Contact3& c : contacts.contacts()) {
    if (!c.touching) continue;
    const std::uint32_t a = store.shapes[c.shapeA].body;
    const std::uint32_t b = store.shapes[c.shapeB].body;
    if (store.bodies[a].type != BodyType::dynamicBody ||
        store.bodies[b].type != BodyType::dynamicBody) {
      continue;
    }
    const std::uint32_t ra = find(a), rb = find(b);
    // The lower index becomes the root, so the islands do not depend on contact order.
    if (ra != rb) parent_[std::max(ra, rb)] = std::min(ra, rb);
  }
  std::vector<std::uint8_t> islandAwake(n, 0);
  islandCount_ = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Body3& b = store.bodies[i];
    if (!store.bodyIds.isAlive(i) || b.type != BodyType::dynamicBody) continue;
    const std::uint32_t r = find(i);
    if (r == i) ++islandCount_;
    if (b.awake) islandAwake[r] = 1;
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    Body3& b = store.bodies[i];
    if (!store.bodyIds.isAlive(i) || b.type != BodyType::dynamicBody || b.awake) continue;
    if (islandAwake[find(i)] != 0) {
      b.awake = true;
      b.sleepTime = 0.0f;
    }
  }
}

void Islands3::sleepRested(BodyStore3& store, const ContactSet3& contacts, float dt) {
  const auto n = static_cast<std::uint32_t>(store.bodies.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    Body3& b = store.bodies[i];
    if (!store.bodyIds.isAlive(i) || b.type != BodyType::dynamicBody || !b.awake) continue;
    const float speed = length(b.linearVelocity);
    const float turning = length(b.angularVelocity) * b.maxExtent;
    const bool resting = b.enableSleep && speed < b.sleepThreshold && turning < b.sleepThreshold;
    b.sleepTime = resting ? b.sleepTime + dt : 0.0f;
  }
  for (const Contact3& c : contacts.contacts()) {
    if (!c.touching) continue;
    Body3& a = store.bodies[store.shapes[c.shapeA].body];
    Body3& b = store.bodies[store.shapes[c.shapeB].body];
    const auto moving = [](const Body3& k) {
      return k.type == BodyType::kinematicBody &&
             (lengthSquared(k.linearVelocity) > 0.0f || lengthSquared(k.angularVelocity) > 0.0f);
    };
    if (moving(a)) b.sleepTime = 0.0f;
    if (moving(b)) a.sleepTime = 0.0f;
  }
  islandRest_.assign(n, kTimeToSleep);
  for (std::uint32_t i = 0; i < n; ++i) {
    const Body3& b = store.bodies[i];
    if (!store.bodyIds.isAlive(i) || b.type != BodyType::dynamicBody || !b.awake) continue;
    float& rest = islandRest_[find(i)];
    rest = std::min(rest, b.sleepTime);
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    Body3& b = store.bodies[i];
    if (!store.bodyIds.isAlive(i) || b.type != BodyType::dynamicBody || !b.awake) continue;
    if (islandRest_[find(i)] >= kTimeToSleep) {
      b.awake = false;
      b.linearVelocity = b.angularVelocity = Vec3{};
    }
  }
}

}  // namespace quack::detail
