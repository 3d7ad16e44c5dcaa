// Behaviour scenarios for plumb audit: JSON or TOML files with a start state, control
// schedules and assertions on paths over time windows.

#include <fmt/format.h>

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/strings.h"
#include "plumb/audit.h"
#include "plumb/error.h"

namespace plumb {
namespace {

using nlohmann::json;

// TOML -> JSON, so both formats share one reader (dates and times, which no scenario entry
// takes, become their TOML text and are refused by the entry's type check).
json ToJson(const toml::node& node) {
  if (const toml::table* table = node.as_table()) {
    json j = json::object();
    for (const auto& [key, value] : *table) j[std::string(key.str())] = ToJson(value);
    return j;
  }
  if (const toml::array* array = node.as_array()) {
    json j = json::array();
    for (const toml::node& value : *array) j.push_back(ToJson(value));
    return j;
  }
  if (auto v = node.value_exact<double>()) return *v;
  if (auto v = node.value_exact<int64_t>()) return *v;
  if (auto v = node.value_exact<bool>()) return *v;
  if (auto v = node.value_exact<std::string>()) return *v;
  std::ostringstream text;
  node.visit([&](const auto& n) { text << n; });
  return text.str();
}


double Number(const json& j, const std::string& key, double fallback, const std::string& where) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_number()) {
    throw ValueError(where + ": must be a number, got " + j[key].dump());
  }
  double v = j[key].get<double>();
  if (!std::isfinite(v)) throw ValueError(where + ": is not finite");
  return v;
}

}  // namespace

double ControlSchedule::At(double t) const {
  if (type == "constant") return value;
  if (type == "step") return t < at ? before : value;
  if (type == "ramp") {
    if (t <= start) return before;
    if (t >= end) return to;
    return before + (to - before) * (t - start) / (end - start);
  }
  return value + amplitude * std::sin(2 * M_PI * frequency * t + phase);  // sine
}

Assertion ParseAssertion(const Model& model, const std::string& text) {
  Assertion a;
  a.text = text;
  auto bad = [&](const std::string& why) {
    return ValueError("assertion '" + text + "': " + why +
                      ". Write e.g. 'xpos[torso][2] > 0.8 during [0, 2]' or "
                      "'maxabs(qvel[*]) < 50'.");
  };
  std::string_view s = Trim(text);
  // split off "during [a, b]"
  std::size_t during = s.find("during");
  std::string_view window;
  if (during != std::string_view::npos) {
    window = Trim(s.substr(during + 6));
    s = Trim(s.substr(0, during));
    if (window.size() < 5 || window.front() != '[' || window.back() != ']') {
      throw bad("the window must look like [0, 2]");
    }
    std::vector<std::string> ends = Split(window.substr(1, window.size() - 2), ',');
    std::optional<double> from = ends.size() == 2 ? ParseNumber(ends[0]) : std::nullopt;
    std::optional<double> to = ends.size() == 2 ? ParseNumber(ends[1]) : std::nullopt;
    if (!from || !to || !(*from <= *to) || *from < 0)
      throw bad("the window must be [a, b], 0 <= a <= b");
    a.from = *from;
    a.to = *to;
  }
  // the comparison
  std::size_t op_at = std::string_view::npos;
  for (const char* op : {"<=", ">=", "<", ">"}) {
    std::size_t at = s.find(op);
    if (at != std::string_view::npos && (op_at == std::string_view::npos || at < op_at)) {
      op_at = at;
      a.op = op;
    }
    if (op_at != std::string_view::npos && std::string(op).size() == 2 && at == op_at) break;
  }
  if (op_at == std::string_view::npos) throw bad("no comparison (<, <=, >, >=)");
  std::optional<double> bound = ParseNumber(s.substr(op_at + a.op.size()));
  if (!bound || !std::isfinite(*bound)) throw bad("the right-hand side must be a number");
  a.bound = *bound;
  std::string_view lhs = Trim(s.substr(0, op_at));
  for (const char* reduce : {"maxabs", "max", "min", "final"}) {
    std::string_view name(reduce);
    if (lhs.substr(0, name.size()) == name && lhs.size() > name.size() + 1 &&
        Trim(lhs.substr(name.size())).front() == '(' && lhs.back() == ')') {
      std::string_view inner = Trim(lhs.substr(name.size()));
      a.reduce = reduce;
      lhs = Trim(inner.substr(1, inner.size() - 2));
      break;
    }
  }
  for (const Path& p : ExpandPath(model, lhs)) {
    for (Path& one : ScalarPaths(p)) a.paths.push_back(std::move(one));
  }
  return a;
}

