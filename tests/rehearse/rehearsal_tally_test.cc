// A rehearsal's assertions: parsing the motor signals beside the model's paths, judging them
// over synthetic states, and the trace the report draws (its decimation).

#include "rehearse/rehearsal_tally.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "corpus_robots.h"
#include "fixture.h"
#include "plumb/error.h"
#include "plumb/rehearse.h"

namespace plumb {
using internal::RehearsalTally;

namespace {

using Signal = RehearsalAssertion::Signal;
using RehearsalTallyTest = testing::MujocoTest;

BridgeConfig PendulumConfig() {
  BridgeConfig config;
  config.motors = {"hinge"};
  return config;
}

// The pendulum's one motor, its torque limited to [-2, 2] N*m.
std::vector<BridgeMotorInfo> PendulumMotors() { return {{"hinge", 0, -1, -2, 2}}; }

const CheckRow* RowOf(const std::vector<CheckRow>& rows, const std::string& subject) {
  for (const CheckRow& row : rows) {
    if (row.subject == subject) return &row;
  }
  ADD_FAILURE() << "no row for " << subject;
  return nullptr;
}

std::size_t SignalIndex(const RehearsalTrace& trace, const std::string& name) {
  for (std::size_t i = 0; i < trace.signals.size(); ++i) {
    if (trace.signals[i] == name) return i;
  }
  ADD_FAILURE() << "no trace signal " << name;
  return 0;
}

TEST_F(RehearsalTallyTest, MotorSignalsAndPathsParseOnThePendulum) {
  Model model = Model::Load(testing::kPendulum);
  BridgeConfig config = PendulumConfig();
  RehearsalAssertion te =
      ParseRehearsalAssertion(model, config, "maxabs(tracking_error[hinge]) < 0.1");
  EXPECT_EQ(te.signal, Signal::kTrackingError);
  EXPECT_EQ(te.assertion.reduce, Reduction::kMaxAbs);
  EXPECT_EQ(te.motors, std::vector<int>{0});
  EXPECT_EQ(te.names, std::vector<std::string>{"tracking_error[hinge]"});
  EXPECT_TRUE(te.assertion.paths.empty());
  RehearsalAssertion torque = ParseRehearsalAssertion(model, config, "torque[0] < 5");
  EXPECT_EQ(torque.signal, Signal::kTorque);
  EXPECT_EQ(torque.names, std::vector<std::string>{"torque[hinge]"});
  RehearsalAssertion sat =
      ParseRehearsalAssertion(model, config, "mean( saturated [ * ] ) < 0.1 during [1, 2]");
  EXPECT_EQ(sat.signal, Signal::kSaturated);
  EXPECT_EQ(sat.assertion.reduce, Reduction::kMean);
  EXPECT_EQ(sat.assertion.from, 1);
  EXPECT_EQ(sat.assertion.to, 2);
  EXPECT_EQ(sat.motors, std::vector<int>{0});
  RehearsalAssertion path = ParseRehearsalAssertion(model, config, "qpos[hinge] > -1");
  EXPECT_EQ(path.signal, Signal::kPath);
  ASSERT_EQ(path.assertion.paths.size(), 1u);
  EXPECT_EQ(path.assertion.paths[0].text, "qpos[hinge]");

  std::string unknown =
      testing::ValueErrorOf([&] { ParseRehearsalAssertion(model, config, "torque[knee] < 1"); });
  EXPECT_NE(unknown.find("assertion 'torque[knee] < 1'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("'knee' is not a motor"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("(hinge)"), std::string::npos) << unknown;
  EXPECT_NE(testing::ValueErrorOf([&] {
              ParseRehearsalAssertion(model, config, "torque[1] < 1");
            }).find("'1' is not a motor"),
            std::string::npos);
  EXPECT_NE(testing::ValueErrorOf([&] {
              ParseRehearsalAssertion(model, config, "torque[0 < 1");
            }).find("one motor in brackets"),
            std::string::npos);
  EXPECT_THROW(ParseRehearsalAssertion(model, config, "torque[0] = 1"), ValueError);
  EXPECT_THROW(ParseRehearsalAssertion(model, config, "qpos[knee] < 1"), Error);
}

TEST_F(RehearsalTallyTest, TheGo2sMotorsAreItsActuatorsInOrder) {
  std::string path = testing::RequireCorpusModel(testing::robots::kGo2);
  if (path.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
  Model model = Model::Load(path);
  BridgeConfig config;  // no motors named: every actuator in order
  RehearsalAssertion all =
      ParseRehearsalAssertion(model, config, "maxabs(tracking_error[*]) < 0.2");
  ASSERT_EQ(all.motors.size(), 12u);
  EXPECT_EQ(all.names.front(), "tracking_error[FL_hip]");
  EXPECT_EQ(all.names.back(), "tracking_error[RR_calf]");
  RehearsalAssertion calf = ParseRehearsalAssertion(model, config, "torque[FR_calf] < 40");
  EXPECT_EQ(calf.motors, std::vector<int>{5});
  RehearsalAssertion height = ParseRehearsalAssertion(model, config, "xpos[base][2] > 0.2");
  EXPECT_EQ(height.signal, Signal::kPath);
  EXPECT_EQ(height.assertion.paths.size(), 1u);
  std::string unknown = testing::ValueErrorOf(
      [&] { ParseRehearsalAssertion(model, config, "saturated[FR_knee] < 1"); });
  EXPECT_NE(unknown.find("'FR_knee' is not a motor of the bridge"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("FL_hip, FL_thigh, FL_calf, FR_hip"), std::string::npos) << unknown;
}

// One state of the pendulum's motor: q, the command in force (mode, q_des, kp) and the
// torque the law asks.
struct State {
  double t, q;
  int mode;
  double q_des, kp, torque;
  bool damping;
};

TEST_F(RehearsalTallyTest, EachSignalPassesOrFailsOverItsWindow) {
  Model model = Model::Load(testing::kPendulum);
  Data data(model);
  BridgeConfig config = PendulumConfig();
  std::vector<std::string> texts = {
      "maxabs(tracking_error[hinge]) < 0.1",  // 0.3 at t = 0.2: FAIL
      "maxabs(tracking_error[hinge]) < 0.5",
      "max(tracking_error[hinge]) < 1 during [0, 0.05]",   // no command yet: no sample
      "torque[hinge] < 1.5",                               // 3 at t = 0.2: FAIL
      "mean(saturated[hinge]) <= 0.25 during [0.1, 0.5]",  // 1 of 4 states
      "mean(saturated[hinge]) < 0.2 during [0.1, 0.5]",
      "qpos[hinge] > -1",
  };
  std::vector<RehearsalAssertion> assertions;
  for (const std::string& text : texts) {
    assertions.push_back(ParseRehearsalAssertion(model, config, text));
  }
  RehearsalTally tally(assertions, PendulumMotors());
  std::vector<State> states = {{0.0, 0.5, 0, 0, 0, 0, false},
                               {0.1, 0.0, 1, 0.05, 10, 0.5, false},
                               {0.2, 0.0, 1, 0.3, 10, 3, false},
                               {0.3, 0.0, 1, 0.3, 10, 3, true},  // damping: not saturated
                               {0.4, 0.2, 1, 0.3, 10, 1, false}};
  for (const State& s : states) {
    data->time = s.t;
    data->qpos[0] = s.q;
    BridgeMotorSample motor;
    motor.q = s.q;
    motor.command.mode = s.mode;
    motor.command.q = s.q_des;
    motor.command.kp = s.kp;
    motor.torque = s.torque;
    motor.damping = s.damping;
    tally.Sample(model, data, {motor});
  }
  tally.Event(0.25, "watchdog: damping");
  std::vector<CheckRow> rows = tally.Rows();
  ASSERT_EQ(rows.size(), texts.size());
  for (const CheckRow& row : rows) {
    EXPECT_EQ(row.section, "assert");
    EXPECT_EQ(row.id, "assert");
    EXPECT_TRUE(row.threshold);
  }
  const CheckRow* te = RowOf(rows, texts[0]);
  ASSERT_NE(te, nullptr);
  EXPECT_EQ(te->status, CheckStatus::kFail);
  EXPECT_EQ(te->measured_text, "maxabs(tracking_error[hinge]) = 0.3");
  EXPECT_NEAR(te->measured.value, 0.3, 1e-12);
  EXPECT_EQ(te->reference.value, 0.1);
  EXPECT_EQ(te->reference_text, "< 0.1");
  EXPECT_EQ(RowOf(rows, texts[1])->status, CheckStatus::kPass);
  EXPECT_EQ(RowOf(rows, texts[2])->status, CheckStatus::kFail);
  EXPECT_EQ(RowOf(rows, texts[2])->measured_text, "no sample in the window");
  const CheckRow* torque = RowOf(rows, texts[3]);
  EXPECT_EQ(torque->status, CheckStatus::kFail);
  EXPECT_EQ(torque->measured_text, "torque[hinge] = 3 at t = 0.2 s");
  EXPECT_EQ(torque->measured.value, 3);
  EXPECT_EQ(torque->measured.unit, "N*m");
  const CheckRow* mean = RowOf(rows, texts[4]);
  EXPECT_EQ(mean->status, CheckStatus::kPass) << mean->measured_text;
  EXPECT_EQ(mean->measured_text, "mean(saturated[hinge]) = 0.25");
  EXPECT_EQ(RowOf(rows, texts[5])->status, CheckStatus::kFail);
  EXPECT_NEAR(RowOf(rows, texts[5])->measured.value, 0.25, 1e-12);
  const CheckRow* path = RowOf(rows, texts[6]);
  EXPECT_EQ(path->status, CheckStatus::kPass);
  EXPECT_EQ(path->measured_text, "holds at every step");
  EXPECT_TRUE(std::isnan(path->measured.value));

  RehearsalTrace trace = tally.TakeTrace();
  EXPECT_EQ(trace.signals,
            (std::vector<std::string>{"tracking_error[hinge]", "torque[hinge]", "saturated[hinge]",
                                      "qpos[hinge]", "q_des[hinge]", "q[hinge]"}));
  ASSERT_EQ(trace.time.size(), states.size());
  ASSERT_EQ(trace.values.size(), trace.signals.size());
  const std::vector<double>& tracking = trace.values[SignalIndex(trace, "tracking_error[hinge]")];
  EXPECT_TRUE(std::isnan(tracking[0]));  // no command in force
  EXPECT_NEAR(tracking[2], 0.3, 1e-12);
  EXPECT_EQ(trace.values[SignalIndex(trace, "saturated[hinge]")],
            (std::vector<double>{0, 0, 1, 0, 0}));
  const std::vector<double>& q_des = trace.values[SignalIndex(trace, "q_des[hinge]")];
  EXPECT_TRUE(std::isnan(q_des[0]));  // before the first command
  EXPECT_EQ(q_des[1], 0.05);
  EXPECT_EQ(trace.values[SignalIndex(trace, "q[hinge]")][4], 0.2);
  ASSERT_EQ(trace.events.size(), 1u);
  EXPECT_EQ(trace.events[0].second, "watchdog: damping");
}

// motors = ["", "hinge"]: a motor number is its slot (motor_cmd[1] is the hinge); '*' and the
// trace leave the empty slot out, and no assertion may name it.
TEST_F(RehearsalTallyTest, AMotorNumberIsItsSlotAndAnEmptySlotIsNoMotor) {
  Model model = Model::Load(testing::kPendulum);
  Data data(model);
  BridgeConfig config;
  config.motors = {"", "hinge"};
  RehearsalAssertion all = ParseRehearsalAssertion(model, config, "max(torque[*]) < 5");
  EXPECT_EQ(all.motors, std::vector<int>{1});
  EXPECT_EQ(all.names, std::vector<std::string>{"torque[hinge]"});
  EXPECT_EQ(ParseRehearsalAssertion(model, config, "torque[1] < 5").motors, std::vector<int>{1});
  EXPECT_EQ(ParseRehearsalAssertion(model, config, "torque[hinge] < 5").motors,
            std::vector<int>{1});
  std::string empty =
      testing::ValueErrorOf([&] { ParseRehearsalAssertion(model, config, "torque[0] < 5"); });
  EXPECT_NE(empty.find("slot 0 is empty in the bridge's motors = [...]"), std::string::npos)
      << empty;
  EXPECT_NE(empty.find("(hinge)"), std::string::npos) << empty;
  EXPECT_NE(testing::ValueErrorOf([&] {
              ParseRehearsalAssertion(model, config, "torque[] < 5");
            }).find("is not a motor"),
            std::string::npos);

  RehearsalTally tally({all}, {BridgeMotorInfo{}, PendulumMotors()[0]});
  BridgeMotorSample hinge;
  hinge.q = 0.25;
  hinge.command.mode = 1;
  hinge.command.q = 0.3;
  hinge.torque = 7;
  tally.Sample(model, data, {BridgeMotorSample{}, hinge});
  EXPECT_EQ(tally.Rows()[0].status, CheckStatus::kFail);
  RehearsalTrace trace = tally.TakeTrace();
  EXPECT_EQ(trace.signals,
            (std::vector<std::string>{"torque[hinge]", "q_des[hinge]", "q[hinge]"}));
  EXPECT_EQ(trace.values[SignalIndex(trace, "q_des[hinge]")][0], 0.3);
  EXPECT_EQ(trace.values[SignalIndex(trace, "q[hinge]")][0], 0.25);
}

TEST_F(RehearsalTallyTest, TheTraceKeepsEvenlySpacedStatesUnderItsCap) {
  Model model = Model::Load(testing::kPendulum);
  Data data(model);
  std::vector<RehearsalAssertion> assertions = {
      ParseRehearsalAssertion(model, PendulumConfig(), "max(qpos[hinge]) < 19")};
  RehearsalTally small(assertions, PendulumMotors(), 8);
  for (int n = 0; n < 20; ++n) {
    data->time = 0.01 * n;
    data->qpos[0] = n;
    small.Sample(model, data, {BridgeMotorSample{}});
  }
  // the judge saw every state, the trace every 4th once it filled twice
  std::vector<CheckRow> rows = small.Rows();
  EXPECT_EQ(rows[0].status, CheckStatus::kFail);
  EXPECT_EQ(rows[0].measured.value, 19);
  RehearsalTrace trace = small.TakeTrace();
  EXPECT_EQ(trace.values[SignalIndex(trace, "qpos[hinge]")],
            (std::vector<double>{0, 4, 8, 12, 16}));
  ASSERT_EQ(trace.time.size(), 5u);
  EXPECT_NEAR(trace.time[1], 0.04, 1e-12);
  for (const std::vector<double>& v : trace.values) EXPECT_EQ(v.size(), 5u);

  RehearsalTally tally(assertions, PendulumMotors());  // the default cap: 20000
  for (int n = 0; n < 50000; ++n) {
    data->time = 0.002 * n;
    tally.Sample(model, data, {BridgeMotorSample{}});
  }
  RehearsalTrace full = tally.TakeTrace();
  EXPECT_LE(full.time.size(), 20000u);
  EXPECT_GE(full.time.size(), 10000u);
  EXPECT_NEAR(full.time[1] - full.time[0], 0.008, 1e-12);  // every 4th state
}

}  // namespace
}  // namespace plumb
