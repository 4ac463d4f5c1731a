// Static triangle meshes and their contacts without ghost bumps (see mesh3.hpp).

#include "quack/collision/mesh3.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include "manifold3_internal.hpp"
#include "quack/collision/proxy3.hpp"

namespace quack {

const char* toString(MeshEdgeKind3 kind) noexcept {
  switch (kind) {
    case MeshEdgeKind3::boundary:
      return "boundary";
    case MeshEdgeKind3::convex:
      return "convex";
    case MeshEdgeKind3::flat:
      return "flat";
    case MeshEdgeKind3::concave:
      return "concave";
  }
  return "unknown";
}

Triangle3 Mesh3::triangle(int i) const noexcept {
  const MeshTriangle3& t = triangles_[static_cast<std::size_t>(i)];
  return {{vertices_[static_cast<std::size_t>(t.v[0])], vertices_[static_cast<std::size_t>(t.v[1])],
           vertices_[static_cast<std::size_t>(t.v[2])]}};
}

namespace {

Aabb3 triangleBox(const Triangle3& t) noexcept {
  Aabb3 b{t.v[0], t.v[0]};
  for (int k = 1; k < 3; ++k) {
    b.lower = minv(b.lower, t.v[k]);
    b.upper = maxv(b.upper, t.v[k]);
  }
  return b;
}

std::string edgeName(std::int32_t a, std::int32_t b) {
  return "(" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

}  // namespace

Result<Mesh3> makeMesh3(std::span<const Vec3> vertices,
                        std::span<const std::array<std::int32_t, 3>> triangles) {
  if (triangles.empty()) return fail("makeMesh3: no triangles");
  if (triangles.size() > static_cast<std::size_t>(kMaxMeshTriangles3)) {
    return fail("makeMesh3: " + std::to_string(triangles.size()) + " triangles, more than " +
                std::to_string(kMaxMeshTriangles3));
  }
  Mesh3 mesh;
  mesh.vertices_.assign(vertices.begin(), vertices.end());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Vec3 v = vertices[i];
    if (!isFinite(v)) return fail("makeMesh3: vertex " + std::to_string(i) + " is not finite");
    if (!(absf(v.x) <= kMaxCoordinate && absf(v.y) <= kMaxCoordinate &&
          absf(v.z) <= kMaxCoordinate)) {
      return fail("makeMesh3: vertex " + std::to_string(i) +
                  " is beyond the coordinate limit 1e9 m");
    }
    mesh.bounds_ =
        i == 0 ? Aabb3{v, v} : Aabb3{minv(mesh.bounds_.lower, v), maxv(mesh.bounds_.upper, v)};
  }
  const auto vertexCount = static_cast<std::int64_t>(vertices.size());
  mesh.triangles_.resize(triangles.size());
  // Each directed edge (a, b) of a triangle, keyed by its undirected pair.
  struct Side {
    std::int32_t triangle;
    int k;
    bool forward;  // runs from the smaller index to the larger
  };
  std::unordered_map<std::uint64_t, std::vector<Side>> sides;
  sides.reserve(triangles.size() * 2);
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const std::string name = "makeMesh3: triangle " + std::to_string(i);
    MeshTriangle3& t = mesh.triangles_[i];
    for (int k = 0; k < 3; ++k) {
      const std::int32_t v = triangles[i][static_cast<std::size_t>(k)];
      if (v < 0 || v >= vertexCount) {
        return fail(name + ": vertex index " + std::to_string(v) + " is out of range (0 to " +
                    std::to_string(vertexCount - 1) + ")");
      }
      t.v[k] = v;
      t.neighbour[k] = -1;
      t.edge[k] = MeshEdgeKind3::boundary;
    }
    if (t.v[0] == t.v[1] || t.v[1] == t.v[2] || t.v[2] == t.v[0])
      return fail(name + ": a vertex index is repeated");
    const Triangle3 shape = mesh.triangle(static_cast<int>(i));
    Result<Triangle3> checked = makeTriangle3(shape.v[0], shape.v[1], shape.v[2]);
    if (!checked) return fail(name + ": " + checked.error().message);
    t.normal = triangleNormal(shape);
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = t.v[k], b = t.v[(k + 1) % 3];
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) |
                                static_cast<std::uint32_t>(std::max(a, b));
      sides[key].push_back({static_cast<std::int32_t>(i), k, a < b});
    }
  }
  for (const auto& [key, list] : sides) {
    const auto a = static_cast<std::int32_t>(key >> 32);
    const auto b = static_cast<std::int32_t>(key & 0xFFFFFFFFu);
    if (list.size() > 2) {
      return fail("makeMesh3: edge " + edgeName(a, b) + " is shared by " +
                  std::to_string(list.size()) + " triangles (a mesh edge has one or two)");
    }
    if (list.size() < 2) continue;
    const Side& s = list[0];
    const Side& u = list[1];
    if (s.forward == u.forward) {
      return fail("makeMesh3: triangles " + std::to_string(std::min(s.triangle, u.triangle)) +
                  " and " + std::to_string(std::max(s.triangle, u.triangle)) +
                  " run along their edge " + edgeName(a, b) +
                  " the same way (their fronts disagree)");
    }
    // The kind of the edge, the same seen from either side: the neighbour's far vertex
    // below this triangle's plane is a ridge, above it a valley.
    MeshTriangle3& ts = mesh.triangles_[static_cast<std::size_t>(s.triangle)];
    MeshTriangle3& tu = mesh.triangles_[static_cast<std::size_t>(u.triangle)];
    MeshEdgeKind3 kind = MeshEdgeKind3::flat;
    if (dot(ts.normal, tu.normal) < kMeshFlatCosine3) {
      const Vec3 far = mesh.vertices_[static_cast<std::size_t>(tu.v[(u.k + 2) % 3])];
      const Vec3 onEdge = mesh.vertices_[static_cast<std::size_t>(ts.v[s.k])];
      kind = dot(ts.normal, far - onEdge) < 0.0f ? MeshEdgeKind3::convex : MeshEdgeKind3::concave;
    }
    ts.neighbour[s.k] = u.triangle;
    tu.neighbour[u.k] = s.triangle;
    ts.edge[s.k] = kind;
    tu.edge[u.k] = kind;
  }
  for (std::size_t i = 0; i < mesh.triangles_.size(); ++i)
    mesh.tree_.insert(static_cast<std::uint32_t>(i),
                      triangleBox(mesh.triangle(static_cast<int>(i))));
  mesh.tree_.rebuild();
  return mesh;
}

