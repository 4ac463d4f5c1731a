// The contact solver: soft contacts solved by sequential impulses over sub-steps, with
// relaxation and restitution (Catto, "Solver2D" (2024) and Box2D v3's soft step, read for
// understanding; Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005, for
// sequential impulses and warm starting). docs/world.md explains the choices.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "solver.hpp"

#include <vector>

#include "body_store.hpp"
#include "contact_set.hpp"
#include "event_dispatcher.hpp"
#include "joint_lanes.hpp"
#include "joint_set.hpp"
#include "joint_solver.hpp"
#include "quack/math/trig.hpp"
#include "quack/world/tasks.hpp"
#include "quack/world/world.hpp"
#include "simd.hpp"
#include "step_context.hpp"
#include "task_runner.hpp"

namespace quack::detail {

namespace {
std::atomic<bool> testReadsRecords{false};
std::atomic<bool> testJointsOneAtATime{false};
}  // namespace
void setTestSolverReadsRecords(bool on) noexcept {
  testReadsRecords.store(on, std::memory_order_relaxed);
}
void setTestJointsOneAtATime(bool on) noexcept {
  testJointsOneAtATime.store(on, std::memory_order_relaxed);
}

namespace {

Rot integrateRotation(Rot q, float deltaAngle) {
  // First-order update then renormalise: exact to second order per sub-step, and cheaper
  // than cos/sin.
  Rot r{q.c - deltaAngle * q.s, q.s + deltaAngle * q.c};
  float inv = 1.0f / std::sqrt(r.c * r.c + r.s * r.s);
  return {r.c * inv, r.s * inv};
}

// ---- the constraints, a block of lanes at a time -----------------------------------------
//
// A block holds F::width contact constraints side by side, each field an array with one
// entry per lane (structure of arrays), so a lane's constraint is solved with the same
// operations as every other lane's. Empty lanes have zero masses and read the resting
// body in slot 0; they change nothing and write nothing. A manifold with one point has a
// second point of zero mass, which gives zero impulses.
template <class F>
struct alignas(F::width * sizeof(float)) ContactBlock {
  static constexpr int W = F::width;
  struct Point {
    float rAx[W], rAy[W], rBx[W], rBy[W];  // anchors from each centre of mass, world axes
    float baseSeparation[W];               // separation minus the anchors' offset along the normal
    float normalImpulse[W], tangentImpulse[W], maxNormalImpulse[W];
    float normalMass[W], tangentMass[W];
    float relativeVelocity[W];  // normal velocity before the step (for restitution)
  };
  Point points[kMaxManifoldPoints];
  float nx[W], ny[W], friction[W], restitution[W];
  float biasRate[W], massScale[W], impulseScale[W];
  float mA[W], iA[W], mB[W], iB[W];
  std::int32_t slotA[W], slotB[W];       // slots of the solver's body states; 0 = at rest
  std::uint32_t writeA = 0, writeB = 0;  // lanes whose body is dynamic (bit per lane)
};

// Warm start: the accumulated impulses of the last step, applied again.
template <class F>
[[gnu::noinline]] void warmStart(ContactBlock<F>* blocks, std::size_t count, BodyState* states) {
  for (std::size_t bi = 0; bi < count; ++bi) {
    ContactBlock<F>& b = blocks[bi];
    BodyLanes<F> A = gather(states, b.slotA, F{});
    BodyLanes<F> B = gather(states, b.slotB, F{});
    const F mA = ld<F>(b.mA), iA = ld<F>(b.iA), mB = ld<F>(b.mB), iB = ld<F>(b.iB);
    const F nx = ld<F>(b.nx), ny = ld<F>(b.ny);
    for (auto& p : b.points) {
      const F ni = ld<F>(p.normalImpulse), ti = ld<F>(p.tangentImpulse);
      // P = ni n + ti t, t = rightPerp(n) = (ny, -nx)
      const F Px = ni * nx + ti * ny;
      const F Py = ni * ny - ti * nx;
      applyImpulse(A, B, mA, iA, mB, iB, ld<F>(p.rAx), ld<F>(p.rAy), ld<F>(p.rBx), ld<F>(p.rBy), Px,
                   Py);
    }
    scatter(states, b.slotA, b.writeA, A);
    scatter(states, b.slotB, b.writeB, B);
  }
}

// One pass over the constraints: normal impulses (soft, or rigid in the relax pass), then
// friction.
//
// The normal impulses of a manifold's points are solved one after the other, and whichever
// goes first takes more of the load in that pass: a box resting flat on another gets a
// little more push under one corner than the other, the same corner every sub-step, and a
// column turns that steady nudge into a lean (docs/world.md, "Contact recycling and point
// order").
// `lastFirst` solves the points in the opposite order; the solver alternates it between
// sub-steps and between the solve and the relax pass, so the nudges cancel.
// The normal impulse at one point of each lane's manifold. `useBias`: the soft push (the
// solve pass) or none (the relax pass).
template <bool useBias, class F>
[[gnu::always_inline]] inline void solveNormalPoint(typename ContactBlock<F>::Point& p,
                                                    BodyLanes<F>& A, BodyLanes<F>& B, F mA, F iA,
                                                    F mB, F iB, F nx, F ny, F dpx, F dpy,
                                                    F biasRate, F softMass, F softImpulse, F invH,
                                                    F minBias) {
  const F zero = sp<F>(0.0f);
  const F rAx = ld<F>(p.rAx), rAy = ld<F>(p.rAy), rBx = ld<F>(p.rBx), rBy = ld<F>(p.rBy);
  // Current separation from the bodies' motion since the step began.
  const F prAx = A.qc * rAx - A.qs * rAy, prAy = A.qs * rAx + A.qc * rAy;
  const F prBx = B.qc * rBx - B.qs * rBy, prBy = B.qs * rBx + B.qc * rBy;
  const F dx = dpx + (prBx - prAx), dy = dpy + (prBy - prAy);
  const F s = (dx * nx + dy * ny) + ld<F>(p.baseSeparation);
  // Apart: speculative, close the gap and no further. Overlapping: the soft push, limited
  // to pushMax (nothing in the relax pass).
  const auto apart = greater(s, zero);
  F bias, massScale, impulseScale;
  if constexpr (useBias) {
    bias = select(apart, s * invH, maxW(biasRate * s, minBias));
    massScale = select(apart, sp<F>(1.0f), softMass);
    impulseScale = select(apart, zero, softImpulse);
  } else {
    bias = select(apart, s * invH, zero);
    massScale = sp<F>(1.0f);
    impulseScale = zero;
  }
  const F dvx = (B.vx - B.w * rBy) - (A.vx - A.w * rAy);
  const F dvy = (B.vy + B.w * rBx) - (A.vy + A.w * rAx);
  const F vn = dvx * nx + dvy * ny;
  const F ni = ld<F>(p.normalImpulse);
  F impulse = (zero - ld<F>(p.normalMass) * massScale * (vn + bias)) - impulseScale * ni;
  const F total = maxW(ni + impulse, zero);
  impulse = total - ni;
  store(p.normalImpulse, total);
  store(p.maxNormalImpulse, maxW(ld<F>(p.maxNormalImpulse), impulse));
  applyImpulse(A, B, mA, iA, mB, iB, rAx, rAy, rBx, rBy, impulse * nx, impulse * ny);
}

// One pass over the constraints: normal impulses (soft, or rigid in the relax pass), then
// friction.
//
// The normal impulses of a manifold's points are solved one after the other, and whichever
// goes first takes more of the load in that pass: a box resting flat on another gets a
// little more push under one corner than the other, the same corner every sub-step, and a
// column turns that steady nudge into a lean (docs/world.md, "Contact recycling and point
// order").
// `lastFirst` solves the points in the opposite order; the solver alternates it between
// sub-steps and between the solve and the relax pass, so the nudges cancel.
template <bool useBias, class F>
[[gnu::noinline]] void solveContacts(ContactBlock<F>* blocks, std::size_t count, BodyState* states,
                                     float invH, float pushMax, bool lastFirst) {
  const F zero = sp<F>(0.0f), one = sp<F>(1.0f), invHW = sp<F>(invH);
  const F minBias = sp<F>(-pushMax);
  for (std::size_t bi = 0; bi < count; ++bi) {
    ContactBlock<F>& b = blocks[bi];
    BodyLanes<F> A = gather(states, b.slotA, F{});
    BodyLanes<F> B = gather(states, b.slotB, F{});
    const F mA = ld<F>(b.mA), iA = ld<F>(b.iA), mB = ld<F>(b.mB), iB = ld<F>(b.iB);
    const F nx = ld<F>(b.nx), ny = ld<F>(b.ny);
    const F dpx = B.dpx - A.dpx, dpy = B.dpy - A.dpy;
    F biasRate = zero, softMass = one, softImpulse = zero;
    if constexpr (useBias) {
      biasRate = ld<F>(b.biasRate);
      softMass = ld<F>(b.massScale);
      softImpulse = ld<F>(b.impulseScale);
    }
    const int first = lastFirst ? 1 : 0;
    solveNormalPoint<useBias, F>(b.points[first], A, B, mA, iA, mB, iB, nx, ny, dpx, dpy, biasRate,
                                 softMass, softImpulse, invHW, minBias);
    solveNormalPoint<useBias, F>(b.points[1 - first], A, B, mA, iA, mB, iB, nx, ny, dpx, dpy,
                                 biasRate, softMass, softImpulse, invHW, minBias);
    const F friction = ld<F>(b.friction);
    for (auto& p : b.points) {
      const F rAx = ld<F>(p.rAx), rAy = ld<F>(p.rAy), rBx = ld<F>(p.rBx), rBy = ld<F>(p.rBy);
      const F dvx = (B.vx - B.w * rBy) - (A.vx - A.w * rAy);
      const F dvy = (B.vy + B.w * rBx) - (A.vy + A.w * rAx);
      const F vt = dvx * ny - dvy * nx;  // along t = (ny, -nx)
      const F ti = ld<F>(p.tangentImpulse);
      const F limit = friction * ld<F>(p.normalImpulse);
      const F total = maxW(minW(ti - ld<F>(p.tangentMass) * vt, limit), zero - limit);
      const F impulse = total - ti;
      store(p.tangentImpulse, total);
      applyImpulse(A, B, mA, iA, mB, iB, rAx, rAy, rBx, rBy, impulse * ny, zero - impulse * nx);
    }
    scatter(states, b.slotA, b.writeA, A);
    scatter(states, b.slotB, b.writeB, B);
  }
}

// Restitution: for points that approached faster than the threshold and were pushed, aim
// the normal velocity at -e times the approach velocity. Lanes without it are left exactly
// as they were (selects, not zero impulses), so skipping a block that has none is safe.
template <class F>
[[gnu::noinline]] void applyRestitution(ContactBlock<F>* blocks, std::size_t count,
                                        BodyState* states, float threshold) {
  const F zero = sp<F>(0.0f), minusThreshold = sp<F>(-threshold);
  for (std::size_t bi = 0; bi < count; ++bi) {
    ContactBlock<F>& b = blocks[bi];
    const F e = ld<F>(b.restitution);
    const auto bouncy = greater(e, zero);
    auto wants = [&](const typename ContactBlock<F>::Point& p) {
      return bouncy & greater(minusThreshold, ld<F>(p.relativeVelocity)) &
             greater(ld<F>(p.maxNormalImpulse), zero);
    };
    const auto want0 = wants(b.points[0]), want1 = wants(b.points[1]);
    if (!any(want0) && !any(want1)) continue;
    BodyLanes<F> A = gather(states, b.slotA, F{});
    BodyLanes<F> B = gather(states, b.slotB, F{});
    const F mA = ld<F>(b.mA), iA = ld<F>(b.iA), mB = ld<F>(b.mB), iB = ld<F>(b.iB);
    const F nx = ld<F>(b.nx), ny = ld<F>(b.ny);
    for (int j = 0; j < kMaxManifoldPoints; ++j) {
      auto& p = b.points[j];
      const auto want = j == 0 ? want0 : want1;
      const F rAx = ld<F>(p.rAx), rAy = ld<F>(p.rAy), rBx = ld<F>(p.rBx), rBy = ld<F>(p.rBy);
      const F dvx = (B.vx - B.w * rBy) - (A.vx - A.w * rAy);
      const F dvy = (B.vy + B.w * rBx) - (A.vy + A.w * rAx);
      const F vn = dvx * nx + dvy * ny;
      const F ni = ld<F>(p.normalImpulse);
      F impulse = zero - ld<F>(p.normalMass) * (vn + e * ld<F>(p.relativeVelocity));
      const F total = maxW(ni + impulse, zero);
      impulse = total - ni;
      store(p.normalImpulse, select(want, total, ni));
      const F maxNi = ld<F>(p.maxNormalImpulse);
      store(p.maxNormalImpulse, select(want, maxW(maxNi, impulse), maxNi));
      BodyLanes<F> A2 = A, B2 = B;
      applyImpulse(A2, B2, mA, iA, mB, iB, rAx, rAy, rBx, rBy, impulse * nx, impulse * ny);
      A.vx = select(want, A2.vx, A.vx);
      A.vy = select(want, A2.vy, A.vy);
      A.w = select(want, A2.w, A.w);
      B.vx = select(want, B2.vx, B.vx);
      B.vy = select(want, B2.vy, B.vy);
      B.w = select(want, B2.w, B.w);
    }
    scatter(states, b.slotA, b.writeA, A);
    scatter(states, b.slotB, b.writeB, B);
  }
}

// Colours (solver.hpp, takeColor); the overflow set is solved one constraint per block, in
// order.
constexpr int kColors = kSolverColors;
constexpr int kOverflow = kSolverOverflow;
// Smallest shares of work handed to a worker: below these a task costs more than it saves.
constexpr int kMinBlocks = 16;
constexpr int kMinSlots = 256;
constexpr int kMinWords = 8;  // of 64 bodies (or 64 contacts, in the touching gather)

}  // namespace

// The per-step arrays, kept between steps so that a step allocates nothing once warm.
// What integrating a body's velocity needs, per sub-step, worked out once per step.
struct SlotSim {
  Vec2 gravityDv, forceDv;                          // h g gravityScale; h F / m
  float torqueDw = 0.0f;                            // h T / I
  float linearScale = 1.0f, angularDivisor = 1.0f;  // 1 / (1 + h c), 1 + h c
  bool dynamic = false, forced = false, torqued = false;
};

struct SolverScratch {
  std::vector<BodyState> states;        // by slot; slot 0 is at rest
  std::vector<SlotSim> sims;            // by slot
  std::vector<float> turned;            // by slot: rotation this step as an angle, radians
  std::vector<std::uint32_t> slotBody;  // slot -> body index
  std::vector<std::int32_t> bodySlot;   // body index -> slot (0: static or dead)
  std::vector<std::uint32_t> wordSlot;  // word of the awake bits -> its first slot
  std::vector<std::uint32_t> touching;  // touching contacts, in index order
  struct Pair {
    std::uint32_t contact;       // index into the contact set
    std::uint32_t bodyA, bodyB;  // body indices
    std::int32_t slotA, slotB;   // their slots
    bool dynamicA, dynamicB;
  };
  std::vector<Pair> pairs;                   // per touching contact
  std::vector<std::vector<Pair>> pairParts;  // pairs gathered per range of contacts
  std::vector<std::uint32_t> lane;           // per touching contact: block * width + lane
  std::vector<std::uint8_t> color;           // per touching contact: colour, or kOverflow
  // What preparing a constraint reads of an awake body, by slot: filled in slot order with
  // the slots, so that preparing reads this short array instead of the body records.
  struct SlotBody {
    float invMass, invInertia;
    Vec2 center, localCenter;
  };
  std::vector<SlotBody> slotBodies;
  // Per block lane, in lane order: its pair (contact kNoContact: an empty lane). Preparing
  // walks this in order and fetches each lane's contact and bodies a few blocks ahead.
  static constexpr std::uint32_t kNoContact = 0xffffffffu;
  std::vector<Pair> lanePairs;
  std::vector<std::uint32_t> slotColors;  // per slot: the colours its body is in
  std::vector<int> stageBlocks;           // the step's job: blocks per stage
  struct Placed {
    Aabb box;     // of a one-shape body
    bool inside;  // the world holds it
    bool follow;  // its proxies must be moved on one thread
  };
  std::vector<Placed> placed;  // by slot: where the step left the body
  struct Hit {
    std::int8_t point;  // the manifold point of the strongest hit, or -1: none
    float speed;
  };
  std::vector<Hit> hits;  // per block lane
  std::vector<ContactBlock<FloatW>> wide;
  std::vector<ContactBlock<FloatS>> narrow;
  // Joints with an awake dynamic body: gathered in joint order (what colouring reads), then
  // laid out by colour (the overflow set first), as the contacts' blocks are.
  struct JointFound {
    std::uint32_t joint;
    std::int32_t slotA, slotB;
    bool writeA, writeB;
    std::uint8_t group;  // 0 plain revolute, 1 other revolute (both in lanes), 2 the rest
  };
  std::vector<JointFound> jointsFound;
  std::vector<JointSim> joints;
  std::vector<std::uint8_t> jointColor;      // per found joint
  std::size_t jointStart[kColors + 2] = {};  // overflow [0, [0]), colour c [c], [c + 1])
  // The joint passes' work items: in each colour, blocks of revolute joints
  // (joint_lanes.hpp; those come first in the colour's joints) then its other joints one
  // by one; the overflow set's joints one by one. An item is kJointBlockItem | block, or
  // an index into `joints`. Ranges as jointStart's, over items.
  static constexpr std::uint32_t kJointBlockItem = 0x80000000u;
  std::vector<std::uint32_t> jointItems;
  std::size_t jointItemStart[kColors + 1] = {};
  struct JointBlockJoints {
    std::uint32_t first, count;  // the block's joints in `joints`
  };
  std::vector<JointBlockJoints> jointBlockJoints;
  std::vector<JointBlock<FloatW>> jointWide;
  std::vector<JointBlock<FloatS>> jointNarrow;
  std::vector<std::uint32_t> broken;  // joints past their break force, in index order
};

namespace {

struct StepParams {
  float h, invH, pushMax, restitutionThreshold;
  Softness soft, staticSoft;
  JointStepParams joint;
};

// Colours the joints first, with the colours their bodies take (as a contact's, below),
// and lays them out: the overflow set, then each colour's in joint order, its plain
// revolute joints first, then its other revolute joints (those two `width` to a block,
// joint_lanes.hpp), then the rest.
void layoutJoints(SolverScratch& s, std::uint32_t* used, int width) {
  const std::size_t n = s.jointsFound.size();
  const bool lanes = !testJointsOneAtATime.load(std::memory_order_relaxed);
  constexpr int kGroups = 3;  // plain revolute, other revolute, one at a time
  s.jointColor.resize(n);
  std::size_t perColor[kColors + 1] = {};
  std::size_t perGroup[kColors + 1][kGroups] = {};
  // The group a found joint is laid out in: its own in a colour's lanes, else one at a time.
  auto groupOf = [&](std::size_t k) {
    return lanes && s.jointColor[k] != kOverflow ? int{s.jointsFound[k].group} : 2;
  };
  for (std::size_t k = 0; k < n; ++k) {
    const SolverScratch::JointFound& j = s.jointsFound[k];
    const int color = takeColor(used, j.slotA, j.slotB, j.writeA, j.writeB);
    s.jointColor[k] = static_cast<std::uint8_t>(color);
    ++perColor[color];
    ++perGroup[color][groupOf(k)];
  }
  s.jointStart[0] = perColor[kOverflow];
  for (int c = 0; c < kColors; ++c)
    s.jointStart[c + 1] = s.jointStart[c] + perColor[c];
  std::size_t fill[kColors + 1][kGroups];
  fill[kOverflow][2] = 0;
  for (int c = 0; c < kColors; ++c) {
    fill[c][0] = s.jointStart[c];
    fill[c][1] = fill[c][0] + perGroup[c][0];
    fill[c][2] = fill[c][1] + perGroup[c][1];
  }
  // Only what the passes read before preparing fills in the rest (prepareJoint); the sims
  // are kept from step to step, so a warm step writes 16 bytes of each, not all of it.
  s.joints.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const SolverScratch::JointFound& j = s.jointsFound[k];
    const int group = groupOf(k);
    JointSim& sim = s.joints[fill[s.jointColor[k]][group]++];
    sim.joint = j.joint;
    sim.slotA = j.slotA;
    sim.slotB = j.slotB;
    sim.writeA = j.writeA;
    sim.writeB = j.writeB;
    sim.lanes = group != 2;
  }
  // The work items.
  const auto w = static_cast<std::size_t>(width);
  s.jointItems.clear();
  s.jointBlockJoints.clear();
  for (std::size_t k = 0; k < s.jointStart[0]; ++k)
    s.jointItems.push_back(static_cast<std::uint32_t>(k));
  for (int c = 0; c < kColors; ++c) {
    s.jointItemStart[c] = s.jointItems.size();
    std::size_t at = s.jointStart[c];
    for (int group = 0; group < 2; ++group) {
      const std::size_t end = at + perGroup[c][group];
      for (; at < end; at += w) {
        s.jointItems.push_back(SolverScratch::kJointBlockItem |
                               static_cast<std::uint32_t>(s.jointBlockJoints.size()));
        s.jointBlockJoints.push_back(
            {static_cast<std::uint32_t>(at), static_cast<std::uint32_t>(std::min(w, end - at))});
      }
      at = end;
    }
    for (; at < s.jointStart[c + 1]; ++at)
      s.jointItems.push_back(static_cast<std::uint32_t>(at));
  }
  s.jointItemStart[kColors] = s.jointItems.size();
}

// Colours the touching contacts and lays them out in blocks: the overflow set first (one
// constraint per block), then each colour's constraints in contact order, `width` to a
// block. Returns the block count; `colorStart[c]` is colour c's first block.
template <class F>
[[gnu::noinline]] std::size_t layoutBlocks(SolverScratch& s, std::vector<ContactBlock<F>>& blocks,
                                           std::size_t* colorStart, std::size_t* colorCount,
                                           Solver::Stats& stats) {
  constexpr int W = F::width;
  // Per slot, the colours its body is already in (bit c; takeColor).
  s.slotColors.assign(s.states.size(), 0);
  std::uint32_t* used = s.slotColors.data();
  layoutJoints(s, used, W);
  std::size_t perColor[kColors + 1] = {};
  s.color.resize(s.touching.size());
  for (std::size_t k = 0; k < s.touching.size(); ++k) {
    const SolverScratch::Pair& pair = s.pairs[k];
    const bool dynA = pair.dynamicA, dynB = pair.dynamicB;
    const std::int32_t sa = pair.slotA, sb = pair.slotB;
    // A contact of two bodies the solver does not write is not made by the world (a
    // dynamic body is in every contact); colour 0 is harmless for it.
    const int color = !dynA && !dynB ? 0 : takeColor(used, sa, sb, dynA, dynB);
    s.color[k] = static_cast<std::uint8_t>(color);
    ++perColor[color];
  }
  // Block ranges: overflow first.
  std::size_t next = perColor[kOverflow];
  stats.overflow = perColor[kOverflow];
  stats.colors = 0;
  for (int c = 0; c < kColors; ++c) {
    colorStart[c] = next;
    next += (perColor[c] + W - 1) / W;
    if (perColor[c] > 0 || s.jointStart[c + 1] > s.jointStart[c]) stats.colors = c + 1;
  }
  colorStart[kColors] = next;
  for (int c = 0; c <= kColors; ++c)
    colorCount[c] = perColor[c];
  blocks.resize(next);  // cleared as they are prepared, on the workers
  std::size_t fill[kColors + 1] = {};
  s.lane.resize(s.touching.size());
  for (std::size_t k = 0; k < s.touching.size(); ++k) {
    const int c = s.color[k];
    if (c == kOverflow) {
      s.lane[k] = static_cast<std::uint32_t>(fill[c]++ * W);
    } else {
      s.lane[k] = static_cast<std::uint32_t>(colorStart[c] * W + fill[c]++);
    }
  }
  return next;
}

// One constraint into its lane.
// A body as preparing reads it: from its slot when awake, else from its record (static,
// kinematic at rest, or asleep: no mass in the constraint, only its centre).
struct PrepBody {
  float invMass, invInertia;
  Vec2 center, localCenter;
};

template <class F>
void prepareLane(ContactBlock<F>& b, int lane, const ContactSim& c, const PrepBody& bodyA,
                 const PrepBody& bodyB, const SolverScratch::Pair& pair, const BodyState& A,
                 const BodyState& B, const StepParams& params) {
  b.slotA[lane] = pair.slotA;
  b.slotB[lane] = pair.slotB;
  // Written back only for an awake dynamic body (its own slot). A body without one (static,
  // kinematic, or, were a wake ever missed, asleep) reads its slot and counts as immovable
  // here, so no lane ever writes slot 0.
  if (pair.dynamicA) b.writeA |= 1u << lane;
  if (pair.dynamicB) b.writeB |= 1u << lane;
  const Vec2 n = c.normal;
  const Vec2 t = rightPerp(n);
  b.nx[lane] = n.x;
  b.ny[lane] = n.y;
  b.friction[lane] = c.friction;
  b.restitution[lane] = c.restitution;
  const float mA = pair.dynamicA ? bodyA.invMass : 0.0f;
  const float iA = pair.dynamicA ? bodyA.invInertia : 0.0f;
  const float mB = pair.dynamicB ? bodyB.invMass : 0.0f;
  const float iB = pair.dynamicB ? bodyB.invInertia : 0.0f;
  b.mA[lane] = mA;
  b.iA[lane] = iA;
  b.mB[lane] = mB;
  b.iB[lane] = iB;
  // Against static (and kinematic) bodies there is only one body to move: twice as stiff.
  const Softness& soft = (mA == 0.0f || mB == 0.0f) ? params.staticSoft : params.soft;
  b.biasRate[lane] = soft.biasRate;
  b.massScale[lane] = soft.massScale;
  b.impulseScale[lane] = soft.impulseScale;
  const Vec2 vA{A.vx, A.vy}, vB{B.vx, B.vy};
  for (int j = 0; j < c.pointCount; ++j) {
    const ContactSim::Point& cp = c.points[j];
    auto& p = b.points[j];
    const Vec2 rA = cp.rA, rB = cp.rB;
    p.rAx[lane] = rA.x;
    p.rAy[lane] = rA.y;
    p.rBx[lane] = rB.x;
    p.rBy[lane] = rB.y;
    p.baseSeparation[lane] = cp.baseSeparation;
    p.normalImpulse[lane] = cp.normalImpulse;
    p.tangentImpulse[lane] = cp.tangentImpulse;
    const float rnA = cross(rA, n), rnB = cross(rB, n);
    const float kn = mA + mB + iA * rnA * rnA + iB * rnB * rnB;
    p.normalMass[lane] = kn > 0.0f ? 1.0f / kn : 0.0f;
    const float rtA = cross(rA, t), rtB = cross(rB, t);
    const float kt = mA + mB + iA * rtA * rtA + iB * rtB * rtB;
    p.tangentMass[lane] = kt > 0.0f ? 1.0f / kt : 0.0f;
    const Vec2 dv = vB + cross(B.w, rB) - vA - cross(A.w, rA);
    p.relativeVelocity[lane] = dot(n, dv);
  }
}

// Gravity, forces and damping for one sub-step (implicit damping: any damping is stable).
[[gnu::noinline]] void integrateVelocities(SolverScratch& s, std::size_t first, std::size_t last) {
  BodyState* states = s.states.data();
  for (std::size_t slot = first; slot < last; ++slot) {
    const SlotSim& m = s.sims[slot];
    if (!m.dynamic) continue;
    BodyState& st = states[slot];
    Vec2 v = Vec2{st.vx, st.vy} + m.gravityDv;
    float w = st.w;
    // Applied forces (applyForce, applyTorque); a branch, so that a body without them
    // gives the same bits as before forces existed.
    if (m.forced) v += m.forceDv;
    if (m.torqued) w += m.torqueDw;
    v = m.linearScale * v;
    // Speed limits (world.hpp): keep speed * dt and every impulse finite.
    v = clampSpeed(v);
    st.vx = v.x;
    st.vy = v.y;
    st.w = clampf(w / m.angularDivisor, -kMaxAngularSpeed, kMaxAngularSpeed);
  }
}

// Moves every body by its velocity for one sub-step.
[[gnu::noinline]] void integratePositions(SolverScratch& s, std::size_t first, std::size_t last,
                                          float h, float maxRotation) {
  BodyState* states = s.states.data();
  const float invH = 1.0f / h;
  for (std::size_t slot = first; slot < last; ++slot) {
    BodyState& st = states[slot];
    if (absf(h * st.w) > maxRotation) st.w = (st.w > 0.0f ? maxRotation : -maxRotation) * invH;
    const Rot q = integrateRotation(Rot{st.qc, st.qs}, h * st.w);
    st.qc = q.c;
    st.qs = q.s;
    // integrateRotation turns by atan(h w), not h w; below 0.01 rad the two differ by
    // under 4e-7 rad, so the arctangent is only paid for fast spinners.
    const float turn = h * st.w;
    s.turned[slot] += absf(turn) < 0.01f ? turn : portableAtan(turn);
    st.dpx += h * st.vx;
    st.dpy += h * st.vy;
  }
}

template <class F>
[[gnu::noinline]] void prepareBlocks(SolverScratch& s, std::vector<ContactBlock<F>>& blocks,
                                     std::size_t first, std::size_t last, const BodyStore& store,
                                     const ContactSet& contactSet, const StepParams& params) {
  constexpr int W = F::width;
  const Contact* contacts = contactSet.contacts.data();
  const ContactSim* sims = contactSet.sims.data();
  const std::size_t simCount = contactSet.sims.size();
  // The largest stamp matches no sim (stamps count up from 1; a sim never written has 0):
  // every lane from the records (the tests' switch).
  const std::uint64_t stamp = testReadsRecords.load(std::memory_order_relaxed)
                                  ? std::numeric_limits<std::uint64_t>::max()
                                  : contactSet.simStamp();
  const SolverScratch::Pair* lanes = s.lanePairs.data();
  // Each lane's sim lies where the narrow phase wrote it: in the lane its contact had in the
  // last step (ContactSet::placeSims), so nearly in the order read here. By contact index,
  // in a pile of many colours, preparing waited on them (a fifth of a pyramid step for a
  // tenth of its instructions). The bodies' states lie anywhere. Both are fetched a few
  // blocks ahead.
  constexpr std::size_t kAhead = 4;
  auto fetch = [&](std::size_t bi) {
    for (int lane = 0; lane < W; ++lane) {
      const SolverScratch::Pair& pair = lanes[bi * W + static_cast<std::size_t>(lane)];
      if (pair.contact == SolverScratch::kNoContact) continue;
      const std::size_t simAt = contactSet.simIndex(pair.contact);
      if (simAt >= simCount) continue;
      const char* c = reinterpret_cast<const char*>(sims + simAt);
      for (std::size_t at = 0; at < sizeof(ContactSim); at += 64)
        __builtin_prefetch(c + at);
      __builtin_prefetch(c + sizeof(ContactSim) - 1);
      __builtin_prefetch(&s.states[static_cast<std::size_t>(pair.slotA)]);
      __builtin_prefetch(&s.states[static_cast<std::size_t>(pair.slotB)]);
      __builtin_prefetch(&s.slotBodies[static_cast<std::size_t>(pair.slotA)]);
      __builtin_prefetch(&s.slotBodies[static_cast<std::size_t>(pair.slotB)]);
    }
  };
  for (std::size_t bi = first; bi < last && bi < first + kAhead; ++bi)
    fetch(bi);
  auto prepBody = [&](std::uint32_t body, std::int32_t slot, bool dynamic) {
    if (slot > 0) {
      const SolverScratch::SlotBody& sb = s.slotBodies[static_cast<std::size_t>(slot)];
      return PrepBody{dynamic ? sb.invMass : 0.0f, dynamic ? sb.invInertia : 0.0f, sb.center,
                      sb.localCenter};
    }
    const Body& b = store.bodies[body];
    return PrepBody{0.0f, 0.0f, b.center, b.localCenter};
  };
  ContactSim local;  // a lane the narrow phase skipped
  for (std::size_t bi = first; bi < last; ++bi) {
    if (bi + kAhead < last) fetch(bi + kAhead);
    blocks[bi] = ContactBlock<F>{};
    for (int lane = 0; lane < W; ++lane) {
      const SolverScratch::Pair& pair = lanes[bi * W + static_cast<std::size_t>(lane)];
      if (pair.contact == SolverScratch::kNoContact) continue;
      const PrepBody bodyA = prepBody(pair.bodyA, pair.slotA, pair.dynamicA);
      const PrepBody bodyB = prepBody(pair.bodyB, pair.slotB, pair.dynamicB);
      const std::size_t simAt = contactSet.simIndex(pair.contact);
      const ContactSim* sim = simAt < simCount ? sims + simAt : nullptr;
      if (sim == nullptr || sim->stamp != stamp) {
        // Not updated by this step's narrow phase (ContactSim): from the records.
        fillContactSim(local, contacts[pair.contact], contactSet.impulses[pair.contact],
                       bodyA.center, bodyA.localCenter, bodyB.center, bodyB.localCenter);
        sim = &local;
      }
      prepareLane(blocks[bi], lane, *sim, bodyA, bodyB, pair,
                  s.states[static_cast<std::size_t>(pair.slotA)],
                  s.states[static_cast<std::size_t>(pair.slotB)], params);
    }
  }
}

// Accumulated impulses back to the contacts (ContactSet::impulses) for the next step's
// warm start, and hit events (in contact order).
template <class F>
[[gnu::noinline]] void storeImpulses(SolverScratch& s, const std::vector<ContactBlock<F>>& blocks,
                                     const WorldDef& def, std::vector<ContactImpulses>& impulses,
                                     std::size_t first, std::size_t last) {
  constexpr int W = F::width;
  // Block by block (the blocks read in order, each lane's impulses written where they lie,
  // fetched a few blocks ahead).
  constexpr std::size_t kAhead = 4;
  auto fetch = [&](std::size_t bi) {
    for (int lane = 0; lane < W; ++lane) {
      const std::uint32_t ci = s.lanePairs[bi * W + static_cast<std::size_t>(lane)].contact;
      if (ci != SolverScratch::kNoContact) __builtin_prefetch(&impulses[ci], 1);
    }
  };
  for (std::size_t bi = first; bi < last && bi < first + kAhead; ++bi)
    fetch(bi);
  for (std::size_t bi = first; bi < last; ++bi) {
    if (bi + kAhead < last) fetch(bi + kAhead);
    const ContactBlock<F>& b = blocks[bi];
    for (int lane = 0; lane < W; ++lane) {
      const std::size_t at = bi * W + static_cast<std::size_t>(lane);
      const std::uint32_t ci = s.lanePairs[at].contact;
      if (ci == SolverScratch::kNoContact) continue;
      // Both points, without reading the contact's point count: a manifold's second point,
      // when it has one point only, has no mass, so its impulses past the count (which
      // nothing reads) are zero and it never hits.
      ContactImpulses& out = impulses[ci];
      float strongest = 0.0f;
      int point = -1;
      for (int j = 0; j < kMaxManifoldPoints; ++j) {
        const auto& p = b.points[j];
        out.normal[j] = p.normalImpulse[lane];
        out.tangent[j] = p.tangentImpulse[lane];
        const float approach = -p.relativeVelocity[lane];
        if (p.maxNormalImpulse[lane] > 0.0f && approach > def.hitEventThreshold &&
            approach > strongest) {
          strongest = approach;
          point = j;
        }
      }
      s.hits[at] = {static_cast<std::int8_t>(point), strongest};
    }
  }
}

// Hit events, in contact order.
void reportHits(const SolverScratch& s, const BodyStore& store, const ContactSet& contactSet,
                EventDispatcher& events) {
  for (std::size_t k = 0; k < s.touching.size(); ++k) {
    const SolverScratch::Hit hit = s.hits[s.lane[k]];
    if (hit.point < 0) continue;
    const Contact& c = contactSet.contacts[s.touching[k]];
    events.events.hit.push_back({store.shapeId(c.shapeA), store.shapeId(c.shapeB),
                                 c.manifold.points[hit.point].point, c.manifold.normal, hit.speed});
  }
}

// The contact part of a step: colour, prepare, then per sub-step integrate velocities,
// warm start, solve, integrate positions, relax; then restitution and the impulses stored.
template <class F>
void runStep(SolverScratch& s, std::vector<ContactBlock<F>>& blocks,
             std::vector<JointBlock<F>>& jointBlocks, const WorldDef& def, BodyStore& store,
             ContactSet& contactSet, JointSet& jointSet, EventDispatcher& events,
             const StepParams& params, int substeps, Solver::Stats& stats, TaskRunner& tasks) {
  constexpr int W = F::width;
  std::size_t colorStart[kColors + 1], colorCount[kColors + 1];
  const std::size_t blockCount = layoutBlocks<F>(s, blocks, colorStart, colorCount, stats);
  jointBlocks.resize(s.jointBlockJoints.size());  // cleared as they are prepared
  // Which contact each lane holds, so that blocks can be prepared apart (a block's lanes
  // share its write masks): every constraint's pair into its lane, on the workers (each
  // lane is written once), then the empty lanes marked: lanes 1.. of the overflow blocks
  // (one constraint each) and the end of each colour's last block. (Filling every lane
  // first cost more than the scatter: a megabyte and a half on one thread.)
  s.lanePairs.resize(blockCount * W);
  tasks.parallelFor(static_cast<int>(s.touching.size()), kMinSlots, [&](int first, int last, int) {
    for (auto k = static_cast<std::size_t>(first); k < static_cast<std::size_t>(last); ++k)
      s.lanePairs[s.lane[k]] = s.pairs[k];
  });
  for (std::size_t b = 0; b < colorStart[0]; ++b)
    for (std::size_t lane = 1; lane < W; ++lane)
      s.lanePairs[b * W + lane].contact = SolverScratch::kNoContact;
  for (int c = 0; c < kColors; ++c)
    for (std::size_t at = colorStart[c] * W + colorCount[c]; at < colorStart[c + 1] * W; ++at)
      s.lanePairs[at].contact = SolverScratch::kNoContact;
  ContactBlock<F>* all = blocks.data();
  BodyState* states = s.states.data();

  // The step as one job of stages (task_runner.hpp). A pass over the constraints is the
  // overflow set (one block: its constraints share bodies), then each colour, whose blocks
  // the workers share (no two constraints of a colour share a dynamic body).
  enum class Kind : std::uint8_t {
    prepare,
    velocities,
    warm,
    solve,
    positions,
    relax,
    bounce,
    impulses
  };
  // A stage's work: first its joints (the same colour's: no body in common with its
  // contacts), then its contact blocks or slots; both split into task blocks.
  struct Stage {
    Kind kind;
    std::uint8_t odd;     // the sub-step's solve order
    std::uint32_t first;  // first contact block (or slot) of the stage
    std::uint32_t count;  // contact blocks (or slots) in it
    std::uint32_t size;   // of them per task block
    std::uint32_t jointFirst = 0, jointCount = 0, jointSize = 1;
    std::uint32_t jointBlocks = 0;  // task blocks of joints, before the contacts'
  };
  std::vector<Stage> stages;  // a hundred or so
  std::vector<int>& stageBlocks = s.stageBlocks;
  stages.clear();
  stageBlocks.clear();
  constexpr int kMinJoints = 32;
  auto add = [&](Kind kind, bool odd, std::size_t first, std::size_t count, int minRange,
                 int perWorker = TaskRunner::kRangesPerWorker, std::size_t jointFirst = 0,
                 std::size_t jointCount = 0) {
    if (count == 0 && jointCount == 0) return;
    Stage st{kind, static_cast<std::uint8_t>(odd), static_cast<std::uint32_t>(first),
             static_cast<std::uint32_t>(count), 1};
    int blocksOf = 0;
    if (count > 0) {
      const int size = tasks.rangeSize(static_cast<int>(count), minRange, perWorker);
      st.size = static_cast<std::uint32_t>(size);
      blocksOf = (static_cast<int>(count) + size - 1) / size;
    }
    if (jointCount > 0) {
      const int size = tasks.rangeSize(static_cast<int>(jointCount), kMinJoints, perWorker);
      st.jointFirst = static_cast<std::uint32_t>(jointFirst);
      st.jointCount = static_cast<std::uint32_t>(jointCount);
      st.jointSize = static_cast<std::uint32_t>(size);
      st.jointBlocks = static_cast<std::uint32_t>((static_cast<int>(jointCount) + size - 1) / size);
    }
    stages.push_back(st);
    stageBlocks.push_back(blocksOf + static_cast<int>(st.jointBlocks));
  };
  const std::size_t* js = s.jointItemStart;
  auto addPass = [&](Kind kind, bool odd) {
    // The overflow set: its joints then its contacts, one at a time (they share bodies).
    if (colorStart[0] != 0 || js[0] != 0) {
      Stage st{kind, static_cast<std::uint8_t>(odd), 0, static_cast<std::uint32_t>(colorStart[0]),
               static_cast<std::uint32_t>(colorStart[0])};
      st.jointCount = static_cast<std::uint32_t>(js[0]);
      st.jointSize = st.jointCount;
      stages.push_back(st);
      stageBlocks.push_back(1);
    }
    for (int c = 0; c < kColors; ++c)
      add(kind, odd, colorStart[c], colorStart[c + 1] - colorStart[c], kMinBlocks,
          TaskRunner::kRangesPerWorker, js[c], js[c + 1] - js[c]);
  };
  const std::size_t slots = s.states.size() - 1;  // slot 0 is the resting dummy
  add(Kind::prepare, false, 0, blockCount, kMinBlocks, TaskRunner::kHeavyRangesPerWorker, 0,
      s.jointItems.size());
  for (int stepIndex = 0; stepIndex < substeps; ++stepIndex) {
    const bool odd = (stepIndex & 1) != 0;
    add(Kind::velocities, false, 1, slots, kMinSlots);
    addPass(Kind::warm, false);
    addPass(Kind::solve, odd);
    add(Kind::positions, false, 1, slots, kMinSlots);
    // Relax: remove the velocity the soft push added, so it does not become bounce.
    addPass(Kind::relax, !odd);
  }
  addPass(Kind::bounce, false);
  s.hits.resize(blockCount * W);
  add(Kind::impulses, false, 0, blockCount, kMinBlocks);

  JointSim* jointSims = s.joints.data();
  auto jointBody = [&](std::uint32_t index, bool moved) {
    JointBody jb;
    if (index == kNoBody) return jb;
    const Body& b = store.bodies[index];
    if (moved) {
      jb.invMass = b.invMass;
      jb.invInertia = b.invInertia;
    }
    jb.center = b.center;
    jb.localCenter = b.localCenter;
    jb.q = b.xf.q;
    return jb;
  };
  auto prepareOne = [&](JointSim& sim) {
    const Joint& joint = jointSet.joints[sim.joint];
    prepareJoint(sim, joint, jointBody(joint.bodyA, sim.writeA), jointBody(joint.bodyB, sim.writeB),
                 params.joint);
  };
  auto runJointBlock = [&](Kind kind, std::uint32_t bi) {
    JointBlock<F>& jb = jointBlocks[bi];
    switch (kind) {
      case Kind::prepare: {
        const SolverScratch::JointBlockJoints r = s.jointBlockJoints[bi];
        jb = JointBlock<F>{};
        for (std::uint32_t lane = 0; lane < r.count; ++lane) {
          const JointSim& sim = jointSims[r.first + lane];
          const Joint& joint = jointSet.joints[sim.joint];
          prepareJointLane(jb, static_cast<int>(lane), sim, joint,
                           jointBody(joint.bodyA, sim.writeA), jointBody(joint.bodyB, sim.writeB),
                           params.joint);
        }
        break;
      }
      case Kind::warm:
        warmStartJointBlock(jb, states);
        break;
      case Kind::solve:
        solveJointBlock<true>(jb, states, s.turned.data(), params.joint);
        break;
      case Kind::relax:
        solveJointBlock<false>(jb, states, s.turned.data(), params.joint);
        break;
      default:
        break;
    }
  };
  auto runJoints = [&](Kind kind, std::size_t first, std::size_t count) {
    for (std::size_t item = first; item < first + count; ++item) {
      const std::uint32_t code = s.jointItems[item];
      if ((code & SolverScratch::kJointBlockItem) != 0) {
        runJointBlock(kind, code & ~SolverScratch::kJointBlockItem);
        continue;
      }
      JointSim& sim = jointSims[code];
      switch (kind) {
        case Kind::prepare:
          prepareOne(sim);
          break;
        case Kind::warm:
          warmStartJoint(sim, states);
          break;
        case Kind::solve:
          solveJoint(sim, states, s.turned.data(), params.joint, true);
          break;
        case Kind::relax:
          solveJoint(sim, states, s.turned.data(), params.joint, false);
          break;
        default:
          break;
      }
    }
  };

  tasks.runStages(stageBlocks, [&](int stage, int taskBlock, int) {
    const Stage& st = stages[static_cast<std::size_t>(stage)];
    std::size_t first = 0, count = 0;
    if (static_cast<std::uint32_t>(taskBlock) < st.jointBlocks) {
      const std::size_t jfirst = st.jointFirst + static_cast<std::size_t>(taskBlock) * st.jointSize;
      runJoints(st.kind, jfirst,
                std::min<std::size_t>(st.jointSize, st.jointFirst + st.jointCount - jfirst));
      return;
    }
    if (st.jointBlocks == 0 && st.jointCount > 0) {
      // The overflow stage: its joints, then its contacts, on this one worker.
      runJoints(st.kind, st.jointFirst, st.jointCount);
    }
    if (st.count == 0) return;
    const int block = taskBlock - static_cast<int>(st.jointBlocks);
    first = st.first + static_cast<std::size_t>(block) * st.size;
    count = std::min<std::size_t>(st.size, st.first + st.count - first);
    switch (st.kind) {
      case Kind::prepare:
        prepareBlocks(s, blocks, first, first + count, store, contactSet, params);
        break;
      case Kind::velocities:
        integrateVelocities(s, first, first + count);
        break;
      case Kind::warm:
        warmStart(all + first, count, states);
        break;
      case Kind::solve:
        solveContacts<true>(all + first, count, states, params.invH, params.pushMax, st.odd != 0);
        break;
      case Kind::positions:
        integratePositions(s, first, first + count, params.h, def.maxRotationPerSubstep);
        break;
      case Kind::relax:
        solveContacts<false>(all + first, count, states, params.invH, params.pushMax, st.odd != 0);
        break;
      case Kind::bounce:
        applyRestitution(all + first, count, states, params.restitutionThreshold);
        break;
      case Kind::impulses:
        storeImpulses(s, blocks, def, contactSet.impulses, first, first + count);
        break;
    }
  });
  reportHits(s, store, contactSet, events);
  // The lanes' joints finished (the others are, after the step, from their sims).
  for (std::size_t bi = 0; bi < s.jointBlockJoints.size(); ++bi) {
    const SolverScratch::JointBlockJoints r = s.jointBlockJoints[bi];
    for (std::uint32_t lane = 0; lane < r.count; ++lane)
      finishJointLane(jointBlocks[bi], static_cast<int>(lane),
                      jointSet.joints[jointSims[r.first + lane].joint], params.invH);
  }
  // The next step's narrow phase writes each sim in this step's lane of its contact.
  contactSet.placeSims(s.touching, s.lane, blockCount * W);
}

}  // namespace

