// The joints' constraints (joint_solver.hpp; docs/world.md, "Joints").
//
// Conventions: every constraint is C(x) = 0 (or >= 0 for a limit) with velocity Cdot = J v;
// an impulse is -m_eff (Cdot + bias) less the soft part of the impulse already accumulated.
// The position error is measured from the bodies' motion since the step began (the solver's
// dp and dq), so that a joint prepared once per step stays right through the sub-steps.

#include "joint_solver.hpp"

#include "quack/math/trig.hpp"

namespace quack::detail {

namespace {

// The mouse joint's spin damping: a soft row of 1 Hz, damping ratio 0.5, with nothing to
// reach: it takes about 2.6% of the spin each sub-step at 240 Hz (e^-6 a second). Box2D v3's
// mouse joint damps spin the same way (read for understanding).
constexpr float kMouseSpinHertz = 1.0f;
constexpr float kMouseSpinDampingRatio = 0.5f;

// x solving [[k11, k12], [k12, k22]] x = b (0 where the matrix is singular).
Vec2 solve22(float k11, float k12, float k22, Vec2 b) {
  float det = k11 * k22 - k12 * k12;
  if (det != 0.0f) det = 1.0f / det;
  return {det * (k22 * b.x - k12 * b.y), det * (k11 * b.y - k12 * b.x)};
}

// The two bodies' velocities and motion, read from their slots and written back only to a
// body the solver moves (never slot 0, which every worker reads).
struct Pair {
  Vec2 vA, vB;
  float wA, wB;
  Vec2 dpA, dpB;
  Rot qA, qB;  // rotation since the step began
  float turnedA, turnedB;