namespace {

// The convex shape's feature that meets a face of normal `n` (mesh frame): a hull's face
// most against n, a capsule's segment, a sphere's centre, a triangle's corners; with the
// rounding radius. Vertex ids are the shape's own vertex indices.
struct Incident {
  Vec3 points[kMaxHullVertices3];
  std::uint32_t ids[kMaxHullVertices3] = {};
  int count = 0;
  float radius = 0.0f;
};

Incident incidentFeature(const ShapeGeometry3& convex, Transform3 meshFromConvex, Vec3 n) noexcept {
  Incident f;
  if (const Hull3* h = std::get_if<Hull3>(&convex)) {
    const Vec3 nLocal = invRotate(meshFromConvex.q, n);
    int best = 0;
    for (int i = 1; i < h->faceCount; ++i)
      if (dot(h->faces[i].normal, nLocal) < dot(h->faces[best].normal, nLocal)) best = i;
    const HullFace3& face = h->faces[best];
    f.radius = h->radius;
    for (int k = 0; k < face.count; ++k) {
      const int v = h->faceVertices[face.first + k];
      f.points[f.count] = transformPoint(meshFromConvex, h->vertices[v]);
      f.ids[f.count++] = static_cast<std::uint32_t>(v);
    }
    return f;
  }
  const ShapeProxy3 proxy = makeProxy(convex);
  f.radius = proxy.radius();
  for (int i = 0; i < proxy.count(); ++i) {
    f.points[f.count] = transformPoint(meshFromConvex, proxy.points()[i]);
    f.ids[f.count++] = static_cast<std::uint32_t>(i);
  }
  return f;
}

struct ClipPoint {
  Vec3 p;
  std::uint32_t id = 0;
};

constexpr int kMeshClipCapacity = kMaxHullVertices3 + 8;

// The contact along a face normal: the incident feature clipped to the triangle's prism.
// `front` is the triangle's unit normal (counter-clockwise winding); `n` is the contact
// normal, front or -front (a lone triangle has two sides). Triangle frame.
Manifold3 faceContact(const Triangle3& tri, Vec3 front, Vec3 n, Transform3 worldFromMesh,
                      const ShapeGeometry3& convex, Transform3 worldFromConvex,
                      float speculativeDistance) noexcept {
  Manifold3 m;
  const Transform3 meshFromConvex = invMul(worldFromMesh, worldFromConvex);
  const Incident f = incidentFeature(convex, meshFromConvex, n);

  ClipPoint bufA[kMeshClipCapacity], bufB[kMeshClipCapacity];
  ClipPoint* poly = bufA;
  ClipPoint* next = bufB;
  int count = f.count;
  for (int i = 0; i < f.count; ++i)
    poly[i] = {f.points[i], f.ids[i]};
  // Sutherland-Hodgman against the three side planes (outward normal cross(edge, front),
  // whichever side the contact is on). A segment (two points) and a point clip the same
  // way: a closed polygon of 2 or 1.
  for (int k = 0; k < 3 && count > 0; ++k) {
    const Vec3 v0 = tri.v[k];
    const Vec3 side = cross(tri.v[(k + 1) % 3] - v0, front);
    int out = 0;
    if (count == 1) {
      if (dot(side, poly[0].p - v0) <= 0.0f) next[out++] = poly[0];
    } else {
      const int edges = count == 2 ? 1 : count;
      for (int i = 0; i < count && out + 2 <= kMeshClipCapacity; ++i) {
        const ClipPoint& p = poly[i];
        const ClipPoint& q = poly[(i + 1) % count];
        const float dp = dot(side, p.p - v0), dq = dot(side, q.p - v0);
        if (dp <= 0.0f) next[out++] = p;
        if (i < edges && (dp <= 0.0f) != (dq <= 0.0f)) {
          ClipPoint c;
          c.p = p.p + (dp / (dp - dq)) * (q.p - p.p);
          c.id = kManifold3IdClip | (static_cast<std::uint32_t>(k) << 8) | (p.id & 0xFFu);
          next[out++] = c;
        }
      }
    }
    std::swap(poly, next);
    count = out;
  }

  ManifoldPoint3 pts[kMeshClipCapacity];
  int kept = 0;
  for (int i = 0; i < count; ++i) {
    const float height = dot(n, poly[i].p - tri.v[0]);
    const float separation = height - f.radius;
    if (separation > speculativeDistance) continue;
    // Midway between the convex surface (the core point less the radius along n) and the
    // triangle's plane.
    const Vec3 mid = poly[i].p - (f.radius + 0.5f * separation) * n;
    pts[kept++] = detail::makeManifoldPoint3(transformPoint(worldFromMesh, mid), separation,
                                             poly[i].id, worldFromMesh, worldFromConvex);
  }
  if (kept == 0) return m;
  m.normal = transformVector(worldFromMesh, n);
  m.pointCount = detail::reduceManifoldPoints3(pts, kept, m.normal);
  for (int i = 0; i < m.pointCount; ++i)
    m.points[i] = pts[i];
  return m;
}

// Whether the triangle's feature at `pointOnTriangle` (mesh frame) may carry a normal that is
// not the face's: a convex or boundary edge, or a vertex whose two edges both are.
bool featureAllowsEdgeNormal(const MeshTriangle3& t, const Triangle3& tri,
                             Vec3 pointOnTriangle) noexcept {
  // Barycentric weights of the point's projection on the plane.
  const Vec3 e0 = tri.v[1] - tri.v[0], e1 = tri.v[2] - tri.v[0], p = pointOnTriangle - tri.v[0];
  const float d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1);
  const float d20 = dot(p, e0), d21 = dot(p, e1);
  const float denom = d00 * d11 - d01 * d01;
  const float wb = (d11 * d20 - d01 * d21) / denom;
  const float wc = (d00 * d21 - d01 * d20) / denom;
  const float w[3] = {1.0f - wb - wc, wb, wc};
  // Edge k (v[k] to v[k + 1]) is where the weight of v[k + 2] vanishes.
  constexpr float kOnFeature = 1e-4f;
  bool any = false;
  for (int k = 0; k < 3; ++k) {
    if (w[(k + 2) % 3] > kOnFeature) continue;
    any = true;
    if (t.edge[k] != MeshEdgeKind3::boundary && t.edge[k] != MeshEdgeKind3::convex) return false;
  }
  return any;  // inside the face: only the face normal
}

}  // namespace

