// The flight recorder (flight_recorder.h).

#include "bridge/flight_recorder.h"

#include <cstdio>

#include "plumb/error.h"
#include "plumb/sample_writer.h"

namespace plumb::bridge {
namespace {

void Put(std::FILE* f, const std::string& text) {
  if (std::fputs(text.c_str(), f) < 0) throw IoError("the flight recorder cannot write its log");
}

}  // namespace

FlightRecorder::FlightRecorder(const std::string& path, const Model& model, const MotorMap& motors)
    : file_(std::make_unique<AtomicFile>(path)), m_(model.get()) {
  std::string header = "time,event";
  for (int i = 0; i < m_->nq; ++i) header += ",qpos[" + std::to_string(i) + "]";
  for (int i = 0; i < m_->nv; ++i) header += ",qvel[" + std::to_string(i) + "]";
  for (const Motor& motor : motors.motors()) {
    if (motor.actuator >= 0) {
      ctrl_.push_back(motor.actuator);
      header += ",ctrl[" + std::to_string(motor.actuator) + "]";
    } else {
      applied_.push_back(motor.dof);
      header += ",qfrc_applied[" + std::to_string(motor.dof) + "]";
    }
  }
  for (int i = 0; i < m_->nsensordata; ++i) header += ",sensordata[" + std::to_string(i) + "]";
  columns_ = 2 + m_->nq + m_->nv + ctrl_.size() + applied_.size() + m_->nsensordata;
  Put(file_->stream(), header + "\n");
}

void FlightRecorder::Row(const mjData* d) {
  std::string row = CsvNumber(d->time) + ",";
  for (int i = 0; i < m_->nq; ++i) row += "," + CsvNumber(d->qpos[i]);
  for (int i = 0; i < m_->nv; ++i) row += "," + CsvNumber(d->qvel[i]);
  for (int u : ctrl_) row += "," + CsvNumber(d->ctrl[u]);
  for (int v : applied_) row += "," + CsvNumber(d->qfrc_applied[v]);
  for (int i = 0; i < m_->nsensordata; ++i) row += "," + CsvNumber(d->sensordata[i]);
  Put(file_->stream(), row + "\n");
}

void FlightRecorder::Event(double time, const std::string& what) {
  Put(file_->stream(),
      CsvNumber(time) + "," + CsvField(what) + std::string(columns_ - 2, ',') + "\n");
}

void FlightRecorder::Finish() { file_->Commit(); }

}  // namespace plumb::bridge
