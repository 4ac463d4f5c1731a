// Queries as a game makes them: every query builds its two transforms from the
// bodies' angles inside the timed loop, then asks the kernel. Quack beside Box2D 2.4.1
// (Debian libbox2d-dev, QUACK_HAVE_BOX2D) and Box2D v3 (QUACK_BOX2D_V3_DIR,
// QUACK_HAVE_BOX2D_V3) on the same queries in the same run. docs/narrow-phase.md,
// "Queries from angles", has the sets, the commands and the figures.
//
// Sets, fixed seeds: a pool of 4,096 random 8-gons of size about 1 (sharp: radius zero in
// every library) and 200,000 queries that each pick two of them and two poses:
// - mixed: half apart, half overlapping (GJK distance);
// - separated: all apart (GJK distance);
// - overlapping: all overlapping (contact manifold);
// - sweeps: B crosses 3 to 8 m towards A turning up to 1 rad, A drifts (time of impact).
// Apart and overlapping are decided by Quack's distance when the set is made.
//
// A benchmark iteration is a batch of 1,000 consecutive queries (the next 1,000 each time,
// cycling through the 200,000); the `query` counter is the time per query.
//
// Before timing, a sample of every set is answered by every library and compared; the
// benchmark prints the disagreement and aborts when it passes the tolerance.
//
// Instruction counts: `query_bench --count KERNEL N` answers the first N queries of one
// kernel once and exits; run it under callgrind with --toggle-collect='*Batch*' so that
// only the timed loop counts (kernels: quack_gjk_mixed, box2d_gjk_separated,
// box2d_v3_manifold, quack_toi, ...; `--count list` names them).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "quack/collision/gjk.hpp"
#include "quack/collision/manifold.hpp"
#include "quack/collision/toi.hpp"
#include "query_sets.hpp"
#include "support/random_shapes.hpp"

#if QUACK_HAVE_BOX2D
#include <box2d/b2_collision.h>
#include <box2d/b2_distance.h>
#include <box2d/b2_polygon_shape.h>
#include <box2d/b2_time_of_impact.h>
#endif
#if QUACK_HAVE_BOX2D_V3
#include "box2d_v3_peer.hpp"
#endif

