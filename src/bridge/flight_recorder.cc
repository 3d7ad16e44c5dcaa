// The flight recorder (flight_recorder.h).

#include "bridge/flight_recorder.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "io/atomic_file.h"
#include "plumb/error.h"
#include "plumb/path.h"
#include "plumb/sample_writer.h"

namespace plumb::bridge {
using internal::AtomicFile;

namespace {

constexpr const char* kCommandFields[] = {"mode", "q", "dq", "kp", "kd", "tau"};
constexpr const char* kStateFields[] = {"q", "dq", "tau_est"};

std::string Empty(std::size_t cells) { return std::string(cells, ','); }

// `field[name]` for a named element, else `field[index]` (the array's row).
std::string Label(const Model& model, const char* field, int type, int id, int index) {
  std::string name = model.Name(type, id);
  return std::string(field) + "[" + (name.empty() ? std::to_string(index) : name) + "]";
}

// A column of what crossed the link for motor i: "cmd.q[FR_hip]" (the motor's actuator or
// joint name; its slot number when it has none).
std::string LinkColumn(const char* message, const char* field, const MotorMap& motors,
                       std::size_t i) {
  const std::string& name = motors.motors()[i].name;
  return std::string(message) + "." + field + "[" + (name.empty() ? std::to_string(i) : name) + "]";
}

}  // namespace

FlightRecorder::FlightRecorder(const std::string& path, const Model& model, const MotorMap& motors)
    : path_(path), m_(model.get()) {
  // an empty slot ("" in motors = [...]) has no columns: the mapped motors' keep their names
  for (std::size_t i = 0; i < motors.size(); ++i) {
    if (!motors.motors()[i].empty()) slots_.push_back(i);
  }
  motors_ = slots_.size();
  // qpos, qvel and sensordata named as `plumb run` names them (by joint and sensor, one column
  // an element, in address order); what was applied and what crossed the link by motor
  std::vector<Path> named = DefaultColumns(model);
  auto columns = [&](const std::string& field) {
    std::string text;
    for (const Path& p : named) {
      if (p.field == field) text += "," + CsvField(p.text);
    }
    return text;
  };
  std::string header = "time,kind,event" + columns("qpos") + columns("qvel");
  for (std::size_t i : slots_) {
    const Motor& motor = motors.motors()[i];
    if (motor.actuator >= 0) {
      ctrl_.push_back(motor.ctrl);
      header += "," + CsvField(Label(model, "ctrl", mjOBJ_ACTUATOR, motor.actuator, motor.ctrl));
    } else {
      applied_.push_back(motor.dof);
      header += "," + CsvField(Label(model, "qfrc_applied", mjOBJ_JOINT, motor.joint, motor.dof));
    }
  }
  header += columns("sensordata");
  simulated_ = m_->nq + m_->nv + ctrl_.size() + applied_.size() + m_->nsensordata;
  for (std::size_t i : slots_) {
    for (const char* f : kCommandFields) header += "," + CsvField(LinkColumn("cmd", f, motors, i));
  }
  for (std::size_t i : slots_) {
    for (const char* f : kStateFields) header += "," + CsvField(LinkColumn("state", f, motors, i));
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
  for (std::size_t i : slots_) {
    const PublishedMotor& p = published[i];
    row += "," + CsvNumber(p.q) + "," + CsvNumber(p.dq) + "," + CsvNumber(p.tau_est);
  }
  Line(row);
}

void FlightRecorder::Command(double time, const std::vector<MotorCommand>& command) {
  std::string row = CsvNumber(time) + ",command," + Empty(simulated_);
  for (std::size_t i : slots_) {
    const MotorCommand& c = command[i];
    row += "," + std::to_string(int(c.mode));
    for (double v : {c.q, c.dq, c.kp, c.kd, c.tau}) row += "," + CsvNumber(v);
  }
  Line(row + Empty(3 * motors_));
}

void FlightRecorder::Event(double time, const std::string& what) { Note(time, "event", what); }

void FlightRecorder::Gamepad(double time, const std::string& what) { Note(time, "gamepad", what); }

void FlightRecorder::Note(double time, const char* kind, const std::string& what) {
  Line(CsvNumber(time) + "," + kind + "," + CsvField(what) + Empty(simulated_ + 9 * motors_));
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
