// Quickhull in 3D: hand-worked point sets (duplicates, coplanar and collinear points, what
// the report says was dropped), every error, and random clouds against qhull (the oracle:
// Debian libqhull-dev, optional; the oracle tests skip with a message without it).

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "quack/geometry/hull3.hpp"
#include "quack/geometry/mass3.hpp"
#include "quack/geometry/shapes3.hpp"

#if QUACK_HAVE_QHULL
extern "C" {
#include <libqhull_r/qhull_ra.h>
}
#endif

namespace quack {
namespace {

std::vector<Vec3> cubeCorners(float h, Vec3 c = {}) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i)
    v.push_back(c + Vec3{(i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h});
  return v;
}

// Largest signed distance of p outside the hull's face planes (double).
double outside(const Hull3& hull, Vec3 p) {
  double h = -1e300;
  for (int f = 0; f < hull.faceCount; ++f) {
    const HullFace3& face = hull.faces[f];
    double d = double(face.normal.x) * p.x + double(face.normal.y) * p.y +
               double(face.normal.z) * p.z - double(face.offset);
    h = std::max(h, d);
  }
  return h;
}

TEST(Hull3, CubeWithDuplicatesCoplanarCollinearAndInteriorPoints) {
  std::vector<Vec3> pts = cubeCorners(1);
  pts.push_back({1, 1, 1});          // exact duplicate
  pts.push_back({1, 1, 1 + 1e-7f});  // near duplicate (far below the tolerance 2e-5)
  for (int axis = 0; axis < 3; ++axis) {
    for (float s : {-1.0f, 1.0f}) {  // face centres: coplanar
      Vec3 c{};
      (axis == 0 ? c.x : axis == 1 ? c.y : c.z) = s;
      pts.push_back(c);
    }
  }
  pts.push_back({0, 1, 1});  // edge midpoints: collinear
  pts.push_back({1, 0, -1});
  pts.push_back({-1, -1, 0.3f});
  pts.push_back({0.2f, 0.1f, -0.3f});  // interior
  pts.push_back({0, 0, 0});
  Result<Hull3Build> r = computeHull3(pts);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Hull3& hull = r->hull;
  EXPECT_TRUE(validateHull3(hull).ok()) << validateHull3(hull).message();
  EXPECT_EQ(hull.vertexCount, 8);
  EXPECT_EQ(hull.faceCount, 6);
  EXPECT_EQ(hull.edgeCount, 12);
  const Hull3Report& rep = r->report;
  EXPECT_EQ(rep.inputCount, static_cast<int>(pts.size()));
  EXPECT_EQ(rep.vertices, 8);
  EXPECT_EQ(rep.duplicates, 2);
  EXPECT_EQ(rep.onBoundary, 9);
  EXPECT_EQ(rep.inside, 2);
  EXPECT_NEAR(hull.centroid.x, 0, 1e-6f);
  for (int f = 0; f < hull.faceCount; ++f) {
    EXPECT_EQ(hull.faces[f].count, 4);
    EXPECT_NEAR(hull.faces[f].offset, 1.0f, 1e-6f);
  }
}

TEST(Hull3, EveryErrorNamesItsCause) {
  std::vector<Vec3> none;
  EXPECT_NE(computeHull3(none).error().message.find("got none"), std::string::npos);
  std::vector<Vec3> nan = cubeCorners(1);
  nan[3].y = NAN;
  EXPECT_NE(computeHull3(nan).error().message.find("points[3] is not finite"), std::string::npos);
  std::vector<Vec3> huge = cubeCorners(1);
  huge[5].x = 2e9f;
  EXPECT_NE(computeHull3(huge).error().message.find("points[5]"), std::string::npos);
  std::vector<Vec3> one{{1, 2, 3}, {1, 2, 3}, {1, 2, 3 + 1e-9f}};
  EXPECT_NE(computeHull3(one).error().message.find("one point"), std::string::npos);
  std::vector<Vec3> line{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {0.5f, 0.5f, 0.5f}};
  EXPECT_NE(computeHull3(line).error().message.find("collinear"), std::string::npos);
  std::vector<Vec3> plane{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1e-7f}, {3, 2, 0}};
  EXPECT_NE(computeHull3(plane).error().message.find("coplanar"), std::string::npos);
  std::vector<Vec3> sphere;
  std::mt19937 rng(1);
  std::normal_distribution<float> n(0, 1);
  for (int i = 0; i < 300; ++i)
    sphere.push_back(normalize(Vec3{n(rng), n(rng), n(rng)}));
  EXPECT_NE(computeHull3(sphere).error().message.find("more than 64"), std::string::npos);
}

