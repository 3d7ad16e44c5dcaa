// The files every report inlines, compiled in (cmake/PlumbEmbed.cmake writes them into
// report_assets.cc at build time): Chart.js from Debian's libjs-chart.js, and the page's
// own script and style from src/report/assets/.

#ifndef PLUMB_SRC_REPORT_ASSETS_H_
#define PLUMB_SRC_REPORT_ASSETS_H_

#include <string_view>

namespace plumb::report {

extern const std::string_view kChartJs;
extern const std::string_view kReportJs;
extern const std::string_view kReportCss;

}  // namespace plumb::report

#endif  // PLUMB_SRC_REPORT_ASSETS_H_
