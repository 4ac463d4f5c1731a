#pragma once
/// `Hull3`: a convex polyhedron with polygonal faces, and `computeHull3`, the quickhull that
/// builds one from a point cloud.
///
/// Naming in the 3D layer: the 3D types carry a `3` where a 2D type has the same name
/// (`Vec3`, `Transform3`, `Capsule3`, `Hull3`, `Triangle3`), and `Sphere` (no 2D namesake).
///
/// The hull is computed by quickhull (C. B. Barber, D. P. Dobkin, H. Huhdanpaa, "The
/// quickhull algorithm for convex hulls", ACM TOMS 22(4), 1996): start from a tetrahedron
/// of extreme points, repeatedly add the point furthest outside the current hull, replacing
/// the faces it sees by a cone from their horizon. It runs in double with a tolerance
/// relative to the point set's size ("thick" planes): a point within the tolerance of the
/// hull is never added, so near-coplanar, collinear and duplicate points are dropped rather
/// than producing slivers. Afterwards adjacent triangles within a tenth of it of one plane
/// merge into one polygonal face and vertices left on a straight run of a face's boundary
/// are dropped, so every face has a well-defined normal and every vertex is a true corner.
/// Written from the paper; no peer's code was consulted (qhull serves only as the tests'
/// oracle).

#include <cstdint>
#include <span>

#include "quack/core/result.hpp"
#include "quack/geometry/hull.hpp"
#include "quack/math/vec3.hpp"

namespace quack {

/// Most vertices a 3D hull may have (the same 64 as a polygon; the issue asks for >= 64).
inline constexpr int kMaxHullVertices3 = 64;
/// Most faces: a convex polyhedron of V vertices has at most 2V - 4 faces.
inline constexpr int kMaxHullFaces3 = 2 * kMaxHullVertices3 - 4;
/// Most edges: at most 3V - 6.
inline constexpr int kMaxHullEdges3 = 3 * kMaxHullVertices3 - 6;

/// Relative tolerance of quickhull: a point closer than this fraction of the point set's
/// size to the hull is not a vertex, two faces within it of one plane are one face. As in
/// 2D (kHullRelativeTolerance): about 100 float ulps of the size, above the rounding of the
/// float inputs, below any feature drawn on purpose.
inline constexpr float kHull3RelativeTolerance = 1e-5f;

/// Adjacent triangles of the hull merge into one face when they lie within this fraction of
/// the tolerance of one plane. Far above the rounding of float corners (a rotated box's
/// faces are planar to ~1e-7 of its size, a hundredth of this), far enough below the
/// tolerance that merging never bends a face by more than it.
inline constexpr float kHull3MergeFraction = 0.1f;

/// An edge of a Hull3: vertices v0, v1; `faceLeft` has v0 -> v1 in its counter-clockwise
/// (seen from outside) loop, `faceRight` has v1 -> v0.
struct HullEdge3 {
  std::uint8_t v0 = 0;
  std::uint8_t v1 = 0;
  std::uint8_t faceLeft = 0;
  std::uint8_t faceRight = 0;
};

/// A face of a Hull3: its outward unit normal, its plane offset (dot(normal, x) = offset on
/// the face), and its vertex loop `faceVertices[first .. first + count)`, counter-clockwise
/// seen from outside.
struct HullFace3 {
  Vec3 normal;
  float offset = 0.0f;
  std::uint16_t first = 0;
  std::uint8_t count = 0;
};

/// A convex polyhedron with polygonal faces, optionally rounded, shape frame. The solid is
/// the points within `radius` of the polyhedron (its "core"): the Minkowski sum of the core
/// and a ball, as a rounded polygon in 2D and Jolt's convex radius. Invariants
/// (validateHull3): 4 <= vertexCount <= kMaxHullVertices3, V - E + F = 2, every face
/// strictly convex and planar within the tolerance, every vertex on or inside every face
/// plane within it, every edge joins two faces of different normals, radius finite and
/// in [0, kMaxCoordinate]. `centroid` is the core's centre of volume (the rounded solid's
/// may differ: computeMass).
struct Hull3 {
  Vec3 vertices[kMaxHullVertices3];
  HullFace3 faces[kMaxHullFaces3];
  HullEdge3 edges[kMaxHullEdges3];
  std::uint8_t faceVertices[2 * kMaxHullEdges3];
  Vec3 centroid;
  float radius = 0.0f;  ///< rounding radius, metres (0: the plain polyhedron)
  int vertexCount = 0;
  int faceCount = 0;
  int edgeCount = 0;
};

/// What computeHull3 dropped from its input, and why. Every input point is counted once:
/// inputCount = vertices + duplicates + inside + onBoundary.
struct Hull3Report {
  int inputCount = 0;
  int vertices = 0;        ///< points that became hull vertices
  int duplicates = 0;      ///< within the tolerance of an earlier input point
  int inside = 0;          ///< strictly inside the hull (further than the tolerance)
  int onBoundary = 0;      ///< on a face or an edge within the tolerance but not a corner
                           ///< (coplanar and collinear points)
  float tolerance = 0.0f;  ///< the absolute tolerance used, metres
};

/// A hull and the report of its construction.
struct Hull3Build {
  Hull3 hull;
  Hull3Report report;
};

/// Tolerance used for a point set whose bounding box is `lower`..`upper`: relative to its
/// size, never below the float resolution of its coordinates.
float hull3Tolerance(Vec3 lower, Vec3 upper) noexcept;

/// Convex hull of `points` (shape frame, any order, duplicates allowed). Allocates (it is a
/// construction, not a query). Errors, naming the problem: no points, a non-finite or
/// out-of-range coordinate (with its index), all points within the tolerance of one point,
/// a line or a plane (no volume: use a capsule or a triangle), more than
/// kMaxHullVertices3 hull vertices (found early: the build stops once its hull has four
/// times that many), or (never expected) a failed internal check.
Result<Hull3Build> computeHull3(std::span<const Vec3> points);

/// Checks every invariant of a Hull3 (see the struct). Tests call it after every hull.
Status validateHull3(const Hull3& hull);

}  // namespace quack
