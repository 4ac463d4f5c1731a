// World benchmark: milliseconds per step, single-threaded, for Quack's World and Box2D
// 2.4.1's b2World on the same scenes in the same run.
//
//   world_bench [--rows N] [--field N] [--steps N] [--warmup N] [--scene NAME]
//               [--only quack|box2d]
//
// Scenes (both libraries, 60 Hz):
//   pyramid  a pyramid of N rows of 1 m boxes (N = 100: 5,050 boxes), the peers' standard scene;
//   many     20 x 20 pyramids of 10 rows (22,000 boxes), each row of pyramids on its own
//            ground (Box2D v3's "many pyramids" benchmark, its figures quoted in docs/world.md);
//   rain     N mixed shapes (boxes, circles, capsules, triangles) raining into a box, timed
//            from the start while they fall and pile up;
//   field    the same N shapes timed after 4 s, once they have piled up;
//   sleep    the pyramid settled until it sleeps, timed asleep, against the same pyramid
//            simulated in full and Box2D 2.4.1's pyramid asleep;
//   sleepers (Quack only) 10,000 boxes asleep on a grid and 100 balls moving between them,
//            against the 100 balls alone.
// Sleeping is off in every other scene, in both libraries.
// --scene runs one scene; --only runs one library (for callgrind: instruction counts per
// library, `valgrind --tool=callgrind world_bench --scene pyramid --only quack --steps 20`).
// Quack runs its default 4 sub-steps; Box2D its standard 8 velocity and 3 position
// iterations; with sleeping off, both simulate every body every step.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "quack/world/world.hpp"

#ifdef QUACK_BENCH_HAS_BOX2D
#include <box2d/box2d.h>
#endif

namespace {

using namespace quack;
using Clock = std::chrono::steady_clock;

struct Options {
  int rows = 100;
  int field = 2000;
  int steps = 200;
  int warmup = 20;
  int workers = 1;    // Quack's WorldDef::workerCount
  std::string scene;  // empty: all
  std::string only;   // empty: both libraries
};

// Many pyramids: kManyGrid x kManyGrid pyramids of kManyRows rows, kManySpacing metres apart
// both ways; each row of pyramids stands on its own ground segment (the layout of Box2D v3's
// "many pyramids" benchmark: 2 (rows + 1) m between grounds, a 2 m gap between pyramids).
constexpr int kManyGrid = 20;
constexpr int kManyRows = 10;
constexpr float kManySpacing = 2.0f * (kManyRows + 1);

// One falling shape of the field scene, the same for both libraries.
struct Piece {
  int kind;  // 0 box, 1 circle, 2 capsule, 3 triangle
  Vec2 position;
  float angle;
  float size;
};

std::vector<Piece> makeField(int n) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Piece> pieces;
  int perRow = 40;
  for (int i = 0; i < n; ++i) {
    float x = -30.0f + 60.0f * (static_cast<float>(i % perRow) + 0.5f) / static_cast<float>(perRow);
    float y = 2.0f + 1.6f * static_cast<float>(i / perRow);
    pieces.push_back({i % 4, {x, y}, 3.0f * u(rng), 0.3f + 0.2f * u(rng)});
  }
  return pieces;
}

// The field is timed once the shapes have landed and piled up (4 s), not in free fall.
constexpr int kFieldSettleSteps = 240;

struct Timing {
  double msPerStep = 0;
  std::size_t contacts = 0;
};

template <class StepFn, class CountFn>
Timing timeSteps(const Options& o, StepFn step, CountFn count, int extraWarmup = 0) {
  for (int i = 0; i < o.warmup + extraWarmup; ++i)
    step();
  auto t0 = Clock::now();
  for (int i = 0; i < o.steps; ++i)
    step();
  double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  return {ms / o.steps, count()};
}

// ---- Quack ------------------------------------------------------------------------------

