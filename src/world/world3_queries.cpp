// World3's queries (ray casts, box and shape overlaps, shape casts): read-only walks over
// the body store through the 3D broad phase, the 2D World's queries in three dimensions.
// Every answer is in shape-index order where several shapes tie, whatever order the tree
// visits them in.

#include <algorithm>
#include <string>

#include "quack/collision/epa3.hpp"
#include "quack/collision/toi3.hpp"
#include "quack/geometry/raycast3.hpp"
#include "quack/world/world3.hpp"
#include "world_state3.hpp"

namespace quack {

namespace {

bool accepts(const detail::Shape3& s, const QueryFilter& filter) noexcept {
  return (s.def.filter.category & filter.mask) != 0 && (filter.category & s.def.filter.mask) != 0;
}

bool finiteTransform(Transform3 xf) noexcept {
  return isFinite(xf.p) && isFinite(xf.q) && lengthSquared(xf.q) > 0.0f;
}

// The shapes whose boxes meet `box` and that the filter accepts, by shape index.
std::vector<std::uint32_t> candidatesIn(const detail::WorldState3& w, Aabb3 box,
                                        const QueryFilter& filter) {
  std::vector<std::uint32_t> out;
  w.store.broadPhase().queryAabb(box, [&](ProxyId, std::uint64_t user) {
    const auto s = static_cast<std::uint32_t>(user);
    if (accepts(w.store.shapes[s], filter)) out.push_back(s);
    return true;
  });
  std::sort(out.begin(), out.end());
  return out;
}

// The ray against one shape, world frame in and out; `maxFraction` clips it.
RayHitResult3 castRay(const detail::WorldState3& w, std::uint32_t shape, Vec3 origin,
                      Vec3 translation, float maxFraction, bool& hit) {
  const detail::Shape3& s = w.store.shapes[shape];
  const Transform3 xf = w.store.bodies[s.body].transform();
  RayHitResult3 r{w.shapeId(shape), w.bodyId(s.body), {}, {}, 0.0f, -1};
  if (s.mesh) {
    const MeshRayHit3 h = rayCastMesh(*s.mesh, xf, {origin, translation, maxFraction});
    hit = h.hit;
    r.point = h.point;
    r.normal = h.normal;
    r.fraction = h.fraction;
    r.triangle = h.triangle;
    return r;
  }
  const RayCastInput3 in{invTransformPoint(xf, origin), invRotate(xf.q, translation), maxFraction};
  const RayHit3 h = rayCast(*s.geometry, in);
  hit = h.hit;
  r.point = transformPoint(xf, h.point);
  r.normal = rotate(xf.q, h.normal);
  r.fraction = h.fraction;
  return r;
}

}  // namespace

std::optional<RayHitResult3> World3::rayCastClosest(Vec3 origin, Vec3 translation,
                                                    QueryFilter filter) const {
  if (!isFinite(origin) || !isFinite(translation)) return std::nullopt;
  const detail::WorldState3& w = *state_;
  std::optional<RayHitResult3> best;
  float bestFraction = 1.0f;
  w.store.broadPhase().rayCast(origin, translation, [&](ProxyId, std::uint64_t user, float) {
    const auto s = static_cast<std::uint32_t>(user);
    if (!accepts(w.store.shapes[s], filter)) return -1.0f;
    bool hit = false;
    const RayHitResult3 r = castRay(w, s, origin, translation, bestFraction, hit);
    if (!hit) return -1.0f;
    // Equal fractions: the lower shape index wins, whatever order the tree visits.
    if (best && r.fraction == bestFraction && s > best->shape.index) return -1.0f;
    bestFraction = r.fraction;
    best = r;
    return r.fraction > 0.0f ? r.fraction : 0.0f;
  });
  return best;
}

std::vector<RayHitResult3> World3::rayCastAll(Vec3 origin, Vec3 translation,
                                              QueryFilter filter) const {
  std::vector<RayHitResult3> hits;
  if (!isFinite(origin) || !isFinite(translation)) return hits;
  const detail::WorldState3& w = *state_;
  w.store.broadPhase().rayCast(origin, translation, [&](ProxyId, std::uint64_t user, float) {
    const auto s = static_cast<std::uint32_t>(user);
    if (!accepts(w.store.shapes[s], filter)) return -1.0f;
    bool hit = false;
    const RayHitResult3 r = castRay(w, s, origin, translation, 1.0f, hit);
    if (hit) hits.push_back(r);
    return 1.0f;
  });
  std::sort(hits.begin(), hits.end(), [](const RayHitResult3& a, const RayHitResult3& b) {
    return a.fraction != b.fraction ? a.fraction < b.fraction : a.shape.index < b.shape.index;
  });
  return hits;
}

std::vector<ShapeId3> World3::overlapAabb(Aabb3 box, QueryFilter filter) const {
  std::vector<ShapeId3> out;
  if (!quack::isValid(box)) return out;
  const detail::WorldState3& w = *state_;
  w.store.broadPhase().queryAabb(box, [&](ProxyId, std::uint64_t user) {
    const auto s = static_cast<std::uint32_t>(user);
    if (accepts(w.store.shapes[s], filter)) out.push_back(w.shapeId(s));
    return true;
  });
  std::sort(out.begin(), out.end(), [](ShapeId3 a, ShapeId3 b) { return a.index < b.index; });
  return out;
}

Result<std::vector<ShapeOverlap3>> World3::overlapShape(const ShapeGeometry3& geometry,
                                                        Transform3 xf, QueryFilter filter) const {
  if (!finiteTransform(xf)) return fail("overlapShape: transform is not finite");
  if (Status s = validateShape(geometry); !s) return fail("overlapShape: geometry: " + s.message());
  xf.q = normalize(xf.q);
  const detail::WorldState3& w = *state_;
  const ShapeProxy3 query = makeProxy(geometry);
  std::vector<ShapeOverlap3> out;
  for (std::uint32_t s : candidatesIn(w, detail::proxyBox(query, xf), filter)) {
    const detail::Shape3& shape = w.store.shapes[s];
    const Transform3 sx = w.store.bodies[shape.body].transform();
    // The shape met is A, the query B: B moves along the normal (A to B) by the depth.
    PenetrationOutput3 p;
    if (shape.mesh) {
      p = computePenetrationMesh(*shape.mesh, sx, query, xf);
    } else {
      p = computePenetration(makeProxy(*shape.geometry), sx, query, xf);
    }
    if (p.overlap) out.push_back({w.shapeId(s), w.bodyId(shape.body), p.depth, p.depth * p.normal});
  }
  return out;
}

Result<std::optional<ShapeCastResult3>> World3::castShape(const ShapeGeometry3& geometry,
                                                          Transform3 xf, Vec3 translation,
                                                          QueryFilter filter) const {
  if (!finiteTransform(xf)) return fail("castShape: transform is not finite");
  if (!isFinite(translation)) return fail("castShape: translation is not finite");
  if (Status s = validateShape(geometry); !s) return fail("castShape: geometry: " + s.message());
  xf.q = normalize(xf.q);
  const detail::WorldState3& w = *state_;
  const ShapeProxy3 cast = makeProxy(geometry);
  // Everything the swept box of the cast meets is a candidate.
  const Aabb3 start = detail::proxyBox(cast, xf);
  const Aabb3 swept{minv(start.lower, start.lower + translation),
                    maxv(start.upper, start.upper + translation)};
  std::optional<ShapeCastResult3> best;
  for (std::uint32_t s : candidatesIn(w, swept, filter)) {
    const detail::Shape3& shape = w.store.shapes[s];
    const Transform3 sx = w.store.bodies[shape.body].transform();
    const float maxFraction = best ? best->fraction : 1.0f;
    const ShapeCastOutput3 out =
        shape.mesh
            ? castShapeMesh(*shape.mesh, sx, cast, xf, translation, maxFraction)
            : quack::castShape(makeProxy(*shape.geometry), sx, cast, xf, translation, maxFraction);
    // In index order, so a later shape at an equal fraction does not replace the first.
    if (!out.hit || (best && out.fraction >= best->fraction)) continue;
    best =
        ShapeCastResult3{w.shapeId(s), w.bodyId(shape.body), out.point, out.normal, out.fraction};
  }
  return best;
}

}  // namespace quack
