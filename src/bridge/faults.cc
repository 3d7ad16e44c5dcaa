// Fault injection (faults.h).

#include "bridge/faults.h"

#include <algorithm>

#include "plumb/random.h"

namespace plumb::bridge {

Faults::Faults(std::vector<FaultSpec> specs, std::uint64_t seed)
    : specs_(std::move(specs)), phase_(specs_.size(), 0), seed_(seed) {}

std::vector<std::string> Faults::Transitions(double t) {
  std::vector<std::string> said;
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const FaultSpec& f = specs_[i];
    if (phase_[i] == 0 && t >= f.start) {
      phase_[i] = 1;
      said.push_back("fault starts: " + f.text);
    }
    if (phase_[i] == 1 && t >= f.stop) {
      phase_[i] = 2;
      said.push_back("fault stops: " + f.text);
    }
  }
  return said;
}

bool Faults::Drop(bool state, double t, std::uint32_t n) const {
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const FaultSpec& f = specs_[i];
    if (f.kind == FaultSpec::Kind::kDrop && f.state == state && Active(f, t) &&
        Uniform01(seed_, i, 0, n) < f.probability) {
      return true;
    }
  }
  return false;
}

double Faults::Latency(bool state, double t, std::uint32_t n) const {
  double delay = 0;
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const FaultSpec& f = specs_[i];
    if (f.kind == FaultSpec::Kind::kLatency && f.state == state && Active(f, t)) {
      delay += f.fixed + f.jitter * Uniform01(seed_, i, 1, n);
    }
  }
  return delay;
}

double Faults::Noise(const std::string& signal, int motor, double t, std::uint32_t n) const {
  double add = 0;
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const FaultSpec& f = specs_[i];
    if (f.kind != FaultSpec::Kind::kNoise || f.signal != signal || !Active(f, t)) continue;
    if (f.motor >= 0 && f.motor != motor) continue;
    // one stream a fault, one key a motor or component, one counter a message
    add += f.bias + f.sigma * StandardNormal(seed_, i, static_cast<std::uint32_t>(motor + 1), n);
  }
  return add;
}

double Faults::TorqueLimit(int motor, double t) const {
  double limit = INFINITY;
  for (const FaultSpec& f : specs_) {
    if (f.kind == FaultSpec::Kind::kTorqueLimit && Active(f, t) &&
        (f.motor < 0 || f.motor == motor)) {
      limit = std::min(limit, f.limit);
    }
  }
  return limit;
}

int Faults::Failure(int motor, double t) const {
  for (const FaultSpec& f : specs_) {
    if (f.kind == FaultSpec::Kind::kMotorFailure && Active(f, t) && f.motor == motor) {
      return f.stuck ? 2 : 1;
    }
  }
  return 0;
}

bool Faults::ImuFrozen(double t) const {
  return std::any_of(specs_.begin(), specs_.end(), [&](const FaultSpec& f) {
    return f.kind == FaultSpec::Kind::kImuFreeze && Active(f, t);
  });
}

bool Faults::ControllerPaused(double t) const {
  return std::any_of(specs_.begin(), specs_.end(), [&](const FaultSpec& f) {
    return f.kind == FaultSpec::Kind::kControllerPause && Active(f, t);
  });
}

}  // namespace plumb::bridge
