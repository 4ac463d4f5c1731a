#include "quack/collision/gjk.hpp"

#include <cstdint>
#include <limits>
#include <type_traits>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include "gjk_internal.hpp"
#include "simplex2_internal.hpp"

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

[[gnu::always_inline]] inline bool loadCache(const GjkCache* cache, const ShapeProxy& a,
                                             const ShapeProxy& b, Transform aFromB,
                                             GjkVertex* v) noexcept {
  if (cache == nullptr || cache->count < 1 || cache->count > 3) return false;
  for (int i = 0; i < cache->count; ++i) {
    if (cache->indexA[i] >= a.count() || cache->indexB[i] >= b.count()) return false;
    v[i].key = packGjkIndices(cache->indexA[i], cache->indexB[i]);
    v[i].w = supportOf(v[i], a, b, aFromB).w;
  }
  return true;
}

// normalize(v) given length(v), so one square root serves both the direction and |v|.
Vec2 normalizeWithLength(Vec2 v, float len) noexcept {
  if (len < kNormalizeEpsilon) return {};
  float inv = 1.0f / len;
  return {inv * v.x, inv * v.y};
}

// closestDirection's normalize(leftPerp(edge)) for a solved edge: the squared length of
// leftPerp(edge) is the solve's dot(edge, edge) (the same two products, added in the other
// order, so the same float).
[[gnu::always_inline]] inline Vec2 edgeNormal(const SegmentSolve& r) noexcept {
  return normalizeWithLength(leftPerp(r.edge), std::sqrt(r.edgeSq));
}

// The edge ij of the loop's simplex (i < j: the kept vertices stay in insertion order) as
// the new simplex, as solveSimplex2's keepSegment does it, with selects for its branches.
[[gnu::always_inline]] inline int keepEdge(GjkVertex* v, int i, int j,
                                           const SegmentSolve& r) noexcept {
  const SegmentWeights weights = segmentWeights(r);
  const GjkVertex vi = v[i];
  const GjkVertex vj = v[j];
  const bool both = (weights.a > 0.0f) & (weights.b > 0.0f);
  v[0] = weights.a > 0.0f ? vi : vj;
  v[0].weight = both ? weights.a : 1.0f;
  v[1] = vj;  // unused when only one end stays
  v[1].weight = weights.b;
  return both ? 2 : 1;
}

// The points of a proxy of up to kPlacedMax points placed by a transform once, up front,
// with transformPoint's arithmetic (two points per register: c (x, y) + (-s, s) (y, x) + p,
// the same products and sums), so that GJK's support point is a load rather than a
// transform on the chain search -> support -> solve -> direction, which sets the query's
// time. The searches run over the placed points too, along a direction in A's frame: the
// direction need not be turned into B's frame first (a rotation on that chain), and the
// products are those of the points as GJK uses them. Larger proxies are transformed point
// by point when asked, and searched in their own frame.
class PlacedPoints {
 public:
  static constexpr int kPlacedMax = 8;

  PlacedPoints(Transform xf, const Vec2* points, int count) noexcept
      : xf_(xf), points_(points), isPlaced_(count <= kPlacedMax) {
    if (!isPlaced_) return;
    int i = 0;
#if defined(__SSE2__)
    const __m128 c = _mm_set1_ps(xf.q.c);
    const __m128 s = _mm_setr_ps(-xf.q.s, xf.q.s, -xf.q.s, xf.q.s);
    const __m128 t = _mm_setr_ps(xf.p.x, xf.p.y, xf.p.x, xf.p.y);
    for (; i + 2 <= count; i += 2) {
      const __m128 v = _mm_loadu_ps(&points[i].x);
      const __m128 swapped = _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1));
      _mm_store_ps(&placed_[i].x,
                   _mm_add_ps(_mm_add_ps(_mm_mul_ps(c, v), _mm_mul_ps(s, swapped)), t));
    }
