#pragma once
/// `Sweep3`: the motion of a rigid body in 3D over one step, for continuous collision.

#include "quack/math/transform3.hpp"

namespace quack {

/// Motion over a step, t in [0, 1]: the centre of mass moves linearly from c1 to c2, and the
/// body turns at a constant rate about a fixed world axis, by `rotation` (axis times angle,
/// radians, world frame) in all, from q1. The angle may exceed half a turn, so a body can
/// spin more than that in one step. `localCenter` is the centre of mass in the body frame.
struct Sweep3 {
  Vec3 localCenter;  ///< centre of mass, body frame
  Vec3 c1, c2;       ///< centre of mass at t = 0 and t = 1, world frame
  Quat q1;           ///< orientation at t = 0 (unit)
  Vec3 rotation;     ///< axis times angle turned over the step, world frame, radians
};

/// The angle turned over the whole sweep, radians (the body's angular speed per unit t).
inline float sweepAngle(const Sweep3& s) noexcept {
  return length(s.rotation);
}

/// worldFromBody at fraction t of the sweep (t not clamped).
inline Transform3 transformAt(const Sweep3& s, float t) noexcept {
  Vec3 c = (1.0f - t) * s.c1 + t * s.c2;
  float angle = length(s.rotation);
  Quat q = s.q1;
  if (angle > 0.0f)
    q = normalize(Quat::fromAxisAngle((1.0f / angle) * s.rotation, t * angle) * s.q1);
  return {c - rotate(q, s.localCenter), q};
}

/// Sweep between two poses (worldFromBody at the start and end), the short way round.
inline Sweep3 makeSweep3(Vec3 localCenter, Transform3 start, Transform3 end) noexcept {
  Quat d = end.q * conjugate(start.q);  // world-frame rotation from start to end
  if (d.w < 0.0f) d = {-d.x, -d.y, -d.z, -d.w};
  Vec3 v = d.vector();
  float s = length(v);
  Vec3 rotation;
  if (s > 0.0f) rotation = (2.0f * portableAtan2(s, d.w) / s) * v;
  return {localCenter, transformPoint(start, localCenter), transformPoint(end, localCenter),
          start.q, rotation};
}

}  // namespace quack
