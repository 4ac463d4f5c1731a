#include "quack/collision/toi.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>

#include "quack/collision/epa.hpp"

#include "gjk_internal.hpp"

namespace quack {
namespace {

bool isFiniteSweep(const Sweep& s) noexcept {
  return isFinite(s.localCenter) && isFinite(s.c1) && isFinite(s.c2) && isFinite(s.a1) &&
         isFinite(s.a2);
}

// The rotation by x, |x| <= pi/4, to about 2e-7 (|sin| and |cos| errors): Taylor
// polynomials to x^9 and x^10.
inline Rot smallRotation(float x) noexcept {
  const float x2 = x * x;
  const float sine =
      x * (1.0f + x2 * (-1.0f / 6.0f +
                        x2 * (1.0f / 120.0f + x2 * (-1.0f / 5040.0f + x2 * (1.0f / 362880.0f)))));
  const float cosine =
      1.0f +
      x2 * (-0.5f + x2 * (1.0f / 24.0f + x2 * (-1.0f / 720.0f +
                                               x2 * (1.0f / 40320.0f - x2 * (1.0f / 3628800.0f)))));
  return {cosine, sine};
}

// The rotation by `radians`, to about 2e-7, in a fraction of the instructions of std::cos
// and std::sin. The search evaluates a turning sweep's pose several times per query, so
// the rotation is a large part of its cost. The difference from transformAt's
// rotation moves a point 10 m from the centre by a few micrometres, far below the smallest
// acceptance band (kToiMinTolerance). Reduction to [-pi/4, pi/4] by quarter turns (pi/2
// split in two parts, Cody and Waite), then smallRotation.
inline Rot approximateRotation(float radians) noexcept {
  // Round half away from zero by truncation: std::nearbyint is a library call on x86-64's
  // baseline instruction set. Angles here are far below 2^23 quarter turns.
  const float scaled = radians * 0.636619772f;
  const float quarters =
      static_cast<float>(static_cast<int>(scaled + (scaled >= 0.0f ? 0.5f : -0.5f)));
  const Rot r = smallRotation((radians - quarters * 1.5703125f) - quarters * 4.83826794897e-4f);
  switch (static_cast<int>(quarters) & 3) {
    case 0:
      return r;
    case 1:
      return {-r.s, r.c};
    case 2:
      return {-r.c, -r.s};
    default:
      return {r.s, -r.c};
  }
}

// One evaluation of the distance along the sweeps.
struct Sample {
  float t = 0.0f;
  float distance = 0.0f;
  float approach = 0.0f;  // the advancement bound mu at t, metres per unit time
  // How far each shape's nearest point along the normal can still move towards the other
  // by turning alone, metres (see `reachAlongNormal`).
  float slackA = 0.0f, slackB = 0.0f;
  Vec2 point;
  Vec2 normal;
  // The features GJK ended on when one is an edge: the edge's points (indices into the
  // proxy of A when faceOnA, else of B) facing a point of the other shape. -1: none.
  std::int8_t face0 = -1, face1 = -1;
  bool faceOnA = false;
};

// The first time after s.t at which the separation along s.normal (a fixed world axis) may
// come within `aim`, or infinity. Along a fixed axis n the gap is the support of B along -n
// minus the support of A along n. Translation moves it linearly (`closing`, metres per unit
// time). Turning moves a shape's support at most at |w| r (`spinA`, `spinB`), but never
// beyond the shape's extent r from its centre: the support can lose at most its slack
// (the support's present offset from the centre plus r). So the gap is at least the convex
// piecewise-linear d - closing u - min(spinA u, slackA) - min(spinB u, slackB), u = t - s.t,
// and the first time it reaches `aim` is found piece by piece. The clamp is what makes a
// fast spinner cheap: once its whole extent is counted, the bound is exact in translation.
float reachAlongNormal(const Sample& s, float closing, float spinA, float spinB,
                       float aim) noexcept {
  constexpr float kNever = std::numeric_limits<float>::infinity();
  // Breakpoints where a shape's turning has used its slack.
  float breakA = spinA > 0.0f ? s.slackA / spinA : kNever;
  float breakB = spinB > 0.0f ? s.slackB / spinB : kNever;
  float rateA = spinA, rateB = spinB;
  if (breakB < breakA) {
    std::swap(breakA, breakB);
    std::swap(rateA, rateB);
  }
  const float gap = s.distance - aim;
  float u = 0.0f, value = gap;
  const float pieces[3][2] = {
      {breakA, closing + rateA + rateB}, {breakB, closing + rateB}, {kNever, closing}};
  for (const auto& [until, rate] : pieces) {
    if (rate > 0.0f) {
      const float hit = u + value / rate;
      if (hit <= until) return s.t + hit;
    }
    if (until == kNever) return kNever;
    value -= rate * (until - u);
    u = until;
  }
  return kNever;
}

// Steps of the second-order search along one axis (computeToi's axisReach). Each step is
// proven free; the search stops earlier when the gap along the axis is at the aim. Six
// steps take a spinner's tip from a metre away to the band in the benchmark's sweeps.
constexpr int kToiAxisSteps = 6;

// The axis search runs when turning costs the first-order step more than this many bands.
constexpr float kToiAxisGate = 4.0f;

// The first time in [0, tMax] at which the disc of radius extentT about the centre of mass
// of sweep st may come within `clearance` of shape n, which does not turn (sweep sn,
// rotation qn), as far as n's edge lines tell; 0 when they tell nothing, infinity when the
// disc stays beyond one of them throughout (then `bound` is a lower bound on the distance
// at tMax). In n's body frame the disc's centre moves on a segment, so its gap to a line is
// linear in t. Each line goes through n's support along its normal, so any order of a
// proxy's points gives true bounds (a counter-clockwise polygon's give its faces).
// The edge the disc's centre lies furthest beyond at t = 0 is returned in `face` (its two
// points, n's frame), untouched when the centre lies beyond none.
struct Edge {
  Vec2 from, to;
  bool set = false;
};
float edgeStart(const ShapeProxy& n, const Sweep& sn, Rot qn, const Sweep& st, float extentT,
                float tMax, float clearance, float& bound, Edge& face) noexcept {
  const int count = n.count();
  if (count < 2) return 0.0f;
  const Vec2* v = n.points();
  const Vec2 p0 = invRotate(qn, st.c1 - sn.c1) + sn.localCenter;
  const Vec2 p1 = invRotate(qn, ((1.0f - tMax) * st.c1 + tMax * st.c2) -
                                    ((1.0f - tMax) * sn.c1 + tMax * sn.c2)) +
                  sn.localCenter;
  const float reach = extentT + n.radius() + clearance;
  const float reach2 = reach * reach;
  float start = 0.0f;
  // Each edge e, from the point before to point i, has the outward normal rightPerp(e) on a
  // counter-clockwise polygon; the disc's centre lies dot(rightPerp(e), p - from) / |e|
  // beyond the edge's point along it (q0 at t = 0, times |e|). The support is no nearer
  // than the edge's point, so an edge whose q0 is within reach tells nothing, and most
  // edges stop there, before the support is looked for.
  // The edge the centre lies furthest beyond at t = 0 (largest q0 / |e|) is kept for the
  // search along its normal (`face`).
  Vec2 from = v[count - 1];
  float bestQ = 0.0f, bestEE = 1.0f;
  for (int i = 0; i < count; ++i) {
    const Vec2 e = v[i] - from;
    const float q0 = e.y * (p0.x - from.x) - e.x * (p0.y - from.y);
    const float ee = lengthSquared(e);
    if (q0 > 0.0f && q0 * q0 * bestEE > bestQ * bestQ * ee) {
      face = {from, v[i], true};
      bestQ = q0;
      bestEE = ee;
    }
    from = v[i];
    if (q0 <= 0.0f) continue;
    if (q0 * q0 <= ee * reach2) continue;
    const Vec2 m = rightPerp(e);
    float support = dot(m, v[0]);
    for (int k = 1; k < count; ++k)
      support = maxf(support, dot(m, v[k]));
    const float length = std::sqrt(ee);
    const float g0 = dot(m, p0) - support, g1 = dot(m, p1) - support;  // times |e|
    const float r = reach * length;
    if (!(g0 > r)) continue;
    if (g1 > r) {
      bound = g1 / length - extentT - n.radius();
      return std::numeric_limits<float>::infinity();
    }
    start = maxf(start, tMax * ((g0 - r) / (g0 - g1)));
  }
  return start;
}

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
  const Vec2* points = proxy.points();
  const int count = proxy.count();
  // Two running maxima, so that the chain of dependent comparisons is half as long (every
  // query starts with two of these); the largest is the same whichever way it is taken.
  float even = 0.0f, odd = 0.0f;
  int i = 0;
  for (; i + 1 < count; i += 2) {
    even = maxf(even, distanceSquared(points[i], center));
    odd = maxf(odd, distanceSquared(points[i + 1], center));
  }
  if (i < count) even = maxf(even, distanceSquared(points[i], center));
  return std::sqrt(maxf(even, odd)) + proxy.radius();
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
  const float spinA = absf(sweepA.a2 - sweepA.a1) * extentA;
  const float spinB = absf(sweepB.a2 - sweepB.a1) * extentB;
  const float spin = spinA + spinB;
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

