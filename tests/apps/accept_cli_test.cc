// plumb audit --accept as a team's CI meets it: an accepted FAIL or WARN no longer fails the
// run, a stale entry warns, and a bad accept list is bad input.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "fixture.h"

namespace plumb {
namespace {

using testing::CommandResult;
using testing::RunPlumb;
using testing::TempDir;

// The audit's skipped count on two_findings.xml: MuJoCo 2.x adds the inertia.shape SKIP row (no
// mjSpec to tell written inertias from derived ones).
// inertia.shape judges from the geoms on every MuJoCo (no SKIP on 2.x without the MJCF)
std::string Skipped() { return "1 skipped"; }
using testing::WriteFile;

// WARN actuator.limits about actuator 'strong', FAIL contact.free_fall about body 'marker'.
const std::string kModel = testing::kSourceDir + "/tests/models/two_findings.xml";

const char* const kAcceptFail = R"([[accept]]
check = "contact.free_fall"
element = "body 'marker'"
reason = "the rig welds the marker; judged 2026-10"
)";

const char* const kAcceptWarn = R"(
[[accept]]
check = "actuator.limits"
element = "actuator 'strong'"
status = "WARN"
reason = "the motor driver bounds the current"
)";

TEST(AcceptCliTest, AnAcceptedFailNoLongerFailsTheRun) {
  TempDir dir;
  CommandResult before = RunPlumb("audit '" + kModel + "'", dir.path());
  EXPECT_EQ(before.exit_code, 1) << before.out << before.err;
  EXPECT_NE(before.out.find("FAIL  contact.free_fall          body 'marker'"), std::string::npos)
      << before.out;

  WriteFile(dir.File("accept.toml"), kAcceptFail);
  CommandResult after = RunPlumb("audit '" + kModel + "' --accept accept.toml", dir.path());
  EXPECT_EQ(after.exit_code, 0) << after.out << after.err;
  EXPECT_NE(after.out.find("ACCEPT  contact.free_fall        body 'marker' (id 2)\n"),
            std::string::npos)
      << after.out;
  EXPECT_NE(after.out.find("      FAIL accepted: the rig welds the marker; judged 2026-10\n"),
            std::string::npos)
      << after.out;
  EXPECT_EQ(after.out.find("\nFAIL  "), std::string::npos) << after.out;  // grep ^FAIL finds none
  EXPECT_NE(after.out.find(" 1 warned, 0 failed, " + Skipped() + ", 1 accepted"),
            std::string::npos)
      << after.out;

  // the JSON keeps the row's status and says why it was accepted
  CommandResult json =
      RunPlumb("audit '" + kModel + "' --accept accept.toml --format json", dir.path());
  EXPECT_EQ(json.exit_code, 0) << json.err;
  nlohmann::json j = nlohmann::json::parse(json.out);
  int accepted = 0;
  for (const auto& [layer, rows] : j["layers"].items()) {
    for (const nlohmann::json& row : rows) {
      if (row["accepted"].is_null()) continue;
      ++accepted;
      EXPECT_EQ(row["id"], "contact.free_fall");
      EXPECT_EQ(row["status"], "FAIL");
      EXPECT_EQ(row["element_name"], "marker");
      EXPECT_EQ(row["accepted"], "the rig welds the marker; judged 2026-10");
    }
  }
  EXPECT_EQ(accepted, 1) << json.out;
  EXPECT_EQ(j["summary"]["fail"], 0);
  EXPECT_EQ(j["summary"]["accepted"], 1);
}

TEST(AcceptCliTest, StrictPassesOnceEveryWarningIsAccepted) {
  TempDir dir;
  WriteFile(dir.File("fail.toml"), kAcceptFail);
  WriteFile(dir.File("both.toml"), std::string(kAcceptFail) + kAcceptWarn);
  // the motor's WARN is not accepted: --strict fails on it
  CommandResult fail_only =
      RunPlumb("audit '" + kModel + "' --strict --accept fail.toml", dir.path());
  EXPECT_EQ(fail_only.exit_code, 1) << fail_only.out << fail_only.err;
  EXPECT_NE(fail_only.out.find("WARN  actuator.limits            actuator 'strong'"),
            std::string::npos)
      << fail_only.out;
  CommandResult both = RunPlumb("audit '" + kModel + "' --strict --accept both.toml", dir.path());
  EXPECT_EQ(both.exit_code, 0) << both.out << both.err;
  EXPECT_NE(both.out.find("      WARN accepted: the motor driver bounds the current\n"),
            std::string::npos)
      << both.out;
  EXPECT_NE(both.out.find(" 0 warned, 0 failed, " + Skipped() + ", 2 accepted"),
            std::string::npos)
      << both.out;
}

TEST(AcceptCliTest, AStaleEntryIsAWarningNamingItsLine) {
  TempDir dir;
  // the marker was renamed "tracker": the entry for 'marker' matches nothing now
  WriteFile(dir.File("accept.toml"), std::string(kAcceptWarn) + R"(
[[accept]]
check = "contact.free_fall"
element = "body 'tracker'"
reason = "the rig welds the tracker"
)");
  CommandResult r = RunPlumb("audit '" + kModel + "' --accept accept.toml", dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;  // the marker's FAIL is not accepted
  EXPECT_NE(r.out.find("== accept\n"
                       "WARN  accept.stale               accept.toml:8: contact.free_fall about "
                       "body 'tracker'\n"
                       "      no WARN or FAIL of contact.free_fall about body 'tracker'\n"
                       "      fix: delete the entry (accept.toml:8) if its finding is gone, or "
                       "name the element as the rows do, by kind and name (\"body 'name'\"); "
                       "contact.free_fall is about: body 'marker'\n"),
            std::string::npos)
      << r.out;

  // once the marker collides with the floor the FAIL is gone, and the stale entry alone fails
  // --strict
  std::string xml = testing::ReadFile(kModel);
  const std::string collides_with_nothing = R"(contype="0" conaffinity="0")";
  WriteFile(dir.File("fixed.xml"),
            xml.replace(xml.find(collides_with_nothing), collides_with_nothing.size(), ""));
  WriteFile(dir.File("accept.toml"), std::string(kAcceptWarn) + "\n" + kAcceptFail);
  CommandResult fixed = RunPlumb("audit fixed.xml --accept accept.toml", dir.path());
  EXPECT_EQ(fixed.exit_code, 0) << fixed.out << fixed.err;
  EXPECT_NE(fixed.out.find("WARN  accept.stale               accept.toml:8: contact.free_fall "
                           "about body 'marker'\n"),
            std::string::npos)
      << fixed.out;
  EXPECT_EQ(RunPlumb("audit fixed.xml --accept accept.toml --strict", dir.path()).exit_code, 1);
}

TEST(AcceptCliTest, ABadAcceptListIsBadInputNamingTheFile) {
  TempDir dir;
  WriteFile(dir.File("accept.toml"), "[[accept]]\ncheck = \"contact.free_fall\"\n");
  CommandResult r = RunPlumb("audit '" + kModel + "' --accept accept.toml", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_EQ(r.out, "");  // refused before the audit ran
  EXPECT_NE(r.err.find("plumb: error: accept.toml:1:1: the [[accept]] entry for "
                       "contact.free_fall needs a 'reason'"),
            std::string::npos)
      << r.err;

  CommandResult missing = RunPlumb("audit '" + kModel + "' --accept nowhere.toml", dir.path());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("nowhere.toml"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace plumb
