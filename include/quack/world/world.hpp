#pragma once
/// `World`: rigid bodies carrying shapes, stepped through four phases (docs/background.md) —
/// proximity (filters), broad phase (fat boxes in any of the five structures), narrow phase
/// (contact manifolds) and execution (a soft-contact sequential-impulse solver, then events
/// to the game). docs/world.md explains the solver and every default.
///
/// ```
/// World world = World::create({}).value();
/// BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
/// world.createShape(ground, {}, makeBox(20, 0.5f).value());
/// BodyId ball = world.createBody({.position = {0, 5}}).value();
/// world.createShape(ball, {.restitution = 0.5f}, makeCircle({}, 0.5f).value());
/// for (int i = 0; i < 60; ++i) world.step();
/// ```
///
/// Error policy: every public function checks its arguments (stale or null handles,
/// NaN or infinite numbers, negative densities, ...) and fails with an `Error` that names
/// the argument; a failed call changes nothing. Bodies and shapes may be created and
/// destroyed at any time outside `step`; from inside an event callback, destruction is
/// deferred until the callbacks of that step are done (the handle stays valid until then,
/// and the step's later events involving it still get their callbacks: the callbacks and
/// the event lists always agree). Calling `step` from a callback fails.
///
/// Determinism: the same scene built in the same order and stepped with the same inputs
/// gives bit-identical state (`stateHash`) on the same build.

#include <cstddef>
#include <functional>
#include <iterator>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "quack/collision/manifold.hpp"
#include "quack/world/tasks.hpp"
#include "quack/world/types.hpp"

