// Broad-phase benchmark: Quack's five structures and the peers (Box2D 2.4.1's b2BroadPhase,
// Chipmunk 7's bounding-box tree and spatial hash) on the same workload, in one run.
//
// Workload: N boxes with half-extents uniform in [0.25, 0.5] m whose areas sum to
// a quarter of a square world; each frame the moving ones (100% or 5%) take a random-walk
// step of at most 0.05 m; W warm-up frames, then F timed frames of "update + pairs". Then
// closest-hit ray casts (random origins in the world, random directions, 20 m long).
//
//   broadphase_bench [--n 1000,10000,100000,1000000] [--moving 100,5]
//                    [--only tree,quadtree,sap,hash,brute,tree-tight,box2d,cp-bbtree,cp-hash]
//                    [--warmup 60] [--frames 100] [--rays 20000] [--csv FILE]
//
// Pairs reported per frame, by library (the "pairs" column):
//   Quack (all five) and Box2D: pairs with at least one proxy re-inserted this frame whose
//     fat boxes overlap (Box2D's contract; existing contacts are kept by the world).
//   Chipmunk (both): every overlapping pair of fat boxes, every frame (its contact cache
//     is driven by seeing each pair each step). More pairs, by design: compare times with
//     that in mind.

#include <malloc.h>

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

#include "quack/broadphase/broad_phase.hpp"

#if defined(QUACK_BENCH_HAS_BOX2D)
#include <box2d/b2_broad_phase.h>
#endif
#if defined(QUACK_BENCH_HAS_CHIPMUNK)
#include <chipmunk/chipmunk.h>
#endif

namespace {

using quack::Aabb;
using quack::Vec2;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// In-use heap bytes: small blocks plus mmap-ed large ones (big arrays live there).
std::size_t heapBytes() {
  const struct mallinfo2 mi = mallinfo2();
  return mi.uordblks + mi.hblkhd;
}

// The scene every library runs.
struct Scene {
  std::vector<Aabb> boxes;            // current tight boxes
  std::vector<std::uint32_t> moving;  // indices that move
  std::vector<Vec2> steps;            // a pool of random-walk steps (power-of-two size)
  std::vector<Vec2> lastStep;         // per box, the displacement of the last frame
  float side = 0.0f;
};

Scene makeScene(std::size_t n, int movingPercent, std::uint32_t seed) {
  Scene s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> half(0.25f, 0.5f);
  std::vector<Vec2> halves(n);
  double area = 0.0;
  for (Vec2& h : halves) {
    h = {half(rng), half(rng)};
    area += 4.0 * static_cast<double>(h.x) * static_cast<double>(h.y);
  }
  s.side = static_cast<float>(std::sqrt(4.0 * area));
  std::uniform_real_distribution<float> pos(0.0f, s.side);
  s.boxes.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 c{pos(rng), pos(rng)};
    s.boxes[i] = {c - halves[i], c + halves[i]};
  }
  const std::size_t every =
      movingPercent >= 100 ? 1 : static_cast<std::size_t>(100 / movingPercent);
  for (std::size_t i = 0; i < n; i += every)
    s.moving.push_back(static_cast<std::uint32_t>(i));
  std::uniform_real_distribution<float> angle(0.0f, 2.0f * quack::kPi);
  std::uniform_real_distribution<float> len(0.0f, 0.05f);
  s.steps.resize(1 << 16);
  for (Vec2& d : s.steps) {
    const float a = angle(rng);
    const float l = len(rng);
    d = {l * std::cos(a), l * std::sin(a)};
  }
  s.lastStep.assign(n, Vec2{});
  return s;
}

// Applies frame f's steps to the moving boxes and calls move(i, box, d) for each.
template <class Move>
void stepScene(Scene& s, int frame, Move&& move) {
  const std::size_t mask = s.steps.size() - 1;
  const std::size_t offset = static_cast<std::size_t>(frame) * 7919u;
  for (std::uint32_t i : s.moving) {
    const Vec2 d = s.steps[(i * 2654435761u + offset) & mask];
    Aabb& b = s.boxes[i];
    b.lower += d;
    b.upper += d;
    s.lastStep[i] = d;
    move(i, b, d);
  }
}

struct Ray {
  Vec2 origin;
  Vec2 translation;
};

std::vector<Ray> makeRays(const Scene& s, std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(0.0f, s.side);
  std::uniform_real_distribution<float> angle(0.0f, 2.0f * quack::kPi);
  std::vector<Ray> rays(count);
  for (Ray& r : rays) {
    const float a = angle(rng);
    r = {{pos(rng), pos(rng)}, {20.0f * std::cos(a), 20.0f * std::sin(a)}};
  }
  return rays;
}

