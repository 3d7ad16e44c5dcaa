#include "core/worker_pool.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

#include "core/demand.h"

namespace plumb::internal {

int ThreadsOrAllCores(int threads) {
  return threads > 0 ? threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

namespace {

// One job on the worker of the thread that runs it, unless a stop was asked before it began:
// then it is skipped, without a worker. The worker is made on first use, and dropped when
// the job is abandoned (its copy may hold the job's edits) or throws (a MuJoCo error left it
// mid-job), so the next job on that thread, if any, makes a fresh one from the nominal model:
// a stop makes no model copy.
template <typename Finished>
void RunJob(const Model& nominal, std::optional<WorkerPool::Worker>& worker,
            const std::function<bool(WorkerPool::Worker&, std::size_t)>& run, std::size_t i,
            Finished* finished, const StopToken& stop) {
  if (stop.stop_requested()) return;  // not finished: Stream sees the stop

  MujocoCallScope scope;  // MuJoCo's errors on this thread are plumb's
  if (!worker) worker.emplace(nominal);
  bool done;
  try {
    done = run(*worker, i);
  } catch (...) {
    worker.reset();
    throw;
  }
  if (done) {
    finished->Set(i);
  } else {
    worker.reset();
  }
}

}  // namespace

struct WorkerPool::Impl {
  const Model& nominal;
  int threads;
#if !defined(__SANITIZE_THREAD__)
  tbb::task_arena arena;
  tbb::enumerable_thread_specific<std::optional<Worker>> workers;
  Impl(const Model& m, int n) : nominal(m), threads(n), arena(n) {}
#else
  std::vector<std::optional<Worker>> slots;  // one per std::thread (see RunChunk)
  Impl(const Model& m, int n) : nominal(m), threads(n), slots(n) {}
#endif
};

WorkerPool::WorkerPool(const Model& nominal, int threads) {
  PLUMB_DEMAND(threads >= 1);  // sweep, rollout and identify validate their thread counts
  impl_ = std::make_unique<Impl>(nominal, threads);
}

WorkerPool::~WorkerPool() = default;

int WorkerPool::threads() const { return impl_->threads; }

#if !defined(__SANITIZE_THREAD__)

void WorkerPool::RunChunk(std::size_t n, const std::function<bool(Worker&, std::size_t)>& run,
                          Finished* finished, const std::function<void()>& after_own_job,
                          const StopToken& stop) {
  Impl& p = *impl_;
  const std::thread::id caller = std::this_thread::get_id();
  // the calling thread takes a slot of the arena (one is kept for it) and runs jobs too
  p.arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      RunJob(p.nominal, p.workers.local(), run, i, finished, stop);
      if (std::this_thread::get_id() == caller) after_own_job();
    });
  });
}

#else

// ThreadSanitizer builds (make test-tsan) run each chunk on std::threads, which TSan follows,
// instead of the TBB arena: Debian's oneTBB is not built with TSan, so the fork and join
// inside libtbb are invisible to it and every job would be reported as racing with the
// thread that set it up. The jobs, their workers and everything they share are the same.
// Declaring the fork and the join to TSan (__tsan_release and __tsan_acquire around each job)
// is not enough: parallel_for's task tree, inlined from oneTBB's headers into plumb, is written
// by one thread and read by another through libtbb's queues (tried: races reported in
// start_for, tree_node and fold_tree). Checking the arena itself needs a oneTBB built with TSan.
void WorkerPool::RunChunk(std::size_t n, const std::function<bool(Worker&, std::size_t)>& run,
                          Finished* finished, const std::function<void()>& after_own_job,
                          const StopToken& stop) {
  Impl& p = *impl_;
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto thread_body = [&](int slot) {
    for (std::size_t i; (i = next++) < n;) {
      try {
        RunJob(p.nominal, p.slots[slot], run, i, finished, stop);
        if (slot == 0) after_own_job();  // slot 0 is the calling thread
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next = n;  // no further jobs
      }
    }
  };
  std::vector<std::thread> threads;
  for (int slot = 1; slot < p.threads; ++slot) threads.emplace_back(thread_body, slot);
  thread_body(0);
  for (std::thread& t : threads) t.join();
  if (error) std::rethrow_exception(error);
}

#endif

}  // namespace plumb::internal
