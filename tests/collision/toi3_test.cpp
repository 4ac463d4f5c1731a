// Shape cast and time of impact in 3D: hand-worked casts and a spinning rod, and random
// shapes with random translations and rotations (up to a full turn) against dense sampling
// of the GJK distance along the motion: a hit is within the band at its time and nothing
// is closer than the target before it; a miss never comes within the target.

#include <gtest/gtest.h>

#include <cmath>

#include "oracle3.hpp"
#include "quack/collision/toi3.hpp"

namespace quack {
namespace {

using namespace testing3;

TEST(ShapeCast3, SphereOntoBox) {
  Hull3 box = makeBox3({1, 1, 1}).value();
  Sphere s = makeSphere({}, 0.5f).value();
  ShapeCastOutput3 c = castShape(makeProxy(box), {}, makeProxy(s), {{0, 5, 0}, {}}, {0, -8, 0});
  ASSERT_EQ(c.status, ShapeCastStatus::hit);
  EXPECT_NEAR(c.fraction, 3.5f / 8, 2e-5f);
  EXPECT_NEAR(c.normal.y, 1, 1e-5f);
  EXPECT_NEAR(c.point.y, 1, 1e-4f);
  EXPECT_EQ(castShape(makeProxy(box), {}, makeProxy(s), {{0, 5, 0}, {}}, {0, -3, 0}).status,
            ShapeCastStatus::missed);
  EXPECT_EQ(castShape(makeProxy(box), {}, makeProxy(s), {{0, 5, 0}, {}}, {3, 8, 0}).status,
            ShapeCastStatus::missed);
  ShapeCastOutput3 o = castShape(makeProxy(box), {}, makeProxy(s), {{0, 1.2f, 0}, {}}, {0, -1, 0});
  EXPECT_EQ(o.status, ShapeCastStatus::overlapped);
  EXPECT_NEAR(o.depth, 0.3f, 1e-5f);
  EXPECT_EQ(castShape(makeProxy(box), {}, makeProxy(s), {}, {NAN, 0, 0}).status,
            ShapeCastStatus::invalidInput);
}

TEST(Toi3, SpinningRodHitsASphere) {
  // A thin rod (box 2 x 0.05 x 0.05) spins about y from along x toward +z; a sphere of
  // radius 0.2 waits at (0, 0, 1). The rod's face reaches distance d when
  // cos(theta) = (d + 0.05 + 0.2) / 1.
  Hull3 rod = makeBox3({2, 0.05f, 0.05f}).value();
  Sphere s = makeSphere({}, 0.2f).value();
  Sweep3 spin{{}, {}, {}, {}, {0, -0.5f * kPi, 0}};  // a quarter turn
  Sweep3 still{{}, {0, 0, 1}, {0, 0, 1}, {}, {}};
  ToiOutput3 r = computeToi(makeProxy(rod), spin, makeProxy(s), still);
  ASSERT_EQ(r.status, ToiStatus::hit);
  float thetaHit = std::acos(r.distance + 0.25f);
  EXPECT_NEAR(r.t * 0.5f * kPi, thetaHit, 1e-4f);
  EXPECT_GE(r.distance, kToiTargetSeparation - 1e-5f);
  EXPECT_LE(r.distance, kToiTargetSeparation + kToiTolerance + 1e-5f);
  // Without the spin it never gets there.
  Sweep3 none{{}, {}, {}, {}, {}};
  EXPECT_EQ(computeToi(makeProxy(rod), none, makeProxy(s), still).status, ToiStatus::separated);
  // Spinning the other way it never gets there either within a quarter turn: the rod's
  // other half comes round from -z.
  Sweep3 back{{}, {}, {}, {}, {0, 0.25f * kPi, 0}};
  EXPECT_EQ(computeToi(makeProxy(rod), back, makeProxy(s), still).status, ToiStatus::separated);
  Sweep3 bad = spin;
  bad.c2.x = INFINITY;
  EXPECT_EQ(computeToi(makeProxy(rod), bad, makeProxy(s), still).status, ToiStatus::invalidInput);
}

TEST(Toi3, MakeSweepTakesTheShortWay) {
  Transform3 a{{1, 2, 3}, Quat::fromAxisAngle({0, 0, 1}, 0.3f)};
  Transform3 b{{4, 5, 6}, Quat::fromAxisAngle({0, 0, 1}, 0.3f + 0.5f * kPi)};
  Sweep3 s = makeSweep3({0.1f, 0, 0}, a, b);
  EXPECT_NEAR(sweepAngle(s), 0.5f * kPi, 1e-5f);
  Transform3 end = transformAt(s, 1);
  EXPECT_NEAR(std::fabs(dot(end.q, b.q)), 1, 1e-6f);
  EXPECT_NEAR(end.p.x, 4, 1e-5f);
  Transform3 mid = transformAt(s, 0.5f);
  EXPECT_NEAR(std::fabs(dot(mid.q, Quat::fromAxisAngle({0, 0, 1}, 0.3f + 0.25f * kPi))), 1, 1e-6f);
}

const Kind3 kKinds[] = {Kind3::sphere, Kind3::capsule, Kind3::box, Kind3::hull};

TEST(Toi3, RandomSweepsAgainstDenseSampling) {
  std::mt19937 rng(1111);
  int hits = 0, separated = 0, failed = 0, mismatches = 0;
  const int n = 600 * testScale();
  const int samples = 400;
  for (int i = 0; i < n; ++i) {
    Shape3 a = randomShape3(rng, kKinds[i % 4], 1.0f, 12),
           b = randomShape3(rng, kKinds[(i / 4) % 4], 1.0f, 12);
    Vec3 origin = (i % 4 == 3) ? Vec3{1e3f, 1e3f, -1e3f} : Vec3{};
    Sweep3 sa{{}, origin, origin + randomVec(rng, 0.5f), randomQuat(rng), randomVec(rng, 1.5f)};
    Vec3 startB = origin + 3.0f * normalize(randomVec(rng, 1) + Vec3{1e-3f, 0, 0});
    Sweep3 sb{{}, startB, origin + randomVec(rng, 1.0f), randomQuat(rng), randomVec(rng, 3.0f)};
    ToiOutput3 r = computeToi(a.proxy(), sa, b.proxy(), sb);
    if (r.status == ToiStatus::overlapped || r.status == ToiStatus::invalidInput) continue;
    auto distanceAt = [&](float t) {
      return computeDistance(a.proxy(), transformAt(sa, t), b.proxy(), transformAt(sb, t)).distance;
    };
    const float eps = 2e-5f + 4e-7f * length(origin);
    bool ok = true;
    // Before a hit, and before the last time a capped run proved free, nothing is closer.
    float end = (r.status == ToiStatus::hit || r.status == ToiStatus::failed) ? r.t : 1.0f;
    for (int k = 0; k < samples && ok; ++k) {
      float t = end * float(k) / samples;
      if (distanceAt(t) < kToiTargetSeparation - eps) ok = false;  // a closer time before it
    }
    if (r.status == ToiStatus::hit) {
      ++hits;
      float d = distanceAt(r.t);
      if (d < kToiTargetSeparation - eps || d > kToiTargetSeparation + kToiTolerance + eps)
        ok = false;
    } else if (r.status == ToiStatus::separated) {
      ++separated;
      if (distanceAt(1.0f) < kToiTargetSeparation - eps) ok = false;
    } else {
      ++failed;
    }
    if (!ok) ++mismatches;
    EXPECT_TRUE(ok) << "pair " << i << " status " << toString(r.status) << " t " << r.t << "\nA "
                    << describe(a) << "\nB " << describe(b);
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(hits, n / 5);
  EXPECT_GT(separated, n / 10);
  EXPECT_LT(failed, n / 50 + 1);
  std::printf("  hits %d, separated %d, failed %d\n", hits, separated, failed);
}

TEST(ShapeCast3, RandomCastsAgainstDenseSampling) {
  std::mt19937 rng(1212);
  int mismatches = 0, hits = 0;
  const int n = 1000 * testScale();
  for (int i = 0; i < n; ++i) {
    Shape3 a = randomShape3(rng, kKinds[i % 4], 1.0f, 12),
           b = randomShape3(rng, kKinds[(i / 4) % 4], 1.0f, 12);
    Transform3 ta{randomVec(rng, 0.5f), randomQuat(rng)};
    Transform3 tb{3.0f * normalize(randomVec(rng, 1) + Vec3{1e-3f, 0, 0}), randomQuat(rng)};
    Vec3 move = -tb.p + randomVec(rng, 1.5f);
    ShapeCastOutput3 c = castShape(a.proxy(), ta, b.proxy(), tb, move);
    if (c.status == ShapeCastStatus::overlapped) continue;
    auto distanceAt = [&](float s) {
      return computeDistance(a.proxy(), ta, b.proxy(), {tb.p + s * move, tb.q}).distance;
    };
    bool ok = c.status == ShapeCastStatus::hit || c.status == ShapeCastStatus::missed;
    float end = c.status == ShapeCastStatus::hit ? c.fraction : 1.0f;
    for (int k = 0; k < 400 && ok; ++k)
      if (distanceAt(end * float(k) / 400) <= 0.0f) ok = false;
    if (c.status == ShapeCastStatus::hit) {
      ++hits;
      float d = distanceAt(c.fraction);
      if (d > kShapeCastTolerance + 1e-5f) ok = false;
    }
    if (!ok) ++mismatches;
    EXPECT_TRUE(ok) << "cast " << i << " status " << toString(c.status) << " fraction "
                    << c.fraction;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(hits, n / 5);
}

}  // namespace
}  // namespace quack
