#pragma once
// The arithmetic of the 2D simplex solver (simplex2.hpp), shared by solveSimplex2 and GJK's
// loop. The loop keeps a smaller simplex than Simplex2 (the support points' differences and
// indices only) and solves it inline; both go through these functions, so they form the
// same values in the same order and give the same bits.

#include <cmath>
#include <cstdint>
#include <cstring>

#include "quack/math/vec2.hpp"

namespace quack::detail {

// True when a and b are both positive or both negative (zero matches nothing): a weight
// of exactly zero drops its vertex, so a point on an edge is solved on that edge. Bitwise
// & and |, not && and ||: the four comparisons are cheap, and the branches short-circuits
// would make go at random in GJK (the signs are what the solver is there to find).
[[gnu::always_inline]] inline bool sameSign(float a, float b) noexcept {
  return ((a > 0.0f) & (b > 0.0f)) | ((a < 0.0f) & (b < 0.0f));
}

// A float's bits and back. std::memcpy, not std::bit_cast, which emscripten 3.1.6's libc++
// (the web build) lacks; the compilers make either one register move.
[[gnu::always_inline]] inline std::uint32_t floatBits(float x) noexcept {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &x, sizeof bits);
  return bits;
}
[[gnu::always_inline]] inline float bitsFloat(std::uint32_t bits) noexcept {
  float x = 0.0f;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

// c ? x : y by masks: the compilers otherwise branch on c where GJK's pairs make it go
// either way at random (which axis of a segment is longer, which end is nearer).
[[gnu::always_inline]] inline float selectf(bool c, float x, float y) noexcept {
  const std::uint32_t mask = 0u - static_cast<std::uint32_t>(c);
  return bitsFloat((floatBits(x) & mask) | (floatBits(y) & ~mask));
}
[[gnu::always_inline]] inline Vec2 selectv(bool c, Vec2 x, Vec2 y) noexcept {
  return {selectf(c, x.x, y.x), selectf(c, x.y, y.y)};
}

// Montanari et al.'s S1D in the plane: the origin projected onto the line through a and b,
// and its barycentric coordinates measured along the axis where the segment is longest
// (the best conditioned of the two ratios). The weights are left as numerators over mu and
// divided only for the edge that is kept (the triangle solve compares two or three edges).
struct SegmentSolve {
  Vec2 closest;         // the point of segment ab nearest the origin
  Vec2 edge;            // b - a
  float edgeSq = 0.0f;  // dot(edge, edge)
  float c1 = 0.0f;      // weight of a times mu, when inside
  float c2 = 0.0f;      // weight of b times mu, when inside
  float mu = 0.0f;      // a - b along the longer axis
  bool inside = false;  // the projection falls strictly inside the segment
  bool atA = false;     // otherwise: a is the nearer end (b when false)
};

[[gnu::always_inline]] inline SegmentSolve solveSegment(Vec2 a, Vec2 b) noexcept {
  SegmentSolve r;
  r.edge = b - a;
  r.edgeSq = dot(r.edge, r.edge);
  // Formed whatever the outcome (a division by zero when ee is, whose value goes unused):
  // selecting the outcome afterwards costs no branch.
  Vec2 p0 = a - (dot(a, r.edge) / r.edgeSq) * r.edge;
  // std::fabs, not absf: the same comparison (only the sign of a zero or NaN differs), and
  // a mask where absf compiles to a branch.
  const bool useX = std::fabs(r.edge.x) >= std::fabs(r.edge.y);
  // The axis, and below the closest point, are picked by indexing a small table rather
  // than by branches (which GJK's pairs take at random) or bit masks (a dozen moves
  // between the float and integer registers a segment).
  const float coords[3][2] = {{a.x, a.y}, {b.x, b.y}, {p0.x, p0.y}};
  const int axis = static_cast<int>(!useX);  // arithmetic on the bools: no branch
  const float pa = coords[0][axis];
  const float pb = coords[1][axis];
  const float pp = coords[2][axis];
  r.mu = pa - pb;
  r.c1 = pp - pb;
  r.c2 = pa - pp;
  const bool degenerate = r.edgeSq == 0.0f;  // a and b coincide (to float): keep a
  const bool towardA = sameSign(r.mu, r.c1);
  r.inside = !degenerate & towardA & sameSign(r.mu, r.c2);
  // Outside (or on an end of) the segment: the nearer end is closest.
  r.atA = degenerate | towardA;
  const int nearest = 2 * static_cast<int>(r.inside) + static_cast<int>(!r.inside & !r.atA);
  r.closest = {coords[nearest][0], coords[nearest][1]};
  return r;
}

struct SegmentWeights {
  float a;
  float b;
};

// Both quotients are formed whatever the outcome, so that choosing takes no branch.
[[gnu::always_inline]] inline SegmentWeights segmentWeights(const SegmentSolve& r) noexcept {
  const float a = r.c1 / r.mu;
  const float b = r.c2 / r.mu;
  return {r.inside ? a : (r.atA ? 1.0f : 0.0f), r.inside ? b : (r.atA ? 0.0f : 1.0f)};
}

// The triangle abc: twice its signed area mu, and of the three triangles with the origin in
// place of one vertex; they sum to mu, so sub[k] / mu are the origin's barycentric
// coordinates, and a vertex whose sub-area has the wrong sign faces the edge opposite it
// towards the origin.
struct TriangleAreas {
  float mu;
  float sub[3];
  bool faces[3];  // the edge opposite vertex k faces the origin: !sameSign(mu, sub[k])
};

[[gnu::always_inline]] inline TriangleAreas triangleAreas(Vec2 a, Vec2 b, Vec2 c) noexcept {
  TriangleAreas t;
  t.mu = cross(b - a, c - a);
  t.sub[0] = cross(b, c);
  t.sub[1] = cross(c, a);
  t.sub[2] = cross(a, b);
  for (int k = 0; k < 3; ++k)
    t.faces[k] = !sameSign(t.mu, t.sub[k]);
  return t;
}

}  // namespace quack::detail
