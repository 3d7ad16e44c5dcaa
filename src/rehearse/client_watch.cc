#include "rehearse/client_watch.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/strings.h"

namespace plumb::internal {
namespace {

// `value` to `digits` significant digits ("%.3g").
std::string Num(double value, int digits = 3) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

std::string Ms(double seconds) { return Num(seconds * 1e3) + " ms"; }

std::string Hz(double rate) { return Num(rate, 4) + " Hz"; }

std::string Percent(double fraction) { return Num(fraction * 100) + " %"; }

// "joint 'hinge'", or "joint #3" when unnamed.
std::string Named(const Model& model, int type, int id, const char* noun) {
  std::string name = model.Name(type, id);
  return name.empty() ? std::string(noun) + " #" + std::to_string(id)
                      : std::string(noun) + " '" + name + "'";
}

// A slot the client asks torque of (kp, kd or tau not 0); see client_watch.h.
bool AsksTorque(const BridgeCommandSlot& s) { return s.kp != 0 || s.kd != 0 || s.tau != 0; }

// "slot 12 (mode 1, kp 20, kd 0.5, q 0.3)": the mode and what is not 0; an empty slot of the
// motor map says so: "slot 6 (empty in motors = [...]) (mode 1, kp 20)".
std::string SlotText(std::size_t index, const BridgeCommandSlot& s, bool empty) {
  std::string text = "slot " + std::to_string(index) + (empty ? " (empty in motors = [...])" : "") +
                     " (mode " + std::to_string(s.mode);
  const std::pair<const char*, double> fields[] = {
      {"kp", s.kp}, {"kd", s.kd}, {"q", s.q}, {"dq", s.dq}, {"tau", s.tau}};
  for (const auto& [name, value] : fields) {
    if (value != 0) text += std::string(", ") + name + " " + Num(value, 4);
  }
  return text + ")";
}

bool IsMotorJoint(const std::vector<BridgeMotorInfo>& motors, int joint) {
  for (const BridgeMotorInfo& m : motors) {
    if (m.joint == joint) return true;
  }
  return false;
}

bool IsMotorActuator(const std::vector<BridgeMotorInfo>& motors, int actuator) {
  for (const BridgeMotorInfo& m : motors) {
    if (m.actuator == actuator) return true;
  }
  return false;
}

// The model's actuators that act on a motor's joint with a bias of their own (a position or
// velocity servo, a general actuator with bias terms: with its control at 0 it still pulls
// the joint), and the motors' joints with a spring.
std::vector<std::string> OwnPd(const Model& model, const std::vector<BridgeMotorInfo>& motors) {
  const mjModel* m = model.get();
  std::vector<std::string> found;
  for (int u = 0; u < m->nu; ++u) {
    int type = m->actuator_trntype[u];
    if (type != mjTRN_JOINT && type != mjTRN_JOINTINPARENT) continue;
    int joint = m->actuator_trnid[2 * u];
    if (IsMotorActuator(motors, u) || !IsMotorJoint(motors, joint)) continue;
    const mjtNum* bias = m->actuator_biasprm + u * mjNBIAS;
    if (m->actuator_biastype[u] == mjBIAS_NONE || (bias[1] == 0 && bias[2] == 0)) continue;
    double gear = m->actuator_gear[6 * u];
    std::string gains = "kp " + Num(0.0 - bias[1], 4) + ", kv " + Num(0.0 - bias[2], 4);
    if (gear != 1) gains += ", gear " + Num(gear, 4);
    found.push_back(Named(model, mjOBJ_ACTUATOR, u, "actuator") + " on " +
                    Named(model, mjOBJ_JOINT, joint, "joint") + " (" + gains + ")");
  }
  for (const BridgeMotorInfo& motor : motors) {
    if (motor.joint < 0 || m->jnt_stiffness[motor.joint] <= 0) continue;
    bool slide = m->jnt_type[motor.joint] == mjJNT_SLIDE;
    found.push_back(
        Named(model, mjOBJ_JOINT, motor.joint, "joint") + ": a spring of the model (stiffness " +
        Num(m->jnt_stiffness[motor.joint], 4) + (slide ? " N/m" : " N*m/rad") + ", rest at " +
        Num(m->qpos_spring[m->jnt_qposadr[motor.joint]], 4) + (slide ? " m)" : " rad)"));
  }
  return found;
}

CheckRow ClientRow(const char* id, const char* title) {
  CheckRow row;
  row.section = "client";
  row.id = id;
  row.title = title;
  return row;
}

CheckRow Skipped(const char* id, const char* title) {
  CheckRow row = ClientRow(id, title);
  row.status = CheckStatus::kSkip;
  row.explanation = "the client sent no command";
  return row;
}

}  // namespace

ClientWatch::ClientWatch(const Model& model, const std::vector<BridgeMotorInfo>& motors,
                         const BridgeConfig& config)
    : control_period_(config.control_period),
      realtime_(config.mode == BridgeMode::kRealtime),
      tally_(motors.size()) {
  const mjModel* m = model.get();
  for (const BridgeMotorInfo& info : motors) {
    MotorFacts f;
    f.info = info;
    if (info.empty()) {  // a slot the model has no motor for
      motors_.push_back(f);
      continue;
    }
    mapped_.push_back(motors_.size());
    f.element =
        info.actuator >= 0
            ? CheckElement{"actuator", model.Name(mjOBJ_ACTUATOR, info.actuator), info.actuator}
            : CheckElement{"joint", model.Name(mjOBJ_JOINT, info.joint), info.joint};
    if (info.joint >= 0 && info.joint < m->njnt) {
      int type = m->jnt_type[info.joint];
      bool moves = type == mjJNT_HINGE || type == mjJNT_SLIDE;
      f.limited = moves && m->jnt_limited[info.joint];
      if (f.limited) {
        f.lo = m->jnt_range[2 * info.joint];
        f.hi = m->jnt_range[2 * info.joint + 1];
      }
      if (type == mjJNT_SLIDE) {
        f.unit = "m";
        f.torque_unit = "N";
      }
    }
    motors_.push_back(f);
  }
  own_pd_ = OwnPd(model, motors);
}

void ClientWatch::Commanded(double t, double wall, const std::vector<BridgeCommandSlot>& slots) {
  if (commands_ == 0) {
    first_wall_ = wall;
    first_time_ = t;
  } else {
    periods_.Add(wall - last_wall_);
  }
  ++commands_;
  last_wall_ = wall;
  latest_time_ = std::isnan(latest_time_) ? t : std::max(latest_time_, t);
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const BridgeCommandSlot& s = slots[i];
    bool empty = i < motors_.size() && motors_[i].info.empty();
    if (i >= motors_.size() || empty) {
      if (!AsksTorque(s)) continue;
      if (std::find(unknown_slots_.begin(), unknown_slots_.end(), int(i)) != unknown_slots_.end())
        continue;
      unknown_slots_.push_back(int(i));
      unknown_.push_back(SlotText(i, s, empty));
      continue;
    }
    if (s.mode == 0) continue;
    MotorTally& tally = tally_[i];
    ++tally.commands;
    const MotorFacts& f = motors_[i];
    if (!f.limited || s.kp <= 0) continue;
    double excess = s.q < f.lo ? f.lo - s.q : s.q > f.hi ? s.q - f.hi : 0;
    if (excess > 0) {
      ++tally.outside_range;
      tally.worst_outside = std::max(tally.worst_outside, excess);
    }
  }
}

