// plumb.verify, plumb.audit, plumb.converge, plumb.snapshot and plumb.diff: the checks, each
// returning a result with typed rows or figures, the CLI's JSON and table, and its HTML report.

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "common.h"
#include "core/file_kind.h"
#include "core/input_file.h"
#include "io/atomic_file.h"
#include "plumb/accept.h"
#include "plumb/audit.h"
#include "plumb/check_table.h"
#include "plumb/converge.h"
#include "plumb/error.h"
#include "plumb/regression.h"
#include "plumb/report.h"
#include "plumb/repro.h"
#include "plumb/result_json.h"
#include "plumb/result_table.h"
#include "plumb/scenario.h"
#include "plumb/verify.h"
#include "report/html.h"

PLUMB_PYTHON_ARG(SnapshotArg, "Snapshot | str | os.PathLike[str]")

namespace plumb::python {
namespace {

// How many of `rows` have `status` ('PASS', 'WARN', 'FAIL', 'SKIP'), accepted ones included.
int CountRows(const std::vector<CheckRow>& rows, const std::string& status) {
  for (CheckStatus s :
       {CheckStatus::kPass, CheckStatus::kWarn, CheckStatus::kFail, CheckStatus::kSkip}) {
    if (status == CheckStatusName(s)) return CountStatus(rows, s);
  }
  throw ArgumentError("status", Quoted(status), "expected PASS, WARN, FAIL or SKIP");
}

// A result's rows as a pandas.DataFrame: the JSON rows' columns.
nb::object RowsFrame(const nb::object& rows_json) { return Pandas().attr("DataFrame")(rows_json); }

// ---- verify ------------------------------------------------------------------------------

struct VerifyResult {
  std::shared_ptr<PyModel> model;
  std::vector<Assignment> sets;
  VerifyReport report;
  std::vector<Notice> notices;  // what the call said (plumb.Notice)
  std::string html, full_html;  // the light view, the whole report (each made once)

