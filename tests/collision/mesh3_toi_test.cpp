// Time of impact and penetration against static triangle meshes: a sphere falling onto a
// flat grid and a cube tumbling onto it against their closed forms, one-sidedness, and
// random rotating sweeps and random poses through the mesh's tree against a brute-force
// loop over every triangle, to the bit.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "mesh3_test_util.hpp"
#include "oracle3.hpp"
#include "quack/collision/mesh3.hpp"
#include "quack/collision/proxy3.hpp"

namespace quack {
namespace {

using testing::closedBox;
using testing::ConvexKinds;
using testing::grid;
using testing::rollingField;

const Transform3 kIdentity{};

// A sweep that only translates, from `from` to `to` (centre of mass at the body origin).
Sweep3 falling(Vec3 from, Vec3 to) {
  return {{}, from, to, {}, {}};
}

// computeToi against every triangle in order (a triangle skipped when B's centre leaves its
// front), the earliest hit or overlap kept (at t = 0 the deepest overlap, by
// computePenetration; other ties to the lowest index), a failed run first when its last free
// time is before that hit: what computeToiMesh must give.
MeshToiOutput3 bruteToi(const Mesh3& mesh, Transform3 worldFromMesh, const ShapeProxy3& b,
                        const Sweep3& sweepB, float tMax = 1.0f,
                        float target = kToiTargetSeparation) {
  const Sweep3 still{{}, worldFromMesh.p, worldFromMesh.p, worldFromMesh.q, {}};
  const Vec3 v = invTransformVector(worldFromMesh, sweepB.c2 - sweepB.c1);
  MeshToiOutput3 best, failed;
  float bestDepth = -1.0f;  // of the best overlap; -1 for a hit
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    if (dot(v, mesh.triangles()[static_cast<std::size_t>(t)].normal) > 0.0f) continue;
    const ShapeProxy3 tri = makeProxy(mesh.triangle(t));
    const ToiOutput3 c = computeToi(tri, still, b, sweepB, tMax, target);
    const float depth =
        c.status == ToiStatus::overlapped
            ? computePenetration(tri, worldFromMesh, b, transformAt(sweepB, 0.0f)).depth
            : -1.0f;
    if (c.status == ToiStatus::hit || c.status == ToiStatus::overlapped) {
      if (best.triangle < 0 || c.t < best.t || (c.t == best.t && depth > bestDepth)) {
        static_cast<ToiOutput3&>(best) = c;
        best.triangle = t;
        bestDepth = depth;
      }
    } else if (c.status == ToiStatus::failed && (failed.triangle < 0 || c.t < failed.t)) {
      static_cast<ToiOutput3&>(failed) = c;
      failed.triangle = t;
    }
  }
  if (failed.triangle >= 0 && (best.triangle < 0 || failed.t < best.t)) return failed;
  if (best.triangle < 0) {
    best.status = ToiStatus::separated;
    best.t = tMax;
  }
  return best;
}

// computePenetration against every triangle in order, the deepest overlap kept; when none
// overlaps, the closest triangle's (by computeDistance) answer.
MeshPenetrationOutput3 brutePenetration(const Mesh3& mesh, Transform3 worldFromMesh,
                                        const ShapeProxy3& b, Transform3 worldFromB) {
  MeshPenetrationOutput3 best;
  float closest = 0.0f;
  int closestTriangle = -1;
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const ShapeProxy3 tri = makeProxy(mesh.triangle(t));
    const PenetrationOutput3 p = computePenetration(tri, worldFromMesh, b, worldFromB);
    if (p.overlap && (best.triangle < 0 || p.depth > best.depth)) {
      static_cast<PenetrationOutput3&>(best) = p;
      best.triangle = t;
    }
    const float d = computeDistance(tri, worldFromMesh, b, worldFromB).distance;
    if (closestTriangle < 0 || d < closest) {
      closest = d;
      closestTriangle = t;
    }
  }
  if (best.triangle >= 0) return best;
  static_cast<PenetrationOutput3&>(best) =
      computePenetration(makeProxy(mesh.triangle(closestTriangle)), worldFromMesh, b, worldFromB);
  best.triangle = closestTriangle;
  return best;
}

