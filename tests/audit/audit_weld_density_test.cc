// inertia.density on weld groups and on geoms' written masses (issue 50, part 3), on real robots
// of the corpus: a mass no material has, put where the audit used to look away (a body welded to
// its parent, a geom's own mass attribute), the way it happens in practice, is caught and named;
// the same robots as published give no inertia.density row; a lump meant as one is accepted
// through the accept list and its row stays.

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "core/mujoco_compat.h"
#include "corpus_robots.h"
#include "fixture.h"
#include "plumb/accept.h"
#include "plumb/audit.h"

namespace plumb {
namespace {

using namespace testing::robots;  // NOLINT: the corpus robots by name

using Edits = std::vector<std::pair<std::string, std::string>>;

// The G1 with a 5 kg lump (a hand or payload written as an inertial-only body) welded onto its
// 85 g left wrist roll link.
Edits G1HandLump() {
  return {{R"(<geom class="visual" mesh="left_wrist_roll_link"/>)",
           R"(<geom class="visual" mesh="left_wrist_roll_link"/>
              <body name="hand_lump" pos="0.03 0 0">
                <inertial pos="0 0 0" mass="5" diaginertia="0.001 0.001 0.001"/>
              </body>)"}};
}

class WeldDensityTest : public ::testing::Test {
 protected:
  // The inertia.density WARN and FAIL rows of the audit of `path` after `edits`.
  std::vector<CheckRow> DensityRows(const std::string& path, const Edits& edits = {}) {
    std::string model = edits.empty() ? path : testing::EditedModelCopy(path, edits, dir_.path());
    return DensityRows(Audit(Model::Load(model), AuditOptions{}).findings);
  }

  static std::vector<CheckRow> DensityRows(const std::vector<CheckRow>& findings) {
    std::vector<CheckRow> out;
    for (const CheckRow& row : findings) {
      bool finding = row.status == CheckStatus::kWarn || row.status == CheckStatus::kFail;
      if (row.id == "inertia.density" && finding) out.push_back(row);
    }
    return out;
  }

  static std::string Rows(const std::vector<CheckRow>& rows) {
    std::string out;
    for (const CheckRow& row : rows) {
      out += row.About() + ": " + row.measured_text + "\n  fix: " + row.fix + "\n";
    }
    return out;
  }

  // Expects one inertia.density WARN about `kind` `name` whose measured text holds each of
  // `words`, the robot as published having none.
  void ExpectCaught(const char* robot, const Edits& edits, const std::string& kind,
                    const std::string& name, const std::vector<std::string>& words) {
    std::string path = testing::RequireCorpusModel(robot);
    if (path.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
    EXPECT_TRUE(DensityRows(path).empty()) << Rows(DensityRows(path));
    std::vector<CheckRow> rows = DensityRows(path, edits);
    ASSERT_EQ(rows.size(), 1u) << Rows(rows);
    EXPECT_EQ(rows[0].status, CheckStatus::kWarn);
    EXPECT_EQ(rows[0].element.kind, kind) << Rows(rows);
    EXPECT_EQ(rows[0].element.name, name) << Rows(rows);
    for (const std::string& word : words) {
      EXPECT_NE(rows[0].measured_text.find(word), std::string::npos) << "no '" << word << "' in\n"
                                                                     << Rows(rows);
    }
  }

  testing::TempDir dir_;
};

// G1: a 5 kg lump (a hand or payload written as an inertial-only body) welded onto the 85 g
// wrist roll link: 5.09 kg in the link's 11.9 cm^3 mesh, 4.3e5 kg/m^3. The row names the group's
// root and the welded body that carries the mass.
TEST_F(WeldDensityTest, AHeavyLumpWeldedOntoALightLinkIsCaught) {
  ExpectCaught(kG1, G1HandLump(), "body", "left_wrist_roll_link",
               {"weld group of 'left_wrist_roll_link' and 1 welded body ('hand_lump')",
                "welded 'hand_lump' carries 5 kg"});
}

// Robotiq 2F-85: the welded pad's 3.5 g written as 3.5 (grams taken for kg): the follower's
// group holds 3.51 kg in 15 cm^3.
TEST_F(WeldDensityTest, AWeldedPadsMassInGramsIsCaught) {
  ExpectCaught(
      kRobotiq,
      {{R"(<inertial mass="0.0035" pos="0 -0.0025 0.0185")",
        R"(<inertial mass="3.5" pos="0 -0.0025 0.0185")"}},
      "body", "right_follower",
      {"welded bodies ('right_pad', 'right_silicone_pad')", "welded 'right_pad' carries 3.5 kg"});
}

// Robotiq 2F-85: the left silicone pad's STL, in mm, loaded without its class's scale 0.001
// (1000 times too long, 1300 m^3) with its 1.3 g written on the geom, so the compiler keeps the
// mass: 1e-6 kg/m^3. The follower's group is as light as its pad: its row is the one, naming
// the geom as the cause.
TEST_F(WeldDensityTest, AMeshInMillimetresWithItsMassWrittenIsCaught) {
  if (!PLUMB_MUJOCO_HAS_SPEC) GTEST_SKIP() << "needs mjSpec to read the geom's mass";
  std::string robot = testing::RequireCorpusModel(kRobotiq);
  if (robot.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> rows =
      DensityRows(robot, {{R"(<mesh class="2f85" file="silicone_pad.stl"/>)",
                           R"(<mesh class="2f85" file="silicone_pad.stl"/>
                  <mesh name="silicone_pad_mm" file="silicone_pad.stl"/>)"},
                          {R"(<body name="left_silicone_pad">
                <geom class="visual" mesh="silicone_pad" material="black"/>)",
                           R"(<body name="left_silicone_pad">
                <geom name="left_silicone" class="visual" mesh="silicone_pad_mm" mass="0.0013"
                      material="black"/>)"}});
  ASSERT_EQ(rows.size(), 1u) << Rows(rows);
  EXPECT_EQ(rows[0].element.name, "left_follower") << Rows(rows);
  EXPECT_LT(rows[0].measured.value, 10);  // the mesh band's floor
  EXPECT_NE(rows[0].fix.find("geom 'left_silicone'"), std::string::npos) << Rows(rows);
}

// Robotiq 2F-85: the right silicone pad (a mesh geom) given its 1.3 g as mass="1.3": 1e6 kg/m^3
// in its own 1.3 cm^3, while the follower's group, 1.32 kg in 15 cm^3, still passes the mesh
// band. The geom's own row names it.
TEST_F(WeldDensityTest, AMeshGeomsMassInTheWrongUnitIsCaught) {
  if (!PLUMB_MUJOCO_HAS_SPEC) GTEST_SKIP() << "needs mjSpec to read the geom's mass";
  ExpectCaught(kRobotiq,
               {{R"(<body name="right_silicone_pad">
                <geom class="visual" mesh="silicone_pad" material="black"/>)",
                 R"(<body name="right_silicone_pad">
                <geom name="right_silicone" class="visual" mesh="silicone_pad" mass="1.3"
                      material="black"/>)"}},
               "geom", "right_silicone", {"mass=\"1.3\" kg written", "body 'right_silicone_pad'"});
}

// Go2: the welded foot pad (a 2.2 cm sphere, mass="0" as published) given mass="20", its 20 g
// in grams: 4.5e5 kg/m^3. The calf's group (20.2 kg in its meshes' 242 cm^3) passes the mesh
// band; the geom does not pass the primitive one.
TEST_F(WeldDensityTest, AFootPadsMassInGramsIsCaught) {
  if (!PLUMB_MUJOCO_HAS_SPEC) GTEST_SKIP() << "needs mjSpec to read the geom's mass";
  ExpectCaught(kGo2,
               {{R"(<geom name="FL" class="collision" size="0.022" mass="0"/>)",
                 R"(<geom name="FL" class="collision" size="0.022" mass="20"/>)"}},
               "geom", "FL", {"mass=\"20\" kg written", "body 'FL_foot'"});
}

// UR5e: a tool flange welded to the wrist, its 0.5 kg written as 500 (grams). The wrist's group
// is not judged (its mesh is open); the flange geom's 1.8e7 kg/m^3 is.
TEST_F(WeldDensityTest, AToolFlangesMassInGramsIsCaught) {
  if (!PLUMB_MUJOCO_HAS_SPEC) GTEST_SKIP() << "needs mjSpec to read the geom's mass";
  ExpectCaught(kUr5e,
               {{R"(<site name="attachment_site" pos="0 0.1 0" quat="-1 1 0 0"/>)",
                 R"(<site name="attachment_site" pos="0 0.1 0" quat="-1 1 0 0"/>
                  <body name="tool_flange" pos="0 0.1 0" quat="-1 1 0 0">
                    <geom name="flange" type="cylinder" size="0.03 0.005" mass="500"/>
                  </body>)"}},
               "geom", "flange", {"mass=\"500\" kg written", "body 'tool_flange'"});
}

// One cause, one row: a sphere's mass written in grams makes its body's group too heavy too, so
// the group's row names the sphere and the sphere gets no row of its own (body 'a'); where the
// group still passes (body 'b': its 1 kg box dilutes the sphere's 20 kg to 21000 kg/m^3), the
// sphere's own row names it. Body 'c' has nothing welded and no written mass: the row it always
// had, with no word of weld groups or of the accept list.
TEST_F(WeldDensityTest, AGeomIsNamedOnceInTheRowItsMassCauses) {
  if (!PLUMB_MUJOCO_HAS_SPEC) GTEST_SKIP() << "needs mjSpec to read the geoms' masses";
  Model model = Model::FromXmlString(R"(<mujoco><worldbody>
    <body name="a"><freejoint/><geom type="box" size=".05 .05 .05"/>
      <geom name="a_lump" size=".005" mass="50"/></body>
    <body name="b" pos="1 0 0"><freejoint/><geom type="box" size=".05 .05 .05"/>
      <geom name="b_lump" size=".005" mass="20"/></body>
    <body name="c" pos="2 0 0"><freejoint/>
      <inertial pos="0 0 0" mass="30" diaginertia=".001 .001 .001"/>
      <geom type="box" size=".05 .05 .05"/></body>
  </worldbody></mujoco>)");
  std::vector<CheckRow> rows = DensityRows(Audit(model, AuditOptions{}).findings);
  ASSERT_EQ(rows.size(), 3u) << Rows(rows);
  EXPECT_EQ(rows[0].About(), "body 'a' (id 1)");
  EXPECT_NE(rows[0].fix.find("geom 'a_lump'"), std::string::npos) << Rows(rows);
  EXPECT_EQ(rows[1].About(), "geom 'b_lump' (id 3)");
  EXPECT_NE(rows[1].measured_text.find("in body 'b'"), std::string::npos) << Rows(rows);
  EXPECT_EQ(rows[2].About(), "body 'c' (id 3)");
  EXPECT_EQ(rows[2].measured_text, "3e+04 kg/m^3 (30 kg in 0.001 m^3)");
  EXPECT_EQ(rows[2].fix,
            "no solid is this light or heavy (water 1000, steel 7850): check the mass, the geom "
            "sizes and their units (a mesh in mm is 1e9 times too big)");
}

// A lump meant as one (the G1's 5 kg hand of the first test, modelled as a point on purpose) is
// declared in the accept list: its row stays, with its status, marked accepted with the reason,
// and fails no run.
TEST_F(WeldDensityTest, ALumpMeantAsOneIsAcceptedAndItsRowStays) {
  std::string g1 = testing::RequireCorpusModel(kG1);
  if (g1.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::string edited = testing::EditedModelCopy(g1, G1HandLump(), dir_.path());
  AuditReport report = Audit(Model::Load(edited), AuditOptions{});
  AcceptList accepted;
  accepted.entries.push_back({"inertia.density", "body 'left_wrist_roll_link'", CheckStatus::kWarn,
                              "the 5 kg gripper is lumped at the wrist on purpose", 0});
  ApplyAcceptList(accepted, &report.findings);
  std::vector<CheckRow> rows = DensityRows(report.findings);
  ASSERT_EQ(rows.size(), 1u) << Rows(rows);
  EXPECT_EQ(rows[0].status, CheckStatus::kWarn);
  EXPECT_EQ(rows[0].accepted, "the 5 kg gripper is lumped at the wrist on purpose");
  for (const CheckRow& row : report.findings) {
    EXPECT_NE(row.id, kAcceptStale) << row.measured_text;  // the entry accepted its row
  }
  int unaccepted = 0;
  for (const CheckRow& row : DensityRows(report.findings)) unaccepted += row.accepted.empty();
  EXPECT_EQ(unaccepted, 0);
}

}  // namespace
}  // namespace plumb
