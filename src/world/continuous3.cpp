#include "continuous3.hpp"

#include <algorithm>
#include <cmath>

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
    out = computeToi(makeProxy(s.geometry), still, proxy, sweep, tMax);
  }
  touchingAtStart =
      (out.status == ToiStatus::hit || out.status == ToiStatus::overlapped) && out.t == 0.0f;
  return out.status == ToiStatus::hit && out.t > 0.0f ? out.t : tMax;
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

// Box2D v3's continuous stage (solver.c, read for understanding) does this in 2D: a body is
// fast when it moved more than half its thinnest extent; it is swept against static shapes,
// and (as v3 does for its bullets) against the bodies that are not fast, held at their
// poses at the end of the step; a shape it touches at the start of the sweep is met by a
// small core ball instead. Fast bodies are not swept against each other: each is put back
// on its own, against shapes no fast body moves, so the order cannot change a result.
int Continuous3::solve(BodyStore3& store) {
  int putBack = 0;
  fast_.clear();
  sweeps_.clear();
  for (const Start& start : starts_) {
    const Body3& body = store.bodies[start.body];
    const Sweep3 sweep = makeSweep3(body.localCenter, start.pose, body.transform());
    const float moved = length(sweep.c2 - sweep.c1) + sweepAngle(sweep) * body.maxExtent;
    if (moved > 0.5f * body.minExtent) {
      fast_.push_back(start);
      sweeps_.push_back(sweep);
    }
  }
  isFast_.assign(store.bodies.size(), 0);
  for (const Start& f : fast_)
    isFast_[f.body] = 1;
  for (std::size_t n = 0; n < fast_.size(); ++n) {
    const Start& start = fast_[n];
    Body3& body = store.bodies[start.body];
    const Transform3 end = body.transform();
    const Sweep3& sweep = sweeps_[n];

    float first = 1.0f;
    for (std::uint32_t shape : body.shapes) {
      const Shape3& moving = store.shapes[shape];
      const ShapeProxy3 proxy = makeProxy(moving.geometry);
      const Sphere core = coreBall(moving.geometry, body.minExtent);
      const ShapeProxy3 coreProxy = makeProxy(core);
      const Aabb3 swept = merge(store.shapeBox(shape, start.pose), store.shapeBox(shape, end));
      candidates_.clear();
      store.broadPhase().queryAabb(swept, [&](ProxyId, std::uint64_t userData) {
        const auto other = static_cast<std::uint32_t>(userData);
        const Shape3& s = store.shapes[other];
        if (s.body != start.body && isFast_[s.body] == 0 &&
            shouldCollide(s.def.filter, moving.def.filter))
          candidates_.push_back(other);
        return true;
      });
      // The tree's visiting order is its own: sorted, the earliest hit is found the same way
      // whatever the tree's shape (ties go to the lowest shape index).
      std::sort(candidates_.begin(), candidates_.end());
      for (std::uint32_t other : candidates_) {
        const Shape3& s = store.shapes[other];
        // Static, or a body that is not fast, at its pose after the solver.
        const Transform3 worldFromStatic = store.bodies[s.body].transform();
        bool touching = false;
        float t = impact(s, worldFromStatic, proxy, sweep, first, touching);
        if (touching) t = impact(s, worldFromStatic, coreProxy, sweep, first, touching);
        first = std::min(first, t);
      }
    }
    if (first >= 1.0f) continue;
    // Back to the time of impact; the velocity stays, and the next step's speculative
    // contact (sized by the speed) meets the surface.
    const Transform3 at = transformAt(sweep, first);
    const Vec3 oldCenter = body.center;
    body.origin = at.p;
    body.rotation = at.q;
    body.center = transformPoint(at, body.localCenter);
    store.moveProxies(start.body, body.center - oldCenter);
    ++putBack;
  }
  return putBack;
}

}  // namespace quack::detail
