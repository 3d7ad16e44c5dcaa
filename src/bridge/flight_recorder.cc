// The flight recorder (flight_recorder.h).

#include "bridge/flight_recorder.h"

#include <cstdio>

#include "plumb/error.h"
#include "plumb/sample_writer.h"

namespace plumb::bridge {
namespace {

constexpr const char* kCommandFields[] = {"mode", "q", "dq", "kp", "kd", "tau"};
constexpr const char* kStateFields[] = {"q", "dq", "tau_est"};

std::string Empty(std::size_t cells) { return std::string(cells, ','); }

}  // namespace

FlightRecorder::FlightRecorder(const std::string& path, const Model& model, const MotorMap& motors)
    : file_(std::make_unique<AtomicFile>(path)), m_(model.get()), motors_(motors.size()) {
  std::string header = "time,kind,event";
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
  simulated_ = m_->nq + m_->nv + ctrl_.size() + applied_.size() + m_->nsensordata;
  for (std::size_t i = 0; i < motors_; ++i) {
    for (const char* f : kCommandFields)
      header += ",cmd." + std::string(f) + "[" + std::to_string(i) + "]";
  }
  for (std::size_t i = 0; i < motors_; ++i) {
    for (const char* f : kStateFields)
      header += ",state." + std::string(f) + "[" + std::to_string(i) + "]";
  }
  Line(header);
}

void FlightRecorder::Line(const std::string& text) {
  if (std::fputs(text.c_str(), file_->stream()) < 0 || std::fputc('\n', file_->stream()) < 0) {
    throw IoError("the flight recorder cannot write its log '" + file_->path() + "'");
  }
}

void FlightRecorder::State(const mjData* d, const std::vector<PublishedMotor>& published,
                           const std::string& note) {
  std::string row = CsvNumber(d->time) + ",state," + CsvField(note);
  for (int i = 0; i < m_->nq; ++i) row += "," + CsvNumber(d->qpos[i]);
  for (int i = 0; i < m_->nv; ++i) row += "," + CsvNumber(d->qvel[i]);
  for (int u : ctrl_) row += "," + CsvNumber(d->ctrl[u]);
  for (int v : applied_) row += "," + CsvNumber(d->qfrc_applied[v]);
  for (int i = 0; i < m_->nsensordata; ++i) row += "," + CsvNumber(d->sensordata[i]);
  row += Empty(6 * motors_);
  for (const PublishedMotor& p : published) {
    row += "," + CsvNumber(p.q) + "," + CsvNumber(p.dq) + "," + CsvNumber(p.tau_est);
  }
  Line(row);
}

void FlightRecorder::Command(double time, const std::vector<MotorCommand>& command) {
  std::string row = CsvNumber(time) + ",command," + Empty(simulated_);
  for (const MotorCommand& c : command) {
    row += "," + std::to_string(int(c.mode));
    for (double v : {c.q, c.dq, c.kp, c.kd, c.tau}) row += "," + CsvNumber(v);
  }
  Line(row + Empty(3 * motors_));
}

void FlightRecorder::Event(double time, const std::string& what) {
  Line(CsvNumber(time) + ",event," + CsvField(what) + Empty(simulated_ + 9 * motors_));
}

void FlightRecorder::Finish() { file_->Commit(); }

}  // namespace plumb::bridge
