// The IMU reading (imu.h).

#include "bridge/imu.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "bridge/positions.h"
#include "core/joint_size.h"
#include "core/strings.h"
#include "plumb/error.h"

namespace plumb::bridge {
using internal::Echo;
using internal::FirstFreeBody;

namespace {

// The sensordata address of the sensor called `name` (of `type`); when `name` is empty, of the
// one called `preferred` or (`first`) the first of `type`; -1 when there is none unnamed.
// `key` is "[imu] quaternion"; `place` where the name was written ("FILE:LINE:COLUMN: " or "").
int FindSensor(const mjModel* m, int type, const std::string& name, const char* preferred,
               bool first, const std::string& key, const std::string& place,
               const char* type_name) {
  std::string have;
  int first_of_type = -1;
  for (int s = 0; s < m->nsensor; ++s) {
    if (m->sensor_type[s] != type) continue;
    const char* its = mj_id2name(m, mjOBJ_SENSOR, s);
    bool called = its != nullptr && (name.empty() ? std::string(preferred) == its : name == its);
    if (called) return m->sensor_adr[s];
    if (first_of_type < 0) first_of_type = m->sensor_adr[s];
    have += fmt::format("{}'{}'", have.empty() ? "" : ", ", its != nullptr ? its : "");
  }
  if (name.empty()) return first ? first_of_type : -1;
  throw ValueError(fmt::format("{}{} = '{}': the model has no {} sensor of that name ({})", place,
                               key, Echo(name), type_name,
                               have.empty() ? std::string("it has none") : "it has " + have));
}

}  // namespace

std::array<double, 3> RollPitchYaw(const std::array<double, 4>& q) {
  double w = q[0], x = q[1], y = q[2], z = q[3];
  double roll = std::atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y));
  double pitch = std::asin(std::clamp(2 * (w * y - z * x), -1.0, 1.0));
  double yaw = std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
  return {roll, pitch, yaw};
}

Imu Imu::Bind(const Model& model, const BridgeImuSource& source, const ImuDefaults& defaults,
              const BridgePositions& positions) {
  const mjModel* m = model.get();
  Imu imu;
  std::string t = "[" + std::string(defaults.table) + "] ";
  auto place = [&](const char* key) {
    return Place(positions, defaults.table + ("." + std::string(key)));
  };
  bool first = defaults.first_of_type;
  imu.quat_ = FindSensor(m, mjSENS_FRAMEQUAT, source.quaternion, defaults.quaternion, first,
                         t + "quaternion", place("quaternion"), "framequat");
  imu.gyro_ = FindSensor(m, mjSENS_GYRO, source.gyroscope, defaults.gyroscope, first,
                         t + "gyroscope", place("gyroscope"), "gyro");
  imu.accel_ = FindSensor(m, mjSENS_ACCELEROMETER, source.accelerometer, defaults.accelerometer,
                          first, t + "accelerometer", place("accelerometer"), "accelerometer");
  if (!source.body.empty()) {
    imu.base_ = mj_name2id(m, mjOBJ_BODY, source.body.c_str());
    if (imu.base_ <= 0) {
      throw ValueError(fmt::format("{}[{}] body = '{}': the model has no such body{}",
                                   place("body"), defaults.table, Echo(source.body),
                                   imu.base_ == 0 ? " (the world body cannot carry an IMU)" : ""));
    }
    return imu;
  }
  if (defaults.base_body) imu.base_ = FirstFreeBody(m);
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
