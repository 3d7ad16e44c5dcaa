// plumb.replay and plumb.identify: a log replayed on the model, and the model's parameters
// fitted to logs, with the CLI's JSON, tables and reports.

#include <fmt/format.h>

#include <cmath>

#include "common.h"
#include "plumb/error.h"
#include "plumb/identify_job.h"
#include "plumb/replay.h"
#include "plumb/report.h"
#include "plumb/result_json.h"
#include "plumb/result_table.h"
#include "plumb/robot_log.h"

PLUMB_PYTHON_ARG(LogsArg, "str | os.PathLike[str] | collections.abc.Sequence[str | os.PathLike[str]]")

namespace plumb::python {
namespace {

// The model a replay or a fit runs: the caller's start's parameters written into a copy (the
// state and inputs come from the logs).
std::shared_ptr<Model> ParameterModel(const PyModel& model, const std::vector<std::string>& sets) {
  std::vector<std::string> texts = model.SetTexts(sets);
  std::vector<Assignment> edits;
  for (const std::string& text : texts) edits.push_back(ParseAssignment(model.model(), text));
  std::shared_ptr<Model> out = model.EditableFor(edits);
  if (!texts.empty()) ApplyParameterAssignments(*out, texts);
  return out;
}

// plumb.ReplayResult
struct PyReplay {
  std::shared_ptr<PyModel> model;
  std::shared_ptr<Model> ran;
  RobotLog log;
  ReplayOptions options;
  ReplayResult result;
  std::vector<Notice> notices;  // what the call said (plumb.Notice): a cut log, ...
  std::string html;
  std::string Json() const { return ReplayToJson(model->name(), log, options, result); }
  std::string Table() const { return ReplayTable(model->name(), log, options, result); }
  void WriteReport(const std::string& path) const {
    WriteReplayReport(path, *ran, log, result, options, PythonReportInfo("replay"));
  }
};

// What save_report must not replace: the model and the log (common.h).
std::vector<internal::NamedPath> ResultInputs(const PyReplay& r) {
  return {{"the model", r.model->name()}, {"the log", r.log.source}};
}

void BindReplay(nb::module_& m) {
  nb::class_<PyReplay> type(m, "ReplayResult",
                            "plumb.replay's result: per measured signal its fit, rms and largest "
                            "error as arrays, the simulated values, and the CLI's JSON, table and "
                            "report.");
  type.def_prop_ro(
          "fit", [](const PyReplay& r) { return r.result.fit; },
          "%: the signals pooled in units of their noise, the error beyond it (100: the log up "
          "to its noise); no nearly flat signal can sink it (fits_beyond_noise per signal)")
      .def_prop_ro(
          "columns",
          [](const PyReplay& r) {
            std::vector<std::string> out;
            for (const SignalFit& f : r.result.signals) out.push_back(f.column);
            return out;
          },
          "the measured signals, as the log names them")
      .def_prop_ro(
          "fits", [](const PyReplay& r) { return FieldArray(r.result.signals, &SignalFit::fit); },
          "% per signal, 100 (1 - rms / spread)")
      .def_prop_ro(
          "fits_beyond_noise",
          [](const PyReplay& r) {
            return FieldArray(r.result.signals, &SignalFit::fit_beyond_noise);
          },
          "% per signal, judged against its noise: the error beyond the noise over the spread")
      .def_prop_ro(
          "rms", [](const PyReplay& r) { return FieldArray(r.result.signals, &SignalFit::rms); },
          "rms of simulated - logged, per signal")
      .def_prop_ro(
          "max_abs",
          [](const PyReplay& r) { return FieldArray(r.result.signals, &SignalFit::max_abs); })
      .def_prop_ro(
          "noise",
          [](const PyReplay& r) { return FieldArray(r.result.signals, &SignalFit::noise); },
          "each signal's noise as the log's differences show it")
      .def_prop_ro(
          "simulated",
          [](const PyReplay& r) {
            nb::list out;
            for (const auto& values : r.result.simulated.values) out.append(Array(values));
            return out;
          },
          "per signal, the simulation at the log's sample times (NaN after a divergence)")
      .def_prop_ro(
          "times",
          [](const PyReplay& r) {
            nb::list out;
            for (const LogSignal& s : r.log.measured) out.append(Array(s.time));
            return out;
          },
          "per signal, the log's sample times (s)")
      .def_prop_ro(
          "logged",
          [](const PyReplay& r) {
            nb::list out;
            for (const LogSignal& s : r.log.measured) out.append(Array(s.value));
            return out;
          },
          "per signal, the logged values")
      .def_prop_ro("diverged", [](const PyReplay& r) { return r.result.simulated.diverged; })
      .def_prop_ro("notes", [](const PyReplay& r) { return r.result.notes; })
      .def(
          "to_pandas",
          [](const PyReplay& r) {
            DataFrame(
                std::vector<std::pair<std::string, nb::object>>{});  // ImportError without pandas
            return nb::module_::import_("pandas").attr("DataFrame")(FromJson(r.Json())["signals"]);
          },
          "the signals' table as a pandas.DataFrame");
  AddResultMethods(type, "replay");

  m.def(
      "replay",
      [](ModelArg model, FileArg log, std::optional<FileArg> columns, double window,
         double input_delay, double sensor_delay, SetArg set) {
        auto r = std::make_shared<PyReplay>();
        CallNotices notices;
        r->model = ToModel(model, notices.sink());
        std::string file = PathArg(log, "log");
        std::string column_map = OptionalPathArg(columns, "columns");
        std::vector<std::string> sets = SetTexts(set);
        r->options.window = window;
        r->options.input_delay = input_delay;
        r->options.sensor_delay = sensor_delay;
        CheckReplayOptions(r->options);
        RunLong([&](StopToken stop) {
          r->ran = ParameterModel(*r->model, sets);
          r->log = std::move(LoadRobotLogs(*r->ran, {file}, column_map, notices.sink()).front());
          ReplayOptions options = r->options;
          options.stop = stop;
          r->result = Replay(*r->ran, r->log, options);
          TakeMujocoWarnings();
          return 0;
        });
        notices.Issue();
        r->notices = notices.all();
        return r;
      },
      nb::arg("model"), nb::arg("log"), nb::arg("columns") = nb::none(),
      nb::arg("window") = ReplayOptions{}.window,
      nb::arg("input_delay") = ReplayOptions{}.input_delay,
      nb::arg("sensor_delay") = ReplayOptions{}.sensor_delay, nb::arg("set") = nb::none(),
      "Drives the model with a log's inputs from its logged start state and compares what it "
      "measured (plumb replay). `log`: a CSV of time and plumb paths; `columns`: a column map "
      "(TOML); `window`: restart from the logged state every so many seconds; `set`: model "
      "parameters only. Returns a ReplayResult.");
}

// plumb.IdentifyResult
struct PyIdentify {
  std::shared_ptr<PyModel> model;
  std::shared_ptr<Model> ran;
  IdentifyJobResult job;
  std::vector<Notice> notices;  // what the call said (plumb.Notice): a cut log, ...
  std::string html;