namespace {

using namespace quack;
using quack_bench::PoolPolygon;
using quack_bench::Pose;
using quack_bench::QueryPair;
using quack_bench::QuerySweep;

constexpr std::size_t kPoolSize = 4096;
constexpr std::size_t kQueries = 200000;
constexpr std::size_t kBatch = 1000;

// ---- The pool, in each library's form ------------------------------------------------

struct Pool {
  std::vector<Polygon> quack;
  std::vector<PoolPolygon> plain;
#if QUACK_HAVE_BOX2D
  std::vector<b2PolygonShape> box2d;
#endif
};

// Box2D v3's hull welds vertices closer than 4 slops (2 cm) and drops a vertex within 2
// slops (1 cm) of the line through its neighbours; 2.4.1 welds at half a slop. Polygons
// with room to spare on both counts are kept whatever peers are built, so the pool (and
// every set) is the same in every build.
bool clearOfEveryHullTolerance(const Polygon& p) {
  for (int i = 0; i < p.count; ++i) {
    const Vec2 prev = p.vertices[(i + p.count - 1) % p.count];
    const Vec2 v = p.vertices[i];
    const Vec2 next = p.vertices[(i + 1) % p.count];
    if (length(v - prev) < 0.03f) return false;
    const Vec2 chord = next - prev;
    if (cross(chord, v - prev) * cross(chord, v - prev) < 0.015f * 0.015f * dot(chord, chord))
      return false;
  }
  return true;
}

Pool makePool() {
  std::mt19937 rng(3101u);
  Pool pool;
  while (pool.quack.size() < kPoolSize) {
    Polygon p = testing::randomPolygon(rng, 8, 1.0f);
    if (!clearOfEveryHullTolerance(p)) continue;
    PoolPolygon plain;
    plain.count = p.count;
    for (int i = 0; i < p.count; ++i) {
      plain.x[i] = p.vertices[i].x;
      plain.y[i] = p.vertices[i].y;
    }
#if QUACK_HAVE_BOX2D
    b2Vec2 v[8];
    for (int i = 0; i < p.count; ++i)
      v[i].Set(plain.x[i], plain.y[i]);
    b2PolygonShape shape;
    shape.Set(v, p.count);
    // Box2D pads polygons with a skin (b2_polygonRadius); Quack's are sharp.
    shape.m_radius = 0.0f;
    if (shape.m_count != p.count) {
      std::fprintf(stderr, "query_bench: Box2D 2.4.1 welded a pool polygon\n");
      std::abort();
    }
    pool.box2d.push_back(shape);
#endif
    pool.quack.push_back(p);
    pool.plain.push_back(plain);
  }
  return pool;
}

const Pool& thePool() {
  static const Pool pool = [] {
    Pool p = makePool();
#if QUACK_HAVE_BOX2D_V3
    if (!quack_bench::v3::setPool(p.plain.data(), p.plain.size())) {
      std::fprintf(stderr, "query_bench: Box2D v3 welded a pool polygon\n");
      std::abort();
    }
#endif
    return p;
  }();
  return pool;
}

// ---- The query sets ------------------------------------------------------------------

Transform transformOf(const Pose& pose) {
  return makeTransform({pose.x, pose.y}, pose.angle);
}

enum class Placement { apart, overlapping, mixed };

std::vector<QueryPair> makePairs(Placement placement, unsigned seed) {
  const Pool& pool = thePool();
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::uint32_t> pick(0, kPoolSize - 1);
  std::vector<QueryPair> pairs;
  pairs.reserve(kQueries);
  // Mixed: apart and overlapping in turn, each drawn until it is what it should be
  // (drawing the kind per attempt would favour the kind rejected less often), then shuffled.
  while (pairs.size() < kQueries) {
    const bool overlap = placement == Placement::overlapping ||
                         (placement == Placement::mixed && pairs.size() % 2 == 1);
    QueryPair q;
    q.a = pick(rng);
    q.b = pick(rng);
    q.pa = {testing::uniform(rng, -5, 5), testing::uniform(rng, -5, 5),
            testing::uniform(rng, -kPi, kPi)};
    const float heading = testing::uniform(rng, -kPi, kPi);
    const float reach =
        overlap ? testing::uniform(rng, 0.0f, 0.8f) : testing::uniform(rng, 0.3f, 3.0f);
    q.pb = {q.pa.x + reach * std::cos(heading), q.pa.y + reach * std::sin(heading),
            testing::uniform(rng, -kPi, kPi)};
    const float d = computeDistance(makeProxy(pool.quack[q.a]), transformOf(q.pa),
                                    makeProxy(pool.quack[q.b]), transformOf(q.pb))
                        .distance;
    // Apart means clearly apart (a centimetre or more), so that no library's tolerance
    // decides which side a pair is on.
    if (overlap ? d > 0.0f : d < 0.01f) continue;
    pairs.push_back(q);
  }
  if (placement == Placement::mixed) std::shuffle(pairs.begin(), pairs.end(), rng);
  return pairs;
}

std::vector<QuerySweep> makeSweeps() {
  (void)thePool();  // Box2D v3's copy of the pool too
  std::mt19937 rng(3104u);
  std::uniform_int_distribution<std::uint32_t> pick(0, kPoolSize - 1);
  std::vector<QuerySweep> sweeps(kQueries);
  for (QuerySweep& s : sweeps) {
    s.a = pick(rng);
    s.b = pick(rng);
    s.a1 = {testing::uniform(rng, -0.5f, 0.5f), testing::uniform(rng, -0.5f, 0.5f), 0.0f};
    s.a2 = {s.a1.x + testing::uniform(rng, -0.3f, 0.3f), s.a1.y,
            testing::uniform(rng, -0.5f, 0.5f)};
    s.b1 = {testing::uniform(rng, -6.0f, -2.5f), testing::uniform(rng, -2.0f, 2.0f),
            testing::uniform(rng, -kPi, kPi)};
    s.b2 = {s.b1.x + testing::uniform(rng, 3.0f, 8.0f), s.b1.y + testing::uniform(rng, -2, 2),
            s.b1.angle + testing::uniform(rng, -1.0f, 1.0f)};
  }
  return sweeps;
}

const std::vector<QueryPair>& mixedSet() {
  static const std::vector<QueryPair> s = makePairs(Placement::mixed, 3102u);
  return s;
}
const std::vector<QueryPair>& separatedSet() {
  static const std::vector<QueryPair> s = makePairs(Placement::apart, 3103u);
  return s;
}
const std::vector<QueryPair>& overlappingSet() {
  static const std::vector<QueryPair> s = makePairs(Placement::overlapping, 3105u);
  return s;
}
const std::vector<QuerySweep>& sweepSet() {
  static const std::vector<QuerySweep> s = makeSweeps();
  return s;
}

// ---- The timed loops, one per library and kernel ---------------------------------------

Sweep sweepOf(const Pose& p1, const Pose& p2) {
  return {{}, {p1.x, p1.y}, {p2.x, p2.y}, p1.angle, p2.angle};
}

[[gnu::noinline]] float quackDistanceBatch(const QueryPair* pairs, std::size_t count) {
  const Polygon* shapes = thePool().quack.data();
  float sum = 0.0f;
  for (std::size_t i = 0; i < count; ++i) {
    const QueryPair& q = pairs[i];
    sum += computeDistance(makeProxy(shapes[q.a]), transformOf(q.pa), makeProxy(shapes[q.b]),
                           transformOf(q.pb))
               .distance;
  }
  return sum;
}

[[gnu::noinline]] float quackManifoldBatch(const QueryPair* pairs, std::size_t count) {
  const Polygon* shapes = thePool().quack.data();
  float sum = 0.0f;
  for (std::size_t i = 0; i < count; ++i) {
    const QueryPair& q = pairs[i];
    // Quack's default speculative distance (4 slops), the same as v3's; 2.4.1 keeps only
    // overlapping points with the skin zeroed. Every pair of this set overlaps.
    const Manifold m =
        collidePolygons(shapes[q.a], transformOf(q.pa), shapes[q.b], transformOf(q.pb));
    sum += m.normal.x + static_cast<float>(m.pointCount);
  }
  return sum;
}

[[gnu::noinline]] float quackToiBatch(const QuerySweep* sweeps, std::size_t count) {
  const Polygon* shapes = thePool().quack.data();
  float sum = 0.0f;
  for (std::size_t i = 0; i < count; ++i) {
    const QuerySweep& s = sweeps[i];
    sum += computeToi(makeProxy(shapes[s.a]), sweepOf(s.a1, s.a2), makeProxy(shapes[s.b]),
                      sweepOf(s.b1, s.b2))
               .t;
  }
  return sum;
}

#if QUACK_HAVE_BOX2D
b2Transform box2dTransformOf(const Pose& pose) {
  b2Transform xf;
  xf.Set(b2Vec2(pose.x, pose.y), pose.angle);
  return xf;
}

b2DistanceOutput box2dDistance(const QueryPair& q) {
  const b2PolygonShape* shapes = thePool().box2d.data();
  b2DistanceInput input;
  input.proxyA.Set(&shapes[q.a], 0);
  input.proxyB.Set(&shapes[q.b], 0);
  input.transformA = box2dTransformOf(q.pa);
  input.transformB = box2dTransformOf(q.pb);
  input.useRadii = true;
  b2SimplexCache cache;
  cache.count = 0;
  b2DistanceOutput out;
  b2Distance(&out, &cache, &input);
  return out;
}

b2Manifold box2dManifold(const QueryPair& q, b2Transform* xfA, b2Transform* xfB) {
  const b2PolygonShape* shapes = thePool().box2d.data();
  *xfA = box2dTransformOf(q.pa);
  *xfB = box2dTransformOf(q.pb);
  b2Manifold m;
  b2CollidePolygons(&m, &shapes[q.a], *xfA, &shapes[q.b], *xfB);
  return m;
}

b2Sweep box2dSweepOf(const Pose& p1, const Pose& p2) {
  b2Sweep s;
  s.localCenter.SetZero();
  s.c0.Set(p1.x, p1.y);
  s.c.Set(p2.x, p2.y);
  s.a0 = p1.angle;
  s.a = p2.angle;
  s.alpha0 = 0.0f;
  return s;
}

b2TOIOutput box2dToi(const QuerySweep& s) {
  const b2PolygonShape* shapes = thePool().box2d.data();
  b2TOIInput input;
  input.proxyA.Set(&shapes[s.a], 0);
  input.proxyB.Set(&shapes[s.b], 0);
  input.sweepA = box2dSweepOf(s.a1, s.a2);
  input.sweepB = box2dSweepOf(s.b1, s.b2);
  input.tMax = 1.0f;
  b2TOIOutput out;
  b2TimeOfImpact(&out, &input);
  return out;
}

[[gnu::noinline]] float box2dDistanceBatch(const QueryPair* pairs, std::size_t count) {
  float sum = 0.0f;
  for (std::size_t i = 0; i < count; ++i)
    sum += box2dDistance(pairs[i]).distance;
  return sum;
}

[[gnu::noinline]] float box2dManifoldBatch(const QueryPair* pairs, std::size_t count) {
  float sum = 0.0f;
  for (std::size_t i = 0; i < count; ++i) {
    b2Transform xfA, xfB;
    const b2Manifold m = box2dManifold(pairs[i], &xfA, &xfB);
    sum += m.localNormal.x + static_cast<float>(m.pointCount);
  }
  return sum;
}

[[gnu::noinline]] float box2dToiBatch(const QuerySweep* sweeps, std::size_t count) {
  float sum = 0.0f;
  for (std::size_t i = 0; i < count; ++i)
    sum += box2dToi(sweeps[i]).t;
  return sum;
}
#endif

// ---- Agreement ------------------------------------------------------------------------

// Quack's answers for the agreement check. `rotationOf` builds each rotation: Quack's own
// (Rot::fromAngle) when compared with 2.4.1 (whose b2Rot::Set calls the C library's sinf and
// cosf, within an ulp of Quack's), Box2D v3's when compared with v3, whose b2MakeRot is an
// approximation about 1e-3 rad off (see the message printed for the exact rotations).
using RotationOf = Rot (*)(float radians);

Rot quackRotation(float radians) {
  return Rot::fromAngle(radians);
}

Transform transformOf(const Pose& pose, RotationOf rotationOf) {
  return {{pose.x, pose.y}, rotationOf(pose.angle)};
}

float quackDistance(const QueryPair& q, RotationOf rotationOf) {
  const Pool& pool = thePool();
  return computeDistance(makeProxy(pool.quack[q.a]), transformOf(q.pa, rotationOf),
                         makeProxy(pool.quack[q.b]), transformOf(q.pb, rotationOf))
      .distance;
}

float quackManifoldSeparation(const QueryPair& q, RotationOf rotationOf, float speculative,
                              int* pointCount) {
  const Pool& pool = thePool();
  const Manifold m = collidePolygons(pool.quack[q.a], transformOf(q.pa, rotationOf),
                                     pool.quack[q.b], transformOf(q.pb, rotationOf), speculative);
  *pointCount = m.pointCount;
  float deepest = std::numeric_limits<float>::infinity();
  for (int i = 0; i < m.pointCount; ++i)
    deepest = std::min(deepest, m.points[i].separation);
  return deepest;
}

float quackToi(const QuerySweep& s, bool* hit) {
  const Pool& pool = thePool();
  const ToiOutput out = computeToi(makeProxy(pool.quack[s.a]), sweepOf(s.a1, s.a2),
                                   makeProxy(pool.quack[s.b]), sweepOf(s.b1, s.b2));
  *hit = out.status == ToiStatus::hit;
  return out.t;
}

struct Disagreement {
  const char* what;
  int compared = 0;
  int counted = 0;  // answers of a different kind (point counts, hit or not)
  double largest = 0.0;
};

void print(const char* peer, const Disagreement& d) {
  std::printf(
      "query_bench: %-9s %-32s %5d compared, largest |difference| %.2e, %d differ in "
      "kind\n",
      peer, d.what, d.compared, d.largest, d.counted);
}

template <class F>
void sample(F f) {
  for (std::size_t i = 0; i < kQueries; i += 50)
    f(i);
}

struct Peer {
  const char* name;
  RotationOf rotationOf;      // the rotation the peer builds from an angle
  float speculativeDistance;  // how far apart the peer's manifolds keep points
  std::function<float(const QueryPair&)> distance;
  std::function<float(const QueryPair&, int*)> manifoldSeparation;
  std::function<float(const QuerySweep&, bool*)> timeOfImpact;
};

// Every 50th query of each set (4,000 a set), Quack asked at the peer's rotations.
// Distances within 1e-5 m (coordinates up to 10 m: float carries 1e-6 there). Manifolds:
// the deepest point's separation within 1e-3 m where the point counts agree, and the counts
// differ on at most 5% of pairs: v3 keeps A's face unless B's separates by 0.1 slop (5e-4 m)
// more, Quack takes the larger (A's on a tie), so near-ties choose different reference
// faces, whose normals differ slightly and whose clipped points may be one or two. Time of
// impact: hit or not differs on at most 2%; the largest difference of the fraction where
// both hit is printed, not checked (each library stops somewhere in its tolerance band,
// and v3 turns its sweep by normalised linear interpolation of the rotation, Quack and
// 2.4.1 by the angle).
bool agrees(const Peer& peer) {
  bool ok = true;
  for (const auto* set : {&mixedSet(), &separatedSet()}) {
    const bool mixed = set == &mixedSet();
    Disagreement d{mixed ? "distance, mixed" : "distance, separated"};
    Disagreement exact{mixed ? "distance, mixed, exact angles"
                             : "distance, separated, exact angles"};
    sample([&](std::size_t i) {
      const QueryPair& q = (*set)[i];
      const double p = double(peer.distance(q));
      d.largest = std::max(d.largest, std::fabs(double(quackDistance(q, peer.rotationOf)) - p));
      exact.largest =
          std::max(exact.largest, std::fabs(double(quackDistance(q, quackRotation)) - p));
      ++d.compared;
      ++exact.compared;
    });
    print(peer.name, d);
    if (peer.rotationOf != quackRotation) print(peer.name, exact);
    ok = ok && d.largest <= 1e-5;
  }
  Disagreement m{"manifold, deepest point"};
  sample([&](std::size_t i) {
    const QueryPair& q = overlappingSet()[i];
    int nq = 0, np = 0;
    const float sq = quackManifoldSeparation(q, peer.rotationOf, peer.speculativeDistance, &nq);
    const float sp = peer.manifoldSeparation(q, &np);
    ++m.compared;
    if (nq != np || nq == 0) {
      ++m.counted;
      return;
    }
    m.largest = std::max(m.largest, std::fabs(double(sq) - double(sp)));
  });
  print(peer.name, m);
  ok = ok && m.largest <= 1e-3 && m.counted * 20 <= m.compared;
  Disagreement t{"time of impact (fraction)"};
  sample([&](std::size_t i) {
    const QuerySweep& s = sweepSet()[i];
    bool hq = false, hp = false;
    const float tq = quackToi(s, &hq), tp = peer.timeOfImpact(s, &hp);
    ++t.compared;
    if (hq != hp) {
      ++t.counted;
      return;
    }
    if (hq) t.largest = std::max(t.largest, std::fabs(double(tq) - double(tp)));
  });
  print(peer.name, t);
  return ok && t.counted * 50 <= t.compared;
}

void checkAgreement() {
  std::vector<Peer> peers;
#if QUACK_HAVE_BOX2D
  peers.push_back({"box2d", quackRotation, 0.0f,
                   [](const QueryPair& q) { return box2dDistance(q).distance; },
                   [](const QueryPair& q, int* n) {
                     b2Transform xfA, xfB;
                     const b2Manifold m = box2dManifold(q, &xfA, &xfB);
                     b2WorldManifold wm;
                     wm.Initialize(&m, xfA, 0.0f, xfB, 0.0f);
                     *n = m.pointCount;
                     float deepest = std::numeric_limits<float>::infinity();
                     for (int i = 0; i < m.pointCount; ++i)
                       deepest = std::min(deepest, wm.separations[i]);
                     return deepest;
                   },
                   [](const QuerySweep& s, bool* hit) {
                     const b2TOIOutput out = box2dToi(s);
                     *hit = out.state == b2TOIOutput::e_touching;
                     return out.t;
                   }});
#endif
#if QUACK_HAVE_BOX2D_V3
  peers.push_back({"box2d_v3",
                   [](float radians) {
                     Rot q;
                     quack_bench::v3::rotation(radians, &q.c, &q.s);
                     return q;
                   },
                   // v3's b2CollidePolygons keeps points up to its speculative distance, 4
                   // slops, as Quack's default does.
                   kSpeculativeDistance, quack_bench::v3::distance,
                   quack_bench::v3::manifoldSeparation, quack_bench::v3::timeOfImpact});
#endif
  bool ok = true;
  for (const Peer& peer : peers)
    ok = agrees(peer) && ok;
  if (!ok) {
    std::fflush(stdout);
    std::fprintf(stderr,
                 "query_bench: the libraries disagree beyond the tolerance (above); "
                 "they are not answering the same question\n");
    std::abort();
  }
}

// ---- Kernels by name ------------------------------------------------------------------

struct Kernel {
  std::string name;
  std::function<float(std::size_t begin, std::size_t count)> run;
};

template <class Set, class Batch>
Kernel kernel(std::string name, const Set& (*set)(), Batch batch) {
  return {std::move(name), [set, batch](std::size_t begin, std::size_t count) {
            return batch(set().data() + begin, count);
          }};
}

std::vector<Kernel> kernels() {
  std::vector<Kernel> k;
  auto add = [&](const std::string& lib, auto distance, auto manifold, auto toi) {
    k.push_back(kernel(lib + "_gjk_mixed", &mixedSet, distance));
    k.push_back(kernel(lib + "_gjk_separated", &separatedSet, distance));
    k.push_back(kernel(lib + "_manifold", &overlappingSet, manifold));
    k.push_back(kernel(lib + "_toi", &sweepSet, toi));
  };
  add("quack", quackDistanceBatch, quackManifoldBatch, quackToiBatch);
#if QUACK_HAVE_BOX2D
  add("box2d", box2dDistanceBatch, box2dManifoldBatch, box2dToiBatch);
#endif
#if QUACK_HAVE_BOX2D_V3
  add("box2d_v3", quack_bench::v3::distanceBatch, quack_bench::v3::manifoldBatch,
      quack_bench::v3::toiBatch);
#endif
  return k;
}

void runBatches(benchmark::State& state, const Kernel& k) {
  std::size_t begin = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(k.run(begin, kBatch));
    begin = (begin + kBatch) % kQueries;
  }
  state.counters["query"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(kBatch),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// `--count NAME N`: answer queries [0, N) of one kernel once, for callgrind.
int countMode(const char* name, const char* n) {
  std::vector<Kernel> all = kernels();
  for (const Kernel& k : all) {
    if (std::strcmp(name, "list") == 0) {
      std::printf("%s\n", k.name.c_str());
    } else if (k.name == name) {
      const std::size_t count = std::min<std::size_t>(std::strtoul(n, nullptr, 10), kQueries);
      // Make the pool and the set first: both are built lazily, and must not be counted.
      (void)thePool();
      k.run(0, 0);
      const float sum = k.run(0, count);
      std::printf("%s: %zu queries, checksum %g\n", k.name.c_str(), count, double(sum));
      return 0;
    }
  }
  if (std::strcmp(name, "list") == 0) return 0;
  std::fprintf(stderr, "query_bench: no kernel %s (--count list)\n", name);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::strcmp(argv[1], "--count") == 0) {
    if (argc < 3) return 2;
    return countMode(argv[2], argc >= 4 ? argv[3] : "20000");
  }
  // Every set before any timing (they are built lazily).
  (void)mixedSet();
  (void)separatedSet();
  (void)overlappingSet();
  (void)sweepSet();
  checkAgreement();
  for (const Kernel& k : kernels())
    benchmark::RegisterBenchmark(k.name.c_str(), [k](benchmark::State& s) { runBatches(s, k); });
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
