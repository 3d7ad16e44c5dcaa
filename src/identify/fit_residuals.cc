// The residual vector a fit minimises (identify/fit_residuals.h).

#include "identify/fit_residuals.h"

#include <algorithm>
#include <cmath>

#include "plumb/error.h"
#include "plumb/path.h"

namespace plumb::internal {

ParameterWriter::ParameterWriter(const Model& nominal, const std::vector<FitParameter>& params)
    : params_(params), inertia_(nominal->body_inertia, nominal->body_inertia + 3 * nominal->nbody) {
  for (const FitParameter& p : params) arrays_ = arrays_ || ChangesModelArrays(p.path);
}

void ParameterWriter::Write(WorkerPool::Worker& w, const double* x) const {
  mjModel* m = w.work.get_mutable();
  for (const FitParameter& p : params_) WriteValues(w.work, w.data, p.path, {p.nominal});
  std::copy(inertia_.begin(), inertia_.end(), m->body_inertia);
  for (std::size_t i = 0; i < params_.size(); ++i) {
    WriteValues(w.work, w.data, params_[i].path, {x[i] * params_[i].scale});
  }
  if (arrays_) mj_setConst(m, w.data.get());
}

Residuals::Residuals(const Model& nominal, const std::vector<RobotLog>& logs,
                     const std::vector<FitParameter>& params, const ReplayOptions& replay,
                     int threads, const StopToken& stop)
    : logs_(logs),
      writer_(nominal, params),
      pool_(nominal, threads),
      physical_(params.size()),
      n_(params.size()),
      replay_(replay) {
  replay_.stop = stop;  // a replay stops mid-log when asked
  // per log: its windows and each window's start offsets; the samples and their weights
  std::vector<std::size_t> windows_of, offsets_of;
  std::size_t starts = 0;
  for (const RobotLog& log : logs) {
    windows_of.push_back(WindowStarts(nominal, log, replay).size());
    offsets_of.push_back(StartOffsetsPerWindow(nominal, log));
    starts += windows_of.back() * offsets_of.back();
    weights_.emplace_back();
    for (const LogSignal& s : log.measured) {
      m_ += static_cast<long>(s.value.size());
      weights_.back().push_back(NoiseFromDifferences(s.value));
    }
  }
  fit_starts_ = starts <= kMostStartUnknowns &&
                static_cast<std::size_t>(m_) * (params.size() + starts) <= kMostJacobianEntries;
  std::size_t windows = 0;  // of the logs before this one
  for (std::size_t l = 0; l < logs.size(); ++l) {
    starts_.push_back(n_);
    if (fit_starts_) {
      n_ += windows_of[l] * offsets_of[l];
      colors_ = std::max(colors_, offsets_of[l]);
      for (std::size_t w = 0; w < windows_of[l]; ++w) {
        for (std::size_t j = 0; j < offsets_of[l]; ++j) {
          start_window_.push_back(windows + w);
          start_color_.push_back(j);
        }
      }
    }
    for (const std::vector<std::size_t>& signal : SampleWindows(nominal, logs[l], replay)) {
      for (std::size_t w : signal) row_window_.push_back(windows + w);
    }
    windows += windows_of[l];
  }
  starts_.push_back(n_);
}

std::vector<std::vector<double>> Residuals::At(const std::vector<std::vector<double>>& points) {
  std::vector<std::shared_ptr<const std::vector<double>>> errors(points.size());
  std::vector<long> todo;
  for (std::size_t k = 0; k < points.size(); ++k) {
    errors[k] = Remembered(points[k]);
    if (!errors[k]) todo.push_back(static_cast<long>(k));
  }
  runs_ += static_cast<long>(todo.size());
  std::size_t next = 0, emitted = 0;  // results come back in the order asked
  pool_.Stream<std::vector<double>>(
      std::max<std::size_t>(1, todo.size()),
      [&](std::vector<long>* chunk) {
        for (; next < todo.size(); ++next) chunk->push_back(todo[next]);
      },
      [&](WorkerPool::Worker& w, long index, std::vector<double>* e) {
        writer_.Write(w, points[index].data());
        *e = AllErrors(w, points[index]);
        return true;
      },
      [&](const std::vector<double>& e) {
        long k = todo[emitted++];
        errors[k] = std::make_shared<const std::vector<double>>(e);
        Remember(points[k], errors[k]);
      },
      stop(), [] { return Interrupted("plumb identify stopped before the fit finished"); });
  std::vector<std::vector<double>> out;
  out.reserve(points.size());
  for (const auto& e : errors) out.push_back(Weighted(*e));
  return out;
}

std::vector<std::vector<double>> Residuals::Errors(WorkerPool::Worker& w, std::size_t log,
                                                   const std::vector<double>& x) const {
  std::vector<double> offsets(x.begin() + starts_[log], x.begin() + starts_[log + 1]);
  Simulated s = Simulate(w.work, w.data, logs_[log], replay_, fit_starts_ ? &offsets : nullptr);
  std::vector<std::vector<double>> e(s.values.size());
  for (std::size_t i = 0; i < s.values.size(); ++i) {
    const std::vector<double>& logged = logs_[log].measured[i].value;
    for (std::size_t k = 0; k < logged.size(); ++k) e[i].push_back(s.values[i][k] - logged[k]);
  }
  return e;
}

std::vector<double> Residuals::AllErrors(WorkerPool::Worker& w,
                                         const std::vector<double>& x) const {
  std::vector<double> all;
  all.reserve(m_);
  for (std::size_t log = 0; log < logs_.size(); ++log) {
    for (const std::vector<double>& e : Errors(w, log, x))
      all.insert(all.end(), e.begin(), e.end());
  }
  return all;
}

std::vector<double> Residuals::Weighted(const std::vector<double>& errors) const {
  std::vector<double> r;
  r.reserve(errors.size());
  std::size_t at = 0;
  for (std::size_t log = 0; log < logs_.size(); ++log) {
    for (std::size_t i = 0; i < logs_[log].measured.size(); ++i) {
      for (std::size_t k = 0; k < logs_[log].measured[i].value.size(); ++k, ++at) {
        double scaled = errors[at] / weights_[log][i];
        r.push_back(std::isfinite(scaled) ? scaled : kDiverged);
      }
    }
  }
  return r;
}

std::shared_ptr<const std::vector<double>> Residuals::Remembered(const std::vector<double>& point) {
  for (auto it = remembered_.begin(); it != remembered_.end(); ++it) {
    if (it->first == point) {
      remembered_.splice(remembered_.begin(), remembered_, it);  // the most recent first
      return remembered_.front().second;
    }
  }
  return nullptr;
}

void Residuals::Remember(const std::vector<double>& point,
                         std::shared_ptr<const std::vector<double>> e) {
  remembered_.emplace_front(point, std::move(e));
  // two Jacobians' points, within a bound on memory
  std::size_t most =
      std::min(2 * (n_ + 1) + 2, std::max<std::size_t>(2, kRememberBytes / (sizeof(double) * m_)));
  while (remembered_.size() > most) remembered_.pop_back();
}

}  // namespace plumb::internal