Manifold3 collideMeshTriangle(const Mesh3& mesh, int triangle, Transform3 worldFromMesh,
                              const ShapeGeometry3& convex, Transform3 worldFromConvex,
                              float speculativeDistance) noexcept {
  const MeshTriangle3& t = mesh.triangles()[static_cast<std::size_t>(triangle)];
  const Triangle3 tri = mesh.triangle(triangle);
  Manifold3 g = collideGeneral(makeProxy(tri), worldFromMesh, makeProxy(convex), worldFromConvex,
                               speculativeDistance);
  if (g.pointCount == 0) return g;
  const Vec3 n = invTransformVector(worldFromMesh, g.normal);
  const float along = dot(n, t.normal);
  if (along < kMeshFaceNormalCosine3) {
    // Not the face's normal: kept only at a convex or boundary feature, and only from the
    // front (the mesh is one-sided).
    const ManifoldPoint3& p = g.points[0];
    const Vec3 onTriangle = invTransformPoint(worldFromMesh, p.point) - (0.5f * p.separation) * n;
    if (along > 0.0f && featureAllowsEdgeNormal(t, tri, onTriangle)) return g;
  }
  return faceContact(tri, t.normal, t.normal, worldFromMesh, convex, worldFromConvex,
                     speculativeDistance);
}

