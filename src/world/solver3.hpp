#pragma once
// The 3D world's contact solver: the soft step (Catto, "Solver2D", 2024, and Box2D v3's
// solver, read for understanding): per step, prepare each touching manifold once (anchors
// from the centres of mass, effective masses, the base separation); then per sub-step
// integrate velocities, warm start, solve with a soft push (bias), integrate positions, and
// relax (solve again without the push); after the sub-steps, restitution; then store the
// impulses for the next step's warm start. Friction along two tangents, clamped to the
// Coulomb circle of each point; rolling resistance on the relative angular velocity.
//
// Scalar and single-threaded: constraints are solved one after another in contact order
// (Gauss-Seidel), without the 2D solver's graph colouring and SIMD lanes (docs/world3.md).

#include <cstdint>
#include <vector>

#include "contact_set3.hpp"
#include "quack/world/world.hpp"
#include "solver.hpp"

namespace quack::detail {

// A body's state while the solver runs. Slot 0 is a resting body that static and sleeping
// bodies read: no mass, no velocity, never moved.
struct BodyState3 {
  Vec3 v, w;
  Vec3 dp;     // motion of the centre of mass since the step began
  Quat q, q0;  // rotation now, and at the start of the step
  float invMass = 0.0f;
  Mat3 invI;  // world axes, fixed over the step (as Box2D v3 keeps its inertia)
};

// One direction of a point's constraint (the normal or a tangent d), prepared once a step:
// the arms crossed with d, and the angular responses I^-1 (r x d). A relative velocity along
// d is then dot(vB - vA, d) + dot(wB, rB x d) - dot(wA, rA x d), and an impulse of size p
// along d changes wA by -p I_A^-1 (rA x d) and wB by +p I_B^-1 (rB x d): no cross product
// or matrix product inside the iterations (the arms stay fixed over the step).
struct Axis3 {
  Vec3 crossA, crossB;      // rA x d, rB x d
  Vec3 angularA, angularB;  // I_A^-1 (rA x d), I_B^-1 (rB x d)
};

struct PointConstraint3 {
  Axis3 normal;
  float separation = 0.0f;  // as the manifold has it, at the start of the step
  float normalMass = 0.0f;
  float normalImpulse = 0.0f;
  float maxNormalImpulse = 0.0f;
  float relativeVelocity = 0.0f;  // normal velocity before the step (restitution)
  float lever = 0.0f;             // distance from the manifold's centre (twist friction)
};

struct Constraint3 {
  ContactManifold3* source = nullptr;
  std::uint32_t slotA = 0, slotB = 0;
  Vec3 normal, t1, t2;
  float friction = 0.0f, restitution = 0.0f, rolling = 0.0f;
  Softness soft;
  // Friction at the manifold's centre along the two tangents, and about the normal (twist),
  // limited by friction times the points' total normal impulse (and times each point's
  // lever arm for the twist), as Box3D's contact solver does (read for understanding).
  Axis3 tangent[2];
  float tangentMass[2] = {};
  float tangentImpulse[2] = {};
  Vec3 twistA, twistB;  // I_A^-1 n, I_B^-1 n
  float twistMass = 0.0f;
  float twistImpulse = 0.0f;
  Mat3 rollingMass;
  Vec3 rollingImpulse;
  PointConstraint3 points[kMaxManifoldPoints3];
  int count = 0;
};

class Solver3 {
 public:
  // Advances the awake dynamic and kinematic bodies by dt in `substeps` sub-steps, solving
  // the touching contacts that have one of them. Moves their proxies. Bodies whose motion
  // would leave the world (beyond kMaxCoordinate / 2, or not finite) are held at their
  // pose from the start of the step with zero velocity.
  void step(BodyStore3& store, ContactSet3& contacts, const WorldDef3& def, float dt, int substeps);

 private:
  std::vector<std::uint32_t> slotOf_;  // per body index: its slot, 0 for none
  std::vector<std::uint32_t> movers_;  // body index per slot (slot 0: none)
  // Kept between steps for their capacity only: refilled every step.
  std::vector<BodyState3> states_;
  std::vector<Constraint3> constraints_;
};

}  // namespace quack::detail
