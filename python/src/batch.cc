// plumb.sweep and plumb.rollout: batches of runs on the library's worker pool, returning a
// plumb.Batch with the per-case table as numpy arrays, the summary, the CLI's JSON and the HTML
// report. A batch given db= is stored as the CLI stores it (plumb/batch.h names it the same
// way), so --resume and resume=True continue each other's runs.

#include "plumb/batch.h"
#include "plumb/batch_job.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <utility>

#include "common.h"
#include "core/worker_pool.h"
#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/report.h"
#include "plumb/rollout.h"
#include "plumb/rollout_csv.h"
#include "plumb/stored_run.h"
#include "plumb/sweep.h"
#include "plumb/timing.h"

namespace plumb::python {
namespace {

// A case's metrics that could not be measured, each with why: (metric, reason).
using Unmeasured = std::vector<std::pair<std::size_t, std::string>>;
// What a batch calls with each case as it finishes.
using Keep = std::function<void(const RolloutResult&, const Unmeasured&)>;

// The cases of a batch, column by column: a few numbers a case (a million rollouts hold tens of
// megabytes, not the hundreds their result structs would), and the rare texts by case index.
class BatchTable {
 public:
  void Resize(std::size_t parameters, std::size_t metrics) {
    nparams_ = parameters;
    nmetrics_ = metrics;
  }

  // Case `r`; for a sweep, `unmeasured` gives each metric that could not be measured its
  // reason (the JSON says it per metric).
  void Add(const RolloutResult& r, const Unmeasured& unmeasured) {
    index_.push_back(r.index);
    params_.insert(params_.end(), r.params.begin(), r.params.end());
    metrics_.insert(metrics_.end(), r.metrics.begin(), r.metrics.end());
    diverged_.push_back(r.diverged ? 1 : 0);
    diverged_time_.push_back(r.diverged ? r.diverged_time : NAN);
    if (!r.problem.empty()) problems_[r.index] = r.problem;
    for (const auto& [m, why] : unmeasured) unmeasured_[{r.index, m}] = why;
  }

  // Puts the cases in index order (a resume adds those run now after those stored).
  void SortByIndex() {
    std::vector<std::size_t> order(index_.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t x, std::size_t y) { return index_[x] < index_[y]; });
    Permute(order, 1, &index_);
    Permute(order, nparams_, &params_);
    Permute(order, nmetrics_, &metrics_);
    Permute(order, 1, &diverged_);
    Permute(order, 1, &diverged_time_);
  }

  std::size_t size() const { return index_.size(); }
  const std::vector<std::int64_t>& index() const { return index_; }
  const std::vector<double>& params() const { return params_; }
  const std::vector<double>& metrics() const { return metrics_; }
  const std::vector<std::uint8_t>& diverged() const { return diverged_; }
  const std::vector<double>& diverged_time() const { return diverged_time_; }
  const std::string& Problem(std::size_t k) const {
    static const std::string kNone;
    auto it = problems_.find(index_[k]);
    return it == problems_.end() ? kNone : it->second;
  }

  // Case `k` as the library's result row.
  RolloutResult Result(std::size_t k) const {
    RolloutResult r;
    r.index = index_[k];
    r.params.assign(params_.begin() + k * nparams_, params_.begin() + (k + 1) * nparams_);
    r.metrics.assign(metrics_.begin() + k * nmetrics_, metrics_.begin() + (k + 1) * nmetrics_);
    r.diverged = diverged_[k] != 0;
    r.diverged_time = r.diverged ? diverged_time_[k] : 0;
    r.problem = Problem(k);
    return r;
  }

  // Case `k`'s metrics as a sweep measured them: a value, or not measured and why.
  std::vector<Measurement> Measurements(std::size_t k) const {
    std::vector<Measurement> out(nmetrics_);
    for (std::size_t m = 0; m < nmetrics_; ++m) {
      out[m].value = metrics_[k * nmetrics_ + m];
      auto it = unmeasured_.find({index_[k], m});
      out[m].ok = it == unmeasured_.end();
      if (!out[m].ok) out[m].problem = it->second;
    }
    return out;
  }

 private:
  template <typename T>
  static void Permute(const std::vector<std::size_t>& order, std::size_t width,
                      std::vector<T>* column) {
    std::vector<T> sorted;
    sorted.reserve(column->size());
    for (std::size_t k : order) {
      sorted.insert(sorted.end(), column->begin() + k * width, column->begin() + (k + 1) * width);
    }
    column->swap(sorted);
  }

