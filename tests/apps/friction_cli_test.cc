// The friction a new user meets on the command line: typos in commands and options,
// repeated options, integers in other notations, tables that bury their findings, and
// `plumb results` on a store with several runs.

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "fixture.h"

namespace plumb {
namespace {

using testing::CommandResult;
using testing::RunPlumb;
using testing::TempDir;

const std::string kPendulum = testing::kPendulum;

// The number of lines of `text` that start with `prefix`.
int LinesStartingWith(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);) n += line.rfind(prefix, 0) == 0;
  return n;
}

TEST(FrictionCliTest, MistypedCommandSuggestsTheNearest) {
  CommandResult r = RunPlumb("rn " + kPendulum);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown command 'rn'; did you mean 'run'?"), std::string::npos) << r.err;
  r = RunPlumb("verfy " + kPendulum);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("did you mean 'verify'?"), std::string::npos) << r.err;
  // nothing close: no guess, but the list of commands
  r = RunPlumb("xyzzy");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.find("did you mean"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("The commands are: verify, audit"), std::string::npos) << r.err;
}

TEST(FrictionCliTest, MistypedOptionSuggestsTheNearestOnEveryCommand) {
  struct Case {
    std::string args, suggestion;
  };
  const std::vector<Case> cases = {
      {"run " + kPendulum + " --untill 1", "'--until'"},
      {"verify " + kPendulum + " --untill 1", "'--until'"},
      {"audit " + kPendulum + " --scenaro s.toml", "'--scenario'"},
      {"snapshot " + kPendulum + " --ouput snap.json", "'--output'"},
      {"diff snap.json " + kPendulum + " --tol=0.1 --formt json", "'--format'"},
      {"inspect " + kPendulum + " --sett 'qpos[hinge]=1'", "'--set'"},
      {"converge " + kPendulum + " --halving 3", "'--halvings'"},
      {"sweep " + kPendulum + " --vary 'qpos[hinge]=0:1:3' --metrics 'qpos[hinge]@1'",
       "'--metric'"},
      {"rollout " + kPendulum + " --cuont 10", "'--count'"},
      {"results store.sqlite --rnu 2", "'--run'"},
      {"merge a.sqlite b.sqlite --ouptut c.sqlite", "'--output'"},
  };
  for (const Case& c : cases) {
    CommandResult r = RunPlumb(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.err.find("did you mean " + c.suggestion + "?"), std::string::npos) << c.args << "\n"
                                                                                   << r.err;
    std::string command = c.args.substr(0, c.args.find(' '));
    EXPECT_NE(r.err.find("Run 'plumb " + command + " --help'"), std::string::npos) << r.err;
  }
}

TEST(FrictionCliTest, RepeatedSingleValuedOptionIsRefused) {
  CommandResult r = RunPlumb("run " + kPendulum + " --until 1 --until=2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--until was given 2 times ('1', '2'); it takes one value: give it once"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  r = RunPlumb("verify " + kPendulum + " --format json --format table");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--format was given 2 times"), std::string::npos) << r.err;
  // every problem of the line is named, each as an error of its own
  r = RunPlumb("run " + kPendulum + " --evry 0.1 --until 1 --until 2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("plumb: error: unknown option --evry for 'plumb run'; did you mean "
                       "'--every'?\nplumb: error: --until was given 2 times"),
            std::string::npos)
      << r.err;
  // repeatable options stay repeatable
  r = RunPlumb("run " + kPendulum +
               " --set 'qpos[hinge]=0.1' --set 'qvel[hinge]=1' --until 0.1 --format csv");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\n0,0.1"), std::string::npos) << r.out;
}

