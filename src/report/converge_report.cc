// plumb converge --report: each metric's ladder on log-log axes with its observed order.

#include <fmt/format.h>

#include <cmath>

#include "plumb/report.h"
#include "report/page_start.h"
#include "report/verify_charts.h"

namespace plumb {

void WriteConvergeReport(const std::string& path, const Model& model,
                         const std::vector<Assignment>& sets,
                         const std::vector<ConvergenceResult>& results, int integrator,
                         const ReportInfo& info) {
  report::Page page = report::StartPage("converge", model, info);
  report::AddModelPictures(&page, model, sets, info);
  double expected = ExpectedOrder(integrator);
  page.Heading("Levels");
  for (const ConvergenceResult& c : results) {
    std::string rows;
    for (const ConvergenceLevel& l : c.levels) {
      rows += fmt::format(
          "<tr><td>{:g}</td><td>{:.12g}</td><td>{:.3g}</td><td>{:.3g}</td>"
          "<td>{:.3g}{}</td></tr>\n",
          l.dt, l.value, l.diff, l.order, l.error, l.roundoff ? " (round-off)" : "");
    }
    CheckStatus status = !c.ok                  ? CheckStatus::kFail
                         : c.recommended_dt > 0 ? CheckStatus::kPass
                                                : CheckStatus::kWarn;
    page.Html(fmt::format(
        "<h3>{}</h3><table><tr>{}<td>{}</td></tr></table>"
        "<table><tr><th>dt (s)</th><th>value</th><th>difference to dt/2</th><th>order</th>"
        "<th>estimated error</th></tr>\n{}</table>\n",
        report::Escape(c.metric), report::StatusCell(status),
        report::Escape(!c.ok ? c.problem
                       : c.recommended_dt > 0
                           ? fmt::format("largest timestep within tol {:g}: {:g} s. {}", c.tol,
                                         c.recommended_dt, c.estimate.note)
                           : "no tested timestep is within tol. " + c.estimate.note),
        rows));
  }
  for (const ConvergenceResult& c : results) {
    report::AddConvergenceChart(&page, c.metric, c, expected);
  }
  report::WritePage(page, path);
}

}  // namespace plumb
