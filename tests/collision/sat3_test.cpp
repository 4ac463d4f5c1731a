// SAT for hulls in 3D: hand-worked face and edge cases, and random hull pairs against the
// Minkowski difference (qhull: overlapping pairs' depth equals minus the separation) and the
// brute-force distance (apart pairs: the separation is a positive lower bound on it).

#include <gtest/gtest.h>

#include "oracle3.hpp"
#include "quack/collision/gjk3.hpp"
#include "quack/collision/sat3.hpp"

namespace quack {
namespace {

using namespace testing3;

constexpr float kTol = 1e-5f;

TEST(Sat3, BoxFacesApartAndOverlapping) {
  Hull3 box = makeBox3({1, 1, 1}).value();
  SatOutput3 s = computeSat(box, {}, box, {{3, 0.2f, 0.1f}, {}});
  EXPECT_NEAR(s.separation, 1, kTol);
  EXPECT_NEAR(s.normal.x, 1, kTol);
  EXPECT_EQ(s.feature, SatFeature3::faceA);
  s = computeSat(box, {}, box, {{0.2f, -1.6f, 0.1f}, {}});
  EXPECT_NEAR(s.separation, -0.4f, kTol);
  EXPECT_NEAR(s.normal.y, -1, kTol);
}

TEST(Sat3, CrossedEdges) {
  // Two boxes turned 45 degrees about x and about z, meeting edge to edge along y:
  // A's top edge runs along x, B's bottom edge along z.
  Hull3 box = makeBox3({1, 1, 1}).value();
  float r2 = std::sqrt(2.0f);
  Transform3 ta{{}, Quat::fromAxisAngle({1, 0, 0}, 0.25f * kPi)};
  Transform3 tb{{0.1f, 2 * r2 + 0.5f, 0.2f}, Quat::fromAxisAngle({0, 0, 1}, 0.25f * kPi)};
  SatOutput3 s = computeSat(box, ta, box, tb);
  EXPECT_EQ(s.feature, SatFeature3::edges);
  EXPECT_NEAR(s.separation, 0.5f, 1e-5f);
  EXPECT_NEAR(s.normal.y, 1, 1e-5f);
  tb.p.y = 2 * r2 - 0.25f;
  s = computeSat(box, ta, box, tb);
  EXPECT_EQ(s.feature, SatFeature3::edges);
  EXPECT_NEAR(s.separation, -0.25f, 1e-5f);
}

// stopAbove: an answer with the full answer's axis when that separation is at most the
// threshold; otherwise some axis whose separation is above it too (and the normal's
// projections say so), sooner.
TEST(Sat3, StopAboveAnswersAsTheFullTestOrBeyondTheThreshold) {
  std::mt19937 rng(77);
  int stoppedEarly = 0, same = 0;
  for (int i = 0; i < 2000; ++i) {
    Shape3 a = randomShape3(rng, i % 2 ? Kind3::box : Kind3::hull, 1.0f, 20);
    Shape3 b = randomShape3(rng, i % 3 ? Kind3::hull : Kind3::box, 1.0f, 20);
    Transform3 ta{randomVec(rng, 1), randomQuat(rng)};
    Transform3 tb{ta.p + randomVec(rng, 2.5f), randomQuat(rng)};
    const float stop = static_cast<float>(i % 4) * 0.02f;
    SatOutput3 full = computeSat(a.hull, ta, b.hull, tb);
    SatOutput3 early = computeSat(a.hull, ta, b.hull, tb, stop);
    if (full.separation <= stop) {
      ++same;
      EXPECT_EQ(early.separation, full.separation) << i;
      EXPECT_EQ(early.normal, full.normal) << i;
      EXPECT_EQ(early.feature, full.feature) << i;
      EXPECT_EQ(early.faceIndex, full.faceIndex) << i;
      EXPECT_EQ(early.edgeA, full.edgeA) << i;
      EXPECT_EQ(early.edgeB, full.edgeB) << i;
    } else {
      ++stoppedEarly;
      EXPECT_GT(early.separation, stop) << i;
      EXPECT_LE(early.separation, full.separation) << i;
      // The certificate: along the normal, B's least projection is `separation` beyond A's
      // greatest.
      float maxA = -1e30f, minB = 1e30f;
      for (int k = 0; k < a.hull.vertexCount; ++k)
        maxA = std::max(maxA, dot(early.normal, transformPoint(ta, a.hull.vertices[k])));
      for (int k = 0; k < b.hull.vertexCount; ++k)
        minB = std::min(minB, dot(early.normal, transformPoint(tb, b.hull.vertices[k])));
      EXPECT_NEAR(minB - maxA, early.separation, 1e-4f) << i;
    }
  }
  EXPECT_GT(stoppedEarly, 100);
  EXPECT_GT(same, 100);
}

TEST(Sat3, RandomHullPairsAgreeWithTheOracles) {
  std::mt19937 rng(909);
  int mismatches = 0, overlapChecked = 0, apartChecked = 0;
  long pairsTested = 0, pairsTotal = 0;
  const int n = 3000 * testScale();
  for (int i = 0; i < n; ++i) {
    Shape3 a = randomShape3(rng, i % 2 ? Kind3::box : Kind3::hull, 1.0f, 20);
    Shape3 b = randomShape3(rng, i % 3 ? Kind3::hull : Kind3::box, 1.0f, 20);
    Vec3 origin = (i % 4 == 3) ? Vec3{1e4f, 1e4f, 1e4f} : Vec3{};
    Transform3 ta{origin + randomVec(rng, 1), randomQuat(rng)};
    Transform3 tb{ta.p + randomVec(rng, 1.5f), randomQuat(rng)};
    SatOutput3 s = computeSat(a.hull, ta, b.hull, tb);
    pairsTested += s.edgePairsTested;
    pairsTotal += long(a.hull.edgeCount) * b.hull.edgeCount;
    Features fa = a.features(ta), fb = b.features(tb);
    double size = a.extent() + b.extent() + lenD(toD(tb.p) - toD(ta.p));
    double tol = 4e-6 * size;
    bool ok = true;
    double oracle = 0;
    // The normal's certificate: along it, the projections are `separation` apart.
    D3 nrm = toD(s.normal);
    double maxA = -1e300, minB = 1e300;
    for (D3 v : fa.v)
      maxA = std::max(maxA, dotD(nrm, v));
    for (D3 v : fb.v)
      minB = std::min(minB, dotD(nrm, v));
    if (std::fabs((minB - maxA) - s.separation) > tol) ok = false;
    if (s.separation > tol) {
      ++apartChecked;
      oracle = bruteCoreDistance(fa, fb);
      if (s.separation > oracle + tol) ok = false;
    } else if (s.separation < -tol) {
#if QUACK_HAVE_QHULL
      MinkowskiAnswer m = minkowskiDepth(fa, fb);
      if (m.ok) {
        ++overlapChecked;
        oracle = -m.depth;
        if (std::fabs(oracle - s.separation) > tol) ok = false;
      }
#endif
    }
    if (!ok) ++mismatches;
    EXPECT_TRUE(ok) << "pair " << i << " sat " << s.separation << " oracle " << oracle
                    << " along normal " << (minB - maxA) << " feature " << int(s.feature) << "\nA "
                    << describe(a) << "\nB " << describe(b);
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(apartChecked, n / 5);
#if QUACK_HAVE_QHULL
  EXPECT_GT(overlapChecked, n / 5);
#endif
  // The Gauss map keeps a small share of the edge pairs.
  EXPECT_LT(pairsTested * 4, pairsTotal);
  std::printf("  edge pairs tested: %ld of %ld\n", pairsTested, pairsTotal);
}

}  // namespace
}  // namespace quack
