// 3D broad-phase benchmark: Quack's DynamicTree3 and loose Octree (through BroadPhase3)
// against Bullet's btDbvtBroadphase, on the same workload, in one run.
//
// Workload (issue 32): N boxes with half-extents uniform in [0.25, 0.5] m whose volumes sum
// to an eighth of a cubic world; each frame the moving ones (100% or a given percentage)
// take a random-walk step of at most 0.05 m in a random direction; W warm-up frames, then F
// timed frames of "update + pairs". The whole run is repeated R times (each library in turn
// within a repeat) and the median of the R means is reported, because the machine is shared.
//
//   broadphase3d_bench [--n 100000] [--moving 100] [--warmup 20] [--frames 50]
//                      [--repeat 5] [--only tree,octree,bullet] [--margin 0.05]
//                      [--scale 1] [--callgrind]
//
// Both libraries get the same fat-box margin (--margin, Bullet's gDbvtMargin default
// 0.05 m). Quack also stretches fat boxes by --scale times the displacement (its
// default 1); Bullet's velocity prediction stays off (its default), since moveProxy-style
// displacements are not passed to setAabb.
//
// Pairs, by library (the "pairs" column):
//   Quack: pairs with at least one proxy re-inserted this frame whose fat boxes overlap
//     (Box2D's contract; a world keeps its contacts until their fat boxes part).
//   Bullet: the size of its persistent overlapping-pair cache after the frame (every pair
//     of overlapping fat boxes; calculateOverlappingPairs adds the new ones and removes,
//     10% of the cache a frame, those that parted). The work per frame is comparable: each
//     finds the new pairs of the proxies that left their fat boxes; Bullet also keeps its
//     cache, Quack leaves that to the world.
//
// --callgrind: counts instructions of the timed frames only (run under
//   valgrind --tool=callgrind --instr-atstart=no, with --only naming one library).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "quack/broadphase/broad_phase3.hpp"

#if defined(QUACK_BENCH_HAS_BULLET)
#include <btBulletCollisionCommon.h>
#endif
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define QUACK_BENCH_START_COUNT() CALLGRIND_START_INSTRUMENTATION
#define QUACK_BENCH_STOP_COUNT() CALLGRIND_STOP_INSTRUMENTATION
#else
#define QUACK_BENCH_START_COUNT() ((void)0)
#define QUACK_BENCH_STOP_COUNT() ((void)0)
#endif

namespace {

using quack::Aabb3;
using quack::Vec3;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct Scene {
  std::vector<Aabb3> boxes;           // current tight boxes
  std::vector<std::uint32_t> moving;  // indices that move
  std::vector<Vec3> steps;            // a pool of random-walk steps (power-of-two size)
  float side = 0.0f;
};

Scene makeScene(std::size_t n, int movingPercent, std::uint32_t seed) {
  Scene s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> half(0.25f, 0.5f);
  std::vector<Vec3> halves(n);
  double volume = 0.0;
  for (Vec3& h : halves) {
    h = {half(rng), half(rng), half(rng)};
    volume += 8.0 * static_cast<double>(h.x) * static_cast<double>(h.y) * static_cast<double>(h.z);
  }
  s.side = static_cast<float>(std::cbrt(8.0 * volume));
  std::uniform_real_distribution<float> pos(0.0f, s.side);
  s.boxes.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 c{pos(rng), pos(rng), pos(rng)};
    s.boxes[i] = {c - halves[i], c + halves[i]};
  }
  const std::size_t every =
      movingPercent >= 100 ? 1 : static_cast<std::size_t>(100 / std::max(movingPercent, 1));
  for (std::size_t i = 0; i < n; i += every)
    s.moving.push_back(static_cast<std::uint32_t>(i));
  // Directions uniform on the sphere (normalised Gaussians), lengths uniform in [0, 0.05].
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  std::uniform_real_distribution<float> len(0.0f, 0.05f);
  s.steps.resize(1 << 16);
  for (Vec3& d : s.steps) {
    Vec3 dir{};
    while (quack::lengthSquared(dir) < 1e-6f)
      dir = {gauss(rng), gauss(rng), gauss(rng)};
    d = len(rng) * quack::normalize(dir);
  }
  return s;
}

