// 3D broad-phase benchmark: Quack's DynamicTree3 and loose Octree (through BroadPhase3)
// against Bullet's btDbvtBroadphase, on the same workload, in one run.
//
// Workload: N boxes with half-extents uniform in [0.25, 0.5] m whose volumes sum
// to an eighth of a cubic world; each frame the moving ones (100% or a given percentage)
// take a random-walk step of at most 0.05 m in a random direction; W warm-up frames, then F
// timed frames of "update + pairs". Every library drives its own copy of the scene, and the
// libraries take turns frame by frame (the order rotating), so that the frames compared ran
// under about the same load: the machine this was written on is shared. Printed: the median
// ms/frame per repeat and over all frames, and the median over frames of the per-frame
// ratio of the last library's time to each other one's (Bullet's, with the default list).
//
//   broadphase3d_bench [--n 100000] [--moving 100] [--warmup 20] [--frames 50]
//                      [--repeat 5] [--only tree,octree,bullet] [--margin 0.05]
//                      [--scale 1] [--cell 1] [--callgrind]
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
#include <utility>
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
  float cell = 1.0f;  // the octree's smallest cell side, about the fat boxes (0.6 to 1.1 m)
  bool callgrind = false;
  std::vector<std::string> only{"tree", "octree", "bullet"};
};

// One library driving its own copy of the scene: frame(f) steps the scene and runs
// "update + pairs", returning the pair count of that frame.
class Runner {
 public:
  explicit Runner(std::string name) : name_(std::move(name)) {}
  virtual ~Runner() = default;
  Runner(const Runner&) = delete;
  Runner& operator=(const Runner&) = delete;
  const std::string& name() const noexcept { return name_; }
  virtual std::size_t frame(int f) = 0;
  // Proxies re-inserted per frame so far (Quack); 0 where the library does not say.
  virtual double reinsertsPerFrame() const { return 0.0; }
  // Tree height or octree depth; -1 where the library does not say.
  virtual int height() const { return -1; }

 private:
  std::string name_;
};

class QuackRunner final : public Runner {
 public:
  QuackRunner(const Options& o, const Scene& scene, quack::BroadPhase3Kind kind)
      : Runner(quack::toString(kind)), s_(scene), bp_(make(o, kind)), ids_(scene.boxes.size()) {
    for (std::size_t i = 0; i < s_.boxes.size(); ++i)
      ids_[i] = bp_.createProxy(s_.boxes[i], i).value();
    bp_.rebuild();
    bp_.updatePairs(pairs_);
  }
  std::size_t frame(int f) override {
    stepScene(s_, f, [&](std::uint32_t i, Aabb3 b, Vec3 d) {
      // Checked once per frame by a world, not per call.
      const quack::Result<bool> r = bp_.moveProxy(ids_[i], b, d);
      reinserted_ += r.ok() && r.value() ? 1 : 0;
    });
    bp_.updatePairs(pairs_);
    ++frames_;
    return pairs_.size();
  }
  double reinsertsPerFrame() const override {
    return frames_ == 0 ? 0.0 : static_cast<double>(reinserted_) / frames_;
  }
  int height() const override { return bp_.stats().height; }

 private:
  static quack::BroadPhase3 make(const Options& o, quack::BroadPhase3Kind kind) {
    quack::BroadPhase3Config config;
    config.kind = kind;
    config.margin = o.margin;
    config.displacementScale = o.scale;
    config.cellSize = o.cell;
    return quack::BroadPhase3::create(config).value();
  }
  Scene s_;
  quack::BroadPhase3 bp_;
  std::vector<quack::ProxyId> ids_;
  std::vector<quack::ProxyPair> pairs_;
  std::size_t reinserted_ = 0;
  int frames_ = 0;
};

#if defined(QUACK_BENCH_HAS_BULLET)
btVector3 bt(Vec3 v) {
  return {v.x, v.y, v.z};
}

class BulletRunner final : public Runner {
 public:
  BulletRunner(const Options& o, const Scene& scene)
      : Runner("bullet"), s_(scene), dispatcher_(&configuration_), proxies_(scene.boxes.size()) {
    gDbvtMargin = o.margin;
    for (std::size_t i = 0; i < s_.boxes.size(); ++i) {
      proxies_[i] = bp_.createProxy(
          bt(s_.boxes[i].lower), bt(s_.boxes[i].upper), BOX_SHAPE_PROXYTYPE,
          reinterpret_cast<void*>(static_cast<std::uintptr_t>(i)), btBroadphaseProxy::DefaultFilter,
          btBroadphaseProxy::AllFilter, &dispatcher_);
    }
    bp_.optimize();
    bp_.calculateOverlappingPairs(&dispatcher_);
  }
  ~BulletRunner() override {
    for (btBroadphaseProxy* p : proxies_)
      bp_.destroyProxy(p, &dispatcher_);
  }
  std::size_t frame(int f) override {
    stepScene(s_, f, [&](std::uint32_t i, Aabb3 b, Vec3) {
      bp_.setAabb(proxies_[i], bt(b.lower), bt(b.upper), &dispatcher_);
    });
    bp_.calculateOverlappingPairs(&dispatcher_);
    return static_cast<std::size_t>(bp_.getOverlappingPairCache()->getNumOverlappingPairs());
  }