  Pair(const JointSim& sim, const BodyState* states, const float* turned) {
    const BodyState& a = states[sim.slotA];
    const BodyState& b = states[sim.slotB];
    vA = {a.vx, a.vy};
    wA = a.w;
    vB = {b.vx, b.vy};
    wB = b.w;
    dpA = {a.dpx, a.dpy};
    dpB = {b.dpx, b.dpy};
    qA = {a.qc, a.qs};
    qB = {b.qc, b.qs};
    turnedA = turned != nullptr ? turned[sim.slotA] : 0.0f;
    turnedB = turned != nullptr ? turned[sim.slotB] : 0.0f;
  }
  void store(const JointSim& sim, BodyState* states) const {
    if (sim.writeA) {
      BodyState& a = states[sim.slotA];
      a.vx = vA.x;
      a.vy = vA.y;
      a.w = wA;
    }
    if (sim.writeB) {
      BodyState& b = states[sim.slotB];
      b.vx = vB.x;
      b.vy = vB.y;
      b.w = wB;
    }
  }
  // B's angle relative to A, less the reference, now.
  float angle(const JointSim& sim) const { return wrapAngle(sim.deltaAngle + (turnedB - turnedA)); }
  // The linear impulse P at the arms rA, rB: -P on A, +P on B.
  void applyLinear(const JointSim& sim, Vec2 rA, Vec2 rB, Vec2 P) {
    vA -= sim.mA * P;
    wA -= sim.iA * cross(rA, P);
    vB += sim.mB * P;
    wB += sim.iB * cross(rB, P);
  }
  // An angular impulse: -L on A, +L on B.
  void applyAngular(const JointSim& sim, float L) {
    wA -= sim.iA * L;
    wB += sim.iB * L;
  }
};

// The soft coefficients of one constraint row: none (relax), or the rigid joint push.
struct Row {
  float bias = 0.0f, massScale = 1.0f, impulseScale = 0.0f;
};
Row soft(const Softness& s, float C) {
  return {s.biasRate * C, s.massScale, s.impulseScale};
}

// A one-sided limit on a scalar C >= 0 with velocity Cdot and effective mass `mass`:
// speculative while apart (close the gap and no further), soft when past it.
float limitImpulse(float C, float Cdot, float mass, float& accumulated,
                   const JointStepParams& params, bool useBias) {
  Row r;
  if (C > 0.0f) {
    r.bias = C * params.invH;
  } else if (useBias) {
    r = soft(params.jointSoft, C);
  }
  const float impulse = -mass * r.massScale * (Cdot + r.bias) - r.impulseScale * accumulated;
  const float total = maxf(accumulated + impulse, 0.0f);
  const float applied = total - accumulated;
  accumulated = total;
  return applied;
}

// The point constraint: B's anchor on A's (revolute, weld). The soft row `r` is applied to
// the separation `sep`.
void solvePoint(const JointSim& sim, Pair& p, Vec2 rA, Vec2 rB, Vec2 sep, const Softness* s,
                Vec2& accumulated) {
  const Vec2 cdot = (p.vB + cross(p.wB, rB)) - (p.vA + cross(p.wA, rA));
  Vec2 bias{};
  float massScale = 1.0f, impulseScale = 0.0f;
  if (s != nullptr) {
    bias = s->biasRate * sep;
    massScale = s->massScale;
    impulseScale = s->impulseScale;
  }
  const float mA = sim.mA, mB = sim.mB, iA = sim.iA, iB = sim.iB;
  const float k11 = mA + mB + rA.y * rA.y * iA + rB.y * rB.y * iB;
  const float k12 = -rA.y * rA.x * iA - rB.y * rB.x * iB;
  const float k22 = mA + mB + rA.x * rA.x * iA + rB.x * rB.x * iB;
  const Vec2 b = solve22(k11, k12, k22, cdot + bias);
  const Vec2 impulse = (-massScale) * b - impulseScale * accumulated;
  accumulated += impulse;
  p.applyLinear(sim, rA, rB, impulse);
}

// What prismatic and wheel joints measure along and across their axis.
struct AxisFrame {
  Vec2 d;        // B's anchor from A's, now
  Vec2 axis;     // now
  float a1, a2;  // the arms' moments about the axis
  Vec2 perp;     // leftPerp(axis)
  float s1, s2;  // and about the perpendicular
  float translation;
};
AxisFrame axisFrame(const JointSim& sim, const Pair& p, Vec2 rA, Vec2 rB) {
  AxisFrame f;
  f.d = (p.dpB - p.dpA) + sim.deltaCenter + (rB - rA);
  f.axis = rotate(p.qA, sim.axis);
  f.translation = dot(f.axis, f.d);
  f.a1 = cross(f.d + rA, f.axis);
  f.a2 = cross(rB, f.axis);
  f.perp = leftPerp(f.axis);
  f.s1 = cross(f.d + rA, f.perp);
  f.s2 = cross(rB, f.perp);
  return f;
}
// An impulse `lambda` along the axis (positive pushes B along it).
void applyAxial(const JointSim& sim, Pair& p, const AxisFrame& f, float lambda) {
  p.vA -= (sim.mA * lambda) * f.axis;
  p.wA -= sim.iA * lambda * f.a1;
  p.vB += (sim.mB * lambda) * f.axis;
  p.wB += sim.iB * lambda * f.a2;
}
float axialVelocity(const Pair& p, const AxisFrame& f) {
  return dot(f.axis, p.vB - p.vA) + f.a2 * p.wB - f.a1 * p.wA;
}
float axialMass(const JointSim& sim, const AxisFrame& f) {
  const float k = sim.mA + sim.mB + sim.iA * f.a1 * f.a1 + sim.iB * f.a2 * f.a2;
  return k > 0.0f ? 1.0f / k : 0.0f;
}

// Spring, motor and limits along the axis (prismatic; the wheel has no axial motor).
void solveAxial(const JointSim& sim, JointRun& j, Pair& p, const AxisFrame& f,
                const JointStepParams& params, bool useBias, bool motor) {
  const JointRun::Def& def = j.def;
  const float mass = axialMass(sim, f);
  if (def.enableSpring && def.hertz > 0.0f) {
    const float C = f.translation;
    const float impulse =
        -mass * sim.spring.massScale * (axialVelocity(p, f) + sim.spring.biasRate * C) -
        sim.spring.impulseScale * j.springImpulse;
    j.springImpulse += impulse;
    applyAxial(sim, p, f, impulse);
  }
  if (motor && def.enableMotor) {
    const float impulse = mass * (def.motorSpeed - axialVelocity(p, f));
    const float old = j.motorImpulse;
    const float most = params.h * def.maxMotorForce;
    j.motorImpulse = clampf(old + impulse, -most, most);
    applyAxial(sim, p, f, j.motorImpulse - old);
  }
  if (def.enableLimit) {
    const float lower = limitImpulse(f.translation - def.lower, axialVelocity(p, f), mass,
                                     j.lowerImpulse, params, useBias);
    applyAxial(sim, p, f, lower);
    const float upper = limitImpulse(def.upper - f.translation, -axialVelocity(p, f), mass,
                                     j.upperImpulse, params, useBias);
    applyAxial(sim, p, f, -upper);
  }
}

void solveRevolute(const JointSim& sim, JointRun& j, Pair& p, const JointStepParams& params,
                   bool useBias) {
  const JointRun::Def& def = j.def;
  const float iSum = sim.iA + sim.iB;
  if (iSum > 0.0f) {
    const float axialMass = 1.0f / iSum;
    if (def.enableSpring && def.hertz > 0.0f) {
      const float C = p.angle(sim);
      const float impulse =
          -axialMass * sim.spring.massScale * ((p.wB - p.wA) + sim.spring.biasRate * C) -
          sim.spring.impulseScale * j.springImpulse;
      j.springImpulse += impulse;
      p.applyAngular(sim, impulse);
    }
    if (def.enableMotor) {
      const float impulse = -axialMass * ((p.wB - p.wA) - def.motorSpeed);
      const float old = j.motorImpulse;
      const float most = params.h * def.maxMotorTorque;
      j.motorImpulse = clampf(old + impulse, -most, most);
      p.applyAngular(sim, j.motorImpulse - old);
    }
    if (def.enableLimit) {
      const float angle = p.angle(sim);
      const float lower =
          limitImpulse(angle - def.lower, p.wB - p.wA, axialMass, j.lowerImpulse, params, useBias);
      p.applyAngular(sim, lower);
      const float upper =
          limitImpulse(def.upper - angle, p.wA - p.wB, axialMass, j.upperImpulse, params, useBias);
      p.applyAngular(sim, -upper);
    }
  }
  const Vec2 rA = rotate(p.qA, sim.rA), rB = rotate(p.qB, sim.rB);
  const Vec2 sep = (p.dpB - p.dpA) + (rB - rA) + sim.deltaCenter;
  solvePoint(sim, p, rA, rB, sep, useBias ? &params.jointSoft : nullptr, j.linearImpulse);
}

void solvePrismatic(const JointSim& sim, JointRun& j, Pair& p, const JointStepParams& params,
                    bool useBias) {
  const Vec2 rA = rotate(p.qA, sim.rA), rB = rotate(p.qB, sim.rB);
  AxisFrame f = axisFrame(sim, p, rA, rB);
  solveAxial(sim, j, p, f, params, useBias, true);
  // Across the axis and the angle, together (a 2x2 block).
  const Vec2 cdot{dot(f.perp, p.vB - p.vA) + f.s2 * p.wB - f.s1 * p.wA, p.wB - p.wA};
  Row r;
  Vec2 bias{};
  if (useBias) {
    r = soft(params.jointSoft, 0.0f);
    bias = params.jointSoft.biasRate * Vec2{dot(f.perp, f.d), p.angle(sim)};
  }
  const float k11 = sim.mA + sim.mB + sim.iA * f.s1 * f.s1 + sim.iB * f.s2 * f.s2;
  const float k12 = sim.iA * f.s1 + sim.iB * f.s2;
  float k22 = sim.iA + sim.iB;
  if (k22 == 0.0f) k22 = 1.0f;  // neither body turns: the angle row is free
  const Vec2 b = solve22(k11, k12, k22, cdot + bias);
  const Vec2 impulse = (-r.massScale) * b - r.impulseScale * j.linearImpulse;
  j.linearImpulse += impulse;
  const Vec2 P = impulse.x * f.perp;
  p.vA -= sim.mA * P;
  p.wA -= sim.iA * (impulse.x * f.s1 + impulse.y);
  p.vB += sim.mB * P;
  p.wB += sim.iB * (impulse.x * f.s2 + impulse.y);
}

void solveWheel(const JointSim& sim, JointRun& j, Pair& p, const JointStepParams& params,
                bool useBias) {
  const JointRun::Def& def = j.def;
  const float iSum = sim.iA + sim.iB;
  if (def.enableMotor && iSum > 0.0f) {
    const float impulse = -(1.0f / iSum) * ((p.wB - p.wA) - def.motorSpeed);
    const float old = j.motorImpulse;
    const float most = params.h * def.maxMotorTorque;
    j.motorImpulse = clampf(old + impulse, -most, most);
    p.applyAngular(sim, j.motorImpulse - old);
  }
  const Vec2 rA = rotate(p.qA, sim.rA), rB = rotate(p.qB, sim.rB);
  const AxisFrame f = axisFrame(sim, p, rA, rB);
  solveAxial(sim, j, p, f, params, useBias, false);
  // B's anchor on A's axis.
  const float k = sim.mA + sim.mB + sim.iA * f.s1 * f.s1 + sim.iB * f.s2 * f.s2;
  const float perpMass = k > 0.0f ? 1.0f / k : 0.0f;
  Row r;
  if (useBias) r = soft(params.jointSoft, dot(f.perp, f.d));
  const float cdot = dot(f.perp, p.vB - p.vA) + f.s2 * p.wB - f.s1 * p.wA;
  const float impulse = -perpMass * r.massScale * (cdot + r.bias) - r.impulseScale * j.perpImpulse;
  j.perpImpulse += impulse;
  const Vec2 P = impulse * f.perp;
  p.vA -= sim.mA * P;
  p.wA -= sim.iA * impulse * f.s1;
  p.vB += sim.mB * P;
  p.wB += sim.iB * impulse * f.s2;
}

void solveDistance(const JointSim& sim, JointRun& j, Pair& p, const JointStepParams& params,
                   bool useBias) {
  const JointRun::Def& def = j.def;
  const Vec2 rA = rotate(p.qA, sim.rA), rB = rotate(p.qB, sim.rB);
  const Vec2 d = (p.dpB - p.dpA) + sim.deltaCenter + (rB - rA);
  const float len = length(d);
  // Anchors on top of each other have no direction: push along x, as good as any.
  const Vec2 axis = len > 0.0f ? (1.0f / len) * d : Vec2{1.0f, 0.0f};
  const float crA = cross(rA, axis), crB = cross(rB, axis);
  const float k = sim.mA + sim.mB + sim.iA * crA * crA + sim.iB * crB * crB;
  const float mass = k > 0.0f ? 1.0f / k : 0.0f;
  auto velocity = [&] { return dot(axis, (p.vB + cross(p.wB, rB)) - (p.vA + cross(p.wA, rA))); };
  if (!def.enableSpring) {
    // Rigid: the length held at its rest length.
    Row r;
    if (useBias) r = soft(params.jointSoft, len - j.length);
    const float impulse =
        -mass * r.massScale * (velocity() + r.bias) - r.impulseScale * j.axialImpulse;
    j.axialImpulse += impulse;
    p.applyLinear(sim, rA, rB, impulse * axis);
    return;
  }
  if (def.hertz > 0.0f) {
    const float C = len - j.length;
    const float impulse = -mass * sim.spring.massScale * (velocity() + sim.spring.biasRate * C) -
                          sim.spring.impulseScale * j.springImpulse;
    j.springImpulse += impulse;
    p.applyLinear(sim, rA, rB, impulse * axis);
  }
  if (def.enableLimit) {
    const float lower =
        limitImpulse(len - def.minLength, velocity(), mass, j.lowerImpulse, params, useBias);
    p.applyLinear(sim, rA, rB, lower * axis);
    const float upper =
        limitImpulse(def.maxLength - len, -velocity(), mass, j.upperImpulse, params, useBias);
    p.applyLinear(sim, rA, rB, -upper * axis);
  }
}

void solveWeld(const JointSim& sim, JointRun& j, Pair& p, const JointStepParams& params,
               bool useBias) {
  const JointRun::Def& def = j.def;
  const float iSum = sim.iA + sim.iB;
  if (iSum > 0.0f) {
    Row r;
    if (def.angularHertz > 0.0f) {
      r = soft(sim.angularSoft, p.angle(sim));
    } else if (useBias) {
      r = soft(params.jointSoft, p.angle(sim));
    }
    const float impulse =
        -(1.0f / iSum) * r.massScale * ((p.wB - p.wA) + r.bias) - r.impulseScale * j.angularImpulse;
    j.angularImpulse += impulse;
    p.applyAngular(sim, impulse);
  }
  const Vec2 rA = rotate(p.qA, sim.rA), rB = rotate(p.qB, sim.rB);
  const Vec2 sep = (p.dpB - p.dpA) + (rB - rA) + sim.deltaCenter;
  const Softness* s = nullptr;
  if (def.linearHertz > 0.0f) {
    s = &sim.linearSoft;
  } else if (useBias) {
    s = &params.jointSoft;
  }
  solvePoint(sim, p, rA, rB, sep, s, j.linearImpulse);
}

void solveMotor(const JointSim& sim, JointRun& j, Pair& p, const JointStepParams& params) {
  const JointRun::Def& def = j.def;
  const float correction = def.correctionFactor * params.invH;
  const float iSum = sim.iA + sim.iB;
  if (iSum > 0.0f) {
    const float impulse = -(1.0f / iSum) * ((p.wB - p.wA) + correction * p.angle(sim));
    const float old = j.angularImpulse;
    const float most = params.h * def.maxTorque;
    j.angularImpulse = clampf(old + impulse, -most, most);
    p.applyAngular(sim, j.angularImpulse - old);
  }
  const Vec2 rA = rotate(p.qA, sim.rA), rB = rotate(p.qB, sim.rB);
  const Vec2 sep = (p.dpB - p.dpA) + (rB - rA) + sim.deltaCenter;
  const Vec2 cdot = (p.vB + cross(p.wB, rB)) - (p.vA + cross(p.wA, rA));
  const float mA = sim.mA, mB = sim.mB, iA = sim.iA, iB = sim.iB;
  const float k11 = mA + mB + rA.y * rA.y * iA + rB.y * rB.y * iB;
  const float k12 = -rA.y * rA.x * iA - rB.y * rB.x * iB;
  const float k22 = mA + mB + rA.x * rA.x * iA + rB.x * rB.x * iB;
  const Vec2 impulse = -1.0f * solve22(k11, k12, k22, cdot + correction * sep);
  const Vec2 old = j.linearImpulse;
  Vec2 total = old + impulse;
  const float most = params.h * def.maxForce;
  const float size = length(total);
  if (size > most) total = (most / size) * total;
  j.linearImpulse = total;
  p.applyLinear(sim, rA, rB, total - old);
}

void solveMouse(const JointSim& sim, JointRun& j, Pair& p, const JointStepParams& params) {
  // Spin damped softly (no angle to reach): a body held off its centre would otherwise
  // swing about the grabbed point for as long as it is held.
  if (sim.iB > 0.0f) {
    const float impulse = -(1.0f / sim.iB) * sim.angularSoft.massScale * p.wB -
                          sim.angularSoft.impulseScale * j.angularImpulse;
    j.angularImpulse += impulse;
    p.wB += sim.iB * impulse;
  }
  const Vec2 rB = rotate(p.qB, sim.rB);
  const Vec2 sep = p.dpB + rB + sim.deltaCenter;  // the grabbed point from the target
  const Vec2 cdot = p.vB + cross(p.wB, rB);
  const float mB = sim.mB, iB = sim.iB;
  const float k11 = mB + rB.y * rB.y * iB;
  const float k12 = -rB.y * rB.x * iB;
  const float k22 = mB + rB.x * rB.x * iB;
  const Vec2 b = solve22(k11, k12, k22, cdot + sim.spring.biasRate * sep);
  const Vec2 old = j.linearImpulse;
  Vec2 total = old + ((-sim.spring.massScale) * b - sim.spring.impulseScale * old);
  const float most = params.h * j.def.maxForce;
  const float size = length(total);
  if (size > most) total = (most / size) * total;
  j.linearImpulse = total;
  const Vec2 impulse = total - old;
  p.vB += mB * impulse;
  p.wB += iB * cross(rB, impulse);
}

}  // namespace

void prepareJoint(JointSim& sim, const Joint& joint, const JointBody& a, const JointBody& b,
                  const JointStepParams& params) {
  const JointDef& def = joint.def;
  JointRun& run = sim.run;
  run.def = {
      def.type,        def.enableLimit,     def.enableMotor,    def.enableSpring,  def.lower,
      def.upper,       def.motorSpeed,      def.maxMotorTorque, def.maxMotorForce, def.hertz,
      def.linearHertz, def.angularHertz,    def.minLength,      def.maxLength,     def.maxForce,
      def.maxTorque,   def.correctionFactor};
  run.length = joint.length;
  run.linearImpulse = joint.linearImpulse;
  run.angularImpulse = joint.angularImpulse;
  run.perpImpulse = joint.perpImpulse;
  run.axialImpulse = joint.axialImpulse;
  run.springImpulse = joint.springImpulse;
  run.motorImpulse = joint.motorImpulse;
  run.lowerImpulse = joint.lowerImpulse;
  run.upperImpulse = joint.upperImpulse;
  sim.mA = a.invMass;
  sim.iA = a.invInertia;
  sim.mB = b.invMass;
  sim.iB = b.invInertia;
  sim.rA = rotate(a.q, joint.localAnchorA - a.localCenter);
  sim.rB = rotate(b.q, joint.localAnchorB - b.localCenter);
  sim.deltaCenter = b.center - a.center;
  // The relative angle costs an arctangent: only the rows that read it get it (a revolute
  // joint without a limit or spring, the bulk of a chain or a grid, does not).
  const bool angled = def.type == JointType::weld || def.type == JointType::prismatic ||
                      def.type == JointType::motor ||
                      (def.type == JointType::revolute &&
                       (def.enableLimit || (def.enableSpring && def.hertz > 0.0f)));
  const float relative = angled ? invMulRot(a.q, b.q).angle() : 0.0f;
  sim.deltaAngle = angled ? wrapAngle(relative - joint.referenceAngle) : 0.0f;
  sim.axis = rotate(a.q, joint.localAxisA);
  sim.spring = makeSoftness(def.hertz, def.dampingRatio, params.h);
  switch (def.type) {
    case JointType::weld:
      sim.linearSoft = makeSoftness(def.linearHertz, def.linearDampingRatio, params.h);
      sim.angularSoft = makeSoftness(def.angularHertz, def.angularDampingRatio, params.h);
      break;
    case JointType::motor:
      // B's origin held at the offset from A's origin.
      sim.rA = rotate(a.q, def.linearOffset - a.localCenter);
      sim.rB = rotate(b.q, Vec2{} - b.localCenter);
      sim.deltaAngle = wrapAngle(relative - def.angularOffset);
      break;
    case JointType::mouse:
      sim.rA = {};
      sim.deltaCenter = b.center - def.target;
      sim.deltaAngle = 0.0f;
      sim.angularSoft = makeSoftness(kMouseSpinHertz, kMouseSpinDampingRatio, params.h);
      break;
    default:
      break;
  }
}

void warmStartJoint(const JointSim& sim, BodyState* states) {
  const JointRun& j = sim.run;
  Pair p(sim, states, nullptr);
  const Vec2 rA = rotate(p.qA, sim.rA), rB = rotate(p.qB, sim.rB);
  switch (j.def.type) {
    case JointType::revolute: {
      const float axial = j.springImpulse + j.motorImpulse + j.lowerImpulse - j.upperImpulse;
      p.applyLinear(sim, rA, rB, j.linearImpulse);
      p.applyAngular(sim, axial);
      break;
    }
    case JointType::weld:
    case JointType::motor:
      p.applyLinear(sim, rA, rB, j.linearImpulse);
      p.applyAngular(sim, j.angularImpulse);
      break;
    case JointType::prismatic:
    case JointType::wheel: {
      const AxisFrame f = axisFrame(sim, p, rA, rB);
      const bool prismatic = j.def.type == JointType::prismatic;
      const float axial =
          j.springImpulse + (prismatic ? j.motorImpulse : 0.0f) + j.lowerImpulse - j.upperImpulse;
      const float across = prismatic ? j.linearImpulse.x : j.perpImpulse;
      const float turn = prismatic ? j.linearImpulse.y : j.motorImpulse;
      const Vec2 P = axial * f.axis + across * f.perp;
      p.vA -= sim.mA * P;
      p.wA -= sim.iA * (axial * f.a1 + across * f.s1 + turn);
      p.vB += sim.mB * P;
      p.wB += sim.iB * (axial * f.a2 + across * f.s2 + turn);
      break;
    }
    case JointType::distance: {
      const Vec2 d = (p.dpB - p.dpA) + sim.deltaCenter + (rB - rA);
      const float len = length(d);
      const Vec2 axis = len > 0.0f ? (1.0f / len) * d : Vec2{1.0f, 0.0f};
      const float axial = j.axialImpulse + j.springImpulse + j.lowerImpulse - j.upperImpulse;
      p.applyLinear(sim, rA, rB, axial * axis);
      break;
    }
    case JointType::mouse:
      p.vB += sim.mB * j.linearImpulse;
      p.wB += sim.iB * (cross(rB, j.linearImpulse) + j.angularImpulse);
      break;
  }
  p.store(sim, states);
}

void solveJoint(JointSim& sim, BodyState* states, const float* turned,
                const JointStepParams& params, bool useBias) {
  JointRun& joint = sim.run;
  Pair p(sim, states, turned);
  switch (joint.def.type) {
    case JointType::revolute:
      solveRevolute(sim, joint, p, params, useBias);
      break;
    case JointType::prismatic:
      solvePrismatic(sim, joint, p, params, useBias);
      break;
    case JointType::distance:
      solveDistance(sim, joint, p, params, useBias);
      break;
    case JointType::weld:
      solveWeld(sim, joint, p, params, useBias);
      break;
    case JointType::wheel:
      solveWheel(sim, joint, p, params, useBias);
      break;
    case JointType::motor:
      solveMotor(sim, joint, p, params);
      break;
    case JointType::mouse:
      solveMouse(sim, joint, p, params);
      break;
  }
  p.store(sim, states);
}

void finishJoint(const JointSim& sim, Joint& joint, float invH) {
  const JointRun& j = sim.run;
  joint.linearImpulse = j.linearImpulse;
  joint.angularImpulse = j.angularImpulse;
  joint.perpImpulse = j.perpImpulse;
  joint.axialImpulse = j.axialImpulse;
  joint.springImpulse = j.springImpulse;
  joint.motorImpulse = j.motorImpulse;
  joint.lowerImpulse = j.lowerImpulse;
  joint.upperImpulse = j.upperImpulse;
  Vec2 P;
  float L = 0.0f;
  switch (j.def.type) {
    case JointType::revolute:
      P = j.linearImpulse;
      L = j.springImpulse + j.motorImpulse + j.lowerImpulse - j.upperImpulse;
      break;
    case JointType::weld:
    case JointType::motor:
      P = j.linearImpulse;
      L = j.angularImpulse;
      break;
    case JointType::prismatic:
      P = (j.springImpulse + j.motorImpulse + j.lowerImpulse - j.upperImpulse) * sim.axis +
          j.linearImpulse.x * leftPerp(sim.axis);
      L = j.linearImpulse.y;
      break;
    case JointType::wheel:
      P = (j.springImpulse + j.lowerImpulse - j.upperImpulse) * sim.axis +
          j.perpImpulse * leftPerp(sim.axis);
      L = j.motorImpulse;
      break;
    case JointType::distance: {
      const Vec2 d = sim.deltaCenter + (sim.rB - sim.rA);
      const float len = length(d);
      const Vec2 axis = len > 0.0f ? (1.0f / len) * d : Vec2{1.0f, 0.0f};
      P = (j.axialImpulse + j.springImpulse + j.lowerImpulse - j.upperImpulse) * axis;
      break;
    }
    case JointType::mouse:
      P = j.linearImpulse;
      L = j.angularImpulse;
      break;
  }
  joint.force = invH * P;
  joint.torque = invH * L;
}

}  // namespace quack::detail
