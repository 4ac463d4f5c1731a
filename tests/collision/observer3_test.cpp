// The 3D GJK and EPA observers (Gjk3Trace, Epa3Trace in gjk3.hpp and epa3.hpp): observing
// changes no answer (bit for bit), the records account for every support point of the
// loops, the last GJK record is the returned simplex, EPA's polytopes grow by one vertex a
// pass and stay closed, and a buffer too small for the run is filled, flagged and never
// overrun.

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>
#include <vector>

#include "quack/collision/epa3.hpp"
#include "quack/collision/gjk3.hpp"

namespace quack {
namespace {

bool sameBits(float x, float y) {
  return std::bit_cast<std::uint32_t>(x) == std::bit_cast<std::uint32_t>(y);
}
bool sameBits(Vec3 x, Vec3 y) {
  return sameBits(x.x, y.x) && sameBits(x.y, y.y) && sameBits(x.z, y.z);
}

struct Pair {
  ShapeGeometry3 a;
  ShapeGeometry3 b;
  Transform3 pa;
  Transform3 pb;
};

// Boxes, spheres, capsules and a hull at poses from deep overlap to apart.
std::vector<Pair> pairs() {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<ShapeGeometry3> shapes;
  shapes.push_back(makeBox3({0.6f, 0.4f, 0.5f}).value());
  shapes.push_back(makeSphere({0.1f, 0, 0}, 0.5f).value());
  shapes.push_back(makeCapsule3({0, -0.5f, 0}, {0, 0.5f, 0}, 0.3f).value());
  const Vec3 points[] = {{0.7f, 0, 0},       {-0.5f, 0.5f, 0.1f},  {-0.4f, -0.6f, 0.2f},
                         {0.1f, 0.2f, 0.8f}, {0.2f, -0.1f, -0.7f}, {0.4f, 0.6f, -0.3f}};
  shapes.push_back(makeHull3(points).value());
  std::vector<Pair> out;
  for (const ShapeGeometry3& a : shapes) {
    for (const ShapeGeometry3& b : shapes) {
      for (int k = 0; k < 12; ++k) {
        float reach = 0.1f + 0.15f * static_cast<float>(k);
        Transform3 pa{{u(rng), u(rng), u(rng)},
                      Quat::fromAxisAngle(normalize(Vec3{u(rng), u(rng), u(rng)}), 3 * u(rng))};
        Transform3 pb{pa.p + reach * normalize(Vec3{u(rng), u(rng), u(rng)}),
                      Quat::fromAxisAngle(normalize(Vec3{u(rng), u(rng), u(rng)}), 3 * u(rng))};
        out.push_back({a, b, pa, pb});
      }
    }
  }
  return out;
}

TEST(Observer3, GjkTraceChangesNothingAndEndsOnTheAnswer) {
  std::vector<Gjk3IterationRecord> records(kGjk3MaxTraceRecords);
  int runs = 0;
  for (const Pair& p : pairs()) {
    ShapeProxy3 a = makeProxy(p.a), b = makeProxy(p.b);
    DistanceOutput3 plain = computeDistance(a, p.pa, b, p.pb);
    Gjk3Trace trace{records.data(), kGjk3MaxTraceRecords};
    DistanceOutput3 traced = computeDistance(a, p.pa, b, p.pb, nullptr, trace);
    ASSERT_TRUE(sameBits(plain.distance, traced.distance));
    ASSERT_TRUE(sameBits(plain.pointA, traced.pointA));
    ASSERT_TRUE(sameBits(plain.pointB, traced.pointB));
    ASSERT_TRUE(sameBits(plain.normal, traced.normal));
    ASSERT_EQ(plain.iterations, traced.iterations);
    ASSERT_EQ(plain.status, traced.status);
    ASSERT_FALSE(trace.truncated);
    ASSERT_GE(trace.count, 1);
    ASSERT_EQ(trace.count, trace.passes);
    // A cold start takes one support point before the loop; every other is in a record.
    int supports = 0;
    for (int k = 0; k < trace.count; ++k) {
      const Gjk3IterationRecord& r = records[k];
      ASSERT_GE(r.simplex.count, 1);
      ASSERT_LE(r.simplex.count, 4);
      if (r.hasSupport) {
        ++supports;
        ASSERT_NEAR(length(r.direction), 1.0f, 1e-5f);
      }
      // Each pass but the last adds its support point to the next simplex.
      if (k + 1 < trace.count) {
        ASSERT_TRUE(r.hasSupport);
      }
    }
    ASSERT_EQ(supports + 1, traced.iterations);
    const Gjk3IterationRecord& last = records[trace.count - 1];
    ASSERT_EQ(last.simplex.count, traced.simplex.count);
    for (int i = 0; i < last.simplex.count; ++i) {
      ASSERT_TRUE(sameBits(last.simplex.v[i].w, traced.simplex.v[i].w));
      ASSERT_TRUE(sameBits(last.simplex.weights[i], traced.simplex.weights[i]));
    }
    if (traced.status == GjkStatus::overlap) {
      ASSERT_EQ(lengthSquared(last.closest), 0.0f);
    }
    ++runs;
  }
  EXPECT_EQ(runs, 192);
}

TEST(Observer3, EpaTraceChangesNothingAndRecordsAClosedGrowingPolytope) {
  std::vector<Gjk3IterationRecord> gjkRecords(kGjk3MaxTraceRecords);
  std::vector<Epa3IterationRecord> records(kEpa3MaxTraceRecords);
  int ran = 0;
  for (const Pair& p : pairs()) {
    ShapeProxy3 a = makeProxy(p.a), b = makeProxy(p.b);
    PenetrationOutput3 plain = computePenetration(a, p.pa, b, p.pb);
    Gjk3Trace gjk{gjkRecords.data(), kGjk3MaxTraceRecords};
    Epa3Trace trace{records.data(), kEpa3MaxTraceRecords};
    PenetrationOutput3 traced = computePenetration(a, p.pa, b, p.pb, nullptr, &gjk, &trace);
    ASSERT_EQ(plain.overlap, traced.overlap);
    ASSERT_TRUE(sameBits(plain.depth, traced.depth));
    ASSERT_TRUE(sameBits(plain.normal, traced.normal));
    ASSERT_TRUE(sameBits(plain.pointA, traced.pointA));
    ASSERT_TRUE(sameBits(plain.pointB, traced.pointB));
    ASSERT_EQ(plain.iterations, traced.iterations);
    ASSERT_EQ(plain.status, traced.status);
    ASSERT_GE(gjk.count, 1);
    ASSERT_FALSE(trace.truncated);
    const bool epaRan =
        traced.status == Epa3Status::converged || traced.status == Epa3Status::repeatedSupport;
    if (!epaRan) {
      if (traced.status != Epa3Status::gaveUp && traced.status != Epa3Status::bufferFull) {
        ASSERT_EQ(trace.count, 0);
      }
      continue;
    }
    ++ran;
    ASSERT_GE(trace.count, 1);
    ASSERT_EQ(records[0].vertexCount, 4);
    for (int k = 0; k < trace.count; ++k) {
      const Epa3IterationRecord& r = records[k];
      if (k > 0) {
        ASSERT_EQ(r.vertexCount, records[k - 1].vertexCount + 1);
      }
      ASSERT_EQ(r.faceCount, 2 * r.vertexCount - 4);  // closed and triangulated
      ASSERT_GE(r.nearest, 0);
      ASSERT_LT(r.nearest, r.faceCount);
      ASSERT_TRUE(r.hasSupport);
      ASSERT_NEAR(length(r.faceNormal), 1.0f, 1e-5f);
      // Every face is made of the record's vertices.
      for (int f = 0; f < r.faceCount; ++f) {
        for (int v : r.faces[f]) {
          ASSERT_GE(v, 0);
          ASSERT_LT(v, r.vertexCount);
        }
      }
    }
  }
  EXPECT_GT(ran, 40);
}

TEST(Observer3, SmallBuffersAreFilledFlaggedAndKeepTheLastPass) {
  // Two turned boxes deep in each other: several GJK and EPA passes.
  ShapeGeometry3 box = makeBox3({0.6f, 0.4f, 0.5f}).value();
  ShapeProxy3 proxy = makeProxy(box);
  Transform3 pa{{0, 0, 0}, Quat::fromAxisAngle(normalize(Vec3{1, 2, 3}), 0.4f)};
  Transform3 pb{{0.3f, 0.2f, 0.1f}, Quat::fromAxisAngle(normalize(Vec3{3, -1, 1}), 0.9f)};
  std::vector<Gjk3IterationRecord> fullG(kGjk3MaxTraceRecords);
  std::vector<Epa3IterationRecord> fullE(kEpa3MaxTraceRecords);
  Gjk3Trace gjk{fullG.data(), kGjk3MaxTraceRecords};
  Epa3Trace epa{fullE.data(), kEpa3MaxTraceRecords};
  PenetrationOutput3 full = computePenetration(proxy, pa, proxy, pb, nullptr, &gjk, &epa);
  ASSERT_GE(gjk.passes, 3);
  ASSERT_GE(epa.passes, 3);

  std::vector<Gjk3IterationRecord> smallG(3);
  std::vector<Epa3IterationRecord> smallE(3);
  Gjk3Trace g2{smallG.data(), 2};  // the third record must stay untouched
  Epa3Trace e2{smallE.data(), 2};
  smallG[2].simplex.count = 99;
  smallE[2].vertexCount = 99;
  PenetrationOutput3 small = computePenetration(proxy, pa, proxy, pb, nullptr, &g2, &e2);
  EXPECT_TRUE(sameBits(small.depth, full.depth));
  EXPECT_EQ(g2.count, 2);
  EXPECT_EQ(g2.passes, gjk.passes);
  EXPECT_TRUE(g2.truncated);
  EXPECT_EQ(e2.count, 2);
  EXPECT_EQ(e2.passes, epa.passes);
  EXPECT_TRUE(e2.truncated);
  EXPECT_EQ(smallG[2].simplex.count, 99);
  EXPECT_EQ(smallE[2].vertexCount, 99);
  // The last slot holds the final pass.
  EXPECT_EQ(smallG[1].simplex.count, fullG[gjk.count - 1].simplex.count);
  EXPECT_EQ(smallE[1].vertexCount, fullE[epa.count - 1].vertexCount);
  EXPECT_EQ(smallE[1].faceCount, fullE[epa.count - 1].faceCount);

  // No buffer: nothing recorded, the same answer.
  Gjk3Trace none;
  DistanceOutput3 d = computeDistance(proxy, pa, proxy, pb, nullptr, none);
  EXPECT_EQ(none.count, 0);
  EXPECT_EQ(d.status, GjkStatus::overlap);
}

}  // namespace
}  // namespace quack
