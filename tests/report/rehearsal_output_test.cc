// A rehearsal's JSON, table and page, from results made by hand: every part of the result
// shows, numbers stay numbers (null where nothing was measured), and the client's output (text
// a stranger's program printed) comes out as text: escaped in the page, its unprintable bytes
// written \xNN in the table, and bytes that are not UTF-8 replaced in the JSON.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fixture.h"
#include "plumb/check_table.h"
#include "plumb/rehearse.h"
#include "plumb/report.h"
#include "plumb/result_json.h"

namespace plumb {
namespace {

CheckRow Row(const std::string& section, const std::string& id, CheckStatus status,
             const std::string& subject, const std::string& measured) {
  CheckRow row;
  row.section = section;
  row.id = id;
  row.status = status;
  row.subject = subject;
  row.measured_text = measured;
  row.title = section == "assert" ? "" : "how " + id + " went";
  row.explanation = id + " explained";
  return row;
}

// A client that died 0.42 s in: one assertion holds, one breaks, the process row FAILs.
RehearsalResult EndedEarly() {
  RehearsalResult r;
  CheckRow high = Row("assert", "assert", CheckStatus::kPass, "xpos[base][2] > 0.2",
                      "lowest 0.27 m at t = 0.40 s");
  high.reference = {0.2, "m"};
  high.reference_text = "> 0.2 m";
  high.threshold = true;
  CheckRow tracking = Row("assert", "assert", CheckStatus::kFail, "tracking_error[*] < 0.3",
                          "0.41 rad at t = 0.38 s (FR_hip)");
  tracking.reference = {0.3, "rad"};
  tracking.reference_text = "< 0.3 rad";
  tracking.threshold = true;
  tracking.fix = "look at the gains";
  r.rows = {high, tracking,
            Row("client", "client.process", CheckStatus::kFail, "", "exited with status 1"),
            Row("client", "client.period", CheckStatus::kPass, "", "median 2.0 ms"),
            Row("bridge", "bridge.crc", CheckStatus::kPass, "", "0 bad")};
  r.client.kind = ClientEnding::Kind::kExitedEarly;
  r.client.exit_code = 1;
  r.client.time = 0.42;
  r.client.wall = 3.14;
  r.client.text = "exited with status 1";
  r.client.last_lines = {"Traceback (most recent call last):", "<script>alert('owned')</script>",
                         "colour \x1b[31mred\x1b[0m, byte \xff"};
  r.view.commands = 210;
  r.view.first_command = 2.7;
  r.view.first_command_time = 0.002;
  r.view.period_median = 0.002;
  r.view.period_p95 = 0.0025;
  r.view.period_worst = 0.009;
  r.view.commands_per_period = 1;
  ClientMotorView hip;
  hip.name = "FR_hip";
  hip.commands = 210;
  hip.outside_range = 3;
  hip.worst_outside = 0.05;
  hip.saturated = 20;
  hip.saturated_fraction = 0.1;
  hip.worst_torque = 31.5;
  hip.tracking_rms = 0.12;
  hip.tracking_worst = 0.41;
  ClientMotorView thigh;
  thigh.name = "FR_thigh";  // never commanded: no tracking error
  r.view.motors = {hip, thigh};
  r.view.unknown_motors = {"slot 12 (mode 1, kp 20)"};
  r.view.own_pd = {"actuator 'FR_hip_pos' on joint 'FR_hip_joint' (kp 50)"};
  r.bridge.commands = 210;
  r.bridge.states = 210;
  r.bridge.steps = 210;
  r.bridge.time = 0.42;
  r.bridge.realtime_factor = 0.98;
  r.bridge.gamepad_messages = 4;
  RehearsalTrace& t = r.trace;
  t.signals = {"xpos[base][2]", "tracking_error[FR_hip]", "q_des[FR_hip]",
               "q[FR_hip]",     "q_des[FR_thigh]",        "q[FR_thigh]"};
  t.values.resize(t.signals.size());
  for (int k = 0; k <= 210; ++k) {
    double time = 0.002 * k;
    t.time.push_back(time);
    t.values[0].push_back(0.3 - 0.07 * time / 0.42);
    t.values[1].push_back(0.4 * std::sin(10 * time));
    t.values[2].push_back(k == 0 ? NAN : 0.1);  // no command in force yet
    t.values[3].push_back(0.1 - 0.1 * std::exp(-20 * time));
    t.values[4].push_back(NAN);
    t.values[5].push_back(0.8);
  }
  t.events = {{0.1, "gamepad: A pressed"}, {0.3, "fault: motor <FR_hip> off"}};
  return r;
}

// A client that ran to the end and stopped on plumb's signal: everything holds.
RehearsalResult Stopped() {
  RehearsalResult r;
  r.rows = {Row("assert", "assert", CheckStatus::kPass, "xpos[base][2] > 0.2", "lowest 0.27 m"),
            Row("assert", "assert", CheckStatus::kPass, "mean(saturated[*]) < 0.05", "0.01"),
            Row("client", "client.process", CheckStatus::kPass, "", "ended on SIGINT")};
  r.client.kind = ClientEnding::Kind::kStopped;
  r.client.signal = 2;
  r.client.time = 10;
  r.client.wall = 10.2;
  r.client.text = "ended on SIGINT";
  r.client.last_lines = {"policy running", "bye"};
  r.bridge.time = 10;
  return r;
}

int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
    ++n;
  }
  return n;
}

