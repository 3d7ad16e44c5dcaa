// plumb crosscheck --report: what ran on each side, the five checks' rows, and for the
// trajectory check when each signal parted in the engine and in the chaos baseline.

#include <fmt/format.h>

#include <cmath>

#include "plumb/report.h"
#include "report/page_start.h"

namespace plumb {
namespace {

// Per signal, the time it parted at each start: the engine against the chaos baseline.
void AddDivergenceChart(report::Page* page, const std::vector<DivergenceTrack>& tracks,
                        double horizon) {
  if (tracks.empty()) return;
  std::vector<double> x, engine, chaos;
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    for (std::size_t k = 0; k < tracks[i].engine.size(); ++k) {
      x.push_back(static_cast<double>(i));
      engine.push_back(std::isfinite(tracks[i].engine[k]) ? tracks[i].engine[k] : horizon);
      chaos.push_back(std::isfinite(tracks[i].chaos[k]) ? tracks[i].chaos[k] : horizon);
    }
  }
  report::Chart chart("When each signal parts from CPU MuJoCo", report::Axis("signal (index)"),
                      report::Axis("time to part (s)"));
  chart.series.emplace_back("engine", x, engine, report::Series::kPoints, "", false, "circle");
  chart.series.emplace_back("chaos baseline (CPU MuJoCo rounded to float32)", x, chaos,
                            report::Series::kPoints, "", false, "crossRot");
  std::string names;
  for (std::size_t i = 0; i < tracks.size() && i < 40; ++i) {
    names += fmt::format("{}{}: {}", i ? ", " : "", i, tracks[i].signal);
  }
  chart.how_to_read = fmt::format(
      "One point per signal and start; {:g} s means it never parted. Engine points near or above "
      "the baseline's: the engine differs only by float32 rounding, which this model amplifies. "
      "Engine points far below: a difference in the physics. Signals: {}.",
      horizon, names);
  page->Add(chart);
}

}  // namespace

void WriteCrosscheckReport(const std::string& path, const Model& model,
                           const std::vector<Assignment>& sets, const CrosscheckReport& result,
                           double until, const ReportInfo& info) {
  report::Page page = report::StartPage("crosscheck", model, info);
  const EngineInfo& e = result.engine;
  page.Meta("engine", fmt::format("{} {} ({}), MuJoCo {}, {} on {}", e.engine, e.engine_version,
                                  e.backend, e.mujoco_version, e.precision, e.device));
  page.Meta("model sent as", result.model_transfer);
  report::AddModelPictures(&page, model, sets, info);
  page.Heading("Checks");
  page.StatusSummary(result.Count(CheckStatus::kPass), result.Count(CheckStatus::kWarn),
                     result.Count(CheckStatus::kFail), result.Count(CheckStatus::kSkip));
  page.Html(report::CheckRowsTable(result.rows, /*findings=*/true));
  AddDivergenceChart(&page, result.divergence, until);
  report::WritePage(page, path);
}

}  // namespace plumb