  std::string Json() const { return VerifyToJson(report); }
  std::string Table() const {
    return VerifyTable(report, TableDetail::kFindings, "result.rows holds every row");
  }
  void WriteReport(const std::string& path, ReportView view) const {
    WriteVerifyReport(path, model->model(), sets, report,
                      PythonReportInfo("verify", true, view));
  }
};

void BindVerify(nb::module_& m) {
  nb::class_<VerifyResult> type(
      m, "VerifyResult",
      "plumb.verify's result: .rows (plumb.CheckRow), .ok, the run it judged (.horizon), the "
      "CLI's JSON (to_json, to_dict) and table (repr), and the HTML report (_repr_html_ shows it "
      "in a notebook, save_report writes it).");
  type.def_prop_ro("rows", [](const VerifyResult& r) { return RowList(r.report.checks); })
      .def_prop_ro(
          "ok", [](const VerifyResult& r) { return !r.report.failed(); }, "no check FAILed")
      .def_prop_ro("model", [](const VerifyResult& r) { return r.report.model; })
      .def_prop_ro("tol", [](const VerifyResult& r) { return r.report.tol; })
      .def_prop_ro(
          "start", [](const VerifyResult& r) { return r.report.start; },
          "what every run started from: \"keyframe 'home'\", \"qpos0 with qpos[hinge]=0.7\"")
      .def_prop_ro(
          "horizon",
          [](const VerifyResult& r) {
            nb::dict d;
            d["until"] = r.report.horizon.until;
            d["requested"] = r.report.horizon.requested;
            d["steps"] = r.report.horizon.steps;
            d["why"] = r.report.horizon.why;
            return d;
          },
          "the nominal run: until and requested (s), steps, and why it is shorter")
      .def(
          "count",
          [](const VerifyResult& r, const std::string& status) {
            return CountRows(r.report.checks, status);
          },
          nb::arg("status"), "how many rows have this status ('PASS', 'WARN', 'FAIL', 'SKIP')")
      .def(
          "to_pandas",
          [](const VerifyResult& r) { return RowsFrame(FromJson(r.Json())["checks"]); },
          "the rows as a pandas.DataFrame (the JSON rows' columns)");
  AddResultMethods(type, "verify");

  m.def(
      "verify",
      [](ModelArg model, SetArg set, double tol, std::optional<double> until,
         std::optional<NameOrId> keyframe, std::optional<FileArg> pose, QposArg qpos) {
        auto result = std::make_shared<VerifyResult>();
        CallNotices notices;
        std::string pose_file = OptionalPathArg(pose, "pose");
        std::string qpos_text = QposText(qpos);  // with the GIL, before RunLong releases it
        result->model = ToModel(model, notices.sink());
        std::vector<std::string> sets = SetTexts(set);
        result->report = RunLong([&](StopToken stop) {
          const Model& work = result->model->model();
          VerifyOptions options;
          // the library starts at the reference pose; the load's and the call's sets on top
          options.keyframe = (keyframe ? keyframe->text : result->model->keyframe());
          options.sets =
              StartAssignments(work, result->model->Spec("", pose_file, qpos_text, sets),
                               notices.sink());
          options.tol = tol;
          options.until = until;
          options.stop = stop;
          result->sets = VerifyStart(work, options);  // the pose the report's pictures show
          return Verify(work, options);
        });
        notices.Issue();
        result->notices = notices.all();
        return result;
      },
      nb::arg("model"), nb::arg("set") = nb::none(), nb::arg("tol") = VerifyOptions{}.tol,
      nb::arg("until") = nb::none(), nb::arg("keyframe") = nb::none(),
      nb::arg("pose") = nb::none(), nb::arg("qpos") = nb::none(),
      "Checks that a model's numbers are credible (plumb verify): the start, determinism, "
      "warnings, convergence as the timestep shrinks, energy, and for a single hinge pendulum "
      "the analytic references and the chapter's experiments. Every run starts at `keyframe` "
      "(else the model's, else keyframe 'home', else 'test', else qpos0; result.start says "
      "which; a name or an id), then `pose` (a pose file, as --pose) and `qpos` (nq numbers, as "
      "--qpos), with `set` on top, the CLI's --set assignments ({'qpos[hinge]': 0.7}); `tol` is "
      "the relative tolerance, `until` the nominal run's length in s. Returns a VerifyResult; "
      "raises plumb.Error subclasses for bad input and KeyboardInterrupt on Ctrl-C.");
}

// ---- audit -------------------------------------------------------------------------------

struct AuditResult {
  std::shared_ptr<PyModel> model;
  std::vector<Assignment> start;  // the pose the pictures show
  AuditReport report;
  bool strict = false;
  std::vector<Notice> notices;  // what the call said (plumb.Notice)
  std::string html, full_html;  // the light view, the whole report (each made once)

