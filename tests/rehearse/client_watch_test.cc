// What plumb sees of a rehearsal's client (src/rehearse/client_watch.h), fed directly with the
// bridge observer's calls: each row quiet on a clean stream and raised on its defect.

#include "rehearse/client_watch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "corpus_robots.h"
#include "fixture.h"

namespace plumb::internal {
namespace {

constexpr double kPeriod = 0.002;
constexpr double kPosStopF = 2.146e9;  // Unitree's "no position control"
constexpr double kVelStopF = 16000;

// The model's actuators as the bridge's motors, in order (the Go2's are torque motors with a
// control range, gain 1).
std::vector<BridgeMotorInfo> ActuatorMotors(const Model& model) {
  const mjModel* m = model.get();
  std::vector<BridgeMotorInfo> motors;
  for (int u = 0; u < m->nu; ++u) {
    double limit = m->actuator_ctrlrange[2 * u + 1] * m->actuator_gainprm[u * mjNGAIN] *
                   m->actuator_gear[6 * u];
    motors.push_back({model.Name(mjOBJ_ACTUATOR, u), m->actuator_trnid[2 * u], u, -limit, limit});
  }
  return motors;
}

// The middle of each motor's joint range (0 for an unlimited joint).
std::vector<double> MidRange(const Model& model, const std::vector<BridgeMotorInfo>& motors) {
  std::vector<double> q;
  for (const BridgeMotorInfo& motor : motors) {
    bool limited = model->jnt_limited[motor.joint];
    q.push_back(
        limited ? 0.5 * (model->jnt_range[2 * motor.joint] + model->jnt_range[2 * motor.joint + 1])
                : 0);
  }
  return q;
}

// A client's stream: `slots` slots, the first motors at `targets` with kp/kd, the rest as
// Unitree's InitLowCmd leaves them (mode 1, PosStopF, VelStopF, no gain: drives nothing).
struct Stream {
  std::vector<double> targets;
  std::size_t slots = 20;
  double kp = 20, kd = 0.5;
  double error = 0.01;  // q_des - q at each state

  std::vector<BridgeCommandSlot> Command() const {
    std::vector<BridgeCommandSlot> command(slots, {1, kPosStopF, kVelStopF, 0, 0, 0});
    for (std::size_t i = 0; i < targets.size(); ++i) {
      command[i] = {1, targets[i], 0, 0, kp, kd};
    }
    return command;
  }
  std::vector<BridgeMotorSample> State() const {
    std::vector<BridgeMotorSample> state;
    for (const BridgeCommandSlot& c : Command()) {
      if (state.size() == targets.size()) break;
      state.push_back({c.q - error, 0, c, c.kp * error, false});
    }
    return state;
  }
};

// `count` commands, one a period of simulated time, `wall(i)` s of the steady clock for the
// i-th, each followed by its state.
template <typename Wall>
void Feed(ClientWatch& watch, const Model& model, const Stream& stream, int count, Wall wall,
          double period = kPeriod) {
  Data data(model);
  for (int i = 0; i < count; ++i) {
    double t = i * period;
    watch.Commanded(t, wall(i), stream.Command());
    data->time = t + period;
    watch.Published(model, data, stream.State());
  }
}

void FeedSteady(ClientWatch& watch, const Model& model, const Stream& stream, int count = 500) {
  Feed(watch, model, stream, count, [](int i) { return 100 + i * kPeriod; });
}

const CheckRow* Find(const std::vector<CheckRow>& rows, const std::string& id) {
  for (const CheckRow& row : rows) {
    if (row.id == id) return &row;
  }
  return nullptr;
}

std::vector<const CheckRow*> FindAll(const std::vector<CheckRow>& rows, const std::string& id) {
  std::vector<const CheckRow*> found;
  for (const CheckRow& row : rows) {
    if (row.id == id) found.push_back(&row);
  }
  return found;
}

CheckStatus StatusOf(const std::vector<CheckRow>& rows, const std::string& id) {
  const CheckRow* row = Find(rows, id);
  EXPECT_NE(row, nullptr) << id;
  return row ? row->status : CheckStatus::kSkip;
}

const char* kRowIds[] = {"client.commands", "client.period", "client.range", "client.torque",
                         "client.motors",   "client.own_pd", "client.flood"};

class ClientWatchGo2Test : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string path = testing::RequireCorpusModel(testing::robots::kGo2);
    if (path.empty()) GTEST_SKIP() << "no robot corpus (make corpus)";
    model_.emplace(Model::Load(path));
    motors_ = ActuatorMotors(*model_);
    config_.control_period = kPeriod;
    stream_.targets = MidRange(*model_, motors_);
  }
  ClientWatch Watch() const { return ClientWatch(*model_, motors_, config_); }