Manifold3 collideTriangle(const Triangle3& triangle, Transform3 worldFromTriangle,
                          const ShapeGeometry3& convex, Transform3 worldFromConvex,
                          float speculativeDistance) noexcept {
  Manifold3 g = collideGeneral(makeProxy(triangle), worldFromTriangle, makeProxy(convex),
                               worldFromConvex, speculativeDistance);
  if (g.pointCount == 0) return g;
  // A face normal (on either side) gets the face's points; any other normal is an edge's, a
  // corner's, or, deep inside, the other shape's own face: all edges of a lone triangle are
  // boundaries, so unlike a mesh triangle there is no neighbour's edge to guard against, and
  // the general contact (the least push out) stands.
  const Vec3 front = normalize(cross(triangle.v[1] - triangle.v[0], triangle.v[2] - triangle.v[0]));
  const float along = dot(invTransformVector(worldFromTriangle, g.normal), front);
  if (absf(along) < kMeshFaceNormalCosine3) return g;
  const Manifold3 face =
      faceContact(triangle, front, along < 0.0f ? -front : front, worldFromTriangle, convex,
                  worldFromConvex, speculativeDistance);
  // The clipped feature must hold the deepest point. A shape that reaches over an edge with
  // its deepest part outside the triangle's prism (a ball whose centre is past the edge, a
  // thin slab crossing the edge) clips to nothing or to points shallower than the shapes
  // are: a lone triangle has no neighbour to take the contact, so the general one stands.
  float deepest = std::numeric_limits<float>::infinity();
  for (int i = 0; i < face.pointCount; ++i)
    deepest = std::min(deepest, face.points[i].separation);
  return deepest <= g.points[0].separation + kLinearSlop ? face : g;
}

int collideMesh(const Mesh3& mesh, Transform3 worldFromMesh, const ShapeGeometry3& convex,
                Transform3 worldFromConvex, std::vector<MeshContact3>& contacts,
                float speculativeDistance) {
  // The convex shape's box in the mesh frame, grown by its radius and the speculative
  // distance.
  const Transform3 meshFromConvex = invMul(worldFromMesh, worldFromConvex);
  const ShapeProxy3 proxy = makeProxy(convex);
  Aabb3 box;
  for (int i = 0; i < proxy.count(); ++i) {
    const Vec3 p = transformPoint(meshFromConvex, proxy.points()[i]);
    box = i == 0 ? Aabb3{p, p} : Aabb3{minv(box.lower, p), maxv(box.upper, p)};
  }
  const float grow = proxy.radius() + speculativeDistance;
  box.lower = box.lower - Vec3{grow, grow, grow};
  box.upper = box.upper + Vec3{grow, grow, grow};
  const std::size_t first = contacts.size();
  mesh.query(box, [&](int triangle) {
    Manifold3 m = collideMeshTriangle(mesh, triangle, worldFromMesh, convex, worldFromConvex,
                                      speculativeDistance);
    if (m.pointCount > 0) contacts.push_back({triangle, m});
    return true;
  });
  std::sort(contacts.begin() + static_cast<std::ptrdiff_t>(first), contacts.end(),
            [](const MeshContact3& a, const MeshContact3& b) { return a.triangle < b.triangle; });
  return static_cast<int>(contacts.size() - first);
}

