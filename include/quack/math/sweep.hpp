#pragma once
/// `Sweep`: the motion of a rigid body over one step, for continuous collision.

#include "quack/math/transform.hpp"

namespace quack {

/// Motion of a body over a step, parameterised by t in [0, 1]: the centre of mass moves
/// linearly from c1 to c2 and the angle linearly from a1 to a2 (so a body can spin more
/// than half a turn per step). `localCenter` is the centre of mass in the body frame.
struct Sweep {
  Vec2 localCenter;  ///< centre of mass, body frame
  Vec2 c1, c2;       ///< centre of mass at t = 0 and t = 1, world frame
  float a1 = 0.0f;   ///< angle at t = 0, radians
  float a2 = 0.0f;   ///< angle at t = 1, radians

  friend constexpr bool operator==(const Sweep&, const Sweep&) noexcept = default;
};

/// worldFromBody at fraction t of the sweep (t is not clamped; [0, 1] is the step).
inline Transform transformAt(const Sweep& s, float t) noexcept {
  Vec2 c = (1.0f - t) * s.c1 + t * s.c2;
  Rot q = Rot::fromAngle((1.0f - t) * s.a1 + t * s.a2);
  // The body origin sits at c minus the rotated local centre.
  return {c - rotate(q, s.localCenter), q};
}

/// Sweep between two body poses (worldFromBody at the start and end of the step).
inline Sweep makeSweep(Vec2 localCenter, Transform start, Transform end) noexcept {
  float a1 = start.q.angle();
  float a2 = end.q.angle();
  // Take the short way round; a caller that wants more than half a turn sets a2 itself.
  float d = a2 - a1;
  if (d > kPi) a2 -= 2.0f * kPi;
  if (d < -kPi) a2 += 2.0f * kPi;
  return {localCenter, transformPoint(start, localCenter), transformPoint(end, localCenter), a1,
          a2};
}

/// Moves the start of the sweep to fraction `alpha` (used when a body is advanced to its
/// time of impact): the remaining motion is [alpha, 1] re-parameterised to [0, 1].
constexpr Sweep advance(Sweep s, float alpha) noexcept {
  s.c1 = (1.0f - alpha) * s.c1 + alpha * s.c2;
  s.a1 = (1.0f - alpha) * s.a1 + alpha * s.a2;
  return s;
}

}  // namespace quack
