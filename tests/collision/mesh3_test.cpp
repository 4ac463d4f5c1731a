// Static triangle meshes: construction and adjacency, the tree against brute force, contacts
// through the tree against every triangle, and no ghost bumps on shared edges.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "mesh3_test_util.hpp"
#include "quack/collision/mesh3.hpp"

namespace quack {
namespace {

using testing::grid;

using Tri = std::array<std::int32_t, 3>;

// A flat square floor of side 2h at y = 0 as two triangles sharing the diagonal (0, 2).
Mesh3 twoTriangleFloor(float h) {
  const std::vector<Vec3> v = {{-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}};
  const std::vector<Tri> t = {{0, 3, 2}, {0, 2, 1}};
  return makeMesh3(v, t).value();
}

TEST(Mesh3, AdjacencyOfAFloorAndAGrid) {
  const Mesh3 floor = twoTriangleFloor(5);
  ASSERT_EQ(floor.triangleCount(), 2);
  for (int i = 0; i < 2; ++i) {
    const MeshTriangle3& t = floor.triangles()[static_cast<std::size_t>(i)];
    EXPECT_EQ(t.normal, (Vec3{0, 1, 0}));
    int shared = 0;
    for (int k = 0; k < 3; ++k) {
      if (t.neighbour[k] >= 0) {
        ++shared;
        EXPECT_EQ(t.neighbour[k], 1 - i);
        EXPECT_EQ(t.edge[k], MeshEdgeKind3::flat);
      } else {
        EXPECT_EQ(t.edge[k], MeshEdgeKind3::boundary);
      }
    }
    EXPECT_EQ(shared, 1);
  }
  // A 6 x 6 grid: 72 triangles; interior edges 3 n^2 - 2 n = 96, each seen twice; the
  // boundary 4 n = 24 edges.
  const Mesh3 g = grid(6, 3, [](float, float) { return 0.0f; });
  ASSERT_EQ(g.triangleCount(), 72);
  int interiorSides = 0, boundary = 0;
  for (int i = 0; i < g.triangleCount(); ++i) {
    const MeshTriangle3& t = g.triangles()[static_cast<std::size_t>(i)];
    for (int k = 0; k < 3; ++k) {
      if (t.neighbour[k] < 0) {
        ++boundary;
        continue;
      }
      ++interiorSides;
      const MeshTriangle3& u = g.triangles()[static_cast<std::size_t>(t.neighbour[k])];
      // The neighbour lists this triangle across the same edge, reversed.
      int back = -1;
      for (int m = 0; m < 3; ++m)
        if (u.neighbour[m] == i) back = m;
      ASSERT_GE(back, 0);
      EXPECT_EQ(u.v[back], t.v[(k + 1) % 3]);
      EXPECT_EQ(u.v[(back + 1) % 3], t.v[k]);
      EXPECT_EQ(t.edge[k], MeshEdgeKind3::flat);
    }
  }
  EXPECT_EQ(interiorSides, 2 * 96);
  EXPECT_EQ(boundary, 24);
}

TEST(Mesh3, RidgesAndValleys) {
  // A roof ridge along z at x = 0 (y = 1), and the same folded into a valley (y = -1).
  for (float top : {1.0f, -1.0f}) {
    const std::vector<Vec3> v = {{-2, 0, -2}, {0, top, -2}, {2, 0, -2},
                                 {-2, 0, 2},  {0, top, 2},  {2, 0, 2}};
    const std::vector<Tri> t = {{0, 3, 4}, {0, 4, 1}, {1, 4, 5}, {1, 5, 2}};
    const Mesh3 m = makeMesh3(v, t).value();
    const MeshEdgeKind3 want = top > 0 ? MeshEdgeKind3::convex : MeshEdgeKind3::concave;
    // Edge (1, 4), the ridge, is edge 1 of triangle 1 and edge 0 of triangle 2.
    EXPECT_EQ(m.triangles()[1].edge[1], want);
    EXPECT_EQ(m.triangles()[2].edge[0], want);
    EXPECT_EQ(m.triangles()[1].neighbour[1], 2);
    // Edge (0, 4) inside the left slope is flat.
    EXPECT_EQ(m.triangles()[0].edge[2], MeshEdgeKind3::flat);
  }
  EXPECT_STREQ(toString(MeshEdgeKind3::concave), "concave");
}

TEST(Mesh3, ErrorsNameTheTriangleOrEdge) {
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {1, 0, 1}, {2, 0, 0}};
  auto error = [&](std::vector<Tri> t, std::vector<Vec3> verts) {
    Result<Mesh3> m = makeMesh3(verts, t);
    EXPECT_FALSE(m.ok());
    return m.ok() ? std::string() : m.error().message;
  };
  EXPECT_EQ(error({}, v), "makeMesh3: no triangles");
  EXPECT_EQ(error({{0, 1, 7}}, v),
            "makeMesh3: triangle 0: vertex index 7 is out of range (0 to 4)");
  EXPECT_EQ(error({{0, 2, 1}, {0, 0, 1}}, v), "makeMesh3: triangle 1: a vertex index is repeated");
  EXPECT_EQ(error({{0, 1, 4}}, v).rfind("makeMesh3: triangle 0: triangle", 0), 0u);  // collinear
  EXPECT_EQ(error({{0, 2, 1}, {2, 1, 3}}, v),
            "makeMesh3: triangles 0 and 1 run along their edge (1, 2) the same way (their fronts "
            "disagree)");
  const std::vector<Vec3> fan = {{0, 0, 0}, {1, 0, 0}, {0, 1, 1}, {0, -1, 1}, {0, 0, 1}};
  EXPECT_EQ(error({{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}, fan),
            "makeMesh3: edge (0, 1) is shared by 3 triangles (a mesh edge has one or two)");
  std::vector<Vec3> nan = v;
  nan[2].y = std::nanf("");
  EXPECT_EQ(error({{0, 2, 1}}, nan), "makeMesh3: vertex 2 is not finite");
  std::vector<Vec3> far = v;
  far[3].x = 2e9f;
  EXPECT_EQ(error({{0, 2, 1}}, far), "makeMesh3: vertex 3 is beyond the coordinate limit 1e9 m");
}

TEST(Mesh3, TreeQueriesAgreeWithBruteForce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1);
  const Mesh3 m = grid(16, 8, [](float x, float z) { return std::sin(x) * std::cos(0.7f * z); });
  ASSERT_TRUE(m.tree().validate().ok());
  for (int q = 0; q < 500; ++q) {
    const Vec3 c{9 * u(rng), 1.5f * u(rng), 9 * u(rng)};
    const Vec3 e{std::abs(u(rng)) * 2, std::abs(u(rng)), std::abs(u(rng)) * 2};
    const Aabb3 box{c - e, c + e};
    std::vector<int> found;
    m.query(box, [&](int t) {
      found.push_back(t);
      return true;
    });
    std::vector<int> brute;
    for (int t = 0; t < m.triangleCount(); ++t) {
      const Triangle3 tri = m.triangle(t);
      Aabb3 tb{tri.v[0], tri.v[0]};
      for (const Vec3& p : tri.v)
        tb = {minv(tb.lower, p), maxv(tb.upper, p)};
      if (overlaps(tb, box)) brute.push_back(t);
    }
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, brute) << "query " << q;
  }
}

