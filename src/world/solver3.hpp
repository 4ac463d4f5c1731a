#pragma once
// The 3D world's contact solver: the soft step (Catto, "Solver2D", 2024, and Box2D v3's
// solver, read for understanding): per step, prepare each touching manifold once (anchors
// from the centres of mass, effective masses, the base separation); then per sub-step
// integrate velocities, warm start, solve with a soft push (bias), integrate positions, and
// relax (solve again without the push); after the sub-steps, restitution; then store the
// impulses for the next step's warm start. Friction along two tangents, clamped to the
// Coulomb circle of each point; rolling resistance on the relative angular velocity.
//
// Scalar and single-threaded: constraints are solved one after another in contact order
// (Gauss-Seidel), without the 2D solver's graph colouring and SIMD lanes (docs/world3.md).

#include <cstdint>
#include <vector>

#include "contact_set3.hpp"

namespace quack::detail {

class Solver3 {
 public:
  // Advances the awake dynamic and kinematic bodies by dt in `substeps` sub-steps, solving
  // the touching contacts that have one of them. Moves their proxies. Bodies whose motion
  // would leave the world (beyond kMaxCoordinate / 2, or not finite) are held at their
  // pose from the start of the step with zero velocity.
  void step(BodyStore3& store, ContactSet3& contacts, const WorldDef3& def, float dt, int substeps);

 private:
  std::vector<std::uint32_t> slotOf_;  // per body index: its slot, 0 for none
  std::vector<std::uint32_t> movers_;  // body index per slot (slot 0: none)
};

}  // namespace quack::detail