namespace {

float maxAbs(Vec3 v) noexcept {
  return std::max({absf(v.x), absf(v.y), absf(v.z)});
}

// A margin for the tree's box tests: a triangle's own test (Moller-Trumbore, or GJK within
// kShapeCastTolerance) rounds differently from the slab test against its box, and could
// accept a point a few ulps outside that box. 1e-5 of the largest coordinate in play is
// about 80 float ulps of it: far more than either test's rounding, far less than any
// triangle worth keeping, so the tree finds every triangle the brute-force loop would.
float treeMargin(Aabb3 bounds, Vec3 a, Vec3 b) noexcept {
  const float scale =
      std::max({maxAbs(bounds.lower), maxAbs(bounds.upper), maxAbs(a), maxAbs(b), 1.0f});
  return 1e-5f * scale;
}

// The triangle's own hit, kept only when the ray comes at the front: rayCast(Triangle3)
// is two-sided and turns its normal towards the origin, so a normal against the face's
// means the ray came from behind.
RayHit3 frontHit(const Mesh3& mesh, int triangle, const RayCastInput3& ray) noexcept {
  RayHit3 h = rayCast(mesh.triangle(triangle), ray);
  if (h.hit && dot(h.normal, mesh.triangles()[static_cast<std::size_t>(triangle)].normal) <= 0.0f) {
    return {};
  }
  return h;
}

}  // namespace

MeshRayHit3 rayCastMesh(const Mesh3& mesh, Transform3 worldFromMesh,
                        const RayCastInput3& ray) noexcept {
  MeshRayHit3 best;
  if (!isFinite(ray.origin) || !isFinite(ray.translation) || !std::isfinite(ray.maxFraction) ||
      !(ray.maxFraction >= 0.0f) || lengthSquared(ray.translation) <= 0.0f ||
      !isFinite(worldFromMesh.p) || !isFinite(worldFromMesh.q)) {
    return best;
  }
  // The ray in the mesh frame, where the triangles and their tree are.
  RayCastInput3 local{invTransformPoint(worldFromMesh, ray.origin),
                      invTransformVector(worldFromMesh, ray.translation), ray.maxFraction};
  const float m =
      treeMargin(mesh.bounds(), local.origin, local.origin + local.maxFraction * local.translation);
  RayHit3 hit;
  mesh.tree().rayCast(local.origin, local.translation, local.maxFraction, Vec3{m, m, m},
                      [&](std::uint32_t proxy, float maxFraction) {
                        const int t = static_cast<int>(proxy);
                        RayCastInput3 clipped = local;
                        clipped.maxFraction = maxFraction;
                        const RayHit3 h = frontHit(mesh, t, clipped);
                        // The same fraction as the best so far: the lower index wins, as in
                        // a loop over every triangle in order.
                        if (h.hit && (!hit.hit || h.fraction < hit.fraction ||
                                      (h.fraction == hit.fraction && t < best.triangle))) {
                          hit = h;
                          best.triangle = t;
                        }
                        // Clip the ray to the best hit; ties at its fraction are still
                        // visited. A hit at 0 leaves the reach as it is: the tree stops
                        // at a clip of 0, and a lower index may tie there.
                        return hit.hit && hit.fraction > 0.0f ? hit.fraction : maxFraction;
                      });
  if (!hit.hit) {
    best.triangle = -1;
    return best;
  }
  best.hit = true;
  best.fraction = hit.fraction;
  best.point = transformPoint(worldFromMesh, hit.point);
  best.normal = transformVector(worldFromMesh, hit.normal);
  return best;
}

