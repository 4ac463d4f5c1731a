// World: the facade over the world's parts (world_state.hpp). Each public function checks
// its arguments and hands the work to the part that owns it.

#include "quack/world/world.hpp"

#include <algorithm>
#include <atomic>
#include <new>
#include <string>

#include "quack/collision/toi.hpp"
#include "quack/geometry/bounds.hpp"
#include "step_context.hpp"
#include "world_state.hpp"

namespace quack::detail {
namespace {
std::atomic<int> testWorkerCount{0};
}  // namespace
void setTestWorkerCount(int workers) noexcept {
  testWorkerCount.store(workers < 1 ? 0 : (workers > kMaxWorkers ? kMaxWorkers : workers),
                        std::memory_order_relaxed);
}
int effectiveWorkerCount(int workerCount, bool gameScheduler) noexcept {
  if (workerCount == 1 && !gameScheduler) {
    const int forTests = testWorkerCount.load(std::memory_order_relaxed);
    if (forTests > 1) return forTests;
  }
  return workerCount;
}
int effectiveWorkerCount(const WorldDef& def) noexcept {
  return effectiveWorkerCount(def.workerCount, def.enqueueTask != nullptr);
}
}  // namespace quack::detail

namespace quack {

using detail::Body;
using detail::Shape;

namespace {

constexpr std::uint32_t kNull = 0xffffffffu;

std::string describeId(std::uint32_t index, std::uint32_t generation) {
  return "{index " + std::to_string(index) + ", generation " + std::to_string(generation) + "}";
}

Status checkFiniteNonNegative(float x, const char* name) {
  if (!isFinite(x) || x < 0.0f)
    return fail(std::string(name) + " must be finite and >= 0, got " + std::to_string(x));
  return {};
}

std::string describe(Vec2 v) {
  return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ")";
}

// Hands what the contact set changed to the islands, its one consumer.
void applyContactChanges(detail::WorldState& w) {
  w.islands.apply(w.store, w.contacts.changes());
  w.contacts.clearChanges();
}

}  // namespace

namespace detail {

// World ids: unique in the process, never 0 (the null handle's), so a handle from one world
// is refused by every other.
std::uint32_t nextWorldId() {
  static std::atomic<std::uint32_t> counter{0};
  std::uint32_t id = ++counter;
  if (id == 0) id = ++counter;
  return id;
}

Status checkWorldDef(const WorldDef& def) {
  if (!isFinite(def.gravity)) return fail("WorldDef.gravity is not finite");
  if (length(def.gravity) > kMaxGravity)
    return fail("WorldDef.gravity " + describe(def.gravity) +
                " is stronger than kMaxGravity (1e4 m/s^2)");
  if (!isFinite(def.timeStep) || def.timeStep <= 0.0f || def.timeStep > kMaxTimeStep)
    return fail("WorldDef.timeStep must be finite, > 0 and at most kMaxTimeStep (1 s), got " +
                std::to_string(def.timeStep));
  if (def.substeps < 1 || def.substeps > 64)
    return fail("WorldDef.substeps must be in 1..64, got " + std::to_string(def.substeps));
  for (auto [value, name] :
       {std::pair{def.contactHertz, "WorldDef.contactHertz"},
        std::pair{def.contactDampingRatio, "WorldDef.contactDampingRatio"},
        std::pair{def.jointHertz, "WorldDef.jointHertz"},
        std::pair{def.jointDampingRatio, "WorldDef.jointDampingRatio"},
        std::pair{def.contactPushMaxSpeed, "WorldDef.contactPushMaxSpeed"},
        std::pair{def.restitutionThreshold, "WorldDef.restitutionThreshold"},
        std::pair{def.hitEventThreshold, "WorldDef.hitEventThreshold"},
        std::pair{def.speculativeDistance, "WorldDef.speculativeDistance"},
        std::pair{def.contactRecycleDistance, "WorldDef.contactRecycleDistance"}}) {
    if (Status s = checkFiniteNonNegative(value, name); !s) return fail(s.message());
  }
  if (!isFinite(def.maxRotationPerSubstep) || def.maxRotationPerSubstep <= 0.0f) {
    return fail("WorldDef.maxRotationPerSubstep must be finite and > 0");
  }
  if (def.workerCount < 1 || def.workerCount > kMaxWorkers)
    return fail("WorldDef.workerCount must be in 1..kMaxWorkers (64), got " +
                std::to_string(def.workerCount));
  if ((def.enqueueTask == nullptr) != (def.finishTask == nullptr)) {
    return fail(std::string("WorldDef.enqueueTask and WorldDef.finishTask come together; only ") +
                (def.enqueueTask != nullptr ? "enqueueTask" : "finishTask") + " was given");
  }
  return {};
}

}  // namespace detail

World::World(std::unique_ptr<detail::WorldState> state) : s_(std::move(state)) {}
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;
World::~World() = default;

detail::WorldState& World::state() const noexcept {
  if (s_) return *s_;
  // What a moved-from World reads: an empty world that no call changes (checkUsable refuses
  // every change first). World id 0 matches no handle, so every handle reads as invalid.
  static detail::WorldState empty(WorldDef{}, BroadPhase::create({}).value(), 0);
  return empty;
}

Status World::checkUsable(const char* function) const {
  if (!s_)
    return fail(std::string(function) +
                ": this World was moved from and holds nothing (use the World it was moved to)");
  if (!s_->failure.empty())
    return fail(std::string(function) + ": " + s_->failure +
                "; restore a snapshot into this world (World::restore) to go on");
  return {};
}

BroadPhaseConfig detail::worldBroadPhaseConfig(const WorldDef& def) noexcept {
  BroadPhaseConfig config;
  config.kind = def.broadPhase;
  // The world's fat boxes are Box2D v3's (shape.c at 617d32a, read for understanding): the
  // speculative distance plus an eighth of the shape's extent, at most 5 cm, a side
  // (shapeFatMargin, given to each proxy), not stretched along the motion. The broad
  // phase's default (10 cm, stretched by a step's motion) made churning piles keep two to
  // three times the contacts, each updated every step: a stretched box trails a fast body
  // by its whole step. Re-inserting the proxies that leave the tighter boxes is the price,
  // and it is the smaller one since many moves enlarge the tree in place (docs/world.md,
  // "Fat boxes"). This margin, the largest a shape gets, is only the default for proxies
  // made without one.
  config.margin = kWorldFatMargin + def.speculativeDistance;
  config.displacementScale = 0.0f;
  return config;
}

float detail::shapeFatMargin(const ShapeGeometry& geometry, BodyType type,
                             const WorldDef& def) noexcept {
  // A static shape never moves: its margin only widens the pairs it finds, and pairs within
  // the speculative distance are found through the other shape's margin alone.
  if (type == BodyType::staticBody) return 2.0f * def.speculativeDistance;
  const ShapeProxy proxy = makeProxy(geometry);
  const float extent = computeMaxExtent(proxy, proxy.center());
  return def.speculativeDistance + minf(kWorldFatMargin, kWorldFatMarginFraction * extent);
}

Result<World> World::create(const WorldDef& def) {
  if (Status s = detail::checkWorldDef(def); !s) return fail(s.message());
  const BroadPhaseConfig config = detail::worldBroadPhaseConfig(def);
  Result<BroadPhase> bp = BroadPhase::create(config);
  if (!bp) return fail("broad phase: " + bp.error().message);
  return World(
      std::make_unique<detail::WorldState>(def, std::move(bp).value(), detail::nextWorldId()));
}

const WorldDef& World::def() const noexcept {
  return state().def;
}
std::uint32_t World::id() const noexcept {
  return state().store.worldId();
}
std::size_t World::bodyCount() const noexcept {
  return state().store.bodyIds.liveCount();
}
std::size_t World::shapeCount() const noexcept {
  return state().store.shapeIds.liveCount();
}
std::size_t World::contactCount() const noexcept {
  return state().contacts.count();
}
std::size_t World::touchingContactCount() const noexcept {
  return state().contacts.touchingCount();
}
const StepEvents& World::events() const noexcept {
  return state().events.events;
}
std::uint64_t World::stepCount() const noexcept {
  return state().stepCount;
}
double World::time() const noexcept {
  return state().time;
}
const BroadPhase& World::broadPhase() const noexcept {
  return state().broadPhase;
}

// ---- handles ---------------------------------------------------------------------------

bool World::isValid(BodyId id) const noexcept {
  return state().store.isValid(id);
}

bool World::isValid(ShapeId id) const noexcept {
  return state().store.isValid(id);
}

namespace {

template <class Id>
Status describeBadHandle(Id id, const char* function, const char* what, std::uint32_t worldId,
                         std::uint32_t capacity) {
  const std::string head = std::string(function) + ": " + what + " ";
  if (id.index == kNull) return fail(head + "is the null handle");
  if (id.world != worldId)
    return fail(head + describeId(id.index, id.generation) + " belongs to another world (" +
                std::to_string(id.world) + ", this is " + std::to_string(worldId) + ")");
  if (id.index >= capacity)
    return fail(head + describeId(id.index, id.generation) + " does not exist");
  return fail(head + describeId(id.index, id.generation) + " is stale (destroyed)");
}

}  // namespace

Status World::checkBody(BodyId id, const char* function) const {
  if (isValid(id)) return {};
  return describeBadHandle(id, function, "body", id.world == 0 ? 0 : state().store.worldId(),
                           state().store.bodyIds.capacity());
}

Status World::checkShape(ShapeId id, const char* function) const {
  if (isValid(id)) return {};
  return describeBadHandle(id, function, "shape", id.world == 0 ? 0 : state().store.worldId(),
                           state().store.shapeIds.capacity());
}

Status World::checkJoint(JointId id, const char* function) const {
  if (isValid(id)) return {};
  return describeBadHandle(id, function, "joint", id.world == 0 ? 0 : state().store.worldId(),
                           state().joints.ids.capacity());
}

// ---- bodies ------------------------------------------------------------------------------

Result<BodyId> World::createBody(const BodyDef& def) {
  if (Status u = checkUsable("createBody"); !u) return fail(u.message());
  if (state().inStep && !state().inCallbacks) return fail("createBody: called during step");
  if (!isFinite(def.position)) return fail("createBody: BodyDef.position is not finite");
  if (!withinCoordinateLimit(def.position))
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
  if (!isFinite(def.sleepThreshold) || def.sleepThreshold < 0.0f)
    return fail("createBody: BodyDef.sleepThreshold must be finite and >= 0, got " +
                std::to_string(def.sleepThreshold));
  const std::uint32_t index = state().store.createBody(def);
  // A body that may not sleep, in a world that may not, starts awake whatever isAwake says.
  const bool awake = def.isAwake || !def.enableSleep || !state().def.enableSleep;
  state().islands.addBody(state().store, index, awake);
  return state().store.bodyId(index);
}

Status World::destroyBody(BodyId id) {
  if (Status u = checkUsable("destroyBody"); !u) return u;
  if (Status s = checkBody(id, "destroyBody"); !s) return s;
  if (state().inStep && !state().inCallbacks) return fail("destroyBody: called during step");
  if (state().inCallbacks) {
    Body& b = state().store.bodies[id.index];
    if (!b.pendingDestroy) {
      b.pendingDestroy = true;
      state().pendingBodyDestroy.push_back(id.index);
    }
    return {};
  }
  destroyBodyNow(*s_, id.index);
  return {};
}

void World::destroyBodyNow(detail::WorldState& w, std::uint32_t index) {
  // Its joints go first, each reported with the next step's events.
  std::vector<std::uint32_t> joints;
  w.joints.forEachOf(index, [&](std::uint32_t j) { joints.push_back(j); });
  for (std::uint32_t j : joints) {
    const detail::Joint& joint = w.joints.joints[j];
    w.joints.endsSinceStep.push_back(
        {detail::jointId(w, j),
         joint.bodyA == detail::kNoBody ? BodyId{} : w.store.bodyId(joint.bodyA),
         w.store.bodyId(joint.bodyB), JointEndReason::bodyDestroyed, joint.force, joint.torque,
         joint.def.userData});
    detail::destroyJointNow(w, j);
  }
  std::vector<std::uint32_t> shapes = w.store.bodies[index].shapes;
  for (std::uint32_t s : shapes)
    destroyShapeNow(w, s);
  w.islands.removeBody(w.store, index);
  applyContactChanges(w);
  w.store.releaseBody(index);
}

// ---- shapes -------------------------------------------------------------------------------

Result<ShapeId> World::createShape(BodyId bodyId, const ShapeDef& def,
                                   const ShapeGeometry& geometry) {
  if (Status u = checkUsable("createShape"); !u) return fail(u.message());
  if (Status s = checkBody(bodyId, "createShape"); !s) return fail(s.message());
  if (state().inStep && !state().inCallbacks) return fail("createShape: called during step");
  if (Status s = checkFiniteNonNegative(def.density, "createShape: ShapeDef.density"); !s)
    return fail(s.message());
  if (Status s = checkFiniteNonNegative(def.friction, "createShape: ShapeDef.friction"); !s)
    return fail(s.message());
  if (Status s = checkFiniteNonNegative(def.restitution, "createShape: ShapeDef.restitution"); !s)
    return fail(s.message());
  if (def.restitution > kMaxRestitution)
    return fail("createShape: ShapeDef.restitution " + std::to_string(def.restitution) +
                " is above kMaxRestitution (10)");
  detail::BodyStore& store = state().store;
  Result<std::shared_ptr<const ShapeGeometry>> stored =
      store.geometries.intern(geometry, validateShape);
  if (!stored) return fail("createShape: geometry: " + stored.error().message);
  const Body& body = store.bodies[bodyId.index];
  // The body's mass with the new shape, summed as BodyStore::updateMass would sum it (the
  // stored geometry last), so that the store takes it rather than summing again.
  detail::BodyMass m;
  if (body.type == BodyType::dynamicBody) {
    // The body's mass with the new shape must stay a usable float (kMaxBodyMass), and so
    // must its inverse: refuse here rather than let a mass of infinity into the solver.
    m = detail::sumMass([&](const auto& f) {
      for (std::uint32_t s : body.shapes)
        f(*store.shapes[s].geometry, store.shapes[s].def.density);
      f(*stored.value(), def.density);
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
  const Aabb box = computeAabb(geometry, body.xf);
  const std::uint32_t index = store.shapeIds.nextIndex();
  const ProxyKind kind =
      body.type == BodyType::staticBody ? ProxyKind::staticProxy : ProxyKind::dynamicProxy;
  Result<ProxyId> proxy = state().broadPhase.createProxy(
      box, index, def.filter, kind, detail::shapeFatMargin(geometry, body.type, state().def));
  if (!proxy) return fail("createShape: " + proxy.error().message);
  const std::uint32_t created =
      store.createShape(bodyId.index, def, std::move(stored).value(),
                        body.type == BodyType::dynamicBody ? &m : nullptr);
  QUACK_ASSERT(created == index);
  store.shapes[created].proxy = proxy.value();
  if (body.type == BodyType::staticBody) state().edges.markDirty();
  // A shape added to a body that had some changes its mass: it wakes. A body being built
  // (its first shape) keeps the state it was created in (BodyDef::isAwake).
  if (store.bodies[bodyId.index].shapes.size() > 1) state().islands.wake(store, bodyId.index);
  return store.shapeId(created);
}

Status World::destroyShape(ShapeId id) {
  if (Status u = checkUsable("destroyShape"); !u) return u;
  if (Status s = checkShape(id, "destroyShape"); !s) return s;
  if (state().inStep && !state().inCallbacks) return fail("destroyShape: called during step");
  if (state().inCallbacks) {
    Shape& shape = state().store.shapes[id.index];
    if (!shape.pendingDestroy) {
      shape.pendingDestroy = true;
      state().pendingShapeDestroy.push_back(id.index);
    }
    return {};
  }
  destroyShapeNow(*s_, id.index);
  return {};
}

void World::destroyShapeNow(detail::WorldState& w, std::uint32_t index) {
  detail::BodyStore& store = w.store;
  Shape& s = store.shapes[index];
  // What rested on it, and its own body, wake.
  w.islands.wake(store, s.body);
  w.islands.wakeTouching(store, w.contacts, w.joints, s.body);
  std::vector<std::uint32_t> contacts = s.contacts;
  for (std::uint32_t c : contacts)
    w.contacts.destroy(c, store, w.events, true, w.inStep);
  Status st = w.broadPhase.destroyProxy(s.proxy);
  QUACK_ASSERT(st.ok());
  (void)st;
  if (store.bodies[s.body].type == BodyType::staticBody) w.edges.markDirty();
  store.releaseShape(index);
  applyContactChanges(w);
}

// ---- stepping -----------------------------------------------------------------------------

StepStatus World::step() {
  return step(state().def.timeStep, state().def.substeps);
}

namespace {

// The step's phases, in order: bodies -> broad phase -> contact set -> solver -> continuous
// phase -> islands and sleep. Each takes the step's context and what it needs, and hands on
// what it produced. Callbacks run after, in World::step.
void runPhases(detail::WorldState& w, float dt, int substeps) {
  detail::StepContext step{w.def, w.store, w.broadPhase, w.joints, w.events, w.tasks, dt, substeps};
  // New contacts from the broad phase's pairs; sleeping bodies they find with static
  // geometry wake.
  w.contacts.findNew(step);
  applyContactChanges(w);
  const std::size_t bodyCount = w.store.bodyIds.liveCount();
  w.contacts.markAwake(w.store, w.islands.awakeBits(), w.islands.awakeCount(), bodyCount);
  if (w.edges.dirty()) {
    w.edges.update(w.store, w.def.removeGhostCollisions);
    // Static geometry changed: which contacts are ghosts may have too, so no manifold is
    // recycled across the change.
    w.contacts.forgetAllPoses();
  }
  // The narrow phase. Contacts that began touching join islands, and wake the sleeping
  // ones they reach (whose contacts, unchanged while they slept, the solver now takes too).
  w.contacts.update(step, w.edges, w.islands.awakeBits());
  applyContactChanges(w);
  w.contacts.markAwake(w.store, w.islands.awakeBits(), w.islands.awakeCount(), bodyCount);
  // Joints past their break thresholds break now, reported in this step's events.
  for (std::uint32_t j : w.solver.solve(step, w.contacts, w.joints, w.islands.awakeBits())) {
    const detail::Joint& joint = w.joints.joints[j];
    w.events.events.jointEnd.push_back(
        {detail::jointId(w, j),
         joint.bodyA == detail::kNoBody ? BodyId{} : w.store.bodyId(joint.bodyA),
         w.store.bodyId(joint.bodyB), JointEndReason::broken, joint.force, joint.torque,
         joint.def.userData});
    detail::destroyJointNow(w, j);
  }
  // A bullet may have hit a sleeping body: it moves now.
  for (std::uint32_t b : w.continuous.run(step, w.islands.awakeBits(), w.edges, w.contacts))
    w.islands.wake(w.store, b);
  w.islands.updateSleep(w.def, w.store, w.contacts, w.joints, dt, w.tasks);
  // The solver and the continuous phase may both have stopped a body at the edge.
  std::vector<BodyId>& held = w.events.events.outOfBounds;
  std::sort(held.begin(), held.end(), [](BodyId a, BodyId b) { return a.index < b.index; });
  held.erase(std::unique(held.begin(), held.end()), held.end());
}

}  // namespace

void World::finishCallbacks(detail::WorldState& w) {
  w.inCallbacks = false;
  w.inStep = false;
  for (std::uint32_t j : w.pendingJointDestroy) {
    if (w.joints.ids.isAlive(j) && w.joints.joints[j].pendingDestroy) detail::destroyJointNow(w, j);
  }
  w.pendingJointDestroy.clear();
  for (std::uint32_t s : w.pendingShapeDestroy) {
    if (w.store.shapeAlive(s) && w.store.shapes[s].pendingDestroy) destroyShapeNow(w, s);
  }
  for (std::uint32_t b : w.pendingBodyDestroy) {
    if (w.store.bodyAlive(b) && w.store.bodies[b].pendingDestroy) destroyBodyNow(w, b);
  }
  w.pendingShapeDestroy.clear();
  w.pendingBodyDestroy.clear();
}

StepStatus World::step(float dt, int substeps) {
  if (Status u = checkUsable("step"); !u) return fail(u.message());
  detail::WorldState& w = *s_;
  if (w.inStep) return fail("step: called during a step or from an event callback");
  if (!isFinite(dt) || dt <= 0.0f || dt > kMaxTimeStep)
    return fail("step: dt must be finite, > 0 and at most kMaxTimeStep (1 s), got " +
                std::to_string(dt));
  if (substeps < 1 || substeps > 64)
    return fail("step: substeps must be in 1..64, got " + std::to_string(substeps));
  w.inStep = true;
  w.events.beginStep();
  // Joints taken by bodies destroyed since the last step come first in this step's list.
  for (const JointEndEvent& e : w.joints.endsSinceStep)
    w.events.events.jointEnd.push_back(e);
  w.joints.endsSinceStep.clear();
  // The phases throw only std::bad_alloc of their own; a game's job system (enqueueTask)
  // may throw anything. Either way the step stopped part way.
  auto stopped = [&](const char* why) {
    w.inStep = false;
    w.failure = "step " + std::to_string(w.stepCount + 1) + " " + why +
                " part way through, so the world's state is not trusted";
  };
  try {
    runPhases(w, dt, substeps);
  } catch (const std::bad_alloc&) {
    stopped("ran out of memory");
    throw;
  } catch (...) {
    stopped("was stopped by an exception");
    throw;
  }
  ++w.stepCount;
  w.time += static_cast<double>(dt);

  // Callbacks, then the destruction they asked for, in request order. Both run on the state
  // `w`, not through this World: a callback may have moved the World (this one is then
  // empty). An exception from a callback ends the callbacks; the step is complete and the
  // requested destruction still happens before it goes on to the caller.
  w.inCallbacks = true;
  try {
    w.events.dispatch(*this, w.store);
  } catch (...) {
    finishCallbacks(w);
    throw;
  }
  finishCallbacks(w);
  return {};
}

// ---- callbacks ----------------------------------------------------------------------------

// On a moved-from World these register nothing (there is no world to call them from).
void World::onContactBegin(std::uint64_t a, std::uint64_t b, ContactCallback f) {
  if (!s_) return;
  state().events.add(detail::EventDispatcher::Kind::begin, a, b, std::move(f), {},
                     state().inCallbacks);
}
void World::onContactEnd(std::uint64_t a, std::uint64_t b, ContactCallback f) {
  if (!s_) return;
  state().events.add(detail::EventDispatcher::Kind::end, a, b, std::move(f), {},
                     state().inCallbacks);
}
void World::onHit(std::uint64_t a, std::uint64_t b, HitCallback f) {
  if (!s_) return;
  state().events.add(detail::EventDispatcher::Kind::hit, a, b, {}, std::move(f),
                     state().inCallbacks);
}
void World::onImpact(std::uint64_t a, std::uint64_t b, ImpactCallback f) {
  if (!s_) return;
  state().events.add(detail::EventDispatcher::Kind::impact, a, b, {}, {}, state().inCallbacks,
                     std::move(f));
}
void World::onSensorBegin(std::uint64_t a, std::uint64_t b, ContactCallback f) {
  if (!s_) return;
  state().events.add(detail::EventDispatcher::Kind::sensorBegin, a, b, std::move(f), {},
                     state().inCallbacks);
}
void World::onSensorEnd(std::uint64_t a, std::uint64_t b, ContactCallback f) {
  if (!s_) return;
  state().events.add(detail::EventDispatcher::Kind::sensorEnd, a, b, std::move(f), {},
                     state().inCallbacks);
}

// ---- body state ----------------------------------------------------------------------------
// A stale, foreign or null handle reads a neutral value (documented in world.hpp), never
// another body's memory, in every build.

namespace {
const ShapeGeometry kNoGeometry{};
const ShapeDef kNoShapeDef{};
}  // namespace

BodyType World::bodyType(BodyId id) const {
  return isValid(id) ? state().store.bodies[id.index].type : BodyType::staticBody;
}
Transform World::transform(BodyId id) const {
  return isValid(id) ? state().store.bodies[id.index].xf : Transform{};
}
Vec2 World::position(BodyId id) const {
  return transform(id).p;
}
float World::angle(BodyId id) const {
  return transform(id).q.angle();
}
Vec2 World::linearVelocity(BodyId id) const {
  return isValid(id) ? state().store.bodies[id.index].v : Vec2{};
}
float World::angularVelocity(BodyId id) const {
  return isValid(id) ? state().store.bodies[id.index].w : 0.0f;
}
float World::mass(BodyId id) const {
  return isValid(id) ? state().store.bodies[id.index].mass : 0.0f;
}
float World::rotationalInertia(BodyId id) const {
  return isValid(id) ? state().store.bodies[id.index].inertia : 0.0f;
}
Vec2 World::worldCenterOfMass(BodyId id) const {
  return isValid(id) ? state().store.bodies[id.index].center : Vec2{};
}
std::uint64_t World::userData(BodyId id) const {
  return isValid(id) ? state().store.bodies[id.index].userData : 0;
}
BodyId World::body(ShapeId id) const {
  return isValid(id) ? state().store.bodyId(state().store.shapes[id.index].body) : BodyId{};
}
const ShapeGeometry& World::geometry(ShapeId id) const {
  return isValid(id) ? *state().store.shapes[id.index].geometry : kNoGeometry;
}
const ShapeDef& World::shapeDef(ShapeId id) const {
  return isValid(id) ? state().store.shapes[id.index].def : kNoShapeDef;
}

// ---- iteration ------------------------------------------------------------------------------

std::uint32_t World::nextBody(std::uint32_t from) const noexcept {
  const auto n = static_cast<std::uint32_t>(state().store.bodies.size());
  while (from < n && !state().store.bodyAlive(from))
    ++from;
  return from;
}
std::uint32_t World::nextTouchingContact(std::uint32_t from) const noexcept {
  const std::vector<detail::Contact>& contacts = state().contacts.contacts;
  const auto n = static_cast<std::uint32_t>(contacts.size());
  while (from < n && !(contacts[from].alive && contacts[from].touching && !contacts[from].sensor))
    ++from;
  return from;
}
BodyId World::bodyAt(std::uint32_t index) const noexcept {
  return state().store.bodyId(index);
}
ShapeId World::shapeAt(std::uint32_t index) const noexcept {
  return state().store.shapeId(index);
}
World::ContactView World::contactAt(std::uint32_t index) const noexcept {
  const detail::Contact& c = state().contacts.contacts[index];
  return {state().store.shapeId(c.shapeA), state().store.shapeId(c.shapeB), c.manifold};
}
World::BodyRange World::bodies() const noexcept {
  return {this, nextBody(0), static_cast<std::uint32_t>(state().store.bodies.size())};
}
World::ShapeRange World::shapes(BodyId id) const noexcept {
  if (!isValid(id)) return {this, {}};
  return {this, state().store.bodies[id.index].shapes};
}
World::ContactRange World::touchingContacts() const noexcept {
  return {this, nextTouchingContact(0),
          static_cast<std::uint32_t>(state().contacts.contacts.size())};
}

Status World::setTransform(BodyId id, Vec2 position, float angle) {
  if (Status u = checkUsable("setTransform"); !u) return u;
  if (Status s = checkBody(id, "setTransform"); !s) return s;
  if (state().inStep && !state().inCallbacks) return fail("setTransform: called during step");
  if (!isFinite(position) || !isFinite(angle))
    return fail("setTransform: position and angle must be finite");
  const Transform xf = makeTransform(position, angle);
  Body& b = state().store.bodies[id.index];
  // moveBody checks every shape against the edge of the world and moves nothing if one
  // would leave it.
  if (!withinCoordinateLimit(position) ||
      !state().store.moveBody(state().broadPhase, id.index, xf, transformPoint(xf, b.localCenter),
                              Vec2{}))
    return fail("setTransform: position " + describe(position) +
                " would put the body beyond kMaxCoordinate (1e9 m) from the origin");
  if (b.type == BodyType::staticBody) state().edges.markDirty();
  state().contacts.forgetPoses(state().store, id.index);
  state().islands.wake(state().store, id.index);
  // Every body near it wakes, touching or not yet: it may have been moved into them.
  state().islands.wakeNear(state().store, state().broadPhase, state().contacts, id.index);
  return {};
}

Status World::setLinearVelocity(BodyId id, Vec2 v) {
  if (Status u = checkUsable("setLinearVelocity"); !u) return u;
  if (Status s = checkBody(id, "setLinearVelocity"); !s) return s;
  if (!isFinite(v) || length(v) > kMaxLinearSpeed)
    return fail("setLinearVelocity: velocity " + describe(v) +
                " must be finite and no faster than kMaxLinearSpeed (1e5 m/s)");
  Body& b = state().store.bodies[id.index];
  if (b.type == BodyType::staticBody) return {};
  b.v = v;
  wakeForChange(id.index);
  return {};
}

Status World::setAngularVelocity(BodyId id, float w) {
  if (Status u = checkUsable("setAngularVelocity"); !u) return u;
  if (Status s = checkBody(id, "setAngularVelocity"); !s) return s;
  if (!isFinite(w) || absf(w) > kMaxAngularSpeed)
    return fail("setAngularVelocity: velocity " + std::to_string(w) +
                " must be finite and no faster than kMaxAngularSpeed (1e5 rad/s)");
  // (A dynamic body without rotational inertia keeps it only until the next step: the
  // solver does not turn such a body.)
  Body& b = state().store.bodies[id.index];
  if (b.type == BodyType::staticBody) return {};
  b.w = w;
  wakeForChange(id.index);
  return {};
}

Status World::applyLinearImpulse(BodyId id, Vec2 impulse, Vec2 point) {
  if (Status u = checkUsable("applyLinearImpulse"); !u) return u;
  if (Status s = checkBody(id, "applyLinearImpulse"); !s) return s;
  if (!isFinite(impulse) || !isFinite(point))
    return fail("applyLinearImpulse: impulse and point must be finite");
  if (!withinCoordinateLimit(point))
    return fail("applyLinearImpulse: point " + describe(point) +
                " lies beyond kMaxCoordinate (1e9 m) from the origin");
  Body& b = state().store.bodies[id.index];
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
  wakeForChange(id.index);
  return {};
}

Status World::applyAngularImpulse(BodyId id, float impulse) {
  if (Status u = checkUsable("applyAngularImpulse"); !u) return u;
  if (Status s = checkBody(id, "applyAngularImpulse"); !s) return s;
  if (!isFinite(impulse)) return fail("applyAngularImpulse: impulse must be finite");
  Body& b = state().store.bodies[id.index];
  if (b.type != BodyType::dynamicBody) return {};
  const float w = b.w + b.invInertia * impulse;
  if (!isFinite(w) || absf(w) > kMaxAngularSpeed)
    return fail("applyAngularImpulse: impulse " + std::to_string(impulse) +
                " would make the angular velocity " + std::to_string(w) +
                ", faster than kMaxAngularSpeed (1e5 rad/s)");
  b.w = w;
  wakeForChange(id.index);
  return {};
}

Status World::applyForce(BodyId id, Vec2 force, Vec2 point) {
  if (Status u = checkUsable("applyForce"); !u) return u;
  if (Status s = checkBody(id, "applyForce"); !s) return s;
  if (!isFinite(force) || !isFinite(point))
    return fail("applyForce: force and point must be finite");
  if (!withinCoordinateLimit(point))
    return fail("applyForce: point " + describe(point) +
                " lies beyond kMaxCoordinate (1e9 m) from the origin");
  Body& b = state().store.bodies[id.index];
  if (b.type != BodyType::dynamicBody) return {};
  const Vec2 f = b.force + force;
  const float t = b.torque + cross(point - b.center, force);
  if (!isFinite(f) || !isFinite(t))
    return fail("applyForce: force " + describe(force) + " makes the body's total force infinite");
  b.force = f;
  b.torque = t;
  wakeForChange(id.index);
  return {};
}

Status World::applyTorque(BodyId id, float torque) {
  if (Status u = checkUsable("applyTorque"); !u) return u;
  if (Status s = checkBody(id, "applyTorque"); !s) return s;
  if (!isFinite(torque)) return fail("applyTorque: torque must be finite");
  Body& b = state().store.bodies[id.index];
  if (b.type != BodyType::dynamicBody) return {};
  if (!isFinite(b.torque + torque))
    return fail("applyTorque: torque " + std::to_string(torque) +
                " makes the body's total torque infinite");
  b.torque += torque;
  wakeForChange(id.index);
  return {};
}

Status World::setBodyType(BodyId id, BodyType type) {
  if (Status u = checkUsable("setBodyType"); !u) return u;
  if (Status s = checkBody(id, "setBodyType"); !s) return s;
  if (state().inStep && !state().inCallbacks) return fail("setBodyType: called during step");
  if (type != BodyType::staticBody && type != BodyType::kinematicBody &&
      type != BodyType::dynamicBody)
    return fail("setBodyType: type is not a body type");
  detail::BodyStore& store = state().store;
  Body& b = store.bodies[id.index];
  if (b.type == type) return {};
  detail::BodyMass m;  // summed once: the check below, then updateMass
  if (type == BodyType::dynamicBody) {
    // Its shapes' mass must be usable, as createShape demands.
    m = detail::sumMass([&](const auto& f) {
      for (std::uint32_t s : b.shapes)
        f(*store.shapes[s].geometry, store.shapes[s].def.density);
    });
    if (!isFinite(m.mass) || m.mass > kMaxBodyMass || !isFinite(m.inertia))
      return fail("setBodyType: the body's shapes weigh " + std::to_string(m.mass) +
                  " kg, beyond kMaxBodyMass (1e20 kg)");
  }
  if (b.type == BodyType::staticBody || type == BodyType::staticBody) state().edges.markDirty();
  // It and what it touches wake; it leaves its island and joins a new one under its new
  // type.
  state().islands.wake(store, id.index);
  state().islands.wakeNear(store, state().broadPhase, state().contacts, id.index);
  // Contacts end now and are found again under the new rules; proxies are made again with
  // the new kind (a static proxy does not look for pairs with other static ones).
  for (std::uint32_t s : b.shapes) {
    std::vector<std::uint32_t> contacts = store.shapes[s].contacts;
    for (std::uint32_t c : contacts)
      state().contacts.destroy(c, store, state().events, true, state().inStep);
  }
  b.type = type;
  if (type == BodyType::staticBody) {
    b.v = {};
    b.w = 0.0f;
  }
  b.force = {};
  b.torque = 0.0f;
  const ProxyKind kind =
      type == BodyType::staticBody ? ProxyKind::staticProxy : ProxyKind::dynamicProxy;
  for (std::uint32_t s : b.shapes) {
    Shape& shape = store.shapes[s];
    Status st = state().broadPhase.destroyProxy(shape.proxy);
    QUACK_ASSERT(st.ok());
    (void)st;
    Result<ProxyId> proxy =
        state().broadPhase.createProxy(computeAabb(*shape.geometry, b.xf), s, shape.def.filter,
                                       kind, detail::shapeFatMargin(*shape.geometry, type, def()));
    // The box was accepted a moment ago under the old kind.
    QUACK_ASSERT(proxy.ok());
    shape.proxy = proxy.valueOr(ProxyId{});
  }
  store.updateMass(id.index, type == BodyType::dynamicBody ? &m : nullptr);
  state().islands.removeBody(store, id.index);
  applyContactChanges(*s_);
  state().islands.addBody(store, id.index, true);
  // Its joints join it to its neighbours' islands again under the new type.
  state().joints.forEachOf(id.index, [&](std::uint32_t j) {
    const detail::Joint& joint = state().joints.joints[j];
    state().islands.link(store, joint.bodyA, joint.bodyB);
  });
  return {};
}

Status World::setAwake(BodyId id, bool awake) {
  if (Status u = checkUsable("setAwake"); !u) return u;
  if (Status s = checkBody(id, "setAwake"); !s) return s;
  if (state().inStep && !state().inCallbacks) return fail("setAwake: called during step");
  detail::Body& b = state().store.bodies[id.index];
  if (b.type == BodyType::staticBody) return {};
  if (awake) {
    wakeForChange(id.index);
  } else if (state().def.enableSleep) {
    state().islands.sleepNow(state().store, state().contacts, state().joints, id.index);
  }
  return {};
}

void World::wakeForChange(std::uint32_t index) {
  state().islands.wake(state().store, index);
  // A kinematic body carries what rests on it.
  if (state().store.bodies[index].type == BodyType::kinematicBody)
    state().islands.wakeTouching(state().store, state().contacts, state().joints, index);
}

bool World::isAwake(BodyId id) const {
  return isValid(id) && state().islands.isAwake(id.index);
}

std::size_t World::awakeBodyCount() const noexcept {
  return state().islands.awakeCount();
}

std::size_t World::islandCount() const noexcept {
  return state().islands.islandCount();
}

// ---- validation ----------------------------------------------------------------------------

Status World::validate() const {
  if (Status u = checkUsable("validate"); !u) return u;
  const detail::BodyStore& store = state().store;
  if (Status s = store.bodyIds.validate(); !s) return fail("bodies: " + s.message());
  if (Status s = store.shapeIds.validate(); !s) return fail("shapes: " + s.message());
  if (store.bodies.size() != store.bodyIds.capacity())
    return fail("body records and body slots differ in number");
  if (store.shapes.size() != store.shapeIds.capacity())
    return fail("shape records and shape slots differ in number");
  if (state().broadPhase.proxyCount() != store.shapeIds.liveCount())
    return fail("the broad phase has " + std::to_string(state().broadPhase.proxyCount()) +
                " proxies for " + std::to_string(store.shapeIds.liveCount()) + " shapes");
  for (std::uint32_t i = 0; i < store.bodies.size(); ++i) {
    if (!store.bodyAlive(i)) continue;
    const Body& b = store.bodies[i];
    const std::string name = "body " + std::to_string(i);
    if (!isFinite(b.xf.p) || !isFinite(b.xf.q.c) || !isFinite(b.xf.q.s) || !isFinite(b.v) ||
        !isFinite(b.w) || !isFinite(b.center))
      return fail(name + ": state is not finite");
    if (b.type == BodyType::staticBody && (b.v != Vec2{} || b.w != 0.0f))
      return fail(name + ": a static body moves");
    for (std::uint32_t s : b.shapes) {
      if (!store.shapeAlive(s) || store.shapes[s].body != i)
        return fail(name + ": lists shape " + std::to_string(s) + ", which is not its own");
    }
  }
  for (std::uint32_t i = 0; i < store.shapes.size(); ++i) {
    if (!store.shapeAlive(i)) continue;
    const Shape& s = store.shapes[i];
    const std::string name = "shape " + std::to_string(i);
    if (!store.bodyAlive(s.body)) return fail(name + ": its body is dead");
    const auto& list = store.bodies[s.body].shapes;
    if (std::count(list.begin(), list.end(), i) != 1)
      return fail(name + ": not listed once by its body");
    if (!state().broadPhase.isValid(s.proxy)) return fail(name + ": its proxy is not live");
    if (state().broadPhase.userData(s.proxy) != i)
      return fail(name + ": its proxy carries another shape's index");
    const Aabb box = computeAabb(*s.geometry, store.bodies[s.body].xf);
    if (!contains(state().broadPhase.fatBox(s.proxy), box))
      return fail(name + ": its broad-phase box does not hold it");
    for (std::uint32_t c : s.contacts) {
      if (c >= state().contacts.contacts.size() || !state().contacts.contacts[c].alive)
        return fail(name + ": lists a dead contact");
    }
  }
  if (Status s = state().contacts.validate(store); !s) return s;
  if (Status s = state().joints.validate(store); !s) return fail("joints: " + s.message());
  if (Status s = state().islands.validate(store, state().contacts, state().joints); !s)
    return fail("sleep: " + s.message());
  return {};
}

}  // namespace quack