void ClientWatch::Published(const Model& /*model*/, const Data& data,
                            const std::vector<BridgeMotorSample>& motors) {
  if (commands_ == 0) return;
  ++states_;
  latest_time_ = std::max(latest_time_, data->time);
  for (std::size_t i = 0; i < motors.size() && i < motors_.size(); ++i) {
    const BridgeMotorSample& s = motors[i];
    if (s.command.mode == 0 || s.damping || motors_[i].info.empty()) continue;
    MotorTally& tally = tally_[i];
    const BridgeMotorInfo& info = motors_[i].info;
    double size = std::fabs(s.torque);
    if (s.torque > info.torque_hi || s.torque < info.torque_lo) ++tally.saturated;
    double error = s.command.q - s.q;
    if (size > tally.worst_torque) {
      tally.worst_torque = size;
      tally.worst_signed = s.torque;
      tally.worst_kp = s.command.kp;
      tally.worst_error = error;
    }
    if (s.command.kp <= 0) continue;
    tally.tracking_squares += error * error;
    ++tally.tracked;
    tally.tracking_worst = std::max(tally.tracking_worst, std::fabs(error));
  }
}

ClientView ClientWatch::View(double client_start) const {
  ClientView view;
  view.commands = commands_;
  view.first_command = first_wall_ - client_start;  // NaN when either is
  view.first_command_time = first_time_;
  if (periods_.count() > 0) {
    view.period_median = periods_.q50();
    view.period_p95 = periods_.q95();
    view.period_worst = periods_.max();
  }
  double span = latest_time_ - first_time_;
  if (commands_ > 0 && span > 0 && control_period_ > 0) {
    view.commands_per_period = commands_ / (span / control_period_);
  }
  for (std::size_t i : mapped_) {
    const MotorTally& t = tally_[i];
    ClientMotorView m;
    m.name = motors_[i].info.name;
    m.commands = t.commands;
    m.outside_range = t.outside_range;
    m.worst_outside = t.worst_outside;
    m.saturated = t.saturated;
    m.saturated_fraction = states_ > 0 ? double(t.saturated) / states_ : 0;
    m.worst_torque = t.worst_torque;
    if (t.tracked > 0) m.tracking_rms = std::sqrt(t.tracking_squares / t.tracked);
    m.tracking_worst = t.tracking_worst;
    view.motors.push_back(m);
  }
  view.unknown_motors = unknown_;
  view.own_pd = own_pd_;
  return view;
}