  std::optional<Model> model_;
  std::vector<BridgeMotorInfo> motors_;
  BridgeConfig config_;
  Stream stream_;
};

TEST_F(ClientWatchGo2Test, ACleanStreamPassesEveryRow) {
  ASSERT_EQ(motors_.size(), 12u);
  ClientWatch watch = Watch();
  FeedSteady(watch, *model_, stream_);
  ClientView view = watch.View(99.5);
  EXPECT_EQ(view.commands, 500);
  EXPECT_NEAR(view.first_command, 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(view.first_command_time, 0);
  EXPECT_NEAR(view.period_median, kPeriod, 1e-9);
  EXPECT_NEAR(view.period_worst, kPeriod, 1e-9);
  EXPECT_NEAR(view.commands_per_period, 1, 1e-9);
  ASSERT_EQ(view.motors.size(), 12u);
  EXPECT_EQ(view.motors[0].name, "FL_hip");
  EXPECT_EQ(view.motors[0].commands, 500);
  EXPECT_NEAR(view.motors[0].tracking_rms, 0.01, 1e-9);
  EXPECT_NEAR(view.motors[0].worst_torque, 0.2, 1e-9);
  EXPECT_TRUE(view.unknown_motors.empty());  // InitLowCmd's filler in slots 12..19
  EXPECT_TRUE(view.own_pd.empty());
  std::vector<CheckRow> rows = watch.Rows(view, BridgeStats{});
  for (const char* id : kRowIds) {
    EXPECT_EQ(FindAll(rows, id).size(), 1u) << id;
    EXPECT_EQ(StatusOf(rows, id), CheckStatus::kPass) << id << ": " << Find(rows, id)->explanation;
    EXPECT_EQ(Find(rows, id)->section, "client");
  }
}

TEST_F(ClientWatchGo2Test, NoCommandFailsAndSkipsWhatNeedsOne) {
  ClientWatch watch = Watch();
  Data data(*model_);
  watch.Published(*model_, data, stream_.State());  // before any command: not counted
  ClientView view = watch.View(NAN);
  EXPECT_EQ(view.commands, 0);
  EXPECT_TRUE(std::isnan(view.period_median));
  EXPECT_TRUE(std::isnan(view.commands_per_period));
  std::vector<CheckRow> rows = watch.Rows(view, BridgeStats{});
  const CheckRow* commands = Find(rows, "client.commands");
  ASSERT_NE(commands, nullptr);
  EXPECT_EQ(commands->status, CheckStatus::kFail);
  EXPECT_NE(commands->explanation.find("never sent a command on rt/lowcmd"), std::string::npos);
  for (const char* id :
       {"client.period", "client.range", "client.torque", "client.motors", "client.flood"}) {
    EXPECT_EQ(StatusOf(rows, id), CheckStatus::kSkip) << id;
  }
  EXPECT_EQ(StatusOf(rows, "client.own_pd"), CheckStatus::kPass);
}

TEST_F(ClientWatchGo2Test, ATargetBeyondTheRangeWarnsForThatMotor) {
  stream_.targets[2] = 0;  // FL_calf: range [-2.7227, -0.83776]
  ClientWatch watch = Watch();
  FeedSteady(watch, *model_, stream_, 50);
  ClientView view = watch.View(NAN);
  EXPECT_EQ(view.motors[2].outside_range, 50);
  EXPECT_NEAR(view.motors[2].worst_outside, 0.83776, 1e-6);
  EXPECT_EQ(view.motors[1].outside_range, 0);
  std::vector<CheckRow> rows = watch.Rows(view, BridgeStats{});
  std::vector<const CheckRow*> range = FindAll(rows, "client.range");
  ASSERT_EQ(range.size(), 1u);
  EXPECT_EQ(range[0]->status, CheckStatus::kWarn);
  EXPECT_EQ(range[0]->element.name, "FL_calf");
  EXPECT_EQ(range[0]->measured.unit, "rad");
  EXPECT_NEAR(range[0]->measured.value, 0.83776, 1e-6);
}

TEST_F(ClientWatchGo2Test, ATargetAtTheEdgeOfTheRangeIsNoFinding) {
  // a policy's target a hair past a limit (1 mrad, well under 2 % of the calf's 1.88 rad)
  stream_.targets[2] = -0.83776 + 1e-3;
  ClientWatch watch = Watch();
  FeedSteady(watch, *model_, stream_, 50);
  ClientView view = watch.View(NAN);
  EXPECT_EQ(view.motors[2].outside_range, 50);  // counted in the view
  std::vector<CheckRow> rows = watch.Rows(view, BridgeStats{});
  std::vector<const CheckRow*> range = FindAll(rows, "client.range");
  ASSERT_EQ(range.size(), 1u);
  EXPECT_EQ(range[0]->status, CheckStatus::kPass);
  EXPECT_NE(range[0]->measured_text.find("1 motors at most 0.001 beyond"), std::string::npos)
      << range[0]->measured_text;
}

TEST_F(ClientWatchGo2Test, PositionStopTargetsWithoutGainAreNotOutsideTheRange) {
  stream_.targets[2] = kPosStopF;
  stream_.kp = 0;  // torque control through tau: the target means nothing
  ClientWatch watch = Watch();
  FeedSteady(watch, *model_, stream_, 20);
  std::vector<CheckRow> rows = watch.Rows(watch.View(NAN), BridgeStats{});
  EXPECT_EQ(StatusOf(rows, "client.range"), CheckStatus::kPass);
}

TEST_F(ClientWatchGo2Test, AKpThatAsksMoreThanTheMotorHasWarns) {
  stream_.kp = 500;
  stream_.error = 0.2;  // 100 N*m against the hips' 23.7 and the knees' 45.43
  ClientWatch watch = Watch();
  FeedSteady(watch, *model_, stream_, 100);
  ClientView view = watch.View(NAN);
  EXPECT_EQ(view.motors[0].saturated, 100);
  EXPECT_DOUBLE_EQ(view.motors[0].saturated_fraction, 1);
  EXPECT_NEAR(view.motors[0].worst_torque, 100, 1e-9);
  std::vector<CheckRow> rows = watch.Rows(view, BridgeStats{});
  std::vector<const CheckRow*> torque = FindAll(rows, "client.torque");
  ASSERT_EQ(torque.size(), 12u);  // one a motor, the same finding
  EXPECT_EQ(torque[0]->status, CheckStatus::kWarn);
  EXPECT_EQ(torque[0]->finding, torque[11]->finding);
  EXPECT_DOUBLE_EQ(torque[0]->measured.value, 1);  // of the states
  EXPECT_DOUBLE_EQ(torque[0]->reference.value, ClientWatch::kSaturated);
  EXPECT_NE(torque[0]->measured_text.find("kp 500 x error 0.2 rad (with kd and tau) asks 100 N*m "
                                          "beyond the motor's 23.7 N*m"),
            std::string::npos)
      << torque[0]->measured_text;
}

TEST_F(ClientWatchGo2Test, SaturationUnderFivePercentPasses) {
  ClientWatch watch = Watch();
  FeedSteady(watch, *model_, stream_, 100);
  Stream hard = stream_;
  hard.kp = 500;
  hard.error = 0.2;
  Data data(*model_);
  data->time = 0.3;
  for (int i = 0; i < 4; ++i) watch.Published(*model_, data, hard.State());  // 4 of 104
  std::vector<CheckRow> rows = watch.Rows(watch.View(NAN), BridgeStats{});
  EXPECT_EQ(StatusOf(rows, "client.torque"), CheckStatus::kPass);
}

TEST_F(ClientWatchGo2Test, StatesWhileTheWatchdogDampsAreNotSaturated) {
  ClientWatch watch = Watch();
  FeedSteady(watch, *model_, stream_, 10);
  Stream hard = stream_;
  hard.kp = 500;
  hard.error = 0.2;
  std::vector<BridgeMotorSample> damped = hard.State();
  for (BridgeMotorSample& s : damped) s.damping = true;
  Data data(*model_);
  for (int i = 0; i < 100; ++i) watch.Published(*model_, data, damped);
  ClientView view = watch.View(NAN);
  EXPECT_EQ(view.motors[0].saturated, 0);
  EXPECT_NEAR(view.motors[0].worst_torque, 0.2, 1e-9);
}

TEST_F(ClientWatchGo2Test, ASlotBeyondTheModelsMotorsFails) {
  ClientWatch watch = Watch();
  Data data(*model_);
  for (int i = 0; i < 10; ++i) {
    std::vector<BridgeCommandSlot> command = stream_.Command();
    command[15] = {1, 0.3, 0, 0, 20.0 + i, 0};  // the first occurrence is reported
    watch.Commanded(i * kPeriod, i * kPeriod, command);
  }
  ClientView view = watch.View(NAN);
  ASSERT_EQ(view.unknown_motors.size(), 1u);
  EXPECT_EQ(view.unknown_motors[0], "slot 15 (mode 1, kp 20, q 0.3)");
  std::vector<CheckRow> rows = watch.Rows(view, BridgeStats{});
  const CheckRow* motors = Find(rows, "client.motors");
  ASSERT_NE(motors, nullptr);
  EXPECT_EQ(motors->status, CheckStatus::kFail);
  EXPECT_NE(motors->measured_text.find("slot 15"), std::string::npos);
}

TEST_F(ClientWatchGo2Test, AJitteryLoopInLockstepIsTheClientsSpeedNotItsPeriod) {
  ClientWatch watch = Watch();  // lockstep: simulated time waits for each command
  Feed(watch, *model_, stream_, 200, [](int i) { return i * kPeriod + (i % 10 == 9 ? 6e-3 : 0); });
  ClientView view = watch.View(NAN);
  std::vector<CheckRow> rows = watch.Rows(view, BridgeStats{});
  const CheckRow* period = Find(rows, "client.period");
  ASSERT_NE(period, nullptr);
  EXPECT_EQ(period->status, CheckStatus::kPass);
  EXPECT_NE(period->explanation.find("rehearse in realtime"), std::string::npos);
}

TEST_F(ClientWatchGo2Test, AJitteryLoopWarns) {
  config_.mode = BridgeMode::kRealtime;
  ClientWatch watch = Watch();
  // every tenth command 6 ms late: p95 is the median, the worst 4 x it
  Feed(watch, *model_, stream_, 200, [](int i) { return i * kPeriod + (i % 10 == 9 ? 6e-3 : 0); });
  ClientView view = watch.View(NAN);
  EXPECT_GT(view.period_worst, 3 * view.period_median);
  std::vector<CheckRow> rows = watch.Rows(view, BridgeStats{});
  const CheckRow* period = Find(rows, "client.period");
  ASSERT_NE(period, nullptr);
  EXPECT_EQ(period->status, CheckStatus::kWarn);
  EXPECT_NE(period->explanation.find("jittery"), std::string::npos);
}

TEST_F(ClientWatchGo2Test, AClientFasterThanTheControlPeriodFloods) {
  ClientWatch watch = Watch();
  // realtime: four commands in each period of simulated time
  Feed(
      watch, *model_, stream_, 400, [](int i) { return i * kPeriod / 4; }, kPeriod / 4);
  ClientView view = watch.View(NAN);
  EXPECT_NEAR(view.commands_per_period, 4, 1e-9);
  EXPECT_EQ(StatusOf(watch.Rows(view, BridgeStats{}), "client.flood"), CheckStatus::kWarn);
}

TEST_F(ClientWatchGo2Test, CommandsDroppedFromTheQueueFlood) {
  ClientWatch watch = Watch();
  FeedSteady(watch, *model_, stream_, 50);
  BridgeStats stats;
  stats.queue_drops = 3;
  std::vector<CheckRow> rows = watch.Rows(watch.View(NAN), stats);
  const CheckRow* flood = Find(rows, "client.flood");
  ASSERT_NE(flood, nullptr);
  EXPECT_EQ(flood->status, CheckStatus::kWarn);
  EXPECT_NE(flood->measured_text.find("3 dropped"), std::string::npos);
}

// The pendulum, its hinge a motor driven through qfrc_applied, with `extra` in the model.
std::string Pendulum(const std::string& joint, const std::string& actuators) {
  return R"(<mujoco model="pendulum"><option timestep="0.002"/><worldbody>
      <body name="link" pos="0 0 1.5"><joint name="hinge" axis="0 1 0" )" +
         joint + R"(/><geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05" mass="1"/>
      </body></worldbody><actuator>)" +
         actuators + "</actuator></mujoco>";
}

