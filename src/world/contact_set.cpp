#include "contact_set.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "body_store.hpp"
#include "event_dispatcher.hpp"
#include "ghost_edges.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/world/world.hpp"
#include "world_state.hpp"

namespace quack::detail {
namespace {

std::uint64_t pairKey(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

}  // namespace

std::size_t ContactSet::touchingCount() const noexcept {
  std::size_t n = 0;
  for (const Contact& c : contacts)
    n += (c.alive && c.touching && !c.sensor) ? 1 : 0;
  return n;
}

const std::uint32_t* ContactSet::find(std::uint32_t a, std::uint32_t b) const {
  auto it = byPair_.find(pairKey(a, b));
  return it == byPair_.end() ? nullptr : &it->second;
}

void ContactSet::destroy(std::uint32_t index, BodyStore& store, EventDispatcher& events,
                         bool emitEnd, bool inStep) {
  Contact& c = contacts[index];
  if (emitEnd && c.touching) events.contactEnded(store, c, inStep);
  for (std::uint32_t s : {c.shapeA, c.shapeB}) {
    auto& list = store.shapes[s].contacts;
    list.erase(std::find(list.begin(), list.end(), index));
  }
  byPair_.erase(pairKey(c.shapeA, c.shapeB));
  c.alive = false;
  free_.push_back(index);
  --count_;
}

void ContactSet::findNew(BroadPhase& broadPhase, BodyStore& store) {
  broadPhase.updatePairs(pairScratch_);
  // Structure-independent order, so contacts (and the solver) run in the same order
  // whichever broad phase found them.
  std::sort(pairScratch_.begin(), pairScratch_.end(), [](const ProxyPair& x, const ProxyPair& y) {
    return x.a.index != y.a.index ? x.a.index < y.a.index : x.b.index < y.b.index;
  });
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
    if (byPair_.count(pairKey(sa, sb)) != 0) continue;
    std::uint32_t index;
    if (!free_.empty()) {
      index = free_.back();
      free_.pop_back();
    } else {
      index = static_cast<std::uint32_t>(contacts.size());
      contacts.emplace_back();
    }
    Contact& c = contacts[index];
    c = Contact{};
    c.alive = true;
    // The sensor, if any, is shape A; otherwise keep the broad phase's order.
    if (shapeB.def.sensor) std::swap(sa, sb);
    c.shapeA = sa;
    c.shapeB = sb;
    c.sensor = store.shapes[sa].def.sensor;
    const ShapeGeometry& ga = store.shapes[sa].geometry;
    const ShapeGeometry& gb = store.shapes[sb].geometry;
    c.fn = findManifoldFn(shapeType(ga), shapeType(gb));
    c.friction = std::sqrt(store.shapes[sa].def.friction * store.shapes[sb].def.friction);
    c.restitution = maxf(store.shapes[sa].def.restitution, store.shapes[sb].def.restitution);
    byPair_.emplace(pairKey(sa, sb), index);
    store.shapes[sa].contacts.push_back(index);
    store.shapes[sb].contacts.push_back(index);
    ++count_;
  }
}

void ContactSet::update(const WorldDef& def, const BroadPhase& broadPhase, BodyStore& store,
                        const GhostEdges& edges, EventDispatcher& events) {
  for (std::uint32_t i = 0; i < contacts.size(); ++i) {
    Contact& c = contacts[i];
    if (!c.alive) continue;
    const Shape& sa = store.shapes[c.shapeA];
    const Shape& sb = store.shapes[c.shapeB];
    if (!overlaps(broadPhase.fatBox(sa.proxy), broadPhase.fatBox(sb.proxy))) {
      destroy(i, store, events, true, true);
      continue;
    }
    const Transform xa = store.bodies[sa.body].xf;
    const Transform xb = store.bodies[sb.body].xf;
    bool wasTouching = c.touching;
    if (c.sensor) {
      c.touching = testOverlap(sa.geometry, xa, sb.geometry, xb);
      if (c.touching && !wasTouching)
        events.events.sensorBegin.push_back({store.shapeId(c.shapeA), store.shapeId(c.shapeB)});
      if (!c.touching && wasTouching) events.contactEnded(store, c, true);
      continue;
    }
    Manifold old = c.manifold;
    float oldNormal[kMaxManifoldPoints], oldTangent[kMaxManifoldPoints];
    std::copy(c.normalImpulse, c.normalImpulse + kMaxManifoldPoints, oldNormal);
    std::copy(c.tangentImpulse, c.tangentImpulse + kMaxManifoldPoints, oldTangent);
    c.manifold = c.fn(sa.geometry, xa, sb.geometry, xb, def.speculativeDistance);
    // Ghost collisions: only contacts with flagged static shapes pay for the check.
    if (edges.activeShapes() != 0 && (sa.edges.active || sb.edges.active))
      edges.removeGhostContacts(store, c);
    // Warm start: a point keeps the impulses of the old point with the same feature id.
    for (int k = 0; k < c.manifold.pointCount; ++k) {
      c.normalImpulse[k] = 0.0f;
      c.tangentImpulse[k] = 0.0f;
      for (int j = 0; j < old.pointCount; ++j) {
        if (old.points[j].id == c.manifold.points[k].id) {
          c.normalImpulse[k] = oldNormal[j];
          c.tangentImpulse[k] = oldTangent[j];
          break;
        }
      }
    }
    c.touching = c.manifold.pointCount > 0;
    if (c.touching && !wasTouching)
      events.events.begin.push_back({store.shapeId(c.shapeA), store.shapeId(c.shapeB)});
    if (!c.touching && wasTouching) events.contactEnded(store, c, true);
  }
}

Status ContactSet::validate(const BodyStore& store) const {
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