#endif
    for (; i < count; ++i)
      placed_[i] = transformPoint(xf, points[i]);
  }

  Vec2 at(int i) const noexcept {
    if (isPlaced_) return placed_[i];
    return transformPoint(xf_, points_[i]);
  }
  // The points to search: the placed ones (A's frame) or, past kPlacedMax, B's own.
  const Vec2* searchPoints() const noexcept {
    return isPlaced_ ? placed_ : points_;
  }
  // A direction in A's frame as the search over searchPoints() wants it.
  Vec2 searchDirection(Vec2 directionInA) const noexcept {
    return isPlaced_ ? directionInA : invRotate(xf_.q, directionInA);
  }

 private:
  Transform xf_;
  const Vec2* points_;
  bool isPlaced_;
  alignas(16) Vec2 placed_[kPlacedMax];  // not zero-filled: written before read
};

}  // namespace

Vec2 closestDirection(const GjkRun& run) noexcept {
  Vec2 v = run.closest;
  if (run.count == 2) {
    Vec2 a = run.vertices[0].w;
    Vec2 n = normalize(leftPerp(run.vertices[1].w - a));
    float side = dot(n, a);
    if (side < 0.0f) return -n;
    if (side > 0.0f) return n;
  }
  return normalizeWithLength(v, length(v));
}

Simplex2 toSimplex2(const GjkRun& run, const ShapeProxy& a, const ShapeProxy& b,
                    Transform aFromB) noexcept {
  Simplex2 s;
  s.count = run.count;
  for (int i = 0; i < run.count; ++i) {
    s.vertices[i].support = supportOf(run.vertices[i], a, b, aFromB);
    s.vertices[i].weight = run.vertices[i].weight;
  }
  return s;
}

