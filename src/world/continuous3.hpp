#pragma once
// The 3D world's continuous collision: after the solver, a body that moved more than half
// its thinnest shape in the step is swept from where the step began to where it ended
// against the static shapes and meshes in the way and the bodies that did not move fast
// (at their end poses), and is put back to the first time of impact (its velocity kept, so
// the next step's contacts meet the surface). Private to the world layer.

#include <cstdint>
#include <vector>

#include "body_store3.hpp"
#include "quack/math/sweep3.hpp"

namespace quack::detail {

class Continuous3 {
 public:
  // Before the solver: remembers where every awake dynamic body starts the step.
  void recordStarts(const BodyStore3& store);
  // After the solver: sweeps the fast bodies, in body order (each on its own, against
  // shapes no fast body moves, so the order changes nothing). Returns how many were put back.
  int solve(BodyStore3& store);

 private:
  struct Start {
    std::uint32_t body;
    Transform3 pose;
  };
  std::vector<Start> starts_;
  std::vector<Start> fast_;           // the bodies that moved fast, in body order
  std::vector<Sweep3> sweeps_;        // their sweeps
  std::vector<std::uint8_t> isFast_;  // per body index
  std::vector<std::uint32_t> candidates_;
};

}  // namespace quack::detail
