// The robot's IMU as the bridge publishes it: quaternion (w, x, y, z), gyroscope (rad/s) and
// accelerometer (m/s^2, specific force) in the IMU's frame, and roll-pitch-yaw (rad).
// Each from the sensor the configuration names ([imu] quaternion / gyroscope / accelerometer),
// else the sensor named imu_quat / imu_gyro / imu_acc, else the model's first framequat / gyro /
// accelerometer sensor, else the base body: the
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

// Which sensors an IMU reads where its table names none.
struct ImuDefaults {
  const char* table;  // "imu", "secondary_imu": for messages
  // the sensor names taken when the model has them (unitree_mujoco's)
  const char *quaternion, *gyroscope, *accelerometer;
  bool first_of_type;  // else the model's first sensor of each type
  bool base_body;      // else the base body (the first moved by a free joint)
};
inline constexpr ImuDefaults kPrimaryImu = {"imu", "imu_quat", "imu_gyro", "imu_acc", true, true};
// The second IMU takes only what is named, or unitree_mujoco's secondary_imu_* sensors.
inline constexpr ImuDefaults kSecondaryImu = {
    "secondary_imu", "secondary_imu_quat", "secondary_imu_gyro", "secondary_imu_acc", false, false};

class Imu {
 public:
  // @throws ValueError when a named sensor is missing or of another type, or the named body
  // is missing; the message names the table's key (at its file:line, given `positions`,
  // BridgeConfig::positions) and lists what the model has.
  static Imu Bind(const Model& model, const BridgeImuSource& source = {},
                  const ImuDefaults& defaults = kPrimaryImu, const BridgePositions& positions = {});
  // Whether anything is read (a sensor or a body): else Read gives the identity and zeros.
  bool reads() const { return quat_ >= 0 || gyro_ >= 0 || accel_ >= 0 || base_ >= 0; }
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