namespace {

// runGjk's loop, with earlyOut (earlyOutRadius >= 0) fixed at compile time: only
// testOverlap asks for it, and the tests it adds to every pass of the other queries cost
// about 20 instructions a query.
template <class Observer, bool earlyOut>
[[gnu::always_inline]] inline GjkRun gjkLoop(const ShapeProxy& a, const ShapeProxy& b,
                                             const Transform& aFromB, GjkCache* cache,
                                             float earlyOutRadius, Observer& observer) noexcept {
  GjkRun run;
  GjkVertex* v = run.vertices;
  int& count = run.count;
  auto observe = [&]([[maybe_unused]] const SupportPoint* support) {
    if constexpr (!std::is_same_v<Observer, NoGjkObserver>) observer.onPass(run, aFromB, support);
  };

  // supportMinkowski, with the proxies' points and counts and the transform read once:
  // the loop's stores into the run may alias them as far as the compiler knows (an int is
  // an int), and it would load them again for every search.
  const Vec2* const pointsA = a.points();
  const Vec2* const pointsB = b.points();
  const int countA = a.count();
  const int countB = b.count();
  const Transform xf = aFromB;
  const PointSearch searchA(pointsA, countA);
  const PlacedPoints placedB(xf, pointsB, countB);
  const PointSearch searchB(placedB.searchPoints(), countB);
  const bool edgeColumns = searchA.hasColumns() && searchB.hasColumns();
  // The support point of B - A along -direction (any length): A searched along direction,
  // B along -direction. Always inlined: left to itself the compiler calls it for the first
  // search and saves and restores a dozen registers around the call.
  auto support = [&](Vec2 direction) __attribute__((always_inline)) {
    const int indexA = searchA.findFirstMaxDot(-direction);
    const int indexB = searchB.findFirstMaxDot(placedB.searchDirection(direction));
    GjkVertex s;
    s.w = placedB.at(indexB) - pointsA[indexA];
    s.key = packGjkIndices(indexA, indexB);
    return s;
  };

  if (loadCache(cache, a, b, aFromB, v)) {
    count = cache->count;
  } else {
    // Start from the support point towards the origin as seen from the centre of B - A:
    // on a cold start it is usually one edge away from the answer (docs/background.md,
    // "Narrow phase").
    Vec2 c = transformPoint(aFromB, b.center()) - a.center();
    if (c == Vec2{}) c = {1.0f, 0.0f};
    v[0] = support(-c);
    count = 1;
  }

  // The simplex of the pass before, for the stall test: at most two vertices (a triangle
  // either holds the origin, which ends the run, or is reduced), copied whole each pass.
  GjkVertex previous[2];
  int previousCount = 0;
  Vec2 previousClosest;
  Vec2 previousDirection;
  float previousVV = std::numeric_limits<float>::infinity();
  const float earlyOutSq = earlyOutRadius * earlyOutRadius;
  int unchangedSteps = 0;
  for (;;) {
    // Solve the simplex (solveSimplex2's arithmetic, simplex2_internal.hpp). When it ends
    // as a segment, the direction below is that segment's unit normal, formed here from
    // the solve's edge and squared length.
    Vec2 point;
    Vec2 normal;
    Vec2 perp;  // leftPerp of the kept edge: the normal's direction, exact and not unit
    // The kept edge's first vertex, for the side test below. When the edge is kept (count
    // 2) it is v[0] after keepEdge, but read before: keepEdge's choice waits on the solve's
    // division, and the side test, on the chain to the next search, need not.
    Vec2 edgeStart;
    if (count == 1) {
      v[0].weight = 1.0f;
      point = v[0].w;
    } else if (count == 2) {
      edgeStart = v[0].w;
      const SegmentSolve r = solveSegment(v[0].w, v[1].w);
      count = keepEdge(v, 0, 1, r);
      point = r.closest;
      normal = edgeNormal(r);
      perp = leftPerp(r.edge);
    } else {
      const TriangleAreas t = triangleAreas(v[0].w, v[1].w, v[2].w);
      if (!(t.faces[0] | t.faces[1] | t.faces[2])) {
        v[0].weight = t.sub[0] / t.mu;
        v[1].weight = t.sub[1] / t.mu;
        v[2].weight = t.sub[2] / t.mu;
        run.closest = {};
        run.status = GjkStatus::overlap;
        observe(nullptr);
        break;
      }
      // The nearest of the edges facing the origin, tried in solveSimplex2's order (the
      // edges opposite vertex 0, 1, 2) with its strict comparison. Both edges through
      // vertex 2 are solved whether they face it or not, so that choosing costs no branch:
      // in the loop vertex 2 is the support point just found beyond edge 01, so the
      // origin is on their side and edge 01 faces it only through rounding.
      const SegmentSolve r0 = solveSegment(v[1].w, v[2].w);
      const SegmentSolve r1 = solveSegment(v[0].w, v[2].w);
      const float d0 = lengthSquared(r0.closest);
      const float d1 = lengthSquared(r1.closest);
      const bool take0 = t.faces[0] & (d0 < std::numeric_limits<float>::infinity());
      float best = take0 ? d0 : std::numeric_limits<float>::infinity();
      const bool take1 = t.faces[1] & (d1 < best);
      best = take1 ? d1 : best;
      const SegmentSolve* chosen = take1 ? &r1 : (take0 ? &r0 : nullptr);
      int i = take1 ? 0 : 1;
      int j = 2;
      // Both normals are formed before the choice, so that their square roots and
      // divisions overlap the solves' instead of waiting for the comparison.
      const Vec2 normals[2] = {edgeNormal(r0), edgeNormal(r1)};
      normal = normals[static_cast<int>(take1)];
      perp = leftPerp(take1 ? r1.edge : r0.edge);
      SegmentSolve r2;
      if (t.faces[2]) {
        r2 = solveSegment(v[0].w, v[1].w);
        if (lengthSquared(r2.closest) < best) {
          chosen = &r2;
          i = 0;
          j = 1;
          normal = edgeNormal(r2);
          perp = leftPerp(r2.edge);
        }
      }
      if (chosen == nullptr) {
        // Only reachable with NaN coordinates: keep one vertex so that the run stops.
        count = 1;
        v[0].weight = 1.0f;
        point = v[0].w;
      } else {
        edgeStart = v[i].w;
        count = keepEdge(v, i, j, *chosen);
        point = chosen->closest;
      }
    }

    const Vec2 vPoint = point;
    float vv = lengthSquared(vPoint);
    // The largest |w|^2 of the (one or two) vertices left, in the order of a loop over them.
    float maxWW = maxf(0.0f, lengthSquared(v[0].w));
    const float maxWW2 = maxf(maxWW, lengthSquared(v[1].w));
    maxWW = count == 2 ? maxWW2 : maxWW;
    if (vv <= kGjkContactRelativeTolerance * kGjkContactRelativeTolerance * maxWW) {
      run.closest = {};
      run.status = GjkStatus::overlap;
      observe(nullptr);
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
      if (previousCount > 0) {
        v[0] = previous[0];
        v[1] = previous[1];
        count = previousCount;
        run.closest = previousClosest;
        run.direction = previousDirection;
        run.hasDirection = true;
      }
      run.status = GjkStatus::stalled;
      observe(nullptr);
      break;
    }
    run.closest = vPoint;
    if constexpr (earlyOut) {
      if (vv <= earlyOutSq) {
        run.status = GjkStatus::overlap;
        observe(nullptr);
        break;
      }
    }
    if (run.iterations >= kGjkMaxIterations) {
      run.status = GjkStatus::maxIterations;
      observe(nullptr);
      break;
    }
    previous[0] = v[0];
    previous[1] = v[1];
    previousCount = count;
    previousClosest = vPoint;
    previousVV = vv;

    // On an edge, search along the edge's normal rather than -v (see closestDirection):
    // with a thin B - A and the origin near it, -v can be off by 1e-3 rad and find the
    // wrong support point, stopping GJK on a diagonal instead of an edge. The search runs
    // along the exact, unnormalised perpendicular (off an edge, along v itself): the unit
    // vector's direction, so the same support points but for rounding in near-ties, without
    // waiting for the square root and division that make it (about a quarter of each pass's
    // time on the chain search -> support -> solve -> direction). The unit direction is
    // still formed, beside the search, for the stopping test and the answer.
    const float vLength = std::sqrt(vv);
    bool onEdge = false;
    bool flipped = false;
    Vec2 dir;
    if (count == 2) {
      const Vec2 n = normal;
      const float side = dot(perp, edgeStart);
      onEdge = (side < 0.0f) | (side > 0.0f);
      flipped = side < 0.0f;
      // -n when side < 0 (exactly: a product with -1), by a table, not a branch.
      constexpr float kSign[2] = {1.0f, -1.0f};
      const float sign = kSign[static_cast<int>(flipped)];
      dir = {sign * n.x, sign * n.y};
    }
    if (!onEdge) dir = normalizeWithLength(vPoint, vLength);
    run.direction = dir;
    previousDirection = dir;
    run.hasDirection = true;
    GjkVertex w;
    if (onEdge & edgeColumns) {
      // dir is along perp or -perp, and every product along -perp is the one along perp
      // negated (exactly), so both searches run along perp and take the first largest or
      // least product once the side is known: the searches need not wait for the side test
      // and the sign. A is searched along dir, B along -dir.
      int mostA = 0, leastA = 0, mostB = 0, leastB = 0;
      searchA.findFirstMaxAndMinDot(perp, mostA, leastA);
      searchB.findFirstMaxAndMinDot(placedB.searchDirection(perp), mostB, leastB);
      const int mask = -static_cast<int>(flipped);  // all ones when dir = -perp
      const int indexA = mostA ^ ((mostA ^ leastA) & mask);
      const int indexB = leastB ^ ((leastB ^ mostB) & mask);
      w.w = placedB.at(indexB) - pointsA[indexA];
      w.key = packGjkIndices(indexA, indexB);
    } else if (onEdge) {
      const Vec2 along = flipped ? -perp : perp;
      w = support(-along);
    } else {
      w = support(-vPoint);
    }
    ++run.iterations;
    // Seen before the stopping tests: whichever ends the loop, this pass's answer is the
    // final one (closest, direction and simplex are not touched again).
    if constexpr (!std::is_same_v<Observer, NoGjkObserver>) {
      const SupportPoint found = supportOf(w, a, b, aFromB);
      observe(&found);
    }
    // v.w measured along the exact direction: |v| * (dir . w).
    const float vw = vLength * dot(dir, w.w);
    if constexpr (earlyOut) {
      if (vw > 0.0f && vw * vw > earlyOutSq * vv) {
        run.separatedEarly = true;
        run.status = GjkStatus::converged;
        break;
      }
    }
    const std::uint32_t key = w.key;
    if ((v[0].key == key) | ((count == 2) & (v[1].key == key))) {
      run.status = GjkStatus::repeatedSupport;
      break;
    }
    if (vw >= vv) {
      run.status = GjkStatus::converged;
      break;
    }
    v[count].w = w.w;
    v[count].key = key;
    ++count;
    run.hasDirection = false;
  }

  if (cache != nullptr) {
    cache->count = count;
    for (int i = 0; i < count; ++i) {
      cache->indexA[i] = static_cast<std::uint8_t>(v[i].indexA());
      cache->indexB[i] = static_cast<std::uint8_t>(v[i].indexB());
    }
  }
  return run;
}

}  // namespace

