// The 3D world benchmark: Box3D's benchmark scenes `large_pyramid` and `convex_pile`
// (scenes3.hpp) stepped by Quack's World3 and, when built with them, by Box3D (Erin Catto's
// 3D engine; -DQUACK_BOX3D_DIR=...) and by Bullet's btDiscreteDynamicsWorld (Debian
// libbullet-dev), side by side in one run.
//
//   world3_bench [--scene NAME[,NAME...]] [--workers 1,2] [--runs 3] [--steps N]
//                [--only quack|box3d|bullet[,...]] [--no-continuous] [--trace K]
//
// Each run builds the scene, times that, times the first step on its own and then the mean
// of the remaining steps (Box3D's benchmark program does the same; its step counts,
// scenes3.hpp). Runs interleave the libraries; the table gives each figure's median over the
// runs and the speed ratio peer time / Quack time (above 1: Quack is faster). Quack's World3
// runs once for each worker count (its own pool, `workers` threads) and Box3D too (its own
// scheduler); Bullet is single-threaded and runs once per run. The speed ratio compares
// each row with Quack at the same worker count. Box3D's continuous collision is on, as in
// its benchmark, and Quack's (--no-continuous turns both off).
//
// After the last step (not timed) each run reports the state its world ended in, so that the
// comparison is honest: the contact count, the awake bodies, the apex's height (pyramid; it
// starts at 99.5 m) or the highest centre (pile), the lowest centre, the mean height, the
// largest distance a body moved from its start, and the bodies whose centre is below the
// ground's top face (y < 0: through the ground) or not finite. --trace K prints the same
// columns every K steps of each library's last run (taking them is then timed too).
//
// For instruction counts run one library alone under callgrind:
// `valgrind --tool=callgrind world3_bench --scene large_pyramid --only quack --runs 1
// --steps 10`.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "quack/world/world3.hpp"
#include "scenes3.hpp"

