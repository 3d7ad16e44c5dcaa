// What the front ends of the batch commands share (include/plumb/batch.h).

#include "plumb/batch.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <utility>

#include "batch/no_effect.h"
#include "core/strings.h"
#include "io/hash.h"
#include "plumb/error.h"
#include "plumb/stored_run.h"
#include "plumb/version.h"

namespace plumb {
namespace {

using Json = nlohmann::ordered_json;

// A number, or null for NaN (a metric that was not measured).
Json NumberOrNull(double value) { return std::isnan(value) ? Json(nullptr) : Json(value); }

// The metrics' texts, as typed.
std::vector<std::string> MetricTexts(const std::vector<Metric>& metrics) {
  std::vector<std::string> out;
  for (const Metric& m : metrics) out.push_back(m.text);
  return out;
}
}  // namespace

std::string StartConfig(const Model& model, const StartSpec& start) {
  std::string config = StartStateConfig(model);
  if (!start.keyframe.empty()) config += " keyframe=" + start.keyframe;
  if (!start.pose.empty() || !start.qpos.empty()) {
    StartSpec pose;
    pose.pose = start.pose;
    pose.qpos = start.qpos;
    for (const Assignment& a : StartAssignments(model, pose)) {
      config += " pose=" + a.path.text + "=";
      for (std::size_t i = 0; i < a.values.size(); ++i) {
        config += fmt::format("{}{:.17g}", i ? "," : "", a.values[i]);
      }
    }
  }
  for (const std::string& s : start.sets) config += " set=" + s;
  return config;
}

std::string RolloutConfig(const RolloutSpec& spec, const std::string& model_hash,
                          const std::string& start) {
  std::string config = fmt::format(
      "rollout model={} count={} until={:.17g} seed={} "
      "ctrl_noise={:.17g} plumb={} mujoco={}",
      model_hash, spec.count, spec.until, spec.seed, spec.ctrl_noise, PLUMB_VERSION,
      MujocoVersion());
  config += start;
  for (const Randomization& r : spec.randomize) config += " randomize=" + r.text;
  for (const Metric& m : spec.metrics) config += " metric=" + m.text;
  return config;
}

std::string SweepConfig(const SweepSpec& spec, const std::string& model_hash,
                        const std::string& start) {
  std::string config = fmt::format("sweep model={} until={:.17g} plumb={} mujoco={}", model_hash,
                                   spec.until, PLUMB_VERSION, MujocoVersion());
  config += start;
  for (const SweepAxis& a : spec.axes) config += " vary=" + a.text;
  for (const Metric& m : spec.metrics) config += " metric=" + m.text;
  return config;
}

RunInfo RolloutRunInfo(const Model& model, const RolloutSpec& spec, const BatchOrigin& origin,
                       const std::string& db) {
  std::string model_hash = db.empty() ? std::string() : internal::HashModel(model);
  RunInfo info = NewRunInfo("rollout", RolloutConfig(spec, model_hash, origin.start),
                            origin.command, origin.model_file, model_hash);
  info.parameters = ParameterNames(spec);
  info.metrics = MetricTexts(spec.metrics);
  info.count = spec.count;
  return info;
}

RunInfo SweepRunInfo(const Model& model, const SweepSpec& spec, const BatchOrigin& origin,
                     const std::string& db) {
  std::string model_hash = db.empty() ? std::string() : internal::HashModel(model);
  RunInfo info = NewRunInfo("sweep", SweepConfig(spec, model_hash, origin.start), origin.command,
                            origin.model_file, model_hash);
  info.parameters = AxisNames(spec);
  info.metrics = MetricTexts(spec.metrics);
  info.count = CaseCount(spec.axes);
  return info;
}

void ParseShard(std::string_view text, RolloutSpec* spec) {
  std::vector<std::string> parts = internal::Split(std::string(text), '/');
  std::optional<long> i = parts.size() == 2 ? internal::ParseIndex(parts[0]) : std::nullopt;
  std::optional<long> n = parts.size() == 2 ? internal::ParseIndex(parts[1]) : std::nullopt;
  if (!i || !n || *n < 1 || *i >= *n) {
    throw ArgumentError("shard", Quoted(std::string(text)),
                        "expected I/N with 0 <= I < N, e.g. 0/4.");
  }
  spec->shard_index = *i;
  spec->shard_count = *n;
}

std::vector<std::string> AxisNames(const SweepSpec& spec) {
  std::vector<std::string> out;
  for (const SweepAxis& a : spec.axes) out.push_back(a.path.text);
  return out;
}

RolloutResult SweepCaseResult(const SweepSpec& spec, const SweepCase& c) {
  RolloutResult r;
  r.index = c.index;
  for (std::size_t a = 0; a < spec.axes.size(); ++a) {
    r.params.push_back(spec.axes[a].Value(c.choice[a]).values[0]);
  }
  for (const Measurement& m : c.metrics) {
    r.metrics.push_back(m.ok ? m.value : NAN);
    if (!m.ok) {
      r.diverged = r.diverged || m.diverged;
      r.problem += (r.problem.empty() ? "" : "; ") + m.problem;
    }
  }
  return r;
}

RolloutJson::RolloutJson(std::vector<std::string> parameters, std::vector<std::string> metrics)
    : parameters_(std::move(parameters)), metrics_(std::move(metrics)) {}

std::string RolloutJson::Begin() const { return "[\n"; }

std::string RolloutJson::Row(const RolloutResult& r) {
  Json row;
  row["rollout"] = r.index;
  Json p = Json::object(), m = Json::object();
  for (std::size_t k = 0; k < r.params.size(); ++k) p[parameters_[k]] = r.params[k];
  for (std::size_t k = 0; k < r.metrics.size(); ++k) m[metrics_[k]] = NumberOrNull(r.metrics[k]);
  row["params"] = p;
  row["metrics"] = m;
  row["diverged"] = r.diverged;
  if (r.diverged) row["diverged_time"] = r.diverged_time;
  if (!r.problem.empty()) row["problem"] = r.problem;
  return (rows_++ ? ",\n  " : "  ") + row.dump();
}

std::string RolloutJson::End() const { return "\n]\n"; }

SweepJson::SweepJson(std::string model_file, std::vector<std::string> axes,
                     std::vector<std::string> metrics)
    : model_file_(std::move(model_file)), axes_(std::move(axes)), metrics_(std::move(metrics)) {}

std::string SweepJson::Begin() const {
  return "{\n  \"model\": " + Json(model_file_).dump() + ",\n  \"vary\": " + Json(axes_).dump() +
         ",\n  \"metrics\": " + Json(metrics_).dump() + ",\n  \"cases\": [";
}

std::string SweepJson::Row(long index, const std::vector<double>& values,
                           const std::vector<Measurement>& metrics) {
  Json by_axis, by_metric, problems = Json::object();
  for (std::size_t a = 0; a < values.size(); ++a) by_axis[axes_[a]] = values[a];
  for (std::size_t m = 0; m < metrics.size(); ++m) {
    const Measurement& r = metrics[m];
    by_metric[metrics_[m]] = r.ok ? Json(r.value) : Json(nullptr);
    if (!r.ok) problems[metrics_[m]] = r.problem;
  }
  Json row = {{"case", index}, {"values", by_axis}, {"metrics", by_metric}};
  if (!problems.empty()) row["problems"] = problems;
  return std::string(rows_++ ? ",\n    " : "\n    ") + row.dump();
}

std::string SweepJson::End() const { return std::string(rows_ ? "\n  " : "") + "]\n}\n"; }

SweepEffects::SweepEffects(const SweepSpec& spec, const Model* model)
    : spec_(spec), model_(model), lines_(spec.axes.size()) {}

void SweepEffects::See(const RolloutResult& row) {
  std::vector<std::size_t> choice = CaseChoice(spec_.axes, row.index);
  for (std::size_t a = 0; a < spec_.axes.size(); ++a) {
    if (spec_.axes[a].size() > kMostWatched) continue;
    bool on_line = true;
    for (std::size_t b = 0; b < choice.size(); ++b) on_line = on_line && (b == a || choice[b] == 0);
    if (on_line) lines_[a][choice[a]] = row.metrics;
  }
}

std::vector<std::string> SweepEffects::Notes() const {
  std::vector<std::string> notes;
  for (std::size_t a = 0; a < spec_.axes.size(); ++a) {
    const SweepAxis& axis = spec_.axes[a];
    if (axis.size() < 2 || lines_[a].size() != axis.size()) continue;
    // values grouped by their results (NaN, not measured, is no evidence either way)
    std::map<std::string, std::vector<std::size_t>> groups;
    for (const auto& [choice, values] : lines_[a]) {
      bool measured =
          std::none_of(values.begin(), values.end(), [](double v) { return std::isnan(v); });
      if (!measured) continue;
      std::string key(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double));
      groups[key].push_back(choice);
    }
    std::vector<std::string> same;
    for (const auto& [key, choices] : groups) {
      if (choices.size() < 2) continue;
      std::vector<std::string> labels;
      for (std::size_t c : choices) labels.push_back(axis.Label(c));
      same.push_back(fmt::format("{}", fmt::join(labels, ", ")));
    }
    if (same.empty()) continue;
    std::string what =
        groups.size() == 1 && same.size() == 1 && lines_[a].size() == groups.begin()->second.size()
            ? "changed no metric: every value gave bit-identical results"
            : "values that gave bit-identical results: " + fmt::format("{}", fmt::join(same, "; "));
    notes.push_back("vary '" + axis.text + "' " + what +
                    " (the other axes at their first value). " +
                    internal::WhyNoEffect(model_, {axis.path}));
  }
  return notes;
}
RolloutEffects::RolloutEffects(const RolloutSpec& spec, const Model* model)
    : spec_(spec), model_(model) {}

