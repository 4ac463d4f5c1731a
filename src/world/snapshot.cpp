// Snapshots of a world (World::snapshot, World::restore, World::fromSnapshot): the format,
// its checks and the codec that writes and rebuilds every part of WorldState that decides
// future steps. docs/determinism.md, "Snapshots", documents the format and the guarantees.
//
// A snapshot is a 48-byte header and a payload. The payload is made of two sections:
// - the structure: what does not change while shapes and static geometry do not (the
//   settings, the handles' slots and generations, bodies' mass and settings, static bodies'
//   poses, shapes, ghost-edge data, the broad phase's proxy slots, filters and static boxes);
// - the motion: everything else (steps and time, moving bodies' poses, velocities, forces
//   and sleep, shapes' contact lists, contacts with manifolds, warm-start impulses and
//   recycling caches, islands, moving proxies' boxes, the move buffer, pending end events).
// A full snapshot carries both; a dynamic one carries the motion and the structure's
// fingerprint, and is restored by pairing it with the present world's structure.
//
// Every number is written little-endian, floats as their IEEE bits, so a snapshot reads the
// same on every target. Reading checks every count against the bytes left before
// allocating and every index against what it indexes, then the rebuilt world goes through
// World::validate before it replaces anything.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <string>

#include "quack/geometry/shapes.hpp"
#include "snapshot_codec.hpp"
#include "world_state.hpp"

