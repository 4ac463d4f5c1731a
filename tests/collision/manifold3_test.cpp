// 3D contact manifolds: hand-worked resting contacts (four points for a box on a box, two
// for a capsule lying on a face or along a capsule), ids that stay put under small motion,
// swapping A and B, and random pairs whose deepest point agrees with EPA / the brute-force
// distance and whose every point lies on both surfaces.

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "oracle3.hpp"
#include "quack/collision/epa3.hpp"
#include "quack/collision/manifold3.hpp"
#include "quack/collision/mesh3.hpp"

namespace quack {
namespace {

using namespace testing3;

constexpr float kTol = 1e-5f;

void expectNear(Vec3 a, Vec3 b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

float deepest(const Manifold3& m) {
  float s = m.points[0].separation;
  for (int i = 1; i < m.pointCount; ++i)
    s = std::min(s, m.points[i].separation);
  return s;
}

std::set<std::uint32_t> ids(const Manifold3& m) {
  std::set<std::uint32_t> out;
  for (int i = 0; i < m.pointCount; ++i)
    out.insert(m.points[i].id);
  return out;
}

TEST(Manifold3, BoxRestingOnBoxHasFourPoints) {
  Hull3 ground = makeBox3({5, 1, 5}).value();
  Hull3 box = makeBox3({0.5f, 0.5f, 0.5f}).value();
  Transform3 tb{{0.3f, 1.5f - 0.01f, -0.2f}, Quat::fromAxisAngle({0, 1, 0}, 0.3f)};
  Manifold3 m = collideHulls(ground, {}, box, tb);
  ASSERT_EQ(m.pointCount, 4);
  EXPECT_NEAR(m.normal.y, 1, kTol);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(m.points[i].separation, -0.01f, kTol);
    EXPECT_NEAR(m.points[i].point.y, 1 - 0.005f, kTol);
  }
  EXPECT_EQ(ids(m).size(), 4u);
  // A small motion keeps the same features, so the same ids.
  Transform3 moved{tb.p + Vec3{1e-3f, 2e-4f, -1e-3f}, tb.q};
  EXPECT_EQ(ids(collideHulls(ground, {}, box, moved)), ids(m));
  // Swapped: the normal flips, the points and separations stay.
  Manifold3 s = collideHulls(box, tb, ground, {});
  ASSERT_EQ(s.pointCount, 4);
  EXPECT_NEAR(s.normal.y, -1, kTol);
  EXPECT_NEAR(deepest(s), -0.01f, kTol);
}

TEST(Manifold3, TwistedBoxesReduceEightPointsToFour) {
  // Two equal boxes face to face, one turned 45 degrees: the overlap is an octagon.
  Hull3 box = makeBox3({1, 1, 1}).value();
  Transform3 tb{{0, 2 - 0.02f, 0}, Quat::fromAxisAngle({0, 1, 0}, 0.25f * kPi)};
  Manifold3 m = collideHulls(box, {}, box, tb);
  ASSERT_EQ(m.pointCount, 4);
  EXPECT_NEAR(deepest(m), -0.02f, kTol);
  // The four kept points span the octagon: the area of their quadrilateral is most of it.
  Vec3 p[4];
  for (int i = 0; i < 4; ++i)
    p[i] = m.points[i].point;
  float area =
      0.5f * (length(cross(p[1] - p[0], p[2] - p[0])) + length(cross(p[2] - p[0], p[3] - p[0])));
  float octagon = 8.0f * (std::sqrt(2.0f) - 1.0f);  // side-1 square and its 45-degree twin
  EXPECT_GT(area, 0.6f * octagon);
}

TEST(Manifold3, CrossedEdgesGiveOnePoint) {
  Hull3 box = makeBox3({1, 1, 1}).value();
  float r2 = std::sqrt(2.0f);
  Transform3 ta{{}, Quat::fromAxisAngle({1, 0, 0}, 0.25f * kPi)};
  Transform3 tb{{0.1f, 2 * r2 - 0.01f, 0.2f}, Quat::fromAxisAngle({0, 0, 1}, 0.25f * kPi)};
  Manifold3 m = collideHulls(box, ta, box, tb);
  ASSERT_EQ(m.pointCount, 1);
  EXPECT_NEAR(m.points[0].separation, -0.01f, 1e-5f);
  EXPECT_NE(m.points[0].id & kManifold3IdEdges, 0u);
  EXPECT_NEAR(m.points[0].point.x, 0.1f, 1e-4f);
  EXPECT_NEAR(m.points[0].point.z, 0.0f, 1e-4f);
}

TEST(Manifold3, CapsuleLyingOnABoxAndAlongACapsule) {
  Hull3 box = makeBox3({2, 1, 2}).value();
  Capsule3 cap = makeCapsule3({-1, 0, 0}, {1, 0, 0}, 0.25f).value();
  Manifold3 m = collideHullAndCapsule(box, {}, cap, {{0.5f, 1.24f, 0.3f}, {}});
  ASSERT_EQ(m.pointCount, 2);
  EXPECT_NEAR(m.normal.y, 1, kTol);
  EXPECT_NEAR(m.points[0].separation, -0.01f, kTol);
  EXPECT_NEAR(m.points[1].separation, -0.01f, kTol);
  // Half over the edge: clipped at x = 2.
  m = collideHullAndCapsule(box, {}, cap, {{1.5f, 1.24f, 0.3f}, {}});
  ASSERT_EQ(m.pointCount, 2);
  EXPECT_NEAR(std::max(m.points[0].point.x, m.points[1].point.x), 2, kTol);
  // Standing up: one point.
  m = collideHullAndCapsule(box, {}, cap,
                            {{0, 2.2f, 0}, Quat::fromAxisAngle({0, 0, 1}, 0.5f * kPi)});
  EXPECT_EQ(m.pointCount, 1);
  EXPECT_NEAR(m.points[0].separation, -0.05f, kTol);
  // Two parallel capsules: two points; crossed: one.
  Manifold3 c = collideCapsules(cap, {}, cap, {{0.5f, 0.45f, 0}, {}});
  ASSERT_EQ(c.pointCount, 2);
  EXPECT_NEAR(c.points[0].separation, -0.05f, kTol);
  c = collideCapsules(cap, {}, cap, {{0, 0.45f, 0}, Quat::fromAxisAngle({0, 1, 0}, 1.0f)});
  EXPECT_EQ(c.pointCount, 1);
}

TEST(Manifold3, SpheresAndSpeculativeDistance) {
  Sphere s = makeSphere({}, 1).value();
  Manifold3 m = collideSpheres(s, {}, s, {{0, 0, 2.01f}, {}});
  ASSERT_EQ(m.pointCount, 1);
  EXPECT_NEAR(m.points[0].separation, 0.01f, kTol);
  EXPECT_EQ(collideSpheres(s, {}, s, {{0, 0, 2.5f}, {}}).pointCount, 0);
  Hull3 box = makeBox3({1, 1, 1}).value();
  m = collideHullAndSphere(box, {}, s, {{0, 0, 1.9f}, {}});
  ASSERT_EQ(m.pointCount, 1);
  EXPECT_NEAR(m.points[0].separation, -0.1f, kTol);
  EXPECT_NEAR(m.normal.z, 1, kTol);
}

TEST(Manifold3, RegressionApartFaceClipMissedTheNearestVertex) {
  // Found by the slow random run (pair 13072): a sliver and a hull 1.5 cm apart, within the
  // speculative distance. SAT chose a face whose clipped incident points were all further
  // than the nearest features (1.63 cm against 1.48 cm); the manifold now falls back to
  // GJK's point when the clip loses SAT's support vertex.
  std::vector<Vec3> pa{{-0.740097344f, 0.213846892f, 0.0192335825f},
                       {0.680381835f, 0.005843536f, 0.00905461516f},
                       {-0.263985276f, 0.274863511f, 0.0191878993f},
                       {0.761431456f, -0.187080443f, -0.0123052876f},
                       {0.29503879f, -0.270674109f, -0.00929864403f},
                       {-0.312593311f, 0.154010758f, -0.00570207601f}};
  std::vector<Vec3> pb{
      {-0.0762140155f, 0.0175658092f, 0.648395181f}, {-0.00838121213f, 0.123399563f, -0.669669211f},
      {0.46472317f, 0.259125441f, -0.22211656f},     {-0.324862987f, -0.301736623f, -0.310452402f},
      {-0.466978818f, 0.22582382f, -0.355622232f},   {0.501687765f, 0.0801637694f, 0.85570693f},
      {-0.387309581f, -0.200965285f, 0.0826375186f}};
  Hull3 a = makeHull3(pa).value(), b = makeHull3(pb).value();
  Transform3 ta{{-0.956360459f, 0.36311698f, 0.425440073f},
                {0.630128503f, -0.694719493f, -0.132639721f, -0.320483416f}};
  Transform3 tb{{-0.996554136f, 0.0681886077f, 1.40086961f},
                {0.755152643f, 0.619742393f, -0.0748410597f, -0.200156271f}};
  DistanceOutput3 d = computeDistance(makeProxy(a), ta, makeProxy(b), tb);
  ASSERT_GT(d.distance, 0.01f);
  Manifold3 m = collideHulls(a, ta, b, tb);
  ASSERT_GT(m.pointCount, 0);
  EXPECT_LE(deepest(m), d.distance + 1e-5f);
  EXPECT_GE(deepest(m), 0.0f);
}

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

TEST(Manifold3, DispatchMatchesThePairRoutinesAndSwaps) {
  const Kind3 kinds[] = {Kind3::sphere, Kind3::capsule, Kind3::triangle, Kind3::box, Kind3::hull};
  std::mt19937 rng(1313);
  for (int i = 0; i < 1500; ++i) {
    Shape3 a = randomShape3(rng, kinds[i % 5], 1.0f, 12),
           b = randomShape3(rng, kinds[(i / 5) % 5], 1.0f, 12);
    Transform3 ta{randomVec(rng, 1), randomQuat(rng)};
    Transform3 tb{ta.p + randomVec(rng, 1.2f), randomQuat(rng)};
    ShapeGeometry3 ga = geometryOf(a), gb = geometryOf(b);
    Manifold3 ab = collide(ga, ta, gb, tb), ba = collide(gb, tb, ga, ta);
    const bool triangle = a.kind == Kind3::triangle || b.kind == Kind3::triangle;
    if (!triangle && a.kind != Kind3::sphere && a.kind != Kind3::capsule &&
        b.kind != Kind3::sphere && b.kind != Kind3::capsule) {
      // Hull pairs: the dispatch is collideHulls itself.
      Manifold3 direct = collideHulls(a.hull, ta, b.hull, tb);
      ASSERT_EQ(ab.pointCount, direct.pointCount) << i;
      for (int k = 0; k < ab.pointCount; ++k)
        EXPECT_EQ(ab.points[k].id, direct.points[k].id) << i;
    }
    // Same types (a box and a hull are both Hull3): either may be the reference, no swap rule.
    if (shapeType(ga) == shapeType(gb)) continue;
    ASSERT_EQ(ab.pointCount, ba.pointCount) << i << " " << name(a.kind) << " " << name(b.kind);
    if (ab.pointCount == 0) continue;
    // A pair routine (collideTriangle for a triangle) in both orders: the same manifold, the
    // normal flipped, anchors swapped.
    expectNear(ab.normal, -ba.normal, 0);
    for (int k = 0; k < ab.pointCount; ++k) {
      EXPECT_EQ(ab.points[k].id, ba.points[k].id) << i;
      EXPECT_EQ(ab.points[k].separation, ba.points[k].separation) << i;
      expectNear(ab.points[k].anchorA, ba.points[k].anchorB, 0);
      expectNear(ab.points[k].anchorA, ab.points[k].point - ta.p, 1e-5f);
    }
  }
}

// Signed distance of a world point from a shape's surface (double).
double surfaceDistance(const Shape3& s, Transform3 t, Vec3 pWorld) {
  Features f = s.features(t);
  D3 p = toD(pWorld);
  if (s.kind == Kind3::sphere) return lenD(p - f.v[0]) - f.radius;
  if (s.kind == Kind3::capsule) return lenD(p - closestOnSegment(p, f.v[0], f.v[1])) - f.radius;
  double best = -1e300;  // hull: the largest face-plane distance
  for (int k = 0; k < s.hull.faceCount; ++k) {
    const HullFace3& face = s.hull.faces[k];
    D3 n = rotateD(t.q, toD(face.normal));
    D3 onFace = transformD(t, s.hull.vertices[s.hull.faceVertices[face.first]]);
    best = std::max(best, dotD(n, p - onFace));
  }
  return best;
}

Manifold3 collideAny(const Shape3& a, Transform3 ta, const Shape3& b, Transform3 tb, float spec) {
  auto isHull = [](Kind3 k) { return k == Kind3::box || k == Kind3::hull; };
  if (isHull(a.kind) && isHull(b.kind)) return collideHulls(a.hull, ta, b.hull, tb, spec);
  if (isHull(a.kind) && b.kind == Kind3::capsule)
    return collideHullAndCapsule(a.hull, ta, b.capsule, tb, spec);
  if (isHull(a.kind) && b.kind == Kind3::sphere)
    return collideHullAndSphere(a.hull, ta, b.sphere, tb, spec);
  if (a.kind == Kind3::capsule && b.kind == Kind3::capsule)
    return collideCapsules(a.capsule, ta, b.capsule, tb, spec);
  if (a.kind == Kind3::capsule && b.kind == Kind3::sphere)
    return collideCapsuleAndSphere(a.capsule, ta, b.sphere, tb, spec);
  return collideSpheres(a.sphere, ta, b.sphere, tb, spec);
}

// A lone triangle is two-sided: a box resting on it from either side has four points, an
// edge or a corner touching it one, a triangle lying on it three.
TEST(Manifold3, LoneTriangleFaceContactsFromEitherSide) {
  const Triangle3 tri = makeTriangle3({-4, 0, -4}, {4, 0, -4}, {0, 0, 5}).value();
  const Hull3 box = makeBox3({0.5f, 0.5f, 0.5f}).value();
  for (float side : {1.0f, -1.0f}) {
    SCOPED_TRACE(side);
    // Rotated about y only: the bottom (or top) face lies flat, 0.01 deep.
    Transform3 tb{{0.2f, side * (0.5f - 0.01f), -0.3f}, Quat::fromAxisAngle({0, 1, 0}, 0.4f)};
    Manifold3 m = collide(tri, {}, box, tb);
    ASSERT_EQ(m.pointCount, 4);
    EXPECT_NEAR(m.normal.y, side, kTol);
    for (int i = 0; i < 4; ++i) {
      EXPECT_NEAR(m.points[i].separation, -0.01f, kTol);
      EXPECT_NEAR(m.points[i].point.y, side * -0.005f, kTol);
    }
    EXPECT_EQ(ids(m).size(), 4u);
    // Box first: the same points, the normal towards the box's side reversed.
    Manifold3 s = collide(box, tb, tri, {});
    ASSERT_EQ(s.pointCount, 4);
    EXPECT_NEAR(s.normal.y, -side, kTol);
    EXPECT_EQ(ids(s), ids(m));
    // Apart by 0.015 (within the speculative distance): four points at +0.015.
    Transform3 above{{0.2f, side * (0.5f + 0.015f), -0.3f}, tb.q};
    Manifold3 a = collide(tri, {}, box, above);
    ASSERT_EQ(a.pointCount, 4);
    for (int i = 0; i < 4; ++i)
      EXPECT_NEAR(a.points[i].separation, 0.015f, kTol);
  }
  // A box beyond the triangle's edge z = -4, tipped 45 degrees about x, so its edge along x
  // reaches 0.01 over the triangle's edge in the triangle's plane. The least push out is
  // along either face of the box at that edge: 0.01 cos 45 deg, one point (the edge rule).
  const float h = 0.5f * std::sqrt(2.0f);
  Transform3 edge{{0, 0, -4 - h + 0.01f}, Quat::fromAxisAngle({1, 0, 0}, 0.785398163f)};
  Manifold3 e = collide(tri, {}, box, edge);
  ASSERT_EQ(e.pointCount, 1);
  EXPECT_NEAR(e.points[0].separation, -0.01f * std::sqrt(0.5f), 1e-5f);
  EXPECT_NEAR(std::fabs(e.normal.y), std::sqrt(0.5f), 1e-3f);
  EXPECT_NEAR(e.normal.z, -std::sqrt(0.5f), 1e-3f);
  // A small triangle lying 0.02 above, parallel, inside: its three corners.
  const Triangle3 small = makeTriangle3({-1, 0, -1}, {1, 0, -1}, {0, 0, 1}).value();
  Transform3 ts{{0.1f, 0.02f, 0.1f}, Quat::fromAxisAngle({0, 1, 0}, 1.0f)};
  Manifold3 t = collide(tri, {}, small, ts, 0.05f);
  ASSERT_EQ(t.pointCount, 3);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(t.points[i].separation, 0.02f, kTol);
  // A sphere above the face: one point, at its bottom.
  const Sphere ball = makeSphere({0, 0, 0}, 0.5f).value();
  Manifold3 b = collide(tri, {}, ball, Transform3{{1, 0.49f, 0}, {}});
  ASSERT_EQ(b.pointCount, 1);
  EXPECT_NEAR(b.points[0].separation, -0.01f, kTol);
  EXPECT_NEAR(b.normal.y, 1, kTol);
}

// Signed distance of a world point from a lone triangle (double): it has no inside, so the
// distance to its surface.
double triangleDistance(const Shape3& s, Transform3 t, Vec3 pWorld) {
  const Features f = s.features(t);
  return lenD(toD(pWorld) - closestOnTriangle(toD(pWorld), f.v[0], f.v[1], f.v[2]));
}

// Random triangles against every kind, and the same pairs swapped: the manifold is empty
// exactly when the brute-force distance (or EPA's depth) is beyond the speculative
// distance; a contact along an edge or a corner is the general one (its separation the
// oracle's); a face manifold's points lie on the triangle and on the other shape's surface,
// and its deepest point is the oracle's to within the slop.
TEST(Manifold3, RandomLoneTrianglesAgreeWithTheOracles) {
  const Kind3 kinds[] = {Kind3::sphere, Kind3::capsule, Kind3::triangle, Kind3::box, Kind3::hull};
  std::mt19937 rng(2027);
  int mismatches = 0, checked = 0, faces = 0;
  const int n = 3000 * testScale();
  for (int i = 0; i < n && mismatches <= 10; ++i) {
    Shape3 a = randomShape3(rng, Kind3::triangle, 1.0f),
           b = randomShape3(rng, kinds[i % 5], 0.6f, 12);
    Transform3 ta{randomVec(rng, 1), randomQuat(rng)};
    Transform3 tb{ta.p + randomVec(rng, 0.6f), randomQuat(rng)};
    const bool flat = i % 3 == 0 && b.kind == Kind3::box;
    if (flat) {
      // A box flat on the face, on either side: its y axis turned onto the triangle's
      // normal (then a face lies along the triangle's plane), shifted along the normal.
      const Features fa = a.features(ta);
      const D3 nD = crossD(fa.v[1] - fa.v[0], fa.v[2] - fa.v[0]);
      const Vec3 nrm = normalize(Vec3{float(nD.x), float(nD.y), float(nD.z)});
      const Vec3 axis = cross(Vec3{0, 1, 0}, nrm);
      const float angle = std::atan2(length(axis), nrm.y);
      tb.q = length(axis) > 1e-6f ? Quat::fromAxisAngle(normalize(axis), angle) : Quat{};
      tb.p = ta.p + uni(rng, -0.6f, 0.6f) * nrm;
    }
    const float spec = kSpeculativeDistance;
    const ShapeGeometry3 ga = geometryOf(a), gb = geometryOf(b);
    const Manifold3 m = collide(ga, ta, gb, tb, spec);
    const PenetrationOutput3 p = computePenetration(a.proxy(), ta, b.proxy(), tb);
    const double expected =
        p.overlap ? -p.depth
                  : bruteCoreDistance(a.features(ta), b.features(tb)) - b.features(tb).radius;
    const D3 faceD = crossD(a.features(ta).v[1] - a.features(ta).v[0],
                            a.features(ta).v[2] - a.features(ta).v[0]);
    const double faceLen = lenD(faceD);
    const double size = a.extent() + b.extent() + lenD(toD(tb.p) - toD(ta.p));
    const double tol = 2e-5 * size;
    bool ok = true;
    if (expected > spec + tol) {
      ok = m.pointCount == 0;
    } else if (expected < spec - tol) {
      ++checked;
      if (m.pointCount == 0) {
        ok = false;
      } else if (std::fabs(dotD(toD(m.normal), faceD)) < kMeshFaceNormalCosine3 * faceLen) {
        // The general contact (an edge or a corner): the oracle's separation.
        ok = std::fabs(deepest(m) - expected) <= tol;
      } else {
        ++faces;
        // Along the face normal: the clipped points hold the deepest one (to within the
        // slop), and, apart, every point is in the triangle's prism, on B, so none is
        // closer than the shapes are.
        ok = deepest(m) >= expected - tol && deepest(m) <= expected + kLinearSlop + tol;
        for (int k = 0; k < m.pointCount && ok; ++k) {
          const ManifoldPoint3& mp = m.points[k];
          const Vec3 onA = mp.point - (0.5f * mp.separation) * m.normal;
          const Vec3 onB = mp.point + (0.5f * mp.separation) * m.normal;
          if (triangleDistance(a, ta, onA) > tol) ok = false;
          // A capsule's two ends each give their sphere's lowest point: on the surface for
          // the lower end, inside the capsule for the higher one when it is tilted.
          const double onSurface = b.kind == Kind3::triangle ? triangleDistance(b, tb, onB)
                                                             : surfaceDistance(b, tb, onB);
          if (onSurface > tol || (b.kind != Kind3::capsule && onSurface < -tol)) ok = false;
          if (mp.separation > spec + tol) ok = false;
        }
      }
    }
    // Swapped: the same manifold mirrored (the triangle is A in both calls unless both are).
    if (b.kind != Kind3::triangle) {
      const Manifold3 s = collide(gb, tb, ga, ta, spec);
      if (s.pointCount != m.pointCount) ok = false;
      for (int k = 0; k < m.pointCount && ok; ++k)
        if (s.points[k].separation != m.points[k].separation) ok = false;
    }
    if (!ok) ++mismatches;
    EXPECT_TRUE(ok) << "pair " << i << " expected " << expected << " got "
                    << (m.pointCount ? deepest(m) : 99.0f) << " points " << m.pointCount << "\nA "
                    << describe(a) << "\nB " << describe(b);
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(checked, n / 4);
  EXPECT_GT(faces, n / 20);
}

TEST(Manifold3, RandomPairsAgreeWithEpaAndLieOnBothSurfaces) {
  // Pairs (A, B) with A at least as "big" a kind as B: hull/box, capsule, sphere.
  const Kind3 kinds[] = {Kind3::hull, Kind3::box, Kind3::capsule, Kind3::sphere};
  std::mt19937 rng(1001);
  int mismatches = 0, checked = 0, multi = 0, facePreferred = 0;
  const int n = 6000 * testScale();
  for (int i = 0; i < n; ++i) {
    int ia = i % 4, ib = ia + (i / 4) % (4 - ia);
    Shape3 a = randomShape3(rng, kinds[ia], 1.0f, 12), b = randomShape3(rng, kinds[ib], 1.0f, 12);
    Vec3 origin = (i % 4 == 3) ? Vec3{1e4f, -1e4f, 1e4f} : Vec3{};
    Transform3 ta{origin + randomVec(rng, 1), randomQuat(rng)};
    Transform3 tb{ta.p + randomVec(rng, 1.2f), randomQuat(rng)};
    const float spec = kSpeculativeDistance;
    Manifold3 m = collideAny(a, ta, b, tb, spec);
    PenetrationOutput3 p = computePenetration(a.proxy(), ta, b.proxy(), tb);
    DistanceOutput3 d = computeDistance(a.proxy(), ta, b.proxy(), tb);
    double size = a.extent() + b.extent() + lenD(toD(tb.p) - toD(ta.p));
    double tol = 2e-5 * size + 4 * 1.2e-7 * lenD(toD(ta.p));
    bool ok = true;
    double expected = p.overlap ? -p.depth : d.distance;
    if (expected > spec + tol) {
      ok = m.pointCount == 0;
    } else if (expected < spec - tol) {
      ++checked;
      // Overlapping: the deepest point is EPA's depth. Apart (speculative): a hull pair
      // reports SAT's separation, a lower bound on the distance (exact for a face and a
      // vertex, conservative otherwise), never a false overlap.
      bool hulls = m.pointCount > 0 && a.kind != Kind3::sphere && a.kind != Kind3::capsule &&
                   b.kind != Kind3::sphere && b.kind != Kind3::capsule;
      if (m.pointCount == 0) {
        ok = false;
      } else if (expected < 0 && hulls) {
        // A face within kLinearSlop of the best (edge) axis is kept, so the deepest point
        // may be that much deeper than EPA's depth; never shallower.
        ok = deepest(m) >= expected - kLinearSlop - tol && deepest(m) <= expected + tol;
        if (deepest(m) < expected - tol) ++facePreferred;
      } else if (expected < 0 || !hulls) {
        ok = std::fabs(deepest(m) - expected) <= tol;
      } else {
        ok = deepest(m) >= -tol && deepest(m) <= expected + tol;
      }
      if (m.pointCount > 1) ++multi;
      // Every point lies on both surfaces: exactly for hull pairs (clipped faces); within
      // the slop for a capsule's two points (kept only while the capsule is parallel to
      // within kLinearSlop, so its ends' true normals differ from the manifold's by that).
      double surfaceTol = (hulls || m.pointCount == 1) ? tol : tol + kLinearSlop;
      for (int k = 0; k < m.pointCount && ok; ++k) {
        const ManifoldPoint3& mp = m.points[k];
        Vec3 onA = mp.point - (0.5f * mp.separation) * m.normal;
        Vec3 onB = mp.point + (0.5f * mp.separation) * m.normal;
        if (std::fabs(surfaceDistance(a, ta, onA)) > surfaceTol) ok = false;
        if (std::fabs(surfaceDistance(b, tb, onB)) > surfaceTol) ok = false;
        if (mp.separation > spec + tol) ok = false;
      }
    }
    if (!ok) ++mismatches;
    EXPECT_TRUE(ok) << "pair " << i << " expected " << expected << " got "
                    << (m.pointCount ? deepest(m) : 99.0f) << " points " << m.pointCount << " tol "
                    << tol << "\nA " << describe(a) << "\nB " << describe(b);
    if (mismatches > 10) break;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(checked, n / 4);
  EXPECT_GT(multi, n / 50);
  EXPECT_GT(facePreferred, 0);  // the tolerance above is used, and only by some pairs
  EXPECT_LT(facePreferred, checked / 10);
}

// The pair cache: hull pairs moving towards and past each other in small steps, the cached
// call beside the plain one at every pose. Wherever the plain manifold touches (a point at
// or below zero separation) the cached one is the same to the bit; wherever the cache
// skipped SAT, GJK's distance is beyond the speculative distance (no contact was lost); and
// the cache does skip (most poses are apart).
TEST(Manifold3, HullPairCacheSkipsOnlyPairsThatAreApart) {
  std::mt19937 rng(2024);
  int skipped = 0, touching = 0;
  for (int pair = 0; pair < 60; ++pair) {
    Shape3 a = randomShape3(rng, Kind3::hull, 1.0f, 12),
           b = randomShape3(rng, Kind3::hull, 1.0f, 12);
    const Transform3 ta{randomVec(rng, 1), randomQuat(rng)};
    const Vec3 start = ta.p + Vec3{4, 0.3f, -0.2f}, end = ta.p + Vec3{-4, -0.3f, 0.2f};
    const Quat q0 = randomQuat(rng);
    HullPairCache3 cache;
    for (int k = 0; k <= 80; ++k) {
      const float t = float(k) / 80.0f;
      const Transform3 tb{(1 - t) * start + t * end,
                          normalize(Quat::fromAxisAngle({0, 1, 0}, 0.05f * float(k)) * q0)};
      const Manifold3 plain = collideHulls(a.hull, ta, b.hull, tb);
      const bool wasValid = cache.valid;
      const Manifold3 cached = collideHulls(a.hull, ta, b.hull, tb, kSpeculativeDistance, cache);
      float deepest = 1e9f;
      for (int n = 0; n < plain.pointCount; ++n)
        deepest = std::min(deepest, plain.points[n].separation);
      if (deepest <= 0.0f) {
        ++touching;
        ASSERT_EQ(cached.pointCount, plain.pointCount) << pair << " " << k;
        for (int n = 0; n < plain.pointCount; ++n) {
          EXPECT_EQ(cached.points[n].separation, plain.points[n].separation);
          EXPECT_EQ(cached.points[n].id, plain.points[n].id);
        }
      }
      if (wasValid && cached.pointCount == 0 && plain.pointCount > 0) {
        // Skipped where SAT's clipping made a speculative point: the shapes are apart.
        const DistanceOutput3 d = computeDistance(a.proxy(), ta, b.proxy(), tb);
        EXPECT_GT(d.distance, kSpeculativeDistance) << pair << " " << k;
      }
      if (wasValid && cached.pointCount == 0) ++skipped;
    }
  }
  EXPECT_GT(touching, 100);
  EXPECT_GT(skipped, 2000);
}

}  // namespace
}  // namespace quack
