#pragma once
// The body store: one part of the world (docs/ARCHITECTURE.md, "The world inside"). It owns
// the records of bodies and shapes, their handles (IdPool) and their mass properties; it
// knows nothing of contacts, the solver or events.

#include <cstdint>
#include <memory>
#include <vector>

#include "geometry_key.hpp"
#include "ghost_edges.hpp"
#include "quack/broadphase/broad_phase.hpp"
#include "quack/core/id_pool.hpp"
#include "quack/geometry/mass.hpp"
#include "quack/math/transform.hpp"
#include "quack/world/types.hpp"
#include "quack/world/world.hpp"  // kMaxLinearSpeed

namespace quack::detail {

// `v` shortened to kMaxLinearSpeed if it is faster. Components are clamped first, so even
// an infinite component gives a finite result. The solver and the continuous phase's
// impacts both hold bodies to the limit with it.
inline Vec2 clampSpeed(Vec2 v) {
  constexpr float kMaxSquared = kMaxLinearSpeed * kMaxLinearSpeed;
  if (dot(v, v) <= kMaxSquared) return v;
  v = {clampf(v.x, -kMaxLinearSpeed, kMaxLinearSpeed),
       clampf(v.y, -kMaxLinearSpeed, kMaxLinearSpeed)};
  return (kMaxLinearSpeed / length(v)) * v;
}

struct Body {
  BodyType type = BodyType::dynamicBody;
  bool pendingDestroy = false;
  Transform xf;      // worldFromBody
  Vec2 center;       // centre of mass, world frame
  Vec2 localCenter;  // centre of mass, body frame
  Vec2 v;            // velocity of the centre of mass
  float w = 0.0f;
  Vec2 force;           // applied through the next step (applyForce), then cleared
  float torque = 0.0f;  // likewise (applyTorque)
  float mass = 0.0f, invMass = 0.0f, inertia = 0.0f, invInertia = 0.0f;
  float linearDamping = 0.0f, angularDamping = 0.0f, gravityScale = 1.0f;
  bool bullet = false;
  // Continuous collision: the body's size (from updateMass) and its motion in this step.
  float minExtent = 0.0f;  // smallest half-thickness of its shapes, metres
  float maxExtent = 0.0f;  // largest distance from the centre of mass to a surface, metres
  bool fast = false;       // moved more than kCcdFastFraction of minExtent in this step
  Vec2 startCenter;        // centre of mass at the start of the step (when fast)
  float startAngle = 0.0f, endAngle = 0.0f;  // radians, unwrapped (when fast)
  // Sleeping (islands.hpp). Static bodies are never awake; kinematic ones are awake while
  // they move.
  bool awake = true;
  bool enableSleep = true;
  float sleepThreshold = 0.05f;
  float sleepTime = 0.0f;              // seconds at rest
  std::uint32_t island = 0xffffffffu;  // dynamic bodies only (kNoIsland otherwise)
  std::uint64_t userData = 0;
  std::vector<std::uint32_t> shapes;  // in creation order
};

// Shapes' geometries, stored once for all the shapes whose bytes are equal (every used
// field, bit for bit). A polygon is about 1 KB (room for kMaxPolygonVertices vertices and
// normals): a copy per shape made the shape records too big to stay in cache, and building a
// pile validated each copy. The other kinds are small: each shape gets its own.
class SharedGeometries {
 public:
  // The stored copy of `geometry`: the one already held when one is equal, else a new one,
  // made only if `validate` passes it (its error returned as it is). Sharing changes no
  // result: a stored geometry is never written.
  Result<std::shared_ptr<const ShapeGeometry>> intern(const ShapeGeometry& geometry,
                                                      Status (*validate)(const ShapeGeometry&));

 private:
  InternTable<ShapeGeometry> polygons_;
};

struct Shape {
  bool pendingDestroy = false;
  std::uint32_t body = 0;
  // Shared, read-only (SharedGeometries); null for a free slot.
  std::shared_ptr<const ShapeGeometry> geometry;
  ShapeDef def;
  ProxyId proxy;
  std::vector<std::uint32_t> contacts;  // indices into the contact set
  StaticEdges edges;
};

struct BodyMass;

class BodyStore {
 public:
  explicit BodyStore(std::uint32_t worldId) : worldId_(worldId) {}

  std::vector<Body> bodies;  // indexed by BodyId::index; live where bodyIds.isAlive
  std::vector<Shape> shapes;
  IdPool bodyIds, shapeIds;

