// The world suite: Box2D v3's benchmark scenes that need no joints, in Quack and (when
// built with QUACK_BOX2D_V3_DIR) Box2D v3, side by side in one run.
//
//   world_suite [--scene NAME[,NAME...]] [--workers 1,2] [--runs 3] [--steps N]
//               [--only quack|v3]
//
// Each run builds the scene, times that, times the first step on its own and then the mean
// of the remaining steps (v3's step counts, suite.hpp). Runs alternate between the
// libraries; the table gives each figure's median over the runs, and the speed ratio
// v3 time / Quack time (above 1: Quack is faster). Both step at 60 Hz with 4 sub-steps, each
// with its own thread pool of `workers` threads. For instruction counts run one library
// alone under callgrind: `valgrind --tool=callgrind world_suite --scene large_pyramid
// --only quack --runs 1 --steps 20`.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "quack/world/world.hpp"
#include "suite.hpp"

namespace suite {

double junkyardTargetX(int step) {
  return 60.0 * std::sin(0.2 * (static_cast<double>(step) / 60.0));
}

namespace quackside {

using namespace quack;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

Vec2 vec(double x, double y) {
  return {static_cast<float>(x), static_cast<float>(y)};
}

void pyramid(World& world, int rows, double left, double base) {
  const Polygon box = makeBox(0.5f, 0.5f).value();
  for (int row = 0; row < rows; ++row) {
    for (int i = 0; i < rows - row; ++i) {
      BodyId b =
          world.createBody({.position = vec(left + 0.5 * row + i + 0.5, base + row + 0.5)}).value();
      (void)world.createShape(b, {}, box);
    }
  }
}

void largePyramid(World& world) {
  BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
  (void)world.createShape(ground, {}, makeBox(100.0f, 1.0f, {0, -1}).value());
  pyramid(world, 100, -50.0, 0.0);
}

void manyPyramids(World& world) {
  BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
  for (int r = 0; r < 20; ++r)
    (void)world.createShape(ground, {},
                            makeSegment(vec(-110, 11.0 * r), vec(110, 11.0 * r)).value());
  for (int r = 0; r < 20; ++r)
    for (int c = 0; c < 20; ++c)
      pyramid(world, 10, -110.0 + 11.0 * c + 0.5, 11.0 * r);
}

void smash(World& world) {
  BodyId heavy = world.createBody({.position = {-20, 0}, .linearVelocity = {40, 0}}).value();
  (void)world.createShape(heavy, {.density = 8.0f}, makeBox(4.0f, 4.0f).value());
  const Polygon small = makeBox(0.2f, 0.2f).value();
  for (int i = 0; i < 120; ++i) {
    for (int j = 0; j < 80; ++j) {
      BodyId b =
          world.createBody({.position = vec(30.0 + 0.4 * i, 0.4 * (j - 40)), .isAwake = false})
              .value();
      (void)world.createShape(b, {}, small);
      (void)world.setAwake(b, false);
    }
  }
}

void pit(World& world, BodyId ground, int floor, int wall, double half) {
  for (int i = 0; i < floor; ++i)
    (void)world.createShape(ground, {}, makeBox(0.55f, 0.5f, vec(-half + i, 0)).value());
  for (int i = 0; i < wall; ++i) {
    (void)world.createShape(ground, {}, makeBox(0.5f, 0.55f, vec(-half, 1.0 + i)).value());
    (void)world.createShape(ground, {}, makeBox(0.5f, 0.55f, vec(half, 1.0 + i)).value());
  }
}

BodyId junkyard(World& world) {
  pit(world, world.createBody({.type = BodyType::staticBody}).value(), 161, 50, 80.0);
  Vec2 points[5];
  const double golden = 3.14159265358979 * (std::sqrt(5.0) - 1.0);
  for (int i = 0; i < 5; ++i)
    points[i] = vec(0.25 * std::cos(golden * i), 0.25 * std::sin(golden * i));
  const Polygon pentagon = makePolygon(points).value();
  double side = -0.1;
  for (int i = 0; i < 200; ++i) {
    for (int j = 0; j < 40; ++j) {
      BodyId b =
          world.createBody({.position = vec(0.375 * (2 * i - 200) + side, 15.0 + j)}).value();
      side = -side;
      (void)world.createShape(b, {}, pentagon);
    }
  }
  BodyId pusher = world.createBody({.type = BodyType::kinematicBody}).value();
  (void)world.createShape(pusher, {}, makeBox(2.0f, 4.0f, {0, 4}).value());
  return pusher;
}

void compounds(World& world) {
  BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
  pit(world, ground, 81, 100, 40.0);
  (void)world.createShape(ground, {}, makeSegment({-800, -80}, {800, -80}).value());
  const Vec2 leftPoints[3] = {{-1, 0}, {0.5f, 1}, {0, 2}};
  const Vec2 rightPoints[3] = {{1, 0}, {-0.5f, 1}, {0, 2}};
  const Polygon left = makePolygon(leftPoints).value();
  const Polygon right = makePolygon(rightPoints).value();
  const ShapeDef def{.friction = 0.5f};
  double side = 0.25;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 150; ++j) {
      BodyId b =
          world.createBody({.position = vec(2.0 * i - 19.0 + side, 2.25 * j + 5.575)}).value();
      side = -side;
      (void)world.createShape(b, def, left);
      (void)world.createShape(b, def, right);
    }
  }
}

