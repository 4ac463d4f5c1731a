// World3: the facade. It checks input at the public boundary and hands the work to the parts
// (body store, contact set, solver, islands), held together in WorldState3.

#include "quack/world/world3.hpp"

#include <cmath>
#include <string>

#include "quack/world/world.hpp"
#include "world_state3.hpp"

namespace quack {

namespace {

std::string str(float v) {
  return std::to_string(v);
}

bool finite(Vec3 v) {
  return isFinite(v);
}

Status checkDef(const WorldDef3& d) {
  if (!finite(d.gravity) || std::fabs(d.gravity.x) > kMaxGravity ||
      std::fabs(d.gravity.y) > kMaxGravity || std::fabs(d.gravity.z) > kMaxGravity) {
    return fail("WorldDef3::gravity: must be finite, each component within kMaxGravity");
  }
  if (!(d.timeStep > 0.0f && d.timeStep <= kMaxTimeStep)) {
    return fail("WorldDef3::timeStep: must be in (0, kMaxTimeStep], got " + str(d.timeStep));
  }
  if (d.substeps < 1 || d.substeps > 64) {
    return fail("WorldDef3::substeps: must be in 1..64, got " + std::to_string(d.substeps));
  }
  if (!(d.contactHertz > 0.0f && std::isfinite(d.contactHertz))) {
    return fail("WorldDef3::contactHertz: must be finite and > 0");
  }
  if (!(d.contactDampingRatio >= 0.0f && std::isfinite(d.contactDampingRatio))) {
    return fail("WorldDef3::contactDampingRatio: must be finite and >= 0");
  }
  if (!(d.contactPushMaxSpeed > 0.0f && std::isfinite(d.contactPushMaxSpeed))) {
    return fail("WorldDef3::contactPushMaxSpeed: must be finite and > 0");
  }
  if (!(d.restitutionThreshold >= 0.0f && std::isfinite(d.restitutionThreshold))) {
    return fail("WorldDef3::restitutionThreshold: must be finite and >= 0");
  }
  if (!(d.speculativeDistance >= 0.0f && d.speculativeDistance <= 1.0f)) {
    return fail("WorldDef3::speculativeDistance: must be in [0, 1] m");
  }
  if (!(d.contactRecycleDistance >= 0.0f && d.contactRecycleDistance <= 1.0f)) {
    return fail("WorldDef3::contactRecycleDistance: must be in [0, 1] m");
  }
  if (!(d.aabbMargin >= d.speculativeDistance && std::isfinite(d.aabbMargin))) {
    return fail("WorldDef3::aabbMargin: must be finite and >= speculativeDistance");
  }
  if (d.workerCount < 1 || d.workerCount > kMaxWorkers) {
    return fail("WorldDef3::workerCount: must be in 1..kMaxWorkers (64), got " +
                std::to_string(d.workerCount));
  }
  if ((d.enqueueTask == nullptr) != (d.finishTask == nullptr)) {
    return fail(std::string("WorldDef3::enqueueTask and WorldDef3::finishTask come together; "
                            "only ") +
                (d.enqueueTask != nullptr ? "enqueueTask" : "finishTask") + " was given");
  }
  return {};
}

Status checkBodyDef(const BodyDef3& d) {
  if (!finite(d.position) || std::fabs(d.position.x) > 0.5f * kMaxCoordinate ||
      std::fabs(d.position.y) > 0.5f * kMaxCoordinate ||
      std::fabs(d.position.z) > 0.5f * kMaxCoordinate) {
    return fail("BodyDef3::position: must be finite and within kMaxCoordinate / 2");
  }
  if (!isFinite(d.rotation) || lengthSquared(d.rotation) < kNormalizeEpsilon) {
    return fail("BodyDef3::rotation: must be a finite, non-zero quaternion");
  }
  if (!finite(d.linearVelocity) || length(d.linearVelocity) > kMaxLinearSpeed) {
    return fail("BodyDef3::linearVelocity: must be finite, at most kMaxLinearSpeed");
  }
  if (!finite(d.angularVelocity) || length(d.angularVelocity) > kMaxAngularSpeed) {
    return fail("BodyDef3::angularVelocity: must be finite, at most kMaxAngularSpeed");
  }
  if (!(d.linearDamping >= 0.0f && std::isfinite(d.linearDamping))) {
    return fail("BodyDef3::linearDamping: must be finite and >= 0");
  }
  if (!(d.angularDamping >= 0.0f && std::isfinite(d.angularDamping))) {
    return fail("BodyDef3::angularDamping: must be finite and >= 0");
  }
  if (!(std::fabs(d.gravityScale) <= kMaxGravityScale)) {
    return fail("BodyDef3::gravityScale: must be finite, within kMaxGravityScale");
  }
  if (!(d.sleepThreshold >= 0.0f && std::isfinite(d.sleepThreshold))) {
    return fail("BodyDef3::sleepThreshold: must be finite and >= 0");
  }
  return {};
}

Status checkShapeDef(const ShapeDef3& d) {
  if (!(d.density >= 0.0f && std::isfinite(d.density))) {
    return fail("ShapeDef3::density: must be finite and >= 0, got " + str(d.density));
  }
  if (!(d.friction >= 0.0f && std::isfinite(d.friction))) {
    return fail("ShapeDef3::friction: must be finite and >= 0, got " + str(d.friction));
  }
  if (!(d.restitution >= 0.0f && d.restitution <= kMaxRestitution)) {
    return fail("ShapeDef3::restitution: must be in [0, kMaxRestitution], got " +
                str(d.restitution));
  }
  if (!(d.rollingResistance >= 0.0f && std::isfinite(d.rollingResistance))) {
    return fail("ShapeDef3::rollingResistance: must be finite and >= 0");
  }
  return {};
}

}  // namespace

World3::World3(std::unique_ptr<detail::WorldState3> state) : state_(std::move(state)) {}
World3::World3(World3&&) noexcept = default;
World3& World3::operator=(World3&&) noexcept = default;
World3::~World3() = default;

Status detail::checkWorldDef3(const WorldDef3& def) {
  return checkDef(def);
}

Result<World3> World3::create(const WorldDef3& def) {
  if (Status s = checkDef(def); !s) return Error{s.message()};
  Result<BroadPhase3> bp = BroadPhase3::create({.margin = def.aabbMargin});
  if (!bp) return Error{"WorldDef3: " + bp.error().message};
  return World3(
      std::make_unique<detail::WorldState3>(def, std::move(bp).value(), detail::nextWorldId()));
}

const WorldDef3& World3::def() const noexcept {
  return state_->def;
}
std::uint32_t World3::id() const noexcept {
  return state_->id;
}

bool World3::isValid(BodyId3 body) const noexcept {
  return body.world == state_->id && state_->store.bodyIds.isValid(body.index, body.generation);
}
bool World3::isValid(ShapeId3 shape) const noexcept {
  return shape.world == state_->id && state_->store.shapeIds.isValid(shape.index, shape.generation);
}

Result<BodyId3> World3::createBody(const BodyDef3& def) {
  if (Status s = checkBodyDef(def); !s) return Error{s.message()};
  const std::uint32_t index = state_->store.addBody(def);
  return BodyId3{index, state_->store.bodyIds.generation(index), state_->id};
}

Status World3::destroyBody(BodyId3 body) {
  if (!isValid(body)) return fail("destroyBody: body: null, stale or another world's handle");
  detail::BodyStore3& store = state_->store;
  // Shapes go one by one (their contacts with them, waking what they touched).
  while (!store.bodies[body.index].shapes.empty()) {
    const std::uint32_t shape = store.bodies[body.index].shapes.back();
    Status s = destroyShape({shape, store.shapeIds.generation(shape), state_->id});
    QUACK_ASSERT(s.ok());
  }
  store.removeBody(body.index);
  return {};
}

Result<ShapeId3> World3::createShape(BodyId3 body, const ShapeDef3& def,
                                     const ShapeGeometry3& geometry) {
  if (!isValid(body)) return fail("createShape: body: null, stale or another world's handle");
  if (Status s = checkShapeDef(def); !s) return Error{s.message()};
  detail::BodyStore3& store = state_->store;
  Result<detail::StoredGeometry3> stored = store.geometries.intern(geometry, validateShape);
  if (!stored) return fail("createShape: geometry: " + stored.error().message);
  Result<std::uint32_t> shape = store.addShape(body.index, def, std::move(stored).value(), nullptr);
  if (!shape) return Error{shape.error()};
  detail::Body3& b = store.bodies[body.index];
  b.awake = true;
  b.sleepTime = 0.0f;
  return ShapeId3{shape.value(), store.shapeIds.generation(shape.value()), state_->id};
}

Result<ShapeId3> World3::createShape(BodyId3 body, const ShapeDef3& def, Mesh3 mesh) {
  if (!isValid(body)) return fail("createShape: body: null, stale or another world's handle");
  if (Status s = checkShapeDef(def); !s) return Error{s.message()};
  detail::BodyStore3& store = state_->store;
  if (store.bodies[body.index].type != BodyType::staticBody) {
    return fail("createShape: mesh: a triangle mesh may only be put on a static body");
  }
  auto shared = std::make_shared<Mesh3>(std::move(mesh));
  // A mesh shape's geometry is a placeholder nothing reads (the mesh is the shape).
  Result<std::uint32_t> shape =
      store.addShape(body.index, def, {std::make_shared<const ShapeGeometry3>(Sphere{}), nullptr},
                     std::move(shared));
  if (!shape) return Error{shape.error()};
  return ShapeId3{shape.value(), store.shapeIds.generation(shape.value()), state_->id};
}

Status World3::destroyShape(ShapeId3 shape) {
  if (!isValid(shape)) return fail("destroyShape: shape: null, stale or another world's handle");
  detail::BodyStore3& store = state_->store;
  // What it touched wakes, so that a pile does not float where the shape was.
  for (const detail::Contact3& c : state_->contacts.contacts()) {
    if (c.shapeA != shape.index && c.shapeB != shape.index) continue;
    for (std::uint32_t s : {c.shapeA, c.shapeB}) {
      detail::Body3& b = store.bodies[store.shapes[s].body];
      b.awake = true;
      b.sleepTime = 0.0f;
    }
  }
  StepEvents3 ends;
  state_->contacts.removeShape(store, shape.index, ends);
  for (const ContactEvent3& e : ends.end)
    state_->pendingEnds.push_back(e);
  store.removeShape(shape.index);
  return {};
}

std::size_t World3::bodyCount() const noexcept {
  return state_->store.bodyIds.liveCount();
}
std::size_t World3::shapeCount() const noexcept {
  return state_->store.shapeIds.liveCount();
}
std::size_t World3::contactCount() const noexcept {
  return state_->contacts.contacts().size();
}
std::size_t World3::touchingContactCount() const noexcept {
  return state_->contacts.touchingCount();
}
std::size_t World3::awakeBodyCount() const noexcept {
  std::size_t count = 0;
  const detail::BodyStore3& store = state_->store;
  for (std::uint32_t i = 0; i < store.bodies.size(); ++i) {
    if (store.bodyIds.isAlive(i) && store.bodies[i].type != BodyType::staticBody &&
        store.bodies[i].awake) {
      ++count;
    }
  }
  return count;
}

std::vector<ContactView3> World3::touchingContacts() const {
  std::vector<ContactView3> out;
  for (const detail::Contact3& c : state_->contacts.contacts()) {
    if (!c.touching) continue;
    ContactView3 view{state_->contacts.shapeId(state_->store, c.shapeA),
                      state_->contacts.shapeId(state_->store, c.shapeB),
                      {}};
    for (const detail::ContactManifold3& m : c.manifolds)
      view.manifolds.push_back(m.manifold);
    out.push_back(std::move(view));
  }
  return out;
}

BodyType World3::bodyType(BodyId3 body) const {
  return isValid(body) ? state_->store.bodies[body.index].type : BodyType::staticBody;
}
bool World3::isAwake(BodyId3 body) const {
  return isValid(body) && state_->store.bodies[body.index].awake;
}
Transform3 World3::transform(BodyId3 body) const {
  return isValid(body) ? state_->store.bodies[body.index].transform() : Transform3{};
}
Vec3 World3::position(BodyId3 body) const {
  return isValid(body) ? state_->store.bodies[body.index].origin : Vec3{};
}
Quat World3::rotation(BodyId3 body) const {
  return isValid(body) ? state_->store.bodies[body.index].rotation : Quat{};
}
Vec3 World3::linearVelocity(BodyId3 body) const {
  return isValid(body) ? state_->store.bodies[body.index].linearVelocity : Vec3{};
}
Vec3 World3::angularVelocity(BodyId3 body) const {
  return isValid(body) ? state_->store.bodies[body.index].angularVelocity : Vec3{};
}
float World3::mass(BodyId3 body) const {
  return isValid(body) ? state_->store.bodies[body.index].mass : 0.0f;
}
Mat3 World3::inertia(BodyId3 body) const {
  if (!isValid(body)) return {};
  const detail::Body3& b = state_->store.bodies[body.index];
  const Mat3 r = toMat3(b.rotation);
  return r * b.inertiaLocal * transpose(r);
}
Vec3 World3::worldCenterOfMass(BodyId3 body) const {
  return isValid(body) ? state_->store.bodies[body.index].center : Vec3{};
}
std::uint64_t World3::userData(BodyId3 body) const {
  return isValid(body) ? state_->store.bodies[body.index].userData : 0;
}
BodyId3 World3::body(ShapeId3 shape) const {
  if (!isValid(shape)) return {};
  const std::uint32_t b = state_->store.shapes[shape.index].body;
  return {b, state_->store.bodyIds.generation(b), state_->id};
}

Status World3::setTransform(BodyId3 body, Vec3 position, Quat rotation) {
  if (!isValid(body)) return fail("setTransform: body: null, stale or another world's handle");
  BodyDef3 probe;
  probe.position = position;
  probe.rotation = rotation;
  if (Status s = checkBodyDef(probe); !s) return fail("setTransform: " + s.message());
  detail::Body3& b = state_->store.bodies[body.index];
  b.origin = position;
  b.rotation = detail::unitRotation(rotation);
  b.center = transformPoint(b.transform(), b.localCenter);
  b.awake = true;
  b.sleepTime = 0.0f;
  ++b.poseVersion;  // its contacts get new manifolds
  // A teleport: no displacement to stretch the fat boxes by.
  state_->store.moveProxies(body.index, Vec3{});
  return {};
}

Status World3::setLinearVelocity(BodyId3 body, Vec3 velocity) {
  if (!isValid(body)) return fail("setLinearVelocity: body: null, stale or another world's handle");
  if (!finite(velocity) || length(velocity) > kMaxLinearSpeed) {
    return fail("setLinearVelocity: velocity: must be finite, at most kMaxLinearSpeed");
  }
  detail::Body3& b = state_->store.bodies[body.index];
  if (b.type == BodyType::staticBody) return fail("setLinearVelocity: body: a static body");
  b.linearVelocity = velocity;
  b.awake = true;
  b.sleepTime = 0.0f;
  return {};
}

Status World3::setAngularVelocity(BodyId3 body, Vec3 velocity) {
  if (!isValid(body)) {
    return fail("setAngularVelocity: body: null, stale or another world's handle");
  }
  if (!finite(velocity) || length(velocity) > kMaxAngularSpeed) {
    return fail("setAngularVelocity: velocity: must be finite, at most kMaxAngularSpeed");
  }
  detail::Body3& b = state_->store.bodies[body.index];
  if (b.type == BodyType::staticBody) return fail("setAngularVelocity: body: a static body");
  b.angularVelocity = velocity;
  b.awake = true;
  b.sleepTime = 0.0f;
  return {};
}

Status World3::applyLinearImpulse(BodyId3 body, Vec3 impulse, Vec3 worldPoint) {
  if (!isValid(body)) {
    return fail("applyLinearImpulse: body: null, stale or another world's handle");
  }
  if (!finite(impulse)) return fail("applyLinearImpulse: impulse: must be finite");
  if (!finite(worldPoint)) return fail("applyLinearImpulse: worldPoint: must be finite");
  detail::Body3& b = state_->store.bodies[body.index];
  if (b.type != BodyType::dynamicBody) return fail("applyLinearImpulse: body: not dynamic");
  const Vec3 v = b.linearVelocity + b.invMass * impulse;
  const Vec3 w = b.angularVelocity + b.invInertiaWorld() * cross(worldPoint - b.center, impulse);
  if (!finite(v) || !finite(w) || length(v) > kMaxLinearSpeed || length(w) > kMaxAngularSpeed) {
    return fail(
        "applyLinearImpulse: impulse: the body's speed would pass kMaxLinearSpeed or "
        "kMaxAngularSpeed");
  }
  b.linearVelocity = v;
  b.angularVelocity = w;
  b.awake = true;
  b.sleepTime = 0.0f;
  return {};
}

Status World3::setAwake(BodyId3 body, bool awake) {
  if (!isValid(body)) return fail("setAwake: body: null, stale or another world's handle");
  detail::Body3& b = state_->store.bodies[body.index];
  if (b.type == BodyType::staticBody) return {};
  b.awake = awake;
  b.sleepTime = 0.0f;
  if (!awake) b.linearVelocity = b.angularVelocity = Vec3{};
  return {};
}

Status World3::step() {
  return step(state_->def.timeStep, state_->def.substeps);
}

// The step, top to bottom: new contacts from the broad phase, manifolds for contacts with
// an awake body, islands woken by touch, the soft-step solver, continuous collision of fast
// bodies against static geometry, sleep.
Status World3::step(float dt, int substeps) {
  if (!(dt > 0.0f && dt <= kMaxTimeStep)) {
    return fail("step: dt: must be in (0, kMaxTimeStep], got " + str(dt));
  }
  if (substeps < 1 || substeps > 64) {
    return fail("step: substeps: must be in 1..64, got " + std::to_string(substeps));
  }
  detail::WorldState3& w = *state_;
  if (w.inCallbacks) return fail("step: called from a contact callback");
  w.events.begin.clear();
  w.events.end.assign(w.pendingEnds.begin(), w.pendingEnds.end());
  w.pendingEnds.clear();
  w.contacts.findNew(w.store, w.tasks);
  w.contacts.update(w.store, w.def, dt, w.events, w.tasks);
  w.islands.wakeTouched(w.store, w.contacts);
  if (w.def.enableContinuous) w.continuous.recordStarts(w.store);
  w.solver.step(w.store, w.contacts, w.def, dt, substeps, w.tasks);
  if (w.def.enableContinuous) w.continuous.solve(w.store, w.tasks);
  if (w.def.enableSleep) w.islands.sleepRested(w.store, w.contacts, dt);
  ++w.stepCount;
  dispatchCallbacks();
  return {};
}

// The step's events to the callbacks, begin events first, each in event order. Copies of
// both lists are walked, so a callback may destroy shapes (their end events go to the next
// step) or register callbacks (they run from the next step).
void World3::dispatchCallbacks() {
  detail::WorldState3& w = *state_;
  if (w.callbacks.empty()) return;
  const std::vector<detail::WorldState3::Callback> callbacks = w.callbacks;
  const StepEvents3 events = w.events;
  w.inCallbacks = true;
  for (int pass = 0; pass < 2; ++pass) {
    const bool begin = pass == 0;
    for (const ContactEvent3& e : begin ? events.begin : events.end) {
      for (const detail::WorldState3::Callback& c : callbacks) {
        if (c.begin != begin) continue;
        if ((e.categoryA & c.categoriesA) != 0 && (e.categoryB & c.categoriesB) != 0) {
          c.f(*this, e.shapeA, e.shapeB);
        } else if ((e.categoryB & c.categoriesA) != 0 && (e.categoryA & c.categoriesB) != 0) {
          c.f(*this, e.shapeB, e.shapeA);
        }
      }
    }
  }
  w.inCallbacks = false;
}

void World3::onContactBegin(std::uint64_t categoriesA, std::uint64_t categoriesB,
                            ContactCallback3 f) {
  if (f) state_->callbacks.push_back({true, categoriesA, categoriesB, std::move(f)});
}

void World3::onContactEnd(std::uint64_t categoriesA, std::uint64_t categoriesB,
                          ContactCallback3 f) {
  if (f) state_->callbacks.push_back({false, categoriesA, categoriesB, std::move(f)});
}

const StepEvents3& World3::events() const noexcept {
  return state_->events;
}
std::uint64_t World3::stepCount() const noexcept {
  return state_->stepCount;
}
World3::SolverStats World3::solverStats() const noexcept {
  const detail::Solver3::Stats& s = state_->solver.stats();
  return {s.colors, s.constraints, s.overflow};
}
int World3::workerCount() const noexcept {
  return state_->tasks.workers();
}

}  // namespace quack
