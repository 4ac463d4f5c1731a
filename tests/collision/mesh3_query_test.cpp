// Ray casts and shape casts against static triangle meshes: through the mesh's tree against
// a brute-force loop over every triangle (random rays and casts against a height-field grid
// and a closed box), and hand-worked answers.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "mesh3_test_util.hpp"
#include "quack/collision/mesh3.hpp"
#include "quack/collision/proxy3.hpp"

namespace quack {
namespace {

// An n x n height field over [-s, s]^2 (fronts up): the mesh tests' grid.
using testing::grid;

using testing::closedBox;
using testing::ConvexKinds;
using testing::rollingField;

// The closest front hit over every triangle in order, in the mesh frame as rayCastMesh
// works, carried back to the world.
MeshRayHit3 bruteRay(const Mesh3& mesh, Transform3 worldFromMesh, const RayCastInput3& ray) {
  const RayCastInput3 local{invTransformPoint(worldFromMesh, ray.origin),
                            invTransformVector(worldFromMesh, ray.translation), ray.maxFraction};
  MeshRayHit3 best;
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const RayHit3 h = rayCast(mesh.triangle(t), local);
    if (!h.hit || dot(h.normal, mesh.triangles()[static_cast<std::size_t>(t)].normal) <= 0.0f) {
      continue;
    }
    if (!best.hit || h.fraction < best.fraction) {
      best.hit = true;
      best.fraction = h.fraction;
      best.point = transformPoint(worldFromMesh, h.point);
      best.normal = transformVector(worldFromMesh, h.normal);
      best.triangle = t;
    }
  }
  return best;
}

MeshShapeCastOutput3 bruteCast(const Mesh3& mesh, Transform3 worldFromMesh, const ShapeProxy3& b,
                               Transform3 worldFromB, Vec3 translation) {
  MeshShapeCastOutput3 best;
  const Vec3 local = invTransformVector(worldFromMesh, translation);
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    if (dot(local, mesh.triangles()[static_cast<std::size_t>(t)].normal) > 0.0f) continue;
    const ShapeCastOutput3 c =
        castShape(makeProxy(mesh.triangle(t)), worldFromMesh, b, worldFromB, translation);
    if (c.hit && (!best.hit || c.fraction < best.fraction)) {
      static_cast<ShapeCastOutput3&>(best) = c;
      best.triangle = t;
    }
  }
  return best;
}

