// The rehearsal's assertions and time axis (rehearsal_tally.h).

#include "rehearse/rehearsal_tally.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace plumb::internal {
namespace {
using Signal = RehearsalAssertion::Signal;

std::vector<Assertion> Plain(const std::vector<RehearsalAssertion>& assertions) {
  std::vector<Assertion> plain;
  for (const RehearsalAssertion& r : assertions) plain.push_back(r.assertion);
  return plain;
}

// Each assertion's signals as the tally names them: none for a path assertion (its paths).
std::vector<std::vector<std::string>> SignalNames(const std::vector<RehearsalAssertion>& all) {
  std::vector<std::vector<std::string>> names;
  for (const RehearsalAssertion& r : all) {
    names.push_back(r.signal == Signal::kPath ? std::vector<std::string>{} : r.names);
  }
  return names;
}

const char* Unit(Signal signal) {
  return signal == Signal::kTorque ? "N*m" : "";  // a tracking error is rad or m
}

// Keeps the even positions of `v`: the samples of a trace whose stride doubles.
void KeepEveryOther(std::vector<double>* v) {
  std::size_t n = (v->size() + 1) / 2;
  for (std::size_t i = 0; i < n; ++i) (*v)[i] = (*v)[2 * i];
  v->resize(n);
}

}  // namespace

RehearsalTally::RehearsalTally(const std::vector<RehearsalAssertion>& assertions,
                               const std::vector<BridgeMotorInfo>& motors, std::size_t trace_cap)
    : assertions_(assertions),
      plain_(Plain(assertions)),
      tally_(plain_, SignalNames(assertions)),
      motors_(motors),
      trace_cap_(std::max<std::size_t>(trace_cap, 2)) {
  for (std::size_t i = 0; i < motors.size(); ++i) {
    if (motors[i].empty()) continue;  // "" in motors = [...]: no motor, no trace
    motor_slots_.push_back(i);
    motor_names_.push_back(motors[i].name.empty() ? std::to_string(i) : motors[i].name);
  }
  // the asserted signals, each once, then each motor's commanded and measured position
  std::map<std::string, std::size_t> index;
  auto add = [&](const std::string& name) {
    auto [at, fresh] = index.emplace(name, trace_.signals.size());
    if (fresh) trace_.signals.push_back(name);
    return at->second;
  };
  for (const RehearsalAssertion& r : assertions_) {
    std::vector<std::size_t> rows;
    if (r.signal == Signal::kPath) {
      for (const Path& p : r.assertion.paths) rows.push_back(add(p.text));
    } else {
      for (const std::string& name : r.names) rows.push_back(add(name));
    }
    trace_index_.push_back(std::move(rows));
  }
  for (const std::string& name : motor_names_) add("q_des[" + name + "]");
  for (const std::string& name : motor_names_) add("q[" + name + "]");
  trace_.values.resize(trace_.signals.size());
}

std::optional<double> RehearsalTally::Value(std::size_t a, std::size_t k, const Model& model,
                                            const Data& data,
                                            const std::vector<BridgeMotorSample>& motors) const {
  const RehearsalAssertion& r = assertions_[a];
  if (r.signal == Signal::kPath) return ReadValue(model, data, r.assertion.paths[k]);
  std::size_t m = static_cast<std::size_t>(r.motors[k]);
  if (m >= motors.size()) return std::nullopt;
  const BridgeMotorSample& s = motors[m];
  const BridgeCommandSlot& c = s.command;
  switch (r.signal) {
    case Signal::kTrackingError:  // only while a position command is in force
      if (c.mode == 0 || !(c.kp > 0)) return std::nullopt;
      return c.q - s.q;
    case Signal::kTorque:
      return s.torque;
    case Signal::kSaturated: {
      if (c.mode == 0 || s.damping || m >= motors_.size()) return 0.0;
      const BridgeMotorInfo& info = motors_[m];
      return s.torque < info.torque_lo || s.torque > info.torque_hi ? 1.0 : 0.0;
    }
    case Signal::kPath:
      break;
  }
  return std::nullopt;
}

// A long rehearsal at 500 states per second would keep 100 MB of trace: the trace keeps at
// most trace_cap_ samples, evenly spaced. Once full, every other sample is dropped and the
// stride doubles (every 2nd state from then on, then every 4th, ...), so the kept states stay
// those whose count is a multiple of the stride.
bool RehearsalTally::KeepInTrace() {
  long n = states_++;
  if (n % stride_ != 0) return false;
  if (trace_.time.size() >= trace_cap_) {
    KeepEveryOther(&trace_.time);
    for (std::vector<double>& v : trace_.values) KeepEveryOther(&v);
    stride_ *= 2;
    if (n % stride_ != 0) return false;
  }
  return true;
}

void RehearsalTally::Sample(const Model& model, const Data& data,
                            const std::vector<BridgeMotorSample>& motors) {
  double t = data->time;
  bool keep = KeepInTrace();
  if (keep) {
    trace_.time.push_back(t);
    for (std::vector<double>& v : trace_.values) v.push_back(NAN);
  }
  for (std::size_t a = 0; a < assertions_.size(); ++a) {
    if (!keep && !tally_.InWindow(a, t)) continue;
    for (std::size_t k = 0; k < trace_index_[a].size(); ++k) {
      std::optional<double> v = Value(a, k, model, data, motors);
      if (!v) continue;
      tally_.SampleValue(a, k, *v, t);
      if (keep) trace_.values[trace_index_[a][k]].back() = *v;
    }
  }
  if (!keep) return;
  std::size_t q_des = trace_.values.size() - 2 * motor_names_.size();
  for (std::size_t m = 0; m < motor_slots_.size(); ++m) {
    std::size_t slot = motor_slots_[m];
    if (slot >= motors.size()) break;
    const BridgeCommandSlot& c = motors[slot].command;
    trace_.values[q_des + m].back() = c.mode != 0 ? c.q : NAN;
    trace_.values[q_des + motor_names_.size() + m].back() = motors[slot].q;
  }
}

void RehearsalTally::Event(double t, const std::string& what) {
  trace_.events.emplace_back(t, what);
}

std::vector<CheckRow> RehearsalTally::Rows() const {
  std::vector<CheckRow> rows;
  for (std::size_t a = 0; a < assertions_.size(); ++a) {
    const RehearsalAssertion& r = assertions_[a];
    const Assertion& as = r.assertion;
    AssertionTally::Verdict verdict = tally_.Judge(a);
    CheckRow row;
    row.section = "assert";
    row.id = "assert";
    row.subject = as.text;
    row.status = verdict.ok ? CheckStatus::kPass : CheckStatus::kFail;
    row.measured = {verdict.value, Unit(r.signal)};
    row.measured_text = verdict.measured;
    row.reference = {as.bound, Unit(r.signal)};
    row.threshold = true;
    row.reference_text = fmt::format("{} {:g}", ComparisonName(as.op), as.bound);
    row.explanation = verdict.ok ? "The assertion holds over its window."
                                 : "The assertion fails: the robot did not do what it expects "
                                   "over its window.";
    rows.push_back(std::move(row));
  }
  return rows;
}

RehearsalTrace RehearsalTally::TakeTrace() { return std::move(trace_); }

}  // namespace plumb::internal