std::vector<CheckRow> ClientWatch::Rows(const ClientView& view, const BridgeStats& stats) const {
  std::vector<CheckRow> rows;
  CheckRow commands = ClientRow("client.commands", "the client commands the robot");
  commands.measured = {double(view.commands), ""};
  if (view.commands == 0) {
    commands.status = CheckStatus::kFail;
    commands.measured_text = "no command";
    commands.explanation =
        "the client never sent a command on rt/lowcmd (a good one: CRC and "
        "values checked, from the controller in charge)";
    commands.fix =
        "check that the client publishes rt/lowcmd on the bridge's DDS domain with "
        "the bridge's family of messages, and read its output for an error";
  } else {
    commands.status = CheckStatus::kPass;
    commands.measured_text = std::to_string(view.commands) +
                             " commands, the first at t = " + Num(view.first_command_time, 4) +
                             " s";
    if (std::isfinite(view.first_command)) {
      commands.measured_text += ", " + Num(view.first_command) + " s after the client started";
    }
  }
  rows.push_back(commands);
  if (view.commands == 0) {
    for (const auto& [id, title] : {std::pair{"client.period", "the client keeps its period"},
                                    std::pair{"client.range", "targets within the joints' range"},
                                    std::pair{"client.torque", "gains within the motors' torque"},
                                    std::pair{"client.motors", "only the model's motors"}}) {
      rows.push_back(Skipped(id, title));
    }
  } else {
    rows.push_back(PeriodRow(view));
    for (CheckRow& row : RangeRows(view)) rows.push_back(std::move(row));
    for (CheckRow& row : TorqueRows(view)) rows.push_back(std::move(row));
    rows.push_back(MotorsRow(view));
  }
  rows.push_back(OwnPdRow(view));
  rows.push_back(FloodRow(view, stats));
  return rows;
}

CheckRow ClientWatch::PeriodRow(const ClientView& view) const {
  CheckRow row = ClientRow("client.period", "the client keeps its period");
  if (!std::isfinite(view.period_median)) {
    row.status = CheckStatus::kSkip;
    row.explanation = "one command: no period between commands";
    return row;
  }
  double median = view.period_median;
  row.measured = {view.period_p95, "s"};
  row.measured_text = "median " + Ms(median) + ", p95 " + Ms(view.period_p95) + ", worst " +
                      Ms(view.period_worst) + " between commands (wall time)";
  bool jitter = view.period_p95 > kJitterP95 * median || view.period_worst > kJitterWorst * median;
  row.reference = {kJitterP95 * median, "s"};
  row.threshold = true;
  row.reference_text = "p95 <= " + Num(kJitterP95) +
                       " x the median, worst <= " + Num(kJitterWorst) + " x the median";
  if (jitter && !realtime_) {
    // lockstep: simulated time waits for each command, so the wall time between them is how
    // fast the client and the bridge answer each other, not a period the robot would feel
    row.status = CheckStatus::kPass;
    row.explanation = "in lockstep simulated time waits for each command: the wall time "
                      "between commands is the client's speed, not a period the motors feel; "
                      "rehearse in realtime to judge the period the client keeps";
    return row;
  }
  if (!jitter) {
    row.status = CheckStatus::kPass;
    row.explanation = "the client sends a command every " + Ms(median) + " (" + Hz(1 / median) +
                      "), steadily; the bridge's control period is " + Ms(control_period_);
    return row;
  }
  row.status = CheckStatus::kWarn;
  row.finding = "jitter";
  row.explanation = "a jittery loop: the client's period is " + Ms(median) +
                    " in the median, but " + Ms(view.period_p95) + " at p95 and " +
                    Ms(view.period_worst) +
                    " at worst; on the robot the motors hold a stale "
                    "command that long (the bridge's control period is " +
                    Ms(control_period_) + ")";
  row.fix =
      "find what stalls the client's loop (a policy call, logging, garbage collection, "
      "a shared CPU) and pace it with a clock, not a sleep after the work";
  return row;
}

