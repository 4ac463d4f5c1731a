#pragma once
// Revolute joints in lanes (solver.cpp). The joints of one colour share no body the solver
// writes, so F::width revolute joints are solved side by side, as the contacts are, with the
// operations joint_solver.cpp uses for one joint, in the same order: the same bits as
// solving them one at a time (JointDeterminism tests compare the two). A lane whose joint
// lacks a row (a spring, a motor, a limit) computes it and keeps its old values by a select,
// as the contacts' restitution does; a block none of whose joints has one (the plain joints
// of a chain, a grid or a bridge come first in their colour) skips those rows. Other joint
// types stay on the one-at-a-time path.

#include <cstdint>

#include "joint_solver.hpp"
#include "simd.hpp"

namespace quack::detail {

/// The joints the lanes take.
inline bool solvedInLanes(const JointDef& def) noexcept {
  return def.type == JointType::revolute;
}
/// Of those, the ones whose only row is the point constraint.
inline bool plainRevolute(const JointDef& def) noexcept {
  return !def.enableLimit && !def.enableMotor && !(def.enableSpring && def.hertz > 0.0f);
}

template <class F>
struct alignas(F::width * sizeof(float)) JointBlock {
  static constexpr int W = F::width;
  float mA[W], iA[W], mB[W], iB[W];
  float rAx[W], rAy[W], rBx[W], rBy[W];  // arms at the step's start (JointSim::rA, rB)
  float dcx[W], dcy[W];                  // JointSim::deltaCenter
  float px[W], py[W];                    // the accumulated linear impulse (JointRun)
  // The angular rows: 1 where the joint has the row, else 0.
  float springOn[W], motorOn[W], limitOn[W];
  float deltaAngle[W];                                                 // JointSim::deltaAngle
  float springBiasRate[W], springMassScale[W], springImpulseScale[W];  // JointSim::spring
  float motorSpeed[W], motorMost[W];  // the most motor impulse a sub-step (h maxMotorTorque)
  float lower[W], upper[W];
  float springImpulse[W], motorImpulse[W], lowerImpulse[W], upperImpulse[W];
  std::int32_t slotA[W], slotB[W];       // 0 in an empty lane: the resting body
  std::uint32_t writeA = 0, writeB = 0;  // lanes whose body is written (bit per lane)
  bool rows = false;                     // a lane has an angular row
};

/// A revolute joint prepared straight into its lane: what prepareJoint would put in its
/// JointSim for the lanes to read, by the same expressions (the block starts zeroed: empty
/// lanes change nothing).
template <class F>
void prepareJointLane(JointBlock<F>& b, int lane, const JointSim& slots, const Joint& joint,
                      const JointBody& a, const JointBody& bb, const JointStepParams& params) {
  const JointDef& def = joint.def;
  b.mA[lane] = a.invMass;
  b.iA[lane] = a.invInertia;
  b.mB[lane] = bb.invMass;
  b.iB[lane] = bb.invInertia;
  const Vec2 rA = rotate(a.q, joint.localAnchorA - a.localCenter);
  const Vec2 rB = rotate(bb.q, joint.localAnchorB - bb.localCenter);
  const Vec2 deltaCenter = bb.center - a.center;
  b.rAx[lane] = rA.x;
  b.rAy[lane] = rA.y;
  b.rBx[lane] = rB.x;
  b.rBy[lane] = rB.y;
  b.dcx[lane] = deltaCenter.x;
  b.dcy[lane] = deltaCenter.y;
  b.px[lane] = joint.linearImpulse.x;
  b.py[lane] = joint.linearImpulse.y;
  b.springImpulse[lane] = joint.springImpulse;
  b.motorImpulse[lane] = joint.motorImpulse;
  b.lowerImpulse[lane] = joint.lowerImpulse;
  b.upperImpulse[lane] = joint.upperImpulse;
  const bool spring = def.enableSpring && def.hertz > 0.0f;
  if (spring || def.enableLimit || def.enableMotor) b.rows = true;
  b.springOn[lane] = spring ? 1.0f : 0.0f;
  b.motorOn[lane] = def.enableMotor ? 1.0f : 0.0f;
  b.limitOn[lane] = def.enableLimit ? 1.0f : 0.0f;
  // As prepareJoint: the relative angle only where a row reads it.
  const bool angled = def.enableLimit || spring;
  const float relative = angled ? invMulRot(a.q, bb.q).angle() : 0.0f;
  b.deltaAngle[lane] = angled ? wrapAngle(relative - joint.referenceAngle) : 0.0f;
  const Softness soft = makeSoftness(def.hertz, def.dampingRatio, params.h);
  b.springBiasRate[lane] = soft.biasRate;
  b.springMassScale[lane] = soft.massScale;
  b.springImpulseScale[lane] = soft.impulseScale;
  b.motorSpeed[lane] = def.motorSpeed;
  b.motorMost[lane] = params.h * def.maxMotorTorque;
  b.lower[lane] = def.lower;
  b.upper[lane] = def.upper;
  b.slotA[lane] = slots.slotA;
  b.slotB[lane] = slots.slotB;
  if (slots.writeA) b.writeA |= 1u << lane;
  if (slots.writeB) b.writeB |= 1u << lane;
}

/// finishJoint for the joint in `lane`: its impulses back to the record, and the step's
/// force and torque.
template <class F>
void finishJointLane(const JointBlock<F>& b, int lane, Joint& joint, float invH) {
  joint.linearImpulse = {b.px[lane], b.py[lane]};
  joint.springImpulse = b.springImpulse[lane];
  joint.motorImpulse = b.motorImpulse[lane];
  joint.lowerImpulse = b.lowerImpulse[lane];
  joint.upperImpulse = b.upperImpulse[lane];
  const float L =
      joint.springImpulse + joint.motorImpulse + joint.lowerImpulse - joint.upperImpulse;
  joint.force = invH * joint.linearImpulse;
  joint.torque = invH * L;
}

namespace jointlanes {

// -x exactly (a product with -1 is exact and flips the sign of zeros as negation does);
// a subtraction from zero would not (0 - 0 is +0).
template <class F>
F neg(F x) {
  return x * sp<F>(-1.0f);
}

// Pair::applyAngular (-L on A, +L on B) in the lanes of `on` only.
template <class F, class M>
void applyAngular(BodyLanes<F>& A, BodyLanes<F>& B, F iA, F iB, F L, M on) {
  A.w = select(on, A.w - iA * L, A.w);
  B.w = select(on, B.w + iB * L, B.w);
}

// clampf(a, lo, hi): a < lo ? lo : (a > hi ? hi : a).
template <class F>
F clamp(F a, F lo, F hi) {
  return select(greater(lo, a), lo, select(greater(a, hi), hi, a));
}

// The slot's rotation this step (the solver's `turned`), per lane.
template <class F>
F turnedOf(const float* turned, const std::int32_t* slots) {
  alignas(F::width * sizeof(float)) float t[F::width];
  for (int lane = 0; lane < F::width; ++lane)
    t[lane] = turned[slots[lane]];
  return ld<F>(t);
}

// limitImpulse: a one-sided limit C >= 0, speculative while apart, soft (solve) or rigid
// (relax) when past it; the accumulated impulse updated in the lanes of `on`.
template <bool useBias, class F, class M>
F limitImpulse(F C, F Cdot, F mass, float* accumulated, F invH, const Softness& soft, M on) {
  const F zero = sp<F>(0.0f);
  const auto apart = greater(C, zero);
  F bias, massScale = sp<F>(1.0f), impulseScale = zero;
  if constexpr (useBias) {
    bias = select(apart, C * invH, sp<F>(soft.biasRate) * C);
    massScale = select(apart, massScale, sp<F>(soft.massScale));
    impulseScale = select(apart, zero, sp<F>(soft.impulseScale));
  } else {
    bias = select(apart, C * invH, zero);
  }
  const F acc = ld<F>(accumulated);
  const F impulse = neg(mass) * massScale * (Cdot + bias) - impulseScale * acc;
  const F total = maxW(acc + impulse, zero);
  store(accumulated, select(on, total, acc));
  return total - acc;
}

}  // namespace jointlanes

/// warmStartJoint for a block of revolute joints.
template <class F>
void warmStartJointBlock(const JointBlock<F>& b, BodyState* states) {
  using namespace jointlanes;
  BodyLanes<F> A = gather(states, b.slotA, F{});
  BodyLanes<F> B = gather(states, b.slotB, F{});
  const F rAx0 = ld<F>(b.rAx), rAy0 = ld<F>(b.rAy), rBx0 = ld<F>(b.rBx), rBy0 = ld<F>(b.rBy);
  const F rAx = A.qc * rAx0 - A.qs * rAy0, rAy = A.qs * rAx0 + A.qc * rAy0;
  const F rBx = B.qc * rBx0 - B.qs * rBy0, rBy = B.qs * rBx0 + B.qc * rBy0;
  const F mA = ld<F>(b.mA), iA = ld<F>(b.iA), mB = ld<F>(b.mB), iB = ld<F>(b.iB);
  // Pair::applyLinear's operations.
  applyImpulse(A, B, mA, iA, mB, iB, rAx, rAy, rBx, rBy, ld<F>(b.px), ld<F>(b.py));
  const F axial = ((ld<F>(b.springImpulse) + ld<F>(b.motorImpulse)) + ld<F>(b.lowerImpulse)) -
                  ld<F>(b.upperImpulse);
  A.w = A.w - iA * axial;  // Pair::applyAngular
  B.w = B.w + iB * axial;
  scatter(states, b.slotA, b.writeA, A);
  scatter(states, b.slotB, b.writeB, B);
}

/// solveRevolute for a block of revolute joints: `useBias` with the joints' soft push
/// (the solve pass), or rigid without it (relax). `turned`: each slot's rotation this step.
template <bool useBias, class F>
void solveJointBlock(JointBlock<F>& b, BodyState* states, const float* turned,
                     const JointStepParams& params) {
  using namespace jointlanes;
  BodyLanes<F> A = gather(states, b.slotA, F{});
  BodyLanes<F> B = gather(states, b.slotB, F{});
  const F zero = sp<F>(0.0f), one = sp<F>(1.0f);
  const F mA = ld<F>(b.mA), iA = ld<F>(b.iA), mB = ld<F>(b.mB), iB = ld<F>(b.iB);
  if (b.rows) {
    // Spring, motor, limits, in that order, where the joint has them and a body turns.
    const F iSum = iA + iB;
    const auto turns = greater(iSum, zero);
    const F axialMass = one / select(turns, iSum, one);
    const F pi = sp<F>(kPi), twoPi = sp<F>(2.0f * kPi);
    const F raw =
        ld<F>(b.deltaAngle) + (turnedOf<F>(turned, b.slotB) - turnedOf<F>(turned, b.slotA));
    const F angle = select(greater(raw, pi), raw - twoPi,
                           select(greater(neg(pi), raw), raw + twoPi, raw));  // wrapAngle, in lanes
    const auto spring = turns & greater(ld<F>(b.springOn), zero);
    if (any(spring)) {
      const F acc = ld<F>(b.springImpulse);
      const F impulse = neg(axialMass) * ld<F>(b.springMassScale) *
                            ((B.w - A.w) + ld<F>(b.springBiasRate) * angle) -
                        ld<F>(b.springImpulseScale) * acc;
      store(b.springImpulse, select(spring, acc + impulse, acc));
      applyAngular(A, B, iA, iB, impulse, spring);
    }
    const auto motor = turns & greater(ld<F>(b.motorOn), zero);
    if (any(motor)) {
      const F impulse = neg(axialMass) * ((B.w - A.w) - ld<F>(b.motorSpeed));
      const F old = ld<F>(b.motorImpulse), most = ld<F>(b.motorMost);
      const F total = clamp(old + impulse, neg(most), most);
      store(b.motorImpulse, select(motor, total, old));
      applyAngular(A, B, iA, iB, total - old, motor);
    }
    const auto limit = turns & greater(ld<F>(b.limitOn), zero);
    if (any(limit)) {
      const F invH = sp<F>(params.invH);
      const F lower = limitImpulse<useBias>(angle - ld<F>(b.lower), B.w - A.w, axialMass,
                                            b.lowerImpulse, invH, params.jointSoft, limit);
      applyAngular(A, B, iA, iB, lower, limit);
      const F upper = limitImpulse<useBias>(ld<F>(b.upper) - angle, A.w - B.w, axialMass,
                                            b.upperImpulse, invH, params.jointSoft, limit);
      applyAngular(A, B, iA, iB, neg(upper), limit);
    }
  }
  // The point constraint (solvePoint).
  const F rAx0 = ld<F>(b.rAx), rAy0 = ld<F>(b.rAy), rBx0 = ld<F>(b.rBx), rBy0 = ld<F>(b.rBy);
  const F rAx = A.qc * rAx0 - A.qs * rAy0, rAy = A.qs * rAx0 + A.qc * rAy0;
  const F rBx = B.qc * rBx0 - B.qs * rBy0, rBy = B.qs * rBx0 + B.qc * rBy0;
  // cdot = (vB + cross(wB, rB)) - (vA + cross(wA, rA)); v + (-(w r)) is v - w r exactly.
  const F cdx = (B.vx - B.w * rBy) - (A.vx - A.w * rAy);
  const F cdy = (B.vy + B.w * rBx) - (A.vy + A.w * rAx);
  F bx = zero, by = zero, massScale = one, impulseScale = zero;
  if constexpr (useBias) {
    const Softness& soft = params.jointSoft;
    const F sepx = ((B.dpx - A.dpx) + (rBx - rAx)) + ld<F>(b.dcx);
    const F sepy = ((B.dpy - A.dpy) + (rBy - rAy)) + ld<F>(b.dcy);
    const F biasRate = sp<F>(soft.biasRate);
    bx = biasRate * sepx;
    by = biasRate * sepy;
    massScale = sp<F>(soft.massScale);
    impulseScale = sp<F>(soft.impulseScale);
  }
  const F mAB = mA + mB;
  const F k11 = (mAB + rAy * rAy * iA) + rBy * rBy * iB;
  const F k12 = neg(rAy * rAx * iA) - rBy * rBx * iB;
  const F k22 = (mAB + rAx * rAx * iA) + rBx * rBx * iB;
  const F ux = cdx + bx, uy = cdy + by;
  // solve22: det made 1 / det unless it is zero (either sign), kept otherwise.
  const F det = k11 * k22 - k12 * k12;
  const auto positive = greater(det, zero), negative = greater(zero, det);
  const F safe = select(positive, det, select(negative, det, one));
  const F inv = one / safe;
  const F d = select(positive, inv, select(negative, inv, det));
  const F sx = d * (k22 * ux - k12 * uy);
  const F sy = d * (k11 * uy - k12 * ux);
  const F px = ld<F>(b.px), py = ld<F>(b.py);
  const F minusScale = neg(massScale);
  const F ix = minusScale * sx - impulseScale * px;
  const F iy = minusScale * sy - impulseScale * py;
  store(b.px, px + ix);
  store(b.py, py + iy);
  applyImpulse(A, B, mA, iA, mB, iB, rAx, rAy, rBx, rBy, ix, iy);
  scatter(states, b.slotA, b.writeA, A);
  scatter(states, b.slotB, b.writeB, B);
}

}  // namespace quack::detail
