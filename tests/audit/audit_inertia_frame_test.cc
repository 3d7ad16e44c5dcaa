// inertia.frame: an <inertial> whose pos or quat were written in another frame (the parent's,
// the joint's) is caught against the body's shape filled uniformly, naming the body with the
// offset of its centre of mass and the angle of its principal axes; clean robots stay quiet.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "audit/check_rows.h"
#include "corpus_robots.h"
#include "fixture.h"
#include "plumb/audit.h"

namespace plumb {
namespace {

using namespace testing::robots;  // NOLINT: the corpus robots by name

// The WARN and FAIL rows of inertia.frame in `r`.
std::vector<CheckRow> Frames(const AuditReport& r) {
  std::vector<CheckRow> rows;
  for (const CheckRow& row : r.findings) {
    if (row.id == "inertia.frame") rows.push_back(row);
  }
  return testing::FindingRows(rows);
}

bool Flags(const AuditReport& r, const std::string& id, const std::string& body) {
  for (const CheckRow& row : r.findings) {
    bool finding = row.status == CheckStatus::kWarn || row.status == CheckStatus::kFail;
    if (row.id == id && finding && row.element.name == body) return true;
  }
  return false;
}

// A 0.4 x 0.1 x 0.04 m plate of 1.6 kg (water's density): its principal moments are distinct, its
// smallest about x (along its length). `inertial` is its <inertial> element ("" to let the
// compiler derive it from the box).
std::string Plate(const std::string& inertial) {
  return R"(<mujoco><worldbody><body name="plate" pos="0 0 1"><freejoint/>)" + inertial +
         R"(<geom type="box" size="0.2 0.05 0.02" density="1000"/></body></worldbody></mujoco>)";
}

constexpr char kPlateInertia[] = R"(mass="1.6" diaginertia="0.0015467 0.021547 0.022667")";

TEST(InertiaFrameTest, APlateWhoseInertialQuatIsTurnedNinetyDegreesIsCaught) {
  AuditReport r =
      Audit(Model::FromXmlString(Plate(std::string(R"(<inertial pos="0 0 0" quat="0.7071068 0 0 )"
                                                   R"(0.7071068" )") +
                                       kPlateInertia + "/>"),
                                 "plate.xml"),
            AuditOptions{});
  std::vector<CheckRow> rows = Frames(r);
  ASSERT_EQ(rows.size(), 1u) << testing::RowsText(rows);
  EXPECT_EQ(rows[0].element.name, "plate");
  EXPECT_EQ(rows[0].status, CheckStatus::kWarn);
  EXPECT_NEAR(rows[0].measured.value, 90, 0.5);
  EXPECT_EQ(rows[0].measured.unit, "deg");
  EXPECT_NE(rows[0].measured_text.find("0 mm from its shape's centroid"), std::string::npos)
      << rows[0].measured_text;
  EXPECT_NE(rows[0].measured_text.find("90 deg off the shape's (the smallest moment's"),
            std::string::npos)
      << rows[0].measured_text;
  // the centre of mass is where it belongs: nothing else to say
  EXPECT_FALSE(Flags(r, "inertia.com", "plate"));
  EXPECT_FALSE(Flags(r, "inertia.shape", "plate"));
}

TEST(InertiaFrameTest, TheSamePlateWithItsOwnFrameOrItsDerivedInertiaIsQuiet) {
  for (const std::string& inertial :
       {std::string(R"(<inertial pos="0 0 0" )") + kPlateInertia + "/>", std::string()}) {
    AuditReport r = Audit(Model::FromXmlString(Plate(inertial), "plate.xml"), AuditOptions{});
    EXPECT_TRUE(Frames(r).empty()) << inertial << "\n" << testing::RowsText(Frames(r));
  }
}

// A plate turned 90 degrees about its length: its two larger moments differ by 0.05 of the
// largest, so the axes between them are not compared, and its length still agrees.
TEST(InertiaFrameTest, AxesOfNearlyEqualMomentsAreNotCompared) {
  AuditReport r =
      Audit(Model::FromXmlString(Plate(std::string(R"(<inertial pos="0 0 0" quat="0.7071068 )"
                                                   R"(0.7071068 0 0" )") +
                                       kPlateInertia + "/>"),
                                 "plate.xml"),
            AuditOptions{});
  EXPECT_TRUE(Frames(r).empty()) << testing::RowsText(Frames(r));
}