  std::string Json() const { return AuditToJson(report); }
  std::string Table() const {
    return AuditTable(report, TableDetail::kFindings, "result.rows holds every row");
  }
  void WriteReport(const std::string& path, ReportView view) const {
    WriteAuditReport(path, model->model(), start, report, PythonReportInfo("audit", true, view));
  }
};

void BindAudit(nb::module_& m) {
  nb::class_<AuditResult> type(
      m, "AuditResult",
      "plumb.audit's result: .rows (one plumb.CheckRow per finding; .section is its layer), "
      ".ok, .repro_folders, the CLI's JSON and table, and the HTML report.");
  type.def_prop_ro("rows", [](const AuditResult& r) { return RowList(r.report.findings); })
      .def_prop_ro(
          "ok", [](const AuditResult& r) { return !r.report.Failed(r.strict); },
          "no unaccepted FAIL (and with strict=True no unaccepted WARN)")
      .def_prop_ro("model", [](const AuditResult& r) { return r.report.model; })
      .def_prop_ro(
          "start", [](const AuditResult& r) { return r.report.start; },
          "what the audit judged from: \"keyframe 'home'\", \"qpos0 with qpos[thj0]=0.5\"")
      .def_prop_ro(
          "repro_folders", [](const AuditResult& r) { return r.report.repro_folders; },
          "the repro folders written for runs that diverged (with repro=)")
      .def(
          "count",
          [](const AuditResult& r, const std::string& status) {
            return CountRows(r.report.findings, status);
          },
          nb::arg("status"), "how many rows have this status ('PASS', 'WARN', 'FAIL', 'SKIP')")
      .def(
          "to_pandas",
          [](const AuditResult& r) {
            nb::list rows;
            for (auto [layer, findings] : nb::borrow<nb::dict>(FromJson(r.Json())["layers"])) {
              for (nb::handle row : findings) rows.append(row);
            }
            return RowsFrame(rows);
          },
          "the rows as a pandas.DataFrame (the JSON rows' columns; 'section' is the layer)");
  AddResultMethods(type, "audit");

  m.def(
      "audit",
      [](ModelArg model, bool strict, std::optional<FileArg> accept, SetArg set,
         std::optional<NameOrId> keyframe, std::optional<FileArg> scenario,
         std::optional<FileArg> repro) {
        auto result = std::make_shared<AuditResult>();
        CallNotices notices;
        result->model = ToModel(model, notices.sink());
        result->strict = strict;
        std::vector<std::string> sets = result->model->SetTexts(SetTexts(set));
        std::string accept_file = OptionalPathArg(accept, "accept");
        std::string scenario_file = OptionalPathArg(scenario, "scenario");
        std::string repro_dir = OptionalPathArg(repro, "repro");
        internal::RefuseOutputsOntoInputs({{"repro", repro_dir}},
                                          {{"the model", result->model->name()},
                                           {"the accept list", accept_file},
                                           {"the scenario file", scenario_file}});
        std::string key = (keyframe ? keyframe->text : result->model->keyframe());
        result->report = RunLong([&](StopToken stop) {
          const Model& work = result->model->model();
          AuditOptions options;
          options.sets = StartAssignments(work, {"", "", "", sets}, notices.sink());
          options.keyframe = key;
          if (!scenario_file.empty()) options.scenario = LoadScenario(work, scenario_file);
          AcceptList accepted = accept_file.empty() ? AcceptList() : LoadAcceptList(accept_file);
          if (!repro_dir.empty()) {
            options.keep_diverged = [&](const Model& ran, const RunResult& run,
                                        const std::string& what) {
              return WriteRepro(ran, run, {"python", "plumb.audit(...)"}, repro_dir, what);
            };
          }
          options.stop = stop;
          result->start = AuditStart(work, options);  // the pose the report's pictures show
          AuditReport report = Audit(work, options);
          ApplyAcceptList(accepted, &report.findings);
          return report;
        });
        notices.Issue();
        result->notices = notices.all();
        return result;
      },
      nb::arg("model"), nb::arg("strict") = false, nb::arg("accept") = nb::none(),
      nb::arg("set") = nb::none(), nb::arg("keyframe") = nb::none(),
      nb::arg("scenario") = nb::none(), nb::arg("repro") = nb::none(),
      "Audits a model (plumb audit): structure, inertia, actuators, contacts, behaviour and "
      "warnings, one row per finding. `accept` is a reviewed accept list (TOML, as --accept), "
      "`strict` fails on WARN too, `keyframe` names the reference pose, `scenario` a scenario "
      "file, `repro` a folder for repro folders of runs that diverge (none are written "
      "without it). Returns an AuditResult.");
}

// ---- converge ----------------------------------------------------------------------------

struct ConvergeResult {
  std::shared_ptr<PyModel> model;
  std::vector<Assignment> sets;
  ConvergenceResult result;
  std::vector<Notice> notices;  // what the call said (plumb.Notice)
  std::string html, full_html;  // the light view, the whole report (each made once)

