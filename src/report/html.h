// The page every report is: a header, sections of tables, charts and pictures, with
// Chart.js and the page's own script and style inlined (report_assets.cc), so the file
// opens from file:// with no network.

#ifndef PLUMB_SRC_REPORT_HTML_H_
#define PLUMB_SRC_REPORT_HTML_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "plumb/image.h"
#include "plumb/verify.h"

namespace plumb::report {

// One line or set of points of a chart.
struct Series {
  enum Style { kLine, kPoints };
  Series(std::string label, std::vector<double> x, std::vector<double> y, Style style = kLine,
         std::string color = "", bool dashed = false, std::string marker = "")
      : label(std::move(label)),
        x(std::move(x)),
        y(std::move(y)),
        style(style),
        color(std::move(color)),
        dashed(dashed),
        marker(std::move(marker)) {}
  std::string label;
  // Non-finite points are left out; a line, or points in order of x (a logged signal), of
  // more points than a chart can show is drawn from KeepExtremes (all its peaks kept); other
  // points (a scatter of cases) are all drawn.
  std::vector<double> x, y;
  Style style = kLine;
  std::string color;  // CSS colour; empty: the next of the palette
  bool dashed = false;
  std::string marker;  // Chart.js point style for kPoints ("circle", "crossRot", ...)
};

struct Axis {
  Axis(std::string label, bool log = false) : label(std::move(label)), log(log) {}
  std::string label;
  bool log = false;  // logarithmic (non-positive values are left out)
};

struct Chart {
  Chart(std::string title, Axis x, Axis y)
      : title(std::move(title)), x(std::move(x)), y(std::move(y)) {}
  std::string title;
  Axis x, y;
  std::vector<Series> series;
  std::string how_to_read;  // what a healthy and a sick curve look like
};

// A histogram: bins' edges and stacked counts per group (e.g. finished / diverged).
struct Histogram {
  Histogram(std::string title, std::string x_label)
      : title(std::move(title)), x_label(std::move(x_label)) {}
  std::string title;
  std::string x_label;
  std::vector<double> edges;  // bins + 1
  std::vector<std::pair<std::string, std::vector<long>>> groups;
  std::string how_to_read;
};

// The samples of a curve (x[i], y[i]) worth drawing when it has more than a chart can
// show: split into `buckets` runs of consecutive samples, each keeps its first and last
// and those with the smallest and largest finite x and y, in their order. The kept points
// span exactly the range of the finite data (no peak is lost, no axis is cut short); at
// most 6 * buckets indices. Every index when the curve has no more than 6 * buckets points
// or `buckets` is 0.
std::vector<std::size_t> KeepExtremes(const std::vector<double>& x, const std::vector<double>& y,
                                      std::size_t buckets);

// data:image/png;base64,... of a PNG's bytes.
std::string PngDataUri(const std::string& png);

// HTML-escaped text.
std::string Escape(const std::string& text);

class Page {
 public:
  explicit Page(std::string title);

  // The header's key/value list (model, hash, versions, command line, date, ...).
  void Meta(const std::string& key, const std::string& value);
  void Heading(const std::string& text);     // a section
  void Subheading(const std::string& text);  // within a section
  void Paragraph(const std::string& text, const std::string& css_class = "");
  void Html(const std::string& html);  // trusted markup made by the report code
  void StatusSummary(int pass, int warn, int fail, int skip);
  void Add(const Chart& chart);
  void Add(const Histogram& histogram);
  void BeginGrid();  // charts side by side until EndGrid
  void EndGrid();
  // Pictures in a row: each a PNG with its caption.
  void Pictures(const std::vector<std::pair<std::string, std::string>>& png_and_caption);
  // An animation of PNG frames shown `interval_ms` apart.
  void Flipbook(const std::vector<std::string>& pngs, int interval_ms, const std::string& caption);

  // The whole page, ready to be written.
  std::string Render() const;

 private:
  std::string NextId();
  std::string title_;
  std::vector<std::pair<std::string, std::string>> meta_;
  std::string body_;
  nlohmann::json charts_ = nlohmann::json::array();
  int palette_ = 0;
};

// Row markup for a status table: <tr class="row-FAIL"><td class="status FAIL">FAIL</td>...
std::string StatusCell(CheckStatus status);

// A table of check rows: status, the check (its id over its title), measured, reference and
// explanation. With `findings`, a check also names what it is about (its element or subject),
// the explanation ends with the fix, and a heading row starts each section.
std::string CheckRowsTable(const std::vector<CheckRow>& rows, bool findings);

}  // namespace plumb::report

#endif  // PLUMB_SRC_REPORT_HTML_H_