namespace quack {

namespace detail {
struct WorldState;
}

/// Default WorldDef::contactRecycleDistance: ten linear slops (5 cm), as Box2D v3.
inline constexpr float kContactRecycleDistance = 10.0f * kLinearSlop;
/// Contacts are recycled only while neither body has turned further than the angle with this
/// cosine since the manifold was computed (0.98: about 11.5 degrees), as Box2D v3.
inline constexpr float kContactRecycleCosAngle = 0.98f;

/// How a world is made. Every default is documented in docs/world.md.
struct WorldDef {
  Vec2 gravity{0.0f, -10.0f};     ///< m/s^2
  float timeStep = 1.0f / 60.0f;  ///< seconds per step() without arguments, > 0
  int substeps = 4;               ///< solver sub-steps per step, 1..64
  BroadPhaseKind broadPhase = BroadPhaseKind::tree;
  /// Stiffness of contacts, Hz (capped at a quarter of the sub-step rate): how fast overlap
  /// is pushed out. 30 Hz, as Box2D v3.
  float contactHertz = 30.0f;
  /// Damping ratio of contacts: 10, heavily over-damped, so pushing out does not bounce.
  float contactDampingRatio = 10.0f;
  /// Stiffness of rigid joints, Hz (capped at a quarter of the sub-step rate, like
  /// contactHertz): how fast a joint pulled apart is pushed back together. 60 Hz, twice the
  /// contacts', so that a chain does not stretch under the bodies it holds.
  float jointHertz = 60.0f;
  /// Damping ratio of rigid joints: 2, over-damped, so that closing a gap does not bounce.
  float jointDampingRatio = 2.0f;
  /// Fastest speed at which overlap is pushed out, m/s.
  float contactPushMaxSpeed = 3.0f;
  /// Approach speed below which restitution is ignored, m/s (resting contacts do not jitter).
  float restitutionThreshold = 1.0f;
  /// Approach speed above which a contact reports a hit event, m/s.
  float hitEventThreshold = 1.0f;
  /// Contacts appear while shapes are this close (see kSpeculativeDistance), metres.
  float speculativeDistance = kSpeculativeDistance;
  /// Largest turn a body may make in one sub-step, radians (keeps fast spinners stable).
  float maxRotationPerSubstep = 0.25f * kPi;
  /// Continuous collision (swept boxes, time of impact, the time-ordered event phase) for
  /// fast bodies and bullets. On by default; off gives the discrete solver alone.
  bool enableContinuous = true;
  /// Continuous collision between two dynamic bodies, neither a bullet: a fast body is swept
  /// against the other's sweep, in time order (docs/continuous.md). On by default. Off, a
  /// fast body that is not a bullet is swept against static and kinematic shapes only, as
  /// Box2D v3 does: cheaper in churning piles (about half the step's time in world_suite's
  /// spinner), but a fast body may pass through a thin dynamic one. Bullets are always
  /// swept against everything.
  bool sweepDynamicPairs = true;
  /// Ghost-collision removal on static geometry (docs/concave.md): edges of static polygons
  /// laid flush against an opposite edge of another static polygon are internal, contacts
  /// on them are dropped, and contact normals at vertices where flush faces meet are turned
  /// into the cone of the faces that really meet there; chains (createChain) use their
  /// neighbours the same way. Costs nothing per contact when no static shape is flagged.
  bool removeGhostCollisions = true;
  /// Contact recycling (docs/world.md, "Contact recycling and point order"): while two touching
  /// bodies have moved less than this (metres, plus their largest extent times the sine of
  /// their relative turn) relative to each other since their manifold was computed, and
  /// neither has turned more than about 11 degrees, the manifold is kept: same normal, same
  /// points fixed on each body, separation updated from the bodies' motion. 0 recomputes
  /// every step. Ten slops, as Box2D v3.
  float contactRecycleDistance = kContactRecycleDistance;
  /// Solve contacts with the portable one-lane path even where the build has SIMD lanes
  /// (QUACK_SIMD; World::simdPath). The answer is the same to the bit (docs/world.md, "The
  /// solver's data"); this is for tests and for measuring what the lanes buy.
  bool scalarSolver = false;
  /// Sleeping (docs/world.md, "Sleeping"): islands of bodies at rest stop being simulated
  /// until something wakes them. Off: every body is simulated every step.
  bool enableSleep = true;
  /// Threads (docs/world.md, "Threads"; quack/world/tasks.hpp): how many workers run a step,
  /// 1..kMaxWorkers. With enqueueTask and finishTask (both or neither) the game's job system
  /// runs them; without, a pool of workerCount - 1 threads owned by the world does, the
  /// thread that calls step being the first worker. The same bits whatever the count.
  int workerCount = 1;
  EnqueueTaskFn enqueueTask = nullptr;
  FinishTaskFn finishTask = nullptr;
  void* userTaskContext = nullptr;  ///< passed to enqueueTask and finishTask
};

/// Two edges of static polygons whose ends are this close (metres), running opposite ways,
/// are laid flush: the seam between two tiles. A tenth of a slop: tiles placed by float
/// arithmetic meet within a few ulps, while a step a body should feel is at least a slop.
inline constexpr float kFlushEdgeTolerance = 0.1f * kLinearSlop;

/// A contact point within this distance (metres) of a vertex where flush faces meet (or of
/// a chain joint) is treated as touching that vertex. The speculative distance plus a slop:
/// a body's corner reaches that far past the seam while its contact is still speculative or
/// resolving the slop, which is when ghost normals appear.
inline constexpr float kGhostVertexRadius = kSpeculativeDistance + kLinearSlop;

/// A dynamic body is fast, and gets continuous collision in a step, when its centre moves
/// more than this fraction of its smallest half-thickness (plus its rotation times its
/// largest extent) in that step. A half: a body that moved less cannot have its centre
/// past the middle of what it entered, so the contact solver still pushes it back the way
/// it came (Box2D v3 uses the same rule, read for understanding).
inline constexpr float kCcdFastFraction = 0.5f;

/// Seconds every body of an island must rest (move slower than its
/// BodyDef::sleepThreshold) before the island sleeps. Half a second, as Box2D: long enough
/// that a body at the top of its bounce or a pendulum at its turning point is not taken
/// for resting, short enough that a settled pile stops costing soon (docs/world.md,
/// "Sleeping").
inline constexpr float kTimeToSleep = 0.5f;

/// Most time-of-impact events one body may have in a step. After that the body stays where
/// its last event left it for the rest of the step: a bound so that a pathological scene (a
/// body wedged between walls) cannot loop. Eight, as Box2D 2.4's b2_maxSubSteps.
inline constexpr int kMaxToiEventsPerBody = 8;

/// Limits on what a world accepts, so that nothing it computes can overflow a float
/// (docs/world.md, "Limits"). Inputs beyond them are refused with a message naming the
/// field; speeds the solver produces are held within them.
///
/// Longest step, seconds. The contact softness and the continuous phase are tuned for steps
/// of milliseconds; a second is already far beyond any frame, and a bound keeps
/// gravity * dt and speed * dt finite.
inline constexpr float kMaxTimeStep = 1.0f;
/// Strongest gravity, m/s^2 (a thousand g). Times kMaxTimeStep and any sensible gravity
/// scale it stays far from overflow.
inline constexpr float kMaxGravity = 1.0e4f;
/// Largest |BodyDef::gravityScale|.
inline constexpr float kMaxGravityScale = 1.0e3f;
/// Fastest linear speed, m/s (100 km/s, two hundred times a rifle bullet). Velocities set
/// through the API beyond it are refused; the solver clamps to it (as Box2D v3 clamps to its
/// maximum linear speed), so speed * dt stays within a few kMaxCoordinate.
inline constexpr float kMaxLinearSpeed = 1.0e5f;
/// Fastest spin, rad/s. The solver also limits the turn per sub-step (maxRotationPerSubstep).
inline constexpr float kMaxAngularSpeed = 1.0e5f;
/// Heaviest body, kg. An impulse is mass times speed: 1e20 kg at kMaxLinearSpeed, times a
/// lever arm of kMaxCoordinate, stays below 1e35, inside float range.
inline constexpr float kMaxBodyMass = 1.0e20f;
/// Largest restitution. Above 1 a contact adds energy (a bounce pad); ten is already a
/// cartoon, and a bound keeps restitution times approach speed finite.
inline constexpr float kMaxRestitution = 10.0f;

/// A shape a ray met. World frame.
struct RayHitResult {
  ShapeId shape;
  BodyId body;
  Vec2 point;
  Vec2 normal;         ///< outward from the shape
  float fraction = 0;  ///< along the ray's translation
};

/// A shape an overlap query met, and how to get the query shape out of it.
struct ShapeOverlap {
  ShapeId shape;
  BodyId body;
  float depth = 0.0f;  ///< metres, >= 0
  /// Move the query shape by this (world frame, metres) to separate it from `shape`:
  /// minus the normal from the query shape to `shape`, times the depth.
  Vec2 depenetration;
};

/// The first shape a world shape cast met. World frame.
struct ShapeCastResult {
  ShapeId shape;
  BodyId body;
  Vec2 point;          ///< on the shape met, where the cast shape touches it
  Vec2 normal;         ///< unit, from the shape met towards the cast shape
  float fraction = 0;  ///< of the translation; 0 when the cast shape starts overlapping
};

/// What `step` says: done, or why it refused (called from a callback, a bad dt). Unlike
/// `Status` it may be ignored, so `world.step();` reads plainly in a game loop; check it
/// where a refusal matters (`if (!world.step(dt, 4)) ...`).
class StepStatus {
 public:
  StepStatus() = default;
  StepStatus(Error error) : status_(std::move(error)) {}  // NOLINT: implicit, as Status
  bool ok() const noexcept { return status_.ok(); }
  explicit operator bool() const noexcept { return ok(); }
  const std::string& message() const noexcept { return status_.message(); }
  operator Status() const { return status_; }  // NOLINT: a StepStatus is a Status