TEST(Mesh3Query, RayStraightDownOntoAFlatGrid) {
  // A 4 x 4 flat grid at y = 0 over [-2, 2]^2; quads are 1 m wide.
  const Mesh3 m = grid(4, 2, [](float, float) { return 0.0f; });
  const Transform3 worldFromMesh{{0, 1, 0}, Quat{}};  // the grid at y = 1
  const MeshRayHit3 h = rayCastMesh(m, worldFromMesh, {{0.3f, 5, -0.6f}, {0, -10, 0}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_FLOAT_EQ(h.fraction, 0.4f);  // 4 m of the 10 m ray
  EXPECT_EQ(h.point, (Vec3{0.3f, 1, -0.6f}));
  EXPECT_EQ(h.normal, (Vec3{0, 1, 0}));
  // Quad (i, j) = (2, 1) holds (0.3, -0.6); i + j is odd, so its diagonal runs from (0, 0)
  // to (1, -1) (x + z = 0), and the point (x + z = -0.3) is on corner (0, -1)'s side: the
  // quad's first triangle.
  EXPECT_EQ(h.triangle, 2 * (2 * 4 + 1));
  // From below the floor the ray passes through (one-sided); too short a ray misses.
  EXPECT_FALSE(rayCastMesh(m, worldFromMesh, {{0.3f, -5, -0.6f}, {0, 10, 0}, 1}).hit);
  EXPECT_FALSE(rayCastMesh(m, worldFromMesh, {{0.3f, 5, -0.6f}, {0, -10, 0}, 0.39f}).hit);
  // Off the grid, along it, and bad rays miss.
  EXPECT_FALSE(rayCastMesh(m, worldFromMesh, {{3, 5, 0}, {0, -10, 0}, 1}).hit);
  EXPECT_FALSE(rayCastMesh(m, worldFromMesh, {{-3, 1, 0.5f}, {6, 0, 0}, 1}).hit);
  EXPECT_FALSE(rayCastMesh(m, worldFromMesh, {{0, 5, 0}, {0, 0, 0}, 1}).hit);
  EXPECT_FALSE(rayCastMesh(m, worldFromMesh, {{0, NAN, 0}, {0, -1, 0}, 1}).hit);
  EXPECT_EQ(rayCastMesh(m, worldFromMesh, {{0, 5, 0}, {0, 0, 0}, 1}).triangle, -1);
}

TEST(Mesh3Query, RayThroughAClosedBoxHitsTheNearFaceFromOutsideOnly) {
  const Mesh3 box = closedBox({1, 2, 3});
  const Transform3 worldFromMesh{{5, 0, 0}, Quat::fromAxisAngle({0, 1, 0}, 0.5f * kPi)};
  // Turned a quarter about y, the box's local z (half 3) lies along world x.
  const MeshRayHit3 h = rayCastMesh(box, worldFromMesh, {{-5, 0.5f, 0.25f}, {20, 0, 0}, 1});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, 7.0f / 20.0f, 1e-6f);  // enters at x = 5 - 3 = 2
  EXPECT_NEAR(h.normal.x, -1.0f, 1e-6f);
  EXPECT_NEAR(h.point.x, 2.0f, 1e-5f);
  // From inside the box, the ray leaves through a back face: no hit.
  EXPECT_FALSE(rayCastMesh(box, worldFromMesh, {{5, 0.5f, 0.25f}, {20, 0, 0}, 1}).hit);
}

TEST(Mesh3Query, RandomRaysAgreeWithEveryTriangle) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1);
  const Mesh3 field =
      grid(12, 4, [](float x, float z) { return 0.5f * std::sin(1.1f * x) * std::cos(z); });
  const Mesh3 box = closedBox({1.5f, 0.7f, 1.1f});
  const Mesh3 flat = grid(6, 3, [](float, float) { return 0.0f; });
  const Mesh3* meshes[3] = {&field, &box, &flat};
  int hits = 0;
  for (int q = 0; q < 3000; ++q) {
    const Mesh3& m = *meshes[q % 3];
    const Transform3 worldFromMesh{{2 * u(rng), 2 * u(rng), 2 * u(rng)},
                                   normalize(Quat{u(rng), u(rng), u(rng), u(rng) + 0.01f})};
    // Rays from around the mesh towards points near it; a third aimed at grid vertices
    // (shared edges and corners), where ties between triangles happen.
    Vec3 target{4 * u(rng), u(rng), 4 * u(rng)};
    if (q % 3 == 2) target = {std::round(target.x), 0, std::round(target.z)};
    const Vec3 from = 6.0f * normalize(Vec3{u(rng), u(rng), u(rng)});
    const RayCastInput3 ray{transformPoint(worldFromMesh, from),
                            transformVector(worldFromMesh, 1.5f * (target - from)),
                            q % 5 == 0 ? 0.5f : 1.0f};
    const MeshRayHit3 a = rayCastMesh(m, worldFromMesh, ray);
    const MeshRayHit3 b = bruteRay(m, worldFromMesh, ray);
    ASSERT_EQ(a.hit, b.hit) << "ray " << q;
    hits += a.hit ? 1 : 0;
    if (!a.hit) continue;
    EXPECT_EQ(a.triangle, b.triangle) << "ray " << q;
    EXPECT_EQ(a.fraction, b.fraction) << "ray " << q;
    EXPECT_EQ(a.point, b.point) << "ray " << q;
    EXPECT_EQ(a.normal, b.normal) << "ray " << q;
    // The face normal, facing the ray.
    EXPECT_LT(dot(a.normal, ray.translation), 0.0f);
  }
  EXPECT_GT(hits, 600);
}

TEST(Mesh3Query, BoxDroppedOntoAFlatGridHitsAtTheGap) {
  const Mesh3 m = grid(4, 2, [](float, float) { return 0.0f; });
  // A hull's proxy points into the hull: keep it alive as long as the proxy.
  const Hull3 hull = makeBox3({0.5f, 0.5f, 0.5f}).value();
  const ShapeProxy3 cube = makeProxy(hull);
  // The cube's bottom 2 m above the floor, dropped 4 m: touches at half the way.
  const MeshShapeCastOutput3 c =
      castShapeMesh(m, Transform3{}, cube, Transform3{{0.2f, 2.5f, 0.1f}, Quat{}}, {0, -4, 0});
  ASSERT_EQ(c.status, ShapeCastStatus::hit);
  EXPECT_NEAR(c.fraction, 0.5f, kShapeCastTolerance);
  EXPECT_NEAR(c.normal.y, 1.0f, 1e-5f);
  EXPECT_GE(c.triangle, 0);
  // Thrown up, it leaves every front: no hit; sinking from inside the floor: overlapped.
  EXPECT_EQ(castShapeMesh(m, Transform3{}, cube, Transform3{{0.2f, 2.5f, 0.1f}, Quat{}}, {0, 4, 0})
                .status,
            ShapeCastStatus::missed);
  const MeshShapeCastOutput3 o =
      castShapeMesh(m, Transform3{}, cube, Transform3{{0.2f, 0.3f, 0.1f}, Quat{}}, {0, -1, 0});
  EXPECT_EQ(o.status, ShapeCastStatus::overlapped);
  EXPECT_EQ(o.fraction, 0.0f);
  EXPECT_EQ(castShapeMesh(m, Transform3{}, cube, Transform3{{0, 2, 0}, Quat{}}, {0, NAN, 0}).status,
            ShapeCastStatus::invalidInput);
}

