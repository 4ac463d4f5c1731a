// Narrow-phase kernels on random 8-gon pairs: Quack's GJK distance (cold and warm cache),
// EPA and SAT, with Box2D 2.4.1's b2Distance and b2CollidePolygons on the same pairs in the
// same run when Box2D is built (QUACK_HAVE_BOX2D). Read ns per query; the ratio is the
// Box2D time over Quack's. Pairs: 1024 fixed-seed pairs of 8-gons of size ~1, half apart
// and half overlapping, cycled through so the caches see realistic variety.

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/manifold.hpp"
#include "quack/collision/sat.hpp"
#include "support/random_shapes.hpp"

#if QUACK_HAVE_BOX2D
#include <box2d/b2_collision.h>
#include <box2d/b2_distance.h>
#include <box2d/b2_polygon_shape.h>
#endif

namespace {

using namespace quack;

struct Pair {
  Polygon a, b;
  Transform xa, xb;
#if QUACK_HAVE_BOX2D
  b2PolygonShape ba, bb;
  b2Transform bxa, bxb;
#endif
};

std::vector<Pair> makePairs(bool overlapping) {
  std::mt19937 rng(overlapping ? 99u : 98u);
  std::vector<Pair> pairs(1024);
  for (Pair& p : pairs) {
    p.a = testing::randomPolygon(rng, 8, 1.0f);
    p.b = testing::randomPolygon(rng, 8, 1.0f);
    float angle = testing::uniform(rng, -kPi, kPi);
    float reach =
        overlapping ? testing::uniform(rng, 0.2f, 0.9f) : testing::uniform(rng, 2.1f, 4.0f);
    p.xa = makeTransform({testing::uniform(rng, -5, 5), testing::uniform(rng, -5, 5)},
                         testing::uniform(rng, -kPi, kPi));
    p.xb = makeTransform(p.xa.p + reach * Vec2{std::cos(angle), std::sin(angle)},
                         testing::uniform(rng, -kPi, kPi));
#if QUACK_HAVE_BOX2D
    b2Vec2 va[8], vb[8];
    for (int i = 0; i < 8; ++i) {
      va[i].Set(p.a.vertices[i].x, p.a.vertices[i].y);
      vb[i].Set(p.b.vertices[i].x, p.b.vertices[i].y);
    }
    p.ba.Set(va, 8);
    p.bb.Set(vb, 8);
    // Box2D pads polygons with a skin (b2_polygonRadius); Quack's are sharp. Zero it so
    // both answer the same question.
    p.ba.m_radius = 0.0f;
    p.bb.m_radius = 0.0f;
    p.bxa.Set(b2Vec2(p.xa.p.x, p.xa.p.y), p.xa.q.angle());
    p.bxb.Set(b2Vec2(p.xb.p.x, p.xb.p.y), p.xb.q.angle());
#endif
  }
  return pairs;
}

const std::vector<Pair>& apart() {
  static const std::vector<Pair> pairs = makePairs(false);
  return pairs;
}
const std::vector<Pair>& overlapping() {
  static const std::vector<Pair> pairs = makePairs(true);
  return pairs;
}

void BM_QuackGjkDistanceCold(benchmark::State& state) {
  const auto& pairs = apart();
  std::size_t i = 0;
  for (auto _ : state) {
    const Pair& p = pairs[i++ & 1023];
    DistanceOutput d = computeDistance(makeProxy(p.a), p.xa, makeProxy(p.b), p.xb);
    benchmark::DoNotOptimize(d);
  }
}
BENCHMARK(BM_QuackGjkDistanceCold);

void BM_QuackGjkDistanceWarm(benchmark::State& state) {
  const auto& pairs = apart();
  std::vector<GjkCache> caches(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    (void)computeDistance(makeProxy(pairs[k].a), pairs[k].xa, makeProxy(pairs[k].b), pairs[k].xb,
                          &caches[k]);
  }
  std::size_t i = 0;
  for (auto _ : state) {
    std::size_t k = i++ & 1023;
    const Pair& p = pairs[k];
    DistanceOutput d = computeDistance(makeProxy(p.a), p.xa, makeProxy(p.b), p.xb, &caches[k]);
    benchmark::DoNotOptimize(d);
  }
}
BENCHMARK(BM_QuackGjkDistanceWarm);

void BM_QuackEpa(benchmark::State& state) {
  const auto& pairs = overlapping();
  std::size_t i = 0;
  for (auto _ : state) {
    const Pair& p = pairs[i++ & 1023];
    PenetrationOutput d = computePenetration(makeProxy(p.a), p.xa, makeProxy(p.b), p.xb);
    benchmark::DoNotOptimize(d);
  }
}
BENCHMARK(BM_QuackEpa);

void BM_QuackSat(benchmark::State& state) {
  const auto& pairs = overlapping();
  std::size_t i = 0;
  for (auto _ : state) {
    const Pair& p = pairs[i++ & 1023];
    SatOutput d = computeSat(p.a, p.xa, p.b, p.xb);
    benchmark::DoNotOptimize(d);
  }
}
BENCHMARK(BM_QuackSat);

// Contact manifolds: Quack's collidePolygons against b2CollidePolygons below,
// on the overlapping pairs and on the apart ones (where both should leave early).
void BM_QuackCollidePolygons(benchmark::State& state) {
  const auto& pairs = overlapping();
  std::size_t i = 0;
  for (auto _ : state) {
    const Pair& p = pairs[i++ & 1023];
    Manifold m = collidePolygons(p.a, p.xa, p.b, p.xb, 0.0f);
    benchmark::DoNotOptimize(m);
  }
}
BENCHMARK(BM_QuackCollidePolygons);

void BM_QuackCollidePolygonsApart(benchmark::State& state) {
  const auto& pairs = apart();
  std::size_t i = 0;
  for (auto _ : state) {
    const Pair& p = pairs[i++ & 1023];
    Manifold m = collidePolygons(p.a, p.xa, p.b, p.xb, 0.0f);
    benchmark::DoNotOptimize(m);
  }
}
BENCHMARK(BM_QuackCollidePolygonsApart);

#if QUACK_HAVE_BOX2D
void BM_Box2dDistanceCold(benchmark::State& state) {
  const auto& pairs = apart();
  std::size_t i = 0;
  for (auto _ : state) {
    const Pair& p = pairs[i++ & 1023];
    b2DistanceInput input;
    input.proxyA.Set(&p.ba, 0);
    input.proxyB.Set(&p.bb, 0);
    input.transformA = p.bxa;
    input.transformB = p.bxb;
    input.useRadii = true;
    b2SimplexCache cache;
    cache.count = 0;
    b2DistanceOutput out;
    b2Distance(&out, &cache, &input);
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_Box2dDistanceCold);

void BM_Box2dDistanceWarm(benchmark::State& state) {
  const auto& pairs = apart();
  std::vector<b2SimplexCache> caches(pairs.size());
  auto run = [&](std::size_t k) {
    const Pair& p = pairs[k];
    b2DistanceInput input;
    input.proxyA.Set(&p.ba, 0);
    input.proxyB.Set(&p.bb, 0);
    input.transformA = p.bxa;
    input.transformB = p.bxb;
    input.useRadii = true;
    b2DistanceOutput out;
    b2Distance(&out, &caches[k], &input);
    return out;
  };
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    caches[k].count = 0;
    (void)run(k);
  }
  std::size_t i = 0;
  for (auto _ : state) {
    b2DistanceOutput out = run(i++ & 1023);
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_Box2dDistanceWarm);

void BM_Box2dCollidePolygons(benchmark::State& state) {
  const auto& pairs = overlapping();
  std::size_t i = 0;
  for (auto _ : state) {
    const Pair& p = pairs[i++ & 1023];
    b2Manifold m;
    b2CollidePolygons(&m, &p.ba, p.bxa, &p.bb, p.bxb);
    benchmark::DoNotOptimize(m);
  }
}
BENCHMARK(BM_Box2dCollidePolygons);

void BM_Box2dCollidePolygonsApart(benchmark::State& state) {
  const auto& pairs = apart();
  std::size_t i = 0;
  for (auto _ : state) {
    const Pair& p = pairs[i++ & 1023];
    b2Manifold m;
    b2CollidePolygons(&m, &p.ba, p.bxa, &p.bb, p.bxb);
    benchmark::DoNotOptimize(m);
  }
}
BENCHMARK(BM_Box2dCollidePolygonsApart);
#endif

}  // namespace

BENCHMARK_MAIN();