TEST(InertiaFrameCorpusTest, CleanRobotsAreQuiet) {
  int audited = 0;
  for (const char* robot : {kUr5e, kG1, kGo2, kT1, kIiwa14, kShadow, kAllegro, kSpotArm}) {
    std::string path = testing::RequireCorpusModel(robot);
    if (path.empty()) continue;
    ++audited;
    AuditReport r = Audit(Model::Load(path), AuditOptions{});
    EXPECT_TRUE(Frames(r).empty()) << robot << "\n" << testing::RowsText(Frames(r));
  }
  if (audited == 0) GTEST_SKIP() << "no robot corpus (make corpus)";
}

// Menagerie's Panda carries the identified inertias of Gaz et al. (2019): link2's smallest
// moment lies across the link, 90 degrees from its mesh's length. The one row on the clean
// Panda, accepted as true (docs/audit.md).
TEST(InertiaFrameCorpusTest, PandasIdentifiedLink2IsTheOneRowOnAPanda) {
  std::string panda = testing::RequireCorpusModel(kPanda);
  if (panda.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  std::vector<CheckRow> rows = Frames(Audit(Model::Load(panda), AuditOptions{}));
  ASSERT_EQ(rows.size(), 1u) << testing::RowsText(rows);
  EXPECT_EQ(rows[0].element.name, "link2");
  EXPECT_NEAR(rows[0].measured.value, 89.7, 0.5);
}

// One planted defect: `edits` on `robot` put `body`'s inertial frame in another frame.
struct Plant {
  const char* robot;
  std::vector<std::pair<std::string, std::string>> edits;
  const char* body;
  double min_angle;  // deg
};

// As it happens in practice: a quat written in the joint's or parent's frame (turned 90
// degrees about x on a UR5e forearm, a G1 shin and a Go2 calf, about the knee's y on a Booster
// T1 shank), and a whole <inertial> of Panda's link4 (pos and fullinertia) written in link3's
// frame. Each centre of mass stays inside its body's box, so inertia.com is quiet: only the
// axes tell.
TEST(InertiaFrameCorpusTest, InertialFramesWrittenInAnotherFrameAreCaught) {
  const std::vector<Plant> plants = {
      {kUr5e,
       {{R"(<inertial mass="2.275" pos="0 0 0.196")",
         R"(<inertial mass="2.275" pos="0 0 0.196" quat="1 1 0 0")"}},
       "forearm_link",
       70},
      {kG1,
       {{R"(quat="0.923418 -0.0327699 0.0158246 0.382067")",
         R"(quat="0.676127 0.629783 -0.258972 0.281352")"}},
       "left_knee_link",
       80},
      {kGo2,
       {{R"(quat="0.710672 0.00154099 -0.00450087 0.703508")",
         R"(quat="0.501431 0.503611 -0.500638 0.494273")"}},
       "FL_calf",
       85},
      {kT1,
       {{R"(quat="0.997573 0.00144024 -0.023949 0.0653706")",
         R"(quat="0.722325 0.0472424 0.688456 0.0452056")"}},
       "Shank_Left",
       85},
      {kPanda,
       {{R"(pos="-5.317e-2 1.04419e-1 2.7454e-2")", R"(pos="0.02933 -0.027454 0.104419")"},
        {R"(fullinertia="2.5853e-2 1.9552e-2 2.8323e-2 7.796e-3 -1.332e-3 8.641e-3")",
         R"(fullinertia="0.025853 0.028323 0.019552 0.001332 0.007796 -0.008641")"}},
       "link4",
       70},
  };
  testing::TempDir dir;
  int planted = 0;
  for (const Plant& plant : plants) {
    std::string path = testing::RequireCorpusModel(plant.robot);
    if (path.empty()) continue;
    // a folder of its own: the copy sits beside links to its model's folder
    std::string copy = dir.path() + "/" + std::to_string(++planted);
    std::filesystem::create_directories(copy);
    AuditReport r =
        Audit(Model::Load(testing::EditedModelCopy(path, plant.edits, copy)), AuditOptions{});
    std::vector<CheckRow> rows = Frames(r);
    const CheckRow* row = nullptr;
    for (const CheckRow& x : rows) {
      if (x.element.name == plant.body) row = &x;
    }
    ASSERT_NE(row, nullptr) << plant.robot << ": " << plant.body << "\n" << testing::RowsText(rows);
    EXPECT_EQ(row->status, CheckStatus::kWarn);
    EXPECT_EQ(row->measured.unit, "deg");
    EXPECT_GT(row->measured.value, plant.min_angle) << row->measured_text;
    EXPECT_NE(row->measured_text.find("mm from its shape's centroid"), std::string::npos);
    EXPECT_NE(row->measured_text.find("shape radii"), std::string::npos);
    EXPECT_FALSE(Flags(r, "inertia.com", plant.body)) << plant.robot;
  }
  if (planted == 0) GTEST_SKIP() << "no robot corpus (make corpus)";
}

}  // namespace
}  // namespace plumb