namespace {

// Where an entry of a scenario file is, for messages: "stand.toml:12 (controls[1].type)"
// for TOML (the line found by scanning the text, as for a key in a table array), "stand.json
// at /controls/1/type" (a JSON pointer) for JSON.
class Locator {
 public:
  Locator(std::string file, bool toml, const std::string& text)
      : file_(std::move(file)), toml_(toml) {
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines_.push_back(line);
  }

  // `table`: "" (top level), "initial" or "controls"; `index`: which [[controls]] table
  // (or which assertion); `key`: the entry ("" for the table itself).
  std::string At(const std::string& table, int index, const std::string& key) const {
    std::string entry = table.empty() ? key : table;
    if (index >= 0) entry += "[" + std::to_string(index) + "]";
    if (!table.empty() && !key.empty()) entry += "." + key;
    if (!toml_) {
      std::string pointer = "/" + (table.empty() ? key : table);
      if (index >= 0) pointer += "/" + std::to_string(index);
      if (!table.empty() && !key.empty()) pointer += "/" + key;
      return file_ + " at " + pointer + " (" + entry + ")";
    }
    int line = Line(table, index, key);
    return file_ + (line > 0 ? ":" + std::to_string(line) : "") + " (" + entry + ")";
  }

 private:
  static bool IsKey(const std::string& line, const std::string& key) {
    std::string_view s = Trim(line);
    if (!s.empty() && s.front() == '"') s.remove_prefix(1);
    if (s.substr(0, key.size()) != key) return false;
    s = Trim(s.substr(key.size()));
    if (!s.empty() && s.front() == '"') s = Trim(s.substr(1));
    return !s.empty() && s.front() == '=';
  }
  static bool IsHeader(const std::string& line) {
    std::string_view s = Trim(line);
    return !s.empty() && s.front() == '[';
  }
  static bool IsHeaderOf(const std::string& line, const std::string& table) {
    std::string compact;
    for (char c : line) {
      if (!std::isspace(static_cast<unsigned char>(c))) compact += c;
    }
    return compact == "[" + table + "]" || compact == "[[" + table + "]]";
  }

  // 1-based line, 0 when not found.
  int Line(const std::string& table, int index, const std::string& key) const {
    int n = static_cast<int>(lines_.size());
    if (table.empty() || table == "assertions") {
      // a top-level key: before the first table header
      for (int i = 0; i < n && !IsHeader(lines_[i]); ++i) {
        if (IsKey(lines_[i], table.empty() ? key : table)) {
          if (table.empty() || index < 0) return i + 1;
          // the index-th string of a multi-line array, else the key's line
          int strings = 0;
          for (int k = i; k < n; ++k) {
            std::size_t quote = lines_[k].find('"', k == i ? lines_[k].find('=') : 0);
            if (quote != std::string::npos && strings++ == index) return k + 1;
            if (k > i && Trim(lines_[k]).substr(0, 1) == "]") break;
          }
          return i + 1;
        }
      }
      return 0;
    }
    int seen = -1;
    for (int i = 0; i < n; ++i) {
      if (!IsHeaderOf(lines_[i], table)) continue;
      if (index >= 0 && ++seen != index) continue;
      if (key.empty()) return i + 1;
      for (int k = i + 1; k < n && !IsHeader(lines_[k]); ++k) {
        if (IsKey(lines_[k], key)) return k + 1;
      }
      return i + 1;
    }
    // an inline table or array: the line that names it
    for (int i = 0; i < n; ++i) {
      if (IsKey(lines_[i], table)) return i + 1;
    }
    return 0;
  }

