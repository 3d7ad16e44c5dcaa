// plumb rollout, results and merge as a user runs them, including a SIGKILL mid-batch.

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "corpus_robots.h"
#include "fixture.h"

namespace plumb {
namespace {

using testing::CommandResult;
using testing::ReadFile;
using testing::RunPlumb;
using testing::TempDir;
using testing::WriteFile;

const std::string kArgs =
    " --until 0.5 --randomize 'body_mass[torso]=*U(0.9,1.1)' "
    "--randomize 'geom_friction[floor][0]=U(0.5,1.2)' --ctrl-noise 0.01 "
    "--metric 'xpos[torso][2]@0.5' --format csv --seed 3";

std::string Rows(const std::string& csv) { return csv.substr(csv.find('\n') + 1); }

// The results store's rows without the run column, as `plumb rollout --format csv` prints.
std::string StoredRows(const std::string& store, const std::string& dir) {
  std::istringstream in(RunPlumb("results " + store, dir).out);
  std::string line, out;
  std::getline(in, line);  // header
  while (std::getline(in, line)) out += line.substr(line.find(',') + 1) + "\n";
  return out;
}

TEST(CliRolloutTest, CsvCarriesOnlyDataAndTheSummaryGoesToStderr) {
  CommandResult r = RunPlumb("rollout " + testing::kHumanoid + " --count 6" + kArgs);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')),
            "rollout,body_mass[torso],geom_friction[floor][0],xpos[torso][2]@0.5,diverged,"
            "diverged_at,problem");
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 7);
  EXPECT_NE(r.err.find("6 rollouts, 0 diverged"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("median"), std::string::npos) << r.err;
  // equal runs give byte-identical output, whatever the thread count
  EXPECT_EQ(RunPlumb("rollout " + testing::kHumanoid + " --count 6 --threads 2" + kArgs).out,
            r.out);
}

// Starts `command` (plumb's arguments, with --db r.sqlite) in `dir`, waits until the store
// holds a result, then SIGKILLs it; the exit code.
int KillOnceStored(const TempDir& dir, const std::string& command) {
  const std::string cli = std::string("'") + PLUMB_CLI + "'";
  WriteFile(dir.File("kill.sh"), cli + " " + command +
                                     " >/dev/null 2>&1 & pid=$!\n"
                                     "for i in $(seq 600); do\n"
                                     "  n=$(" + cli + " results r.sqlite 2>/dev/null | wc -l)\n"
                                     "  [ \"$n\" -gt 1 ] && break; sleep 0.05; done\n"
                                     "kill -9 $pid; wait $pid; echo $? > rc.txt\n");
  testing::RunShell("bash kill.sh", dir.path());
  return std::stoi(ReadFile(dir.File("rc.txt")));
}

// Kills `command` once it stored a result, checks the store holds part of the batch, and
// resumes it: the store then holds exactly `full`'s rows.
void KillResumeAndCompare(const std::string& command, const std::string& full, long count) {
  TempDir dir;
  EXPECT_EQ(KillOnceStored(dir, command), 137);
  std::string partial = StoredRows("r.sqlite", dir.path());
  long stored = std::count(partial.begin(), partial.end(), '\n');
  EXPECT_GT(stored, 0);
  EXPECT_LT(stored, count);
  // the same command without --resume refuses; with it, it completes the set
  CommandResult again = RunPlumb(command, dir.path());
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("--resume"), std::string::npos) << again.err;
  CommandResult resumed = RunPlumb(command + " --resume", dir.path());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(StoredRows("r.sqlite", dir.path()), Rows(full));
}

TEST(CliRolloutTest, KilledRunResumesToTheSameRowsWithoutDuplicates) {
  std::string command = "rollout " + testing::kHumanoid + " --count 400" + kArgs;
  KillResumeAndCompare(command + " --db r.sqlite", RunPlumb(command).out, 400);
}

