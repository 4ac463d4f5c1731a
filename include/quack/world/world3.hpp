#pragma once
/// `World3`: the 3D rigid-body world. Bodies carry convex shapes (sphere, capsule, box and
/// convex hull from shapes3.hpp; triangles) or, on static bodies, triangle meshes
/// (mesh3.hpp); they fall, collide, stack, slide, roll and fall asleep. It is built as the 2D
/// `World` is (docs/world3.md): a thin facade over parts with one job each (a body store, a
/// contact set, a soft-step solver, islands), in `src/world/*3.*`.
///
/// ```
/// World3 world = World3::create().value();
/// BodyId3 ground = world.createBody({.type = BodyType::staticBody}).value();
/// world.createShape(ground, {}, makeBox3({10, 0.5f, 10}).value()).value();
/// BodyId3 ball = world.createBody({.position = {0, 2, 0}}).value();
/// world.createShape(ball, {.density = 1000}, Sphere{{}, 0.25f}).value();
/// for (int i = 0; i < 60; ++i) world.step();
/// Vec3 where = world.position(ball);
/// ```
///
/// It has continuous collision, queries, snapshots, contact callbacks, and a solver that
/// runs by colour in SIMD lanes on any number of workers with the same bits. What it does
/// not do yet (docs/world3.md, "Not yet"): joints, sensors, ghost-collision removal between
/// separate convex shapes (a mesh's triangles have it).
///
/// Units: metres, kilograms, seconds, radians; world frame, y up. Every input is checked at
/// this boundary: a bad one fails with a message naming the field, and nothing changes.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "quack/broadphase/proxy.hpp"
#include "quack/collision/manifold3.hpp"
#include "quack/collision/mesh3.hpp"
#include "quack/geometry/shapes3.hpp"
#include "quack/math/quat.hpp"
#include "quack/world/tasks.hpp"
#include "quack/world/types.hpp"