// The mesh's contacts through its tree are those of every triangle, one by one.
TEST(Mesh3, ContactsThroughTheTreeAgreeWithEveryTriangle) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1, 1);
  const Mesh3 m = grid(8, 4, [](float x, float z) { return 0.4f * std::sin(1.3f * x + z); });
  const Transform3 worldFromMesh{{1, -2, 3}, normalize(Quat{0.1f, 0.3f, -0.2f, 1})};
  const std::vector<ShapeGeometry3> shapes = {
      makeSphere({0, 0, 0}, 0.4f).value(), makeCapsule3({-0.5f, 0, 0}, {0.5f, 0, 0}, 0.2f).value(),
      makeBox3({0.5f, 0.3f, 0.4f}).value(),
      makeHull3(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.6f, 0.6f, 0.6f}})
          .value(),
      makeTriangle3({-0.6f, 0, -0.6f}, {0.6f, 0, -0.6f}, {0, 0, 0.7f}).value()};
  int withContacts = 0, nonFace = 0;
  for (int q = 0; q < 600; ++q) {
    const ShapeGeometry3& shape = shapes[static_cast<std::size_t>(q) % shapes.size()];
    const Vec3 local{3.5f * u(rng), 0.4f * u(rng), 3.5f * u(rng)};
    const Transform3 worldFromShape{transformPoint(worldFromMesh, local),
                                    normalize(Quat{u(rng), u(rng), u(rng), u(rng) + 0.01f})};
    std::vector<MeshContact3> tree;
    collideMesh(m, worldFromMesh, shape, worldFromShape, tree);
    std::vector<MeshContact3> brute;
    for (int t = 0; t < m.triangleCount(); ++t) {
      Manifold3 c = collideMeshTriangle(m, t, worldFromMesh, shape, worldFromShape);
      if (c.pointCount > 0) brute.push_back({t, c});
    }
    ASSERT_EQ(tree.size(), brute.size()) << "pose " << q;
    withContacts += tree.empty() ? 0 : 1;
    for (std::size_t i = 0; i < tree.size(); ++i) {
      EXPECT_EQ(tree[i].triangle, brute[i].triangle);
      const Manifold3& a = tree[i].manifold;
      const Manifold3& b = brute[i].manifold;
      ASSERT_EQ(a.pointCount, b.pointCount);
      EXPECT_EQ(a.normal, b.normal);
      for (int k = 0; k < a.pointCount; ++k) {
        EXPECT_EQ(a.points[k].point, b.points[k].point);
        EXPECT_EQ(a.points[k].separation, b.points[k].separation);
        EXPECT_EQ(a.points[k].id, b.points[k].id);
      }
      // A normal other than the face's only at a convex or boundary edge, out of the front.
      const MeshTriangle3& t = m.triangles()[static_cast<std::size_t>(tree[i].triangle)];
      const Vec3 faceNormal = transformVector(worldFromMesh, t.normal);
      EXPECT_NEAR(length(a.normal), 1.0f, 1e-5f);
      if (dot(a.normal, faceNormal) < kMeshFaceNormalCosine3) {
        ++nonFace;
        EXPECT_GT(dot(a.normal, faceNormal), 0.0f);
        bool sharpOrOpen = false;
        for (MeshEdgeKind3 e : t.edge)
          sharpOrOpen |= e == MeshEdgeKind3::convex || e == MeshEdgeKind3::boundary;
        EXPECT_TRUE(sharpOrOpen) << "triangle " << tree[i].triangle;
      }
      for (int k = 0; k < a.pointCount; ++k)
        EXPECT_LE(a.points[k].separation, kSpeculativeDistance + 1e-6f);
    }
  }
  // The loop saw contacts, and some were not along a face.
  EXPECT_GT(withContacts, 100);
  EXPECT_GT(nonFace, 0);
}

