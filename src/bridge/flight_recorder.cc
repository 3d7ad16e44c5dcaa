// The flight recorder (flight_recorder.h).

#include "bridge/flight_recorder.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "plumb/atomic_file.h"
#include "plumb/error.h"
#include "plumb/sample_writer.h"

namespace plumb::bridge {
namespace {

constexpr const char* kCommandFields[] = {"mode", "q", "dq", "kp", "kd", "tau"};
constexpr const char* kStateFields[] = {"q", "dq", "tau_est"};

std::string Empty(std::size_t cells) { return std::string(cells, ','); }

}  // namespace

FlightRecorder::FlightRecorder(const std::string& path, const Model& model, const MotorMap& motors)
    : path_(path), m_(model.get()), motors_(motors.size()) {
  std::string header = "time,kind,event";
  for (int i = 0; i < m_->nq; ++i) header += ",qpos[" + std::to_string(i) + "]";
  for (int i = 0; i < m_->nv; ++i) header += ",qvel[" + std::to_string(i) + "]";
  for (const Motor& motor : motors.motors()) {
    if (motor.actuator >= 0) {
      ctrl_.push_back(motor.ctrl);
      header += ",ctrl[" + std::to_string(motor.ctrl) + "]";
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
  // the log appears with its header whole, then grows a line at a time
  AtomicFile file(path_);
  header += '\n';
  std::fwrite(header.data(), 1, header.size(), file.stream());
  fd_ = file.CommitForAppending();
}

FlightRecorder::~FlightRecorder() {
  if (fd_ >= 0) ::close(fd_);
}

void FlightRecorder::Line(const std::string& text) {
  std::string line = text + '\n';
  std::size_t done = 0;
  while (done < line.size()) {
    ssize_t n = ::write(fd_, line.data() + done, line.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      throw IoError("the flight recorder cannot write its log '" + path_ +
                    "': " + std::strerror(n < 0 ? errno : EIO));
    }
    done += static_cast<std::size_t>(n);
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

void FlightRecorder::Finish() {
  // a log written to a FIFO or a terminal has nothing to sync
  bool synced = fsync(fd_) == 0 || errno == EINVAL || errno == EROFS;
  int error = errno;
  bool closed = ::close(fd_) == 0;
  fd_ = -1;
  if (!synced || !closed) {
    throw IoError("the flight recorder cannot write its log '" + path_ +
                  "': " + std::strerror(synced ? errno : error));
  }
}

}  // namespace plumb::bridge
