#include "check/worker_pool.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <optional>

#include "core/demand.h"

#if defined(__SANITIZE_THREAD__)
#include <sanitizer/tsan_interface.h>
#endif

namespace plumb {
namespace {

// ThreadSanitizer builds (make test-tsan) run the same TBB arena as every other build.
// Debian's oneTBB is not built with TSan, so two hand-overs inside libtbb are invisible to
// it: a job given to a TBB thread, and the end of parallel_for waiting for every job. Each
// is declared to TSan as a release and an acquire on one address; everything else (the
// jobs, their workers and what they share) is checked as it runs in production.
#if defined(__SANITIZE_THREAD__)
void HandOver(void* address) { __tsan_release(address); }
void TakeOver(void* address) { __tsan_acquire(address); }
#else
void HandOver(void*) {}
void TakeOver(void*) {}
#endif

// Declares a job's end to TSan however it ends (returning or throwing).
class JobEnd {
 public:
  explicit JobEnd(void* join) : join_(join) {}
  ~JobEnd() { HandOver(join_); }
  JobEnd(const JobEnd&) = delete;
  JobEnd& operator=(const JobEnd&) = delete;

 private:
  void* join_;
};

// One job on the worker of the thread that runs it: the worker is made on first use, and
// dropped when the job is abandoned (its copy may hold the job's edits) or throws (a MuJoCo
// error left it mid-job), so the next job on that thread starts from the nominal model.
void RunJob(const Model& nominal, std::optional<WorkerPool::Worker>& worker,
            const std::function<bool(WorkerPool::Worker&, std::size_t)>& run, std::size_t i,
            std::vector<char>* finished) {
  if (!worker) worker.emplace(nominal);
  bool done;
  try {
    done = run(*worker, i);
  } catch (...) {
    worker.reset();
    throw;
  }
  if (!done) worker.reset();
  (*finished)[i] = done ? 1 : 0;
}

}  // namespace

struct WorkerPool::Impl {
  const Model& nominal;
  int threads;
  tbb::task_arena arena;
  tbb::enumerable_thread_specific<std::optional<Worker>> workers;
  Impl(const Model& m, int n) : nominal(m), threads(n), arena(n) {}
};

WorkerPool::WorkerPool(const Model& nominal, int threads) {
  PLUMB_DEMAND(threads >= 1);  // sweep, rollout and identify validate their thread counts
  impl_ = std::make_unique<Impl>(nominal, threads);
}

WorkerPool::~WorkerPool() = default;

int WorkerPool::threads() const { return impl_->threads; }

void WorkerPool::RunChunk(std::size_t n, const std::function<bool(Worker&, std::size_t)>& run,
                          std::vector<char>* finished) {
  Impl& p = *impl_;
  char fork = 0, join = 0;  // addresses the TSan hand-overs are declared on
  HandOver(&fork);
  try {
    p.arena.execute([&] {
      tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
        TakeOver(&fork);
        JobEnd end(&join);
        RunJob(p.nominal, p.workers.local(), run, i, finished);
      });
    });
  } catch (...) {
    TakeOver(&join);  // a job threw: TBB carried its exception across threads
    throw;
  }
  TakeOver(&join);
}

}  // namespace plumb