  // Each sweep's rotation at its start, once: a sweep that does not turn keeps it, so the
  // static side of most queries pays no trigonometry per evaluation, and a turning sweep's
  // rotation at t is it turned by the angle turned so far (poseAt). (An angle of +0, the
  // usual static body's, gives the identity, as approximateRotation would; -0 goes through
  // it, for its sign.)
  auto fixedRotation = [](const Sweep& s) {
    const bool plusZero = s.a1 == 0.0f && !std::signbit(s.a1);
    return plusZero ? Rot{} : approximateRotation(s.a1);
  };
  const Rot fixedA = fixedRotation(sweepA), fixedB = fixedRotation(sweepB);

  // Bounds on the first time the shapes may come within the aim, before any distance is
  // evaluated: the bounding circles (circleReach), and for a shape that does not turn its
  // edge lines against the other's circle (edgeStart). Everything before the latest bound is
  // free, so the search starts there: a pair that begins far apart (a bullet metres from a
  // wall) costs no evaluation on the way, and one that never comes close costs none at all.
  // (The edges ran only against sweeps that turn more than a sixteenth of what they move
  // until the face certificate below: without it a bullet paid for the edges and still
  // evaluated twice; with it most of them evaluate never.)
  float start = circleReach(0.0f);
  float bound = length(offset0 + tMax * offsetRate) - extentA - extentB;  // at tMax
  // The still shape's edge the other's centre lies furthest beyond at t = 0 (`face`, in
  // the frame of A when faceOnA, else of B), for the search along its normal below; its
  // normal as a world axis from A towards B (zero: none).
  Edge face;
  bool faceOnA = false;
  Vec2 faceAxis;
  auto stillEdges = [&](const ShapeProxy& still, const Sweep& stillSweep, Rot q, const Sweep& other,
                        float otherExtent, bool onA) {
    if (!(start <= tMax && stillSweep.a1 == stillSweep.a2)) return;
    Edge edge;
    start =
        maxf(start, edgeStart(still, stillSweep, q, other, otherExtent, tMax, aim, bound, edge));
    if (!edge.set) return;
    face = edge;
    faceOnA = onA;
    const Vec2 outward = rotate(q, normalize(rightPerp(edge.to - edge.from)));
    faceAxis = onA ? outward : -outward;
  };
  stillEdges(a, sweepA, fixedA, sweepB, extentB, true);
  stillEdges(b, sweepB, fixedB, sweepA, extentA, false);
  if (!(start <= tMax)) {
    out.status = ToiStatus::separated;
    out.t = tMax;
    out.distance = maxf(target, bound);
    return out;
  }
  // The turn so far within an eighth of a turn (most sweeps' whole turn) is one
  // polynomial and a product, with no reduction and no branch on the quarter: rotations
  // are a large share of the evaluations of a pair that both turn.
  auto poseAt = [](const Sweep& s, Rot fixed, float t) {
    const Vec2 c = (1.0f - t) * s.c1 + t * s.c2;
    Rot q = fixed;
    if (s.a1 != s.a2) {
      const float turned = t * (s.a2 - s.a1);
      q = absf(turned) <= 0.785398f ? mulRot(fixed, smallRotation(turned))
                                    : approximateRotation((1.0f - t) * s.a1 + t * s.a2);
    }
    return Transform{c - rotate(q, s.localCenter), q};
  };
  // GJK runs in A's body frame (the proxies' own), as computeDistance does, but only what
  // the search needs is formed: distance, normal and the witness points (for the slack).
  GjkCache cache;
  detail::NoGjkObserver none;
  const float radii = a.radius() + b.radius();
  auto evaluatePosed = [&](float t, const Transform& worldFromA, const Transform& worldFromB) {
    const Transform aFromB = invMul(worldFromA, worldFromB);
    const detail::GjkRun run = detail::runGjk(a, b, aFromB, &cache, -1.0f, none);
    ++out.iterations;
    Sample sample;
    sample.t = t;
    if (run.status == GjkStatus::overlap) return sample;  // distance 0: within any target
    if (run.count == 2) {
      const detail::GjkVertex& s0 = run.vertices[0];
      const detail::GjkVertex& s1 = run.vertices[1];
      if (s0.indexA() == s1.indexA() && s0.indexB() != s1.indexB()) {
        sample.face0 = static_cast<std::int8_t>(s0.indexB());
        sample.face1 = static_cast<std::int8_t>(s1.indexB());
      } else if (s0.indexB() == s1.indexB() && s0.indexA() != s1.indexA()) {
        sample.face0 = static_cast<std::int8_t>(s0.indexA());
        sample.face1 = static_cast<std::int8_t>(s1.indexA());
        sample.faceOnA = true;
      }
    }
    const float core = length(run.closest);
    const Vec2 n = run.hasDirection ? run.direction : detail::closestDirection(run);
    const WitnessPoints witness = detail::witnessPoints(run, a, b, aFromB);
    // Only the rounding overlaps: distance 0, as computeDistance says.
    sample.distance = maxf(core - radii, 0.0f);
    sample.normal = rotate(worldFromA.q, n);
    sample.approach = dot(relativeVelocity, sample.normal) + spin;
    sample.point = transformPoint(worldFromA, witness.pointA + a.radius() * n);
    // Slack of each support along the normal: its offset from the centre towards the other
    // shape, up to the extent. A witness point on the shape is never beyond the true
    // support, so rounding in it only makes the slack larger (the bound more cautious).
    if (spinA > 0.0f)
      sample.slackA =
          maxf(0.0f, extentA - dot(n, witness.pointA - sweepA.localCenter) - a.radius());
    if (spinB > 0.0f)
      sample.slackB =
          maxf(0.0f, extentB + dot(n, witness.pointB - transformPoint(aFromB, sweepB.localCenter)) -
                         b.radius());
    return sample;
  };
  auto evaluate = [&](float t) {
    return evaluatePosed(t, poseAt(sweepA, fixedA, t), poseAt(sweepB, fixedB, t));
  };
  // Settles the query as a hit at t, a time proven free up to, with no GJK call, when a face
  // shows the distance there in the band. The face is the segment from `from` to `to`
  // (points of A when onA, else of B, in that shape's frame) and n a world axis from A
  // towards B. The distance is at least the gap along n (a separating axis: the least of B
  // along it minus the most of A, every point counted) and at most the distance from the
  // other shape's point furthest along the axis towards the face (its support) to the
  // face's segment, which lies in its shape. When both lie in the band, so does the
  // distance. A support that lies off the face, or a face that is not at its shape's
  // support (points in another order), leaves the two apart: false. (Box2D's time of
  // impact also works from a face's separation, with a root finder on it; here it is a
  // bound on both sides, so nothing is assumed about which features meet.)
  auto settleOnFace = [&](float t, const Transform& xfA, const Transform& xfB, bool onA, Vec2 from,
                          Vec2 to, Vec2 n) {
    const Vec2 axisInA = invRotate(xfA.q, n), axisInB = invRotate(xfB.q, n);
    int mostA = 0, leastB = 0;
    float mostAlong = dot(axisInA, a.points()[0]), leastAlong = dot(axisInB, b.points()[0]);
    for (int i = 1; i < a.count(); ++i) {
      const float along = dot(axisInA, a.points()[i]);
      if (along > mostAlong) {
        mostAlong = along;
        mostA = i;
      }
    }
    for (int i = 1; i < b.count(); ++i) {
      const float along = dot(axisInB, b.points()[i]);
      if (along < leastAlong) {
        leastAlong = along;
        leastB = i;
      }
    }
    const float lower = leastAlong - mostAlong + dot(n, xfB.p - xfA.p) - radii;
    // Touching (0) is GJK's to tell from overlapping.
    if (!(lower > 0.0f && lower >= target && lower < target + tolerance)) return false;
    // The support in the face's shape's frame, through the relative pose (subtracting the
    // positions first, so that far from the origin their rounding does not enter).
    const Transform& faceXf = onA ? xfA : xfB;
    const Vec2 tip = onA ? transformPoint(invMul(xfA, xfB), b.points()[leastB])
                         : transformPoint(invMul(xfB, xfA), a.points()[mostA]);
    const Vec2 e = to - from;
    const float along = dot(tip - from, e) / lengthSquared(e);
    // The support must lie square over the segment (its foot within it), and the face at
    // its shape's support along n (the two numbers agree to a sixteenth of the band): then
    // the nearest points are the support and its foot, and n is the true normal. A foot
    // past an end (a corner comes first, with a normal of its own, up to 37 degrees off the
    // face's within the band) or a face short of the support is left to GJK.
    if (!(along >= 0.0f && along <= 1.0f)) return false;
    const Vec2 onFace = from + along * e;
    const float upper = length(tip - onFace) - radii;
    if (!(upper < target + tolerance && upper - lower <= 0.0625f * tolerance)) return false;
    out.status = ToiStatus::hit;
    out.t = t;
    out.distance = upper;
    out.normal = n;
    // On A's surface: the face's point (A holds the face) or the support (B does).
    out.point = transformPoint(faceXf, onA ? onFace : tip) + a.radius() * n;
    return true;
  };
  // The second-order search along a sample's normal n, a fixed world axis. The gap along n,
  //   G(t) = dot(n, cB - cA) - radii + min_i dot(n, RB qB_i) + min_j dot(-n, RA qA_j)
  // (q: core points about the centre of mass), is at most the distance, and each term of a
  // turning shape is a sinusoid in t whose second derivative is at most w^2 |q|. So from a
  // time u, point i's term is at least f_i + g_i s - w^2 |q_i| s^2 / 2 after s more (f, g its
  // value and rate at u: Taylor), and the other shape's support drops at most at its |w| r.
  // The first s at which one of these quadratics (plus the centres' linear motion) reaches
  // the aim is free: step there, re-expand with the exact rotation, repeat. Near the root
  // the quadratic term vanishes and the steps converge like Newton's; a spinner's tip that
  // approaches end-on (which the first-order bound charges |w| r throughout) lands on its
  // time of impact along n in a few steps, and GJK there confirms it or gives a better axis.
  // The shape with the larger spin gets the per-point model.
  const bool modelB = spinB >= spinA;
  const ShapeProxy& modelProxy = modelB ? b : a;
  const Sweep& modelSweep = modelB ? sweepB : sweepA;
  const ShapeProxy& otherProxy = modelB ? a : b;
  const Sweep& otherSweep = modelB ? sweepA : sweepB;
  const float modelOmega = modelSweep.a2 - modelSweep.a1;
  const float otherSpin = modelB ? spinA : spinB;
  float halfCurve[kMaxPolygonVertices];  // w^2 |q| / 2 per core point, set on first use
  bool haveCurve = false;
  auto axisReach = [&](const Sample& s, float tEnd) {
    constexpr float kNever = std::numeric_limits<float>::infinity();
    if (!haveCurve) {
      for (int i = 0; i < modelProxy.count(); ++i)
        halfCurve[i] = 0.5f * modelOmega * modelOmega *
                       length(modelProxy.points()[i] - modelSweep.localCenter);
      haveCurve = true;
    }
    // B's offsets count along n, A's along -n.
    const Vec2 modelAxis = modelB ? s.normal : -s.normal;
    const float closing = -dot(relativeVelocity, s.normal) - otherSpin;
    float u = s.t;
    for (int k = 0; k < kToiAxisSteps; ++k) {
      const Transform modelPose = poseAt(modelSweep, modelB ? fixedB : fixedA, u);
      const Transform otherPose = poseAt(otherSweep, modelB ? fixedA : fixedB, u);
      const Vec2 cA = (1.0f - u) * sweepA.c1 + u * sweepA.c2;
      const Vec2 cB = (1.0f - u) * sweepB.c1 + u * sweepB.c2;
      const Vec2 m = invRotate(modelPose.q, modelAxis);
      const Vec2 o = invRotate(otherPose.q, -modelAxis);
      float otherLeast = dot(o, otherProxy.points()[0]);
      for (int j = 1; j < otherProxy.count(); ++j)
        otherLeast = minf(otherLeast, dot(o, otherProxy.points()[j]));
      otherLeast -= dot(o, otherSweep.localCenter);
      const float base = dot(s.normal, cB - cA) - radii - aim + otherLeast;
      const Vec2 mc = modelSweep.localCenter;
      float gap = kNever, step = kNever;
      for (int i = 0; i < modelProxy.count(); ++i)
        gap = minf(gap, dot(m, modelProxy.points()[i]));
      gap += base - dot(m, mc);
      if (gap <= 0.5f * tolerance) break;  // at the aim along n: GJK decides from here
      for (int i = 0; i < modelProxy.count(); ++i) {
        const Vec2 q = modelProxy.points()[i] - mc;
        const float p0 = base + dot(m, q);
        const float slope = closing + modelOmega * dot(m, leftPerp(q));
        const float c = halfCurve[i];
        // Before `step` the quadratic stays above p0 - (max(0, -slope) + c step) x: a point
        // that far above the aim cannot cross first (skips the square root).
        if (p0 >= (maxf(0.0f, -slope) + c * step) * step) continue;
        // First root of p0 + slope x - c x^2 = 0 for x >= 0 (p0 > 0), in the forms without
        // cancellation.
        float x = kNever;
        if (c > 0.0f) {
          const float root = std::sqrt(slope * slope + 4.0f * c * p0);
          x = slope <= 0.0f ? 2.0f * p0 / (root - slope) : (slope + root) / (2.0f * c);
        } else if (slope < 0.0f) {
          x = -p0 / slope;
        }
        step = minf(step, x);
      }
      if (!(u + step < tEnd)) return tEnd;
      u += step;
    }
    return u;
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

  // Along the facing edge's axis, the second-order search moves the start on, with no GJK
  // call: the turning shape's tip is what comes first, and the search follows it. Landing
  // on tMax means the gap along the axis never reaches the aim: separated.
  const bool alongFace = lengthSquared(faceAxis) > 0.0f && start < tMax;
  if (alongFace) {
    Sample axis;
    axis.t = start;
    axis.normal = faceAxis;
    const float reached = axisReach(axis, tMax);
    if (!(reached < tMax)) {
      out.status = ToiStatus::separated;
      out.t = tMax;
      out.distance = target;  // a lower bound: the gap along the axis stays above the aim
      return out;
    }
    start = maxf(start, reached);
  }
  // Where the search along the face lands the still shape's face may settle the query;
  // otherwise the first evaluation is there, at the same poses. A pair that starts later
  // than 0 is apart at 0 too: it cannot be overlapped.
  const Transform startA = poseAt(sweepA, fixedA, start), startB = poseAt(sweepB, fixedB, start);
  if (alongFace && settleOnFace(start, startA, startB, faceOnA, face.from, face.to, faceAxis))
    return out;
  Sample lo = evaluatePosed(start, startA, startB);
  if (start == 0.0f && lo.distance <= 0.0f) {
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
  // Raw storage: most queries never bisect, and constructing kToiStackDepth samples (their
  // members zero by default) would be a large share of a typical query.
  union Stack {
    Stack() noexcept {}
    Sample items[kToiStackDepth];
  } pending;
  Sample* const stack = pending.items;
  int top = 0;
  int advances = 0;
  for (;;) {
    if (lo.distance < target + tolerance) return finish(ToiStatus::hit, lo);
    // Nothing comes within the target before `reach` (the advancement bound).
    const float end = top > 0 ? stack[top - 1].t : tMax;
    float reach =
        maxf(reachAlongNormal(lo, lo.approach - spin, spinA, spinB, aim), circleReach(lo.t));
    // The search along the axis pays only where turning is what holds the first-order
    // step back, by more than a few bands of gap (below that one more GJK call is cheaper),
    // and only when the other shape does not turn (charged at its first-order |w| r, two
    // shapes turning alike gain too little: on bench/ccd's random set it costs more than
    // it saves).
    if (spin > 0.0f && reach < end && otherSpin == 0.0f &&
        lo.distance - aim - (lo.approach - spin) * (reach - lo.t) > kToiAxisGate * tolerance)
      reach = maxf(reach, axisReach(lo, end));
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
      const Transform xfA = poseAt(sweepA, fixedA, reach), xfB = poseAt(sweepB, fixedB, reach);
      // The edge GJK ended on at lo may settle it at reach, turned with its shape, along
      // its normal there (from A towards B: the other shape's point lies on that side).
      if (lo.face0 >= 0 &&
          lo.distance - (lo.approach - spin) * (reach - lo.t) < target + tolerance) {
        const Transform& faceXf = lo.faceOnA ? xfA : xfB;
        const ShapeProxy& faceProxy = lo.faceOnA ? a : b;
        const Vec2 from = faceProxy.points()[lo.face0], to = faceProxy.points()[lo.face1];
        Vec2 n = rotate(faceXf.q, normalize(rightPerp(to - from)));
        if (dot(n, lo.normal) < 0.0f) n = -n;
        if (settleOnFace(reach, xfA, xfB, lo.faceOnA, from, to, n)) return out;
      }
      const Sample next = evaluatePosed(reach, xfA, xfB);
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
    std::construct_at(&stack[top++], mid);
  }
}

}  // namespace quack
