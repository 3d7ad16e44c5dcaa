#include "plumb/rollout_csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "plumb/sample_writer.h"

namespace plumb {
namespace {

TEST(RolloutCsvTest, ColumnsAreTheRolloutItsParametersItsMetricsAndHowItEnded) {
  std::vector<std::string> columns =
      RolloutCsvColumns({"body_mass[link]", "dof_damping[hinge]"}, {"qpos[hinge]@1"});
  EXPECT_EQ(columns,
            (std::vector<std::string>{"rollout", "body_mass[link]", "dof_damping[hinge]",
                                      "qpos[hinge]@1", "diverged", "diverged_at", "problem"}));
  // a header quotes what holds a comma: a metric such as max(qpos[a],qpos[b]) stays one column
  EXPECT_EQ(CsvLine({"rollout", "max(a,b)", "say \"hi\""}),
            "rollout,\"max(a,b)\",\"say \"\"hi\"\"\"\n");
}

TEST(RolloutCsvTest, ARowReadsBackExactlyWithEmptyFieldsForWhatWasNotMeasured) {
  RolloutResult ok;
  ok.index = 7;
  ok.params = {0.1, 1.0 / 3};
  ok.metrics = {-0.25};
  EXPECT_EQ(RolloutCsvRow(ok), "7,0.1,0.3333333333333333,-0.25,0,,\n");
  EXPECT_EQ(std::stod("0.3333333333333333"), 1.0 / 3);

  RolloutResult bad;
  bad.index = 12;
  bad.params = {2.5, NAN};
  bad.metrics = {NAN};
  bad.diverged = true;
  bad.diverged_time = 0.042;
  bad.problem = "qacc NaN, at t = 0.042 s";
  EXPECT_EQ(RolloutCsvRow(bad), "12,2.5,,,1,0.042,\"qacc NaN, at t = 0.042 s\"\n");
}

}  // namespace
}  // namespace plumb