TEST(RehearsalOutputTest, ClientEndingsHaveTheirNames) {
  EXPECT_STREQ(ClientEndingName(ClientEnding::Kind::kStopped), "stopped");
  EXPECT_STREQ(ClientEndingName(ClientEnding::Kind::kKilled), "killed");
  EXPECT_STREQ(ClientEndingName(ClientEnding::Kind::kExitedEarly), "exited early");
  EXPECT_STREQ(ClientEndingName(ClientEnding::Kind::kNotStarted), "not started");
}

TEST(RehearsalOutputTest, JsonHasEveryPartWithNullWhereNothingWasMeasured) {
  nlohmann::json j = nlohmann::json::parse(RehearsalToJson("go2.xml", EndedEarly()));
  EXPECT_EQ(j["command"], "rehearse");
  EXPECT_EQ(j["model"], "go2.xml");
  EXPECT_EQ(j["mujoco_version"], MujocoVersion());
  EXPECT_EQ(j["passed"], false);
  ASSERT_EQ(j["rows"].size(), 5u);
  EXPECT_EQ(j["rows"][1]["status"], "FAIL");
  EXPECT_EQ(j["rows"][1]["element"], "tracking_error[*] < 0.3");
  EXPECT_EQ(j["rows"][1]["reference"], 0.3);
  EXPECT_EQ(j["rows"][1]["fix"], "look at the gains");
  EXPECT_EQ(j["summary"]["fail"], 2);
  EXPECT_EQ(j["summary"]["pass"], 3);

  const nlohmann::json& c = j["client"];
  EXPECT_EQ(c["kind"], "exited early");
  EXPECT_EQ(c["exit_code"], 1);
  EXPECT_EQ(c["signal"], 0);
  EXPECT_EQ(c["time"], 0.42);
  EXPECT_EQ(c["wall"], 3.14);
  EXPECT_EQ(c["text"], "exited with status 1");
  ASSERT_EQ(c["last_lines"].size(), 3u);
  EXPECT_EQ(c["last_lines"][1], "<script>alert('owned')</script>");
  // not UTF-8: replaced, the document still valid
  EXPECT_EQ(c["last_lines"][2], "colour \x1b[31mred\x1b[0m, byte \xEF\xBF\xBD");

  const nlohmann::json& v = j["view"];
  EXPECT_EQ(v["commands"], 210);
  EXPECT_EQ(v["first_command"], 2.7);
  EXPECT_EQ(v["first_command_time"], 0.002);
  EXPECT_EQ(v["period_median"], 0.002);
  EXPECT_EQ(v["period_p95"], 0.0025);
  EXPECT_EQ(v["period_worst"], 0.009);
  EXPECT_EQ(v["commands_per_period"], 1.0);
  ASSERT_EQ(v["motors"].size(), 2u);
  const nlohmann::json& hip = v["motors"][0];
  EXPECT_EQ(hip["name"], "FR_hip");
  EXPECT_EQ(hip["commands"], 210);
  EXPECT_EQ(hip["outside_range"], 3);
  EXPECT_EQ(hip["worst_outside"], 0.05);
  EXPECT_EQ(hip["saturated"], 20);
  EXPECT_EQ(hip["saturated_fraction"], 0.1);
  EXPECT_EQ(hip["worst_torque"], 31.5);
  EXPECT_EQ(hip["tracking_rms"], 0.12);
  EXPECT_EQ(hip["tracking_worst"], 0.41);
  EXPECT_TRUE(v["motors"][1]["tracking_rms"].is_null());
  EXPECT_EQ(v["unknown_motors"][0], "slot 12 (mode 1, kp 20)");
  EXPECT_EQ(v["own_pd"][0], "actuator 'FR_hip_pos' on joint 'FR_hip_joint' (kp 50)");

  const nlohmann::json& b = j["bridge"];
  EXPECT_EQ(b["commands"], 210);
  EXPECT_EQ(b["states"], 210);
  EXPECT_EQ(b["time"], 0.42);
  EXPECT_EQ(b["realtime_factor"], 0.98);
  EXPECT_EQ(b["gamepad_messages"], 4);
  EXPECT_TRUE(b["band_released"].is_null());
  EXPECT_EQ(b["diverged"], false);
  for (const char* key : {"bad_crc", "non_finite", "watchdog_trips", "dropped_commands",
                          "dropped_states", "paused_commands", "foreign_commands", "queue_drops",
                          "steps", "sport_states", "secondary_imu_states", "late_periods",
                          "worst_lateness", "late_commands", "longest_wait", "problem"}) {
    EXPECT_TRUE(b.contains(key)) << key;
  }
  ASSERT_EQ(j["events"].size(), 2u);
  EXPECT_EQ(j["events"][1]["time"], 0.3);
  EXPECT_EQ(j["events"][1]["what"], "fault: motor <FR_hip> off");
}

