#include "quack/collision/shape_cast.hpp"

#include "quack/collision/epa.hpp"

namespace quack {
namespace {

bool isFiniteTransform(Transform xf) noexcept {
  return isFinite(xf.p) && isFinite(xf.q.c) && isFinite(xf.q.s);
}

// A unit direction that is never zero: `n` when it is a direction, else `fallback`, else +y.
Vec2 nonZeroDirection(Vec2 n, Vec2 fallback) noexcept {
  if (lengthSquared(n) > 0.25f) return normalize(n);
  if (lengthSquared(fallback) > 0.0f) return normalize(fallback);
  return {0.0f, 1.0f};
}

}  // namespace

const char* toString(ShapeCastStatus status) noexcept {
  switch (status) {
    case ShapeCastStatus::hit:
      return "hit";
    case ShapeCastStatus::missed:
      return "missed";
    case ShapeCastStatus::overlapped:
      return "overlapped";
    case ShapeCastStatus::maxIterations:
      return "max_iterations";
    case ShapeCastStatus::invalidInput:
      return "invalid_input";
  }
  return "unknown";
}

ShapeCastOutput castShape(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                          Transform worldFromB, Vec2 translationB, float maxFraction) noexcept {
  ShapeCastOutput out;
  if (!isFiniteTransform(worldFromA) || !isFiniteTransform(worldFromB) || !isFinite(translationB) ||
      !(maxFraction >= 0.0f && maxFraction <= 1.0f)) {
    out.status = ShapeCastStatus::invalidInput;
    return out;
  }
  GjkCache cache;
  DistanceOutput d = computeDistance(a, worldFromA, b, worldFromB, &cache);
  out.iterations = 1;
  if (d.distance <= 0.0f) {
    // Overlap (or exact touching) at the start: a defined answer, EPA's depth and normal.
    PenetrationOutput p = computePenetration(a, worldFromA, b, worldFromB);
    out.hit = true;
    out.status = ShapeCastStatus::overlapped;
    out.fraction = 0.0f;
    // EPA's degenerate cases already fall back to the centres; the last resort is the
    // direction opposite the motion, which backs B out the way it came.
    out.normal = nonZeroDirection(p.normal, -translationB);
    out.depth = p.depth;
    out.point = p.pointA;
    return out;
  }
  // Aim half a tolerance above touching, so rounding cannot carry the last step into
  // overlap (where GJK has no normal), and stop anywhere below a whole tolerance.
  const float aim = 0.5f * kShapeCastTolerance;
  float s = 0.0f;
  for (;;) {
    const float approach = -dot(translationB, d.normal);  // metres per unit fraction
    if (d.distance < kShapeCastTolerance) {
      if (approach <= 0.0f && s == 0.0f) break;  // touching but leaving: a miss
      out.hit = true;
      out.status = ShapeCastStatus::hit;
      out.fraction = s;
      out.point = d.pointA;
      out.normal = d.normal;
      return out;
    }
    // Convexity: with no approach along the separating normal, d never decreases.
    if (approach <= 0.0f) break;
    const float next = s + (d.distance - aim) / approach;
    if (!(next <= maxFraction)) break;  // also catches NaN
    if (out.iterations >= kShapeCastMaxIterations) {
      out.status = ShapeCastStatus::maxIterations;
      out.fraction = s;
      return out;
    }
    s = next;
    const Vec2 lastNormal = d.normal;
    d = computeDistance(a, worldFromA, b, {worldFromB.p + s * translationB, worldFromB.q}, &cache);
    ++out.iterations;
    if (d.distance <= 0.0f) {
      // Rounding carried the step into contact: the previous fraction was free and this
      // one touches, so this is the hit, with the last separating normal kept.
      out.hit = true;
      out.status = ShapeCastStatus::hit;
      out.fraction = s;
      out.point = d.pointA;
      out.normal = nonZeroDirection(d.normal, lastNormal);
      return out;
    }
  }
  out.status = ShapeCastStatus::missed;
  out.fraction = maxFraction;
  return out;
}

}  // namespace quack