// 10,000 boxes asleep on a grid (3 m apart, no gravity) and 100 balls moving through the
// lanes between its rows without touching them; or (`sleepers` false) the 100 balls alone.
Timing quackSleepers(const Options& o, bool sleepers) {
  World world = World::create({.gravity = {0, 0}}).value();
  const Polygon box = makeBox(0.25f, 0.25f).value();
  const Circle ball = makeCircle({}, 0.25f).value();
  if (sleepers) {
    for (int r = 0; r < 100; ++r) {
      for (int c = 0; c < 100; ++c) {
        BodyId b = world
                       .createBody({.position = {3.0f * static_cast<float>(c),
                                                 3.0f * static_cast<float>(r)},
                                    .isAwake = false})
                       .value();
        (void)world.createShape(b, {}, box);
        (void)world.setAwake(b, false);  // adding the shape woke it
      }
    }
  }
  for (int i = 0; i < 100; ++i) {
    const float y = 3.0f * static_cast<float>(i) + 1.5f;
    BodyId b = world
                   .createBody({.position = {-3.0f, y},
                                .linearVelocity = {i % 2 == 0 ? 5.0f : 4.0f, 0},
                                .enableSleep = false})
                   .value();
    (void)world.createShape(b, {}, ball);
  }
  return timeSteps(
      o, [&] { world.step(); }, [&] { return world.awakeBodyCount(); });
}

// 1,000 bullets (small discs and boxes, 20 to 40 m/s, any heading, restitution 1, no
// friction, no gravity) in a closed box of 1 m walls, 40 m across: every bullet
// goes through the continuous phase every step (sweeps against the walls and each other).
// With `continuous` false the same world without it. The walls hold most bullets either
// way (without the phase 52 of the 1,000 are outside by the end of the run: the baseline
// does a little less work, so the ratio errs against the phase). With `farStatics` the
// world also holds 164 static boxes far outside the walls, which nothing meets: more
// shapes outside the bullets than the phase lists (64), so its searches query the broad
// phase, as in a level of many static shapes (docs/continuous.md).
Timing quackBullets(const Options& o, bool continuous, bool farStatics = false) {
  World world = World::create({.gravity = {0, 0}, .enableContinuous = continuous}).value();
  constexpr float kHalf = 20.0f, kWall = 0.5f;
  const Vec2 walls[4][2] = {{{0, -kHalf - kWall}, {kHalf + 2 * kWall, kWall}},
                            {{0, kHalf + kWall}, {kHalf + 2 * kWall, kWall}},
                            {{-kHalf - kWall, 0}, {kWall, kHalf + 2 * kWall}},
                            {{kHalf + kWall, 0}, {kWall, kHalf + 2 * kWall}}};
  for (const auto& w : walls) {
    BodyId b = world.createBody({.type = BodyType::staticBody, .position = w[0]}).value();
    (void)world.createShape(b, {}, makeBox(w[1].x, w[1].y).value());
  }
  for (int k = 0; farStatics && k < 164; ++k) {
    const Vec2 at{100.0f + 3.0f * static_cast<float>(k % 16),
                  100.0f + 3.0f * static_cast<float>(k / 16)};
    BodyId b = world.createBody({.type = BodyType::staticBody, .position = at}).value();
    (void)world.createShape(b, {}, makeBox(1.0f, 1.0f).value());
  }
  std::mt19937 rng(18);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const Circle disc = makeCircle({}, 0.05f).value();
  const Polygon box = makeBox(0.06f, 0.03f).value();
  for (int i = 0; i < 1000; ++i) {
    const float heading = 6.2831853f * u(rng);
    const float speed = 20.0f + 20.0f * u(rng);
    BodyId b =
        world
            .createBody(
                {.position = {(2 * u(rng) - 1) * (kHalf - 1), (2 * u(rng) - 1) * (kHalf - 1)},
                 .angle = 3 * u(rng),
                 .linearVelocity = {speed * std::cos(heading), speed * std::sin(heading)},
                 .bullet = true,
                 .enableSleep = false})
            .value();
    const ShapeDef def{.friction = 0.0f, .restitution = 1.0f};
    if (i % 2 == 0)
      (void)world.createShape(b, def, disc);
    else
      (void)world.createShape(b, def, box);
  }
  return timeSteps(
      o, [&] { world.step(); }, [&] { return world.contactCount(); });
}

// The solver's figures after the last timed step of the last Quack scene.
World::SolverStats gQuackSolver;