namespace quack {

const char* toString(SnapshotKind kind) noexcept {
  switch (kind) {
    case SnapshotKind::full:
      return "full";
    case SnapshotKind::dynamic:
      return "dynamic";
  }
  return "unknown";
}

namespace detail {
namespace {

constexpr char kMagic[8] = {'Q', 'U', 'A', 'C', 'K', 'S', 'N', 'P'};
constexpr std::size_t kHeaderSize = 48;
constexpr std::size_t kChecksumOffset = 40;
constexpr std::uint32_t kNone = 0xffffffffu;

// What a build must share with the one that wrote a snapshot for the snapshot to mean the
// same thing: the layout constants and the constants the step's arithmetic uses. The SIMD
// lanes, the compiler, the optimisation level and the target are not in it: every build
// gives the same bits (docs/world.md, "The solver's data"; docs/determinism.md).
std::uint64_t buildFingerprint() {
  Writer w;
  w.u32(kSnapshotFormatVersion);
  w.u32(static_cast<std::uint32_t>(kMaxManifoldPoints));
  w.u32(static_cast<std::uint32_t>(kMaxPolygonVertices));
  w.u32(static_cast<std::uint32_t>(kMaxToiEventsPerBody));
  for (float f : {kLinearSlop,
                  kSpeculativeDistance,
                  kContactRecycleDistance,
                  kContactRecycleCosAngle,
                  kFlushEdgeTolerance,
                  kGhostVertexRadius,
                  kCcdFastFraction,
                  kTimeToSleep,
                  kMaxTimeStep,
                  kMaxGravity,
                  kMaxGravityScale,
                  kMaxLinearSpeed,
                  kMaxAngularSpeed,
                  kMaxBodyMass,
                  kMaxRestitution,
                  kMaxCoordinate,
                  worldBroadPhaseConfig(WorldDef{}).margin,
                  worldBroadPhaseConfig(WorldDef{}).displacementScale,
                  BroadPhaseConfig{}.cellSize,
                  kWorldFatMargin,
                  kWorldFatMarginFraction})
    w.f32(f);
  return fnv1a(w.bytes);
}

void writeGeometry(Writer& w, const ShapeGeometry& g) {
  w.u8(static_cast<std::uint8_t>(g.index()));
  if (const auto* c = std::get_if<Circle>(&g)) {
    w.vec(c->center);
    w.f32(c->radius);
  } else if (const auto* k = std::get_if<Capsule>(&g)) {
    w.vec(k->p1);
    w.vec(k->p2);
    w.f32(k->radius);
  } else if (const auto* s = std::get_if<Segment>(&g)) {
    w.vec(s->p1);
    w.vec(s->p2);
  } else if (const auto* p = std::get_if<Polygon>(&g)) {
    w.u8(static_cast<std::uint8_t>(p->count));
    for (int i = 0; i < p->count; ++i)
      w.vec(p->vertices[i]);
    for (int i = 0; i < p->count; ++i)
      w.vec(p->normals[i]);
    w.vec(p->centroid);
    w.f32(p->radius);
  }
}

ShapeGeometry readGeometry(Reader& r) {
  const std::uint8_t type = r.u8("shape type");
  switch (type) {
    case 0: {
      Circle c;
      c.center = r.vec("circle centre");
      c.radius = r.f32("circle radius");
      return c;
    }
    case 1: {
      Capsule k;
      k.p1 = r.vec("capsule p1");
      k.p2 = r.vec("capsule p2");
      k.radius = r.f32("capsule radius");
      return k;
    }
    case 2: {
      Segment s;
      s.p1 = r.vec("segment p1");
      s.p2 = r.vec("segment p2");
      return s;
    }
    case 3: {
      Polygon p;
      const std::uint8_t n = r.u8("polygon vertex count");
      if (n < 3 || n > kMaxPolygonVertices) {
        r.fail("polygon vertex count " + std::to_string(n) + " is not in 3.." +
               std::to_string(kMaxPolygonVertices));
        return p;
      }
      p.count = n;
      for (int i = 0; i < n; ++i)
        p.vertices[i] = r.vec("polygon vertex");
      for (int i = 0; i < n; ++i)
        p.normals[i] = r.vec("polygon normal");
      p.centroid = r.vec("polygon centroid");
      p.radius = r.f32("polygon radius");
      return p;
    }
    default:
      r.fail("shape type " + std::to_string(type) + " is not 0..3");
      return Circle{};
  }
}

// True when `list` names every slot below `slots` for which dead(slot) holds, once each, and
// no other.
template <class Dead>
bool isFreeList(const std::vector<std::uint32_t>& list, std::size_t slots, Dead dead) {
  std::vector<std::uint8_t> seen(slots, 0);
  for (std::uint32_t i : list) {
    if (i >= slots || seen[i] != 0 || !dead(i)) return false;
    seen[i] = 1;
  }
  std::size_t deadCount = 0;
  for (std::uint32_t i = 0; i < slots; ++i)
    deadCount += dead(i) ? 1 : 0;
  return deadCount == list.size();
}

// Vertices of a shape that ghost-edge data may name, and its edges.
int ghostVertices(const ShapeGeometry& g) {
  if (const auto* p = std::get_if<Polygon>(&g)) return p->count;
  return std::holds_alternative<Segment>(g) ? 2 : 0;
}
int ghostEdges(const ShapeGeometry& g) {
  if (const auto* p = std::get_if<Polygon>(&g)) return p->count;
  return std::holds_alternative<Segment>(g) ? 1 : 0;
}

// A body's state that moves: in the motion section for moving bodies, in the structure
// for static ones (their pose changes only through the API, which changes the structure).
// True when every bit of the numbers is zero (not -0: that must come back as it was).
bool allZeroBits(std::initializer_list<float> values) {
  for (float v : values) {
    if (bitCast<std::uint32_t>(v) != 0) return false;
  }
  return true;
}

void writeBodyMotion(Writer& w, const Body& b) {
  // Resting and sleeping bodies have no velocity, and most bodies no force: a flag each
  // instead of 12 bytes each.
  const bool still = allZeroBits({b.v.x, b.v.y, b.w});
  const bool unforced = allZeroBits({b.force.x, b.force.y, b.torque});
  w.u8(static_cast<std::uint8_t>((b.awake ? 1 : 0) | (b.fast ? 2 : 0) | (still ? 4 : 0) |
                                 (unforced ? 8 : 0)));
  w.xf(b.xf);
  w.vec(b.center);
  if (!still) {
    w.vec(b.v);
    w.f32(b.w);
  }
  if (!unforced) {
    w.vec(b.force);
    w.f32(b.torque);
  }
  w.f32(b.sleepTime);
  w.var(b.island);
  if (b.fast) {
    w.vec(b.startCenter);
    w.f32(b.startAngle);
    w.f32(b.endAngle);
  }
}

void readBodyMotion(Reader& r, Body& b) {
  const std::uint8_t flags = r.u8("body flags");
  if (flags > 15) r.fail("body flags " + std::to_string(flags) + " has unknown bits");
  b.awake = (flags & 1) != 0;
  b.fast = (flags & 2) != 0;
  b.xf = r.xf("body pose");
  b.center = r.vec("body centre of mass");
  if ((flags & 4) == 0) {
    b.v = r.vec("body velocity");
    b.w = r.f32("body angular velocity");
  }
  if ((flags & 8) == 0) {
    b.force = r.vec("body force");
    b.torque = r.f32("body torque");
  }
  b.sleepTime = r.f32("body rest time");
  b.island = r.var("body island");
  if (b.fast) {
    b.startCenter = r.vec("body sweep start");
    b.startAngle = r.f32("body sweep start angle");
    b.endAngle = r.f32("body sweep end angle");
  }
}

// A snapshot stores a contact's recycling reference only when deriving it from the manifold
// and the poses it was computed at (deriveRecycleReference, as the narrow phase does) does
// not give back its bits (a recycled manifold).
bool derivesRecycleReference(const Contact& c) {
  Contact derived = c;
  deriveRecycleReference(derived);
  return std::memcmp(derived.localA, c.localA, sizeof c.localA) == 0 &&
         std::memcmp(derived.localB, c.localB, sizeof c.localB) == 0 &&
         std::memcmp(derived.baseSeparation, c.baseSeparation, sizeof c.baseSeparation) == 0;
}

void writePool(Writer& w, const IdPool& pool) {
  w.size(pool.capacity());
  for (std::uint32_t i = 0; i < pool.capacity(); ++i)
    w.u32(pool.generation(i));
  w.list(pool.freeSlots());
}

IdPool readPool(Reader& r, const char* what) {
  std::vector<std::uint32_t> generations(r.count(what, 4));
  for (std::uint32_t& g : generations)
    g = r.u32(what);
  std::vector<std::uint32_t> freeSlots = r.indexList(what, generations.size());
  if (!r.ok()) return {};
  Result<IdPool> pool = IdPool::fromSlots(std::move(generations), std::move(freeSlots));
  if (!pool) {
    r.fail(std::string(what) + ": " + pool.error().message);
    return {};
  }
  return std::move(pool).value();
}

// A float that may be infinite (a joint's break thresholds): a flag, then the value.
void writeLimit(Writer& w, float v) {
  w.flag(std::isinf(v));
  if (!std::isinf(v)) w.f32(v);
}
float readLimit(Reader& r, const char* what) {
  if (r.flag(what)) return std::numeric_limits<float>::infinity();
  return r.f32(what);
}

void writeJoint(Writer& w, const Joint& j) {
  const JointDef& d = j.def;
  w.u8(static_cast<std::uint8_t>(d.type));
  w.u32(j.bodyA);
  w.u32(j.bodyB);
  w.u8(static_cast<std::uint8_t>((d.enableLimit ? 1 : 0) | (d.enableMotor ? 2 : 0) |
                                 (d.enableSpring ? 4 : 0) | (d.collideConnected ? 8 : 0)));
  for (Vec2 v : {d.anchorA, d.anchorB, d.axis, d.linearOffset, d.target})
    w.vec(v);
  for (float f :
       {d.lower, d.upper, d.motorSpeed, d.maxMotorTorque, d.maxMotorForce, d.hertz, d.dampingRatio,
        d.length, d.minLength, d.maxLength, d.linearHertz, d.angularHertz, d.linearDampingRatio,
        d.angularDampingRatio, d.angularOffset, d.maxForce, d.maxTorque, d.correctionFactor})
    w.f32(f);
  writeLimit(w, d.breakForce);
  writeLimit(w, d.breakTorque);
  w.u64(d.userData);
  for (Vec2 v : {j.localAnchorA, j.localAnchorB, j.localAxisA, j.linearImpulse, j.force})
    w.vec(v);
  for (float f : {j.referenceAngle, j.length, j.angularImpulse, j.perpImpulse, j.axialImpulse,
                  j.springImpulse, j.motorImpulse, j.lowerImpulse, j.upperImpulse, j.torque})
    w.f32(f);
}

void readJoint(Reader& r, Joint& j, std::size_t bodySlots) {
  JointDef& d = j.def;
  const std::uint8_t type = r.u8("joint type");
  if (type > static_cast<std::uint8_t>(JointType::mouse))
    r.fail("joint type " + std::to_string(type) + " is not a joint type");
  d.type = static_cast<JointType>(type);
  j.bodyA = r.u32("joint body A");
  j.bodyB = r.u32("joint body B");
  if (j.bodyA != kNoBody && j.bodyA >= bodySlots) r.fail("joint body A is out of range");
  if (j.bodyB >= bodySlots) r.fail("joint body B is out of range");
  if ((j.bodyA == kNoBody) != (d.type == JointType::mouse))
    r.fail("joint body A: only a mouse joint has none");
  const std::uint8_t flags = r.u8("joint flags");
  if (flags > 15) r.fail("joint flags has unknown bits");
  d.enableLimit = (flags & 1) != 0;
  d.enableMotor = (flags & 2) != 0;
  d.enableSpring = (flags & 4) != 0;
  d.collideConnected = (flags & 8) != 0;
  for (Vec2* v : {&d.anchorA, &d.anchorB, &d.axis, &d.linearOffset, &d.target})
    *v = r.vec("joint setting");
  for (float* f : {&d.lower, &d.upper, &d.motorSpeed, &d.maxMotorTorque, &d.maxMotorForce, &d.hertz,
                   &d.dampingRatio, &d.length, &d.minLength, &d.maxLength, &d.linearHertz,
                   &d.angularHertz, &d.linearDampingRatio, &d.angularDampingRatio, &d.angularOffset,
                   &d.maxForce, &d.maxTorque, &d.correctionFactor})
    *f = r.f32("joint setting");
  d.breakForce = readLimit(r, "joint break force");
  d.breakTorque = readLimit(r, "joint break torque");
  d.userData = r.u64("joint user data");
  for (Vec2* v : {&j.localAnchorA, &j.localAnchorB, &j.localAxisA, &j.linearImpulse, &j.force})
    *v = r.vec("joint state");
  for (float* f : {&j.referenceAngle, &j.length, &j.angularImpulse, &j.perpImpulse, &j.axialImpulse,
                   &j.springImpulse, &j.motorImpulse, &j.lowerImpulse, &j.upperImpulse, &j.torque})
    *f = r.f32("joint state");
  j.alive = true;
}

}  // namespace

// A world state being read: what the structure section gives the motion section.
struct SnapshotLoading {
  std::unique_ptr<WorldState> s;
  BroadPhaseConfig config;
  BroadPhaseRecords bp;                  // filled by both sections, built last
  std::vector<std::uint8_t> proxyAlive;  // per proxy slot
};

// Writes and rebuilds WorldState, part by part (a friend of the parts with private state).
class SnapshotCodec {
 public:
  static void writeStructure(Writer& w, const WorldState& s);
  static void writeMotion(Writer& w, const WorldState& s);
  // Builds a world state from the two sections; `worldId` is the id its handles carry.
  static Result<std::unique_ptr<WorldState>> read(std::span<const std::uint8_t> structure,
                                                  std::span<const std::uint8_t> motion,
                                                  std::uint32_t worldId);
  static Status readStructure(std::span<const std::uint8_t> structure, std::uint32_t worldId,
                              SnapshotLoading& l);
  static Status readMotion(std::span<const std::uint8_t> motion, std::uint32_t worldId,
                           SnapshotLoading& l);
  static void keepCallbacks(EventDispatcher& to, EventDispatcher& from) {
    to.callbacks_ = std::move(from.callbacks_);
    to.pending_ = std::move(from.pending_);
  }
};

void SnapshotCodec::writeStructure(Writer& w, const WorldState& s) {
  const WorldDef& d = s.def;
  w.vec(d.gravity);
  w.f32(d.timeStep);
  w.i32(d.substeps);
  w.u8(static_cast<std::uint8_t>(d.broadPhase));
  for (float f :
       {d.contactHertz, d.contactDampingRatio, d.contactPushMaxSpeed, d.restitutionThreshold,
        d.hitEventThreshold, d.speculativeDistance, d.maxRotationPerSubstep,
        d.contactRecycleDistance, d.jointHertz, d.jointDampingRatio})
    w.f32(f);
  w.u8(static_cast<std::uint8_t>((d.enableContinuous ? 1 : 0) | (d.removeGhostCollisions ? 2 : 0) |
                                 (d.scalarSolver ? 4 : 0) | (d.enableSleep ? 8 : 0) |
                                 (d.sweepDynamicPairs ? 0 : 16)));

  const BodyStore& store = s.store;
  writePool(w, store.bodyIds);
  for (std::uint32_t i = 0; i < store.bodies.size(); ++i) {
    if (!store.bodyAlive(i)) continue;
    const Body& b = store.bodies[i];
    w.u8(static_cast<std::uint8_t>(b.type));
    w.u8(static_cast<std::uint8_t>((b.bullet ? 1 : 0) | (b.enableSleep ? 2 : 0)));
    w.vec(b.localCenter);
    for (float f : {b.mass, b.invMass, b.inertia, b.invInertia, b.linearDamping, b.angularDamping,
                    b.gravityScale, b.minExtent, b.maxExtent, b.sleepThreshold})
      w.f32(f);
    w.u64(b.userData);
    w.list(b.shapes);
    if (b.type == BodyType::staticBody) writeBodyMotion(w, b);
  }
  writePool(w, store.shapeIds);
  for (std::uint32_t i = 0; i < store.shapes.size(); ++i) {
    if (!store.shapeAlive(i)) continue;
    const Shape& sh = store.shapes[i];
    w.var(sh.body);
    w.u32(sh.proxy.index);
    writeGeometry(w, *sh.geometry);
    w.f32(sh.def.density);
    w.f32(sh.def.friction);
    w.f32(sh.def.restitution);
    w.flag(sh.def.sensor);
    w.u64(sh.def.filter.category);
    w.u64(sh.def.filter.mask);
    w.i32(sh.def.filter.group);
    w.u64(sh.def.userData);
    // A chain's links are made by createChain; the rest of the ghost-edge data is derived
    // from the static geometry at the next step, so it goes with the motion (a structure
    // fingerprint taken before that step still matches one taken after).
    const StaticEdges& e = sh.edges;
    w.u8(static_cast<std::uint8_t>((e.chain ? 1 : 0) | (e.hasPrev ? 2 : 0) | (e.hasNext ? 4 : 0)));
    if (e.chain) {
      w.vec(e.prev);
      w.vec(e.next);
    }
  }

  // The broad phase: its slots, and what stays put of each proxy.
  const BroadPhaseRecords bp = s.broadPhase.records();
  w.size(bp.generations.size());
  for (std::uint32_t g : bp.generations)
    w.u32(g);
  w.list(bp.freeSlots);
  std::vector<std::uint8_t> alive(bp.generations.size(), 1);
  for (std::uint32_t f : bp.freeSlots)
    alive[f] = 0;
  for (std::uint32_t p = 0; p < bp.generations.size(); ++p) {
    if (alive[p] == 0) continue;
    const bool isStatic = bp.kinds[p] == ProxyKind::staticProxy;
    w.flag(isStatic);
    w.u64(bp.filters[p].category);
    w.u64(bp.filters[p].mask);
    w.i32(bp.filters[p].group);
    w.u64(bp.userData[p]);
    if (isStatic) {
      w.box(bp.tight[p]);
      w.box(bp.fat[p]);
    }
  }
}

void SnapshotCodec::writeMotion(Writer& w, const WorldState& s) {
  w.u64(s.stepCount);
  w.f64(s.time);
  const BodyStore& store = s.store;
  for (std::uint32_t i = 0; i < store.bodies.size(); ++i) {
    if (store.bodyAlive(i) && store.bodies[i].type != BodyType::staticBody)
      writeBodyMotion(w, store.bodies[i]);
  }
  for (std::uint32_t i = 0; i < store.shapes.size(); ++i) {
    if (store.shapeAlive(i)) w.list(store.shapes[i].contacts);
  }
  // Ghost-edge data (only static shapes have any).
  w.flag(s.edges.dirty_);
  w.u32(static_cast<std::uint32_t>(s.edges.activeShapes_));
  for (std::uint32_t i = 0; i < store.shapes.size(); ++i) {
    if (!store.shapeAlive(i) || store.bodies[store.shapes[i].body].type != BodyType::staticBody)
      continue;
    const StaticEdges& e = store.shapes[i].edges;
    const bool data = !e.covered.empty() || !e.cones.empty();
    w.u8(static_cast<std::uint8_t>((e.active ? 1 : 0) | (data ? 2 : 0)));
    if (!data) continue;
    w.size(e.covered.size());
    for (const CoveredSpan& c : e.covered) {
      w.i32(c.edge);
      w.f32(c.t0);
      w.f32(c.t1);
    }
    w.size(e.cones.size());
    for (const EdgeCone& c : e.cones) {
      w.u8(static_cast<std::uint8_t>(c.kind));
      w.vec(c.lo);
      w.vec(c.hi);
    }
  }

  // Contacts: the slots (a free slot is one byte), the free list, then the change lists
  // the island set has not taken yet (empty between steps, kept for completeness).
  const ContactSet& cs = s.contacts;
  // The poses manifolds were computed at: the contacts of a body computed in one step share
  // its pose, so each distinct pose is written once, in order of first use, and contacts
  // name them by number.
  std::vector<Transform> poses;
  std::map<std::array<std::uint32_t, 4>, std::uint32_t> poseIndex;
  auto poseOf = [&](Transform t) {
    const std::array<std::uint32_t, 4> key{
        bitCast<std::uint32_t>(t.p.x), bitCast<std::uint32_t>(t.p.y), bitCast<std::uint32_t>(t.q.c),
        bitCast<std::uint32_t>(t.q.s)};
    auto [it, added] = poseIndex.emplace(key, static_cast<std::uint32_t>(poses.size()));
    if (added) poses.push_back(t);
    return it->second;
  };
  for (const Contact& c : cs.contacts) {
    if (c.alive && c.recycleValid) {
      poseOf(c.cachedA);
      poseOf(c.cachedB);
    }
  }
  w.size(poses.size());
  for (const Transform& t : poses)
    w.xf(t);
  w.size(cs.contacts.size());
  for (std::size_t index = 0; index < cs.contacts.size(); ++index) {
    const Contact& c = cs.contacts[index];
    if (!c.alive) {
      w.u8(0);
      continue;
    }
    const bool derived = c.recycleValid && derivesRecycleReference(c);
    const bool reference = c.recycleValid && !derived;
    w.u8(static_cast<std::uint8_t>(1 | (c.touching ? 2 : 0) | (c.sensor ? 4 : 0) |
                                   (c.recycleValid ? 8 : 0) | (c.recycled ? 16 : 0) |
                                   (derived ? 32 : 0)));
    w.var(c.shapeA);
    w.var(c.shapeB);
    w.vec(c.manifold.normal);
    w.u8(static_cast<std::uint8_t>(c.manifold.pointCount));
    // Only the manifold's points are ever read: warm starting, recycling and the solver
    // all go up to pointCount.
    for (int k = 0; k < c.manifold.pointCount; ++k) {
      const ManifoldPoint& p = c.manifold.points[k];
      w.vec(p.point);
      w.vec(p.anchorA);
      w.vec(p.anchorB);
      w.f32(p.separation);
      w.u32(p.id);
      w.f32(cs.impulses[index].normal[k]);
      w.f32(cs.impulses[index].tangent[k]);
      if (reference) {
        w.vec(c.localA[k]);
        w.vec(c.localB[k]);
        w.f32(c.baseSeparation[k]);
      }
    }
    if (c.recycleValid) {
      w.var(poseOf(c.cachedA));
      w.var(poseOf(c.cachedB));
    }
  }
  w.list(cs.free_);
  for (const auto* pairs : {&cs.changes_.began, &cs.changes_.ended}) {
    w.size(pairs->size());
    for (const BodyPair& p : *pairs) {
      w.var(p.a);
      w.var(p.b);
    }
  }
  w.list(cs.changes_.toWake);

  // Islands.
  const IslandSet& is = s.islands;
  w.size(is.islands_.size());
  for (const Island& island : is.islands_) {
    w.u8(static_cast<std::uint8_t>((island.alive ? 1 : 0) | (island.awake ? 2 : 0) |
                                   (island.dirty ? 4 : 0)));
    if (island.alive) w.list(island.bodies);
  }
  w.list(is.free_);
  w.size(is.awakeBits_.size());
  for (std::uint64_t word : is.awakeBits_)
    w.u64(word);
  w.u64(is.step_);

  // The broad phase: what moves.
  const BroadPhaseRecords bp = s.broadPhase.records();
  std::vector<std::uint8_t> alive(bp.generations.size(), 1);
  for (std::uint32_t f : bp.freeSlots)
    alive[f] = 0;
  for (std::uint32_t p = 0; p < bp.generations.size(); ++p) {
    if (alive[p] == 0) continue;
    w.u8(bp.buffered[p]);
    if (bp.kinds[p] != ProxyKind::staticProxy) {
      w.box(bp.tight[p]);
      w.box(bp.fat[p]);
    }
  }
  w.list(bp.moveBuffer);

  // Ends of contacts whose shapes were destroyed since the last step: the next step
  // reports them.
  const EventDispatcher& ev = s.events;
  w.size(ev.endsSinceStep_.size());
  for (const EventDispatcher::PendingEnd& e : ev.endsSinceStep_) {
    w.u32(e.shapeA.index);
    w.u32(e.shapeA.generation);
    w.u32(e.shapeB.index);
    w.u32(e.shapeB.generation);
    w.u64(e.categoryA);
    w.u64(e.categoryB);
    w.flag(e.sensor);
  }

  // Joints: settings and warm-start impulses alike (a rollback brings back a joint that
  // broke since). The bodies' lists of joints are rebuilt from them.
  const JointSet& js = s.joints;
  writePool(w, js.ids);
  for (std::uint32_t j = 0; j < js.joints.size(); ++j) {
    if (js.ids.isAlive(j)) writeJoint(w, js.joints[j]);
  }
  w.size(js.endsSinceStep.size());
  for (const JointEndEvent& e : js.endsSinceStep) {
    w.u32(e.joint.index);
    w.u32(e.joint.generation);
    w.u32(e.bodyA.index);
    w.u32(e.bodyA.generation);
    w.u32(e.bodyB.index);
    w.u32(e.bodyB.generation);
    w.u8(static_cast<std::uint8_t>(e.reason));
    w.vec(e.force);
    w.f32(e.torque);
    w.u64(e.userData);
  }
}

Result<std::unique_ptr<WorldState>> SnapshotCodec::read(std::span<const std::uint8_t> structure,
                                                        std::span<const std::uint8_t> motion,
                                                        std::uint32_t worldId) {
  SnapshotLoading l;
  if (Status st = readStructure(structure, worldId, l); !st) return fail(st.message());
  if (Status st = readMotion(motion, worldId, l); !st) return fail(st.message());
  // Each proxy's margin is its shape's (shapeFatMargin): a function of what the snapshot
  // holds, so it is not stored. A slot no live shape names keeps the config's margin.
  const BodyStore& store = l.s->store;
  l.bp.margins.assign(l.bp.generations.size(), l.config.margin);
  for (std::uint32_t sh = 0; sh < store.shapes.size(); ++sh) {
    if (!store.shapeAlive(sh)) continue;
    const Shape& shape = store.shapes[sh];
    if (shape.proxy.index < l.bp.margins.size())
      l.bp.margins[shape.proxy.index] =
          shapeFatMargin(*shape.geometry, store.bodies[shape.body].type, l.s->def);
  }
  Result<BroadPhase> built = BroadPhase::fromRecords(l.config, std::move(l.bp));
  if (!built) return fail("motion section: " + built.error().message);
  l.s->broadPhase = std::move(built).value();
  return std::move(l.s);
}

Status SnapshotCodec::readStructure(std::span<const std::uint8_t> structure, std::uint32_t worldId,
                                    SnapshotLoading& l) {
  Reader r(structure, "structure");
  WorldDef d;
  d.gravity = r.vec("WorldDef.gravity");
  d.timeStep = r.f32("WorldDef.timeStep");
  d.substeps = r.i32("WorldDef.substeps");
  const std::uint8_t kind = r.u8("WorldDef.broadPhase");
  if (kind > static_cast<std::uint8_t>(BroadPhaseKind::brute))
    r.fail("WorldDef.broadPhase " + std::to_string(kind) + " is not a broad-phase kind");
  d.broadPhase = static_cast<BroadPhaseKind>(kind);
  for (float* f :
       {&d.contactHertz, &d.contactDampingRatio, &d.contactPushMaxSpeed, &d.restitutionThreshold,
        &d.hitEventThreshold, &d.speculativeDistance, &d.maxRotationPerSubstep,
        &d.contactRecycleDistance, &d.jointHertz, &d.jointDampingRatio})
    *f = r.f32("WorldDef setting");
  const std::uint8_t defFlags = r.u8("WorldDef flags");
  if (defFlags > 31) r.fail("WorldDef flags has unknown bits");
  d.enableContinuous = (defFlags & 1) != 0;
  d.removeGhostCollisions = (defFlags & 2) != 0;
  d.scalarSolver = (defFlags & 4) != 0;
  d.enableSleep = (defFlags & 8) != 0;
  // Set when the pairs are not swept, so that snapshots from before the setting read as on.
  d.sweepDynamicPairs = (defFlags & 16) == 0;
  if (!r.ok()) return fail(r.error());
  if (Status st = checkWorldDef(d); !st) return fail("structure section: " + st.message());
  l.config = worldBroadPhaseConfig(d);
  Result<BroadPhase> empty = BroadPhase::create(l.config);
  if (!empty) return fail("structure section: broad phase: " + empty.error().message);
  l.s = std::make_unique<WorldState>(d, std::move(empty).value(), worldId);
  BodyStore& store = l.s->store;

  // Bodies.
  store.bodyIds = readPool(r, "body slots");
  store.bodies.resize(store.bodyIds.capacity());
  for (std::uint32_t i = 0; i < store.bodies.size() && r.ok(); ++i) {
    if (!store.bodyIds.isAlive(i)) continue;
    Body& b = store.bodies[i];
    const std::uint8_t type = r.u8("body type");
    if (type > static_cast<std::uint8_t>(BodyType::dynamicBody))
      r.fail("body " + std::to_string(i) + " type " + std::to_string(type) + " is not a type");
    b.type = static_cast<BodyType>(type);
    const std::uint8_t flags = r.u8("body settings");
    if (flags > 3) r.fail("body settings has unknown bits");
    b.bullet = (flags & 1) != 0;
    b.enableSleep = (flags & 2) != 0;
    b.localCenter = r.vec("body local centre");
    for (float* f :
         {&b.mass, &b.invMass, &b.inertia, &b.invInertia, &b.linearDamping, &b.angularDamping,
          &b.gravityScale, &b.minExtent, &b.maxExtent, &b.sleepThreshold})
      *f = r.f32("body mass or setting");
    b.userData = r.u64("body user data");
    b.shapes = r.indexList("body shape", 0xffffffffu);
    if (b.type == BodyType::staticBody) {
      readBodyMotion(r, b);
    } else {
      b.awake = false;  // until the motion section says
    }
  }

  // Shapes.
  store.shapeIds = readPool(r, "shape slots");
  store.shapes.resize(store.shapeIds.capacity());
  std::vector<std::uint32_t> proxyOf(store.shapes.size(), kNone);
  for (std::uint32_t i = 0; i < store.shapes.size() && r.ok(); ++i) {
    if (!store.shapeIds.isAlive(i)) continue;
    Shape& sh = store.shapes[i];
    sh.body = r.index("shape body", store.bodies.size());
    if (r.ok() && !store.bodyIds.isAlive(sh.body))
      r.fail("shape " + std::to_string(i) + " names dead body " + std::to_string(sh.body));
    proxyOf[i] = r.u32("shape proxy");
    const ShapeGeometry geometry = readGeometry(r);
    if (r.ok()) {
      // Validated, and shared as when the shapes were made.
      Result<std::shared_ptr<const ShapeGeometry>> stored =
          store.geometries.intern(geometry, validateShape);
      if (stored)
        sh.geometry = std::move(stored).value();
      else
        r.fail("shape " + std::to_string(i) + " geometry: " + stored.error().message);
    }
    // Bad bytes leave a placeholder: the checks below read the geometry before the reader's
    // error is returned.
    if (!sh.geometry) sh.geometry = std::make_shared<const ShapeGeometry>();
    sh.def.density = r.f32("shape density");
    sh.def.friction = r.f32("shape friction");
    sh.def.restitution = r.f32("shape restitution");
    sh.def.sensor = r.flag("shape sensor");
    sh.def.filter.category = r.u64("shape category");
    sh.def.filter.mask = r.u64("shape mask");
    sh.def.filter.group = r.i32("shape group");
    sh.def.userData = r.u64("shape user data");
    StaticEdges& e = sh.edges;
    const std::uint8_t ef = r.u8("shape chain flags");
    if (ef > 7) r.fail("shape chain flags has unknown bits");
    e.chain = (ef & 1) != 0;
    e.hasPrev = (ef & 2) != 0;
    e.hasNext = (ef & 4) != 0;
    if (e.chain) {
      e.prev = r.vec("chain previous point");
      e.next = r.vec("chain next point");
    }
    if (r.ok() && e.chain &&
        (store.bodies[sh.body].type != BodyType::staticBody ||
         !std::holds_alternative<Segment>(*sh.geometry)))
      r.fail("shape " + std::to_string(i) + " is a chain link but not a static segment");
  }

  // Bodies and shapes agree.
  for (std::uint32_t i = 0; i < store.bodies.size() && r.ok(); ++i) {
    if (!store.bodyIds.isAlive(i)) continue;
    for (std::uint32_t sh : store.bodies[i].shapes) {
      if (sh >= store.shapes.size() || !store.shapeIds.isAlive(sh) || store.shapes[sh].body != i)
        r.fail("body " + std::to_string(i) + " lists shape " + std::to_string(sh) +
               ", which is not its own");
    }
  }

  // The broad phase's fixed records.
  BroadPhaseRecords& bp = l.bp;
  bp.generations.resize(r.count("proxy slots", 4));
  for (std::uint32_t& g : bp.generations)
    g = r.u32("proxy generation");
  bp.freeSlots = r.indexList("free proxy slot", bp.generations.size());
  const std::size_t proxySlots = bp.generations.size();
  std::vector<std::uint8_t>& proxyAlive = l.proxyAlive;
  proxyAlive.assign(proxySlots, 1);
  for (std::uint32_t f : bp.freeSlots)
    proxyAlive[f] = 0;
  bp.tight.resize(proxySlots);
  bp.fat.resize(proxySlots);
  bp.kinds.resize(proxySlots);
  bp.buffered.resize(proxySlots);
  bp.filters.resize(proxySlots);
  bp.userData.resize(proxySlots);
  for (std::uint32_t p = 0; p < proxySlots && r.ok(); ++p) {
    if (proxyAlive[p] == 0) continue;
    const bool isStatic = r.flag("proxy kind");
    bp.kinds[p] = isStatic ? ProxyKind::staticProxy : ProxyKind::dynamicProxy;
    bp.filters[p].category = r.u64("proxy category");
    bp.filters[p].mask = r.u64("proxy mask");
    bp.filters[p].group = r.i32("proxy group");
    bp.userData[p] = r.u64("proxy user data");
    if (isStatic) {
      bp.tight[p] = r.box("static proxy tight box");
      bp.fat[p] = r.box("static proxy fat box");
    }
  }
  if (r.ok() && !r.atEnd()) r.fail(std::to_string(r.left()) + " bytes left over");
  if (!r.ok()) return fail(r.error());
  // Each shape's proxy is live and carries the shape's index; proxies and shapes match one
  // to one (World::validate checks the count and the boxes).
  for (std::uint32_t i = 0; i < store.shapes.size(); ++i) {
    if (!store.shapeIds.isAlive(i)) continue;
    const std::uint32_t p = proxyOf[i];
    if (p >= proxySlots || proxyAlive[p] == 0 || bp.userData[p] != i)
      return fail("structure section: shape " + std::to_string(i) +
                  " has no live proxy of its own");
    store.shapes[i].proxy = {p, bp.generations[p]};
    const bool isStatic = store.bodies[store.shapes[i].body].type == BodyType::staticBody;
    if (isStatic != (bp.kinds[p] == ProxyKind::staticProxy))
      return fail("structure section: shape " + std::to_string(i) +
                  "'s proxy kind disagrees with its body's type");
  }

  return {};
}

Status SnapshotCodec::readMotion(std::span<const std::uint8_t> motion, std::uint32_t worldId,
                                 SnapshotLoading& l) {
  WorldState* s = l.s.get();
  BodyStore& store = s->store;
  BroadPhaseRecords& bp = l.bp;
  const std::size_t proxySlots = bp.generations.size();
  const std::vector<std::uint8_t>& proxyAlive = l.proxyAlive;
  Reader m(motion, "motion");
  s->stepCount = m.u64("step count");
  s->time = m.f64("time");
  for (std::uint32_t i = 0; i < store.bodies.size() && m.ok(); ++i) {
    if (store.bodyIds.isAlive(i) && store.bodies[i].type != BodyType::staticBody)
      readBodyMotion(m, store.bodies[i]);
  }
  for (std::uint32_t i = 0; i < store.bodies.size() && m.ok(); ++i) {
    if (!store.bodyIds.isAlive(i)) continue;
    const Body& b = store.bodies[i];
    const bool wantsIsland = b.type == BodyType::dynamicBody;
    if (wantsIsland == (b.island == kNoIsland))
      m.fail("body " + std::to_string(i) + " island " + std::to_string(b.island) +
             (wantsIsland ? " is missing" : " on a body that is not dynamic"));
  }
  ContactSet& cs = s->contacts;
  for (std::uint32_t i = 0; i < store.shapes.size() && m.ok(); ++i) {
    if (store.shapeIds.isAlive(i)) store.shapes[i].contacts = m.indexList("shape contact", kNone);
  }
  s->edges.dirty_ = m.flag("ghost edges dirty");
  s->edges.activeShapes_ = m.u32("active ghost shapes");
  std::size_t active = 0;
  for (std::uint32_t i = 0; i < store.shapes.size() && m.ok(); ++i) {
    if (!store.shapeIds.isAlive(i) ||
        store.bodies[store.shapes[i].body].type != BodyType::staticBody)
      continue;
    Shape& sh = store.shapes[i];
    StaticEdges& e = sh.edges;
    const std::uint8_t flags = m.u8("ghost edge flags");
    if (flags > 3) m.fail("ghost edge flags " + std::to_string(flags) + " has unknown bits");
    e.active = (flags & 1) != 0;
    active += e.active ? 1 : 0;
    // ghost_edges.cpp reads an active shape's cone at every vertex.
    if (e.active && (flags & 2) == 0)
      m.fail("shape " + std::to_string(i) + " is flagged for ghost edges but has no cones");
    if ((flags & 2) == 0) continue;
    const int edgeCount = ghostEdges(*sh.geometry);
    e.covered.resize(m.count("covered spans", 12));
    for (CoveredSpan& c : e.covered) {
      c.edge = m.i32("covered span edge");
      if (c.edge < 0 || c.edge >= edgeCount) m.fail("covered span edge is out of range");
      c.t0 = m.f32("covered span start");
      c.t1 = m.f32("covered span end");
    }
    e.cones.resize(m.count("vertex cones", 17));
    if (!e.cones.empty() && e.cones.size() != static_cast<std::size_t>(ghostVertices(*sh.geometry)))
      m.fail("shape " + std::to_string(i) + " has " + std::to_string(e.cones.size()) +
             " vertex cones for " + std::to_string(ghostVertices(*sh.geometry)) + " vertices");
    for (EdgeCone& c : e.cones) {
      const std::uint8_t k = m.u8("vertex cone kind");
      if (k > static_cast<std::uint8_t>(EdgeCone::Kind::inside))
        m.fail("vertex cone kind " + std::to_string(k) + " is not a kind");
      c.kind = static_cast<EdgeCone::Kind>(k);
      c.lo = m.vec("vertex cone");
      c.hi = m.vec("vertex cone");
    }
    // Covered edges are polygons' (ghost_edges.cpp reads the shape as one); chain links are
    // segments.
    if (m.ok() && e.active &&
        !(e.chain ? std::holds_alternative<Segment>(*sh.geometry)
                  : std::holds_alternative<Polygon>(*sh.geometry)))
      m.fail("shape " + std::to_string(i) + " has ghost-edge data but is not a polygon " +
             "(or a chain's segment)");
    if (m.ok() && e.active &&
        e.cones.size() != static_cast<std::size_t>(ghostVertices(*sh.geometry)))
      m.fail("shape " + std::to_string(i) + " is flagged for ghost edges but lacks its cones");
    if (m.ok() && !e.active && (!e.covered.empty() || !e.cones.empty()))
      m.fail("shape " + std::to_string(i) + " has ghost-edge data but is not flagged");
  }
  if (m.ok() && active != s->edges.activeShapes_)
    m.fail("active ghost shapes " + std::to_string(s->edges.activeShapes_) + " but " +
           std::to_string(active) + " shapes are flagged");
  std::vector<Transform> poses(m.count("manifold poses", 16));
  for (Transform& t : poses)
    t = m.xf("manifold pose");
  cs.contacts.resize(m.count("contact slots", 1));
  cs.impulses.assign(cs.contacts.size(), ContactImpulses{});
  for (std::uint32_t i = 0; i < cs.contacts.size() && m.ok(); ++i) {
    Contact& c = cs.contacts[i];
    const std::uint8_t flags = m.u8("contact flags");
    if (flags == 0) continue;
    if ((flags & 1) == 0 || flags > 63 || ((flags & 32) != 0 && (flags & 8) == 0))
      m.fail("contact flags " + std::to_string(flags) + " has unknown bits");
    const bool derived = (flags & 32) != 0;
    c.alive = true;
    c.touching = (flags & 2) != 0;
    c.sensor = (flags & 4) != 0;
    c.recycleValid = (flags & 8) != 0;
    c.recycled = (flags & 16) != 0;
    c.shapeA = m.index("contact shape", store.shapes.size());
    c.shapeB = m.index("contact shape", store.shapes.size());
    if (m.ok() && (!store.shapeIds.isAlive(c.shapeA) || !store.shapeIds.isAlive(c.shapeB) ||
                   c.shapeA == c.shapeB))
      m.fail("contact " + std::to_string(i) + " names a dead shape or one shape twice");
    // What findNew lets through: shapes of two bodies, one of them dynamic.
    if (m.ok()) {
      const std::uint32_t ba = store.shapes[c.shapeA].body, bb = store.shapes[c.shapeB].body;
      if (ba == bb || (store.bodies[ba].type != BodyType::dynamicBody &&
                       store.bodies[bb].type != BodyType::dynamicBody))
        m.fail("contact " + std::to_string(i) + " is not between two bodies, one dynamic");
    }
    c.manifold.normal = m.vec("manifold normal");
    const std::uint8_t points = m.u8("manifold point count");
    if (points > kMaxManifoldPoints) m.fail("manifold point count is above kMaxManifoldPoints");
    c.manifold.pointCount = m.ok() ? points : 0;
    for (int k = 0; k < c.manifold.pointCount; ++k) {
      ManifoldPoint& p = c.manifold.points[k];
      p.point = m.vec("manifold point");
      p.anchorA = m.vec("manifold anchor");
      p.anchorB = m.vec("manifold anchor");
      p.separation = m.f32("manifold separation");
      p.id = m.u32("manifold feature id");
      cs.impulses[i].normal[k] = m.f32("normal impulse");
      cs.impulses[i].tangent[k] = m.f32("tangent impulse");
      if (c.recycleValid && !derived) {
        c.localA[k] = m.vec("recycled point");
        c.localB[k] = m.vec("recycled point");
        c.baseSeparation[k] = m.f32("recycled separation");
      }
    }
    if (c.recycleValid) {
      // index() fails (and gives 0) on any number when there are no poses: look only when ok.
      const std::uint32_t pa = m.index("manifold pose", poses.size());
      const std::uint32_t pb = m.index("manifold pose", poses.size());
      if (!m.ok()) break;
      c.cachedA = poses[pa];
      c.cachedB = poses[pb];
      if (derived) deriveRecycleReference(c);
    }
    if (!m.ok()) break;
    // What findNew derives from the shapes (contact_set.cpp), derived the same way.
    const Shape& sa = store.shapes[c.shapeA];
    const Shape& sb = store.shapes[c.shapeB];
    c.bodyA = sa.body;
    c.bodyB = sb.body;
    c.proxyA = sa.proxy;
    c.proxyB = sb.proxy;
    c.fn = findManifoldFn(shapeType(*sa.geometry), shapeType(*sb.geometry));
    c.friction = std::sqrt(sa.def.friction * sb.def.friction);
    c.restitution = maxf(sa.def.restitution, sb.def.restitution);
    cs.byPair_.set((static_cast<std::uint64_t>(std::min(c.shapeA, c.shapeB)) << 32) |
                       std::max(c.shapeA, c.shapeB),
                   i);
    ++cs.count_;
  }
  cs.rebuildHeads();
  cs.free_ = m.indexList("free contact slot", cs.contacts.size());
  if (m.ok() && !isFreeList(cs.free_, cs.contacts.size(),
                            [&](std::uint32_t i) { return !cs.contacts[i].alive; }))
    m.fail("the free contact slots are not exactly the dead ones, once each");
  for (auto* pairs : {&cs.changes_.began, &cs.changes_.ended}) {
    pairs->resize(m.count("island change", 2));
    for (BodyPair& p : *pairs) {
      p.a = m.index("island change body", store.bodies.size());
      p.b = m.index("island change body", store.bodies.size());
    }
  }
  cs.changes_.toWake = m.indexList("body to wake", store.bodies.size());

  IslandSet& is = s->islands;
  is.islands_.resize(m.count("island slots", 1));
  for (Island& island : is.islands_) {
    const std::uint8_t flags = m.u8("island flags");
    if (flags > 7) m.fail("island flags has unknown bits");
    island.alive = (flags & 1) != 0;
    island.awake = (flags & 2) != 0;
    island.dirty = (flags & 4) != 0;
    if (island.alive) island.bodies = m.indexList("island body", store.bodies.size());
  }
  is.free_ = m.indexList("free island slot", is.islands_.size());
  if (m.ok() && !isFreeList(is.free_, is.islands_.size(),
                            [&](std::uint32_t i) { return !is.islands_[i].alive; }))
    m.fail("the free island slots are not exactly the dead ones, once each");
  for (std::uint32_t i = 0; i < store.bodies.size() && m.ok(); ++i) {
    if (store.bodyIds.isAlive(i) && store.bodies[i].island != kNoIsland &&
        (store.bodies[i].island >= is.islands_.size() ||
         !is.islands_[store.bodies[i].island].alive))
      m.fail("body " + std::to_string(i) + " names island " +
             std::to_string(store.bodies[i].island) + ", which is not live");
  }
  is.awakeBits_.resize(m.count("awake words", 8));
  if (is.awakeBits_.size() > (store.bodies.size() + 63) / 64)
    m.fail("more awake words than bodies need");
  for (std::uint64_t& word : is.awakeBits_)
    word = m.u64("awake bits");
  // Bits past the last body would send the solver beyond the body array.
  for (std::size_t b = store.bodies.size(); m.ok() && b < 64 * is.awakeBits_.size(); ++b) {
    if (((is.awakeBits_[b / 64] >> (b % 64)) & 1u) != 0)
      m.fail("an awake bit is set past the last body");
  }
  is.step_ = m.u64("island step");

  for (std::uint32_t p = 0; p < proxySlots && m.ok(); ++p) {
    if (proxyAlive[p] == 0) continue;
    bp.buffered[p] = m.u8("proxy buffered flag");
    if (bp.kinds[p] != ProxyKind::staticProxy) {
      bp.tight[p] = m.box("proxy tight box");
      bp.fat[p] = m.box("proxy fat box");
    }
  }
  bp.moveBuffer = m.indexList("move buffer entry", proxySlots);

  EventDispatcher& ev = s->events;
  ev.endsSinceStep_.resize(m.count("pending end events", 33));
  for (EventDispatcher::PendingEnd& e : ev.endsSinceStep_) {
    e.shapeA.index = m.u32("pending end shape");
    e.shapeA.generation = m.u32("pending end shape");
    e.shapeB.index = m.u32("pending end shape");
    e.shapeB.generation = m.u32("pending end shape");
    e.shapeA.world = e.shapeB.world = worldId;
    e.categoryA = m.u64("pending end category");
    e.categoryB = m.u64("pending end category");
    e.sensor = m.flag("pending end sensor flag");
  }

  JointSet& js = s->joints;
  js.ids = readPool(m, "joint slots");
  js.joints.assign(js.ids.capacity(), Joint{});
  for (std::uint32_t j = 0; j < js.joints.size() && m.ok(); ++j) {
    if (!js.ids.isAlive(j)) continue;
    Joint& joint = js.joints[j];
    readJoint(m, joint, store.bodies.size());
    joint.def.bodyA = joint.bodyA == kNoBody ? BodyId{} : store.bodyId(joint.bodyA);
    joint.def.bodyB = store.bodyId(joint.bodyB);
  }
  js.endsSinceStep.resize(m.count("pending joint end events", 45));
  for (JointEndEvent& e : js.endsSinceStep) {
    e.joint.index = m.u32("pending joint end");
    e.joint.generation = m.u32("pending joint end");
    e.bodyA.index = m.u32("pending joint end body");
    e.bodyA.generation = m.u32("pending joint end body");
    e.bodyB.index = m.u32("pending joint end body");
    e.bodyB.generation = m.u32("pending joint end body");
    e.joint.world = worldId;
    e.bodyA.world = e.bodyA.index == kNoBody ? 0 : worldId;
    e.bodyB.world = worldId;
    const std::uint8_t reason = m.u8("pending joint end reason");
    if (reason > static_cast<std::uint8_t>(JointEndReason::bodyDestroyed))
      m.fail("pending joint end reason " + std::to_string(reason) + " is not a reason");
    e.reason = static_cast<JointEndReason>(reason);
    e.force = m.vec("pending joint end force");
    e.torque = m.f32("pending joint end torque");
    e.userData = m.u64("pending joint end user data");
  }
  if (m.ok()) js.rebuildLists(store.bodies.size());
  if (m.ok() && !m.atEnd()) m.fail(std::to_string(m.left()) + " bytes left over");
  if (!m.ok()) return fail(m.error());
  return {};
}

namespace {

std::vector<std::uint8_t> structureBytes(const WorldState& s) {
  Writer w;
  SnapshotCodec::writeStructure(w, s);
  return std::move(w.bytes);
}

}  // namespace
}  // namespace detail

Result<std::vector<std::uint8_t>> World::snapshot(SnapshotKind kind) const {
  if (Status u = checkUsable("snapshot"); !u) return fail(u.message());
  if (state().inStep) return fail("snapshot: called during a step or from an event callback");
  if (kind != SnapshotKind::full && kind != SnapshotKind::dynamic)
    return fail("snapshot: kind is not a SnapshotKind");
  const std::vector<std::uint8_t> structure = detail::structureBytes(state());
  detail::Writer payload;
  if (kind == SnapshotKind::full) {
    payload.u64(structure.size());
    payload.bytes.insert(payload.bytes.end(), structure.begin(), structure.end());
  }
  detail::SnapshotCodec::writeMotion(payload, state());

  detail::Writer out;
  out.bytes.assign(std::begin(detail::kMagic), std::end(detail::kMagic));
  out.u32(kSnapshotFormatVersion);
  out.u8(static_cast<std::uint8_t>(kind));
  out.u8(0);
  out.u8(0);
  out.u8(0);
  out.u64(detail::buildFingerprint());
  out.u64(detail::fnv1a(structure));
  out.u64(payload.bytes.size());
  QUACK_ASSERT(out.bytes.size() == detail::kChecksumOffset);
  const std::uint64_t sum =
      detail::fnv1a(payload.bytes, detail::fnv1a(out.bytes));  // header, then payload
  out.u64(sum);
  out.bytes.insert(out.bytes.end(), payload.bytes.begin(), payload.bytes.end());
  return std::move(out.bytes);
}

namespace {

struct Parsed {
  SnapshotKind kind = SnapshotKind::full;
  std::uint64_t structureFingerprint = 0;
  std::span<const std::uint8_t> structure;  // empty for a dynamic snapshot
  std::span<const std::uint8_t> motion;
};

// The header's checks, in the order that names the most useful problem first.
Result<Parsed> parseHeader(std::span<const std::uint8_t> bytes) {
  using detail::kHeaderSize;
  if (bytes.size() < 8 || std::memcmp(bytes.data(), detail::kMagic, 8) != 0)
    return fail("not a Quack snapshot (it does not start with \"QUACKSNP\")");
  if (bytes.size() < kHeaderSize)
    return fail("snapshot is truncated: " + std::to_string(bytes.size()) +
                " bytes, the header alone is 48");
  detail::Reader h(bytes.subspan(8, kHeaderSize - 8), "header");
  const std::uint32_t version = h.u32("version");
  if (version != kSnapshotFormatVersion)
    return fail("snapshot format version " + std::to_string(version) + " is not this build's (" +
                std::to_string(kSnapshotFormatVersion) + ")");
  const std::uint8_t kind = h.u8("kind");
  if (kind > static_cast<std::uint8_t>(SnapshotKind::dynamic))
    return fail("snapshot kind " + std::to_string(kind) + " is neither full (0) nor dynamic (1)");
  if (h.u8("reserved") != 0 || h.u8("reserved") != 0 || h.u8("reserved") != 0)
    return fail("snapshot header's reserved bytes are not zero");
  const std::uint64_t build = h.u64("build fingerprint");
  if (build != detail::buildFingerprint())
    return fail(
        "snapshot was made by a build with other simulation constants (build "
        "fingerprint " +
        std::to_string(build) + ", this build's " + std::to_string(detail::buildFingerprint()) +
        ")");
  Parsed p;
  p.kind = static_cast<SnapshotKind>(kind);
  p.structureFingerprint = h.u64("structure fingerprint");
  const std::uint64_t length = h.u64("payload length");
  const std::uint64_t sum = h.u64("checksum");
  const std::size_t present = bytes.size() - kHeaderSize;
  if (length > present)
    return fail("snapshot is truncated: the payload should be " + std::to_string(length) +
                " bytes, " + std::to_string(present) + " are present");
  if (length < present)
    return fail("snapshot has " + std::to_string(present - length) + " bytes after its payload (" +
                std::to_string(length) + " bytes)");
  const std::span<const std::uint8_t> payload = bytes.subspan(kHeaderSize);
  if (detail::fnv1a(payload, detail::fnv1a(bytes.first(detail::kChecksumOffset))) != sum)
    return fail("snapshot is corrupted: its checksum does not match its contents");
  if (p.kind == SnapshotKind::dynamic) {
    p.motion = payload;
    return p;
  }
  detail::Reader r(payload, "payload");
  const std::uint64_t structureLength = r.u64("structure length");
  if (!r.ok() || structureLength > r.left())
    return fail("snapshot's structure length " + std::to_string(structureLength) +
                " runs past its payload");
  p.structure = payload.subspan(8, static_cast<std::size_t>(structureLength));
  p.motion = payload.subspan(8 + static_cast<std::size_t>(structureLength));
  if (detail::fnv1a(p.structure) != p.structureFingerprint)
    return fail("snapshot's structure fingerprint does not match its structure section");
  return p;
}

}  // namespace

Status World::restore(std::span<const std::uint8_t> bytes) {
  // A world that refuses changes after a failed step takes a snapshot: that is the way out.
  if (!s_)
    return fail(
        "restore: this World was moved from and holds nothing (use the World it was "
        "moved to)");
  if (s_->inStep) return fail("restore: called during a step or from an event callback");
  Result<Parsed> parsed = parseHeader(bytes);
  if (!parsed) return fail("restore: " + parsed.error().message);
  const Parsed& p = parsed.value();
  std::vector<std::uint8_t> ours;
  std::span<const std::uint8_t> structure = p.structure;
  if (p.kind == SnapshotKind::dynamic) {
    ours = detail::structureBytes(*s_);
    if (detail::fnv1a(ours) != p.structureFingerprint)
      return fail(
          "restore: this dynamic snapshot was taken of a world with another static structure "
          "(settings, bodies, shapes, static poses or handles differ from this world's): it "
          "restores only into the world it was taken of, or one built the same way");
    structure = ours;
  }
  Result<std::unique_ptr<detail::WorldState>> state =
      detail::SnapshotCodec::read(structure, p.motion, id());
  if (!state) return fail("restore: snapshot " + state.error().message);
  World restored(std::move(state).value());
  if (Status st = restored.validate(); !st)
    return fail("restore: the snapshot's contents are inconsistent: " + st.message());
  detail::SnapshotCodec::keepCallbacks(restored.s_->events, s_->events);
  // The threads are this world's, not the snapshot's (they do not change the bits).
  WorldDef& def = restored.s_->def;
  def.workerCount = s_->def.workerCount;
  def.enqueueTask = s_->def.enqueueTask;
  def.finishTask = s_->def.finishTask;
  def.userTaskContext = s_->def.userTaskContext;
  std::swap(restored.s_->tasks, s_->tasks);
  s_ = std::move(restored.s_);
  return {};
}

Result<World> World::fromSnapshot(std::span<const std::uint8_t> bytes) {
  Result<Parsed> parsed = parseHeader(bytes);
  if (!parsed) return fail("fromSnapshot: " + parsed.error().message);
  if (parsed.value().kind != SnapshotKind::full)
    return fail(
        "fromSnapshot: a dynamic snapshot holds only what moves; restore it into the world "
        "it was taken from (World::restore), or take a full snapshot");
  Result<std::unique_ptr<detail::WorldState>> state = detail::SnapshotCodec::read(
      parsed.value().structure, parsed.value().motion, detail::nextWorldId());
  if (!state) return fail("fromSnapshot: snapshot " + state.error().message);
  World world(std::move(state).value());
  if (Status st = world.validate(); !st)
    return fail("fromSnapshot: the snapshot's contents are inconsistent: " + st.message());
  return world;
}

}  // namespace quack