 private:
  Status status_;
};

/// What World::snapshot saves (docs/determinism.md, "Snapshots").
enum class SnapshotKind : std::uint8_t {
  /// Everything that decides future steps: the settings, every body and shape (static
  /// geometry included), contacts with their warm-start impulses, islands and sleep, the
  /// broad phase's proxies and move buffer, handles' generations. Restores into any world.
  full,
  /// Only what changes while shapes and static geometry do not (body motion and sleep,
  /// contacts, islands, moving proxies), for rollback: restores only into a world whose
  /// static structure (settings, bodies and shapes, static poses, handles) is the one the
  /// snapshot was taken from, which a fingerprint checks.
  dynamic,
};
/// "full" or "dynamic".
const char* toString(SnapshotKind kind) noexcept;

/// The snapshot format's version (docs/determinism.md, "Snapshots"): snapshots of another
/// version are refused. Bumped whenever the layout, or the arithmetic of a step, changes.
inline constexpr std::uint32_t kSnapshotFormatVersion = 2;

class World {
 public:
  static Result<World> create(const WorldDef& def = {});

  /// A moved-from World holds nothing: every call on it fails with a message that says so
  /// (or, where a call cannot fail, reads an empty world), and it is never a crash.
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;
  ~World();

  const WorldDef& def() const noexcept;
  /// This world's id, carried by every handle it gives out (BodyId::world), so that a
  /// handle from another world is refused. Unique in the process; never 0.
  std::uint32_t id() const noexcept;

