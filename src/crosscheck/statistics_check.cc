#include "crosscheck/statistics_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "core/fields.h"
#include "core/worker_pool.h"
#include "plumb/statistics.h"
#include "plumb/timing.h"
#include "scenario/metric_probe.h"

namespace plumb::internal {
namespace {

// What CPU MuJoCo's rollout of each world started from and was driven with.
struct WorldRecord {
  nlohmann::json edits;  // where its model differs from the engine's loaded one
  std::unique_ptr<Data> start;
  std::vector<double> ctrl;  // [steps][nu]
};

// The engine's per-world values of every field some world changed.
std::vector<WorldField> VariedFields(const Model& loaded, const std::vector<WorldRecord>& worlds) {
  std::set<std::string> names;
  for (const WorldRecord& w : worlds) {
    for (const nlohmann::json& e : w.edits) names.insert(e.at(0).get<std::string>());
  }
  std::vector<WorldField> out;
  for (const std::string& name : names) {
    const std::vector<double> nominal = FieldValues(loaded, name);
    WorldField field{name, {}};
    for (const WorldRecord& w : worlds) {
      const std::size_t at = field.values.size();
      field.values.insert(field.values.end(), nominal.begin(), nominal.end());
      for (const nlohmann::json& e : w.edits) {
        if (e.at(0) == name) field.values[at + e.at(1).get<std::size_t>()] = e.at(2).get<double>();
      }
    }
    out.push_back(std::move(field));
  }
  return out;
}

// CPU MuJoCo's rollouts, recording each world's parameters, start and controls.
std::vector<std::vector<double>> CpuRollouts(const Model& nominal, const Model& loaded,
                                             const CrosscheckOptions& o,
                                             const std::vector<Metric>& metrics, long steps,
                                             std::vector<WorldRecord>* worlds) {
  RolloutSpec spec;
  spec.count = o.worlds;
  spec.until = o.until;
  spec.seed = o.seed;
  spec.threads = ThreadsOrAllCores(o.threads);
  spec.sets = o.sets;
  spec.randomize = o.randomize;
  spec.ctrl_noise = o.ctrl_noise;
  spec.metrics = metrics;
  worlds->resize(o.worlds);
  for (WorldRecord& w : *worlds) {
    w.start = std::make_unique<Data>(loaded);
    w.ctrl.assign(static_cast<std::size_t>(steps) * loaded->nu, 0);
  }
  spec.observe = [&](long index, long step, const Model& work, const mjData* d) {
    WorldRecord& w = (*worlds)[index];
    if (step == 0) {
      w.edits = ModelEdits(loaded, work);
      mj_copyData(w.start->get(), loaded.get(), d);
    } else if (step <= steps) {
      std::copy(d->ctrl, d->ctrl + work->nu, w.ctrl.begin() + (step - 1) * work->nu);
    }
  };
  std::vector<std::vector<double>> measured(o.worlds);
  ValidateRolloutSpec(nominal, spec);
  Rollout(
      nominal, spec, [&](const RolloutResult& r) { measured[r.index] = r.metrics; }, o.stop);
  return measured;
}

// The metrics of the engine's runs, measured by the probe plumb rollout uses.
std::vector<std::vector<double>> EngineMetrics(const Model& loaded, const EngineRollout& run,
                                               const std::vector<WorldRecord>& worlds,
                                               const std::vector<Metric>& metrics, double until) {
  const mjModel* m = loaded.get();
  const int count = static_cast<int>(worlds.size());
  std::vector<std::vector<double>> out(count);
  for (int w = 0; w < count; ++w) {
    Model model = loaded.Clone();
    ApplyEdits(worlds[w].edits, model);
    Data data(model);
    mj_copyData(data.get(), model.get(), worlds[w].start->get());
    MetricProbe probe(model, metrics, /*scales=*/false);
    for (long row = 0; row < run.rows; ++row) {
      mjData* d = data.get();
      const std::size_t at = static_cast<std::size_t>(row) * count + w;
      std::copy_n(run.qpos.data() + at * m->nq, m->nq, d->qpos);
      std::copy_n(run.qvel.data() + at * m->nv, m->nv, d->qvel);
      std::copy_n(run.act.data() + at * m->na, m->na, d->act);  // data(): na may be 0
      if (row > 0) std::copy_n(worlds[w].ctrl.data() + (row - 1) * m->nu, m->nu, d->ctrl);
      d->time = worlds[w].start->get()->time + row * m->opt.timestep;
      probe.Observe(data, row);
    }
    for (std::size_t k = 0; k < metrics.size(); ++k) out[w].push_back(probe.Result(k, until).value);
  }
  return out;
}

CheckRow MetricRow(const Metric& metric, const std::vector<double>& cpu,
                   const std::vector<double>& engine, const CrosscheckOptions& o) {
  SummaryStatistics spread;
  std::vector<double> differences;
  for (std::size_t w = 0; w < cpu.size(); ++w) {
    spread.Add(cpu[w]);
    differences.push_back(engine[w] - cpu[w]);
  }
  const double margin =
      std::max(o.margin * spread.stddev(), o.tol * std::max(1.0, std::abs(spread.mean())));
  const EquivalenceTest t = PairedEquivalence(differences, margin, o.alpha);
  CheckRow row;
  row.id = "statistics";
  row.section = "statistics";
  row.title = "randomized worlds: the metric's mean in the engine equals CPU MuJoCo's (TOST)";
  row.subject = metric.text;
  row.measured = {t.mean, ""};
  row.reference = {margin, ""};
  row.threshold = true;
  row.measured_text = fmt::format(
      "mean difference {:.3g}, {:.0f} % interval [{:.3g}, {:.3g}], "
      "p = {:.3g}, N = {}",
      t.mean, 100 * (1 - 2 * o.alpha), t.lower, t.upper, t.p_value, t.n);
  row.reference_text = fmt::format(
      "|difference| < {:.3g} (max({:g} x CPU spread {:.3g}, {:g} x "
      "max(1, |CPU mean|))), alpha = {:g}",
      margin, o.margin, spread.stddev(), o.tol, o.alpha);
  if (t.equivalent) {
    row.status = CheckStatus::kPass;
    row.explanation = "equivalent: both one-sided tests reject a difference beyond the margin";
  } else if (t.n >= 2 && (t.lower > margin || t.upper < -margin)) {
    row.status = CheckStatus::kFail;
    row.explanation = "the engine's mean differs from CPU MuJoCo's by more than the margin";
    row.fix = "read the stages and trajectory rows for where the physics differs";
  } else {
    row.status = CheckStatus::kWarn;
    row.explanation =
        "undecided: the interval straddles the margin; equivalence is not shown "
        "(not the same as a difference)";
    row.fix = "raise the number of worlds to narrow the interval";
  }
  return row;
}

}  // namespace

bool WorldsAreIdentical(const CrosscheckOptions& options) {
  return options.randomize.empty() && !(options.ctrl_noise > 0);
}

void JudgeIdenticalWorlds(const CrosscheckOptions& options, CheckRow* row) {
  if (!WorldsAreIdentical(options) || row->status == CheckStatus::kFail) return;
  row->status = CheckStatus::kSkip;
  row->explanation = fmt::format(
      "the {} worlds are identical (nothing randomized, no control noise): the engine met CPU "
      "MuJoCo on one world {} times, which the trajectory check already judges; the "
      "distribution is not tested",
      options.worlds, options.worlds);
  row->fix =
      "vary the worlds: randomize a field or the start per world (a distribution such as "
      "body_mass[*]=*U(0.9,1.1)), or add noise to the controls";
}

std::vector<Metric> DefaultCrosscheckMetrics(const Model& model, double until) {
  std::vector<Metric> out;
  auto add = [&](const std::string& path) {
    out.push_back(ParseMetric(model, fmt::format("{}@{:g}", path, until)));
  };
  for (int j = 0; j < model->njnt; ++j) {
    if (model->jnt_type[j] != mjJNT_FREE) continue;
    const std::string name = model.Name(mjOBJ_JOINT, j);
    const std::string ref = name.empty() ? "#" + std::to_string(j) : name;
    for (int k = 0; k < 3; ++k) add(fmt::format("qpos[{}][{}]", ref, k));
    return out;
  }
  for (int j = 0; j < model->njnt && out.size() < 4; ++j) {
    if (model->jnt_type[j] != mjJNT_HINGE && model->jnt_type[j] != mjJNT_SLIDE) continue;
    const std::string name = model.Name(mjOBJ_JOINT, j);
    add(fmt::format("qpos[{}]", name.empty() ? "#" + std::to_string(j) : name));
  }
  return out;
}

std::vector<CheckRow> StatisticsCheck(const Model& nominal, const Model& loaded,
                                      EngineSession& engine, const CrosscheckOptions& options) {
  const long steps = StepsToReach(options.until, loaded->opt.timestep);
  const std::vector<Metric> metrics =
      options.metrics.empty() ? DefaultCrosscheckMetrics(nominal, options.until) : options.metrics;
  std::vector<WorldRecord> worlds;
  const std::vector<std::vector<double>> cpu =
      CpuRollouts(nominal, loaded, options, metrics, steps, &worlds);
  std::vector<const mjData*> starts;
  std::vector<double> ctrl(static_cast<std::size_t>(steps) * worlds.size() * loaded->nu);
  for (std::size_t w = 0; w < worlds.size(); ++w) {
    starts.push_back(worlds[w].start->get());
    for (long s = 0; s < steps; ++s) {
      std::copy_n(worlds[w].ctrl.data() + s * loaded->nu, loaded->nu,
                  ctrl.data() + (s * worlds.size() + w) * loaded->nu);  // nu may be 0
    }
  }
  const EngineRollout run =
      engine.Rollout(loaded, starts, ctrl, steps, 1, VariedFields(loaded, worlds));
  const std::vector<std::vector<double>> other =
      EngineMetrics(loaded, run, worlds, metrics, options.until);
  std::vector<CheckRow> rows;
  for (const std::string& u : run.unvaried) {
    CheckRow row;
    row.id = "statistics.unvaried";
    row.section = "statistics";
    row.status = CheckStatus::kSkip;
    row.subject = u.substr(0, u.find(':'));
    row.explanation =
        "the engine cannot vary this field per world, so its worlds ran with the "
        "nominal value and the metrics below are not comparable in it: " +
        u;
    rows.push_back(row);
  }
  for (std::size_t k = 0; k < metrics.size(); ++k) {
    std::vector<double> a, b;
    for (std::size_t w = 0; w < worlds.size(); ++w) {
      a.push_back(cpu[w].size() > k ? cpu[w][k] : NAN);
      b.push_back(other[w][k]);
    }
    rows.push_back(MetricRow(metrics[k], a, b, options));
    JudgeIdenticalWorlds(options, &rows.back());
    if (!run.unvaried.empty()) {
      rows.back().status = CheckStatus::kSkip;
      rows.back().fix.clear();
      rows.back().explanation =
          "not comparable: the engine's worlds could not vary every "
          "randomized field (the statistics.unvaried rows name them)";
    }
  }
  return rows;
}

}  // namespace plumb::internal