 private:
  Scene s_;
  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase bp_;
  std::vector<btBroadphaseProxy*> proxies_;
};
#endif

std::unique_ptr<Runner> makeRunner(const std::string& name, const Options& o, const Scene& s) {
  if (name == "tree") return std::make_unique<QuackRunner>(o, s, quack::BroadPhase3Kind::tree);
  if (name == "octree") return std::make_unique<QuackRunner>(o, s, quack::BroadPhase3Kind::octree);
#if defined(QUACK_BENCH_HAS_BULLET)
  if (name == "bullet") return std::make_unique<BulletRunner>(o, s);
#endif
  return nullptr;
}

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
    } else if (a == "--cell") {
      o.cell = std::strtof(next(), nullptr);
    } else if (a == "--only") {
      o.only = splitList(next());
    } else if (a == "--callgrind") {
      o.callgrind = true;
    } else {
      std::fprintf(stderr,
                   "usage: broadphase3d_bench [--n N] [--moving PERCENT] [--warmup W] "
                   "[--frames F] [--repeat R] [--margin M] [--scale S] [--cell C] "
                   "[--only tree,octree,bullet] [--callgrind]\n");
      std::exit(2);
    }
  }
  if (o.n == 0 || o.frames <= 0 || o.repeat <= 0 || o.warmup < 0 || !(o.margin >= 0.0f) ||
      !(o.scale >= 0.0f) || !(o.cell >= quack::kMinCellSize)) {
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
      "# %zu boxes in a %.1f m cube, %zu moving; margin %.3f m, Quack stretch %.2f, octree "
      "cell %.2f m; %d warm-up + %d timed frames, %d repeats, libraries interleaved frame by "
      "frame\n",
      o.n, static_cast<double>(scene.side), scene.moving.size(), static_cast<double>(o.margin),
      static_cast<double>(o.scale), static_cast<double>(o.cell), o.warmup, o.frames, o.repeat);
  std::vector<std::string> names;
  for (const std::string& name : o.only) {
    if (name != "tree" && name != "octree" && name != "bullet") {
      std::fprintf(stderr, "unknown library '%s' (tree, octree, bullet)\n", name.c_str());
      return 2;
    }
#if !defined(QUACK_BENCH_HAS_BULLET)
    if (name == "bullet") {
      std::printf("# bullet: not built in (apt-get install libbullet-dev, then reconfigure)\n");
      continue;
    }
#endif
    names.push_back(name);
  }
  if (names.empty()) return 2;
  std::printf("%-8s %6s %10s %12s %12s %10s %7s\n", "library", "repeat", "build ms", "ms/frame",
              "pairs/frame", "reinserts", "height");
  // Per library, every timed frame of every repeat; and per frame, the ratio of the last
  // library's time to each one's (the frames of one index run back to back, so under about
  // the same load: the ratio is steadier than the times on a shared machine).
  std::vector<std::vector<double>> all(names.size());
  std::vector<std::vector<double>> ratios(names.size());
  for (int r = 0; r < o.repeat; ++r) {
    std::vector<std::unique_ptr<Runner>> runners;
    std::vector<double> buildMs;
    for (const std::string& name : names) {
      const auto t0 = Clock::now();
      runners.push_back(makeRunner(name, o, scene));
      buildMs.push_back(msSince(t0));
    }
    for (auto& runner : runners) {
      for (int f = 0; f < o.warmup; ++f)
        runner->frame(f);
    }
    std::vector<std::vector<double>> ms(names.size());
    std::vector<double> pairs(names.size(), 0.0);
    for (int f = 0; f < o.frames; ++f) {
      // Rotate the order each frame, so that no library always runs first or last.
      for (std::size_t j = 0; j < runners.size(); ++j) {
        const std::size_t k = (j + static_cast<std::size_t>(f)) % runners.size();
        if (o.callgrind) QUACK_BENCH_START_COUNT();
        const auto t0 = Clock::now();
        pairs[k] += static_cast<double>(runners[k]->frame(o.warmup + f));
        ms[k].push_back(msSince(t0));
        if (o.callgrind) QUACK_BENCH_STOP_COUNT();
      }
      for (std::size_t k = 0; k < runners.size(); ++k)
        ratios[k].push_back(ms.back().back() / ms[k].back());
    }
    for (std::size_t k = 0; k < runners.size(); ++k) {
      all[k].insert(all[k].end(), ms[k].begin(), ms[k].end());
      std::printf("%-8s %6d %10.1f %12.3f %12.0f %10.0f %7d\n", names[k].c_str(), r, buildMs[k],
                  median(ms[k]), pairs[k] / o.frames, runners[k]->reinsertsPerFrame(),
                  runners[k]->height());
    }
    std::fflush(stdout);
  }
  std::printf("# median ms/frame over all %d x %d timed frames:", o.repeat, o.frames);
  for (std::size_t k = 0; k < names.size(); ++k)
    std::printf(" %s %.3f", names[k].c_str(), median(all[k]));
  std::printf("\n");
  for (std::size_t k = 0; k + 1 < names.size(); ++k) {
    std::printf("# %s / %s, median of the per-frame ratios: %.2fx\n", names.back().c_str(),
                names[k].c_str(), median(ratios[k]));
  }
  return 0;
}
