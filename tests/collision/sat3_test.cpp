// SAT for hulls in 3D: hand-worked face and edge cases, and random hull pairs against the
// Minkowski difference (qhull: overlapping pairs' depth equals minus the separation) and the
// brute-force distance (apart pairs: the separation is a positive lower bound on it).

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

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

// The plain SAT, as computeSat was before its bounds and lanes: every face of both hulls,
// every edge pair that passes the Gauss-map test, first best wins. The oracle for the
// bounds: they may skip only what cannot change the answer.
struct PlainSat {
  float separation = 0;
  SatFeature3 feature = SatFeature3::faceA;
  int faceIndex = 0, edgeA = 0, edgeB = 0;
  long gaussPairs = 0;
};

PlainSat plainSat(const Hull3& a, Transform3 worldFromA, const Hull3& b, Transform3 worldFromB) {
  Transform3 aFromB = invMul(worldFromA, worldFromB);
  Transform3 bFromA = inverse(aFromB);
  PlainSat out;
  float size = 0;
  for (int i = 0; i < a.vertexCount; ++i)
    size = std::max(size, length(a.vertices[i] - a.centroid));
  for (int i = 0; i < b.vertexCount; ++i)
    size = std::max(size, length(b.vertices[i] - b.centroid));
  auto least = [](const Hull3& h, Vec3 d) {
    float m = dot(h.vertices[0], d);
    for (int i = 1; i < h.vertexCount; ++i)
      m = std::min(m, dot(h.vertices[i], d));
    return m;
  };
  float best = -std::numeric_limits<float>::infinity();
  for (int f = 0; f < a.faceCount; ++f) {
    const HullFace3& face = a.faces[f];
    float s = least(b, invRotate(aFromB.q, face.normal)) + dot(face.normal, aFromB.p) - face.offset;
    if (s > best) {
      best = s;
      out.feature = SatFeature3::faceA;
      out.faceIndex = f;
    }
  }
  for (int f = 0; f < b.faceCount; ++f) {
    const HullFace3& face = b.faces[f];
    float s = least(a, invRotate(bFromA.q, face.normal)) + dot(face.normal, bFromA.p) - face.offset;
    if (s > best) {
      best = s;
      out.feature = SatFeature3::faceB;
      out.faceIndex = f;
    }
  }
  float bestEdge = -std::numeric_limits<float>::infinity();
  int ba = 0, bb = 0;
  for (int i = 0; i < a.edgeCount; ++i) {
    const HullEdge3& ea = a.edges[i];
    Vec3 pa = a.vertices[ea.v0], da = a.vertices[ea.v1] - pa;
    Vec3 na1 = a.faces[ea.faceLeft].normal, na2 = a.faces[ea.faceRight].normal;
    Vec3 bxa = cross(na2, na1);
    for (int j = 0; j < b.edgeCount; ++j) {
      const HullEdge3& eb = b.edges[j];
      Vec3 c = -rotate(aFromB.q, b.faces[eb.faceLeft].normal);
      Vec3 d = -rotate(aFromB.q, b.faces[eb.faceRight].normal);
      Vec3 dxc = cross(d, c);
      float cba = dot(c, bxa), dba = dot(d, bxa), adc = dot(na1, dxc), bdc = dot(na2, dxc);
      if (!(cba * dba < 0 && adc * bdc < 0 && cba * bdc > 0)) continue;
      ++out.gaussPairs;
      Vec3 pb = transformPoint(aFromB, b.vertices[eb.v0]);
      Vec3 db = transformPoint(aFromB, b.vertices[eb.v1]) - pb;
      Vec3 axis = cross(da, db);
      float len = length(axis);
      if (len < 1e-6f * length(da) * length(db)) continue;
      axis = (1 / len) * axis;
      if (dot(axis, pa - a.centroid) < 0) axis = -axis;
      float s = dot(axis, pb - pa);
      if (s > bestEdge) {
        bestEdge = s;
        ba = i;
        bb = j;
      }
    }
  }
  out.separation = best;
  if (bestEdge > best + kSat3FaceBiasRelative * size) {
    out.separation = bestEdge;
    out.feature = SatFeature3::edges;
    out.edgeA = ba;
    out.edgeB = bb;
  }
  return out;
}

// A random hull of up to `maxVertices` points whose shape origin is `offset` away from
// its points (the bounds' slack grows with the centroids' distance from the origin).
Hull3 offsetHull(std::mt19937& rng, int maxVertices, Vec3 offset) {
  while (true) {
    std::vector<Vec3> pts;
    int n = std::uniform_int_distribution<int>(4, maxVertices)(rng);
    for (int i = 0; i < n; ++i)
      pts.push_back(offset + randomVec(rng, 1));
    Result<Hull3> h = makeHull3(pts);
    if (h.ok()) return *h;
  }
}

