// Time of impact: Quack's computeToi beside Box2D 2.4.1's b2TimeOfImpact on the
// same sweeps in the same run, and how often each lets the shapes pass through each other
// (checked against the distance sampled densely along every sweep).
//
// Three sets of 1,024 sweeps (fixed seeds): "bullet" (a 2 x 0.8 cm box at 1,000 m/s and up
// to 0.5 rad per step across a 1 cm wall), "spinner" (a 1 m x 8 mm rod turning up to half a
// turn per step beside the wall) and "random" (pairs of random 8-gons of size 1, one moving
// up to 8 m and 1 rad). Polygons are sharp on both sides (Box2D's skin radius set to 0), so
// both aim at the same target separation, one linear slop (5 mm).

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "quack/collision/toi.hpp"
#include "support/random_shapes.hpp"

#if QUACK_HAVE_BOX2D
#include <box2d/b2_distance.h>
#include <box2d/b2_polygon_shape.h>
#include <box2d/b2_time_of_impact.h>
#endif

namespace {

using namespace quack;

struct Case {
  Polygon a, b;
  Sweep sa, sb;
#if QUACK_HAVE_BOX2D
  b2PolygonShape ba, bb;
  b2Sweep bsa, bsb;
#endif
};

enum class Set { bullet, spinner, random };
const char* toString(Set s) {
  return s == Set::bullet ? "bullet" : s == Set::spinner ? "spinner" : "random";
}

Sweep makeSweepAt(Vec2 c1, float a1, Vec2 c2, float a2) {
  return {{}, c1, c2, a1, a2};
}

std::vector<Case> makeCases(Set set) {
  std::mt19937 rng(set == Set::bullet ? 701u : set == Set::spinner ? 702u : 703u);
  std::vector<Case> cases(1024);
  for (Case& c : cases) {
    if (set == Set::random) {
      c.a = testing::randomPolygon(rng, 8, 1.0f);
      c.b = testing::randomPolygon(rng, 8, 1.0f);
      Vec2 a1{testing::uniform(rng, -0.5f, 0.5f), testing::uniform(rng, -0.5f, 0.5f)};
      c.sa = makeSweepAt(a1, 0.0f, a1 + Vec2{testing::uniform(rng, -0.3f, 0.3f), 0.0f},
                         testing::uniform(rng, -0.5f, 0.5f));
      Vec2 b1{testing::uniform(rng, -6.0f, -2.5f), testing::uniform(rng, -2.0f, 2.0f)};
      float turn0 = testing::uniform(rng, -kPi, kPi);
      c.sb = makeSweepAt(b1, turn0,
                         b1 + Vec2{testing::uniform(rng, 3.0f, 8.0f), testing::uniform(rng, -2, 2)},
                         turn0 + testing::uniform(rng, -1.0f, 1.0f));
    } else {
      c.a = makeBox(0.005f, 2.0f).value();
      c.sa = makeSweepAt({0, 0}, 0, {0, 0}, 0);
      if (set == Set::bullet) {
        c.b = makeBox(0.01f, 0.004f).value();
        float heading = testing::uniform(rng, -1.2f, 1.2f);
        Vec2 dir{std::cos(heading), std::sin(heading)};
        Vec2 crossing{0.0f, testing::uniform(rng, -1.8f, 1.8f)};
        float step = 1000.0f / 60.0f;
        Vec2 start = crossing - testing::uniform(rng, 0.05f, 0.95f) * step * dir;
        float a1 = testing::uniform(rng, -kPi, kPi);
        c.sb = makeSweepAt(start, a1, start + step * dir, a1 + testing::uniform(rng, -0.5f, 0.5f));
      } else {
        c.b = makeBox(0.5f, 0.004f).value();
        Vec2 c1{testing::uniform(rng, -1.5f, -0.52f), testing::uniform(rng, -1.0f, 1.0f)};
        float a1 = testing::uniform(rng, -kPi, kPi);
        c.sb = makeSweepAt(
            c1, a1,
            c1 + Vec2{testing::uniform(rng, 0.0f, 1.0f), testing::uniform(rng, -0.5f, 0.5f)},
            a1 + testing::uniform(rng, -kPi, kPi));
      }
    }
#if QUACK_HAVE_BOX2D
    auto toBox2d = [](const Polygon& p, b2PolygonShape& out) {
      b2Vec2 v[kMaxPolygonVertices];
      for (int i = 0; i < p.count; ++i)
        v[i].Set(p.vertices[i].x, p.vertices[i].y);
      out.Set(v, p.count);
      out.m_radius = 0.0f;  // sharp, as Quack's
    };
    toBox2d(c.a, c.ba);
    toBox2d(c.b, c.bb);
    auto sweep2 = [](const Sweep& s, b2Sweep& out) {
      out.localCenter.Set(s.localCenter.x, s.localCenter.y);
      out.c0.Set(s.c1.x, s.c1.y);
      out.c.Set(s.c2.x, s.c2.y);
      out.a0 = s.a1;
      out.a = s.a2;
      out.alpha0 = 0.0f;
    };
    sweep2(c.sa, c.bsa);
    sweep2(c.sb, c.bsb);
#endif
  }
  return cases;
}

const std::vector<Case>& casesOf(Set set) {
  static const std::vector<Case> sets[3] = {makeCases(Set::bullet), makeCases(Set::spinner),
                                            makeCases(Set::random)};
  return sets[static_cast<int>(set)];
}

ToiOutput runQuack(const Case& c) {
  return computeToi(makeProxy(c.a), c.sa, makeProxy(c.b), c.sb);
}

#if QUACK_HAVE_BOX2D
b2TOIOutput runBox2d(const Case& c) {
  b2TOIInput in;
  in.proxyA.Set(&c.ba, 0);
  in.proxyB.Set(&c.bb, 0);
  in.sweepA = c.bsa;
  in.sweepB = c.bsb;
  in.tMax = 1.0f;
  b2TOIOutput out;
  b2TimeOfImpact(&out, &in);
  return out;
}
#endif

// The first sampled time at which the shapes overlap (2,000 samples), or 2 if none.
float firstOverlap(const Case& c) {
  const ShapeProxy a = makeProxy(c.a), b = makeProxy(c.b);
  for (int k = 0; k <= 2000; ++k) {
    const float t = static_cast<float>(k) / 2000.0f;
    if (computeDistance(a, transformAt(c.sa, t), b, transformAt(c.sb, t)).distance <= 0.0f)
      return t;
  }
  return 2.0f;
}

// Agreement and tunnelling, printed before the timings.
void report() {
  std::printf("%-8s %5s | %-34s | %-34s | %s\n", "set", "cases", "quack: hit sep ovl fail tunnel",
              "box2d: touch sep ovl fail tunnel", "|t_q - t_b| mean / max (both hit)");
  for (Set set : {Set::bullet, Set::spinner, Set::random}) {
    int q[5] = {}, b[5] = {}, qTunnel = 0, bTunnel = 0, both = 0;
    double sum = 0.0, worst = 0.0;
    for (const Case& c : casesOf(set)) {
      const float first = firstOverlap(c);
      ToiOutput qo = runQuack(c);
      q[static_cast<int>(qo.status)]++;
      // Passing through: the answer is past the first sampled overlap (a separated answer
      // counts as t = 1), unless the pair overlapped from the start.
      const float qt = qo.status == ToiStatus::separated ? 1.0f : qo.t;
      if (qo.status != ToiStatus::overlapped && first <= 1.0f && qt > first) ++qTunnel;
#if QUACK_HAVE_BOX2D
      b2TOIOutput bo = runBox2d(c);
      const int bs = bo.state == b2TOIOutput::e_touching     ? 0
                     : bo.state == b2TOIOutput::e_separated  ? 1
                     : bo.state == b2TOIOutput::e_overlapped ? 2
                                                             : 3;
      b[bs]++;
      const float bt = bo.state == b2TOIOutput::e_separated ? 1.0f : bo.t;
      if (bs != 2 && first <= 1.0f && bt > first) ++bTunnel;
      if (bs == 0 && qo.status == ToiStatus::hit) {
        ++both;
        const double d = std::abs(static_cast<double>(qo.t) - static_cast<double>(bo.t));
        sum += d;
        worst = std::max(worst, d);
      }
#endif
    }
    std::printf(
        "%-8s %5zu | %6d %4d %4d %4d %6d          | %6d %4d %4d %4d %6d          | %.2e / %.2e\n",
        toString(set), casesOf(set).size(), q[0], q[1], q[2], q[3], qTunnel, b[0], b[1], b[2], b[3],
        bTunnel, both > 0 ? sum / both : 0.0, worst);
  }
  std::fflush(stdout);
}

void BM_QuackToi(benchmark::State& state) {
  const auto& cases = casesOf(static_cast<Set>(state.range(0)));
  std::size_t i = 0;
  long iterations = 0;
  for (auto _ : state) {
    ToiOutput out = runQuack(cases[i++ & 1023]);
    iterations += out.iterations;
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(toString(static_cast<Set>(state.range(0))));
  state.counters["gjk_per_toi"] =
      static_cast<double>(iterations) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_QuackToi)->Arg(0)->Arg(1)->Arg(2);

#if QUACK_HAVE_BOX2D
void BM_Box2dToi(benchmark::State& state) {
  const auto& cases = casesOf(static_cast<Set>(state.range(0)));
  std::size_t i = 0;
  for (auto _ : state) {
    b2TOIOutput out = runBox2d(cases[i++ & 1023]);
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(toString(static_cast<Set>(state.range(0))));
}
BENCHMARK(BM_Box2dToi)->Arg(0)->Arg(1)->Arg(2);
#endif

}  // namespace

int main(int argc, char** argv) {
  // --no_report skips the agreement table (for profiling the timed loops alone).
  bool wantReport = true;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--no_report") {
      wantReport = false;
      for (int j = i; j + 1 < argc; ++j)
        argv[j] = argv[j + 1];
      --argc;
      break;
    }
  }
  if (wantReport) report();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
