#pragma once
/// Contact manifolds: for two shapes that touch (or are about to), the normal from A to B
/// and up to two contact points, each with its separation and a feature id.
///
/// Every pair of circle, capsule, segment and polygon has a routine; `collide` dispatches
/// through a table of function pointers (no virtual call, no allocation) in which
/// B-versus-A reuses A-versus-B with the normal flipped. Polygon pairs use reference and
/// incident faces with clipping (Catto, "Contact Manifolds", GDC 2007; Ericson, "Real-Time
/// Collision Detection", 2005, sec. 5.2.1); capsules and segments enter the same routine as
/// two-vertex polygons, the way Box2D v3 treats them. `collideGeneral` serves any pair of
/// support proxies through GJK and EPA, with one point. The design and its tolerances are in
/// docs/manifolds.md.

#include <cstdint>

#include "quack/collision/proxy.hpp"
#include "quack/geometry/shapes.hpp"

namespace quack {

/// Most contact points in a 2D manifold: two points span a face.
inline constexpr int kMaxManifoldPoints = 2;

/// The collision tolerance a world works to, metres: penetration a solver leaves in place
/// so that contacts persist between steps (Box2D's 5 mm; objects in metres, 0.1 to 10 m).
inline constexpr float kLinearSlop = 0.005f;

/// Default speculative distance, metres: contacts are reported while the surfaces are up to
/// this far apart, so a solver can stop bodies before they touch rather than after they
/// overlap. Four slops: about what a body at 1.2 m/s covers in a 60 Hz step.
inline constexpr float kSpeculativeDistance = 4.0f * kLinearSlop;

/// The bit of a feature id that says the reference face belongs to B (the second argument).
inline constexpr std::uint32_t kManifoldIdReferenceOnB = 1u << 16;

/// One contact point. World frame.
struct ManifoldPoint {
  Vec2 point;               ///< midway between the two surfaces, world frame
  Vec2 anchorA;             ///< point minus A's origin (worldFromA.p), world axes
  Vec2 anchorB;             ///< point minus B's origin (worldFromB.p), world axes
  float separation = 0.0f;  ///< distance between the surfaces along the normal; < 0 overlaps
  /// Names the touching features (which face is the reference, which vertex is incident);
  /// the same while the same features touch, so a solver can match points between steps
  /// and warm start. Swapping A and B of different types keeps the ids; for two shapes of
  /// the same type, the ids differ in kManifoldIdReferenceOnB only.
  std::uint32_t id = 0;
};

/// Contact manifold. World frame.
struct Manifold {
  Vec2 normal;  ///< unit, from A to B (meaningless when pointCount is 0)
  ManifoldPoint points[kMaxManifoldPoints];
  int pointCount = 0;  ///< 0 when the shapes are further apart than the speculative distance
};

/// The pair routines. Each takes shapes in their own frames, placed by worldFromA and
/// worldFromB, and reports points whose separation is at most `speculativeDistance`
/// (metres, >= 0). Preconditions: shapes built by the make* functions, finite transforms.
Manifold collideCircles(const Circle& a, Transform worldFromA, const Circle& b,
                        Transform worldFromB,
                        float speculativeDistance = kSpeculativeDistance) noexcept;
Manifold collideCapsuleAndCircle(const Capsule& a, Transform worldFromA, const Circle& b,
                                 Transform worldFromB,
                                 float speculativeDistance = kSpeculativeDistance) noexcept;
Manifold collideSegmentAndCircle(const Segment& a, Transform worldFromA, const Circle& b,
                                 Transform worldFromB,
                                 float speculativeDistance = kSpeculativeDistance) noexcept;
Manifold collidePolygonAndCircle(const Polygon& a, Transform worldFromA, const Circle& b,
                                 Transform worldFromB,
                                 float speculativeDistance = kSpeculativeDistance) noexcept;
Manifold collideCapsules(const Capsule& a, Transform worldFromA, const Capsule& b,
                         Transform worldFromB,
                         float speculativeDistance = kSpeculativeDistance) noexcept;
Manifold collideSegmentAndCapsule(const Segment& a, Transform worldFromA, const Capsule& b,
                                  Transform worldFromB,
                                  float speculativeDistance = kSpeculativeDistance) noexcept;
/// Two segments have no interior; crossing segments get the smaller push along either
/// segment's normal.
Manifold collideSegments(const Segment& a, Transform worldFromA, const Segment& b,
                         Transform worldFromB,
                         float speculativeDistance = kSpeculativeDistance) noexcept;
Manifold collidePolygonAndCapsule(const Polygon& a, Transform worldFromA, const Capsule& b,
                                  Transform worldFromB,
                                  float speculativeDistance = kSpeculativeDistance) noexcept;
Manifold collidePolygonAndSegment(const Polygon& a, Transform worldFromA, const Segment& b,
                                  Transform worldFromB,
                                  float speculativeDistance = kSpeculativeDistance) noexcept;
Manifold collidePolygons(const Polygon& a, Transform worldFromA, const Polygon& b,
                         Transform worldFromB,
                         float speculativeDistance = kSpeculativeDistance) noexcept;

/// A pair routine for shapes of any kind, as stored in the dispatch table. The entry for
/// types (a, b) knows its types: it must be called with shapes of those types only.
using ManifoldFn = Manifold (*)(const ShapeGeometry& a, Transform worldFromA,
                                const ShapeGeometry& b, Transform worldFromB,
                                float speculativeDistance) noexcept;

/// The routine for shapes of types a and b (never null).
ManifoldFn findManifoldFn(ShapeType a, ShapeType b) noexcept;

/// Manifold of any two shapes, through the dispatch table.
Manifold collide(const ShapeGeometry& a, Transform worldFromA, const ShapeGeometry& b,
                 Transform worldFromB, float speculativeDistance = kSpeculativeDistance) noexcept;

/// The general path: any two support proxies, through GJK (apart) or EPA (overlapping),
/// giving at most one point (id 0). Serves shape pairs with no special routine, and checks
/// the special routines in the tests.
Manifold collideGeneral(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                        Transform worldFromB,
                        float speculativeDistance = kSpeculativeDistance) noexcept;

/// The deepest point of a manifold (least separation); precondition: pointCount > 0.
const ManifoldPoint& deepestPoint(const Manifold& manifold) noexcept;

}  // namespace quack
