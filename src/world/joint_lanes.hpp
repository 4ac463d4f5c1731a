#pragma once
// Plain revolute joints in lanes (solver.cpp). A revolute joint without a limit, a motor or a
// spring is one point constraint: the bulk of a chain, a grid or a bridge. The joints of one
// colour share no body the solver writes, so F::width of them are solved side by side, as
// the contacts are, with the operations joint_solver.cpp uses for one joint, in the same
// order: the same bits as solving them one at a time (SolverLanes tests compare the two).
// Joints with more rows stay on the one-at-a-time path.

#include <cstdint>

#include "joint_solver.hpp"
#include "simd.hpp"

namespace quack::detail {

/// The joints the lanes take: a revolute joint whose only row is the point constraint.
inline bool solvedInLanes(const JointDef& def) noexcept {
  return def.type == JointType::revolute && !def.enableLimit && !def.enableMotor &&
         !(def.enableSpring && def.hertz > 0.0f);
}

template <class F>
struct alignas(F::width * sizeof(float)) JointBlock {
  static constexpr int W = F::width;
  float mA[W], iA[W], mB[W], iB[W];
  float rAx[W], rAy[W], rBx[W], rBy[W];  // arms at the step's start (JointSim::rA, rB)
  float dcx[W], dcy[W];                  // JointSim::deltaCenter
  float axial[W];                        // the warm start's angular impulse
  float px[W], py[W];                    // the accumulated linear impulse (JointRun)
  std::int32_t slotA[W], slotB[W];       // 0 in an empty lane: the resting body
  std::uint32_t writeA = 0, writeB = 0;  // lanes whose body is written (bit per lane)
};

/// A plain revolute joint prepared straight into its lane: what prepareJoint would put in
/// its JointSim for the lanes to read, by the same expressions (the block starts zeroed:
/// empty lanes change nothing).
template <class F>
void prepareJointLane(JointBlock<F>& b, int lane, const JointSim& slots, const Joint& joint,
                      const JointBody& a, const JointBody& bb) {
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
  // As warmStartJoint sums it; the impulses do not change in a plain joint's step.
  b.axial[lane] =
      joint.springImpulse + joint.motorImpulse + joint.lowerImpulse - joint.upperImpulse;
  b.px[lane] = joint.linearImpulse.x;
  b.py[lane] = joint.linearImpulse.y;
  b.slotA[lane] = slots.slotA;
  b.slotB[lane] = slots.slotB;
  if (slots.writeA) b.writeA |= 1u << lane;
  if (slots.writeB) b.writeB |= 1u << lane;
}

/// finishJoint for the joint in `lane`: its impulse back to the record, and the step's
/// force and torque (its other impulses are the record's own, unchanged).
template <class F>
void finishJointLane(const JointBlock<F>& b, int lane, Joint& joint, float invH) {
  joint.linearImpulse = {b.px[lane], b.py[lane]};
  const float L =
      joint.springImpulse + joint.motorImpulse + joint.lowerImpulse - joint.upperImpulse;
  joint.force = invH * joint.linearImpulse;
  joint.torque = invH * L;
}

namespace jointlanes {

template <class F>
F ld(const float* p) {
  return load(p, F{});
}
template <class F>
F sp(float x) {
  return splat(x, F{});
}
// -x exactly (a product with -1 is exact and flips the sign of zeros as negation does);
// a subtraction from zero would not (0 - 0 is +0).
template <class F>
F neg(F x) {
  return x * sp<F>(-1.0f);
}

// Pair::applyLinear: -P on A at rA, +P on B at rB.
template <class F>
void applyLinear(BodyLanes<F>& A, BodyLanes<F>& B, F mA, F iA, F mB, F iB, F rAx, F rAy, F rBx,
                 F rBy, F Px, F Py) {
  A.vx = A.vx - mA * Px;
  A.vy = A.vy - mA * Py;
  A.w = A.w - iA * (rAx * Py - rAy * Px);
  B.vx = B.vx + mB * Px;
  B.vy = B.vy + mB * Py;
  B.w = B.w + iB * (rBx * Py - rBy * Px);
}

}  // namespace jointlanes

/// warmStartJoint for a block of plain revolute joints.
template <class F>
void warmStartJointBlock(const JointBlock<F>& b, BodyState* states) {
  using namespace jointlanes;
  BodyLanes<F> A = gather(states, b.slotA, F{});
  BodyLanes<F> B = gather(states, b.slotB, F{});
  const F rAx0 = ld<F>(b.rAx), rAy0 = ld<F>(b.rAy), rBx0 = ld<F>(b.rBx), rBy0 = ld<F>(b.rBy);
  const F rAx = A.qc * rAx0 - A.qs * rAy0, rAy = A.qs * rAx0 + A.qc * rAy0;
  const F rBx = B.qc * rBx0 - B.qs * rBy0, rBy = B.qs * rBx0 + B.qc * rBy0;
  const F mA = ld<F>(b.mA), iA = ld<F>(b.iA), mB = ld<F>(b.mB), iB = ld<F>(b.iB);
  applyLinear(A, B, mA, iA, mB, iB, rAx, rAy, rBx, rBy, ld<F>(b.px), ld<F>(b.py));
  const F axial = ld<F>(b.axial);  // Pair::applyAngular
  A.w = A.w - iA * axial;
  B.w = B.w + iB * axial;
  scatter(states, b.slotA, b.writeA, A);
  scatter(states, b.slotB, b.writeB, B);
}

/// solveRevolute (its point constraint, solvePoint) for a block of plain revolute joints:
/// `useBias` with the joints' soft push `soft` (the solve pass), or rigid without it (relax).
template <bool useBias, class F>
void solveJointBlock(JointBlock<F>& b, BodyState* states, const Softness& soft) {
  using namespace jointlanes;
  BodyLanes<F> A = gather(states, b.slotA, F{});
  BodyLanes<F> B = gather(states, b.slotB, F{});
  const F zero = sp<F>(0.0f), one = sp<F>(1.0f);
  const F rAx0 = ld<F>(b.rAx), rAy0 = ld<F>(b.rAy), rBx0 = ld<F>(b.rBx), rBy0 = ld<F>(b.rBy);
  const F rAx = A.qc * rAx0 - A.qs * rAy0, rAy = A.qs * rAx0 + A.qc * rAy0;
  const F rBx = B.qc * rBx0 - B.qs * rBy0, rBy = B.qs * rBx0 + B.qc * rBy0;
  // cdot = (vB + cross(wB, rB)) - (vA + cross(wA, rA)); v + (-(w r)) is v - w r exactly.
  const F cdx = (B.vx - B.w * rBy) - (A.vx - A.w * rAy);
  const F cdy = (B.vy + B.w * rBx) - (A.vy + A.w * rAx);
  F bx = zero, by = zero, massScale = one, impulseScale = zero;
  if constexpr (useBias) {
    const F sepx = ((B.dpx - A.dpx) + (rBx - rAx)) + ld<F>(b.dcx);
    const F sepy = ((B.dpy - A.dpy) + (rBy - rAy)) + ld<F>(b.dcy);
    const F biasRate = sp<F>(soft.biasRate);
    bx = biasRate * sepx;
    by = biasRate * sepy;
    massScale = sp<F>(soft.massScale);
    impulseScale = sp<F>(soft.impulseScale);
  }
  const F mA = ld<F>(b.mA), iA = ld<F>(b.iA), mB = ld<F>(b.mB), iB = ld<F>(b.iB);
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
  applyLinear(A, B, mA, iA, mB, iB, rAx, rAy, rBx, rBy, ix, iy);
  scatter(states, b.slotA, b.writeA, A);
  scatter(states, b.slotB, b.writeB, B);
}

}  // namespace quack::detail