void expectSameToi(const MeshToiOutput3& a, const MeshToiOutput3& r, int q) {
  EXPECT_EQ(a.status, r.status) << "sweep " << q;
  EXPECT_EQ(a.triangle, r.triangle) << "sweep " << q;
  EXPECT_EQ(a.t, r.t) << "sweep " << q;
  EXPECT_EQ(a.distance, r.distance) << "sweep " << q;
  EXPECT_EQ(a.point, r.point) << "sweep " << q;
  EXPECT_EQ(a.normal, r.normal) << "sweep " << q;
}

bool triangleHolds(const Triangle3& tri, float x, float z) {
  // Inside in the xz plane (the grid is flat), by the signs of the three edge functions.
  float sign = 0.0f;
  for (int k = 0; k < 3; ++k) {
    const Vec3 p = tri.v[k], q = tri.v[(k + 1) % 3];
    const float e = (q.x - p.x) * (z - p.z) - (q.z - p.z) * (x - p.x);
    if (e != 0.0f && sign != 0.0f && (e > 0.0f) != (sign > 0.0f)) return false;
    if (e != 0.0f) sign = e;
  }
  return true;
}

TEST(Mesh3Toi, SphereFallingOntoAFlatGridHitsAtItsClosedForm) {
  // A sphere of radius 0.5 falls from y = 2 to y = -1 over a flat 4 x 4 grid at y = 0
  // while spinning: its centre is target + 0.5 above the floor at t = (1.5 - target) / 3,
  // and the hit band [target, target + kToiTolerance] is 3 times shorter in t.
  const Mesh3 m = grid(4, 2, [](float, float) { return 0.0f; });
  const Sphere ball = makeSphere({}, 0.5f).value();
  const ShapeProxy3 b = makeProxy(ball);
  const float target = kToiTargetSeparation;
  const float late = (1.5f - target) / 3.0f, early = (1.5f - target - kToiTolerance) / 3.0f;
  const float places[4][2] = {{0.3f, -0.7f}, {-1.6f, 1.2f}, {0.0f, 0.0f}, {1.0f, -1.0f}};
  for (const auto& xz : places) {
    const Sweep3 s{{}, {xz[0], 2, xz[1]}, {xz[0], -1, xz[1]}, {}, {0.4f, 2.0f, -1.0f}};
    const MeshToiOutput3 r = computeToiMesh(m, kIdentity, b, s);
    ASSERT_EQ(r.status, ToiStatus::hit) << xz[0] << " " << xz[1];
    EXPECT_GE(r.t, early - 2e-6f);
    EXPECT_LE(r.t, late + 2e-6f);
    EXPECT_GE(r.distance, target - 1e-6f);
    EXPECT_LE(r.distance, target + kToiTolerance + 1e-6f);
    EXPECT_NEAR(r.normal.y, 1.0f, 1e-6f);
    EXPECT_NEAR(r.point.x, xz[0], 1e-5f);
    EXPECT_NEAR(r.point.y, 0.0f, 1e-6f);
    EXPECT_NEAR(r.point.z, xz[1], 1e-5f);
    // The triangle under the centre (at a grid vertex, the lowest index of those there).
    ASSERT_GE(r.triangle, 0);
    EXPECT_TRUE(triangleHolds(m.triangle(r.triangle), xz[0], xz[1])) << r.triangle;
    expectSameToi(r, bruteToi(m, kIdentity, b, s), 0);
  }
  // Stopped short of the floor, the sweep is separated at tMax; the target moves the hit.
  const Sweep3 s = falling({0.3f, 2, 0.2f}, {0.3f, -1, 0.2f});
  const MeshToiOutput3 shortSweep = computeToiMesh(m, kIdentity, b, s, 0.4f);
  EXPECT_EQ(shortSweep.status, ToiStatus::separated);
  EXPECT_EQ(shortSweep.t, 0.4f);
  EXPECT_EQ(shortSweep.triangle, -1);
  const MeshToiOutput3 far = computeToiMesh(m, kIdentity, b, s, 1.0f, 0.3f);
  ASSERT_EQ(far.status, ToiStatus::hit);
  EXPECT_NEAR(far.t, (1.5f - 0.3f) / 3.0f, kToiTolerance / 3.0f + 2e-6f);
}

