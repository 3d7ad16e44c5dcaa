#include "scenario/metric_probe.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/strings.h"
#include "plumb/analytic.h"

namespace plumb::internal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool ReadsDerived(const Metric& metric) {
  return metric.kind == MetricKind::kEnergyDrift ||
         (metric.kind != MetricKind::kStateAt && metric.path.role == Role::kDerived);
}

}  // namespace

MetricProbe::MetricProbe(const Model& work, const std::vector<Metric>& metrics, bool scales)
    : work_(work),
      metrics_(metrics),
      scales_(scales),
      dt_(work->opt.timestep),
      read_step_(metrics.size(), -1),
      tracks_(metrics.size()),
      refresh_(work) {
  for (std::size_t k = 0; k < metrics.size(); ++k) {
    const Metric& metric = metrics[k];
    if (metric.kind == MetricKind::kValueAt || metric.kind == MetricKind::kStateAt) {
      read_step_[k] = std::lround(metric.time / dt_);
    }
  }
}

bool MetricProbe::Reads(std::size_t k, long step) const {
  return scales_ || read_step_[k] < 0 || read_step_[k] == step;
}

void MetricProbe::Observe(Data& data, long step) {
  // after mj_step, derived quantities still describe the state before the step: recompute
  // them (without touching the trajectory) when a metric reads one now
  for (std::size_t k = 0; k < metrics_.size(); ++k) {
    if (ReadsDerived(metrics_[k]) && Reads(k, step)) {
      refresh_(data);
      break;
    }
  }
  for (std::size_t k = 0; k < metrics_.size(); ++k) {
    if (Reads(k, step)) Read(k, data, step);
  }
}

void MetricProbe::Read(std::size_t k, const Data& data, long step) {
  const Metric& metric = metrics_[k];
  Track* track = &tracks_[k];
  const mjModel* m = work_.get();
  const mjData* d = data.get();
  bool at_time = read_step_[k] == step;
  double t = static_cast<double>(step) * dt_;
  switch (metric.kind) {
    case MetricKind::kValueAt:
    case MetricKind::kMaxAbs:
    case MetricKind::kPeriod: {
      const Path& path = metric.path;
      double v = ReadValue(work_, data, path);
      if (metric.kind == MetricKind::kPeriod) {
        track->t.push_back(t);
        track->x.push_back(v);
      }
      if (metric.kind == MetricKind::kValueAt && at_time) track->value = v;
      track->maxabs = track->seen ? std::max(track->maxabs, std::fabs(v)) : std::fabs(v);
      track->low = track->seen ? std::min(track->low, v) : v;
      track->high = track->seen ? std::max(track->high, v) : v;
      break;
    }
    case MetricKind::kStateAt: {
      std::vector<double>& state = state_;
      state.assign(d->qpos, d->qpos + m->nq);
      state.insert(state.end(), d->qvel, d->qvel + m->nv);
      state.insert(state.end(), d->act, d->act + m->na);
      if (!track->seen) track->first = state;
      double norm = 0, moved = 0;
      for (std::size_t i = 0; i < state.size(); ++i) {
        norm += state[i] * state[i];
        moved += (state[i] - track->first[i]) * (state[i] - track->first[i]);
      }
      track->maxabs = std::max(track->maxabs, std::sqrt(norm));
      track->excursion = std::max(track->excursion, std::sqrt(moved));
      if (at_time) track->last = state;
      break;
    }
    case MetricKind::kEnergyDrift: {
      double e = d->energy[0] + d->energy[1];
      if (!track->seen) track->e0 = e;
      track->e1 = e;
      track->max_kinetic = std::max(track->max_kinetic, d->energy[1]);
      break;
    }
  }
  track->seen = true;
}

Measurement MetricProbe::Result(std::size_t k, double until) const {
  const Metric& metric = metrics_[k];
  const Track& track = tracks_[k];
  Measurement out;
  // how far the signal moves: half its range (the amplitude of a swing), or for a state the
  // largest distance from the start; independent of the coordinate's offset, so a pendulum
  // swinging about q = 100 is judged like one swinging about 0; a signal that does not move
  // falls back to its magnitude
  double moved =
      metric.kind == MetricKind::kStateAt ? track.excursion : 0.5 * (track.high - track.low);
  out.scale = std::max(moved > 0 ? moved : track.maxabs, 1e-300);
  switch (metric.kind) {
    case MetricKind::kValueAt:
      out.value = track.value;
      break;
    case MetricKind::kMaxAbs:
      out.value = track.maxabs;
      break;
    case MetricKind::kStateAt: {
      out.state = track.last;
      double norm = 0;
      for (double v : out.state) norm += v * v;
      out.value = std::sqrt(norm);
      break;
    }
    case MetricKind::kPeriod: {
      // oscillation about the signal's mid-range
      std::optional<double> period;
      if (!track.x.empty()) {
        auto [lo, hi] = std::minmax_element(track.x.begin(), track.x.end());
        period = PeriodFromCrossings(track.t, track.x, 0.5 * (*lo + *hi));
      }
      if (!period) {
        out.ok = false;
        out.value = kNaN;
        out.problem = "'" + metric.path.text +
                      "' crossed its mid-range upward fewer than twice in " + FormatNumber(until) +
                      " s; run longer or it does not oscillate";
        return out;
      }
      out.value = *period;
      out.scale = *period;
      break;
    }
    case MetricKind::kEnergyDrift: {
      double scale = track.max_kinetic > 0 ? track.max_kinetic : std::max(std::fabs(track.e0), 1.0);
      out.value = (track.e1 - track.e0) / scale;
      out.scale = 1;
      break;
    }
  }
  return out;
}

}  // namespace plumb::internal
