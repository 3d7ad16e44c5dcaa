// The report page: markup, inlined assets and the chart data Chart.js draws from.

#include "report/html.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "report/assets.h"

namespace plumb::report {
namespace {

// Colours that stay apart for the colour-blind (Okabe and Ito).
const char* const kPalette[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                "#E69F00", "#56B4E9", "#000000", "#F0E442"};

// JSON inside <script>: "</" would end the element.
std::string ScriptSafe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (std::size_t i = 0; i < json.size(); ++i) {
    if (json[i] == '<' && i + 1 < json.size() && json[i + 1] == '/') {
      out += "<\\/";
      ++i;
    } else {
      out += json[i];
    }
  }
  return out;
}

// Buckets of a line: what a chart a thousand pixels wide can show, peaks included.
constexpr std::size_t kLineBuckets = 500;

nlohmann::json AxisJson(const Axis& axis) { return {{"label", axis.label}, {"log", axis.log}}; }

}  // namespace

std::vector<std::size_t> KeepExtremes(const std::vector<double>& x, const std::vector<double>& y,
                                      std::size_t buckets) {
  std::size_t count = std::min(x.size(), y.size());
  std::vector<std::size_t> kept;
  if (count <= 6 * buckets || buckets == 0) {
    for (std::size_t i = 0; i < count; ++i) kept.push_back(i);
    return kept;
  }
  for (std::size_t b = 0; b < buckets; ++b) {
    std::size_t begin = b * count / buckets, end = (b + 1) * count / buckets;
    // the first and last of the run, and the extremes of each coordinate
    std::size_t pick[6] = {begin, end - 1, begin, begin, begin, begin};
    bool found = false;
    for (std::size_t i = begin; i < end; ++i) {
      if (!std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
      if (!found) {
        for (int k = 2; k < 6; ++k) pick[k] = i;
        found = true;
      }
      if (x[i] < x[pick[2]]) pick[2] = i;
      if (x[i] > x[pick[3]]) pick[3] = i;
      if (y[i] < y[pick[4]]) pick[4] = i;
      if (y[i] > y[pick[5]]) pick[5] = i;
    }
    std::sort(std::begin(pick), std::end(pick));
    for (std::size_t i : pick) {
      if (kept.empty() || kept.back() != i) kept.push_back(i);
    }
  }
  return kept;
}

std::string PngDataUri(const std::string& png) {
  static const char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out = "data:image/png;base64,";
  out.reserve(out.size() + (png.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < png.size(); i += 3) {
    unsigned v =
        (unsigned char)png[i] << 16 | (unsigned char)png[i + 1] << 8 | (unsigned char)png[i + 2];
    out += {kDigits[v >> 18], kDigits[(v >> 12) & 63], kDigits[(v >> 6) & 63], kDigits[v & 63]};
  }
  if (i + 1 == png.size()) {
    unsigned v = (unsigned char)png[i] << 16;
    out += {kDigits[v >> 18], kDigits[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == png.size()) {
    unsigned v = (unsigned char)png[i] << 16 | (unsigned char)png[i + 1] << 8;
    out += {kDigits[v >> 18], kDigits[(v >> 12) & 63], kDigits[(v >> 6) & 63], '='};
  }
  return out;
}

std::string Escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string StatusCell(CheckStatus status) {
  const char* name = CheckStatusName(status);
  return fmt::format("<td class=\"status {0}\">{0}</td>", name);
}

std::string CheckRowsTable(const std::vector<CheckRow>& rows, bool findings) {
  std::string html;
  std::string section;
  for (const CheckRow& c : rows) {
    if (findings && c.section != section) {
      section = c.section;
      html += fmt::format("<tr><th colspan=\"5\">{}</th></tr>\n", Escape(section));
    }
    std::string check = Escape(c.title);
    std::string explanation = c.explanation;
    if (findings) {
      const std::string about = c.About();
      if (!about.empty()) check += (check.empty() ? "" : "<br>") + Escape(about);
      if (!c.fix.empty()) explanation += " Fix: " + c.fix;
    }
    html += fmt::format(
        "<tr class=\"row-{}\">{}<td><code>{}</code><br>{}</td><td>{}</td><td>{}</td>"
        "<td class=\"detail\">{}</td></tr>\n",
        CheckStatusName(c.status), StatusCell(c.status), Escape(c.id), check,
        Escape(c.measured_text), Escape(c.reference_text), Escape(explanation));
  }
  return "<table><tr><th>status</th><th>check</th><th>measured</th><th>reference</th>"
         "<th>explanation</th></tr>\n" +
         html + "</table>\n";
}

Page::Page(std::string title) : title_(std::move(title)) {}

void Page::Meta(const std::string& key, const std::string& value) {
  meta_.emplace_back(key, value);
}
void Page::Heading(const std::string& text) { body_ += "<h2>" + Escape(text) + "</h2>\n"; }
void Page::Subheading(const std::string& text) { body_ += "<h3>" + Escape(text) + "</h3>\n"; }
void Page::Paragraph(const std::string& text, const std::string& css_class) {
  body_ +=
      (css_class.empty() ? "<p>" : "<p class=\"" + css_class + "\">") + Escape(text) + "</p>\n";
}
void Page::Html(const std::string& html) { body_ += html; }

void Page::StatusSummary(int pass, int warn, int fail, int skip) {
  body_ += fmt::format(
      "<p class=\"summary\"><span class=\"PASS\">{} PASS</span><span class=\"WARN\">{} "
      "WARN</span><span class=\"FAIL\">{} FAIL</span><span class=\"SKIP\">{} SKIP</span></p>\n",
      pass, warn, fail, skip);
}

std::string Page::NextId() { return "chart" + std::to_string(charts_.size()); }

void Page::Add(const Chart& chart) {
  std::string id = NextId();
  nlohmann::json series = nlohmann::json::array();
  int local = 0;
  for (const Series& s : chart.series) {
    nlohmann::json points = nlohmann::json::array();
    // a line or a time series (points in order of x) is drawn from its extremes; a scatter
    // of cases is drawn whole
    bool in_order = std::is_sorted(s.x.begin(), s.x.end());
    std::vector<std::size_t> kept = s.style == Series::kLine || in_order
                                        ? KeepExtremes(s.x, s.y, kLineBuckets)
                                        : KeepExtremes(s.x, s.y, 0);
    for (std::size_t i : kept) {
      double x = s.x[i], y = s.y[i];
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      if ((chart.x.log && x <= 0) || (chart.y.log && y <= 0)) continue;
      points.push_back({{"x", x}, {"y", y}});
    }
    std::string color = s.color.empty() ? kPalette[local++ % 8] : s.color;
    nlohmann::json j = {{"label", s.label},
                        {"points", points},
                        {"color", color},
                        {"style", s.style == Series::kPoints ? "points" : "line"},
                        {"dashed", s.dashed}};
    if (!s.marker.empty()) j["marker"] = s.marker;
    series.push_back(j);
  }
  charts_.push_back({{"id", id},
                     {"kind", "xy"},
                     {"x", AxisJson(chart.x)},
                     {"y", AxisJson(chart.y)},
                     {"series", series}});
  body_ += fmt::format(
      "<div class=\"chart\"><span class=\"tools\">drag to zoom, double-click to reset</span>"
      "<h3>{}</h3><canvas id=\"{}\" class=\"plumb-chart\"></canvas>"
      "<div class=\"how\"><b>How to read this.</b> {}</div></div>\n",
      Escape(chart.title), id, Escape(chart.how_to_read));
}

void Page::Add(const Histogram& h) {
  std::string id = NextId();
  nlohmann::json labels = nlohmann::json::array();
  for (std::size_t i = 0; i + 1 < h.edges.size(); ++i) {
    labels.push_back(fmt::format("{:.4g}..{:.4g}", h.edges[i], h.edges[i + 1]));
  }
  nlohmann::json series = nlohmann::json::array();
  int local = 0;
  for (const auto& [name, counts] : h.groups) {
    series.push_back({{"label", name}, {"values", counts}, {"color", kPalette[local++ % 8]}});
  }
  charts_.push_back({{"id", id},
                     {"kind", "bar"},
                     {"labels", labels},
                     {"x", AxisJson({h.x_label, false})},
                     {"y", AxisJson({"cases", false})},
                     {"series", series}});
  body_ += fmt::format(
      "<div class=\"chart\"><h3>{}</h3><canvas id=\"{}\" class=\"plumb-chart\"></canvas>"
      "<div class=\"how\"><b>How to read this.</b> {}</div></div>\n",
      Escape(h.title), id, Escape(h.how_to_read));
}

void Page::BeginGrid() { body_ += "<div class=\"grid2\">\n"; }
void Page::EndGrid() { body_ += "</div>\n"; }

void Page::Pictures(const std::vector<std::pair<std::string, std::string>>& png_and_caption) {
  body_ += "<div class=\"pictures\">";
  for (const auto& [png, caption] : png_and_caption) {
    body_ +=
        fmt::format("<figure><img alt=\"{0}\" src=\"{1}\"><figcaption>{0}</figcaption></figure>",
                    Escape(caption), PngDataUri(png));
  }
  body_ += "</div>\n";
}

void Page::Flipbook(const std::vector<std::string>& pngs, int interval_ms,
                    const std::string& caption) {
  if (pngs.empty()) return;
  nlohmann::json frames = nlohmann::json::array();
  for (const std::string& png : pngs) frames.push_back(PngDataUri(png));
  body_ += fmt::format(
      "<figure class=\"flipbook\" data-interval=\"{}\" data-frames=\"{}\"><img alt=\"{}\" "
      "src=\"{}\"><figcaption>{}</figcaption></figure>\n",
      interval_ms, Escape(frames.dump()), Escape(caption), PngDataUri(pngs.front()),
      Escape(caption));
}

std::string Page::Render() const {
  std::string meta;
  for (const auto& [key, value] : meta_) {
    meta += "<dt>" + Escape(key) + "</dt><dd>" + Escape(value) + "</dd>";
  }
  std::string page;
  page.reserve(body_.size() + kChartJs.size() + 64 * 1024);
  page += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  // nothing may be fetched: the page is self-contained
  page +=
      "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; "
      "img-src data:; style-src 'unsafe-inline'; script-src 'unsafe-inline'\">\n";
  page += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  page += "<title>" + Escape(title_) + "</title>\n<style>\n";
  page += kReportCss;
  page += "</style>\n</head><body>\n<h1>" + Escape(title_) + "</h1>\n<dl class=\"meta\">" + meta +
          "</dl>\n";
  page += body_;
  page += "<script id=\"plumb-charts\" type=\"application/json\">" + ScriptSafe(charts_.dump()) +
          "</script>\n";
  page += "<script>/* Chart.js 3.9 (MIT), from Debian's libjs-chart.js */\n";
  page += kChartJs;
  page += "\n</script>\n<script>\n";
  page += kReportJs;
  page += "</script>\n</body></html>\n";
  return page;
}

}  // namespace plumb::report
