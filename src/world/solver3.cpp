#include "solver3.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "body_store3.hpp"
#include "quack/world/world.hpp"
#include "simd.hpp"
#include "solver.hpp"
#include "task_runner.hpp"

namespace quack::detail {

namespace {

// ---- three-vectors of lanes --------------------------------------------------------------

template <class F>
struct V3 {
  F x, y, z;
};
template <class F>
[[gnu::always_inline]] inline V3<F> operator+(V3<F> a, V3<F> b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class F>
[[gnu::always_inline]] inline V3<F> operator-(V3<F> a, V3<F> b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class F>
[[gnu::always_inline]] inline V3<F> operator*(F s, V3<F> a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class F>
[[gnu::always_inline]] inline F dot(V3<F> a, V3<F> b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class F>
[[gnu::always_inline]] inline V3<F> cross(V3<F> a, V3<F> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class F>
[[gnu::always_inline]] inline V3<F> select(decltype(greater(F{}, F{})) m, V3<F> a, V3<F> b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
template <class F>
V3<F> ld3(const float* x, const float* y, const float* z) {
  return {ld<F>(x), ld<F>(y), ld<F>(z)};
}
template <class F>
void st3(float* x, float* y, float* z, V3<F> v) {
  store(x, v.x);
  store(y, v.y);
  store(z, v.z);
}

// A symmetric 3 x 3 matrix of lanes (an inverse inertia in world axes): xx, xy, xz, yy, yz,
// zz. Only the upper triangle of a body's R I^-1 R^T is read, so the product is the same
// whichever way round rounding left the two triangles.
template <class F>
struct Sym3 {
  F xx, xy, xz, yy, yz, zz;
};
template <class F>
[[gnu::always_inline]] inline V3<F> operator*(const Sym3<F>& m, V3<F> v) {
  return {m.xx * v.x + m.xy * v.y + m.xz * v.z, m.xy * v.x + m.yy * v.y + m.yz * v.z,
          m.xz * v.x + m.yz * v.y + m.zz * v.z};
}
template <class F>
Sym3<F> ldSym(const float (*m)[F::width]) {
  return {ld<F>(m[0]), ld<F>(m[1]), ld<F>(m[2]), ld<F>(m[3]), ld<F>(m[4]), ld<F>(m[5])};
}

// ---- the constraints, a block of lanes at a time -----------------------------------------
//
// A block holds F::width manifolds side by side, each field an array with one entry per
// lane (structure of arrays), so that a lane's manifold is solved with the same operations
// as every other lane's and as the one-lane path's. Empty lanes have zero masses and read
// the resting body in slot 0; they change nothing and write nothing. A lane with fewer
// points than the block's most has points of zero mass, which give zero impulses (+0), and
// adding or subtracting them leaves every velocity as it was: no velocity in the solver is
// ever -0 (velocities enter as v + 0, and sums and positive scalings never make a -0 from
// anything else), so the bits do not depend on which lanes a manifold shares a block with.
template <class F>
struct alignas(64) ContactBlock3 {
  static constexpr int W = F::width;
  struct Point {
    float rAx[W], rAy[W], rAz[W], rBx[W], rBy[W], rBz[W];  // arms from the centres of mass
    float separation[W];  // as the manifold has it, at the start of the step
    float normalMass[W], normalImpulse[W], maxNormalImpulse[W];
    float relativeVelocity[W];  // normal velocity before the step (restitution)
    float lever[W];             // distance from the manifold's centre (twist friction)
  };
  Point points[kMaxManifoldPoints3];
  float nx[W], ny[W], nz[W], t1x[W], t1y[W], t1z[W], t2x[W], t2y[W], t2z[W];
  // Friction acts at the centre of the points (its arms the mean of the points' arms).
  float cAx[W], cAy[W], cAz[W], cBx[W], cBy[W], cBz[W];
  float tangentMass1[W], tangentMass2[W], tangentImpulse1[W], tangentImpulse2[W];
  float twistMass[W], twistImpulse[W];
  float friction[W], restitution[W], rolling[W];
  float biasRate[W], massScale[W], impulseScale[W];
  float mA[W], mB[W];
  float iA[6][W], iB[6][W];  // inverse inertia, world axes (Sym3)
  float rollingMass[6][W], rollingImpulse[3][W];
  std::int32_t slotA[W], slotB[W];       // slots of the solver's body states; 0 = at rest
  std::uint32_t writeA = 0, writeB = 0;  // lanes whose body is dynamic (bit per lane)
  std::int32_t pointCount = 0;           // the most points of any lane
};

template <class F>
struct BlockBodies {
  BodyLanes3<F> A, B;
  F mA, mB;
  Sym3<F> iA, iB;
};

template <class F>
[[gnu::always_inline]] inline BlockBodies<F> gatherBodies(const ContactBlock3<F>& b,
                                                          const BodyState3* states) {
  return {gather3(states, b.slotA, F{}),
          gather3(states, b.slotB, F{}),
          ld<F>(b.mA),
          ld<F>(b.mB),
          ldSym<F>(b.iA),
          ldSym<F>(b.iB)};
}
template <class F>
V3<F> velocity(const BodyLanes3<F>& s) {
  return {s.vx, s.vy, s.vz};
}
template <class F>
V3<F> spin(const BodyLanes3<F>& s) {
  return {s.wx, s.wy, s.wz};
}
template <class F>
void setVelocity(BodyLanes3<F>& s, V3<F> v) {
  s.vx = v.x;
  s.vy = v.y;
  s.vz = v.z;
}
template <class F>
void setSpin(BodyLanes3<F>& s, V3<F> w) {
  s.wx = w.x;
  s.wy = w.y;
  s.wz = w.z;
}

// An impulse P at arms rA, rB: A loses it, B gains it.
template <class F>
[[gnu::always_inline]] inline void applyImpulse(BlockBodies<F>& k, V3<F> rA, V3<F> rB, V3<F> P) {
  setVelocity(k.A, velocity(k.A) - k.mA * P);
  setSpin(k.A, spin(k.A) - k.iA * cross(rA, P));
  setVelocity(k.B, velocity(k.B) + k.mB * P);
  setSpin(k.B, spin(k.B) + k.iB * cross(rB, P));
}
// An angular impulse L: A loses it, B gains it.
template <class F>
[[gnu::always_inline]] inline void applyAngular(BlockBodies<F>& k, V3<F> L) {
  setSpin(k.A, spin(k.A) - k.iA * L);
  setSpin(k.B, spin(k.B) + k.iB * L);
}
// B's velocity at rB less A's at rA.
template <class F>
[[gnu::always_inline]] inline V3<F> relativeVelocity(const BlockBodies<F>& k, V3<F> rA, V3<F> rB) {
  return (velocity(k.B) + cross(spin(k.B), rB)) - (velocity(k.A) + cross(spin(k.A), rA));
}

template <class F>
[[gnu::noinline]] void warmStart(ContactBlock3<F>* blocks, std::size_t count, BodyState3* states) {
  for (std::size_t bi = 0; bi < count; ++bi) {
    ContactBlock3<F>& b = blocks[bi];
    BlockBodies<F> k = gatherBodies(b, states);
    const V3<F> n = ld3<F>(b.nx, b.ny, b.nz);
    for (int j = 0; j < b.pointCount; ++j) {
      const auto& p = b.points[j];
      applyImpulse(k, ld3<F>(p.rAx, p.rAy, p.rAz), ld3<F>(p.rBx, p.rBy, p.rBz),
                   ld<F>(p.normalImpulse) * n);
    }
    const V3<F> P = ld<F>(b.tangentImpulse1) * ld3<F>(b.t1x, b.t1y, b.t1z) +
                    ld<F>(b.tangentImpulse2) * ld3<F>(b.t2x, b.t2y, b.t2z);
    applyImpulse(k, ld3<F>(b.cAx, b.cAy, b.cAz), ld3<F>(b.cBx, b.cBy, b.cBz), P);
    applyAngular(k, ld<F>(b.twistImpulse) * n);
    applyAngular(k, ld3<F>(b.rollingImpulse[0], b.rollingImpulse[1], b.rollingImpulse[2]));
    scatter3(states, b.slotA, b.writeA, k.A);
    scatter3(states, b.slotB, b.writeB, k.B);
  }
}

// One pass: normal impulses (soft with the push when useBias, rigid without it in the relax
// pass; speculative points ahead of contact in both), then friction at the manifold's
// centre (two tangents within the Coulomb circle of the total normal impulse, then the
// twist within friction times each point's lever arm times its normal impulse), then
// rolling resistance. The points go first-to-last or, when `lastFirst`, last-to-first: the
// first point solved takes more of the load in a pass, and always the same corner first
// would push a box sideways a little every sub-step (the 2D solver alternates the same way).
template <bool useBias, class F>
[[gnu::noinline]] void solveBlocks(ContactBlock3<F>* blocks, std::size_t count, BodyState3* states,
                                   float invH, float pushMax, bool lastFirst) {
  const F zero = sp<F>(0.0f), one = sp<F>(1.0f), invHW = sp<F>(invH), minBias = sp<F>(-pushMax);
  for (std::size_t bi = 0; bi < count; ++bi) {
    ContactBlock3<F>& b = blocks[bi];
    BlockBodies<F> k = gatherBodies(b, states);
    const V3<F> n = ld3<F>(b.nx, b.ny, b.nz);
    const V3<F> dp = V3<F>{k.B.dpx, k.B.dpy, k.B.dpz} - V3<F>{k.A.dpx, k.A.dpy, k.A.dpz};
    const V3<F> turnA{k.A.tx, k.A.ty, k.A.tz}, turnB{k.B.tx, k.B.ty, k.B.tz};
    F biasRate = zero, softMass = one, softImpulse = zero;
    if constexpr (useBias) {
      biasRate = ld<F>(b.biasRate);
      softMass = ld<F>(b.massScale);
      softImpulse = ld<F>(b.impulseScale);
    }
    F totalNormal = zero;
    const int points = b.pointCount;
    for (int m = 0; m < points; ++m) {
      auto& p = b.points[lastFirst ? points - 1 - m : m];
      const V3<F> rA = ld3<F>(p.rAx, p.rAy, p.rAz), rB = ld3<F>(p.rBx, p.rBy, p.rBz);
      // The separation now, from the bodies' motion since the manifold was made: each
      // anchor r moved by dp + turn x r. The anchors turn to first order only: turned
      // exactly, a rolling ball's anchor would rise by r (1 - cos angle) and the solver
      // would let the ball sink by as much; the manifold, made anew each step, carries the
      // true geometry.
      const F s = dot(n, dp + (cross(turnB, rB) - cross(turnA, rA))) + ld<F>(p.separation);
      const auto apart = greater(s, zero);
      F bias, massScale, impulseScale;
      if constexpr (useBias) {
        bias = select(apart, s * invHW, maxW(biasRate * s, minBias));
        massScale = select(apart, one, softMass);
        impulseScale = select(apart, zero, softImpulse);
      } else {
        bias = select(apart, s * invHW, zero);  // speculative: close the gap, no more
        massScale = one;
        impulseScale = zero;
      }
      const F vn = dot(relativeVelocity(k, rA, rB), n);
      const F ni = ld<F>(p.normalImpulse);
      F impulse = (zero - ld<F>(p.normalMass) * massScale * (vn + bias)) - impulseScale * ni;
      const F total = maxW(ni + impulse, zero);
      impulse = total - ni;
      store(p.normalImpulse, total);
      store(p.maxNormalImpulse, maxW(ld<F>(p.maxNormalImpulse), impulse));
      totalNormal = totalNormal + total;
      applyImpulse(k, rA, rB, impulse * n);
    }
    const F friction = ld<F>(b.friction);
    {
      const V3<F> cA = ld3<F>(b.cAx, b.cAy, b.cAz), cB = ld3<F>(b.cBx, b.cBy, b.cBz);
      const V3<F> t1 = ld3<F>(b.t1x, b.t1y, b.t1z), t2 = ld3<F>(b.t2x, b.t2y, b.t2z);
      const V3<F> dv = relativeVelocity(k, cA, cB);
      const F old1 = ld<F>(b.tangentImpulse1), old2 = ld<F>(b.tangentImpulse2);
      F f1 = old1 - ld<F>(b.tangentMass1) * dot(dv, t1);
      F f2 = old2 - ld<F>(b.tangentMass2) * dot(dv, t2);
      // The Coulomb circle: the friction impulse within friction times the normal impulse.
      const F limit = friction * totalNormal;
      const F f = sqrtW(f1 * f1 + f2 * f2);
      const auto over = greater(f, limit);
      const F scale = limit / select(over, f, one);
      f1 = select(over, f1 * scale, f1);
      f2 = select(over, f2 * scale, f2);
      store(b.tangentImpulse1, f1);
      store(b.tangentImpulse2, f2);
      applyImpulse(k, cA, cB, (f1 - old1) * t1 + (f2 - old2) * t2);
    }
    {
      // A point's lever is zero in a lane with one point (or none): no twist there.
      F twistLimit = zero;
      for (int j = 0; j < points; ++j)
        twistLimit = twistLimit + ld<F>(b.points[j].lever) * ld<F>(b.points[j].normalImpulse);
      twistLimit = friction * twistLimit;
      const F old = ld<F>(b.twistImpulse);
      const F twist = dot(n, spin(k.B) - spin(k.A));
      const F total = maxW(minW(old - ld<F>(b.twistMass) * twist, twistLimit), zero - twistLimit);
      store(b.twistImpulse, total);
      applyAngular(k, (total - old) * n);
    }
    const F rolling = ld<F>(b.rolling);
    if (any(greater(rolling, zero))) {
      const V3<F> old = ld3<F>(b.rollingImpulse[0], b.rollingImpulse[1], b.rollingImpulse[2]);
      V3<F> total = old - ldSym<F>(b.rollingMass) * (spin(k.B) - spin(k.A));
      const F limit = rolling * totalNormal;
      const F len = sqrtW(dot(total, total));
      const auto over = greater(len, limit);
      total = select(over, (limit / select(over, len, one)) * total, total);
      st3(b.rollingImpulse[0], b.rollingImpulse[1], b.rollingImpulse[2], total);
      applyAngular(k, total - old);
    }
    scatter3(states, b.slotA, b.writeA, k.A);
    scatter3(states, b.slotB, b.writeB, k.B);
  }
}

// After the sub-steps: points that approached faster than the threshold and were pushed get
// the normal velocity -e times their approach speed (Box2D v3's restitution, on the relaxed
// velocities). Lanes without it are left exactly as they were (selects, not zero impulses).
template <class F>
[[gnu::noinline]] void applyRestitution(ContactBlock3<F>* blocks, std::size_t count,
                                        BodyState3* states, float threshold) {
  const F zero = sp<F>(0.0f), minusThreshold = sp<F>(-threshold);
  for (std::size_t bi = 0; bi < count; ++bi) {
    ContactBlock3<F>& b = blocks[bi];
    const F e = ld<F>(b.restitution);
    const auto bouncy = greater(e, zero);
    if (!any(bouncy)) continue;
    BlockBodies<F> k = gatherBodies(b, states);
    const V3<F> n = ld3<F>(b.nx, b.ny, b.nz);
    for (int j = 0; j < b.pointCount; ++j) {
      auto& p = b.points[j];
      const auto want = bouncy & greater(minusThreshold, ld<F>(p.relativeVelocity)) &
                        greater(ld<F>(p.maxNormalImpulse), zero);
      if (!any(want)) continue;
      const V3<F> rA = ld3<F>(p.rAx, p.rAy, p.rAz), rB = ld3<F>(p.rBx, p.rBy, p.rBz);
      const F vn = dot(relativeVelocity(k, rA, rB), n);
      const F ni = ld<F>(p.normalImpulse);
      F impulse = zero - ld<F>(p.normalMass) * (vn + e * ld<F>(p.relativeVelocity));
      const F total = maxW(ni + impulse, zero);
      impulse = total - ni;
      store(p.normalImpulse, select(want, total, ni));
      const F maxNi = ld<F>(p.maxNormalImpulse);
      store(p.maxNormalImpulse, select(want, maxW(maxNi, impulse), maxNi));
      BlockBodies<F> moved = k;
      applyImpulse(moved, rA, rB, impulse * n);
      setVelocity(k.A, select(want, velocity(moved.A), velocity(k.A)));
      setSpin(k.A, select(want, spin(moved.A), spin(k.A)));
      setVelocity(k.B, select(want, velocity(moved.B), velocity(k.B)));
      setSpin(k.B, select(want, spin(moved.B), spin(k.B)));
    }
    scatter3(states, b.slotA, b.writeA, k.A);
    scatter3(states, b.slotB, b.writeB, k.B);
  }
}

// ---- colours and the per-step arrays -----------------------------------------------------

// Colours (solver.hpp, takeColor). A body with more manifolds than the colours hold (a box
// on a mesh floor has one per triangle it touches) sends the rest to the overflow set.
constexpr int kColors = kSolverColors;
constexpr int kOverflow = kSolverOverflow;
// Smallest shares of work handed to a worker: below these a task costs more than it saves.
constexpr int kMinBlocks = 4;
constexpr int kMinSlots = 64;

// What a slot's body needs over the step besides its lanes: read by integration, preparing
// and the write-back.
struct SlotSim3 {
  std::uint32_t body = 0;
  bool dynamic = false;
  float invMass = 0.0f;
  float invI[6] = {};  // world axes, fixed over the step (as Box2D v3 keeps its inertia)
  Quat q, q0;          // rotation now, and at the start of the step
  Vec3 gravityDv;      // gravity's velocity change per sub-step
  float linearScale = 1.0f, angularScale = 1.0f;  // implicit damping per sub-step
};

}  // namespace

struct SolverScratch3 {
  // A touching manifold with an awake body, in contact order.
  struct Item {
    ContactManifold3* manifold;
    const Contact3* contact;
    std::int32_t slotA, slotB;
    bool dynamicA, dynamicB;
  };
  std::vector<std::uint32_t> bodySlot;  // per body index: its slot, 0 for none
  std::vector<BodyState3> states;       // per slot (slot 0: at rest)
  std::vector<SlotSim3> sims;
  std::vector<Item> items;
  std::vector<std::uint8_t> color;
  std::vector<std::uint32_t> slotColors;  // per slot: the colours its body is in
  std::vector<const Item*> laneItems;     // per lane: its item, or none
  std::vector<ContactBlock3<FloatS>> narrow;
  std::vector<ContactBlock3<FloatW>> wide;
  std::vector<int> stageBlocks;
  std::vector<std::uint8_t> inside;  // per slot: the body stayed inside the world
  std::vector<Aabb3> boxes;          // per shape of a moved body: its new box
};

namespace {

struct StepParams3 {
  float h = 0.0f, invH = 0.0f, pushMax = 0.0f, restitutionThreshold = 0.0f;
  Softness soft, staticSoft;
};

// Colours the items and lays them out in blocks: the overflow set first (one manifold per
// block), then each colour's in contact order, `W` to a block. Returns the block count.
std::size_t layoutBlocks(SolverScratch3& s, int W, std::size_t* colorStart, Solver3::Stats& stats) {
  s.slotColors.assign(s.states.size(), 0);
  std::uint32_t* used = s.slotColors.data();
  std::size_t perColor[kColors + 1] = {};
  s.color.resize(s.items.size());
  for (std::size_t k = 0; k < s.items.size(); ++k) {
    const SolverScratch3::Item& item = s.items[k];
    const int color = takeColor(used, item.slotA, item.slotB, item.dynamicA, item.dynamicB);
    s.color[k] = static_cast<std::uint8_t>(color);
    ++perColor[color];
  }
  const std::size_t width = static_cast<std::size_t>(W);
  std::size_t next = perColor[kOverflow];
  stats.overflow = perColor[kOverflow];
  stats.colors = 0;
  for (int c = 0; c < kColors; ++c) {
    colorStart[c] = next;
    next += (perColor[c] + width - 1) / width;
    if (perColor[c] > 0) stats.colors = c + 1;
  }
  colorStart[kColors] = next;
  std::size_t fill[kColors + 1] = {};
  s.laneItems.assign(next * width, nullptr);
  for (std::size_t k = 0; k < s.items.size(); ++k) {
    const int c = s.color[k];
    const std::size_t at = c == kOverflow ? fill[c]++ * width : colorStart[c] * width + fill[c]++;
    s.laneItems[at] = &s.items[k];
  }
  return next;
}

Vec3 stateVelocity(const BodyState3& s) {
  return {s.vx, s.vy, s.vz};
}
Vec3 stateSpin(const BodyState3& s) {
  return {s.wx, s.wy, s.wz};
}
Vec3 symMul(const float* m, Vec3 v) {
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[1] * v.x + m[3] * v.y + m[4] * v.z,
          m[2] * v.x + m[4] * v.y + m[5] * v.z};
}
// 1 / (mA + mB + (rA x d) . I_A^-1 (rA x d) + (rB x d) . I_B^-1 (rB x d)), or 0.
float invEffectiveMass(const SlotSim3& a, const SlotSim3& b, Vec3 rA, Vec3 rB, Vec3 d) {
  const Vec3 xA = cross(rA, d), xB = cross(rB, d);
  const float k = a.invMass + b.invMass + dot(xA, symMul(a.invI, xA)) + dot(xB, symMul(b.invI, xB));
  return k > 0.0f ? 1.0f / k : 0.0f;
}
// Two unit tangents that make a right-handed basis with the unit normal n, chosen by n
// alone (so the same normal always gets the same basis): t1 is perpendicular to n and to
// the coordinate axis n is furthest from.
void computeTangents(Vec3 n, Vec3& t1, Vec3& t2) noexcept {
  if (std::fabs(n.x) >= 0.57735f) {
    t1 = normalize(Vec3{n.y, -n.x, 0.0f});
  } else {
    t1 = normalize(Vec3{0.0f, n.z, -n.y});
  }
  t2 = cross(n, t1);
}
template <int W>
void put3(float (&x)[W], float (&y)[W], float (&z)[W], int lane, Vec3 v) {
  x[lane] = v.x;
  y[lane] = v.y;
  z[lane] = v.z;
}

// One manifold into its lane.
template <class F>
void prepareLane(ContactBlock3<F>& b, int lane, const SolverScratch3::Item& item,
                 const SolverScratch3& s, const StepParams3& params) {
  const SlotSim3& a = s.sims[static_cast<std::size_t>(item.slotA)];
  const SlotSim3& bb = s.sims[static_cast<std::size_t>(item.slotB)];
  const BodyState3& sa = s.states[static_cast<std::size_t>(item.slotA)];
  const BodyState3& sb = s.states[static_cast<std::size_t>(item.slotB)];
  const ContactManifold3& m = *item.manifold;
  const Contact3& contact = *item.contact;
  b.slotA[lane] = item.slotA;
  b.slotB[lane] = item.slotB;
  if (item.dynamicA) b.writeA |= 1u << lane;
  if (item.dynamicB) b.writeB |= 1u << lane;
  const int count = m.manifold.pointCount;
  b.pointCount = std::max(b.pointCount, count);
  const Vec3 n = m.manifold.normal;
  Vec3 t1, t2;
  computeTangents(n, t1, t2);
  put3(b.nx, b.ny, b.nz, lane, n);
  put3(b.t1x, b.t1y, b.t1z, lane, t1);
  put3(b.t2x, b.t2y, b.t2z, lane, t2);
  b.friction[lane] = contact.friction;
  b.restitution[lane] = contact.restitution;
  b.rolling[lane] = contact.rollingResistance;
  const Softness soft = (a.invMass == 0.0f || bb.invMass == 0.0f) ? params.staticSoft : params.soft;
  b.biasRate[lane] = soft.biasRate;
  b.massScale[lane] = soft.massScale;
  b.impulseScale[lane] = soft.impulseScale;
  b.mA[lane] = a.invMass;
  b.mB[lane] = bb.invMass;
  for (int i = 0; i < 6; ++i) {
    b.iA[i][lane] = a.invI[i];
    b.iB[i][lane] = bb.invI[i];
  }
  if (contact.rollingResistance > 0.0f) {
    float sum[6];
    for (int i = 0; i < 6; ++i)
      sum[i] = a.invI[i] + bb.invI[i];
    const Mat3 k = Mat3::fromRows({sum[0], sum[1], sum[2]}, {sum[1], sum[3], sum[4]},
                                  {sum[2], sum[4], sum[5]});
    if (determinant(k) > 0.0f) {
      const Mat3 inv = inverse(k);
      const float upper[6] = {inv.cx.x, inv.cy.x, inv.cz.x, inv.cy.y, inv.cz.y, inv.cz.z};
      for (int i = 0; i < 6; ++i)
        b.rollingMass[i][lane] = upper[i];
    }
    b.rollingImpulse[0][lane] = m.rollingImpulse.x;
    b.rollingImpulse[1][lane] = m.rollingImpulse.y;
    b.rollingImpulse[2][lane] = m.rollingImpulse.z;
  }
  // The centre of the points, where friction acts, and each point's lever arm about it.
  Vec3 centreA, centreB;
  for (int i = 0; i < count; ++i) {
    centreA = centreA + m.armA[i];
    centreB = centreB + m.armB[i];
  }
  const float share = 1.0f / static_cast<float>(count);
  centreA = share * centreA;
  centreB = share * centreB;
  const Vec3 vA = stateVelocity(sa), wA = stateSpin(sa), vB = stateVelocity(sb), wB = stateSpin(sb);
  for (int i = 0; i < count; ++i) {
    auto& p = b.points[i];
    // The arms as the manifold was computed (kept while it is recycled: arms turned with
    // the bodies under a normal that stays put tilt a column further).
    const Vec3 rA = m.armA[i], rB = m.armB[i];
    put3(p.rAx, p.rAy, p.rAz, lane, rA);
    put3(p.rBx, p.rBy, p.rBz, lane, rB);
    p.separation[lane] = m.manifold.points[i].separation;
    p.normalMass[lane] = invEffectiveMass(a, bb, rA, rB, n);
    p.normalImpulse[lane] = m.normalImpulse[i];
    p.relativeVelocity[lane] = dot((vB + cross(wB, rB)) - (vA + cross(wA, rA)), n);
    p.lever[lane] = count > 1 ? length(rA - centreA) : 0.0f;
  }
  put3(b.cAx, b.cAy, b.cAz, lane, centreA);
  put3(b.cBx, b.cBy, b.cBz, lane, centreB);
  b.tangentMass1[lane] = invEffectiveMass(a, bb, centreA, centreB, t1);
  b.tangentMass2[lane] = invEffectiveMass(a, bb, centreA, centreB, t2);
  b.tangentImpulse1[lane] = dot(m.frictionImpulse, t1);
  b.tangentImpulse2[lane] = dot(m.frictionImpulse, t2);
  const float twist = dot(n, symMul(a.invI, n)) + dot(n, symMul(bb.invI, n));
  b.twistMass[lane] = twist > 0.0f ? 1.0f / twist : 0.0f;
  // One point has no lever arm and so no twist friction: an impulse carried from when the
  // manifold had more points must not be applied every sub-step (it spun a hull up to
  // 25 rad/s in the hull pile before this was caught).
  b.twistImpulse[lane] = count > 1 ? m.twistImpulse : 0.0f;
}

template <class F>
void prepareBlocks(SolverScratch3& s, std::vector<ContactBlock3<F>>& blocks, std::size_t first,
                   std::size_t last, const StepParams3& params) {
  constexpr int W = F::width;
  for (std::size_t bi = first; bi < last; ++bi) {
    ContactBlock3<F>& b = blocks[bi];
    b = ContactBlock3<F>{};
    for (int lane = 0; lane < W; ++lane) {
      const SolverScratch3::Item* item = s.laneItems[bi * W + static_cast<std::size_t>(lane)];
      if (item != nullptr) prepareLane(b, lane, *item, s, params);
    }
  }
}

// The impulses back to the manifolds for the next step's warm start.
template <class F>
void storeImpulses(const SolverScratch3& s, const std::vector<ContactBlock3<F>>& blocks,
                   std::size_t first, std::size_t last) {
  constexpr int W = F::width;
  for (std::size_t bi = first; bi < last; ++bi) {
    const ContactBlock3<F>& b = blocks[bi];
    for (int lane = 0; lane < W; ++lane) {
      const SolverScratch3::Item* item = s.laneItems[bi * W + static_cast<std::size_t>(lane)];
      if (item == nullptr) continue;
      ContactManifold3& m = *item->manifold;
      for (int i = 0; i < m.manifold.pointCount; ++i) {
        m.normalImpulse[i] = b.points[i].normalImpulse[lane];
        m.maxNormalImpulse[i] = b.points[i].maxNormalImpulse[lane];
      }
      const Vec3 t1{b.t1x[lane], b.t1y[lane], b.t1z[lane]};
      const Vec3 t2{b.t2x[lane], b.t2y[lane], b.t2z[lane]};
      m.frictionImpulse = b.tangentImpulse1[lane] * t1 + b.tangentImpulse2[lane] * t2;
      m.twistImpulse = b.twistImpulse[lane];
      if (item->contact->rollingResistance > 0.0f) {
        m.rollingImpulse = {b.rollingImpulse[0][lane], b.rollingImpulse[1][lane],
                            b.rollingImpulse[2][lane]};
      }
    }
  }
}

void integrateVelocities(SolverScratch3& s, std::size_t first, std::size_t last, float h) {
  for (std::size_t slot = first; slot < last; ++slot) {
    const SlotSim3& m = s.sims[slot];
    if (!m.dynamic) continue;  // kinematic: keeps its velocity
    BodyState3& st = s.states[slot];
    Vec3 v = stateVelocity(st) + m.gravityDv;
    v = m.linearScale * v;
    Vec3 w = m.angularScale * stateSpin(st);
    // Speed limits keep every number finite; a quarter turn per sub-step keeps the
    // first-order rotation update meaningful.
    const float speed = length(v);
    if (speed > kMaxLinearSpeed) v = (kMaxLinearSpeed / speed) * v;
    const float turn = length(w) * h;
    if (turn > 0.25f * kPi) w = (0.25f * kPi / turn) * w;
    st.vx = v.x;
    st.vy = v.y;
    st.vz = v.z;
    st.wx = w.x;
    st.wy = w.y;
    st.wz = w.z;
  }
}

void integratePositions(SolverScratch3& s, std::size_t first, std::size_t last, float h) {
  for (std::size_t slot = first; slot < last; ++slot) {
    BodyState3& st = s.states[slot];
    SlotSim3& m = s.sims[slot];
    st.dpx = st.dpx + h * st.vx;
    st.dpy = st.dpy + h * st.vy;
    st.dpz = st.dpz + h * st.vz;
    m.q = integrateRotation(m.q, stateSpin(st), h);
    // The turn since the step began, as a rotation vector to first order (2 x the vector
    // part of the delta quaternion, on the short way round).
    const Quat dq = m.q * conjugate(m.q0);
    const Vec3 turn = (dq.w < 0.0f ? -2.0f : 2.0f) * dq.vector();
    st.tx = turn.x;
    st.ty = turn.y;
    st.tz = turn.z;
  }
}

// The contact part of a step as one job of stages (task_runner.hpp): prepare, then per
// sub-step integrate velocities, warm start, solve, integrate positions, relax; then
// restitution and the impulses stored. A pass over the manifolds is the overflow set (one
// stage of one task: its manifolds share bodies), then each colour, whose blocks the
// workers share.
template <class F>
void runStep(SolverScratch3& s, std::vector<ContactBlock3<F>>& blocks, const StepParams3& params,
             int substeps, Solver3::Stats& stats, TaskRunner& tasks) {
  constexpr int W = F::width;
  std::size_t colorStart[kColors + 1];
  const std::size_t blockCount = layoutBlocks(s, W, colorStart, stats);
  blocks.resize(blockCount);
  ContactBlock3<F>* all = blocks.data();
  BodyState3* states = s.states.data();

  enum class Kind : std::uint8_t {
    prepare,
    velocities,
    warm,
    solve,
    positions,
    relax,
    bounce,
    store
  };
  struct Stage {
    Kind kind;
    bool odd;
    std::uint32_t first, count, size;  // blocks (or slots): first, how many, per task
  };
  std::vector<Stage> stages;
  s.stageBlocks.clear();
  auto add = [&](Kind kind, bool odd, std::size_t first, std::size_t count, int minRange,
                 int perWorker) {
    if (count == 0) return;
    const int size = tasks.rangeSize(static_cast<int>(count), minRange, perWorker);
    stages.push_back({kind, odd, static_cast<std::uint32_t>(first),
                      static_cast<std::uint32_t>(count), static_cast<std::uint32_t>(size)});
    s.stageBlocks.push_back((static_cast<int>(count) + size - 1) / size);
  };
  auto addPass = [&](Kind kind, bool odd) {
    if (colorStart[0] != 0) {
      // The overflow set, one manifold at a time on one worker.
      stages.push_back({kind, odd, 0, static_cast<std::uint32_t>(colorStart[0]),
                        static_cast<std::uint32_t>(colorStart[0])});
      s.stageBlocks.push_back(1);
    }
    for (int c = 0; c < kColors; ++c)
      add(kind, odd, colorStart[c], colorStart[c + 1] - colorStart[c], kMinBlocks,
          TaskRunner::kRangesPerWorker);
  };
  const std::size_t slots = s.states.size() - 1;  // slot 0 is the resting body
  add(Kind::prepare, false, 0, blockCount, kMinBlocks, TaskRunner::kHeavyRangesPerWorker);
  for (int sub = 0; sub < substeps; ++sub) {
    const bool odd = (sub & 1) != 0;
    add(Kind::velocities, false, 1, slots, kMinSlots, TaskRunner::kRangesPerWorker);
    addPass(Kind::warm, false);
    addPass(Kind::solve, odd);
    add(Kind::positions, false, 1, slots, kMinSlots, TaskRunner::kRangesPerWorker);
    // Relax: remove the velocity the soft push added, so it does not become bounce.
    addPass(Kind::relax, !odd);
  }
  addPass(Kind::bounce, false);
  add(Kind::store, false, 0, blockCount, kMinBlocks, TaskRunner::kRangesPerWorker);

  tasks.runStages(s.stageBlocks, [&](int stage, int task, int) {
    const Stage& st = stages[static_cast<std::size_t>(stage)];
    const std::size_t first = st.first + static_cast<std::size_t>(task) * st.size;
    const std::size_t count = std::min<std::size_t>(st.size, st.first + st.count - first);
    switch (st.kind) {
      case Kind::prepare:
        prepareBlocks(s, blocks, first, first + count, params);
        break;
      case Kind::velocities:
        integrateVelocities(s, first, first + count, params.h);
        break;
      case Kind::warm:
        warmStart(all + first, count, states);
        break;
      case Kind::solve:
        solveBlocks<true>(all + first, count, states, params.invH, params.pushMax, st.odd);
        break;
      case Kind::positions:
        integratePositions(s, first, first + count, params.h);
        break;
      case Kind::relax:
        solveBlocks<false>(all + first, count, states, params.invH, params.pushMax, st.odd);
        break;
      case Kind::bounce:
        applyRestitution(all + first, count, states, params.restitutionThreshold);
        break;
      case Kind::store:
        storeImpulses(s, blocks, first, first + count);
        break;
    }
  });
}

}  // namespace

Solver3::Solver3() : scratch_(std::make_unique<SolverScratch3>()) {}
Solver3::~Solver3() = default;

void Solver3::step(BodyStore3& store, ContactSet3& contacts, const WorldDef3& def, float dt,
                   int substeps, TaskRunner& tasks) {
  SolverScratch3& s = *scratch_;
  StepParams3 params;
  params.h = dt / static_cast<float>(substeps);
  params.invH = 1.0f / params.h;
  params.pushMax = def.contactPushMaxSpeed;
  params.restitutionThreshold = def.restitutionThreshold;
  // Contacts stiffer than a quarter of the sub-step rate are not resolved by the sub-step;
  // against static and kinematic bodies twice as stiff (the 2D solver's choice).
  const float hertz = std::min(def.contactHertz, 0.25f * params.invH);
  params.soft = makeSoftness(hertz, def.contactDampingRatio, params.h);
  params.staticSoft = makeSoftness(2.0f * hertz, def.contactDampingRatio, params.h);
  const float h = params.h;

  // The awake dynamic and kinematic bodies get slots in body order.
  s.bodySlot.assign(store.bodies.size(), 0);
  s.states.assign(1, BodyState3{});
  s.sims.assign(1, SlotSim3{});
  for (std::uint32_t i = 0; i < store.bodies.size(); ++i) {
    const Body3& b = store.bodies[i];
    if (!store.bodyIds.isAlive(i) || b.type == BodyType::staticBody || !b.awake) continue;
    s.bodySlot[i] = static_cast<std::uint32_t>(s.states.size());
    BodyState3 st;
    // + 0 turns a -0 into +0 (and changes nothing else): no velocity in the solver is -0,
    // which makes zero impulses exact no-ops (ContactBlock3).
    st.vx = b.linearVelocity.x + 0.0f;
    st.vy = b.linearVelocity.y + 0.0f;
    st.vz = b.linearVelocity.z + 0.0f;
    st.wx = b.angularVelocity.x + 0.0f;
    st.wy = b.angularVelocity.y + 0.0f;
    st.wz = b.angularVelocity.z + 0.0f;
    s.states.push_back(st);
    SlotSim3 m;
    m.body = i;
    m.dynamic = b.type == BodyType::dynamicBody;
    m.invMass = b.invMass;
    const Mat3 invI = b.invInertiaWorld();
    const float upper[6] = {invI.cx.x, invI.cy.x, invI.cz.x, invI.cy.y, invI.cz.y, invI.cz.z};
    std::copy(upper, upper + 6, m.invI);
    m.q = m.q0 = b.rotation;
    m.gravityDv = (h * b.gravityScale) * def.gravity;
    m.linearScale = 1.0f / (1.0f + h * b.linearDamping);
    m.angularScale = 1.0f / (1.0f + h * b.angularDamping);
    s.sims.push_back(m);
  }

  // The touching manifolds with an awake body that moves, in contact order.
  s.items.clear();
  for (Contact3& contact : contacts.contacts()) {
    if (!contact.touching) continue;
    const auto slotA = static_cast<std::int32_t>(s.bodySlot[store.shapes[contact.shapeA].body]);
    const auto slotB = static_cast<std::int32_t>(s.bodySlot[store.shapes[contact.shapeB].body]);
    const bool dynA = s.sims[static_cast<std::size_t>(slotA)].dynamic;
    const bool dynB = s.sims[static_cast<std::size_t>(slotB)].dynamic;
    if (!dynA && !dynB) continue;
    for (ContactManifold3& m : contact.manifolds)
      if (m.manifold.pointCount > 0) s.items.push_back({&m, &contact, slotA, slotB, dynA, dynB});
  }
  stats_.constraints = s.items.size();

  if (def.scalarSolver) {
    runStep(s, s.narrow, params, substeps, stats_, tasks);
  } else {
    runStep(s, s.wide, params, substeps, stats_, tasks);
  }

  // A body whose centre would leave the world (or whose numbers are no longer finite) is
  // held where the step found it. The bodies and their shapes' boxes on the workers (each
  // writes its own), then the proxies moved in slot order here (the tree is shared).
  const float limit = 0.5f * kMaxCoordinate;
  s.inside.resize(s.states.size());
  s.boxes.resize(store.shapes.size());
  tasks.parallelFor(
      static_cast<int>(s.states.size()) - 1, kMinSlots,
      [&](int first, int last, int) {
        for (auto slot = static_cast<std::size_t>(first) + 1;
             slot <= static_cast<std::size_t>(last); ++slot) {
          const BodyState3& st = s.states[slot];
          const SlotSim3& m = s.sims[slot];
          Body3& body = store.bodies[m.body];
          const Vec3 center = body.center + Vec3{st.dpx, st.dpy, st.dpz};
          const Vec3 far = absv(center);
          const bool inside = isFinite(center) && isFinite(stateVelocity(st)) &&
                              isFinite(stateSpin(st)) && isFinite(m.q) && far.x < limit &&
                              far.y < limit && far.z < limit;
          s.inside[slot] = inside;
          if (!inside) {
            body.linearVelocity = body.angularVelocity = Vec3{};
            continue;
          }
          body.center = center;
          body.rotation = m.q;
          body.linearVelocity = stateVelocity(st);
          body.angularVelocity = stateSpin(st);
          BodyStore3::syncOrigin(body);
          const Transform3 xf = body.transform();
          for (std::uint32_t shape : body.shapes)
            s.boxes[shape] = store.shapeBox(shape, xf);
        }
      },
      TaskRunner::kHeavyRangesPerWorker);
  for (std::size_t slot = 1; slot < s.states.size(); ++slot) {
    if (!s.inside[slot]) continue;
    const BodyState3& st = s.states[slot];
    const std::uint32_t body = s.sims[slot].body;
    for (std::uint32_t shape : store.bodies[body].shapes)
      store.moveProxy(shape, s.boxes[shape], Vec3{st.dpx, st.dpy, st.dpz});
  }
}

}  // namespace quack::detail
