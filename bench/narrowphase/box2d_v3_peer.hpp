#pragma once
// Box2D v3, the second peer of the query benchmark, behind plain data (query_sets.hpp):
// this header names no b2 type, so query_bench.cpp can include Box2D 2.4.1 beside it.
// Built only when QUACK_BOX2D_V3_DIR is set (docs/narrow-phase.md, "Queries from angles").

#include <cstddef>

#include "query_sets.hpp"

namespace quack_bench::v3 {

/// Replaces the pool. Returns false (and keeps nothing) when Box2D v3's hull of some
/// polygon keeps fewer vertices than given, so that the caller can retry with other shapes.
bool setPool(const PoolPolygon* polygons, std::size_t count);

/// Box2D v3's rotation for `radians` (b2MakeRot: an approximate cosine and sine, then
/// normalised), so that the agreement check can ask Quack the very question v3 answers.
void rotation(float radians, float* cosine, float* sine);

/// One query each, for the agreement check (the timed loops are the *Batch functions).
float distance(const QueryPair& pair);
/// Deepest separation of the manifold (0 points: +infinity); `pointCount` out.
float manifoldSeparation(const QueryPair& pair, int* pointCount);
/// Fraction of the step at the time of impact; `hit` out (true: b2_toiStateHit).
float timeOfImpact(const QuerySweep& sweep, bool* hit);

/// The timed loops: `count` queries from `pairs`, each building both transforms from the
/// poses' angles (b2MakeRot) and the relative transform (b2InvMulTransforms). They return a
/// checksum so that nothing is optimised away.
float distanceBatch(const QueryPair* pairs, std::size_t count);
float manifoldBatch(const QueryPair* pairs, std::size_t count);
float toiBatch(const QuerySweep* sweeps, std::size_t count);

}  // namespace quack_bench::v3