MeshShapeCastOutput3 castShapeMesh(const Mesh3& mesh, Transform3 worldFromMesh,
                                   const ShapeProxy3& b, Transform3 worldFromB, Vec3 translationB,
                                   float maxFraction) noexcept {
  MeshShapeCastOutput3 best;
  best.status = ShapeCastStatus::missed;
  if (!isFinite(worldFromMesh.p) || !isFinite(worldFromMesh.q) || !isFinite(worldFromB.p) ||
      !isFinite(worldFromB.q) || !isFinite(translationB) ||
      !(maxFraction >= 0.0f && maxFraction <= 1.0f)) {
    best.status = ShapeCastStatus::invalidInput;
    return best;
  }
  // B's swept box in the mesh frame: the box of its points at the start and at the end of
  // the (clipped) translation holds every point of the sweep (the sweep is their convex
  // hull), grown by B's radius, the cast's tolerance and the rounding margin.
  const Transform3 meshFromB = invMul(worldFromMesh, worldFromB);
  const Vec3 move = invTransformVector(worldFromMesh, maxFraction * translationB);
  Aabb3 box;
  for (int i = 0; i < b.count(); ++i) {
    const Vec3 p = transformPoint(meshFromB, b.points()[i]);
    const Aabb3 pb{minv(p, p + move), maxv(p, p + move)};
    box = i == 0 ? pb : Aabb3{minv(box.lower, pb.lower), maxv(box.upper, pb.upper)};
  }
  const float grow =
      b.radius() + kShapeCastTolerance + treeMargin(mesh.bounds(), box.lower, box.upper);
  box.lower = box.lower - Vec3{grow, grow, grow};
  box.upper = box.upper + Vec3{grow, grow, grow};
  const Vec3 translationInMesh = invTransformVector(worldFromMesh, translationB);
  bool capped = false;
  float cappedFraction = maxFraction;
  mesh.query(box, [&](int t) {
    const MeshTriangle3& tri = mesh.triangles()[static_cast<std::size_t>(t)];
    if (dot(translationInMesh, tri.normal) > 0.0f) return true;  // leaves its front
    // Conservative advancement's steps do not depend on maxFraction, only where it stops,
    // so casting to the best fraction so far finds the same hit at or before it as a cast
    // to the end would (a later one is no use).
    const float reach = best.hit ? best.fraction : maxFraction;
    const ShapeCastOutput3 c =
        castShape(makeProxy(mesh.triangle(t)), worldFromMesh, b, worldFromB, translationB, reach);
    if (c.hit) {
      if (!best.hit || c.fraction < best.fraction ||
          (c.fraction == best.fraction && t < best.triangle)) {
        static_cast<ShapeCastOutput3&>(best) = c;
        best.triangle = t;
      }
    } else if (c.status == ShapeCastStatus::maxIterations) {
      capped = true;
      cappedFraction = std::min(cappedFraction, c.fraction);
    }
    return true;
  });
  if (!best.hit && capped) {
    best.status = ShapeCastStatus::maxIterations;
    best.fraction = cappedFraction;
  }
  return best;
}

namespace {

// B's box in the mesh frame, grown by its radius and `extra`.
Aabb3 boxInMesh(Transform3 meshFromB, const ShapeProxy3& b, float extra) noexcept {
  Aabb3 box;
  for (int i = 0; i < b.count(); ++i) {
    const Vec3 p = transformPoint(meshFromB, b.points()[i]);
    box = i == 0 ? Aabb3{p, p} : Aabb3{minv(box.lower, p), maxv(box.upper, p)};
  }
  const float grow = b.radius() + extra;
  box.lower = box.lower - Vec3{grow, grow, grow};
  box.upper = box.upper + Vec3{grow, grow, grow};
  return box;
}

}  // namespace

bool testOverlapMesh(const Mesh3& mesh, Transform3 worldFromMesh, const ShapeProxy3& b,
                     Transform3 worldFromB) noexcept {
  const Transform3 meshFromB = invMul(worldFromMesh, worldFromB);
  Aabb3 box = boxInMesh(meshFromB, b, 0.0f);
  const float m = treeMargin(mesh.bounds(), box.lower, box.upper);
  box.lower = box.lower - Vec3{m, m, m};
  box.upper = box.upper + Vec3{m, m, m};
  bool overlap = false;
  mesh.query(box, [&](int t) {
    overlap = testOverlap(makeProxy(mesh.triangle(t)), worldFromMesh, b, worldFromB);
    return !overlap;
  });
  return overlap;
}