TEST(RehearsalOutputTest, JsonOfAClientThatDidNotExitHasNoExitCode) {
  RehearsalResult r = Stopped();
  r.client.exit_code = -1;
  nlohmann::json j = nlohmann::json::parse(RehearsalToJson("go2.xml", r));
  EXPECT_EQ(j["passed"], true);
  EXPECT_TRUE(j["client"]["exit_code"].is_null());
  EXPECT_EQ(j["client"]["signal"], 2);
  EXPECT_EQ(j["client"]["kind"], "stopped");
  EXPECT_TRUE(j["view"]["period_median"].is_null());
  EXPECT_TRUE(j["view"]["motors"].empty());
}

TEST(RehearsalOutputTest, TableShowsTheFindingsTheClientsLastLinesAndTheVerdict) {
  const std::string expected_end =
      "\n\n== assert\n"
      "FAIL  assert                   tracking_error[*] < 0.3\n"
      "      measured 0.41 rad at t = 0.38 s (FR_hip)   reference < 0.3 rad\n"
      "      assert explained\n"
      "      fix: look at the gains\n"
      "\n== client\n"
      "FAIL  client.process           how client.process went\n"
      "      measured exited with status 1\n"
      "      client.process explained\n"
      "\n"
      "3 passed, 0 warned, 2 failed, 0 skipped (passed checks not listed: add --all)\n"
      "\n"
      "client: exited early: exited with status 1 at t = 0.42 s (3.1 s of wall time); its last "
      "lines:\n"
      "      Traceback (most recent call last):\n"
      "      <script>alert('owned')</script>\n"
      "      colour \\x1b[31mred\\x1b[0m, byte \\xff\n"
      "rehearsal FAIL: 1 of 2 assertions broken; client.process failed; client exited early: "
      "exited with status 1 at t = 0.42 s (3.1 s of wall time)\n";
  std::string table = RehearsalTable("go2.xml", EndedEarly(), TableDetail::kFindings, "add --all");
  EXPECT_EQ(table.rfind(
                "rehearsal of go2.xml over 0.42 s simulated (MuJoCo " + MujocoVersion() + ")\n", 0),
            0u)
      << table;
  ASSERT_GE(table.size(), expected_end.size());
  EXPECT_EQ(table.substr(table.find('\n')), expected_end) << table;
}

