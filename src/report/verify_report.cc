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
  page.Html(report::CheckRowsTable(result.checks, /*findings=*/false));

  report::AddRunCharts(&page, model, result.figures);
  report::AddConvergenceChart(&page, result.figures.convergence_metric, result.figures.convergence,
                              result.figures.expected_order);
  if (result.figures.pendulum) report::AddPeriodChart(&page, *result.figures.pendulum);
  report::WritePage(page, path);
}

}  // namespace plumb
