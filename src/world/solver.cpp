// The contact solver: soft contacts solved by sequential impulses over sub-steps, with
// relaxation and restitution (Catto, "Solver2D" (2024) and Box2D v3's soft step, read for
// understanding; Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005, for
// sequential impulses and warm starting). docs/world.md explains the choices.

#include <cmath>

#include "solver.hpp"

#include "body_store.hpp"
#include "contact_set.hpp"
#include "event_dispatcher.hpp"
#include "quack/world/world.hpp"

namespace quack::detail {
namespace {

Softness makeSoftness(float hertz, float zeta, float h) {
  if (hertz == 0.0f) return {0.0f, 1.0f, 0.0f};
  float omega = 2.0f * kPi * hertz;
  float a1 = 2.0f * zeta + h * omega;
  float a2 = h * omega * a1;
  float a3 = 1.0f / (1.0f + a2);
  return {omega / a1, a2 * a3, a3};
}

// `v` shortened to kMaxLinearSpeed if it is faster. Components are clamped first, so even
// an infinite component gives a finite result.
Vec2 clampSpeed(Vec2 v) {
  constexpr float kMaxSquared = kMaxLinearSpeed * kMaxLinearSpeed;
  if (dot(v, v) <= kMaxSquared) return v;
  v = {clampf(v.x, -kMaxLinearSpeed, kMaxLinearSpeed),
       clampf(v.y, -kMaxLinearSpeed, kMaxLinearSpeed)};
  return (kMaxLinearSpeed / length(v)) * v;
}

Rot integrateRotation(Rot q, float deltaAngle) {
  // First-order update then renormalise: exact to second order per sub-step, and cheaper
  // than cos/sin.
  Rot r{q.c - deltaAngle * q.s, q.s + deltaAngle * q.c};
  float inv = 1.0f / std::sqrt(r.c * r.c + r.s * r.s);
  return {r.c * inv, r.s * inv};
}

// One pass over the contact constraints. Velocities are copied into locals and written
// back once per constraint, so the compiler need not assume every impulse aliases them.
// (Templated on the world's private record types, which it deduces.)
//
// The normal impulses of a manifold's points are solved one after the other, and whichever
// goes first takes more of the load in that pass: a box resting flat on another gets a
// little more push under one corner than the other, the same corner every sub-step, and a
// column turns that steady nudge into a lean (docs/world.md, "What made columns drift").
// `lastFirst` solves the points in the opposite order; the solver alternates it between
// sub-steps and between the solve and the relax pass, so the nudges cancel.
template <class Constraint, class Body>
void solveContacts(Constraint* constraints, std::size_t count, Body* bodies, float invH,
                   float pushMax, bool useBias, bool lastFirst) {
  for (std::size_t ci = 0; ci < count; ++ci) {
    Constraint& k = constraints[ci];
    Body& A = bodies[k.bodyA];
    Body& B = bodies[k.bodyB];
    const float mA = A.invMass, iA = A.invInertia, mB = B.invMass, iB = B.invInertia;
    Vec2 vA = A.v, vB = B.v;
    float wA = A.w, wB = B.w;
    const Vec2 dp = B.dp - A.dp;
    const Rot qA = A.dq, qB = B.dq;
    const Vec2 n = k.normal;
    const Vec2 t = rightPerp(n);
    const int pointCount = k.pointCount;
    for (int i = 0; i < pointCount; ++i) {
      const int j = lastFirst ? pointCount - 1 - i : i;
      auto& p = k.points[j];
      // Current separation from the bodies' motion since the step began.
      const Vec2 d = dp + (rotate(qB, p.rB) - rotate(qA, p.rA));
      const float s = dot(d, n) + p.baseSeparation;
      float bias = 0.0f, massScale = 1.0f, impulseScale = 0.0f;
      if (s > 0.0f) {
        bias = s * invH;  // speculative: close the gap, no further
      } else if (useBias) {
        bias = maxf(k.softness.biasRate * s, -pushMax);
        massScale = k.softness.massScale;
        impulseScale = k.softness.impulseScale;
      }
      const Vec2 dv = vB + cross(wB, p.rB) - vA - cross(wA, p.rA);
      const float vn = dot(dv, n);
      float impulse = -p.normalMass * massScale * (vn + bias) - impulseScale * p.normalImpulse;
      const float total = maxf(p.normalImpulse + impulse, 0.0f);
      impulse = total - p.normalImpulse;
      p.normalImpulse = total;
      p.maxNormalImpulse = maxf(p.maxNormalImpulse, impulse);
      const Vec2 P = impulse * n;
      vA -= mA * P;
      wA -= iA * cross(p.rA, P);
      vB += mB * P;
      wB += iB * cross(p.rB, P);
    }
    for (int j = 0; j < pointCount; ++j) {
      auto& p = k.points[j];
      const Vec2 dv = vB + cross(wB, p.rB) - vA - cross(wA, p.rA);
      float impulse = -p.tangentMass * dot(dv, t);
      const float limit = k.friction * p.normalImpulse;
      const float total = clampf(p.tangentImpulse + impulse, -limit, limit);
      impulse = total - p.tangentImpulse;
      p.tangentImpulse = total;
      const Vec2 P = impulse * t;
      vA -= mA * P;
      wA -= iA * cross(p.rA, P);
      vB += mB * P;
      wB += iB * cross(p.rB, P);
    }
    A.v = vA;
    A.w = wA;
    B.v = vB;
    B.w = wB;
  }
}

}  // namespace

void Solver::solve(const WorldDef& worldDef, BodyStore& store, ContactSet& contactSet,
                   BroadPhase& broadPhase, EventDispatcher& events, float dt, int substeps) {
  std::vector<Body>& bodies = store.bodies;
  const std::vector<Shape>& shapes = store.shapes;
  const std::vector<Contact>& contacts = contactSet.contacts;
  const WorldDef& def = worldDef;
  const float h = dt / static_cast<float>(substeps);
  const float invH = 1.0f / h;
  // Contacts stiffer than a quarter of the sub-step rate are not resolved by the sub-step.
  const float hertz = minf(def.contactHertz, 0.25f * invH);
  const Softness soft = makeSoftness(hertz, def.contactDampingRatio, h);
  // Against static (and kinematic) bodies there is only one body to move: twice as stiff.
  const Softness staticSoft = makeSoftness(2.0f * hertz, def.contactDampingRatio, h);
  const float pushMax = def.contactPushMaxSpeed;

  std::vector<SolverBody>& sb = solverBodies_;
  sb.assign(bodies.size(), SolverBody{});
  for (std::uint32_t i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    if (!store.bodyAlive(i)) continue;
    SolverBody& s = sb[i];
    s.v = b.v;
    // A dynamic body without rotational inertia (zero density, or segments only) does not
    // turn, whatever spin it was given.
    s.w = (b.type == BodyType::dynamicBody && b.invInertia == 0.0f) ? 0.0f : b.w;
    s.invMass = b.invMass;
    s.invInertia = b.invInertia;
  }

  // Prepare the constraints of touching contacts (a dynamic body in every one).
  constraints_.clear();
  for (std::uint32_t ci = 0; ci < contacts.size(); ++ci) {
    const Contact& c = contacts[ci];
    if (!c.alive || !c.touching || c.sensor) continue;
    ContactConstraint k;
    k.contact = ci;
    k.bodyA = shapes[c.shapeA].body;
    k.bodyB = shapes[c.shapeB].body;
    k.normal = c.manifold.normal;
    k.friction = c.friction;
    k.restitution = c.restitution;
    const SolverBody& A = sb[k.bodyA];
    const SolverBody& B = sb[k.bodyB];
    k.softness = (A.invMass == 0.0f || B.invMass == 0.0f) ? staticSoft : soft;
    k.pointCount = c.manifold.pointCount;
    const Vec2 cA = bodies[k.bodyA].center;
    const Vec2 cB = bodies[k.bodyB].center;
    const Vec2 n = k.normal;
    const Vec2 t = rightPerp(n);
    for (int j = 0; j < k.pointCount; ++j) {
      const ManifoldPoint& mp = c.manifold.points[j];
      ContactConstraint::Point& p = k.points[j];
      if (c.recycled) {
        // A recycled manifold (contact_set.cpp, recycle): the arms from each centre of mass
        // to the point as they were when the manifold was computed, not turned with the
        // bodies since. Box2D v3 does the same (its anchors stay as computed while a
        // contact is recycled; physics_world.c and contact_solver.c, read for
        // understanding). Arms that turn with the bodies while the normal stays put let a
        // column's tilt move its contact forces the way that tilts it further: columns of
        // 15 boxes or more toppled so (docs/world.md, "What made columns drift").
        p.rA = rotate(c.cachedA.q, c.localA[j] - bodies[k.bodyA].localCenter);
        p.rB = rotate(c.cachedB.q, c.localB[j] - bodies[k.bodyB].localCenter);
      } else {
        p.rA = mp.point - cA;
        p.rB = mp.point - cB;
      }
      p.baseSeparation = mp.separation - dot(p.rB - p.rA, n);
      p.normalImpulse = c.normalImpulse[j];
      p.tangentImpulse = c.tangentImpulse[j];
      p.maxNormalImpulse = 0.0f;
      float rnA = cross(p.rA, n), rnB = cross(p.rB, n);
      float kn = A.invMass + B.invMass + A.invInertia * rnA * rnA + B.invInertia * rnB * rnB;
      p.normalMass = kn > 0.0f ? 1.0f / kn : 0.0f;
      float rtA = cross(p.rA, t), rtB = cross(p.rB, t);
      float kt = A.invMass + B.invMass + A.invInertia * rtA * rtA + B.invInertia * rtB * rtB;
      p.tangentMass = kt > 0.0f ? 1.0f / kt : 0.0f;
      Vec2 dv = B.v + cross(B.w, p.rB) - A.v - cross(A.w, p.rA);
      p.relativeVelocity = dot(n, dv);
    }
    constraints_.push_back(k);
  }

  auto applyImpulse = [](SolverBody& A, SolverBody& B, Vec2 rA, Vec2 rB, Vec2 P) {
    A.v -= A.invMass * P;
    A.w -= A.invInertia * cross(rA, P);
    B.v += B.invMass * P;
    B.w += B.invInertia * cross(rB, P);
  };

  const float maxRotation = def.maxRotationPerSubstep;
  for (int stepIndex = 0; stepIndex < substeps; ++stepIndex) {
    // Integrate velocities: gravity and damping (implicit, so any damping is stable).
    for (std::uint32_t i = 0; i < bodies.size(); ++i) {
      const Body& b = bodies[i];
      if (!store.bodyAlive(i) || b.type != BodyType::dynamicBody) continue;
      SolverBody& s = sb[i];
      Vec2 v = s.v + (h * b.gravityScale) * def.gravity;
      float w = s.w;
      // Applied forces (applyForce, applyTorque); a branch, so that a body without them
      // gives the same bits as before forces existed.
      if (b.force.x != 0.0f || b.force.y != 0.0f) v += (h * b.invMass) * b.force;
      if (b.torque != 0.0f) w += h * b.invInertia * b.torque;
      s.v = (1.0f / (1.0f + h * b.linearDamping)) * v;
      s.w = w / (1.0f + h * b.angularDamping);
      // Speed limits (world.hpp): keep speed * dt and every impulse finite.
      s.v = clampSpeed(s.v);
      s.w = clampf(s.w, -kMaxAngularSpeed, kMaxAngularSpeed);
    }
    // Warm start with the accumulated impulses.
    for (const ContactConstraint& k : constraints_) {
      SolverBody& A = sb[k.bodyA];
      SolverBody& B = sb[k.bodyB];
      const Vec2 t = rightPerp(k.normal);
      for (int j = 0; j < k.pointCount; ++j) {
        const ContactConstraint::Point& p = k.points[j];
        applyImpulse(A, B, p.rA, p.rB, p.normalImpulse * k.normal + p.tangentImpulse * t);
      }
    }
    solveContacts(constraints_.data(), constraints_.size(), sb.data(), invH, pushMax, true,
                  (stepIndex & 1) != 0);
    // Integrate positions.
    for (std::uint32_t i = 0; i < bodies.size(); ++i) {
      const Body& b = bodies[i];
      if (!store.bodyAlive(i) || b.type == BodyType::staticBody) continue;
      SolverBody& s = sb[i];
      if (absf(h * s.w) > maxRotation) s.w = (s.w > 0.0f ? maxRotation : -maxRotation) * invH;
      s.dq = integrateRotation(s.dq, h * s.w);
      // integrateRotation turns by atan(h w), not h w; below 0.01 rad the two differ by
      // under 4e-7 rad, so the arctangent is only paid for fast spinners.
      const float turn = h * s.w;
      s.da += absf(turn) < 0.01f ? turn : std::atan(turn);
      s.dp += h * s.v;
    }
    // Relax: remove the velocity the soft push added, so it does not become bounce.
    solveContacts(constraints_.data(), constraints_.size(), sb.data(), invH, pushMax, false,
                  (stepIndex & 1) == 0);
  }

  // Restitution: for points that approached faster than the threshold, aim the normal
  // velocity at -e times the approach velocity.
  const float threshold = def.restitutionThreshold;
  for (ContactConstraint& k : constraints_) {
    if (k.restitution == 0.0f) continue;
    SolverBody& A = sb[k.bodyA];
    SolverBody& B = sb[k.bodyB];
    for (int j = 0; j < k.pointCount; ++j) {
      ContactConstraint::Point& p = k.points[j];
      if (p.relativeVelocity > -threshold || p.maxNormalImpulse == 0.0f) continue;
      Vec2 dv = B.v + cross(B.w, p.rB) - A.v - cross(A.w, p.rA);
      float vn = dot(dv, k.normal);
      float impulse = -p.normalMass * (vn + k.restitution * p.relativeVelocity);
      float total = maxf(p.normalImpulse + impulse, 0.0f);
      impulse = total - p.normalImpulse;
      p.normalImpulse = total;
      p.maxNormalImpulse = maxf(p.maxNormalImpulse, impulse);
      applyImpulse(A, B, p.rA, p.rB, impulse * k.normal);
    }
  }

  // Store impulses for warm starting; report hits.
  for (const ContactConstraint& k : constraints_) {
    Contact& c = contactSet.contacts[k.contact];
    float strongest = 0.0f;
    int at = -1;
    for (int j = 0; j < k.pointCount; ++j) {
      c.normalImpulse[j] = k.points[j].normalImpulse;
      c.tangentImpulse[j] = k.points[j].tangentImpulse;
      float approach = -k.points[j].relativeVelocity;
      if (k.points[j].maxNormalImpulse > 0.0f && approach > def.hitEventThreshold &&
          approach > strongest) {
        strongest = approach;
        at = j;
      }
    }
    if (at >= 0) {
      events.events.hit.push_back({store.shapeId(c.shapeA), store.shapeId(c.shapeB),
                                   c.manifold.points[at].point, k.normal, strongest});
    }
  }

  // Finalise bodies and move their proxies.
  for (std::uint32_t i = 0; i < bodies.size(); ++i) {
    Body& b = bodies[i];
    if (!store.bodyAlive(i) || b.type == BodyType::staticBody) continue;
    const SolverBody& s = sb[i];
    // Forces act through one step.
    b.force = {};
    b.torque = 0.0f;
    // Restitution may have sped a body up after the last clamp.
    b.v = clampSpeed(s.v);
    b.w = clampf(s.w, -kMaxAngularSpeed, kMaxAngularSpeed);
    // Continuous collision wants the sweeps of fast bodies (world.hpp, kCcdFastFraction).
    b.fast = b.type == BodyType::dynamicBody && def.enableContinuous && b.maxExtent > 0.0f &&
             (b.bullet || length(s.dp) + absf(s.da) * b.maxExtent > kCcdFastFraction * b.minExtent);
    if (b.fast) {
      b.startCenter = b.center;
      b.startAngle = b.xf.q.angle();
      b.endAngle = b.startAngle + s.da;
    }
    const Vec2 center = b.center + s.dp;
    const Rot q = normalizeRot(mulRot(s.dq, b.xf.q));
    const Transform xf{center - rotate(q, b.localCenter), q};
    if (!store.moveBody(broadPhase, i, xf, center, s.dp)) {
      // The edge of the world (world.hpp, kMaxCoordinate): the body stays where the step
      // began, stopped, and the game is told (StepEvents::outOfBounds).
      b.v = {};
      b.w = 0.0f;
      b.fast = false;
      events.events.outOfBounds.push_back(store.bodyId(i));
    }
  }
}

}  // namespace quack::detail
