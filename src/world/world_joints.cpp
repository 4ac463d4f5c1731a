// World's joints: creating, destroying, reading and changing them (world.hpp; docs/world.md,
// "Joints"). The joint set holds them, the solver solves them, the islands join their
// bodies.

#include <cmath>
#include <string>

#include "quack/world/world.hpp"
#include "world_state.hpp"

namespace quack {

using detail::Joint;
using detail::kNoBody;

namespace detail {

JointId jointId(const WorldState& w, std::uint32_t joint) noexcept {
  return {joint, w.joints.ids.generation(joint), w.store.worldId()};
}

void destroyJointNow(WorldState& w, std::uint32_t index) {
  const Joint& joint = w.joints.joints[index];
  const std::uint32_t a = joint.bodyA, b = joint.bodyB;
  const bool blocked = !joint.def.collideConnected;
  w.joints.release(index);
  w.islands.unlink(w.store, a, b);
  // Their shapes were kept from colliding: let the broad phase offer their pairs again (the
  // shapes of the body with fewer look again).
  if (blocked && a != kNoBody && w.store.bodyAlive(a) && w.store.bodyAlive(b) &&
      !w.joints.blocksCollision(a, b)) {
    const std::uint32_t look =
        w.store.bodies[a].shapes.size() <= w.store.bodies[b].shapes.size() ? a : b;
    for (std::uint32_t s : w.store.bodies[look].shapes) {
      Status st = w.broadPhase.touchProxy(w.store.shapes[s].proxy);
      QUACK_ASSERT(st.ok());
      (void)st;
    }
  }
}

}  // namespace detail

namespace {

std::string number(float x) {
  return std::to_string(x);
}

// The checks of a JointDef, each naming the field; `a` and `b` are its bodies (a: none for a
// mouse joint).
Status checkJointDef(const JointDef& d) {
  const int type = static_cast<int>(d.type);
  if (type < 0 || type > static_cast<int>(JointType::mouse))
    return fail("JointDef.type is not a joint type");
  for (auto [v, name] :
       {std::pair{d.anchorA, "anchorA"}, std::pair{d.anchorB, "anchorB"}, std::pair{d.axis, "axis"},
        std::pair{d.linearOffset, "linearOffset"}, std::pair{d.target, "target"}}) {
    if (!isFinite(v) || !withinCoordinateLimit(v))
      return fail(std::string("JointDef.") + name + " must be finite and within kMaxCoordinate");
  }
  for (auto [v, name] : {std::pair{d.lower, "lower"}, std::pair{d.upper, "upper"},
                         std::pair{d.motorSpeed, "motorSpeed"}, std::pair{d.length, "length"},
                         std::pair{d.angularOffset, "angularOffset"}}) {
    if (!std::isfinite(v)) return fail(std::string("JointDef.") + name + " is not finite");
  }
  for (auto [v, name] :
       {std::pair{d.maxMotorTorque, "maxMotorTorque"}, std::pair{d.maxMotorForce, "maxMotorForce"},
        std::pair{d.hertz, "hertz"}, std::pair{d.dampingRatio, "dampingRatio"},
        std::pair{d.minLength, "minLength"}, std::pair{d.maxLength, "maxLength"},
        std::pair{d.linearHertz, "linearHertz"}, std::pair{d.angularHertz, "angularHertz"},
        std::pair{d.linearDampingRatio, "linearDampingRatio"},
        std::pair{d.angularDampingRatio, "angularDampingRatio"}, std::pair{d.maxForce, "maxForce"},
        std::pair{d.maxTorque, "maxTorque"}}) {
    if (!std::isfinite(v) || v < 0.0f)
      return fail(std::string("JointDef.") + name + " must be finite and >= 0, got " + number(v));
  }
  for (auto [v, name] :
       {std::pair{d.breakForce, "breakForce"}, std::pair{d.breakTorque, "breakTorque"}}) {
    if (std::isnan(v) || v < 0.0f)
      return fail(std::string("JointDef.") + name + " must be >= 0 (infinite: never breaks)");
  }
  if (!(d.correctionFactor >= 0.0f && d.correctionFactor <= 1.0f))
    return fail("JointDef.correctionFactor must be in [0, 1], got " + number(d.correctionFactor));
  const bool axial = d.type == JointType::prismatic || d.type == JointType::wheel;
  if (axial && length(d.axis) == 0.0f) return fail("JointDef.axis must not be zero");
  const bool limited = d.type == JointType::revolute || axial || d.type == JointType::distance;
  if (limited && d.enableLimit && d.type != JointType::distance && d.lower > d.upper)
    return fail("JointDef.lower (" + number(d.lower) + ") is above JointDef.upper (" +
                number(d.upper) + ")");
  if (d.type == JointType::revolute && d.enableLimit && (d.lower < -kPi || d.upper > kPi))
    return fail("JointDef.lower and upper of a revolute joint must be within [-pi, pi]");
  if (d.type == JointType::distance && d.minLength > d.maxLength)
    return fail("JointDef.minLength (" + number(d.minLength) + ") is above JointDef.maxLength (" +
                number(d.maxLength) + ")");
  if (d.type == JointType::mouse && d.hertz <= 0.0f)
    return fail("JointDef.hertz of a mouse joint must be > 0 (it is a spring)");
  // Both default to 0, shared with other types: a mouse or motor joint without them would
  // silently do nothing.
  if (d.type == JointType::mouse && d.maxForce <= 0.0f)
    return fail("JointDef.maxForce of a mouse joint must be > 0 (the most it may pull)");
  if (d.type == JointType::motor && d.maxForce <= 0.0f && d.maxTorque <= 0.0f)
    return fail("JointDef.maxForce or maxTorque of a motor joint must be > 0");
  return {};
}

}  // namespace

Result<JointId> World::createJoint(const JointDef& def) {
  if (Status u = checkUsable("createJoint"); !u) return fail(u.message());
  detail::WorldState& w = state();
  if (w.inStep && !w.inCallbacks) return fail("createJoint: called during step");
  if (Status s = checkJointDef(def); !s) return fail("createJoint: " + s.message());
  const bool mouse = def.type == JointType::mouse;
  if (mouse) {
    if (!(def.bodyA == BodyId{}))
      return fail("createJoint: JointDef.bodyA of a mouse joint must be null (it pulls body B)");
  } else if (Status s = checkBody(def.bodyA, "createJoint: JointDef.bodyA"); !s) {
    return fail(s.message());
  }
  if (Status s = checkBody(def.bodyB, "createJoint: JointDef.bodyB"); !s) return fail(s.message());
  if (def.bodyA == def.bodyB)
    return fail("createJoint: JointDef.bodyA and bodyB are the same body");
  detail::BodyStore& store = w.store;
  const std::uint32_t a = mouse ? kNoBody : def.bodyA.index;
  const std::uint32_t b = def.bodyB.index;
  const Transform xfA = mouse ? Transform{} : store.bodies[a].xf;
  const Transform xfB = store.bodies[b].xf;

  Joint j;
  j.def = def;
  j.bodyA = a;
  j.bodyB = b;
  j.localAnchorA = invTransformPoint(xfA, def.anchorA);
  j.localAnchorB =
      invTransformPoint(xfB, def.type == JointType::distance ? def.anchorB : def.anchorA);
  if (def.type == JointType::prismatic || def.type == JointType::wheel) {
    j.def.axis = normalize(def.axis);
    j.localAxisA = invRotate(xfA.q, j.def.axis);
  }
  j.referenceAngle = invMulRot(xfA.q, xfB.q).angle();
  if (def.type == JointType::distance) {
    j.length = def.length >= 0.0f ? def.length : length(def.anchorB - def.anchorA);
    if (j.length < kLinearSlop)
      return fail(
          "createJoint: the length of a distance joint (JointDef.length, or the anchors' "
          "distance) must be at least kLinearSlop (0.005 m), got " +
          number(j.length) + "; a revolute joint holds two points together");
    j.def.length = j.length;
  }
  const std::uint32_t index = w.joints.create(j);
  w.islands.link(store, a, b);
  // Contacts between the two bodies end now (end events with the next step) and are not
  // made again while the joint lives (ContactSet::findNew asks the joint set).
  if (!def.collideConnected && a != kNoBody) {
    const std::uint32_t look =
        store.bodies[a].shapes.size() <= store.bodies[b].shapes.size() ? a : b;
    const std::uint32_t other = look == a ? b : a;
    std::vector<std::uint32_t> doomed;
    for (std::uint32_t s : store.bodies[look].shapes) {
      for (std::uint32_t c : store.shapes[s].contacts) {
        const detail::Contact& contact = w.contacts.contacts[c];
        if (contact.bodyA == other || contact.bodyB == other) doomed.push_back(c);
      }
    }
    // Reported with the next step's events, also from a callback (this step's lists are
    // being handed out).
    for (std::uint32_t c : doomed)
      w.contacts.destroy(c, store, w.events, true, false);
    w.islands.apply(store, w.contacts.changes());
    w.contacts.clearChanges();
  }
  return detail::jointId(w, index);
}

Status World::destroyJoint(JointId id) {
  if (Status u = checkUsable("destroyJoint"); !u) return u;
  if (Status s = checkJoint(id, "destroyJoint"); !s) return s;
  detail::WorldState& w = state();
  if (w.inStep && !w.inCallbacks) return fail("destroyJoint: called during step");
  if (w.inCallbacks) {
    Joint& joint = w.joints.joints[id.index];
    if (!joint.pendingDestroy) {
      joint.pendingDestroy = true;
      w.pendingJointDestroy.push_back(id.index);
    }
    return {};
  }
  detail::destroyJointNow(w, id.index);
  return {};
}

bool World::isValid(JointId id) const noexcept {
  return id.world == state().store.worldId() && id.world != 0 &&
         state().joints.ids.isValid(id.index, id.generation);
}

std::size_t World::jointCount() const noexcept {
  return state().joints.count();
}

std::uint32_t World::nextJoint(std::uint32_t from) const noexcept {
  const auto n = static_cast<std::uint32_t>(state().joints.joints.size());
  while (from < n && !state().joints.joints[from].alive)
    ++from;
  return from;
}

JointId World::jointAt(std::uint32_t index) const noexcept {
  return detail::jointId(state(), index);
}

World::JointRange World::joints() const noexcept {
  return {this, nextJoint(0), static_cast<std::uint32_t>(state().joints.joints.size())};
}

namespace {
const JointDef kNoJointDef{};
}

const JointDef& World::jointDef(JointId id) const {
  return isValid(id) ? state().joints.joints[id.index].def : kNoJointDef;
}

std::pair<Vec2, Vec2> World::jointAnchors(JointId id) const {
  if (!isValid(id)) return {};
  const Joint& j = state().joints.joints[id.index];
  const Transform xfB = state().store.bodies[j.bodyB].xf;
  const Vec2 onB = transformPoint(xfB, j.localAnchorB);
  if (j.bodyA == kNoBody) return {j.def.target, onB};
  const Transform xfA = state().store.bodies[j.bodyA].xf;
  return {transformPoint(xfA, j.localAnchorA), onB};
}

Vec2 World::jointForce(JointId id) const {
  return isValid(id) ? state().joints.joints[id.index].force : Vec2{};
}

float World::jointTorque(JointId id) const {
  return isValid(id) ? state().joints.joints[id.index].torque : 0.0f;
}

float World::jointAngle(JointId id) const {
  if (!isValid(id)) return 0.0f;
  const Joint& j = state().joints.joints[id.index];
  if (j.def.type != JointType::revolute && j.def.type != JointType::weld) return 0.0f;
  const Rot qA = state().store.bodies[j.bodyA].xf.q, qB = state().store.bodies[j.bodyB].xf.q;
  float angle = invMulRot(qA, qB).angle() - j.referenceAngle;
  if (angle > kPi) angle -= 2.0f * kPi;
  if (angle < -kPi) angle += 2.0f * kPi;
  return angle;
}

float World::jointTranslation(JointId id) const {
  if (!isValid(id)) return 0.0f;
  const Joint& j = state().joints.joints[id.index];
  const auto [onA, onB] = jointAnchors(id);
  switch (j.def.type) {
    case JointType::prismatic:
    case JointType::wheel:
      return dot(rotate(state().store.bodies[j.bodyA].xf.q, j.localAxisA), onB - onA);
    case JointType::distance:
      return length(onB - onA);
    default:
      return 0.0f;
  }
}

namespace {
void wakeJoint(detail::WorldState& w, const Joint& j) {
  if (j.bodyA != kNoBody) w.islands.wake(w.store, j.bodyA);
  w.islands.wake(w.store, j.bodyB);
}
}  // namespace

Status World::setJointMotor(JointId id, bool enable, float speed, float maxTorqueOrForce) {
  if (Status u = checkUsable("setJointMotor"); !u) return u;
  if (Status s = checkJoint(id, "setJointMotor"); !s) return s;
  Joint& j = state().joints.joints[id.index];
  const JointType t = j.def.type;
  if (t != JointType::revolute && t != JointType::prismatic && t != JointType::wheel)
    return fail(std::string("setJointMotor: a ") + toString(t) + " joint has no motor");
  if (!std::isfinite(speed)) return fail("setJointMotor: speed is not finite");
  if (!std::isfinite(maxTorqueOrForce) || maxTorqueOrForce < 0.0f)
    return fail("setJointMotor: maxTorqueOrForce must be finite and >= 0");
  j.def.enableMotor = enable;
  j.def.motorSpeed = speed;
  (t == JointType::prismatic ? j.def.maxMotorForce : j.def.maxMotorTorque) = maxTorqueOrForce;
  if (!enable) j.motorImpulse = 0.0f;
  wakeJoint(state(), j);
  return {};
}

Status World::setJointLimits(JointId id, bool enable, float lower, float upper) {
  if (Status u = checkUsable("setJointLimits"); !u) return u;
  if (Status s = checkJoint(id, "setJointLimits"); !s) return s;
  Joint& j = state().joints.joints[id.index];
  const JointType t = j.def.type;
  if (t != JointType::revolute && t != JointType::prismatic && t != JointType::wheel &&
      t != JointType::distance)
    return fail(std::string("setJointLimits: a ") + toString(t) + " joint has no limits");
  if (!std::isfinite(lower) || !std::isfinite(upper) || lower > upper)
    return fail("setJointLimits: lower and upper must be finite with lower <= upper");
  if (t == JointType::revolute && (lower < -kPi || upper > kPi))
    return fail("setJointLimits: a revolute joint's limits must be within [-pi, pi]");
  if (t == JointType::distance && lower < 0.0f)
    return fail("setJointLimits: a distance joint's lower limit must be >= 0");
  j.def.enableLimit = enable;
  if (t == JointType::distance) {
    j.def.minLength = lower;
    j.def.maxLength = upper;
  } else {
    j.def.lower = lower;
    j.def.upper = upper;
  }
  j.lowerImpulse = j.upperImpulse = 0.0f;
  wakeJoint(state(), j);
  return {};
}

Status World::setMouseTarget(JointId id, Vec2 target) {
  if (Status u = checkUsable("setMouseTarget"); !u) return u;
  if (Status s = checkJoint(id, "setMouseTarget"); !s) return s;
  Joint& j = state().joints.joints[id.index];
  if (j.def.type != JointType::mouse) return fail("setMouseTarget: not a mouse joint");
  if (!isFinite(target) || !withinCoordinateLimit(target))
    return fail("setMouseTarget: target must be finite and within kMaxCoordinate");
  j.def.target = target;
  wakeJoint(state(), j);
  return {};
}

Status World::setMotorTarget(JointId id, Vec2 linearOffset, float angularOffset) {
  if (Status u = checkUsable("setMotorTarget"); !u) return u;
  if (Status s = checkJoint(id, "setMotorTarget"); !s) return s;
  Joint& j = state().joints.joints[id.index];
  if (j.def.type != JointType::motor) return fail("setMotorTarget: not a motor joint");
  if (!isFinite(linearOffset) || !withinCoordinateLimit(linearOffset) ||
      !std::isfinite(angularOffset))
    return fail("setMotorTarget: the offsets must be finite (and within kMaxCoordinate)");
  j.def.linearOffset = linearOffset;
  j.def.angularOffset = angularOffset;
  wakeJoint(state(), j);
  return {};
}

void World::onJointEnd(JointEndCallback f) {
  if (!s_) return;
  state().events.addJointEnd(std::move(f), state().inCallbacks);
}

}  // namespace quack
