#include "quack/collision/toi.hpp"

#include <cmath>
#include <limits>

#include "quack/collision/epa.hpp"

namespace quack {
namespace {

bool isFiniteSweep(const Sweep& s) noexcept {
  return isFinite(s.localCenter) && isFinite(s.c1) && isFinite(s.c2) && isFinite(s.a1) &&
         isFinite(s.a2);
}

// One evaluation of the distance along the sweeps.
struct Sample {
  float t = 0.0f;
  float distance = 0.0f;
  float approach = 0.0f;  // the advancement bound mu at t, metres per unit time
  Vec2 point;
  Vec2 normal;
};

}  // namespace

const char* toString(ToiStatus status) noexcept {
  switch (status) {
    case ToiStatus::hit:
      return "hit";
    case ToiStatus::separated:
      return "separated";
    case ToiStatus::overlapped:
      return "overlapped";
    case ToiStatus::failed:
      return "failed";
    case ToiStatus::invalidInput:
      return "invalid_input";
  }
  return "unknown";
}

Status checkSweep(const Sweep& sweep, const std::string& name) {
  auto check = [&](float x, const char* field) -> Status {
    if (isFinite(x)) return {};
    return fail(name + "." + field + " is not finite: " + std::to_string(x));
  };
  for (auto [x, field] :
       {std::pair{sweep.localCenter.x, "localCenter.x"},
        std::pair{sweep.localCenter.y, "localCenter.y"}, std::pair{sweep.c1.x, "c1.x"},
        std::pair{sweep.c1.y, "c1.y"}, std::pair{sweep.c2.x, "c2.x"}, std::pair{sweep.c2.y, "c2.y"},
        std::pair{sweep.a1, "a1"}, std::pair{sweep.a2, "a2"}}) {
    if (Status s = check(x, field); !s) return s;
  }
  return {};
}

float computeMaxExtent(const ShapeProxy& proxy, Vec2 center) noexcept {
  float best = 0.0f;
  for (int i = 0; i < proxy.count(); ++i)
    best = maxf(best, distanceSquared(proxy.points()[i], center));
  return std::sqrt(best) + proxy.radius();
}

ToiOutput computeToi(const ShapeProxy& a, const Sweep& sweepA, const ShapeProxy& b,
                     const Sweep& sweepB, float tMax, float targetSeparation) noexcept {
  ToiOutput out;
  if (!isFiniteSweep(sweepA) || !isFiniteSweep(sweepB) || !(tMax >= 0.0f && tMax <= 1.0f) ||
      !isFinite(targetSeparation) || targetSeparation < 0.0f) {
    out.status = ToiStatus::invalidInput;
    return out;
  }
  const float target = targetSeparation;
  const float tolerance = clampf(0.25f * target, kToiMinTolerance, kToiTolerance);
  // Aim at the middle of the accepted band, so rounding in the last step lands inside it
  // rather than below the target.
  const float aim = target + 0.5f * tolerance;
  const Vec2 relativeVelocity = (sweepA.c2 - sweepA.c1) - (sweepB.c2 - sweepB.c1);
  const float extentA = computeMaxExtent(a, sweepA.localCenter);
  const float extentB = computeMaxExtent(b, sweepB.localCenter);
  const float spin = absf(sweepA.a2 - sweepA.a1) * extentA + absf(sweepB.a2 - sweepB.a1) * extentB;
  // The second bound, blind to rotation: each shape lies within its extent of its centre
  // of mass, so nothing is within the target while the centres are further apart than
  // extentA + extentB + aim. The centres' offset is linear in t: a quadratic gives the
  // first time it fails. It certifies the long approach of a fast spinner in one step.
  const Vec2 offset0 = sweepB.c1 - sweepA.c1;
  const Vec2 offsetRate = -relativeVelocity;
  const float reachRadius = extentA + extentB + aim;
  auto circleReach = [&](float t) {
    const Vec2 o = offset0 + t * offsetRate;
    const float c = lengthSquared(o) - reachRadius * reachRadius;
    if (c <= 0.0f) return t;  // the bounding circles already meet
    const float bb = dot(o, offsetRate);
    const float aa = lengthSquared(offsetRate);
    if (bb >= 0.0f || aa == 0.0f) return std::numeric_limits<float>::infinity();
    const float disc = bb * bb - aa * c;
    if (disc < 0.0f) return std::numeric_limits<float>::infinity();
    // The smaller root of aa s^2 + 2 bb s + c = 0, in the cancellation-free form.
    return t + c / (-bb + std::sqrt(disc));
  };

  // A sweep that does not turn keeps one rotation, so the static side of most queries pays
  // no trigonometry per evaluation; a turning sweep goes through transformAt.
  const Rot fixedA = Rot::fromAngle(sweepA.a1), fixedB = Rot::fromAngle(sweepB.a1);
  auto poseAt = [](const Sweep& s, Rot fixed, float t) {
    if (s.a1 != s.a2) return transformAt(s, t);
    const Vec2 c = (1.0f - t) * s.c1 + t * s.c2;
    return Transform{c - rotate(fixed, s.localCenter), fixed};
  };
  GjkCache cache;
  auto evaluate = [&](float t) {
    DistanceOutput d =
        computeDistance(a, poseAt(sweepA, fixedA, t), b, poseAt(sweepB, fixedB, t), &cache);
    ++out.iterations;
    return Sample{t, d.distance, dot(relativeVelocity, d.normal) + spin, d.pointA, d.normal};
  };
  auto finish = [&](ToiStatus status, const Sample& s) {
    out.status = status;
    out.t = s.t;
    out.distance = s.distance;
    if (status == ToiStatus::hit || status == ToiStatus::failed) {
      out.point = s.point;
      out.normal = s.normal;
    }
    return out;
  };

  Sample lo = evaluate(0.0f);
  if (lo.distance <= 0.0f) {
    PenetrationOutput p =
        computePenetration(a, transformAt(sweepA, 0.0f), b, transformAt(sweepB, 0.0f));
    out.status = ToiStatus::overlapped;
    out.t = 0.0f;
    out.distance = -p.depth;
    out.point = p.pointA;
    // EPA falls back to the centres itself; +y is the last resort for coincident points.
    out.normal = lengthSquared(p.normal) > 0.25f ? p.normal : Vec2{0.0f, 1.0f};
    return out;
  }

  // Samples later than `lo` that are still to be passed, the earliest on top. A sample
  // closer than the target is always alone at the bottom (everything after it is moot).
  Sample stack[kToiStackDepth];
  int top = 0;
  int advances = 0;
  for (;;) {
    if (lo.distance < target + tolerance) return finish(ToiStatus::hit, lo);
    // Nothing comes within the target before `reach` (the advancement bound).
    const float reach = maxf(lo.approach > 0.0f ? lo.t + (lo.distance - aim) / lo.approach
                                                : std::numeric_limits<float>::infinity(),
                             circleReach(lo.t));
    const float end = top > 0 ? stack[top - 1].t : tMax;
    // A free sample bounds backwards as well: nothing within the target after `back`.
    // Backwards in time the separation along n shrinks at most at spin - dot(v, n).
    float back = end;
    if (top > 0 && stack[top - 1].distance >= target + tolerance) {
      const float recede = 2.0f * spin - stack[top - 1].approach;
      back = recede > 0.0f ? end - (stack[top - 1].distance - aim) / recede : lo.t;
    }
    if (reach >= back) {
      if (top == 0) {
        Sample last = lo;
        last.t = tMax;
        return finish(ToiStatus::separated, last);
      }
      lo = stack[--top];
      continue;
    }
    if (out.iterations >= kToiMaxIterations) return finish(ToiStatus::failed, lo);
    if (advances < kToiMaxAdvancements && reach > lo.t) {
      ++advances;
      const Sample next = evaluate(reach);
      // Rounding can carry a step a hair past the target; the bound says `reach` is free
      // (up to that rounding), so it is the answer, or `lo` if rounding made it overlap.
      if (next.distance < target + tolerance)
        return finish(ToiStatus::hit, next.distance > 0.0f ? next : lo);
      lo = next;
      continue;
    }
    // Bisection between the last free time and the earliest pending sample (or tMax).
    const Sample mid = evaluate(0.5f * (lo.t + end));
    if (!(mid.t > lo.t && mid.t < end)) return finish(ToiStatus::failed, lo);  // float limit
    if (mid.distance < target + tolerance) {
      top = 0;  // the first contact is no later than mid
    } else if (top == kToiStackDepth) {
      return finish(ToiStatus::failed, lo);
    }
    stack[top++] = mid;
  }
}

}  // namespace quack
