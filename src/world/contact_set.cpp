#include "contact_set.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "body_store.hpp"
#include "event_dispatcher.hpp"
#include "ghost_edges.hpp"
#include "joint_set.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/world/world.hpp"
#include "radix_sort.hpp"
#include "step_context.hpp"
#include "task_runner.hpp"

namespace quack::detail {
namespace {

std::uint64_t pairKey(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

// Contact recycling, the idea of Box2D v3's b2CollideTask (physics_world.c, "contact
// recycling", read for understanding; our own code): while the two bodies are near the
// relative pose at which the manifold was computed, keep the manifold rather than clip a
// new one. The normal stays as it was in the world frame and each point stays fixed on
// each body; only the separation follows the bodies, as it does inside the sub-steps. A
// column of boxes then keeps, step after step, the contact it was built with, instead of
// one re-clipped from a slightly tilted pose each step (docs/world.md explains why that
// matters). Returns false, touching nothing, when the bodies moved too far.
bool recycle(Contact& c, Transform xa, Transform xb, const Body& ba, const Body& bb,
             float recycleDistance) {
  if (recycleDistance <= 0.0f) return false;
  const float cosA = xa.q.c * c.cachedA.q.c + xa.q.s * c.cachedA.q.s;
  const float cosB = xb.q.c * c.cachedB.q.c + xb.q.s * c.cachedB.q.s;
  if (minf(cosA, cosB) <= kContactRecycleCosAngle) return false;
  const Transform rel = invMul(xa, xb);
  const Transform rel0 = invMul(c.cachedA, c.cachedB);
  const Rot qr = invMulRot(rel.q, rel0.q);
  const float extentA = ba.type == BodyType::staticBody ? 0.0f : ba.maxExtent;
  const float extentB = bb.type == BodyType::staticBody ? 0.0f : bb.maxExtent;
  // Distance plus turn times reach bounds how far any point of B moved relative to A.
  if (distance(rel.p, rel0.p) + maxf(extentA, extentB) * absf(qr.s) >= recycleDistance)
    return false;
  const Vec2 n = c.manifold.normal;
  for (int k = 0; k < c.manifold.pointCount; ++k) {
    ManifoldPoint& mp = c.manifold.points[k];
    const Vec2 rA = rotate(xa.q, c.localA[k]);
    const Vec2 rB = rotate(xb.q, c.localB[k]);
    const Vec2 d = (xb.p - xa.p) + (rB - rA);  // B's point relative to A's
    mp.separation = c.baseSeparation[k] + dot(d, n);
    mp.anchorA = rA + 0.5f * d;  // midway between the two, as a computed manifold has it
    mp.anchorB = mp.anchorA + (xa.p - xb.p);
    mp.point = xa.p + mp.anchorA;
  }
  return true;
}

}  // namespace

std::size_t ContactSet::touchingCount() const noexcept {
  std::size_t n = 0;
  for (const Contact& c : contacts)
    n += (c.alive && c.touching && !c.sensor) ? 1 : 0;
  return n;
}

const std::uint32_t* ContactSet::find(std::uint32_t a, std::uint32_t b) const {
  return byPair_.find(pairKey(a, b));
}

void ContactSet::destroy(std::uint32_t index, BodyStore& store, EventDispatcher& events,
                         bool emitEnd, bool inStep) {
  Contact& c = contacts[index];
  if (emitEnd && c.touching) events.contactEnded(store, c, inStep);
  if (c.touching && !c.sensor) changes_.ended.push_back({c.bodyA, c.bodyB});
  for (std::uint32_t s : {c.shapeA, c.shapeB}) {
    auto& list = store.shapes[s].contacts;
    list.erase(std::find(list.begin(), list.end(), index));
  }
  byPair_.erase(pairKey(c.shapeA, c.shapeB));
  c.alive = false;
  heads_[index].alive = false;
  free_.push_back(index);
  --count_;
}

// Many pairs (a churning pile's step finds tens of thousands) are sorted by radix, least
// significant digit first, on the two indices packed into one key of just the bits they
// use: a few stable counting passes where std::sort spent 2 to 5% of the step. Pairs with
// equal keys are equal within a step (an index names one live proxy), so the order is
// exactly std::sort's (tests/world/index_test.cpp checks it).
void sortPairs(std::vector<ProxyPair>& pairs, std::vector<ProxyPair>& scratch) {
  auto byIndices = [](const ProxyPair& x, const ProxyPair& y) {
    return x.a.index != y.a.index ? x.a.index < y.a.index : x.b.index < y.b.index;
  };
  constexpr std::size_t kMinRadix = 1024;
  if (pairs.size() < kMinRadix) {
    std::sort(pairs.begin(), pairs.end(), byIndices);
    return;
  }
  std::uint32_t most = 1;
  for (const ProxyPair& p : pairs)
    most |= p.a.index | p.b.index;
  const int bits = 32 - __builtin_clz(most);  // of each index
  auto key = [bits](const ProxyPair& p) {
    return (std::uint64_t{p.a.index} << bits) | std::uint64_t{p.b.index};
  };
  radixSortByKey(pairs, scratch, 2 * bits, key);
}

void ContactSet::findNew(StepContext& step) {
  BroadPhase& broadPhase = step.broadPhase;
  BodyStore& store = step.store;
  TaskRunner& tasks = step.tasks;
  // The moved proxies' queries on the workers, each into its own list.
  pairParts_.resize(static_cast<std::size_t>(tasks.workers()));
  broadPhase.updatePairs(pairScratch_, pairParts_, [&](std::size_t count, auto&& body) {
    tasks.parallelFor(static_cast<int>(count), kMinProxiesPerTask,
                      [&](int first, int last, int participant) {
                        body(static_cast<std::size_t>(first), static_cast<std::size_t>(last),
                             static_cast<std::size_t>(participant));
                      });
  });
  // Structure-independent order, so contacts (and the solver) run in the same order
  // whichever broad phase found them.
  sortPairs(pairScratch_, pairSortScratch_);
  for (const ProxyPair& pair : pairScratch_) {
    auto sa = static_cast<std::uint32_t>(broadPhase.userData(pair.a));
    auto sb = static_cast<std::uint32_t>(broadPhase.userData(pair.b));
    const Shape& shapeA = store.shapes[sa];
    const Shape& shapeB = store.shapes[sb];
    if (shapeA.body == shapeB.body) continue;  // a body's shapes never collide with each other
    const Body& bodyA = store.bodies[shapeA.body];
    const Body& bodyB = store.bodies[shapeB.body];
    if (bodyA.type != BodyType::dynamicBody && bodyB.type != BodyType::dynamicBody) continue;
    if (shapeA.def.sensor && shapeB.def.sensor) continue;  // sensors do not sense sensors
    // Jointed bodies do not collide unless the joint says so (JointDef::collideConnected).
    if (step.joints.blocksCollision(shapeA.body, shapeB.body)) continue;
    if (byPair_.contains(pairKey(sa, sb))) continue;
    std::uint32_t index;
    if (!free_.empty()) {
      index = free_.back();
      free_.pop_back();
    } else {
      index = static_cast<std::uint32_t>(contacts.size());
      contacts.emplace_back();
      impulses.emplace_back();
      heads_.emplace_back();
    }
    Contact& c = contacts[index];
    c = Contact{};
    impulses[index] = ContactImpulses{};
    c.alive = true;
    // The sensor, if any, is shape A; otherwise keep the broad phase's order.
    if (shapeB.def.sensor) std::swap(sa, sb);
    c.shapeA = sa;
    c.shapeB = sb;
    c.bodyA = store.shapes[sa].body;
    c.bodyB = store.shapes[sb].body;
    c.proxyA = store.shapes[sa].proxy;
    c.proxyB = store.shapes[sb].proxy;
    c.sensor = store.shapes[sa].def.sensor;
    heads_[index] = {c.bodyA, c.bodyB, true, false, c.sensor};
    const ShapeGeometry& ga = *store.shapes[sa].geometry;
    const ShapeGeometry& gb = *store.shapes[sb].geometry;
    c.fn = findManifoldFn(shapeType(ga), shapeType(gb));
    c.friction = std::sqrt(store.shapes[sa].def.friction * store.shapes[sb].def.friction);
    c.restitution = maxf(store.shapes[sa].def.restitution, store.shapes[sb].def.restitution);
    byPair_.set(pairKey(sa, sb), index);
    store.shapes[sa].contacts.push_back(index);
    store.shapes[sb].contacts.push_back(index);
    ++count_;
    // A contact with nothing awake in it was made by static (or resting kinematic) geometry
    // created or moved by the game next to a sleeping body: wake that body, or the contact
    // would never be looked at (sensors excepted: they only watch). Between two sleeping
    // dynamic bodies (created asleep side by side) it rests with them: whichever wakes first
    // brings it into the narrow phase, and a touch then joins their islands.
    if (!c.sensor && !bodyA.awake && !bodyB.awake &&
        (bodyA.type != BodyType::dynamicBody || bodyB.type != BodyType::dynamicBody)) {
      if (bodyA.type == BodyType::dynamicBody) changes_.toWake.push_back(shapeA.body);
      if (bodyB.type == BodyType::dynamicBody) changes_.toWake.push_back(shapeB.body);
    }
  }
}

void ContactSet::markAwake(const BodyStore& store, const std::vector<std::uint64_t>& awakeBodies,
                           std::size_t awakeCount, std::size_t bodyCount) {
  allAwake_ = 2 * awakeCount > bodyCount;
  if (allAwake_) return;
  awake_.assign((contacts.size() + 63) / 64, 0);
  for (std::size_t w = 0; w < awakeBodies.size(); ++w) {
    for (std::uint64_t bits = awakeBodies[w]; bits != 0; bits &= bits - 1) {
      const std::size_t body = w * 64 + static_cast<std::size_t>(__builtin_ctzll(bits));
      for (std::uint32_t s : store.bodies[body].shapes)
        for (std::uint32_t c : store.shapes[s].contacts)
          awake_[c / 64] |= std::uint64_t{1} << (c % 64);
    }
  }
}

void ContactSet::update(StepContext& step, const GhostEdges& edges,
                        const std::vector<std::uint64_t>& awakeBodies) {
  const WorldDef& def = step.def;
  const BroadPhase& broadPhase = step.broadPhase;
  BodyStore& store = step.store;
  EventDispatcher& events = step.events;
  TaskRunner& tasks = step.tasks;
  auto isAwake = [&](std::uint32_t body) {
    return body / 64 < awakeBodies.size() && ((awakeBodies[body / 64] >> (body % 64)) & 1u) != 0;
  };
  // The contacts to look at, in index order.
  // Gathered on the workers (the contact heads and the awake bits), joined in order.
  [[maybe_unused]] const BodyStore& readStore = store;
  tasks.gather(awakeWordCount(), kMinWordsPerTask, updateParts_, updateList_,
               [&](int first, int last, std::vector<std::uint32_t>& list) {
                 forEachAwakeIn(first, last, [&](std::uint32_t i) {
                   const ContactHead& c = heads_[i];
                   if (!c.alive) return;
                   // Nothing in it moves (both asleep, or asleep and static): kept as it is,
                   // touching or not, with its impulses (docs/world.md, "Sleeping"). The
                   // awake bits mirror Body::awake in a few cache lines.
                   QUACK_ASSERT(isAwake(c.bodyA) == readStore.bodies[c.bodyA].awake &&
                                isAwake(c.bodyB) == readStore.bodies[c.bodyB].awake);
                   if (!isAwake(c.bodyA) && !isAwake(c.bodyB)) return;
                   list.push_back(i);
                 });
               });
  updateOutcome_.resize(updateList_.size());
  ++simStamp_;
  if (simLane_.size() < contacts.size()) simLane_.resize(contacts.size(), kNoSimLane);
  if (sims.size() < simLanes_ + contacts.size()) sims.resize(simLanes_ + contacts.size());
  const std::uint64_t stamp = simStamp_;
  // Each contact on its own, on any worker: it reads shapes and bodies and writes only
  // itself and its outcome (docs/world.md, "Threads").
  const BodyStore& cstore = store;
  tasks.parallelFor(
      static_cast<int>(updateList_.size()), kMinContactsPerTask,
      [&](int first, int last, int) {
        for (int k = first; k < last; ++k) {
          const auto at = static_cast<std::size_t>(k);
          const std::uint32_t i = updateList_[at];
          updateOutcome_[at] = updateOne(contacts[i], impulses[i], sims[simIndex(i)], stamp, def,
                                         broadPhase, cstore, edges);
          heads_[i].touching = contacts[i].touching;
        }
      },
      TaskRunner::kHeavyRangesPerWorker);
  // What changes the set and the events, in contact order whatever the workers did.
  for (std::size_t k = 0; k < updateList_.size(); ++k) {
    const std::uint32_t i = updateList_[k];
    const Contact& c = contacts[i];
    switch (updateOutcome_[k]) {
      case Outcome::kept:
        break;
      case Outcome::apart:
        destroy(i, store, events, true, true);
        break;
      case Outcome::sensorBegan:
        events.events.sensorBegin.push_back({store.shapeId(c.shapeA), store.shapeId(c.shapeB)});
        break;
      case Outcome::sensorEnded:
        events.contactEnded(store, c, true);
        break;
      case Outcome::began:
        events.events.begin.push_back({store.shapeId(c.shapeA), store.shapeId(c.shapeB)});
        changes_.began.push_back({c.bodyA, c.bodyB});
        break;
      case Outcome::ended:
        events.contactEnded(store, c, true);
        changes_.ended.push_back({c.bodyA, c.bodyB});
        break;
    }
  }
}

void ContactSet::placeSims(std::span<const std::uint32_t> touching,
                           std::span<const std::uint32_t> lanes, std::size_t laneCount) {
  QUACK_ASSERT(touching.size() == lanes.size());
  for (const std::uint32_t ci : simPlaced_)
    if (ci < simLane_.size()) simLane_[ci] = kNoSimLane;
  if (simLane_.size() < contacts.size()) simLane_.resize(contacts.size(), kNoSimLane);
  simPlaced_.assign(touching.begin(), touching.end());
  for (std::size_t k = 0; k < touching.size(); ++k) {
    QUACK_ASSERT(lanes[k] < laneCount);
    simLane_[touching[k]] = lanes[k];
  }
  simLanes_ = laneCount;
}

void fillContactSim(ContactSim& sim, const Contact& c, const ContactImpulses& impulses,
                    Vec2 centerA, Vec2 localCenterA, Vec2 centerB, Vec2 localCenterB) {
  const Vec2 n = c.manifold.normal;
  sim.normal = n;
  sim.friction = c.friction;
  sim.restitution = c.restitution;
  sim.pointCount = c.manifold.pointCount;
  for (int j = 0; j < c.manifold.pointCount; ++j) {
    const ManifoldPoint& mp = c.manifold.points[j];
    ContactSim::Point& p = sim.points[j];
    if (c.recycled) {
      // A recycled manifold (recycle, above): the arms from each centre of mass to the
      // point as they were when the manifold was computed, not turned with the bodies
      // since. Box2D v3 does the same (its anchors stay as computed while a contact is
      // recycled; physics_world.c and contact_solver.c, read for understanding). Arms that
      // turn with the bodies while the normal stays put let a column's tilt move its
      // contact forces the way that tilts it further: columns of 15 boxes or more topple so
      // (docs/world.md, "Contact recycling and point order").
      p.rA = rotate(c.cachedA.q, c.localA[j] - localCenterA);
      p.rB = rotate(c.cachedB.q, c.localB[j] - localCenterB);
    } else {
      p.rA = mp.point - centerA;
      p.rB = mp.point - centerB;
    }
    p.baseSeparation = mp.separation - dot(p.rB - p.rA, n);
    p.normalImpulse = impulses.normal[j];
    p.tangentImpulse = impulses.tangent[j];
  }
}

ContactSet::Outcome ContactSet::updateOne(Contact& c, ContactImpulses& impulses, ContactSim& sim,
                                          std::uint64_t stamp, const WorldDef& def,
                                          const BroadPhase& broadPhase, const BodyStore& store,
                                          const GhostEdges& edges) {
  if (!overlaps(broadPhase.fatBox(c.proxyA), broadPhase.fatBox(c.proxyB))) return Outcome::apart;
  const Body& ba = store.bodies[c.bodyA];
  const Body& bb = store.bodies[c.bodyB];
  const Transform xa = ba.xf;
  const Transform xb = bb.xf;
  const bool wasTouching = c.touching;
  if (c.sensor) {
    const Shape& sa = store.shapes[c.shapeA];
    const Shape& sb = store.shapes[c.shapeB];
    c.touching = testOverlap(*sa.geometry, xa, *sb.geometry, xb);
    if (c.touching && !wasTouching) return Outcome::sensorBegan;
    if (!c.touching && wasTouching) return Outcome::sensorEnded;
    return Outcome::kept;
  }
  c.recycled = c.touching && c.recycleValid && !ba.fast && !bb.fast &&
               recycle(c, xa, xb, ba, bb, def.contactRecycleDistance);
  if (c.recycled) {
    // Still touching; impulses, ids and events as they were.
    fillContactSim(sim, c, impulses, ba.center, ba.localCenter, bb.center, bb.localCenter);
    sim.stamp = stamp;
    return Outcome::kept;
  }
  const Shape& sa = store.shapes[c.shapeA];
  const Shape& sb = store.shapes[c.shapeB];
  Manifold old = c.manifold;
  float oldNormal[kMaxManifoldPoints], oldTangent[kMaxManifoldPoints];
  std::copy(impulses.normal, impulses.normal + kMaxManifoldPoints, oldNormal);
  std::copy(impulses.tangent, impulses.tangent + kMaxManifoldPoints, oldTangent);
  c.manifold = c.fn(*sa.geometry, xa, *sb.geometry, xb, def.speculativeDistance);
  // Ghost collisions: only contacts with flagged static shapes pay for the check.
  if (edges.activeShapes() != 0 && (sa.edges.active || sb.edges.active))
    edges.removeGhostContacts(store, c);
  // Warm start: a point keeps the impulses of the old point with the same feature id.
  for (int k = 0; k < c.manifold.pointCount; ++k) {
    impulses.normal[k] = 0.0f;
    impulses.tangent[k] = 0.0f;
    for (int j = 0; j < old.pointCount; ++j) {
      if (old.points[j].id == c.manifold.points[k].id) {
        impulses.normal[k] = oldNormal[j];
        impulses.tangent[k] = oldTangent[j];
        break;
      }
    }
  }
  // The reference for recycling: where each point is fixed on A and on B, and the
  // separation less the points' (rounding-size) offset along the normal, so that a
  // recycled contact whose bodies have not moved has exactly this separation.
  c.cachedA = xa;
  c.cachedB = xb;
  c.recycleValid = true;
  deriveRecycleReference(c);
  c.touching = c.manifold.pointCount > 0;
  if (c.touching) {
    fillContactSim(sim, c, impulses, ba.center, ba.localCenter, bb.center, bb.localCenter);
    sim.stamp = stamp;
  }
  if (c.touching && !wasTouching) return Outcome::began;
  if (!c.touching && wasTouching) return Outcome::ended;
  return Outcome::kept;
}

void deriveRecycleReference(Contact& c) {
  const Transform xa = c.cachedA, xb = c.cachedB;
  for (int k = 0; k < c.manifold.pointCount; ++k) {
    const ManifoldPoint& mp = c.manifold.points[k];
    c.localA[k] = invRotate(xa.q, mp.anchorA);
    c.localB[k] = invRotate(xb.q, mp.anchorB);
    const Vec2 d = (xb.p - xa.p) + (rotate(xb.q, c.localB[k]) - rotate(xa.q, c.localA[k]));
    c.baseSeparation[k] = mp.separation - dot(d, c.manifold.normal);
  }
}

void ContactSet::forgetPoses(const BodyStore& store, std::uint32_t body) {
  for (std::uint32_t s : store.bodies[body].shapes)
    for (std::uint32_t c : store.shapes[s].contacts)
      contacts[c].recycleValid = false;
}

void ContactSet::rebuildHeads() {
  heads_.resize(contacts.size());
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const Contact& c = contacts[i];
    heads_[i] = {c.bodyA, c.bodyB, c.alive, c.touching, c.sensor};
  }
}

Status ContactSet::validate(const BodyStore& store) const {
  if (heads_.size() != contacts.size()) return fail("contact heads and contacts differ in count");
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const Contact& c = contacts[i];
    const ContactHead& h = heads_[i];
    if (h.alive != c.alive || (c.alive && (h.bodyA != c.bodyA || h.bodyB != c.bodyB ||
                                           h.touching != c.touching || h.sensor != c.sensor)))
      return fail("contact " + std::to_string(i) + ": its head disagrees with it");
  }
  std::size_t live = 0;
  for (std::uint32_t i = 0; i < contacts.size(); ++i) {
    const Contact& c = contacts[i];
    if (!c.alive) continue;
    ++live;
    const std::string name = "contact " + std::to_string(i);
    for (std::uint32_t s : {c.shapeA, c.shapeB}) {
      if (!store.shapeAlive(s)) return fail(name + ": shape " + std::to_string(s) + " is dead");
      const auto& list = store.shapes[s].contacts;
      if (std::count(list.begin(), list.end(), i) != 1)
        return fail(name + ": not listed once by shape " + std::to_string(s));
    }
    if (c.shapeA == c.shapeB) return fail(name + ": a shape with itself");
    if (c.bodyA != store.shapes[c.shapeA].body || c.bodyB != store.shapes[c.shapeB].body)
      return fail(name + ": its bodies are not its shapes' bodies");
    if (c.proxyA != store.shapes[c.shapeA].proxy || c.proxyB != store.shapes[c.shapeB].proxy)
      return fail(name + ": its proxies are not its shapes' proxies");
    const std::uint32_t* found = find(c.shapeA, c.shapeB);
    if (found == nullptr || *found != i) return fail(name + ": pair map disagrees");
    if (c.sensor != store.shapes[c.shapeA].def.sensor)
      return fail(name + ": sensor flag disagrees with shape A");
    if (!c.sensor && c.touching != (c.manifold.pointCount > 0))
      return fail(name + ": touching disagrees with the manifold");
  }
  if (live != count_) return fail("contact count is wrong");
  if (byPair_.size() != count_) return fail("pair map size differs from the contact count");
  for (std::uint32_t f : free_) {
    if (f >= contacts.size() || contacts[f].alive) return fail("a free contact slot is live");
  }
  if (free_.size() + count_ != contacts.size()) return fail("free + live contacts != slots");
  return {};
}

}  // namespace quack::detail