  std::string file_;
  bool toml_;
  std::vector<std::string> lines_;
};

const char* KindOf(const json& j) {
  return j.is_number()    ? "a number"
         : j.is_string()  ? "a string"
         : j.is_boolean() ? "a boolean"
         : j.is_array()   ? "an array"
         : j.is_object()  ? "a table/object"
                          : "null";
}

[[noreturn]] void Bad(const std::string& where, const std::string& what) {
  throw ValueError(where + ": " + what);
}

// The entries each control type reads.
const std::vector<std::string>& ControlKeys(const std::string& type) {
  static const std::map<std::string, std::vector<std::string>> keys = {
      {"constant", {"actuator", "type", "value"}},
      {"step", {"actuator", "type", "before", "value", "at"}},
      {"ramp", {"actuator", "type", "from", "to", "start", "end"}},
      {"sine", {"actuator", "type", "offset", "amplitude", "frequency", "phase"}},
  };
  return keys.at(type);
}

Scenario ReadScenario(const Model& model, const std::string& file, const json& j,
                      const Locator& at) {
  if (!j.is_object()) Bad(file, "a scenario must be a table/object, got " + std::string(KindOf(j)));
  static const std::vector<std::string> known = {"name",    "duration", "keyframe",
                                                 "initial", "controls", "assertions"};
  for (const auto& [key, value] : j.items()) {
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      Bad(at.At("", -1, key), "unknown entry '" + key +
                                  "'; known: name, duration, keyframe, initial, controls, "
                                  "assertions. " +
                                  DidYouMean(key, known));
    }
  }
  Scenario sc;
  sc.file = file;
  sc.name = file;
  if (j.contains("name")) {
    if (!j["name"].is_string())
      Bad(at.At("", -1, "name"), "must be a string, got " + j["name"].dump());
    sc.name = j["name"].get<std::string>();
  }
  sc.duration = Number(j, "duration", 2.0, at.At("", -1, "duration"));
  if (!(sc.duration > 0)) Bad(at.At("", -1, "duration"), "must be > 0 s");
  if (j.contains("keyframe")) {
    std::string where = at.At("", -1, "keyframe");
    if (!j["keyframe"].is_string()) {
      Bad(where, "must be a keyframe's name (a string), got " + j["keyframe"].dump() +
                     "; keyframes are referred to by name");
    }
    std::string key = j["keyframe"].get<std::string>();
    sc.keyframe = mj_name2id(model.get(), mjOBJ_KEY, key.c_str());
    if (sc.keyframe < 0) {
      std::vector<std::string> names;
      for (int k = 0; k < model->nkey; ++k) names.push_back(model.Name(mjOBJ_KEY, k));
      Bad(where, "no keyframe named '" + key + "'. " +
                     (names.empty() ? "The model has no named keyframe." : DidYouMean(key, names)));
    }
  }
  if (j.contains("initial")) {
    if (!j["initial"].is_object()) {
      Bad(at.At("", -1, "initial"), "'initial' maps paths to values, e.g. \"qpos[elbow]\" = 0.2");
    }
    for (const auto& [path, value] : j["initial"].items()) {
      std::string where = at.At("initial", -1, path);
      std::string values;
      if (value.is_array()) {
        for (const json& v : value) {
          if (!v.is_number()) Bad(where, "values must be numbers, got " + v.dump());
          values += (values.empty() ? "" : ",") + v.dump();
        }
      } else if (value.is_number() || value.is_string()) {
        values = value.is_string() ? value.get<std::string>() : value.dump();
      } else {
        Bad(where, "must be a number or an array of numbers, got " + value.dump());
      }
      try {
        sc.initial.push_back(ParseAssignment(model, path + "=" + values));
      } catch (const Error& e) {
        Bad(where, e.what());
      }
    }
  }
  if (j.contains("controls")) {
    if (!j["controls"].is_array()) {
      Bad(at.At("", -1, "controls"), "'controls' is a list of tables ([[controls]] in TOML), got " +
                                         std::string(KindOf(j["controls"])));
    }
    for (std::size_t i = 0; i < j["controls"].size(); ++i) {
      const json& c = j["controls"][i];
      int index = static_cast<int>(i);
      if (!c.is_object()) {
        Bad(at.At("controls", index, ""),
            "a control is a table with actuator and type, got " + c.dump());
      }
      ControlSchedule s;
      if (!c.contains("actuator") || !c["actuator"].is_string()) {
        Bad(at.At("controls", index, "actuator"), "give the actuator's name as a string");
      }
      s.actuator = c["actuator"].get<std::string>();
      s.id = mj_name2id(model.get(), mjOBJ_ACTUATOR, s.actuator.c_str());
      if (s.id < 0) {
        std::vector<std::string> names;
        for (int u = 0; u < model->nu; ++u) names.push_back(model.Name(mjOBJ_ACTUATOR, u));
        Bad(at.At("controls", index, "actuator"),
            "no actuator named '" + s.actuator + "'. " + DidYouMean(s.actuator, names));
      }
      s.type = "constant";
      if (c.contains("type")) {
        if (!c["type"].is_string()) Bad(at.At("controls", index, "type"), "must be a string");
        s.type = c["type"].get<std::string>();
      }
      if (s.type != "constant" && s.type != "step" && s.type != "ramp" && s.type != "sine") {
        Bad(at.At("controls", index, "type"),
            "type '" + s.type + "' is not one of constant, step, ramp, sine");
      }
      const std::vector<std::string>& keys = ControlKeys(s.type);
      for (const auto& [key, value] : c.items()) {
        if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
          std::string list;
          for (const std::string& k : keys) list += (list.empty() ? "" : ", ") + k;
          Bad(at.At("controls", index, key), "a " + s.type + " control has no entry '" + key +
                                                 "'; it reads " + list + ". " +
                                                 DidYouMean(key, keys));
        }
      }
      auto number = [&](const char* key, double fallback) {
        return Number(c, key, fallback, at.At("controls", index, key));
      };
      s.value = number(s.type == "sine" ? "offset" : "value", 0);
      s.before = number(s.type == "ramp" ? "from" : "before", 0);
      s.at = number("at", 0);
      s.start = number("start", 0);
      s.end = number("end", s.start);
      s.to = number("to", 0);
      s.amplitude = number("amplitude", 0);
      s.frequency = number("frequency", 0);
      s.phase = number("phase", 0);
      if (s.type == "ramp" && !(s.end > s.start)) {
        Bad(at.At("controls", index, "end"), "a ramp needs end > start");
      }
      sc.controls.push_back(s);
    }
  }
  if (j.contains("assertions")) {
    if (!j["assertions"].is_array()) {
      Bad(at.At("", -1, "assertions"),
          "'assertions' is a list of strings, e.g. [\"maxabs(qvel[*]) < 50\"]");
    }
    for (std::size_t i = 0; i < j["assertions"].size(); ++i) {
      const json& a = j["assertions"][i];
      std::string where = at.At("assertions", static_cast<int>(i), "");
      if (!a.is_string()) Bad(where, "an assertion is a string, got " + a.dump());
      Assertion parsed;
      try {
        parsed = ParseAssertion(model, a.get<std::string>());
      } catch (const Error& e) {
        Bad(where, e.what());
      }
      if (parsed.from > sc.duration || parsed.to > sc.duration) {
        Bad(where, fmt::format("the window [{:g}, {:g}] ends after the scenario's duration "
                               "({:g} s): shorten the window or raise duration",
                               parsed.from, parsed.to, sc.duration));
      }
      sc.assertions.push_back(std::move(parsed));
    }
  }
  return sc;
}

}  // namespace

