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
