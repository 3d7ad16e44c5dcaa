// What plumb identify and plumb.identify share before and after a fit: the delay's name, the
// options' checks naming their argument, the covariance, and the fitted model.

#include <gtest/gtest.h>

#include <cmath>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/identify.h"

namespace plumb {
namespace {

using IdentifyOptionsTest = testing::MujocoTest;

TEST_F(IdentifyOptionsTest, DelayKindsByTheirNames) {
  EXPECT_EQ(ParseDelayKind(""), DelayKind::kNone);
  EXPECT_EQ(ParseDelayKind("ctrl"), DelayKind::kInput);
  EXPECT_EQ(ParseDelayKind("sensor"), DelayKind::kSensor);
  try {
    ParseDelayKind("ctl");
    ADD_FAILURE();
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.argument(), "delay");
    EXPECT_EQ(e.value(), "'ctl'");
  }
}

// Each bad option is refused naming the argument it came in.
TEST_F(IdentifyOptionsTest, ChecksNameTheArgument) {
  auto refused = [](IdentifyOptions o) {
    try {
      CheckIdentifyOptions(o);
    } catch (const ArgumentError& e) {
      return e.argument();
    }
    return std::string("accepted");
  };
  IdentifyOptions o;
  EXPECT_EQ(refused(o), "accepted");
  o.replay.window = -1;
  EXPECT_EQ(refused(o), "window");
  o = {};
  o.replay.window = NAN;
  EXPECT_EQ(refused(o), "window");
  o = {};
  o.max_delay = 0;
  EXPECT_EQ(refused(o), "max_delay");
  o = {};
  o.threads = -1;
  EXPECT_EQ(refused(o), "threads");
  o = {};
  o.max_iterations = 0;
  EXPECT_EQ(refused(o), "max_iterations");
  o = {};
  o.replay.input_delay = INFINITY;
  EXPECT_EQ(refused(o), "input_delay");
}

// cov = corr x se_i x se_j: the diagonal is the variances.
TEST_F(IdentifyOptionsTest, CovarianceFromCorrelationAndErrors) {
  IdentifyResult r;
  r.estimates.resize(2);
  r.estimates[0].classical_std_error = 2;
  r.estimates[1].classical_std_error = 3;
  r.correlation = {{1, -0.5}, {-0.5, 1}};
  std::vector<std::vector<double>> cov = ClassicalCovariance(r);
  EXPECT_DOUBLE_EQ(cov[0][0], 4);
  EXPECT_DOUBLE_EQ(cov[1][1], 9);
  EXPECT_DOUBLE_EQ(cov[0][1], -3);
  EXPECT_DOUBLE_EQ(cov[1][0], -3);
}

TEST_F(IdentifyOptionsTest, FittedModelIsACopyWithTheEstimates) {
  Model model = Model::Load(testing::kPendulum);
  IdentifyResult r;
  Estimate e;
  e.path = "dof_damping[hinge]";
  e.value = 0.25;
  r.estimates = {e};
  Model fitted = FittedModel(model, r);
  EXPECT_EQ(fitted->dof_damping[0], 0.25);
  EXPECT_EQ(model->dof_damping[0], 0.05);
}

}  // namespace
}  // namespace plumb