CheckRow ClientWatch::RangeRow(const ClientMotorView& view, const MotorFacts& motor) const {
  CheckRow row = ClientRow("client.range", "targets within the joints' range");
  row.status = CheckStatus::kWarn;
  row.finding = "target outside the joint's range";
  row.element = motor.element;
  row.measured = {view.worst_outside, motor.unit};
  row.measured_text = std::to_string(view.outside_range) + " of " + std::to_string(view.commands) +
                      " targets outside the range, the worst " + Num(view.worst_outside) + " " +
                      motor.unit + " beyond it";
  row.reference = {0, motor.unit};
  row.threshold = true;
  row.reference_text = "within [" + Num(motor.lo, 4) + ", " + Num(motor.hi, 4) + "] " + motor.unit;
  row.explanation =
      "the client commands positions the joint cannot reach: the motor pushes "
      "it into its limit with the full kp x error";
  row.fix =
      "check the client's default pose, action scale and joint order against the "
      "model's (the bridge's motors = [...] list), or the model's joint range against "
      "the robot's";
  return row;
}

std::vector<CheckRow> ClientWatch::RangeRows(const ClientView& view) const {
  std::vector<CheckRow> rows;
  int at_edge = 0;  // motors whose targets passed a range's end by less than the tolerance
  double worst_at_edge = 0;
  for (std::size_t k = 0; k < view.motors.size() && k < mapped_.size(); ++k) {
    const MotorFacts& motor = motors_[mapped_[k]];
    const ClientMotorView& m = view.motors[k];
    if (m.outside_range > 0 && m.worst_outside > kRangeTolerance * (motor.hi - motor.lo)) {
      rows.push_back(RangeRow(m, motor));
    } else if (m.outside_range > 0) {
      ++at_edge;
      worst_at_edge = std::max(worst_at_edge, m.worst_outside);
    }
  }
  if (!rows.empty()) return rows;
  CheckRow row = ClientRow("client.range", "targets within the joints' range");
  row.status = CheckStatus::kPass;
  row.measured = {0, ""};
  row.measured_text = at_edge == 0 ? "no target outside a joint's range"
                                   : "targets of " + std::to_string(at_edge) +
                                         " motors at most " + Num(worst_at_edge) +
                                         " beyond a range's end (within " +
                                         Percent(kRangeTolerance) + " of its width)";
  return {row};
}

CheckRow ClientWatch::TorqueRow(const ClientMotorView& view, const MotorFacts& motor,
                                const MotorTally& tally) const {
  CheckRow row = ClientRow("client.torque", "gains within the motors' torque");
  row.status = CheckStatus::kWarn;
  row.finding = "saturated";
  row.element = motor.element;
  // the limit on the side of the worst torque asked
  double limit = std::fabs(tally.worst_signed < 0 ? motor.info.torque_lo : motor.info.torque_hi);
  const char* unit = motor.torque_unit;
  row.measured = {view.saturated_fraction, ""};
  row.measured_text = "saturated in " + Percent(view.saturated_fraction) + " of the states; kp " +
                      Num(tally.worst_kp) + " x error " + Num(tally.worst_error) + " " +
                      motor.unit + " (with kd and tau) asks " + Num(view.worst_torque) + " " +
                      unit + " beyond the motor's " + Num(limit) + " " + unit;
  row.reference = {kSaturated, ""};
  row.threshold = true;
  row.reference_text = "saturated in <= " + Percent(kSaturated) + " of the states";
  row.explanation =
      "the client's gains ask for more torque than the motor has: the motor "
      "clips it, and the robot tracks worse than the client expects";
  row.fix =
      "lower kp (or the target's steps) in the client's configuration, or check the "
      "model's motor limits (forcerange, ctrlrange) against the robot's";
  return row;
}