namespace quack {

namespace detail {
struct WorldState3;
}

/// Handle to a body of a `World3`: slot index, the slot's generation when it was made (a
/// handle kept after the body was destroyed is refused), and the id of its world (a handle
/// given to another world is refused). The default handle is null.
struct BodyId3 {
  std::uint32_t index = 0xffffffffu;
  std::uint32_t generation = 0;
  std::uint32_t world = 0;  ///< World3::id() of its world; 0: none
  friend constexpr bool operator==(BodyId3, BodyId3) noexcept = default;
};

/// Handle to a shape on a body of a `World3`, as BodyId3.
struct ShapeId3 {
  std::uint32_t index = 0xffffffffu;
  std::uint32_t generation = 0;
  std::uint32_t world = 0;  ///< World3::id() of its world; 0: none
  friend constexpr bool operator==(ShapeId3, ShapeId3) noexcept = default;
};

/// How a `World3` is made. The defaults are the 2D world's (docs/world.md), which suit
/// bodies of about 0.1 to 10 m.
struct WorldDef3 {
  Vec3 gravity{0.0f, -10.0f, 0.0f};  ///< m/s^2, each component within kMaxGravity
  float timeStep = 1.0f / 60.0f;     ///< seconds per step() without arguments, in (0, kMaxTimeStep]
  int substeps = 4;                  ///< solver sub-steps per step, 1..64
  /// Contact stiffness (Hz, > 0) and damping ratio (>= 0) of the soft step; the stiffness
  /// is capped at a quarter of the sub-step rate.
  float contactHertz = 30.0f;
  float contactDampingRatio = 10.0f;
  /// Fastest speed (m/s, > 0) at which overlapping shapes are pushed apart.
  float contactPushMaxSpeed = 3.0f;
  /// Restitution acts only when the bodies approach faster than this (m/s, >= 0).
  float restitutionThreshold = 1.0f;
  /// Contact points are made this far (m, in [0, 1]) before the shapes touch.
  float speculativeDistance = kSpeculativeDistance;
  /// Broad-phase margin (m, >= speculativeDistance): the fat boxes' growth.
  float aabbMargin = 0.1f;
  /// A resting pair of flat shapes (hulls and boxes, on each other or on a mesh) keeps its
  /// manifold while the bodies' relative pose stays within this (m, in [0, 1]; 0: a new
  /// manifold every step), as the 2D world does (docs/world3.md, "Contact recycling").
  float contactRecycleDistance = 10.0f * kLinearSlop;  // the 2D kContactRecycleDistance
  /// Continuous collision: a body that moves more than half its thinnest shape in a step
  /// is stopped at the first static shape, mesh or slower body in its way (docs/world3.md).
  /// Off gives the discrete solver alone, whose speculative contacts reach at most 1 m.
  bool enableContinuous = true;
  bool enableSleep = true;
  /// Solve contacts with the portable one-lane path even where the build has SIMD lanes
  /// (QUACK_SIMD). The answer is the same to the bit (docs/world3.md, "Colours, lanes and
  /// workers"); this is for tests and for measuring what the lanes buy.
  bool scalarSolver = false;
  /// Threads, as the 2D world's (WorldDef::workerCount, docs/world.md, "Threads"): how many
  /// workers run a step, 1..kMaxWorkers; with enqueueTask and finishTask (both or neither)
  /// the game's job system runs them, without, a pool of workerCount - 1 threads owned by
  /// the world. The same bits whatever the count. Not part of a snapshot: restore keeps the
  /// world's own, fromSnapshot runs on one worker.
  int workerCount = 1;
  EnqueueTaskFn enqueueTask = nullptr;
  FinishTaskFn finishTask = nullptr;
  void* userTaskContext = nullptr;  ///< passed to enqueueTask and finishTask
};

/// A new body. World frame.
struct BodyDef3 {
  BodyType type = BodyType::dynamicBody;
  Vec3 position;                ///< origin of the body frame
  Quat rotation;                ///< worldFromBody's rotation; any non-zero quaternion (normalised)
  Vec3 linearVelocity;          ///< of the centre of mass, m/s
  Vec3 angularVelocity;         ///< rad/s, world axes
  float linearDamping = 0.0f;   ///< 1/s, >= 0
  float angularDamping = 0.0f;  ///< 1/s, >= 0
  float gravityScale = 1.0f;    ///< within kMaxGravityScale
  /// May this body fall asleep? A body that may not keeps every body it touches awake.
  bool enableSleep = true;
  /// Below this speed (m/s, >= 0) the body rests: its centre's speed, and its angular speed
  /// times its largest extent from the centre of mass.
  float sleepThreshold = 0.05f;
  std::uint64_t userData = 0;
};

/// A new shape on a body.
struct ShapeDef3 {
  float density = 1.0f;      ///< kg/m^3, >= 0
  float friction = 0.6f;     ///< Coulomb coefficient, >= 0; a pair uses sqrt(fa fb)
  float restitution = 0.0f;  ///< in [0, kMaxRestitution]; a pair uses the larger
  /// Rolling resistance (dimensionless, >= 0; a pair uses the larger): a rolling sphere or
  /// capsule is slowed by a torque of at most this times the normal force times its radius.
  float rollingResistance = 0.0f;
  Filter filter;
  std::uint64_t userData = 0;
};

/// Two shapes started touching (their contact gained points), or stopped (lost them, or a
/// shape was destroyed). A is the lower shape index, or the mesh.
struct ContactEvent3 {
  ShapeId3 shapeA, shapeB;
  /// The shapes' filter categories when the event happened (so that a callback can match an
  /// end event whose shape is already destroyed).
  std::uint64_t categoryA = 0, categoryB = 0;
};

/// The events of one step.
struct StepEvents3 {
  std::vector<ContactEvent3> begin;
  std::vector<ContactEvent3> end;
};

/// One touching contact (World3::touchingContacts): shape A, shape B and its manifolds
/// (one for two convex shapes; one per touching triangle when A is a mesh). World frame,
/// normals from A to B.
struct ContactView3 {
  ShapeId3 shapeA, shapeB;
  std::vector<Manifold3> manifolds;
};

/// The 3D snapshot format's version: snapshots of another version are refused by name.
/// Bumped whenever the layout, or the arithmetic of a step, changes.
inline constexpr std::uint32_t kSnapshot3FormatVersion = 1;

/// The first shape a World3 ray cast entered. World frame.
struct RayHitResult3 {
  ShapeId3 shape;
  BodyId3 body;
  Vec3 point;
  Vec3 normal;         ///< unit, outward from the shape (a mesh: its triangle's face normal)
  float fraction = 0;  ///< along the ray's translation
  int triangle = -1;   ///< the mesh triangle entered, or -1
};

/// A shape a World3 overlap query met, and how to get the query shape out of it.
struct ShapeOverlap3 {
  ShapeId3 shape;
  BodyId3 body;
  float depth = 0.0f;  ///< metres, >= 0
  /// Move the query shape by this (world frame, metres) to separate it from `shape`.
  Vec3 depenetration;
};

/// The first shape a World3 shape cast met. World frame.
struct ShapeCastResult3 {
  ShapeId3 shape;
  BodyId3 body;
  Vec3 point;          ///< on the shape met, where the cast shape touches it
  Vec3 normal;         ///< unit, from the shape met towards the cast shape
  float fraction = 0;  ///< of the translation; 0 when the cast shape starts overlapping
};

/// The 3D world (see the top of this file). Move-only.
class World3 {
 public:
  /// Fails on a bad WorldDef3 field, naming it.
  static Result<World3> create(const WorldDef3& def = {});
  World3(World3&&) noexcept;
  World3& operator=(World3&&) noexcept;
  World3(const World3&) = delete;
  World3& operator=(const World3&) = delete;
  ~World3();

