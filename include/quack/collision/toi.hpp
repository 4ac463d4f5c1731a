#pragma once
/// Time of impact: the first time two convex shapes, each moving with its body over a step
/// (`Sweep`: centre of mass linear, angle linear), come within a target separation.
///
/// Conservative advancement driven by GJK distance (Mirtich, "Impulse-based dynamic
/// simulation of rigid body systems", PhD thesis, 1996, ch. 2; Zhang, Redon, Lee and
/// Manocha, "Continuous collision detection for articulated models using Taylor models
/// and temporal culling", SIGGRAPH 2007, sec. 4, for the bound). At a time t GJK gives the
/// distance d and the unit normal n from A to B. The separation along n can shrink no faster
/// than
///
///     mu = dot(vA - vB, n) + |wA| rA + |wB| rB     (metres per unit of sweep time)
///
/// where v and w are the sweeps' linear and angular velocities and r the largest distance
/// from a body's centre of mass to its shape's surface; the slab along n is a lower bound on
/// the distance, so nothing touches before t + (d - target) / mu. Advancing to there is
/// exact for translation onto a face and fast whenever the translation dominates.
///
/// It is slow when the bound is loose (a fast spinner whose nearest point moves mostly
/// sideways: each step shrinks the gap by a fixed ratio). After kToiMaxAdvancements steps
/// the search becomes a bisection that keeps the same guarantee (the binary search for the
/// collision time of docs/background.md): halve the interval between the last time proven
/// free and the end; a midpoint closer than the target is a new end (the first contact is
/// before it); a midpoint that is apart is kept on a stack and becomes the new free time
/// once the advancement bound from the current free time reaches it. Every interval the
/// search skips is proven free by the bound, so the answer is never later than the first
/// contact (no tunnelling), and the stack is a fixed array (no allocation).
///
/// Read for understanding, not copied: Catto, "Continuous Collision", GDC 2013, and Box2D
/// 2.4's b2TimeOfImpact (which root-finds on separating-axis functions instead).

#include <cstdint>
#include <string>

#include "quack/collision/gjk.hpp"
#include "quack/collision/manifold.hpp"
#include "quack/core/result.hpp"
#include "quack/math/sweep.hpp"

namespace quack {

/// Default target separation, metres: the shapes stop one linear slop apart, so that after
/// a world moves a body to its time of impact the pair is still apart (a contact's
/// speculative distance, 4 slops, sees it next step) rather than overlapping.
inline constexpr float kToiTargetSeparation = kLinearSlop;

/// A time of impact is accepted when the distance is within this above the target, metres.
/// A quarter slop, as Box2D: a band wide enough that float rounding of distances (about
/// 1e-6 m at 10 m) never decides it, narrow enough that a stopped body is still inside the
/// speculative distance.
inline constexpr float kToiTolerance = 0.25f * kLinearSlop;

/// The smallest acceptance band, metres, used when the target separation is small: the
/// band is a quarter of the target, clamped to [kToiMinTolerance, kToiTolerance], so that a
/// target below a slop (a body already closer than a slop that must not get closer still)
/// has a band that ends short of where it starts. 0.1 mm: a hundred times the rounding of
/// GJK distances at 10 m coordinates.
inline constexpr float kToiMinTolerance = 1e-4f;

/// Advancement steps before the search switches to bisection. Translation-dominated sweeps
/// end in 2 or 3 steps; 20 steps of a loose bound (ratio 0.8 per step) still shrink the gap
/// a hundredfold, and past that bisection (halving per evaluation) is the better bet.
inline constexpr int kToiMaxAdvancements = 20;

/// Most GJK distance evaluations in one query. The bisection needs about
/// log2(mu / kToiTolerance) halvings (about 25 for a body at 1,000 m/s over a 60 Hz step),
/// on top of the advancement budget; 64 leaves room for one back-track.
inline constexpr int kToiMaxIterations = 64;

/// Depth of the bisection stack (fixed array). 40 halvings reach a 1e-12 interval, below
/// float resolution on [0, 1].
inline constexpr int kToiStackDepth = 40;

/// How a time-of-impact query ended.
enum class ToiStatus : std::uint8_t {
  hit,           ///< within [target, target + band] at `t` (band: see kToiMinTolerance);
                 ///< nothing closer before
  separated,     ///< never closer than the target within [0, tMax]; `t` is tMax
  overlapped,    ///< the shapes overlap or touch at t = 0; `t` is 0, normal from EPA
  failed,        ///< hit kToiMaxIterations (or the stack); `t` is the last time proven free
  invalidInput,  ///< a non-finite sweep, tMax outside [0, 1], or a bad target
};

/// Name of a status for output ("hit", "separated", "overlapped", "failed",
/// "invalid_input").
const char* toString(ToiStatus status) noexcept;

/// Result of `computeToi`. World frame, at time `t` of the sweeps.
struct ToiOutput {
  ToiStatus status = ToiStatus::separated;
  float t = 0.0f;  ///< sweep fraction in [0, tMax]
  /// Between the shapes at t (hit: in [target, target + tol]). Separated: at least the
  /// target; the distance at the search's last evaluation, or, when bounds settled the
  /// query with no evaluation (iterations 0), a lower bound on the distance at tMax. A hit
  /// that a face settled without a last GJK call (docs/continuous.md, "The face
  /// certificate") reports the distance from the other shape's support to the face, which
  /// exceeds the true distance by at most a sixteenth of the band.
  float distance = 0.0f;
  Vec2 point;  ///< on A's surface, nearest B, at t (overlapped: deepest in B)
  /// Unit, from A to B at t (overlapped: EPA's direction to move B out; never zero). Zero
  /// when separated.
  Vec2 normal;
  int iterations = 0;  ///< GJK distance evaluations
};

/// The first time in [0, tMax] at which proxy A moving with `sweepA` and proxy B moving with
/// `sweepB` come within `targetSeparation` (metres, >= 0) of each other. The proxies are in
/// their body frames (`transformAt(sweep, t)` is worldFromBody). No allocation.
/// Preconditions: valid proxies. Non-finite sweeps, tMax outside [0, 1] or a negative or
/// non-finite target give `invalidInput` (use `checkSweep` for a message).
ToiOutput computeToi(const ShapeProxy& a, const Sweep& sweepA, const ShapeProxy& b,
                     const Sweep& sweepB, float tMax = 1.0f,
                     float targetSeparation = kToiTargetSeparation) noexcept;
/// The same for shapes of any kind (in their body frames), through their proxies.
inline ToiOutput computeToi(const ShapeGeometry& a, const Sweep& sweepA, const ShapeGeometry& b,
                            const Sweep& sweepB, float tMax = 1.0f,
                            float targetSeparation = kToiTargetSeparation) noexcept {
  return computeToi(makeProxy(a), sweepA, makeProxy(b), sweepB, tMax, targetSeparation);
}

/// Checks that every number of a sweep is finite; the error names `name` and the field
/// ("sweepA.c2.x is not finite: nan").
Status checkSweep(const Sweep& sweep, const std::string& name);

/// The largest distance from `center` (shape frame) to the rounded shape's surface: the
/// radius r of the advancement bound.
float computeMaxExtent(const ShapeProxy& proxy, Vec2 center) noexcept;

}  // namespace quack