Run run(const std::string& scene, int workers, int steps) {
  const bool noSleep = scene == "large_pyramid" || scene == "many_pyramids";
  WorldDef def{.enableSleep = !noSleep, .workerCount = workers};
  if (scene == "smash") def.gravity = {0, 0};
  Run out;
  auto t0 = Clock::now();
  World world = World::create(def).value();
  BodyId pusher;
  bool hasPusher = false;
  if (scene == "large_pyramid") {
    largePyramid(world);
  } else if (scene == "many_pyramids") {
    manyPyramids(world);
  } else if (scene == "smash") {
    smash(world);
  } else if (scene == "junkyard") {
    pusher = junkyard(world);
    hasPusher = true;
  } else if (scene == "compounds") {
    compounds(world);
  } else {
    throw std::invalid_argument("no scene " + scene);
  }
  out.buildMs = msSince(t0);
  constexpr float dt = 1.0f / 60.0f;
  auto step = [&](int i) {
    if (hasPusher) {
      // What v3's b2Body_SetTargetTransform does: the velocity that reaches the target in dt.
      const float x = world.position(pusher).x;
      (void)world.setLinearVelocity(
          pusher, {static_cast<float>((junkyardTargetX(i) - static_cast<double>(x)) /
                                      static_cast<double>(dt)),
                   0.0f});
    }
    world.step(dt, 4);
  };
  t0 = Clock::now();
  step(0);
  out.firstStepMs = msSince(t0);
  t0 = Clock::now();
  for (int i = 1; i < steps; ++i)
    step(i);
  out.msPerStep = steps > 1 ? msSince(t0) / (steps - 1) : 0.0;
  out.contacts = static_cast<long>(world.contactCount());
  out.awake = static_cast<long>(world.awakeBodyCount());
  return out;
}

}  // namespace quackside
}  // namespace suite

#if !QUACK_HAVE_BOX2D_V3
namespace suite::v3 {
Run run(const std::string&, int, int) {
  throw std::runtime_error("built without Box2D v3 (configure with -DQUACK_BOX2D_V3_DIR=...)");
}
}  // namespace suite::v3
#endif

