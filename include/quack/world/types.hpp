#pragma once
/// The vocabulary of the world: handles, body and shape definitions, events.

#include <cstdint>
#include <limits>
#include <variant>

#include "quack/broadphase/broad_phase.hpp"
#include "quack/geometry/shapes.hpp"

namespace quack {

/// Handle to a body: slot index plus the slot's generation at creation, so a handle kept
/// after the body was destroyed is caught instead of reaching a reused slot, plus the id of
/// the world that made it, so a handle given to another world is refused. The default
/// handle is null.
struct BodyId {
  std::uint32_t index = 0xffffffffu;
  std::uint32_t generation = 0;
  std::uint32_t world = 0;  ///< World::id() of its world; 0: none
  friend constexpr bool operator==(BodyId, BodyId) noexcept = default;
};

/// Handle to a shape on a body, as BodyId.
struct ShapeId {
  std::uint32_t index = 0xffffffffu;
  std::uint32_t generation = 0;
  std::uint32_t world = 0;  ///< World::id() of its world; 0: none
  friend constexpr bool operator==(ShapeId, ShapeId) noexcept = default;
};

/// Handle to a joint, as BodyId.
struct JointId {
  std::uint32_t index = 0xffffffffu;
  std::uint32_t generation = 0;
  std::uint32_t world = 0;  ///< World::id() of its world; 0: none
  friend constexpr bool operator==(JointId, JointId) noexcept = default;
};

/// Which shapes a query sees: those whose filter accepts this one (see shouldCollide), in
/// the 2D and the 3D world.
struct QueryFilter {
  std::uint64_t category = 1;
  std::uint64_t mask = ~std::uint64_t{0};
  bool includeSensors = false;
};

/// Static bodies never move; kinematic bodies move at the velocity they are given and are
/// not pushed; dynamic bodies are moved by gravity, forces and contacts.
enum class BodyType : std::uint8_t { staticBody, kinematicBody, dynamicBody };

/// The scene-file name of a body type ("static", "kinematic", "dynamic").
const char* toString(BodyType type) noexcept;

/// A new body. World frame, SI units.
struct BodyDef {
  BodyType type = BodyType::dynamicBody;
  Vec2 position;                 ///< origin of the body frame, world frame
  float angle = 0.0f;            ///< radians
  Vec2 linearVelocity;           ///< of the centre of mass, m/s
  float angularVelocity = 0.0f;  ///< rad/s
  float linearDamping = 0.0f;    ///< 1/s, >= 0
  float angularDamping = 0.0f;   ///< 1/s, >= 0
  float gravityScale = 1.0f;
  /// Continuous collision in every step, however slowly it moves. Every dynamic body already
  /// gets continuous collision (against static, kinematic and dynamic shapes, sweep against
  /// sweep) in any step where it moves more than kCcdFastFraction of its thickness
  /// (docs/continuous.md, "In the world").
  bool bullet = false;
  /// May this body fall asleep (docs/world.md, "Sleeping")? A body that may not keeps every
  /// body it touches awake.
  bool enableSleep = true;
  /// Created awake (false: created asleep, at rest until something wakes it; its first
  /// shape leaves it asleep, later ones wake it, as any change does).
  bool isAwake = true;
  /// Below this speed (m/s) the body rests: its centre's speed, and its angular speed times
  /// its largest extent (the speed of its farthest point from the turning). >= 0.
  float sleepThreshold = 0.05f;
  std::uint64_t userData = 0;
};

/// A new shape on a body.
struct ShapeDef {
  float density = 1.0f;      ///< kg/m^2, >= 0
  float friction = 0.6f;     ///< Coulomb coefficient, >= 0; a pair uses sqrt(fa fb)
  float restitution = 0.0f;  ///< >= 0; a pair uses the larger
  /// A sensor reports overlaps (sensor events) and takes no part in the solver.
  bool sensor = false;
  Filter filter;
  std::uint64_t userData = 0;
};

/// The kinds of joint (docs/world.md, "Joints").
enum class JointType : std::uint8_t {
  revolute,   ///< a shared point: B turns about it (limits, motor, spring on the angle)
  prismatic,  ///< B slides along an axis fixed in A, without turning (limits, motor, spring)
  distance,   ///< two points held at a length, or within [minLength, maxLength] (a rope)
  weld,       ///< B held fixed to A, rigidly or through linear and angular springs
  wheel,      ///< B slides on an axis of A on a spring (suspension) and turns freely (motor)
  motor,      ///< B driven towards a pose relative to A, with a most force and torque
  mouse,      ///< a point of B pulled towards a target, softly, with a most force
};
/// The scene-file name of a joint type ("revolute", "prismatic", ...).
const char* toString(JointType type) noexcept;

/// A new joint between two bodies (World::createJoint). One record for every type: the
/// fields a type does not use are ignored. Anchors, axes and targets are in the world frame
/// at creation (the bodies' poses then fix them to the bodies); angles in radians, lengths
/// in metres. Every setting is documented in docs/world.md, "Joints".
struct JointDef {
  JointType type = JointType::revolute;
  /// The two bodies; they must differ. A joint acts while one of them is dynamic (a joint
  /// between static bodies waits for setBodyType). A mouse joint has no body A (leave it
  /// null): it pulls body B towards `target`.
  BodyId bodyA, bodyB;
  /// The joint's point (revolute, prismatic, weld, wheel; the point of B a mouse grabs);
  /// for a distance joint, the end on body A.
  Vec2 anchorA;
  /// A distance joint's end on body B.
  Vec2 anchorB;
  /// Prismatic and wheel: the direction B slides along, fixed in A (any length but zero).
  Vec2 axis{1.0f, 0.0f};