MeshDistanceOutput3 computeDistanceMesh(const Mesh3& mesh, Transform3 worldFromMesh,
                                        const ShapeProxy3& b, Transform3 worldFromB) {
  const Transform3 meshFromB = invMul(worldFromMesh, worldFromB);
  const Aabb3 box = boxInMesh(meshFromB, b, 0.0f);
  const float margin = treeMargin(mesh.bounds(), box.lower, box.upper);
  // Each triangle's lower bound: the gap between its box and B's (B's box holds B with its
  // radius), less the rounding margin so that GJK's own rounding cannot undercut it.
  struct Candidate {
    float bound;
    int triangle;
  };
  std::vector<Candidate> order(static_cast<std::size_t>(mesh.triangleCount()));
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const Aabb3 tb = triangleBox(mesh.triangle(t));
    const Vec3 gap = maxv(Vec3{}, maxv(tb.lower - box.upper, box.lower - tb.upper));
    order[static_cast<std::size_t>(t)] = {length(gap) - margin, t};
  }
  std::sort(order.begin(), order.end(), [](const Candidate& x, const Candidate& y) {
    return x.bound < y.bound || (x.bound == y.bound && x.triangle < y.triangle);
  });
  MeshDistanceOutput3 best;
  for (const Candidate& c : order) {
    if (best.triangle >= 0 && c.bound > best.distance) break;
    const DistanceOutput3 d =
        computeDistance(makeProxy(mesh.triangle(c.triangle)), worldFromMesh, b, worldFromB);
    if (best.triangle < 0 || d.distance < best.distance ||
        (d.distance == best.distance && c.triangle < best.triangle)) {
      static_cast<DistanceOutput3&>(best) = d;
      best.triangle = c.triangle;
    }
  }
  return best;
}

namespace {

bool finiteSweep(const Sweep3& s) noexcept {
  return isFinite(s.localCenter) && isFinite(s.c1) && isFinite(s.c2) && isFinite(s.q1) &&
         isFinite(s.rotation) && lengthSquared(s.q1) > 0.0f;
}

// Whether a triangle's run `c` comes before `best`: an earlier t; at one t an overlap
// before a hit, and the deeper overlap first (depths are computePenetration's, 0 for runs
// that did not overlap); then the lower index, as in a loop over every triangle in order.
bool comesBefore(const ToiOutput3& c, float depth, int triangle, const MeshToiOutput3& best,
                 float bestDepth) noexcept {
  if (best.triangle < 0 || c.t != best.t) return best.triangle < 0 || c.t < best.t;
  const bool overlap = c.status == ToiStatus::overlapped;
  if (overlap != (best.status == ToiStatus::overlapped)) return overlap;
  if (depth != bestDepth) return depth > bestDepth;
  return triangle < best.triangle;
}

}  // namespace