TEST(RehearsalOutputTest, TableOfAPassingRehearsalCountsAndLeavesTheLinesOut) {
  std::string table = RehearsalTable("go2.xml", Stopped(), TableDetail::kFindings);
  EXPECT_EQ(table.find("its last lines"), std::string::npos) << table;
  EXPECT_NE(table.find("\nclient: stopped: ended on SIGINT at t = 10.00 s (10.2 s of wall time)\n"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("\nrehearsal PASS: 2 assertions hold; client stopped: ended on SIGINT at "
                       "t = 10.00 s (10.2 s of wall time)\n"),
            std::string::npos)
      << table;
  // every row, and the lines, when all is asked for
  std::string all = RehearsalTable("go2.xml", Stopped(), TableDetail::kAll);
  EXPECT_NE(all.find("PASS  assert                   mean(saturated[*]) < 0.05\n"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("its last lines:\n      policy running\n      bye\n"), std::string::npos)
      << all;
  // quiet: the counts and the verdict
  std::string quiet = RehearsalTable("go2.xml", Stopped(), TableDetail::kQuiet);
  EXPECT_EQ(quiet,
            "3 passed, 0 warned, 0 failed, 0 skipped\nrehearsal PASS: 2 assertions hold; client "
            "stopped: ended on SIGINT at t = 10.00 s (10.2 s of wall time)\n");
}

TEST(RehearsalOutputTest, VerdictNamesADivergenceAndWarnings) {
  RehearsalResult r = Stopped();
  r.rows.push_back(Row("client", "client.period", CheckStatus::kWarn, "", "jitter"));
  r.bridge.diverged = true;
  EXPECT_EQ(RehearsalVerdict(r),
            "rehearsal FAIL: 2 assertions hold; the simulation diverged; 1 warning; client "
            "stopped: ended on SIGINT at t = 10.00 s (10.2 s of wall time)");
  r.rows.clear();
  r.bridge.diverged = false;
  r.client = ClientEnding();
  r.client.text = "not started: the bridge stopped before it was up";
  EXPECT_EQ(RehearsalVerdict(r),
            "rehearsal PASS: no assertions; client not started: the bridge "
            "stopped before it was up");
}

TEST(RehearsalOutputTest, ReportHasTheRowsChartsEventsAndTheClientsOutputAsText) {
  RehearsalResult r = EndedEarly();
  Model model = Model::Load(testing::kPendulum);
  testing::TempDir dir;
  ReportInfo info{{"plumb", "bridge", "pendulum.xml", "--client", "python3 deploy.py"}};
  info.pictures = false;
  WriteRehearsalReport(dir.File("r.html"), model, {}, r, info);
  std::string html = testing::ReadFile(dir.File("r.html"));
  // a copy for the browser check (tests/report/browser_test.sh)
  if (const char* out = std::getenv("PLUMB_REHEARSAL_REPORT")) {
    std::filesystem::copy_file(dir.File("r.html"), out,
                               std::filesystem::copy_options::overwrite_existing);
  }
  EXPECT_NE(html.find("<title>plumb bridge "), std::string::npos);
  EXPECT_NE(html.find("default-src 'none'"), std::string::npos);
  EXPECT_EQ(Count(html, "<td class=\"status "), static_cast<int>(r.rows.size()));
  EXPECT_NE(html.find("tracking_error[*] &lt; 0.3"), std::string::npos);
  // the verdict and the client's ending
  EXPECT_NE(html.find("rehearsal FAIL: 1 of 2 assertions broken"), std::string::npos);
  EXPECT_NE(html.find("exited early: exited with status 1 at t = 0.42 s"), std::string::npos);
  // its output: text, never markup
  EXPECT_EQ(html.find("<script>alert("), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(&#39;owned&#39;)&lt;/script&gt;"), std::string::npos);
  EXPECT_NE(html.find("colour \\x1b[31mred"), std::string::npos);
  EXPECT_NE(html.find("byte \\xff"), std::string::npos);
  // two asserted signals and one chart of the two motors, each explained
  EXPECT_EQ(Count(html, "class=\"plumb-chart\""), 3);
  EXPECT_EQ(Count(html, "How to read this."), 3);
  EXPECT_NE(html.find("\"label\":\"bound: xpos[base][2] > 0.2\""), std::string::npos);
  EXPECT_NE(html.find("\"label\":\"bound: tracking_error[*] < 0.3\""), std::string::npos);
  EXPECT_EQ(Count(html, "\"label\":\"events (listed below)\""), 2);
  EXPECT_NE(html.find("\"label\":\"FR_hip commanded\""), std::string::npos);
  EXPECT_NE(html.find("\"label\":\"FR_thigh measured\""), std::string::npos);
  // the events, the client view and the bridge
  EXPECT_NE(html.find("<td>0.3</td><td>fault: motor &lt;FR_hip&gt; off</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>FR_hip</td><td>210</td><td>3</td>"), std::string::npos);
  EXPECT_NE(html.find("10.0 %"), std::string::npos);  // FR_hip's saturated fraction
  EXPECT_NE(html.find("2 ms"), std::string::npos);    // the median period
  EXPECT_NE(html.find("slot 12 (mode 1, kp 20)"), std::string::npos);
  EXPECT_NE(html.find("actuator &#39;FR_hip_pos&#39;"), std::string::npos);
  EXPECT_NE(html.find("<th>states published</th><td>210</td>"), std::string::npos);
  EXPECT_NE(html.find("<th>gamepad messages</th><td>4</td>"), std::string::npos);
}

// The charts' data the page carries (the JSON in its plumb-charts script).
nlohmann::json ChartsOf(const std::string& html) {
  const std::string open = "<script id=\"plumb-charts\" type=\"application/json\">";
  std::size_t from = html.find(open) + open.size();
  std::string json = html.substr(from, html.find("</script>", from) - from);
  for (std::size_t at = json.find("<\\/"); at != std::string::npos; at = json.find("<\\/")) {
    json.replace(at, 3, "</");
  }
  return nlohmann::json::parse(json);
}

TEST(RehearsalOutputTest, ReportDrawsEachBoundThatHoldsEverySampleOverItsWindow) {
  RehearsalResult r;
  auto row = [](const std::string& text, double bound) {
    CheckRow c = Row("assert", "assert", CheckStatus::kPass, text, "");
    c.reference = {bound, ""};
    c.threshold = true;
    return c;
  };
  r.rows = {row("min(xpos[base][2]) > 0.2 during [0.1, 0.3]", 0.2),
            row("mean(xpos[base][2]) > 0.25", 0.25), row("maxabs(xpos[base][2]) < 0.5", 0.5),
            row("xpos[*][2] > 0.1 during [0.2, -1]", 0.1), row("qpos[other] > 0", 0)};
  r.trace.signals = {"xpos[base][2]"};
  r.trace.values.resize(1);
  for (int k = 0; k <= 100; ++k) {
    r.trace.time.push_back(0.005 * k);
    r.trace.values[0].push_back(0.3);
  }
  Model model = Model::Load(testing::kPendulum);
  testing::TempDir dir;
  ReportInfo info;
  info.pictures = false;
  WriteRehearsalReport(dir.File("r.html"), model, {}, r, info);
  nlohmann::json charts = ChartsOf(testing::ReadFile(dir.File("r.html")));
  ASSERT_EQ(charts.size(), 1u);
  std::vector<std::string> labels;
  std::vector<std::vector<double>> lines;  // x0, x1, y of each bound
  for (const nlohmann::json& s : charts[0]["series"]) {
    labels.push_back(s["label"]);
    if (labels.back().rfind("bound: ", 0) != 0) continue;
    ASSERT_EQ(s["points"].size(), 2u);
    lines.push_back({s["points"][0]["x"], s["points"][1]["x"], s["points"][0]["y"]});
  }
  // the signal, then min (its window), maxabs (both signs), the wildcard (to the end)
  ASSERT_EQ(labels.size(), 5u) << charts.dump();
  EXPECT_EQ(labels[0], "xpos[base][2]");
  EXPECT_EQ(labels[1], "bound: min(xpos[base][2]) > 0.2 during [0.1, 0.3]");
  EXPECT_EQ(lines[0], (std::vector<double>{0.1, 0.3, 0.2}));
  EXPECT_EQ(labels[2], "bound: maxabs(xpos[base][2]) < 0.5");
  EXPECT_EQ(lines[1], (std::vector<double>{0, 0.5, 0.5}));
  EXPECT_EQ(lines[2], (std::vector<double>{0, 0.5, -0.5}));
  EXPECT_EQ(labels[4], "bound: xpos[*][2] > 0.1 during [0.2, -1]");
  EXPECT_EQ(lines[3], (std::vector<double>{0.2, 0.5, 0.1}));
}

TEST(RehearsalOutputTest, ReportOfARehearsalWithNoStateSaysSo) {
  RehearsalResult r;
  r.client.text = "not started: the bridge stopped before it was up";
  Model model = Model::Load(testing::kPendulum);
  testing::TempDir dir;
  ReportInfo info;
  info.pictures = false;
  WriteRehearsalReport(dir.File("r.html"), model, {}, r, info);
  std::string html = testing::ReadFile(dir.File("r.html"));
  EXPECT_NE(html.find("No state was published"), std::string::npos);
  EXPECT_NE(html.find("It printed nothing."), std::string::npos);
  EXPECT_EQ(Count(html, "class=\"plumb-chart\""), 0);
}

}  // namespace
}  // namespace plumb
