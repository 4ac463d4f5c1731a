#pragma once
/// Pair queries over shapes given as convex pieces (one piece for a convex shape, several
/// for a concave outline cut up by decomposeConcave), world frame: the rules of
/// docs/concave.md, shared by `quack query` and the Python module. A shape of one piece gets
/// the single-shape answer unchanged. For several pieces: overlap when any pair of pieces
/// overlaps; the distance of the closest pair (the first in order on ties); the penetration
/// of the deepest overlapping pair, else the closest pair's; a ray hits the nearest piece it
/// enters (the first on ties), and none when it starts inside a piece (as a ray starting
/// inside a convex shape is not entering it).

#include <cstddef>
#include <span>

#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/geometry/bounds.hpp"
#include "quack/geometry/raycast.hpp"

namespace quack {

using Pieces = std::span<const ShapeGeometry>;

inline bool overlapPieces(Pieces a, Transform worldFromA, Pieces b, Transform worldFromB) {
  for (const ShapeGeometry& x : a)
    for (const ShapeGeometry& y : b)
      if (testOverlap(x, worldFromA, y, worldFromB)) return true;
  return false;
}

/// The closest pair of pieces' answer; `bestA`, `bestB` (may be null) receive their indices.
inline DistanceOutput distancePieces(Pieces a, Transform worldFromA, Pieces b, Transform worldFromB,
                                     std::size_t* bestA = nullptr, std::size_t* bestB = nullptr) {
  if (a.size() == 1 && b.size() == 1) return computeDistance(a[0], worldFromA, b[0], worldFromB);
  DistanceOutput closest;
  bool first = true;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t k = 0; k < b.size(); ++k) {
      DistanceOutput d = computeDistance(a[i], worldFromA, b[k], worldFromB);
      if (first || d.distance < closest.distance) {
        closest = d;
        if (bestA != nullptr) *bestA = i;
        if (bestB != nullptr) *bestB = k;
        first = false;
      }
    }
  }
  return closest;
}

/// The deepest overlapping pair's answer, else the closest pair's; `bestA`, `bestB` (may be
/// null) receive the indices of the pair it is.
inline PenetrationOutput penetrationPieces(Pieces a, Transform worldFromA, Pieces b,
                                           Transform worldFromB, std::size_t* bestA = nullptr,
                                           std::size_t* bestB = nullptr) {
  std::size_t ia = 0, ib = 0;
  if (a.size() == 1 && b.size() == 1) {
    if (bestA != nullptr) *bestA = 0;
    if (bestB != nullptr) *bestB = 0;
    return computePenetration(a[0], worldFromA, b[0], worldFromB);
  }
  (void)distancePieces(a, worldFromA, b, worldFromB, &ia, &ib);
  PenetrationOutput best = computePenetration(a[ia], worldFromA, b[ib], worldFromB);
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t k = 0; k < b.size(); ++k) {
      PenetrationOutput p = computePenetration(a[i], worldFromA, b[k], worldFromB);
      if (p.overlap && (!best.overlap || p.depth > best.depth)) {
        best = p;
        ia = i;
        ib = k;
      }
    }
  }
  if (bestA != nullptr) *bestA = ia;
  if (bestB != nullptr) *bestB = ib;
  return best;
}

/// The ray origin + t translation (world frame, t in [0, 1]) against the shape placed by
/// worldFromA; the hit's point and normal in the world frame (zero when missed).
inline RayHit rayCastPieces(Pieces a, Transform worldFromA, Vec2 origin, Vec2 translation) {
  const RayCastInput input{invTransformPoint(worldFromA, origin),
                           invRotate(worldFromA.q, translation), 1.0f};
  bool inside = false;
  if (a.size() > 1) {
    for (const ShapeGeometry& piece : a)
      inside = inside || containsPoint(piece, input.origin);
  }
  RayHit best;
  if (!inside) {
    for (const ShapeGeometry& piece : a) {
      RayHit h = rayCast(piece, input);
      if (h.hit && (!best.hit || h.fraction < best.fraction)) best = h;
    }
  }
  if (best.hit) {
    best.point = transformPoint(worldFromA, best.point);
    best.normal = rotate(worldFromA.q, best.normal);
  } else {
    best.point = {};
    best.normal = {};
  }
  return best;
}

}  // namespace quack
