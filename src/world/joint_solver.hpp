#pragma once
// The joints' part of the solver (docs/world.md, "Joints"): each joint type's constraints
// in the soft step the contacts use (solver.cpp). Per step a joint is prepared once (its
// arms, the bodies' offsets and masses at the step's start); per sub-step it is warm
// started, solved with the position error as a soft bias, and relaxed without it, as the
// contacts are. Joints are solved one at a time here; revolute joints go in lanes instead
// (joint_lanes.hpp), with the same operations. Box2D v3's
// joint files (revolute_joint.c, prismatic_joint.c, ...) and Catto's "Solver2D" notes showed the
// constraints (read for understanding; the code is ours).

#include <cstdint>

#include "joint_set.hpp"
#include "simd.hpp"
#include "solver.hpp"

namespace quack::detail {

/// An angle brought into [-pi, pi] by one turn (angles here differ by less than 3 pi).
inline float wrapAngle(float a) noexcept {
  if (a > kPi) return a - 2.0f * kPi;
  if (a < -kPi) return a + 2.0f * kPi;
  return a;
}

/// What preparing a joint reads of one of its bodies: zero masses for a body the solver
/// does not move (static, kinematic, asleep, or a mouse joint's missing body A).
struct JointBody {
  float invMass = 0.0f, invInertia = 0.0f;
  Vec2 center;       // centre of mass, world frame, at the step's start
  Vec2 localCenter;  // body frame
  Rot q;             // at the step's start
};

struct JointStepParams {
  float h = 0.0f, invH = 0.0f;
  Softness jointSoft;  // the rigid constraints' push (WorldDef::jointHertz)
};

/// What the passes read and write of a joint: its settings and warm-start impulses, copied
/// from its record when it is prepared and the impulses copied back when the step is done,
/// so that the passes stream through the step's joints in colour order instead of reaching
/// into the records (two hundred bytes each, in index order) four times a sub-step.
struct JointRun {
  struct Def {
    JointType type = JointType::revolute;
    bool enableLimit = false, enableMotor = false, enableSpring = false;
    float lower = 0.0f, upper = 0.0f, motorSpeed = 0.0f, maxMotorTorque = 0.0f;
    float maxMotorForce = 0.0f, hertz = 0.0f, linearHertz = 0.0f, angularHertz = 0.0f;
    float minLength = 0.0f, maxLength = 0.0f, maxForce = 0.0f, maxTorque = 0.0f;
    float correctionFactor = 0.0f;
  } def;
  float length = 0.0f;
  Vec2 linearImpulse;
  float angularImpulse = 0.0f, perpImpulse = 0.0f, axialImpulse = 0.0f;
  float springImpulse = 0.0f, motorImpulse = 0.0f, lowerImpulse = 0.0f, upperImpulse = 0.0f;
};

/// One joint as a step solves it.
struct JointSim {
  std::uint32_t joint = 0;
  std::int32_t slotA = 0, slotB = 0;    // the solver's body states (0: at rest)
  bool writeA = false, writeB = false;  // the body is dynamic and awake: its state is written
  bool lanes = false;  // solved in lanes (joint_lanes.hpp), which read and finish the record
  float mA = 0.0f, iA = 0.0f, mB = 0.0f, iB = 0.0f;
  Vec2 rA, rB;              // arms from the centres of mass to the anchors, world axes, at start
  Vec2 deltaCenter;         // cB - cA at start (mouse: cB - target)
  float deltaAngle = 0.0f;  // B's angle less A's less the reference, in [-pi, pi], at start
  Vec2 axis;                // prismatic, wheel: the axis, world frame, at start
  Softness spring;          // the joint's own spring (revolute, prismatic, wheel, distance, mouse)
  Softness linearSoft, angularSoft;  // weld
  JointRun run;
};

void prepareJoint(JointSim& sim, const Joint& joint, const JointBody& a, const JointBody& b,
                  const JointStepParams& params);
/// The impulses of the last sub-step applied again.
void warmStartJoint(const JointSim& sim, BodyState* states);
/// One pass: `useBias` pushes the position error out (the solve pass), or not (relax).
/// `turned`: each slot's rotation since the step began, radians.
void solveJoint(JointSim& sim, BodyState* states, const float* turned,
                const JointStepParams& params, bool useBias);
/// The impulses back to the record, and the step's force and torque from them
/// (Joint::force, torque).
void finishJoint(const JointSim& sim, Joint& joint, float invH);

}  // namespace quack::detail