struct Measure {
  double buildMs = 0;
  double frameMs = 0;  // mean over timed frames
  double worstMs = 0;
  double pairs = 0;                 // mean per timed frame
  double bytesPerProxy = 0;         // heap growth from before build to after the timed frames
  double structBytesPerProxy = -1;  // Quack only: the structure alone
  double raysPerSecond = 0;
  double raysHit = 0;
  int height = -1;
};

struct Options {
  std::vector<std::size_t> ns{1000, 10000, 100000, 1000000};
  std::vector<int> moving{100, 5};
  std::vector<std::string> only;
  int warmup = 60;
  int frames = 100;
  std::size_t rays = 20000;
  std::string csv;
};

template <class Frame>
void timeFrames(const Options& o, Scene& s, Measure& m, Frame&& frame) {
  for (int f = 0; f < o.warmup; ++f)
    frame(f);
  double total = 0.0;
  double pairs = 0.0;
  for (int f = 0; f < o.frames; ++f) {
    const auto t0 = Clock::now();
    const std::size_t p = frame(o.warmup + f);
    const double ms = msSince(t0);
    total += ms;
    m.worstMs = std::max(m.worstMs, ms);
    pairs += static_cast<double>(p);
  }
  m.frameMs = total / o.frames;
  m.pairs = pairs / o.frames;
  (void)s;
}

template <class Cast>
void timeRays(const std::vector<Ray>& rays, Measure& m, Cast&& cast) {
  std::size_t hits = 0;
  const auto t0 = Clock::now();
  for (const Ray& r : rays)
    hits += cast(r) ? 1 : 0;
  const double ms = msSince(t0);
  m.raysPerSecond = static_cast<double>(rays.size()) / (ms / 1000.0);
  m.raysHit = static_cast<double>(hits) / static_cast<double>(rays.size());
}

Measure runQuack(const Options& o, Scene s, quack::BroadPhaseKind kind, bool tight,
                 const std::vector<Ray>& rays) {
  Measure m;
  const std::size_t heap0 = heapBytes();
  quack::BroadPhaseConfig config;
  config.kind = kind;
  config.checkTightBoxes = tight;
  quack::BroadPhase bp = quack::BroadPhase::create(config).value();
  std::vector<quack::ProxyId> ids(s.boxes.size());
  auto t0 = Clock::now();
  for (std::size_t i = 0; i < s.boxes.size(); ++i)
    ids[i] = bp.createProxy(s.boxes[i], i).value();
  bp.rebuild();
  m.buildMs = msSince(t0);
  std::vector<quack::ProxyPair> pairs;
  timeFrames(o, s, m, [&](int f) {
    stepScene(s, f, [&](std::uint32_t i, Aabb b, Vec2 d) {
      // The result is checked once per frame below, not per call, as a world would.
      (void)bp.moveProxy(ids[i], b, d);
    });
    bp.updatePairs(pairs);
    return pairs.size();
  });
  const quack::BroadPhaseStats st = bp.stats();
  m.bytesPerProxy =
      static_cast<double>(heapBytes() - heap0 - ids.capacity() * sizeof(quack::ProxyId) -
                          pairs.capacity() * sizeof(quack::ProxyPair)) /
      static_cast<double>(s.boxes.size());
  m.structBytesPerProxy =
      static_cast<double>(st.structureBytes) / static_cast<double>(s.boxes.size());
  m.height = st.height;
  timeRays(rays, m,
           [&](const Ray& r) { return bp.rayCastClosest(r.origin, r.translation).has_value(); });
  return m;
}

#if defined(QUACK_BENCH_HAS_BOX2D)
struct Box2dPairCounter {
  std::size_t count = 0;
  void AddPair(void*, void*) { ++count; }
};
struct Box2dRay {
  const b2BroadPhase* bp;
  const Scene* s;
  Ray ray;
  bool hit = false;
  float RayCastCallback(const b2RayCastInput& input, int32 proxyId) {
    const auto i = reinterpret_cast<std::uintptr_t>(bp->GetUserData(proxyId));
    const quack::AabbRayHit h =
        quack::rayCast(s->boxes[i], ray.origin, ray.translation, input.maxFraction);
    if (!h.hit) return input.maxFraction;
    hit = true;
    return h.fraction;
  }
};

b2AABB toB2(Aabb b) {
  return {{b.lower.x, b.lower.y}, {b.upper.x, b.upper.y}};
}

