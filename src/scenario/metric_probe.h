// The one probe that measures metrics during a run, for every command that has metrics
// (converge and sweep through plumb::Measure, rollout for each rollout): fed the state after
// each step, it reads what each metric needs, recomputing derived quantities (xpos,
// sensordata, energy) only at the steps a metric reads them.

#ifndef PLUMB_SRC_SCENARIO_METRIC_PROBE_H_
#define PLUMB_SRC_SCENARIO_METRIC_PROBE_H_

#include <vector>

#include "plumb/metric.h"
#include "plumb/model.h"
#include "plumb/run.h"

namespace plumb::internal {

class MetricProbe {
 public:
  // `metrics` must outlive the probe. With `scales`, every metric is read at every step so
  // that Result can say how far its signal moves (Measurement::scale) and give state@T's
  // vector; without, a value@T is read only at T (rollout's speed).
  MetricProbe(const Model& work, const std::vector<Metric>& metrics, bool scales);

  // The state after step `step` (0: the start); `data` is the run's data.
  void Observe(Data& data, long step);

  // Metric k measured over what was observed; ok is false (value NaN) when it cannot be
  // (a period with fewer than two upward crossings of its mid-range). `until` is the run's
  // length, for the message.
  Measurement Result(std::size_t k, double until) const;

 private:
  struct Track {
    std::vector<double> t, x;         // period: every sample
    std::vector<double> first, last;  // state@T: the start and the state at T
    double value = 0;                 // value@T, maxabs
    double low = 0, high = 0, maxabs = 0, excursion = 0;
    double e0 = 0, e1 = 0, max_kinetic = 0;  // energy_drift
    bool seen = false;
  };
  // Whether metric k reads the state after `step`.
  bool Reads(std::size_t k, long step) const;
  void Read(std::size_t k, const Data& data, long step);

  const Model& work_;
  const std::vector<Metric>& metrics_;
  bool scales_;
  double dt_;
  std::vector<long> read_step_;  // value@T and state@T: the step of T
  std::vector<Track> tracks_;
  std::vector<double> state_;  // state@T's qpos, qvel, act, reused from step to step
  DerivedRefresher refresh_;
};

}  // namespace plumb::internal

#endif  // PLUMB_SRC_SCENARIO_METRIC_PROBE_H_
