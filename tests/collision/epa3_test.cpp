// EPA in 3D: hand-worked depths, swapping A and B, and random overlapping pairs of every
// kind against the Minkowski difference's hull (qhull: the least facet distance is the
// core depth), with a certificate for every normal: along it, the shapes overlap by exactly
// the reported depth. Includes touching, nearly parallel faces, slivers and poses 1e4 m from
// the origin. Tolerance: kDepthRel of the pair's size.

#include <gtest/gtest.h>

#include <map>

#include "oracle3.hpp"
#include "quack/collision/epa3.hpp"
#include "quack/collision/manifold3.hpp"
#include "quack/collision/sat3.hpp"

namespace quack {
namespace {

using namespace testing3;

constexpr float kTol = 1e-5f;
constexpr double kDepthRel = 4e-6;

void expectNear(Vec3 a, Vec3 b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(Epa3, BoxesOverlapAlongX) {
  Hull3 box = makeBox3({1, 1, 1}).value();
  PenetrationOutput3 p =
      computePenetration(makeProxy(box), {}, makeProxy(box), {{1.5f, 0.2f, -0.1f}, {}});
  ASSERT_TRUE(p.overlap);
  EXPECT_NEAR(p.depth, 0.5f, kTol);
  expectNear(p.normal, {1, 0, 0}, kTol);
  EXPECT_NEAR(p.pointA.x, 1.0f, kTol);
  EXPECT_NEAR(p.pointB.x, 0.5f, kTol);
  expectNear(p.pointB, p.pointA - p.depth * p.normal, kTol);
  EXPECT_TRUE(p.status == Epa3Status::converged || p.status == Epa3Status::repeatedSupport)
      << toString(p.status);
}

TEST(Epa3, SphereCentreInsideBox) {
  Hull3 box = makeBox3({2, 1, 3}).value();
  Sphere s = makeSphere({}, 0.25f).value();
  PenetrationOutput3 p =
      computePenetration(makeProxy(box), {}, makeProxy(s), {{0.3f, 0.6f, 0}, {}});
  ASSERT_TRUE(p.overlap);
  EXPECT_NEAR(p.depth, 0.4f + 0.25f, kTol);
  expectNear(p.normal, {0, 1, 0}, kTol);
}

TEST(Epa3, SpheresOnlyRadiiOverlap) {
  Sphere s = makeSphere({}, 1).value();
  PenetrationOutput3 p = computePenetration(makeProxy(s), {}, makeProxy(s), {{0, 0, 1.5f}, {}});
  EXPECT_EQ(p.status, Epa3Status::coresSeparated);
  EXPECT_NEAR(p.depth, 0.5f, kTol);
  expectNear(p.normal, {0, 0, 1}, kTol);
}

TEST(Epa3, SeparatedGivesGjk) {
  Hull3 box = makeBox3({1, 1, 1}).value();
  PenetrationOutput3 p = computePenetration(makeProxy(box), {}, makeProxy(box), {{0, 3, 0}, {}});
  EXPECT_FALSE(p.overlap);
  EXPECT_EQ(p.status, Epa3Status::separated);
  EXPECT_EQ(p.depth, 0.0f);
  expectNear(p.normal, {0, 1, 0}, kTol);
}

TEST(Epa3, CrossingCapsuleCoresAreDegenerate) {
  // Two capsules whose segments cross: B - A's core is a flat parallelogram.
  Capsule3 a = makeCapsule3({-1, 0, 0}, {1, 0, 0}, 0.2f).value();
  Capsule3 b = makeCapsule3({0, -1, 0}, {0, 1, 0}, 0.3f).value();
  PenetrationOutput3 p = computePenetration(makeProxy(a), {}, makeProxy(b), {});
  EXPECT_TRUE(p.overlap);
  EXPECT_EQ(p.status, Epa3Status::degenerate);
  EXPECT_NEAR(p.depth, 0.5f, kTol);
  EXPECT_NEAR(std::fabs(p.normal.z), 1.0f, kTol);
}

struct Pair3 {
  Shape3 a, b;
  Transform3 ta, tb;
};

const Kind3 kKinds[] = {Kind3::sphere, Kind3::capsule, Kind3::triangle, Kind3::box, Kind3::hull};

std::map<Epa3Status, int> g_statuses;
int g_oracleChecked = 0;

// Checks one answer; true when it agrees with the oracles.
bool checkPair(const Pair3& p, int index) {
  PenetrationOutput3 r = computePenetration(p.a.proxy(), p.ta, p.b.proxy(), p.tb);
  ++g_statuses[r.status];
  Features fa = p.a.features(p.ta), fb = p.b.features(p.tb);
  double size = p.a.extent() + p.b.extent() + lenD(toD(p.tb.p) - toD(p.ta.p));
  double tol = kDepthRel * size;
  if (!r.overlap) return true;  // the distance side is gjk3_test's
  // Certificate: along the normal, A reaches past B's near side by exactly the depth.
  D3 n = toD(r.normal);
  double maxA = -1e300, minB = 1e300;
  for (D3 v : fa.v)
    maxA = std::max(maxA, dotD(n, v));
  for (D3 v : fb.v)
    minB = std::min(minB, dotD(n, v));
  double along = maxA + fa.radius - (minB - fb.radius);
  bool ok = std::fabs(along - r.depth) <= tol;
  double oracle = -1;
  if (r.status == Epa3Status::coresSeparated) {
    oracle = fa.radius + fb.radius - bruteCoreDistance(fa, fb);
  } else {
#if QUACK_HAVE_QHULL
    MinkowskiAnswer m = minkowskiDepth(fa, fb);
    if (m.ok) oracle = std::max(m.depth, 0.0) + fa.radius + fb.radius;
#endif
  }
  if (oracle >= 0) {
    ++g_oracleChecked;
    if (std::fabs(oracle - r.depth) > tol) ok = false;
  }
  EXPECT_TRUE(ok) << "pair " << index << " status " << toString(r.status) << " depth " << r.depth
                  << " oracle " << oracle << " along normal " << along << " tol " << tol << "\nA "
                  << describe(p.a) << "\nB " << describe(p.b);
  return ok;
}

TEST(Epa3, RandomOverlapsAgreeWithTheMinkowskiDifference) {
#if !QUACK_HAVE_QHULL
  GTEST_SKIP() << "qhull is missing (install Debian libqhull-dev): the depth oracle did not run";
#else
  std::mt19937 rng(606);
  int mismatches = 0;
  const int n = 20000 * testScale();
  for (int i = 0; i < n; ++i) {
    Pair3 p;
    p.a = randomShape3(rng, kKinds[i % 5], 1.0f);
    p.b = randomShape3(rng, kKinds[(i / 5) % 5], 1.0f);
    Vec3 origin = (i % 4 == 3) ? Vec3{-1e4f, 1e4f, 1e4f} : Vec3{};
    p.ta = {origin + randomVec(rng, 1), randomQuat(rng)};
    p.tb = {p.ta.p + randomVec(rng, 0.7f), randomQuat(rng)};
    if (!checkPair(p, i)) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(g_oracleChecked, n / 2);
  for (auto [status, count] : g_statuses)
    std::printf("  %s: %d\n", toString(status), count);
  EXPECT_EQ(g_statuses[Epa3Status::bufferFull], 0);
#endif
}

TEST(Epa3, NearlyParallelFacesAndTouching) {
#if !QUACK_HAVE_QHULL
  GTEST_SKIP() << "qhull is missing (install Debian libqhull-dev): the depth oracle did not run";
#else
  std::mt19937 rng(707);
  int mismatches = 0;
  for (int i = 0; i < 4000; ++i) {
    Pair3 p;
    p.a.kind = p.b.kind = Kind3::box;
    p.a.hull = makeBox3({1, uni(rng, 0.2f, 1), uni(rng, 0.2f, 1)}).value();
    p.b.hull = makeBox3({1, uni(rng, 0.2f, 1), uni(rng, 0.2f, 1)}).value();
    float tilt = (i % 3 == 0) ? 0.0f : uni(rng, -1e-3f, 1e-3f);
    float overlap = (i % 5 == 0) ? 0.0f : uni(rng, 0, 1e-2f);
    Vec3 origin = (i % 2) ? Vec3{1e4f, 1e4f, -1e4f} : Vec3{};
    p.ta = {origin, randomQuat(rng)};
    Transform3 aFromB{{2 - overlap, uni(rng, -0.5f, 0.5f), uni(rng, -0.5f, 0.5f)},
                      Quat::fromAxisAngle(normalize(Vec3{0, 1, 1}), tilt)};
    p.tb = p.ta * aFromB;
    p.tb.q = normalize(p.tb.q);
    if (!checkPair(p, i)) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0);
#endif
}

TEST(Epa3, SixtyFourVertexHullsAgreeWithTheOracles) {
  // The largest hulls (kMaxHullVertices3 vertices: a Fibonacci sphere scaled to an
  // ellipsoid) through GJK, EPA, SAT and the manifold, against the same oracles.
  std::vector<Vec3> pts;
  const int n = kMaxHullVertices3;
  for (int i = 0; i < n; ++i) {
    float z = 1.0f - (2.0f * float(i) + 1.0f) / float(n);
    float r = std::sqrt(1.0f - z * z), phi = 2.39996323f * float(i);
    pts.push_back({1.0f * r * std::cos(phi), 0.7f * r * std::sin(phi), 0.5f * z});
  }
  Result<Hull3Build> built = computeHull3(pts);
  ASSERT_TRUE(built.ok()) << built.error().message;
  ASSERT_EQ(built->hull.vertexCount, n);
  Shape3 s;
  s.kind = Kind3::hull;
  s.hull = built->hull;
  std::mt19937 rng(4242);
  int mismatches = 0, apart = 0, deep = 0;
  for (int i = 0; i < 300; ++i) {
    Transform3 ta{randomVec(rng, 1), randomQuat(rng)};
    Transform3 tb{ta.p + randomVec(rng, 1.2f), randomQuat(rng)};
    Features fa = s.features(ta), fb = s.features(tb);
    double tol = 4e-6 * (2 * s.extent() + 2);
    DistanceOutput3 d = computeDistance(s.proxy(), ta, s.proxy(), tb);
    PenetrationOutput3 p = computePenetration(s.proxy(), ta, s.proxy(), tb);
    SatOutput3 sat = computeSat(s.hull, ta, s.hull, tb);
    Manifold3 m = collideHulls(s.hull, ta, s.hull, tb);
    bool ok = p.status != Epa3Status::bufferFull && p.status != Epa3Status::gaveUp;
    if (d.status != GjkStatus::overlap) {
      ++apart;
      ok = ok && std::fabs(bruteCoreDistance(fa, fb) - d.coreDistance) <= tol;
      ok = ok && sat.separation <= d.distance + tol;
    } else {
#if QUACK_HAVE_QHULL
      MinkowskiAnswer mk = minkowskiDepth(fa, fb);
      if (mk.ok && mk.inside) {
        ++deep;
        ok = ok && std::fabs(mk.depth - p.depth) <= tol &&
             std::fabs(-sat.separation - p.depth) <= tol;
        ok = ok && m.pointCount > 0;
        float deepest = 0;
        for (int k = 0; k < m.pointCount; ++k)
          deepest = std::min(deepest, m.points[k].separation);
        // A face within kLinearSlop of the best (edge) axis is kept (collideHulls): the
        // deepest point may be that much deeper than EPA's, never shallower.
        ok = ok && deepest <= -p.depth + 10 * tol && deepest >= -p.depth - kLinearSlop - 10 * tol;
      }
#endif
    }
    if (!ok) ++mismatches;
    EXPECT_TRUE(ok) << "pair " << i << " gjk " << d.coreDistance << " epa " << p.depth << " "
                    << toString(p.status) << " sat " << sat.separation;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(apart, 30);
#if QUACK_HAVE_QHULL
  EXPECT_GT(deep, 30);
#endif
}

TEST(Epa3, SwapFlipsTheNormal) {
  std::mt19937 rng(808);
  for (int i = 0; i < 2000; ++i) {
    Shape3 a = randomShape3(rng, kKinds[i % 5], 1.0f),
           b = randomShape3(rng, kKinds[(i / 5) % 5], 1.0f);
    Transform3 ta{randomVec(rng, 1), randomQuat(rng)};
    Transform3 tb{ta.p + randomVec(rng, 0.7f), randomQuat(rng)};
    PenetrationOutput3 ab = computePenetration(a.proxy(), ta, b.proxy(), tb);
    PenetrationOutput3 ba = computePenetration(b.proxy(), tb, a.proxy(), ta);
    ASSERT_EQ(ab.overlap, ba.overlap) << i;
    double tol = kDepthRel * (a.extent() + b.extent() + 2);
    EXPECT_NEAR(ab.depth, ba.depth, 2 * tol) << i;
    // The normal flips (random poses leave no ties between faces of B - A).
    if (ab.overlap && ab.status != Epa3Status::degenerate) {
      EXPECT_NEAR(dot(ab.normal, ba.normal), -1.0f, 1e-4f) << i;
    }
  }
}

TEST(Epa3, RigidMotionOfBothKeepsTheDepthAndTurnsTheNormal) {
  std::mt19937 rng(909);
  for (int i = 0; i < 2000; ++i) {
    Shape3 a = randomShape3(rng, kKinds[i % 5], 1.0f),
           b = randomShape3(rng, kKinds[(i / 5) % 5], 1.0f);
    Transform3 ta{randomVec(rng, 1), randomQuat(rng)};
    Transform3 tb{ta.p + randomVec(rng, 0.7f), randomQuat(rng)};
    PenetrationOutput3 p0 = computePenetration(a.proxy(), ta, b.proxy(), tb);
    Transform3 m{randomVec(rng, 100), randomQuat(rng)};
    Transform3 ma = m * ta, mb = m * tb;
    ma.q = normalize(ma.q);
    mb.q = normalize(mb.q);
    PenetrationOutput3 p1 = computePenetration(a.proxy(), ma, b.proxy(), mb);
    // Moving the pair 100 m rounds its relative pose by ~1e-5 m.
    EXPECT_NEAR(p0.depth, p1.depth, 1e-4f) << i;
    if (p0.overlap && p1.overlap && p0.depth > 1e-2f && p0.status != Epa3Status::degenerate) {
      EXPECT_NEAR(dot(transformVector(m, p0.normal), p1.normal), 1.0f, 1e-3f) << i;
    }
  }
}

}  // namespace
}  // namespace quack
