// plumb verify --report: the checks, the nominal run's curves, the convergence study and a
// pendulum's period against amplitude.

#include <fmt/format.h>

#include <cmath>

#include "plumb/report.h"
#include "report/page_start.h"
#include "report/verify_charts.h"

namespace plumb {
namespace {

// The header's line for the run the checks judged: "0.5 s simulated (250 steps), not 2 s:
// verify's step budget ...", or "2 s simulated (1000 steps)".
std::string NominalRunText(const VerifyHorizon& h) {
  std::string text = fmt::format("{:g} s simulated ({} steps)", h.until, h.steps);
  if (h.shortened()) text += fmt::format(", not {:g} s: {}", h.requested, h.why);
  return text;
}

}  // namespace

void WriteVerifyReport(const std::string& path, const Model& model,
                       const std::vector<Assignment>& sets, const VerifyReport& result,
                       const ReportInfo& info) {
  report::Page page = report::StartPage("verify", model, info);
  page.Meta("start", result.start);
  page.Meta("nominal run", NominalRunText(result.horizon));
  // the pictures show the run the checks judged: pictures drawn ahead for another length
  // are drawn again
  ReportInfo pictures = info;
  if (pictures.nominal_until != result.horizon.until) pictures.ahead = nullptr;
  pictures.nominal_until = result.horizon.until;
  report::AddModelPictures(&page, model, sets, pictures);

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
