// Reading robot logs and column maps (plumb/robot_log.h).

#include "plumb/robot_log.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>

#include "core/input_file.h"
#include "plumb/error.h"

namespace plumb {
using internal::InputKind;
using internal::ReadInputFile;

namespace {

// The cells of one CSV line (RFC 4180: quoted cells may hold commas and doubled quotes).
// Returns false for a quote left open.
bool SplitCsv(const std::string& line, std::vector<std::string>* cells) {
  cells->clear();
  std::string cell;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cell += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells->push_back(std::move(cell));
      cell.clear();
    } else if (c != '\r') {
      cell += c;
    }
  }
  cells->push_back(std::move(cell));
  return !quoted;
}

// The flight recorder's own columns, which name no path: read only when a map names them.
bool IsLinkColumn(const std::string& name) {
  return name == "kind" || name == "event" || name.rfind("cmd.", 0) == 0 ||
         name.rfind("state.", 0) == 0;
}

// What one column of the file becomes: a signal (index into inputs or measured), or nothing.
struct ColumnUse {
  bool used = false;
  bool input = false;
  std::size_t index = 0;
};

// The lines of a text as std::getline reads them from a stream: eof() once a line ran to the
// end of the text without a newline (or nothing was left).
class Lines {
 public:
  explicit Lines(std::string text) : text_(std::move(text)) {}
  bool Next(std::string* line) {
    if (at_ >= text_.size()) {
      eof_ = true;
      return false;
    }
    std::size_t end = text_.find('\n', at_);
    eof_ = end == std::string::npos;
    if (eof_) end = text_.size();
    line->assign(text_, at_, end - at_);
    at_ = end + 1;
    return true;
  }
  bool eof() const { return eof_; }

 private:
  std::string text_;
  std::size_t at_ = 0;
  bool eof_ = false;
};

class LogReader {
 public:
  LogReader(const Model& model, const std::string& path, const ColumnMap& map)
      : model_(model), path_(path), map_(map) {}

  RobotLog Read(double timestep) {
    Lines in(ReadInputFile(path_, InputKind::kRobotLog));
    log_.source = path_;
    std::string line;
    if (!in.Next(&line) || line.empty()) Fail(1, "", "is empty: a log starts with a header row");
    Header(line);
    std::vector<std::string> cells;
    long row = 1;
    bool first = true;
    double last = -INFINITY;
    while (in.Next(&line)) {
      ++row;
      if (line.empty() || line == "\r") continue;
      // every line of the flight recorder ends with a newline: one without was being written
      // when the bridge was killed, and may be cut anywhere (flight_recorder.h)
      if (in.eof() && kind_ >= 0) {
        log_.last_line_cut = true;
        break;
      }
      if (!SplitCsv(line, &cells)) Fail(row, "", "has a quote that is never closed");
      if (cells.size() != names_.size()) {
        Fail(row, "",
             fmt::format("has {} cells where the header has {}", cells.size(), names_.size()));
      }
      // events and gamepad messages carry text, not samples
      if (kind_ >= 0 && cells[kind_] != "state" && cells[kind_] != "command") continue;
      double t = Number(row, time_, cells[time_]);
      if (t < last) {
        Fail(row, "time", fmt::format("goes backwards: {} s after {} s", t, last));
      }
      last = t;
      if (first) log_.start = t;
      first = false;
      log_.end = t;
      for (std::size_t c = 0; c < uses_.size(); ++c) {
        if (!uses_[c].used || cells[c].empty()) continue;
        LogSignal& s = uses_[c].input ? log_.inputs[uses_[c].index] : log_.measured[uses_[c].index];
        s.time.push_back(t);
        s.value.push_back(Number(row, c, cells[c]));
      }
    }
    if (first) Fail(row, "", "has a header but no rows");
    if (log_.end - log_.start < timestep * (1 - 1e-9)) {
      Fail(row, "time",
           fmt::format("spans {:g} s, less than one timestep of the model ({:g} s): nothing to "
                       "simulate",
                       log_.end - log_.start, timestep));
    }
    for (const LogSignal& s : log_.measured) {
      if (s.time.empty()) Fail(1, s.column, "has no value in any row");
    }
    for (const LogSignal& s : log_.inputs) {
      if (s.time.empty()) Fail(1, s.column, "has no value in any row");
    }
    return std::move(log_);
  }

 private:
  [[noreturn]] void Fail(long row, const std::string& column, const std::string& why) const {
    std::string where = fmt::format("{}: row {}", path_, row);
    if (!column.empty()) where += fmt::format(", column '{}'", column);
    throw ValueError(where + ": " + why);
  }

  double Number(long row, std::size_t column, const std::string& cell) const {
    const char* text = cell.c_str();
    char* end = nullptr;
    errno = 0;
    double v = std::strtod(text, &end);
    while (end != nullptr && (*end == ' ' || *end == '\t')) ++end;
    if (cell.empty() || end == text || *end != '\0') {
      Fail(row, names_[column], fmt::format("'{}' is not a number", cell));
    }
    if (!std::isfinite(v)) {
      Fail(row, names_[column],
           fmt::format("is {}: a log must hold finite numbers (drop or repair the row)", cell));
    }
    return v;
  }

