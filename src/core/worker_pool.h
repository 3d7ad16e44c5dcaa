// The one worker pool of sweep and rollout: a TBB arena of `threads`, and per thread a copy
// of the nominal model with its data, made on first use and kept for every job that thread
// runs. Jobs run a chunk at a time and their results are handed on in job order as soon as
// they and every job before them are done, so output streams in order and memory stays
// flat, and a stop request keeps what finished before it.

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

namespace plumb {

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
  // replaced, and so is the worker of a job that throws; the exception then leaves Stream.
  template <typename Result>
  using Job = std::function<bool(Worker& worker, long index, Result* result)>;

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
  // are done (so with one thread each result is emitted before the next job starts). Between
  // chunks it looks at `stop`: when asked, or when a job was abandoned, it throws what
  // `interrupted` makes, after emitting every result before the first unfinished job.
  template <typename Result>
  void Stream(std::size_t chunk, const std::function<void(std::vector<long>*)>& next_chunk,
              const Job<Result>& job, const std::function<void(const Result&)>& emit,
              const StopToken& stop, const std::function<Interrupted()>& interrupted) {
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
          &finished, emit_ready);
      emit_ready();
      if (emitted < indices.size()) throw interrupted();  // the results before it were emitted
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
  // true; calls `after_own_job` on the calling thread after each job that thread ran.
  void RunChunk(std::size_t n, const std::function<bool(Worker&, std::size_t)>& run,
                Finished* finished, const std::function<void()>& after_own_job);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace plumb

#endif  // PLUMB_SRC_CORE_WORKER_POOL_H_
