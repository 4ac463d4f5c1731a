#include "solver3.hpp"

#include <algorithm>
#include <cmath>

#include "quack/world/world.hpp"
#include "solver.hpp"

namespace quack::detail {

namespace {

[[gnu::always_inline]] inline float speedAlong(const BodyState3& a, const BodyState3& b, Vec3 d,
                                               const Axis3& x) noexcept {
  return dot(b.v - a.v, d) + dot(b.w, x.crossB) - dot(a.w, x.crossA);
}

[[gnu::always_inline]] inline void pushAlong(BodyState3& a, BodyState3& b, Vec3 d, const Axis3& x,
                                             float p) noexcept {
  a.v = a.v - (a.invMass * p) * d;
  a.w = a.w - p * x.angularA;
  b.v = b.v + (b.invMass * p) * d;
  b.w = b.w + p * x.angularB;
}

Axis3 makeAxis(const BodyState3& a, const BodyState3& b, Vec3 rA, Vec3 rB, Vec3 d) noexcept {
  Axis3 x;
  x.crossA = cross(rA, d);
  x.crossB = cross(rB, d);
  x.angularA = a.invI * x.crossA;
  x.angularB = b.invI * x.crossB;
  return x;
}

// 1 / (mA + mB + (rA x d) . I_A^-1 (rA x d) + (rB x d) . I_B^-1 (rB x d)), or 0.
float invEffectiveMass(const BodyState3& a, const BodyState3& b, const Axis3& x) noexcept {
  const float k = a.invMass + b.invMass + dot(x.crossA, x.angularA) + dot(x.crossB, x.angularB);
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

struct StepParams {
  float h = 0.0f, invH = 0.0f, pushMax = 0.0f, restitutionThreshold = 0.0f;
  Vec3 gravity;
};

void warmStart(Constraint3& c, std::vector<BodyState3>& states) {
  BodyState3& a = states[c.slotA];
  BodyState3& b = states[c.slotB];
  for (int k = 0; k < c.count; ++k) {
    const PointConstraint3& p = c.points[k];
    pushAlong(a, b, c.normal, p.normal, p.normalImpulse);
  }
  pushAlong(a, b, c.t1, c.tangent[0], c.tangentImpulse[0]);
  pushAlong(a, b, c.t2, c.tangent[1], c.tangentImpulse[1]);
  a.w = a.w - c.twistImpulse * c.twistA;
  b.w = b.w + c.twistImpulse * c.twistB;
  a.w = a.w - a.invI * c.rollingImpulse;
  b.w = b.w + b.invI * c.rollingImpulse;
}

// Normal impulses (soft with the push when useBias, rigid without it in the relax pass;
// speculative points ahead of contact in both), then friction at the manifold's centre
// (two tangents within the Coulomb circle of the total normal impulse, then the twist
// within friction times each point's lever arm times its normal impulse), then rolling
// resistance.
// The points go first-to-last or, when `reverse`, last-to-first: the first point solved
// takes more of the load in a pass, and always the same corner first would push a box
// sideways a little every sub-step (the 2D solver alternates the same way).
template <bool useBias>
void solveConstraint(Constraint3& c, std::vector<BodyState3>& states, const StepParams& params,
                     bool reverse) {
  BodyState3& a = states[c.slotA];
  BodyState3& b = states[c.slotB];
  // The bodies' turns since the step began, as rotation vectors (2 x the vector part of the
  // delta quaternion, to first order). The anchors turn to first order only: turned exactly,
  // a rolling ball's contact anchor would rise by r (1 - cos angle) and the solver would
  // let the ball sink by as much (a steady 2 mm for a 0.5 m ball at 6 rad/s); the manifold,
  // made anew each step, carries the true geometry.
  const Quat dqA = a.q * conjugate(a.q0);
  const Quat dqB = b.q * conjugate(b.q0);
  const Vec3 turnA = (dqA.w < 0.0f ? -2.0f : 2.0f) * dqA.vector();
  const Vec3 turnB = (dqB.w < 0.0f ? -2.0f : 2.0f) * dqB.vector();
  float totalNormalImpulse = 0.0f;
  const int first = reverse ? c.count - 1 : 0;
  const int stride = reverse ? -1 : 1;
  for (int n = 0, k = first; n < c.count; ++n, k += stride) {
    PointConstraint3& p = c.points[k];
    // The separation now, from the bodies' motion since the manifold was made: each anchor
    // r moved by dp + turn x r, and (turn x r) . n = turn . (r x n).
    const float s = dot(b.dp - a.dp, c.normal) +
                    (dot(turnB, p.normal.crossB) - dot(turnA, p.normal.crossA)) + p.separation;
    float bias = 0.0f, massScale = 1.0f, impulseScale = 0.0f;
    if (s > 0.0f) {
      bias = s * params.invH;  // speculative: may close the gap in this sub-step, no more
    } else if constexpr (useBias) {
      bias = std::max(c.soft.biasRate * s, -params.pushMax);
      massScale = c.soft.massScale;
      impulseScale = c.soft.impulseScale;
    }
    const float vn = speedAlong(a, b, c.normal, p.normal);
    float impulse = -p.normalMass * massScale * (vn + bias) - impulseScale * p.normalImpulse;
    const float total = std::max(p.normalImpulse + impulse, 0.0f);
    impulse = total - p.normalImpulse;
    p.normalImpulse = total;
    p.maxNormalImpulse = std::max(p.maxNormalImpulse, impulse);
    totalNormalImpulse += total;
    pushAlong(a, b, c.normal, p.normal, impulse);
  }
  {
    float f1 = c.tangentImpulse[0] - c.tangentMass[0] * speedAlong(a, b, c.t1, c.tangent[0]);
    float f2 = c.tangentImpulse[1] - c.tangentMass[1] * speedAlong(a, b, c.t2, c.tangent[1]);
    // The Coulomb circle: the friction impulse within friction times the normal impulse.
    const float limit = c.friction * totalNormalImpulse;
    const float f = std::sqrt(f1 * f1 + f2 * f2);
    if (f > limit) {
      const float scale = f > 0.0f ? limit / f : 0.0f;
      f1 *= scale;
      f2 *= scale;
    }
    pushAlong(a, b, c.t1, c.tangent[0], f1 - c.tangentImpulse[0]);
    pushAlong(a, b, c.t2, c.tangent[1], f2 - c.tangentImpulse[1]);
    c.tangentImpulse[0] = f1;
    c.tangentImpulse[1] = f2;
  }
  if (c.count > 1) {
    float twistLimit = 0.0f;
    for (int k = 0; k < c.count; ++k)
      twistLimit += c.points[k].lever * c.points[k].normalImpulse;
    twistLimit *= c.friction;
    const float spin = dot(b.w - a.w, c.normal);
    const float total = std::clamp(c.twistImpulse - c.twistMass * spin, -twistLimit, twistLimit);
    const float impulse = total - c.twistImpulse;
    c.twistImpulse = total;
    a.w = a.w - impulse * c.twistA;
    b.w = b.w + impulse * c.twistB;
  }
  if (c.rolling > 0.0f) {
    const Vec3 dw = b.w - a.w;
    Vec3 total = c.rollingImpulse - c.rollingMass * dw;
    const float limit = c.rolling * totalNormalImpulse;
    const float len = length(total);
    if (len > limit) total = (len > 0.0f ? limit / len : 0.0f) * total;
    const Vec3 impulse = total - c.rollingImpulse;
    c.rollingImpulse = total;
    a.w = a.w - a.invI * impulse;
    b.w = b.w + b.invI * impulse;
  }
}

// After the sub-steps: points that approached faster than the threshold get the normal
// velocity -e times their approach speed (Box2D v3's restitution, on the relaxed velocities).
void applyRestitution(Constraint3& c, std::vector<BodyState3>& states, float threshold) {
  if (c.restitution == 0.0f) return;
  BodyState3& a = states[c.slotA];
  BodyState3& b = states[c.slotB];
  for (int k = 0; k < c.count; ++k) {
    PointConstraint3& p = c.points[k];
    if (p.relativeVelocity > -threshold || p.maxNormalImpulse == 0.0f) continue;
    const float vn = speedAlong(a, b, c.normal, p.normal);
    float impulse = -p.normalMass * (vn + c.restitution * p.relativeVelocity);
    const float total = std::max(p.normalImpulse + impulse, 0.0f);
    impulse = total - p.normalImpulse;
    p.normalImpulse = total;
    p.maxNormalImpulse = std::max(p.maxNormalImpulse, impulse);
    pushAlong(a, b, c.normal, p.normal, impulse);
  }
}

void integrateVelocities(std::vector<BodyState3>& states, const std::vector<std::uint32_t>& movers,
                         const BodyStore3& store, const StepParams& params) {
  for (std::size_t slot = 1; slot < states.size(); ++slot) {
    const Body3& body = store.bodies[movers[slot]];
    if (body.type != BodyType::dynamicBody) continue;  // kinematic: keeps its velocity
    BodyState3& s = states[slot];
    Vec3 v = s.v + (params.h * body.gravityScale) * params.gravity;
    v = (1.0f / (1.0f + params.h * body.linearDamping)) * v;
    Vec3 w = (1.0f / (1.0f + params.h * body.angularDamping)) * s.w;
    // Speed limits keep every number finite; a quarter turn per sub-step keeps the
    // first-order rotation update meaningful.
    const float speed = length(v);
    if (speed > kMaxLinearSpeed) v = (kMaxLinearSpeed / speed) * v;
    const float turn = length(w) * params.h;
    if (turn > 0.25f * kPi) w = (0.25f * kPi / turn) * w;
    s.v = v;
    s.w = w;
  }
}

void integratePositions(std::vector<BodyState3>& states, float h) {
  for (std::size_t slot = 1; slot < states.size(); ++slot) {
    BodyState3& s = states[slot];
    s.dp = s.dp + h * s.v;
    s.q = integrateRotation(s.q, s.w, h);
  }
}

}  // namespace

void Solver3::step(BodyStore3& store, ContactSet3& contacts, const WorldDef3& def, float dt,
                   int substeps) {
  StepParams params;
  params.h = dt / static_cast<float>(substeps);
  params.invH = 1.0f / params.h;
  params.pushMax = def.contactPushMaxSpeed;
  params.restitutionThreshold = def.restitutionThreshold;
  params.gravity = def.gravity;
  // Contacts stiffer than a quarter of the sub-step rate are not resolved by the sub-step;
  // against static and kinematic bodies twice as stiff (the 2D solver's choice).
  const float hertz = std::min(def.contactHertz, 0.25f * params.invH);
  const Softness soft = makeSoftness(hertz, def.contactDampingRatio, params.h);
  const Softness staticSoft = makeSoftness(2.0f * hertz, def.contactDampingRatio, params.h);

  std::vector<BodyState3>& states = states_;
  states.assign(1, BodyState3{});
  slotOf_.assign(store.bodies.size(), 0);
  movers_.assign(1, 0);
  for (std::uint32_t i = 0; i < store.bodies.size(); ++i) {
    const Body3& b = store.bodies[i];
    if (!store.bodyIds.isAlive(i) || b.type == BodyType::staticBody || !b.awake) continue;
    slotOf_[i] = static_cast<std::uint32_t>(states.size());
    movers_.push_back(i);
    BodyState3 s;
    s.v = b.linearVelocity;
    s.w = b.angularVelocity;
    s.q = s.q0 = b.rotation;
    s.invMass = b.invMass;
    s.invI = b.invInertiaWorld();
    states.push_back(s);
  }

  std::vector<Constraint3>& constraints = constraints_;
  constraints.clear();
  for (Contact3& contact : contacts.contacts()) {
    if (!contact.touching) continue;
    const std::uint32_t bodyA = store.shapes[contact.shapeA].body;
    const std::uint32_t bodyB = store.shapes[contact.shapeB].body;
    const std::uint32_t slotA = slotOf_[bodyA], slotB = slotOf_[bodyB];
    if (slotA == 0 && slotB == 0) continue;
    const BodyState3& a = states[slotA];
    const BodyState3& b = states[slotB];
    for (ContactManifold3& m : contact.manifolds) {
      // Filled in place: a constraint is about a kilobyte, too big to build and copy.
      Constraint3& c = constraints.emplace_back();
      c.source = &m;
      c.slotA = slotA;
      c.slotB = slotB;
      c.normal = m.manifold.normal;
      computeTangents(c.normal, c.t1, c.t2);
      c.friction = contact.friction;
      c.restitution = contact.restitution;
      c.rolling = contact.rollingResistance;
      c.soft = (a.invMass == 0.0f || b.invMass == 0.0f) ? staticSoft : soft;
      const Mat3 k = a.invI + b.invI;
      if (c.rolling > 0.0f && determinant(k) > 0.0f) c.rollingMass = inverse(k);
      c.rollingImpulse = m.rollingImpulse;
      c.count = m.manifold.pointCount;
      // The centre of the points (its arms the mean of the points' arms), where friction
      // acts, and each point's lever arm about it for the twist.
      Vec3 centreA, centreB;
      for (int i = 0; i < c.count; ++i) {
        centreA = centreA + m.armA[i];
        centreB = centreB + m.armB[i];
      }
      const float share = 1.0f / static_cast<float>(c.count);
      centreA = share * centreA;
      centreB = share * centreB;
      for (int i = 0; i < c.count; ++i) {
        const ManifoldPoint3& mp = m.manifold.points[i];
        PointConstraint3& p = c.points[i];
        // The arms as the manifold was computed (kept while it is recycled: arms turned
        // with the bodies under a normal that stays put tilt a column further).
        const Vec3 rA = m.armA[i], rB = m.armB[i];
        p.normal = makeAxis(a, b, rA, rB, c.normal);
        p.separation = mp.separation;
        p.normalMass = invEffectiveMass(a, b, p.normal);
        p.normalImpulse = m.normalImpulse[i];
        p.relativeVelocity = speedAlong(a, b, c.normal, p.normal);
        p.lever = length(rA - centreA);
      }
      c.tangent[0] = makeAxis(a, b, centreA, centreB, c.t1);
      c.tangent[1] = makeAxis(a, b, centreA, centreB, c.t2);
      c.tangentMass[0] = invEffectiveMass(a, b, c.tangent[0]);
      c.tangentMass[1] = invEffectiveMass(a, b, c.tangent[1]);
      c.tangentImpulse[0] = dot(m.frictionImpulse, c.t1);
      c.tangentImpulse[1] = dot(m.frictionImpulse, c.t2);
      c.twistA = a.invI * c.normal;
      c.twistB = b.invI * c.normal;
      const float twist = dot(c.normal, c.twistA) + dot(c.normal, c.twistB);
      c.twistMass = twist > 0.0f ? 1.0f / twist : 0.0f;
      // One point has no lever arm and so no twist friction: an impulse carried from when
      // the manifold had more points must not be applied every sub-step (it spun a hull up
      // to 25 rad/s in the hull pile before this was caught).
      c.twistImpulse = c.count > 1 ? m.twistImpulse : 0.0f;
    }
  }

  for (int sub = 0; sub < substeps; ++sub) {
    integrateVelocities(states, movers_, store, params);
    for (Constraint3& c : constraints)
      warmStart(c, states);
    const bool odd = (sub & 1) != 0;
    for (Constraint3& c : constraints)
      solveConstraint<true>(c, states, params, odd);
    integratePositions(states, params.h);
    for (Constraint3& c : constraints)
      solveConstraint<false>(c, states, params, !odd);
  }
  for (Constraint3& c : constraints)
    applyRestitution(c, states, params.restitutionThreshold);

  for (Constraint3& c : constraints) {
    ContactManifold3& m = *c.source;
    for (int i = 0; i < c.count; ++i) {
      const PointConstraint3& p = c.points[i];
      m.normalImpulse[i] = p.normalImpulse;
      m.maxNormalImpulse[i] = p.maxNormalImpulse;
    }
    m.frictionImpulse = c.tangentImpulse[0] * c.t1 + c.tangentImpulse[1] * c.t2;
    m.twistImpulse = c.twistImpulse;
    m.rollingImpulse = c.rollingImpulse;
  }

  // A body whose centre would leave the world (or whose numbers are no longer finite) is
  // held where the step found it.
  const float limit = 0.5f * kMaxCoordinate;
  for (std::size_t slot = 1; slot < states.size(); ++slot) {
    const BodyState3& s = states[slot];
    Body3& body = store.bodies[movers_[slot]];
    const Vec3 center = body.center + s.dp;
    const Vec3 far = absv(center);
    const bool inside = isFinite(center) && isFinite(s.v) && isFinite(s.w) && isFinite(s.q) &&
                        far.x < limit && far.y < limit && far.z < limit;
    if (!inside) {
      body.linearVelocity = body.angularVelocity = Vec3{};
      continue;
    }
    body.center = center;
    body.rotation = s.q;
    body.linearVelocity = s.v;
    body.angularVelocity = s.w;
    BodyStore3::syncOrigin(body);
    store.moveProxies(movers_[slot], s.dp);
  }
}

}  // namespace quack::detail
