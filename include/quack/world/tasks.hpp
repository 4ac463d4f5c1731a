#pragma once
/// Running a world's step on several threads (docs/world.md, "Threads"). A game that has a
/// job system hands the world two callbacks, as Box2D v3 and Jolt take them: one to start a
/// task over a range of items, one to wait for it. Without them the world uses a small
/// pool of its own (std::thread) when WorldDef::workerCount is above 1. The result is the
/// same to the bit whatever the number of workers: the work is split so that no two items
/// write the same data, and everything whose order matters is merged in item order.

namespace quack {

/// Most workers a world takes (WorldDef::workerCount).
inline constexpr int kMaxWorkers = 64;

/// Items [begin, end) of a task, run by `worker` (0 .. workerCount - 1). No two ranges of
/// one task run with the same worker index at the same time: the world keeps per-worker
/// scratch space under that index.
using TaskFn = void(int begin, int end, int worker, void* taskContext);

/// Starts `task` over `itemCount` items, split into ranges of at least `minRange` items
/// (the last may be shorter), each passed to `task` with a worker index, in any order and
/// on any threads. Returns a handle for FinishTaskFn, or nullptr when every range has
/// already run. `userContext` is WorldDef::userTaskContext.
using EnqueueTaskFn = void* (*)(TaskFn* task, int itemCount, int minRange, void* taskContext,
                                void* userContext);

/// Waits until every range of the task behind `userTask` has run.
using FinishTaskFn = void (*)(void* userTask, void* userContext);

namespace detail {
/// For Quack's own test suites (QUACK_TEST_WORKERS, tests/world/test_workers.cpp): worlds
/// created from then on with one worker and no task callbacks get `workers` instead, so
/// that every world test can run on the pool, under ThreadSanitizer too. 0 or 1 turns it
/// off. Not for games: set WorldDef::workerCount.
void setTestWorkerCount(int workers) noexcept;
/// For Quack's own tests: when true, the solver prepares every contact from the contact
/// and body records, as it does for a contact the step's narrow phase did not update,
/// instead of from the narrow phase's compact record; the two must give the same bits.
void setTestSolverReadsRecords(bool on) noexcept;
/// For Quack's own tests: when true, the solver solves every joint one at a time, plain
/// revolute joints too, which it otherwise solves in lanes; the two must give the same bits.
void setTestJointsOneAtATime(bool on) noexcept;
}  // namespace detail

}  // namespace quack