  std::string Json() const { return ConvergeToJson(result); }
  std::string Table() const { return ConvergeTable(result); }
  void WriteReport(const std::string& path, ReportView view) const {
    WriteConvergeReport(path, model->model(), sets, {result}, result.integrator,
                        PythonReportInfo("converge", true, view));
  }
};

void BindConverge(nb::module_& m) {
  nb::class_<ConvergeResult> type(
      m, "ConvergeResult",
      "plumb.converge's result: the metric at each timestep of the ladder (.dt, .values, "
      ".errors as numpy arrays), the observed order, the recommended timestep, .ok, the CLI's "
      "JSON and table, and the HTML report.");
  type.def_prop_ro(
          "ok", [](const ConvergeResult& r) { return r.result.ok; },
          "every level ran (False: one diverged; .problem says where)")
      .def_prop_ro("diverged", [](const ConvergeResult& r) { return r.result.diverged; })
      .def_prop_ro("problem", [](const ConvergeResult& r) { return r.result.problem; })
      .def_prop_ro("metric", [](const ConvergeResult& r) { return r.result.metric; })
      .def_prop_ro(
          "dt",
          [](const ConvergeResult& r) {
            return FieldArray(r.result.levels, &ConvergenceLevel::dt);
          },
          "each level's timestep (s), coarsest first")
      .def_prop_ro(
          "values",
          [](const ConvergeResult& r) {
            return FieldArray(r.result.levels, &ConvergenceLevel::value);
          },
          "the metric at each level")
      .def_prop_ro(
          "errors",
          [](const ConvergeResult& r) {
            return FieldArray(r.result.levels, &ConvergenceLevel::error);
          },
          "each level's estimated error (nan where none)")
      .def_prop_ro("observed_order",
                   [](const ConvergeResult& r) { return r.result.estimate.order; })
      .def_prop_ro("expected_order",
                   [](const ConvergeResult& r) { return r.result.expected_order; })
      .def_prop_ro(
          "recommended_dt", [](const ConvergeResult& r) { return r.result.recommended_dt; },
          "the coarsest tested timestep that, with every finer level, meets the tolerance "
          "(0: none)")
      .def_prop_ro(
          "solref_floor", [](const ConvergeResult& r) { return r.result.solref_floor; },
          "s: solref time constants below it were held at it across levels (MuJoCo's 2*dt "
          "floor at the coarsest level); 0 when none was")
      .def_prop_ro(
          "solref_held", [](const ConvergeResult& r) { return r.result.solref_held; },
          "the solref arrays held and their rows, e.g. 'geom_solref (2)'; empty when none")
      .def(
          "to_pandas",
          [](const ConvergeResult& r) { return RowsFrame(FromJson(r.Json())["levels"]); },
          "the levels as a pandas.DataFrame (the JSON levels' columns)");
  AddResultMethods(type, "converge");

  m.def(
      "converge",
      [](ModelArg model, const std::string& metric, SetArg set, std::optional<double> dt,
         int halvings, double tol, std::optional<double> until) {
        auto result = std::make_shared<ConvergeResult>();
        CallNotices notices;
        result->model = ToModel(model, notices.sink());
        std::vector<std::string> sets = SetTexts(set);
        result->result = RunLong([&](StopToken stop) {
          ConvergeOptions options;
          options.sets = result->model->Start(sets, notices.sink());
          options.dt = dt;
          options.halvings = halvings;
          options.tol = tol;
          options.until = until;
          options.stop = stop;
          result->sets = options.sets;
          return Converge(result->model->model(), ParseMetric(result->model->model(), metric),
                          options);
        });
        notices.Issue();
        result->notices = notices.all();
        return result;
      },
      nb::arg("model"), nb::arg("metric"), nb::arg("set") = nb::none(), nb::arg("dt") = nb::none(),
      nb::arg("halvings") = ConvergeOptions{}.halvings, nb::arg("tol") = ConvergeOptions{}.tol,
      nb::arg("until") = nb::none(),
      "Runs `metric` (the CLI's vocabulary: 'qpos[hinge]@2', 'period(qpos[hinge])', "
      "'maxabs(PATH)', 'energy_drift', 'state@T') at dt, dt/2, ... dt/2^halvings (plumb "
      "converge): observed order, extrapolation, the recommended timestep. `dt` defaults to the "
      "model's, `until` to the metric's run. Returns a ConvergeResult.");
}

// ---- snapshot and diff -------------------------------------------------------------------

// A regression snapshot: the JSON text plumb snapshot writes, and where it came from.
struct Snapshot {
  std::string text;
  std::string source;  // the file it was loaded from, or the model it was taken of