Scenario LoadScenario(const Model& model, const std::string& file) {
  std::ifstream in(file);
  if (!in) throw IoError("cannot read scenario '" + file + "': no such file or not readable.");
  std::stringstream text;
  text << in.rdbuf();
  json j;
  bool toml = file.size() > 5 && file.substr(file.size() - 5) == ".toml";
  try {
    if (toml) {
      j = ToJson(toml::parse(text.str(), file));
    } else {
      j = json::parse(text.str());
    }
  } catch (const toml::parse_error& e) {
    // toml++ knows where: the line and column of the first problem
    throw ValueError(fmt::format("scenario '{}' is not valid TOML: line {}, column {}: {}", file,
                                 e.source().begin.line, e.source().begin.column,
                                 e.description()));
  } catch (const std::exception& e) {
    throw ValueError("scenario '" + file + "' is not valid " + (toml ? "TOML" : "JSON") + ": " +
                     e.what());
  }
  try {
    return ReadScenario(model, file, j, Locator(file, toml, text.str()));
  } catch (const json::exception& e) {
    // a shape the checks above missed: still bad input, never a crash
    throw ValueError("scenario '" + file + "': unexpected entry: " + e.what() +
                     ". See README \"Scenarios\" for the format.");
  }
}

}  // namespace plumb
