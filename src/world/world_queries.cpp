// World queries (ray casts, overlap tests) and inspection: read-only walks over the body
// store through the broad phase.

#include <algorithm>
#include <cstring>

#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/shape_cast.hpp"
#include "quack/geometry/bounds.hpp"
#include "quack/geometry/raycast.hpp"
#include "quack/world/world.hpp"
#include "world_state.hpp"

namespace quack {
// ---- queries -------------------------------------------------------------------------------

bool World::acceptsQuery(std::uint32_t shape, const QueryFilter& filter) const {
  const detail::Shape& s = state().store.shapes[shape];
  if (s.def.sensor && !filter.includeSensors) return false;
  return (s.def.filter.category & filter.mask) != 0 && (filter.category & s.def.filter.mask) != 0;
}

namespace {

// The ray in a shape's frame, clipped to `maxFraction`.
RayHit castRay(const ShapeGeometry& g, Transform xf, Vec2 origin, Vec2 translation,
               float maxFraction) {
  RayCastInput in{invTransformPoint(xf, origin), invRotate(xf.q, translation), maxFraction};
  return rayCast(g, in);
}

}  // namespace

std::optional<RayHitResult> World::rayCastClosest(Vec2 origin, Vec2 translation,
                                                  QueryFilter filter) const {
  if (!isFinite(origin) || !isFinite(translation)) return std::nullopt;
  std::optional<RayHitResult> best;
  float bestFraction = 1.0f;
  state().broadPhase.rayCast(origin, translation, [&](ProxyId, std::uint64_t user, float) -> float {
    auto s = static_cast<std::uint32_t>(user);
    if (!acceptsQuery(s, filter)) return -1.0f;
    const Transform xf = state().store.bodies[state().store.shapes[s].body].xf;
    RayHit h = castRay(*state().store.shapes[s].geometry, xf, origin, translation, bestFraction);
    if (!h.hit) return -1.0f;
    // Equal fractions: the lower shape index wins, whatever order the structure visits.
    if (best && h.fraction == bestFraction && s > best->shape.index) return -1.0f;
    bestFraction = h.fraction;
    best =
        RayHitResult{state().store.shapeId(s), state().store.bodyId(state().store.shapes[s].body),
                     transformPoint(xf, h.point), rotate(xf.q, h.normal), h.fraction};
    return h.fraction > 0.0f ? h.fraction : 0.0f;
  });
  return best;
}

std::vector<RayHitResult> World::rayCastAll(Vec2 origin, Vec2 translation,
                                            QueryFilter filter) const {
  std::vector<RayHitResult> hits;
  if (!isFinite(origin) || !isFinite(translation)) return hits;
  state().broadPhase.rayCast(origin, translation, [&](ProxyId, std::uint64_t user, float) -> float {
    auto s = static_cast<std::uint32_t>(user);
    if (!acceptsQuery(s, filter)) return -1.0f;
    const Transform xf = state().store.bodies[state().store.shapes[s].body].xf;
    RayHit h = castRay(*state().store.shapes[s].geometry, xf, origin, translation, 1.0f);
    if (h.hit) {
      hits.push_back({state().store.shapeId(s), state().store.bodyId(state().store.shapes[s].body),
                      transformPoint(xf, h.point), rotate(xf.q, h.normal), h.fraction});
    }
    return 1.0f;
  });
  std::sort(hits.begin(), hits.end(), [](const RayHitResult& a, const RayHitResult& b) {
    return a.fraction != b.fraction ? a.fraction < b.fraction : a.shape.index < b.shape.index;
  });
  return hits;
}

std::vector<ShapeId> World::overlapAabb(Aabb box, QueryFilter filter) const {
  std::vector<ShapeId> out;
  if (!quack::isValid(box)) return out;
  state().broadPhase.queryAabb(box, [&](ProxyId, std::uint64_t user) {
    auto s = static_cast<std::uint32_t>(user);
    if (acceptsQuery(s, filter)) out.push_back(state().store.shapeId(s));
    return true;
  });
  std::sort(out.begin(), out.end(), [](ShapeId a, ShapeId b) { return a.index < b.index; });
  return out;
}

Result<std::vector<ShapeOverlap>> World::overlapShape(const ShapeGeometry& geometry, Transform xf,
                                                      QueryFilter filter) const {
  if (!isFinite(xf.p) || !isFinite(xf.q.c) || !isFinite(xf.q.s))
    return fail("overlapShape: transform is not finite");
  if (Status s = validateShape(geometry); !s) return fail("overlapShape: geometry: " + s.message());
  std::vector<ShapeOverlap> out;
  const ShapeProxy query = makeProxy(geometry);
  state().broadPhase.queryAabb(computeAabb(geometry, xf), [&](ProxyId, std::uint64_t user) {
    auto s = static_cast<std::uint32_t>(user);
    if (!acceptsQuery(s, filter)) return true;
    const Transform sx = state().store.bodies[state().store.shapes[s].body].xf;
    PenetrationOutput p =
        computePenetration(query, xf, makeProxy(*state().store.shapes[s].geometry), sx);
    if (p.overlap) {
      out.push_back({state().store.shapeId(s), state().store.bodyId(state().store.shapes[s].body),
                     p.depth, -p.depth * p.normal});
    }
    return true;
  });
  std::sort(out.begin(), out.end(), [](const ShapeOverlap& a, const ShapeOverlap& b) {
    return a.shape.index < b.shape.index;
  });
  return out;
}

Result<std::optional<ShapeCastResult>> World::castShape(const ShapeGeometry& geometry, Transform xf,
                                                        Vec2 translation,
                                                        QueryFilter filter) const {
  if (!isFinite(xf.p) || !isFinite(xf.q.c) || !isFinite(xf.q.s))
    return fail("castShape: transform is not finite");
  if (!isFinite(translation)) return fail("castShape: translation is not finite");
  if (Status s = validateShape(geometry); !s) return fail("castShape: geometry: " + s.message());
  const ShapeProxy cast = makeProxy(geometry);
  // Everything the swept box of the cast meets is a candidate.
  const Aabb start = computeAabb(geometry, xf);
  const Aabb swept{minv(start.lower, start.lower + translation),
                   maxv(start.upper, start.upper + translation)};
  std::optional<ShapeCastResult> best;
  state().broadPhase.queryAabb(swept, [&](ProxyId, std::uint64_t user) {
    auto s = static_cast<std::uint32_t>(user);
    if (!acceptsQuery(s, filter)) return true;
    const detail::Shape& shape = state().store.shapes[s];
    const Transform sx = state().store.bodies[shape.body].xf;
    // The shape met is A, the cast shape is B moving along the translation.
    const ShapeCastOutput out =
        quack::castShape(makeProxy(*shape.geometry), sx, cast, xf, translation);
    if (!out.hit) return true;
    if (best && (out.fraction > best->fraction ||
                 (out.fraction == best->fraction && s > best->shape.index)))
      return true;
    best = ShapeCastResult{state().store.shapeId(s), state().store.bodyId(shape.body), out.point,
                           out.normal, out.fraction};
    return true;
  });
  return best;
}

// ---- inspection ------------------------------------------------------------------------------

const char* World::simdPath() noexcept {
  return detail::Solver::simdPath();
}

int World::workerCount() const noexcept {
  return state().tasks.workers();
}

World::SolverStats World::solverStats() const noexcept {
  const auto& st = state().solver.stats();
  return {st.colors, st.constraints, st.overflow};
}

World::ContinuousStats World::continuousStats() const noexcept {
  const auto& st = state().continuous.stats();
  return {st.fastBodies, st.toiSearches};
}

std::uint64_t World::stateHash() const noexcept {
  // FNV-1a over the bit patterns, so that any difference at all changes the hash.
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](float f) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    for (int k = 0; k < 4; ++k) {
      h ^= (bits >> (8 * k)) & 0xffu;
      h *= 1099511628211ull;
    }
  };
  for (std::uint32_t i = 0; i < state().store.bodies.size(); ++i) {
    if (!state().store.bodyAlive(i)) continue;
    const detail::Body& b = state().store.bodies[i];
    mix(b.xf.p.x);
    mix(b.xf.p.y);
    mix(b.xf.q.c);
    mix(b.xf.q.s);
    mix(b.v.x);
    mix(b.v.y);
    mix(b.w);
    // Asleep or awake, and how long it has rested: sleeping is part of the state.
    mix(b.awake ? 1.0f : 0.0f);
    mix(b.sleepTime);
  }
  return h;
}

}  // namespace quack