// MuJoCo 4.0: rollouts of a model with a delayed motor (its history buffer) and a plastic
// spring, from a keyframe that bends the spring's rest angle and with the bend randomized:
// resumed after a kill, the stored rows are the rows of one whole run.
TEST(CliRolloutTest, AResumedRolloutWithDelaysAndPlasticSpringsGivesTheSameRows) {
#if mjVERSION_HEADER >= 4000000
  TempDir models;
  WriteFile(models.File("arm.xml"), R"(<mujoco model="delayed_plastic_arm">
      <option timestep="0.002" gravity="0 0 0"/><worldbody>
        <body name="arm" pos="0 0 1"><joint name="bend" axis="0 1 0" stiffness="10" springyield="1" damping="0.05"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/></body></worldbody>
      <actuator><motor name="push" joint="bend" ctrlrange="-1 1" delay="0.01" nsample="5"/></actuator>
      <keyframe><key name="bent" plastic="0.4"/></keyframe></mujoco>)");
  std::string command = "rollout '" + models.File("arm.xml") +
                        "' --count 300 --until 4 --keyframe bent --ctrl-noise 0.5 --seed 5 "
                        "--randomize 'plastic[0]=+U(-0.1,0.1)' --metric 'qpos[bend]@4' "
                        "--format csv";
  CommandResult full = RunPlumb(command);
  ASSERT_EQ(full.exit_code, 0) << full.err;
  KillResumeAndCompare(command + " --db r.sqlite", full.out, 300);
  // a run stored before plumb restored this state (its config lacks the start state) is not
  // resumed into rows of another start: the refusal names what differs
  TempDir dir;
  ASSERT_EQ(KillOnceStored(dir, command + " --db r.sqlite"), 137);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(dir.File("r.sqlite").c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "UPDATE runs SET config = replace(config, "
                         "' start_state=mjSTATE_INTEGRATION', '')",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  EXPECT_EQ(sqlite3_changes(db), 1);
  sqlite3_close(db);
  CommandResult old = RunPlumb(command + " --db r.sqlite --resume", dir.path());
  EXPECT_EQ(old.exit_code, 2);
  EXPECT_NE(old.err.find("now start_state=mjSTATE_INTEGRATION"), std::string::npos) << old.err;
#else
  GTEST_SKIP() << "plastic springs came with MuJoCo 4.0";
#endif
}

TEST(CliRolloutTest, MergedShardsEqualTheSingleRun) {
  TempDir dir;
  std::string full = RunPlumb("rollout " + testing::kHumanoid + " --count 9" + kArgs).out;
  for (int s = 0; s < 3; ++s) {
    CommandResult r =
        RunPlumb("rollout " + testing::kHumanoid + " --count 9" + kArgs + " --shard " +
                     std::to_string(s) + "/3 --db s" + std::to_string(s) + ".sqlite",
                 dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  CommandResult merge = RunPlumb("merge s0.sqlite s1.sqlite s2.sqlite -o all.sqlite", dir.path());
  ASSERT_EQ(merge.exit_code, 0) << merge.err;
  EXPECT_EQ(StoredRows("all.sqlite", dir.path()), Rows(full));
  nlohmann::json j =
      nlohmann::json::parse(RunPlumb("results all.sqlite --format json", dir.path()).out);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["rollouts"].size(), 9u);
  EXPECT_FALSE(j[0]["finished"].get<std::string>().empty());
  EXPECT_EQ(j[0]["mujoco_version"], testing::CompiledMujocoVersion());
  // merging into an existing file is refused
  EXPECT_EQ(RunPlumb("merge s0.sqlite -o all.sqlite", dir.path()).exit_code, 2);
}

TEST(CliRolloutTest, SlurmArrayVariablesPickTheShard) {
  std::string shard1 =
      RunPlumb("rollout " + testing::kHumanoid + " --count 6" + kArgs + " --shard 1/3").out;
  std::string slurm = testing::RunShell("SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=3 '" +
                                        std::string(PLUMB_CLI) + "' rollout " + testing::kHumanoid +
                                        " --count 6" + kArgs)
                          .out;
  EXPECT_EQ(shard1, slurm);
  EXPECT_EQ(std::count(shard1.begin(), shard1.end(), '\n'), 3);  // header + rollouts 1, 4
  // an array declared --array=1-3 numbers its tasks from 1: task 2 is shard 1
  std::string from_one =
      testing::RunShell("SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_COUNT=3 '" +
                        std::string(PLUMB_CLI) + "' rollout " + testing::kHumanoid + " --count 6" +
                        kArgs)
          .out;
  EXPECT_EQ(shard1, from_one);
}

TEST(CliRolloutTest, TheStoreGuardsItsRuns) {
  TempDir dir;
  const std::string run = "rollout " + testing::kHumanoid + " --count 4" + kArgs;
  ASSERT_EQ(RunPlumb(run + " --db r.sqlite", dir.path()).exit_code, 0);
  // --resume with other options is not the same run: refused, naming what differs
  CommandResult other =
      RunPlumb("rollout " + testing::kHumanoid + " --count 5" + kArgs + " --db r.sqlite --resume",
               dir.path());
  EXPECT_EQ(other.exit_code, 2) << other.err;
  EXPECT_NE(other.err.find("stored count=4"), std::string::npos) << other.err;
  EXPECT_NE(other.err.find("now count=5"), std::string::npos) << other.err;
  // an SQLite file of another program is refused, and left as it was
  ASSERT_EQ(testing::RunShell(
                "sqlite3 foreign.sqlite 'CREATE TABLE t(x); INSERT INTO t VALUES(1);'", dir.path())
                .exit_code,
            0);
  CommandResult foreign = RunPlumb(run + " --db foreign.sqlite", dir.path());
  EXPECT_EQ(foreign.exit_code, 2);
  EXPECT_NE(foreign.err.find("not a plumb results store"), std::string::npos) << foreign.err;
  EXPECT_EQ(RunPlumb("results foreign.sqlite", dir.path()).exit_code, 2);
  EXPECT_EQ(
      testing::RunShell("sqlite3 foreign.sqlite 'SELECT count(*) FROM sqlite_master'", dir.path())
          .out,
      "1\n");
  // exporting never writes: a read-only store can be exported
  ASSERT_EQ(testing::RunShell("chmod a-w r.sqlite", dir.path()).exit_code, 0);
  EXPECT_EQ(RunPlumb("results r.sqlite", dir.path()).exit_code, 0);
  // a failed merge leaves no temporary file behind
  CommandResult merge = RunPlumb("merge r.sqlite foreign.sqlite -o m.sqlite", dir.path());
  EXPECT_EQ(merge.exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir.File("m.sqlite")));
  EXPECT_FALSE(std::filesystem::exists(dir.File("m.sqlite.tmp-merge")));
}

TEST(CliRolloutTest, MergeKeepsEveryShardsCommand) {
  TempDir dir;
  for (int s = 0; s < 2; ++s) {
    ASSERT_EQ(RunPlumb("rollout " + testing::kHumanoid + " --count 4" + kArgs + " --shard " +
                           std::to_string(s) + "/2 --db s" + std::to_string(s) + ".sqlite",
                       dir.path())
                  .exit_code,
              0);
  }
  ASSERT_EQ(RunPlumb("merge s0.sqlite s1.sqlite -o all.sqlite", dir.path()).exit_code, 0);
  nlohmann::json j =
      nlohmann::json::parse(RunPlumb("results all.sqlite --format json", dir.path()).out);
  std::string command = j[0]["command"];
  EXPECT_NE(command.find("--shard 0/2"), std::string::npos) << command;
  EXPECT_NE(command.find("--shard 1/2"), std::string::npos) << command;
}

TEST(CliRolloutTest, SweepsWriteTheStoreToo) {
  TempDir dir;
  testing::CommandResult r = RunPlumb("sweep " + testing::kPendulum +
                                          " --set 'qpos[hinge]=0.7' --vary "
                                          "'dof_damping[hinge]=0,0.05' --metric 'qpos[hinge]@2' "
                                          "--db sweep.sqlite",
                                      dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json j =
      nlohmann::json::parse(RunPlumb("results sweep.sqlite --format json", dir.path()).out);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["kind"], "sweep");
  ASSERT_EQ(j[0]["rollouts"].size(), 2u);
  EXPECT_NEAR(j[0]["rollouts"][1]["metrics"]["qpos[hinge]@2"].get<double>(), 0.310947692600239,
              1e-12);
}

TEST(CliRolloutTest, ASummaryWithoutValuesPrintsNoInfinity) {
  // from rest the pendulum never crosses: no period in any rollout
  CommandResult r = RunPlumb("rollout " + testing::kPendulum +
                             " --count 3 --until 0.2 --metric 'period(qpos[hinge])' --format csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("no value measured (3 missing)"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("inf"), std::string::npos) << r.err;
}

// issue 46: a store where none can be said "unable to open database file" or "disk I/O error"
TEST(CliRolloutTest, AStoreWhereNoneCanBeIsExit2WithTheCause) {
  TempDir dir;
  const std::string rollout =
      "rollout " + testing::kPendulum + " --count 2 --until 0.01 --metric 'qpos[hinge]@0.01' --db ";
  CommandResult r = RunPlumb(rollout + "/dev/null", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("results store '/dev/null' is not a regular file (a character device)"),
            std::string::npos)
      << r.err;
  r = RunPlumb(rollout + "missing/r.db", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("the folder 'missing' does not exist"), std::string::npos) << r.err;
  // a read-only file system: a tmpfs mounted read-only in a mount namespace of its own, where
  // the machine allows one (unshare); root's writes stop there too
  std::filesystem::create_directory(dir.File("ro"));
  r = testing::RunShell(
      "unshare --user --map-root-user --mount sh -c \"mount -t tmpfs -o ro none "
      "ro && '" +
          std::string(PLUMB_CLI) + "' " + rollout + "ro/r.db\"",
      dir.path());
  if (r.err.find("results store") == std::string::npos) {
    GTEST_SKIP() << "no read-only mount here (unshare): " << r.err;
  }
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("results store 'ro/r.db': its folder 'ro' is on a read-only file system"),
            std::string::npos)
      << r.err;
}

TEST(CliRolloutTest, BadInputIsExit2) {
  EXPECT_EQ(
      RunPlumb("rollout " + testing::kHumanoid + " --randomize 'body_mass[*]=W(1,2)'").exit_code,
      2);
  EXPECT_EQ(RunPlumb("rollout " + testing::kHumanoid + " --shard 3/3").exit_code, 2);
  EXPECT_EQ(RunPlumb("rollout " + testing::kHumanoid + " --resume").exit_code, 2);
  EXPECT_EQ(RunPlumb("results /nonexistent/x.sqlite").exit_code, 2);
  for (const char* option : {"--count 0", "--count -5", "--threads 0"}) {
    CommandResult r = RunPlumb("rollout " + testing::kHumanoid + " " + option);
    EXPECT_EQ(r.exit_code, 2) << option;
    EXPECT_NE(r.err.find(std::string(option).substr(0, std::string(option).find(' '))),
              std::string::npos)
        << r.err;
  }
}

// --pose FILE and --qpos start the batch commands and the checks where --set would: the same
// numbers from verify, audit, rollout and sweep, and not those of the default start. A batch's
// stored config holds the pose's values, so --resume from another pose is refused, naming it.
TEST(CliRolloutTest, EveryCommandStartsFromAPoseFileOrAWholeQpos) {
  TempDir dir;
  WriteFile(dir.File("pose.txt"), "# let go from here\nqpos[hinge]=0.4\n");
  std::string model = testing::kPendulum;
  auto out = [&](const std::string& args) {
    CommandResult r = RunPlumb(args, dir.path());
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
    return r.out;
  };
  const std::string set = " --set 'qpos[hinge]=0.4'";
  for (const std::string& command :
       {"audit " + model + " --all",
        "rollout " + model + " --count 3 --until 0.5 --metric 'qpos[hinge]@0.5' --randomize "
            "'dof_damping[hinge]=*U(0.5,2)' --seed 1 --format csv",
        "sweep " + model + " --vary 'dof_damping[hinge]=0.1,0.2' --metric 'qpos[hinge]@0.5' "
            "--until 0.5"}) {
    SCOPED_TRACE(command);
    std::string by_set = out(command + set);
    // audit's header names the start as it was given ("from qpos0 with qpos=0.4"); the rest of
    // its page, and every row, is the same
    std::string by_qpos = out(command + " --qpos 0.4");
    if (command.rfind("audit", 0) == 0) {
      EXPECT_NE(by_qpos.find("from qpos0 with qpos=0.4)"), std::string::npos) << by_qpos;
      auto body = [](const std::string& page) { return page.substr(page.find('\n')); };
      auto rows = [&](std::string page) {
        std::string from = "qpos0 with qpos=0.4", to = "qpos0 with qpos[hinge]=0.4";
        for (size_t at = page.find(from); at != std::string::npos; at = page.find(from, at)) {
          page.replace(at, from.size(), to);
        }
        return body(page);
      };
      EXPECT_EQ(rows(by_qpos), body(by_set));
    } else {
      EXPECT_EQ(by_qpos, by_set);
    }
    EXPECT_EQ(out(command + " --pose pose.txt"), by_set);
    EXPECT_NE(out(command), by_set);
  }
  // verify quotes the assignment in a note, so the file (same text) gives the same page
  std::string verify = "verify " + model + " --all";
  EXPECT_EQ(out(verify + " --pose pose.txt"), out(verify + set));
  EXPECT_NE(out(verify + " --qpos 0.5").find("qpos = 0.5 rad"), std::string::npos);

  std::string batch = "rollout " + model + " --count 3 --until 0.5 --metric 'qpos[hinge]@0.5' --db r.sqlite";
  out(batch + " --pose pose.txt");
  CommandResult again = RunPlumb(batch + " --resume --qpos 0.5", dir.path());
  EXPECT_EQ(again.exit_code, 2) << again.err;
  EXPECT_NE(again.err.find("stored pose=qpos[hinge]=0.40000000000000002, now pose=qpos=0.5"),
            std::string::npos)
      << again.err;
  EXPECT_EQ(RunPlumb(batch + " --resume --pose pose.txt", dir.path()).exit_code, 0);
}

// The last column of each csv row before "diverged": the one metric's values.
std::vector<double> MetricColumn(const std::string& csv, int column) {
  std::vector<double> out;
  std::istringstream in(Rows(csv));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream cells(line);
    std::string cell;
    for (int c = 0; c <= column && std::getline(cells, cell, ','); ++c) {
    }
    out.push_back(std::stod(cell));
  }
  return out;
}