// Whether `c` (seen from above: x and z) lies inside the convex outline of `points`, by at
// least 1 mm.
bool holdsUp(std::vector<Vec3> points, Vec3 c) {
  std::sort(points.begin(), points.end(),
            [](Vec3 a, Vec3 b) { return a.x < b.x || (a.x == b.x && a.z < b.z); });
  auto turn = [](Vec3 o, Vec3 a, Vec3 b) {
    return (a.x - o.x) * (b.z - o.z) - (a.z - o.z) * (b.x - o.x);
  };
  std::vector<Vec3> hull;  // Andrew's monotone chain, counter-clockwise in (x, z)
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t start = hull.size();
    for (const Vec3& p : points) {
      while (hull.size() >= start + 2 && turn(hull[hull.size() - 2], hull.back(), p) <= 0.0f)
        hull.pop_back();
      hull.push_back(p);
    }
    hull.pop_back();
    std::reverse(points.begin(), points.end());
  }
  if (hull.size() < 3) return false;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vec3 a = hull[i], b = hull[(i + 1) % hull.size()];
    if (turn(a, b, c) / distance(Vec3{a.x, 0, a.z}, Vec3{b.x, 0, b.z}) < 1e-3f) return false;
  }
  return true;
}

// A unit cube sliding 5 mm deep across a flat floor of two triangles, over their shared
// diagonal, turned at several headings: every contact normal is the floor's, every point
// 5 mm deep under the cube, and the points hold the cube up. The same slide
// through the plain triangle contact (collide on each Triangle3) shows the ghost normals
// this removes.
TEST(Mesh3, BoxSlidingAcrossASharedEdgeHasNoGhostBumps) {
  const Mesh3 floor = twoTriangleFloor(5);
  const Hull3 cube = makeBox3({0.5f, 0.5f, 0.5f}).value();
  const ShapeGeometry3 box = cube;
  int poses = 0, ghostsWithoutTheRule = 0;
  std::vector<MeshContact3> contacts;
  for (float heading : {0.0f, 0.3f, 0.785398f, 1.2f}) {
    const Quat q = Quat::fromAxisAngle({0, 1, 0}, heading);
    for (float z : {-1.0f, 0.0f, 0.37f}) {
      for (int step = 0; step <= 400; ++step) {
        const float x = -2.0f + 0.01f * static_cast<float>(step);
        const Transform3 pose{{x, 0.495f, z}, q};
        contacts.clear();
        collideMesh(floor, Transform3{}, box, pose, contacts);
        ++poses;
        ASSERT_FALSE(contacts.empty()) << x << " " << z << " " << heading;
        std::vector<Vec3> points;
        for (const MeshContact3& c : contacts) {
          ASSERT_GT(c.manifold.pointCount, 0);
          EXPECT_NEAR(c.manifold.normal.x, 0.0f, 1e-6f) << x << " " << z << " " << heading;
          EXPECT_NEAR(c.manifold.normal.y, 1.0f, 1e-6f) << x << " " << z << " " << heading;
          EXPECT_NEAR(c.manifold.normal.z, 0.0f, 1e-6f) << x << " " << z << " " << heading;
          for (int k = 0; k < c.manifold.pointCount; ++k) {
            EXPECT_NEAR(c.manifold.points[k].separation, -0.005f, 2e-6f);
            points.push_back(c.manifold.points[k].point);
          }
        }
        // Every point under the cube's bottom, midway between it and the floor, and the
        // cube's centre inside the points' outline seen from above (it is held up).
        for (const Vec3& p : points) {
          const Vec3 local = invTransformPoint(pose, p);
          EXPECT_NEAR(p.y, -0.0025f, 1e-6f);
          EXPECT_LE(std::abs(local.x), 0.5f + 1e-4f);
          EXPECT_LE(std::abs(local.z), 0.5f + 1e-4f);
        }
        EXPECT_TRUE(holdsUp(points, pose.p)) << x << " " << z << " " << heading;
        // The plain contact of each triangle on its own.
        for (int t = 0; t < 2; ++t) {
          Manifold3 plain = collide(ShapeGeometry3{floor.triangle(t)}, Transform3{}, box, pose);
          if (plain.pointCount > 0 && plain.normal.y < 0.999f) ++ghostsWithoutTheRule;
        }
      }
    }
  }
  EXPECT_EQ(poses, 4 * 3 * 401);
  EXPECT_GT(ghostsWithoutTheRule, 0) << "the control should show ghost normals";
}

