// The batch job both front ends run (plumb/batch_job.h): the spec from text, the store opened
// or resumed, the tally, the commit on a stop, and what it says as notices.

#include "plumb/batch_job.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

class BatchJobTest : public testing::MujocoTest {
 protected:
  Model pendulum_ = Model::Load(testing::kPendulum);
};

// The ArgumentError `f` throws: its argument and value, or "" when it throws none.
std::string ArgumentOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ArgumentError& e) {
    return e.argument() + " " + e.value();
  }
  return "";
}

std::vector<std::string> Texts(const Notices& notices) {
  std::vector<std::string> out;
  for (const Notice& n : notices.all()) out.push_back(n.Line());
  return out;
}

bool BitEqual(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

TEST_F(BatchJobTest, ASpecFromTextNamesTheArgumentOfABadText) {
  RolloutSpec given;
  given.count = 4;
  auto rollout = [&](BatchText text) { ParseRolloutSpec(pendulum_, given, text); };
  EXPECT_EQ(ArgumentOf([&] { rollout({{"dof_damping[hinge]=*U(0.9"}, {}, {}, ""}); }),
            "randomize 'dof_damping[hinge]=*U(0.9'");
  EXPECT_EQ(ArgumentOf([&] { rollout({{}, {}, {"qpos[hinge]@"}, ""}); }),
            "metric 'qpos[hinge]@'");
  EXPECT_EQ(ArgumentOf([&] { rollout({{}, {}, {}, "2/2"}); }), "shard '2/2'");
  auto sweep = [&](BatchText text) { ParseSweepSpec(pendulum_, SweepSpec{}, text); };
  EXPECT_EQ(ArgumentOf([&] { sweep({{}, {"dof_damping[hinge]=a,b"}, {"qpos[hinge]@1"}, ""}); }),
            "vary 'dof_damping[hinge]=a,b'");

  // a good text is the spec its parts make
  RolloutSpec spec =
      ParseRolloutSpec(pendulum_, given, {{"dof_damping[hinge]=*U(0.5,1.5)"}, {}, {"energy_drift"},
                                          "1/2"});
  EXPECT_EQ(spec.count, 4);
  ASSERT_EQ(spec.randomize.size(), 1u);
  ASSERT_EQ(spec.metrics.size(), 1u);
  EXPECT_EQ(spec.shard_index, 1);
  EXPECT_EQ(spec.shard_count, 2);
}

TEST_F(BatchJobTest, AnAxisWarningIsANoticeNamedAsTheCallerNamesTheOption) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("arm.xml"), R"(<mujoco><worldbody><body><joint name="j"/>
    <geom size="0.1"/></body></worldbody>
    <actuator><motor name="m" joint="j" ctrlrange="-1 1" ctrllimited="true"/></actuator></mujoco>)");
  Model arm = Model::Load(dir.File("arm.xml"));
  Notices notices;
  BatchWords words;
  words.vary = "--vary";
  ParseSweepSpec(arm, SweepSpec{}, {{}, {"ctrl[m]=0,5"}, {"qpos[j]@0.1"}, ""}, words, &notices);
  std::vector<Notice> all = notices.all();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].subject, "--vary 'ctrl[m]=0,5'");
  EXPECT_EQ(all[0].topic, NoticeTopic::kStart);
  EXPECT_NE(all[0].text.find("outside the ctrlrange"), std::string::npos) << all[0].text;
}

