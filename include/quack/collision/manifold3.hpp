#pragma once
/// Contact manifolds in 3D: for two shapes that touch (or are about to), the normal from A
/// to B and up to four contact points, each with its separation and a feature id.
///
/// Hull pairs (boxes are hulls) take SAT's axis (sat3.hpp): on a face axis, the incident
/// face of the other hull (the one most against the reference normal) is clipped against
/// the reference face's side planes (Sutherland-Hodgman) and the points below the speculative
/// distance are kept, then reduced to four: the deepest, the furthest from it, the one that
/// makes the largest triangle with both, and the one furthest outside that triangle (the
/// usual contact reduction, as Gregorius's GDC 2015 talk describes it), so a box resting on a box
/// has four points rather than the single jittering one the peers' trackers show. On an edge axis
/// the manifold is one point between the two edges. Spheres take one point from GJK or EPA;
/// capsules lying flat on a hull face or along another capsule take two (their segment
/// clipped), otherwise one. Catto, "Contact Manifolds", GDC 2007, and Gregorius, "Robust
/// Contact Creation for Physics Simulations", GDC 2015, describe the approach.

#include <cstdint>

#include "quack/collision/manifold.hpp"
#include "quack/collision/proxy3.hpp"
#include "quack/collision/sat3.hpp"