// A sphere and a capsule rolling across a flat grid, over its vertices (where six
// triangles meet) and edges: every normal is the floor's, every point 5 mm deep.
TEST(Mesh3, SphereAndCapsuleAcrossAFlatGridHaveNoGhostBumps) {
  const Mesh3 g = grid(4, 2, [](float, float) { return 0.0f; });
  const std::vector<ShapeGeometry3> shapes = {
      makeSphere({0, 0, 0}, 0.3f).value(), makeCapsule3({-0.4f, 0, 0}, {0.4f, 0, 0}, 0.3f).value()};
  std::vector<MeshContact3> contacts;
  int points = 0;
  for (const ShapeGeometry3& shape : shapes) {
    for (float z : {0.0f, 0.5f, 0.23f}) {
      for (int step = 0; step <= 300; ++step) {
        const float x = -1.5f + 0.01f * static_cast<float>(step);
        const Transform3 pose{{x, 0.295f, z}, Quat::fromAxisAngle({0, 1, 0}, 0.4f)};
        contacts.clear();
        collideMesh(g, Transform3{}, shape, pose, contacts);
        ASSERT_FALSE(contacts.empty()) << x << " " << z;
        for (const MeshContact3& c : contacts) {
          EXPECT_NEAR(c.manifold.normal.y, 1.0f, 1e-6f) << x << " " << z;
          for (int k = 0; k < c.manifold.pointCount; ++k) {
            EXPECT_NEAR(c.manifold.points[k].separation, -0.005f, 2e-6f) << x << " " << z;
            ++points;
          }
        }
      }
    }
  }
  EXPECT_GE(points, 2 * 3 * 301);
}