  /// Limits: revolute, the angle of B relative to A since creation (radians, within
  /// [-pi, pi]); prismatic and wheel, B's travel along the axis from the anchor (metres);
  /// distance, the length within [minLength, maxLength].
  bool enableLimit = false;
  float lower = 0.0f, upper = 0.0f;
  /// Motor: a revolute or wheel joint turns B relative to A at motorSpeed (rad/s) with at
  /// most maxMotorTorque (N m); a prismatic joint slides it at motorSpeed (m/s) with at most
  /// maxMotorForce (N).
  bool enableMotor = false;
  float motorSpeed = 0.0f;
  float maxMotorTorque = 0.0f;
  float maxMotorForce = 0.0f;
  /// Spring: on the revolute angle (towards 0), the prismatic or wheel travel (towards 0),
  /// the distance (towards `length`). Also the mouse joint's stiffness (always on). Hertz
  /// >= 0 (0: no spring force: a distance joint's length is then free within its limits,
  /// a rope), damping ratio >= 0.
  bool enableSpring = false;
  float hertz = 5.0f;
  float dampingRatio = 0.7f;

  /// Distance: the rest length (< 0: the anchors' distance at creation) and the limits'
  /// range. Without a spring the length is held rigidly at `length`; a rope is a spring of
  /// 0 Hz with a limit at maxLength.
  float length = -1.0f;
  float minLength = 0.0f;
  float maxLength = 1.0e6f;

  /// Weld: springs on the offset and the angle (Hz; 0: rigid) and their damping ratios.
  float linearHertz = 0.0f, angularHertz = 0.0f;
  float linearDampingRatio = 1.0f, angularDampingRatio = 1.0f;

  /// Motor joint: B's centre held at linearOffset from A's origin (in A's frame) and its
  /// angle at angularOffset from A's, with at most maxForce (N) and maxTorque (N m);
  /// correctionFactor in [0, 1] is the share of the error corrected per sub-step.
  Vec2 linearOffset;
  float angularOffset = 0.0f;
  float maxForce = 0.0f;
  float maxTorque = 0.0f;
  float correctionFactor = 0.3f;

  /// Mouse: where B's grabbed point is pulled (maxForce, which must be > 0, caps the pull;
  /// hertz and dampingRatio set the spring). A motor joint needs maxForce or maxTorque > 0.
  Vec2 target;

