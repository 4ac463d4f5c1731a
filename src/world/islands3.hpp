#pragma once
// The 3D world's islands and sleep: dynamic bodies joined by touching contacts form an
// island; an island sleeps when every body in it has rested (moved slower than its sleep
// threshold) for kTimeToSleep seconds, and wakes whole when an awake body touches it.
//
// Unlike the 2D world's persistent islands (merged and split as contacts change), these are
// found again each step by a union-find over the touching contacts, in index order (the
// same islands whatever happened before): simple and O(bodies + contacts) a step.

#include <cstdint>
#include <vector>

#include "contact_set3.hpp"

namespace quack::detail {

class Islands3 {
 public:
  // After the narrow phase: joins the islands along the touching contacts and wakes every
  // island that holds an awake body (its sleeping bodies start the step awake).
  void wakeTouched(BodyStore3& store, const ContactSet3& contacts);
  // After the solver, with the islands of wakeTouched: adds dt to the rest time of each
  // awake dynamic body that moved slower than its threshold (else zero; a body touching a
  // moving kinematic body never rests), and puts to sleep every island whose bodies have all
  // rested kTimeToSleep seconds (their velocities set to zero).
  void sleepRested(BodyStore3& store, const ContactSet3& contacts, float dt);
  std::size_t islandCount() const noexcept { return islandCount_; }

 private:
  std::uint32_t find(std::uint32_t i) noexcept;
  std::vector<std::uint32_t> parent_;
  std::vector<float> islandRest_;
  std::size_t islandCount_ = 0;
};

}  // namespace quack::detail
