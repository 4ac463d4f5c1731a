// Rounded hulls (a Hull3 with a radius: the points within it of the polyhedron): make*
// errors, mass properties against a rounded box worked by hand (a different decomposition:
// slabs, quarter cylinders and ball octants along the axes), Steiner's volume formula,
// Monte Carlo integration over random rounded hulls with its standard error, the plain
// hull at r = 0, and ray casts against an independent containment test (the distance to
// the core by the closest point on each face triangle, in double) sampled along the ray.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "quack/geometry/mass3.hpp"
#include "quack/geometry/raycast3.hpp"
#include "quack/geometry/shapes3.hpp"

namespace quack {
namespace {

constexpr double kPiD = 3.14159265358979323846;

struct V {
  double x = 0, y = 0, z = 0;
};
V operator-(V a, V b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
V operator+(V a, V b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
V operator*(double s, V a) {
  return {s * a.x, s * a.y, s * a.z};
}
double dotV(V a, V b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
V toV(Vec3 v) {
  return {v.x, v.y, v.z};
}

// Closest point on segment ab to p.
V onSegment(V p, V a, V b) {
  V ab = b - a;
  double t = std::clamp(dotV(p - a, ab) / dotV(ab, ab), 0.0, 1.0);
  return a + t * ab;
}

// Closest point on triangle abc to p: the plane's foot when it is inside (barycentric), else
// the nearest of the three edges.
V onTriangle(V p, V a, V b, V c) {
  V ab = b - a, ac = c - a, ap = p - a;
  double d00 = dotV(ab, ab), d01 = dotV(ab, ac), d11 = dotV(ac, ac);
  double d20 = dotV(ap, ab), d21 = dotV(ap, ac);
  double den = d00 * d11 - d01 * d01;
  double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
  if (v >= 0 && w >= 0 && v + w <= 1) return a + v * ab + w * ac;
  V best = onSegment(p, a, b);
  for (V q : {onSegment(p, b, c), onSegment(p, c, a)})
    if (dotV(p - q, p - q) < dotV(p - best, p - best)) best = q;
  return best;
}

// The core's closest point to p (p itself inside), by the face planes and every face
// triangle of the hull.
V closestOnCore(const Hull3& h, V p) {
  bool inside = true;
  for (int f = 0; f < h.faceCount; ++f)
    inside = inside && dotV(toV(h.faces[f].normal), p) - h.faces[f].offset <= 0;
  if (inside) return p;
  V best;
  double bestD = 1e300;
  for (int f = 0; f < h.faceCount; ++f) {
    const HullFace3& face = h.faces[f];
    V a = toV(h.vertices[h.faceVertices[face.first]]);
    for (int k = 1; k + 1 < face.count; ++k) {
      V q = onTriangle(p, a, toV(h.vertices[h.faceVertices[face.first + k]]),
                       toV(h.vertices[h.faceVertices[face.first + k + 1]]));
      double dq = dotV(p - q, p - q);
      if (dq < bestD) {
        bestD = dq;
        best = q;
      }
    }
  }
  return best;
}

// Signed distance from the rounded surface (<= 0 inside); exact outside the core, -r inside.
double roundedDistance(const Hull3& h, V p) {
  V q = closestOnCore(h, p);
  return std::sqrt(dotV(p - q, p - q)) - h.radius;
}

Quat randomQuat(std::mt19937& rng) {
  std::normal_distribution<float> n(0, 1);
  return normalize(Quat{n(rng), n(rng), n(rng), n(rng)});
}

Hull3 randomHull(std::mt19937& rng, int points, float radius) {
  std::normal_distribution<float> g(0, 1);
  std::uniform_real_distribution<float> u(0.4f, 1.0f);
  Vec3 axes{u(rng), u(rng), u(rng)};
  std::vector<Vec3> pts;
  for (int i = 0; i < points; ++i) {
    Vec3 p = normalize(Vec3{g(rng), g(rng), g(rng)});
    pts.push_back({p.x * axes.x + 0.3f, p.y * axes.y - 0.2f, p.z * axes.z + 0.1f});
  }
  return makeHull3(pts, radius).value();
}

TEST(RoundedHull3, MakeAndValidateRefuseBadRadii) {
  const Vec3 pts[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_NE(makeHull3(pts, -0.1f).error().message.find("hull radius must be >= 0, got -0.1"),
            std::string::npos);
  EXPECT_NE(makeHull3(pts, NAN).error().message.find("hull radius is not finite"),
            std::string::npos);
  EXPECT_NE(makeHull3(pts, INFINITY).error().message.find("hull radius is not finite"),
            std::string::npos);
  EXPECT_NE(makeHull3(pts, 2e9f).error().message.find("hull radius 2e+09 m is beyond"),
            std::string::npos);
  EXPECT_NE(makeBox3({1, 1, 1}, {}, -1).error().message.find("box radius must be >= 0"),
            std::string::npos);
  Hull3 h = makeHull3(pts, 0.25f).value();
  EXPECT_EQ(h.radius, 0.25f);
  EXPECT_EQ(makeHull3(pts).value().radius, 0.0f);
  EXPECT_TRUE(validateHull3(h).ok());
  h.radius = NAN;
  EXPECT_NE(validateShape(h).message().find("hull.radius"), std::string::npos);
  h.radius = -1;
  EXPECT_NE(validateHull3(h).message().find("hull.radius"), std::string::npos);
}

// The rounded box [-a, a] x [-b, b] x [-c, c] grown by r, by hand: the integral of x^2 over
// the box, the two slabs across x, the four slabs along x, the quarter cylinders along x
// (x^2 over their length) and along y and z (quarter disks at x = +-a), and the ball octants.
double secondMomentX(double a, double b, double c, double r) {
  double core = (2 * a * a * a / 3) * (2 * b) * (2 * c);
  double slabsAcross = 2 * 4 * b * c * (std::pow(a + r, 3) - a * a * a) / 3;
  double slabsAlong = 2 * (2 * a * a * a / 3) * r * (2 * c) + 2 * (2 * a * a * a / 3) * r * (2 * b);
  double cylAlong = 4 * (2 * a * a * a / 3) * (kPiD * r * r / 4);
  double quarterDisk =
      a * a * kPiD * r * r / 4 + 2 * a * r * r * r / 3 + kPiD * std::pow(r, 4) / 16;
  double cylAcross = 4 * quarterDisk * (2 * b) + 4 * quarterDisk * (2 * c);
  double octant = a * a * kPiD * r * r * r / 6 + 2 * a * kPiD * std::pow(r, 4) / 16 +
                  kPiD * std::pow(r, 5) / 30;
  return core + slabsAcross + slabsAlong + cylAlong + cylAcross + 8 * octant;
}

TEST(RoundedHull3, RoundedBoxMatchesTheClosedForm) {
  const double a = 1.0, b = 0.5, c = 0.25, r = 0.2, rho = 3.0;
  double vol = 8 * a * b * c + 2 * r * (4 * a * b + 4 * b * c + 4 * c * a) +
               kPiD * r * r * (2 * a + 2 * b + 2 * c) + 4.0 / 3.0 * kPiD * r * r * r;
  double sx = secondMomentX(a, b, c, r), sy = secondMomentX(b, c, a, r),
         sz = secondMomentX(c, a, b, r);
  Mat3 want =
      Mat3::diagonal({float(rho * (sy + sz)), float(rho * (sx + sz)), float(rho * (sx + sy))});
  MassProperties3 m = computeMass(makeBox3({1, 0.5f, 0.25f}, {}, 0.2f).value(), float(rho));
  EXPECT_NEAR(m.volume, vol, 2e-6 * vol);
  EXPECT_NEAR(m.mass, rho * vol, 2e-6 * rho * vol);
  EXPECT_NEAR(length(m.centroid), 0, 1e-6);
  const float* pm = &m.inertia.cx.x;
  const float* pw = &want.cx.x;
  for (int i = 0; i < 9; ++i)
    EXPECT_NEAR(pm[i], pw[i], 2e-6 * pw[0]) << "entry " << i;

  // Turned and moved: the same tensor turned, the centre moved.
  std::mt19937 rng(5);
  for (int k = 0; k < 10; ++k) {
    Transform3 t{{1.5f, -2, 0.5f}, randomQuat(rng)};
    MassProperties3 mt = computeMass(makeBox3({1, 0.5f, 0.25f}, t, 0.2f).value(), float(rho));
    Mat3 rot = toMat3(t.q);
    Mat3 turned = rot * want * transpose(rot);
    EXPECT_NEAR(mt.volume, vol, 1e-5 * vol);
    EXPECT_NEAR(length(mt.centroid - t.p), 0, 1e-5);
    const float* p1 = &mt.inertia.cx.x;
    const float* p2 = &turned.cx.x;
    for (int i = 0; i < 9; ++i)
      EXPECT_NEAR(p1[i], p2[i], 1e-5 * pw[0]) << "entry " << i;
  }
}

TEST(RoundedHull3, ZeroRadiusIsThePlainHullAndSmallRadiiConverge) {
  std::mt19937 rng(17);
  for (int k = 0; k < 20; ++k) {
    Hull3 h = randomHull(rng, 6 + k, 0.0f);
    MassProperties3 plain = computeMass(h, 2.0f);
    Hull3 copy = h;
    copy.radius = 0.0f;
    MassProperties3 zero = computeMass(copy, 2.0f);
    EXPECT_EQ(zero.volume, plain.volume);
    EXPECT_EQ(zero.centroid, plain.centroid);
    // Tiny radius: within O(r) of the plain hull (the surface area times r).
    copy.radius = 1e-4f;
    MassProperties3 tiny = computeMass(copy, 2.0f);
    EXPECT_GT(tiny.volume, plain.volume);
    EXPECT_NEAR(tiny.volume, plain.volume, 2e-3 * plain.volume);
    EXPECT_NEAR(length(tiny.centroid - plain.centroid), 0, 1e-3);
    const float* p1 = &tiny.inertia.cx.x;
    const float* p2 = &plain.inertia.cx.x;
    for (int i = 0; i < 9; ++i)
      EXPECT_NEAR(p1[i], p2[i], 4e-3 * plain.inertia.cx.x) << "entry " << i;
  }
}

// Steiner's formula from the hull's faces (areas) and edges (length x exterior angle), each
// computed here: V + A r + M r^2 / 2 + 4/3 pi r^3.
TEST(RoundedHull3, VolumeIsSteinersFormula) {
  std::mt19937 rng(23);
  for (int k = 0; k < 50; ++k) {
    float r = std::uniform_real_distribution<float>(0.01f, 1.5f)(rng);
    Hull3 h = randomHull(rng, 4 + k % 30, r);
    double area = 0, meanWidth = 0;
    for (int f = 0; f < h.faceCount; ++f) {
      const HullFace3& face = h.faces[f];
      V a = toV(h.vertices[h.faceVertices[face.first]]);
      for (int j = 1; j + 1 < face.count; ++j) {
        V b = toV(h.vertices[h.faceVertices[face.first + j]]) - a;
        V c = toV(h.vertices[h.faceVertices[face.first + j + 1]]) - a;
        V x{b.y * c.z - b.z * c.y, b.z * c.x - b.x * c.z, b.x * c.y - b.y * c.x};
        area += 0.5 * std::sqrt(dotV(x, x));
      }
    }
    for (int e = 0; e < h.edgeCount; ++e) {
      V d = toV(h.vertices[h.edges[e].v1]) - toV(h.vertices[h.edges[e].v0]);
      double cosine =
          dotV(toV(h.faces[h.edges[e].faceLeft].normal), toV(h.faces[h.edges[e].faceRight].normal));
      meanWidth += std::sqrt(dotV(d, d)) * std::acos(std::clamp(cosine, -1.0, 1.0));
    }
    Hull3 core = h;
    core.radius = 0;
    double v0 = computeMass(core, 1).volume;
    double want = v0 + area * r + meanWidth * r * r / 2 + 4.0 / 3.0 * kPiD * r * r * r;
    EXPECT_NEAR(computeMass(h, 1).volume, want, 1e-5 * want) << k;
  }
}

// Monte Carlo over the rounded hull's box: volume, first moment and the inertia about the
// shape origin, each against the exact answer within five standard errors (plus float
// rounding). The containment test is roundedDistance's (face triangles in double).
TEST(RoundedHull3, MassAgreesWithMonteCarlo) {
  std::mt19937 rng(41);
  const int samples = 60000;
  for (int k = 0; k < 4; ++k) {
    float r = k == 0 ? 0.6f : std::uniform_real_distribution<float>(0.05f, 0.5f)(rng);
    Hull3 h = randomHull(rng, 5 + 6 * k, r);
    Vec3 lo = h.vertices[0], hi = h.vertices[0];
    for (int i = 0; i < h.vertexCount; ++i) {
      lo = minv(lo, h.vertices[i]);
      hi = maxv(hi, h.vertices[i]);
    }
    V l = toV(lo) - V{r, r, r}, u = toV(hi) + V{r, r, r};
    double box = (u.x - l.x) * (u.y - l.y) * (u.z - l.z);
    // Per sample: indicator, x, y, z, and the inertia integrands about the origin.
    double sum[10] = {}, sq[10] = {};
    std::uniform_real_distribution<double> uni(0, 1);
    for (int s = 0; s < samples; ++s) {
      V p{l.x + uni(rng) * (u.x - l.x), l.y + uni(rng) * (u.y - l.y), l.z + uni(rng) * (u.z - l.z)};
      if (roundedDistance(h, p) > 0) continue;
      double f[10] = {1,
                      p.x,
                      p.y,
                      p.z,
                      p.y * p.y + p.z * p.z,
                      p.x * p.x + p.z * p.z,
                      p.x * p.x + p.y * p.y,
                      -p.x * p.y,
                      -p.x * p.z,
                      -p.y * p.z};
      for (int i = 0; i < 10; ++i) {
        sum[i] += f[i];
        sq[i] += f[i] * f[i];
      }
    }
    MassProperties3 m = computeMass(h, 1.0f);
    V c = toV(m.centroid);
    double vol = m.volume;
    // The exact inertia about the origin by the parallel-axis theorem.
    Mat3 I = m.inertia;
    double exact[10] = {vol,
                        vol * c.x,
                        vol * c.y,
                        vol * c.z,
                        I.cx.x + vol * (c.y * c.y + c.z * c.z),
                        I.cy.y + vol * (c.x * c.x + c.z * c.z),
                        I.cz.z + vol * (c.x * c.x + c.y * c.y),
                        I.cy.x - vol * c.x * c.y,
                        I.cz.x - vol * c.x * c.z,
                        I.cz.y - vol * c.y * c.z};
    for (int i = 0; i < 10; ++i) {
      double mean = sum[i] / samples;
      double var = sq[i] / samples - mean * mean;
      double se = box * std::sqrt(var / samples);
      EXPECT_NEAR(box * mean, exact[i], 5 * se + 1e-5 * vol) << "hull " << k << " moment " << i;
    }
  }
}

// Random rays at a rounded hull: a hit's point is on the rounded surface and its normal
// points from the core's closest point; no sample before the hit (or along a missing ray)
// is inside; a ray from inside misses.
void checkRays(const Hull3& h, V centre, float size, std::mt19937& rng, int count) {
  std::uniform_real_distribution<float> u(-1, 1);
  int hits = 0, inside = 0;
  const double tol = 2e-5 * size;
  for (int i = 0; i < count; ++i) {
    Vec3 c{float(centre.x), float(centre.y), float(centre.z)};
    RayCastInput3 ray{c + 2.0f * size * Vec3{u(rng), u(rng), u(rng)},
                      3.0f * size * Vec3{u(rng), u(rng), u(rng)}, 1.0f};
    if (i % 5 == 0)
      ray.translation = 2.5f * (c - ray.origin) + 0.5f * size * Vec3{u(rng), u(rng), u(rng)};
    RayHit3 hit = rayCast(h, ray);
    if (roundedDistance(h, toV(ray.origin)) <= 0) {
      ++inside;
      EXPECT_FALSE(hit.hit);
      continue;
    }
    float end = hit.hit ? hit.fraction : ray.maxFraction;
    for (int k = 0; k < 40; ++k) {
      Vec3 p = ray.origin + (end * float(k) / 40.0f) * ray.translation;
      ASSERT_GT(roundedDistance(h, toV(p)), -tol)
          << "a sample before the entry is inside, ray " << i;
    }
    if (!hit.hit) continue;
    ++hits;
    EXPECT_NEAR(roundedDistance(h, toV(hit.point)), 0, tol) << i;
    V q = closestOnCore(h, toV(hit.point));
    V n = toV(hit.point) - q;
    n = (1.0 / std::sqrt(dotV(n, n))) * n;
    // Near a seam between patches (a cylinder and its end sphere) the closest feature of a
    // point eps inside the surface moves by sqrt(2 r eps) along it, turning the normal by
    // sqrt(2 eps / r): with eps the rounding of the hit (about 1e-6 of the size), that.
    const double normalTol = 1e-4 + std::sqrt(2e-6 * size / h.radius);
    EXPECT_NEAR(hit.normal.x, n.x, normalTol) << i;
    EXPECT_NEAR(hit.normal.y, n.y, normalTol) << i;
    EXPECT_NEAR(hit.normal.z, n.z, normalTol) << i;
    EXPECT_NEAR(length(hit.normal), 1, 1e-5);
    EXPECT_LT(dot(hit.normal, ray.translation), 0);
  }
  EXPECT_GT(hits, count / 5);
  EXPECT_GT(inside, 0);
}

TEST(RoundedHull3, RayCastsAgainstContainment) {
  std::mt19937 rng(61);
  Transform3 t{{3, 0, -1}, randomQuat(rng)};
  checkRays(makeBox3({1, 0.5f, 2}, t, 0.3f).value(), {3, 0, -1}, 2.3f, rng, 1500);
  for (int k = 0; k < 4; ++k) {
    float r = std::uniform_real_distribution<float>(0.02f, 0.8f)(rng);
    checkRays(randomHull(rng, 8 + 10 * k, r), {0.3, -0.2, 0.1}, 1.0f + r, rng, 1000);
  }
}

TEST(RoundedHull3, RayCastHandWorked) {
  Hull3 box = makeBox3({1, 1, 1}, {}, 0.5f).value();
  RayHit3 h = rayCast(box, {{0, 5, 0}, {0, -10, 0}, 1});  // a face, lifted by r
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, 0.35f, 1e-6f);
  EXPECT_NEAR(h.normal.y, 1, 1e-6f);
  h = rayCast(box, {{5, 5, 0}, {-10, -10, 0}, 1});  // the edge x = y = 1: its cylinder
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, (5 - (1 + 0.5 / std::sqrt(2.0))) / 10, 1e-6);
  EXPECT_NEAR(h.normal.x, 1 / std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(h.normal.z, 0, 1e-6);
  h = rayCast(box, {{5, 5, 5}, {-10, -10, -10}, 1});  // the corner: its sphere
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, (5 - (1 + 0.5 / std::sqrt(3.0))) / 10, 1e-6);
  EXPECT_NEAR(h.normal.y, 1 / std::sqrt(3.0), 1e-6);
  // Past the core's face but within the radius: inside, no hit; just beyond it: a hit.
  EXPECT_FALSE(rayCast(box, {{1.2f, 1.2f, 0}, {10, 0, 0}, 1}).hit);
  EXPECT_FALSE(rayCast(box, {{1.2f, 1.2f, 0}, {-10, 0, 0}, 1}).hit);
  h = rayCast(box, {{1.4f, 1.4f, 0}, {-10, 0, 0}, 1});
  ASSERT_TRUE(h.hit);  // enters the edge's cylinder where (x - 1)^2 + 0.16 = 0.25
  EXPECT_NEAR(h.fraction, (0.4 - 0.3) / 10, 1e-6);
  EXPECT_FALSE(rayCast(box, {{0, 5, 0}, {0, -10, 0}, 0.3f}).hit);  // too short
  EXPECT_FALSE(rayCast(box, {{0, 5, 0}, {0, 0, 0}, 1}).hit);       // zero translation
}

}  // namespace
}  // namespace quack
