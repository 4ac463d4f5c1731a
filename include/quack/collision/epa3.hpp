#pragma once
/// EPA in 3D: the penetration depth of two overlapping convex shapes, the normal to
/// separate them along, and the deepest point of each in the other.
///
/// The expanding polytope algorithm (van den Bergen, GDC 2001; Ericson 9.5) on the cores in
/// A's frame, from GJK's final simplex grown to a tetrahedron: repeatedly take the polytope
/// face nearest the origin and push it out to the support point of B - A along its normal,
/// replacing the faces that point sees by a cone from their horizon, until the support point
/// lies on the face. Faces keep their adjacency, so the faces a point sees are found by a
/// walk from the nearest face that also yields the horizon in order (Ericson 9.5). Every
/// buffer is a fixed array on the stack (no allocation), and each
/// pass either adds a vertex or stops, so it cannot loop: at worst it runs out of vertices
/// (kEpa3MaxVertices) and says so. Faces keep signed distances, so a start polytope that
/// only touches the origin (GJK stopped at contact on a face or an edge) grows to hold it.
/// It gives up, with a status and the best face found, when rounding makes a new face
/// meaningless (a horizon that is not one loop, a face with no normal), the failure the
/// peers' trackers show as loops on touching and flat shapes. Written from the published
/// descriptions cited here; no peer's code was consulted.

#include <cstdint>

#include "quack/collision/gjk3.hpp"

namespace quack {

/// Most polytope vertices. Polytopes of hull pairs end in a few dozen passes; 128 leaves
/// room for the worst cases seen in the tests (curved-looking 64-vertex hulls) and keeps
/// the stack buffers (polytope with face adjacency, horizon, cone) at about 45 kB.
inline constexpr int kEpa3MaxVertices = 128;
/// Most polytope faces: a closed triangulated polytope of V vertices has 2V - 4.
inline constexpr int kEpa3MaxFaces = 2 * kEpa3MaxVertices - 4;

/// EPA stops when the support point along the nearest face's normal is within this
/// fraction of the polytope's size of the face: the cores are polytopes, so the support
/// lands on the face exactly at the end and this only absorbs rounding (about 8 float ulps
/// of the size; the depth is then good to that).
inline constexpr float kEpa3RelativeTolerance = 1e-6f;

/// How computePenetration (3D) reached its answer.
enum class Epa3Status : std::uint8_t {
  separated,        ///< no overlap: GJK's distance answer, depth 0
  coresSeparated,   ///< only the radii overlap: depth from GJK's core distance, exact
  converged,        ///< EPA's support point met the nearest face
  repeatedSupport,  ///< EPA's support point was a vertex of the nearest face
  bufferFull,       ///< kEpa3MaxVertices reached; the answer is the best face found
  gaveUp,           ///< rounding made the next polytope unusable; the best face found
  degenerate,       ///< B - A's core is flat (points, segments, coplanar triangles):
                    ///< depth the radii, normal the flat set's normal or the centres'
};

/// Name of a status for output ("converged", "buffer_full", ...).
const char* toString(Epa3Status status) noexcept;

/// Result of computePenetration (3D). Points and normal in the world frame.
struct PenetrationOutput3 {
  bool overlap = false;  ///< the closed shapes share a point
  float depth = 0.0f;    ///< metres to move B along `normal` to separate them; 0 when apart
  Vec3 normal;           ///< unit, from A to B (when apart: GJK's normal)
  Vec3 pointA;           ///< A's surface point deepest in B (when apart: closest on A)
  Vec3 pointB;           ///< B's surface point deepest in A (pointB = pointA - depth normal)
  int iterations = 0;    ///< GJK plus EPA support-point evaluations
  Epa3Status status = Epa3Status::separated;
};

/// One pass of EPA's 3D loop, as an observer sees it: the polytope (its vertices and its
/// faces, each counter-clockwise seen from outside), its face nearest the origin, and the
/// support point along that face's normal.
struct Epa3IterationRecord {
  SupportPoint3 vertices[kEpa3MaxVertices];  ///< A frame
  int vertexCount = 0;
  int faces[kEpa3MaxFaces][3] = {};  ///< vertex indices of the live faces
  int faceCount = 0;
  int nearest = 0;            ///< index into `faces` of the face nearest the origin
  Vec3 faceNormal;            ///< its outward unit normal, A frame
  float faceDistance = 0.0f;  ///< its plane's signed distance from the origin (the core depth)
  bool hasSupport = false;    ///< a support point was taken in this pass
  SupportPoint3 support;      ///< the support point of B - A along faceNormal when hasSupport
};

/// Enough 3D EPA records for any run: every pass but the last adds a vertex to a polytope
/// that starts with 4 and holds at most kEpa3MaxVertices.
inline constexpr int kEpa3MaxTraceRecords = kEpa3MaxVertices - 3;

/// A caller-owned buffer that the traced computePenetration fills with one record per pass
/// of EPA's loop; the contract of Gjk3Trace. `count` is 0 when EPA did not run (separated,
/// coresSeparated, degenerate, or no usable start tetrahedron). A record is about 9 kB.
struct Epa3Trace {
  Epa3IterationRecord* records = nullptr;  ///< caller-owned array of `capacity` records
  int capacity = 0;
  int count = 0;           ///< records written: min(passes, capacity)
  int passes = 0;          ///< passes the run made
  bool truncated = false;  ///< passes > capacity: middle passes were dropped
};

/// Penetration of proxy B (placed by `worldFromB`) into proxy A (placed by `worldFromA`):
/// GJK first; when the cores overlap, EPA on the cores plus both radii. `cache` as for
/// computeDistance. No allocation. Preconditions: valid proxies, finite transforms.
PenetrationOutput3 computePenetration(const ShapeProxy3& a, Transform3 worldFromA,
                                      const ShapeProxy3& b, Transform3 worldFromB,
                                      GjkCache3* cache = nullptr) noexcept;
/// computePenetration that also records every pass of GJK into `gjkTrace` and of EPA into
/// `epaTrace` (either may be null; see Gjk3Trace, Epa3Trace). The answer is the same, bit
/// for bit.
PenetrationOutput3 computePenetration(const ShapeProxy3& a, Transform3 worldFromA,
                                      const ShapeProxy3& b, Transform3 worldFromB, GjkCache3* cache,
                                      Gjk3Trace* gjkTrace, Epa3Trace* epaTrace) noexcept;
/// The same for 3D shapes of any kind, through their proxies.
inline PenetrationOutput3 computePenetration(const ShapeGeometry3& a, Transform3 worldFromA,
                                             const ShapeGeometry3& b, Transform3 worldFromB,
                                             GjkCache3* cache = nullptr) noexcept {
  return computePenetration(makeProxy(a), worldFromA, makeProxy(b), worldFromB, cache);
}

}  // namespace quack