  std::size_t nparams_ = 0, nmetrics_ = 0;
  std::vector<std::int64_t> index_;
  std::vector<double> params_, metrics_;  // row major
  std::vector<std::uint8_t> diverged_;
  std::vector<double> diverged_time_;  // NaN for a case that did not diverge
  std::map<long, std::string> problems_;
  std::map<std::pair<long, std::size_t>, std::string> unmeasured_;  // (case, metric): why
};

// plumb.Batch: every case of a sweep or a rollout batch in index order (those a resume found
// stored and those run now) and the summary.
struct Batch {
  std::string kind;  // "rollout" or "sweep"
  std::shared_ptr<PyModel> model;
  std::vector<Assignment> sets;  // the start every case began from
  std::vector<std::string> parameters, metrics;
  double until = 0;  // s; a sweep's 0: each metric's default
  std::string db;
  BatchTable rows;
  BatchSummary summary{0};
  double seconds = 0;              // the cases run now took
  std::vector<std::string> notes;  // what changed nothing (SweepEffects, RolloutEffects)
  std::vector<Notice> said;        // what the call said (.notices), each issued as a warning
  std::string html;                // the report, made on first _repr_html_

  // The document `plumb rollout|sweep --format json` prints.
  std::string Json() const {
    std::string text;
    if (kind == "rollout") {
      RolloutJson json(parameters, metrics);
      text = json.Begin();
      for (std::size_t k = 0; k < rows.size(); ++k) text += json.Row(rows.Result(k));
      return text + json.End();
    }
    SweepJson json(model->name(), parameters, metrics);
    text = json.Begin();
    for (std::size_t k = 0; k < rows.size(); ++k) {
      RolloutResult r = rows.Result(k);
      text += json.Row(r.index, r.params, rows.Measurements(k));
    }
    return text + json.End();
  }

  // The summary plumb rollout prints after its rows (a sweep's: the same of its cases, and
  // the notes plumb sweep prints).
  std::string Table() const {
    std::string text = summary.Text(metrics, kind == "rollout" ? "rollouts" : "cases", seconds);
    for (const std::string& note : notes) text += "note: " + note + "\n";
    return text.substr(text.find_first_not_of('\n'));
  }

  // The --report page of the command.
  void WriteReport(const std::string& path) const {
    BatchCollector collector(parameters, metrics);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      RolloutResult r = rows.Result(k);
      collector.Add(r.params, r.metrics, r.diverged);
    }
    ReportInfo info = PythonReportInfo(kind.c_str());
    info.nominal_until = until > 0 ? until : 2.0;
    WriteBatchReport(path, kind, model->model(), sets, collector, info);
  }

  std::vector<std::string> Columns() const {
    if (kind == "rollout") return RolloutCsvColumns(parameters, metrics);
    std::vector<std::string> out = {"case"};
    out.insert(out.end(), parameters.begin(), parameters.end());
    out.insert(out.end(), metrics.begin(), metrics.end());
    out.insert(out.end(), {"diverged", "diverged_at", "problem"});
    return out;
  }
};

// The len x columns matrix of the cases' parameters (`metrics` false) or metrics.
nb::object RowMatrix(const Batch& b, bool metrics) {
  std::vector<double> values = metrics ? b.rows.metrics() : b.rows.params();
  return Matrix(std::move(values), b.rows.size(), metrics ? b.metrics.size() : b.parameters.size());
}

nb::object IndexArray(const Batch& b) {
  return OwnedArray(std::vector<std::int64_t>(b.rows.index()), {b.rows.index().size()});
}

nb::object DivergedArray(const Batch& b) {
  return OwnedArray(std::vector<std::uint8_t>(b.rows.diverged()), {b.rows.diverged().size()})
      .attr("astype")("bool");
}

nb::object DivergedTimes(const Batch& b) { return Array(b.rows.diverged_time()); }

nb::list Problems(const Batch& b) {
  nb::list out;
  for (std::size_t k = 0; k < b.rows.size(); ++k) out.append(nb::str(b.rows.Problem(k).c_str()));
  return out;
}

