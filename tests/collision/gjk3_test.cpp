// GJK in 3D: hand-worked cases, swapping A and B, rigid motions of both, warm starts, and
// random pairs of every kind against the brute-force feature-pair distance (oracle3.hpp),
// with a separating-plane certificate for every "apart" answer and the Minkowski
// difference's hull (qhull) for every "overlap" answer. Tolerance: distances agree to
// kRel3 of the pair's size (extents plus offset), about 16 float ulps.

#include <gtest/gtest.h>

#include "oracle3.hpp"
#include "quack/collision/gjk3.hpp"

namespace quack {
namespace {

using namespace testing3;

constexpr float kTol = 1e-5f;
constexpr double kRel3 = 2e-6;

void expectNear(Vec3 a, Vec3 b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

Transform3 pose(Vec3 p, Vec3 axis = {0, 0, 1}, float angle = 0) {
  return {p, Quat::fromAxisAngle(normalize(axis), angle)};
}

TEST(Gjk3, SpheresApart) {
  Sphere s = makeSphere({}, 1).value();
  DistanceOutput3 d = computeDistance(makeProxy(s), {}, makeProxy(s), pose({0, 5, 0}));
  EXPECT_NEAR(d.distance, 3, kTol);
  EXPECT_NEAR(d.coreDistance, 5, kTol);
  expectNear(d.normal, {0, 1, 0}, kTol);
  expectNear(d.pointA, {0, 1, 0}, kTol);
  expectNear(d.pointB, {0, 4, 0}, kTol);
}

TEST(Gjk3, BoxesFaceToFace) {
  Hull3 box = makeBox3({1, 1, 1}).value();
  DistanceOutput3 d =
      computeDistance(makeProxy(box), {}, makeProxy(box), pose({3, 0.5f, -0.25f}, {1, 0, 0}, 0.3f));
  EXPECT_NEAR(d.distance, 1, kTol);  // a turn about x keeps B's x extent
  expectNear(d.normal, {1, 0, 0}, kTol);
  EXPECT_NEAR(d.pointA.x, 1, kTol);
  EXPECT_NE(d.status, GjkStatus::maxIterations);
}

TEST(Gjk3, BoxCornerToSphere) {
  Hull3 box = makeBox3({1, 1, 1}).value();
  Sphere s = makeSphere({}, 0.5f).value();
  DistanceOutput3 d = computeDistance(makeProxy(box), {}, makeProxy(s), pose({3, 3, 3}));
  EXPECT_NEAR(d.distance, std::sqrt(12.0f) - 0.5f, kTol);
  expectNear(d.pointA, {1, 1, 1}, kTol);
  float c = 1 / std::sqrt(3.0f);
  expectNear(d.normal, {c, c, c}, kTol);
}

TEST(Gjk3, SkewCapsules) {
  Capsule3 a = makeCapsule3({-2, 0, 0}, {2, 0, 0}, 0.25f).value();
  Capsule3 b = makeCapsule3({0, -2, 0}, {0, 2, 0}, 0.5f).value();
  DistanceOutput3 d = computeDistance(makeProxy(a), {}, makeProxy(b), pose({0.5f, -0.3f, 2}));
  EXPECT_NEAR(d.distance, 2 - 0.75f, kTol);
  expectNear(d.normal, {0, 0, 1}, kTol);
  expectNear(d.pointA, {0.5f, 0, 0.25f}, kTol);
  expectNear(d.pointB, {0.5f, 0, 1.5f}, kTol);
}

TEST(Gjk3, TriangleAboveBoxAndTouching) {
  Hull3 box = makeBox3({1, 1, 1}).value();
  Triangle3 t = makeTriangle3({-3, 2, -3}, {3, 2, -3}, {0, 2, 3}).value();
  DistanceOutput3 d = computeDistance(makeProxy(box), {}, makeProxy(t), {});
  EXPECT_NEAR(d.distance, 1, kTol);
  expectNear(d.normal, {0, 1, 0}, kTol);
  // Touching: the faces meet exactly.
  Hull3 other = makeBox3({1, 1, 1}).value();
  DistanceOutput3 touch = computeDistance(makeProxy(box), {}, makeProxy(other), pose({2, 0.3f, 0}));
  EXPECT_NEAR(touch.distance, 0, kTol);
  EXPECT_TRUE(testOverlap(makeProxy(box), {}, makeProxy(other), pose({2, 0.3f, 0})));
  EXPECT_FALSE(testOverlap(makeProxy(box), {}, makeProxy(other), pose({2.01f, 0.3f, 0})));
}

TEST(Gjk3, DeepOverlapReportsOverlap) {
  Hull3 box = makeBox3({1, 1, 1}).value();
  DistanceOutput3 d = computeDistance(makeProxy(box), {}, makeProxy(box), pose({0.5f, 0.2f, 0.1f}));
  EXPECT_EQ(d.status, GjkStatus::overlap);
  EXPECT_EQ(d.distance, 0.0f);
  EXPECT_EQ(d.coreDistance, 0.0f);
}

const Kind3 kKinds[] = {Kind3::sphere, Kind3::capsule, Kind3::triangle, Kind3::box, Kind3::hull};

struct Pair3 {
  Shape3 a, b;
  Transform3 ta, tb;
};

// A random pair: shapes of size ~1, B placed at a random offset of up to `reach` from A,
// both around `origin`.
Pair3 randomPair(std::mt19937& rng, int index, Vec3 origin, float reach) {
  Pair3 p;
  p.a = randomShape3(rng, kKinds[index % 5], 1.0f);
  p.b = randomShape3(rng, kKinds[(index / 5) % 5], 1.0f);
  p.ta = {origin + randomVec(rng, 1), randomQuat(rng)};
  p.tb = {p.ta.p + randomVec(rng, reach), randomQuat(rng)};
  return p;
}

TEST(Gjk3, SwapFlipsTheNormal) {
  std::mt19937 rng(101);
  for (int i = 0; i < 2000; ++i) {
    Pair3 p = randomPair(rng, i, {}, 3);
    DistanceOutput3 ab = computeDistance(p.a.proxy(), p.ta, p.b.proxy(), p.tb);
    DistanceOutput3 ba = computeDistance(p.b.proxy(), p.tb, p.a.proxy(), p.ta);
    double tol = kRel3 * (p.a.extent() + p.b.extent() + 3);
    EXPECT_NEAR(ab.coreDistance, ba.coreDistance, 2 * tol) << i;
    if (ab.coreDistance > 1e-3f && ba.coreDistance > 1e-3f) {
      expectNear(ab.normal, -ba.normal, 1e-3f);
    }
  }
}

TEST(Gjk3, RigidMotionOfBothKeepsTheDistance) {
  std::mt19937 rng(202);
  for (int i = 0; i < 2000; ++i) {
    Pair3 p = randomPair(rng, i, {}, 3);
    DistanceOutput3 d0 = computeDistance(p.a.proxy(), p.ta, p.b.proxy(), p.tb);
    Transform3 m{randomVec(rng, 1e4f), randomQuat(rng)};
    Transform3 ta = m * p.ta, tb = m * p.tb;
    ta.q = normalize(ta.q);
    tb.q = normalize(tb.q);
    DistanceOutput3 d1 = computeDistance(p.a.proxy(), ta, p.b.proxy(), tb);
    // Moving the pair 1e4 m rounds its relative pose by ~1e-7 of 1e4 (the positions'
    // float ulp is ~1e-3 there): the distances agree to that.
    EXPECT_NEAR(d0.coreDistance, d1.coreDistance, 2e-3) << i;
    if (d0.coreDistance > 0.5f) expectNear(transformVector(m, d0.normal), d1.normal, 5e-3f);
  }
}

TEST(Gjk3, WarmStartGivesTheSameAnswer) {
  std::mt19937 rng(303);
  int fewer = 0, total = 0;
  for (int i = 0; i < 1000; ++i) {
    Pair3 p = randomPair(rng, i, {}, 4);
    GjkCache3 cache;
    DistanceOutput3 cold = computeDistance(p.a.proxy(), p.ta, p.b.proxy(), p.tb, &cache);
    // A small motion, as between two steps.
    Transform3 tb{p.tb.p + Vec3{1e-3f, 0, 0}, p.tb.q};
    DistanceOutput3 ref = computeDistance(p.a.proxy(), p.ta, p.b.proxy(), tb);
    DistanceOutput3 warm = computeDistance(p.a.proxy(), p.ta, p.b.proxy(), tb, &cache);
    double tol = kRel3 * (p.a.extent() + p.b.extent() + 4);
    EXPECT_NEAR(warm.coreDistance, ref.coreDistance, 2 * tol) << i;
    if (cold.status != GjkStatus::overlap) {
      ++total;
      if (warm.iterations <= ref.iterations) ++fewer;
    }
  }
  EXPECT_GT(fewer, total * 9 / 10);
}

// Checks one GJK answer against the oracles; returns false on a mismatch.
int g_apart = 0, g_overlap = 0, g_overlapUnverified = 0;
bool checkPair(const Pair3& p, int index) {
  DistanceOutput3 d = computeDistance(p.a.proxy(), p.ta, p.b.proxy(), p.tb);
  Features fa = p.a.features(p.ta), fb = p.b.features(p.tb);
  double size = p.a.extent() + p.b.extent() + lenD(toD(p.tb.p) - toD(p.ta.p));
  double tol = kRel3 * size;
  bool ok = true;
  if (d.status != GjkStatus::overlap) {
    ++g_apart;
    // Certificate: along the reported normal, B's cores lie at least coreDistance beyond A's.
    D3 n = toD(d.normal);
    double maxA = -1e300, minB = 1e300;
    for (D3 v : fa.v)
      maxA = std::max(maxA, dotD(n, v));
    for (D3 v : fb.v)
      minB = std::min(minB, dotD(n, v));
    double brute = bruteCoreDistance(fa, fb);
    int why = 0;
    if (minB - maxA < d.coreDistance - tol) why = 1;  // not separated that far along n
    if (std::fabs(brute - d.coreDistance) > tol) why = 2;
    // Rounded distance and points.
    double expected = std::max(0.0, brute - fa.radius - fb.radius);
    if (std::fabs(d.distance - expected) > tol) why = 3;
    // The points are world coordinates: far from the origin they carry its float rounding.
    double world = 4 * 1.2e-7 * lenD(toD(p.ta.p));
    if (d.distance > 0 &&
        std::fabs(lenD(toD(d.pointB) - toD(d.pointA)) - d.distance) > 2 * tol + world)
      why = 4;
    ok = why == 0;
    EXPECT_TRUE(ok) << "pair " << index << " check " << why << " status " << toString(d.status)
                    << " it " << d.iterations << " gjk " << d.coreDistance << " brute " << brute
                    << " gap along n " << (minB - maxA) << " tol " << tol << "\nA " << describe(p.a)
                    << "\nB " << describe(p.b);
  } else {
    ++g_overlap;
    double brute = bruteCoreDistance(fa, fb);
    if (brute <= tol) return true;  // features meet: overlapping or touching
#if QUACK_HAVE_QHULL
    MinkowskiAnswer m = minkowskiDepth(fa, fb);
    if (m.ok) {
      ok = m.inside || m.depth > -tol;
      EXPECT_TRUE(ok) << "pair " << index << " gjk says overlap, Minkowski depth " << m.depth
                      << "\nA " << describe(p.a) << "\nB " << describe(p.b);
    } else {
      ++g_overlapUnverified;
    }
#else
    ++g_overlapUnverified;
#endif
  }
  return ok;
}

// The support search takes four points at a time in SIMD lanes: the same index as a plain
// scan with a strict `>` (the first maximum), for every count up to the largest hull, on
// random points and on lattice points with axis directions, where many points tie.
TEST(Gjk3, SupportSearchAgreesWithAPlainScan) {
  std::mt19937 rng(77);
  std::uniform_int_distribution<int> lattice(-2, 2);
  auto scan = [](const Vec3* p, int count, Vec3 d) {
    int best = 0;
    for (int i = 1; i < count; ++i) {
      if (dot(p[i], d) > dot(p[best], d)) best = i;
    }
    return best;
  };
  int ties = 0;
  for (int count = 1; count <= kMaxHullVertices3; ++count) {
    for (int trial = 0; trial < 200; ++trial) {
      Vec3 points[kMaxHullVertices3];
      const bool onLattice = trial % 2 == 1;
      for (int i = 0; i < count; ++i) {
        points[i] = onLattice
                        ? Vec3{static_cast<float>(lattice(rng)), static_cast<float>(lattice(rng)),
                               static_cast<float>(lattice(rng))}
                        : randomVec(rng, 3.0f);
      }
      Vec3 d = randomVec(rng, 1.0f);
      if (onLattice)
        d = Vec3{static_cast<float>(lattice(rng)), static_cast<float>(lattice(rng)),
                 static_cast<float>(lattice(rng))};
      const int expected = scan(points, count, d);
      const ShapeProxy3 proxy = ShapeProxy3::fromPoints(points, count, 0.0f, Vec3{});
      ASSERT_EQ(findSupport(proxy, d), expected) << "count " << count << " trial " << trial;
      for (int i = expected + 1; i < count; ++i) {
        if (dot(points[i], d) == dot(points[expected], d)) {
          ++ties;
          break;
        }
      }
    }
  }
  EXPECT_GT(ties, 1000);  // the lattice cases do test the tie-break
}

TEST(Gjk3, RandomPairsAgreeWithBruteForce) {
  std::mt19937 rng(404);
  int mismatches = 0;
  const int n = 20000 * testScale();
  for (int i = 0; i < n; ++i) {
    // Near the origin and 1e4 m from it; reach chosen so that about half overlap.
    Vec3 origin = (i % 4 == 3) ? Vec3{1e4f, -1e4f, 1e4f} : Vec3{};
    Pair3 p = randomPair(rng, i, origin, (i % 2) ? 0.8f : 2.5f);
    if (!checkPair(p, i)) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(g_apart, n / 5);
  EXPECT_GT(g_overlap, n / 10);
  EXPECT_LT(g_overlapUnverified, n / 100 + 1);
}

TEST(Gjk3, NearlyParallelFacesAndTouching) {
  // Two boxes face to face with a small tilt and a gap from 0 to 1e-3: the hard case for
  // GJK's termination (many nearly equal support points).
  std::mt19937 rng(505);
  int mismatches = 0;
  for (int i = 0; i < 4000; ++i) {
    Pair3 p;
    p.a.kind = p.b.kind = Kind3::box;
    p.a.hull = makeBox3({1, uni(rng, 0.2f, 1), uni(rng, 0.2f, 1)}).value();
    p.b.hull = makeBox3({1, uni(rng, 0.2f, 1), uni(rng, 0.2f, 1)}).value();
    float tilt = (i % 3 == 0) ? 0.0f : uni(rng, -1e-3f, 1e-3f);
    float gap = (i % 5 == 0) ? 0.0f : uni(rng, 0, 1e-3f);
    Vec3 origin = (i % 2) ? Vec3{1e4f, 1e4f, -1e4f} : Vec3{};
    Quat qa = randomQuat(rng);
    p.ta = {origin, qa};
    // B's face at x = -1 meets A's at x = +1 plus the gap (corners of the tilted face
    // reach a bit further: the oracle measures the true distance).
    Transform3 aFromB{
        {2 + gap + std::fabs(std::sin(tilt)) * 1.0f, uni(rng, -0.5f, 0.5f), uni(rng, -0.5f, 0.5f)},
        Quat::fromAxisAngle(normalize(Vec3{0, 1, 1}), tilt)};
    p.tb = p.ta * aFromB;
    p.tb.q = normalize(p.tb.q);
    if (!checkPair(p, i)) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0);
}

}  // namespace
}  // namespace quack