std::vector<CheckRow> ClientWatch::TorqueRows(const ClientView& view) const {
  std::vector<CheckRow> rows;
  double most = 0;
  for (std::size_t k = 0; k < view.motors.size() && k < mapped_.size(); ++k) {
    most = std::max(most, view.motors[k].saturated_fraction);
    if (view.motors[k].saturated_fraction > kSaturated) {
      std::size_t i = mapped_[k];
      rows.push_back(TorqueRow(view.motors[k], motors_[i], tally_[i]));
    }
  }
  if (!rows.empty()) return rows;
  CheckRow row = ClientRow("client.torque", "gains within the motors' torque");
  row.status = CheckStatus::kPass;
  row.measured = {most, ""};
  row.measured_text = "saturated in " + Percent(most) + " of the states at most";
  row.reference = {kSaturated, ""};
  row.threshold = true;
  row.reference_text = "<= " + Percent(kSaturated);
  return {row};
}

CheckRow ClientWatch::MotorsRow(const ClientView& view) const {
  CheckRow row = ClientRow("client.motors", "only the model's motors");
  row.measured = {double(view.unknown_motors.size()), ""};
  if (view.unknown_motors.empty()) {
    row.status = CheckStatus::kPass;
    row.measured_text =
        "the client drives only the model's " + std::to_string(mapped_.size()) + " motors";
    return row;
  }
  row.status = CheckStatus::kFail;
  std::string slots = std::to_string(motors_.size());
  row.subject = mapped_.size() == motors_.size()
                    ? "slots beyond the model's " + slots + " motors"
                    : "slots the model has no motor for (empty in motors = [...] or beyond its " +
                          slots + " slots)";
  row.measured_text = Join(view.unknown_motors, "; ");
  row.explanation =
      "the client drives motors the model lacks: what it sends there drives "
      "nothing here, and on the robot it moves a joint the rehearsal never saw";
  row.fix =
      "check the motor map: the bridge configuration's motors = [...] lists the model's "
      "motors in the robot's order; a client for a robot with more motors (a G1 of 29 "
      "against a model of 23) needs the matching model";
  return row;
}

CheckRow ClientWatch::OwnPdRow(const ClientView& view) const {
  CheckRow row = ClientRow("client.own_pd", "no PD of the model's own on the motors' joints");
  row.measured = {double(view.own_pd.size()), ""};
  if (view.own_pd.empty()) {
    row.status = CheckStatus::kPass;
    row.measured_text = "nothing of the model pulls the motors' joints";
    return row;
  }
  row.status = CheckStatus::kWarn;
  row.subject = "the motors' joints";
  row.measured_text = Join(view.own_pd, "; ");
  row.explanation =
      "two PDs act on those joints: the client's through the motor and the "
      "model's own, which the robot does not have; the joints are stiffer (or "
      "pulled elsewhere) than the client's gains say";
  row.fix =
      "remove those actuators (or their kp and kv) and joint stiffness from the model "
      "the bridge runs, or list them as the motors when they are the robot's motors";
  return row;
}

CheckRow ClientWatch::FloodRow(const ClientView& view, const BridgeStats& stats) const {
  CheckRow row = ClientRow("client.flood", "the client keeps the bridge's control period");
  bool flood = view.commands_per_period > kFlood || stats.queue_drops > 0;
  if (!std::isfinite(view.commands_per_period) && stats.queue_drops == 0) {
    row.status = CheckStatus::kSkip;
    row.explanation = view.commands == 0 ? "the client sent no command"
                                         : "no simulated time passed after the first command";
    return row;
  }
  row.measured = {view.commands_per_period, ""};
  double rate = view.commands_per_period / control_period_;
  row.measured_text = Num(view.commands_per_period) + " commands per control period (about " +
                      Hz(rate) + " against the bridge's " + Hz(1 / control_period_) + ")";
  if (stats.queue_drops > 0) {
    row.measured_text +=
        "; " + std::to_string(stats.queue_drops) + " dropped from the full command queue";
  }
  row.reference = {kFlood, ""};
  row.threshold = true;
  row.reference_text = "<= " + Num(kFlood) + " per period, none dropped";
  if (!flood) {
    row.status = CheckStatus::kPass;
    return row;
  }
  row.status = CheckStatus::kWarn;
  row.explanation = "the client sends faster than the bridge's control period (" +
                    Ms(control_period_) + "): commands pile up; " +
                    (realtime_ ? "at each period only the latest is in force, the rest are "
                                 "never applied"
                               : "each waits in the bridge's queue for a period of its own, "
                                 "later and later, and the oldest are dropped when it is full "
                                 "(command_queue)");
  row.fix =
      "run the client's loop at the robot's control rate, or set control_period in the "
      "bridge configuration to the client's period";
  return row;
}

}  // namespace plumb::internal