Solver::Solver() : scratch_(std::make_unique<SolverScratch>()) {}
Solver::~Solver() = default;

const char* Solver::simdPath() noexcept {
  return kSimdPath;
}

std::span<const std::uint32_t> Solver::solve(StepContext& step, ContactSet& contactSet,
                                             JointSet& jointSet,
                                             const std::vector<std::uint64_t>& awake) {
  const WorldDef& def = step.def;
  BodyStore& store = step.store;
  BroadPhase& broadPhase = step.broadPhase;
  EventDispatcher& events = step.events;
  TaskRunner& tasks = step.tasks;
  const float dt = step.dt;
  const int substeps = step.substeps;
  SolverScratch& s = *scratch_;
  std::vector<Body>& bodies = store.bodies;
  const std::vector<ContactHead>& heads = contactSet.heads();
  StepParams params;
  params.h = dt / static_cast<float>(substeps);
  params.invH = 1.0f / params.h;
  // Contacts stiffer than a quarter of the sub-step rate are not resolved by the sub-step.
  const float hertz = minf(def.contactHertz, 0.25f * params.invH);
  params.soft = makeSoftness(hertz, def.contactDampingRatio, params.h);
  params.staticSoft = makeSoftness(2.0f * hertz, def.contactDampingRatio, params.h);
  params.pushMax = def.contactPushMaxSpeed;
  params.restitutionThreshold = def.restitutionThreshold;
  params.joint.h = params.h;
  params.joint.invH = params.invH;
  params.joint.jointSoft =
      makeSoftness(minf(def.jointHertz, 0.25f * params.invH), def.jointDampingRatio, params.h);

  // The moving bodies' state, contiguous: slot 0 is the resting body static bodies read.
  // The awake set in body order (sleeping bodies, like static ones, read slot 0): each word
  // of the awake bits gets its slots from a running count, then the words fill their slots
  // on the workers.
  const float h = params.h;
  s.wordSlot.resize(awake.size() + 1);
  std::size_t slotCount = 1;
  for (std::size_t word = 0; word < awake.size(); ++word) {
    s.wordSlot[word] = static_cast<std::uint32_t>(slotCount);
    slotCount += static_cast<std::size_t>(__builtin_popcountll(awake[word]));
  }
  s.states.resize(slotCount);
  s.slotBodies.resize(slotCount);
  s.sims.resize(slotCount);
  s.slotBody.resize(slotCount);
  s.states[0] = BodyState{};
  s.sims[0] = SlotSim{};
  s.slotBody[0] = 0;
  s.bodySlot.assign(bodies.size(), 0);
  tasks.parallelFor(static_cast<int>(awake.size()), kMinWords, [&](int first, int last, int) {
    for (auto word = static_cast<std::size_t>(first); word < static_cast<std::size_t>(last);
         ++word) {
      std::size_t slot = s.wordSlot[word];
      for (std::uint64_t bits = awake[word]; bits != 0; bits &= bits - 1, ++slot) {
        const auto i = static_cast<std::uint32_t>(word * 64 + __builtin_ctzll(bits));
        const Body& b = bodies[i];
        s.bodySlot[i] = static_cast<std::int32_t>(slot);
        s.slotBody[slot] = i;
        BodyState& st = s.states[slot];
        st = BodyState{};
        st.vx = b.v.x;
        st.vy = b.v.y;
        // A dynamic body without rotational inertia (zero density, or segments only) does
        // not turn, whatever spin it was given.
        st.w = (b.type == BodyType::dynamicBody && b.invInertia == 0.0f) ? 0.0f : b.w;
        s.slotBodies[slot] = {b.invMass, b.invInertia, b.center, b.localCenter};
        SlotSim& m = s.sims[slot];
        m = SlotSim{};
        m.dynamic = b.type == BodyType::dynamicBody;
        m.gravityDv = (h * b.gravityScale) * def.gravity;
        m.forced = b.force.x != 0.0f || b.force.y != 0.0f;
        m.forceDv = (h * b.invMass) * b.force;
        m.torqued = b.torque != 0.0f;
        m.torqueDw = h * b.invInertia * b.torque;
        m.linearScale = 1.0f / (1.0f + h * b.linearDamping);
        m.angularDivisor = 1.0f + h * b.angularDamping;
      }
    }
  });
  s.turned.assign(s.states.size(), 0.0f);

  // Touching contacts (a dynamic body in every one), in contact order.
  // Gathered on the workers (the contact heads, in order), joined in order.
  tasks.gather(contactSet.awakeWordCount(), kMinWords, s.pairParts, s.pairs,
               [&](int first, int last, std::vector<SolverScratch::Pair>& list) {
                 contactSet.forEachAwakeIn(first, last, [&](std::uint32_t ci) {
                   const ContactHead& c = heads[ci];
                   if (!c.alive || !c.touching || c.sensor) return;
                   const std::uint32_t a = c.bodyA, b = c.bodyB;
                   const std::int32_t sa = s.bodySlot[a], sb = s.bodySlot[b];
                   // Solved when a dynamic body in it is awake (contacts of sleeping bodies
                   // rest).
                   if (!s.sims[sa].dynamic && !s.sims[sb].dynamic) return;
                   list.push_back({ci, a, b, sa, sb, s.sims[sa].dynamic, s.sims[sb].dynamic});
                 });
               });
  s.touching.resize(s.pairs.size());
  for (std::size_t k = 0; k < s.pairs.size(); ++k)
    s.touching[k] = s.pairs[k].contact;
  stats_.constraints = s.touching.size();
  // Joints with an awake dynamic body, in joint order (a mouse joint's missing body A reads
  // the resting slot).
  s.jointsFound.clear();
  for (std::uint32_t j = 0; j < jointSet.joints.size(); ++j) {
    const Joint& joint = jointSet.joints[j];
    if (!joint.alive) continue;
    const std::int32_t sa = joint.bodyA == kNoBody ? 0 : s.bodySlot[joint.bodyA];
    const std::int32_t sb = s.bodySlot[joint.bodyB];
    const bool dynA = s.sims[static_cast<std::size_t>(sa)].dynamic;
    const bool dynB = s.sims[static_cast<std::size_t>(sb)].dynamic;
    if (!dynA && !dynB) continue;
    const std::uint8_t group = !solvedInLanes(joint.def) ? 2 : plainRevolute(joint.def) ? 0 : 1;
    s.jointsFound.push_back({j, sa, sb, dynA, dynB, group});
  }
  stats_.joints = s.jointsFound.size();

  if (def.scalarSolver) {
    runStep(s, s.narrow, s.jointNarrow, def, store, contactSet, jointSet, events, params, substeps,
            stats_, tasks);
  } else {
    runStep(s, s.wide, s.jointWide, def, store, contactSet, jointSet, events, params, substeps,
            stats_, tasks);
  }
  // The joints' force and torque of this step, and those past their break thresholds.
  s.broken.clear();
  for (const JointSim& sim : s.joints) {
    Joint& joint = jointSet.joints[sim.joint];
    if (!sim.lanes) finishJoint(sim, joint, params.invH);
    if (length(joint.force) > joint.def.breakForce || absf(joint.torque) > joint.def.breakTorque)
      s.broken.push_back(sim.joint);
  }
  std::sort(s.broken.begin(), s.broken.end());

  // Finalise bodies (on the workers: each writes its own body), then move their proxies
  // and report those stopped at the edge of the world, in slot order.
  s.placed.resize(s.states.size());
  tasks.parallelFor(
      static_cast<int>(s.states.size()) - 1, kMinSlots,
      [&](int first, int last, int) {
        for (auto slot = static_cast<std::size_t>(first) + 1;
             slot <= static_cast<std::size_t>(last); ++slot) {
          const std::uint32_t i = s.slotBody[slot];
          Body& b = bodies[i];
          const BodyState& st = s.states[slot];
          const Vec2 dp{st.dpx, st.dpy};
          // Forces act through one step.
          b.force = {};
          b.torque = 0.0f;
          // Restitution may have sped a body up after the last clamp.
          b.v = clampSpeed(Vec2{st.vx, st.vy});
          b.w = clampf(st.w, -kMaxAngularSpeed, kMaxAngularSpeed);
          const float turned = s.turned[slot];
          // Continuous collision wants the sweeps of fast bodies (world.hpp, kCcdFastFraction).
          b.fast = b.type == BodyType::dynamicBody && def.enableContinuous && b.maxExtent > 0.0f &&
                   (b.bullet ||
                    length(dp) + absf(turned) * b.maxExtent > kCcdFastFraction * b.minExtent);
          if (b.fast) {
            b.startCenter = b.center;
            b.startAngle = b.xf.q.angle();
            b.endAngle = b.startAngle + turned;
          }
          const Vec2 center = b.center + dp;
          const Rot q = normalizeRot(mulRot(Rot{st.qc, st.qs}, b.xf.q));
          const Transform xf{center - rotate(q, b.localCenter), q};
          SolverScratch::Placed& p = s.placed[slot];
          p.inside = store.placeBody(i, xf, center, p.box);
          p.follow = p.inside && store.placeProxy(broadPhase, i, p.box, dp);
          if (!p.inside) {
            // The edge of the world (world.hpp, kMaxCoordinate): the body stays where the step
            // began, stopped, and the game is told (StepEvents::outOfBounds).
            b.v = {};
            b.w = 0.0f;
            b.fast = false;
          }
        }
      },
      TaskRunner::kHeavyRangesPerWorker);
  for (std::size_t slot = 1; slot < s.states.size(); ++slot) {
    const std::uint32_t i = s.slotBody[slot];
    const SolverScratch::Placed& p = s.placed[slot];
    if (p.follow) {
      const BodyState& st = s.states[slot];
      store.followBody(broadPhase, i, p.box, Vec2{st.dpx, st.dpy});
    } else if (!p.inside) {
      events.events.outOfBounds.push_back(store.bodyId(i));
    }
  }
  return s.broken;
}

}  // namespace quack::detail
