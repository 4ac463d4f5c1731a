#pragma once
// The contact solver: one part of the world. Soft contacts solved by sequential impulses
// over sub-steps, with relaxation and restitution; it reads the bodies and the touching
// contacts, writes the bodies' velocities and poses and the contacts' accumulated impulses,
// and reports hits. docs/world.md explains the choices.

#include <cstdint>
#include <vector>

#include "quack/collision/manifold.hpp"
#include "quack/math/transform.hpp"

namespace quack {
struct WorldDef;
class BroadPhase;
}  // namespace quack

namespace quack::detail {

class BodyStore;
class ContactSet;
class EventDispatcher;

// Soft-constraint coefficients for one sub-step (Catto, "Solver2D", 2024; the soft step of
// Box2D v3): a spring of `hertz` with damping ratio zeta, implicit in the sub-step h.
struct Softness {
  float biasRate = 0.0f;
  float massScale = 1.0f;
  float impulseScale = 0.0f;
};

struct ContactConstraint {
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
struct SolverBody {
  Vec2 v;
  float w = 0.0f;
  float invMass = 0.0f, invInertia = 0.0f;
  Vec2 dp;          // displacement of the centre of mass since the step began
  Rot dq;           // rotation since the step began
  float da = 0.0f;  // the same rotation as an unwrapped angle, radians
};

class Solver {
 public:
  /// One step of dt seconds in `substeps` sub-steps. Bodies whose motion would leave the
  /// world are held (StepEvents::outOfBounds).
  void solve(const WorldDef& def, BodyStore& store, ContactSet& contacts, BroadPhase& broadPhase,
             EventDispatcher& events, float dt, int substeps);

 private:
  std::vector<ContactConstraint> constraints_;
  std::vector<SolverBody> solverBodies_;
};

}  // namespace quack::detail