  void Header(const std::string& line) {
    if (!SplitCsv(line, &names_)) Fail(1, "", "has a quote that is never closed");
    for (const auto& [from, to] : map_.columns) {
      if (std::find(names_.begin(), names_.end(), from) == names_.end()) {
        throw ValueError(fmt::format("{}: the column map names '{}', which {} has no column of",
                                     map_.source, from, path_));
      }
    }
    for (std::size_t c = 0; c < names_.size(); ++c) {
      auto mapped = map_.columns.find(names_[c]);
      if ((mapped != map_.columns.end() ? mapped->second : names_[c]) == "time") time_ = c;
    }
    if (time_ == kNone) Fail(1, "", "has no 'time' column (seconds); name one in a column map");
    std::set<std::string> seen;
    uses_.resize(names_.size());
    for (std::size_t c = 0; c < names_.size(); ++c) {
      const std::string& name = names_[c];
      if (!seen.insert(name).second) Fail(1, name, "appears twice in the header");
      auto mapped = map_.columns.find(name);
      std::string target = mapped != map_.columns.end() ? mapped->second : name;
      if (target.empty()) continue;  // dropped by the map
      if (target == "time") continue;
      if (mapped == map_.columns.end() && IsLinkColumn(name)) {
        if (name == "kind") kind_ = static_cast<long>(c);
        continue;
      }
      Use(c, name, target);
    }
    if (log_.measured.empty()) {
      Fail(1, "",
           "has no measured column (qpos[...], qvel[...], sensordata[...]): nothing to compare");
    }
  }

  void Use(std::size_t c, const std::string& name, const std::string& target) {
    Path p;
    try {
      p = ResolvePath(model_, target);
    } catch (const PathError& e) {
      Fail(1, name,
           fmt::format("{}{} (rename the robot's columns with a column map)",
                       target == name ? std::string() : "mapped to '" + target + "': ", e.what()));
    }
    if (p.count != 1) {
      Fail(1, name,
           fmt::format("'{}' has {} elements: a column holds one (e.g. '{}[0]')", p.text, p.count,
                       p.text));
    }
    if (p.role == Role::kParameter) {
      Fail(1, name, fmt::format("'{}' is a model parameter, not something a log records", p.text));
    }
    if (p.field == "time") Fail(1, name, "is a second time column");
    for (const std::vector<LogSignal>* signals : {&log_.inputs, &log_.measured}) {
      for (const LogSignal& s : *signals) {
        if (s.path.field_index == p.field_index && s.path.first == p.first) {
          Fail(1, name, "names the same element as column '" + s.column + "'");
        }
      }
    }
    bool input = p.role == Role::kInput;
    std::vector<LogSignal>& into = input ? log_.inputs : log_.measured;
    uses_[c] = {true, input, into.size()};
    into.push_back({name, p, {}, {}});
  }

  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  const Model& model_;
  std::string path_;
  const ColumnMap& map_;
  std::vector<std::string> names_;
  std::vector<ColumnUse> uses_;
  std::size_t time_ = kNone;
  long kind_ = -1;
  RobotLog log_;
};

}  // namespace

ColumnMap LoadColumnMap(const std::string& path) {
  ColumnMap map;
  map.source = path;
  std::string text = ReadInputFile(path, InputKind::kColumnMap);
  toml::table table;
  try {
    table = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw ValueError(fmt::format("{}:{}:{}: {}", path, where.line, where.column, e.description()));
  }
  auto at = [&](const toml::node& node) {
    return fmt::format("{}:{}:{}", path, node.source().begin.line, node.source().begin.column);
  };
  for (const auto& [key, node] : table) {
    if (key.str() != "columns") {
      throw ValueError(fmt::format("{}: '{}': unknown key (a column map has one [columns] table)",
                                   at(node), key.str()));
    }
  }
  const toml::table* columns = table["columns"].as_table();
  if (columns == nullptr) {
    throw ValueError(
        fmt::format("{}: no [columns] table (\"robot column\" = \"plumb path\")", path));
  }
  for (const auto& [key, node] : *columns) {
    std::optional<std::string> to = node.value<std::string>();
    if (!to) {
      throw ValueError(
          fmt::format("{}: columns.'{}': must be a plumb path in quotes (\"\" drops "
                      "the column)",
                      at(node), key.str()));
    }
    map.columns[std::string(key.str())] = *to;
  }
  return map;
}

std::vector<RobotLog> LoadRobotLogs(const Model& model, const std::vector<std::string>& paths,
                                    const std::string& column_map, Notices* notices) {
  ColumnMap map;
  if (!column_map.empty()) map = LoadColumnMap(column_map);
  std::vector<RobotLog> logs;
  for (const std::string& path : paths) {
    logs.push_back(LoadRobotLog(model, path, model->opt.timestep, map));
    if (!logs.back().last_line_cut) continue;
    AddTo(notices, {NoticeLevel::kNote, NoticeTopic::kLog, logs.back().source,
                    "the last line is cut short (the bridge was killed while writing it); it is "
                    "left out"});
  }
  return logs;
}

RobotLog LoadRobotLog(const Model& model, const std::string& path, double timestep,
                      const ColumnMap& map) {
  return LogReader(model, path, map).Read(timestep);
}

}  // namespace plumb