void RolloutEffects::See(const RolloutResult& row) {
  if (std::any_of(row.metrics.begin(), row.metrics.end(), [](double v) { return std::isnan(v); })) {
    return;  // not measured: no evidence either way
  }
  if (measured_++ == 0) {
    first_ = row.metrics;
  } else if (row.metrics != first_) {
    differ_ = true;
  }
}

std::vector<std::string> RolloutEffects::Notes() const {
  std::vector<std::string> notes;
  if (differ_ || measured_ < 2 || first_.empty()) return notes;
  for (const Randomization& r : spec_.randomize) {
    notes.push_back(fmt::format("randomize '{}' changed no metric: all {} measured rollouts gave "
                                "bit-identical results. {}",
                                r.text, measured_, internal::WhyNoEffect(model_, r.paths)));
  }
  return notes;
}

std::vector<std::string> RolloutEffects::Finish(Notices* notices) const {
  std::vector<std::string> notes = Notes();
  for (const std::string& note : notes) {
    AddTo(notices, {NoticeLevel::kNote, NoticeTopic::kBatch, "", note});
  }
  return notes;
}

void BatchSummary::Add(

    const RolloutResult& r) {
  diverged += r.diverged;
  for (std::size_t k = 0; k < r.metrics.size() && k < metrics.size(); ++k) {
    metrics[k].Add(r.metrics[k]);
  }
}

