#pragma once
// The contact solver: one part of the world. Soft contacts solved by sequential impulses
// over sub-steps, with relaxation and restitution; it reads the bodies and the touching
// contacts, writes the bodies' velocities and poses and the contacts' accumulated impulses,
// and reports hits. docs/world.md explains the choices.

#include <cstddef>
#include <cstdint>
#include <memory>
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

struct SolverScratch;  // solver.cpp: the per-step arrays

class Solver {
 public:
  /// One step of step.dt seconds in step.substeps sub-steps: the touching contacts of
  /// `contacts` solved, their impulses stored back, the bodies moved and their proxies with
  /// them. Bodies whose motion would leave the world are held (StepEvents::outOfBounds).
  /// `awake`: a bit per body index for the bodies that move (IslandSet::awakeBits).
  void solve(StepContext& step, ContactSet& contacts, const std::vector<std::uint64_t>& awake);

  Solver();
  ~Solver();
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;

  /// Figures of the last step, for tests and benchmarks.
  struct Stats {
    int colors = 0;               // colours used
    std::size_t constraints = 0;  // touching contacts solved
    std::size_t overflow = 0;     // of which solved one at a time (no colour had room)
  };
  const Stats& stats() const noexcept { return stats_; }
  /// The lanes this build solves with: "sse2", "avx2", "neon" or "scalar" (QUACK_SIMD).
  static const char* simdPath() noexcept;

 private:
  std::unique_ptr<SolverScratch> scratch_;
  Stats stats_;
};

}  // namespace quack::detail