  /// Whether the two bodies' shapes still collide with each other (false: they pass
  /// through each other, as the parts of a ragdoll at a joint should).
  bool collideConnected = false;
  /// The joint breaks (is destroyed, StepEvents::jointEnd) in the first step whose
  /// constraint force (N) or torque (N m) passes these. Infinite: never.
  float breakForce = std::numeric_limits<float>::infinity();
  float breakTorque = std::numeric_limits<float>::infinity();
  std::uint64_t userData = 0;
};

/// Why a joint ended.
enum class JointEndReason : std::uint8_t {
  broken,         ///< its force or torque passed JointDef::breakForce or breakTorque
  bodyDestroyed,  ///< one of its bodies was destroyed (World::destroyBody)
};
/// A joint ended without World::destroyJoint: broken in the step, or taken with a body
/// destroyed since the last step. The handle is stale when the event is read.
struct JointEndEvent {
  JointId joint;
  BodyId bodyA, bodyB;  ///< stale too when that body was destroyed
  JointEndReason reason = JointEndReason::broken;
  Vec2 force;           ///< the constraint force of its last step, N, world frame
  float torque = 0.0f;  ///< the constraint torque of its last step, N m
  std::uint64_t userData = 0;
};

/// Two shapes started touching (their manifold gained points).
struct ContactBeginEvent {
  ShapeId shapeA, shapeB;
};
/// Two shapes stopped touching, or one of them was destroyed.
struct ContactEndEvent {
  ShapeId shapeA, shapeB;
};
/// A contact point whose shapes approached faster than the hit threshold this step.
struct ContactHitEvent {
  ShapeId shapeA, shapeB;
  Vec2 point;                  ///< world frame
  Vec2 normal;                 ///< from A to B
  float approachSpeed = 0.0f;  ///< m/s, > 0
};
/// A shape started or stopped overlapping a sensor.
struct SensorEvent {
  ShapeId sensor, visitor;
};

/// A time-of-impact event of the continuous phase: a shape of a fast body (or of a body an
/// impact set moving) reached another shape during the step; both bodies were moved to that
/// time and their velocities answered (see docs/continuous.md, "In the world").
struct ToiEvent {
  float time = 0.0f;  ///< fraction of the step, in [0, 1]
  ShapeId shapeA;     ///< the shape of the body whose sweep found the impact
  ShapeId shapeB;     ///< the shape it reached (static, kinematic, or on a moving body)
  Vec2 point;         ///< on shape A's surface at the time of impact, world frame
  Vec2 normal;        ///< unit, from A to B, world frame
  /// m/s, >= 0: how fast the bodies approached along the normal at the impact point, just
  /// before the impact's impulse (zero when they were already parting there).
  float approachSpeed = 0.0f;
};

/// The events of one step.
struct StepEvents {
  std::vector<ContactBeginEvent> begin;
  std::vector<ContactEndEvent> end;
  std::vector<ContactHitEvent> hit;
  std::vector<SensorEvent> sensorBegin;
  std::vector<SensorEvent> sensorEnd;
  /// Time-of-impact events, sorted by time (ties: in the order they were handled).
  std::vector<ToiEvent> toi;
  /// Bodies whose motion in this step would have taken a shape beyond kMaxCoordinate (the
  /// edge of the world): each was held at its pose from the start of the step with zero
  /// velocity, and is listed once per step in which that happened, in index order.
  std::vector<BodyId> outOfBounds;
  /// Bodies that reached kMaxToiEventsPerBody impacts in this step (the continuous phase's
  /// bound): each was held where its last impact left it for the rest of the step, and met
  /// by others as if it could not move. In the order they reached the bound.
  std::vector<BodyId> toiCapped;
  /// Joints that broke in this step, then those taken by bodies destroyed since the last
  /// step (in the order they were destroyed).
  std::vector<JointEndEvent> jointEnd;
};

}  // namespace quack