  // ---- bodies and shapes -------------------------------------------------------------
  Result<BodyId> createBody(const BodyDef& def);
  /// Destroys the body and its shapes (contacts touching them end with end events).
  Status destroyBody(BodyId body);
  /// Adds a shape (body frame) to a body and recomputes the body's mass. Errors: bad body,
  /// bad numbers in `def`, a shape not built by the make* functions (validated again).
  Result<ShapeId> createShape(BodyId body, const ShapeDef& def, const ShapeGeometry& geometry);
  Status destroyShape(ShapeId shape);
  /// A chain of one-sided segments on a static body (body frame points, metres): segment i
  /// joins points[i] and points[i + 1] (and, with `loop`, the last point to the first).
  /// Collision is one-sided, as Box2D's chain: a segment pushes only towards the right of
  /// its direction (the outward side of a counter-clockwise loop; a floor listed from right
  /// to left pushes up), and a body whose centre is behind it passes through. At each joint
  /// the neighbouring segment serves as a ghost vertex, so a body sliding or rolling along
  /// the chain does not catch on the joints. Errors: a body that is not static, fewer than
  /// 2 points (3 for a loop), a non-finite point, two consecutive points closer than
  /// kFlushEdgeTolerance, and those of createShape. On error nothing is created.
  Result<std::vector<ShapeId>> createChain(BodyId body, const ShapeDef& def,
                                           std::span<const Vec2> points, bool loop = false);

  bool isValid(BodyId body) const noexcept;
  bool isValid(ShapeId shape) const noexcept;
  std::size_t bodyCount() const noexcept;
  std::size_t shapeCount() const noexcept;
  /// Live contacts (fat boxes overlapping) and how many of them touch.
  std::size_t contactCount() const noexcept;
  std::size_t touchingContactCount() const noexcept;
  /// Bodies simulated in the next step: live, not static, awake.
  std::size_t awakeBodyCount() const noexcept;
  /// Islands (groups of dynamic bodies joined by touching contacts).
  std::size_t islandCount() const noexcept;

  // ---- iteration, without allocating -----------------------------------------------------
  class BodyRange;
  class ShapeRange;
  class ContactRange;
  /// Every live body, in index order (a range of BodyId; nothing is allocated).
  BodyRange bodies() const noexcept;
  /// Shapes of a body, in creation order (empty for a bad handle).
  ShapeRange shapes(BodyId body) const noexcept;
  /// Touching, non-sensor contacts (for drawing): the two shapes and the manifold.
  struct ContactView {
    ShapeId shapeA, shapeB;
    Manifold manifold;
  };
  ContactRange touchingContacts() const noexcept;

  // ---- body state ------------------------------------------------------------------------
  // A null, stale (destroyed) or foreign (another world's) handle is caught in every build:
  // the getters then return a neutral value (zero vectors and numbers, the identity
  // transform, a static body type, a null BodyId, an empty circle, a default ShapeDef), and
  // the setters fail with a message. Use isValid to tell.
  BodyType bodyType(BodyId body) const;
  /// False while the body sleeps (and always for a static body).
  bool isAwake(BodyId body) const;
  Transform transform(BodyId body) const;  ///< worldFromBody
  Vec2 position(BodyId body) const;        ///< of the body origin, world frame
  float angle(BodyId body) const;
  Vec2 linearVelocity(BodyId body) const;  ///< of the centre of mass, m/s
  float angularVelocity(BodyId body) const;
  float mass(BodyId body) const;
  float rotationalInertia(BodyId body) const;  ///< about the centre of mass
  Vec2 worldCenterOfMass(BodyId body) const;
  std::uint64_t userData(BodyId body) const;
  BodyId body(ShapeId shape) const;
  const ShapeGeometry& geometry(ShapeId shape) const;
  const ShapeDef& shapeDef(ShapeId shape) const;

  // Every call below wakes the body (docs/world.md, "Sleeping"); moving a static or
  // kinematic body, or giving a kinematic body a velocity, also wakes what touches it.