std::vector<BridgeMotorInfo> HingeMotor() { return {{"hinge", 0, -1, -INFINITY, INFINITY}}; }

TEST(ClientWatchTest, ThePendulumAloneHasNoPdOfItsOwn) {
  Model model = Model::Load(std::string(PLUMB_SOURCE_DIR) + "/models/pendulum.xml");
  BridgeConfig config;
  ClientWatch watch(model, HingeMotor(), config);
  Stream stream{{0.3}};
  FeedSteady(watch, model, stream, 100);
  ClientView view = watch.View(NAN);
  EXPECT_TRUE(view.own_pd.empty());
  std::vector<CheckRow> rows = watch.Rows(view, BridgeStats{});
  for (const char* id : kRowIds) EXPECT_EQ(StatusOf(rows, id), CheckStatus::kPass) << id;
}

TEST(ClientWatchTest, APositionActuatorOnAMotorsJointWarns) {
  Model model = Model::FromXmlString(
      // a position servo with kv 2, written as it compiles (MuJoCo 2.x's position has no kv)
      Pendulum("", R"(<general name="hold" joint="hinge" gainprm="50" biastype="affine"
                      biasprm="0 -50 -2"/>)"),
      "servo.xml");
  BridgeConfig config;
  ClientWatch watch(model, HingeMotor(), config);
  ClientView view = watch.View(NAN);
  ASSERT_EQ(view.own_pd.size(), 1u);
  EXPECT_EQ(view.own_pd[0], "actuator 'hold' on joint 'hinge' (kp 50, kv 2)");
  std::vector<CheckRow> rows = watch.Rows(view, BridgeStats{});
  const CheckRow* own = Find(rows, "client.own_pd");
  ASSERT_NE(own, nullptr);
  EXPECT_EQ(own->status, CheckStatus::kWarn);
  EXPECT_NE(own->explanation.find("two PDs"), std::string::npos);
}

