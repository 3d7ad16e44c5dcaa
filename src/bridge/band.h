// The elastic band (plumb/bridge.h, BridgeBand): a spring-damper from a fixed anchor to a
// body's centre of mass that holds a robot up, as robots are started on a gantry, and a
// rotational one that holds the body at its start orientation, as a hoist keeps a robot
// upright, until it is released at a time or by a gamepad button. It pulls and turns through
// the body's xfrc_applied, which the bridge owns while the band is on (and zeroes when it lets
// go).

#ifndef PLUMB_SRC_BRIDGE_BAND_H_
#define PLUMB_SRC_BRIDGE_BAND_H_

#include <cstdint>
#include <string>

#include "plumb/bridge.h"
#include "plumb/model.h"

namespace plumb::bridge {

class Band {
 public:
  Band() = default;  // no band
  // Binds the band to `d`'s state at the start (its anchor and rest length may come from it).
  // @throws ValueError naming [band] body (at its file:line, given `positions`,
  // BridgeConfig::positions) when the body is not in the model.
  Band(const mjModel* m, const mjData* d, const BridgeBand& config,
       const BridgePositions& positions = {});
  bool on() const { return body_ >= 0 && !released_; }
  // Sets the band's pull and hold on the body in d->xfrc_applied; `d`'s positions and
  // velocities must be computed (after mj_step1 or a forward pass).
  void Apply(const mjModel* m, mjData* d) const;
  // Lets go when the time or the button has come: returns what to log ("band: released at
  // t = 3 s (release_at)"), or "" while it holds. `keys`: the gamepad's buttons now.
  std::string Release(mjData* d, std::uint16_t keys);
  // What the band is, for the log ("band: pelvis hangs 1 m below (0, 0, 1.79) ...").
  const std::string& description() const { return description_; }

 private:
  // The hold's gains (BridgeBand's, or their defaults for this robot) and its orientation.
  void SetHold(const mjModel* m, const mjData* d, const BridgeBand& config);

  int body_ = -1;
  double anchor_[3] = {0, 0, 0};
  double stiffness_ = 0, damping_ = 0, length_ = 0;
  double release_at_ = 0;
  double hold_stiffness_ = 0, hold_damping_ = 0;  // N*m/rad, N*m*s/rad
  double start_quat_[4] = {1, 0, 0, 0};           // the body's orientation at the start
  int button_ = -1;                               // the release button's bit, or -1
  std::string button_name_;
  bool released_ = false;
  std::string description_;
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_BAND_H_
