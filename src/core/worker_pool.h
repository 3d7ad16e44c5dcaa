// The one worker pool of sweep and rollout: a TBB arena of `threads`, and per thread a copy
// of the nominal model with its data, made on first use and kept for every job that thread
// runs. Jobs run a chunk at a time and their results are handed on in job order as soon as
// they and every job before them are done, so output streams in order and memory stays
// flat. A stop request is honoured at once: the jobs not yet started are skipped (no worker
// is made for them), the running ones end at their next step, and what finished is kept.

#ifndef PLUMB_SRC_CORE_WORKER_POOL_H_
#define PLUMB_SRC_CORE_WORKER_POOL_H_

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "plumb/error.h"
#include "plumb/model.h"
#include "plumb/stop.h"

namespace plumb::internal {

// The threads a call asked for, or one per core when it asked for 0 (at least 1): what an
// options struct's `threads = 0` means everywhere.
int ThreadsOrAllCores(int threads);

class WorkerPool {
 public:
  // What each thread works with: its own copy of the nominal model and a data for it.
  struct Worker {
    Model work;
    Data data;
    explicit Worker(const Model& nominal) : work(nominal.Clone()), data(work) {}
  };

  // A job runs `index` on `worker`, writing its result; it returns false when a stop request
  // abandoned it. An abandoned job's worker (its model copy may hold the job's edits) is
  // dropped and made again only when its thread next runs a job (never during a stop), and
  // so is the worker of a job that throws; the exception then leaves Stream.
  template <typename Result>
  using Job = std::function<bool(Worker& worker, long index, Result* result)>;

  // What a stop hands on of a chunk's results besides those before its first unfinished job.
  enum class OnStop {
    kInOrderOnly,    // nothing more: `emit` may count on every result coming in job order
    kEveryFinished,  // then every other finished one, in job order with gaps: each result
                     // must name its own job (a rollout's or a sweep case's index)
  };

  // `threads` must be at least 1 (else plumb::InternalError: the callers validate it).
  WorkerPool(const Model& nominal, int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const;

  // Runs the jobs `next_chunk` hands out (it fills the empty vector it is given with the next
  // up to `chunk` indices, none when all are done), each chunk in parallel, and passes their
  // results to `emit` in index order, on the calling thread: the calling thread runs jobs
  // too, and after each of its own it emits every result whose job and all jobs before it
  // are done (so with one thread each result is emitted before the next job starts). A job
  // that has not started when `stop` is asked is skipped; between chunks Stream looks at
  // `stop` too. When asked, or when a job was abandoned, it throws what `interrupted` makes,
  // after emitting every result before the first unfinished job and, with
  // OnStop::kEveryFinished, the finished ones after it.
  template <typename Result>
  void Stream(std::size_t chunk, const std::function<void(std::vector<long>*)>& next_chunk,
              const Job<Result>& job, const std::function<void(const Result&)>& emit,
              const StopToken& stop, const std::function<Interrupted()>& interrupted,
              OnStop on_stop = OnStop::kInOrderOnly) {
    std::vector<long> indices;
    std::vector<Result> results;
    while (true) {
      if (stop.stop_requested()) throw interrupted();
      indices.clear();
      indices.reserve(chunk);
      next_chunk(&indices);
      if (indices.empty()) return;
      results.assign(indices.size(), Result{});
      Finished finished(indices.size());
      std::size_t emitted = 0;
      auto emit_ready = [&] {
        for (; emitted < indices.size() && finished.done(emitted); ++emitted) {
          emit(results[emitted]);
        }
      };
      RunChunk(
          indices.size(),
          [&](Worker& worker, std::size_t i) { return job(worker, indices[i], &results[i]); },
          &finished, emit_ready, stop);
      emit_ready();
      if (emitted == indices.size()) continue;
      // stopped: the results before the first unfinished job were emitted
      for (std::size_t i = emitted; on_stop == OnStop::kEveryFinished && i < indices.size(); ++i) {
        if (finished.done(i)) emit(results[i]);
      }
      throw interrupted();
    }
  }

 private:
  // Which jobs of a chunk returned true: set by the thread that ran the job (after its
  // result), read by the calling thread.
  class Finished {
   public:
    explicit Finished(std::size_t n) : flags_(n) {}
    void Set(std::size_t i) { flags_[i].store(true, std::memory_order_release); }
    bool done(std::size_t i) const { return flags_[i].load(std::memory_order_acquire); }

   private:
    std::vector<std::atomic<bool>> flags_;
  };

  // Runs run(worker, i) for i in [0, n) on the arena and marks in `finished` which returned
  // true; calls `after_own_job` on the calling thread after each job that thread ran. Once
  // `stop` is asked the jobs not started are skipped: no worker is made for them.
  void RunChunk(std::size_t n, const std::function<bool(Worker&, std::size_t)>& run,
                Finished* finished, const std::function<void()>& after_own_job,
                const StopToken& stop);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_WORKER_POOL_H_
