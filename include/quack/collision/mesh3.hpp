#pragma once
/// Static triangle meshes in 3D: triangles with their own tree and edge adjacency, and the
/// contact manifolds of a convex shape against them without ghost bumps on shared edges.
///
/// A mesh is one-sided: each triangle's front is where cross(v1 - v0, v2 - v0) points
/// (counter-clockwise seen from the front), and contacts push the convex shape out of the
/// front. Each edge knows the triangle across it and whether the two bend away from each
/// other (convex), lie in one plane (flat) or fold towards each other (concave).
///
/// Ghost bumps: a box sliding across a flat floor made of two triangles overlaps the
/// second triangle only by a sliver as it crosses their shared edge, and the general
/// contact (GJK or EPA on that triangle alone) then pushes it sideways out of the sliver,
/// a bump the floor does not have. Here a contact normal that is not the triangle's face
/// normal is kept only when the triangle's feature at the contact is a convex or boundary
/// edge, or a vertex whose two edges are; otherwise the contact is made along the face
/// normal, with the convex shape's incident feature clipped to the triangle (the part over
/// the neighbour is the neighbour's contact). This is the Voronoi-region rule of internal
/// edge removal (as Jolt and Box3D describe it; no peer's code was consulted).

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "quack/broadphase/dynamic_tree3.hpp"
#include "quack/collision/epa3.hpp"
#include "quack/collision/manifold3.hpp"
#include "quack/collision/toi3.hpp"
#include "quack/geometry/raycast3.hpp"

namespace quack {

/// Most triangles in a mesh (the tree's proxy ids and the manifold ids leave room).
inline constexpr int kMaxMeshTriangles3 = 1 << 20;

/// Two triangles across an edge are flat when their normals' dot product is at least this
/// (about 0.25 degrees between them).
inline constexpr float kMeshFlatCosine3 = 0.99999f;

/// A contact normal within this cosine of the face normal is the face's.
inline constexpr float kMeshFaceNormalCosine3 = 0.99999f;

/// What the two triangles across an edge do there.
enum class MeshEdgeKind3 : std::uint8_t {
  boundary,  ///< no triangle across it
  convex,    ///< the neighbour bends away from this triangle's front (a ridge)
  flat,      ///< the neighbour lies in this triangle's plane (kMeshFlatCosine3)
  concave,   ///< the neighbour folds towards this triangle's front (a valley)
};

/// Name of an edge kind ("boundary", "convex", "flat", "concave").
const char* toString(MeshEdgeKind3 kind) noexcept;

/// One triangle of a mesh. Mesh frame.
struct MeshTriangle3 {
  std::int32_t v[3] = {};          ///< vertex indices, counter-clockwise seen from the front
  std::int32_t neighbour[3] = {};  ///< the triangle across edge k (v[k] to v[k + 1]), or -1
  MeshEdgeKind3 edge[3] = {};      ///< what edge k is
  Vec3 normal;                     ///< unit, cross(v1 - v0, v2 - v0) normalised: the front
};

/// A static triangle mesh: vertices, triangles with adjacency, and a DynamicTree3 over the
/// triangles' boxes (proxy = triangle index), built once. Mesh frame. Made by makeMesh3.
class Mesh3 {
 public:
  std::span<const Vec3> vertices() const noexcept { return vertices_; }
  std::span<const MeshTriangle3> triangles() const noexcept { return triangles_; }
  int triangleCount() const noexcept { return static_cast<int>(triangles_.size()); }
  /// Triangle `i` as a shape (its three vertices), mesh frame.
  Triangle3 triangle(int i) const noexcept;
  /// The tree over the triangles' boxes.
  const DynamicTree3& tree() const noexcept { return tree_; }
  /// The box of every vertex.
  Aabb3 bounds() const noexcept { return bounds_; }
  /// Calls `visit(triangle)` for every triangle whose box overlaps `box` (mesh frame,
  /// touching counts); `visit` returns false to stop.
  template <class Visit>
  void query(Aabb3 box, Visit&& visit) const {
    tree_.query(box, [&](std::uint32_t proxy) { return visit(static_cast<int>(proxy)); });
  }