std::string BatchSummary::Text(const std::vector<std::string>& names, const std::string& unit,
                               double seconds) const {
  long all = run_now + resumed;
  std::string summary = fmt::format(
      "\n{} {}{}, {} diverged ({:.1f}%), {:.1f} {}/s\n", all, unit,
      resumed ? fmt::format(" ({} stored before it resumed, {} run now)", resumed, run_now) : "",
      diverged, all ? 100.0 * diverged / all : 0.0, seconds > 0 ? run_now / seconds : 0.0, unit);
  for (std::size_t k = 0; k < metrics.size(); ++k) {
    const SummaryStatistics& s = metrics[k];
    if (s.count() == 0) {
      // no value to summarise: no mean, and no +-inf from empty minima and maxima
      summary += fmt::format("{}: n 0, no value measured ({} missing)\n", names[k], s.missing());
      continue;
    }
    summary += fmt::format(
        "{}: n {} mean {:.6g} std {:.6g} min {:.6g} q05 {:.6g} median {:.6g} q95 {:.6g} max "
        "{:.6g}{}\n",
        names[k], s.count(), s.mean(), s.stddev(), s.min(), s.q05(), s.q50(), s.q95(), s.max(),
        s.missing() ? fmt::format(" ({} not measured)", s.missing()) : "");
  }
  return summary;
}

}  // namespace plumb