Measure runBox2d(const Options& o, Scene s, const std::vector<Ray>& rays) {
  Measure m;
  const std::size_t heap0 = heapBytes();
  auto bp = std::make_unique<b2BroadPhase>();
  std::vector<int32> ids(s.boxes.size());
  auto t0 = Clock::now();
  for (std::size_t i = 0; i < s.boxes.size(); ++i) {
    ids[i] =
        bp->CreateProxy(toB2(s.boxes[i]), reinterpret_cast<void*>(static_cast<std::uintptr_t>(i)));
  }
  m.buildMs = msSince(t0);
  Box2dPairCounter counter;
  timeFrames(o, s, m, [&](int f) {
    stepScene(s, f, [&](std::uint32_t i, Aabb b, Vec2 d) {
      bp->MoveProxy(ids[i], toB2(b), {d.x, d.y});
    });
    counter.count = 0;
    bp->UpdatePairs(&counter);
    return counter.count;
  });
  m.bytesPerProxy = static_cast<double>(heapBytes() - heap0 - ids.capacity() * sizeof(int32)) /
                    static_cast<double>(s.boxes.size());
  m.height = bp->GetTreeHeight();
  timeRays(rays, m, [&](const Ray& r) {
    Box2dRay cb{bp.get(), &s, r};
    b2RayCastInput input{{r.origin.x, r.origin.y},
                         {r.origin.x + r.translation.x, r.origin.y + r.translation.y},
                         1.0f};
    bp->RayCast(&cb, input);
    return cb.hit;
  });
  return m;
}
#endif

#if defined(QUACK_BENCH_HAS_CHIPMUNK)
// Chipmunk asks for an object's box through a callback; objects are pointers into the
// scene's box array.
double wide(float x) {
  return static_cast<double>(x);
}
cpBB chipmunkBox(void* obj) {
  const Aabb& b = *static_cast<const Aabb*>(obj);
  return cpBBNew(wide(b.lower.x), wide(b.lower.y), wide(b.upper.x), wide(b.upper.y));
}
const Scene* gChipmunkScene = nullptr;
// cpBBTree stretches a leaf by 0.1 x velocity (plus 10% of its size); velocity = 10 x the
// last displacement makes that stretch one displacement, as Quack's default.
cpVect chipmunkVelocity(void* obj) {
  const auto i =
      static_cast<std::size_t>(static_cast<const Aabb*>(obj) - gChipmunkScene->boxes.data());
  const Vec2 d = gChipmunkScene->lastStep[i];
  return cpv(10.0 * static_cast<double>(d.x), 10.0 * static_cast<double>(d.y));
}
cpCollisionID chipmunkCount(void*, void*, cpCollisionID id, void* data) {
  ++*static_cast<std::size_t*>(data);
  return id;
}
struct ChipmunkRay {
  bool hit = false;
};
cpFloat chipmunkRayHit(void*, void* obj, void* data) {
  // Chipmunk passes the segment through its own query; recompute against the tight box.
  const Aabb& b = *static_cast<const Aabb*>(obj);
  auto* r = static_cast<std::pair<ChipmunkRay*, const Ray*>*>(data);
  const quack::AabbRayHit h = quack::rayCast(b, r->second->origin, r->second->translation, 1.0f);
  if (!h.hit) return 1.0;
  r->first->hit = true;
  return static_cast<cpFloat>(h.fraction);
}

Measure runChipmunk(const Options& o, Scene s, bool hash, const std::vector<Ray>& rays) {
  Measure m;
  gChipmunkScene = &s;
  const std::size_t heap0 = heapBytes();
  auto t0 = Clock::now();
  cpSpatialIndex* index =
      hash ? cpSpaceHashNew(1.0, static_cast<int>(s.boxes.size()) * 2, chipmunkBox, nullptr)
           : cpBBTreeNew(chipmunkBox, nullptr);
  if (!hash) cpBBTreeSetVelocityFunc(index, chipmunkVelocity);
  for (std::size_t i = 0; i < s.boxes.size(); ++i) {
    cpSpatialIndexInsert(index, &s.boxes[i], static_cast<cpHashValue>(i));
  }
  if (!hash) cpBBTreeOptimize(index);
  m.buildMs = msSince(t0);
  std::size_t count = 0;
  timeFrames(o, s, m, [&](int f) {
    stepScene(s, f, [](std::uint32_t, Aabb, Vec2) {});
    count = 0;
    cpSpatialIndexReindexQuery(index, chipmunkCount, &count);
    return count;
  });
  m.bytesPerProxy = static_cast<double>(heapBytes() - heap0) / static_cast<double>(s.boxes.size());
  timeRays(rays, m, [&](const Ray& r) {
    ChipmunkRay cr;
    std::pair<ChipmunkRay*, const Ray*> data{&cr, &r};
    const cpVect a = cpv(wide(r.origin.x), wide(r.origin.y));
    const cpVect b = cpv(wide(r.origin.x + r.translation.x), wide(r.origin.y + r.translation.y));
    cpSpatialIndexSegmentQuery(index, nullptr, a, b, 1.0, chipmunkRayHit, &data);
    return cr.hit;
  });
  cpSpatialIndexFree(index);
  gChipmunkScene = nullptr;
  return m;
}
#endif

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t comma = s.find(',', start);
    const std::size_t end = comma == std::string::npos ? s.size() : comma;
    if (end > start) out.push_back(s.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

bool wanted(const Options& o, const std::string& name) {
  return o.only.empty() || std::find(o.only.begin(), o.only.end(), name) != o.only.end();
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "missing value after %s\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--n") {
      o.ns.clear();
      for (const std::string& v : split(next()))
        o.ns.push_back(std::stoul(v));
    } else if (a == "--moving") {
      o.moving.clear();
      for (const std::string& v : split(next()))
        o.moving.push_back(std::stoi(v));
    } else if (a == "--only") {
      o.only = split(next());
    } else if (a == "--warmup") {
      o.warmup = std::stoi(next());
    } else if (a == "--frames") {
      o.frames = std::stoi(next());
    } else if (a == "--rays") {
      o.rays = std::stoul(next());
    } else if (a == "--csv") {
      o.csv = next();
    } else {
      std::fprintf(stderr,
                   "usage: %s [--n 1000,10000,...] [--moving 100,5] [--only names] [--warmup W] "
                   "[--frames F] [--rays R] [--csv FILE]\n",
                   argv[0]);
      return a == "--help" ? 0 : 2;
    }
  }