// The table's columns, each a numpy array (problem: a list of str).
std::vector<std::pair<std::string, nb::object>> TableColumns(const Batch& b) {
  std::vector<std::string> names = b.Columns();
  std::vector<std::pair<std::string, nb::object>> out;
  std::size_t k = 0;
  out.emplace_back(names[k++], IndexArray(b));
  nb::object params = RowMatrix(b, false), metrics = RowMatrix(b, true);
  for (std::size_t p = 0; p < b.parameters.size(); ++p) {
    out.emplace_back(names[k++],
                     params[nb::make_tuple(nb::slice(nb::none(), nb::none(), nb::none()), p)]);
  }
  for (std::size_t m = 0; m < b.metrics.size(); ++m) {
    out.emplace_back(names[k++],
                     metrics[nb::make_tuple(nb::slice(nb::none(), nb::none(), nb::none()), m)]);
  }
  out.emplace_back(names[k++], DivergedArray(b));
  out.emplace_back(names[k++], DivergedTimes(b));
  out.emplace_back(names[k++], Problems(b));
  return out;
}

nb::dict SummaryDict(const Batch& b) {
  nb::dict out;
  const BatchSummary& s = b.summary;
  out["count"] = s.run_now + s.resumed;
  out["diverged"] = s.diverged;
  out["resumed"] = s.resumed;
  out["run_now"] = s.run_now;
  out["seconds"] = b.seconds;
  nb::dict metrics;
  for (std::size_t k = 0; k < s.metrics.size(); ++k) {
    const SummaryStatistics& m = s.metrics[k];
    nb::dict d;
    bool any = m.count() > 0;
    d["n"] = m.count();
    d["missing"] = m.missing();
    d["mean"] = any ? m.mean() : NAN;
    d["std"] = any ? m.stddev() : NAN;
    d["min"] = any ? m.min() : NAN;
    d["q05"] = m.q05();
    d["median"] = m.q50();
    d["q95"] = m.q95();
    d["max"] = any ? m.max() : NAN;
    metrics[b.metrics[k].c_str()] = d;
  }
  out["metrics"] = metrics;
  return out;
}

// The library's argument names that differ from the Python keywords.
void RenameArgument(const ArgumentError& e) {
  if (e.argument() == "metric") throw ArgumentError("metrics", e.value(), e.problem());
  if (e.argument() == "store") throw ArgumentError("db", e.value(), e.problem());
}

// Runs `parse`, its ArgumentErrors naming the Python keywords.
template <typename Parse>
void WithKeywords(Parse&& parse) {
  try {
    parse();
  } catch (const ArgumentError& e) {
    RenameArgument(e);
    throw;
  }
}

// How the batch job's messages name Python's arguments.
BatchWords PythonWords() { return {"db", "resume=True", "call it again with resume=True", "vary"}; }

// What a batch call was given, in the CLI's vocabulary.
struct BatchArgs {
  std::shared_ptr<PyModel> model;
  // where every case starts, in the CLI's order: the keyframe (the call's, else the model's),
  // the pose file, the whole qpos, then the model's and the call's `set`
  StartSpec start;
  std::vector<std::string> metrics;
  double until = 0;
  int threads = 0;
  std::string db;
  bool resume = false;
  std::string call;  // the call as the store records its command
};

BatchArgs ReadArgs(ModelArg model, SetArg set, std::optional<NameOrId> keyframe,
                   std::optional<FileArg> pose, QposArg qpos, StringsArg metrics, int threads,
                   std::optional<FileArg> db, bool resume) {
  BatchArgs a;
  a.model = ToModel(model);
  a.start = a.model->Spec(keyframe, OptionalPathArg(pose, "pose"), QposText(qpos), SetTexts(set));
  a.metrics = StringList(metrics, "metrics");
  if (threads < 0) {
    throw ArgumentError("threads", std::to_string(threads), "must be 0 (every core) or more");
  }
  a.threads = internal::ThreadsOrAllCores(threads);
  a.db = OptionalPathArg(db, "db");
  internal::RefuseOutputsOntoInputs(
      {{"db", a.db}}, {{"the model", a.model->name()}, {"the pose file", a.start.pose}});
  a.resume = resume;
  return a;
}

BatchOrigin Origin(const BatchArgs& a) {
  const Model& model = a.model->model();
  return {a.model->name(), {a.call}, StartConfig(model, a.start)};
}

