#pragma once
// The 3D world's body store: bodies and shapes in slot arrays with generations (IdPool),
// mass properties from the shapes, and the shapes' boxes in the 3D broad phase. Private to
// the world layer.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "geometry_key.hpp"
#include "quack/broadphase/broad_phase3.hpp"
#include "quack/collision/sat3.hpp"
#include "quack/core/id_pool.hpp"
#include "quack/geometry/mass3.hpp"
#include "quack/world/world3.hpp"

namespace quack::detail {

struct Body3 {
  BodyType type = BodyType::dynamicBody;
  Vec3 origin;       // worldFromBody.p
  Quat rotation;     // worldFromBody.q
  Vec3 localCenter;  // centre of mass, body frame
  Vec3 center;       // centre of mass, world frame
  Vec3 linearVelocity, angularVelocity;
  float mass = 0.0f, invMass = 0.0f;
  Mat3 inertiaLocal;     // about the centre of mass, body axes
  Mat3 invInertiaLocal;  // its inverse (zero: the body does not turn)
  float linearDamping = 0.0f, angularDamping = 0.0f, gravityScale = 1.0f;
  float sleepThreshold = 0.05f;
  float sleepTime = 0.0f;  // seconds at rest
  float maxExtent = 0.0f;  // farthest shape point from the centre of mass, m
  // The thinnest of its shapes (a sphere's or capsule's radius, a hull's inscribed ball
  // about its centroid, 0 for a triangle): moving more than half of it in a step makes the
  // body fast, for continuous collision.
  float minExtent = 0.0f;
  bool enableSleep = true;
  bool awake = true;
  // Counts teleports and mass changes: a contact recycles its manifold only while both
  // bodies' counts are what they were when it was computed.
  std::uint32_t poseVersion = 0;
  std::vector<std::uint32_t> shapes;  // in creation order
  std::uint64_t userData = 0;

  Transform3 transform() const noexcept { return {origin, rotation}; }
  // Inverse inertia about the centre of mass, world axes: R I^-1 R^T.
  Mat3 invInertiaWorld() const noexcept {
    const Mat3 r = toMat3(rotation);
    return r * invInertiaLocal * transpose(r);
  }
};

// A rotation as given, made unit: scaled first by an exact power of two when its largest
// component is huge (its squared length would overflow to infinity and normalising give
// zero), and left to the bit when it is already unit to rounding, so that a rotation read
// back from a body writes back unchanged.
inline Quat unitRotation(Quat q) noexcept {
  const float largest =
      std::max(std::max(std::fabs(q.x), std::fabs(q.y)), std::max(std::fabs(q.z), std::fabs(q.w)));
  if (largest > 0x1p60f) {
    int exponent = 0;
    (void)std::frexp(largest, &exponent);
    const float scale = std::ldexp(1.0f, -exponent);
    q = {scale * q.x, scale * q.y, scale * q.z, scale * q.w};
  }
  const float n2 = dot(q, q);
  if (std::fabs(n2 - 1.0f) <= 4.0f * std::numeric_limits<float>::epsilon()) return q;
  return normalize(q);
}

// The box of a proxy placed by xf (world frame), grown by its radius.
Aabb3 proxyBox(const ShapeProxy3& proxy, Transform3 xf) noexcept;

struct Shape3 {
  std::uint32_t body = 0;
  ShapeDef3 def;
  // Shared, read-only, by every shape of this store whose geometry is the same to the bit
  // (SharedGeometries3): a pile of one hull reads one copy that stays in cache, where a
  // 3.6 KB copy per shape made each hull pair a trip to memory. Null for a free slot; a
  // sphere's placeholder when mesh is set.
  std::shared_ptr<const ShapeGeometry3> geometry;
  // A hull's SAT data (its size, inradius and vertex columns), made once with the stored
  // copy and kept as long as `geometry` is; null for the other kinds.
  const HullSatData3* hullSat = nullptr;
  std::shared_ptr<Mesh3> mesh;  // a static body's triangle mesh
  ProxyId proxy;
};

// A shape's stored geometry and, for a hull, its SAT data.
struct StoredGeometry3 {
  std::shared_ptr<const ShapeGeometry3> geometry;
  const HullSatData3* hullSat = nullptr;  // lives as long as geometry; null but for hulls
};

// Shapes' geometries, stored once for all the shapes whose bytes are equal (every used
// field, bit for bit): a pile of one hull reads one copy, and validates it once.
class SharedGeometries3 {
 public:
  // The stored copy of `geometry`: the one already held when one is equal, else a new one,
  // made only if `validate` passes it (its error returned as it is). Sharing changes no
  // result: a stored geometry is never written.
  Result<StoredGeometry3> intern(const ShapeGeometry3& geometry,
                                 Status (*validate)(const ShapeGeometry3&));

 private:
  struct Hull {
    ShapeGeometry3 geometry;
    HullSatData3 sat;
  };
  // Hulls by their bytes (the other kinds are small: each shape gets its own).
  InternTable<Hull> hulls_;
};

class BodyStore3 {
 public:
  explicit BodyStore3(BroadPhase3 broadPhase) : broadPhase_(std::move(broadPhase)) {}

  std::uint32_t addBody(const BodyDef3& def);
  // Removes the body's shapes' proxies and the body (the caller removes the contacts first).
  void removeBody(std::uint32_t body);
  // Adds a shape (validated by the caller) and recomputes the body's mass. Fails only when
  // the broad phase refuses its box (beyond kMaxCoordinate).
  Result<std::uint32_t> addShape(std::uint32_t body, const ShapeDef3& def, StoredGeometry3 geometry,
                                 std::shared_ptr<Mesh3> mesh);
  void removeShape(std::uint32_t shape);

  // The body's origin from its centre of mass and rotation, after the solver moved it.
  static void syncOrigin(Body3& body) noexcept {
    body.origin = body.center - rotate(body.rotation, body.localCenter);
  }
  // Moves the body's proxies to its present pose (displacement: its centre's motion).
  void moveProxies(std::uint32_t body, Vec3 displacement);
  // Moves one shape's proxy to `box` (its shapeBox at the body's present pose).
  void moveProxy(std::uint32_t shape, const Aabb3& box, Vec3 displacement);
  // The shape's box, world frame, at the body's present pose (or at worldFromBody).
  Aabb3 shapeBox(std::uint32_t shape) const;
  Aabb3 shapeBox(std::uint32_t shape, Transform3 worldFromBody) const;

  SharedGeometries3 geometries;

  IdPool bodyIds, shapeIds;
  std::vector<Body3> bodies;
  std::vector<Shape3> shapes;
  BroadPhase3& broadPhase() noexcept { return broadPhase_; }
  const BroadPhase3& broadPhase() const noexcept { return broadPhase_; }

 private:
  void updateMass(std::uint32_t body);
  BroadPhase3 broadPhase_;
  struct MassMemo {
    std::shared_ptr<const ShapeGeometry3> geometry;
    float density = 0.0f;
    MassProperties3 mass;
  } massMemo_;
};

}  // namespace quack::detail
