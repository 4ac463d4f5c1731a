#pragma once
// The contact solver: one part of the world. Soft contacts solved by sequential impulses
// over sub-steps, with relaxation and restitution; it reads the bodies and the touching
// contacts, writes the bodies' velocities and poses and the contacts' accumulated impulses,
// and reports hits. docs/world.md explains the choices.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "quack/collision/manifold.hpp"
#include "quack/math/transform.hpp"

namespace quack {
struct WorldDef;
class BroadPhase;
}  // namespace quack

namespace quack::detail {

class BodyStore;
class ContactSet;
class JointSet;
class EventDispatcher;
class TaskRunner;
struct StepContext;

// Soft-constraint coefficients for one sub-step (Catto, "Solver2D", 2024; the soft step of
// Box2D v3): a spring of `hertz` with damping ratio zeta, implicit in the sub-step h.
struct Softness {
  float biasRate = 0.0f;
  float massScale = 1.0f;
  float impulseScale = 0.0f;
};
// The coefficients of a spring of `hertz` (0: rigid, no bias) with damping ratio `zeta` in
// sub-steps of h seconds.
inline Softness makeSoftness(float hertz, float zeta, float h) {
  if (hertz == 0.0f) return {0.0f, 1.0f, 0.0f};
  const float omega = 2.0f * kPi * hertz;
  const float a1 = 2.0f * zeta + h * omega;
  const float a2 = h * omega * a1;
  const float a3 = 1.0f / (1.0f + a2);
  return {omega / a1, a2 * a3, a3};
}

// Colours (Box2D v3's constraint graph, read for understanding), for the 2D and 3D
// solvers: no two constraints of a colour share a body the solver writes (a dynamic one),
// so a colour's constraints can be solved side by side in lanes and on several workers
// with the result of solving them one by one. Static and kinematic bodies do not count.
// 24 colours hold any pile of boxes (a box touches at most eight others); constraints of
// a body with more than that go to the overflow set, solved one at a time.
inline constexpr int kSolverColors = 24;
inline constexpr int kSolverOverflow = kSolverColors;
static_assert(kSolverColors < 32, "a slot's colours are a 32-bit mask");
inline constexpr std::uint32_t kAllSolverColors = (std::uint32_t{1} << kSolverColors) - 1u;

// The colour a constraint between slots sa and sb takes: the lowest that neither of its
// written bodies is in yet (`used`: a bit per colour per slot, marked here), colour 0 only
// when both are written (the most constrained pairs first), or kSolverOverflow.
inline int takeColor(std::uint32_t* used, std::int32_t sa, std::int32_t sb, bool writeA,
                     bool writeB) noexcept {
  if (writeA && writeB) {
    const std::uint32_t free = ~(used[sa] | used[sb]) & kAllSolverColors;
    if (free == 0) return kSolverOverflow;
    const int color = __builtin_ctz(free);
    used[sa] |= std::uint32_t{1} << color;
    used[sb] |= std::uint32_t{1} << color;
    return color;
  }
  const std::int32_t d = writeA ? sa : sb;
  const std::uint32_t free = ~used[d] & kAllSolverColors & ~std::uint32_t{1};
  if (free == 0) return kSolverOverflow;
  const int color = __builtin_ctz(free);
  used[d] |= std::uint32_t{1} << color;
  return color;
}

struct SolverScratch;  // solver.cpp: the per-step arrays

class Solver {
 public:
  /// One step of step.dt seconds in step.substeps sub-steps: the touching contacts of
  /// `contacts` solved, their impulses stored back, the bodies moved and their proxies with
  /// them. Bodies whose motion would leave the world are held (StepEvents::outOfBounds).
  /// `awake`: a bit per body index for the bodies that move (IslandSet::awakeBits).
  /// Returns the joints whose force or torque passed their break thresholds in this step,
  /// in index order (the world breaks them); valid until the next solve.
  std::span<const std::uint32_t> solve(StepContext& step, ContactSet& contacts, JointSet& joints,
                                       const std::vector<std::uint64_t>& awake);

  Solver();
  ~Solver();
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;

  /// Figures of the last step, for tests and benchmarks.
  struct Stats {
    int colors = 0;               // colours used
    std::size_t constraints = 0;  // touching contacts solved
    std::size_t overflow = 0;     // of which solved one at a time (no colour had room)
    std::size_t joints = 0;       // joints solved
  };
  const Stats& stats() const noexcept { return stats_; }
  /// The lanes this build solves with: "sse2", "avx2", "neon" or "scalar" (QUACK_SIMD).
  static const char* simdPath() noexcept;

 private:
  std::unique_ptr<SolverScratch> scratch_;
  Stats stats_;
};

}  // namespace quack::detail