  std::string Json() const {
    return IdentifyToJson(model->name(), job.fit, job.logs, job.delay, job.HeldOut());
  }
  std::string Table() const {
    return IdentifyTable(model->name(), job.fit, job.logs, job.delay, job.HeldOut());
  }
  void WriteReport(const std::string& path) const {
    WriteIdentifyReport(path, *ran, job.logs, job.fit, PythonReportInfo("identify"), job.HeldOut());
  }
};

nb::object SquareMatrix(const std::vector<std::vector<double>>& rows) {
  std::vector<double> flat;
  for (const auto& row : rows) flat.insert(flat.end(), row.begin(), row.end());
  return Matrix(std::move(flat), rows.size(), rows.size());
}

// What save_report and save_model must not replace: the model and every log (common.h).
std::vector<internal::NamedPath> ResultInputs(const PyIdentify& r) {
  std::vector<internal::NamedPath> inputs = {{"the model", r.model->name()}};
  for (const RobotLog& log : r.job.logs) inputs.push_back({"the log", log.source});
  for (const RobotLog& log : r.job.validation) inputs.push_back({"the validate log", log.source});
  return inputs;
}

void BindIdentifyCall(nb::module_& m) {
  nb::class_<PyIdentify> type(
      m, "IdentifyResult",
      "plumb.identify's result: .paths and, as arrays in that order, .values, "
      ".nominal, .std_errors, .lo, .hi, .correlation and .covariance; the "
      "fitted model (.fitted, a plumb.Model), the warnings, and the CLI's "
      "JSON, table and report.");
  type.def_prop_ro("paths",
                   [](const PyIdentify& r) {
                     std::vector<std::string> out;
                     for (const Estimate& e : r.job.fit.estimates) out.push_back(e.path);
                     return out;
                   })
      .def_prop_ro(
          "values",
          [](const PyIdentify& r) { return FieldArray(r.job.fit.estimates, &Estimate::value); },
          "the estimates, in the parameters' units")
      .def_prop_ro(
          "nominal",
          [](const PyIdentify& r) { return FieldArray(r.job.fit.estimates, &Estimate::nominal); })
      .def_prop_ro(
          "std_errors",
          [](const PyIdentify& r) { return FieldArray(r.job.fit.estimates, &Estimate::std_error); },
          "the standard errors given (std_error_kind says which; NaN when withheld)")
      .def_prop_ro(
          "lo", [](const PyIdentify& r) { return FieldArray(r.job.fit.estimates, &Estimate::lo); })
      .def_prop_ro(
          "hi", [](const PyIdentify& r) { return FieldArray(r.job.fit.estimates, &Estimate::hi); })
      .def_prop_ro(
          "std_error_kind",
          [](const PyIdentify& r) {
            return std::string(StdErrorKindName(r.job.fit.std_errors.kind));
          },
          "'classical', 'newey-west' or 'withheld'")
      .def_prop_ro(
          "correlation", [](const PyIdentify& r) { return SquareMatrix(r.job.fit.correlation); },
          "of the classical covariance, parameters x parameters")
      .def_prop_ro(
          "covariance",
          [](const PyIdentify& r) { return SquareMatrix(ClassicalCovariance(r.job.fit)); },
          "the classical covariance of the estimates (ClassicalCovariance)")
      .def_prop_ro("singular_values",
                   [](const PyIdentify& r) { return Array(r.job.fit.singular_values); })
      .def_prop_ro("warnings", [](const PyIdentify& r) { return r.job.fit.warnings; })
      .def_prop_ro("converged", [](const PyIdentify& r) { return r.job.fit.converged; })
      .def_prop_ro("iterations", [](const PyIdentify& r) { return r.job.fit.iterations; })
      .def_prop_ro("residual_variance",
                   [](const PyIdentify& r) { return r.job.fit.residual_variance; })
      .def_prop_ro(
          "delay", [](const PyIdentify& r) { return r.job.fit.delay; }, "s")
      .def_prop_ro(
          "fits_before",
          [](const PyIdentify& r) {
            std::vector<double> out;
            for (const ReplayResult& b : r.job.fit.before) out.push_back(b.fit);
            return Array(out);
          },
          "% per log, the nominal model")
      .def_prop_ro(
          "fits_after",
          [](const PyIdentify& r) {
            std::vector<double> out;
            for (const ReplayResult& a : r.job.fit.after) out.push_back(a.fit);
            return Array(out);
          },
          "% per log, the fitted model")
      .def_prop_ro(
          "fitted",
          [](const PyIdentify& r) {
            return std::make_shared<PyModel>(r.job.fitted, nb::none(), "",
                                             std::vector<std::string>{});
          },
          "the model with the fitted values, a plumb.Model (a copy of its own)")
      .def(
          "save_model",
          [](const PyIdentify& r, FileArg path, std::optional<FileArg> source) {
            std::string file = PathArg(path, "path");
            std::string mjcf = OptionalPathArg(source, "source");
            std::vector<internal::NamedPath> inputs = ResultInputs(r);
            inputs.push_back({"the source", mjcf});
            internal::RefuseOutputsOntoInputs({{"path", file}}, inputs);
            RunLong([&](StopToken) {
              SaveFittedModel(r.model->model(), *r.job.fitted, r.job.fit, file, mjcf);
              return 0;
            });
          },
          nb::arg("path"), nb::arg("source") = nb::none(),
          "writes the MJCF with the fitted values (as -o FITTED.xml): the model's MJCF file, or "
          "for a mujoco.MjModel the XML MuJoCo parsed last when it is that model's; `source` "
          "names the MJCF file to write them into instead (an MjModel read from a string, or "
          "one whose meshes are files)")
      .def(
          "to_pandas",
          [](const PyIdentify& r) {
            DataFrame(
                std::vector<std::pair<std::string, nb::object>>{});  // ImportError without pandas
            return nb::module_::import_("pandas").attr("DataFrame")(
                FromJson(r.Json())["estimates"]);
          },
          "the estimates as a pandas.DataFrame");
  AddResultMethods(type, "identify");

  m.def(
      "identify",
      [](ModelArg model, LogsArg logs, StringsArg fit, StringsArg bounds,
         std::optional<FileArg> columns, double window, std::optional<std::string> delay,
         double max_delay, std::optional<FileArg> validate, int threads, int max_iterations,
         SetArg set) {
        auto r = std::make_shared<PyIdentify>();
        CallNotices notices;
        r->model = ToModel(model, notices.sink());
        std::vector<std::string> files;
        nb::handle log = logs.object;
        if (nb::isinstance<nb::str>(log) || nb::hasattr(log, "__fspath__") ||
            PyBytes_Check(log.ptr()) || !nb::hasattr(log, "__iter__")) {  // TypeError if no path
          files.push_back(PathArg(log, "log"));
        } else {
          for (nb::handle one : log) files.push_back(PathArg(one, "log"));
        }
        std::vector<std::string> sets = SetTexts(set);
        IdentifyRequest request;
        request.logs = std::move(files);
        request.columns = OptionalPathArg(columns, "columns");
        request.validate = OptionalPathArg(validate, "validate");
        IdentifyOptions& o = request.options;
        o.fit = StringList(fit, "fit");
        o.bounds = StringList(bounds, "bounds");
        o.replay.window = window;
        o.delay = ParseDelayKind(delay.value_or(""));
        o.max_delay = max_delay;
        o.threads = threads;
        o.max_iterations = max_iterations;
        RunLong([&](StopToken stop) {
          r->ran = ParameterModel(*r->model, sets);
          request.stop = stop;
          request.notices = notices.sink();
          r->job = RunIdentifyJob(*r->ran, request);
          TakeMujocoWarnings();
          return 0;
        });
        notices.Issue();
        r->notices = notices.all();
        return r;
      },
      nb::arg("model"), nb::arg("log"), nb::arg("fit"), nb::arg("bounds") = nb::none(),
      nb::arg("columns") = nb::none(), nb::arg("window") = IdentifyOptions{}.replay.window,
      nb::arg("delay") = nb::none(), nb::arg("max_delay") = IdentifyOptions{}.max_delay,
      nb::arg("validate") = nb::none(), nb::arg("threads") = IdentifyOptions{}.threads,
      nb::arg("max_iterations") = IdentifyOptions{}.max_iterations, nb::arg("set") = nb::none(),
      "Fits model parameters to logs (plumb identify): `log` one CSV or a list (each an "
      "experiment), `fit` paths ('dof_damping[hinge]', '*' rows), `bounds` 'PATH=LO:HI', "
      "`delay` 'ctrl' or 'sensor' to estimate a pure delay, `validate` a held-out log. The "
      "result is the same for any `threads`. Returns an IdentifyResult.");
}

}  // namespace

void BindIdentify(nb::module_& m) {
  BindReplay(m);
  BindIdentifyCall(m);
}

}  // namespace plumb::python
