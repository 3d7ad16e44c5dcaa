// The worker pool of sweep, rollout and identify, on the path production runs (a oneTBB
// arena; make test-tsan runs these under ThreadSanitizer too).

#include "core/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/stop.h"

namespace plumb {
using internal::WorkerPool;

namespace {

using WorkerPoolTest = testing::MujocoTest;

// A job that steps its worker's pendulum from an angle of its own and returns where it got:
// every worker's data is written by the jobs on its thread only.
bool Swing(WorkerPool::Worker& w, long index, double* q) {
  mj_resetData(w.work.get(), w.data.get());
  w.data->qpos[0] = 0.01 * static_cast<double>(index);
  for (int k = 0; k < 50; ++k) mj_step(w.work.get(), w.data.get());
  *q = w.data->qpos[0];
  return true;
}

std::vector<double> SwingAll(const Model& model, int threads, long jobs) {
  WorkerPool pool(model, threads);
  long next = 0;
  std::vector<double> out;
  pool.Stream<double>(
      8,
      [&](std::vector<long>* chunk) {
        for (; next < jobs && chunk->size() < 8; ++next) chunk->push_back(next);
      },
      Swing, [&](const double& q) { out.push_back(q); }, StopToken(),
      [] { return Interrupted("stopped"); });
  return out;
}

TEST_F(WorkerPoolTest, ResultsComeInJobOrderTheSameForAnyThreadCount) {
  Model model = Model::Load(testing::kPendulum);
  std::vector<double> one = SwingAll(model, 1, 100), two = SwingAll(model, 2, 100);
  ASSERT_EQ(one.size(), 100u);
  EXPECT_EQ(one, two);
  EXPECT_NE(one[0], one[99]);
}

TEST_F(WorkerPoolTest, AJobsExceptionLeavesAfterTheResultsBeforeItsChunk) {
  Model model = Model::Load(testing::kPendulum);
  WorkerPool pool(model, 2);
  long next = 0;
  std::vector<long> emitted;
  WorkerPool::Job<long> job = [](WorkerPool::Worker&, long index, long* out) {
    if (index == 21) throw ValueError("job 21 failed");
    *out = index;
    return true;
  };
  EXPECT_THROW(pool.Stream<long>(
                   8,
                   [&](std::vector<long>* chunk) {
                     for (; next < 40 && chunk->size() < 8; ++next) chunk->push_back(next);
                   },
                   job, [&](const long& i) { emitted.push_back(i); }, StopToken(),
                   [] { return Interrupted("stopped"); }),
               ValueError);
  // the two chunks before the one that failed, and of its own chunk at most the results
  // before job 21
  ASSERT_GE(emitted.size(), 16u);
  ASSERT_LE(emitted.size(), 21u);
  for (std::size_t i = 0; i < emitted.size(); ++i) EXPECT_EQ(emitted[i], static_cast<long>(i));
  // the pool goes on working after a job threw (its worker was replaced)
  next = 0;
  std::vector<long> again;
  pool.Stream<long>(
      8,
      [&](std::vector<long>* chunk) {
        for (; next < 8 && chunk->size() < 8; ++next) chunk->push_back(next);
      },
      job, [&](const long& i) { again.push_back(i); }, StopToken(),
      [] { return Interrupted("stopped"); });
  EXPECT_EQ(again.size(), 8u);
}

// Results stream: each is emitted, on the calling thread, once it and every job before it are
// done, not when its whole chunk is. With one thread that is before the next job starts.
TEST_F(WorkerPoolTest, ResultsStreamOnTheCallingThreadAsTheyFinish) {
  Model model = Model::Load(testing::kPendulum);
  for (int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    WorkerPool pool(model, threads);
    std::atomic<long> started{0};
    long next = 0;
    std::vector<long> started_at_emit;
    bool on_caller = true;
    const std::thread::id caller = std::this_thread::get_id();
    WorkerPool::Job<long> job = [&](WorkerPool::Worker&, long index, long* out) {
      ++started;
      *out = index;
      return true;
    };
    pool.Stream<long>(
        64,
        [&](std::vector<long>* chunk) {
          for (; next < 64 && chunk->size() < 64; ++next) chunk->push_back(next);
        },
        job,
        [&](const long&) {
          started_at_emit.push_back(started.load());
          on_caller = on_caller && std::this_thread::get_id() == caller;
        },
        StopToken(), [] { return Interrupted("stopped"); });
    ASSERT_EQ(started_at_emit.size(), 64u);
    EXPECT_TRUE(on_caller);
    // with two threads, when a result leaves depends on how the jobs were shared
    if (threads == 1) {
      for (long i = 0; i < 64; ++i) EXPECT_EQ(started_at_emit[i], i + 1) << "result " << i;
    }
  }
}

// A stop asked in the middle of a chunk: the jobs not started are skipped (no worker is made
// for them, and no job runs), the running ones end, and with OnStop::kEveryFinished every
// job that finished is emitted, those after the first unfinished one last.
TEST_F(WorkerPoolTest, AStopSkipsTheJobsNotStartedAndEmitsEveryFinishedOne) {
  Model model = Model::Load(testing::kPendulum);
  for (auto on_stop : {WorkerPool::OnStop::kEveryFinished, WorkerPool::OnStop::kInOrderOnly}) {
    WorkerPool pool(model, 2);
    StopSource stop;
    std::atomic<long> calls{0};
    std::vector<std::atomic<bool>> done(64);
    WorkerPool::Job<long> job = [&](WorkerPool::Worker&, long index, long* out) {
      if (++calls == 6) {  // the sixth job to start asks to stop and is abandoned
        stop.RequestStop();
        return false;
      }
      *out = index;
      done[index] = true;
      return true;
    };
    long next = 0;
    std::vector<long> emitted;
    EXPECT_THROW(pool.Stream<long>(
                     64,
                     [&](std::vector<long>* chunk) {
                       for (; next < 64 && chunk->size() < 64; ++next) chunk->push_back(next);
                     },
                     job, [&](const long& i) { emitted.push_back(i); }, stop.token(),
                     [] { return Interrupted("stopped"); }, on_stop),
                 Interrupted);
    // the six jobs, and at most one more the other thread had begun before the stop
    EXPECT_LE(calls.load(), 7);
    std::vector<long> finished;
    for (long i = 0; i < 64; ++i) {
      if (done[i]) finished.push_back(i);
    }
    if (on_stop == WorkerPool::OnStop::kEveryFinished) {
      EXPECT_EQ(emitted, finished);
    } else {  // only those before the first unfinished job
      for (std::size_t i = 0; i < emitted.size(); ++i) EXPECT_EQ(emitted[i], static_cast<long>(i));
      EXPECT_LE(emitted.size(), finished.size());
    }
  }
}

TEST_F(WorkerPoolTest, NoThreadsIsABugNotBadInput) {
  // sweep, rollout and identify check their thread counts and say what to change; a pool
  // asked for none is a broken contract inside plumb, not repaired in silence
  Model model = Model::Load(testing::kPendulum);
  EXPECT_THROW(WorkerPool(model, 0), InternalError);
}

}  // namespace
}  // namespace plumb