template <class Observer>
GjkRun runGjk(const ShapeProxy& a, const ShapeProxy& b, const Transform& aFromB, GjkCache* cache,
              float earlyOutRadius, Observer& observer) noexcept {
  if (earlyOutRadius >= 0.0f)
    return gjkLoop<Observer, true>(a, b, aFromB, cache, earlyOutRadius, observer);
  return gjkLoop<Observer, false>(a, b, aFromB, cache, earlyOutRadius, observer);
}

template GjkRun runGjk<NoGjkObserver>(const ShapeProxy&, const ShapeProxy&, const Transform&,
                                      GjkCache*, float, NoGjkObserver&) noexcept;
template GjkRun runGjk<GjkRecorder>(const ShapeProxy&, const ShapeProxy&, const Transform&,
                                    GjkCache*, float, GjkRecorder&) noexcept;

namespace {

// computeDistance's answer from a run's state (the final one, or any pass's, for the trace);
// iterations and status are left to the caller. Always inlined, so that computeDistance
// pays for no call on every query.
[[gnu::always_inline]] inline DistanceOutput makeDistanceOutput(const ShapeProxy& a,
                                                                const ShapeProxy& b,
                                                                Transform worldFromA,
                                                                Transform aFromB,
                                                                const GjkRun& run) noexcept {
  WitnessPoints witness = witnessPoints(run, a, b, aFromB);
  DistanceOutput out;
  float radii = a.radius() + b.radius();
  if (run.status == GjkStatus::overlap) {
    // The weights make pointA and pointB the same point of both cores.
    Vec2 p = 0.5f * (witness.pointA + witness.pointB);
    out.pointA = out.pointB = transformPoint(worldFromA, p);
    return out;
  }
  float core = length(run.closest);
  Vec2 n = run.hasDirection ? run.direction : closestDirection(run);
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

void GjkRecorder::onPass(const GjkRun& run, Transform aFromB,
                         const SupportPoint* support) noexcept {
  if (trace == nullptr) return;
  GjkIterationRecord* record = claimTraceRecord(*trace);
  if (record == nullptr) return;
  record->simplex = toSimplex2(run, a, b, aFromB);
  record->closest = run.closest;
  record->hasSupport = support != nullptr;
  record->direction = support != nullptr ? run.direction : Vec2{};
  record->support = support != nullptr ? *support : SupportPoint{};
  DistanceOutput answer = makeDistanceOutput(a, b, worldFromA, aFromB, run);
  record->distance = answer.distance;
  record->coreDistance = answer.coreDistance;
  record->pointA = answer.pointA;
  record->pointB = answer.pointB;
  record->normal = answer.normal;
}

}  // namespace detail

namespace {

template <class Observer>
DistanceOutput distanceWith(const ShapeProxy& a, const Transform& worldFromA, const ShapeProxy& b,
                            const Transform& worldFromB, GjkCache* cache,
                            Observer& observer) noexcept {
  Transform aFromB = invMul(worldFromA, worldFromB);
  detail::GjkRun run = detail::runGjk(a, b, aFromB, cache, -1.0f, observer);
  DistanceOutput out = detail::makeDistanceOutput(a, b, worldFromA, aFromB, run);
  out.iterations = run.iterations;
  out.status = run.status;
  return out;
}

}  // namespace

DistanceOutput detail::computeDistanceOf(const ShapeProxy& a, const Transform& worldFromA,
                                         const ShapeProxy& b, const Transform& worldFromB,
                                         GjkCache* cache) noexcept {
  NoGjkObserver none;
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
