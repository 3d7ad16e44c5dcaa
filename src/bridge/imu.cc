// The IMU reading (imu.h).

#include "bridge/imu.h"

#include <algorithm>
#include <cmath>

namespace plumb::bridge {
namespace {

int FirstSensor(const mjModel* m, int type) {
  for (int s = 0; s < m->nsensor; ++s) {
    if (m->sensor_type[s] == type) return m->sensor_adr[s];
  }
  return -1;
}

}  // namespace

std::array<double, 3> RollPitchYaw(const std::array<double, 4>& q) {
  double w = q[0], x = q[1], y = q[2], z = q[3];
  double roll = std::atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y));
  double pitch = std::asin(std::clamp(2 * (w * y - z * x), -1.0, 1.0));
  double yaw = std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
  return {roll, pitch, yaw};
}

Imu Imu::Bind(const Model& model) {
  const mjModel* m = model.get();
  Imu imu;
  imu.quat_ = FirstSensor(m, mjSENS_FRAMEQUAT);
  imu.gyro_ = FirstSensor(m, mjSENS_GYRO);
  imu.accel_ = FirstSensor(m, mjSENS_ACCELEROMETER);
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] == mjJNT_FREE) {
      imu.base_ = m->jnt_bodyid[j];
      break;
    }
  }
  return imu;
}

ImuReading Imu::Read(const mjModel* m, mjData* d) const {
  ImuReading r;
  if (quat_ >= 0) {
    std::copy(d->sensordata + quat_, d->sensordata + quat_ + 4, r.quaternion.begin());
  } else if (base_ >= 0) {
    std::copy(d->xquat + 4 * base_, d->xquat + 4 * base_ + 4, r.quaternion.begin());
  }
  mjtNum v[6];
  if (gyro_ >= 0) {
    std::copy(d->sensordata + gyro_, d->sensordata + gyro_ + 3, r.gyroscope.begin());
  } else if (base_ >= 0) {
    mj_objectVelocity(m, d, mjOBJ_BODY, base_, v, 1);  // [angular; linear], local frame
    std::copy(v, v + 3, r.gyroscope.begin());
  }
  if (accel_ >= 0) {
    std::copy(d->sensordata + accel_, d->sensordata + accel_ + 3, r.accelerometer.begin());
  } else if (base_ >= 0) {
    // cacc holds the acceleration with gravity as the base's: what an accelerometer reads
    mj_rnePostConstraint(m, d);
    mj_objectAcceleration(m, d, mjOBJ_BODY, base_, v, 1);
    std::copy(v + 3, v + 6, r.accelerometer.begin());
  }
  r.rpy = RollPitchYaw(r.quaternion);
  return r;
}

}  // namespace plumb::bridge