#if !defined(QUACK_BENCH_HAS_BOX2D)
  std::printf("note: Box2D not found at build time; box2d is skipped\n");
#endif
#if !defined(QUACK_BENCH_HAS_CHIPMUNK)
  std::printf("note: Chipmunk not found at build time; cp-bbtree and cp-hash are skipped\n");
#endif
  std::FILE* csv = o.csv.empty() ? nullptr : std::fopen(o.csv.c_str(), "w");
  if (csv != nullptr) {
    std::fprintf(csv,
                 "structure,n,moving,build_ms,frame_ms,worst_ms,pairs,bytes_per_proxy,"
                 "struct_bytes_per_proxy,rays_per_s,ray_hit_rate,height\n");
  }
  std::printf("warm-up %d frames, %d timed; rays %zu (20 m, closest hit)\n", o.warmup, o.frames,
              o.rays);
  std::printf("%-10s %8s %4s %10s %10s %10s %11s %9s %9s %11s %6s\n", "structure", "N", "mov%",
              "build ms", "ms/frame", "worst ms", "pairs/frm", "B/proxy", "B/struct", "rays/s",
              "height");
  for (std::size_t n : o.ns) {
    for (int mov : o.moving) {
      const Scene scene = makeScene(n, mov, 12345);
      const std::vector<Ray> rays = makeRays(scene, o.rays, 777);
      auto report = [&](const char* name, const Measure& m) {
        std::printf("%-10s %8zu %4d %10.2f %10.3f %10.3f %11.0f %9.1f %9s %11.0f %6d\n", name, n,
                    mov, m.buildMs, m.frameMs, m.worstMs, m.pairs, m.bytesPerProxy,
                    m.structBytesPerProxy < 0
                        ? "-"
                        : std::to_string(static_cast<int>(m.structBytesPerProxy + 0.5)).c_str(),
                    m.raysPerSecond, m.height);
        std::fflush(stdout);
        if (csv != nullptr) {
          std::fprintf(csv, "%s,%zu,%d,%.4f,%.4f,%.4f,%.1f,%.2f,%.2f,%.0f,%.4f,%d\n", name, n, mov,
                       m.buildMs, m.frameMs, m.worstMs, m.pairs, m.bytesPerProxy,
                       m.structBytesPerProxy, m.raysPerSecond, m.raysHit, m.height);
          std::fflush(csv);
        }
      };
      for (quack::BroadPhaseKind k : quack::kAllBroadPhaseKinds) {
        const std::string name(quack::toString(k));
        if (!wanted(o, name)) continue;
        // Brute force is O(N^2) a frame: skip where it would take minutes.
        if (k == quack::BroadPhaseKind::brute && n > 10000) continue;
        report(name.c_str(), runQuack(o, scene, k, false, rays));
      }
      if (wanted(o, "tree-tight")) {
        report("tree-tight", runQuack(o, scene, quack::BroadPhaseKind::tree, true, rays));
      }
#if defined(QUACK_BENCH_HAS_BOX2D)
      if (wanted(o, "box2d")) report("box2d", runBox2d(o, scene, rays));
#endif
#if defined(QUACK_BENCH_HAS_CHIPMUNK)
      if (wanted(o, "cp-bbtree")) report("cp-bbtree", runChipmunk(o, scene, false, rays));
      if (wanted(o, "cp-hash")) report("cp-hash", runChipmunk(o, scene, true, rays));
#endif
    }
  }
  if (csv != nullptr) std::fclose(csv);
  return 0;
}
