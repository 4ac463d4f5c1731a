// The continuous phase of a step: swept boxes for fast bodies, time of impact against what
// they sweep past, and the time-ordered handling of the impacts (the seeds' execution
// phase). docs/world.md, "Continuous collision", explains the choices.

#include <algorithm>
#include <cmath>

#include "continuous.hpp"
#include "quack/collision/toi.hpp"
#include "quack/geometry/bounds.hpp"

#include "body_store.hpp"
#include "event_dispatcher.hpp"
#include "ghost_edges.hpp"
#include "quack/world/world.hpp"
#include "world_state.hpp"

namespace quack::detail {
namespace {

// Earliest first; ties by the shapes' indices, so the order never depends on the broad
// phase (determinism across structures).
template <class Candidate>
bool earlier(const Candidate& x, const Candidate& y) {
  if (x.time != y.time) return x.time < y.time;
  if (x.shapeA != y.shapeA) return x.shapeA < y.shapeA;
  return x.shapeB < y.shapeB;
}

}  // namespace

Aabb ContinuousPhase::sweptBox(const BodyStore& store, const FastBody& f) const {
  const Body& b = store.bodies[f.body];
  Aabb box;
  if (f.sweep.a1 != f.sweep.a2) {
    // Any point of the body stays within maxExtent of the centre, whatever the rotation.
    box = inflate(Aabb{minv(f.sweep.c1, f.sweep.c2), maxv(f.sweep.c1, f.sweep.c2)}, b.maxExtent);
  } else {
    const Transform start = transformAt(f.sweep, 0.0f), end = transformAt(f.sweep, 1.0f);
    bool first = true;
    for (std::uint32_t s : b.shapes) {
      Aabb u = merge(computeAabb(store.shapes[s].geometry, start),
                     computeAabb(store.shapes[s].geometry, end));
      box = first ? u : merge(box, u);
      first = false;
    }
  }
  // Shapes within the target separation count too.
  return inflate(box, kToiTargetSeparation + kToiTolerance);
}

bool ContinuousPhase::findImpact(const BodyStore& store, const BroadPhase& broadPhase,
                                 const GhostEdges& edges, std::uint32_t fast, bool continuation,
                                 ToiCandidate& best, std::uint32_t onlyBody) {
  const FastBody& f = fast_[fast];
  const Body& body = store.bodies[f.body];
  candidates_.clear();
  auto consider = [&](std::uint32_t s) {
    const Shape& other = store.shapes[s];
    if (other.body == f.body || other.def.sensor) return;
    const Body& ob = store.bodies[other.body];
    // Fast bodies meet static and kinematic shapes; bullets meet dynamic non-bullets too,
    // as those stand at the end of the step (Box2D's rule, read for understanding).
    if (ob.type == BodyType::dynamicBody && (!body.bullet || ob.bullet)) return;
    candidates_.push_back(s);
  };
  if (onlyBody != 0xffffffffu) {
    for (std::uint32_t s : store.bodies[onlyBody].shapes)
      consider(s);
  } else {
    broadPhase.queryAabb(f.box, [&](ProxyId, std::uint64_t user) {
      consider(static_cast<std::uint32_t>(user));
      return true;
    });
  }
  std::sort(candidates_.begin(), candidates_.end());
  bool found = false;
  for (std::uint32_t own : body.shapes) {
    const Shape& shape = store.shapes[own];
    if (shape.def.sensor) continue;
    const ShapeProxy proxy = makeProxy(shape.geometry);
    for (std::uint32_t s : candidates_) {
      const Shape& other = store.shapes[s];
      if (!shouldCollide(shape.def.filter, other.def.filter)) continue;
      const Body& ob = store.bodies[other.body];
      const float angle = ob.xf.q.angle();
      const Sweep still{ob.localCenter, ob.center, ob.center, angle, angle};
      const ShapeProxy otherProxy = makeProxy(other.geometry);
      ToiOutput toi = computeToi(proxy, f.sweep, otherProxy, still);
      bool stop = false;
      if ((toi.status == ToiStatus::hit || toi.status == ToiStatus::failed) && toi.t == 0.0f) {
        // Already within the target at the start: usually the shape the body hit last
        // (this step or the step before). Aim at half the present gap, so that the body may
        // slide along it but not into it. With no gap left to halve the pair is touching:
        // at the start of the step the contact solver has it; in a continued sweep, stop.
        if (toi.distance > 4.0f * kToiMinTolerance) {
          toi = computeToi(proxy, f.sweep, otherProxy, still, 1.0f, 0.5f * toi.distance);
          if (toi.status != ToiStatus::hit && toi.status != ToiStatus::failed) continue;
          stop = toi.t == 0.0f;
        } else {
          if (!continuation) continue;
          stop = true;
        }
      } else if (toi.status != ToiStatus::hit && toi.status != ToiStatus::failed) {
        continue;  // separated, or overlapping from the start (the contact solver's pair)
      }
      // A failed search returns the last time proven free: stopping there never tunnels.
      ToiCandidate c;
      c.time = f.t0 + toi.t * (1.0f - f.t0);
      c.fast = fast;
      c.stamp = f.stamp;
      c.shapeA = own;
      c.shapeB = s;
      // Ghost collisions: an impact on a flush seam of static geometry, or from behind a
      // chain, is not a surface (edges.cpp); the discrete contacts handle the real ones.
      if (edges.activeShapes() != 0 && other.edges.active &&
          edges.isGhostImpact(store, s, toi.point, -toi.normal))
        continue;
      c.point = toi.point;
      c.normal = toi.normal;
      c.stop = stop || toi.status == ToiStatus::failed;
      if (!found || earlier(c, best)) best = c;
      found = true;
    }
  }
  return found;
}

void ContinuousPhase::run(const WorldDef& def, BodyStore& store,
                          const std::vector<std::uint64_t>& awake, BroadPhase& broadPhase,
                          const GhostEdges& edges, EventDispatcher& events, float dt) {
  pushed.clear();
  if (!def.enableContinuous) return;
  fast_.clear();
  int bullets = 0;
  // Only bodies that moved can be fast (sleeping ones are not).
  for (std::size_t word = 0; word < awake.size(); ++word) {
    for (std::uint64_t bits = awake[word]; bits != 0; bits &= bits - 1) {
      const auto i = static_cast<std::uint32_t>(word * 64 + __builtin_ctzll(bits));
      Body& b = store.bodies[i];
      if (!b.fast) continue;
      b.fast = false;
      FastBody f;
      f.body = i;
      f.sweep = {b.localCenter, b.startCenter, b.center, b.startAngle, b.endAngle};
      f.box = sweptBox(store, f);
      bullets += b.bullet ? 1 : 0;
      fast_.push_back(f);
    }
  }
  if (fast_.empty()) return;

  // A min-heap by time (std's heap functions keep the largest on top: invert the order).
  auto later = [](const ToiCandidate& x, const ToiCandidate& y) { return earlier(y, x); };
  queue_.clear();
  auto push = [&](const ToiCandidate& c) {
    fast_[c.fast].bestTime = c.time;
    fast_[c.fast].bestBody = store.shapes[c.shapeB].body;
    queue_.push_back(c);
    std::push_heap(queue_.begin(), queue_.end(), later);
  };
  for (std::uint32_t i = 0; i < fast_.size(); ++i) {
    ToiCandidate c;
    if (findImpact(store, broadPhase, edges, i, false, c)) push(c);
  }

  while (!queue_.empty()) {
    std::pop_heap(queue_.begin(), queue_.end(), later);
    const ToiCandidate e = queue_.back();
    queue_.pop_back();
    FastBody& f = fast_[e.fast];
    if (e.stamp != f.stamp) continue;  // the sweep changed since this was found
    f.bestTime = 2.0f;
    f.bestBody = 0xffffffffu;
    Body& b = store.bodies[f.body];
    const Shape& other = store.shapes[e.shapeB];
    Body& ob = store.bodies[other.body];

    // Move the body to the time of impact.
    const float u = f.t0 < 1.0f ? clampf((e.time - f.t0) / (1.0f - f.t0), 0.0f, 1.0f) : 1.0f;
    const Sweep at = advance(f.sweep, u);
    const Vec2 c = at.c1;
    const float angle = at.a1;
    events.events.toi.push_back(
        {e.time, store.shapeId(e.shapeA), store.shapeId(e.shapeB), e.point, e.normal});

    // Immediate velocity response along the normal (no friction: the next step's contact
    // has it), so the rest of the step's motion goes where the body would go after the
    // impact. Restitution as the solver's: the larger of the pair, above the threshold.
    // The impulse acts at the middle of the contact manifold at the impact pose, so that a
    // face meeting a face is pushed square (TOI's single witness point is a corner, and an
    // impulse there would start a spurious spin).
    Vec2 n = e.normal;
    Vec2 hitPoint = e.point;
    const Transform xfAt = {c - rotate(Rot::fromAngle(angle), b.localCenter),
                            Rot::fromAngle(angle)};
    const Manifold m = quack::collide(store.shapes[e.shapeA].geometry, xfAt, other.geometry, ob.xf,
                                      kToiTargetSeparation + 2.0f * kToiTolerance);
    if (m.pointCount > 0) {
      n = m.normal;
      hitPoint = m.points[0].point;
      if (m.pointCount == 2) hitPoint = 0.5f * (m.points[0].point + m.points[1].point);
    }
    const Vec2 rA = hitPoint - c;
    const Vec2 rB = hitPoint - ob.center;
    const bool otherMoves = ob.type == BodyType::dynamicBody;
    const Vec2 vB = ob.v + cross(ob.w, rB);  // zero for static bodies
    const float vn = dot(vB - (b.v + cross(b.w, rA)), n);
    if (vn < 0.0f) {
      float e0 = maxf(store.shapes[e.shapeA].def.restitution, other.def.restitution);
      if (-vn < def.restitutionThreshold) e0 = 0.0f;
      const float rnA = cross(rA, n), rnB = cross(rB, n);
      float k = b.invMass + b.invInertia * rnA * rnA;
      if (otherMoves) k += ob.invMass + ob.invInertia * rnB * rnB;
      if (k > 0.0f) {
        const Vec2 impulse = (-(1.0f + e0) * vn / k) * n;  // on B; A gets its opposite
        b.v -= b.invMass * impulse;
        b.w -= b.invInertia * cross(rA, impulse);
        if (otherMoves) {
          ob.v += ob.invMass * impulse;
          ob.w += ob.invInertia * cross(rB, impulse);
          pushed.push_back(other.body);
        }
      }
    }

    // The rest of the step: on with the new velocity, or, past the bound, stay here.
    ++f.events;
    const float remaining = (1.0f - e.time) * dt;
    if (f.events < kMaxToiEventsPerBody && !e.stop && remaining > 0.0f) {
      // A dynamic body hit by a bullet stands at its end-of-step pose for the rest of the
      // step although the impact set it moving, so the bullet's sweep does not go on
      // towards it (it would meet the frozen pose again and again); the velocity itself is
      // kept for the next step.
      Vec2 sweepVelocity = b.v;
      const float towards = dot(sweepVelocity, n);
      if (otherMoves && towards > 0.0f) sweepVelocity -= towards * n;
      f.sweep = {b.localCenter, c, c + remaining * sweepVelocity, angle, angle + remaining * b.w};
    } else {
      f.sweep = {b.localCenter, c, c, angle, angle};
    }
    if (!store.shapesWithinWorld(
            f.body, makeTransform(f.sweep.c2 - rotate(Rot::fromAngle(f.sweep.a2), b.localCenter),
                                  f.sweep.a2))) {
      // The rest of the sweep would leave the world (kMaxCoordinate): stop here, as the
      // solver does with a body at the edge (StepEvents::outOfBounds).
      f.sweep = {b.localCenter, c, c, angle, angle};
      b.v = {};
      b.w = 0.0f;
      events.events.outOfBounds.push_back(store.bodyId(f.body));
    }
    f.t0 = e.time;
    f.box = sweptBox(store, f);
    ++f.stamp;
    // The body ends the step where its new sweep ends; the broad phase follows at once so
    // that later searches see it there.
    const Vec2 oldCenter = b.center;
    b.center = f.sweep.c2;
    b.xf.q = Rot::fromAngle(f.sweep.a2);
    b.xf.p = b.center - rotate(b.xf.q, b.localCenter);
    store.updateShapeBoxes(broadPhase, f.body, b.center - oldCenter);

    // Re-check what this touches: the body's own new sweep, and bullets that may meet the
    // body's new end pose (only bullets look at dynamic bodies). New events go into the
    // queue in time order; none is earlier than this one.
    ToiCandidate next;
    // A stopped body stays where it is for the rest of the step: nothing more to find.
    if (f.events < kMaxToiEventsPerBody && !e.stop &&
        findImpact(store, broadPhase, edges, e.fast, true, next))
      push(next);
    if (b.bullet || bullets == 0) continue;
    const Aabb moved = f.box;
    for (std::uint32_t g = 0; g < fast_.size(); ++g) {
      FastBody& bullet = fast_[g];
      if (g == e.fast || !store.bodies[bullet.body].bullet || bullet.events >= kMaxToiEventsPerBody)
        continue;
      if (bullet.bestBody != f.body && !overlaps(bullet.box, moved)) continue;
      if (bullet.t0 < e.time) {
        // Only re-parameterised (same path): its queued impact stays valid.
        bullet.sweep =
            advance(bullet.sweep, clampf((e.time - bullet.t0) / (1.0f - bullet.t0), 0.0f, 1.0f));
        bullet.t0 = e.time;
        bullet.box = sweptBox(store, bullet);
      }
      if (bullet.bestBody == f.body) {
        // Its impact was with this body, which has moved: search again from scratch.
        ++bullet.stamp;
        bullet.bestTime = 2.0f;
        bullet.bestBody = 0xffffffffu;
        if (findImpact(store, broadPhase, edges, g, true, next)) push(next);
      } else if (findImpact(store, broadPhase, edges, g, true, next, f.body) &&
                 next.time < bullet.bestTime) {
        // Only this body is new to it: an earlier impact with it goes into the queue beside
        // the old one (same stamp); whichever comes out first is handled, the other is then
        // stale.
        push(next);
      }
    }
  }
}

}  // namespace quack::detail
