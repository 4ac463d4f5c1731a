#pragma once
/// Shape cast and time of impact in 3D, rotating sweeps included.
///
/// Both are conservative advancement (Mirtich, PhD thesis, 1996, ch. 2): at time t, GJK gives
/// the distance d and the normal n; no point can approach faster than
/// mu = -dot(vB - vA, n) + wA rA + wB rB, where v are the centres' velocities, w the angular
/// speeds and r the largest distance of a surface point from each centre of mass (under a
/// pure translation the distance is convex in t, so its tangent bounds it below; a rotation
/// moves every point by at most w r times the time). Stepping t by (d - target) / mu never
/// passes the first contact, and reaches it linearly (one step on a face under translation).
/// The shape cast (translation only) is the same loop with w = 0. Both have an iteration cap
/// and say how they ended (the 2D statuses, ShapeCastStatus and ToiStatus).

#include "quack/collision/gjk3.hpp"
#include "quack/collision/shape_cast.hpp"
#include "quack/collision/toi.hpp"
#include "quack/math/sweep3.hpp"

namespace quack {

/// Most advancement steps of the 3D time of impact. Advancement converges linearly on a
/// glancing approach (each step closes a fixed share of the gap), so it needs more steps
/// than the 2D root finder; 100 reaches a tolerance of 1e-6 of the gap at a 7% share.
inline constexpr int kToi3MaxIterations = 100;

/// Result of the 3D shape cast. World frame.
struct ShapeCastOutput3 {
  bool hit = false;       ///< status is hit or overlapped
  float fraction = 0.0f;  ///< of the translation, in [0, maxFraction]; 0 when overlapped
  Vec3 point;             ///< on A's surface nearest B at `fraction` (overlapped: deepest in B)
  Vec3 normal;            ///< unit, from A to B (overlapped: EPA's direction to move B out)
  float depth = 0.0f;     ///< when overlapped: metres to move B along `normal`; else 0
  int iterations = 0;     ///< GJK distance evaluations
  ShapeCastStatus status = ShapeCastStatus::missed;
};

/// Casts proxy B, placed by `worldFromB`, along `translationB` (world, metres) against proxy
/// A over the fractions [0, maxFraction]; a hit is within kShapeCastTolerance of touching.
/// Cap kShapeCastMaxIterations. No allocation. Non-finite input gives invalidInput.
ShapeCastOutput3 castShape(const ShapeProxy3& a, Transform3 worldFromA, const ShapeProxy3& b,
                           Transform3 worldFromB, Vec3 translationB,
                           float maxFraction = 1.0f) noexcept;

/// Result of the 3D time of impact. World frame.
struct ToiOutput3 {
  ToiStatus status = ToiStatus::separated;
  float t = 0.0f;  ///< sweep fraction in [0, tMax]
  /// Between the shapes at t (hit: in [target, target + kToiTolerance]); when separated,
  /// at the last evaluation before the advancement passed tMax.
  float distance = 0.0f;
  Vec3 point;          ///< on A's surface nearest B at t (overlapped: deepest in B)
  Vec3 normal;         ///< unit, from A to B at t; zero when separated
  int iterations = 0;  ///< GJK distance evaluations
};

/// The largest distance of a surface point of proxy `p` from `center` (shape frame, metres):
/// the ball of this radius about `center` holds the shape however it turns.
float computeReach(const ShapeProxy3& p, Vec3 center) noexcept;

/// The first t in [0, tMax] at which proxies A and B, moving by their sweeps (body frames =
/// the proxies' shape frames), come within `target` metres (kToiTargetSeparation, the 2D
/// one: a slop, so a solver has something to hold). Cap kToi3MaxIterations. No allocation.
/// Errors (invalidInput): non-finite sweeps, tMax outside [0, 1], target < 0 or not finite.
ToiOutput3 computeToi(const ShapeProxy3& a, const Sweep3& sweepA, const ShapeProxy3& b,
                      const Sweep3& sweepB, float tMax = 1.0f,
                      float target = kToiTargetSeparation) noexcept;

}  // namespace quack
