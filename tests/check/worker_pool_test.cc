// The worker pool of sweep, rollout and identify, on the path production runs (a oneTBB
// arena; make test-tsan runs these under ThreadSanitizer too).

#include "check/worker_pool.h"

#include <gtest/gtest.h>

#include <vector>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
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
  EXPECT_EQ(emitted.size(), 16u);  // the two chunks before the one that failed
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

TEST_F(WorkerPoolTest, NoThreadsIsABugNotBadInput) {
  // sweep, rollout and identify check their thread counts and say what to change; a pool
  // asked for none is a broken contract inside plumb, not repaired in silence
  Model model = Model::Load(testing::kPendulum);
  EXPECT_THROW(WorkerPool(model, 0), InternalError);
}

}  // namespace
}  // namespace plumb
