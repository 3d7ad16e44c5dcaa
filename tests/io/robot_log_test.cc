// Reading logs: what is an input and what was measured, sparse rows, the flight recorder's
// layout, column maps, and bad logs named by file, row and column.

#include "plumb/robot_log.h"

#include <gtest/gtest.h>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

class RobotLogTest : public ::testing::Test {
 protected:
  RobotLog Load(const std::string& csv, const ColumnMap& map = {}) {
    testing::WriteFile(dir_.File("log.csv"), csv);
    return LoadRobotLog(model_, dir_.File("log.csv"), 0.002, map);
  }
  // The message a bad log gets.
  std::string Complaint(const std::string& csv, const ColumnMap& map = {}) {
    try {
      Load(csv, map);
    } catch (const ValueError& e) {
      return e.what();
    }
    return "(no error)";
  }
  testing::TempDir dir_;
  Model model_ = Model::Load(testing::kPendulum);
};

TEST_F(RobotLogTest, InputsAndMeasurementsAreToldApartByTheirPaths) {
  RobotLog log = Load(
      "time,qfrc_applied[hinge],qpos[hinge],qvel[hinge]\n0,1,0.7,0\n0.002,2,0.69,-0.01\n"
      "0.005,3,0.68,-0.02\n");
  ASSERT_EQ(log.inputs.size(), 1u);
  ASSERT_EQ(log.measured.size(), 2u);
  EXPECT_EQ(log.inputs[0].path.text, "qfrc_applied[hinge]");
  EXPECT_EQ(log.inputs[0].value, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(log.measured[1].time, (std::vector<double>{0, 0.002, 0.005}));  // irregular
  EXPECT_EQ(log.start, 0);
  EXPECT_EQ(log.end, 0.005);
}

TEST_F(RobotLogTest, EmptyCellsAreNotSamplesAndTheFlightRecordersColumnsAreSkipped) {
  RobotLog log = Load(
      "time,kind,event,qpos[0],qvel[0],qfrc_applied[0],cmd.tau[0],state.q[0]\n"
      "0,state,,0.5,0,0,,0.5\n"
      "0,command,,,,,1.5,\n"
      "0.001,event,\"watchdog: no command, damping\",,,,,\n"
      "0.002,state,,0.51,0.1,1.5,,0.51\n");
  ASSERT_EQ(log.measured.size(), 2u);
  EXPECT_EQ(log.measured[0].value, (std::vector<double>{0.5, 0.51}));
  ASSERT_EQ(log.inputs.size(), 1u);
  EXPECT_EQ(log.inputs[0].time, (std::vector<double>{0, 0.002}));
}

TEST_F(RobotLogTest, AColumnMapRenamesAndDrops) {
  ColumnMap map;
  map.source = "map.toml";
  map.columns = {{"t", "time"},
                 {"angle", "qpos[hinge]"},
                 {"cmd.tau[0]", "qfrc_applied[hinge]"},
                 {"qfrc_applied[0]", ""}};
  RobotLog log = Load("t,angle,cmd.tau[0],qfrc_applied[0]\n0,0.1,1,9\n0.004,0.2,2,9\n", map);
  ASSERT_EQ(log.measured.size(), 1u);
  EXPECT_EQ(log.measured[0].column, "angle");
  EXPECT_EQ(log.measured[0].path.text, "qpos[hinge]");
  ASSERT_EQ(log.inputs.size(), 1u);
  EXPECT_EQ(log.inputs[0].column, "cmd.tau[0]");
  map.columns["nosuch"] = "qvel[hinge]";
  EXPECT_EQ(Complaint("t,angle,cmd.tau[0],qfrc_applied[0]\n0,0.1,1,9\n0.004,0.2,2,9\n", map),
            "map.toml: the column map names 'nosuch', which " + dir_.File("log.csv") +
                " has no column of");
}

TEST_F(RobotLogTest, AColumnMapFileIsRead) {
  testing::WriteFile(dir_.File("map.toml"),
                     "[columns]\n\"angle\" = \"qpos[hinge]\"\nt = \"time\"\n");
  ColumnMap map = LoadColumnMap(dir_.File("map.toml"));
  EXPECT_EQ(map.columns.at("angle"), "qpos[hinge]");
  EXPECT_EQ(map.columns.at("t"), "time");
  testing::WriteFile(dir_.File("bad.toml"), "[columns]\nangle = 3\n");
  try {
    LoadColumnMap(dir_.File("bad.toml"));
    FAIL();
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.toml:2:9: columns.'angle': must be a plumb path"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(LoadColumnMap(dir_.File("missing.toml")), IoError);
}

TEST_F(RobotLogTest, BadLogsAreNamedByFileRowAndColumn) {
  std::string f = dir_.File("log.csv");
  EXPECT_EQ(Complaint("time,qpos[hinge]\n0,0.1\n0.004,0.2\n0.002,0.3\n"),
            f + ": row 4, column 'time': goes backwards: 0.002 s after 0.004 s");
  EXPECT_EQ(Complaint("time,qpos[hinge]\n0,0.1\n0.004,nan\n"),
            f + ": row 3, column 'qpos[hinge]': is nan: a log must hold finite numbers (drop or "
                "repair the row)");
  EXPECT_EQ(Complaint("time,qpos[hinge]\n0,0.1\n0.004,abc\n"),
            f + ": row 3, column 'qpos[hinge]': 'abc' is not a number");
  EXPECT_EQ(Complaint("time,qpos[hinge]\n0,0.1\n0.001,0.2\n"),
            f + ": row 3, column 'time': spans 0.001 s, less than one timestep of the model "
                "(0.002 s): nothing to simulate");
  EXPECT_EQ(Complaint("time,qpos[hinge]\n0,0.1,3\n"),
            f + ": row 2: has 3 cells where the header has 2");
  EXPECT_EQ(Complaint("t,qpos[hinge]\n0,0.1\n"),
            f + ": row 1: has no 'time' column (seconds); name one in a column map");
  EXPECT_EQ(Complaint("time,qfrc_applied[hinge]\n0,0.1\n0.01,0\n"),
            f + ": row 1: has no measured column (qpos[...], qvel[...], sensordata[...]): "
                "nothing to compare");
  EXPECT_EQ(Complaint(""), f + ": row 1: is empty: a log starts with a header row");
  EXPECT_EQ(Complaint("time,qpos[hinge]\n"), f + ": row 1: has a header but no rows");
  std::string unknown = Complaint("time,qpos[hnige]\n0,1\n0.01,1\n");
  EXPECT_NE(unknown.find(f + ": row 1, column 'qpos[hnige]': "), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("hinge"), std::string::npos) << unknown;  // the nearest name
  EXPECT_NE(unknown.find("column map"), std::string::npos) << unknown;
  EXPECT_NE(Complaint("time,dof_damping[hinge]\n0,1\n0.01,1\n").find("is a model parameter"),
            std::string::npos);
  EXPECT_NE(Complaint("time,qpos[hinge],qpos[0]\n0,1,1\n0.01,1,1\n")
                .find("column 'qpos[0]': names the same element as column 'qpos[hinge]'"),
            std::string::npos);
  EXPECT_NE(Complaint("time,xpos[link]\n0,1\n0.01,1\n").find("a column holds one"),
            std::string::npos);
  EXPECT_THROW(LoadRobotLog(model_, dir_.File("missing.csv"), 0.002), IoError);
}

}  // namespace
}  // namespace plumb
