// The robot's IMU as the bridge publishes it: quaternion (w, x, y, z), gyroscope (rad/s) and
// accelerometer (m/s^2, specific force) in the IMU's frame, and roll-pitch-yaw (rad).
// Each from the sensor the configuration names ([imu] quaternion / gyroscope / accelerometer),
// else the model's first framequat / gyro / accelerometer sensor, else the base body: the
// body named by [imu] body, or the first body moved by a free joint (its orientation, its
// angular velocity and its acceleration less gravity, in its own frame). A model without
// either (a fixed arm, the pendulum) reports the identity and zeros.

#ifndef PLUMB_SRC_BRIDGE_IMU_H_
#define PLUMB_SRC_BRIDGE_IMU_H_

#include <array>

#include "plumb/bridge.h"
#include "plumb/model.h"

namespace plumb::bridge {

struct ImuReading {
  std::array<double, 4> quaternion = {1, 0, 0, 0};
  std::array<double, 3> gyroscope = {0, 0, 0};
  std::array<double, 3> accelerometer = {0, 0, 0};
  std::array<double, 3> rpy = {0, 0, 0};
};

// Roll, pitch, yaw (intrinsic z-y-x) of a unit quaternion (w, x, y, z).
std::array<double, 3> RollPitchYaw(const std::array<double, 4>& q);

class Imu {
 public:
  // @throws ValueError when a named sensor is missing or of another type, or the named body
  // is missing; the message names the [imu] key and lists what the model has.
  static Imu Bind(const Model& model, const BridgeImuSource& source = {});
  // `d`'s derived arrays must describe its state (after mj_forward or DerivedRefresher, not
  // right after mj_step); the base-body accelerometer needs mj_rnePostConstraint, which it
  // runs.
  ImuReading Read(const mjModel* m, mjData* d) const;

 private:
  int quat_ = -1, gyro_ = -1, accel_ = -1;  // sensordata addresses
  int base_ = -1;                           // body, or -1
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_IMU_H_
