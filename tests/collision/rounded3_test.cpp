// Rounded hulls (Hull3::radius) in the narrow phase. Oracles: the cores' brute-force
// feature distance and qhull's Minkowski difference (oracle3.hpp), less or plus the radii;
// each manifold point against the rounded surfaces (the distance to the core by the
// closest point on each face triangle); a rounded box resting on a box, on a floor mesh and
// dropped by a shape cast, worked by hand; casts and times of impact against the oracle's
// distance at the reported time and GJK's sampled along the motion.

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "mesh3_test_util.hpp"
#include "oracle3.hpp"
#include "quack/collision/epa3.hpp"
#include "quack/collision/gjk3.hpp"
#include "quack/collision/manifold3.hpp"
#include "quack/collision/mesh3.hpp"
#include "quack/collision/toi3.hpp"

namespace quack {
namespace {

using namespace testing3;

ShapeGeometry3 geometryOf(const Shape3& s) {
  switch (s.kind) {
    case Kind3::sphere:
      return s.sphere;
    case Kind3::capsule:
      return s.capsule;
    case Kind3::triangle:
      return s.triangle;
    default:
      return s.hull;
  }
}

bool isHull(const Shape3& s) {
  return s.kind == Kind3::box || s.kind == Kind3::hull;
}

// A random shape of `kind`; a box or hull rounded by up to 0.4 of the size half the time
// (always when `rounded`).
Shape3 randomMaybeRounded(std::mt19937& rng, Kind3 kind, bool rounded) {
  Shape3 s = randomShape3(rng, kind, 1.0f, 12);
  if (isHull(s) && (rounded || uni(rng, 0, 1) < 0.5f)) s.hull.radius = uni(rng, 0.01f, 0.4f);
  return s;
}

// Distance from a world point to a shape's core (0 inside a hull's), double.
double coreDistance(const Features& f, D3 p, bool solidCore) {
  if (solidCore && f.t.size() >= 4) {
    // Inside every face plane of a hull (its triangles are wound outwards): inside.
    bool inside = true;
    for (auto [i, j, k] : f.t) {
      D3 n = crossD(f.v[j] - f.v[i], f.v[k] - f.v[i]);
      if (dotD(n, p - f.v[i]) > 0) inside = false;
    }
    if (inside) return 0;
  }
  double best = 1e300;
  for (D3 q : f.v)
    best = std::min(best, lenD(p - q));
  for (auto [i, j] : f.e)
    best = std::min(best, lenD(p - closestOnSegment(p, f.v[i], f.v[j])));
  for (auto [i, j, k] : f.t)
    best = std::min(best, lenD(p - closestOnTriangle(p, f.v[i], f.v[j], f.v[k])));
  return best;
}

// Signed distance of a world point from the shape's rounded surface (< 0 inside).
double surfaceDistance(const Shape3& s, Transform3 t, Vec3 p) {
  Features f = s.features(t);
  return coreDistance(f, toD(p), isHull(s)) - f.radius;
}

// The oracle's answer for a pair: whether the cores overlap, the core distance (apart) or
// depth (overlapping), and the rounded shapes' separation (< 0 overlapping).
struct Truth {
  bool known = false;
  bool coresOverlap = false;
  double core = 0;
  double separation = 0;
};

Truth oracle(const Features& fa, const Features& fb) {
  Truth t;
#if QUACK_HAVE_QHULL
  MinkowskiAnswer m = minkowskiDepth(fa, fb);
  if (!m.ok) return t;
  t.known = true;
  t.coresOverlap = m.inside;
  t.core = m.inside ? m.depth : bruteCoreDistance(fa, fb);
  t.separation = (m.inside ? -m.depth : t.core) - fa.radius - fb.radius;
#else
  (void)fa;
  (void)fb;
#endif
  return t;
}

TEST(Rounded3, RandomPairsAgreeWithTheCoresAndTheRadii) {
#if !QUACK_HAVE_QHULL
  GTEST_SKIP() << "qhull is missing (install Debian libqhull-dev): the depth oracle did not run";
#else
  const Kind3 kinds[] = {Kind3::sphere, Kind3::capsule, Kind3::triangle, Kind3::box, Kind3::hull};
  std::mt19937 rng(2024);
  int mismatches = 0, apart = 0, overlapping = 0, radiiOnly = 0, manifolds = 0, multi = 0;
  const int n = 3000 * testScale();
  const float spec = kSpeculativeDistance;
  for (int i = 0; i < n && mismatches <= 10; ++i) {
    Shape3 a = randomMaybeRounded(rng, i % 2 ? Kind3::hull : Kind3::box, true);
    Shape3 b = randomMaybeRounded(rng, kinds[(i / 2) % 5], false);
    Vec3 origin = (i % 8 == 7) ? Vec3{1e3f, -1e3f, 1e3f} : Vec3{};
    Transform3 ta{origin + randomVec(rng, 0.5f), randomQuat(rng)};
    Transform3 tb{ta.p + randomVec(rng, 1.6f), randomQuat(rng)};
    Features fa = a.features(ta), fb = b.features(tb);
    Truth truth = oracle(fa, fb);
    if (!truth.known) continue;
    double size = a.extent() + b.extent() + lenD(toD(tb.p) - toD(ta.p));
    double tol = 4e-6 * size + 4 * 1.2e-7 * lenD(toD(ta.p));
    const ShapeProxy3 pa = a.proxy(), pb = b.proxy();
    bool ok = true;
    std::string why;
    auto fail = [&](const std::string& w) {
      ok = false;
      why += w + "; ";
    };

    // GJK: the rounded distance and its witnesses; the overlap test.
    DistanceOutput3 d = computeDistance(pa, ta, pb, tb);
    bool overlap = testOverlap(pa, ta, pb, tb);
    if (truth.separation > tol) {
      ++apart;
      if (std::fabs(d.distance - truth.separation) > tol) fail("distance");
      if (overlap) fail("overlap when apart");
      if (std::fabs(surfaceDistance(a, ta, d.pointA)) > 4 * tol) fail("pointA off A");
      if (std::fabs(surfaceDistance(b, tb, d.pointB)) > 4 * tol) fail("pointB off B");
    } else if (truth.separation < -tol) {
      if (d.distance != 0.0f) fail("distance when overlapping");
      if (!overlap) fail("no overlap");
      // EPA: the cores' depth (qhull) plus the radii, or the radii less the core distance.
      PenetrationOutput3 p = computePenetration(pa, ta, pb, tb);
      truth.coresOverlap ? ++overlapping : ++radiiOnly;
      if (!p.overlap || std::fabs(p.depth + truth.separation) > tol) fail("depth");
    }

    // The manifold: the deepest point is the oracle's (a lower bound for apart hull pairs,
    // SAT's face separation); every point is inside or on both rounded shapes and on at
    // least one of them (the reference face's side, or both for a one-point contact).
    Manifold3 m = collide(geometryOf(a), ta, geometryOf(b), tb, spec);
    double surfaceTol = 2e-5 * size + 4 * 1.2e-7 * lenD(toD(ta.p));
    if (truth.separation > spec + tol) {
      if (m.pointCount != 0) fail("points beyond the speculative distance");
    } else if (truth.separation < spec - tol) {
      ++manifolds;
      if (m.pointCount > 1) ++multi;
      bool hulls = isHull(a) && isHull(b);
      float deepest = 1e30f;
      for (int k = 0; k < m.pointCount; ++k)
        deepest = std::min(deepest, m.points[k].separation);
      if (m.pointCount == 0) {
        fail("no points");
      } else if (truth.separation < 0 && hulls) {
        // A face within kLinearSlop of the best (edge) axis is kept (collideHulls): the
        // deepest point may be that much deeper than the truth, never shallower.
        if (deepest > truth.separation + surfaceTol ||
            deepest < truth.separation - kLinearSlop - surfaceTol)
          fail("deepest");
      } else if (truth.separation < 0 || !hulls) {
        if (std::fabs(deepest - truth.separation) > surfaceTol) fail("deepest");
      } else if (deepest < -surfaceTol || deepest > truth.separation + surfaceTol) {
        fail("deepest apart");
      }
      // A capsule's two points hold while it is parallel to within kLinearSlop.
      double slop = b.kind == Kind3::capsule ? kLinearSlop : 0.0;
      for (int k = 0; k < m.pointCount; ++k) {
        const ManifoldPoint3& mp = m.points[k];
        Vec3 onA = mp.point - (0.5f * mp.separation) * m.normal;
        Vec3 onB = mp.point + (0.5f * mp.separation) * m.normal;
        double da = surfaceDistance(a, ta, onA), db = surfaceDistance(b, tb, onB);
        if (da > surfaceTol || db > surfaceTol + slop) fail("a point outside a shape");
        if (std::min(std::fabs(da), std::fabs(db)) > surfaceTol + slop) fail("a point on neither");
        if (mp.separation > spec + tol) fail("a point beyond the speculative distance");
      }
    }
    // The other order (a different type): the same manifold, flipped.
    if (shapeType(geometryOf(a)) != shapeType(geometryOf(b)) && b.kind != Kind3::triangle) {
      Manifold3 r = collide(geometryOf(b), tb, geometryOf(a), ta, spec);
      if (r.pointCount != m.pointCount) fail("swap count");
      for (int k = 0; k < std::min(r.pointCount, m.pointCount); ++k)
        if (r.points[k].separation != m.points[k].separation) fail("swap separation");
    }
    if (!ok) ++mismatches;
    EXPECT_TRUE(ok) << "pair " << i << ": " << why << " truth " << truth.separation << " core "
                    << truth.core << (truth.coresOverlap ? " (cores overlap)" : "") << " distance "
                    << d.distance << " points " << m.pointCount << " tol " << tol << "\nA "
                    << describe(a) << "\nB " << describe(b);
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(apart, n / 10);
  EXPECT_GT(overlapping, n / 10);
  EXPECT_GT(radiiOnly, n / 50);
  EXPECT_GT(multi, n / 100);
  std::printf("  apart %d, cores overlapping %d, radii only %d, manifolds %d (%d multi-point)\n",
              apart, overlapping, radiiOnly, manifolds, multi);
#endif
}

// The rounded hulls' manifold is their cores' with the radii added to the speculative
// distance, each point moved and its separation less the radii.
TEST(Rounded3, HullManifoldIsTheCoresShiftedByTheRadii) {
  std::mt19937 rng(77);
  int compared = 0;
  for (int i = 0; i < 1000; ++i) {
    Shape3 a = randomMaybeRounded(rng, i % 2 ? Kind3::hull : Kind3::box, true);
    Shape3 b = randomMaybeRounded(rng, i % 3 ? Kind3::hull : Kind3::box, false);
    Transform3 ta{randomVec(rng, 0.5f), randomQuat(rng)};
    Transform3 tb{ta.p + randomVec(rng, 1.6f), randomQuat(rng)};
    const float ra = a.hull.radius, rb = b.hull.radius, spec = kSpeculativeDistance;
    Manifold3 m = collideHulls(a.hull, ta, b.hull, tb, spec);
    Hull3 ca = a.hull, cb = b.hull;
    ca.radius = cb.radius = 0;
    Manifold3 c = collideHulls(ca, ta, cb, tb, spec + ra + rb);
    int kept = 0;
    for (int k = 0; k < c.pointCount; ++k) {
      if (c.points[k].separation - (ra + rb) > spec) continue;
      ASSERT_LT(kept, m.pointCount) << i;
      const ManifoldPoint3& p = m.points[kept++];
      EXPECT_EQ(p.id, c.points[k].id) << i;
      EXPECT_NEAR(p.separation, c.points[k].separation - (ra + rb), 1e-6f) << i;
      Vec3 want = c.points[k].point + (0.5f * (ra - rb)) * c.normal;
      EXPECT_NEAR(length(p.point - want), 0, 1e-6f) << i;
      EXPECT_NEAR(length(p.anchorA - (p.point - ta.p)), 0, 1e-6f) << i;
      ++compared;
    }
    EXPECT_EQ(kept, m.pointCount) << i;
  }
  EXPECT_GT(compared, 300);
}

TEST(Rounded3, RoundedBoxRestsOnARoundedBox) {
  // A's top rounded face at y = 0.5 + 0.1; B's bottom at its centre - 0.5 - 0.05; 0.01 deep.
  Hull3 slab = makeBox3({2, 0.5f, 2}, {}, 0.1f).value();
  Hull3 cube = makeBox3({0.5f, 0.5f, 0.5f}, {}, 0.05f).value();
  Transform3 ta{{0, 0, 0}, {}}, tb{{0.2f, 0.5f + 0.1f + 0.05f + 0.5f - 0.01f, -0.3f}, {}};
  Manifold3 m = collideHulls(slab, ta, cube, tb);
  ASSERT_EQ(m.pointCount, 4);
  EXPECT_NEAR(m.normal.y, 1, 1e-6f);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(m.points[k].separation, -0.01f, 1e-5f);
    EXPECT_NEAR(m.points[k].point.y, 0.595f, 1e-5f);  // midway between 0.6 and 0.59
    EXPECT_NEAR(std::fabs(m.points[k].point.x - 0.2f), 0.5f, 1e-5f);
    EXPECT_NEAR(std::fabs(m.points[k].point.z + 0.3f), 0.5f, 1e-5f);
  }
  // Lifted 0.015 (0.005 apart): still four speculative points; 0.03 apart: none.
  tb.p.y += 0.015f;
  m = collideHulls(slab, ta, cube, tb, 0.02f);
  ASSERT_EQ(m.pointCount, 4);
  EXPECT_NEAR(m.points[0].separation, 0.005f, 1e-5f);
  tb.p.y += 0.025f;
  EXPECT_EQ(collideHulls(slab, ta, cube, tb, 0.02f).pointCount, 0);
  // GJK and EPA agree: 0.03 apart, and 0.01 deep back down.
  EXPECT_NEAR(computeDistance(makeProxy(slab), ta, makeProxy(cube), tb).distance, 0.03f, 1e-5f);
  tb.p.y -= 0.04f;
  PenetrationOutput3 p = computePenetration(makeProxy(slab), ta, makeProxy(cube), tb);
  EXPECT_NEAR(p.depth, 0.01f, 1e-5f);
  EXPECT_NEAR(p.normal.y, 1, 1e-5f);
  // A sphere at the slab's rounded corner: the core corner's distance less both radii.
  Sphere s = makeSphere({}, 0.2f).value();
  Transform3 ts{{2.5f, 1.0f, 2.5f}, {}};
  float want = std::sqrt(3 * 0.25f) - 0.1f - 0.2f;
  EXPECT_NEAR(computeDistance(makeProxy(slab), ta, makeProxy(s), ts).distance, want, 1e-5f);
  m = collideHullAndSphere(slab, ta, s, ts, 1.0f);
  ASSERT_EQ(m.pointCount, 1);
  EXPECT_NEAR(m.points[0].separation, want, 1e-5f);
  // A capsule lying on the slab's rounded top: two points, 0.01 deep.
  Capsule3 c = makeCapsule3({-1, 0, 0}, {1, 0, 0}, 0.25f).value();
  Transform3 tc{{0.1f, 0.6f + 0.25f - 0.01f, 0.4f}, {}};
  m = collide(ShapeGeometry3{slab}, ta, ShapeGeometry3{c}, tc);
  ASSERT_EQ(m.pointCount, 2);
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(m.points[k].separation, -0.01f, 1e-5f);
    EXPECT_NEAR(m.points[k].point.y, 0.595f, 1e-5f);
  }
}

TEST(Rounded3, RoundedBoxRestsOnAFloorMesh) {
  Mesh3 floor = testing::grid(2, 4.0f, [](float, float) { return 0.0f; });
  Hull3 cube = makeBox3({0.5f, 0.5f, 0.5f}, {}, 0.1f).value();
  for (float heading : {0.0f, 0.4f, 1.1f}) {
    Transform3 tb{{0.3f, 0.5f + 0.1f - 0.005f, -0.2f}, Quat::fromAxisAngle({0, 1, 0}, heading)};
    std::vector<MeshContact3> contacts;
    collideMesh(floor, {}, ShapeGeometry3{cube}, tb, contacts);
    ASSERT_FALSE(contacts.empty());
    int points = 0;
    for (const MeshContact3& c : contacts) {
      EXPECT_NEAR(c.manifold.normal.y, 1, 1e-6f);
      for (int k = 0; k < c.manifold.pointCount; ++k) {
        ++points;
        EXPECT_NEAR(c.manifold.points[k].separation, -0.005f, 1e-5f);
        EXPECT_NEAR(c.manifold.points[k].point.y, -0.0025f, 1e-5f);
      }
    }
    EXPECT_GE(points, 4);
  }
  // The mesh's penetration and a lone triangle's contact see the rounding too; a rounded
  // cube dropped onto the floor by a time of impact stops with its rounding at the target.
  Transform3 tb{{0.3f, 0.5f + 0.1f - 0.005f, -0.2f}, {}};
  MeshPenetrationOutput3 p = computePenetrationMesh(floor, {}, makeProxy(cube), tb);
  ASSERT_TRUE(p.overlap);
  EXPECT_NEAR(p.depth, 0.005f, 1e-5f);
  const Triangle3 lone = makeTriangle3({-3, 0, 3}, {3, 0, 3}, {0, 0, -3}).value();
  Manifold3 m = collide(ShapeGeometry3{lone}, {}, ShapeGeometry3{cube}, tb);
  ASSERT_GE(m.pointCount, 3);
  for (int k = 0; k < m.pointCount; ++k)
    EXPECT_NEAR(m.points[k].separation, -0.005f, 1e-5f);
  Sweep3 drop = makeSweep3({}, {{0, 2, 0}, {}}, {{0, -1, 0}, {}});
  MeshToiOutput3 t = computeToiMesh(floor, {}, makeProxy(cube), drop);
  ASSERT_EQ(t.status, ToiStatus::hit);
  // The rounded bottom at 2 - 0.6 - 3 t reaches the target above y = 0.
  const float want = (2 - 0.6f - kToiTargetSeparation) / 3;
  EXPECT_NEAR(t.t, want, kToiTolerance / 3 + 1e-5f);
}

TEST(Rounded3, ShapeCastOfARoundedBoxHitsWhereItsRoundingTouches) {
  Hull3 slab = makeBox3({2, 0.5f, 2}).value();
  Hull3 cube = makeBox3({0.5f, 0.5f, 0.5f}, {}, 0.1f).value();
  // Bottom of the rounded cube at 2 - 0.6 = 1.4, the slab's top at 0.5: 0.9 of 2 m.
  ShapeCastOutput3 c = castShape(makeProxy(slab), {}, makeProxy(cube), {{0, 2, 0}, {}}, {0, -2, 0});
  ASSERT_EQ(c.status, ShapeCastStatus::hit);
  EXPECT_NEAR(c.fraction, 0.45f, kShapeCastTolerance / 2 + 1e-6f);
  EXPECT_NEAR(c.normal.y, 1, 1e-4f);
}

// Casts and times of impact with rounded hulls: at a hit, the oracle's distance (the cores'
// brute force less the radii) is within the cast's tolerance or the time of impact's band;
// GJK sampled along the motion finds nothing closer before it.
TEST(Rounded3, CastsAndTimesOfImpactAgainstTheOracle) {
  const Kind3 kinds[] = {Kind3::sphere, Kind3::capsule, Kind3::box, Kind3::hull};
  std::mt19937 rng(99);
  int mismatches = 0, castHits = 0, toiHits = 0;
  for (int i = 0; i < 300; ++i) {
    Shape3 a = randomMaybeRounded(rng, i % 2 ? Kind3::hull : Kind3::box, true);
    Shape3 b = randomMaybeRounded(rng, kinds[(i / 2) % 4], false);
    Transform3 ta{randomVec(rng, 0.5f), randomQuat(rng)};
    Transform3 tb{3.0f * normalize(randomVec(rng, 1) + Vec3{1e-3f, 0, 0}), randomQuat(rng)};
    Vec3 move = -tb.p + randomVec(rng, 1.5f);
    bool ok = true;
    auto oracleAt = [&](Transform3 wa, Transform3 wb) {
      Features fa = a.features(wa), fb = b.features(wb);
      return bruteCoreDistance(fa, fb) - fa.radius - fb.radius;
    };
    ShapeCastOutput3 c = castShape(a.proxy(), ta, b.proxy(), tb, move);
    if (c.status == ShapeCastStatus::hit) {
      ++castHits;
      double dh = oracleAt(ta, {tb.p + c.fraction * move, tb.q});
      if (dh < -1e-5 || dh > kShapeCastTolerance + 1e-5) ok = false;
      for (int k = 0; k < 100 && ok; ++k) {
        float s = c.fraction * float(k) / 100;
        if (computeDistance(a.proxy(), ta, b.proxy(), {tb.p + s * move, tb.q}).distance <= 0.0f)
          ok = false;
      }
    } else if (c.status == ShapeCastStatus::missed) {
      if (oracleAt(ta, {tb.p + move, tb.q}) <= 0) ok = false;
    }
    Sweep3 sa{{}, ta.p, ta.p + randomVec(rng, 0.3f), ta.q, randomVec(rng, 1.0f)};
    Sweep3 sb{{}, tb.p, tb.p + move, tb.q, randomVec(rng, 2.0f)};
    ToiOutput3 t = computeToi(a.proxy(), sa, b.proxy(), sb);
    if (t.status == ToiStatus::hit) {
      ++toiHits;
      double dh = oracleAt(transformAt(sa, t.t), transformAt(sb, t.t));
      if (dh < kToiTargetSeparation - 2e-5 || dh > kToiTargetSeparation + kToiTolerance + 2e-5)
        ok = false;
      for (int k = 0; k < 100 && ok; ++k) {
        float s = t.t * float(k) / 100;
        if (computeDistance(a.proxy(), transformAt(sa, s), b.proxy(), transformAt(sb, s)).distance <
            kToiTargetSeparation - 2e-5f)
          ok = false;
      }
    }
    if (!ok) ++mismatches;
    EXPECT_TRUE(ok) << "pair " << i << " cast " << toString(c.status) << " " << c.fraction
                    << " toi " << toString(t.status) << " " << t.t << "\nA " << describe(a)
                    << "\nB " << describe(b);
    if (mismatches > 10) break;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(castHits, 30);
  EXPECT_GT(toiHits, 30);
}

}  // namespace
}  // namespace quack
