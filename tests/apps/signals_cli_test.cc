// Every long command stops cleanly on SIGINT/SIGTERM, and batch commands stream their rows,
// keep what finished and stop when their reader goes away.

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "fixture.h"
#include "sim/log_maker.h"

namespace plumb {
namespace {

using testing::CommandResult;
using testing::Lines;
using testing::ReadFile;
using testing::RunPlumb;
using testing::TempDir;
using testing::WriteFile;

const std::string kCli = std::string("'") + PLUMB_CLI + "' ";

// Starts `args` in the background in `dir`, waits until `ready_file` has at least
// `ready_lines` lines (or for `delay` s when empty), sends `signal`, and returns the exit code
// with stderr in err.txt and stdout in out.txt.
int Interrupt(const TempDir& dir, const std::string& args, const std::string& signal,
              const std::string& ready_file = "", int ready_lines = 0, double delay = 1.0) {
  std::string wait = ready_file.empty()
                         ? "sleep " + std::to_string(delay) + "; "
                         : "for i in $(seq 400); do [ \"$(wc -l < " + ready_file +
                               " 2>/dev/null || echo 0)\" -ge " + std::to_string(ready_lines) +
                               " ] && break; sleep 0.05; done; ";
  WriteFile(dir.File("interrupt.sh"), kCli + args + " >out.txt 2>err.txt & pid=$!; " + wait +
                                          "kill -" + signal +
                                          " $pid; wait $pid; echo $? >rc.txt\n");
  testing::RunShell("bash interrupt.sh", dir.path());
  return std::stoi(ReadFile(dir.File("rc.txt")));
}

// Runs `script` with bash (pipelines with PIPESTATUS) in `dir`.
CommandResult RunBash(const TempDir& dir, const std::string& script) {
  WriteFile(dir.File("script.sh"), script + "\n");
  return testing::RunShell("bash script.sh", dir.path());
}

TEST(CliSignalsTest, VerifyAuditAndConvergeStopWithExit130AndSaySo) {
  // they used to die silently: no message, exit by signal
  TempDir dir;
  WriteFile(dir.File("long.toml"),
            "name = \"long\"\nduration = 100000.0\nassertions = [\"maxabs(qpos[hinge]) < 10\"]\n");
  const std::string set = " --set 'qpos[hinge]=0.7'";
  for (const std::string& args :
       {"verify " + testing::kPendulum + set + " --until 400",
        "audit " + testing::kPendulum + set + " --scenario long.toml",
        "converge " + testing::kPendulum + set + " --metric 'qpos[hinge]@20' --halvings 10"}) {
    for (const char* signal : {"INT", "TERM"}) {
      EXPECT_EQ(Interrupt(dir, args, signal), 130) << args << ReadFile(dir.File("err.txt"));
      std::string err = ReadFile(dir.File("err.txt"));
      EXPECT_NE(err.find("stopped by a signal"), std::string::npos) << args << err;
    }
  }
}

TEST(CliSignalsTest, IdentifyStopsWithExit130AndWritesNoModel) {
  TempDir dir;
  testing::LogSpec spec;
  spec.u = testing::Chirp(2, 3);
  spec.noise = {0.001, 0.01};
  testing::MakeLog(dir.File("chirp.csv"), spec);
  // a delay scan of 2500 fits: far longer than the second it is given
  std::string args = "identify " + testing::kPendulum +
                     " --log chirp.csv --fit 'dof_damping[hinge]' --delay ctrl --max-delay 5"
                     " --report fit.html";
  EXPECT_EQ(Interrupt(dir, args, "INT"), 130) << ReadFile(dir.File("err.txt"));
  EXPECT_NE(ReadFile(dir.File("err.txt")).find("stopped by a signal"), std::string::npos)
      << ReadFile(dir.File("err.txt"));
  EXPECT_FALSE(std::filesystem::exists(dir.File("fit.html")));
  EXPECT_EQ(ReadFile(dir.File("out.txt")), "");
}

TEST(CliSignalsTest, AnInterruptedSweepKeepsItsCasesAndResumeFinishesTheSet) {
  // SIGINT after about 90 of 400 cases left no message, an empty stdout and no --db file
  TempDir dir;
  const std::string sweep = "sweep " + testing::kPendulum +
                            " --set 'qpos[hinge]=0.7' --vary 'dof_damping[hinge]=0:0.02:200' "
                            "--metric 'period(qpos[hinge])' --until 10 --format csv";
  EXPECT_EQ(Interrupt(dir, sweep + " --db s.sqlite", "INT", "out.txt", 20), 130);
  std::string err = ReadFile(dir.File("err.txt"));
  EXPECT_NE(err.find("repeat the command with --resume"), std::string::npos) << err;
  std::vector<std::string> first = Lines(ReadFile(dir.File("out.txt")));
  ASSERT_GE(first.size(), 20u);
  ASSERT_LT(first.size(), 201u);
  // the store holds exactly the printed cases
  CommandResult stored = RunPlumb("results s.sqlite --format csv", dir.path());
  EXPECT_EQ(Lines(stored.out).size(), first.size()) << stored.out;
  // --resume runs the rest; together they are the uninterrupted sweep
  CommandResult rest = RunPlumb(sweep + " --db s.sqlite --resume --threads 2", dir.path());
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  std::vector<std::string> second = Lines(rest.out);
  CommandResult whole = RunPlumb(sweep, dir.path());
  std::vector<std::string> all = Lines(whole.out);
  ASSERT_EQ(all.size(), 201u);
  std::vector<std::string> joined = first;
  joined.insert(joined.end(), second.begin() + 1, second.end());  // one header
  EXPECT_EQ(joined, all);
  EXPECT_EQ(Lines(RunPlumb("results s.sqlite --format csv", dir.path()).out).size(), 201u);
  // a finished sweep is not run twice by accident
  EXPECT_EQ(RunPlumb(sweep + " --db s.sqlite", dir.path()).exit_code, 2);
}

TEST(CliSignalsTest, ResumeOfAFreshStoreIsAFreshStart) {
  // --resume on a new --db failed and left an empty database behind
  TempDir dir;
  CommandResult sweep = RunPlumb("sweep " + testing::kPendulum +
                                     " --vary 'dof_damping[hinge]=0,1' --metric 'qpos[hinge]@0.1' "
                                     "--db new.sqlite --resume",
                                 dir.path());
  ASSERT_EQ(sweep.exit_code, 0) << sweep.err;
  EXPECT_NE(sweep.err.find("holds no sweep run yet; starting one"), std::string::npos) << sweep.err;
  CommandResult rollout = RunPlumb("rollout " + testing::kPendulum +
                                       " --count 3 --until 0.1 --metric 'qpos[hinge]@0.1' "
                                       "--db other.sqlite --resume",
                                   dir.path());
  ASSERT_EQ(rollout.exit_code, 0) << rollout.err;
  EXPECT_EQ(Lines(RunPlumb("results other.sqlite --format csv", dir.path()).out).size(), 4u);
}

TEST(CliSignalsTest, RolloutRowsStreamAndAClosedStdoutStopsTheBatch) {
  // rows appeared only when every rollout had finished: `| head -2` ran all of them
  TempDir dir;
  const std::string rollout = "rollout " + testing::kPendulum +
                              " --set 'qpos[hinge]=0.7' --count 200000 --until 1 "
                              "--randomize 'dof_damping[hinge]=U(0,0.1)' "
                              "--metric 'qpos[hinge]@1' --format csv --db r.sqlite";
  CommandResult head =
      RunBash(dir, kCli + rollout + " 2>err.txt | head -2; echo \"${PIPESTATUS[0]}\"");
  std::vector<std::string> lines = Lines(head.out);
  ASSERT_EQ(lines.size(), 3u) << head.out;
  EXPECT_EQ(lines[2], "141") << ReadFile(dir.File("err.txt"));
  // what finished was kept: the store holds a prefix, and --resume completes the summary
  std::vector<std::string> stored =
      Lines(RunPlumb("results r.sqlite --format csv", dir.path()).out);
  EXPECT_GE(stored.size(), 2u);
  EXPECT_LT(stored.size(), 100000u);
}

TEST(CliSignalsTest, WithOneThreadEachRolloutRowLeavesAsItFinishes) {
  // rows left 64 per thread at a time: 40 rollouts on one thread printed nothing until the
  // last had run. Now the first row is out while the rest still run, and a Ctrl-C then keeps
  // it and stops the batch.
  TempDir dir;
  int rc = Interrupt(dir,
                     "rollout " + testing::kPendulum +
                         " --set 'qpos[hinge]=0.7' --count 40 --until 100 --threads 1 "
                         "--randomize 'dof_damping[hinge]=U(0,0.1)' --metric 'qpos[hinge]@100' "
                         "--format csv",
                     "INT", "out.txt", 2);
  std::vector<std::string> rows = Lines(ReadFile(dir.File("out.txt")));
  EXPECT_EQ(rc, 130) << ReadFile(dir.File("err.txt"));
  ASSERT_GE(rows.size(), 2u);
  EXPECT_LT(rows.size(), 41u) << "every row came out before the first one";
}

TEST(CliSignalsTest, ASummaryAfterResumeCoversEveryRow) {
  // after --resume the summary counted only the rollouts run by the resuming command
  TempDir dir;
  const std::string base = "rollout " + testing::kPendulum +
                           " --set 'qpos[hinge]=0.7' --until 0.1 --count 20000 "
                           "--randomize 'dof_damping[hinge]=U(0,0.1)' "
                           "--metric 'qpos[hinge]@0.1' --format csv --db r.sqlite";
  // a partial run of the same config: its reader closed stdout early
  RunBash(dir, kCli + base + " 2>/dev/null | head -2 >/dev/null");
  long stored =
      static_cast<long>(Lines(RunPlumb("results r.sqlite --format csv", dir.path()).out).size()) -
      1;
  ASSERT_GT(stored, 0);
  ASSERT_LT(stored, 20000);
  CommandResult resumed = RunPlumb(base + " --resume --threads 2", dir.path());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("20000 rollouts (" + std::to_string(stored) +
                             " stored before it resumed"),
            std::string::npos)
      << resumed.err;
  EXPECT_NE(resumed.err.find("qpos[hinge]@0.1: n 20000 "), std::string::npos) << resumed.err;
}

TEST(CliSignalsTest, AHugeSweepSaysItsCostAndStreamsInFlatMemory) {
  // --vary 'x=1:2:100000000' reached 2.9 GB in 18 s with no output
  TempDir dir;
  CommandResult r = RunBash(
      dir, kCli + "sweep " + testing::kPendulum +
               " --vary 'dof_damping[hinge]=1:2:100000000' --metric 'qpos[hinge]@0.1' --format csv "
               "2>err.txt | head -3; echo \"${PIPESTATUS[0]}\"");
  std::vector<std::string> lines = Lines(r.out);
  ASSERT_EQ(lines.size(), 4u) << r.out;
  EXPECT_EQ(lines[0], "case,dof_damping[hinge],qpos[hinge]@0.1");
  EXPECT_EQ(lines[3], "141");
  std::string err = ReadFile(dir.File("err.txt"));
  EXPECT_NE(err.find("sweep of 100000000 cases x 1 metric"), std::string::npos) << err;
  EXPECT_NE(err.find("GB of csv output"), std::string::npos) << err;
}

// The cost line counts what runs: 9 cases x 2 metrics of one run length are 9 runs (it said
// 18, and ran 18).
TEST(CliSignalsTest, ASweepsCostLineCountsOneRunPerCaseForItsMetricsOfOneLength) {
  TempDir dir;
  CommandResult r = RunPlumb("sweep '" + testing::kPendulum +
                                 "' --set 'qpos[hinge]=0.7' --vary 'dof_damping[hinge]=0:0.4:9' "
                                 "--metric 'maxabs(qvel[hinge])' --metric energy_drift "
                                 "--format csv",
                             dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("sweep of 9 cases x 2 metrics: 9 runs, up to 1000 steps a case, 9000 "
                       "steps in all"),
            std::string::npos)
      << r.err;
}

TEST(CliSignalsTest, SweepMemoryDoesNotGrowWithTheNumberOfCases) {
  // a one-axis sweep kept every case for its no-effect note: 250 MB for a million cases
#ifdef PLUMB_UNDER_ASAN
  GTEST_SKIP() << "resident memory under AddressSanitizer says nothing about plumb's";
#else
  auto peak_kb = [](long cases) {
    std::string sweep = kCli + "sweep " + testing::kPendulum +
                        " --vary 'dof_damping[hinge]=0:1:" + std::to_string(cases) +
                        "' --metric 'qpos[hinge]@0.002' --format csv >/dev/null 2>&1";
    EXPECT_EQ(testing::RunShell(sweep).exit_code, 0);
    rusage usage{};
    getrusage(RUSAGE_CHILDREN, &usage);  // the largest child so far
    return usage.ru_maxrss;
  };
  long small = peak_kb(2000), large = peak_kb(200000);
  EXPECT_LT(large, small * 3 / 2) << small << " KB for 2000 cases, " << large << " KB for 200000";
#endif
}

TEST(CliSignalsTest, SlurmVariablesAreNamedWhenTheyPickNoTask) {
  // the error spoke of a --shard the user never passed
  CommandResult r = testing::RunShell("SLURM_ARRAY_TASK_ID=5 SLURM_ARRAY_TASK_COUNT=3 " + kCli +
                                      "rollout " + testing::kPendulum + " --count 6");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("SLURM_ARRAY_TASK_ID=5"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("SLURM_ARRAY_TASK_COUNT=3"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("--shard '"), std::string::npos) << r.err;
}

TEST(CliSignalsTest, ASweepOverAParameterWithNoEffectSaysSo) {
  // floor friction below the other geom's: MuJoCo takes the larger, the metric never moved
  CommandResult r = RunPlumb("sweep " + testing::kHumanoid +
                             " --vary 'geom_friction[floor][0]=0.1,0.5' "
                             "--metric 'xpos[torso][2]@0.5'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("changed no metric"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("larger friction of its two geoms"), std::string::npos) << r.err;
  // a parameter that matters gets no note
  CommandResult damped = RunPlumb("sweep " + testing::kPendulum +
                                  " --set 'qpos[hinge]=0.7' --vary 'dof_damping[hinge]=0,1' "
                                  "--metric 'qpos[hinge]@1'");
  ASSERT_EQ(damped.exit_code, 0) << damped.err;
  EXPECT_EQ(damped.err.find("note:"), std::string::npos) << damped.err;
}

}  // namespace
}  // namespace plumb