MeshToiOutput3 computeToiMesh(const Mesh3& mesh, Transform3 worldFromMesh, const ShapeProxy3& b,
                              const Sweep3& sweepB, float tMax, float target) noexcept {
  MeshToiOutput3 best;
  if (!isFinite(worldFromMesh.p) || !isFinite(worldFromMesh.q) || !finiteSweep(sweepB) ||
      !(tMax >= 0.0f && tMax <= 1.0f) || !(target >= 0.0f && std::isfinite(target))) {
    best.status = ToiStatus::invalidInput;
    return best;
  }
  // B's swept bounds in the mesh frame: its centre of mass runs along a segment, and no
  // point of B is further from it than its reach, however B turns.
  const Vec3 c1 = invTransformPoint(worldFromMesh, sweepB.c1);
  const Vec3 c2 = invTransformPoint(worldFromMesh, (1.0f - tMax) * sweepB.c1 + tMax * sweepB.c2);
  Aabb3 box{minv(c1, c2), maxv(c1, c2)};
  const float grow = computeReach(b, sweepB.localCenter) + target + kToiTolerance +
                     treeMargin(mesh.bounds(), box.lower, box.upper);
  box.lower = box.lower - Vec3{grow, grow, grow};
  box.upper = box.upper + Vec3{grow, grow, grow};
  const Vec3 velocityInMesh = invTransformVector(worldFromMesh, sweepB.c2 - sweepB.c1);
  const Sweep3 meshSweep{Vec3{}, worldFromMesh.p, worldFromMesh.p, worldFromMesh.q, Vec3{}};
  MeshToiOutput3 failed;  // the failed run with the least last free time
  float bestDepth = 0.0f;
  mesh.query(box, [&](int t) {
    const MeshTriangle3& tri = mesh.triangles()[static_cast<std::size_t>(t)];
    if (dot(velocityInMesh, tri.normal) > 0.0f) return true;  // the centre leaves its front
    const ShapeProxy3 proxy = makeProxy(mesh.triangle(t));
    // Advancement's steps do not depend on tMax, only where it stops, so a run cut just
    // past the earliest time so far finds any hit at or before it (ties included) exactly
    // as a full run would.
    const float reach = best.triangle >= 0 ? std::min(std::nextafter(best.t, 2.0f), tMax) : tMax;
    ToiOutput3 c = computeToi(proxy, meshSweep, b, sweepB, reach, target);
    // A cut run that stopped on its last step may be one that the full run would have
    // failed with (its last free time before the cut): run it in full to know.
    if (c.status == ToiStatus::separated && c.iterations == kToi3MaxIterations && reach < tMax)
      c = computeToi(proxy, meshSweep, b, sweepB, tMax, target);
    // Overlaps at t = 0 are ranked by depth, so the answer is the deepest triangle's, as
    // computePenetrationMesh's among these (computeToi's overlap answer is EPA's on the
    // same poses; only its depth is not kept).
    const float depth =
        c.status == ToiStatus::overlapped
            ? computePenetration(proxy, worldFromMesh, b, transformAt(sweepB, 0.0f)).depth
            : 0.0f;
    if (c.status == ToiStatus::hit || c.status == ToiStatus::overlapped) {
      if (comesBefore(c, depth, t, best, bestDepth)) {
        static_cast<ToiOutput3&>(best) = c;
        best.triangle = t;
        bestDepth = depth;
      }
    } else if (c.status == ToiStatus::failed && comesBefore(c, 0.0f, t, failed, 0.0f)) {
      static_cast<ToiOutput3&>(failed) = c;
      failed.triangle = t;
    }
    return true;
  });
  // A failed run leaves its triangle unknown past its last free time: a hit after that is
  // not proven first.
  if (failed.triangle >= 0 && (best.triangle < 0 || failed.t < best.t)) return failed;
  if (best.triangle < 0) {
    best.status = ToiStatus::separated;
    best.t = tMax;
  }
  return best;
}

MeshPenetrationOutput3 computePenetrationMesh(const Mesh3& mesh, Transform3 worldFromMesh,
                                              const ShapeProxy3& b, Transform3 worldFromB) {
  const Transform3 meshFromB = invMul(worldFromMesh, worldFromB);
  Aabb3 box = boxInMesh(meshFromB, b, 0.0f);
  const float m = treeMargin(mesh.bounds(), box.lower, box.upper);
  box.lower = box.lower - Vec3{m, m, m};
  box.upper = box.upper + Vec3{m, m, m};
  MeshPenetrationOutput3 best;
  mesh.query(box, [&](int t) {
    const PenetrationOutput3 p =
        computePenetration(makeProxy(mesh.triangle(t)), worldFromMesh, b, worldFromB);
    if (p.overlap && (best.triangle < 0 || p.depth > best.depth ||
                      (p.depth == best.depth && t < best.triangle))) {
      static_cast<PenetrationOutput3&>(best) = p;
      best.triangle = t;
    }
    return true;
  });
  if (best.triangle >= 0) return best;
  // Apart from every triangle: the closest one's answer, as computePenetration gives for
  // shapes apart.
  const int closest = computeDistanceMesh(mesh, worldFromMesh, b, worldFromB).triangle;
  static_cast<PenetrationOutput3&>(best) =
      computePenetration(makeProxy(mesh.triangle(closest)), worldFromMesh, b, worldFromB);
  best.triangle = closest;
  return best;
}

}  // namespace quack
