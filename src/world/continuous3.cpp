#include "continuous3.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "quack/collision/mesh3.hpp"
#include "quack/collision/proxy3.hpp"
#include "quack/collision/toi3.hpp"
#include "quack/math/sweep3.hpp"

namespace quack::detail {

namespace {

// A small ball at the shape's centre (a quarter of its thickness): swept instead of the
// shape when the shape already touches the static one at the start of the step, so a body
// sliding fast along a floor is not held at t = 0, while its core still cannot pass
// through (Box2D v3's continuous stage falls back so, read for understanding).
Sphere coreBall(const ShapeGeometry3& g, float thickness) noexcept {
  Vec3 c;
  if (const Sphere* s = std::get_if<Sphere>(&g)) c = s->center;
  if (const Capsule3* k = std::get_if<Capsule3>(&g)) c = 0.5f * (k->p1 + k->p2);
  if (const Hull3* h = std::get_if<Hull3>(&g)) c = h->centroid;
  if (const Triangle3* t = std::get_if<Triangle3>(&g))
    c = (1.0f / 3.0f) * (t->v[0] + t->v[1] + t->v[2]);
  return Sphere{c, std::max(0.25f * thickness, kLinearSlop)};
}

// The time of impact of `proxy` (swept) with static shape `s`, up to tMax: the hit's t, or
// tMax when there is none. touchingAtStart: a hit at t = 0.
float impact(const Shape3& s, Transform3 worldFromStatic, const ShapeProxy3& proxy,
             const Sweep3& sweep, float tMax, bool& touchingAtStart) {
  ToiOutput3 out;
  if (s.mesh) {
    out = computeToiMesh(*s.mesh, worldFromStatic, proxy, sweep, tMax);
  } else {
    const Sweep3 still{Vec3{}, worldFromStatic.p, worldFromStatic.p, worldFromStatic.q, Vec3{}};
    out = computeToi(makeProxy(*s.geometry), still, proxy, sweep, tMax);
  }
  touchingAtStart =
      (out.status == ToiStatus::hit || out.status == ToiStatus::overlapped) && out.t == 0.0f;
  return out.status == ToiStatus::hit && out.t > 0.0f ? out.t : tMax;
}

// The same for two shapes on their sweeps; `touchingAtStart` as above.
float impactMoving(const ShapeProxy3& a, const Sweep3& sweepA, const ShapeProxy3& b,
                   const Sweep3& sweepB, float tMax, bool& touchingAtStart) {
  const ToiOutput3 out = computeToi(a, sweepA, b, sweepB, tMax);
  touchingAtStart =
      (out.status == ToiStatus::hit || out.status == ToiStatus::overlapped) && out.t == 0.0f;
  return out.status == ToiStatus::hit && out.t > 0.0f ? out.t : tMax;
}

// The part of `s` from fraction t0 to 1, as a sweep over [0, 1] (same axis, same rate).
Sweep3 restOf(const Sweep3& s, float t0) noexcept {
  const Transform3 at = transformAt(s, t0);
  return {s.localCenter, transformPoint(at, s.localCenter), s.c2, at.q, (1.0f - t0) * s.rotation};
}

// Whether two bodies may come within the target of each other in a step: the gap between
// their bounding balls (radius `reach` about the centre of mass, at the start) against the
// most the centres' relative motion and the turns (each angle times its reach) can close it.
// A cheap test before a time of impact.
bool ballsMayMeet(Vec3 startA, Vec3 moveA, float turnA, float reachA, Vec3 startB, Vec3 moveB,
                  float turnB, float reachB) noexcept {
  const float gap = length(startB - startA) - reachA - reachB;
  const float closing = length(moveB - moveA) + turnA * reachA + turnB * reachB;
  return gap <= closing + 2.0f * kToiTargetSeparation;
}

// The same from the boxes, seen from a's translation: a's box at the start, grown by how
// far its turn can carry a point (angle times reach), against b's box at the start swept by
// the centres' relative motion (linear in t) and grown by b's turn; sound because a point
// turned by an angle w at a distance r from the centre moves at most w r. Fast bodies that
// fall side by side, their balls touching, have boxes apart.
template <class Fast>
bool mayMeet(const Fast& a, float reachA, const Fast& b, float reachB) noexcept {
  const Vec3 d = (b.sweep.c2 - b.sweep.c1) - (a.sweep.c2 - a.sweep.c1);
  const float grow =
      sweepAngle(a.sweep) * reachA + sweepAngle(b.sweep) * reachB + 2.0f * kToiTargetSeparation;
  const Vec3 g{grow, grow, grow};
  const Aabb3 swept{minv(b.startBox.lower, b.startBox.lower + d) - g,
                    maxv(b.startBox.upper, b.startBox.upper + d) + g};
  return overlaps(a.startBox, swept);
}

float component(Vec3 v, int axis) noexcept {
  return axis == 0 ? v.x : axis == 1 ? v.y : v.z;
}

// Earliest first; equal times to the lower body, then the lower other body, then the kind,
// so that the order is total and the heap pops the same sequence whatever was pushed first.
template <class Event>
bool later(const Event& x, const Event& y) noexcept {
  if (x.t != y.t) return x.t > y.t;
  if (x.a != y.a) return x.a > y.a;
  if (x.b != y.b) return x.b > y.b;
  return x.kind > y.kind;
}

}  // namespace

void Continuous3::recordStarts(const BodyStore3& store) {
  starts_.clear();
  for (std::uint32_t i = 0; i < store.bodies.size(); ++i) {
    const Body3& b = store.bodies[i];
    if (store.bodyIds.isAlive(i) && b.type == BodyType::dynamicBody && b.awake)
      starts_.push_back({i, b.transform()});
  }
}

// A body is fast when its centre moved, plus its turn times its largest extent, more than
// half its thinnest shape.
void Continuous3::findFast(const BodyStore3& store) {
  fast_.clear();
  isFast_.assign(store.bodies.size(), 0);
  for (const Start& start : starts_) {
    const Body3& body = store.bodies[start.body];
    const Transform3 end = body.transform();
    const Sweep3 sweep = makeSweep3(body.localCenter, start.pose, end);
    const float moved = length(sweep.c2 - sweep.c1) + sweepAngle(sweep) * body.maxExtent;
    if (!(moved > 0.5f * body.minExtent) || body.shapes.empty()) continue;
    Aabb3 startBox = store.shapeBox(body.shapes[0], start.pose);
    Aabb3 endBox = store.shapeBox(body.shapes[0], end);
    for (std::uint32_t shape : body.shapes) {
      startBox = merge(startBox, store.shapeBox(shape, start.pose));
      endBox = merge(endBox, store.shapeBox(shape, end));
    }
    fast_.push_back({start.body, start.pose, sweep, startBox, merge(startBox, endBox)});
    isFast_[start.body] = 1;
  }
}

// The first impact of fast body f with static shapes, meshes and bodies that are not fast
// (held at their poses after the solver), or 1.
float Continuous3::meetStill(const BodyStore3& store, const Fast& f,
                             std::vector<std::uint32_t>& candidates) const {
  const Body3& body = store.bodies[f.body];
  const Transform3 end = body.transform();
  float first = 1.0f;
  for (std::uint32_t shape : body.shapes) {
    const Shape3& moving = store.shapes[shape];
    const ShapeProxy3 proxy = makeProxy(*moving.geometry);
    const ShapeProxy3 coreProxy = makeProxy(coreBall(*moving.geometry, body.minExtent));
    const Aabb3 swept = body.shapes.size() == 1
                            ? f.box
                            : merge(store.shapeBox(shape, f.start), store.shapeBox(shape, end));
    candidates.clear();
    store.broadPhase().queryAabb(swept, [&](ProxyId, std::uint64_t userData) {
      const auto other = static_cast<std::uint32_t>(userData);
      const Shape3& s = store.shapes[other];
      if (s.body != f.body && isFast_[s.body] == 0 &&
          shouldCollide(s.def.filter, moving.def.filter))
        candidates.push_back(other);
      return true;
    });
    // The tree's visiting order is its own: sorted, the earliest hit is found the same way
    // whatever the tree's shape (ties go to the lowest shape index).
    std::sort(candidates.begin(), candidates.end());
    for (std::uint32_t other : candidates) {
      const Shape3& s = store.shapes[other];
      const Transform3 worldFromStatic = store.bodies[s.body].transform();
      bool touching = false;
      float t = impact(s, worldFromStatic, proxy, f.sweep, first, touching);
      if (touching) t = impact(s, worldFromStatic, coreProxy, f.sweep, first, touching);
      first = std::min(first, t);
    }
  }
  return first;
}

// The first impact of fast bodies a and b, each on its sweep, before tMax (else tMax). Two
// shapes that already touch at the start are left to the solver unless either's core ball
// meets the other (the rule against static shapes, from both sides so that it is symmetric).
float Continuous3::meetMoving(const BodyStore3& store, const Fast& a, const Fast& b,
                              float tMax) const {
  const Body3& bodyA = store.bodies[a.body];
  const Body3& bodyB = store.bodies[b.body];
  if (!mayMeet(a, bodyA.maxExtent, b, bodyB.maxExtent)) return tMax;
  const Transform3 endA = bodyA.transform(), endB = bodyB.transform();
  // The bodies' swept boxes met (findPairs): a shape's own is only worth making when there
  // are others.
  const bool oneShapeEach = bodyA.shapes.size() == 1 && bodyB.shapes.size() == 1;
  float first = tMax;
  for (std::uint32_t sa : bodyA.shapes) {
    const Shape3& shapeA = store.shapes[sa];
    const Aabb3 boxA =
        oneShapeEach ? a.box : merge(store.shapeBox(sa, a.start), store.shapeBox(sa, endA));
    const ShapeProxy3 proxyA = makeProxy(*shapeA.geometry);
    for (std::uint32_t sb : bodyB.shapes) {
      const Shape3& shapeB = store.shapes[sb];
      if (!shouldCollide(shapeA.def.filter, shapeB.def.filter)) continue;
      if (!oneShapeEach &&
          !overlaps(boxA, merge(store.shapeBox(sb, b.start), store.shapeBox(sb, endB))))
        continue;
      const ShapeProxy3 proxyB = makeProxy(*shapeB.geometry);
      bool touching = false;
      float t = impactMoving(proxyA, a.sweep, proxyB, b.sweep, first, touching);
      if (touching) {
        const ShapeProxy3 coreA = makeProxy(coreBall(*shapeA.geometry, bodyA.minExtent));
        const ShapeProxy3 coreB = makeProxy(coreBall(*shapeB.geometry, bodyB.minExtent));
        t = std::min(impactMoving(coreA, a.sweep, proxyB, b.sweep, first, touching),
                     impactMoving(proxyA, a.sweep, coreB, b.sweep, first, touching));
      }
      first = std::min(first, t);
    }
  }
  return first;
}

// The first impact of `moving`, over `rest` (the part of its sweep after `stopped` was put
// back), with `stopped` where it was put back: a fraction of `rest`, or 1.
float Continuous3::meetStopped(const BodyStore3& store, const Fast& moving, const Sweep3& rest,
                               const Fast& stopped) const {
  const Body3& bodyM = store.bodies[moving.body];
  const Body3& bodyS = store.bodies[stopped.body];
  if (!ballsMayMeet(rest.c1, rest.c2 - rest.c1, sweepAngle(rest), bodyM.maxExtent, bodyS.center,
                    Vec3{}, 0.0f, bodyS.maxExtent))
    return 1.0f;
  const Transform3 worldFromStopped = bodyS.transform();
  const bool oneShapeEach = bodyM.shapes.size() == 1 && bodyS.shapes.size() == 1;
  float first = 1.0f;
  for (std::uint32_t sm : bodyM.shapes) {
    const Shape3& shapeM = store.shapes[sm];
    const Aabb3 boxM = oneShapeEach ? Aabb3{}
                                    : merge(store.shapeBox(sm, transformAt(rest, 0.0f)),
                                            store.shapeBox(sm, bodyM.transform()));
    const ShapeProxy3 proxy = makeProxy(*shapeM.geometry);
    for (std::uint32_t ss : bodyS.shapes) {
      const Shape3& shapeS = store.shapes[ss];
      if (!shouldCollide(shapeS.def.filter, shapeM.def.filter)) continue;
      if (!oneShapeEach && !overlaps(boxM, store.shapeBox(ss))) continue;
      bool touching = false;
      float t = impact(shapeS, worldFromStopped, proxy, rest, first, touching);
      if (touching) {
        const ShapeProxy3 core = makeProxy(coreBall(*shapeM.geometry, bodyM.minExtent));
        t = impact(shapeS, worldFromStopped, core, rest, first, touching);
      }
      first = std::min(first, t);
    }
  }
  return first;
}

// Sort and sweep over the fast bodies' swept boxes along the axis on which their centres
// spread furthest (a pile falling in columns overlaps on every horizontal axis; ties to x,
// then y), ties in the sort to the lower body; each pair once as (lower, higher) index into
// fast_, at most maxPairs of them.
void Continuous3::findPairs(int maxPairs, Continuous3Result& result) {
  pairs_.clear();
  Vec3 low = center(fast_[0].box), high = low;
  for (const Fast& f : fast_) {
    low = minv(low, center(f.box));
    high = maxv(high, center(f.box));
  }
  const Vec3 spread = high - low;
  const int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : spread.y >= spread.z ? 1 : 2;
  auto lower = [&](std::uint32_t f) { return component(fast_[f].box.lower, axis); };
  auto upper = [&](std::uint32_t f) { return component(fast_[f].box.upper, axis); };
  order_.resize(fast_.size());
  for (std::uint32_t i = 0; i < fast_.size(); ++i)
    order_[i] = i;
  std::sort(order_.begin(), order_.end(), [&](std::uint32_t x, std::uint32_t y) {
    return lower(x) != lower(y) ? lower(x) < lower(y) : x < y;
  });
  for (std::size_t n = 0; n < order_.size(); ++n) {
    const Aabb3& box = fast_[order_[n]].box;
    const float end = upper(order_[n]);
    for (std::size_t m = n + 1; m < order_.size(); ++m) {
      if (lower(order_[m]) > end) break;
      if (!overlaps(box, fast_[order_[m]].box)) continue;
      if (static_cast<int>(pairs_.size()) >= maxPairs) {
        result.status = Continuous3Status::pairsCapped;
        break;
      }
      pairs_.push_back(std::minmax(order_[n], order_[m]));
    }
  }
  result.fastPairs = static_cast<int>(pairs_.size());
  neighbourStart_.assign(fast_.size() + 1, 0);
  for (const auto& [a, b] : pairs_) {
    ++neighbourStart_[a + 1];
    ++neighbourStart_[b + 1];
  }
  for (std::size_t i = 0; i < fast_.size(); ++i)
    neighbourStart_[i + 1] += neighbourStart_[i];
  neighbours_.resize(2 * pairs_.size());
  std::vector<std::uint32_t>& fill = order_;  // reused as each body's next free slot
  fill.assign(neighbourStart_.begin(), neighbourStart_.end() - 1);
  for (const auto& [a, b] : pairs_) {
    neighbours_[fill[a]++] = b;
    neighbours_[fill[b]++] = a;
  }
}

void Continuous3::pushEvent(const Event& e) {
  events_.push_back(e);
  std::push_heap(events_.begin(), events_.end(), later<Event>);
}

// Back to the time of impact; the velocity stays, and the next step's speculative contact
// (sized by the speed) meets the surface.
void Continuous3::stop(BodyStore3& store, std::uint32_t f, float t, const Transform3& at) {
  Fast& fast = fast_[f];
  Body3& body = store.bodies[fast.body];
  const Vec3 oldCenter = body.center;
  body.origin = at.p;
  body.rotation = at.q;
  body.center = transformPoint(at, body.localCenter);
  store.moveProxies(fast.body, body.center - oldCenter);
  fast.stopped = true;
  fast.stopTime = t;
  justStopped_.push_back(f);
}

// Box2D v3's continuous stage (solver.c, read for understanding) sweeps fast bodies against
// static shapes and its bullets against the bodies that are not fast; the 2D world's
// continuous phase (continuous.cpp) adds sweep against sweep in time order. Here: every
// fast body's first impact with what does not move fast, and every pair of fast bodies'
// first meeting before either's, go into one queue; the earliest is taken, its bodies put
// back; a body put back stays there for the rest of the step, and each fast neighbour still
// moving is swept, from that time on, against it there. Each valid event puts back at least
// one body, so the loop runs at most once per fast body plus the stale events, which are
// bounded by the pairs (at most maxPairs).
Continuous3Result Continuous3::solve(BodyStore3& store, TaskRunner& tasks, int maxPairs) {
  Continuous3Result result;
  findFast(store);
  result.fastBodies = static_cast<int>(fast_.size());
  if (fast_.empty()) return result;
  events_.clear();
  // The searches read the store and write only their own body's or pair's time: on the
  // workers, then queued here in order (the heap's order is total, so the same events pop
  // in the same sequence whatever the workers did).
  candidateParts_.resize(static_cast<std::size_t>(tasks.workers()));
  tasks.parallelFor(
      static_cast<int>(fast_.size()), 8,
      [&](int first, int last, int participant) {
        for (auto i = static_cast<std::size_t>(first); i < static_cast<std::size_t>(last); ++i)
          fast_[i].stillTime =
              meetStill(store, fast_[i], candidateParts_[static_cast<std::size_t>(participant)]);
      },
      TaskRunner::kHeavyRangesPerWorker);
  for (std::uint32_t i = 0; i < fast_.size(); ++i) {
    const float t = fast_[i].stillTime;
    if (t < 1.0f) pushEvent({t, t, i, i, Kind::still});
  }
  findPairs(maxPairs, result);
  // A pair's meeting after either's impact with still shapes never happens as swept: the
  // first one to be put back is met where it stopped instead.
  pairTimes_.resize(pairs_.size());
  tasks.parallelFor(
      static_cast<int>(pairs_.size()), 16,
      [&](int first, int last, int) {
        for (auto k = static_cast<std::size_t>(first); k < static_cast<std::size_t>(last); ++k) {
          const auto [a, b] = pairs_[k];
          const float tMax = std::min(fast_[a].stillTime, fast_[b].stillTime);
          pairTimes_[k] = meetMoving(store, fast_[a], fast_[b], tMax);
        }
      },
      TaskRunner::kHeavyRangesPerWorker);
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const auto [a, b] = pairs_[k];
    const float tMax = std::min(fast_[a].stillTime, fast_[b].stillTime);
    const float t = pairTimes_[k];
    if (t < tMax) pushEvent({t, t, a, b, Kind::moving});
  }
  while (!events_.empty()) {
    std::pop_heap(events_.begin(), events_.end(), later<Event>);
    const Event e = events_.back();
    events_.pop_back();
    Fast& a = fast_[e.a];
    if (a.stopped) continue;  // stale: a was put back earlier
    justStopped_.clear();
    if (e.kind == Kind::still) {
      stop(store, e.a, e.t, transformAt(a.sweep, e.t));
    } else if (e.kind == Kind::moving) {
      if (fast_[e.b].stopped) continue;
      stop(store, e.a, e.t, transformAt(a.sweep, e.t));
      stop(store, e.b, e.t, transformAt(fast_[e.b].sweep, e.t));
    } else {
      stop(store, e.a, e.t, transformAt(restOf(a.sweep, fast_[e.b].stopTime), e.local));
    }
    result.putBack += static_cast<int>(justStopped_.size());
    for (std::uint32_t s : justStopped_) {
      const float t0 = fast_[s].stopTime;
      for (std::uint32_t k = neighbourStart_[s]; k < neighbourStart_[s + 1]; ++k) {
        const std::uint32_t m = neighbours_[k];
        if (fast_[m].stopped) continue;
        const Sweep3 rest = restOf(fast_[m].sweep, t0);
        const float u = meetStopped(store, fast_[m], rest, fast_[s]);
        if (u < 1.0f) pushEvent({t0 + u * (1.0f - t0), u, m, s, Kind::stopped});
      }
    }
  }
  return result;
}

}  // namespace quack::detail
