// Islands and sleep (islands.hpp; docs/world.md, "Sleeping").

#include "islands.hpp"

#include <algorithm>
#include <string>

#include "body_store.hpp"
#include "contact_set.hpp"
#include "joint_set.hpp"
#include "quack/broadphase/broad_phase.hpp"
#include "quack/world/world.hpp"
#include "task_runner.hpp"

namespace quack::detail {

namespace {

// Words of 64 bodies per task block of the rest-time update.
constexpr int kMinWordsPerTask = 8;

bool isDynamic(const BodyStore& store, std::uint32_t body) {
  return store.bodyAlive(body) && store.bodies[body].type == BodyType::dynamicBody;
}

// Calls f(other body) for every body touching `body` through a non-sensor contact, then
// for every body jointed to it (joints hold islands together as touching contacts do).
template <class F>
void forEachTouching(const BodyStore& store, const ContactSet& contacts, const JointSet& joints,
                     std::uint32_t body, F f) {
  for (std::uint32_t s : store.bodies[body].shapes) {
    for (std::uint32_t ci : store.shapes[s].contacts) {
      const Contact& c = contacts.contacts[ci];
      if (!c.touching || c.sensor) continue;
      const std::uint32_t a = c.bodyA, b = c.bodyB;
      f(a == body ? b : a);
    }
  }
  joints.forEachOf(body, [&](std::uint32_t j) {
    const std::uint32_t other = joints.other(j, body);
    if (other != kNoBody) f(other);
  });
}

}  // namespace

std::uint32_t IslandSet::newIsland() {
  std::uint32_t id;
  if (!free_.empty()) {
    id = free_.back();
    free_.pop_back();
  } else {
    id = static_cast<std::uint32_t>(islands_.size());
    islands_.emplace_back();
  }
  Island& island = islands_[id];
  island.bodies.clear();
  island.alive = true;
  island.awake = true;
  island.dirty = false;
  return id;
}

void IslandSet::freeIsland(std::uint32_t id) {
  islands_[id].alive = false;
  islands_[id].bodies.clear();
  free_.push_back(id);
}

void IslandSet::setAwakeBit(std::uint32_t body, bool awake) {
  if (body / 64 >= awakeBits_.size()) awakeBits_.resize(body / 64 + 1, 0);
  const std::uint64_t bit = std::uint64_t{1} << (body % 64);
  if (awake) {
    awakeBits_[body / 64] |= bit;
  } else {
    awakeBits_[body / 64] &= ~bit;
  }
}

std::size_t IslandSet::awakeCount() const noexcept {
  std::size_t n = 0;
  for (std::uint64_t w : awakeBits_)
    n += static_cast<std::size_t>(__builtin_popcountll(w));
  return n;
}

void IslandSet::addBody(BodyStore& store, std::uint32_t body, bool awake) {
  Body& b = store.bodies[body];
  b.island = kNoIsland;
  b.sleepTime = 0.0f;
  if (b.type == BodyType::staticBody) {
    b.awake = false;
    setAwakeBit(body, false);
    return;
  }
  b.awake = awake;
  if (!awake) {
    b.v = {};
    b.w = 0.0f;
  }
  setAwakeBit(body, awake);
  if (b.type == BodyType::dynamicBody) {
    const std::uint32_t id = newIsland();
    islands_[id].bodies.push_back(body);
    islands_[id].awake = awake;
    b.island = id;
  }
}

void IslandSet::removeBody(BodyStore& store, std::uint32_t body) {
  Body& b = store.bodies[body];
  setAwakeBit(body, false);
  if (b.island != kNoIsland) {
    Island& island = islands_[b.island];
    auto it = std::find(island.bodies.begin(), island.bodies.end(), body);
    if (it != island.bodies.end()) island.bodies.erase(it);
    const std::uint32_t id = b.island;
    b.island = kNoIsland;
    if (island.bodies.empty()) {
      freeIsland(id);
    } else {
      island.dirty = true;
      wakeIsland(store, id);
    }
  }
  b.awake = false;
}

void IslandSet::wakeIsland(BodyStore& store, std::uint32_t id) {
  Island& island = islands_[id];
  if (island.awake) return;
  island.awake = true;
  for (std::uint32_t body : island.bodies) {
    Body& b = store.bodies[body];
    b.awake = true;
    b.sleepTime = 0.0f;
    setAwakeBit(body, true);
  }
}

void IslandSet::sleepIsland(BodyStore& store, std::uint32_t id) {
  Island& island = islands_[id];
  island.awake = false;
  for (std::uint32_t body : island.bodies) {
    Body& b = store.bodies[body];
    b.awake = false;
    b.v = {};
    b.w = 0.0f;
    b.force = {};
    b.torque = 0.0f;
    b.fast = false;
    setAwakeBit(body, false);
  }
}

void IslandSet::wake(BodyStore& store, std::uint32_t body) {
  if (!store.bodyAlive(body)) return;
  Body& b = store.bodies[body];
  if (b.type == BodyType::staticBody) return;
  if (b.island != kNoIsland) {
    wakeIsland(store, b.island);
  } else {
    b.awake = true;
    b.sleepTime = 0.0f;
    setAwakeBit(body, true);
  }
}

void IslandSet::wakeTouching(BodyStore& store, const ContactSet& contacts, const JointSet& joints,
                             std::uint32_t body) {
  forEachTouching(store, contacts, joints, body, [&](std::uint32_t other) { wake(store, other); });
}

void IslandSet::link(BodyStore& store, std::uint32_t a, std::uint32_t b) {
  const bool dynA = a != kNoBody && isDynamic(store, a);
  const bool dynB = b != kNoBody && isDynamic(store, b);
  if (dynA && dynB) {
    wake(store, a);
    wake(store, b);
    merge(store, store.bodies[a].island, store.bodies[b].island);
    return;
  }
  if (a != kNoBody) wake(store, a);
  if (b != kNoBody) wake(store, b);
}

void IslandSet::unlink(BodyStore& store, std::uint32_t a, std::uint32_t b) {
  if (a != kNoBody) wake(store, a);
  if (b != kNoBody) wake(store, b);
  if (a != kNoBody && b != kNoBody && isDynamic(store, a) && isDynamic(store, b) &&
      store.bodies[a].island == store.bodies[b].island && store.bodies[a].island != kNoIsland)
    islands_[store.bodies[a].island].dirty = true;
}

void IslandSet::wakeNear(BodyStore& store, const BroadPhase& broadPhase, const ContactSet& contacts,
                         std::uint32_t body) {
  for (std::uint32_t s : store.bodies[body].shapes) {
    for (std::uint32_t ci : store.shapes[s].contacts) {
      const Contact& c = contacts.contacts[ci];
      if (c.sensor) continue;
      const std::uint32_t a = c.bodyA, b = c.bodyB;
      wake(store, a == body ? b : a);
    }
    if (store.shapes[s].def.sensor) continue;
    // The fat box holds the speculative distance: what the next step's contacts may reach.
    broadPhase.queryAabb(broadPhase.fatBox(store.shapes[s].proxy),
                         [&](ProxyId, std::uint64_t user) {
                           const Shape& other = store.shapes[static_cast<std::uint32_t>(user)];
                           if (other.body != body && !other.def.sensor) wake(store, other.body);
                           return true;
                         });
  }
}

void IslandSet::sleepNow(BodyStore& store, const ContactSet& contacts, const JointSet& joints,
                         std::uint32_t body) {
  Body& b = store.bodies[body];
  if (b.type == BodyType::staticBody) return;
  if (b.island == kNoIsland) {
    b.awake = false;
    b.v = {};
    b.w = 0.0f;
    setAwakeBit(body, false);
    return;
  }
  // Only the bodies connected to this one sleep: split a marked island first.
  if (islands_[b.island].dirty) split(store, contacts, joints, b.island, parts_);
  sleepIsland(store, b.island);
}

void IslandSet::merge(BodyStore& store, std::uint32_t a, std::uint32_t b) {
  if (a == b) return;
  // The larger island takes the smaller one's bodies (ties: the lower id), so a body
  // changes island O(log n) times as piles grow.
  std::uint32_t keep = a, gone = b;
  const std::size_t na = islands_[a].bodies.size(), nb = islands_[b].bodies.size();
  if (nb > na || (nb == na && b < a)) std::swap(keep, gone);
  const bool awake = islands_[keep].awake || islands_[gone].awake;
  if (awake) {
    wakeIsland(store, keep);
    wakeIsland(store, gone);
  }
  Island& k = islands_[keep];
  Island& g = islands_[gone];
  for (std::uint32_t body : g.bodies) {
    store.bodies[body].island = keep;
    k.bodies.push_back(body);
  }
  k.dirty = k.dirty || g.dirty;
  freeIsland(gone);
}

void IslandSet::apply(BodyStore& store, const ContactChanges& changes) {
  for (std::uint32_t b : changes.toWake)
    wake(store, b);
  for (const BodyPair& p : changes.began) {
    const bool dynA = isDynamic(store, p.a), dynB = isDynamic(store, p.b);
    if (dynA && dynB) {
      merge(store, store.bodies[p.a].island, store.bodies[p.b].island);
    } else {
      // Touching a static or kinematic body joins nothing, but a body asleep is woken.
      if (dynA) wake(store, p.a);
      if (dynB) wake(store, p.b);
    }
  }
  for (const BodyPair& p : changes.ended) {
    // Either body may have been destroyed since (its slot even reused): marking an island
    // that needs no split only costs that split.
    if (isDynamic(store, p.a) && isDynamic(store, p.b) &&
        store.bodies[p.a].island == store.bodies[p.b].island &&
        store.bodies[p.a].island != kNoIsland)
      islands_[store.bodies[p.a].island].dirty = true;
  }
}

void IslandSet::split(BodyStore& store, const ContactSet& contacts, const JointSet& joints,
                      std::uint32_t id, std::vector<std::uint32_t>& parts) {
  parts.clear();
  // The bodies to sort out, in island order; each is reached once by a depth-first walk
  // over touching contacts between dynamic bodies.
  std::vector<std::uint32_t> bodies = std::move(islands_[id].bodies);
  const bool awake = islands_[id].awake;
  islands_[id].bodies.clear();
  for (std::uint32_t body : bodies)
    store.bodies[body].island = kNoIsland;
  bool first = true;
  for (std::uint32_t seed : bodies) {
    if (store.bodies[seed].island != kNoIsland) continue;
    std::uint32_t part;
    if (first) {
      part = id;
      first = false;
    } else {
      part = newIsland();
    }
    islands_[part].awake = awake;
    islands_[part].dirty = false;
    stack_.assign(1, seed);
    store.bodies[seed].island = part;
    while (!stack_.empty()) {
      const std::uint32_t body = stack_.back();
      stack_.pop_back();
      islands_[part].bodies.push_back(body);
      forEachTouching(store, contacts, joints, body, [&](std::uint32_t other) {
        Body& o = store.bodies[other];
        if (o.type != BodyType::dynamicBody || o.island != kNoIsland) return;
        o.island = part;
        stack_.push_back(other);
      });
    }
    parts.push_back(part);
  }
}

void IslandSet::updateSleep(const WorldDef& def, BodyStore& store, const ContactSet& contacts,
                            const JointSet& joints, float dt, TaskRunner& tasks) {
  if (!def.enableSleep) return;
  ++step_;
  auto forEachAwake = [&](auto f) {
    for (std::size_t w = 0; w < awakeBits_.size(); ++w) {
      std::uint64_t bits = awakeBits_[w];
      while (bits != 0) {
        const auto body = static_cast<std::uint32_t>(w * 64 + __builtin_ctzll(bits));
        bits &= bits - 1;
        f(body);
      }
    }
  };
  // Rest times, on the workers (each body its own).
  tasks.parallelFor(
      static_cast<int>(awakeBits_.size()), kMinWordsPerTask, [&](int first, int last, int) {
        for (auto w = static_cast<std::size_t>(first); w < static_cast<std::size_t>(last); ++w) {
          for (std::uint64_t bits = awakeBits_[w]; bits != 0; bits &= bits - 1) {
            Body& b = store.bodies[w * 64 + static_cast<std::size_t>(__builtin_ctzll(bits))];
            if (b.type == BodyType::kinematicBody) {
              // A kinematic body rests only when it does not move at all: a
              // slow platform keeps going.
              const bool moving = b.v.x != 0.0f || b.v.y != 0.0f || b.w != 0.0f;
              b.sleepTime = (moving || !b.enableSleep) ? 0.0f : b.sleepTime + dt;
              continue;
            }
            const float speed = maxf(length(b.v), b.maxExtent * absf(b.w));
            b.sleepTime = (!b.enableSleep || speed > b.sleepThreshold) ? 0.0f : b.sleepTime + dt;
          }
        }
      });
  // A moving kinematic body keeps the bodies on it awake (and wakes one put to sleep by
  // hand: a crate does not hang in the air while its lift goes on).
  forEachAwake([&](std::uint32_t body) {
    const Body& b = store.bodies[body];
    if (b.type != BodyType::kinematicBody || b.sleepTime > 0.0f) return;
    forEachTouching(store, contacts, joints, body, [&](std::uint32_t other) {
      if (store.bodies[other].type != BodyType::dynamicBody) return;
      wake(store, other);
      store.bodies[other].sleepTime = 0.0f;
    });
  });
  // Each awake island's least and greatest rest, in the order its bodies come.
  if (seenStep_.size() < islands_.size()) {
    seenStep_.resize(islands_.size(), 0);
    minRest_.resize(islands_.size());
    maxRest_.resize(islands_.size());
  }
  candidates_.clear();
  forEachAwake([&](std::uint32_t body) {
    const Body& b = store.bodies[body];
    if (b.island == kNoIsland) return;
    if (seenStep_[b.island] != step_) {
      seenStep_[b.island] = step_;
      minRest_[b.island] = b.sleepTime;
      maxRest_[b.island] = b.sleepTime;
      candidates_.push_back(b.island);
    } else {
      minRest_[b.island] = minf(minRest_[b.island], b.sleepTime);
      maxRest_[b.island] = maxf(maxRest_[b.island], b.sleepTime);
    }
  });
  // Split at most one marked island a step: the one with the body that has rested
  // longest, if that is long enough (Box2D v3 does the same, to bound the work).
  std::uint32_t toSplit = kNoIsland;
  float longest = kTimeToSleep;
  for (std::uint32_t id : candidates_) {
    if (islands_[id].dirty && maxRest_[id] >= longest &&
        (toSplit == kNoIsland || maxRest_[id] > maxRest_[toSplit])) {
      toSplit = id;
      longest = maxRest_[id];
    }
  }
  for (std::uint32_t id : candidates_) {
    if (id == toSplit) {
      split(store, contacts, joints, id, parts_);
      for (std::uint32_t part : parts_) {
        bool rested = true;
        for (std::uint32_t body : islands_[part].bodies)
          rested = rested && store.bodies[body].sleepTime >= kTimeToSleep;
        if (rested) sleepIsland(store, part);
      }
    } else if (!islands_[id].dirty && minRest_[id] >= kTimeToSleep) {
      sleepIsland(store, id);
    }
  }
  // Kinematic bodies at rest long enough.
  forEachAwake([&](std::uint32_t body) {
    Body& b = store.bodies[body];
    if (b.type == BodyType::kinematicBody && b.sleepTime >= kTimeToSleep) {
      b.awake = false;
      setAwakeBit(body, false);
    }
  });
}

Status IslandSet::validate(const BodyStore& store, const ContactSet& contacts,
                           const JointSet& joints) const {
  std::vector<std::uint32_t> seen(store.bodies.size(), 0);
  for (std::uint32_t id = 0; id < islands_.size(); ++id) {
    const Island& island = islands_[id];
    if (!island.alive) continue;
    const std::string name = "island " + std::to_string(id);
    if (island.bodies.empty()) return fail(name + ": empty");
    for (std::uint32_t body : island.bodies) {
      if (!isDynamic(store, body))
        return fail(name + ": body " + std::to_string(body) + " is not a live dynamic body");
      const Body& b = store.bodies[body];
      if (b.island != id)
        return fail(name + ": body " + std::to_string(body) + " names island " +
                    std::to_string(b.island));
      if (b.awake != island.awake)
        return fail(name + ": body " + std::to_string(body) + " is " +
                    (b.awake ? "awake" : "asleep") + " in an island that is not");
      if (++seen[body] != 1) return fail(name + ": body " + std::to_string(body) + " twice");
    }
  }
  for (std::uint32_t i = 0; i < store.bodies.size(); ++i) {
    const bool alive = store.bodyAlive(i);
    const Body& b = store.bodies[i];
    const std::string name = "body " + std::to_string(i);
    if (alive && b.type == BodyType::dynamicBody && seen[i] != 1)
      return fail(name + ": dynamic but in no island");
    if (alive && b.type != BodyType::dynamicBody && b.island != kNoIsland)
      return fail(name + ": not dynamic but names island " + std::to_string(b.island));
    if (alive && b.type == BodyType::staticBody && b.awake)
      return fail(name + ": static and awake");
    if (isAwake(i) != (alive && b.awake && b.type != BodyType::staticBody))
      return fail(name + ": awake bit disagrees with the body");
    if (alive && !b.awake && (b.v != Vec2{} || b.w != 0.0f))
      return fail(name + ": asleep but moving");
  }
  for (const Contact& c : contacts.contacts) {
    if (!c.alive || !c.touching || c.sensor) continue;
    const std::uint32_t a = c.bodyA, b = c.bodyB;
    if (isDynamic(store, a) && isDynamic(store, b) &&
        store.bodies[a].island != store.bodies[b].island)
      return fail("bodies " + std::to_string(a) + " and " + std::to_string(b) +
                  " touch but are in different islands");
  }
  for (std::uint32_t j = 0; j < joints.joints.size(); ++j) {
    const Joint& joint = joints.joints[j];
    if (!joint.alive || joint.bodyA == kNoBody) continue;
    if (isDynamic(store, joint.bodyA) && isDynamic(store, joint.bodyB) &&
        store.bodies[joint.bodyA].island != store.bodies[joint.bodyB].island)
      return fail("joint " + std::to_string(j) + ": its bodies are in different islands");
  }
  return {};
}

}  // namespace quack::detail