TEST(Mesh3Toi, CubeTumblingOntoAFlatGridHitsWhereItsLowestCornerArrives) {
  // A unit cube falls from y = 3 to y = 0 while turning 1.5 rad about z: its lowest point
  // is y(t) - 0.5 (|cos a| + |sin a|) with a = 1.5 t, a decreasing function of t; the
  // first t at which it is `target` above the floor, by bisection in double.
  const Mesh3 m = grid(6, 3, [](float, float) { return 0.0f; });
  const Hull3 cube = makeBox3({0.5f, 0.5f, 0.5f}).value();
  const ShapeProxy3 b = makeProxy(cube);
  const Transform3 worldFromMesh{{0.5f, -0.25f, 1.0f}, {}};
  auto gap = [&](double t) {
    const double a = 1.5 * t;
    return 3.0 - 3.0 * t - 0.5 * (std::abs(std::cos(a)) + std::abs(std::sin(a)));
  };
  auto timeAtGap = [&](double g) {
    double lo = 0, hi = 1;
    for (int i = 0; i < 200; ++i)
      ((gap(0.5 * (lo + hi)) > g) ? lo : hi) = 0.5 * (lo + hi);
    return lo;
  };
  const float target = kToiTargetSeparation;
  const Sweep3 s{{}, {0.7f, 3 - 0.25f, 0.8f}, {0.7f, -0.25f, 0.8f}, {}, {0, 0, 1.5f}};
  const MeshToiOutput3 r = computeToiMesh(m, worldFromMesh, b, s);
  ASSERT_EQ(r.status, ToiStatus::hit);
  EXPECT_GE(r.t, timeAtGap(target + kToiTolerance) - 1e-5);
  EXPECT_LE(r.t, timeAtGap(target) + 1e-5);
  EXPECT_NEAR(r.normal.y, 1.0f, 1e-4f);
  expectSameToi(r, bruteToi(m, worldFromMesh, b, s), 0);
}

TEST(Mesh3Toi, OneSidedOverlappedAndInvalid) {
  const Mesh3 floor = grid(4, 2, [](float, float) { return 0.0f; });
  const Sphere ball = makeSphere({}, 0.25f).value();
  const ShapeProxy3 b = makeProxy(ball);
  // Rising from below through the floor's back: no hit.
  EXPECT_EQ(computeToiMesh(floor, kIdentity, b, falling({0.1f, -1, 0.3f}, {0.1f, 2, 0.3f})).status,
            ToiStatus::separated);
  // Inside a closed box, moving out through a face: no hit; from outside, the face.
  const Mesh3 box = closedBox({1, 1, 1});
  EXPECT_EQ(computeToiMesh(box, kIdentity, b, falling({0, 0, 0}, {3, 0.2f, 0})).status,
            ToiStatus::separated);
  const MeshToiOutput3 in = computeToiMesh(box, kIdentity, b, falling({3, 0.2f, 0}, {0, 0.2f, 0}));
  ASSERT_EQ(in.status, ToiStatus::hit);
  EXPECT_NEAR(in.normal.x, 1.0f, 1e-5f);
  EXPECT_NEAR(in.t, (3.0f - 1.25f - kToiTargetSeparation) / 3.0f, kToiTolerance / 3.0f + 2e-6f);
  // A rod that only turns, its end sweeping down through the floor: the floor is kept.
  const Hull3 rod = makeBox3({1.0f, 0.05f, 0.05f}).value();
  const Sweep3 turn{{}, {0, 0.5f, 0}, {0, 0.5f, 0}, {}, {0, 0, 1.2f}};
  const MeshToiOutput3 spun = computeToiMesh(floor, kIdentity, makeProxy(rod), turn);
  ASSERT_EQ(spun.status, ToiStatus::hit);
  // The rod's lower corner reaches the target above y = 0 when 0.5 - sin(a) - 0.05 cos(a)
  // is the target (a = 1.2 t, the turn lifting +x and lowering -x).
  const float a = 1.2f * spun.t;
  const float lowest = 0.5f - std::sin(a) - 0.05f * std::cos(a);
  EXPECT_GE(lowest, kToiTargetSeparation - 1e-4f);
  EXPECT_LE(lowest, kToiTargetSeparation + kToiTolerance + 1e-4f);
  // Overlapping at the start: overlapped at t = 0 with the deepest triangle's normal, out of
  // the floor (the sphere also overlaps the next triangle of its quad, which alone would
  // push it sideways across their diagonal, and those of the next quad).
  const MeshToiOutput3 o =
      computeToiMesh(floor, kIdentity, b, falling({0.2f, 0.1f, 0.2f}, {0.2f, -1, 0.2f}));
  EXPECT_EQ(o.status, ToiStatus::overlapped);
  EXPECT_EQ(o.t, 0.0f);
  EXPECT_NEAR(o.normal.y, 1.0f, 1e-5f);
  // Bad input.
  Sweep3 bad = falling({0, 1, 0}, {0, -1, 0});
  EXPECT_EQ(computeToiMesh(floor, kIdentity, b, bad, 1.5f).status, ToiStatus::invalidInput);
  EXPECT_EQ(computeToiMesh(floor, kIdentity, b, bad, 1.0f, -0.1f).status, ToiStatus::invalidInput);
  EXPECT_EQ(computeToiMesh(floor, Transform3{{NAN, 0, 0}, {}}, b, bad).status,
            ToiStatus::invalidInput);
  bad.rotation.y = INFINITY;
  EXPECT_EQ(computeToiMesh(floor, kIdentity, b, bad).status, ToiStatus::invalidInput);
}

