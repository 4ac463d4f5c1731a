#pragma once
// Parallel work for the world's step (tasks.hpp; docs/world.md, "Threads").
//
// A job is a list of stages run in order; a stage is split into blocks that may run in any
// order and on any thread, and a stage starts only once every block of the one before has
// finished. Each of the job's participants (the calling thread is participant 0, the others
// run on the world's pool or through the game's enqueueTask) walks the stages itself: it
// claims blocks of the current stage, starting at its own share (so that the same
// participant tends to get the same blocks, and their data, every pass), takes what is left
// of the others' shares, then waits for the stage to finish. No participant waits for
// another to arrive, so a scheduler that runs a task late, or at once inside enqueueTask,
// only makes the job slower. One job per step phase: the solver's whole step (dozens of
// stages) costs one enqueue.
//
// Learned from Box2D v3's solver.c (stages of blocks, a start block per worker, workers
// spinning between stages); the claiming and the arrival-free waiting are our own.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

#include "quack/world/tasks.hpp"

namespace quack::detail {

// A world's worker count (workerCount, and whether the game's enqueueTask runs them), or
// the test suites' override (tasks.hpp, setTestWorkerCount) for a world left at one worker
// on its own pool. In world.cpp, for both worlds.
int effectiveWorkerCount(int workerCount, bool gameScheduler) noexcept;

/// Type-erased job handed to the participants.
struct Job {
  using ExecFn = void(void* context, int stage, int block, int participant);
  ExecFn* exec = nullptr;
  void* context = nullptr;
  int stageCount = 0;
  const int* blockCounts = nullptr;               // per stage
  const int* firstFlag = nullptr;                 // per stage: index of its first claim flag
  std::atomic<std::uint32_t>* claimed = nullptr;  // per block of every stage
  std::atomic<int>* finished = nullptr;           // per stage: blocks finished
  int participants = 1;
  // The first exception a block threw (an allocation failure: the phases throw nothing
  // else), kept so that the thread that started the job rethrows it once every participant
  // is done; a block that throws still counts as finished, so nobody waits for it forever.
  std::exception_ptr error;
  std::atomic<bool> failed{false};

  /// Walks every stage as `participant` (see above).
  void participate(int participant);
};

// A pool of threads for participants 1.. of a job; the thread that calls run is
// participant 0. Between jobs the threads spin a while (a step runs several jobs back to
// back), then yield, then sleep on a condition variable.
class TaskPool {
 public:
  explicit TaskPool(int workers);
  ~TaskPool();
  TaskPool(const TaskPool&) = delete;
  TaskPool& operator=(const TaskPool&) = delete;

  void run(Job& job);
  /// Threads it started (fewer than asked when the system refused some).
  int threadCount() const noexcept { return static_cast<int>(threads_.size()); }

 private:
  void workerLoop(int worker);

  std::vector<std::thread> threads_;
  std::atomic<Job*> job_{nullptr};
  std::atomic<bool> open_{false};  // threads may join job_
  std::atomic<int> inside_{0};     // threads that joined (or are deciding whether to)
  std::atomic<std::uint32_t> generation_{0};
  std::atomic<bool> quit_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
};

class TaskRunner {
 public:
  /// From the world's definition (checked by World::create).
  void configure(int workers, EnqueueTaskFn enqueue, FinishTaskFn finish, void* user);
  int workers() const noexcept { return workers_; }

  /// Runs exec(stage, block, participant) for every block of every stage, stage after
  /// stage. `participant` is below workers(): per-participant scratch may be indexed by
  /// it. With one worker the blocks simply run in order on this thread.
  template <class F>
  void runStages(const std::vector<int>& blockCounts, F&& exec) {
    // A job with no stage of two blocks or more has nothing to share: here, without waking
    // the other workers (a small world would otherwise pay their wake-up every job).
    bool shared = false;
    for (int n : blockCounts)
      shared = shared || n > 1;
    if (workers_ <= 1 || !shared) {
      runHere(blockCounts, exec);
      return;
    }
    using Fn = std::remove_reference_t<F>;
    Job job;
    job.exec = [](void* context, int stage, int block, int participant) {
      (*static_cast<Fn*>(context))(stage, block, participant);
    };
    job.context = const_cast<void*>(static_cast<const void*>(&exec));
    run(job, blockCounts);
  }