  const WorldDef3& def() const noexcept;
  /// Unique in the process (shared with the 2D worlds' ids), never 0.
  std::uint32_t id() const noexcept;

  // ---- bodies and shapes ---------------------------------------------------------------
  Result<BodyId3> createBody(const BodyDef3& def);
  /// Destroys the body, its shapes and their contacts (end events for touching ones in the
  /// next step's events).
  Status destroyBody(BodyId3 body);
  /// A convex shape (or a triangle), in the body frame, checked by validateShape. The body's
  /// mass, centre of mass and inertia are recomputed from all its shapes.
  Result<ShapeId3> createShape(BodyId3 body, const ShapeDef3& def, const ShapeGeometry3& geometry);
  /// A triangle mesh, in the body frame: static bodies only (a mesh has no volume).
  Result<ShapeId3> createShape(BodyId3 body, const ShapeDef3& def, Mesh3 mesh);
  Status destroyShape(ShapeId3 shape);

  bool isValid(BodyId3 body) const noexcept;
  bool isValid(ShapeId3 shape) const noexcept;
  std::size_t bodyCount() const noexcept;
  std::size_t shapeCount() const noexcept;
  /// Contacts: pairs of shapes whose fat boxes overlap; touching ones have points.
  std::size_t contactCount() const noexcept;
  std::size_t touchingContactCount() const noexcept;
  std::size_t awakeBodyCount() const noexcept;
  /// Every touching contact, in contact order (allocates).
  std::vector<ContactView3> touchingContacts() const;

  // ---- body state ------------------------------------------------------------------------
  // A null, stale or foreign handle is caught in every build: getters then return a neutral
  // value (zeros, the identity), setters fail with a message.
  BodyType bodyType(BodyId3 body) const;
  bool isAwake(BodyId3 body) const;
  Transform3 transform(BodyId3 body) const;  ///< worldFromBody
  Vec3 position(BodyId3 body) const;         ///< of the body origin
  Quat rotation(BodyId3 body) const;
  Vec3 linearVelocity(BodyId3 body) const;   ///< of the centre of mass, m/s
  Vec3 angularVelocity(BodyId3 body) const;  ///< rad/s, world axes
  float mass(BodyId3 body) const;
  /// Inertia tensor about the centre of mass, world axes, kg m^2.
  Mat3 inertia(BodyId3 body) const;
  Vec3 worldCenterOfMass(BodyId3 body) const;
  std::uint64_t userData(BodyId3 body) const;
  BodyId3 body(ShapeId3 shape) const;

  // Each wakes the body; a static body cannot be given a velocity or an impulse.
  Status setTransform(BodyId3 body, Vec3 position, Quat rotation);
  Status setLinearVelocity(BodyId3 body, Vec3 velocity);
  Status setAngularVelocity(BodyId3 body, Vec3 velocity);
  /// An impulse (N s) at a world point: changes both velocities of a dynamic body.
  Status applyLinearImpulse(BodyId3 body, Vec3 impulse, Vec3 worldPoint);
  Status setAwake(BodyId3 body, bool awake);

  // ---- stepping ------------------------------------------------------------------------
  /// One step of def().timeStep in def().substeps sub-steps.
  Status step();
  /// One step of `dt` seconds in (0, kMaxTimeStep], in `substeps` sub-steps (1..64).
  Status step(float dt, int substeps);