  /// Teleports a body (errors: bad handle, non-finite numbers).
  Status setTransform(BodyId body, Vec2 position, float angle);
  Status setLinearVelocity(BodyId body, Vec2 velocity);
  Status setAngularVelocity(BodyId body, float velocity);
  /// Impulse (N s) at a world point; dynamic bodies only (others ignore it). Refused when
  /// the resulting speed would pass kMaxLinearSpeed or kMaxAngularSpeed.
  Status applyLinearImpulse(BodyId body, Vec2 impulse, Vec2 worldPoint);
  /// Angular impulse (N m s); dynamic bodies only. Refused past kMaxAngularSpeed.
  Status applyAngularImpulse(BodyId body, float impulse);
  /// Force (N) at a world point, acting through the next step (forces and torques are
  /// summed, and cleared after each step, as in Box2D); dynamic bodies only.
  Status applyForce(BodyId body, Vec2 force, Vec2 worldPoint);
  /// Torque (N m) through the next step; dynamic bodies only.
  Status applyTorque(BodyId body, float torque);
  /// Changes a body's type. Its contacts end (end events) and are found again under the new
  /// type; its mass is recomputed; a body made static stops.
  Status setBodyType(BodyId body, BodyType type);
  /// Wakes the body's island (true), or puts it to sleep now (false), whatever its rest
  /// time. A static body has nothing to change. Waking a body also wakes what it touches
  /// when it is kinematic.
  Status setAwake(BodyId body, bool awake);

  // ---- joints (docs/world.md, "Joints") ---------------------------------------------------
  /// A joint between two bodies, solved with the contacts in every sub-step. Creating it
  /// wakes both bodies and joins their islands (jointed bodies sleep and wake together);
  /// unless `collideConnected`, contacts between the two bodies end (with end events in the
  /// next step) and are not made again while the joint lives. Errors, naming the field:
  /// a bad body handle, the same body twice, non-finite or out-of-range
  /// numbers (negative hertz, lower > upper, a zero axis, ...).
  Result<JointId> createJoint(const JointDef& def);
  /// Destroys the joint (no event: the game asked for it) and wakes its bodies.
  Status destroyJoint(JointId joint);
  bool isValid(JointId joint) const noexcept;
  std::size_t jointCount() const noexcept;
  class JointRange;
  /// Every live joint, in index order (a range of JointId; nothing is allocated).
  JointRange joints() const noexcept;
  /// The joint's settings as created (anchors and axis in the world frame at creation),
  /// with the changes made since by the setters below. A default JointDef for a bad handle.
  const JointDef& jointDef(JointId joint) const;
  /// The joint's anchors now, world frame: on body A and on body B (for a mouse joint, the
  /// target and B's grabbed point). They coincide while a point joint holds.
  std::pair<Vec2, Vec2> jointAnchors(JointId joint) const;
  /// The force (N, world frame, on body B) and torque (N m) the joint applied in the last
  /// step: its accumulated impulse over the sub-step.
  Vec2 jointForce(JointId joint) const;
  float jointTorque(JointId joint) const;
  /// Revolute and weld: B's angle relative to A less the angle at creation (radians, in
  /// [-pi, pi]); 0 for the other types.
  float jointAngle(JointId joint) const;
  /// Prismatic and wheel: B's travel along the axis from the anchor; distance: the length
  /// between the anchors (metres); 0 for the other types.
  float jointTranslation(JointId joint) const;
  /// Motors (revolute, prismatic, wheel): on or off, speed and strength; wakes the bodies.
  Status setJointMotor(JointId joint, bool enable, float speed, float maxTorqueOrForce);
  /// Limits (revolute, prismatic, wheel, distance): on or off and the range; wakes.
  Status setJointLimits(JointId joint, bool enable, float lower, float upper);
  /// A mouse joint's target (world frame); wakes body B.
  Status setMouseTarget(JointId joint, Vec2 target);
  /// A motor joint's target pose of B relative to A; wakes the bodies.
  Status setMotorTarget(JointId joint, Vec2 linearOffset, float angularOffset);

  // ---- stepping ------------------------------------------------------------------------
  /// Advances by `def().timeStep` with `def().substeps`.
  StepStatus step();
  /// Advances by dt seconds (> 0, finite, at most kMaxTimeStep) with `substeps` (1..64)
  /// solver sub-steps.
  ///
  /// Exceptions (docs/world.md, "Exceptions"): an exception thrown by an event callback
  /// leaves step() after the step is complete (bodies moved, stepCount() advanced); the
  /// callbacks after it are not called for this step, and the destruction that earlier
  /// callbacks asked for is carried out. The world is valid and usable. An exception from
  /// inside the step's phases (std::bad_alloc, the only one they throw of their own, or
  /// whatever a game's job system, WorldDef::enqueueTask, throws) leaves the step half
  /// done: the world then refuses every change, step and snapshot with a message naming
  /// the failed step until a snapshot is restored into it (restore()), and can still be
  /// read and destroyed.
  StepStatus step(float dt, int substeps);
  /// The events of the last step (valid until the next step). Contacts and sensor overlaps
  /// ended by destroying a shape between steps are reported, and their callbacks called,
  /// with the next step's end events; their shape handles are then stale (isValid).
  const StepEvents& events() const noexcept;
  /// Steps taken and simulated time.
  std::uint64_t stepCount() const noexcept;
  double time() const noexcept;

