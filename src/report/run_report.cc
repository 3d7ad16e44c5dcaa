// plumb.run's and plumb.render's pages (include/plumb/report.h): the samples as charts, the
// frames as an animation.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "plumb/image.h"
#include "plumb/report.h"
#include "report/page_start.h"

namespace plumb {

// Columns charted at most; the rest are named.
constexpr std::size_t kMostCharts = 24;

void WriteRunReport(const std::string& path, const Model& model,
                    const std::vector<std::string>& columns, const double* values, long rows,
                    const RunResult& result, const ReportInfo& info) {
  report::Page page = report::StartPage("run", model, info);
  std::size_t width = columns.size();
  auto column = [&](std::size_t c) {
    std::vector<double> out(static_cast<std::size_t>(rows));
    for (long r = 0; r < rows; ++r) out[r] = values[r * width + c];
    return out;
  };
  auto time = std::find(columns.begin(), columns.end(), "time");
  std::vector<double> x;
  std::string x_label = "sample";
  if (time != columns.end()) {
    x = column(static_cast<std::size_t>(time - columns.begin()));
    x_label = "time [s]";
  } else {
    for (long r = 0; r < rows; ++r) x.push_back(static_cast<double>(r));
  }
  page.Heading("The run");
  page.Paragraph(fmt::format("{} samples of {} columns{}, {} steps.", rows, width,
                             rows > 0 && !x.empty() && time != columns.end()
                                 ? fmt::format(" from t = {:g} s to {:g} s", x.front(), x.back())
                                 : "",
                             result.steps));
  if (result.diverged && result.divergence) page.Paragraph(result.divergence->reason, "fail");
  for (const WarningSummary& w : result.warnings) {
    page.Paragraph(fmt::format("MuJoCo warning {}: {} time(s), first in step {} (t = {:g} s): {}",
                               w.kind, w.count, w.first_step, w.first_time, w.message),
                   "warn");
  }
  page.Heading("Columns");
  page.BeginGrid();
  std::size_t charted = 0;
  for (std::size_t c = 0; c < width; ++c) {
    if (time != columns.end() && c == static_cast<std::size_t>(time - columns.begin())) continue;
    if (charted == kMostCharts) break;
    report::Chart chart(columns[c], report::Axis(x_label), report::Axis(columns[c]));
    chart.series.emplace_back(columns[c], x, column(c));
    page.Add(chart);
    ++charted;
  }
  page.EndGrid();
  std::size_t shown = charted + (time != columns.end() ? 1 : 0);
  if (shown < width) {
    page.Paragraph(fmt::format("{} more columns are not charted.", width - shown));
  }
  report::WritePage(page, path);
}

void WriteRenderReport(const std::string& path, const Model& model, const std::uint8_t* rgb,
                       long frames, int width, int height, double fps, const ReportInfo& info) {
  report::Page page = report::StartPage("render", model, info);
  page.Meta("pictures", fmt::format("{} frame(s) of {}x{}{}", frames, width, height,
                                    frames > 1 ? fmt::format(" at {:.4g} fps", fps) : ""));
  std::vector<std::string> pngs;
  std::size_t size = static_cast<std::size_t>(width) * height * 3;
  Image image;
  image.width = width;
  image.height = height;
  for (long f = 0; f < frames; ++f) {
    image.rgb.assign(rgb + f * size, rgb + (f + 1) * size);
    pngs.push_back(EncodePng(image, PngEffort::kFast));
  }
  page.Heading(frames > 1 ? "The run" : "The picture");
  if (frames == 1) {
    page.Pictures({{pngs.front(), fmt::format("{}x{}", width, height)}});
  } else {
    int interval = static_cast<int>(std::lround(1000.0 / std::max(fps, 1e-3)));
    page.Flipbook(pngs, interval, fmt::format("{} frames at {:.4g} fps", frames, fps));
  }
  report::WritePage(page, path);
}

}  // namespace plumb