  // ---- snapshots (docs/world3.md, "Snapshots") ------------------------------------------
  /// The world's whole state as bytes (bodies, shapes with their geometry, contacts with
  /// their manifolds, warm-start impulses and recycling caches, the broad phase's records,
  /// the last step's events): a world restored from them steps on to the same bits as this
  /// one.
  std::vector<std::uint8_t> snapshot() const;
  /// Puts the world back in the state a snapshot saved. Handles valid when the snapshot was
  /// taken are valid again, with this world's id. Refused, with a message naming what is
  /// wrong, and leaving the world unchanged: bytes that are not a 3D snapshot, of another
  /// format version, truncated or corrupted (checksum), or contents that fail the checks.
  Status restore(std::span<const std::uint8_t> bytes);
  /// A new world (a new id) from a snapshot; refused as restore is.
  static Result<World3> fromSnapshot(std::span<const std::uint8_t> bytes);

  // ---- queries (world frame; every shape, awake or asleep; QueryFilter as in 2D) --------
  /// The first shape the ray `origin + t translation`, t in [0, 1], enters (a mesh from its
  /// triangles' fronts only); ties go to the lower shape index. Nothing for a zero or
  /// non-finite translation.
  std::optional<RayHitResult3> rayCastClosest(Vec3 origin, Vec3 translation,
                                              QueryFilter filter = {}) const;
  /// Every shape the ray enters, by fraction (ties: lower shape index).
  std::vector<RayHitResult3> rayCastAll(Vec3 origin, Vec3 translation,
                                        QueryFilter filter = {}) const;
  /// Shapes whose bounding boxes overlap `box`, by shape index.
  std::vector<ShapeId3> overlapAabb(Aabb3 box, QueryFilter filter = {}) const;
  /// Shapes that overlap `geometry` placed by `worldFromShape`, by shape index, each with
  /// the depenetration of the query shape (EPA; a mesh: its deepest triangle). Errors: a
  /// bad geometry or a non-finite transform.
  Result<std::vector<ShapeOverlap3>> overlapShape(const ShapeGeometry3& geometry,
                                                  Transform3 worldFromShape,
                                                  QueryFilter filter = {}) const;
  /// Sweeps `geometry` from `worldFromShape` along `translation` (metres) and returns the
  /// first shape it meets (lowest fraction; ties: lower shape index), if any. A shape the
  /// cast starts overlapping is met at fraction 0. Errors: non-finite input, a bad geometry.
  Result<std::optional<ShapeCastResult3>> castShape(const ShapeGeometry3& geometry,
                                                    Transform3 worldFromShape, Vec3 translation,
                                                    QueryFilter filter = {}) const;
  const StepEvents3& events() const noexcept;

  // ---- callbacks (called at the end of each step, in event order) -----------------------
  /// A callback runs for an event whose first shape has a category in `categoriesA` and
  /// whose second has one in `categoriesB` (tried both ways round; the shapes are passed in
  /// the matching order), as the 2D world's do. Inside a callback the world may be read and
  /// changed (bodies created, destroyed, pushed), but not stepped; a callback registered
  /// from inside one runs from the next step. Snapshots do not hold callbacks: a restored
  /// world keeps its own.
  using ContactCallback3 = std::function<void(World3&, ShapeId3 a, ShapeId3 b)>;
  void onContactBegin(std::uint64_t categoriesA, std::uint64_t categoriesB, ContactCallback3 f);
  void onContactEnd(std::uint64_t categoriesA, std::uint64_t categoriesB, ContactCallback3 f);
  std::uint64_t stepCount() const noexcept;
  /// What the solver did in the last step: colours used, manifolds solved, and how many of
  /// them went to the overflow set (solved one at a time). docs/world3.md, "Colours, lanes
  /// and workers".
  struct SolverStats {
    int colors = 0;
    std::size_t constraints = 0;
    std::size_t overflow = 0;
  };
  SolverStats solverStats() const noexcept;
  /// The workers the step's work is spread over (WorldDef3::workerCount, or fewer when the
  /// system would not start the pool's threads). The same bits for any number.
  int workerCount() const noexcept;

 private:
  explicit World3(std::unique_ptr<detail::WorldState3> state);
  void dispatchCallbacks();
  std::unique_ptr<detail::WorldState3> state_;
};

}  // namespace quack
