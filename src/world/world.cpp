#include "quack/world/world.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <string>

#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/toi.hpp"
#include "quack/geometry/bounds.hpp"
#include "quack/geometry/mass.hpp"
#include "quack/geometry/raycast.hpp"
#include "world_internal.hpp"

namespace quack {
namespace {

constexpr std::uint32_t kNull = 0xffffffffu;

std::uint64_t pairKey(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

std::string describeId(std::uint32_t index, std::uint32_t generation) {
  return "{index " + std::to_string(index) + ", generation " + std::to_string(generation) + "}";
}

Status checkFiniteNonNegative(float x, const char* name) {
  if (!isFinite(x) || x < 0.0f)
    return fail(std::string(name) + " must be finite and >= 0, got " + std::to_string(x));
  return {};
}

Aabb shapeBox(const ShapeGeometry& g, Transform xf) {
  return std::visit([&](const auto& s) { return computeAabb(s, xf); }, g);
}

// Re-checks a geometry with the make* validators, so a hand-built struct cannot smuggle a
// NaN or a concave polygon into the world.
Status validateGeometry(const ShapeGeometry& g) {
  struct Visitor {
    Status operator()(const Circle& c) const {
      auto r = makeCircle(c.center, c.radius);
      return r ? Status{} : Status{fail(r.error().message)};
    }
    Status operator()(const Capsule& c) const {
      auto r = makeCapsule(c.p1, c.p2, c.radius);
      return r ? Status{} : Status{fail(r.error().message)};
    }
    Status operator()(const Segment& s) const {
      auto r = makeSegment(s.p1, s.p2);
      return r ? Status{} : Status{fail(r.error().message)};
    }
    Status operator()(const Polygon& p) const { return validatePolygon(p); }
  };
  return std::visit(Visitor{}, g);
}

bool matches(std::uint64_t categories, std::uint64_t wanted) {
  return (categories & wanted) != 0;
}

std::string describe(Vec2 v) {
  return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ")";
}

bool withinWorld(Vec2 p) {
  return absf(p.x) <= kMaxCoordinate && absf(p.y) <= kMaxCoordinate;
}

// A body's mass properties from its shapes (body frame). Zero mass means none of them has
// area and density; the caller decides what that means.
struct BodyMass {
  float mass = 0.0f;
  float inertia = 0.0f;  // about localCenter
  Vec2 localCenter;
};

// `each(f)` calls f(geometry, density) for every shape of the body.
template <class Each>
BodyMass sumMass(const Each& each) {
  BodyMass out;
  Vec2 moment;
  each([&](const ShapeGeometry& g, float density) {
    MassProperties m = std::visit([&](const auto& s) { return computeMass(s, density); }, g);
    out.mass += m.mass;
    moment += m.mass * m.centroid;
  });
  if (out.mass > 0.0f) {
    out.localCenter = (1.0f / out.mass) * moment;
    each([&](const ShapeGeometry& g, float density) {
      MassProperties m = std::visit([&](const auto& s) { return computeMass(s, density); }, g);
      out.inertia += m.inertia + m.mass * distanceSquared(m.centroid, out.localCenter);
    });
  }
  return out;
}

}  // namespace

World::World(const WorldDef& def, BroadPhase broadPhase)
    : def_(def), broadPhase_(std::move(broadPhase)) {}
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;
World::~World() = default;

Result<World> World::create(const WorldDef& def) {
  if (!isFinite(def.gravity)) return fail("WorldDef.gravity is not finite");
  if (length(def.gravity) > kMaxGravity)
    return fail("WorldDef.gravity " + describe(def.gravity) +
                " is stronger than kMaxGravity (1e4 m/s^2)");
  if (!isFinite(def.timeStep) || def.timeStep <= 0.0f || def.timeStep > kMaxTimeStep)
    return fail("WorldDef.timeStep must be finite, > 0 and at most kMaxTimeStep (1 s), got " +
                std::to_string(def.timeStep));
  if (def.substeps < 1 || def.substeps > 64)
    return fail("WorldDef.substeps must be in 1..64, got " + std::to_string(def.substeps));
  for (auto [value, name] : {std::pair{def.contactHertz, "WorldDef.contactHertz"},
                             std::pair{def.contactDampingRatio, "WorldDef.contactDampingRatio"},
                             std::pair{def.contactPushMaxSpeed, "WorldDef.contactPushMaxSpeed"},
                             std::pair{def.restitutionThreshold, "WorldDef.restitutionThreshold"},
                             std::pair{def.hitEventThreshold, "WorldDef.hitEventThreshold"},
                             std::pair{def.speculativeDistance, "WorldDef.speculativeDistance"}}) {
    if (Status s = checkFiniteNonNegative(value, name); !s) return fail(s.message());
  }
  if (!isFinite(def.maxRotationPerSubstep) || def.maxRotationPerSubstep <= 0.0f) {
    return fail("WorldDef.maxRotationPerSubstep must be finite and > 0");
  }
  BroadPhaseConfig config;
  config.kind = def.broadPhase;
  Result<BroadPhase> bp = BroadPhase::create(config);
  if (!bp) return fail("broad phase: " + bp.error().message);
  return World(def, std::move(bp).value());
}

// ---- handles ---------------------------------------------------------------------------

bool World::isValid(BodyId id) const noexcept {
  return id.index < bodies_.size() && bodies_[id.index].alive &&
         bodies_[id.index].generation == id.generation;
}

bool World::isValid(ShapeId id) const noexcept {
  return id.index < shapes_.size() && shapes_[id.index].alive &&
         shapes_[id.index].generation == id.generation;
}

Status World::checkBody(BodyId id, const char* function) const {
  if (isValid(id)) return {};
  if (id.index == kNull) return fail(std::string(function) + ": body is the null handle");
  if (id.index >= bodies_.size())
    return fail(std::string(function) + ": body " + describeId(id.index, id.generation) +
                " does not exist");
  return fail(std::string(function) + ": body " + describeId(id.index, id.generation) +
              " is stale (destroyed)");
}

Status World::checkShape(ShapeId id, const char* function) const {
  if (isValid(id)) return {};
  if (id.index == kNull) return fail(std::string(function) + ": shape is the null handle");
  if (id.index >= shapes_.size())
    return fail(std::string(function) + ": shape " + describeId(id.index, id.generation) +
                " does not exist");
  return fail(std::string(function) + ": shape " + describeId(id.index, id.generation) +
              " is stale (destroyed)");
}

ShapeId World::shapeId(std::uint32_t shape) const {
  return {shape, shapes_[shape].generation};
}

// ---- bodies ------------------------------------------------------------------------------

Result<BodyId> World::createBody(const BodyDef& def) {
  if (inStep_ && !inCallbacks_) return fail("createBody: called during step");
  if (!isFinite(def.position)) return fail("createBody: BodyDef.position is not finite");
  if (!withinWorld(def.position))
    return fail("createBody: BodyDef.position " + describe(def.position) +
                " lies beyond kMaxCoordinate (1e9 m) from the origin");
  if (!isFinite(def.angle)) return fail("createBody: BodyDef.angle is not finite");
  if (!isFinite(def.linearVelocity))
    return fail("createBody: BodyDef.linearVelocity is not finite");
  if (!isFinite(def.angularVelocity))
    return fail("createBody: BodyDef.angularVelocity is not finite");
  if (length(def.linearVelocity) > kMaxLinearSpeed)
    return fail("createBody: BodyDef.linearVelocity " + describe(def.linearVelocity) +
                " is faster than kMaxLinearSpeed (1e5 m/s)");
  if (absf(def.angularVelocity) > kMaxAngularSpeed)
    return fail("createBody: BodyDef.angularVelocity " + std::to_string(def.angularVelocity) +
                " is faster than kMaxAngularSpeed (1e5 rad/s)");
  if (Status s = checkFiniteNonNegative(def.linearDamping, "createBody: BodyDef.linearDamping"); !s)
    return fail(s.message());
  if (Status s = checkFiniteNonNegative(def.angularDamping, "createBody: BodyDef.angularDamping");
      !s)
    return fail(s.message());
  if (!isFinite(def.gravityScale) || absf(def.gravityScale) > kMaxGravityScale)
    return fail(
        "createBody: BodyDef.gravityScale must be finite and within +-kMaxGravityScale "
        "(1e3), got " +
        std::to_string(def.gravityScale));
  if (def.type != BodyType::staticBody && def.type != BodyType::kinematicBody &&
      def.type != BodyType::dynamicBody) {
    return fail("createBody: BodyDef.type is not a body type");
  }
  std::uint32_t index;
  if (!freeBodies_.empty()) {
    index = freeBodies_.back();
    freeBodies_.pop_back();
  } else {
    index = static_cast<std::uint32_t>(bodies_.size());
    bodies_.emplace_back();
  }
  Body& b = bodies_[index];
  std::uint32_t generation = b.generation + 1;
  b = Body{};
  b.generation = generation;
  b.alive = true;
  b.type = def.type;
  b.xf = makeTransform(def.position, def.angle);
  b.center = def.position;
  bool moves = def.type != BodyType::staticBody;
  b.v = moves ? def.linearVelocity : Vec2{};
  b.w = moves ? def.angularVelocity : 0.0f;
  b.linearDamping = def.linearDamping;
  b.angularDamping = def.angularDamping;
  b.gravityScale = def.gravityScale;
  b.bullet = def.bullet;
  b.userData = def.userData;
  ++bodyCount_;
  updateMass(index);
  return BodyId{index, generation};
}

Status World::destroyBody(BodyId id) {
  if (Status s = checkBody(id, "destroyBody"); !s) return s;
  if (inStep_ && !inCallbacks_) return fail("destroyBody: called during step");
  if (inCallbacks_) {
    if (!bodies_[id.index].pendingDestroy) {
      bodies_[id.index].pendingDestroy = true;
      pendingBodyDestroy_.push_back(id.index);
    }
    return {};
  }
  destroyBodyNow(id.index);
  return {};
}

void World::destroyBodyNow(std::uint32_t index) {
  Body& b = bodies_[index];
  std::vector<std::uint32_t> shapes = b.shapes;
  for (std::uint32_t s : shapes)
    destroyShapeNow(s);
  b.alive = false;
  b.pendingDestroy = false;
  b.shapes.clear();
  freeBodies_.push_back(index);
  --bodyCount_;
}

void World::updateMass(std::uint32_t index) {
  Body& b = bodies_[index];
  b.mass = b.invMass = b.inertia = b.invInertia = 0.0f;
  b.localCenter = {};
  if (b.type == BodyType::dynamicBody) {
    const BodyMass m = sumMass([&](const auto& f) {
      for (std::uint32_t s : b.shapes)
        f(shapes_[s].geometry, shapes_[s].def.density);
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
  for (std::uint32_t s : b.shapes) {
    const ShapeGeometry& g = shapes_[s].geometry;
    b.maxExtent = maxf(b.maxExtent, computeMaxExtent(proxyOf(g), b.localCenter));
    float thickness = kLinearSlop;
    if (const Circle* c = std::get_if<Circle>(&g)) thickness = c->radius;
    if (const Capsule* c = std::get_if<Capsule>(&g)) thickness = c->radius;
    if (const Polygon* p = std::get_if<Polygon>(&g)) {
      float inner = std::numeric_limits<float>::max();
      for (int i = 0; i < p->count; ++i)
        inner = minf(inner, dot(p->normals[i], p->vertices[i] - p->centroid));
      thickness = maxf(inner + p->radius, kLinearSlop);
    }
    b.minExtent = b.minExtent == 0.0f ? thickness : minf(b.minExtent, thickness);
  }
  // Keep the origin where it is; the centre of mass follows the shapes.
  Vec2 oldCenter = b.center;
  b.center = transformPoint(b.xf, b.localCenter);
  // The velocity of the new centre, from the rigid motion about the old one.
  b.v += cross(b.w, b.center - oldCenter);
}

// ---- shapes -------------------------------------------------------------------------------

Result<ShapeId> World::createShape(BodyId bodyId, const ShapeDef& def,
                                   const ShapeGeometry& geometry) {
  if (Status s = checkBody(bodyId, "createShape"); !s) return fail(s.message());
  if (inStep_ && !inCallbacks_) return fail("createShape: called during step");
  if (Status s = checkFiniteNonNegative(def.density, "createShape: ShapeDef.density"); !s)
    return fail(s.message());
  if (Status s = checkFiniteNonNegative(def.friction, "createShape: ShapeDef.friction"); !s)
    return fail(s.message());
  if (Status s = checkFiniteNonNegative(def.restitution, "createShape: ShapeDef.restitution"); !s)
    return fail(s.message());
  if (def.restitution > kMaxRestitution)
    return fail("createShape: ShapeDef.restitution " + std::to_string(def.restitution) +
                " is above kMaxRestitution (10)");
  if (Status s = validateGeometry(geometry); !s)
    return fail("createShape: geometry: " + s.message());
  Body& body = bodies_[bodyId.index];
  if (body.type == BodyType::dynamicBody) {
    // The body's mass with the new shape must stay a usable float (kMaxBodyMass), and so
    // must its inverse: refuse here rather than let a mass of infinity into the solver.
    const BodyMass m = sumMass([&](const auto& f) {
      for (std::uint32_t s : body.shapes)
        f(shapes_[s].geometry, shapes_[s].def.density);
      f(geometry, def.density);
    });
    if (!isFinite(m.mass) || m.mass > kMaxBodyMass || !isFinite(m.inertia))
      return fail("createShape: ShapeDef.density " + std::to_string(def.density) +
                  " makes the body's mass " + std::to_string(m.mass) +
                  " kg, beyond kMaxBodyMass (1e20 kg)");
    if (m.mass > 0.0f &&
        (!isFinite(1.0f / m.mass) || (m.inertia > 0.0f && !isFinite(1.0f / m.inertia))))
      return fail("createShape: ShapeDef.density " + std::to_string(def.density) +
                  " makes the body's mass too small to invert");
  }
  Aabb box = shapeBox(geometry, body.xf);
  std::uint32_t index;
  if (!freeShapes_.empty()) {
    index = freeShapes_.back();
  } else {
    index = static_cast<std::uint32_t>(shapes_.size());
  }
  ProxyKind kind = body.type == BodyType::staticBody ? ProxyKind::kStatic : ProxyKind::kDynamic;
  Result<ProxyId> proxy = broadPhase_.createProxy(box, index, def.filter, kind);
  if (!proxy) return fail("createShape: " + proxy.error().message);
  if (!freeShapes_.empty()) {
    freeShapes_.pop_back();
  } else {
    shapes_.emplace_back();
  }
  Shape& s = shapes_[index];
  std::uint32_t generation = s.generation + 1;
  s = Shape{};
  s.generation = generation;
  s.alive = true;
  s.body = bodyId.index;
  s.geometry = geometry;
  s.def = def;
  s.proxy = proxy.value();
  body.shapes.push_back(index);
  ++shapeCount_;
  if (body.type == BodyType::staticBody) staticEdgesDirty_ = true;
  updateMass(bodyId.index);
  return ShapeId{index, generation};
}

Status World::destroyShape(ShapeId id) {
  if (Status s = checkShape(id, "destroyShape"); !s) return s;
  if (inStep_ && !inCallbacks_) return fail("destroyShape: called during step");
  if (inCallbacks_) {
    if (!shapes_[id.index].pendingDestroy) {
      shapes_[id.index].pendingDestroy = true;
      pendingShapeDestroy_.push_back(id.index);
    }
    return {};
  }
  destroyShapeNow(id.index);
  return {};
}

void World::destroyShapeNow(std::uint32_t index) {
  Shape& s = shapes_[index];
  std::vector<std::uint32_t> contacts = s.contacts;
  for (std::uint32_t c : contacts)
    destroyContact(c, true);
  Status st = broadPhase_.destroyProxy(s.proxy);
  QUACK_ASSERT(st.ok());
  (void)st;
  Body& body = bodies_[s.body];
  if (body.type == BodyType::staticBody) staticEdgesDirty_ = true;
  body.shapes.erase(std::find(body.shapes.begin(), body.shapes.end(), index));
  s.alive = false;
  s.pendingDestroy = false;
  s.contacts.clear();
  freeShapes_.push_back(index);
  --shapeCount_;
  if (body.alive) updateMass(s.body);
}

// ---- contacts -----------------------------------------------------------------------------

void World::destroyContact(std::uint32_t index, bool emitEnd) {
  Contact& c = contacts_[index];
  if (emitEnd && c.touching) {
    if (inStep_) {
      pushEnd(c);
    } else {
      // Destroyed between steps: reported (events and callbacks) with the next step.
      endsSinceStep_.push_back({shapeId(c.shapeA), shapeId(c.shapeB),
                                shapes_[c.shapeA].def.filter.category,
                                shapes_[c.shapeB].def.filter.category, c.sensor});
    }
  }
  for (std::uint32_t s : {c.shapeA, c.shapeB}) {
    auto& list = shapes_[s].contacts;
    list.erase(std::find(list.begin(), list.end(), index));
  }
  contactByPair_.erase(pairKey(c.shapeA, c.shapeB));
  c.alive = false;
  freeContacts_.push_back(index);
  --contactCount_;
}

void World::findNewContacts() {
  broadPhase_.updatePairs(pairScratch_);
  // Structure-independent order, so contacts (and the solver) run in the same order
  // whichever broad phase found them.
  std::sort(pairScratch_.begin(), pairScratch_.end(), [](const ProxyPair& x, const ProxyPair& y) {
    return x.a.index != y.a.index ? x.a.index < y.a.index : x.b.index < y.b.index;
  });
  for (const ProxyPair& pair : pairScratch_) {
    auto sa = static_cast<std::uint32_t>(broadPhase_.userData(pair.a));
    auto sb = static_cast<std::uint32_t>(broadPhase_.userData(pair.b));
    const Shape& shapeA = shapes_[sa];
    const Shape& shapeB = shapes_[sb];
    if (shapeA.body == shapeB.body) continue;  // a body's shapes never collide with each other
    const Body& bodyA = bodies_[shapeA.body];
    const Body& bodyB = bodies_[shapeB.body];
    if (bodyA.type != BodyType::dynamicBody && bodyB.type != BodyType::dynamicBody) continue;
    if (shapeA.def.sensor && shapeB.def.sensor) continue;  // sensors do not sense sensors
    if (contactByPair_.count(pairKey(sa, sb)) != 0) continue;
    std::uint32_t index;
    if (!freeContacts_.empty()) {
      index = freeContacts_.back();
      freeContacts_.pop_back();
    } else {
      index = static_cast<std::uint32_t>(contacts_.size());
      contacts_.emplace_back();
    }
    Contact& c = contacts_[index];
    c = Contact{};
    c.alive = true;
    // The sensor, if any, is shape A; otherwise keep the broad phase's order.
    if (shapeB.def.sensor) std::swap(sa, sb);
    c.shapeA = sa;
    c.shapeB = sb;
    c.sensor = shapes_[sa].def.sensor;
    const ShapeGeometry& ga = shapes_[sa].geometry;
    const ShapeGeometry& gb = shapes_[sb].geometry;
    c.fn = findManifoldFn(static_cast<ShapeType>(ga.index()), static_cast<ShapeType>(gb.index()));
    c.friction = std::sqrt(shapes_[sa].def.friction * shapes_[sb].def.friction);
    c.restitution = maxf(shapes_[sa].def.restitution, shapes_[sb].def.restitution);
    contactByPair_.emplace(pairKey(sa, sb), index);
    shapes_[sa].contacts.push_back(index);
    shapes_[sb].contacts.push_back(index);
    ++contactCount_;
  }
}

void World::collide() {
  if (staticEdgesDirty_) updateStaticEdges();
  for (std::uint32_t i = 0; i < contacts_.size(); ++i) {
    Contact& c = contacts_[i];
    if (!c.alive) continue;
    const Shape& sa = shapes_[c.shapeA];
    const Shape& sb = shapes_[c.shapeB];
    if (!overlaps(broadPhase_.fatBox(sa.proxy), broadPhase_.fatBox(sb.proxy))) {
      destroyContact(i, true);
      continue;
    }
    const Transform xa = bodies_[sa.body].xf;
    const Transform xb = bodies_[sb.body].xf;
    bool wasTouching = c.touching;
    if (c.sensor) {
      c.touching = testOverlap(proxyOf(sa.geometry), xa, proxyOf(sb.geometry), xb);
      if (c.touching && !wasTouching)
        events_.sensorBegin.push_back({shapeId(c.shapeA), shapeId(c.shapeB)});
      if (!c.touching && wasTouching) pushEnd(c);
      continue;
    }
    Manifold old = c.manifold;
    float oldNormal[kMaxManifoldPoints], oldTangent[kMaxManifoldPoints];
    std::copy(c.normalImpulse, c.normalImpulse + kMaxManifoldPoints, oldNormal);
    std::copy(c.tangentImpulse, c.tangentImpulse + kMaxManifoldPoints, oldTangent);
    c.manifold =
        c.fn(refOf(sa.geometry).shape, xa, refOf(sb.geometry).shape, xb, def_.speculativeDistance);
    // Ghost collisions: only contacts with flagged static shapes pay for the check.
    if (edgeShapes_ != 0 && (sa.edges.active || sb.edges.active)) removeGhostContacts(c);
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
    if (c.touching && !wasTouching) events_.begin.push_back({shapeId(c.shapeA), shapeId(c.shapeB)});
    if (!c.touching && wasTouching) pushEnd(c);
  }
}

std::size_t World::touchingContactCount() const noexcept {
  std::size_t n = 0;
  for (const Contact& c : contacts_)
    n += (c.alive && c.touching && !c.sensor) ? 1 : 0;
  return n;
}

// ---- stepping -----------------------------------------------------------------------------

Status World::step() {
  return step(def_.timeStep, def_.substeps);
}

Status World::step(float dt, int substeps) {
  if (inStep_) return fail("step: called during a step or from an event callback");
  if (!isFinite(dt) || dt <= 0.0f || dt > kMaxTimeStep)
    return fail("step: dt must be finite, > 0 and at most kMaxTimeStep (1 s), got " +
                std::to_string(dt));
  if (substeps < 1 || substeps > 64)
    return fail("step: substeps must be in 1..64, got " + std::to_string(substeps));
  inStep_ = true;
  events_.begin.clear();
  events_.end.clear();
  endCategories_.clear();
  events_.sensorEnd.clear();
  sensorEndCategories_.clear();
  for (const PendingEnd& e : endsSinceStep_) {
    if (e.sensor) {
      events_.sensorEnd.push_back({e.shapeA, e.shapeB});
      sensorEndCategories_.push_back({e.categoryA, e.categoryB});
    } else {
      events_.end.push_back({e.shapeA, e.shapeB});
      endCategories_.push_back({e.categoryA, e.categoryB});
    }
  }
  endsSinceStep_.clear();
  events_.hit.clear();
  events_.sensorBegin.clear();
  events_.toi.clear();
  events_.outOfBounds.clear();

  findNewContacts();
  collide();
  solve(dt, substeps);
  solveContinuous(dt);
  // The solver and the continuous phase may both have stopped a body at the edge.
  std::sort(events_.outOfBounds.begin(), events_.outOfBounds.end(),
            [](BodyId a, BodyId b) { return a.index < b.index; });
  events_.outOfBounds.erase(std::unique(events_.outOfBounds.begin(), events_.outOfBounds.end()),
                            events_.outOfBounds.end());

  ++stepCount_;
  time_ += static_cast<double>(dt);
  dispatchCallbacks();
  inStep_ = false;
  return {};
}

bool World::shapesWithinWorld(std::uint32_t body, Transform xf) const {
  for (std::uint32_t s : bodies_[body].shapes) {
    const Aabb box = shapeBox(shapes_[s].geometry, xf);
    // Six comparisons, all false for NaN: finite, not inverted, within the broad phase's range.
    if (!(box.lower.x <= box.upper.x && box.lower.y <= box.upper.y &&
          box.lower.x >= -kMaxCoordinate && box.lower.y >= -kMaxCoordinate &&
          box.upper.x <= kMaxCoordinate && box.upper.y <= kMaxCoordinate)) {
      return false;
    }
  }
  return true;
}

void World::updateShapeBoxes(std::uint32_t body, Vec2 displacement) {
  const Body& b = bodies_[body];
  for (std::uint32_t s : b.shapes) {
    Aabb box = shapeBox(shapes_[s].geometry, b.xf);
    Result<bool> moved = broadPhase_.moveProxy(shapes_[s].proxy, box, displacement);
    // Callers keep bodies within the world (shapesWithinWorld), so this cannot fail.
    QUACK_ASSERT(moved.ok());
    (void)moved;
  }
}

// ---- callbacks ----------------------------------------------------------------------------

void World::onContactBegin(std::uint64_t a, std::uint64_t b, ContactCallback f) {
  (inCallbacks_ ? pendingCallbacks_ : callbacks_)
      .push_back({Callback::Kind::begin, a, b, std::move(f), {}});
}
void World::onContactEnd(std::uint64_t a, std::uint64_t b, ContactCallback f) {
  (inCallbacks_ ? pendingCallbacks_ : callbacks_)
      .push_back({Callback::Kind::end, a, b, std::move(f), {}});
}
void World::onHit(std::uint64_t a, std::uint64_t b, HitCallback f) {
  (inCallbacks_ ? pendingCallbacks_ : callbacks_)
      .push_back({Callback::Kind::hit, a, b, {}, std::move(f)});
}
void World::onSensorBegin(std::uint64_t a, std::uint64_t b, ContactCallback f) {
  (inCallbacks_ ? pendingCallbacks_ : callbacks_)
      .push_back({Callback::Kind::sensorBegin, a, b, std::move(f), {}});
}
void World::onSensorEnd(std::uint64_t a, std::uint64_t b, ContactCallback f) {
  (inCallbacks_ ? pendingCallbacks_ : callbacks_)
      .push_back({Callback::Kind::sensorEnd, a, b, std::move(f), {}});
}

void World::pushEnd(const Contact& c) {
  const ShapeId a = shapeId(c.shapeA), b = shapeId(c.shapeB);
  const std::array<std::uint64_t, 2> categories{shapes_[c.shapeA].def.filter.category,
                                                shapes_[c.shapeB].def.filter.category};
  if (c.sensor) {
    events_.sensorEnd.push_back({a, b});
    sensorEndCategories_.push_back(categories);
  } else {
    events_.end.push_back({a, b});
    endCategories_.push_back(categories);
  }
}

void World::dispatchCallbacks() {
  if (callbacks_.empty()) return;
  inCallbacks_ = true;
  // Every event in the lists gets its callbacks, so the two always agree. End events may
  // name shapes destroyed since (stale handles); their categories were kept when they
  // ended. The other events' shapes are valid (destruction asked for inside a callback
  // waits until the callbacks are done).
  auto category = [&](ShapeId s) { return shapes_[s.index].def.filter.category; };
  auto runPairs = [&](Callback::Kind kind, const auto& list,
                      const std::vector<std::array<std::uint64_t, 2>>* kept, bool ordered) {
    for (const Callback& cb : callbacks_) {
      if (cb.kind != kind) continue;
      for (std::size_t i = 0; i < list.size(); ++i) {
        const auto& e = list[i];
        ShapeId a{}, b{};
        if constexpr (requires { e.sensor; }) {
          a = e.sensor;
          b = e.visitor;
        } else {
          a = e.shapeA;
          b = e.shapeB;
        }
        const std::uint64_t ca = kept ? (*kept)[i][0] : category(a);
        const std::uint64_t cb2 = kept ? (*kept)[i][1] : category(b);
        if (matches(ca, cb.categoriesA) && matches(cb2, cb.categoriesB)) {
          cb.contact(*this, a, b);
        } else if (!ordered && matches(cb2, cb.categoriesA) && matches(ca, cb.categoriesB)) {
          cb.contact(*this, b, a);
        }
      }
    }
  };
  runPairs(Callback::Kind::begin, events_.begin, nullptr, false);
  runPairs(Callback::Kind::end, events_.end, &endCategories_, false);
  runPairs(Callback::Kind::sensorBegin, events_.sensorBegin, nullptr, true);
  runPairs(Callback::Kind::sensorEnd, events_.sensorEnd, &sensorEndCategories_, true);
  for (const Callback& cb : callbacks_) {
    if (cb.kind != Callback::Kind::hit) continue;
    for (const ContactHitEvent& e : events_.hit) {
      if (matches(category(e.shapeA), cb.categoriesA) &&
          matches(category(e.shapeB), cb.categoriesB)) {
        cb.hit(*this, e, false);
      } else if (matches(category(e.shapeB), cb.categoriesA) &&
                 matches(category(e.shapeA), cb.categoriesB)) {
        cb.hit(*this, e, true);
      }
    }
  }
  inCallbacks_ = false;
  for (Callback& cb : pendingCallbacks_)
    callbacks_.push_back(std::move(cb));
  pendingCallbacks_.clear();
  // Deferred destruction, in request order.
  inStep_ = false;
  for (std::uint32_t s : pendingShapeDestroy_) {
    if (shapes_[s].alive && shapes_[s].pendingDestroy) destroyShapeNow(s);
  }
  for (std::uint32_t b : pendingBodyDestroy_) {
    if (bodies_[b].alive && bodies_[b].pendingDestroy) destroyBodyNow(b);
  }
  inStep_ = true;
  pendingShapeDestroy_.clear();
  pendingBodyDestroy_.clear();
}

// ---- body state ----------------------------------------------------------------------------

BodyType World::bodyType(BodyId id) const {
  QUACK_ASSERT(isValid(id));
  return bodies_[id.index].type;
}
Transform World::transform(BodyId id) const {
  QUACK_ASSERT(isValid(id));
  return bodies_[id.index].xf;
}
Vec2 World::position(BodyId id) const {
  return transform(id).p;
}
float World::angle(BodyId id) const {
  return transform(id).q.angle();
}
Vec2 World::linearVelocity(BodyId id) const {
  QUACK_ASSERT(isValid(id));
  return bodies_[id.index].v;
}
float World::angularVelocity(BodyId id) const {
  QUACK_ASSERT(isValid(id));
  return bodies_[id.index].w;
}
float World::mass(BodyId id) const {
  QUACK_ASSERT(isValid(id));
  return bodies_[id.index].mass;
}
float World::rotationalInertia(BodyId id) const {
  QUACK_ASSERT(isValid(id));
  return bodies_[id.index].inertia;
}
Vec2 World::worldCenterOfMass(BodyId id) const {
  QUACK_ASSERT(isValid(id));
  return bodies_[id.index].center;
}
std::uint64_t World::userData(BodyId id) const {
  QUACK_ASSERT(isValid(id));
  return bodies_[id.index].userData;
}
BodyId World::body(ShapeId id) const {
  QUACK_ASSERT(isValid(id));
  std::uint32_t b = shapes_[id.index].body;
  return {b, bodies_[b].generation};
}
const ShapeGeometry& World::geometry(ShapeId id) const {
  QUACK_ASSERT(isValid(id));
  return shapes_[id.index].geometry;
}
const ShapeDef& World::shapeDef(ShapeId id) const {
  QUACK_ASSERT(isValid(id));
  return shapes_[id.index].def;
}
std::vector<ShapeId> World::shapes(BodyId id) const {
  QUACK_ASSERT(isValid(id));
  std::vector<ShapeId> out;
  for (std::uint32_t s : bodies_[id.index].shapes)
    out.push_back(shapeId(s));
  return out;
}
std::vector<BodyId> World::bodies() const {
  std::vector<BodyId> out;
  for (std::uint32_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].alive) out.push_back({i, bodies_[i].generation});
  }
  return out;
}

Status World::setTransform(BodyId id, Vec2 position, float angle) {
  if (Status s = checkBody(id, "setTransform"); !s) return s;
  if (inStep_ && !inCallbacks_) return fail("setTransform: called during step");
  if (!isFinite(position) || !isFinite(angle))
    return fail("setTransform: position and angle must be finite");
  const Transform xf = makeTransform(position, angle);
  if (!withinWorld(position) || !shapesWithinWorld(id.index, xf))
    return fail("setTransform: position " + describe(position) +
                " would put the body beyond kMaxCoordinate (1e9 m) from the origin");
  Body& b = bodies_[id.index];
  b.xf = xf;
  b.center = transformPoint(b.xf, b.localCenter);
  if (b.type == BodyType::staticBody) staticEdgesDirty_ = true;
  updateShapeBoxes(id.index, Vec2{});
  return {};
}

Status World::setLinearVelocity(BodyId id, Vec2 v) {
  if (Status s = checkBody(id, "setLinearVelocity"); !s) return s;
  if (!isFinite(v) || length(v) > kMaxLinearSpeed)
    return fail("setLinearVelocity: velocity " + describe(v) +
                " must be finite and no faster than kMaxLinearSpeed (1e5 m/s)");
  if (bodies_[id.index].type != BodyType::staticBody) bodies_[id.index].v = v;
  return {};
}

Status World::setAngularVelocity(BodyId id, float w) {
  if (Status s = checkBody(id, "setAngularVelocity"); !s) return s;
  if (!isFinite(w) || absf(w) > kMaxAngularSpeed)
    return fail("setAngularVelocity: velocity " + std::to_string(w) +
                " must be finite and no faster than kMaxAngularSpeed (1e5 rad/s)");
  // (A dynamic body without rotational inertia keeps it only until the next step: the
  // solver does not turn such a body.)
  if (bodies_[id.index].type != BodyType::staticBody) bodies_[id.index].w = w;
  return {};
}

Status World::applyLinearImpulse(BodyId id, Vec2 impulse, Vec2 point) {
  if (Status s = checkBody(id, "applyLinearImpulse"); !s) return s;
  if (!isFinite(impulse) || !isFinite(point))
    return fail("applyLinearImpulse: impulse and point must be finite");
  if (!withinWorld(point))
    return fail("applyLinearImpulse: point " + describe(point) +
                " lies beyond kMaxCoordinate (1e9 m) from the origin");
  Body& b = bodies_[id.index];
  if (b.type != BodyType::dynamicBody) return {};
  const Vec2 v = b.v + b.invMass * impulse;
  const float w = b.w + b.invInertia * cross(point - b.center, impulse);
  if (!isFinite(v) || length(v) > kMaxLinearSpeed)
    return fail("applyLinearImpulse: impulse " + describe(impulse) + " would make the velocity " +
                describe(v) + ", faster than kMaxLinearSpeed (1e5 m/s)");
  if (!isFinite(w) || absf(w) > kMaxAngularSpeed)
    return fail("applyLinearImpulse: impulse " + describe(impulse) +
                " would make the angular velocity " + std::to_string(w) +
                ", faster than kMaxAngularSpeed (1e5 rad/s)");
  b.v = v;
  b.w = w;
  return {};
}

// ---- queries -------------------------------------------------------------------------------

bool World::acceptsQuery(std::uint32_t shape, const QueryFilter& filter) const {
  const Shape& s = shapes_[shape];
  if (s.def.sensor && !filter.includeSensors) return false;
  return (s.def.filter.category & filter.mask) != 0 && (filter.category & s.def.filter.mask) != 0;
}

namespace {

// The ray in a shape's frame, clipped to `maxFraction`.
RayHit castShape(const ShapeGeometry& g, Transform xf, Vec2 origin, Vec2 translation,
                 float maxFraction) {
  RayCastInput in{invTransformPoint(xf, origin), invRotate(xf.q, translation), maxFraction};
  return std::visit([&](const auto& s) { return rayCast(s, in); }, g);
}

}  // namespace

std::optional<RayHitResult> World::rayCastClosest(Vec2 origin, Vec2 translation,
                                                  QueryFilter filter) const {
  if (!isFinite(origin) || !isFinite(translation)) return std::nullopt;
  std::optional<RayHitResult> best;
  float bestFraction = 1.0f;
  broadPhase_.rayCast(origin, translation, [&](ProxyId, std::uint64_t user, float) -> float {
    auto s = static_cast<std::uint32_t>(user);
    if (!acceptsQuery(s, filter)) return -1.0f;
    const Transform xf = bodies_[shapes_[s].body].xf;
    RayHit h = castShape(shapes_[s].geometry, xf, origin, translation, bestFraction);
    if (!h.hit) return -1.0f;
    // Equal fractions: the lower shape index wins, whatever order the structure visits.
    if (best && h.fraction == bestFraction && s > best->shape.index) return -1.0f;
    bestFraction = h.fraction;
    best = RayHitResult{shapeId(s),
                        {shapes_[s].body, bodies_[shapes_[s].body].generation},
                        transformPoint(xf, h.point),
                        rotate(xf.q, h.normal),
                        h.fraction};
    return h.fraction > 0.0f ? h.fraction : 0.0f;
  });
  return best;
}

std::vector<RayHitResult> World::rayCastAll(Vec2 origin, Vec2 translation,
                                            QueryFilter filter) const {
  std::vector<RayHitResult> hits;
  if (!isFinite(origin) || !isFinite(translation)) return hits;
  broadPhase_.rayCast(origin, translation, [&](ProxyId, std::uint64_t user, float) -> float {
    auto s = static_cast<std::uint32_t>(user);
    if (!acceptsQuery(s, filter)) return -1.0f;
    const Transform xf = bodies_[shapes_[s].body].xf;
    RayHit h = castShape(shapes_[s].geometry, xf, origin, translation, 1.0f);
    if (h.hit) {
      hits.push_back({shapeId(s),
                      {shapes_[s].body, bodies_[shapes_[s].body].generation},
                      transformPoint(xf, h.point),
                      rotate(xf.q, h.normal),
                      h.fraction});
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
  broadPhase_.queryAabb(box, [&](ProxyId, std::uint64_t user) {
    auto s = static_cast<std::uint32_t>(user);
    if (acceptsQuery(s, filter)) out.push_back(shapeId(s));
    return true;
  });
  std::sort(out.begin(), out.end(), [](ShapeId a, ShapeId b) { return a.index < b.index; });
  return out;
}

Result<std::vector<ShapeOverlap>> World::overlapShape(const ShapeGeometry& geometry, Transform xf,
                                                      QueryFilter filter) const {
  if (!isFinite(xf.p) || !isFinite(xf.q.c) || !isFinite(xf.q.s))
    return fail("overlapShape: transform is not finite");
  if (Status s = validateGeometry(geometry); !s)
    return fail("overlapShape: geometry: " + s.message());
  std::vector<ShapeOverlap> out;
  const ShapeProxy query = proxyOf(geometry);
  broadPhase_.queryAabb(shapeBox(geometry, xf), [&](ProxyId, std::uint64_t user) {
    auto s = static_cast<std::uint32_t>(user);
    if (!acceptsQuery(s, filter)) return true;
    const Transform sx = bodies_[shapes_[s].body].xf;
    PenetrationOutput p = computePenetration(query, xf, proxyOf(shapes_[s].geometry), sx);
    if (p.overlap) {
      out.push_back({shapeId(s),
                     {shapes_[s].body, bodies_[shapes_[s].body].generation},
                     p.depth,
                     -p.depth * p.normal});
    }
    return true;
  });
  std::sort(out.begin(), out.end(), [](const ShapeOverlap& a, const ShapeOverlap& b) {
    return a.shape.index < b.shape.index;
  });
  return out;
}

// ---- inspection ------------------------------------------------------------------------------

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
  for (const Body& b : bodies_) {
    if (!b.alive) continue;
    mix(b.xf.p.x);
    mix(b.xf.p.y);
    mix(b.xf.q.c);
    mix(b.xf.q.s);
    mix(b.v.x);
    mix(b.v.y);
    mix(b.w);
  }
  return h;
}

std::vector<World::ContactView> World::touchingContacts() const {
  std::vector<ContactView> out;
  for (const Contact& c : contacts_) {
    if (c.alive && c.touching && !c.sensor)
      out.push_back({shapeId(c.shapeA), shapeId(c.shapeB), c.manifold});
  }
  return out;
}

}  // namespace quack
