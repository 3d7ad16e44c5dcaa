// What plumb sees of a rehearsal's client, whatever the client's own configuration says: the
// commands it sends (the period it keeps in wall time), the targets and gains in them against
// the model (joint ranges, the motors' torque limits, slots the model has no motor for), and
// the model's own actuators that add a PD on top of the commanded one. Fed by the bridge's
// observer (plumb/bridge.h BridgeObserver), on the bridge's thread.
//
// A slot "asks" for something when its mode is not 0: a target position counts against the
// joint's range when its kp is above 0 (Unitree's clients write PosStopF, 2.146e9, with kp 0
// to mean "no position control"); a slot beyond the model's motors, or empty in the bridge's
// motors = [...] ("": the robot's slot the model has no motor for), counts as commanded when it
// asks for torque (kp, kd or tau not 0, whatever its mode: Unitree's InitLowCmd sets mode 1,
// PosStopF and VelStopF with zero gains in every slot, which drives nothing).
//
// Thread-safety: one thread at a time (the bridge's); View and Rows once it has stopped.

#ifndef PLUMB_SRC_REHEARSE_CLIENT_WATCH_H_
#define PLUMB_SRC_REHEARSE_CLIENT_WATCH_H_

#include <cmath>
#include <string>
#include <vector>

#include "plumb/bridge.h"
#include "plumb/check.h"
#include "plumb/model.h"
#include "plumb/rehearse.h"
#include "plumb/statistics.h"

namespace plumb::internal {

class ClientWatch {
 public:
  // `model` is the bridge's copy, `motors` in motor order. The watch keeps no reference to
  // either, nor to `config`: what it needs of them is read here.
  ClientWatch(const Model& model, const std::vector<BridgeMotorInfo>& motors,
              const BridgeConfig& config);

  void Commanded(double t, double wall, const std::vector<BridgeCommandSlot>& slots);
  // States before the first command are not counted.
  void Published(const Model& model, const Data& data,
                 const std::vector<BridgeMotorSample>& motors);

  // What was seen; `client_start` is the steady clock's s when the client started (NaN: not
  // started), for ClientView::first_command.
  ClientView View(double client_start) const;

  // The client's rows (section "client"): client.commands (FAIL: none), client.period,
  // client.range, client.torque, client.motors, client.own_pd, client.flood; each WARN or FAIL
  // names what it saw and what to do. With no command the rows that judge commands are SKIP.
  std::vector<CheckRow> Rows(const ClientView& view, const BridgeStats& stats) const;

  // The thresholds of the rows.
  static constexpr double kJitterP95 = 1.5;   // p95 period beyond this x the median: WARN
  static constexpr double kJitterWorst = 3;   // worst period beyond this x the median: WARN
  static constexpr double kSaturated = 0.05;  // fraction of states saturated beyond it: WARN
  // A target beyond a joint's range by more than this fraction of the range's width: WARN. A
  // policy's target at a limit's edge (H1's hip yaw, 0.09 mrad beyond once in 1200) is not the
  // finding; a joint order or default pose that is wrong is (swapped G1 legs: 0.41 rad).
  static constexpr double kRangeTolerance = 0.02;
  static constexpr double kFlood = 2;         // commands per control period beyond it: WARN

 private:
  // What the watch needs of one motor, read at construction.
  struct MotorFacts {
    BridgeMotorInfo info;
    CheckElement element;  // the actuator, or the joint driven through qfrc_applied
    bool limited = false;  // a hinge or slide with a range
    double lo = -INFINITY, hi = INFINITY;
    const char* unit = "rad";  // of its position: "rad" or "m"
    const char* torque_unit = "N*m";
  };
  struct MotorTally {
    long commands = 0;  // commands with this motor's mode not 0
    long outside_range = 0;
    double worst_outside = 0;
    long saturated = 0;
    double worst_torque = 0;
    double worst_signed = 0, worst_kp = 0, worst_error = 0;  // of the state that asked it
    double tracking_squares = 0;
    long tracked = 0;
    double tracking_worst = 0;
  };

  CheckRow RangeRow(const ClientMotorView& view, const MotorFacts& motor) const;
  CheckRow TorqueRow(const ClientMotorView& view, const MotorFacts& motor,
                     const MotorTally& tally) const;
  std::vector<CheckRow> RangeRows(const ClientView& view) const;
  std::vector<CheckRow> TorqueRows(const ClientView& view) const;
  CheckRow PeriodRow(const ClientView& view) const;
  CheckRow MotorsRow(const ClientView& view) const;
  CheckRow OwnPdRow(const ClientView& view) const;
  CheckRow FloodRow(const ClientView& view, const BridgeStats& stats) const;

  std::vector<MotorFacts> motors_;   // in slot order, empty slots included
  std::vector<std::size_t> mapped_;  // the slots with a motor; ClientView::motors follows them
  double control_period_ = 0;
  bool realtime_ = false;
  std::vector<std::string> own_pd_;  // found at construction
  long commands_ = 0;
  double first_wall_ = NAN, first_time_ = NAN, last_wall_ = NAN;
  double latest_time_ = NAN;   // the latest simulated time seen from the first command on
  SummaryStatistics periods_;  // s of wall time between successive commands
  std::vector<MotorTally> tally_;
  std::vector<int> unknown_slots_;  // in the order first seen
  std::vector<std::string> unknown_;
  long states_ = 0;  // published from the first command on
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_REHEARSE_CLIENT_WATCH_H_