  // ---- snapshots (docs/determinism.md, "Snapshots") -------------------------------------
  /// The world's state as bytes: stepping the world restored from them gives the same bits
  /// (stateHash, state files, events) as stepping this one, for any broad phase, with or
  /// without sleep. Callbacks and the last step's event lists are not saved. Fails when
  /// called during a step or from a callback.
  Result<std::vector<std::uint8_t>> snapshot(SnapshotKind kind = SnapshotKind::full) const;
  /// Puts the world back in the state a snapshot saved. Handles (BodyId, ShapeId) valid when
  /// the snapshot was taken are valid again, with this world's id; the callbacks stay as
  /// they are; events() is empty until the next step (references from events() and
  /// broadPhase() taken before are invalidated). A dynamic snapshot needs this world to
  /// have the snapshot's static structure. Refused, with a message naming what is wrong,
  /// and leaving the world unchanged: bytes that are not a snapshot, truncated or corrupted
  /// (checksum), of another format version or another build's constants, a dynamic
  /// snapshot of another structure, or contents that fail validation; and a call during a
  /// step or from a callback. The world keeps its own workers and task callbacks (they do
  /// not change the bits).
  Status restore(std::span<const std::uint8_t> bytes);
  /// A new world from a full snapshot (a dynamic one is refused: it needs a world to
  /// restore into). Its handles have the old ones' indices and generations and the new
  /// world's id (take them again through bodies() and shapes()). It runs on one worker
  /// (threads are not part of a snapshot); restore into a world made with the workers
  /// wanted to have more.
  static Result<World> fromSnapshot(std::span<const std::uint8_t> bytes);

  // ---- callbacks (called at the end of each step, in event order) -----------------------
  // Always on the thread that called `step`, after the step's parallel work, one at a time,
  // whatever WorldDef::workerCount is.
  // A callback registered from inside a callback takes effect from the next step.
  /// Category masks select the shapes: a callback runs for an event whose first shape has a
  /// category in `categoriesA` and whose second has one in `categoriesB` (tried both ways
  /// round; the shapes are passed in the matching order). "When a weapon touches a player,
  /// call this": onContactBegin(weaponBit, playerBit, f).
  using ContactCallback = std::function<void(World&, ShapeId a, ShapeId b)>;
  using HitCallback = std::function<void(World&, const ContactHitEvent& hit, bool swapped)>;
  void onContactBegin(std::uint64_t categoriesA, std::uint64_t categoriesB, ContactCallback f);
  void onContactEnd(std::uint64_t categoriesA, std::uint64_t categoriesB, ContactCallback f);
  void onHit(std::uint64_t categoriesA, std::uint64_t categoriesB, HitCallback f);
  /// Impacts of the continuous phase (StepEvents::toi), in time order: (world, event,
  /// swapped), swapped true when the event's shape B matched `categoriesA`.
  using ImpactCallback = std::function<void(World&, const ToiEvent& impact, bool swapped)>;
  void onImpact(std::uint64_t categoriesA, std::uint64_t categoriesB, ImpactCallback f);
  /// Sensor callbacks: (world, sensor, visitor), selected by the sensor's and visitor's
  /// categories.
  void onSensorBegin(std::uint64_t sensorCategories, std::uint64_t visitorCategories,
                     ContactCallback f);
  void onSensorEnd(std::uint64_t sensorCategories, std::uint64_t visitorCategories,
                   ContactCallback f);

  /// Joints that ended without destroyJoint (StepEvents::jointEnd), in event order.
  using JointEndCallback = std::function<void(World&, const JointEndEvent& event)>;
  void onJointEnd(JointEndCallback f);