// Seeds were parsed by saturation: every seed beyond 2^64 - 1 became 2^64 - 1 and gave the
// rows of that seed. The largest seed is taken, anything larger is refused naming --seed.
TEST(FrictionCliTest, SeedsBeyondSixtyFourBitsAreRefusedNotSaturated) {
  const std::string rollout = "rollout " + kPendulum +
                              " --count 2 --until 0.1 --randomize 'dof_damping[hinge]=U(0,1)'"
                              " --format csv --seed ";
  CommandResult largest = RunPlumb(rollout + "18446744073709551615");
  ASSERT_EQ(largest.exit_code, 0) << largest.err;
  for (const char* bad : {"18446744073709551616", "99999999999999999999", "-1"}) {
    CommandResult r = RunPlumb(rollout + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.out;
    EXPECT_NE(r.err.find("--seed: takes a non-negative integer"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "") << bad;
  }
  EXPECT_NE(RunPlumb(rollout + "18446744073709551614").out, largest.out);
}

TEST(FrictionCliTest, IntegerOptionTakesAnExactIntegerInAnyNotation) {
  const std::string rollout =
      "rollout " + kPendulum + " --until 0.1 --metric 'qpos[hinge]@0.1' --format csv --count ";
  CommandResult r = RunPlumb(rollout + "1e1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(LinesStartingWith(r.out, "9,"), 1) << r.out;
  EXPECT_EQ(LinesStartingWith(r.out, "10,"), 0) << r.out;
  EXPECT_EQ(RunPlumb(rollout + "10").out, r.out);
  EXPECT_EQ(RunPlumb(rollout + "010").out, r.out);  // decimal, not octal 8
  EXPECT_EQ(RunPlumb(rollout + "10.0").out, r.out);
  // not an integer: refused, naming the option
  for (const char* bad : {"1.5", "abc", "1e-3"}) {
    r = RunPlumb(rollout + bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find(std::string("--count: takes an integer, not '") + bad + "'"),
              std::string::npos)
        << r.err;
  }
  // the same rule on every integer option
  r = RunPlumb("converge " + kPendulum + " --halvings 2.5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--halvings: takes an integer, not '2.5'"), std::string::npos) << r.err;
  r = RunPlumb("results store.sqlite --run 0.5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--run: takes an integer"), std::string::npos) << r.err;
  r = RunPlumb(rollout + "2 --seed 1.5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--seed: takes a non-negative integer, not '1.5'"), std::string::npos)
      << r.err;
  // range checks still apply after the notation is read
  r = RunPlumb(rollout + "0e0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--count"), std::string::npos) << r.err;
}