// Applies frame f's steps to the moving boxes and calls move(i, box, d) for each.
template <class Move>
void stepScene(Scene& s, int frame, Move&& move) {
  const std::size_t mask = s.steps.size() - 1;
  const std::size_t offset = static_cast<std::size_t>(frame) * 7919u;
  for (std::uint32_t i : s.moving) {
    const Vec3 d = s.steps[(i * 2654435761u + offset) & mask];
    Aabb3& b = s.boxes[i];
    b.lower += d;
    b.upper += d;
    move(i, b, d);
  }
}

struct Options {
  std::size_t n = 100000;
  int moving = 100;
  int warmup = 20;
  int frames = 50;
  int repeat = 5;
  float margin = 0.05f;
  float scale = 1.0f;
  bool callgrind = false;
  std::vector<std::string> only{"tree", "octree", "bullet"};
};

struct Measure {
  double buildMs = 0;
  double frameMs = 0;  // mean over the timed frames
  double pairs = 0;    // mean per timed frame
  double extra = 0;    // Quack: re-insertions per frame; Bullet: 0
  int height = 0;
};

template <class Frame>
void timeFrames(const Options& o, Measure& m, Frame&& frame) {
  for (int f = 0; f < o.warmup; ++f)
    frame(f);
  double pairs = 0.0;
  if (o.callgrind) QUACK_BENCH_START_COUNT();
  const auto t0 = Clock::now();
  for (int f = 0; f < o.frames; ++f)
    pairs += static_cast<double>(frame(o.warmup + f));
  const double ms = msSince(t0);
  if (o.callgrind) QUACK_BENCH_STOP_COUNT();
  m.frameMs = ms / o.frames;
  m.pairs = pairs / o.frames;
}

Measure runQuack(const Options& o, Scene s, quack::BroadPhase3Kind kind) {
  Measure m;
  quack::BroadPhase3Config config;
  config.kind = kind;
  config.margin = o.margin;
  config.displacementScale = o.scale;
  config.cellSize = 1.0f;  // about the fat boxes (0.55 to 1.1 m)
  quack::BroadPhase3 bp = quack::BroadPhase3::create(config).value();
  std::vector<quack::ProxyId> ids(s.boxes.size());
  const auto t0 = Clock::now();
  for (std::size_t i = 0; i < s.boxes.size(); ++i)
    ids[i] = bp.createProxy(s.boxes[i], i).value();
  bp.rebuild();
  std::vector<quack::ProxyPair> pairs;
  bp.updatePairs(pairs);
  m.buildMs = msSince(t0);
  std::size_t reinserted = 0;
  timeFrames(o, m, [&](int f) {
    stepScene(s, f, [&](std::uint32_t i, Aabb3 b, Vec3 d) {
      // Checked once per frame by a world, not per call.
      const quack::Result<bool> r = bp.moveProxy(ids[i], b, d);
      reinserted += r.ok() && r.value() ? 1 : 0;
    });
    bp.updatePairs(pairs);
    return pairs.size();
  });
  m.extra = static_cast<double>(reinserted) / (o.warmup + o.frames);
  m.height = bp.stats().height;
  return m;
}

#if defined(QUACK_BENCH_HAS_BULLET)
btVector3 bt(Vec3 v) {
  return {v.x, v.y, v.z};
}

Measure runBullet(const Options& o, Scene s) {
  Measure m;
  gDbvtMargin = o.margin;
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  auto bp = std::make_unique<btDbvtBroadphase>();
  std::vector<btBroadphaseProxy*> proxies(s.boxes.size());
  const auto t0 = Clock::now();
  for (std::size_t i = 0; i < s.boxes.size(); ++i) {
    proxies[i] = bp->createProxy(bt(s.boxes[i].lower), bt(s.boxes[i].upper), BOX_SHAPE_PROXYTYPE,
                                 reinterpret_cast<void*>(static_cast<std::uintptr_t>(i)),
                                 btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter,
                                 &dispatcher);
  }
  bp->optimize();
  bp->calculateOverlappingPairs(&dispatcher);
  m.buildMs = msSince(t0);
  timeFrames(o, m, [&](int f) {
    stepScene(s, f, [&](std::uint32_t i, Aabb3 b, Vec3) {
      bp->setAabb(proxies[i], bt(b.lower), bt(b.upper), &dispatcher);
    });
    bp->calculateOverlappingPairs(&dispatcher);
    return static_cast<std::size_t>(bp->getOverlappingPairCache()->getNumOverlappingPairs());
  });
  m.height = -1;
  for (btBroadphaseProxy* p : proxies)
    bp->destroyProxy(p, &dispatcher);
  return m;
}
#endif

