// decomposePolygon on random star-shaped outlines of 64 to 1,024 points (fixed seed): the
// time per decomposition, with the pieces, reflex vertices and lower bound as counters, so
// the quality figures of docs/concave.md come out of the same run.

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "quack/geometry/decompose.hpp"

namespace {

using namespace quack;

std::vector<Vec2> randomStar(int count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> radius(3.0f, 10.0f);
  std::vector<Vec2> star;
  for (int i = 0; i < count; ++i) {
    float a = 2.0f * kPi * static_cast<float>(i) / static_cast<float>(count);
    float r = radius(rng);
    star.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return star;
}

void BM_DecomposeStar(benchmark::State& state) {
  const std::vector<Vec2> star = randomStar(static_cast<int>(state.range(0)), 1);
  ConvexDecomposition d;
  for (auto _ : state) {
    d = decomposePolygon(star).value();
    benchmark::DoNotOptimize(d.pieces.data());
  }
  state.counters["pieces"] = static_cast<double>(d.pieces.size());
  state.counters["reflex"] = d.reflexCount;
  state.counters["lower_bound"] = d.lowerBound;
  state.counters["pieces_per_bound"] =
      static_cast<double>(d.pieces.size()) / static_cast<double>(d.lowerBound);
}
BENCHMARK(BM_DecomposeStar)->Arg(64)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