TEST(Mesh3Query, RandomShapeCastsAgreeWithEveryTriangle) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1, 1);
  const Mesh3 field = rollingField();
  const Mesh3 box = closedBox({1.5f, 0.7f, 1.1f});
  const ConvexKinds kinds;
  const std::vector<ShapeProxy3>& shapes = kinds.proxies;
  int hits = 0;
  for (int q = 0; q < 240; ++q) {
    const Mesh3& m = q % 2 == 0 ? field : box;
    const Transform3 worldFromMesh{{u(rng), u(rng), u(rng)},
                                   normalize(Quat{u(rng), u(rng), u(rng), u(rng) + 0.01f})};
    const ShapeProxy3& b = shapes[static_cast<std::size_t>(q) % shapes.size()];
    const Vec3 from = 4.0f * normalize(Vec3{u(rng), u(rng), u(rng)});
    const Vec3 to{2 * u(rng), 0.5f * u(rng), 2 * u(rng)};
    const Transform3 worldFromB{transformPoint(worldFromMesh, from),
                                normalize(Quat{u(rng), u(rng), u(rng), u(rng) + 0.01f})};
    const Vec3 translation = transformVector(worldFromMesh, 1.3f * (to - from));
    const MeshShapeCastOutput3 a = castShapeMesh(m, worldFromMesh, b, worldFromB, translation);
    const MeshShapeCastOutput3 r = bruteCast(m, worldFromMesh, b, worldFromB, translation);
    ASSERT_EQ(a.hit, r.hit) << "cast " << q;
    hits += a.hit ? 1 : 0;
    if (!a.hit) continue;
    EXPECT_EQ(a.status, r.status) << "cast " << q;
    EXPECT_EQ(a.triangle, r.triangle) << "cast " << q;
    EXPECT_EQ(a.fraction, r.fraction) << "cast " << q;
    EXPECT_EQ(a.point, r.point) << "cast " << q;
    EXPECT_EQ(a.normal, r.normal) << "cast " << q;
  }
  EXPECT_GT(hits, 80);
}

TEST(Mesh3Query, RandomOverlapAndDistanceAgreeWithEveryTriangle) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(-1, 1);
  const Mesh3 field = rollingField();
  const Mesh3 box = closedBox({1.5f, 0.7f, 1.1f});
  const Sphere sphere = makeSphere({0, 0, 0}, 0.3f).value();
  const Capsule3 capsule = makeCapsule3({-0.4f, 0, 0}, {0.4f, 0, 0}, 0.15f).value();
  const Hull3 hull = makeBox3({0.3f, 0.2f, 0.25f}).value();
  const std::vector<ShapeProxy3> shapes = {makeProxy(sphere), makeProxy(capsule), makeProxy(hull)};
  int overlaps = 0;
  for (int q = 0; q < 300; ++q) {
    const Mesh3& m = q % 2 == 0 ? field : box;
    const Transform3 worldFromMesh{{u(rng), u(rng), u(rng)},
                                   normalize(Quat{u(rng), u(rng), u(rng), u(rng) + 0.01f})};
    const ShapeProxy3& b = shapes[static_cast<std::size_t>(q) % shapes.size()];
    const Transform3 worldFromB{
        transformPoint(worldFromMesh, {3 * u(rng), 1.5f * u(rng), 3 * u(rng)}),
        normalize(Quat{u(rng), u(rng), u(rng), u(rng) + 0.01f})};
    bool overlap = false;
    MeshDistanceOutput3 best;
    for (int t = 0; t < m.triangleCount(); ++t) {
      const ShapeProxy3 tri = makeProxy(m.triangle(t));
      overlap = overlap || testOverlap(tri, worldFromMesh, b, worldFromB);
      const DistanceOutput3 d = computeDistance(tri, worldFromMesh, b, worldFromB);
      if (best.triangle < 0 || d.distance < best.distance) {
        static_cast<DistanceOutput3&>(best) = d;
        best.triangle = t;
      }
    }
    EXPECT_EQ(testOverlapMesh(m, worldFromMesh, b, worldFromB), overlap) << "pose " << q;
    overlaps += overlap ? 1 : 0;
    const MeshDistanceOutput3 d = computeDistanceMesh(m, worldFromMesh, b, worldFromB);
    EXPECT_EQ(d.triangle, best.triangle) << "pose " << q;
    EXPECT_EQ(d.distance, best.distance) << "pose " << q;
    EXPECT_EQ(d.pointA, best.pointA) << "pose " << q;
    EXPECT_EQ(d.pointB, best.pointB) << "pose " << q;
  }
  EXPECT_GT(overlaps, 30);
  EXPECT_LT(overlaps, 270);
}

}  // namespace
}  // namespace quack