// A stopped job stores every rollout that finished and says so in the front end's words; a
// resumed job says how many are stored, runs the rest, and the whole equals a batch never
// stopped.
TEST_F(BatchJobTest, AStopStoresEveryFinishedRowAndAResumedJobEqualsAnUninterruptedOne) {
  testing::TempDir dir;
  const std::string db = dir.File("r.sqlite");
  RolloutSpec spec =
      ParseRolloutSpec(pendulum_, RolloutSpec{}, {{"dof_damping[hinge]=*U(0.5,1.5)"}, {},
                                                  {"qpos[hinge]@0.5"}, ""});
  spec.count = 60;
  spec.until = 0.5;
  spec.threads = 2;
  std::vector<RolloutResult> whole;
  Rollout(pendulum_, spec, [&](const RolloutResult& r) { whole.push_back(r); });
  BatchOrigin origin{"pendulum.xml", {"test"}, StartConfig(pendulum_, StartSpec{})};
  BatchWords words;
  words.resume = "resume=True";
  words.go_on = "call it again with resume=True";

  Notices first;
  long kept = 0;
  {
    BatchJob job(db, true, RolloutRunInfo(pendulum_, spec, origin, db), words, &first);
    EXPECT_EQ(Texts(first), std::vector<std::string>{"note: resume=True: '" + db +
                                                     "' holds no rollout run yet; starting one"});
    StopSource stop;
    try {
      job.Run([&] {
        Rollout(
            pendulum_, spec,
            [&](const RolloutResult& r) {
              job.Add(r);
              if (job.summary().run_now == 10) stop.RequestStop();
            },
            stop.token());
      });
      FAIL() << "the stop did not end the job";
    } catch (const Interrupted& e) {
      kept = job.summary().run_now;
      EXPECT_NE(std::string(e.what()).find(std::to_string(kept) + " rollouts finished and stored in '" +
                                           db + "': call it again with resume=True to go on"),
                std::string::npos)
          << e.what();
    }
  }
  ASSERT_GE(kept, 10);
  ASSERT_LT(kept, spec.count);

  // every finished rollout was committed: the resumed job finds them all
  Notices second;
  BatchJob job(db, true, RolloutRunInfo(pendulum_, spec, origin, db), words, &second);
  EXPECT_EQ(static_cast<long>(job.done().size()), kept);
  std::vector<RolloutResult> rows;
  job.Resume(ShardSize(spec), InShard(spec), [&](const RolloutResult& r) { rows.push_back(r); });
  EXPECT_EQ(Texts(second),
            std::vector<std::string>{"note: resume=True: " + std::to_string(kept) +
                                     " of 60 rollouts are stored in '" + db +
                                     "'; running the rest"});
  RolloutSpec rest = spec;
  rest.skip = job.done();
  job.Run([&] {
    Rollout(pendulum_, rest, [&](const RolloutResult& r) {
      job.Add(r);
      rows.push_back(r);
    });
  });
  job.Complete(spec.count);
  EXPECT_EQ(job.summary().resumed, kept);
  EXPECT_EQ(job.summary().run_now, spec.count - kept);
  std::sort(rows.begin(), rows.end(),
            [](const RolloutResult& a, const RolloutResult& b) { return a.index < b.index; });
  ASSERT_EQ(rows.size(), whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(rows[i].index, whole[i].index);
    EXPECT_TRUE(BitEqual(rows[i].params[0], whole[i].params[0]));
    EXPECT_TRUE(BitEqual(rows[i].metrics[0], whole[i].metrics[0]));
  }
  // a resume of the finished run says there is nothing left to run
  Notices third;
  BatchJob done(db, true, RolloutRunInfo(pendulum_, spec, origin, db), words, &third);
  done.Resume(ShardSize(spec), InShard(spec), [](const RolloutResult&) {});
  EXPECT_EQ(Texts(third), std::vector<std::string>{"note: resume=True: all 60 rollouts are stored "
                                                   "in '" + db + "'; nothing is left to run"});
  // a finished run is not run again by accident: the refusal names the caller's words
  words.store = "db";
  try {
    BatchJob again(db, false, RolloutRunInfo(pendulum_, spec, origin, db), words);
    FAIL() << "a stored run was begun again";
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.argument(), "store");
    EXPECT_NE(e.problem().find("add resume=True to complete it, or use another db file"),
              std::string::npos)
        << e.problem();
  }
}

// A sweep's measurements that could not be made are said once per reason as they happen, then
// counted.
TEST_F(BatchJobTest, ASweepSaysWhatItCouldNotMeasure) {
  SweepSpec given;
  given.sets = {ParseAssignment(pendulum_, "qpos[hinge]=0")};
  // from rest no period: every case n/a; the friction of a pendulum that touches nothing
  SweepSpec spec = ParseSweepSpec(
      pendulum_, given, {{}, {"dof_damping[hinge]=0,0.1,0.2"}, {"period(qpos[hinge])"}, ""});
  Notices notices;
  SweepNotices said(spec, &notices);
  Sweep(pendulum_, spec, {}, [&](const SweepCase& c) { said.See(c, SweepCaseResult(spec, c)); });
  said.Finish();
  std::vector<Notice> all = notices.all();
  ASSERT_GE(all.size(), 3u);
  EXPECT_EQ(all[0].subject, "case 0, period(qpos[hinge])");
  EXPECT_EQ(all[0].topic, NoticeTopic::kBatch);
  EXPECT_NE(all[1].text.find("3 cases in all could not be measured"), std::string::npos)
      << all[1].text;
  EXPECT_EQ(all[2].text, "3 of 3 measurements could not be made (see above)");
}

}  // namespace
}  // namespace plumb