  std::uint32_t worldId() const noexcept { return worldId_; }
  bool bodyAlive(std::uint32_t i) const noexcept { return bodyIds.isAlive(i); }
  bool shapeAlive(std::uint32_t i) const noexcept { return shapeIds.isAlive(i); }
  bool isValid(BodyId id) const noexcept {
    return id.world == worldId_ && bodyIds.isValid(id.index, id.generation);
  }
  bool isValid(ShapeId id) const noexcept {
    return id.world == worldId_ && shapeIds.isValid(id.index, id.generation);
  }
  BodyId bodyId(std::uint32_t i) const noexcept { return {i, bodyIds.generation(i), worldId_}; }
  ShapeId shapeId(std::uint32_t i) const noexcept { return {i, shapeIds.generation(i), worldId_}; }

  /// A new body record (checked by the caller), slot reused last-in first-out.
  std::uint32_t createBody(const BodyDef& def);
  /// A new shape record on `body`; its proxy is set by the caller. `mass`: the body's mass
  /// with the new shape, when the caller has summed it already (sumMass over the shapes in
  /// order, the new one last), so that it is not summed twice.
  std::uint32_t createShape(std::uint32_t body, const ShapeDef& def,
                            std::shared_ptr<const ShapeGeometry> g, const BodyMass* mass = nullptr);
  SharedGeometries geometries;
  /// Frees the slot (the caller has removed the shape's contacts and proxy).
  void releaseShape(std::uint32_t shape);
  void releaseBody(std::uint32_t body);

  /// Mass, centre of mass, inertia and the sizes continuous collision uses, from the shapes
  /// (the mass from `mass` when given: sumMass over them, already done).
  void updateMass(std::uint32_t body, const BodyMass* mass = nullptr);
  // Grows the body's continuous-collision extents by one more shape.
  static void addExtents(Body& b, const ShapeGeometry& g);
  /// True when every shape of `body`, placed by `worldFromBody`, lies within the broad
  /// phase's range (kMaxCoordinate): the edge of the world.
  bool shapesWithinWorld(std::uint32_t body, Transform worldFromBody) const;
  /// Moves the body's proxies to its present pose (callers keep it within the world).
  void updateShapeBoxes(BroadPhase& broadPhase, std::uint32_t body, Vec2 displacement) const;
  /// Puts the body at `worldFromBody` (centre of mass `center`) and moves its proxies, unless
  /// a shape would leave the world: then nothing changes and it returns false. Each shape's
  /// box is computed once (the step's hot path: one shape per body is the common case).
  bool moveBody(BroadPhase& broadPhase, std::uint32_t body, Transform worldFromBody, Vec2 center,
                Vec2 displacement);
  /// moveBody in parts, for the step's workers. placeBody touches only the body (and so may
  /// run for many bodies at once): it puts it at the pose unless a shape would leave the
  /// world, and gives the box of a one-shape body. placeProxy (also for many bodies at once)
  /// gives a one-shape body's proxy its box when no re-insertion is needed, and returns
  /// true when followBody must still run. followBody moves the proxies (one thread).
  bool placeBody(std::uint32_t body, Transform worldFromBody, Vec2 center, Aabb& box);
  bool placeProxy(BroadPhase& broadPhase, std::uint32_t body, const Aabb& box,
                  Vec2 displacement) const;
  void followBody(BroadPhase& broadPhase, std::uint32_t body, const Aabb& box,
                  Vec2 displacement) const;

 private:
  std::uint32_t worldId_;
};

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
  // The first shapes' properties are kept for the second pass (the inertia about the
  // centre of mass) rather than computed again: a rounded polygon's take an arc tangent
  // and a sine a corner, and building a world of boxes spent a sixth of its
  // instructions here.
  constexpr int kKept = 8;
  MassProperties kept[kKept];
  int count = 0;
  each([&](const ShapeGeometry& g, float density) {
    const MassProperties m = computeMass(g, density);
    if (count < kKept) kept[count] = m;
    ++count;
    out.mass += m.mass;
    moment += m.mass * m.centroid;
  });
  if (out.mass > 0.0f) {
    out.localCenter = (1.0f / out.mass) * moment;
    int k = 0;
    each([&](const ShapeGeometry& g, float density) {
      const MassProperties m = k < kKept ? kept[k] : computeMass(g, density);
      ++k;
      out.inertia += m.inertia + m.mass * distanceSquared(m.centroid, out.localCenter);
    });
  }
  return out;
}

}  // namespace quack::detail
