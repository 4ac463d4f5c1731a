#include "quack/collision/gjk.hpp"

#include "gjk_internal.hpp"

namespace quack {

const char* toString(GjkStatus status) noexcept {
  switch (status) {
    case GjkStatus::converged:
      return "converged";
    case GjkStatus::repeatedSupport:
      return "repeated_support";
    case GjkStatus::stalled:
      return "stalled";
    case GjkStatus::overlap:
      return "overlap";
    case GjkStatus::maxIterations:
      return "max_iterations";
  }
  return "unknown";
}

namespace detail {
namespace {

// Rises of |v|^2 within this fraction count as rounding, not as a step backwards: about 8
// float ulps, above the cancellation of the segment projection, below any real rise.
constexpr float kGjkStallRelativeTolerance = 8.0f * std::numeric_limits<float>::epsilon();

SupportPoint supportFromIndices(const ShapeProxy& a, const ShapeProxy& b, Transform aFromB,
                                int indexA, int indexB) noexcept {
  SupportPoint s;
  s.indexA = indexA;
  s.indexB = indexB;
  s.pointA = a.points()[indexA];
  s.pointB = transformPoint(aFromB, b.points()[indexB]);
  s.w = s.pointB - s.pointA;
  return s;
}

bool loadCache(const GjkCache* cache, const ShapeProxy& a, const ShapeProxy& b, Transform aFromB,
               Simplex2& s) noexcept {
  if (cache == nullptr || cache->count < 1 || cache->count > 3) return false;
  for (int i = 0; i < cache->count; ++i) {
    if (cache->indexA[i] >= a.count() || cache->indexB[i] >= b.count()) return false;
    s.vertices[i].support = supportFromIndices(a, b, aFromB, cache->indexA[i], cache->indexB[i]);
  }
  s.count = cache->count;
  return true;
}

// normalize(v) given length(v), so one square root serves both the direction and |v|.
Vec2 normalizeWithLength(Vec2 v, float len) noexcept {
  if (len < kNormalizeEpsilon) return {};
  float inv = 1.0f / len;
  return {inv * v.x, inv * v.y};
}

// closestDirection with |v| = sqrt(vv) computed at most once and returned when formed.
struct Direction {
  Vec2 unit;
  float vLength = -1.0f;  // length(v) when it was needed, else -1
};

// Always inlined, so that the unobserved runGjk is compiled as if it were the only one:
// with the observed instantiation as a third caller the compiler would call it instead,
// and every query would pay for the call.
[[gnu::always_inline]] inline Direction findClosestDirection(const Simplex2& simplex, Vec2 v,
                                                             float vv) noexcept {
  if (simplex.count == 2) {
    Vec2 a = simplex.vertices[0].support.w;
    Vec2 n = normalize(leftPerp(simplex.vertices[1].support.w - a));
    float side = dot(n, a);
    if (side < 0.0f) return {-n};
    if (side > 0.0f) return {n};
  }
  float len = std::sqrt(vv);
  return {normalizeWithLength(v, len), len};
}

}  // namespace

Vec2 closestDirection(const Simplex2& simplex, Vec2 v) noexcept {
  return findClosestDirection(simplex, v, lengthSquared(v)).unit;
}

template <class Observer>
GjkRun runGjk(const ShapeProxy& a, const ShapeProxy& b, Transform aFromB, GjkCache* cache,
              float earlyOutRadius, Observer& observer) noexcept {
  GjkRun run;
  Simplex2& s = run.simplex;
  if (!loadCache(cache, a, b, aFromB, s)) {
    // Start from the support point towards the origin as seen from the centre of B - A:
    // on a cold start it is usually one edge away from the answer (docs/background.md,
    // "Narrow phase").
    Vec2 c = transformPoint(aFromB, b.center()) - a.center();
    if (c == Vec2{}) c = {1.0f, 0.0f};
    s.vertices[0].support = supportMinkowski(a, b, aFromB, -c);
    s.count = 1;
  }

  const bool earlyOut = earlyOutRadius >= 0.0f;
  Simplex2 previous;
  Vec2 previousClosest;
  Vec2 previousDirection;
  float previousVV = std::numeric_limits<float>::infinity();
  const float earlyOutSq = earlyOutRadius * earlyOutRadius;
  int unchangedSteps = 0;
  for (;;) {
    SimplexSolution solution = solveSimplex2(s);
    if (solution.holdsOrigin) {
      run.closest = {};
      run.status = GjkStatus::overlap;
      observer.onPass(run, nullptr);
      break;
    }
    Vec2 v = solution.closest;
    float vv = lengthSquared(v);
    float maxWW = 0.0f;
    for (int i = 0; i < s.count; ++i)
      maxWW = maxf(maxWW, lengthSquared(s.vertices[i].support.w));
    if (vv <= kGjkContactRelativeTolerance * kGjkContactRelativeTolerance * maxWW) {
      run.closest = {};
      run.status = GjkStatus::overlap;
      observer.onPass(run, nullptr);
      break;
    }
    // |v| must fall every iteration. When it rose (or is NaN), rounding has the last word
    // and the previous simplex is better. When it is unchanged in float, keep going: near a
    // vertex |v| changes to second order while its direction still changes to first order
    // (the normal would be off by 1e-4 if GJK stopped here); the repeated-support test or
    // a third unchanged step ends it.
    // "Unchanged" allows a few ulps of rise: a new support point that improves |v| only to
    // second order (far along an edge nearly square to v) can come out a rounding step
    // worse, and stopping there left GJK 1.7e-4 short on a thin pair (regression test
    // Gjk.NearlyFlatFirstEdgeDoesNotStall).
    if (vv <= previousVV * (1.0f + kGjkStallRelativeTolerance) && ++unchangedSteps <= 2) {
      // fall through with the new simplex
    } else if (!(vv < previousVV)) {
      if (previous.count > 0) {
        s = previous;
        run.closest = previousClosest;
        run.direction = previousDirection;
        run.hasDirection = true;
      }
      run.status = GjkStatus::stalled;
      observer.onPass(run, nullptr);
      break;
    }
    run.closest = v;
    if (earlyOut && vv <= earlyOutSq) {
      run.status = GjkStatus::overlap;
      observer.onPass(run, nullptr);
      break;
    }
    if (run.iterations >= kGjkMaxIterations) {
      run.status = GjkStatus::maxIterations;
      observer.onPass(run, nullptr);
      break;
    }
    // Only the vertices in use (a full copy moved three every iteration).
    previous.count = s.count;
    for (int i = 0; i < s.count; ++i)
      previous.vertices[i] = s.vertices[i];
    previousClosest = v;
    previousVV = vv;

    // Search along the exact edge normal rather than -v (see closestDirection): with a
    // thin B - A and the origin near it, -v can be off by 1e-3 rad and find the wrong
    // support point, stopping GJK on a diagonal instead of an edge.
    Direction direction = findClosestDirection(s, v, vv);
    const Vec2 dir = direction.unit;
    previousDirection = dir;
    run.direction = dir;
    run.hasDirection = true;
    SupportPoint w = supportMinkowski(a, b, aFromB, -dir);
    ++run.iterations;
    // Seen before the stopping tests: whichever ends the loop, this pass's answer is the
    // final one (closest, direction and simplex are not touched again).
    observer.onPass(run, &w);
    // v.w measured along the exact direction: |v| * (dir . w). Formed only when a test
    // needs it: most runs end on a repeated support point.
    auto measureVW = [&] {
      float vLength = direction.vLength >= 0.0f ? direction.vLength : length(v);
      return vLength * dot(dir, w.w);
    };
    if (earlyOut) {
      float vw = measureVW();
      if (vw > 0.0f && vw * vw > earlyOutSq * vv) {
        run.separatedEarly = true;
        run.status = GjkStatus::converged;
        break;
      }
    }
    bool repeated = false;
    for (int i = 0; i < s.count; ++i) {
      repeated |=
          s.vertices[i].support.indexA == w.indexA && s.vertices[i].support.indexB == w.indexB;
    }
    if (repeated) {
      run.status = GjkStatus::repeatedSupport;
      break;
    }
    if (measureVW() >= vv) {
      run.status = GjkStatus::converged;
      break;
    }
    s.vertices[s.count].support = w;
    ++s.count;
    run.hasDirection = false;
  }

  if (cache != nullptr) {
    cache->count = s.count;
    for (int i = 0; i < s.count; ++i) {
      cache->indexA[i] = static_cast<std::uint8_t>(s.vertices[i].support.indexA);
      cache->indexB[i] = static_cast<std::uint8_t>(s.vertices[i].support.indexB);
    }
  }
  return run;
}

template GjkRun runGjk<NoGjkObserver>(const ShapeProxy&, const ShapeProxy&, Transform, GjkCache*,
                                      float, NoGjkObserver&) noexcept;
template GjkRun runGjk<GjkRecorder>(const ShapeProxy&, const ShapeProxy&, Transform, GjkCache*,
                                    float, GjkRecorder&) noexcept;

namespace {

// computeDistance's answer from a run's state (the final one, or any pass's, for the trace);
// iterations and status are left to the caller. Always inlined, so that computeDistance
// pays for no call on every query.
[[gnu::always_inline]] inline DistanceOutput makeDistanceOutput(const ShapeProxy& a,
                                                                const ShapeProxy& b,
                                                                Transform worldFromA,
                                                                const GjkRun& run) noexcept {
  WitnessPoints witness = computeWitnessPoints(run.simplex);
  DistanceOutput out;
  float radii = a.radius() + b.radius();
  if (run.status == GjkStatus::overlap) {
    // The weights make pointA and pointB the same point of both cores.
    Vec2 p = 0.5f * (witness.pointA + witness.pointB);
    out.pointA = out.pointB = transformPoint(worldFromA, p);
    return out;
  }
  float core = length(run.closest);
  Vec2 n = run.hasDirection ? run.direction : closestDirection(run.simplex, run.closest);
  out.coreDistance = core;
  out.normal = rotate(worldFromA.q, n);
  Vec2 pa = witness.pointA + a.radius() * n;
  Vec2 pb = witness.pointB - b.radius() * n;
  if (core > radii) {
    out.distance = core - radii;
    out.pointA = transformPoint(worldFromA, pa);
    out.pointB = transformPoint(worldFromA, pb);
  } else {
    // Only the rounding overlaps: the shared point halfway between the surface points.
    out.pointA = out.pointB = transformPoint(worldFromA, 0.5f * (pa + pb));
  }
  return out;
}

}  // namespace

void GjkRecorder::onPass(const GjkRun& run, const SupportPoint* support) noexcept {
  if (trace == nullptr) return;
  GjkIterationRecord* record = claimTraceRecord(*trace);
  if (record == nullptr) return;
  record->simplex = run.simplex;
  record->closest = run.closest;
  record->hasSupport = support != nullptr;
  record->direction = support != nullptr ? run.direction : Vec2{};
  record->support = support != nullptr ? *support : SupportPoint{};
  DistanceOutput answer = makeDistanceOutput(a, b, worldFromA, run);
  record->distance = answer.distance;
  record->coreDistance = answer.coreDistance;
  record->pointA = answer.pointA;
  record->pointB = answer.pointB;
  record->normal = answer.normal;
}

}  // namespace detail

namespace {

template <class Observer>
DistanceOutput distanceWith(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                            Transform worldFromB, GjkCache* cache, Observer& observer) noexcept {
  Transform aFromB = invMul(worldFromA, worldFromB);
  detail::GjkRun run = detail::runGjk(a, b, aFromB, cache, -1.0f, observer);
  DistanceOutput out = detail::makeDistanceOutput(a, b, worldFromA, run);
  out.iterations = run.iterations;
  out.status = run.status;
  return out;
}

}  // namespace

DistanceOutput computeDistance(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                               Transform worldFromB, GjkCache* cache) noexcept {
  detail::NoGjkObserver none;
  return distanceWith(a, worldFromA, b, worldFromB, cache, none);
}

DistanceOutput computeDistance(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                               Transform worldFromB, GjkCache* cache, GjkTrace& trace) noexcept {
  detail::resetTrace(trace);
  detail::GjkRecorder recorder{a, b, worldFromA, &trace};
  return distanceWith(a, worldFromA, b, worldFromB, cache, recorder);
}

bool testOverlap(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                 Transform worldFromB, GjkCache* cache) noexcept {
  Transform aFromB = invMul(worldFromA, worldFromB);
  float radii = a.radius() + b.radius();
  detail::NoGjkObserver none;
  detail::GjkRun run = detail::runGjk(a, b, aFromB, cache, radii, none);
  if (run.separatedEarly) return false;
  if (run.status == GjkStatus::overlap) return true;
  return length(run.closest) <= radii;
}

}  // namespace quack
