#pragma once
// The 3D world's contact solver: the soft step (Catto, "Solver2D", 2024, and Box2D v3's and
// Box3D's solvers, read for understanding): per step, colour the touching manifolds and
// prepare each once (anchors from the centres of mass, effective masses, the base
// separation); then per sub-step integrate velocities, warm start, solve with a soft push
// (bias), integrate positions, and relax (solve again without the push); after the
// sub-steps, restitution; then store the impulses for the next step's warm start.
//
// As the 2D solver (solver.cpp): no two manifolds of a colour share a dynamic body, so a
// colour's manifolds are solved side by side in SIMD lanes and shared among the workers,
// with the bits of solving them one at a time; manifolds of a body with more contacts than
// the colours hold are solved one at a time (the overflow set). docs/world3.md, "Colours,
// lanes and workers".

#include <cstddef>
#include <cstdint>
#include <memory>

#include "contact_set3.hpp"
#include "quack/world/world3.hpp"

namespace quack::detail {

class BodyStore3;
class TaskRunner;
struct SolverScratch3;  // solver3.cpp: the per-step arrays

class Solver3 {
 public:
  // Advances the awake dynamic and kinematic bodies by dt in `substeps` sub-steps, solving
  // the touching contacts that have one of them, on `tasks`' workers. Moves their proxies.
  // Bodies whose motion would leave the world (beyond kMaxCoordinate / 2, or not finite)
  // are held at their pose from the start of the step with zero velocity.
  void step(BodyStore3& store, ContactSet3& contacts, const WorldDef3& def, float dt, int substeps,
            TaskRunner& tasks);

  Solver3();
  ~Solver3();
  Solver3(const Solver3&) = delete;
  Solver3& operator=(const Solver3&) = delete;

  // Figures of the last step, for tests and benchmarks.
  struct Stats {
    int colors = 0;               // colours used
    std::size_t constraints = 0;  // manifolds solved
    std::size_t overflow = 0;     // of which solved one at a time (no colour had room)
  };
  const Stats& stats() const noexcept { return stats_; }

 private:
  std::unique_ptr<SolverScratch3> scratch_;
  Stats stats_;
};

}  // namespace quack::detail