namespace {

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

std::string fixed(double x, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", digits, x);
  return text;
}

int usage(const char* why) {
  std::fprintf(stderr,
               "world_suite: %s\nusage: world_suite [--scene NAME[,NAME...]] [--workers 1,2] "
               "[--runs 3] [--steps N] [--only quack|v3]\n",
               why);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> scenes;
  std::vector<int> workers{1, 2};
  int runs = 3, steps = 0;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
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
    } else if (arg == "--only") {
      only = value;
    } else {
      return usage(("unknown option " + arg).c_str());
    }
  }
  if (runs < 1) return usage("--runs must be >= 1");
  for (int w : workers)
    if (w < 1 || w > 64) return usage("--workers must be in 1..64");
  if (only != "" && only != "quack" && only != "v3") return usage("--only takes quack or v3");
  const bool withV3 = QUACK_HAVE_BOX2D_V3 && only != "quack";
  const bool withQuack = only != "v3";
  if (only == "v3" && !QUACK_HAVE_BOX2D_V3) return usage("built without Box2D v3");
  if (scenes.empty())
    for (const suite::SceneInfo& s : suite::kScenes)
      scenes.push_back(s.name);
  std::printf("%-14s %3s | %9s %9s %6s | %9s %9s %6s | %8s %8s | %8s %8s | %s\n", "scene", "thr",
              "Quack ms", "v3 ms", "speed", "Q first", "v3 first", "speed", "Q build", "v3 build",
              "Q cont", "v3 cont", "awake Q/v3");
  for (const std::string& name : scenes) {
    int sceneSteps = 0;
    for (const suite::SceneInfo& s : suite::kScenes)
      if (name == s.name) sceneSteps = s.steps;
    if (sceneSteps == 0) return usage(("no scene " + name).c_str());
    if (steps > 0) sceneSteps = steps;
    for (int w : workers) {
      std::vector<double> q[3], v[3];
      suite::Run lastQ, lastV;
      for (int r = 0; r < runs; ++r) {
        if (withQuack) {
          lastQ = suite::quackside::run(name, w, sceneSteps);
          q[0].push_back(lastQ.msPerStep);
          q[1].push_back(lastQ.firstStepMs);
          q[2].push_back(lastQ.buildMs);
        }
        if (withV3) {
          lastV = suite::v3::run(name, w, sceneSteps);
          v[0].push_back(lastV.msPerStep);
          v[1].push_back(lastV.firstStepMs);
          v[2].push_back(lastV.buildMs);
        }
      }
      const double qs = median(q[0]), vs = median(v[0]), qf = median(q[1]), vf = median(v[1]);
      if (withQuack && withV3) {
        std::printf(
            "%-14s %3d | %9.3f %9.3f %5.2fx | %9.2f %9.2f %5.2fx | %8.1f %8.1f | %8ld %8ld | "
            "%ld/%ld\n",
            name.c_str(), w, qs, vs, vs / qs, qf, vf, vf / qf, median(q[2]), median(v[2]),
            lastQ.contacts, lastV.contacts, lastQ.awake, lastV.awake);
      } else {
        // One library: its figures in its columns, the other's and the ratios left blank.
        const bool q1 = withQuack;
        const suite::Run& last = q1 ? lastQ : lastV;
        const double ms = q1 ? qs : vs, first = q1 ? qf : vf, build = median(q1 ? q[2] : v[2]);
        std::printf(
            "%-14s %3d | %9s %9s %6s | %9s %9s %6s | %8s %8s | %8s %8s | %s\n", name.c_str(), w,
            q1 ? fixed(ms, 3).c_str() : "-", q1 ? "-" : fixed(ms, 3).c_str(), "-",
            q1 ? fixed(first, 2).c_str() : "-", q1 ? "-" : fixed(first, 2).c_str(), "-",
            q1 ? fixed(build, 1).c_str() : "-", q1 ? "-" : fixed(build, 1).c_str(),
            q1 ? std::to_string(last.contacts).c_str() : "-",
            q1 ? "-" : std::to_string(last.contacts).c_str(), std::to_string(last.awake).c_str());
      }
      std::fflush(stdout);
    }
  }
  return 0;
}
