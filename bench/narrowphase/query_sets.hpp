#pragma once
// Plain data shared by the query benchmark (query_bench.cpp) and its Box2D v3 peer
// (box2d_v3_peer.cpp). No library's types appear here: Box2D 2.4.1 and v3 both name their
// types b2*, so each lives in its own translation unit and they meet only through this.

#include <cstddef>
#include <cstdint>

namespace quack_bench {

/// A body pose: position (metres) and angle (radians). Each library builds its transform
/// from it inside the timed loop, as a game (or the Python batch) does.
struct Pose {
  float x = 0.0f, y = 0.0f, angle = 0.0f;
};

/// One distance or manifold query: two shapes of the pool, each at its pose.
struct QueryPair {
  std::uint32_t a = 0, b = 0;
  Pose pa, pb;
};

/// One time-of-impact query: two shapes of the pool, each moving from its first pose to its
/// second over the step (centre and angle linear; the shapes' local centre is the origin).
struct QuerySweep {
  std::uint32_t a = 0, b = 0;
  Pose a1, a2, b1, b2;
};

/// A pool shape: a convex polygon, counter-clockwise, radius zero.
struct PoolPolygon {
  float x[8] = {}, y[8] = {};
  int count = 0;
};

}  // namespace quack_bench
