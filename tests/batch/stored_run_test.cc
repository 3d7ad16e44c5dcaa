// The protocol of resumable batches: a batch is begun once, resumed only as itself, and a
// resumable job's first attempt starts it.

#include "plumb/stored_run.h"

#include <gtest/gtest.h>

#include <string>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

using testing::TempDir;

RunInfo Info(const std::string& config) {
  RunInfo info = NewRunInfo("rollout", config, {"plumb", "rollout", "arm.xml", "--count", "3"},
                            "arm.xml", "abc");
  info.count = 3;
  return info;
}

void Store(StoredRun& run, long index) {
  RolloutResult r;
  r.index = index;
  run.store->Add(run.id, r);
}

TEST(StoredRunTest, ABatchIsBegunOnceAndResumedWithWhatItHolds) {
  TempDir dir;
  std::string path = dir.File("r.sqlite");
  RunInfo info = Info("count=3 seed=1");
  EXPECT_EQ(info.command, "plumb rollout arm.xml --count 3");
  {
    StoredRun run = OpenStoredRun(path, false, info);
    ASSERT_TRUE(run.store);
    EXPECT_TRUE(run.done.empty());
    EXPECT_FALSE(run.fresh_start);
    Store(run, 0);
    Store(run, 2);
    CompleteStoredRun(run, 3);  // two of three: not finished
  }
  // the same batch again without resuming: refused, naming the store and what it holds
  try {
    OpenStoredRun(path, false, info);
    FAIL() << "a stored batch ran twice";
  } catch (const RunAlreadyStored& e) {
    EXPECT_EQ(e.argument(), "store");
    EXPECT_EQ(e.value(), "'" + path + "'");
    EXPECT_EQ(e.run().id, 1);
    EXPECT_EQ(e.done(), 2);
    EXPECT_NE(e.problem().find("already holds this run (rollout run 1, 2 of 3 done)"),
              std::string::npos)
        << e.what();
  }
  StoredRun resumed = OpenStoredRun(path, true, info);
  EXPECT_EQ(resumed.done, (std::vector<long>{0, 2}));
  Store(resumed, 1);
  CompleteStoredRun(resumed, 3);
  EXPECT_FALSE(resumed.store->Runs().front().finished.empty());
}

TEST(StoredRunTest, AResumeOfAnotherBatchNamesWhatDiffers) {
  TempDir dir;
  std::string path = dir.File("r.sqlite");
  OpenStoredRun(path, false, Info("count=3 seed=1"));
  try {
    OpenStoredRun(path, true, Info("count=3 seed=2"));
    FAIL() << "another batch was resumed";
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.argument(), "store");
    EXPECT_NE(e.problem().find("stored seed=1, now seed=2"), std::string::npos) << e.what();
    EXPECT_NE(e.problem().find("plumb rollout arm.xml --count 3"), std::string::npos) << e.what();
  }
}

TEST(StoredRunTest, AFirstAttemptThatResumesStartsTheBatch) {
  TempDir dir;
  StoredRun run = OpenStoredRun(dir.File("new.sqlite"), true, Info("count=3"));
  EXPECT_TRUE(run.fresh_start);
  EXPECT_GT(run.id, 0);
  // not stored at all: nothing to open, and nothing to resume
  EXPECT_FALSE(OpenStoredRun("", false, Info("count=3")).store);
  try {
    OpenStoredRun("", true, Info("count=3"));
    FAIL() << "resumed without a store";
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.argument(), "resume");
  }
}

// What a stopped batch says is written once, for the CLI and Python alike; only the words for
// going on are each front end's.
TEST(StoredRunTest, AStoppedBatchSaysWhatFinishedAndHowToGoOn) {
  EXPECT_EQ(StoppedBatchMessage("interrupted after 12 rollouts", "12 rollouts finished", "r.sqlite",
                                "call it again with resume=True"),
            "interrupted after 12 rollouts; 12 rollouts finished and stored in 'r.sqlite': call it "
            "again with resume=True to go on");
  EXPECT_EQ(StoppedBatchMessage("interrupted after 3 of 9 cases", "3 cases finished", "", "x"),
            "interrupted after 3 of 9 cases; 3 cases finished");
}

}  // namespace
}  // namespace plumb