std::size_t quackCount(const World& world) {
  gQuackSolver = world.solverStats();
  return world.touchingContactCount();
}

void quackAddPyramid(World& world, const Polygon& box, int rows, Vec2 base) {
  for (int row = 0; row < rows; ++row) {
    for (int i = 0; i < rows - row; ++i) {
      float x = base.x + static_cast<float>(i) - 0.5f * static_cast<float>(rows - row - 1);
      BodyId b =
          world.createBody({.position = {x, base.y + 0.5f + static_cast<float>(row)}}).value();
      (void)world.createShape(b, {}, box);
    }
  }
}

void buildQuackMany(World& world) {
  const float width = kManySpacing * kManyGrid;
  Polygon box = makeBox(0.5f, 0.5f).value();
  for (int r = 0; r < kManyGrid; ++r) {
    const float y = kManySpacing * static_cast<float>(r);
    // One ground body per row: Box2D 2.4 scans a body's whole contact list when a pair is
    // added, so a single ground under all 22,000 boxes would measure that scan, not solving.
    BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
    (void)world.createShape(ground, {},
                            makeSegment({-kManySpacing, y}, {width + kManySpacing, y}).value());
    for (int c = 0; c < kManyGrid; ++c)
      quackAddPyramid(world, box, kManyRows, {kManySpacing * (static_cast<float>(c) + 0.5f), y});
  }
}

Timing quackMany(const Options& o) {
  // Sleeping off, as in box2dMany: both simulate every body of every step.
  World world = World::create({.enableSleep = false, .workerCount = o.workers}).value();
  buildQuackMany(world);
  return timeSteps(
      o, [&] { world.step(); }, [&] { return quackCount(world); });
}

// The pyramid, simulated in full (`sleep` false), or first settled until it sleeps and
// then timed asleep.
void buildQuackPyramid(World& world, int rows) {
  BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
  (void)world.createShape(ground, {}, makeBox(200.0f, 0.5f, {0, -0.5f}).value());
  Polygon box = makeBox(0.5f, 0.5f).value();
  for (int row = 0; row < rows; ++row) {
    for (int i = 0; i < rows - row; ++i) {
      float x = static_cast<float>(i) - 0.5f * static_cast<float>(rows - row - 1);
      BodyId b = world.createBody({.position = {x, 0.5f + static_cast<float>(row)}}).value();
      (void)world.createShape(b, {}, box);
    }
  }
}

Timing quackPyramid(const Options& o, bool sleep = false) {
  World world = World::create({.enableSleep = sleep, .workerCount = o.workers}).value();
  buildQuackPyramid(world, o.rows);
  if (sleep) {
    for (int i = 0; i < 1200 && world.awakeBodyCount() > 0; ++i)
      world.step();
    if (world.awakeBodyCount() > 0)
      std::fprintf(stderr, "world_bench: the pyramid did not sleep\n");
  }
  return timeSteps(
      o, [&] { world.step(); }, [&] { return quackCount(world); });
}

Timing quackField(const Options& o, const std::vector<Piece>& pieces, int settleSteps) {
  // Sleeping off, as in box2dField: both simulate every body of every step.
  World world = World::create({.enableSleep = false, .workerCount = o.workers}).value();
  BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
  (void)world.createShape(ground, {}, makeBox(32.0f, 0.5f, {0, -0.5f}).value());
  (void)world.createShape(ground, {}, makeBox(0.5f, 40.0f, {-32.5f, 40}).value());
  (void)world.createShape(ground, {}, makeBox(0.5f, 40.0f, {32.5f, 40}).value());
  for (const Piece& p : pieces) {
    BodyId b = world.createBody({.position = p.position, .angle = p.angle}).value();
    float s = p.size;
    switch (p.kind) {
      case 0:
        (void)world.createShape(b, {}, makeBox(s, s).value());
        break;
      case 1:
        (void)world.createShape(b, {}, makeCircle({}, s).value());
        break;
      case 2:
        (void)world.createShape(b, {}, makeCapsule({-s, 0}, {s, 0}, 0.5f * s).value());
        break;
      default: {
        const Vec2 tri[] = {{-s, -s}, {s, -s}, {0, s}};
        (void)world.createShape(b, {}, makePolygon(tri).value());
      }
    }
  }
  return timeSteps(
      o, [&] { world.step(); }, [&] { return quackCount(world); }, settleSteps);
}

