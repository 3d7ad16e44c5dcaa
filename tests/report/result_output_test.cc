// The JSON and tables of converge, diff, replay and identify, from results made by hand:
// numbers stay numbers (null where nothing was measured), and every part of a result shows.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "plumb/result_json.h"
#include "plumb/result_table.h"

namespace plumb {
namespace {

ConvergenceResult Ladder() {
  ConvergenceResult r;
  r.model = "pendulum.xml";
  r.metric = "qpos[hinge]@1";
  r.until = 1;
  r.expected_order = 1;
  r.tol = 1e-3;
  r.scale = 0.7;
  for (double dt : {0.004, 0.002, 0.001}) {
    ConvergenceLevel level;
    level.dt = dt;
    level.value = 0.5 + dt;
    level.diff = level.order = level.error = NAN;
    r.levels.push_back(level);
  }
  r.levels[1].diff = 2e-3;
  r.levels[2].diff = 1e-3;
  r.levels[2].order = 1.0;
  r.levels[2].error = 1e-3;
  r.estimate.resolved = true;
  r.estimate.order = 1.0;
  r.estimate.extrapolated = 0.5;
  r.estimate.note = "Richardson";
  r.recommended_dt = 0.001;
  return r;
}

TEST(ResultOutputTest, ConvergeKeepsEveryLevelWithNullWhereALevelHasNoDifference) {
  nlohmann::json j = nlohmann::json::parse(ConvergeToJson(Ladder()));
  EXPECT_EQ(j["model"], "pendulum.xml");
  EXPECT_EQ(j["metric"], "qpos[hinge]@1");
  EXPECT_EQ(j["integrator_expected_order"], 1.0);
  ASSERT_EQ(j["levels"].size(), 3u);
  EXPECT_TRUE(j["levels"][0]["diff"].is_null());
  EXPECT_EQ(j["levels"][1]["diff"], 2e-3);
  EXPECT_EQ(j["observed_order"], 1.0);
  EXPECT_EQ(j["recommended_dt"], 0.001);
  EXPECT_TRUE(j["caveat"].is_null());

  std::string table = ConvergeTable(Ladder());
  EXPECT_EQ(table.rfind("metric qpos[hinge]@1 on pendulum.xml, over 1 s\n", 0), 0u) << table;
  EXPECT_NE(table.find("observed order  1.00 (the integrator's is 1)\n"), std::string::npos)
      << table;
  EXPECT_NE(table.find("recommended dt  0.001 s"), std::string::npos) << table;

  ConvergenceResult none = Ladder();
  none.recommended_dt = 0;
  EXPECT_TRUE(nlohmann::json::parse(ConvergeToJson(none))["recommended_dt"].is_null());
  EXPECT_NE(ConvergeTable(none).find("recommended dt  none"), std::string::npos);
}

TEST(ResultOutputTest, DiffListsEachChangeWithItsOldAndNewValuesAsJson) {
  SnapshotDiff diff;
  diff.model = "arm.xml";
  diff.tol = 1e-6;
  diff.model_sets = {"body_mass[upper]=3"};
  diff.snapshot_mujoco_version = "1.0.0";  // a release no leg runs: the upgrade line
  SnapshotChange change;
  change.what = "body_mass[upper]: 1 -> 3";
  change.kind = "parameter";
  change.path = "body_mass[upper]";
  change.old_value = "1";
  change.new_value = "3";
  diff.changes.push_back(change);
  nlohmann::json j = nlohmann::json::parse(DiffToJson(diff, "arm.snap.json"));
  EXPECT_EQ(j["snapshot"], "arm.snap.json");
  EXPECT_EQ(j["model"], "arm.xml");
  EXPECT_EQ(j["identical"], false);
  EXPECT_EQ(j["sets"][0], "body_mass[upper]=3");
  EXPECT_EQ(j["changes"][0]["old"], 1);
  EXPECT_EQ(j["changes"][0]["new"], 3);
  EXPECT_FALSE(j["changes"][0].contains("step"));  // not a trajectory change

  std::string table = DiffTable(diff, "arm.snap.json");
  EXPECT_NE(table.find("body_mass[upper]: 1 -> 3\n1 change(s) beyond tol 1e-06\n"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("upgrade 1.0.0 -> "), std::string::npos) << table;
  diff.changes.clear();
  EXPECT_NE(DiffTable(diff, "arm.snap.json").find("identical to arm.snap.json within tol 1e-06"),
            std::string::npos);
}

TEST(ResultOutputTest, ReplayAndIdentifyShowEverySignalLogAndEstimate) {
  RobotLog log;
  log.source = "run1.csv";
  log.end = 2;
  log.measured.push_back({"angle", {}, {0, 1}, {0.1, 0.2}});
  ReplayResult replay;
  replay.signals.push_back({"angle", "qpos[hinge]", 2, 0.01, 0.02, 1.5, 97.5});
  replay.fit = 97.5;
  ReplayOptions options;
  options.window = 0.5;
  nlohmann::json r = nlohmann::json::parse(ReplayToJson("arm.xml", log, options, replay));
  EXPECT_EQ(r["log"], "run1.csv");
  EXPECT_EQ(r["window"], 0.5);
  EXPECT_EQ(r["signals"][0]["path"], "qpos[hinge]");
  EXPECT_EQ(r["fit"], 97.5);
  EXPECT_TRUE(r["signals"][0].contains("noise_fit"));
  std::string table = ReplayTable("arm.xml", log, options, replay);
  EXPECT_NE(table.find("restarted from the logged state every 0.5 s"), std::string::npos) << table;
  EXPECT_NE(table.find("overall fit 97.50 %"), std::string::npos) << table;

  IdentifyResult id;
  id.estimates.push_back({"dof_damping[hinge]", 0.05, 0.1, 0.01, 0, 1, false, 3});
  id.correlation = {{1.0}};
  id.noise = {{0.01}};
  id.before = {replay};
  id.after = {replay};
  id.residual_variance = NAN;
  id.delay = 0.004;
  HeldOutLog held{&log, replay, replay};
  nlohmann::json i =
      nlohmann::json::parse(IdentifyToJson("arm.xml", id, {log}, DelayKind::kInput, &held));
  EXPECT_EQ(i["estimates"][0]["value"], 0.1);
  EXPECT_EQ(i["delay"]["kind"], "ctrl");
  EXPECT_EQ(i["delay"]["value"], 0.004);
  EXPECT_TRUE(i["residual_variance"].is_null());
  EXPECT_EQ(i["logs"][0]["noise"]["angle"], 0.01);
  EXPECT_EQ(i["validation"]["log"], "run1.csv");
  EXPECT_FALSE(
      nlohmann::json::parse(IdentifyToJson("arm.xml", id, {log}, DelayKind::kNone, nullptr))
          .contains("delay"));
  EXPECT_EQ(i["std_errors"]["kind"], "classical");
  EXPECT_FALSE(i["misspecification"]["detected"].get<bool>());
  std::string text = IdentifyTable("arm.xml", id, {log}, DelayKind::kInput, &held);
  EXPECT_NE(text.find("input delay [s]"), std::string::npos) << text;
  // misspecified, no robust standard error: withheld in the table, said why, and no
  // reassurance from the residual variance
  IdentifyResult wrong = id;
  wrong.misspecification.detected = true;
  wrong.misspecification.reason = "the evidence";
  wrong.std_errors = {StdErrorKind::kWithheld, 0, "withheld: the reason"};
  wrong.estimates[0].std_error = NAN;
  std::string warned = IdentifyTable("arm.xml", wrong, {log}, DelayKind::kNone, nullptr);
  EXPECT_NE(warned.find("withheld"), std::string::npos) << warned;
  EXPECT_NE(warned.find("WARN misspecified: the evidence"), std::string::npos) << warned;
  EXPECT_NE(warned.find("standard errors: withheld: the reason"), std::string::npos) << warned;
  EXPECT_EQ(warned.find("about 1 when"), std::string::npos) << warned;
  nlohmann::json w =
      nlohmann::json::parse(IdentifyToJson("arm.xml", wrong, {log}, DelayKind::kNone, nullptr));
  EXPECT_EQ(w["std_errors"]["kind"], "withheld");
  EXPECT_TRUE(w["estimates"][0]["std_error"].is_null());
  EXPECT_NE(text.find("dof_damping[hinge]: 0.05 -> 0.1 (+100.0 %)"), std::string::npos) << text;
  EXPECT_NE(text.find("validation on run1.csv"), std::string::npos) << text;
}

}  // namespace
}  // namespace plumb