  // ---- queries (world frame) ---------------------------------------------------------------
  /// The first shape the ray `origin + t translation`, t in [0, 1], enters.
  std::optional<RayHitResult> rayCastClosest(Vec2 origin, Vec2 translation,
                                             QueryFilter filter = {}) const;
  /// Every shape the ray enters, by fraction.
  std::vector<RayHitResult> rayCastAll(Vec2 origin, Vec2 translation,
                                       QueryFilter filter = {}) const;
  /// Shapes whose bounding boxes overlap `box`.
  std::vector<ShapeId> overlapAabb(Aabb box, QueryFilter filter = {}) const;
  /// Shapes that overlap `geometry` placed by `worldFromShape`, each with the depenetration
  /// vector of the query shape. Errors: a non-finite transform.
  Result<std::vector<ShapeOverlap>> overlapShape(const ShapeGeometry& geometry,
                                                 Transform worldFromShape,
                                                 QueryFilter filter = {}) const;
  /// Sweeps `geometry` from `worldFromShape` along `translation` (metres) and returns the
  /// first shape it meets (lowest fraction; ties: lower shape index), if any. A shape the
  /// cast starts overlapping is met at fraction 0. Errors: non-finite input, a bad geometry.
  Result<std::optional<ShapeCastResult>> castShape(const ShapeGeometry& geometry,
                                                   Transform worldFromShape, Vec2 translation,
                                                   QueryFilter filter = {}) const;

  // ---- inspection ----------------------------------------------------------------------------
  /// A hash of every body's position, angle, velocities, awake flag and rest time
  /// (bitwise), in index order.
  std::uint64_t stateHash() const noexcept;
  /// The broad phase, for drawing and statistics.
  const BroadPhase& broadPhase() const noexcept;
  /// The solver's lanes in this build: "sse2", "avx2", "neon" or "scalar" (CMake option
  /// QUACK_SIMD). Every path gives the same bits.
  static const char* simdPath() noexcept;
  /// What the solver did in the last step: colours used, constraints, and how many of them
  /// went to the overflow set (solved one at a time). docs/world.md, "The solver's data".
  struct SolverStats {
    int colors = 0;
    std::size_t constraints = 0;
    std::size_t overflow = 0;
  };
  SolverStats solverStats() const noexcept;
  /// What the continuous phase did in the last step: the bodies it found fast, and the
  /// time-of-impact searches it ran (docs/continuous.md, "In the world").
  struct ContinuousStats {
    std::size_t fastBodies = 0;
    std::size_t toiSearches = 0;
  };
  ContinuousStats continuousStats() const noexcept;
  /// The workers the step's work is spread over: WorldDef::workerCount, or fewer when the
  /// system would not start the pool's threads (a WebAssembly build without threads). The
  /// result is the same to the bit for any number (docs/world.md, "Threads").
  int workerCount() const noexcept;
  /// Checks every cross-reference: handles and free slots, each shape on its body's list and
  /// in the broad phase under its own index with its box at the body's pose, each contact's
  /// shapes live and listing it, the pair map, counts, finite body state. For tests (call it
  /// after every operation) and for debugging; costs a walk over everything.
  Status validate() const;

 private:
  explicit World(std::unique_ptr<detail::WorldState> state);
  // For the ranges: the first live body (touching contact) at or after `from`, or the
  // number of slots when none; the handle of a slot; a body's shape slots.
  std::uint32_t nextBody(std::uint32_t from) const noexcept;
  std::uint32_t nextTouchingContact(std::uint32_t from) const noexcept;
  std::uint32_t nextJoint(std::uint32_t from) const noexcept;
  JointId jointAt(std::uint32_t index) const noexcept;
  BodyId bodyAt(std::uint32_t index) const noexcept;
  ShapeId shapeAt(std::uint32_t index) const noexcept;
  ContactView contactAt(std::uint32_t index) const noexcept;
  Status checkBody(BodyId id, const char* function) const;
  Status checkShape(ShapeId id, const char* function) const;
  Status checkJoint(JointId id, const char* function) const;
  // Fails when this World was moved from, or is refusing changes after a step that failed
  // to allocate (see step()); says which call it was.
  Status checkUsable(const char* function) const;
  // The state, or an empty one that never changes when this World was moved from, so that
  // reading a moved-from World is defined.
  detail::WorldState& state() const noexcept;
  // Take the state, not the World: the deferred destruction after a step's callbacks runs on
  // the state even when a callback moved the World that owns it.
  static void destroyShapeNow(detail::WorldState& w, std::uint32_t shape);
  static void destroyBodyNow(detail::WorldState& w, std::uint32_t body);
  // Ends a step's callbacks: clears the step flags and carries out the destruction the
  // callbacks asked for, in request order.
  static void finishCallbacks(detail::WorldState& w);
  void wakeForChange(std::uint32_t body);
  bool acceptsQuery(std::uint32_t shape, const QueryFilter& filter) const;

