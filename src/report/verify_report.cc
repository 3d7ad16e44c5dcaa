// plumb verify --report: the checks, the nominal run's curves, the convergence study and a
// pendulum's period against amplitude.

#include <fmt/format.h>

#include <cmath>

#include "plumb/report.h"
#include "report/page_start.h"
#include "report/verify_charts.h"

namespace plumb {

void WriteVerifyReport(const std::string& path, const Model& model,
                       const std::vector<Assignment>& sets, const VerifyReport& result,
                       const ReportInfo& info) {
  report::Page page = report::StartPage("verify", model, info);
  report::AddModelPictures(&page, model, sets, info);

  page.Heading("Checks");
  page.StatusSummary(result.Count(CheckStatus::kPass), result.Count(CheckStatus::kWarn),
                     result.Count(CheckStatus::kFail), result.Count(CheckStatus::kSkip));
  std::string rows;
  for (const CheckRow& c : result.checks) {
    const char* status = CheckStatusName(c.status);
    rows += fmt::format(
        "<tr class=\"row-{}\">{}<td><code>{}</code><br>{}</td><td>{}</td><td>{}</td>"
        "<td class=\"detail\">{}</td></tr>\n",
        status, report::StatusCell(c.status), report::Escape(c.id), report::Escape(c.title),
        report::Escape(c.measured_text), report::Escape(c.reference_text),
        report::Escape(c.explanation));
  }
  page.Html(
      "<table><tr><th>status</th><th>check</th><th>measured</th><th>reference</th>"
      "<th>explanation</th></tr>\n" +
      rows + "</table>\n");

  report::AddRunCharts(&page, model, result.figures);
  report::AddConvergenceChart(&page, result.figures.convergence_metric, result.figures.convergence,
                              result.figures.expected_order);
  if (result.figures.pendulum) report::AddPeriodChart(&page, *result.figures.pendulum);
  report::WritePage(page, path);
}

}  // namespace plumb
