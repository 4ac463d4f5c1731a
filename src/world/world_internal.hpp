#pragma once
// The world's private records, shared by world.cpp (bookkeeping, events, queries) and
// solver.cpp (the contact solver).

#include <vector>

#include "quack/collision/proxy.hpp"
#include "quack/math/sweep.hpp"
#include "quack/world/world.hpp"

namespace quack {

struct World::Body {
  BodyType type = BodyType::dynamicBody;
  std::uint32_t generation = 0;
  bool alive = false;
  bool pendingDestroy = false;
  Transform xf;      // worldFromBody
  Vec2 center;       // centre of mass, world frame
  Vec2 localCenter;  // centre of mass, body frame
  Vec2 v;            // velocity of the centre of mass
  float w = 0.0f;
  float mass = 0.0f, invMass = 0.0f, inertia = 0.0f, invInertia = 0.0f;
  float linearDamping = 0.0f, angularDamping = 0.0f, gravityScale = 1.0f;
  bool bullet = false;
  // Continuous collision: the body's size (from updateMass) and its motion in this step.
  float minExtent = 0.0f;  // smallest half-thickness of its shapes, metres
  float maxExtent = 0.0f;  // largest distance from the centre of mass to a surface, metres
  bool fast = false;       // moved more than kCcdFastFraction of minExtent in this step
  Vec2 startCenter;        // centre of mass at the start of the step (when fast)
  float startAngle = 0.0f, endAngle = 0.0f;  // radians, unwrapped (when fast)
  std::uint64_t userData = 0;
  std::vector<std::uint32_t> shapes;
};

// What a static shape knows about its neighbours, for ghost-collision removal (edges.cpp).
// Shape frame. Vertex i of a polygon joins edge i - 1 and edge i; a chain segment has
// vertices 0 (p1) and 1 (p2) and one edge.
struct EdgeCone {
  enum class Kind : std::uint8_t {
    natural,  // no correction at this vertex
    range,    // normals from `lo` counter-clockwise to `hi` (lo == hi: one normal)
    snap,     // a reflex corner of the union: the nearer of `lo` and `hi`
    inside,   // the vertex is inside the union of flush shapes: contacts here are ghosts
  };
  Kind kind = Kind::natural;
  Vec2 lo, hi;
};

// The part of edge `edge` from t0 to t1 metres along it that lies flush against an
// opposite edge of another static shape: inside the union, so no contact belongs there.
struct CoveredSpan {
  int edge = 0;
  float t0 = 0.0f, t1 = 0.0f;
};

struct StaticEdges {
  bool active = false;               // contacts with this shape go through removeGhostContacts
  std::vector<CoveredSpan> covered;  // internal (parts of) edges
  std::vector<EdgeCone> cones;       // per vertex
  // Chains: the segment pushes only along `normal` (right of p1 -> p2); ghost vertices.
  bool chain = false;
  bool hasPrev = false, hasNext = false;
  Vec2 prev, next;  // the neighbouring chain points before p1 and after p2
};

struct World::Shape {
  std::uint32_t generation = 0;
  bool alive = false;
  bool pendingDestroy = false;
  std::uint32_t body = 0;
  ShapeGeometry geometry;
  ShapeDef def;
  ProxyId proxy;
  std::vector<std::uint32_t> contacts;
  StaticEdges edges;
};

struct World::Contact {
  bool alive = false;
  bool touching = false;
  bool sensor = false;  // shapeA is the sensor
  std::uint32_t shapeA = 0, shapeB = 0;
  ManifoldFn fn = nullptr;
  float friction = 0.0f, restitution = 0.0f;
  Manifold manifold;
  // Accumulated impulses of the manifold points, for warm starting (matched by id).
  float normalImpulse[kMaxManifoldPoints] = {};
  float tangentImpulse[kMaxManifoldPoints] = {};
};

// Soft-constraint coefficients for one sub-step (Catto, "Solver2D", 2024; the soft step of
// Box2D v3): a spring of `hertz` with damping ratio zeta, implicit in the sub-step h.
struct Softness {
  float biasRate = 0.0f;
  float massScale = 1.0f;
  float impulseScale = 0.0f;
};

struct World::ContactConstraint {
  struct Point {
    Vec2 rA, rB;                  // anchors from each centre of mass, world axes
    float baseSeparation = 0.0f;  // separation minus the anchors' offset along the normal
    float normalImpulse = 0.0f, tangentImpulse = 0.0f, maxNormalImpulse = 0.0f;
    float normalMass = 0.0f, tangentMass = 0.0f;
    float relativeVelocity = 0.0f;  // normal velocity before the step (for restitution)
  };
  std::uint32_t contact = 0;
  std::uint32_t bodyA = 0, bodyB = 0;
  Vec2 normal;
  float friction = 0.0f, restitution = 0.0f;
  Softness softness;
  int pointCount = 0;
  Point points[kMaxManifoldPoints];
};

// Per-body state of the solver, indexed like the world's bodies.
struct World::SolverBody {
  Vec2 v;
  float w = 0.0f;
  float invMass = 0.0f, invInertia = 0.0f;
  Vec2 dp;          // displacement of the centre of mass since the step began
  Rot dq;           // rotation since the step began
  float da = 0.0f;  // the same rotation as an unwrapped angle, radians
};

// One fast body in the continuous phase: what remains of its motion is `sweep`, which
// covers the step's fractions [t0, 1].
struct World::FastBody {
  std::uint32_t body = 0;
  Sweep sweep;
  float t0 = 0.0f;
  int events = 0;
  std::uint32_t stamp = 0;  // bumped whenever the sweep changes; older queue entries are stale
  Aabb box;                 // sweptBox of the sweep
  float bestTime = 2.0f;    // time of its queued impact (2: none)
  std::uint32_t bestBody = 0xffffffffu;  // the body that impact is with
};

// The earliest impact found along a fast body's sweep.
struct World::ToiCandidate {
  float time = 0.0f;  // fraction of the step
  std::uint32_t fast = 0, stamp = 0;
  std::uint32_t shapeA = 0, shapeB = 0;  // fast body's shape, the other
  Vec2 point, normal;
  bool stop = false;  // already touching at the start of a continued sweep: stop there
};

struct World::Callback {
  enum class Kind { begin, end, hit, sensorBegin, sensorEnd };
  Kind kind;
  std::uint64_t categoriesA, categoriesB;
  ContactCallback contact;
  HitCallback hit;
};

// The support proxy of any geometry (views a polygon: keep the geometry alive and still).
inline ShapeProxy proxyOf(const ShapeGeometry& g) {
  return std::visit([](const auto& s) { return makeProxy(s); }, g);
}
inline ShapeRef refOf(const ShapeGeometry& g) {
  return std::visit([](const auto& s) { return ShapeRef(s); }, g);
}

}  // namespace quack