 private:
  friend Result<Mesh3> makeMesh3(std::span<const Vec3>,
                                 std::span<const std::array<std::int32_t, 3>>);
  std::vector<Vec3> vertices_;
  std::vector<MeshTriangle3> triangles_;
  DynamicTree3 tree_;
  Aabb3 bounds_;
};

/// A mesh of `triangles` (vertex indices, counter-clockwise seen from the front) over
/// `vertices` (mesh frame). Allocates; builds the adjacency and the tree. Errors, naming
/// the triangle or edge: no triangles or more than kMaxMeshTriangles3, a vertex that is not
/// finite or beyond the coordinate limit, an index out of range or repeated in a triangle,
/// a triangle with no area (makeTriangle3's test), an edge shared by more than two
/// triangles, or two triangles that run along their shared edge the same way (their fronts
/// disagree).
Result<Mesh3> makeMesh3(std::span<const Vec3> vertices,
                        std::span<const std::array<std::int32_t, 3>> triangles);

/// The contact of a convex shape with one triangle of a mesh.
struct MeshContact3 {
  int triangle = 0;
  Manifold3 manifold;  ///< A is the mesh: the normal points from the mesh to the convex
};

/// The manifold of triangle `triangle` of the mesh (placed by worldFromMesh) against a
/// convex shape (placed by worldFromConvex), with the edge rule above: the general contact
/// when its normal is the face's or the triangle's feature at the contact is a convex or
/// boundary edge (or a vertex whose edges both are); otherwise up to four points along the
/// face normal, the convex shape's incident feature (a hull's face most against the normal,
/// a capsule's segment, a sphere's centre, a triangle) clipped to the triangle. Ids: the
/// general contact's, or the clipped feature's vertex, with kManifold3IdClip for a point
/// made by a side of the triangle. No allocation.
Manifold3 collideMeshTriangle(const Mesh3& mesh, int triangle, Transform3 worldFromMesh,
                              const ShapeGeometry3& convex, Transform3 worldFromConvex,
                              float speculativeDistance = kSpeculativeDistance) noexcept;

/// Every triangle's contact with a convex shape: the triangles the tree finds around the
/// shape's box (grown by the speculative distance), each through collideMeshTriangle,
/// appended to `contacts` in triangle order (those with at least one point). Returns how
/// many were appended. Allocates only when `contacts` grows.
int collideMesh(const Mesh3& mesh, Transform3 worldFromMesh, const ShapeGeometry3& convex,
                Transform3 worldFromConvex, std::vector<MeshContact3>& contacts,
                float speculativeDistance = kSpeculativeDistance);

/// Where a ray first enters a mesh from a triangle's front. World frame.
struct MeshRayHit3 : RayHit3 {
  int triangle = -1;  ///< the triangle hit, or -1 on a miss
};

/// The ray `ray` (world frame: origin + t * translation, t in [0, maxFraction]) against the
/// mesh placed by worldFromMesh: the closest hit over the triangles the mesh's tree finds
/// along it, each by rayCast(Triangle3) in the mesh frame. One-sided, as the mesh's
/// contacts are: a triangle is hit only from its front (the ray's translation against the
/// face normal); a ray from behind, or in a triangle's plane, passes through. The normal is
/// the face normal (unit, world). Ties (a shared edge or vertex) go to the lowest triangle
/// index, so the answer is the brute-force loop's over every triangle, to the bit. A zero
/// or non-finite translation, or a maxFraction that is negative or not finite, misses. No
/// allocation.
MeshRayHit3 rayCastMesh(const Mesh3& mesh, Transform3 worldFromMesh,
                        const RayCastInput3& ray) noexcept;

/// The earliest hit of a convex shape swept along a translation against a mesh. World frame.
struct MeshShapeCastOutput3 : ShapeCastOutput3 {
  int triangle = -1;  ///< the triangle hit (or overlapped), or -1
};

/// Casts convex proxy B, placed by worldFromB, along translationB (world, metres, fractions
/// [0, maxFraction]) against the mesh placed by worldFromMesh: castShape against each
/// triangle whose box overlaps B's swept box (grown by B's radius and
/// kShapeCastTolerance), the earliest hit kept; ties go to the lowest triangle index, so the
/// answer is the brute-force loop's over every triangle. One-sided as rayCastMesh: a
/// triangle whose front the translation leaves (dot(translationB, face normal) > 0) is not
/// hit; a shape sliding along a face or standing still keeps it. `point` and `normal` are
/// the triangle's cast (normal from the mesh to B). Status: the earliest triangle's hit or
/// overlapped; missed when no triangle is hit; maxIterations when none is hit and some
/// triangle's cast reached the cap (then `fraction` is the least fraction proven free over
/// those); invalidInput as castShape. No allocation.
MeshShapeCastOutput3 castShapeMesh(const Mesh3& mesh, Transform3 worldFromMesh,
                                   const ShapeProxy3& b, Transform3 worldFromB, Vec3 translationB,
                                   float maxFraction = 1.0f) noexcept;

/// Whether convex proxy B, placed by worldFromB, overlaps (or touches) any triangle of the
/// mesh placed by worldFromMesh: testOverlap against each triangle the tree finds around
/// B's box. Two-sided: a triangle is a solid sliver here, whichever side B is on. No
/// allocation.
bool testOverlapMesh(const Mesh3& mesh, Transform3 worldFromMesh, const ShapeProxy3& b,
                     Transform3 worldFromB) noexcept;

/// The distance from a mesh to a convex shape: the closest triangle's. World frame.
struct MeshDistanceOutput3 : DistanceOutput3 {
  int triangle = -1;  ///< the closest triangle (the lowest index among equals)
};

/// The closest triangle of the mesh placed by worldFromMesh to convex proxy B placed by
/// worldFromB: computeDistance against the triangles in order of their boxes' distance
/// from B's box, stopping once a box is further than the best distance found, so the
/// answer is the brute-force loop's over every triangle (ties to the lowest index).
/// Two-sided, as testOverlapMesh; 0 when B touches or overlaps a triangle. Allocates a list
/// of the triangles.
MeshDistanceOutput3 computeDistanceMesh(const Mesh3& mesh, Transform3 worldFromMesh,
                                        const ShapeProxy3& b, Transform3 worldFromB);

/// The first time a convex shape on a rotating sweep comes within the target of a mesh.
/// World frame.
struct MeshToiOutput3 : ToiOutput3 {
  int triangle = -1;  ///< the triangle hit (or overlapped, or whose run failed), or -1
};

/// The first t in [0, tMax] at which convex proxy B, moving by sweepB (body frame = the
/// proxy's shape frame), comes within `target` metres of the static mesh placed by
/// worldFromMesh: computeToi against each triangle whose box overlaps B's swept bounds (the
/// segment its centre of mass travels up to tMax, grown by its reach from that centre, the
/// target, kToiTolerance and the rounding margin: no point of B leaves that ball), each run
/// only to the earliest time found so far (advancement's steps do not depend on tMax, so
/// the answer is the brute-force loop's over every triangle; ties at one t go to the lowest
/// triangle index, except that at t = 0 an overlap comes before a hit and the deepest
/// overlap (computePenetration's depth) first, so an overlapped answer is the deepest
/// triangle's among the candidates, not a sliver's sideways normal). One-sided as castShapeMesh: a
/// triangle is skipped when B's centre of mass moves out of its front (dot(c2 - c1, face normal) >
/// 0); a sweep that only turns keeps every triangle. For a sweep without rotation the candidates
/// are castShapeMesh's. Status, as computeToi's: the earliest triangle's hit or overlapped (at t =
/// 0); failed when some triangle's run reached kToi3MaxIterations at a last free time before every
/// hit (then `t` is the least such time, `triangle` that triangle); separated (t = tMax,
/// distance and normal 0, triangle -1) when no triangle comes within the target;
/// invalidInput as computeToi, or a non-finite worldFromMesh. No allocation.
MeshToiOutput3 computeToiMesh(const Mesh3& mesh, Transform3 worldFromMesh, const ShapeProxy3& b,
                              const Sweep3& sweepB, float tMax = 1.0f,
                              float target = kToiTargetSeparation) noexcept;

/// The penetration of a convex shape into a mesh. World frame.
struct MeshPenetrationOutput3 : PenetrationOutput3 {
  int triangle = -1;  ///< the deepest triangle (or the closest, when none overlaps)
};

/// The deepest penetration of convex proxy B, placed by worldFromB, into any one triangle
/// of the mesh placed by worldFromMesh: computePenetration against each triangle the tree
/// finds around B's box, the largest depth kept (ties to the lowest triangle index), so the
/// answer is the brute-force loop's over every triangle. Two-sided, as testOverlapMesh:
/// each triangle is a solid sliver, and its depth is EPA's on that triangle alone (no edge
/// rule: collideMesh is where ghost normals are removed). The deepest depth is the least
/// distance any translation of B must cover to clear every triangle (each triangle alone
/// needs its own depth); the normal clears that triangle, not always its neighbours. When
/// B overlaps no triangle, computeDistanceMesh's closest triangle, as computePenetration
/// answers for shapes apart (overlap false, depth 0, status separated). Allocates only
/// then (computeDistanceMesh's list).
MeshPenetrationOutput3 computePenetrationMesh(const Mesh3& mesh, Transform3 worldFromMesh,
                                              const ShapeProxy3& b, Transform3 worldFromB);

}  // namespace quack
