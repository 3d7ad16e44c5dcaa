// What rt/sportmodestate reports (unitree_go SportModeState_), read from the simulation: the
// base body's position and linear velocity (world frame, at the body's origin) and its yaw
// rate, its height above the feet (base z less the feet's mean z; base z without feet), and for
// each foot its position and velocity relative to the base in the base's frame and its contact
// force (the normal force of every contact it makes, N). A foot is a site, geom or body (named
// in that order of lookup); a site's or body's contacts are those of its body's geoms.

#ifndef PLUMB_SRC_BRIDGE_SPORT_STATE_H_
#define PLUMB_SRC_BRIDGE_SPORT_STATE_H_

#include <array>
#include <vector>

#include "plumb/bridge.h"
#include "plumb/model.h"

namespace plumb::bridge {

struct SportReading {
  std::array<double, 3> position = {0, 0, 0};
  std::array<double, 3> velocity = {0, 0, 0};
  double yaw_speed = 0;
  double body_height = 0;
  std::array<std::array<double, 3>, 4> foot_position = {};  // base frame, m
  std::array<std::array<double, 3>, 4> foot_speed = {};     // base frame, m/s
  std::array<double, 4> foot_force = {0, 0, 0, 0};          // N
};

class SportState {
 public:
  // An unbound reader publishes nothing (no base body, or [sport_state] publish = false).
  // @throws ValueError naming the [sport_state] key when the base or a foot is not in the model.
  // With `positions` (BridgeConfig::positions) the message starts at the name's file:line.
  static SportState Bind(const Model& model, const BridgeSportState& config,
                         const BridgePositions& positions = {});
  bool enabled() const { return base_ >= 0; }
  std::size_t feet() const { return feet_.size(); }
  // `d`'s derived arrays (poses, velocities, contacts) must describe its state.
  SportReading Read(const mjModel* m, const mjData* d) const;

 private:
  struct Foot {
    int type = mjOBJ_BODY;  // mjOBJ_SITE, mjOBJ_GEOM or mjOBJ_BODY
    int id = -1;
    int body = -1;  // whose geoms' contacts count (a geom: only itself)
  };
  bool Touches(const Foot& foot, const mjModel* m, int geom) const;
  int base_ = -1;
  std::vector<Foot> feet_;
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_SPORT_STATE_H_
