// Parallel work for the world's step (task_runner.hpp).

#include "task_runner.hpp"

#include <algorithm>
#include <system_error>

namespace quack::detail {
namespace {

// A hint to the core that this thread is spinning.
inline void relax() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

// Spins before yielding the core while waiting for a stage, and (pool threads) for a job.
constexpr int kSpins = 2000;
// WebAssembly without threads (the web demo, the node build of quack): the pool would fail
// to start a thread (and exceptions are off there), so it is never made.
#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
constexpr bool kThreadsAvailable = false;
#else
constexpr bool kThreadsAvailable = true;
#endif
constexpr int kYields = 2000;

void backOff(int& spins) {
  if (++spins < kSpins) {
    relax();
  } else {
    std::this_thread::yield();
  }
}

}  // namespace

void Job::participate(int participant) {
  for (int s = 0; s < stageCount; ++s) {
    const int n = blockCounts[s];
    if (n == 0) continue;
    std::atomic<std::uint32_t>* flags = claimed + firstFlag[s];
    int done = 0;
    auto tryRun = [&](int b) {
      if (flags[b].load(std::memory_order_relaxed) != 0) return false;
      if (flags[b].exchange(1, std::memory_order_acquire) != 0) return false;
      try {
        exec(context, s, b, participant);
      } catch (...) {
        // Only the first is kept; the rest of the job still runs so the stages stay in step.
        if (!failed.exchange(true, std::memory_order_acq_rel)) error = std::current_exception();
      }
      ++done;
      return true;
    };
    // Own share first, forwards; then backwards from it; then whatever is left anywhere.
    const int start = static_cast<int>(static_cast<std::int64_t>(participant) * n / participants);
    for (int b = start; b < n && tryRun(b); ++b) {
    }
    for (int b = start - 1; b >= 0 && tryRun(b); --b) {
    }
    for (int b = 0; b < n; ++b)
      (void)tryRun(b);
    if (done != 0) finished[s].fetch_add(done, std::memory_order_release);
    int spins = 0;
    while (finished[s].load(std::memory_order_acquire) < n)
      backOff(spins);
  }
}

TaskPool::TaskPool(int workers) {
  // A thread that cannot be started (a WebAssembly build without threads, a process at its
  // limit) leaves the pool smaller: the work is shared by fewer workers, with the same bits.
  try {
    for (int w = 1; w < workers; ++w)
      threads_.emplace_back([this, w] { workerLoop(w); });
  } catch (const std::system_error&) {
  }
}

TaskPool::~TaskPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit_.store(true);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  for (std::thread& t : threads_)
    t.join();
}

void TaskPool::workerLoop(int worker) {
  std::uint32_t seen = 0;
  for (;;) {
    std::uint32_t gen;
    int spins = 0;
    while ((gen = generation_.load(std::memory_order_acquire)) == seen) {
      if (spins < kSpins + kYields) {
        backOff(spins);
      } else {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return generation_.load(std::memory_order_acquire) != seen; });
      }
    }
    seen = gen;
    if (quit_.load()) return;
    // Join the job only while it is open: the caller does not wait for a thread that has not
    // arrived (a sleeping thread's wake-up would cost every job of a small world tens of
    // microseconds). Entering, then reading `open_` (and the caller closing, then reading
    // `inside_`), both sequentially consistent, means that either this thread sees the job
    // closed or the caller sees it inside and waits for it.
    inside_.fetch_add(1);
    if (open_.load()) job_.load(std::memory_order_acquire)->participate(worker);
    inside_.fetch_sub(1, std::memory_order_release);
  }
}

void TaskPool::run(Job& job) {
  job_.store(&job, std::memory_order_relaxed);
  open_.store(true);
  {
    // Under the lock, so that a thread about to sleep sees the new generation or the
    // notification.
    std::lock_guard<std::mutex> lock(mutex_);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  job.participate(0);
  // Every block is done. The job lives on the caller's stack: close it, then wait for the
  // threads inside it to leave (a thread that arrives later sees it closed).
  open_.store(false);
  int spins = 0;
  while (inside_.load() != 0)
    backOff(spins);
}

void TaskRunner::configure(int workers, EnqueueTaskFn enqueue, FinishTaskFn finish, void* user) {
  workers_ = std::max(workers, 1);
  enqueue_ = enqueue;
  finish_ = finish;
  user_ = user;
  pool_.reset();
  if (workers_ > 1 && enqueue_ == nullptr && !kThreadsAvailable) workers_ = 1;
  if (workers_ > 1 && enqueue_ == nullptr) {
    pool_ = std::make_unique<TaskPool>(workers_);
    workers_ = pool_->threadCount() + 1;
    if (workers_ == 1) pool_.reset();
  }
}

int TaskRunner::rangeSize(int count, int minRange, int perWorker) const noexcept {
  const int blocks = std::max(1, perWorker * workers_);
  return std::max(std::max(minRange, 1), (count + blocks - 1) / blocks);
}

void TaskRunner::run(Job& job, const std::vector<int>& blockCounts) {
  const std::size_t stages = blockCounts.size();
  firstFlag_.resize(stages);
  std::size_t flags = 0;
  for (std::size_t s = 0; s < stages; ++s) {
    firstFlag_[s] = static_cast<int>(flags);
    flags += static_cast<std::size_t>(blockCounts[s]);
  }
  if (claimedSize_ < flags) {
    claimedSize_ = std::max(flags, 2 * claimedSize_);
    claimed_ = std::make_unique<std::atomic<std::uint32_t>[]>(claimedSize_);
  }
  if (finishedSize_ < stages) {
    finishedSize_ = std::max(stages, 2 * finishedSize_);
    finished_ = std::make_unique<std::atomic<int>[]>(finishedSize_);
  }
  for (std::size_t i = 0; i < flags; ++i)
    claimed_[i].store(0, std::memory_order_relaxed);
  for (std::size_t s = 0; s < stages; ++s)
    finished_[s].store(0, std::memory_order_relaxed);
  job.stageCount = static_cast<int>(stages);
  job.blockCounts = blockCounts.data();
  job.firstFlag = firstFlag_.data();
  job.claimed = claimed_.get();
  job.finished = finished_.get();
  job.participants = workers_;
  if (enqueue_ == nullptr) {
    pool_->run(job);
    if (job.failed.load(std::memory_order_acquire)) std::rethrow_exception(job.error);
    return;
  }
  // Participants 1.. through the game's scheduler, one item each; this thread is 0. The
  // enqueue publishes the job to the threads that run it.
  auto participant = [](int begin, int end, int, void* context) {
    for (int i = begin; i < end; ++i)
      static_cast<Job*>(context)->participate(i + 1);
  };
  void* handle = enqueue_(participant, workers_ - 1, 1, &job, user_);
  job.participate(0);
  if (handle != nullptr) finish_(handle, user_);
  if (job.failed.load(std::memory_order_acquire)) std::rethrow_exception(job.error);
}

}  // namespace quack::detail