std::vector<std::string> splitList(const char* s) {
  std::vector<std::string> out;
  std::string cur;
  for (const char* c = s; *c != '\0'; ++c) {
    if (*c == ',') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += *c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--n") {
      o.n = std::strtoull(next(), nullptr, 10);
    } else if (a == "--moving") {
      o.moving = std::atoi(next());
    } else if (a == "--warmup") {
      o.warmup = std::atoi(next());
    } else if (a == "--frames") {
      o.frames = std::atoi(next());
    } else if (a == "--repeat") {
      o.repeat = std::atoi(next());
    } else if (a == "--margin") {
      o.margin = std::strtof(next(), nullptr);
    } else if (a == "--scale") {
      o.scale = std::strtof(next(), nullptr);
    } else if (a == "--only") {
      o.only = splitList(next());
    } else if (a == "--callgrind") {
      o.callgrind = true;
    } else {
      std::fprintf(stderr,
                   "usage: broadphase3d_bench [--n N] [--moving PERCENT] [--warmup W] "
                   "[--frames F] [--repeat R] [--margin M] [--scale S] "
                   "[--only tree,octree,bullet] [--callgrind]\n");
      std::exit(2);
    }
  }
  if (o.n == 0 || o.frames <= 0 || o.repeat <= 0 || o.warmup < 0 || !(o.margin >= 0.0f) ||
      !(o.scale >= 0.0f)) {
    std::fprintf(stderr, "bad option value\n");
    std::exit(2);
  }
  return o;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 == 1 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const Scene scene = makeScene(o.n, o.moving, 12345u);
  std::printf(
      "# %zu boxes in a %.1f m cube, %zu moving; margin %.3f m, Quack stretch %.2f; "
      "%d warm-up + %d timed frames, %d repeats\n",
      o.n, static_cast<double>(scene.side), scene.moving.size(), static_cast<double>(o.margin),
      static_cast<double>(o.scale), o.warmup, o.frames, o.repeat);
  std::printf("%-8s %6s %10s %12s %12s %10s %7s\n", "library", "repeat", "build ms", "ms/frame",
              "pairs/frame", "reinserts", "height");
  std::vector<std::string> names;
  std::vector<std::vector<double>> times;
  for (const std::string& name : o.only) {
#if !defined(QUACK_BENCH_HAS_BULLET)
    if (name == "bullet") {
      std::printf("# bullet: not built in (apt-get install libbullet-dev, then reconfigure)\n");
      continue;
    }
#endif
    if (name != "tree" && name != "octree" && name != "bullet") {
      std::fprintf(stderr, "unknown library '%s' (tree, octree, bullet)\n", name.c_str());
      return 2;
    }
    names.push_back(name);
    times.emplace_back();
  }
  for (int r = 0; r < o.repeat; ++r) {
    for (std::size_t k = 0; k < names.size(); ++k) {
      const std::string& name = names[k];
      Measure m;
      if (name == "tree") {
        m = runQuack(o, scene, quack::BroadPhase3Kind::tree);
      } else if (name == "octree") {
        m = runQuack(o, scene, quack::BroadPhase3Kind::octree);
      }
#if defined(QUACK_BENCH_HAS_BULLET)
      else {
        m = runBullet(o, scene);
      }
#endif
      times[k].push_back(m.frameMs);
      std::printf("%-8s %6d %10.1f %12.3f %12.0f %10.0f %7d\n", name.c_str(), r, m.buildMs,
                  m.frameMs, m.pairs, m.extra, m.height);
      std::fflush(stdout);
    }
  }
  std::printf("# median ms/frame over %d repeats:", o.repeat);
  for (std::size_t k = 0; k < names.size(); ++k)
    std::printf(" %s %.3f", names[k].c_str(), median(times[k]));
  std::printf("\n");
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (names[k] == "bullet") {
      for (std::size_t j = 0; j < names.size(); ++j) {
        if (j != k) {
          std::printf("# bullet / %s: %.2fx\n", names[j].c_str(),
                      median(times[k]) / median(times[j]));
        }
      }
    }
  }
  return 0;
}
