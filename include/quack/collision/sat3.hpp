#pragma once
/// SAT in 3D for two convex hulls: face normals of both, and the cross products of the edge
/// pairs that form a face of the Minkowski difference, found on the Gauss map.
///
/// Two convex polyhedra are apart exactly when some face normal of either, or the cross
/// product of an edge of each, separates them; when they overlap, the least push is along
/// a face normal of B - A, and the faces of B - A are the faces of A, of -B, and the
/// edge pairs whose arcs cross on the Gauss map (D. Gregorius, "The Separating Axis Test
/// between Convex Polyhedra", GDC 2013). Testing only those edge pairs ("edge pruning")
/// makes the edge-edge separation exact rather than a guess from two edge points, and skips
/// most of the n x m pairs. Written from the talk; no peer's
/// code was consulted.
///
/// Bounds skip what cannot win, leaving every answer as the full test gives it: a hull's
/// least projection on a unit direction is at most its centroid's less the radius of the
/// ball about the centroid inside it, so each face has an upper bound on its separation
/// (one dot product); the face with the largest bound is tested first, and a face whose
/// bound is below a separation already found is not tested. An edge pair's axis lies on
/// both edges' arcs, where the same bound, taken along the arc, is at most the edge's faces'
/// bounds over cos(theta / 2) (theta the arc's angle); edges that cannot beat the best
/// face are dropped before the pairs are formed, and the Gauss-map test runs four pairs at
/// a time (SSE2 lanes).

#include <cstdint>
#include <limits>

#include "quack/geometry/shapes3.hpp"

namespace quack {

/// Which features gave a SatOutput3's axis.
enum class SatFeature3 : std::uint8_t {
  faceA,  ///< the normal of face `faceIndex` of A
  faceB,  ///< the normal of face `faceIndex` of B (negated: from A to B)
  edges,  ///< the cross product of edge `edgeA` of A and edge `edgeB` of B
};

/// A face axis within this fraction of the hulls' size of the best edge axis wins over it,
/// so resting contact keeps a face (four points) rather than flickering to an edge (one):
/// about 10 float ulps, above the rounding of the separations.
inline constexpr float kSat3FaceBiasRelative = 1e-6f;

/// Result of computeSat for two hulls. Normal in the world frame.
struct SatOutput3 {
  /// Largest separation over the axes: negative is the penetration depth of the hulls
  /// (exact up to rounding), positive a lower bound on their distance.
  float separation = 0.0f;
  Vec3 normal;  ///< unit, from A to B
  SatFeature3 feature = SatFeature3::faceA;
  int faceIndex = 0;  ///< the best face axis's face (also when an edge axis won)
  /// The best face axis, also when an edge axis won (the caller may prefer a face within a
  /// tolerance, as collideHulls does): faceA or faceB, its separation and world normal.
  SatFeature3 faceFeature = SatFeature3::faceA;
  float faceSeparation = -std::numeric_limits<float>::infinity();
  Vec3 faceNormal;
  int edgeA = 0;            ///< for edges
  int edgeB = 0;            ///< for edges
  int edgePairsTested = 0;  ///< edge pairs that the bounds kept and the Gauss map passed
};

/// SAT over the face normals of both hulls and their Minkowski-face edge pairs, computed in
/// A's frame (B brought in by the relative pose). No allocation. Preconditions: valid hulls
/// (validateHull3), finite transforms with unit quaternions.
///
/// `stopAbove` (metres): once an axis shows that the answer's separation will exceed it,
/// SAT stops and answers with that axis, whose separation exceeds `stopAbove` but need not
/// be the largest (collideHulls passes its speculative distance: such hulls have no
/// contact). The default, infinity, never stops early.
SatOutput3 computeSat(const Hull3& a, Transform3 worldFromA, const Hull3& b, Transform3 worldFromB,
                      float stopAbove = std::numeric_limits<float>::infinity()) noexcept;

/// What computeSat works out of one hull alone, each call: its largest squared vertex
/// distance from the centroid, the radius of the ball about the centroid inside it, and its
/// vertices as columns, padded to a multiple of four with copies of vertex 0. A caller that
/// meets one hull again and again (the 3D world keeps one per stored hull) makes it once;
/// computeSat given it answers to the bit as without it.
struct HullSatData3 {
  float size2 = 0.0f;
  float inradius = 0.0f;
  int columnCount = 0;
  alignas(16) float x[kMaxHullVertices3];
  alignas(16) float y[kMaxHullVertices3];
  alignas(16) float z[kMaxHullVertices3];
};
HullSatData3 makeHullSatData3(const Hull3& hull) noexcept;

/// computeSat with each hull's HullSatData3 (made by makeHullSatData3 from that hull).
SatOutput3 computeSat(const Hull3& a, const HullSatData3& dataA, Transform3 worldFromA,
                      const Hull3& b, const HullSatData3& dataB, Transform3 worldFromB,
                      float stopAbove = std::numeric_limits<float>::infinity()) noexcept;

}  // namespace quack