  /// f(begin, end, participant) over [0, count) in ranges of at least minRange items,
  /// about `perWorker` ranges per worker (see rangeSize).
  template <class F>
  void parallelFor(int count, int minRange, F&& f, int perWorker = kRangesPerWorker) {
    if (count <= 0) return;
    const int size = rangeSize(count, minRange, perWorker);
    if (size >= count) {
      f(0, count, 0);
      return;
    }
    blocks_.assign(1, (count + size - 1) / size);
    runStages(blocks_, [&](int, int block, int participant) {
      const int begin = block * size;
      f(begin, begin + size < count ? begin + size : count, participant);
    });
  }

  /// Ranges per worker of a stage of light work: more ranges balance the workers better at
  /// the stage's end, and cost a claim each.
  static constexpr int kRangesPerWorker = 4;
  /// Ranges per worker of a heavy stage (a tenth of a step or more: preparing constraints,
  /// updating manifolds, placing bodies), where the wait for the last range dominates: with
  /// few large ranges, the first worker to finish waits for the other to end its last one.
  /// Finer ranges shorten that wait for a claim each, which a heavy stage can afford
  /// (docs/world.md, "Threads").
  static constexpr int kHeavyRangesPerWorker = 16;

  /// Items per block for `count` items: `perWorker` blocks per worker, none below minRange.
  int rangeSize(int count, int minRange, int perWorker = kRangesPerWorker) const noexcept;

  /// Gathers items in order on the workers: f(begin, end, part) over [0, count) in ranges of
  /// rangeSize(count, minRange), each appending what it finds to its own part (reused from
  /// call to call), then the parts joined in range order into `out`. The result is what one
  /// pass over [0, count) would append, whatever the workers did.
  template <class T, class F>
  void gather(int count, int minRange, std::vector<std::vector<T>>& parts, std::vector<T>& out,
              F&& f) {
    out.clear();
    if (count <= 0) return;
    const int size = rangeSize(count, minRange);
    const int ranges = (count + size - 1) / size;
    if (ranges == 1) {
      f(0, count, out);
      return;
    }
    if (parts.size() < static_cast<std::size_t>(ranges))
      parts.resize(static_cast<std::size_t>(ranges));
    blocks_.assign(1, ranges);
    runStages(blocks_, [&](int, int block, int) {
      std::vector<T>& part = parts[static_cast<std::size_t>(block)];
      part.clear();
      const int begin = block * size;
      f(begin, begin + size < count ? begin + size : count, part);
    });
    std::size_t total = 0;
    for (int r = 0; r < ranges; ++r)
      total += parts[static_cast<std::size_t>(r)].size();
    out.reserve(total);
    for (int r = 0; r < ranges; ++r)
      out.insert(out.end(), parts[static_cast<std::size_t>(r)].begin(),
                 parts[static_cast<std::size_t>(r)].end());
  }

 private:
  void run(Job& job, const std::vector<int>& blockCounts);
  // One worker: every block in order, here. Never inlined, so that a profile of a
  // one-worker run shows what several workers would share (docs/world.md, "Threads").
  template <class F>
  [[gnu::noinline]] static void runHere(const std::vector<int>& blockCounts, F& exec) {
    const int stages = static_cast<int>(blockCounts.size());
    for (int s = 0; s < stages; ++s)
      for (int b = 0; b < blockCounts[static_cast<std::size_t>(s)]; ++b)
        exec(s, b, 0);
  }

  int workers_ = 1;
  EnqueueTaskFn enqueue_ = nullptr;
  FinishTaskFn finish_ = nullptr;
  void* user_ = nullptr;
  std::unique_ptr<TaskPool> pool_;
  // Claim flags and counters, reused from job to job.
  std::unique_ptr<std::atomic<std::uint32_t>[]> claimed_;
  std::size_t claimedSize_ = 0;
  std::unique_ptr<std::atomic<int>[]> finished_;
  std::size_t finishedSize_ = 0;
  std::vector<int> firstFlag_;
  std::vector<int> blocks_;
};

}  // namespace quack::detail
