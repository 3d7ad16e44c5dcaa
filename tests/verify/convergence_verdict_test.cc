// verify's convergence row and plumb converge decide by one rule (RecommendedLevel) on one
// ladder: they recommend the same timestep, and the row passes exactly when that is the
// model's own.

#include <gtest/gtest.h>

#include "fixture.h"
#include "plumb/converge.h"
#include "plumb/metric.h"
#include "plumb/verify.h"

namespace plumb {
namespace {

const CheckRow& Convergence(const VerifyReport& report) {
  for (const CheckRow& r : report.checks) {
    if (r.id == "convergence") return r;
  }
  throw std::runtime_error("no convergence row");
}

// What plumb converge recommends for verify's start, metric, run and tolerance.
double ConvergeRecommends(const Model& model, const VerifyOptions& options,
                          const VerifyReport& report) {
  ConvergeOptions converge;
  converge.sets = options.sets;
  converge.tol = options.tol;
  Metric metric = ParseMetric(model, report.figures.convergence_metric);
  return Converge(model, metric, converge).recommended_dt;
}

class ConvergenceVerdictTest : public testing::MujocoTest {};

// Regression (issue 45): verify's ladder began at 2*dt and converge's at dt, and each took the
// coarsest level whose own estimate met the tolerance, so they named different timesteps,
// and verify could name one coarser than the model's while failing it.
TEST_F(ConvergenceVerdictTest, VerifyAndConvergeRecommendTheSameTimestep) {
  Model pendulum = Model::Load(testing::kPendulum);
  for (double tol : {0.05, 1e-2, 1e-3, 1e-4}) {
    VerifyOptions options;
    options.sets = {ParseAssignment(pendulum, "qpos[hinge]=0.7")};
    options.tol = tol;
    VerifyReport report = Verify(pendulum, options);
    double recommended = report.figures.convergence.recommended_dt;
    EXPECT_EQ(recommended, ConvergeRecommends(pendulum, options, report)) << "tol " << tol;
    EXPECT_LE(recommended, 0.002) << "tol " << tol;  // never coarser than the level it judged
    const CheckRow& row = Convergence(report);
    EXPECT_EQ(row.status == CheckStatus::kPass, recommended == 0.002)
        << "tol " << tol << ": " << row.explanation;
  }
}

// A ball dropped on a plane whose contacts (solref 1 ms, below 2 * dt) MuJoCo stiffens level by
// level: before, the ladder measured that model change (the rest depth falls 4x a halving) as
// the error; held, the levels agree to round-off, no order shows, and the row passes on the
// differences, saying what was held.
TEST_F(ConvergenceVerdictTest, LevelsThatAgreePassWithoutAnOrder) {
  Model ball = Model::FromXmlString(R"(<mujoco><option timestep="0.002"/>
      <default><geom solref="0.001 1"/></default>
      <worldbody><geom type="plane" size="1 1 0.1"/>
        <body pos="0 0 0.3"><freejoint/><geom type="sphere" size="0.1" mass="1"/></body>
      </worldbody></mujoco>)");
  VerifyReport report = Verify(ball, {});
  const CheckRow& row = Convergence(report);
  EXPECT_EQ(row.status, CheckStatus::kPass) << row.explanation;
  EXPECT_LT(row.measured.value, 1e-6 * row.reference.value) << row.explanation;
  EXPECT_NE(row.explanation.find("held at 0.004 s across levels"), std::string::npos)
      << row.explanation;
  EXPECT_NE(row.explanation.find("Caveat: contacts occur"), std::string::npos) << row.explanation;
}

}  // namespace
}  // namespace plumb