namespace quack {

/// Most contact points in a 3D manifold: four points span a face (a solver needs at least
/// three, not all on a line, to hold a box flat).
inline constexpr int kMaxManifoldPoints3 = 4;

/// The bit of a 3D feature id that says the reference face belongs to B.
inline constexpr std::uint32_t kManifold3IdReferenceOnB = 1u << 31;
/// The bit of a 3D feature id that marks an edge-edge contact.
inline constexpr std::uint32_t kManifold3IdEdges = 1u << 30;
/// The bit that marks a point made by clipping (an incident edge crossing a side plane)
/// rather than an incident vertex.
inline constexpr std::uint32_t kManifold3IdClip = 1u << 15;

/// One contact point. World frame.
struct ManifoldPoint3 {
  Vec3 point;               ///< midway between the two surfaces, world frame
  Vec3 anchorA;             ///< point minus A's origin (worldFromA.p), world axes
  Vec3 anchorB;             ///< point minus B's origin (worldFromB.p), world axes
  float separation = 0.0f;  ///< distance between the surfaces along the normal; < 0 overlaps
  /// Names the touching features: for face contacts (reference face << 16) | incident
  /// vertex, or with kManifold3IdClip set, (reference face << 16) | (side << 8) | incident
  /// edge; kManifold3IdReferenceOnB when the reference face is B's; edge contacts
  /// kManifold3IdEdges | (edge of A << 8) | edge of B; capsule points their end (0 or 1).
  /// The same while the same features touch, so a solver can warm start.
  std::uint32_t id = 0;
};

/// Contact manifold in 3D. World frame.
struct Manifold3 {
  Vec3 normal;  ///< unit, from A to B (meaningless when pointCount is 0)
  ManifoldPoint3 points[kMaxManifoldPoints3];
  int pointCount = 0;  ///< 0 when the shapes are further apart than the speculative distance
};

/// The pair routines: shapes in their own frames, placed by worldFromA and worldFromB;
/// points whose separation is at most `speculativeDistance` (metres, >= 0; kLinearSlop and
/// kSpeculativeDistance as in 2D). Preconditions: shapes built by the make* functions,
/// finite transforms with unit quaternions. No allocation.
Manifold3 collideSpheres(const Sphere& a, Transform3 worldFromA, const Sphere& b,
                         Transform3 worldFromB,
                         float speculativeDistance = kSpeculativeDistance) noexcept;
Manifold3 collideCapsuleAndSphere(const Capsule3& a, Transform3 worldFromA, const Sphere& b,
                                  Transform3 worldFromB,
                                  float speculativeDistance = kSpeculativeDistance) noexcept;
Manifold3 collideHullAndSphere(const Hull3& a, Transform3 worldFromA, const Sphere& b,
                               Transform3 worldFromB,
                               float speculativeDistance = kSpeculativeDistance) noexcept;
/// Two points when the segments are parallel enough that the separation changes by less
/// than kLinearSlop across their common stretch; one otherwise.
Manifold3 collideCapsules(const Capsule3& a, Transform3 worldFromA, const Capsule3& b,
                          Transform3 worldFromB,
                          float speculativeDistance = kSpeculativeDistance) noexcept;
/// Two points when the capsule lies along the hull's nearest face (its ends' heights above
/// the face differ by less than kLinearSlop), clipped to the face; one otherwise.
Manifold3 collideHullAndCapsule(const Hull3& a, Transform3 worldFromA, const Capsule3& b,
                                Transform3 worldFromB,
                                float speculativeDistance = kSpeculativeDistance) noexcept;
Manifold3 collideHulls(const Hull3& a, Transform3 worldFromA, const Hull3& b, Transform3 worldFromB,
                       float speculativeDistance = kSpeculativeDistance) noexcept;

/// What collideHulls keeps between calls for one pair of hulls that were apart: the axis
/// (A's frame) that separated them and A's greatest projection on it. While B's least
/// projection on that axis stays beyond A's by more than the speculative distance (plus the
/// radii), the pair has no contact and SAT is not run (Box3D keeps a SAT cache per contact
/// for the same reason; read for understanding). The cache is part of the pair's state: a
/// pair apart along the cached axis by more than the speculative distance gets no points,
/// where SAT's own axes (a lower bound on the distance) might have let a clipped point
/// within the speculative distance through; so a caller that saves its state (World3's
/// snapshots) saves the cache.
struct HullPairCache3 {
  Vec3 axis;  ///< unit, A's frame, from A towards B
  float maxA = 0.0f;
  bool valid = false;
};
/// collideHulls with a cache for the pair (start with a default one; it fills it).
Manifold3 collideHulls(const Hull3& a, Transform3 worldFromA, const Hull3& b, Transform3 worldFromB,
                       float speculativeDistance, HullPairCache3& cache) noexcept;
/// The same with each hull's HullSatData3 (sat3.hpp), made once by a caller that meets the
/// hulls again and again: the same answer to the bit, without working those out each call.
Manifold3 collideHulls(const Hull3& a, const HullSatData3& dataA, Transform3 worldFromA,
                       const Hull3& b, const HullSatData3& dataB, Transform3 worldFromB,
                       float speculativeDistance, HullPairCache3& cache) noexcept;

/// A lone triangle (two-sided) against any 3D shape. When the general contact's normal is the
/// face's (kMeshFaceNormalCosine3, on either side), up to four points along it, the shape's
/// incident feature clipped to the triangle as for a mesh triangle (mesh3.hpp,
/// collideMeshTriangle), or the general contact if that clips to nothing; any other normal
/// (an edge, a corner, or the other shape's face when deep) keeps the general contact, one
/// point. Defined in mesh3.cpp beside the mesh's triangles. No allocation.
Manifold3 collideTriangle(const Triangle3& a, Transform3 worldFromA, const ShapeGeometry3& b,
                          Transform3 worldFromB,
                          float speculativeDistance = kSpeculativeDistance) noexcept;

/// Manifold of any two 3D shapes: the pair routine for their types (B-versus-A reuses
/// A-versus-B with the normal flipped and the anchors swapped; the ids are kept), and
/// collideTriangle for a triangle. No allocation.
Manifold3 collide(const ShapeGeometry3& a, Transform3 worldFromA, const ShapeGeometry3& b,
                  Transform3 worldFromB, float speculativeDistance = kSpeculativeDistance) noexcept;

/// The general path: any two 3D support proxies, through GJK (apart) or EPA (overlapping),
/// one point (id 0).
Manifold3 collideGeneral(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                         Transform3 worldFromB,
                         float speculativeDistance = kSpeculativeDistance) noexcept;

}  // namespace quack
