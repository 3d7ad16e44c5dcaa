// Table, CSV and JSON-lines writers for sampled rows.

#include "plumb/sample_writer.h"

#include <fmt/format.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>

#include "plumb/error.h"

namespace plumb {
namespace {

class Writer : public SampleSink {
 public:
  explicit Writer(std::FILE* out) : out_(out) {}
  void End() override {
    if (std::fflush(out_) != 0 || std::ferror(out_)) {
      throw IoError(std::string("cannot write samples: ") + std::strerror(errno));
    }
  }

 protected:
  void Put(const std::string& s) { std::fwrite(s.data(), 1, s.size(), out_); }
  std::FILE* out_;
};

// Fixed-width columns with 5 decimals, as the chapter prints them. A number whose fixed text
// would not leave a space before it in its column (-2e6, 1e308) is printed in exponent form,
// so columns never run together and a row never grows 300 digits.
class TableWriter : public Writer {
 public:
  using Writer::Writer;
  void Begin(const std::vector<Path>& columns) override {
    std::string header;
    for (const Path& p : columns) {
      int width = std::max<int>(12, static_cast<int>(p.text.size()) + 2);
      widths_.push_back(width);
      header += fmt::format("{:>{}}", p.text, width);
    }
    Put(header + "\n");
  }
  void Sample(const std::vector<double>& row) override {
    line_.clear();
    for (std::size_t c = 0; c < row.size(); ++c) {
      std::size_t room = static_cast<std::size_t>(widths_[c]) - 1;  // one space before
      double v = row[c];
      bool fits = std::fabs(v) < 1e15 && fmt::formatted_size("{:.5f}", v) <= room;
      if (fits || !std::isfinite(v)) {
        fmt::format_to(std::back_inserter(line_), "{:>{}.5f}", v, widths_[c]);
      } else {
        fmt::format_to(std::back_inserter(line_), "{:>{}.4e}", v, widths_[c]);
      }
    }
    line_ += '\n';
    Put(line_);
  }

 private:
  std::vector<int> widths_;
  std::string line_;
};

class CsvWriter : public Writer {
 public:
  using Writer::Writer;
  void Begin(const std::vector<Path>& columns) override {
    std::vector<std::string> names;
    for (const Path& column : columns) names.push_back(column.text);
    Put(CsvLine(names));
  }
  void Sample(const std::vector<double>& row) override {
    line_.clear();
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (c) line_ += ',';
      AppendCsvNumber(&line_, row[c]);
    }
    line_ += '\n';
    Put(line_);
  }

 private:
  std::string line_;
};

std::string JsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          out += fmt::format("\\u{:04x}", c);
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

class JsonlWriter : public Writer {
 public:
  using Writer::Writer;
  void Begin(const std::vector<Path>& columns) override {
    for (const Path& p : columns) keys_.push_back(JsonString(p.text) + ":");
  }
  void Sample(const std::vector<double>& row) override {
    line_ = "{";
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (c) line_ += ',';
      line_ += keys_[c];
      // JSON has no NaN or Inf
      if (std::isfinite(row[c])) {
        AppendCsvNumber(&line_, row[c]);
      } else {
        line_ += "null";
      }
    }
    line_ += "}\n";
    Put(line_);
  }

 private:
  std::vector<std::string> keys_;
  std::string line_;
};

}  // namespace

std::unique_ptr<SampleSink> MakeSampleWriter(SampleFormat format, std::FILE* out) {
  switch (format) {
    case SampleFormat::kTable:
      return std::make_unique<TableWriter>(out);
    case SampleFormat::kCsv:
      return std::make_unique<CsvWriter>(out);
    case SampleFormat::kJsonl:
      return std::make_unique<JsonlWriter>(out);
  }
  return nullptr;
}

std::string CsvLine(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + CsvField(fields[i]);
  return line + "\n";
}

void AppendCsvNumber(std::string* out, double v) {
  if (std::isnan(v)) return;
  char buffer[32];
  std::to_chars_result r = std::to_chars(buffer, buffer + sizeof(buffer), v);
  out->append(buffer, r.ptr);
}

std::string CsvNumber(double v) {
  std::string out;
  AppendCsvNumber(&out, v);
  return out;
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

}  // namespace plumb
