// Threads (docs/world.md, "Threads"): the same bits on any number of workers, with the
// world's own pool or a game's scheduler, and bad settings refused by name.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <future>
#include <random>
#include <string>
#include <vector>

#include "quack/world/world.hpp"
#include "world_test_util.hpp"

namespace quack {
namespace {

using testing::addPyramid;
using testing::addStaticBox;

// A random scene of 2,000 mixed shapes with sleeping on: a pyramid, then circles, boxes,
// capsules, hexagons, a few sensors and bullets raining into a walled box, a few thousand
// contacts in several colours, and bodies falling asleep and waking.
void buildScene(World& world) {
  addStaticBox(world, {0, -0.5f}, {40, 0.5f});
  addStaticBox(world, {-40.5f, 30}, {0.5f, 30});
  addStaticBox(world, {40.5f, 30}, {0.5f, 30});
  (void)addPyramid(world, 20);  // 210 boxes
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<Vec2> hexagon;
  for (int k = 0; k < 6; ++k)
    hexagon.push_back(0.35f * Vec2{std::cos(1.0471976f * static_cast<float>(k)),
                                   std::sin(1.0471976f * static_cast<float>(k))});
  const Polygon hex = makePolygon(hexagon).value();
  for (int i = 0; i < 1790; ++i) {
    const Vec2 p{-38 + 76 * u(rng), 22 + 60 * u(rng)};
    BodyId b = world
                   .createBody({.position = p,
                                .angle = 3 * u(rng),
                                .linearVelocity = {8 * u(rng) - 4, -10 * u(rng)},
                                .bullet = i % 97 == 0})
                   .value();
    const ShapeDef def{.restitution = i % 5 == 0 ? 0.5f : 0.0f};
    testing::addMixedShape(
        world, b, def, i, [&] { return u(rng); }, hex);
    if (i % 150 == 0) (void)world.createShape(b, {.sensor = true}, makeCircle({}, 1.0f).value());
  }
}

// Every field of every event of a step, folded into one number (FNV-1a over the bits).
std::uint64_t eventDigest(const StepEvents& e) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](std::uint64_t v) {
    for (int k = 0; k < 8; ++k) {
      h ^= (v >> (8 * k)) & 0xffu;
      h *= 1099511628211ull;
    }
  };
  auto mixF = [&](float f) { mix(std::bit_cast<std::uint32_t>(f)); };
  auto mixId = [&](ShapeId id) { mix((std::uint64_t{id.index} << 32) | id.generation); };
  for (const auto& x : e.begin) {
    mixId(x.shapeA);
    mixId(x.shapeB);
  }
  mix(0xb1);
  for (const auto& x : e.end) {
    mixId(x.shapeA);
    mixId(x.shapeB);
  }
  mix(0xe2);
  for (const auto& x : e.hit) {
    mixId(x.shapeA);
    mixId(x.shapeB);
    mixF(x.point.x);
    mixF(x.point.y);
    mixF(x.normal.x);
    mixF(x.normal.y);
    mixF(x.approachSpeed);
  }
  mix(0x43);
  for (const auto* list : {&e.sensorBegin, &e.sensorEnd}) {
    for (const auto& x : *list) {
      mixId(x.sensor);
      mixId(x.visitor);
    }
    mix(0x5e);
  }
  for (const auto& x : e.toi) {
    mixF(x.time);
    mixId(x.shapeA);
    mixId(x.shapeB);
    mixF(x.point.x);
    mixF(x.point.y);
  }
  return h;
}

struct Trace {
  std::vector<std::uint64_t> hashes, events;
  std::size_t eventCount = 0, asleep = 0;
};

Trace run(WorldDef def, int steps) {
  World world = World::create(def).value();
  buildScene(world);
  Trace t;
  for (int s = 0; s < steps; ++s) {
    EXPECT_TRUE(world.step().ok());
    t.hashes.push_back(world.stateHash());
    t.events.push_back(eventDigest(world.events()));
    const StepEvents& e = world.events();
    t.eventCount += e.begin.size() + e.end.size() + e.hit.size() + e.sensorBegin.size() +
                    e.sensorEnd.size() + e.toi.size();
  }
  t.asleep = world.bodyCount() - world.awakeBodyCount();
  EXPECT_TRUE(testing::valid(world));
  return t;
}

TEST(Threads, SameBitsAndEventsOnAnyNumberOfWorkers) {
  constexpr int kSteps = 240;
  const Trace one = run({.workerCount = 1}, kSteps);
  // The scene does what it is here for: events, and some bodies asleep by the end.
  EXPECT_GT(one.eventCount, 2000u);
  EXPECT_GT(one.asleep, 0u);
  for (int workers : {2, 3, 4, 8}) {
    SCOPED_TRACE("workers " + std::to_string(workers));
    const Trace many = run({.workerCount = workers}, kSteps);
    for (int s = 0; s < kSteps; ++s) {
      ASSERT_EQ(many.hashes[s], one.hashes[s]) << "parts at step " << s + 1;
      ASSERT_EQ(many.events[s], one.events[s]) << "events part at step " << s + 1;
    }
  }
}