TEST(Hull3, RegressionLargeRoundCloudIsRefusedEarly) {
  // 100,000 points on a sphere: the hull would have tens of thousands of vertices. The
  // build once ran to the end (about three minutes in a release build) before refusing it;
  // it now stops at four times the vertex limit, in milliseconds.
  std::mt19937 rng(5);
  std::normal_distribution<float> n(0, 1);
  std::vector<Vec3> pts;
  for (int i = 0; i < 100000; ++i)
    pts.push_back(normalize(Vec3{n(rng), n(rng), n(rng)}));
  Result<Hull3Build> r = computeHull3(pts);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("more than 64 vertices"), std::string::npos)
      << r.error().message;
  // A large cloud with a small hull still builds.
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<Vec3> box = cubeCorners(1);
  for (int i = 0; i < 100000; ++i)
    box.push_back({u(rng), u(rng), u(rng)});
  Result<Hull3Build> b = computeHull3(box);
  ASSERT_TRUE(b.ok()) << b.error().message;
  EXPECT_EQ(b->hull.vertexCount, 8);
  EXPECT_EQ(b->report.inside + b->report.onBoundary + b->report.duplicates, 100000);
}

TEST(Hull3, LatticeIsItsBoundingBox) {
  // A 5x5x5 lattice: almost every point is coplanar or collinear with others.
  std::vector<Vec3> pts;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k)
        pts.push_back({float(i), float(j) * 0.5f, float(k) * 2.0f});
  Result<Hull3Build> r = computeHull3(pts);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->hull.vertexCount, 8);
  EXPECT_EQ(r->hull.faceCount, 6);
  EXPECT_EQ(r->report.inside, 27);
  EXPECT_EQ(r->report.onBoundary, 125 - 27 - 8);
  MassProperties3 m = computeMass(r->hull, 1.0f);
  EXPECT_NEAR(m.volume, 4.0f * 2.0f * 8.0f, 1e-4f);
}

TEST(Hull3, MakeBox3IsAnOrientedBox) {
  Quat q = Quat::fromAxisAngle(normalize(Vec3{1, 2, 3}), 0.7f);
  Result<Hull3> box = makeBox3({1, 2, 3}, {{10, 0, -5}, q});
  ASSERT_TRUE(box.ok()) << box.error().message;
  EXPECT_EQ(box->vertexCount, 8);
  EXPECT_EQ(box->faceCount, 6);
  EXPECT_TRUE(validateHull3(*box).ok());
  EXPECT_NEAR(box->centroid.x, 10.0f, 1e-5f);
  EXPECT_NEAR(box->centroid.z, -5.0f, 1e-5f);
  EXPECT_FALSE(makeBox3({1, 0, 1}).ok());
  EXPECT_NE(makeBox3({1, NAN, 1}).error().message.find("not finite"), std::string::npos);
}