// A sphere resting on a ridge touches its convex edge: one normal straight up, between the
// two faces'. Resting in a valley it touches both faces, each along its own normal.
TEST(Mesh3, SphereOnARidgeAndInAValley) {
  for (float top : {1.0f, -1.0f}) {
    const std::vector<Vec3> v = {{-2, 0, -2}, {0, top, -2}, {2, 0, -2},
                                 {-2, 0, 2},  {0, top, 2},  {2, 0, 2}};
    const std::vector<Tri> t = {{0, 3, 4}, {0, 4, 1}, {1, 4, 5}, {1, 5, 2}};
    const Mesh3 m = makeMesh3(v, t).value();
    const ShapeGeometry3 ball = makeSphere({0, 0, 0}, 0.5f).value();
    std::vector<MeshContact3> contacts;
    if (top > 0) {
      collideMesh(m, Transform3{}, ball, Transform3{{0, 1.49f, 0.3f}, {}}, contacts);
      ASSERT_FALSE(contacts.empty());
      for (const MeshContact3& c : contacts) {
        ASSERT_EQ(c.manifold.pointCount, 1);
        EXPECT_NEAR(c.manifold.normal.y, 1.0f, 1e-5f);
        EXPECT_NEAR(c.manifold.points[0].separation, -0.01f, 1e-5f);
      }
    } else {
      // The valley's faces drop 1 over 2 m: the centre above the valley's floor line is
      // sqrt(1.25) times its distance to either face, so 0.49 from both faces at this y.
      const float y = -1.0f + std::sqrt(1.25f) * 0.49f;
      collideMesh(m, Transform3{}, ball, Transform3{{0, y, 0.3f}, {}}, contacts);
      ASSERT_EQ(contacts.size(), 2u);
      for (const MeshContact3& c : contacts) {
        const Vec3 n = m.triangles()[static_cast<std::size_t>(c.triangle)].normal;
        ASSERT_EQ(c.manifold.pointCount, 1);
        EXPECT_NEAR(dot(c.manifold.normal, n), 1.0f, 1e-6f);
        EXPECT_NEAR(c.manifold.points[0].separation, -0.01f, 1e-5f);
      }
    }
  }
}

}  // namespace
}  // namespace quack