// A game's scheduler: each range of a task on its own std::async thread, the worker index
// being the range's position (a game's job system would give its thread's index).
struct AsyncScheduler {
  std::vector<std::future<void>> running;
  int calls = 0;
};

void* enqueueAsync(TaskFn* task, int itemCount, int minRange, void* taskContext, void* user) {
  auto* scheduler = static_cast<AsyncScheduler*>(user);
  ++scheduler->calls;
  constexpr int kWorkers = 3;
  const int range = std::max(minRange, (itemCount + kWorkers - 1) / kWorkers);
  auto* batch = new std::vector<std::future<void>>;
  int worker = 0;
  for (int begin = 0; begin < itemCount; begin += range, ++worker) {
    const int end = std::min(itemCount, begin + range);
    batch->push_back(
        std::async(std::launch::async, [=] { task(begin, end, worker, taskContext); }));
  }
  return batch;
}

void finishAsync(void* userTask, void*) {
  auto* batch = static_cast<std::vector<std::future<void>>*>(userTask);
  for (auto& f : *batch)
    f.get();
  delete batch;
}

TEST(Threads, AGamesSchedulerRunsTheWork) {
  constexpr int kSteps = 120;
  const Trace one = run({.workerCount = 1}, kSteps);
  AsyncScheduler scheduler;
  const Trace game = run({.workerCount = 3,
                          .enqueueTask = enqueueAsync,
                          .finishTask = finishAsync,
                          .userTaskContext = &scheduler},
                         kSteps);
  EXPECT_GT(scheduler.calls, kSteps);  // the work went through it
  for (int s = 0; s < kSteps; ++s) {
    ASSERT_EQ(game.hashes[s], one.hashes[s]) << "parts at step " << s + 1;
    ASSERT_EQ(game.events[s], one.events[s]) << "events part at step " << s + 1;
  }
}

TEST(Threads, WorkerCountIsWhatWasAsked) {
  EXPECT_EQ(World::create({.workerCount = 3}).value().workerCount(), 3);
  // The test-suite hook (QUACK_TEST_WORKERS) changes only single-worker worlds without
  // callbacks.
  const char* env = std::getenv("QUACK_TEST_WORKERS");
  const int before = env != nullptr ? std::atoi(env) : 0;
  detail::setTestWorkerCount(4);
  EXPECT_EQ(World::create({}).value().workerCount(), 4);
  EXPECT_EQ(World::create({.workerCount = 2}).value().workerCount(), 2);
  detail::setTestWorkerCount(0);
  EXPECT_EQ(World::create({}).value().workerCount(), 1);
  detail::setTestWorkerCount(before);
  EXPECT_EQ(World::create({}).value().workerCount(), before > 1 ? before : 1);
}

// A restored world keeps its own workers, and continues as a one-worker world would.
TEST(Threads, RestoreKeepsTheWorldsWorkers) {
  World one = World::create({.workerCount = 1}).value();
  World three = World::create({.workerCount = 3}).value();
  buildScene(one);
  buildScene(three);
  for (int s = 0; s < 30; ++s) {
    ASSERT_TRUE(one.step().ok());
    ASSERT_TRUE(three.step().ok());
  }
  const std::vector<std::uint8_t> bytes = one.snapshot().value();
  for (int s = 0; s < 20; ++s)
    ASSERT_TRUE(three.step().ok());  // diverge, then go back to `one`'s state
  ASSERT_TRUE(three.restore(bytes).ok());
  EXPECT_EQ(three.workerCount(), 3);
  for (int s = 0; s < 60; ++s) {
    ASSERT_TRUE(one.step().ok());
    ASSERT_TRUE(three.step().ok());
    ASSERT_EQ(three.stateHash(), one.stateHash()) << "step " << s + 1 << " after restore";
  }
}

TEST(Threads, BadSettingsAreRefusedByName) {
  for (int workers : {0, -1, kMaxWorkers + 1}) {
    Result<World> w = World::create({.workerCount = workers});
    ASSERT_FALSE(w.ok());
    EXPECT_NE(w.error().message.find("workerCount"), std::string::npos) << w.error().message;
  }
  Result<World> half = World::create({.enqueueTask = enqueueAsync});
  ASSERT_FALSE(half.ok());
  EXPECT_NE(half.error().message.find("finishTask"), std::string::npos) << half.error().message;
  Result<World> otherHalf = World::create({.finishTask = finishAsync});
  ASSERT_FALSE(otherHalf.ok());
  EXPECT_NE(otherHalf.error().message.find("enqueueTask"), std::string::npos);
  EXPECT_TRUE(World::create({.workerCount = kMaxWorkers}).ok());
}

}  // namespace
}  // namespace quack
