// plumb.verify, plumb.audit, plumb.converge, plumb.snapshot and plumb.diff: the checks, each
// returning a result with typed rows, the CLI's JSON and the HTML report.

#include <fmt/format.h>

#include "common.h"
#include "plumb/check_table.h"
#include "plumb/error.h"
#include "plumb/report.h"
#include "plumb/result_json.h"
#include "plumb/verify.h"

namespace plumb::python {
namespace {

// plumb.VerifyResult: what Verify returned, with the model and start it judged.
struct VerifyResult {
  std::shared_ptr<PyModel> model;
  std::vector<Assignment> sets;
  VerifyReport report;
  std::string html;  // the report, made on first _repr_html_
};

ReportInfo PythonReportInfo(const char* call) {
  ReportInfo info{{"python", fmt::format("plumb.{}(...)", call)}};
  return info;
}

void BindVerify(nb::module_& m) {
  nb::class_<VerifyResult>(m, "VerifyResult",
                           "plumb.verify's result: .rows (plumb.CheckRow), .ok, the run it "
                           "judged (.horizon), the CLI's JSON (to_json, to_dict) and the HTML "
                           "report (_repr_html_ shows it in a notebook).")
      .def_prop_ro("rows", [](const VerifyResult& r) { return RowList(r.report.checks); })
      .def_prop_ro("ok", [](const VerifyResult& r) { return !r.report.failed(); },
                   "no check FAILed")
      .def_prop_ro("model", [](const VerifyResult& r) { return r.report.model; })
      .def_prop_ro("tol", [](const VerifyResult& r) { return r.report.tol; })
      .def_prop_ro("horizon",
                   [](const VerifyResult& r) {
                     nb::dict d;
                     d["until"] = r.report.horizon.until;
                     d["requested"] = r.report.horizon.requested;
                     d["steps"] = r.report.horizon.steps;
                     d["why"] = r.report.horizon.why;
                     return d;
                   },
                   "the nominal run: until and requested (s), steps, and why it is shorter")
      .def("count",
           [](const VerifyResult& r, const std::string& status) {
             for (CheckStatus s : {CheckStatus::kPass, CheckStatus::kWarn, CheckStatus::kFail,
                                   CheckStatus::kSkip}) {
               if (status == CheckStatusName(s)) return r.report.Count(s);
             }
             throw ArgumentError("status", Quoted(status), "expected PASS, WARN, FAIL or SKIP");
           },
           nb::arg("status"), "how many rows have this status ('PASS', 'WARN', 'FAIL', 'SKIP')")
      .def("to_json", [](const VerifyResult& r) { return VerifyToJson(r.report); },
           "the JSON document `plumb verify --format json` prints")
      .def("to_dict", [](const VerifyResult& r) { return FromJson(VerifyToJson(r.report)); },
           "to_json() as Python objects")
      .def("to_pandas",
           [](const VerifyResult& r) {
             return nb::module_::import_("pandas").attr("DataFrame")(
                 FromJson(VerifyToJson(r.report))["checks"]);
           },
           "the rows as a pandas.DataFrame (the JSON rows' columns)")
      .def("save_report",
           [](const VerifyResult& r, const std::string& path) {
             RunLong([&](StopToken) {
               WriteVerifyReport(path, r.model->model(), r.sets, r.report,
                                 PythonReportInfo("verify"));
               return 0;
             });
           },
           nb::arg("path"), "writes the self-contained HTML report (as --report FILE.html)")
      .def("_repr_html_",
           [](VerifyResult& r) {
             if (r.html.empty()) {
               r.html = RunLong([&](StopToken) {
                 return ReportHtml([&](const std::string& path) {
                   WriteVerifyReport(path, r.model->model(), r.sets, r.report,
                                     PythonReportInfo("verify"));
                 });
               });
             }
             return r.html;
           })
      .def("__repr__", [](const VerifyResult& r) {
        return VerifyTable(r.report, TableDetail::kFindings, "print(result.rows) lists every row");
      });

  m.def(
      "verify",
      [](nb::handle model, nb::handle set, double tol, std::optional<double> until) {
        auto result = std::make_shared<VerifyResult>();
        result->model = ToModel(model);
        std::vector<std::string> sets = SetTexts(set);
        result->report = RunLong([&](StopToken stop) {
          VerifyOptions options;
          options.sets = result->model->Start(sets);
          options.tol = tol;
          options.until = until;
          options.stop = stop;
          result->sets = options.sets;
          return Verify(result->model->model(), options);
        });
        return result;
      },
      nb::arg("model"), nb::arg("set") = nb::none(), nb::arg("tol") = 1e-2,
      nb::arg("until") = nb::none(),
      "Checks that a model's numbers are credible (plumb verify): determinism, warnings, "
      "convergence as the timestep shrinks, energy, and for a single hinge pendulum the "
      "analytic references and the chapter's experiments. Returns a VerifyResult; raises "
      "plumb.Error subclasses for bad input, KeyboardInterrupt on Ctrl-C.");
}

}  // namespace

void BindChecks(nb::module_& m) { BindVerify(m); }

}  // namespace plumb::python