namespace bench3 {
namespace quack3 {

using namespace quack;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

BodyId3 ground(World3& world, float half) {
  const BodyId3 body =
      world.createBody({.type = BodyType::staticBody, .position = {0.0f, -1.0f, 0.0f}}).value();
  (void)world.createShape(body, {.friction = kFriction}, makeBox3({half, 1.0f, half}).value())
      .value();
  return body;
}

std::vector<BodyId3> largePyramid(World3& world) {
  (void)ground(world, kPyramidGroundHalf);
  const Hull3 box = makeBox3({kPyramidHalf, kPyramidHalf, kPyramidHalf}).value();
  const ShapeDef3 sd{.density = kPyramidDensity, .friction = kFriction};
  std::vector<BodyId3> bodies;
  for (const P3& p : pyramidPositions()) {
    const BodyId3 b = world.createBody({.position = {p.x, p.y, p.z}}).value();
    (void)world.createShape(b, sd, box).value();
    bodies.push_back(b);
  }
  return bodies;
}

std::vector<BodyId3> convexPile(World3& world) {
  (void)ground(world, kPileGroundHalf);
  std::vector<Vec3> points;
  for (const P3& p : pilePoints())
    points.push_back({p.x, p.y, p.z});
  const Hull3 hull = makeHull3(points).value();
  const ShapeDef3 sd{.density = kPileDensity, .friction = kFriction};
  std::vector<BodyId3> bodies;
  for (const P3& p : pilePositions()) {
    const BodyId3 b = world.createBody({.position = {p.x, p.y, p.z}}).value();
    (void)world.createShape(b, sd, hull).value();
    bodies.push_back(b);
  }
  return bodies;
}

bool finite(Vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

Run run(const Plan& plan) {
  Run out;
  auto t0 = Clock::now();
  // Sleeping is off in the pyramid (Box3D's b3World_EnableSleeping(false)), on in the pile.
  World3 world = World3::create({.timeStep = kTimeStep,
                                 .substeps = kSubsteps,
                                 .enableContinuous = plan.continuous,
                                 .enableSleep = plan.scene != "large_pyramid",
                                 .workerCount = plan.workers})
                     .value();
  std::vector<BodyId3> bodies;
  if (plan.scene == "large_pyramid") {
    bodies = largePyramid(world);
  } else if (plan.scene == "convex_pile") {
    bodies = convexPile(world);
  } else {
    throw std::invalid_argument("no scene " + plan.scene);
  }
  out.buildMs = msSince(t0);
  auto positions = [&] {
    std::vector<P3> at;
    for (BodyId3 b : bodies) {
      const Vec3 p = world.position(b);
      at.push_back({p.x, p.y, p.z});
    }
    return at;
  };
  auto step = [&](int i) {
    (void)world.step(kTimeStep, kSubsteps);
    if (plan.traceEvery > 0 && (i + 1) % plan.traceEvery == 0) out.trace.push_back(positions());
  };
  t0 = Clock::now();
  step(0);
  out.firstStepMs = msSince(t0);
  t0 = Clock::now();
  for (int i = 1; i < plan.steps; ++i)
    step(i);
  out.msPerStep = plan.steps > 1 ? msSince(t0) / (plan.steps - 1) : 0.0;
  out.contacts = static_cast<long>(world.contactCount());
  out.awake = static_cast<long>(world.awakeBodyCount());
  out.positions = positions();
  for (BodyId3 b : bodies)
    if (!finite(world.position(b)) || !finite(world.linearVelocity(b)) ||
        !finite(world.angularVelocity(b)))
      ++out.nonFinite;
  return out;
}

}  // namespace quack3

#if !QUACK_HAVE_BOX3D
namespace box3d {
bool available() {
  return false;
}
Run run(const Plan&) {
  throw std::runtime_error("built without Box3D (configure with -DQUACK_BOX3D_DIR=...)");
}
}  // namespace box3d
#endif

#if !QUACK_HAVE_BULLET
namespace bullet {
bool available() {
  return false;
}
Run run(const Plan&) {
  throw std::runtime_error("built without Bullet (apt-get install libbullet-dev)");
}
}  // namespace bullet
#endif

}  // namespace bench3

namespace {

using bench3::P3;
using bench3::Run;

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at <= s.size()) {
    const std::size_t comma = s.find(',', at);
    const std::size_t end = comma == std::string::npos ? s.size() : comma;
    if (end > at) out.push_back(s.substr(at, end - at));
    at = end + 1;
  }
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

// The end state of a run, from its bodies' positions (see the top of the file).
struct Check {
  double top = 0, low = 0, mean = 0, moved = 0;
  long under = 0;
  std::size_t mover = 0;  // the body that moved furthest
  P3 moverAt{};           // and where it is
};

Check check(const std::string& scene, const std::vector<P3>& at) {
  const std::vector<P3> start =
      scene == "large_pyramid" ? bench3::pyramidPositions() : bench3::pilePositions();
  Check c;
  if (at.size() != start.size() || start.empty()) return c;
  c.low = std::numeric_limits<double>::infinity();
  c.top = scene == "large_pyramid" ? static_cast<double>(at.back().y)
                                   : -std::numeric_limits<double>::infinity();
  double sum = 0;
  for (std::size_t i = 0; i < start.size(); ++i) {
    const P3 p = at[i];
    const double y = static_cast<double>(p.y);
    if (scene != "large_pyramid") c.top = std::max(c.top, y);
    c.low = std::min(c.low, y);
    sum += y;
    if (y < 0.0) ++c.under;
    const double dx = static_cast<double>(p.x - start[i].x);
    const double dy = static_cast<double>(p.y - start[i].y);
    const double dz = static_cast<double>(p.z - start[i].z);
    const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (d > c.moved) {
      c.moved = d;
      c.mover = i;
      c.moverAt = p;
    }
  }
  c.mean = sum / static_cast<double>(start.size());
  return c;
}

int usage(const char* why) {
  std::fprintf(
      stderr,
      "world3_bench: %s\nusage: world3_bench [--scene NAME[,NAME...]] [--workers 1,2] "
      "[--runs 3] [--steps N] [--only quack|box3d|bullet[,...]] [--no-continuous] [--trace K]\n",
      why);
  return 2;
}

// One row of the table: a library (and worker count) on a scene.
struct Row {
  std::string library;
  int workers = 1;
  std::vector<double> ms, first, build;
  Run last;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> scenes;
  std::vector<int> workers{1, 2};
  std::vector<std::string> libraries{"quack", "box3d", "bullet"};
  bool explicitLibraries = false, continuous = true;
  int runs = 3, steps = 0, traceEvery = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--no-continuous") {
      continuous = false;
      continue;
    }
    if (i + 1 >= argc) return usage(("missing value after " + arg).c_str());
    const std::string value = argv[++i];
    if (arg == "--scene") {
      scenes = split(value);
    } else if (arg == "--workers") {
      workers.clear();
      for (const std::string& w : split(value))
        workers.push_back(std::atoi(w.c_str()));
    } else if (arg == "--runs") {
      runs = std::atoi(value.c_str());
    } else if (arg == "--steps") {
      steps = std::atoi(value.c_str());
      if (steps < 1) return usage("--steps must be >= 1");
    } else if (arg == "--trace") {
      traceEvery = std::atoi(value.c_str());
      if (traceEvery < 1) return usage("--trace must be >= 1");
    } else if (arg == "--only") {
      libraries = split(value);
      explicitLibraries = true;
    } else {
      return usage(("unknown option " + arg).c_str());
    }
  }
  if (runs < 1) return usage("--runs must be >= 1");
  if (workers.empty()) return usage("--workers needs at least one count");
  for (int w : workers)
    if (w < 1 || w > 64) return usage("--workers must be in 1..64");
  for (const std::string& l : libraries) {
    if (l != "quack" && l != "box3d" && l != "bullet")
      return usage("--only takes quack, box3d or bullet");
    if (explicitLibraries && l == "box3d" && !bench3::box3d::available())
      return usage("built without Box3D (configure with -DQUACK_BOX3D_DIR=...)");
    if (explicitLibraries && l == "bullet" && !bench3::bullet::available())
      return usage("built without Bullet (apt-get install libbullet-dev)");
  }
  std::erase_if(libraries, [](const std::string& l) {
    return (l == "box3d" && !bench3::box3d::available()) ||
           (l == "bullet" && !bench3::bullet::available());
  });
  if (scenes.empty())
    for (const bench3::SceneInfo& s : bench3::kScenes)
      scenes.push_back(s.name);
  for (const std::string& name : scenes)
    if (std::none_of(std::begin(bench3::kScenes), std::end(bench3::kScenes),
                     [&](const bench3::SceneInfo& s) { return name == s.name; }))
      return usage(("no scene " + name).c_str());

  std::printf(
      "60 Hz, 4 sub-steps (Bullet: 1 step, 10 iterations); median of %d runs; Box3D "
      "continuous %s; Bullet single-threaded\n",
      runs, continuous ? "on" : "off");
  std::printf("%-13s %-7s %3s | %9s %7s | %8s %8s | %7s %5s | %7s %7s %7s %7s %5s %4s\n", "scene",
              "library", "thr", "ms/step", "Q speed", "first ms", "build ms", "contact", "awake",
              "top y", "low y", "mean y", "moved", "under", "nan");
  for (const std::string& name : scenes) {
    int sceneSteps = 0;
    for (const bench3::SceneInfo& s : bench3::kScenes)
      if (name == s.name) sceneSteps = s.steps;
    if (sceneSteps == 0) return usage(("no scene " + name).c_str());
    if (steps > 0) sceneSteps = steps;
    std::vector<Row> rows;
    for (const std::string& l : libraries) {
      if (l == "box3d" || l == "quack") {
        for (int w : workers)
          rows.push_back({.library = l, .workers = w});
      } else {
        rows.push_back({.library = l});
      }
    }
    for (int r = 0; r < runs; ++r) {
      for (Row& row : rows) {
        const bench3::Plan plan{.scene = name,
                                .workers = row.workers,
                                .steps = sceneSteps,
                                .continuous = continuous,
                                .traceEvery = traceEvery};
        if (row.library == "quack") {
          row.last = bench3::quack3::run(plan);
        } else if (row.library == "box3d") {
          row.last = bench3::box3d::run(plan);
        } else {
          row.last = bench3::bullet::run(plan);
        }
        row.ms.push_back(row.last.msPerStep);
        row.first.push_back(row.last.firstStepMs);
        row.build.push_back(row.last.buildMs);
      }
    }
    for (const Row& row : rows) {
      const double ms = median(row.ms);
      // Against Quack with the same worker count (Bullet: one).
      double quackMs = 0.0;
      for (const Row& q : rows)
        if (q.library == "quack" && q.workers == row.workers) quackMs = median(q.ms);
      const Check c = check(name, row.last.positions);
      char speed[16] = "-";
      if (quackMs > 0.0 && row.library != "quack")
        std::snprintf(speed, sizeof speed, "%.2fx", ms / quackMs);
      std::printf(
          "%-13s %-7s %3d | %9.3f %7s | %8.2f %8.1f | %7ld %5ld | %7.3f %7.3f %7.3f %7.3f %5ld "
          "%4ld\n",
          name.c_str(), row.library.c_str(), row.workers, ms, speed, median(row.first),
          median(row.build), row.last.contacts, row.last.awake, c.top, c.low, c.mean, c.moved,
          c.under, row.last.nonFinite);
    }
    std::printf("  (%d steps; Q speed: the row's time over Quack's, above 1: Quack faster)\n",
                sceneSteps);
    // The end-state columns every traceEvery steps, the libraries side by side.
    for (const Row& row : rows) {
      for (std::size_t k = 0; k < row.last.trace.size(); ++k) {
        const Check c = check(name, row.last.trace[k]);
        const P3 from = (name == "large_pyramid" ? bench3::pyramidPositions()
                                                 : bench3::pilePositions())[c.mover];
        std::printf(
            "  trace %-7s %3d step %5zu | top y %8.3f  low y %7.3f  mean y %7.3f  "
            "moved %7.3f  under %ld | furthest: body %zu from (%.2f %.2f %.2f) at "
            "(%.2f %.2f %.2f)\n",
            row.library.c_str(), row.workers, (k + 1) * static_cast<std::size_t>(traceEvery), c.top,
            c.low, c.mean, c.moved, c.under, c.mover, static_cast<double>(from.x),
            static_cast<double>(from.y), static_cast<double>(from.z),
            static_cast<double>(c.moverAt.x), static_cast<double>(c.moverAt.y),
            static_cast<double>(c.moverAt.z));
      }
    }
    std::fflush(stdout);
  }
  return 0;
}
