// The check row's writers: the tables of verify and audit and their JSON, built from rows
// made by hand (what a check writes), so each rule is seen on its own.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "plumb/check.h"
#include "plumb/check_table.h"
#include "plumb/result_json.h"

namespace plumb {
namespace {

CheckRow Finding(CheckStatus status, const std::string& id, CheckElement element,
                 const std::string& measured, const std::string& fix) {
  CheckRow row;
  row.section = "actuator";
  row.status = status;
  row.id = id;
  row.element = std::move(element);
  row.measured_text = measured;
  row.reference_text = "a force bound";
  row.threshold = true;
  row.fix = fix;
  return row;
}

// A verify check's row: what the table shows of a check with no numbers.
CheckRow Check(CheckStatus status, const std::string& id, const std::string& title,
               const std::string& explanation) {
  CheckRow row;
  row.status = status;
  row.id = id;
  row.title = title;
  row.explanation = explanation;
  return row;
}

// audit's report of arm.xml with `findings`.
AuditReport ArmAudit(std::vector<CheckRow> findings) {
  AuditReport report;
  report.model = "arm.xml";
  report.findings = std::move(findings);
  return report;
}

TEST(CheckRowTest, AnElementReadsWithItsNameAndIdOrItsNumberWhenUnnamed) {
  EXPECT_EQ(ElementLabel({"body", "hand", 3}), "body 'hand' (id 3)");
  EXPECT_EQ(ElementLabel({"body", "", 4}), "body #4");
  EXPECT_EQ(ElementLabel({}), "");
  CheckRow row;
  row.subject = "geom 'a' and geom 'b'";
  EXPECT_EQ(row.About(), "geom 'a' and geom 'b'");
  row.element = {"geom", "a", 0};
  EXPECT_EQ(row.About(), "geom 'a' (id 0)");
  EXPECT_EQ(CountStatus({row, row, CheckRow()}, CheckStatus::kSkip), 3);
  EXPECT_STREQ(CheckStatusName(CheckStatus::kWarn), "WARN");
}

TEST(CheckTableTest, TheSameFindingAboutSeveralElementsIsOneRowNamingThem) {
  AuditReport report;
  report.model = "arm.xml";
  report.findings = {
      Finding(CheckStatus::kWarn, "actuator.limits", {"actuator", "shoulder", 0},
              "ctrl unlimited, gear 1", "a real motor saturates"),
      Finding(CheckStatus::kWarn, "actuator.limits", {"actuator", "", 1}, "ctrl unlimited, gear 50",
              "a real motor saturates"),
      Finding(CheckStatus::kWarn, "actuator.limits", {"actuator", "wrist", 2},
              "ctrl limited, gear 1", "a real motor saturates"),
      Finding(CheckStatus::kPass, "actuator.holding", {"actuator", "wrist", 2}, "holds", "")};
  report.findings[2].finding = "ctrl limited";  // another finding of the same check
  report.findings[3].reference_text = "";       // informational: no threshold
  report.findings[3].threshold = false;
  std::string table = AuditTable(report, TableDetail::kFindings, "--all shows every check");
  EXPECT_NE(table.find("== actuator\n"
                       "WARN  actuator.limits            2 actuators alike:\n"
                       "      shoulder, actuator #1\n"
                       "      e.g. actuator 'shoulder' (id 0): ctrl unlimited, gear 1   threshold "
                       "a force bound\n"
                       "      fix: a real motor saturates\n"
                       "WARN  actuator.limits            actuator 'wrist' (id 2)\n"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("\n1 passed, 3 warned, 0 failed, 0 skipped (passed checks not listed: "
                       "--all shows every check)\n"),
            std::string::npos)
      << table;
  EXPECT_EQ(table.find("actuator.holding"), std::string::npos) << table;

  // every row on its own, the PASS too; the count line alone
  std::string all = AuditTable(report, TableDetail::kAll);
  EXPECT_NE(all.find("WARN  actuator.limits            actuator #1\n"), std::string::npos) << all;
  EXPECT_NE(all.find("PASS  actuator.holding           actuator 'wrist' (id 2)\n      holds\n"),
            std::string::npos)
      << all;
  EXPECT_EQ(AuditTable(report, TableDetail::kQuiet), "1 passed, 3 warned, 0 failed, 0 skipped\n");
}

TEST(CheckTableTest, AnAcceptedFindingShowsItsReasonStandsAloneAndCountsApart) {
  AuditReport report =
      ArmAudit({Finding(CheckStatus::kWarn, "actuator.limits", {"actuator", "shoulder", 0},
                        "ctrl unlimited, gear 1", "a real motor saturates"),
                Finding(CheckStatus::kWarn, "actuator.limits", {"actuator", "elbow", 1},
                        "ctrl unlimited, gear 1", "a real motor saturates"),
                Finding(CheckStatus::kFail, "actuator.step_response", {"actuator", "elbow", 1},
                        "diverged", "bound it")});
  report.findings[1].accepted = "the elbow's driver limits its current; judged 2026-10";
  report.findings[2].accepted = "a test rig";
  std::string table = AuditTable(report, TableDetail::kFindings);
  // the accepted WARN does not group with the one that is not
  EXPECT_NE(
      table.find("== actuator\n"
                 "WARN  actuator.limits            actuator 'shoulder' (id 0)\n"
                 "      ctrl unlimited, gear 1   threshold a force bound\n"
                 "      fix: a real motor saturates\n"
                 "ACCEPT  actuator.limits          actuator 'elbow' (id 1)\n"
                 "      ctrl unlimited, gear 1   threshold a force bound\n"
                 "      WARN accepted: the elbow's driver limits its current; judged 2026-10\n"
                 "ACCEPT  actuator.step_response   actuator 'elbow' (id 1)\n"
                 "      diverged   threshold a force bound\n"
                 "      FAIL accepted: a test rig\n"),
      std::string::npos)
      << table;
  EXPECT_EQ(AuditTable(report, TableDetail::kQuiet),
            "0 passed, 1 warned, 0 failed, 0 skipped, 2 accepted\n");

  // verify's table marks an accepted row the same way
  VerifyReport verify;
  verify.model = "pendulum.xml";
  verify.checks = {Check(CheckStatus::kWarn, "energy", "energy is conserved", "energy grew")};
  verify.checks[0].accepted = "contacts";
  EXPECT_NE(VerifyTable(verify, TableDetail::kFindings)
                .find("ACCEPT  energy                 energy is conserved\n"
                      "      measured -\n"
                      "      energy grew\n"
                      "      WARN accepted: contacts\n"),
            std::string::npos)
      << VerifyTable(verify, TableDetail::kFindings);
}

TEST(CheckTableTest, SkipsSharingAReasonAreOneRowListingTheirIds) {
  VerifyReport report;
  report.model = "humanoid.xml";
  report.tol = 0.01;
  for (const char* id : {"analytic.period", "experiment.A", "experiment.B"}) {
    report.checks.push_back(
        Check(CheckStatus::kSkip, id, "a pendulum's", "not a single hinge pendulum"));
  }
  CheckRow energy = Check(CheckStatus::kFail, "energy", "energy is conserved", "energy grew");
  energy.measured_text = "0.5 of max KE";
  energy.reference_text = "<= 0.01";
  energy.rel_error = 49;
  report.checks.push_back(energy);
  std::string table = VerifyTable(report, TableDetail::kFindings);
  EXPECT_NE(table.find("SKIP  3 checks skipped: not a single hinge pendulum\n"
                       "      analytic.period, experiment.A, experiment.B\n"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("FAIL  energy                   energy is conserved\n"
                       "      measured 0.5 of max KE   reference <= 0.01   rel. error 49\n"
                       "      energy grew\n"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find(", tol 0.01)\n"), std::string::npos) << table;
}

// The Shadow hand's four coupled actuators skip actuator.stability for one reason: the grouped
// row names the actuators, not the check id four times.
TEST(CheckTableTest, SkipsOfOneCheckSharingAReasonListTheirElements) {
  AuditReport report;
  report.model = "right_hand.xml";
  int id = 9;
  for (const char* name : {"rh_A_FFJ0", "rh_A_MFJ0", "rh_A_RFJ0", "rh_A_LFJ0"}) {
    CheckRow row =
        Check(CheckStatus::kSkip, "actuator.stability", "", "its transmission is coupled");
    row.section = "actuator";
    row.element = {"actuator", name, id++};
    report.findings.push_back(row);
  }
  std::string table = AuditTable(report, TableDetail::kFindings);
  EXPECT_NE(table.find("SKIP  4 checks skipped: its transmission is coupled\n"
                       "      actuator.stability: rh_A_FFJ0, rh_A_MFJ0, rh_A_RFJ0, rh_A_LFJ0\n"),
            std::string::npos)
      << table;
}

TEST(ResultJsonTest, ARowKeepsItsNumbersAndUnitsAndNullWhereNothingWasMeasured) {
  VerifyReport report;
  report.model = "pendulum.xml";
  report.tol = 0.01;
  CheckRow period;
  period.id = "analytic.period";
  period.status = CheckStatus::kPass;
  period.measured = {1.72029703652, "s"};
  period.reference = {1.72029703652, "s"};
  period.rel_error = 6.5e-16;
  period.measured_text = period.reference_text = "1.72029703652 s";
  CheckRow determinism;
  determinism.id = "determinism";
  determinism.status = CheckStatus::kPass;
  determinism.measured_text = "identical";
  CheckRow skipped;
  skipped.id = "energy";
  report.checks = {period, determinism, skipped};
  nlohmann::json j = nlohmann::json::parse(VerifyToJson(report));
  EXPECT_EQ(j["model"], "pendulum.xml");
  EXPECT_EQ(j["tol"], 0.01);
  ASSERT_EQ(j["checks"].size(), 3u);
  EXPECT_EQ(j["checks"][0]["measured"], 1.72029703652);
  EXPECT_EQ(j["checks"][0]["measured_unit"], "s");
  EXPECT_EQ(j["checks"][0]["rel_error"], 6.5e-16);
  EXPECT_EQ(j["checks"][1]["measured"], "identical");  // no number: the text
  EXPECT_TRUE(j["checks"][1]["reference"].is_null());
  EXPECT_TRUE(j["checks"][2]["rel_error"].is_null());
  EXPECT_EQ(j["checks"][2]["status"], "SKIP");
  EXPECT_EQ(j["summary"],
            (nlohmann::json{{"pass", 2}, {"warn", 0}, {"fail", 0}, {"skip", 1}, {"accepted", 0}}));
  EXPECT_TRUE(j["checks"][0]["accepted"].is_null());
}

TEST(ResultJsonTest, AuditRowsAreGroupedByLayerWithTheirElements) {
  AuditReport report;
  report.model = "arm.xml";
  report.findings = {Finding(CheckStatus::kWarn, "actuator.limits", {"actuator", "hip", 3},
                             "ctrl unlimited", "bound it")};
  report.findings[0].measured = {2.5, "N*m"};
  report.repro_folders = {"plumb-repro-arm"};
  nlohmann::json j = nlohmann::json::parse(AuditToJson(report));
  const nlohmann::json& row = j["layers"]["actuator"][0];
  EXPECT_EQ(row["id"], "actuator.limits");
  EXPECT_EQ(row["section"], "actuator");
  EXPECT_EQ(row["element"], "actuator 'hip' (id 3)");
  EXPECT_EQ(row["element_type"], "actuator");
  EXPECT_EQ(row["element_name"], "hip");
  EXPECT_EQ(row["element_id"], 3);
  EXPECT_EQ(row["measured"], 2.5);
  EXPECT_EQ(row["measured_unit"], "N*m");
  EXPECT_EQ(row["measured_text"], "ctrl unlimited");
  EXPECT_EQ(row["reference"], "a force bound");
  EXPECT_EQ(row["threshold"], true);
  EXPECT_EQ(row["fix"], "bound it");
  EXPECT_EQ(j["repro_folders"][0], "plumb-repro-arm");
  EXPECT_EQ(j["summary"]["warn"], 1);
}

TEST(ResultJsonTest, AnAcceptedRowKeepsItsStatusAndTheSummaryCountsItApart) {
  AuditReport report = ArmAudit({Finding(CheckStatus::kFail, "actuator.limits",
                                         {"actuator", "hip", 3}, "ctrl unlimited", "bound it"),
                                 Finding(CheckStatus::kWarn, "actuator.limits",
                                         {"actuator", "knee", 4}, "ctrl unlimited", "bound it")});
  report.findings[0].accepted = "the driver bounds it";
  nlohmann::json j = nlohmann::json::parse(AuditToJson(report));
  const nlohmann::json& rows = j["layers"]["actuator"];
  EXPECT_EQ(rows[0]["status"], "FAIL");
  EXPECT_EQ(rows[0]["accepted"], "the driver bounds it");
  EXPECT_TRUE(rows[1]["accepted"].is_null());
  EXPECT_EQ(j["summary"],
            (nlohmann::json{{"pass", 0}, {"warn", 1}, {"fail", 0}, {"skip", 0}, {"accepted", 1}}));
}

}  // namespace
}  // namespace plumb