TEST(Mesh3Toi, RandomRotatingSweepsAgreeWithEveryTriangle) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(-1, 1);
  const Mesh3 field = rollingField();
  const Mesh3 box = closedBox({1.5f, 0.7f, 1.1f});
  const ConvexKinds kinds(Vec3{0.1f, 0, 0});
  const std::vector<ShapeProxy3>& shapes = kinds.proxies;
  int hits = 0, separated = 0, overlapped = 0;
  const int n = 240 * testing3::testScale();
  for (int q = 0; q < n; ++q) {
    const Mesh3& m = q % 2 == 0 ? field : box;
    const Transform3 worldFromMesh{{u(rng), u(rng), u(rng)},
                                   normalize(Quat{u(rng), u(rng), u(rng), u(rng) + 0.01f})};
    const ShapeProxy3& b = shapes[static_cast<std::size_t>(q) % shapes.size()];
    // One start in six is near the surface (or behind it), for overlaps at t = 0.
    const Vec3 from = (q % 6 == 0 ? 1.0f : 4.0f) * normalize(Vec3{u(rng), u(rng), u(rng)});
    const Vec3 to{2 * u(rng), 0.5f * u(rng), 2 * u(rng)};
    const Sweep3 s{b.center(), transformPoint(worldFromMesh, from),
                   transformPoint(worldFromMesh, from + 1.3f * (to - from)),
                   normalize(Quat{u(rng), u(rng), u(rng), u(rng) + 0.01f}),
                   6.0f * Vec3{u(rng), u(rng), u(rng)}};
    const float tMax = q % 5 == 0 ? 0.6f : 1.0f;
    const MeshToiOutput3 a = computeToiMesh(m, worldFromMesh, b, s, tMax);
    expectSameToi(a, bruteToi(m, worldFromMesh, b, s, tMax), q);
    hits += a.status == ToiStatus::hit ? 1 : 0;
    separated += a.status == ToiStatus::separated ? 1 : 0;
    overlapped += a.status == ToiStatus::overlapped ? 1 : 0;
  }
  EXPECT_GT(overlapped, n / 100);
  EXPECT_GT(hits, n / 3);
  EXPECT_GT(separated, n / 12);
}

