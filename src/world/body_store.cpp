#include "body_store.hpp"

#include <algorithm>
#include <limits>

#include "quack/collision/proxy.hpp"
#include "quack/collision/toi.hpp"
#include "quack/geometry/bounds.hpp"
#include "quack/geometry/mass.hpp"

namespace quack {

const char* toString(BodyType type) noexcept {
  switch (type) {
    case BodyType::staticBody:
      return "static";
    case BodyType::kinematicBody:
      return "kinematic";
    case BodyType::dynamicBody:
      return "dynamic";
  }
  return "unknown";
}

}  // namespace quack

namespace quack::detail {

namespace {
// Finite, not inverted, within the broad phase's range (every comparison is false for NaN).
bool boxWithinWorld(const Aabb& box) {
  return box.lower.x <= box.upper.x && box.lower.y <= box.upper.y &&
         withinCoordinateLimit(box.lower) && withinCoordinateLimit(box.upper);
}
}  // namespace

std::uint32_t BodyStore::createBody(const BodyDef& def) {
  const std::uint32_t index = bodyIds.allocate();
  if (index == bodies.size()) bodies.emplace_back();
  Body& b = bodies[index];
  b = Body{};
  b.type = def.type;
  b.xf = makeTransform(def.position, def.angle);
  b.center = def.position;
  const bool moves = def.type != BodyType::staticBody;
  b.v = moves ? def.linearVelocity : Vec2{};
  b.w = moves ? def.angularVelocity : 0.0f;
  b.linearDamping = def.linearDamping;
  b.angularDamping = def.angularDamping;
  b.gravityScale = def.gravityScale;
  b.bullet = def.bullet;
  b.enableSleep = def.enableSleep;
  b.sleepThreshold = def.sleepThreshold;
  b.awake = moves;  // the island set decides (World::createBody)
  b.userData = def.userData;
  updateMass(index);
  return index;
}

namespace {

// Every field a polygon's users read (the arrays' unused tails left out).
std::string polygonKey(const Polygon& p) {
  const std::size_t n = static_cast<std::size_t>(p.count);
  KeyWriter w(sizeof(int) + 3 * sizeof(float) + 2 * n * sizeof(Vec2));
  static_assert(sizeof(Vec2) == 2 * sizeof(float), "vertices copy as their floats");
  w.put(p.count);
  w.put(p.radius);
  w.put(p.centroid);
  w.put(p.vertices, n);
  w.put(p.normals, n);
  return w.take();
}

}  // namespace

Result<std::shared_ptr<const ShapeGeometry>> SharedGeometries::intern(
    const ShapeGeometry& geometry, Status (*validate)(const ShapeGeometry&)) {
  const Polygon* polygon = std::get_if<Polygon>(&geometry);
  if (polygon == nullptr) {
    if (Status s = validate(geometry); !s) return Error{s.message()};
    return std::make_shared<const ShapeGeometry>(geometry);
  }
  std::string key = polygonKey(*polygon);
  if (std::shared_ptr<const ShapeGeometry> held = polygons_.find(key)) return held;
  if (Status s = validate(geometry); !s) return Error{s.message()};
  auto made = std::make_shared<const ShapeGeometry>(geometry);
  polygons_.insert(std::move(key), made);
  return made;
}

std::uint32_t BodyStore::createShape(std::uint32_t body, const ShapeDef& def,
                                     std::shared_ptr<const ShapeGeometry> geometry,
                                     const BodyMass* mass) {
  const std::uint32_t index = shapeIds.allocate();
  if (index == shapes.size()) shapes.emplace_back();
  Shape& s = shapes[index];
  s = Shape{};
  s.body = body;
  s.geometry = std::move(geometry);
  s.def = def;
  bodies[body].shapes.push_back(index);
  // A static body has no mass and its centre stays at its origin: only its extents grow, by
  // this shape (a chain of n segments would otherwise cost n^2).
  if (bodies[body].type == BodyType::staticBody)
    addExtents(bodies[body], *s.geometry);
  else
    updateMass(body, mass);
  return index;
}

void BodyStore::releaseShape(std::uint32_t index) {
  Shape& s = shapes[index];
  Body& body = bodies[s.body];
  body.shapes.erase(std::find(body.shapes.begin(), body.shapes.end(), index));
  s.pendingDestroy = false;
  s.contacts.clear();
  shapeIds.release(index);
  if (bodyIds.isAlive(s.body)) updateMass(s.body);
}

void BodyStore::releaseBody(std::uint32_t index) {
  Body& b = bodies[index];
  b.pendingDestroy = false;
  b.shapes.clear();
  bodyIds.release(index);
}

namespace {

// A shape's thickness for continuous collision: a segment has none, so the linear slop
// stands in.
float shapeThickness(const ShapeGeometry& g) {
  float thickness = kLinearSlop;
  if (const Circle* c = std::get_if<Circle>(&g)) thickness = c->radius;
  if (const Capsule* c = std::get_if<Capsule>(&g)) thickness = c->radius;
  if (const Polygon* p = std::get_if<Polygon>(&g)) {
    float inner = std::numeric_limits<float>::max();
    for (int i = 0; i < p->count; ++i)
      inner = minf(inner, dot(p->normals[i], p->vertices[i] - p->centroid));
    thickness = maxf(inner + p->radius, kLinearSlop);
  }
  return thickness;
}

}  // namespace

// Sizes for continuous collision: the largest reach from the centre of mass, and the
// thinnest shape's half-thickness. Max and min of exact values: the order the shapes come in
// does not change the bits, so adding one shape at a time gives what a full pass gives.
void BodyStore::addExtents(Body& b, const ShapeGeometry& g) {
  b.maxExtent = maxf(b.maxExtent, computeMaxExtent(makeProxy(g), b.localCenter));
  const float thickness = shapeThickness(g);
  b.minExtent = b.minExtent == 0.0f ? thickness : minf(b.minExtent, thickness);
}

void BodyStore::updateMass(std::uint32_t index, const BodyMass* mass) {
  Body& b = bodies[index];
  b.mass = b.invMass = b.inertia = b.invInertia = 0.0f;
  b.localCenter = {};
  if (b.type == BodyType::dynamicBody) {
    const BodyMass m = mass != nullptr ? *mass : sumMass([&](const auto& f) {
      for (std::uint32_t s : b.shapes)
        f(*shapes[s].geometry, shapes[s].def.density);
    });
    if (m.mass > 0.0f) {
      b.mass = m.mass;
      b.invMass = 1.0f / m.mass;
      b.localCenter = m.localCenter;
      b.inertia = m.inertia;
      b.invInertia = m.inertia > 0.0f ? 1.0f / m.inertia : 0.0f;
    } else {
      // A dynamic body with no area (segments only) or zero density still falls: unit mass,
      // no rotation (documented in docs/world.md).
      b.mass = 1.0f;
      b.invMass = 1.0f;
    }
  }
  // Sizes for continuous collision: the largest reach from the centre of mass, and the
  // thinnest shape's half-thickness (a segment has none: the linear slop stands in).
  b.maxExtent = 0.0f;
  b.minExtent = 0.0f;
  for (std::uint32_t s : b.shapes)
    addExtents(b, *shapes[s].geometry);
  // Keep the origin where it is; the centre of mass follows the shapes.
  Vec2 oldCenter = b.center;
  b.center = transformPoint(b.xf, b.localCenter);
  // The velocity of the new centre, from the rigid motion about the old one.
  b.v += cross(b.w, b.center - oldCenter);
}

bool BodyStore::shapesWithinWorld(std::uint32_t body, Transform xf) const {
  for (std::uint32_t s : bodies[body].shapes) {
    if (!boxWithinWorld(computeAabb(*shapes[s].geometry, xf))) return false;
  }
  return true;
}

bool BodyStore::moveBody(BroadPhase& broadPhase, std::uint32_t body, Transform xf, Vec2 center,
                         Vec2 displacement) {
  Aabb box;
  if (!placeBody(body, xf, center, box)) return false;
  followBody(broadPhase, body, box, displacement);
  return true;
}

bool BodyStore::placeBody(std::uint32_t body, Transform xf, Vec2 center, Aabb& box) {
  Body& b = bodies[body];
  if (b.shapes.size() == 1) {
    box = computeAabb(*shapes[b.shapes[0]].geometry, xf);
    if (!boxWithinWorld(box)) return false;
  } else if (!shapesWithinWorld(body, xf)) {
    return false;
  }
  b.xf = xf;
  b.center = center;
  return true;
}

bool BodyStore::placeProxy(BroadPhase& broadPhase, std::uint32_t body, const Aabb& box,
                           Vec2 displacement) const {
  const Body& b = bodies[body];
  if (b.shapes.size() != 1) return true;
  Result<bool> follow = broadPhase.moveProxyInPlace(shapes[b.shapes[0]].proxy, box, displacement);
  QUACK_ASSERT(follow.ok());
  return !follow.ok() || follow.value();
}

void BodyStore::followBody(BroadPhase& broadPhase, std::uint32_t body, const Aabb& box,
                           Vec2 displacement) const {
  const Body& b = bodies[body];
  if (b.shapes.size() != 1) {
    updateShapeBoxes(broadPhase, body, displacement);
    return;
  }
  Result<bool> moved = broadPhase.moveProxy(shapes[b.shapes[0]].proxy, box, displacement);
  QUACK_ASSERT(moved.ok());
  (void)moved;
}

void BodyStore::updateShapeBoxes(BroadPhase& broadPhase, std::uint32_t body,
                                 Vec2 displacement) const {
  const Body& b = bodies[body];
  for (std::uint32_t s : b.shapes) {
    Aabb box = computeAabb(*shapes[s].geometry, b.xf);
    Result<bool> moved = broadPhase.moveProxy(shapes[s].proxy, box, displacement);
    // Callers keep bodies within the world (shapesWithinWorld), so this cannot fail.
    QUACK_ASSERT(moved.ok());
    (void)moved;
  }
}

}  // namespace quack::detail