// The fields of one CSV line (RFC 4180 quotes).
std::vector<std::string> CsvFields(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    char c = line[i];
    if (c == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"') {
      fields.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

// Reads `csv` back as a table: the header, then rows that must each have its width.
std::vector<std::vector<std::string>> ReadTable(const std::string& csv) {
  std::istringstream in(csv);
  std::vector<std::vector<std::string>> table;
  for (std::string line; std::getline(in, line);) {
    table.push_back(CsvFields(line));
    EXPECT_EQ(table.back().size(), table.front().size()) << "line " << table.size() << ": " << line;
  }
  return table;
}

TEST(FrictionCliTest, ResultsOfSeveralRunsAreOneTableWithARunColumn) {
  TempDir dir;
  const std::string rollout = "rollout " + kPendulum +
                              " --until 0.2 --randomize 'qpos[hinge]=U(0,1)' "
                              "--metric 'qpos[hinge]@0.2' --count 3 --format csv --db s.sqlite ";
  ASSERT_EQ(RunPlumb(rollout + "--seed 1", dir.path()).exit_code, 0);
  ASSERT_EQ(RunPlumb(rollout + "--seed 2", dir.path()).exit_code, 0);

  // two runs with the same columns: one header, every row as wide, both runs in the run column
  CommandResult both = RunPlumb("results s.sqlite", dir.path());
  ASSERT_EQ(both.exit_code, 0) << both.err;
  std::vector<std::vector<std::string>> table = ReadTable(both.out);
  ASSERT_EQ(table.size(), 7u) << both.out;
  EXPECT_EQ(table[0][0], "run");
  EXPECT_EQ(LinesStartingWith(both.out, "run,"), 1) << both.out;
  EXPECT_EQ(LinesStartingWith(both.out, "1,"), 3) << both.out;
  EXPECT_EQ(LinesStartingWith(both.out, "2,"), 3) << both.out;

  // a run with other columns: CSV refuses to mix them, naming the runs and --run
  ASSERT_EQ(RunPlumb("rollout " + kPendulum +
                         " --until 0.2 --randomize 'dof_damping[hinge]=U(0,1)' "
                         "--metric 'qvel[hinge]@0.2' --metric 'qpos[hinge]@0.2' --count 2 "
                         "--format csv --db s.sqlite",
                     dir.path())
                .exit_code,
            0);
  CommandResult mixed = RunPlumb("results s.sqlite", dir.path());
  EXPECT_EQ(mixed.exit_code, 2);
  EXPECT_TRUE(mixed.out.empty()) << mixed.out;
  EXPECT_NE(mixed.err.find("3 runs with different columns"), std::string::npos) << mixed.err;
  EXPECT_NE(mixed.err.find("run 3 (rollout, 2 rollouts): parameters dof_damping[hinge]; "
                           "metrics qvel[hinge]@0.2, qpos[hinge]@0.2"),
            std::string::npos)
      << mixed.err;
  EXPECT_NE(mixed.err.find("--run N"), std::string::npos) << mixed.err;

  // one run at a time, and JSON with every run, still work
  CommandResult third = RunPlumb("results s.sqlite --run 3", dir.path());
  ASSERT_EQ(third.exit_code, 0) << third.err;
  table = ReadTable(third.out);
  ASSERT_EQ(table.size(), 3u) << third.out;
  EXPECT_EQ(table[0].size(), 8u) << third.out;  // run, rollout, 1 parameter, 2 metrics, 3 more
  CommandResult json = RunPlumb("results s.sqlite --format json", dir.path());
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_EQ(nlohmann::json::parse(json.out).size(), 3u);
}

// A double pendulum: every single-hinge check is skipped for the same reason.
const char kDoublePendulum[] = R"(<mujoco><worldbody>
    <body name="upper" pos="0 0 2"><joint name="shoulder" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1"/>
      <body name="lower" pos="0 0 -0.5"><joint name="elbow" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1"/></body></body>
  </worldbody></mujoco>)";

// The count line as the table prints it, from the JSON summary of the same command.
std::string CountLine(const nlohmann::json& summary) {
  return std::to_string(summary["pass"].get<int>()) + " passed, " +
         std::to_string(summary["warn"].get<int>()) + " warned, " +
         std::to_string(summary["fail"].get<int>()) + " failed, " +
         std::to_string(summary["skip"].get<int>()) + " skipped";
}

TEST(FrictionCliTest, VerifyTableShowsFindingsAndGroupsSkipsThatShareAReason) {
  TempDir dir;
  testing::WriteFile(dir.File("double.xml"), kDoublePendulum);
  const std::string verify = "verify double.xml --set 'qpos[shoulder]=0.5' --until 1 ";
  CommandResult json = RunPlumb(verify + "--format json", dir.path());
  ASSERT_EQ(json.exit_code, 0) << json.err;
  nlohmann::json j = nlohmann::json::parse(json.out);
  int pass = j["summary"]["pass"], skipped_alike = 0;
  for (const nlohmann::json& c : j["checks"]) {
    skipped_alike += c["explanation"].get<std::string>().rfind("not a single hinge pendulum", 0) == 0;
  }
  ASSERT_GE(pass, 3);
  ASSERT_GE(skipped_alike, 2);

  // default: no PASS row, one row for the skips that share a reason, naming their ids
  CommandResult table = RunPlumb(verify, dir.path());
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_EQ(LinesStartingWith(table.out, "PASS"), 0) << table.out;
  EXPECT_EQ(LinesStartingWith(table.out, "SKIP  " + std::to_string(skipped_alike) +
                                             " checks skipped: not a single hinge pendulum"),
            1)
      << table.out;
  EXPECT_NE(table.out.find("analytic.period, "), std::string::npos) << table.out;
  EXPECT_NE(table.out.find(CountLine(j["summary"]) +
                           " (passed checks not listed: --all shows every check)\n"),
            std::string::npos)
      << table.out;

  // --all: every check on its own row
  CommandResult all = RunPlumb(verify + "--all", dir.path());
  EXPECT_EQ(LinesStartingWith(all.out, "PASS  "), pass) << all.out;
  EXPECT_EQ(LinesStartingWith(all.out, "PASS  ") + LinesStartingWith(all.out, "SKIP  ") +
                LinesStartingWith(all.out, "WARN  ") + LinesStartingWith(all.out, "FAIL  "),
            static_cast<int>(j["checks"].size()))
      << all.out;

  // --quiet: the count line alone; and JSON stays complete whatever the table shows
  CommandResult quiet = RunPlumb(verify + "--quiet", dir.path());
  EXPECT_EQ(quiet.exit_code, 0);
  EXPECT_EQ(quiet.out, CountLine(j["summary"]) + "\n");
  EXPECT_EQ(RunPlumb(verify + "--quiet --format json", dir.path()).out, json.out);
  EXPECT_EQ(RunPlumb(verify + "--all --quiet", dir.path()).exit_code, 2);
}

TEST(FrictionCliTest, AuditTableShowsFindingsNotHundredsOfPassRows) {
  CommandResult json = RunPlumb("audit " + testing::kHumanoid + " --format json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  nlohmann::json j = nlohmann::json::parse(json.out);
  int pass = j["summary"]["pass"];
  ASSERT_GT(pass, 50);

  CommandResult table = RunPlumb("audit " + testing::kHumanoid);
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_EQ(LinesStartingWith(table.out, "PASS"), 0) << table.out;
  EXPECT_EQ(table.out.find("== structure"), std::string::npos) << table.out;  // nothing to show
  EXPECT_NE(table.out.find(CountLine(j["summary"]) + " (passed checks not listed"),
            std::string::npos)
      << table.out;
  EXPECT_EQ(LinesStartingWith(RunPlumb("audit " + testing::kHumanoid + " --all").out, "PASS  "),
            pass);
  EXPECT_EQ(RunPlumb("audit " + testing::kHumanoid + " --quiet").out,
            CountLine(j["summary"]) + "\n");

  // a failure shows under its layer's heading, with its fix, and still exits 1
  TempDir dir;
  testing::WriteFile(dir.File("ghost.xml"), R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="ghost" pos="0 0 1"><freejoint/>
        <geom type="box" size="0.1 0.1 0.1" contype="0" conaffinity="0"/></body>
    </worldbody></mujoco>)");
  CommandResult ghost = RunPlumb("audit ghost.xml", dir.path());
  EXPECT_EQ(ghost.exit_code, 1);
  EXPECT_NE(ghost.out.find("== contact\nFAIL  contact.free_fall"), std::string::npos) << ghost.out;
  EXPECT_NE(ghost.out.find("      fix: "), std::string::npos) << ghost.out;
  EXPECT_EQ(RunPlumb("audit ghost.xml --quiet", dir.path()).exit_code, 1);
}

TEST(FrictionCliTest, AuditTableGroupsTheSameFindingAboutSeveralElements) {
  const std::string quadruped = testing::kSuite + "/quadruped.xml";
  if (!std::filesystem::exists(quadruped)) GTEST_SKIP() << quadruped << " is not here";
  CommandResult json = RunPlumb("audit " + quadruped + " --format json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  nlohmann::json j = nlohmann::json::parse(json.out);
  std::vector<std::string> limited;  // the actuators actuator.limits warns about, in order
  for (const nlohmann::json& f : j["layers"]["actuator"]) {
    if (f["id"] == "actuator.limits" && f["status"] == "WARN") {
      limited.push_back(f["element_name"]);
    }
  }
  ASSERT_EQ(limited.size(), 12u) << json.out;

  // default: one row for the twelve, naming each, with the first as the example and the fix
  CommandResult table = RunPlumb("audit " + quadruped);
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_EQ(LinesStartingWith(table.out, "WARN  actuator.limits"), 1) << table.out;
  EXPECT_NE(table.out.find("WARN  actuator.limits            12 actuators alike:\n      " +
                           limited[0] + ", " + limited[1] + ", "),
            std::string::npos)
      << table.out;
  for (const std::string& name : limited) {
    EXPECT_NE(table.out.find(name), std::string::npos) << name << "\n" << table.out;
  }
  EXPECT_NE(table.out.find("      e.g. actuator '" + limited[0] +
                           "' (id 0): ctrl limited, force unlimited, gear 1   threshold a force "
                           "bound\n      fix: a real motor saturates"),
            std::string::npos)
      << table.out;
  // one fix for the twelve, and structure.solref_clamp's: the suite's coupling equalities
  // write 5 ms at a 5 ms step (inertia.shape judges from the geoms on every MuJoCo: no SKIP row
  // on 2.x either)
  EXPECT_EQ(LinesStartingWith(table.out, "      fix: "), 2) << table.out;
  EXPECT_EQ(LinesStartingWith(table.out, "WARN  structure.solref_clamp"), 1) << table.out;
  EXPECT_NE(table.out.find("13 warned"), std::string::npos) << table.out;  // counts stay per row

  // --all: every warning on its own row; JSON the same whatever the table groups
  EXPECT_EQ(
      LinesStartingWith(RunPlumb("audit " + quadruped + " --all").out, "WARN  actuator.limits"),
      12);
  EXPECT_EQ(RunPlumb("audit " + quadruped + " --all --format json").out, json.out);
}

TEST(FrictionCliTest, AuditTableKeepsDifferentFindingsOfOneCheckApart) {
  // two motors with nothing bounded (different gears: still the same finding) and a
  // position servo whose ctrl is bounded but its force is not (another finding)
  TempDir dir;
  testing::WriteFile(dir.File("arm.xml"), R"(<mujoco><worldbody>
      <body name="link1" pos="0 0 1"><joint name="j1" axis="0 0 1"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/>
        <body name="link2" pos="0.3 0 0"><joint name="j2" axis="0 0 1"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/>
          <body name="link3" pos="0.3 0 0"><joint name="j3" axis="0 0 1"/>
            <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/></body></body></body>
    </worldbody>
    <actuator>
      <motor name="shoulder" joint="j1"/>
      <motor name="elbow" joint="j2" gear="50"/>
      <position name="wrist" joint="j3" kp="10" ctrllimited="true" ctrlrange="-1 1"/>
    </actuator></mujoco>)");
  CommandResult table = RunPlumb("audit arm.xml", dir.path());
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_EQ(LinesStartingWith(table.out, "WARN  actuator.limits"), 2) << table.out;
  EXPECT_NE(
      table.out.find("WARN  actuator.limits            2 actuators alike:\n"
                     "      shoulder, elbow\n"
                     "      e.g. actuator 'shoulder' (id 0): ctrl unlimited, force unlimited"),
      std::string::npos)
      << table.out;
  EXPECT_NE(table.out.find("WARN  actuator.limits            actuator 'wrist' (id 2)\n"
                           "      ctrl limited, force unlimited"),
            std::string::npos)
      << table.out;
  EXPECT_EQ(
      LinesStartingWith(RunPlumb("audit arm.xml --all", dir.path()).out, "WARN  actuator.limits"),
      3);
}

}  // namespace
}  // namespace plumb