// Runs a batch into `batch` as the library's job (plumb/batch_job.h) with its store (`info` in
// a.db), saying what it says to `notices`: first the cases of `shard_total` the store holds
// that are `mine` (`unmeasured` gives each one's unmeasured metrics), then `run(done, keep)`
// runs the rest, calling keep with each case as it finishes, which stores it. On a stop
// (Ctrl-C: the caller raises KeyboardInterrupt with the job's message) what finished is
// committed to the store; at the end the run is marked complete when it holds every case.
template <typename Run>
void RunBatch(Batch& batch, const BatchArgs& a, const RunInfo& info, Notices* notices,
              long shard_total, const std::function<bool(const RolloutResult&)>& mine,
              const std::function<Unmeasured(const RolloutResult&)>& unmeasured, Run&& run) {
  batch.rows.Resize(batch.parameters.size(), batch.metrics.size());
  std::optional<BatchJob> job;
  WithKeywords([&] { job.emplace(a.db, a.resume, info, PythonWords(), notices); });
  job->Resume(shard_total, mine,
              [&](const RolloutResult& r) { batch.rows.Add(r, unmeasured(r)); });
  job->Run([&] {
    run(job->done(), Keep([&](const RolloutResult& r, const Unmeasured& u) {
          job->Add(r);
          batch.rows.Add(r, u);
        }));
  });
  job->Complete(info.count);
  batch.summary = job->summary();
  batch.seconds = job->seconds();
  // the cases a resume found stored come first: index order
  if (batch.summary.resumed > 0) batch.rows.SortByIndex();
}

// Refuses, before any run, a batch whose `rows` (each kept in the Batch: index, parameters,
// metrics, divergence) this machine's memory cannot hold; `argument` = `value` asked for them.
void RequireRowsFit(long rows, std::size_t params, std::size_t metrics, const char* argument,
                    const std::string& value) {
  double bytes = static_cast<double>(rows) * (17.0 + 8.0 * static_cast<double>(params + metrics));
  RequireMemoryFor(bytes, fmt::format("the rows of {} cases", rows), argument, value);
}

// An empty batch of `kind` for the call `a`.
std::shared_ptr<Batch> NewBatch(const char* kind, const BatchArgs& a) {
  auto batch = std::make_shared<Batch>();
  batch->kind = kind;
  batch->model = a.model;
  batch->metrics = a.metrics;
  batch->until = a.until;
  batch->db = a.db;
  return batch;
}

std::shared_ptr<Batch> RunRollout(const BatchArgs& a, long count,
                                  const std::vector<std::string>& randomize, double ctrl_noise,
                                  std::uint64_t seed, const std::string& shard, Notices* notices) {
  std::shared_ptr<Batch> batch = NewBatch("rollout", a);
  RunLong([&](StopToken stop) {
    const Model& model = a.model->model();
    RolloutSpec spec;
    WithKeywords([&] {
      RolloutSpec given;
      given.sets = StartAssignments(model, a.start);
      given.count = count;
      given.until = a.until;
      given.threads = a.threads;
      given.seed = seed;
      given.ctrl_noise = ctrl_noise;
      spec = ParseRolloutSpec(model, given, {randomize, {}, a.metrics, shard}, notices);
      RequireRowsFit(ShardSize(spec), ParameterNames(spec).size(), spec.metrics.size(), "count",
                     std::to_string(count));
    });
    batch->sets = spec.sets;
    batch->parameters = ParameterNames(spec);
    RolloutEffects effects(spec, &model);  // a randomization that changed nothing gets a note
    RunBatch(
        *batch, a, RolloutRunInfo(model, spec, Origin(a), a.db), notices, ShardSize(spec),
        InShard(spec),
        [&](const RolloutResult& r) {
          effects.See(r);
          return Unmeasured{};
        },
        [&](const std::vector<long>& done, const Keep& keep) {
          spec.skip = done;
          Rollout(
              model, spec,
              [&](const RolloutResult& r) {
                effects.See(r);
                keep(r, {});
              },
              stop);
        });
    batch->notes = effects.Finish(notices);
    return 0;
  });
  return batch;
}

