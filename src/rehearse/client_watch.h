// What plumb sees of a rehearsal's client, whatever the client's own configuration says: the
// commands it sends (the period it keeps in wall time), the targets and gains in them against
// the model (joint ranges, the motors' torque limits, slots the model has no motor for), and
// the model's own actuators that add a PD on top of the commanded one. Fed by the bridge's
// observer (plumb/bridge.h BridgeObserver), on the bridge's thread.

#ifndef PLUMB_SRC_REHEARSE_CLIENT_WATCH_H_
#define PLUMB_SRC_REHEARSE_CLIENT_WATCH_H_

#include <vector>

#include "plumb/bridge.h"
#include "plumb/check.h"
#include "plumb/model.h"
#include "plumb/rehearse.h"

namespace plumb::internal {

class ClientWatch {
 public:
  // `model` is the bridge's copy (it outlives the watch's use), `motors` in motor order.
  ClientWatch(const Model& model, const std::vector<BridgeMotorInfo>& motors,
              const BridgeConfig& config);

  void Commanded(double t, double wall, const std::vector<BridgeCommandSlot>& slots);
  void Published(const Model& model, const Data& data,
                 const std::vector<BridgeMotorSample>& motors);

  // What was seen; `client_start` is the steady clock's s when the client started (NaN: not
  // started), for ClientView::first_command.
  ClientView View(double client_start) const;

  // The client's rows (section "client"): client.commands (FAIL: none), client.period,
  // client.range, client.torque, client.motors, client.own_pd, client.flood; each WARN or FAIL
  // names what it saw and what to do.
  std::vector<CheckRow> Rows(const ClientView& view, const BridgeStats& stats) const;

 private:
  const Model& model_;
  std::vector<BridgeMotorInfo> motors_;
  const BridgeConfig& config_;
  // ... (the implementation's accumulators)
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_REHEARSE_CLIENT_WATCH_H_
