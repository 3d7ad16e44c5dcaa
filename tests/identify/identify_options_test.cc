// What plumb identify and plumb.identify share before and after a fit: the delay's name, the
// options' checks naming their argument, the covariance, the fitted model, and the identify job
// (plumb/identify_job.h) that both call.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/identify.h"
#include "plumb/identify_job.h"
#include "sim/log_maker.h"

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

// The pendulum let go at `angle` with damping 0.2, measured with noise: a log at `path`.
std::string DecayLog(const std::string& path, double angle, unsigned seed) {
  testing::LogSpec spec;
  spec.set = {"qpos[hinge]=" + std::to_string(angle), "dof_damping[hinge]=0.2"};
  spec.noise = {0.002, 0.01};
  spec.until = 2;
  spec.every = 5;
  spec.seed = seed;
  return testing::MakeLog(path, spec);
}

// Makes the log at `path` a flight recorder's (a `kind` column, each row a "state") whose last
// line a kill of the bridge cut short: only such a log is known to end each line with a newline.
void CutLastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, text;
  for (bool header = true; std::getline(in, line); header = false) {
    std::size_t comma = line.find(',');
    text += line.substr(0, comma) + (header ? ",kind" : ",state") + line.substr(comma) + "\n";
  }
  in.close();
  text.resize(text.size() - 4);  // the newline and three characters before it
  std::ofstream(path, std::ios::binary) << text;
}

IdentifyRequest DampingRequest(const std::string& log, const std::string& validate) {
  IdentifyRequest request;
  request.logs = {log};
  request.validate = validate;
  request.options.fit = {"dof_damping[hinge]"};
  request.options.threads = 1;
  return request;
}

// The job is its parts in order: the same logs, fit, fitted model and held-out replay.
TEST_F(IdentifyOptionsTest, JobGivesWhatItsPartsGive) {
  testing::TempDir dir;
  std::string log = DecayLog(dir.File("decay.csv"), 0.7, 1);
  std::string held_out = DecayLog(dir.File("held-out.csv"), -0.4, 2);
  Model model = Model::Load(testing::kPendulum);
  IdentifyRequest request = DampingRequest(log, held_out);
  IdentifyJobResult job = RunIdentifyJob(model, request);

  std::vector<RobotLog> logs = LoadRobotLogs(model, {log}, "");
  std::vector<RobotLog> validation = LoadRobotLogs(model, {held_out}, "");
  IdentifyResult fit = Identify(model, logs, request.options);
  Model fitted = FittedModel(model, fit);
  HeldOutLog replayed = ReplayHeldOut(model, fitted, validation.front(), request.options, fit);

  ASSERT_EQ(job.fit.estimates.size(), 1u);
  EXPECT_EQ(job.fit.estimates[0].value, fit.estimates[0].value);
  EXPECT_EQ(job.fit.estimates[0].std_error, fit.estimates[0].std_error);
  EXPECT_NEAR(job.fit.estimates[0].value, 0.2, 0.02);
  EXPECT_EQ(job.fit.runs, fit.runs);
  EXPECT_EQ((*job.fitted)->dof_damping[0], fitted->dof_damping[0]);
  EXPECT_EQ(model->dof_damping[0], 0.05);  // the caller's model is only read
  ASSERT_NE(job.HeldOut(), nullptr);
  EXPECT_EQ(job.HeldOut()->log, &job.validation.front());
  EXPECT_EQ(job.held_out.fitted.fit, replayed.fitted.fit);
  EXPECT_EQ(job.held_out.nominal.fit, replayed.nominal.fit);
  EXPECT_GT(job.held_out.fitted.fit, job.held_out.nominal.fit);
  EXPECT_EQ(job.logs.size(), 1u);
  EXPECT_TRUE(job.notices.empty());

  request.validate = "";
  EXPECT_EQ(RunIdentifyJob(model, request).HeldOut(), nullptr);
}

// A training or held-out log whose last line was cut is noted (NoticeTopic::kLog), on the
// result and in the caller's Notices as it comes.
TEST_F(IdentifyOptionsTest, JobNotesACutLog) {
  testing::TempDir dir;
  std::string log = DecayLog(dir.File("decay.csv"), 0.7, 1);
  std::string held_out = DecayLog(dir.File("held-out.csv"), -0.4, 2);
  CutLastLine(held_out);
  Model model = Model::Load(testing::kPendulum);
  std::vector<Notice> heard;
  Notices notices([&heard](const Notice& n) { heard.push_back(n); });
  IdentifyRequest request = DampingRequest(log, held_out);
  request.notices = &notices;
  IdentifyJobResult job = RunIdentifyJob(model, request);
  ASSERT_EQ(job.notices.size(), 1u);
  EXPECT_EQ(job.notices[0].topic, NoticeTopic::kLog);
  EXPECT_EQ(job.notices[0].subject, held_out);
  EXPECT_NE(job.notices[0].text.find("last line is cut short"), std::string::npos);
  ASSERT_EQ(heard.size(), 1u);
  EXPECT_EQ(heard[0].Line(), job.notices[0].Line());

  CutLastLine(log);
  job = RunIdentifyJob(model, DampingRequest(log, ""));  // no sink: on the result only
  ASSERT_EQ(job.notices.size(), 1u);
  EXPECT_EQ(job.notices[0].subject, log);
  EXPECT_EQ(heard.size(), 1u);
}

// A bad request is refused naming its argument, before any log is read.
TEST_F(IdentifyOptionsTest, JobRefusesABadRequestNamingTheArgument) {
  Model model = Model::Load(testing::kPendulum);
  auto refused = [&model](const IdentifyRequest& request) {
    try {
      RunIdentifyJob(model, request);
    } catch (const ArgumentError& e) {
      return e.argument();
    }
    return std::string("accepted");
  };
  IdentifyRequest request = DampingRequest("nosuch.csv", "");
  request.logs.clear();
  EXPECT_EQ(refused(request), "log");
  request = DampingRequest("nosuch.csv", "");
  request.options.fit.clear();
  EXPECT_EQ(refused(request), "fit");
  request = DampingRequest("nosuch.csv", "");
  request.options.max_delay = 0;
  EXPECT_EQ(refused(request), "max_delay");
  request = DampingRequest("nosuch.csv", "");
  request.options.fit = {"dof_damping[hinj]"};
  EXPECT_THROW(RunIdentifyJob(model, request), PathError);  // the parameters before the logs
  request = DampingRequest("nosuch.csv", "");
  EXPECT_THROW(RunIdentifyJob(model, request), IoError);
}

}  // namespace
}  // namespace plumb