#ifdef QUACK_BENCH_HAS_BOX2D
// Threads: the same scene in a one-worker world and an o.workers world, stepped in turns of
// kScalingRun steps and timed run by run, so that whatever else the machine does falls on both
// alike. Turns of one step each would cost each world its caches every step (the other
// world's step evicts them, and the one-worker time grows far more than the two-worker
// one); runs of ten leave only the first step of each run cold.
constexpr int kScalingRun = 10;
void quackScaling(const Options& o, const char* label, void (*build)(World&, int)) {
  World one = World::create({.enableSleep = false}).value();
  World many = World::create({.enableSleep = false, .workerCount = o.workers}).value();
  build(one, o.rows);
  build(many, o.rows);
  for (int i = 0; i < o.warmup; ++i) {
    one.step();
    many.step();
  }
  double msOne = 0, msMany = 0;
  for (int done = 0; done < o.steps; done += kScalingRun) {
    const int run = std::min(kScalingRun, o.steps - done);
    auto t0 = Clock::now();
    for (int i = 0; i < run; ++i)
      one.step();
    auto t1 = Clock::now();
    for (int i = 0; i < run; ++i)
      many.step();
    auto t2 = Clock::now();
    msOne += std::chrono::duration<double, std::milli>(t1 - t0).count();
    msMany += std::chrono::duration<double, std::milli>(t2 - t1).count();
  }
  const bool same = one.stateHash() == many.stateHash();
  std::printf("%-24s %8.3f ms/step on 1 worker, %8.3f on %d: %.2fx (%s)\n", label, msOne / o.steps,
              msMany / o.steps, o.workers, msOne / msMany,
              same ? "same state hash" : "STATE DIFFERS");
}

// ---- Box2D 2.4.1 --------------------------------------------------------------------------

std::size_t box2dTouching(b2World& world) {
  std::size_t n = 0;
  for (b2Contact* c = world.GetContactList(); c != nullptr; c = c->GetNext())
    n += c->IsTouching() ? 1 : 0;
  return n;
}

