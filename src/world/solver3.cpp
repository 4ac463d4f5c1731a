#include "solver3.hpp"

#include <algorithm>
#include <cmath>

#include "quack/world/world.hpp"
#include "solver.hpp"

namespace quack::detail {

namespace {

// A body's state while the solver runs. Slot 0 is a resting body that static and sleeping
// bodies read: no mass, no velocity, never moved.
struct BodyState {
  Vec3 v, w;
  Vec3 dp;     // motion of the centre of mass since the step began
  Quat q, q0;  // rotation now, and at the start of the step
  float invMass = 0.0f;
  Mat3 invI;  // world axes, fixed over the step (as Box2D v3 keeps its inertia)
};

struct PointConstraint {
  Vec3 rA, rB;  // from each centre of mass at the start of the step, world axes (fixed)
  float baseSeparation = 0.0f;  // separation minus the anchors' offset along the normal
  float normalMass = 0.0f;
  float tangentMass[2] = {};
  float normalImpulse = 0.0f;
  float tangentImpulse[2] = {};
  float maxNormalImpulse = 0.0f;
  float relativeVelocity = 0.0f;  // normal velocity before the step (restitution)
};

struct Constraint {
  ContactManifold3* source = nullptr;
  std::uint32_t slotA = 0, slotB = 0;
  Vec3 normal, t1, t2;
  float friction = 0.0f, restitution = 0.0f, rolling = 0.0f;
  Softness soft;
  Mat3 rollingMass;
  Vec3 rollingImpulse;
  PointConstraint points[kMaxManifoldPoints3];
  int count = 0;
};

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

float invEffectiveMass(float mA, const Mat3& iA, Vec3 rA, float mB, const Mat3& iB, Vec3 rB,
                       Vec3 dir) noexcept {
  const Vec3 rnA = cross(rA, dir);
  const Vec3 rnB = cross(rB, dir);
  const float k = mA + mB + dot(rnA, iA * rnA) + dot(rnB, iB * rnB);
  return k > 0.0f ? 1.0f / k : 0.0f;
}

Vec3 relativeVelocityAt(const BodyState& a, const BodyState& b, Vec3 rA, Vec3 rB) noexcept {
  return (b.v + cross(b.w, rB)) - (a.v + cross(a.w, rA));
}

void applyImpulse(BodyState& a, BodyState& b, Vec3 rA, Vec3 rB, Vec3 p) noexcept {
  a.v = a.v - a.invMass * p;
  a.w = a.w - a.invI * cross(rA, p);
  b.v = b.v + b.invMass * p;
  b.w = b.w + b.invI * cross(rB, p);
}

struct StepParams {
  float h = 0.0f, invH = 0.0f, pushMax = 0.0f, restitutionThreshold = 0.0f;
  Vec3 gravity;
};

void warmStart(Constraint& c, std::vector<BodyState>& states) {
  BodyState& a = states[c.slotA];
  BodyState& b = states[c.slotB];
  for (int k = 0; k < c.count; ++k) {
    const PointConstraint& p = c.points[k];
    const Vec3 impulse =
        p.normalImpulse * c.normal + p.tangentImpulse[0] * c.t1 + p.tangentImpulse[1] * c.t2;
    applyImpulse(a, b, p.rA, p.rB, impulse);
  }
  a.w = a.w - a.invI * c.rollingImpulse;
  b.w = b.w + b.invI * c.rollingImpulse;
}

// Normal impulses (soft with the push when useBias, rigid without it in the relax pass;
// speculative points ahead of contact in both), then friction, then rolling resistance.
// The points go first-to-last or, when `reverse`, last-to-first: the first point solved
// takes more of the load in a pass, and always the same corner first would push a box
// sideways a little every sub-step (the 2D solver alternates the same way).
template <bool useBias>
void solveConstraint(Constraint& c, std::vector<BodyState>& states, const StepParams& params,
                     bool reverse) {
  BodyState& a = states[c.slotA];
  BodyState& b = states[c.slotB];
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
    PointConstraint& p = c.points[k];
    // The separation now, from the bodies' motion since the manifold was made.
    const Vec3 d = (b.dp - a.dp) + ((p.rB + cross(turnB, p.rB)) - (p.rA + cross(turnA, p.rA)));
    const float s = dot(d, c.normal) + p.baseSeparation;
    float bias = 0.0f, massScale = 1.0f, impulseScale = 0.0f;
    if (s > 0.0f) {
      bias = s * params.invH;  // speculative: may close the gap in this sub-step, no more
    } else if constexpr (useBias) {
      bias = std::max(c.soft.biasRate * s, -params.pushMax);
      massScale = c.soft.massScale;
      impulseScale = c.soft.impulseScale;
    }
    const float vn = dot(relativeVelocityAt(a, b, p.rA, p.rB), c.normal);
    float impulse = -p.normalMass * massScale * (vn + bias) - impulseScale * p.normalImpulse;
    const float total = std::max(p.normalImpulse + impulse, 0.0f);
    impulse = total - p.normalImpulse;
    p.normalImpulse = total;
    p.maxNormalImpulse = std::max(p.maxNormalImpulse, impulse);
    totalNormalImpulse += total;
    applyImpulse(a, b, p.rA, p.rB, impulse * c.normal);
  }
  for (int n = 0, k = first; n < c.count; ++n, k += stride) {
    PointConstraint& p = c.points[k];
    const Vec3 dv = relativeVelocityAt(a, b, p.rA, p.rB);
    float f1 = p.tangentImpulse[0] - p.tangentMass[0] * dot(dv, c.t1);
    float f2 = p.tangentImpulse[1] - p.tangentMass[1] * dot(dv, c.t2);
    // The Coulomb cone: the friction impulse within friction times the normal impulse.
    const float limit = c.friction * p.normalImpulse;
    const float f = std::sqrt(f1 * f1 + f2 * f2);
    if (f > limit) {
      const float scale = f > 0.0f ? limit / f : 0.0f;
      f1 *= scale;
      f2 *= scale;
    }
    const Vec3 impulse = (f1 - p.tangentImpulse[0]) * c.t1 + (f2 - p.tangentImpulse[1]) * c.t2;
    p.tangentImpulse[0] = f1;
    p.tangentImpulse[1] = f2;
    applyImpulse(a, b, p.rA, p.rB, impulse);
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
void applyRestitution(Constraint& c, std::vector<BodyState>& states, float threshold) {
  if (c.restitution == 0.0f) return;
  BodyState& a = states[c.slotA];
  BodyState& b = states[c.slotB];
  for (int k = 0; k < c.count; ++k) {
    PointConstraint& p = c.points[k];
    if (p.relativeVelocity > -threshold || p.maxNormalImpulse == 0.0f) continue;
    const float vn = dot(relativeVelocityAt(a, b, p.rA, p.rB), c.normal);
    float impulse = -p.normalMass * (vn + c.restitution * p.relativeVelocity);
    const float total = std::max(p.normalImpulse + impulse, 0.0f);
    impulse = total - p.normalImpulse;
    p.normalImpulse = total;
    p.maxNormalImpulse = std::max(p.maxNormalImpulse, impulse);
    applyImpulse(a, b, p.rA, p.rB, impulse * c.normal);
  }
}

void integrateVelocities(std::vector<BodyState>& states, const std::vector<std::uint32_t>& movers,
                         const BodyStore3& store, const StepParams& params) {
  for (std::size_t slot = 1; slot < states.size(); ++slot) {
    const Body3& body = store.bodies[movers[slot]];
    if (body.type != BodyType::dynamicBody) continue;  // kinematic: keeps its velocity
    BodyState& s = states[slot];
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

void integratePositions(std::vector<BodyState>& states, float h) {
  for (std::size_t slot = 1; slot < states.size(); ++slot) {
    BodyState& s = states[slot];
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

  std::vector<BodyState> states(1);
  slotOf_.assign(store.bodies.size(), 0);
  movers_.assign(1, 0);
  for (std::uint32_t i = 0; i < store.bodies.size(); ++i) {
    const Body3& b = store.bodies[i];
    if (!store.bodyIds.isAlive(i) || b.type == BodyType::staticBody || !b.awake) continue;
    slotOf_[i] = static_cast<std::uint32_t>(states.size());
    movers_.push_back(i);
    BodyState s;
    s.v = b.linearVelocity;
    s.w = b.angularVelocity;
    s.q = s.q0 = b.rotation;
    s.invMass = b.invMass;
    s.invI = b.invInertiaWorld();
    states.push_back(s);
  }

  std::vector<Constraint> constraints;
  for (Contact3& contact : contacts.contacts()) {
    if (!contact.touching) continue;
    const std::uint32_t bodyA = store.shapes[contact.shapeA].body;
    const std::uint32_t bodyB = store.shapes[contact.shapeB].body;
    const std::uint32_t slotA = slotOf_[bodyA], slotB = slotOf_[bodyB];
    if (slotA == 0 && slotB == 0) continue;
    const BodyState& a = states[slotA];
    const BodyState& b = states[slotB];
    for (ContactManifold3& m : contact.manifolds) {
      Constraint c;
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
      for (int i = 0; i < c.count; ++i) {
        const ManifoldPoint3& mp = m.manifold.points[i];
        PointConstraint& p = c.points[i];
        // The arms as the manifold was computed (kept while it is recycled: arms turned
        // with the bodies under a normal that stays put tilt a column further).
        p.rA = m.armA[i];
        p.rB = m.armB[i];
        p.baseSeparation = mp.separation - dot(p.rB - p.rA, c.normal);
        p.normalMass = invEffectiveMass(a.invMass, a.invI, p.rA, b.invMass, b.invI, p.rB, c.normal);
        p.tangentMass[0] = invEffectiveMass(a.invMass, a.invI, p.rA, b.invMass, b.invI, p.rB, c.t1);
        p.tangentMass[1] = invEffectiveMass(a.invMass, a.invI, p.rA, b.invMass, b.invI, p.rB, c.t2);
        p.normalImpulse = m.normalImpulse[i];
        p.tangentImpulse[0] = dot(m.frictionImpulse[i], c.t1);
        p.tangentImpulse[1] = dot(m.frictionImpulse[i], c.t2);
        p.relativeVelocity = dot(relativeVelocityAt(a, b, p.rA, p.rB), c.normal);
      }
      constraints.push_back(c);
    }
  }

  for (int sub = 0; sub < substeps; ++sub) {
    integrateVelocities(states, movers_, store, params);
    for (Constraint& c : constraints)
      warmStart(c, states);
    const bool odd = (sub & 1) != 0;
    for (Constraint& c : constraints)
      solveConstraint<true>(c, states, params, odd);
    integratePositions(states, params.h);
    for (Constraint& c : constraints)
      solveConstraint<false>(c, states, params, !odd);
  }
  for (Constraint& c : constraints)
    applyRestitution(c, states, params.restitutionThreshold);

  for (Constraint& c : constraints) {
    ContactManifold3& m = *c.source;
    for (int i = 0; i < c.count; ++i) {
      const PointConstraint& p = c.points[i];
      m.normalImpulse[i] = p.normalImpulse;
      m.frictionImpulse[i] = p.tangentImpulse[0] * c.t1 + p.tangentImpulse[1] * c.t2;
      m.maxNormalImpulse[i] = p.maxNormalImpulse;
    }
    m.rollingImpulse = c.rollingImpulse;
  }

  // A body whose centre would leave the world (or whose numbers are no longer finite) is
  // held where the step found it.
  const float limit = 0.5f * kMaxCoordinate;
  for (std::size_t slot = 1; slot < states.size(); ++slot) {
    const BodyState& s = states[slot];
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