std::shared_ptr<Batch> RunSweep(const BatchArgs& a, const std::vector<std::string>& vary,
                                Notices* notices) {
  std::shared_ptr<Batch> batch = NewBatch("sweep", a);
  RunLong([&](StopToken stop) {
    const Model& model = a.model->model();
    SweepSpec spec;
    WithKeywords([&] {
      SweepSpec given;
      given.sets = StartAssignments(model, a.start);
      given.threads = a.threads;
      given.until = a.until;
      spec = ParseSweepSpec(model, given, {{}, vary, a.metrics, ""}, PythonWords(), notices);
      RequireRowsFit(CaseCount(spec.axes), AxisNames(spec).size(), spec.metrics.size(), "vary", "");
    });
    batch->sets = spec.sets;
    batch->parameters = AxisNames(spec);
    SweepNotices said(spec, notices, &model);
    RunBatch(
        *batch, a, SweepRunInfo(model, spec, Origin(a), a.db), notices, CaseCount(spec.axes),
        [](const RolloutResult&) { return true; },
        [&](const RolloutResult& r) {
          said.SeeStored(r);
          // a stored case keeps its metrics and its reasons joined (the store's one problem)
          Unmeasured unmeasured;
          for (std::size_t m = 0; m < r.metrics.size(); ++m) {
            if (std::isnan(r.metrics[m])) unmeasured.emplace_back(m, r.problem);
          }
          return unmeasured;
        },
        [&](const std::vector<long>& done, const Keep& keep) {
          Sweep(
              model, spec, done,
              [&](const SweepCase& c) {
                Unmeasured unmeasured;
                for (std::size_t m = 0; m < c.metrics.size(); ++m) {
                  if (!c.metrics[m].ok) unmeasured.emplace_back(m, c.metrics[m].problem);
                }
                RolloutResult row = SweepCaseResult(spec, c);
                said.See(c, row);
                keep(row, unmeasured);
              },
              stop);
        });
    batch->notes = said.Finish();
    return 0;
  });
  return batch;
}

void BindBatchType(nb::module_& m) {
  nb::class_<Batch> type(
      m, "Batch",
      "The result of plumb.rollout and plumb.sweep: every case in index order (a "
      "resumed batch: those stored before and those run now) as numpy arrays "
      "(index, params, metrics, diverged, ...; to_pandas() for a DataFrame), the "
      "summary the CLI prints (repr, .summary), the CLI's JSON (to_json, to_dict) "
      "and its HTML report (_repr_html_ shows it in a notebook).");
  type.def_ro("kind", &Batch::kind, "'rollout' or 'sweep'")
      .def_prop_ro("model", [](const Batch& b) { return b.model->name(); })
      .def_ro("parameters", &Batch::parameters,
              "the parameter names: a rollout's drawn parameters (one per element a "
              "randomization matched), a sweep's axes")
      .def_ro("metric_names", &Batch::metrics, "the metrics, as given")
      .def_prop_ro(
          "db", [](const Batch& b) { return b.db.empty() ? std::optional<std::string>() : b.db; },
          "the results store file, or None")
      .def_prop_ro("columns", &Batch::Columns,
                   "the table's column names: rollout (or case), the parameters, the metrics, "
                   "diverged, diverged_at, problem")
      .def("__len__", [](const Batch& b) { return b.rows.size(); })
      .def_prop_ro("index", &IndexArray, "the cases' indices (int64, length len(batch))")
      .def_prop_ro(
          "params", [](const Batch& b) { return RowMatrix(b, false); },
          "the parameter values, len(batch) x len(parameters) (float64)")
      .def_prop_ro(
          "metrics", [](const Batch& b) { return RowMatrix(b, true); },
          "the metric values, len(batch) x len(metric_names) (float64, NaN where not "
          "measured)")
      .def_prop_ro("diverged", &DivergedArray, "whether each case diverged (bool)")
      .def_prop_ro("diverged_at", &DivergedTimes,
                   "when each diverged case diverged (s; NaN for those that did not)")
      .def_prop_ro("problems", &Problems, "why each case's metrics are missing ('' when none)")
      .def(
          "column",
          [](const Batch& b, const std::string& name) {
            for (auto& [column, values] : TableColumns(b)) {
              if (column == name) return values;
            }
            throw ArgumentError("name", Quoted(name), "not a column of this batch (see .columns)");
          },
          nb::arg("name"), "one column of the table by its name (see .columns)")
      .def_ro("notices", &Batch::said,
              "what the call said besides its result, each also issued as a plumb.BatchWarning "
              "(or plumb.StartWarning): a list of plumb.Notice")
      .def_ro("notes", &Batch::notes,
              "a sweep's notes: each axis along which every metric came out bit-identical; a "
              "rollout's: each randomization when every rollout came out bit-identical; with "
              "the likely reason (the CLI prints them on stderr)")
      .def_prop_ro("summary", &SummaryDict,
                   "count, diverged, resumed (stored before), run_now, seconds, and per metric "
                   "n, missing, mean, std, min, q05, median, q95, max")
      .def(
          "to_pandas", [](const Batch& b) { return DataFrame(TableColumns(b)); },
          "the table as a pandas.DataFrame with .columns (pandas is imported now)");
  AddResultMethods(type, "rollout|sweep");
}

}  // namespace

