// A game's job system running Quack's step: oneTBB (Debian libtbb-dev) through
// WorldDef::enqueueTask and finishTask (quack/world/tasks.hpp, docs/world.md "Threads").
// It steps a pyramid on TBB's threads beside the same pyramid on one thread and checks,
// step by step, that both have the same state hash. Exits 1 if they ever differ.

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cstdio>

#include "quack/quack.hpp"

namespace {

// enqueueTask: the items split into ranges, each a TBB task; the handle is the group.
void* enqueue(quack::TaskFn* task, int itemCount, int minRange, void* taskContext, void*) {
  auto* group = new tbb::task_group;
  const int ranges = std::max(1, itemCount / std::max(minRange, 1));
  const int size = (itemCount + ranges - 1) / ranges;
  for (int begin = 0; begin < itemCount; begin += size) {
    const int end = std::min(itemCount, begin + size);
    group->run([=] {
      // TBB's index of this thread: no two threads of the arena share one.
      task(begin, end, tbb::this_task_arena::current_thread_index(), taskContext);
    });
  }
  return group;
}

// finishTask: wait for the group (this thread may run some of its tasks meanwhile).
void finish(void* userTask, void*) {
  auto* group = static_cast<tbb::task_group*>(userTask);
  group->wait();
  delete group;
}

void buildPyramid(quack::World& world, int rows) {
  quack::BodyId ground = world.createBody({.type = quack::BodyType::staticBody}).value();
  (void)world.createShape(ground, {}, quack::makeBox(60.0f, 1.0f).value());
  const quack::Polygon box = quack::makeBox(0.5f, 0.5f).value();
  for (int row = 0; row < rows; ++row) {
    for (int i = 0; i < rows - row; ++i) {
      const float x = (static_cast<float>(i) - 0.5f * static_cast<float>(rows - row - 1)) * 1.0f;
      const float y = 1.5f + static_cast<float>(row) * 1.0f;
      quack::BodyId b = world.createBody({.position = {x, y}}).value();
      (void)world.createShape(b, {}, box);
    }
  }
}

}  // namespace

int main() {
  const int workers = std::clamp(tbb::info::default_concurrency(), 2, quack::kMaxWorkers);
  quack::World alone = quack::World::create({}).value();
  quack::World shared =
      quack::World::create({.workerCount = workers, .enqueueTask = enqueue, .finishTask = finish})
          .value();
  constexpr int kRows = 30;
  buildPyramid(alone, kRows);
  buildPyramid(shared, kRows);
  constexpr int kSteps = 240;
  for (int step = 1; step <= kSteps; ++step) {
    if (!alone.step().ok() || !shared.step().ok()) {
      std::printf("a step failed\n");
      return 1;
    }
    if (alone.stateHash() != shared.stateHash()) {
      std::printf("step %d: the TBB world (%d workers) differs from the one-thread world\n", step,
                  workers);
      return 1;
    }
  }
  std::printf(
      "%d steps of a %d-row pyramid on %d TBB workers: state hash %016llx, the same "
      "as on one thread at every step\n",
      kSteps, kRows, workers, static_cast<unsigned long long>(shared.stateHash()));
  return 0;
}
