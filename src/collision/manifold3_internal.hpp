#pragma once
// Pieces of the 3D manifolds shared with the mesh contacts (internal to the collision
// layer).

#include "quack/collision/manifold3.hpp"

namespace quack::detail {

// A manifold point at `point` (world) with its anchors from the two origins.
ManifoldPoint3 makeManifoldPoint3(Vec3 point, float separation, std::uint32_t id,
                                  Transform3 worldFromA, Transform3 worldFromB) noexcept;
// Keeps at most four of `count` points (the deepest, the furthest from it, the largest
// triangle, the furthest outside it); returns how many. `normal` orients the areas.
int reduceManifoldPoints3(ManifoldPoint3* points, int count, Vec3 normal) noexcept;

}  // namespace quack::detail