void BindBatch(nb::module_& m) {
  BindBatchType(m);

  m.def(
      "rollout",
      [](ModelArg model, long count, StringsArg randomize, std::optional<double> ctrl_noise,
         StringsArg metrics, SetArg set, std::optional<NameOrId> keyframe,
         std::optional<FileArg> pose, QposArg qpos, double until, int threads, std::uint64_t seed,
         std::optional<std::string> shard, std::optional<FileArg> db, bool resume) {
        BatchArgs a = ReadArgs(model, set, keyframe, pose, qpos, metrics, threads, db, resume);
        a.until = until;
        a.call = fmt::format("plumb.rollout({}, count={}, until={}, seed={})", a.model->name(),
                             count, until, seed);
        CallNotices notices;
        std::shared_ptr<Batch> batch =
            RunRollout(a, count, StringList(randomize, "randomize"),
                       ctrl_noise.value_or(RolloutSpec{}.ctrl_noise), seed, shard.value_or(""),
                       notices.sink());
        notices.Issue();
        batch->said = notices.all();
        return batch;
      },
      nb::arg("model"), nb::arg("count"), nb::arg("randomize") = nb::none(),
      nb::arg("ctrl_noise") = RolloutSpec{}.ctrl_noise, nb::arg("metrics") = nb::none(),
      nb::kw_only(), nb::arg("set") = nb::none(), nb::arg("keyframe") = nb::none(),
      nb::arg("pose") = nb::none(), nb::arg("qpos") = nb::none(),
      nb::arg("until") = RolloutSpec{}.until, nb::arg("threads") = 0,
      nb::arg("seed") = RolloutSpec{}.seed, nb::arg("shard") = nb::none(),
      nb::arg("db") = nb::none(), nb::arg("resume") = false,
      "Runs `count` rollouts of the model (plumb rollout), each `until` s from the start (as the "
      "CLI orders them: keyframe, pose file, whole qpos, set) with parameters drawn by `randomize` "
      "('body_mass[*]=*U(0.9,1.1)'; U, N, LogU; "
      "*DIST scales, +DIST offsets the nominal value) and control noise `ctrl_noise` (a "
      "fraction of each ctrlrange), measuring `metrics` ('xpos[torso][2]@1', energy_drift, "
      "...). threads=0 uses every core; results are identical for any thread count. shard='I/N' "
      "runs the rollouts i with i % N == I. db= records them in a results store (the CLI's "
      "--db); resume=True continues the same batch there (also one the CLI began). Returns a "
      "plumb.Batch. Raises plumb.ArgumentError naming the keyword for a bad argument; "
      "KeyboardInterrupt on Ctrl-C, keeping the finished rollouts in db.");

  m.def(
      "sweep",
      [](ModelArg model, StringsArg vary, StringsArg metrics, SetArg set,
         std::optional<NameOrId> keyframe, std::optional<FileArg> pose, QposArg qpos,
         std::optional<double> until, int threads, std::optional<FileArg> db, bool resume) {
        BatchArgs a = ReadArgs(model, set, keyframe, pose, qpos, metrics, threads, db, resume);
        a.until = until.value_or(0);
        a.call = fmt::format("plumb.sweep({})", a.model->name());
        CallNotices notices;
        std::shared_ptr<Batch> batch = RunSweep(a, StringList(vary, "vary"), notices.sink());
        notices.Issue();
        batch->said = notices.all();
        return batch;
      },
      nb::arg("model"), nb::arg("vary"), nb::arg("metrics"), nb::kw_only(),
      nb::arg("set") = nb::none(), nb::arg("keyframe") = nb::none(), nb::arg("pose") = nb::none(),
      nb::arg("qpos") = nb::none(), nb::arg("until") = nb::none(), nb::arg("threads") = 0,
      nb::arg("db") = nb::none(), nb::arg("resume") = false,
      "Measures `metrics` over the Cartesian product of the `vary` axes (plumb sweep): "
      "'PATH=V1,V2,...' or 'PATH=START:STOP:COUNT', the first axis slowest, each case from the "
      "start (keyframe, pose file, whole qpos, set). until: the run length (s) of "
      "period/maxabs/energy_drift metrics "
      "(None: 20 s for period, else 2 s). threads=0 uses every core; results are identical for "
      "any thread count. db= and resume=True as in plumb.rollout. Returns a plumb.Batch; raises "
      "plumb.ArgumentError naming the keyword for a bad argument, KeyboardInterrupt on Ctrl-C.");
}

}  // namespace plumb::python