// --ctrl-noise is centred on the start's ctrl (issue 49): 0.1 % of noise made the corpus G1 of
// position servos collapse from 0.78 m to 0.23 m when it was centred on the middle of each
// ctrlrange. Started without a ctrl, a note says where the noise is centred.
TEST(CliRolloutTest, CtrlNoiseKeepsTheG1StandingOnItsKeyframe) {
  TempDir dir;
  std::string g1 = testing::robots::G1Servos(dir.path());
  if (g1.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  const std::string args = " --count 2 --ctrl-noise 0.001 --format csv";
  CommandResult r = RunPlumb("rollout " + g1 + " --keyframe stand" + args +
                             " --until 2 --metric 'qpos[floating_base_joint][2]@2'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (double z : MetricColumn(r.out, 1)) EXPECT_GT(z, 0.7) << r.out;
  EXPECT_EQ(r.err.find("the start sets no ctrl"), std::string::npos) << r.err;
  CommandResult bare = RunPlumb("rollout " + g1 + args +
                                " --until 0.01 --metric 'qpos[floating_base_joint][2]@0.01'");
  ASSERT_EQ(bare.exit_code, 0) << bare.err;
  EXPECT_NE(bare.err.find("the start sets no ctrl"), std::string::npos) << bare.err;
  EXPECT_NE(bare.err.find("29 position servos"), std::string::npos) << bare.err;
}

// A pendulum held at 1 rad by a position servo (ctrlrange [-3, 3], middle 0): with noise it
// stays near 1 rad; a start ctrl outside the ctrlrange is centred on the range's end, and said.
TEST(CliRolloutTest, CtrlNoiseIsCentredOnThePendulumsStartCtrl) {
  TempDir dir;
  WriteFile(dir.File("servo.xml"), R"(<mujoco><worldbody><body>
      <joint name="hinge" axis="0 1 0" damping="0.5"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1"/></body></worldbody>
    <actuator><position name="servo" joint="hinge" kp="50" ctrllimited="true" ctrlrange="-3 3"/></actuator>
    <keyframe><key name="held" qpos="1" ctrl="1"/><key name="far" qpos="1" ctrl="5"/></keyframe>
    </mujoco>)");
  const std::string args = " --count 3 --until 1 --ctrl-noise 0.01 --format csv "
                           "--metric 'qpos[hinge]@1'";
  CommandResult r = RunPlumb("rollout servo.xml --keyframe held" + args, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (double q : MetricColumn(r.out, 1)) EXPECT_NEAR(q, 1, 0.1) << r.out;
  CommandResult far = RunPlumb("rollout servo.xml --keyframe far" + args, dir.path());
  ASSERT_EQ(far.exit_code, 0) << far.err;
  EXPECT_NE(far.err.find("'servo' (ctrl 5: centred on 3)"), std::string::npos) << far.err;
}

// A randomization that changes nothing gets the note plumb sweep prints (issue 49), and its
// reason reads geom priority: the G1's feet (priority 1) decide its contacts with the floor, so
// the floor's friction has no say there; it once guessed "below its partner's friction".
TEST(CliRolloutTest, TheG1sFloorFrictionUnderFeetOfHigherPriorityGetsANote) {
  TempDir dir;
  std::string g1 = testing::robots::G1Servos(dir.path());
  if (g1.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  const std::string common = " --keyframe stand --until 0.3 "
                             "--metric 'qpos[floating_base_joint][2]@0.3' --format csv";
  CommandResult r = RunPlumb("rollout " + g1 + common +
                             " --count 3 --randomize 'geom_friction[floor][0]=U(0.3,1)'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("randomize 'geom_friction[floor][0]=U(0.3,1)' changed no metric: all 3 "
                       "measured rollouts gave bit-identical results"),
            std::string::npos)
      << r.err;
  const std::string priority =
      "meets geoms of higher priority (priority 1: 'left_foot1_collision'";
  EXPECT_NE(r.err.find(priority), std::string::npos) << r.err;
  // sweep says the same reason
  CommandResult s = RunPlumb("sweep " + g1 + common + " --vary 'geom_friction[floor][0]=0.3,1'");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  EXPECT_NE(s.err.find("changed no metric"), std::string::npos) << s.err;
  EXPECT_NE(s.err.find(priority), std::string::npos) << s.err;
  // the feet's own friction decides: no note
  CommandResult feet =
      RunPlumb("rollout " + g1 + common +
               " --count 3 --randomize 'geom_friction[left_foot1_collision][0]=U(0.01,0.02)'");
  ASSERT_EQ(feet.exit_code, 0) << feet.err;
  EXPECT_EQ(feet.err.find("changed no metric"), std::string::npos) << feet.err;
}

}  // namespace
}  // namespace plumb