bool box2dAnyAwake(b2World& world) {
  for (b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
    if (b->GetType() != b2_staticBody && b->IsAwake()) return true;
  return false;
}

Timing box2dPyramid(const Options& o, bool sleep = false) {
  b2World world(b2Vec2(0.0f, -10.0f));
  world.SetAllowSleeping(sleep);
  b2BodyDef gd;
  b2Body* ground = world.CreateBody(&gd);
  b2PolygonShape gs;
  gs.SetAsBox(200.0f, 0.5f, b2Vec2(0, -0.5f), 0.0f);
  ground->CreateFixture(&gs, 0.0f);
  b2PolygonShape box;
  box.SetAsBox(0.5f, 0.5f);
  for (int row = 0; row < o.rows; ++row) {
    for (int i = 0; i < o.rows - row; ++i) {
      b2BodyDef bd;
      bd.type = b2_dynamicBody;
      bd.position.Set(static_cast<float>(i) - 0.5f * static_cast<float>(o.rows - row - 1),
                      0.5f + static_cast<float>(row));
      b2FixtureDef fd;
      fd.shape = &box;
      fd.density = 1.0f;
      fd.friction = 0.6f;
      world.CreateBody(&bd)->CreateFixture(&fd);
    }
  }
  if (sleep) {
    for (int i = 0; i < 1200 && box2dAnyAwake(world); ++i)
      world.Step(1.0f / 60.0f, 8, 3);
    if (box2dAnyAwake(world)) std::fprintf(stderr, "world_bench: Box2D's pyramid did not sleep\n");
  }
  return timeSteps(
      o, [&] { world.Step(1.0f / 60.0f, 8, 3); }, [&] { return box2dTouching(world); });
}

void box2dAddPyramid(b2World& world, const b2PolygonShape& box, int rows, b2Vec2 base) {
  for (int row = 0; row < rows; ++row) {
    for (int i = 0; i < rows - row; ++i) {
      b2BodyDef bd;
      bd.type = b2_dynamicBody;
      bd.position.Set(base.x + static_cast<float>(i) - 0.5f * static_cast<float>(rows - row - 1),
                      base.y + 0.5f + static_cast<float>(row));
      b2FixtureDef fd;
      fd.shape = &box;
      fd.density = 1.0f;
      fd.friction = 0.6f;
      world.CreateBody(&bd)->CreateFixture(&fd);
    }
  }
}

Timing box2dMany(const Options& o) {
  b2World world(b2Vec2(0.0f, -10.0f));
  world.SetAllowSleeping(false);
  const float width = kManySpacing * kManyGrid;
  b2PolygonShape box;
  box.SetAsBox(0.5f, 0.5f);
  for (int r = 0; r < kManyGrid; ++r) {
    const float y = kManySpacing * static_cast<float>(r);
    b2BodyDef gd;
    b2Body* ground = world.CreateBody(&gd);
    b2EdgeShape gs;
    gs.SetTwoSided(b2Vec2(-kManySpacing, y), b2Vec2(width + kManySpacing, y));
    ground->CreateFixture(&gs, 0.0f);
    for (int c = 0; c < kManyGrid; ++c)
      box2dAddPyramid(world, box, kManyRows,
                      b2Vec2(kManySpacing * (static_cast<float>(c) + 0.5f), y));
  }
  return timeSteps(
      o, [&] { world.Step(1.0f / 60.0f, 8, 3); }, [&] { return box2dTouching(world); });
}

Timing box2dField(const Options& o, const std::vector<Piece>& pieces, int settleSteps) {
  b2World world(b2Vec2(0.0f, -10.0f));
  world.SetAllowSleeping(false);
  b2BodyDef gd;
  b2Body* ground = world.CreateBody(&gd);
  b2PolygonShape gs;
  gs.SetAsBox(32.0f, 0.5f, b2Vec2(0, -0.5f), 0.0f);
  ground->CreateFixture(&gs, 0.0f);
  gs.SetAsBox(0.5f, 40.0f, b2Vec2(-32.5f, 40), 0.0f);
  ground->CreateFixture(&gs, 0.0f);
  gs.SetAsBox(0.5f, 40.0f, b2Vec2(32.5f, 40), 0.0f);
  ground->CreateFixture(&gs, 0.0f);
  for (const Piece& p : pieces) {
    b2BodyDef bd;
    bd.type = b2_dynamicBody;
    bd.position.Set(p.position.x, p.position.y);
    bd.angle = p.angle;
    b2Body* body = world.CreateBody(&bd);
    float s = p.size;
    b2FixtureDef fd;
    fd.density = 1.0f;
    fd.friction = 0.6f;
    b2PolygonShape poly;
    b2CircleShape circle;
    switch (p.kind) {
      case 0:
        poly.SetAsBox(s, s);
        fd.shape = &poly;
        body->CreateFixture(&fd);
        break;
      case 1:
        circle.m_radius = s;
        fd.shape = &circle;
        body->CreateFixture(&fd);
        break;
      case 2: {
        // Box2D 2.4 has no capsule: a box and two circles on one body, as its users build one.
        poly.SetAsBox(s, 0.5f * s);
        fd.shape = &poly;
        body->CreateFixture(&fd);
        circle.m_radius = 0.5f * s;
        circle.m_p.Set(-s, 0);
        fd.shape = &circle;
        body->CreateFixture(&fd);
        circle.m_p.Set(s, 0);
        body->CreateFixture(&fd);
        break;
      }
      default: {
        b2Vec2 tri[3] = {{-s, -s}, {s, -s}, {0, s}};
        poly.Set(tri, 3);
        fd.shape = &poly;
        body->CreateFixture(&fd);
      }
    }
  }
  return timeSteps(
      o, [&] { world.Step(1.0f / 60.0f, 8, 3); }, [&] { return box2dTouching(world); },
      settleSteps);
}
#endif

int parseInt(const char* flag, const char* value) {
  char* end = nullptr;
  long v = std::strtol(value, &end, 10);
  if (end == value || *end != '\0' || v < 1 || v > 100000) {
    std::fprintf(stderr, "world_bench: %s needs an integer in 1..100000, got '%s'\n", flag, value);
    std::exit(2);
  }
  return static_cast<int>(v);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (i + 1 >= argc) {
      std::fprintf(stderr,
                   "world_bench: %s needs a value\nusage: world_bench [--rows N] [--field N] "
                   "[--steps N] [--warmup N]\n",
                   a.c_str());
      return 2;
    }
    if (a == "--rows")
      o.rows = parseInt("--rows", argv[++i]);
    else if (a == "--field")
      o.field = parseInt("--field", argv[++i]);
    else if (a == "--steps")
      o.steps = parseInt("--steps", argv[++i]);
    else if (a == "--warmup")
      o.warmup = parseInt("--warmup", argv[++i]);
    else if (a == "--workers") {
      o.workers = parseInt("--workers", argv[++i]);
      if (o.workers > kMaxWorkers) {
        std::fprintf(stderr, "world_bench: --workers must be 1..%d, got %d\n", kMaxWorkers,
                     o.workers);
        return 2;
      }
    } else if (a == "--scene")
      o.scene = argv[++i];
    else if (a == "--only")
      o.only = argv[++i];
    else {
      std::fprintf(stderr, "world_bench: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (o.scene == "scaling") {
    // Threads (docs/world.md, "Threads"): one worker against --workers (default 2).
    if (o.workers == 1) o.workers = 2;
    std::printf(
        "world_bench: threads, %d warm-up steps, then %d timed steps in turns; solver "
        "lanes: %s\n",
        o.warmup, o.steps, World::simdPath());
    quackScaling(o, ("pyramid " + std::to_string(o.rows) + " rows").c_str(), buildQuackPyramid);
    quackScaling(o, "many 20x20 pyramids", [](World& w, int) { buildQuackMany(w); });
    return 0;
  }
  if (!o.scene.empty() && o.scene != "pyramid" && o.scene != "sleep" && o.scene != "sleepers" &&
      o.scene != "bullets" && o.scene != "many" && o.scene != "rain" && o.scene != "field") {
    std::fprintf(stderr,
                 "world_bench: --scene must be pyramid, sleep, sleepers, bullets, many, rain, "
                 "field or scaling, got %s\n",
                 o.scene.c_str());
    return 2;
  }
  if (!o.only.empty() && o.only != "quack" && o.only != "box2d") {
    std::fprintf(stderr, "world_bench: --only must be quack or box2d, got %s\n", o.only.c_str());
    return 2;
  }
  const bool runQuack = o.only != "box2d";
#ifdef QUACK_BENCH_HAS_BOX2D
  const bool runBox2d = o.only != "quack";
#endif
  std::vector<Piece> pieces = makeField(o.field);
  std::printf(
      "world_bench: %d warm-up steps, then %d timed steps at 60 Hz; Box2D 2.4.1 on one "
      "thread, Quack on %d worker%s (--workers); Quack's solver lanes: %s\n",
      o.warmup, o.steps, o.workers, o.workers == 1 ? "" : "s", World::simdPath());
  std::printf("%-24s %14s %14s %10s\n", "scene", "library", "ms/step", "contacts");
  auto scene = [&](const std::string& name, const std::string& label, auto quackFn,
                   [[maybe_unused]] auto box2dFn) {
    if (!o.scene.empty() && o.scene != name) return;
    Timing q{}, b{};
    if (runQuack) {
      q = quackFn();
      std::printf("%-24s %14s %14.3f %10zu   (%d colours, %zu overflow)\n", label.c_str(), "quack",
                  q.msPerStep, q.contacts, gQuackSolver.colors, gQuackSolver.overflow);
    }
#ifdef QUACK_BENCH_HAS_BOX2D
    if (runBox2d) {
      b = box2dFn();
      std::printf("%-24s %14s %14.3f %10zu\n", runQuack ? "" : label.c_str(), "box2d 2.4.1",
                  b.msPerStep, b.contacts);
    }
    if (runQuack && runBox2d)
      std::printf("%-24s %14s %14.2fx\n", "", "box2d/quack", b.msPerStep / q.msPerStep);
#endif
  };
#ifdef QUACK_BENCH_HAS_BOX2D
#define QUACK_BOX2D(call) [&] { return call; }
#else
#define QUACK_BOX2D(call) 0
#endif
  scene(
      "pyramid", "pyramid " + std::to_string(o.rows) + " rows", [&] { return quackPyramid(o); },
      QUACK_BOX2D(box2dPyramid(o)));
  // Sleeping: the pyramid settled and asleep, against the same pyramid simulated in full and
  // against Box2D 2.4.1's pyramid asleep.
  if (o.scene.empty() || o.scene == "sleep") {
    const std::string label = "pyramid " + std::to_string(o.rows) + " asleep";
    const Timing awake = runQuack ? quackPyramid(o, false) : Timing{};
    const Timing asleep = runQuack ? quackPyramid(o, true) : Timing{};
    if (runQuack) {
      std::printf("%-24s %14s %14.4f %10zu\n", label.c_str(), "quack awake", awake.msPerStep,
                  awake.contacts);
      std::printf("%-24s %14s %14.4f %10zu   (%.2f%% of awake)\n", "", "quack asleep",
                  asleep.msPerStep, asleep.contacts, 100.0 * asleep.msPerStep / awake.msPerStep);
    }
#ifdef QUACK_BENCH_HAS_BOX2D
    if (runBox2d) {
      const Timing b = box2dPyramid(o, true);
      std::printf("%-24s %14s %14.4f %10zu\n", "", "box2d asleep", b.msPerStep, b.contacts);
      if (runQuack)
        std::printf("%-24s %14s %14.2fx\n", "", "box2d/quack", b.msPerStep / asleep.msPerStep);
    }
#endif
  }
  if (runQuack && (o.scene.empty() || o.scene == "sleepers")) {
    const Timing few = quackSleepers(o, false);
    const Timing many = quackSleepers(o, true);
    std::printf("%-24s %14s %14.4f %10zu\n", "100 moving", "quack", few.msPerStep, few.contacts);
    std::printf("%-24s %14s %14.4f %10zu   (%.2fx the 100 alone)\n", "+ 10000 asleep", "quack",
                many.msPerStep, many.contacts, many.msPerStep / few.msPerStep);
  }
  if (runQuack && (o.scene.empty() || o.scene == "bullets")) {
    const Timing with = quackBullets(o, true);
    const Timing without = quackBullets(o, false);
    std::printf("%-24s %14s %14.4f %10zu\n", "1000 bullets", "quack", with.msPerStep,
                with.contacts);
    std::printf("%-24s %14s %14.4f %10zu   (with / without: %.2fx)\n", "", "no continuous",
                without.msPerStep, without.contacts, with.msPerStep / without.msPerStep);
    // The same with 164 static boxes far away: the phase queries the broad phase.
    const Timing farWith = quackBullets(o, true, true);
    const Timing farWithout = quackBullets(o, false, true);
    std::printf("%-24s %14s %14.4f %10zu\n", "+ 164 far statics", "quack", farWith.msPerStep,
                farWith.contacts);
    std::printf("%-24s %14s %14.4f %10zu   (with / without: %.2fx)\n", "", "no continuous",
                farWithout.msPerStep, farWithout.contacts,
                farWith.msPerStep / farWithout.msPerStep);
  }
  scene(
      "many", "many 20x20 pyramids", [&] { return quackMany(o); }, QUACK_BOX2D(box2dMany(o)));
  scene(
      "rain", "rain " + std::to_string(o.field) + " shapes",
      [&] { return quackField(o, pieces, 0); }, QUACK_BOX2D(box2dField(o, pieces, 0)));
  scene(
      "field", "field " + std::to_string(o.field) + " shapes",
      [&] { return quackField(o, pieces, kFieldSettleSteps); },
      QUACK_BOX2D(box2dField(o, pieces, kFieldSettleSteps)));
#undef QUACK_BOX2D
#ifndef QUACK_BENCH_HAS_BOX2D
  std::printf("(Box2D 2.4.1 not built in: apt-get install libbox2d-dev and reconfigure)\n");
#endif
  return 0;
}