TEST(Hull3, RegressionSliverRimPointsAreKept) {
  // A sliver cloud (42 points, 2e-3 thick) on which quickhull once dropped points[15] as
  // "within the tolerance of every face plane" although it lay 1.7e-4 beyond the rim (a
  // sharp edge: close to both planes, far from both faces). Points near a plane are now
  // dropped only when their true distance to the hull is within the tolerance.
  std::vector<Vec3> pts{{-0.94026494f, -0.741836667f, 0.000874670281f},
                        {0.420503139f, -0.933712721f, 0.000491622835f},
                        {0.197329044f, 0.875737548f, -0.000380540034f},
                        {-0.914101362f, 0.444240332f, 4.36713708e-05f},
                        {0.186289072f, 0.84817946f, 0.000879916945f},
                        {-0.312589645f, 0.00996720791f, -0.000313437486f},
                        {-0.359606266f, 0.407905102f, 0.000332191121f},
                        {0.172678828f, -0.783644736f, -0.000381187041f},
                        {0.724049449f, -0.844160795f, 0.000113079193f},
                        {0.424898267f, -0.270216703f, -0.000328827999f},
                        {-0.110936284f, 0.642846465f, -0.000840298482f},
                        {0.477436662f, -0.0219898224f, -0.000159752017f},
                        {-0.205371201f, -0.289334178f, -0.000449601008f},
                        {0.612143636f, 0.542645097f, 0.000822845614f},
                        {0.607258558f, 0.775855303f, 0.000867895898f},
                        {0.694020629f, 0.638586283f, 0.000835696119f},
                        {0.767527699f, 0.49272418f, -0.000606640708f},
                        {0.100225687f, -0.851309478f, -0.00048931042f},
                        {0.984666586f, 0.159525037f, 0.000704091799f},
                        {-0.271887541f, -0.526916087f, -0.000184425124f},
                        {-0.319375277f, 0.986791492f, 0.000201577321f},
                        {-0.250974298f, 0.86291039f, -0.000598916318f},
                        {-0.750380874f, -0.475511253f, -0.000279302505f},
                        {0.841087103f, -0.563695133f, 0.000307955983f},
                        {0.192581534f, 0.857914925f, -0.000918670557f},
                        {-0.369424343f, -0.162627101f, 0.00084212498f},
                        {0.295420885f, -0.0260954499f, -0.000497209665f},
                        {-0.0261931419f, -0.372499645f, -0.000347280642f},
                        {-0.313402891f, -0.489435911f, -0.00094013894f},
                        {0.946872473f, -0.94711709f, -0.000155679416f},
                        {0.580663204f, 0.851485848f, -0.000322445645f},
                        {0.787767172f, 0.372058034f, -0.000694972405f},
                        {0.676976919f, 0.31633389f, 0.000117446907f},
                        {0.00455319881f, 0.833024383f, -0.000265341369f},
                        {-0.153510511f, -0.162880659f, -0.00031467629f},
                        {0.450347424f, -0.932750583f, -0.000900082756f},
                        {0.0924444199f, 0.24150598f, -0.000498764566f},
                        {-0.728687525f, -0.64252317f, -0.000472247513f},
                        {0.512164831f, 0.331244588f, -5.42759949e-07f},
                        {0.104209304f, -0.658246875f, 0.000524417788f},
                        {-0.87443316f, 0.5342623f, -0.000400506688f},
                        {0.303082705f, 0.118160129f, -0.000950394315f}};
  Result<Hull3Build> r = computeHull3(pts);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(validateHull3(r->hull).ok());
  const Hull3Report& rep = r->report;
  EXPECT_EQ(rep.vertices + rep.duplicates + rep.inside + rep.onBoundary, rep.inputCount);
  for (Vec3 p : pts)
    EXPECT_LE(outside(r->hull, p), 2.0 * rep.tolerance);
}

// Random clouds of several kinds, each checked for the invariants and the report's sum.
enum class Cloud { box, sphere, boxSurfaceJitter, sliver, far, clustered };

std::vector<Vec3> makeCloud(Cloud kind, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1, 1);
  std::normal_distribution<float> n(0, 1);
  std::uniform_int_distribution<int> count(5, 60);
  std::vector<Vec3> pts;
  int m = count(rng);
  for (int i = 0; i < m; ++i) {
    switch (kind) {
      case Cloud::box:
        pts.push_back({u(rng), u(rng), u(rng)});
        break;
      case Cloud::sphere:
        pts.push_back(normalize(Vec3{n(rng), n(rng), n(rng)}));
        break;
      case Cloud::boxSurfaceJitter: {
        // Points on a box's faces, jittered by a hundredth of the tolerance: coplanar.
        Vec3 p{u(rng), u(rng), u(rng)};
        int axis = i % 3;
        float s = (i / 3) % 2 ? 1.0f : -1.0f;
        (axis == 0 ? p.x : axis == 1 ? p.y : p.z) = s + 1e-7f * u(rng);
        pts.push_back(p);
        break;
      }
      case Cloud::sliver:
        pts.push_back({u(rng), u(rng), 1e-3f * u(rng)});
        break;
      case Cloud::far:
        pts.push_back(Vec3{1e4f, -1e4f, 1e4f} + Vec3{u(rng), u(rng), u(rng)});
        break;
      case Cloud::clustered:
        pts.push_back((i % 2 ? 1.0f : 1e-4f) * Vec3{u(rng), u(rng), u(rng)});
        break;
    }
  }
  if (kind == Cloud::boxSurfaceJitter || kind == Cloud::box) {
    std::vector<Vec3> c = cubeCorners(1);
    pts.insert(pts.end(), c.begin(), c.begin() + (m % 9));
  }
  return pts;
}

constexpr Cloud kClouds[] = {Cloud::box,    Cloud::sphere, Cloud::boxSurfaceJitter,
                             Cloud::sliver, Cloud::far,    Cloud::clustered};