TEST(ClientWatchTest, AVelocityServoCountsAndAPlainMotorDoesNot) {
  Model model = Model::FromXmlString(
      Pendulum("damping=\"0.05\"", R"(<velocity name="brake" joint="hinge" kv="3"/>
                                      <motor name="spare" joint="hinge"/>)"),
      "velocity.xml");
  BridgeConfig config;
  ClientWatch watch(model, HingeMotor(), config);
  ClientView view = watch.View(NAN);
  ASSERT_EQ(view.own_pd.size(), 1u);  // joint damping is physics, the motor has no bias
  EXPECT_EQ(view.own_pd[0], "actuator 'brake' on joint 'hinge' (kp 0, kv 3)");
}

TEST(ClientWatchTest, AJointSpringIsTheModelsNotAnActuator) {
  Model model = Model::FromXmlString(Pendulum("stiffness=\"10\"", ""), "spring.xml");
  BridgeConfig config;
  ClientWatch watch(model, HingeMotor(), config);
  ClientView view = watch.View(NAN);
  ASSERT_EQ(view.own_pd.size(), 1u);
  EXPECT_NE(view.own_pd[0].find("joint 'hinge': a spring of the model (stiffness 10"),
            std::string::npos)
      << view.own_pd[0];
}

// motors = ["", "hinge"]: slot 0 is the robot's, the model has no motor for it (as Unitree's
// H1 script leaves slot 6 out). InitLowCmd's filler there drives nothing and passes; torque
// asked of it fails client.motors as a slot beyond the model's motors does.
TEST(ClientWatchTest, TorqueOnAnEmptySlotFailsAndTheFillerDoesNot) {
  Model model = Model::Load(std::string(PLUMB_SOURCE_DIR) + "/models/pendulum.xml");
  std::vector<BridgeMotorInfo> motors = {BridgeMotorInfo{}, HingeMotor()[0]};
  ASSERT_TRUE(motors[0].empty());
  BridgeConfig config;
  auto feed = [&](ClientWatch& watch, const BridgeCommandSlot& slot0) {
    Data data(model);
    for (int i = 0; i < 50; ++i) {
      std::vector<BridgeCommandSlot> command(20, {1, kPosStopF, kVelStopF, 0, 0, 0});
      command[0] = slot0;
      command[1] = {1, 0.3, 0, 0, 20, 0.5};
      watch.Commanded(i * kPeriod, 100 + i * kPeriod, command);
      data->time = (i + 1) * kPeriod;
      watch.Published(model, data, {BridgeMotorSample{}, {0.29, 0, command[1], 0.2, false}});
    }
  };
  ClientWatch filler(model, motors, config);
  feed(filler, {1, kPosStopF, kVelStopF, 0, 0, 0});
  ClientView view = filler.View(NAN);
  ASSERT_EQ(view.motors.size(), 1u);  // the hinge: the empty slot is no motor
  EXPECT_EQ(view.motors[0].name, "hinge");
  EXPECT_EQ(view.motors[0].commands, 50);
  EXPECT_NEAR(view.motors[0].tracking_rms, 0.01, 1e-9);
  EXPECT_TRUE(view.unknown_motors.empty());
  std::vector<CheckRow> rows = filler.Rows(view, BridgeStats{});
  for (const char* id : kRowIds) EXPECT_EQ(StatusOf(rows, id), CheckStatus::kPass) << id;
  EXPECT_EQ(Find(rows, "client.motors")->measured_text,
            "the client drives only the model's 1 motors");

  ClientWatch torque(model, motors, config);
  feed(torque, {1, 0.5, 0, 0, 30, 0});
  view = torque.View(NAN);
  ASSERT_EQ(view.unknown_motors.size(), 1u);
  EXPECT_EQ(view.unknown_motors[0], "slot 0 (empty in motors = [...]) (mode 1, kp 30, q 0.5)");
  rows = torque.Rows(view, BridgeStats{});
  const CheckRow* row = Find(rows, "client.motors");
  ASSERT_NE(row, nullptr);
  EXPECT_EQ(row->status, CheckStatus::kFail);
  EXPECT_NE(row->subject.find("empty in motors = [...]"), std::string::npos) << row->subject;
  EXPECT_NE(row->measured_text.find("slot 0 (empty in motors = [...])"), std::string::npos);
}

TEST(ClientWatchTest, TheMotorItselfIsNotItsOwnPd) {
  // a position actuator bound as the motor would be refused by the bridge; one that is the
  // motor is never listed
  Model model = Model::FromXmlString(
      Pendulum("", R"(<position name="hold" joint="hinge" kp="50"/>)"), "servo.xml");
  BridgeConfig config;
  ClientWatch watch(model, {{"hold", 0, 0, -INFINITY, INFINITY}}, config);
  EXPECT_TRUE(watch.View(NAN).own_pd.empty());
}

}  // namespace
}  // namespace plumb::internal
