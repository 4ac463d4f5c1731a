#pragma once
/// Shape cast: the first time shape B, moving by a translation, touches shape A.
///
/// Conservative advancement over GJK distance (Mirtich, "Impulse-based dynamic
/// simulation of rigid body systems", PhD thesis, 1996, ch. 2; van den Bergen, "Collision
/// Detection in Interactive 3D Environments", 2003, sec. 5.6, discusses it beside his
/// GJK ray cast). Under a pure translation r the distance d(s) between two convex shapes is
/// a convex function of the fraction s, and GJK gives both d and a separating normal n, so
/// d(s) >= d(s0) + (s - s0) dot(r, n). Stepping to where that bound reaches the target is
/// Newton's method on a convex, decreasing function: it approaches the first root from
/// below, never overshoots (in exact arithmetic), and converges quadratically on smooth
/// features and in one step on a face. When dot(r, n) >= 0 the shapes never get closer
/// (convexity), so the cast misses. We chose advancement over GJK ray casting because it
/// reuses `computeDistance` as is (warm-started through a `GjkCache`) and gives the same
/// witness points and normal the rest of the layer uses.
///
/// Initial overlap is a defined answer: status `overlapped`, fraction 0, and EPA's normal
/// and depth (move B by depth * normal to separate). The normal is never zero.

#include <cstdint>

#include "quack/collision/gjk.hpp"

namespace quack {

/// A cast stops when the distance is below this, metres. 0.1 mm: fifty times below the
/// linear slop a world works to (`kLinearSlop`), so a hit is as good as touching for any
/// solver, and about a hundred times above the rounding of GJK distances between shapes
/// whose coordinates are around 10 m (about 1e-6 m), so the test is never decided by noise.
inline constexpr float kShapeCastTolerance = 1e-4f;

/// Most advancement steps. Newton's method on a convex function reaches the tolerance in a
/// handful of steps for any shape pair (one on a face, about log2(log2(d / tol)) on a round
/// feature); 32 is reached only with NaN input or a bug.
inline constexpr int kShapeCastMaxIterations = 32;

/// How a shape cast ended.
enum class ShapeCastStatus : std::uint8_t {
  hit,            ///< B touches A at `fraction` (distance within kShapeCastTolerance)
  missed,         ///< B does not reach A within the translation (times maxFraction)
  overlapped,     ///< A and B overlap (or touch) at fraction 0: EPA's normal and depth
  maxIterations,  ///< hit kShapeCastMaxIterations; `fraction` is the last one proven free
  invalidInput,   ///< a non-finite transform or translation, or maxFraction outside [0, 1]
};

/// Name of a status for output ("hit", "missed", "overlapped", "max_iterations",
/// "invalid_input").
const char* toString(ShapeCastStatus status) noexcept;

/// Result of `castShape`. World frame.
struct ShapeCastOutput {
  bool hit = false;       ///< status is hit or overlapped
  float fraction = 0.0f;  ///< of the translation, in [0, maxFraction]; 0 when overlapped
  /// On hit: the point of A's surface nearest B at `fraction`. When overlapped: A's surface
  /// point deepest in B (EPA's pointA). Otherwise zero.
  Vec2 point;
  /// On hit: unit, from A to B at `fraction` (B's approach is against it). When overlapped:
  /// the unit direction to move B to separate (from A to B); never zero. Otherwise zero.
  Vec2 normal;
  float depth = 0.0f;  ///< when overlapped: metres to move B along `normal`; else 0
  int iterations = 0;  ///< GJK distance evaluations
  ShapeCastStatus status = ShapeCastStatus::missed;
};

/// Casts proxy B, placed by `worldFromB`, along `translationB` (world frame, metres) against
/// proxy A, placed by `worldFromA`, over the fractions [0, maxFraction]. No allocation.
/// Preconditions: valid proxies (see ShapeProxy). Non-finite numbers give `invalidInput`.
ShapeCastOutput castShape(const ShapeProxy& a, Transform worldFromA, const ShapeProxy& b,
                          Transform worldFromB, Vec2 translationB,
                          float maxFraction = 1.0f) noexcept;
/// The same for shapes of any kind, through their proxies.
inline ShapeCastOutput castShape(const ShapeGeometry& a, Transform worldFromA,
                                 const ShapeGeometry& b, Transform worldFromB, Vec2 translationB,
                                 float maxFraction = 1.0f) noexcept {
  return castShape(makeProxy(a), worldFromA, makeProxy(b), worldFromB, translationB, maxFraction);
}

}  // namespace quack