  std::unique_ptr<detail::WorldState> s_;
};

/// A forward range over slots of a world, yielding handles by value (see World::bodies).
template <class Value, class Next, class At>
class WorldSlotIterator {
 public:
  using iterator_category = std::forward_iterator_tag;
  using value_type = Value;
  using difference_type = std::ptrdiff_t;
  using pointer = void;
  using reference = Value;
  WorldSlotIterator() = default;
  WorldSlotIterator(const World* world, std::uint32_t index) : world_(world), index_(index) {}
  Value operator*() const { return At{}(*world_, index_); }
  WorldSlotIterator& operator++() {
    index_ = Next{}(*world_, index_ + 1);
    return *this;
  }
  WorldSlotIterator operator++(int) {
    WorldSlotIterator old = *this;
    ++*this;
    return old;
  }
  friend bool operator==(const WorldSlotIterator& a, const WorldSlotIterator& b) {
    return a.index_ == b.index_;
  }

 private:
  const World* world_ = nullptr;
  std::uint32_t index_ = 0;
};

class World::BodyRange {
  struct Next {
    std::uint32_t operator()(const World& w, std::uint32_t i) const { return w.nextBody(i); }
  };
  struct At {
    BodyId operator()(const World& w, std::uint32_t i) const { return w.bodyAt(i); }
  };

 public:
  using iterator = WorldSlotIterator<BodyId, Next, At>;
  BodyRange(const World* world, std::uint32_t first, std::uint32_t end)
      : world_(world), first_(first), end_(end) {}
  iterator begin() const { return {world_, first_}; }
  iterator end() const { return {world_, end_}; }

 private:
  const World* world_;
  std::uint32_t first_, end_;
};

class World::JointRange {
  struct Next {
    std::uint32_t operator()(const World& w, std::uint32_t i) const { return w.nextJoint(i); }
  };
  struct At {
    JointId operator()(const World& w, std::uint32_t i) const { return w.jointAt(i); }
  };

 public:
  using iterator = WorldSlotIterator<JointId, Next, At>;
  JointRange(const World* world, std::uint32_t first, std::uint32_t end)
      : world_(world), first_(first), end_(end) {}
  iterator begin() const { return {world_, first_}; }
  iterator end() const { return {world_, end_}; }

 private:
  const World* world_;
  std::uint32_t first_, end_;
};

class World::ShapeRange {
 public:
  ShapeRange(const World* world, std::span<const std::uint32_t> slots)
      : world_(world), slots_(slots) {}
  class iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = ShapeId;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = ShapeId;
    iterator() = default;
    iterator(const World* w, const std::uint32_t* p) : world_(w), p_(p) {}
    ShapeId operator*() const { return world_->shapeAt(*p_); }
    iterator& operator++() {
      ++p_;
      return *this;
    }
    iterator operator++(int) {
      iterator old = *this;
      ++p_;
      return old;
    }
    friend bool operator==(const iterator& a, const iterator& b) { return a.p_ == b.p_; }

   private:
    const World* world_ = nullptr;
    const std::uint32_t* p_ = nullptr;
  };
  iterator begin() const { return {world_, slots_.data()}; }
  iterator end() const { return {world_, slots_.data() + slots_.size()}; }
  std::size_t size() const noexcept { return slots_.size(); }
  bool empty() const noexcept { return slots_.empty(); }
  ShapeId operator[](std::size_t i) const { return world_->shapeAt(slots_[i]); }

 private:
  const World* world_;
  std::span<const std::uint32_t> slots_;
};

class World::ContactRange {
  struct Next {
    std::uint32_t operator()(const World& w, std::uint32_t i) const {
      return w.nextTouchingContact(i);
    }
  };
  struct At {
    ContactView operator()(const World& w, std::uint32_t i) const { return w.contactAt(i); }
  };

 public:
  using iterator = WorldSlotIterator<ContactView, Next, At>;
  ContactRange(const World* world, std::uint32_t first, std::uint32_t end)
      : world_(world), first_(first), end_(end) {}
  iterator begin() const { return {world_, first_}; }
  iterator end() const { return {world_, end_}; }

 private:
  const World* world_;
  std::uint32_t first_, end_;
};

}  // namespace quack
