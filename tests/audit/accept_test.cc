#include "plumb/accept.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "fixture.h"
#include "plumb/audit.h"
#include "plumb/error.h"

namespace plumb {
namespace {

using testing::TempDir;
using testing::WriteFile;

// Two real findings of plumb audit: WARN actuator.limits about actuator 'strong', FAIL
// contact.free_fall about body 'marker'.
const std::string kTwoFindings = testing::kSourceDir + "/tests/models/two_findings.xml";

CheckRow Row(CheckStatus status, const std::string& id, CheckElement element,
             const std::string& subject = "") {
  CheckRow row;
  row.status = status;
  row.id = id;
  row.section = id.substr(0, id.find('.'));
  row.element = std::move(element);
  row.subject = subject;
  return row;
}

AcceptEntry Entry(const std::string& check, const std::string& element,
                  std::optional<CheckStatus> status = std::nullopt) {
  AcceptEntry entry;
  entry.check = check;
  entry.element = element;
  entry.status = status;
  entry.reason = "reviewed";
  return entry;
}

// Writes `toml` to accept.toml in `dir`, returning its path.
std::string AcceptFile(const TempDir& dir, const std::string& toml) {
  WriteFile(dir.File("accept.toml"), toml);
  return dir.File("accept.toml");
}

TEST(AcceptTest, TheHeadersExampleAcceptsARealFinding) {
  TempDir dir;
  AcceptList accepted = LoadAcceptList(AcceptFile(dir, R"(
[[accept]]
check = "contact.free_fall"
element = "body 'marker'"
reason = "the marker is welded by the motion-capture rig, not by the model"
)"));
  Model model = Model::Load(kTwoFindings);
  AuditReport report = Audit(model, {});
  TakeMujocoWarnings();
  ASSERT_EQ(CountStatus(report.findings, CheckStatus::kFail), 1);
  ASSERT_EQ(CountStatus(report.findings, CheckStatus::kWarn), 1);

  ApplyAcceptList(accepted, &report.findings);
  EXPECT_EQ(CountUnaccepted(report.findings, CheckStatus::kFail), 0);  // the run passes
  EXPECT_EQ(CountStatus(report.findings, CheckStatus::kFail), 1);      // the row stays a FAIL
  EXPECT_EQ(CountUnaccepted(report.findings, CheckStatus::kWarn), 1);  // the motor: not accepted
  EXPECT_EQ(CountAccepted(report.findings), 1);
  for (const CheckRow& row : report.findings) {
    bool marker = row.id == "contact.free_fall" && row.element.name == "marker";
    EXPECT_EQ(row.accepted,
              marker ? "the marker is welded by the motion-capture rig, not by the model" : "")
        << row.id;
    EXPECT_NE(row.id, kAcceptStale);
  }
}

TEST(AcceptTest, LoadsEachEntryWithItsLine) {
  TempDir dir;
  AcceptList list = LoadAcceptList(AcceptFile(dir, R"(# reviewed 2026-10
[[accept]]
check = "inertia.shape"
element = "body 'base_link'"
reason = "  CAD inertia checked against the vendor datasheet  "

[[accept]]
check = "structure.counts"
status = "WARN"
reason = "one model, one robot"
)"));
  EXPECT_EQ(list.file, dir.File("accept.toml"));
  ASSERT_EQ(list.entries.size(), 2u);
  EXPECT_EQ(list.entries[0].check, "inertia.shape");
  EXPECT_EQ(list.entries[0].element, "body 'base_link'");
  EXPECT_FALSE(list.entries[0].status.has_value());
  EXPECT_EQ(list.entries[0].reason, "CAD inertia checked against the vendor datasheet");
  EXPECT_EQ(list.entries[0].line, 2);
  EXPECT_EQ(list.entries[1].element, "");  // the whole model
  EXPECT_EQ(list.entries[1].status, CheckStatus::kWarn);
  EXPECT_EQ(list.entries[1].line, 7);

  // no entry at all is an empty list, not an error
  WriteFile(dir.File("empty.toml"), "# nothing accepted yet\n");
  EXPECT_TRUE(LoadAcceptList(dir.File("empty.toml")).entries.empty());
}

TEST(AcceptTest, ABadFileIsRefusedNamingTheFileAndLine) {
  TempDir dir;
  const std::string file = dir.File("accept.toml");
  struct Case {
    const char* toml;
    std::string expected;  // a part of the message
  } cases[] = {
      {"[[accept]]\ncheck = \"inertia.shape\"\n", file + ":1:1: the [[accept]] entry for "
                                                         "inertia.shape needs a 'reason'"},
      {"[[accept]]\ncheck = \"inertia.shape\"\nreason = \"  \"\n",
       file + ":3:10: the [[accept]] entry for inertia.shape needs a 'reason'"},
      {"[[accept]]\ncheck = \"inertia.shape\"\nreasn = \"ok\"\n",
       file + ":3:1: an [[accept]] entry has no key 'reasn'; it reads check, element, status, "
              "reason; did you mean: reason?"},
      {"[[accept]]\nreason = \"ok\"\n", file + ":1:1: an [[accept]] entry needs 'check'"},
      {"[[accept]]\ncheck = 3\nreason = \"ok\"\n", file + ":2:9: 'check' must be a string"},
      {"[[accept]]\ncheck = \"inertia.shape\"\nreason = \"ok\n",
       file + ":3:"},  // unterminated string: toml++'s own words follow
      {"[[accept]]\ncheck = \"a.b\"\nstatus = \"PASS\"\nreason = \"ok\"\n",
       file + ":3:10: status \"PASS\" is not \"WARN\" or \"FAIL\""},
      {"[[accept]]\ncheck = \"a.b\"\nelement = \"body 'hand' (id 3)\"\nreason = \"ok\"\n",
       file + ":3:11: element \"body 'hand' (id 3)\" names an id; name the element without it "
              "(\"body 'hand'\")"},
      {"[[accept]]\ncheck = \"a.b\"\nreason = \"ok\"\n[[accept]]\ncheck = \"a.b\"\nreason = "
       "\"again\"\n",
       file + ":4:1: this entry repeats the one at line 1 (a.b about the model)"},
      {"[[acept]]\ncheck = \"a.b\"\nreason = \"ok\"\n",
       file + ":1:3: unknown key 'acept': an accept list holds [[accept]] tables only"},
      {"[accept]\ncheck = \"a.b\"\nreason = \"ok\"\n", file + ":1:1: 'accept' must be [[accept]]"},
  };
  for (const Case& c : cases) {
    std::string message = testing::ValueErrorOf([&] { LoadAcceptList(AcceptFile(dir, c.toml)); });
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.toml << "\n" << message;
  }
  // a file that is not there is named too (IoError: the command-line tool exits 2 for both)
  try {
    LoadAcceptList(dir.File("nowhere.toml"));
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.File("nowhere.toml")), std::string::npos) << e.what();
  }
  EXPECT_THROW(LoadAcceptList(dir.path()), IoError);  // a folder
}

TEST(AcceptTest, AnEntryMatchesByCheckKindAndNameNeverById) {
  CheckRow base = Row(CheckStatus::kWarn, "inertia.shape", {"body", "base_link", 3});
  EXPECT_EQ(AcceptElement(base), "body 'base_link'");
  EXPECT_TRUE(Accepts(Entry("inertia.shape", "body 'base_link'"), base));
  // the id shifted (a body added before it): still the same element
  CheckRow shifted = Row(CheckStatus::kWarn, "inertia.shape", {"body", "base_link", 7});
  EXPECT_TRUE(Accepts(Entry("inertia.shape", "body 'base_link'"), shifted));
  // another kind of the same name, another check, a name alone: not accepted
  EXPECT_FALSE(Accepts(Entry("inertia.shape", "body 'base_link'"),
                       Row(CheckStatus::kWarn, "inertia.shape", {"geom", "base_link", 3})));
  EXPECT_FALSE(Accepts(Entry("inertia.density", "body 'base_link'"), base));
  EXPECT_FALSE(Accepts(Entry("inertia.shape", "base_link"), base));
  // only a WARN or FAIL, and only of the entry's status when it has one
  EXPECT_FALSE(Accepts(Entry("inertia.shape", "body 'base_link'"),
                       Row(CheckStatus::kPass, "inertia.shape", {"body", "base_link", 3})));
  EXPECT_FALSE(Accepts(Entry("inertia.shape", "body 'base_link'"),
                       Row(CheckStatus::kSkip, "inertia.shape", {"body", "base_link", 3})));
  EXPECT_TRUE(Accepts(Entry("inertia.shape", "body 'base_link'", CheckStatus::kWarn), base));
  EXPECT_FALSE(Accepts(Entry("inertia.shape", "body 'base_link'", CheckStatus::kFail), base));
  // no element: rows about the whole model only
  CheckRow model = Row(CheckStatus::kWarn, "inertia.mass_matrix", {});
  EXPECT_EQ(AcceptElement(model), "");
  EXPECT_TRUE(Accepts(Entry("inertia.mass_matrix", ""), model));
  EXPECT_FALSE(Accepts(Entry("inertia.shape", ""), base));
  // a row about several elements: its subject, without the ids in it
  CheckRow pair = Row(CheckStatus::kFail, "contact.penetration", {},
                      "geom 'foot' (id 12) / geom 'floor' (id 0)");
  EXPECT_EQ(AcceptElement(pair), "geom 'foot' / geom 'floor'");
  EXPECT_TRUE(Accepts(Entry("contact.penetration", "geom 'foot' / geom 'floor'"), pair));
  CheckRow warning = Row(CheckStatus::kWarn, "warnings.mujoco", {}, "BADQACC");
  EXPECT_TRUE(Accepts(Entry("warnings.mujoco", "BADQACC"), warning));
  // an unnamed element is known only by its id: never accepted
  CheckRow unnamed = Row(CheckStatus::kWarn, "inertia.shape", {"body", "", 3});
  EXPECT_EQ(AcceptElement(unnamed), "body #3");
  EXPECT_FALSE(Accepts(Entry("inertia.shape", "body #3"), unnamed));
}

TEST(AcceptTest, AStaleEntryIsAWarnRowNamingItsFileAndLine) {
  AcceptList list;
  list.file = "accept.toml";
  list.entries = {Entry("inertia.shape", "body 'base_link'"),    // accepts its row
                  Entry("inertia.density", "body 'base_link'"),  // now PASS
                  Entry("inertia.sise", "body 'base_link'"),     // misspelt check
                  Entry("inertia.shape", "body 'hand'"),         // renamed element
                  Entry("actuator.limits", "actuator 'hip'", CheckStatus::kWarn),  // now a FAIL
                  Entry("inertia.shape", "body #5")};                              // unnamed
  for (std::size_t i = 0; i < list.entries.size(); ++i) {
    list.entries[i].line = 2 + 4 * static_cast<int>(i);
  }
  std::vector<CheckRow> rows = {
      Row(CheckStatus::kWarn, "inertia.shape", {"body", "base_link", 1}),
      Row(CheckStatus::kWarn, "inertia.shape", {"body", "left_hand", 2}),
      Row(CheckStatus::kPass, "inertia.density", {"body", "base_link", 1}),
      Row(CheckStatus::kFail, "actuator.limits", {"actuator", "hip", 0}),
      Row(CheckStatus::kWarn, "inertia.shape", {"body", "", 5})};
  ApplyAcceptList(list, &rows);
  ASSERT_EQ(rows.size(), 10u);  // five rows, then one per stale entry
  EXPECT_EQ(rows[0].accepted, "reviewed");
  for (std::size_t i = 1; i < 5; ++i) EXPECT_EQ(rows[i].accepted, "") << i;
  EXPECT_EQ(CountUnaccepted(rows, CheckStatus::kFail), 1);  // the hip: WARN accepted, FAIL not
  for (std::size_t i = 5; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].id, "accept.stale");
    EXPECT_EQ(rows[i].section, "accept");
    EXPECT_EQ(rows[i].status, CheckStatus::kWarn);
    EXPECT_TRUE(rows[i].element.empty());
    EXPECT_EQ(rows[i].explanation, "accepted because: reviewed");
  }
  EXPECT_EQ(rows[5].subject, "accept.toml:6: inertia.density about body 'base_link'");
  EXPECT_EQ(rows[5].measured_text, "now PASS");
  EXPECT_EQ(rows[5].fix, "the finding it accepted is gone: delete the entry (accept.toml:6)");
  EXPECT_EQ(rows[6].subject, "accept.toml:10: inertia.sise about body 'base_link'");
  EXPECT_EQ(rows[6].measured_text, "no WARN or FAIL of inertia.sise");
  EXPECT_NE(rows[6].fix.find("did you mean: inertia.shape?"), std::string::npos) << rows[6].fix;
  EXPECT_EQ(rows[7].measured_text, "no WARN or FAIL of inertia.shape about body 'hand'");
  EXPECT_NE(rows[7].fix.find("; inertia.shape is about: "), std::string::npos) << rows[7].fix;
  EXPECT_NE(rows[7].fix.find("body 'left_hand'"), std::string::npos) << rows[7].fix;
  EXPECT_EQ(rows[8].subject, "accept.toml:18: actuator.limits about actuator 'hip' (WARN only)");
  EXPECT_EQ(rows[8].measured_text, "now FAIL; the entry accepts a WARN only");
  EXPECT_EQ(rows[9].measured_text, "body #5 has no name");
  EXPECT_NE(rows[9].fix.find("name it in the model"), std::string::npos) << rows[9].fix;

  // an empty list changes nothing
  std::vector<CheckRow> same = {rows[0]};
  ApplyAcceptList(AcceptList(), &same);
  EXPECT_EQ(same.size(), 1u);
}

}  // namespace
}  // namespace plumb