// The face and edge bounds (a hull's least projection is at most its centroid's less its
// inscribed ball's radius; an edge's arc reaches at most its faces' bounds over
// cos(theta / 2)) skip features, never the answer: the same axis, and to the bit the same
// separation, as the plain SAT, on random hulls up to 40 vertices, boxes, flat slabs with
// boxes resting on them, shape origins away from the hulls, and far from the world origin.
TEST(Sat3, BoundsSkipOnlyWhatCannotWin) {
  std::mt19937 rng(4242);
  Hull3 slab = makeBox3({2, 0.5f, 2}).value();
  Hull3 cube = makeBox3({0.5f, 0.5f, 0.5f}).value();
  int same = 0, ties = 0, edgeAnswers = 0, faceAnswers = 0;
  long pairsTested = 0, gaussPairs = 0;
  const int n = 3000 * testScale();
  for (int i = 0; i < n; ++i) {
    Hull3 a, b;
    Transform3 ta{randomVec(rng, 1), randomQuat(rng)};
    Transform3 tb;
    if (i % 5 == 4) {
      // Resting: the cube 0 to 0.01 deep on the slab, tilted up to 0.02 rad.
      a = slab;
      b = cube;
      Quat tilt = Quat::fromAxisAngle(
          normalize(Vec3{uni(rng, -1, 1), 0, uni(rng, -1, 1)} + Vec3{1e-3f, 0, 0}),
          uni(rng, 0, 0.02f));
      Quat turn = Quat::fromAxisAngle({0, 1, 0}, uni(rng, 0, 6.28f));
      Transform3 slabFromCube{
          {uni(rng, -1.5f, 1.5f), 1.0f - uni(rng, 0, 0.01f), uni(rng, -1.5f, 1.5f)}, tilt * turn};
      tb = ta * slabFromCube;
    } else {
      Vec3 offsetA = (i % 3 == 0) ? randomVec(rng, 5) : Vec3{};
      Vec3 offsetB = (i % 4 == 0) ? randomVec(rng, 5) : Vec3{};
      a = (i % 7 == 0) ? cube : offsetHull(rng, 8 + i % 33, offsetA);
      b = (i % 11 == 0) ? cube : offsetHull(rng, 8 + (i / 2) % 33, offsetB);
      // B's centroid within 0.5 to 2.5 of A's: deep overlap to apart.
      Vec3 dir = normalize(randomVec(rng, 1) + Vec3{0, 0, 1e-3f});
      Vec3 centroidA = transformPoint(ta, a.centroid);
      tb.q = randomQuat(rng);
      tb.p = centroidA + uni(rng, 0.5f, 2.5f) * dir - rotate(tb.q, b.centroid);
    }
    if (i % 4 == 3) {
      ta.p = ta.p + Vec3{1e4f, 1e4f, 1e4f};
      tb.p = tb.p + Vec3{1e4f, 1e4f, 1e4f};
    }
    SatOutput3 s = computeSat(a, ta, b, tb);
    // Given each hull's SAT data made beforehand, the answer is the same to the bit.
    const SatOutput3 withData = computeSat(a, makeHullSatData3(a), ta, b, makeHullSatData3(b), tb);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(withData.separation),
              std::bit_cast<std::uint32_t>(s.separation))
        << "pair " << i;
    EXPECT_EQ(withData.feature, s.feature) << "pair " << i;
    EXPECT_EQ(withData.faceIndex, s.faceIndex) << "pair " << i;
    EXPECT_EQ(withData.edgeA, s.edgeA) << "pair " << i;
    EXPECT_EQ(withData.edgeB, s.edgeB) << "pair " << i;
    EXPECT_EQ(withData.normal, s.normal) << "pair " << i;
    PlainSat plain = plainSat(a, ta, b, tb);
    pairsTested += s.edgePairsTested;
    gaussPairs += plain.gaussPairs;
    (plain.feature == SatFeature3::edges ? edgeAnswers : faceAnswers)++;
    bool sameAxis =
        s.feature == plain.feature &&
        (s.feature == SatFeature3::edges ? s.edgeA == plain.edgeA && s.edgeB == plain.edgeB
                                         : s.faceIndex == plain.faceIndex);
    if (sameAxis && s.separation == plain.separation) {
      ++same;
    } else {
      // Another axis only in a tie the rounding of the two computations decides.
      ++ties;
      EXPECT_NEAR(s.separation, plain.separation, 1e-6f * (2 + length(ta.p)))
          << "pair " << i << " feature " << int(s.feature) << " vs " << int(plain.feature);
    }
  }
  // Where both compute alike (x86-64: the lanes are SSE2's and nothing is fused) every
  // answer is the plain one; a tie may go otherwise where a compiler fuses differently.
  EXPECT_GE(same, n - n / 100);
  EXPECT_LE(ties, n / 100);
  EXPECT_GT(edgeAnswers, n / 20);
  EXPECT_GT(faceAnswers, n / 2);
  // And the bounds skip most of what the Gauss map alone would test.
  EXPECT_LT(pairsTested * 2, gaussPairs);
  std::printf("  answers %d (edges %d), same %d; edge pairs tested %ld, Gauss map alone %ld\n", n,
              edgeAnswers, same, pairsTested, gaussPairs);
}

}  // namespace
}  // namespace quack
