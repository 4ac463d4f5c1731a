#pragma once
/// The vocabulary of the world: handles, body and shape definitions, events.

#include <cstdint>
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
};

}  // namespace quack
