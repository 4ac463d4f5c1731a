#include "contact_set3.hpp"

#include <algorithm>
#include <cmath>

#include "quack/world/world.hpp"

namespace quack::detail {

namespace {

bool isAwakeMover(const Body3& b) noexcept {
  return b.type != BodyType::staticBody && b.awake;
}

// The radius a shape rolls on (spheres and capsules), or 0.
float rollingRadius(const Shape3& s) noexcept {
  if (s.mesh) return 0.0f;
  if (const Sphere* sphere = std::get_if<Sphere>(s.geometry.get())) return sphere->radius;
  if (const Capsule3* capsule = std::get_if<Capsule3>(s.geometry.get())) return capsule->radius;
  return 0.0f;
}

// Warm start: each new point takes the impulses of the old point with its feature id, or
// else of the nearest unclaimed old point within kWarmStartMatchDistance. The fallback is
// needed because a box's ids are not stable when it rests exactly flush on another: its
// vertices sit on the reference face's side planes and come out as vertex points one step
// and as clipped points the next (and the reference face can swap between the boxes). Jolt
// matches its contact points by position alone; ids first keeps sliding contacts right.
constexpr float kWarmStartMatchDistance = 4.0f * kLinearSlop;

void carryImpulses(const ContactManifold3& old, ContactManifold3& now) noexcept {
  bool claimed[kMaxManifoldPoints3] = {};
  int match[kMaxManifoldPoints3] = {-1, -1, -1, -1};
  for (int i = 0; i < now.manifold.pointCount; ++i) {
    for (int j = 0; j < old.manifold.pointCount; ++j) {
      if (claimed[j] || old.manifold.points[j].id != now.manifold.points[i].id) continue;
      match[i] = j;
      claimed[j] = true;
      break;
    }
  }
  for (int i = 0; i < now.manifold.pointCount; ++i) {
    if (match[i] >= 0) continue;
    float best = kWarmStartMatchDistance * kWarmStartMatchDistance;
    for (int j = 0; j < old.manifold.pointCount; ++j) {
      if (claimed[j]) continue;
      const float d = distanceSquared(old.manifold.points[j].point, now.manifold.points[i].point);
      if (d <= best) {
        best = d;
        match[i] = j;
      }
    }
    if (match[i] >= 0) claimed[match[i]] = true;
  }
  int matched = 0;
  for (int i = 0; i < now.manifold.pointCount; ++i) {
    if (match[i] < 0) continue;
    now.normalImpulse[i] = old.normalImpulse[match[i]];
    ++matched;
  }
  // The friction at the centre belongs to the contact patch: carried only when every point
  // of the patch is the same (a box that tumbled onto another face starts again), as a
  // stale impulse warm-started into another patch kept a pile jittering.
  if (matched == now.manifold.pointCount && matched == old.manifold.pointCount) {
    now.frictionImpulse = old.frictionImpulse;
    now.twistImpulse = old.twistImpulse;
  }
  now.rollingImpulse = old.rollingImpulse;
}

// Is this a flat shape, whose resting manifolds may be recycled? Round shapes (spheres,
// capsules, rounded hulls) roll: their points move over the surface as they turn, and a
// point held fixed on a rolling ball would rise off the floor.
bool isFlat(const Shape3& s) noexcept {
  if (s.mesh) return true;
  const Hull3* hull = std::get_if<Hull3>(s.geometry.get());
  return hull != nullptr && hull->radius == 0.0f;
}

// Records, for each point of a freshly computed manifold, where it sits on each body and
// the arms from the centres of mass, so that the manifold can be recycled and the solver
// reads the same arms either way.
void recordComputed(ContactManifold3& m, const Body3& a, const Body3& b) noexcept {
  for (int k = 0; k < m.manifold.pointCount; ++k) {
    const ManifoldPoint3& mp = m.manifold.points[k];
    m.localA[k] = invTransformPoint(a.transform(), mp.point);
    m.localB[k] = invTransformPoint(b.transform(), mp.point);
    m.computedSeparation[k] = mp.separation;
    m.armA[k] = mp.point - a.center;
    m.armB[k] = mp.point - b.center;
  }
}

// Contact recycling (learned from Box2D v3's contact softening and recycling, read for
// understanding; the 2D world's contact_set.cpp does the same in 2D): while the two bodies
// are near the relative pose the manifolds were computed at, and neither has turned more
// than about 11.5 degrees since, keep them. The normal stays as it was in the world frame
// and each point stays fixed on each body; only the separation follows the bodies, as it
// does inside the sub-steps, and the solver keeps the arms as computed. A column of boxes
// then keeps the contact it was built with, instead of one clipped anew each step from a
// slightly tilted pose, which moves the contact forces the way that tilts it further: a
// 20-box column toppled in 10 s so. Returns false, touching nothing, when the bodies moved
// too far (or were teleported, or changed mass).
bool recycle(Contact3& c, const Body3& a, const Body3& b, float recycleDistance) noexcept {
  if (recycleDistance <= 0.0f || !c.flat || !c.recycleValid || !c.touching) return false;
  if (a.poseVersion != c.versionA || b.poseVersion != c.versionB) return false;
  const Transform3 xa = a.transform(), xb = b.transform();
  // Each body's own turn: |cos(angle / 2)| = |q . q0|; cos(angle) > 0.98 is
  // cos(angle / 2) > sqrt(0.99).
  const float halfCos = std::sqrt(0.5f * (1.0f + kContactRecycleCosAngle));
  if (std::fabs(dot(xa.q, c.cachedA.q)) <= halfCos || std::fabs(dot(xb.q, c.cachedB.q)) <= halfCos)
    return false;
  const Transform3 rel = invMul(xa, xb);
  const Transform3 rel0 = invMul(c.cachedA, c.cachedB);
  // The relative turn moves a point at distance r by at most r 2 sin(angle / 2) = 2 r |v|.
  const Quat qr = rel.q * conjugate(rel0.q);
  const float extentA = a.type == BodyType::staticBody ? 0.0f : a.maxExtent;
  const float extentB = b.type == BodyType::staticBody ? 0.0f : b.maxExtent;
  const float reach =
      length(rel.p - rel0.p) + 2.0f * std::max(extentA, extentB) * length(qr.vector());
  if (reach >= recycleDistance) return false;
  for (ContactManifold3& m : c.manifolds) {
    const Vec3 n = m.manifold.normal;
    for (int k = 0; k < m.manifold.pointCount; ++k) {
      ManifoldPoint3& mp = m.manifold.points[k];
      const Vec3 pa = transformPoint(xa, m.localA[k]);
      const Vec3 pb = transformPoint(xb, m.localB[k]);
      mp.separation = m.computedSeparation[k] + dot(pb - pa, n);
      mp.point = pa + 0.5f * (pb - pa);
    }
  }
  return true;
}

}  // namespace

void ContactSet3::findNew(BodyStore3& store, TaskRunner& tasks) {
  // The moved proxies' queries on the workers, each into its own list.
  pairParts_.resize(static_cast<std::size_t>(tasks.workers()));
  store.broadPhase().updatePairs(pairs_, pairParts_, [&](std::size_t count, auto&& body) {
    tasks.parallelFor(static_cast<int>(count), 64, [&](int first, int last, int participant) {
      body(static_cast<std::size_t>(first), static_cast<std::size_t>(last),
           static_cast<std::size_t>(participant));
    });
  });
  // Each pair as shape indices, and whether the world wants a contact for it (two bodies,
  // one dynamic, none there yet: most pairs a moving pile reports exist already), on the
  // workers (reads only); the wanted ones then sorted by shape indices, so that contacts
  // are made in one order whatever the structure and the workers found.
  wanted_.resize(pairs_.size());
  tasks.parallelFor(static_cast<int>(pairs_.size()), 256, [&](int first, int last, int) {
    for (auto i = static_cast<std::size_t>(first); i < static_cast<std::size_t>(last); ++i) {
      ProxyPair& p = pairs_[i];
      const auto sa = static_cast<std::uint32_t>(store.broadPhase().userData(p.a));
      const auto sb = static_cast<std::uint32_t>(store.broadPhase().userData(p.b));
      p.a.index = std::min(sa, sb);
      p.b.index = std::max(sa, sb);
      const Shape3& shapeA = store.shapes[sa];
      const Shape3& shapeB = store.shapes[sb];
      wanted_[i] = shapeA.body != shapeB.body &&
                   (store.bodies[shapeA.body].type == BodyType::dynamicBody ||
                    store.bodies[shapeB.body].type == BodyType::dynamicBody) &&
                   index_.count(key(sa, sb)) == 0;
    }
  });
  std::size_t kept = 0;
  for (std::size_t i = 0; i < pairs_.size(); ++i)
    if (wanted_[i] != 0) pairs_[kept++] = pairs_[i];
  pairs_.resize(kept);
  std::sort(pairs_.begin(), pairs_.end(), [](const ProxyPair& x, const ProxyPair& y) {
    return x.a.index != y.a.index ? x.a.index < y.a.index : x.b.index < y.b.index;
  });
  for (const ProxyPair& p : pairs_) {
    std::uint32_t a = p.a.index, b = p.b.index;
    if (store.shapes[b].mesh) std::swap(a, b);
    Contact3 c;
    c.shapeA = a;
    c.shapeB = b;
    const ShapeDef3& da = store.shapes[a].def;
    const ShapeDef3& db = store.shapes[b].def;
    c.friction = std::sqrt(da.friction * db.friction);
    c.restitution = std::max(da.restitution, db.restitution);
    const float ra = rollingRadius(store.shapes[a]);
    const float rb = rollingRadius(store.shapes[b]);
    const float radius = ra > 0.0f && rb > 0.0f ? std::min(ra, rb) : std::max(ra, rb);
    c.rollingResistance = std::max(da.rollingResistance, db.rollingResistance) * radius;
    c.flat = isFlat(store.shapes[a]) && isFlat(store.shapes[b]) && !store.shapes[b].mesh;
    index_.emplace(key(a, b), static_cast<std::uint32_t>(contacts_.size()));
    contacts_.push_back(std::move(c));
  }
}

void ContactSet3::restore(std::vector<Contact3> contacts) {
  contacts_ = std::move(contacts);
  index_.clear();
  for (std::uint32_t i = 0; i < contacts_.size(); ++i)
    index_.emplace(key(contacts_[i].shapeA, contacts_[i].shapeB), i);
}

void ContactSet3::destroy(std::uint32_t index) {
  index_.erase(key(contacts_[index].shapeA, contacts_[index].shapeB));
  const auto last = static_cast<std::uint32_t>(contacts_.size() - 1);
  if (index != last) {
    contacts_[index] = std::move(contacts_[last]);
    index_[key(contacts_[index].shapeA, contacts_[index].shapeB)] = index;
  }
  contacts_.pop_back();
}

// One contact's part of update: what happened to it, written to the contact alone (so the
// contacts can be updated side by side on the workers).
ContactSet3::Outcome ContactSet3::updateOne(Contact3& c, const BodyStore3& store,
                                            const WorldDef3& def, float dt, Scratch& scratch) {
  const Shape3& sa = store.shapes[c.shapeA];
  const Shape3& sb = store.shapes[c.shapeB];
  const Body3& ba = store.bodies[sa.body];
  const Body3& bb = store.bodies[sb.body];
  if (!isAwakeMover(ba) && !isAwakeMover(bb)) return Outcome::same;
  const BroadPhase3& bp = store.broadPhase();
  if (!overlaps(bp.fatBox(sa.proxy), bp.fatBox(sb.proxy))) return Outcome::parted;
  // Still touching: impulses, ids and events as they were.
  if (recycle(c, ba, bb, def.contactRecycleDistance)) return Outcome::same;
  std::vector<ContactManifold3>& fresh = scratch.fresh;
  fresh.clear();
  // Speculative contact (Catto, "Speculative contacts", 2013): points are kept as far
  // ahead as the bodies can close in this step, so a body falling onto a floor at a few
  // metres a second is met at the floor rather than found inside it (or through a thin
  // mesh) a step later; the solver lets such a point close exactly its gap.
  const float closing = length(bb.linearVelocity - ba.linearVelocity) +
                        length(ba.angularVelocity) * ba.maxExtent +
                        length(bb.angularVelocity) * bb.maxExtent;
  const float reach = std::min(def.speculativeDistance + dt * closing, kMaxSpeculativeReach3);
  if (sa.mesh) {
    scratch.mesh.clear();
    collideMesh(*sa.mesh, ba.transform(), *sb.geometry, bb.transform(), scratch.mesh, reach);
    for (const MeshContact3& m : scratch.mesh) {
      ContactManifold3 cm;
      cm.triangle = m.triangle;
      cm.manifold = m.manifold;
      fresh.push_back(cm);
    }
  } else {
    ContactManifold3 cm;
    const Hull3* ha = std::get_if<Hull3>(sa.geometry.get());
    const Hull3* hb = std::get_if<Hull3>(sb.geometry.get());
    cm.manifold = ha != nullptr && hb != nullptr
                      ? collideHulls(*ha, *sa.hullSat, ba.transform(), *hb, *sb.hullSat,
                                     bb.transform(), reach, c.hullCache)
                      : collide(*sa.geometry, ba.transform(), *sb.geometry, bb.transform(), reach);
    if (cm.manifold.pointCount > 0) fresh.push_back(cm);
  }
  // Both lists are in triangle order, so one merge pass matches them.
  std::size_t old = 0;
  for (ContactManifold3& now : fresh) {
    while (old < c.manifolds.size() && c.manifolds[old].triangle < now.triangle)
      ++old;
    if (old < c.manifolds.size() && c.manifolds[old].triangle == now.triangle) {
      carryImpulses(c.manifolds[old], now);
    }
  }
  c.manifolds.swap(fresh);
  for (ContactManifold3& m : c.manifolds)
    recordComputed(m, ba, bb);
  c.cachedA = ba.transform();
  c.cachedB = bb.transform();
  c.versionA = ba.poseVersion;
  c.versionB = bb.poseVersion;
  c.recycleValid = true;
  const bool touching = !c.manifolds.empty();
  const bool was = c.touching;
  c.touching = touching;
  if (touching && !was) return Outcome::began;
  if (!touching && was) return Outcome::ended;
  return Outcome::same;
}

void ContactSet3::update(const BodyStore3& store, const WorldDef3& def, float dt,
                         StepEvents3& events, TaskRunner& tasks) {
  // Every contact on the workers (each writes only its own contact and its participant's
  // scratch), then, in contact order on this thread, the events and the parted contacts
  // destroyed: the same bits and events whatever the workers did.
  scratch_.resize(static_cast<std::size_t>(tasks.workers()));
  outcomes_.resize(contacts_.size());
  tasks.parallelFor(
      static_cast<int>(contacts_.size()), 32,
      [&](int first, int last, int participant) {
        Scratch& scratch = scratch_[static_cast<std::size_t>(participant)];
        for (auto i = static_cast<std::size_t>(first); i < static_cast<std::size_t>(last); ++i)
          outcomes_[i] = updateOne(contacts_[i], store, def, dt, scratch);
      },
      TaskRunner::kHeavyRangesPerWorker);
  for (std::uint32_t i = 0; i < contacts_.size();) {
    const Contact3& c = contacts_[i];
    switch (outcomes_[i]) {
      case Outcome::parted:
        if (c.touching) events.end.push_back(event(store, c.shapeA, c.shapeB));
        // Swap-remove: the last contact (and its outcome) takes this slot, looked at next.
        outcomes_[i] = outcomes_[contacts_.size() - 1];
        outcomes_.pop_back();
        destroy(i);
        continue;
      case Outcome::began:
        events.begin.push_back(event(store, c.shapeA, c.shapeB));
        break;
      case Outcome::ended:
        events.end.push_back(event(store, c.shapeA, c.shapeB));
        break;
      case Outcome::same:
        break;
    }
    ++i;
  }
}

void ContactSet3::removeShape(const BodyStore3& store, std::uint32_t shape, StepEvents3& events) {
  for (std::uint32_t i = 0; i < contacts_.size();) {
    const Contact3& c = contacts_[i];
    if (c.shapeA != shape && c.shapeB != shape) {
      ++i;
      continue;
    }
    if (c.touching) events.end.push_back(event(store, c.shapeA, c.shapeB));
    destroy(i);
  }
}

std::size_t ContactSet3::touchingCount() const noexcept {
  return static_cast<std::size_t>(std::count_if(contacts_.begin(), contacts_.end(),
                                                [](const Contact3& c) { return c.touching; }));
}

}  // namespace quack::detail