  static Snapshot Load(const std::string& path) {
    std::string text = internal::ReadInputFile(
        path, internal::InputKind::kSnapshot);  // refuses a FIFO or a device
    internal::FileKind kind = internal::SniffFileKind(text);
    if (kind != internal::FileKind::kSnapshot && kind != internal::FileKind::kJson &&
        kind != internal::FileKind::kText) {
      throw ValueError("'" + path + "' is " + internal::FileKindName(kind) +
                       ", not a plumb snapshot: take one with plumb.snapshot(model).save(path).");
    }
    return {text, path};
  }
};

struct DiffResult {
  std::shared_ptr<PyModel> model;
  std::string snapshot;  // as given
  SnapshotDiff diff;
  std::vector<Notice> notices;  // what the call said (plumb.Notice)
  std::string html;

  std::string Json() const { return DiffToJson(diff, snapshot); }
  std::string Table() const { return DiffTable(diff, snapshot, "set "); }
  void WriteReport(const std::string& path) const {
    WriteDiffReport(path, model->model(), diff, snapshot, PythonReportInfo("diff"));
  }
};

nb::list ChangeList(const std::vector<SnapshotChange>& changes) {
  nb::list out;
  for (const SnapshotChange& c : changes) {
    nb::dict d;
    d["kind"] = c.kind;
    d["path"] = c.path;
    d["old"] = FromJson(c.old_value);
    d["new"] = FromJson(c.new_value);
    d["step"] = c.step;
    d["what"] = c.what;
    out.append(d);
  }
  return out;
}

void BindSnapshot(nb::module_& m) {
  nb::class_<Snapshot>(m, "Snapshot",
                       "A model's regression snapshot (plumb snapshot): its sizes, every "
                       "element's parameters and a golden trajectory, as JSON text.")
      .def_ro("text", &Snapshot::text, "the JSON text, as plumb snapshot writes it")
      .def_ro("source", &Snapshot::source, "the file it was loaded from, or the model's name")
      .def(
          "save",
          [](const Snapshot& s, FileArg path) {
            internal::AtomicFile file(PathArg(path, "path"));
            std::fwrite(s.text.data(), 1, s.text.size(), file.stream());
            file.Commit();
          },
          nb::arg("path"), "writes it (whole or not at all), for plumb diff or plumb.diff")
      .def_static(
          "load", [](FileArg path) { return Snapshot::Load(PathArg(path, "path")); },
          nb::arg("path"), "reads a snapshot file (plumb snapshot -o FILE)")
      .def(
          "to_json", [](const Snapshot& s) { return s.text; }, "the JSON text")
      .def("to_dict", [](const Snapshot& s) { return FromJson(s.text); })
      .def("_repr_html_",
           [](const Snapshot& s) {
             return fmt::format(
                 "<p><b>plumb snapshot</b> of {} ({} bytes of JSON): "
                 "<code>.save(path)</code> keeps it, <code>plumb.diff(snapshot, "
                 "model)</code> compares a model with it.</p>",
                 report::Escape(s.source), s.text.size());
           })
      .def("__repr__", [](const Snapshot& s) {
        return fmt::format("<plumb.Snapshot of {} ({} bytes)>", s.source, s.text.size());
      });

  m.def(
      "snapshot",
      [](ModelArg model, SetArg set) {
        CallNotices notices;
        std::shared_ptr<PyModel> p = ToModel(model, notices.sink());
        std::vector<std::string> sets = p->SetTexts(SetTexts(set));
        Snapshot snapshot = RunLong([&](StopToken) {
          std::vector<Assignment> parsed =
              StartAssignments(p->model(), {"", "", "", sets}, notices.sink());
          std::string divergence;
          Snapshot s{MakeSnapshot(p->model(), parsed, &divergence), p->name()};
          if (!divergence.empty()) {
            throw Error("no snapshot: the golden trajectory of " + p->name() +
                        " diverges: " + divergence +
                        ". Fix the model first (plumb.audit shows where), e.g. a smaller "
                        "timestep or more damping.");
          }
          return s;
        });
        notices.Issue();
        return snapshot;
      },
      nb::arg("model"), nb::arg("set") = nb::none(),
      "Takes a model's regression snapshot (plumb snapshot), with the `set` assignments "
      "recorded so that plumb.diff applies them again. Raises plumb.Error when the golden "
      "trajectory diverges.");

  nb::class_<DiffResult> type(
      m, "DiffResult",
      "plumb.diff's result: .changes (dicts: kind, path, old, new, step, what), .compiler "
      "(what another MuJoCo's compiler derived differently), .notes, .ok (identical within "
      "tol), .diverged, the CLI's JSON and table, and an HTML page of the changes.");
  type.def_prop_ro(
          "ok", [](const DiffResult& r) { return !r.diff.changed() && !r.diff.diverged; },
          "identical within tol, and the trajectory did not diverge")
      .def_prop_ro("changes", [](const DiffResult& r) { return ChangeList(r.diff.changes); })
      .def_prop_ro("compiler", [](const DiffResult& r) { return ChangeList(r.diff.compiler); })
      .def_prop_ro("notes", [](const DiffResult& r) { return r.diff.notes; })
      .def_prop_ro("diverged", [](const DiffResult& r) { return r.diff.diverged; })
      .def(
          "to_pandas", [](const DiffResult& r) { return RowsFrame(FromJson(r.Json())["changes"]); },
          "the changes as a pandas.DataFrame");
  AddResultMethods(type, "diff");

  m.def(
      "diff",
      [](SnapshotArg snapshot, ModelArg model, SetArg set, double tol) {
        Snapshot s = nb::isinstance<Snapshot>(snapshot.object)
                         ? nb::cast<Snapshot>(snapshot.object)
                         : Snapshot::Load(PathArg(snapshot.object, "snapshot"));
        auto result = std::make_shared<DiffResult>();
        result->snapshot = s.source;
        CallNotices notices;
        std::shared_ptr<PyModel> p = ToModel(model, notices.sink());
        result->model = p;
        std::vector<std::string> sets = p->SetTexts(SetTexts(set));
        result->diff = RunLong([&](StopToken) {
          std::vector<Assignment> parsed =
              StartAssignments(p->model(), {"", "", "", sets}, notices.sink());
          try {
            return DiffSnapshot(s.text, p->model(), parsed, tol);
          } catch (const ArgumentError&) {
            throw;
          } catch (const ValueError& e) {
            throw ValueError(s.source + ": " + e.what() +
                             ". The snapshot is damaged or not a snapshot: take a fresh one with "
                             "plumb.snapshot(model).save(path).");
          }
        });
        notices.Issue();
        result->notices = notices.all();
        return result;
      },
      nb::arg("snapshot"), nb::arg("model"), nb::arg("set") = nb::none(),
      nb::arg("tol") = kDiffTolerance,
      "Compares a model with a snapshot (a plumb.Snapshot or a file plumb snapshot wrote), in "
      "words (plumb diff): sizes, options, every element's parameters and where the golden "
      "trajectory departs. Returns a DiffResult; .ok is False when anything changed.");
}

}  // namespace

void BindChecks(nb::module_& m) {
  BindVerify(m);
  BindAudit(m);
  BindConverge(m);
  BindSnapshot(m);
}

}  // namespace plumb::python