TEST(Mesh3Penetration, CubeSunkIntoAFlatGridIsItsDepthUp) {
  // A unit cube 5 mm deep in a flat grid: every triangle under it needs it moved up 5 mm;
  // the deepest of them is 5 mm up.
  const Mesh3 m = grid(4, 2, [](float, float) { return 0.0f; });
  const Hull3 cube = makeBox3({0.5f, 0.5f, 0.5f}).value();
  const ShapeProxy3 b = makeProxy(cube);
  const Transform3 worldFromMesh{{1, 2, 3}, Quat::fromAxisAngle({0, 0, 1}, 0.3f)};
  const Transform3 meshFromB{{0.3f, 0.495f, -0.4f}, Quat::fromAxisAngle({0, 1, 0}, 0.5f)};
  const Transform3 worldFromB = worldFromMesh * meshFromB;
  const MeshPenetrationOutput3 p = computePenetrationMesh(m, worldFromMesh, b, worldFromB);
  ASSERT_TRUE(p.overlap);
  EXPECT_NEAR(p.depth, 0.005f, 2e-6f);
  const Vec3 up = transformVector(worldFromMesh, {0, 1, 0});
  EXPECT_NEAR(dot(p.normal, up), 1.0f, 1e-5f);
  EXPECT_GE(p.triangle, 0);
  // Lifted 1 cm clear: not overlapping, the closest triangle's distance.
  const Transform3 lifted = worldFromMesh * Transform3{{0.3f, 0.51f, -0.4f}, meshFromB.q};
  const MeshPenetrationOutput3 apart = computePenetrationMesh(m, worldFromMesh, b, lifted);
  EXPECT_FALSE(apart.overlap);
  EXPECT_EQ(apart.depth, 0.0f);
  EXPECT_EQ(apart.status, Epa3Status::separated);
  EXPECT_NEAR(length(apart.pointA - apart.pointB), 0.01f, 2e-6f);
  EXPECT_EQ(apart.triangle, computeDistanceMesh(m, worldFromMesh, b, lifted).triangle);
}

TEST(Mesh3Penetration, RandomPosesAgreeWithEveryTriangle) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<float> u(-1, 1);
  const Mesh3 field = rollingField();
  const Mesh3 box = closedBox({1.5f, 0.7f, 1.1f});
  const ConvexKinds kinds;
  const std::vector<ShapeProxy3>& shapes = kinds.proxies;
  int overlaps = 0;
  const int n = 300 * testing3::testScale();
  for (int q = 0; q < n; ++q) {
    const Mesh3& m = q % 2 == 0 ? field : box;
    const Transform3 worldFromMesh{{u(rng), u(rng), u(rng)},
                                   normalize(Quat{u(rng), u(rng), u(rng), u(rng) + 0.01f})};
    const ShapeProxy3& b = shapes[static_cast<std::size_t>(q) % shapes.size()];
    const Transform3 worldFromB{
        transformPoint(worldFromMesh, {3 * u(rng), 1.5f * u(rng), 3 * u(rng)}),
        normalize(Quat{u(rng), u(rng), u(rng), u(rng) + 0.01f})};
    const MeshPenetrationOutput3 a = computePenetrationMesh(m, worldFromMesh, b, worldFromB);
    const MeshPenetrationOutput3 r = brutePenetration(m, worldFromMesh, b, worldFromB);
    EXPECT_EQ(a.overlap, r.overlap) << "pose " << q;
    EXPECT_EQ(a.triangle, r.triangle) << "pose " << q;
    EXPECT_EQ(a.depth, r.depth) << "pose " << q;
    EXPECT_EQ(a.normal, r.normal) << "pose " << q;
    EXPECT_EQ(a.pointA, r.pointA) << "pose " << q;
    EXPECT_EQ(a.pointB, r.pointB) << "pose " << q;
    EXPECT_EQ(a.status, r.status) << "pose " << q;
    EXPECT_EQ(a.overlap, testOverlapMesh(m, worldFromMesh, b, worldFromB)) << "pose " << q;
    overlaps += a.overlap ? 1 : 0;
  }
  EXPECT_GT(overlaps, n / 10);
  EXPECT_LT(overlaps, n - n / 10);
}

}  // namespace
}  // namespace quack
