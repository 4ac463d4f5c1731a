// Shape cast and time of impact in 3D by conservative advancement (see toi3.hpp).

#include "quack/collision/toi3.hpp"

#include <cmath>

#include "quack/collision/epa3.hpp"

namespace quack {
namespace {

bool finiteTransform(Transform3 t) noexcept {
  return isFinite(t.p) && isFinite(t.q);
}
bool finiteSweep(const Sweep3& s) noexcept {
  return isFinite(s.localCenter) && isFinite(s.c1) && isFinite(s.c2) && isFinite(s.q1) &&
         isFinite(s.rotation) && lengthSquared(s.q1) > 0.0f;
}
}  // namespace

float computeReach(const ShapeProxy3& p, Vec3 center) noexcept {
  float r = 0.0f;
  for (int i = 0; i < p.count(); ++i)
    r = maxf(r, distanceSquared(p.points()[i], center));
  return std::sqrt(r) + p.radius();
}

ShapeCastOutput3 castShape(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                           Transform3 worldFromB, Vec3 translationB, float maxFraction) noexcept {
  ShapeCastOutput3 out;
  if (!finiteTransform(worldFromA) || !finiteTransform(worldFromB) || !isFinite(translationB) ||
      !(maxFraction >= 0.0f && maxFraction <= 1.0f)) {
    out.status = ShapeCastStatus::invalidInput;
    return out;
  }
  GjkCache3 cache;
  float s = 0.0f;
  for (int iter = 0; iter < kShapeCastMaxIterations; ++iter) {
    Transform3 tb{worldFromB.p + s * translationB, worldFromB.q};
    DistanceOutput3 d = computeDistance(a, worldFromA, b, tb, &cache);
    ++out.iterations;
    if (d.distance <= 0.0f && s == 0.0f) {
      PenetrationOutput3 p = computePenetration(a, worldFromA, b, tb);
      out.hit = true;
      out.status = ShapeCastStatus::overlapped;
      out.point = p.pointA;
      out.normal = p.normal;
      out.depth = p.depth;
      return out;
    }
    if (d.distance <= kShapeCastTolerance) {
      out.hit = true;
      out.status = ShapeCastStatus::hit;
      out.fraction = s;
      out.point = d.pointA;
      out.normal = d.normal;
      return out;
    }
    // Under a translation the distance is convex in s: its tangent bounds it below.
    float approach = -dot(translationB, d.normal);
    if (approach <= 0.0f) return out;  // never closer: missed
    s += (d.distance - 0.5f * kShapeCastTolerance) / approach;
    if (s > maxFraction) return out;  // missed
  }
  out.status = ShapeCastStatus::maxIterations;
  out.fraction = s;
  return out;
}

ToiOutput3 computeToi(const ShapeProxy3& a, const Sweep3& sweepA, const ShapeProxy3& b,
                      const Sweep3& sweepB, float tMax, float target) noexcept {
  ToiOutput3 out;
  if (!finiteSweep(sweepA) || !finiteSweep(sweepB) || !(tMax >= 0.0f && tMax <= 1.0f) ||
      !(target >= 0.0f && std::isfinite(target))) {
    out.status = ToiStatus::invalidInput;
    return out;
  }
  const float rA = computeReach(a, sweepA.localCenter), rB = computeReach(b, sweepB.localCenter);
  const float spin = sweepAngle(sweepA) * rA + sweepAngle(sweepB) * rB;
  const Vec3 vRel = (sweepB.c2 - sweepB.c1) - (sweepA.c2 - sweepA.c1);
  // Hits land in [target, target + tol]: aim at the middle of the band.
  const float tol = kToiTolerance;
  GjkCache3 cache;
  float t = 0.0f;
  for (int iter = 0; iter < kToi3MaxIterations; ++iter) {
    Transform3 ta = transformAt(sweepA, t), tb = transformAt(sweepB, t);
    DistanceOutput3 d = computeDistance(a, ta, b, tb, &cache);
    ++out.iterations;
    out.t = t;
    out.distance = d.distance;
    if (t == 0.0f && d.distance <= 0.0f) {
      PenetrationOutput3 p = computePenetration(a, ta, b, tb);
      out.status = ToiStatus::overlapped;
      out.point = p.pointA;
      out.normal = p.normal;
      return out;
    }
    if (d.distance <= target + tol) {
      out.status = ToiStatus::hit;
      out.point = d.pointA;
      out.normal = d.normal;
      return out;
    }
    float mu = -dot(vRel, d.normal) + spin;
    if (mu <= 0.0f) {
      out.status = ToiStatus::separated;
      out.t = tMax;
      out.normal = {};
      return out;
    }
    t += (d.distance - target - 0.5f * tol) / mu;
    if (t >= tMax) {
      out.status = ToiStatus::separated;
      out.t = tMax;
      out.normal = {};
      return out;
    }
  }
  out.status = ToiStatus::failed;
  return out;
}

}  // namespace quack