TEST(Hull3, RandomCloudsAreValidAndContainEveryPoint) {
  std::mt19937 rng(2024);
  int built = 0;
  for (int trial = 0; trial < 600; ++trial) {
    Cloud kind = kClouds[trial % 6];
    std::vector<Vec3> pts = makeCloud(kind, rng);
    Result<Hull3Build> r = computeHull3(pts);
    if (!r.ok()) {
      // Only degenerate clouds may fail: a cloud too small for volume.
      EXPECT_LT(pts.size(), 8u) << r.error().message << " kind " << int(kind);
      continue;
    }
    ++built;
    const Hull3& hull = r->hull;
    ASSERT_TRUE(validateHull3(hull).ok()) << validateHull3(hull).message() << " trial " << trial;
    const Hull3Report& rep = r->report;
    EXPECT_EQ(rep.vertices + rep.duplicates + rep.inside + rep.onBoundary, rep.inputCount);
    for (Vec3 p : pts)
      EXPECT_LE(outside(hull, p), 4.0 * rep.tolerance) << "trial " << trial;
  }
  EXPECT_GT(built, 550);
}

#if QUACK_HAVE_QHULL
// qhull's hull of the points: its facet planes and its vertices (indices into pts).
struct QhullResult {
  std::vector<std::array<double, 4>> planes;  // n.x + offset <= 0 inside
  std::vector<int> vertices;
  double volume = 0;
};

QhullResult runQhull(const std::vector<Vec3>& pts) {
  std::vector<coordT> coords;
  for (Vec3 p : pts) {
    coords.push_back(p.x);
    coords.push_back(p.y);
    coords.push_back(p.z);
  }
  QhullResult out;
  qhT qhStorage;
  qhT* qh = &qhStorage;
  qh_zero(qh, stderr);
  char flags[] = "qhull FA";
  int code = qh_new_qhull(qh, 3, static_cast<int>(pts.size()), coords.data(), False, flags, nullptr,
                          stderr);
  if (code == 0) {
    facetT* facet;
    vertexT* vertex;
    FORALLfacets {
      out.planes.push_back({facet->normal[0], facet->normal[1], facet->normal[2], facet->offset});
    }
    FORALLvertices {
      out.vertices.push_back(qh_pointid(qh, vertex->point));
    }
    qh_getarea(qh, qh->facet_list);
    out.volume = qh->totvol;
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong, totlong;
  qh_memfreeshort(qh, &curlong, &totlong);
  return out;
}
#endif

TEST(Hull3, AgreesWithQhull) {
#if !QUACK_HAVE_QHULL
  GTEST_SKIP() << "qhull is missing (install Debian libqhull-dev): the hull oracle did not run";
#else
  // The hulls agree when each one's vertices lie inside the other within the tolerance
  // (so every qhull vertex is a vertex of ours or on our boundary, and the reverse), and
  // their volumes agree to float rounding.
  std::mt19937 rng(77);
  int compared = 0;
  for (int trial = 0; trial < 1200; ++trial) {
    Cloud kind = kClouds[trial % 6];
    std::vector<Vec3> pts = makeCloud(kind, rng);
    Result<Hull3Build> r = computeHull3(pts);
    if (!r.ok()) continue;
    QhullResult q = runQhull(pts);
    ASSERT_FALSE(q.planes.empty()) << "qhull failed on trial " << trial;
    const Hull3& hull = r->hull;
    double tol = 4.0 * r->report.tolerance;
    for (int v : q.vertices) {
      EXPECT_LE(outside(hull, pts[static_cast<std::size_t>(v)]), tol)
          << "qhull vertex outside ours, trial " << trial;
    }
    for (int i = 0; i < hull.vertexCount; ++i) {
      Vec3 p = hull.vertices[i];
      double h = -1e300;
      for (const auto& pl : q.planes)
        h = std::max(h, pl[0] * p.x + pl[1] * p.y + pl[2] * p.z + pl[3]);
      EXPECT_LE(h, tol) << "our vertex outside qhull's hull, trial " << trial;
    }
    EXPECT_GE(hull.vertexCount, 4);
    EXPECT_LE(static_cast<std::size_t>(hull.vertexCount), q.vertices.size() + 0)
        << "more vertices than qhull (a dropped point kept), trial " << trial;
    MassProperties3 m = computeMass(hull, 1.0f);
    // Volume: the hulls differ by at most the tolerance times the surface.
    double size = 2.0;
    EXPECT_NEAR(m.volume, q.volume, 1e-4 * std::max(q.volume, 1e-3) + 6 * size * size * tol)
        << "trial " << trial;
    ++compared;
  }
  EXPECT_GT(compared, 1100);
#endif
}

}  // namespace
}  // namespace quack
