// The 3D shapes: make* errors, mass properties against closed forms and an independent
// slice integration, and ray casts against an independent containment test sampled along
// the ray.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "quack/geometry/mass3.hpp"
#include "quack/geometry/raycast3.hpp"
#include "quack/geometry/shapes3.hpp"

namespace quack {
namespace {

constexpr double kPiD = 3.14159265358979323846;

void expectNear(Mat3 a, Mat3 b, double tol) {
  const float* pa = &a.cx.x;
  const float* pb = &b.cx.x;
  for (int i = 0; i < 9; ++i)
    EXPECT_NEAR(pa[i], pb[i], tol) << "entry " << i;
}

Quat randomQuat(std::mt19937& rng) {
  std::normal_distribution<float> n(0, 1);
  return normalize(Quat{n(rng), n(rng), n(rng), n(rng)});
}

TEST(Shapes3, MakeErrorsNameTheArgument) {
  EXPECT_NE(makeSphere({0, NAN, 0}, 1).error().message.find("sphere center"), std::string::npos);
  EXPECT_NE(makeSphere({}, 0).error().message.find("sphere radius must be > 0"), std::string::npos);
  EXPECT_NE(makeSphere({}, -1).error().message.find("got -1"), std::string::npos);
  EXPECT_NE(makeCapsule3({}, {0, 1, 0}, INFINITY).error().message.find("capsule radius"),
            std::string::npos);
  EXPECT_NE(makeCapsule3({1, 1, 1}, {1, 1, 1}, 1).error().message.find("use a sphere"),
            std::string::npos);
  EXPECT_NE(makeCapsule3({}, {2e9f, 0, 0}, 1).error().message.find("capsule p2"),
            std::string::npos);
  EXPECT_NE(makeTriangle3({}, {1, 1, 1}, {2, 2, 2}).error().message.find("no area"),
            std::string::npos);
  EXPECT_NE(makeTriangle3({}, {NAN, 0, 0}, {0, 1, 0}).error().message.find("triangle v[1]"),
            std::string::npos);
  EXPECT_TRUE(makeTriangle3({}, {1, 0, 0}, {0, 1, 0}).ok());
  EXPECT_TRUE(makeSphere({1, 2, 3}, 0.5f).ok());
}

TEST(Shapes3, GeometryVariantDispatchesAndValidates) {
  ShapeGeometry3 sphere = makeSphere({1, 0, 0}, 2).value();
  ShapeGeometry3 hull = makeBox3({1, 2, 3}).value();
  EXPECT_EQ(shapeType(sphere), ShapeType3::sphere);
  EXPECT_EQ(shapeType(hull), ShapeType3::hull);
  EXPECT_STREQ(toString(shapeType(hull)), "hull");
  EXPECT_NEAR(computeMass(hull, 1).volume, 48, 1e-4f);
  EXPECT_NEAR(computeMass(sphere, 1).volume, computeMass(std::get<Sphere>(sphere), 1).volume, 0);
  RayHit3 h = rayCast(hull, {{0, 10, 0}, {0, -20, 0}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, 0.4f, 1e-6f);
  EXPECT_TRUE(validateShape(sphere).ok());
  EXPECT_TRUE(validateShape(hull).ok());
  EXPECT_NE(validateShape(Sphere{{0, NAN, 0}, 1}).message().find("sphere center"),
            std::string::npos);
  EXPECT_NE(validateShape(Capsule3{{}, {1, 0, 0}, 0}).message().find("capsule radius"),
            std::string::npos);
  EXPECT_NE(validateShape(Triangle3{{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}}).message().find("no area"),
            std::string::npos);
  EXPECT_NE(validateShape(Hull3{}).message().find("vertexCount"), std::string::npos);
}

TEST(Mass3, SphereClosedForm) {
  MassProperties3 m = computeMass(makeSphere({1, 2, 3}, 2).value(), 3.0f);
  double vol = 4.0 / 3.0 * kPiD * 8.0;
  EXPECT_NEAR(m.volume, vol, 1e-5 * vol);
  EXPECT_NEAR(m.mass, 3.0 * vol, 3e-5 * vol);
  expectNear(m.inertia, Mat3::diagonal(Vec3{1, 1, 1} * float(0.4 * 3.0 * vol * 4.0)), 1e-3);
  EXPECT_EQ(m.centroid, (Vec3{1, 2, 3}));
}

TEST(Mass3, BoxHullIsTheBoxClosedForm) {
  // A box of half-extents (a, b, c) and mass m: I = m/3 diag(b^2 + c^2, a^2 + c^2, a^2 + b^2).
  float a = 0.5f, b = 1.5f, c = 2.5f, rho = 2.0f;
  MassProperties3 m = computeMass(makeBox3({a, b, c}).value(), rho);
  double mass = rho * 8.0 * a * b * c;
  EXPECT_NEAR(m.volume, 8.0 * a * b * c, 1e-5);
  EXPECT_NEAR(m.mass, mass, 1e-4);
  expectNear(
      m.inertia,
      Mat3::diagonal(Vec3{float(mass / 3 * (b * b + c * c)), float(mass / 3 * (a * a + c * c)),
                          float(mass / 3 * (a * a + b * b))}),
      1e-4 * mass);
  EXPECT_NEAR(length(m.centroid), 0, 1e-6);
  // Rotated and moved: I' = R I R^T about the moved centroid.
  std::mt19937 rng(9);
  for (int i = 0; i < 50; ++i) {
    Quat q = randomQuat(rng);
    Vec3 p{100, -50, 2000};
    MassProperties3 r = computeMass(makeBox3({a, b, c}, {p, q}).value(), rho);
    Mat3 R = toMat3(q);
    expectNear(r.inertia, R * m.inertia * transpose(R), 2e-3 * mass);
    EXPECT_NEAR(r.mass, mass, 1e-4 * mass);
    EXPECT_NEAR(distance(r.centroid, p), 0, 2e-3);
  }
}

TEST(Mass3, CornerTetrahedronClosedForm) {
  // Tetrahedron (0, a e1, b e2, c e3): volume abc/6, centroid (a, b, c)/4, about the
  // centroid Ixx = 3m(b^2 + c^2)/80 and Ixy = m ab / 80 (the product of inertia's sign as
  // in I = trace(C) Id - C).
  double a = 1, b = 2, c = 3;
  std::vector<Vec3> pts{{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
  MassProperties3 m = computeMass(makeHull3(pts).value(), 1.0f);
  double mass = a * b * c / 6;
  EXPECT_NEAR(m.volume, mass, 1e-6);
  EXPECT_NEAR(m.centroid.x, a / 4, 1e-6);
  EXPECT_NEAR(m.centroid.y, b / 4, 1e-6);
  EXPECT_NEAR(m.centroid.z, c / 4, 1e-6);
  Mat3 ref = Mat3::fromRows(
      {float(3 * mass * (b * b + c * c) / 80), float(mass * a * b / 80), float(mass * a * c / 80)},
      {float(mass * a * b / 80), float(3 * mass * (a * a + c * c) / 80), float(mass * b * c / 80)},
      {float(mass * a * c / 80), float(mass * b * c / 80), float(3 * mass * (a * a + b * b) / 80)});
  expectNear(m.inertia, ref, 1e-6);
}

TEST(Mass3, RegularTetrahedronIsIsotropic) {
  // Regular tetrahedron of edge L: I = m L^2 / 20 about every axis through the centroid.
  std::vector<Vec3> pts{{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  double L = std::sqrt(8.0);
  MassProperties3 m = computeMass(makeHull3(pts).value(), 1.0f);
  EXPECT_NEAR(m.volume, L * L * L / (6 * std::sqrt(2.0)), 1e-5);
  double i = m.mass * L * L / 20;
  expectNear(m.inertia, Mat3::diagonal(Vec3{float(i), float(i), float(i)}), 1e-5);
}

TEST(Mass3, CapsuleAgainstSliceIntegration) {
  // Independent oracle: the capsule along its axis as disks of radius rho(s), integrated by
  // Simpson's rule in double: m = int pi rho^2, I_axis = int pi rho^4 / 2,
  // I_perp = int pi rho^2 (rho^2 / 4 + s^2) about the centre.
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-3, 3), rr(0.1f, 2.0f);
  for (int trial = 0; trial < 20; ++trial) {
    Vec3 p1{u(rng), u(rng), u(rng)}, p2{u(rng), u(rng), u(rng)};
    float r = rr(rng);
    Capsule3 cap = makeCapsule3(p1, p2, r).value();
    double h = distance(p1, p2);
    const int n = 20000;
    double lo = -h / 2 - r, hi = h / 2 + r, step = (hi - lo) / n;
    double mass = 0, iAxis = 0, iPerp = 0;
    for (int k = 0; k <= n; ++k) {
      double s = lo + k * step;
      double e = std::fabs(s) - h / 2;
      double rho2 = e <= 0 ? double(r) * r : std::max(0.0, double(r) * r - e * e);
      double w = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
      w *= step / 3;
      mass += w * kPiD * rho2;
      iAxis += w * kPiD * rho2 * rho2 / 2;
      iPerp += w * kPiD * rho2 * (rho2 / 4 + s * s);
    }
    MassProperties3 m = computeMass(cap, 1.0f);
    EXPECT_NEAR(m.mass, mass, 1e-4 * mass);
    Vec3 ax = normalize(p2 - p1);
    Vec3 perp = normalize(cross(ax, std::fabs(ax.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
    EXPECT_NEAR(dot(ax, m.inertia * ax), iAxis, 1e-4 * iAxis);
    EXPECT_NEAR(dot(perp, m.inertia * perp), iPerp, 1e-4 * iPerp);
    EXPECT_NEAR(length(m.inertia * ax - dot(ax, m.inertia * ax) * ax), 0, 1e-4 * iPerp);
  }
}

TEST(Mass3, TriangleHasNoVolume) {
  MassProperties3 m = computeMass(makeTriangle3({0, 0, 0}, {3, 0, 0}, {0, 3, 0}).value(), 1.0f);
  EXPECT_EQ(m.mass, 0.0f);
  EXPECT_EQ(m.centroid, (Vec3{1, 1, 0}));
}

// Independent containment tests (double), for the ray-cast oracle.
double segDist(Vec3 p, Vec3 a, Vec3 b) {
  double ab[3] = {b.x - a.x, double(b.y) - a.y, double(b.z) - a.z};
  double ap[3] = {p.x - a.x, double(p.y) - a.y, double(p.z) - a.z};
  double len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  double t = len2 > 0 ? (ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2]) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  double d[3] = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}
double signedDist(const Sphere& s, Vec3 p) {
  return segDist(p, s.center, s.center) - s.radius;
}
double signedDist(const Capsule3& c, Vec3 p) {
  return segDist(p, c.p1, c.p2) - c.radius;
}
double signedDist(const Hull3& h, Vec3 p) {  // max plane distance: <= 0 inside
  double best = -1e300;
  for (int f = 0; f < h.faceCount; ++f)
    best = std::max(best, double(dot(h.faces[f].normal, p)) - h.faces[f].offset);
  return best;
}

// For random rays: a hit's point is on the surface, its normal agrees with the surface,
// and no sample before it is inside; a miss has no sample inside; a ray from inside misses.
template <class Shape>
void checkRays(const Shape& shape, Vec3 centre, float size, std::mt19937& rng, int count) {
  std::uniform_real_distribution<float> u(-1, 1);
  int hits = 0;
  for (int i = 0; i < count; ++i) {
    RayCastInput3 ray{centre + 2.0f * size * Vec3{u(rng), u(rng), u(rng)},
                      3.0f * size * Vec3{u(rng), u(rng), u(rng)}, 1.0f};
    RayHit3 hit = rayCast(shape, ray);
    double tol = 2e-5 * size;
    bool startsInside = signedDist(shape, ray.origin) <= 0;
    if (startsInside) {
      EXPECT_FALSE(hit.hit);
      continue;
    }
    float end = hit.hit ? hit.fraction : ray.maxFraction;
    for (int k = 0; k < 200; ++k) {
      Vec3 p = ray.origin + (end * float(k) / 200.0f) * ray.translation;
      ASSERT_GT(signedDist(shape, p), -tol) << "a sample before the reported entry is inside";
    }
    if (!hit.hit) continue;
    ++hits;
    EXPECT_NEAR(signedDist(shape, hit.point), 0, tol);
    EXPECT_NEAR(length(hit.normal), 1, 1e-5);
    EXPECT_LT(dot(hit.normal, ray.translation), 0);
    // Just past the entry along the normal's opposite is inside.
    EXPECT_LT(signedDist(shape, hit.point - 1e-3f * size * hit.normal), 0);
  }
  EXPECT_GT(hits, count / 20);
}

TEST(RayCast3, SphereCapsuleHullAgainstContainment) {
  std::mt19937 rng(31);
  checkRays(makeSphere({1, 2, 3}, 1.5f).value(), {1, 2, 3}, 1.5f, rng, 2000);
  checkRays(makeCapsule3({-1, 0, 0}, {1, 1, 0.5f}, 0.7f).value(), {0, 0.5f, 0.25f}, 1.5f, rng,
            2000);
  Hull3 box = makeBox3({1, 0.5f, 2}, {{3, 0, 0}, randomQuat(rng)}).value();
  checkRays(box, {3, 0, 0}, 2.0f, rng, 2000);
  std::vector<Vec3> pts;
  std::normal_distribution<float> n(0, 1);
  for (int i = 0; i < 40; ++i)
    pts.push_back(normalize(Vec3{n(rng), n(rng), n(rng)}));
  checkRays(makeHull3(pts).value(), {}, 1.0f, rng, 2000);
}

TEST(RayCast3, HandWorked) {
  RayHit3 h = rayCast(makeSphere({0, 0, 0}, 1).value(), {{-3, 0, 0}, {4, 0, 0}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, 0.5f, 1e-6f);
  EXPECT_NEAR(h.normal.x, -1, 1e-6f);
  Hull3 box = makeBox3({1, 1, 1}).value();
  h = rayCast(box, {{0, 5, 0}, {0, -10, 0}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, 0.4f, 1e-6f);
  EXPECT_NEAR(h.normal.y, 1, 1e-6f);
  EXPECT_FALSE(rayCast(box, {{0, 0, 0}, {0, -10, 0}, 1}).hit);     // starts inside
  EXPECT_FALSE(rayCast(box, {{0, 5, 0}, {0, -10, 0}, 0.3f}).hit);  // too short
  EXPECT_FALSE(rayCast(box, {{0, 5, 0}, {0, 0, 0}, 1}).hit);       // zero translation
  Capsule3 cap = makeCapsule3({0, -1, 0}, {0, 1, 0}, 0.5f).value();
  h = rayCast(cap, {{2, 0.3f, 0}, {-4, 0, 0}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, 1.5f / 4, 1e-6f);
  h = rayCast(cap, {{0, 3, 0}, {0, -4, 0}, 1});  // end cap
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, 0.375f, 1e-6f);
  EXPECT_NEAR(h.normal.y, 1, 1e-6f);
  Triangle3 tri = makeTriangle3({0, 0, 0}, {2, 0, 0}, {0, 2, 0}).value();
  h = rayCast(tri, {{0.5f, 0.5f, 3}, {0, 0, -6}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, 0.5f, 1e-6f);
  EXPECT_NEAR(h.normal.z, 1, 1e-6f);
  h = rayCast(tri, {{0.5f, 0.5f, -3}, {0, 0, 6}, 1});  // two-sided: the normal faces the ray
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.normal.z, -1, 1e-6f);
  EXPECT_FALSE(rayCast(tri, {{1.5f, 1.5f, 3}, {0, 0, -6}, 1}).hit);  // beyond the hypotenuse
  EXPECT_FALSE(rayCast(tri, {{-1, 0.5f, 0}, {5, 0, 0}, 1}).hit);     // in its plane
}

}  // namespace
}  // namespace quack
