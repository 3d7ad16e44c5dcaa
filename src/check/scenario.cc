// Behaviour scenarios for plumb audit: JSON or TOML files with a start state, control
// schedules and assertions on paths over time windows.

#include <cpptoml.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/strings.h"
#include "plumb/audit.h"
#include "plumb/error.h"

namespace plumb {
namespace {

using nlohmann::json;

// TOML -> JSON, so both formats share one reader.
json ToJson(const std::shared_ptr<cpptoml::base>& node) {
  if (node->is_table()) {
    json j = json::object();
    for (const auto& [key, value] : *node->as_table()) j[key] = ToJson(value);
    return j;
  }
  if (node->is_table_array()) {
    json j = json::array();
    for (const auto& table : *node->as_table_array()) j.push_back(ToJson(table));
    return j;
  }
  if (node->is_array()) {
    json j = json::array();
    for (const auto& value : *node->as_array()) j.push_back(ToJson(value));
    return j;
  }
  if (auto v = node->as<double>()) return v->get();
  if (auto v = node->as<int64_t>()) return v->get();
  if (auto v = node->as<bool>()) return v->get();
  if (auto v = node->as<std::string>()) return v->get();
  return nullptr;
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

double Number(const json& j, const std::string& key, double fallback, const std::string& where) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_number()) {
    throw ValueError(where + ": '" + key + "' must be a number, got " + j[key].dump() + ".");
  }
  double v = j[key].get<double>();
  if (!std::isfinite(v)) throw ValueError(where + ": '" + key + "' is not finite.");
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

Scenario LoadScenario(const Model& model, const std::string& file) {
  std::ifstream in(file);
  if (!in) throw IoError("cannot read scenario '" + file + "': no such file or not readable.");
  std::stringstream text;
  text << in.rdbuf();
  json j;
  bool toml = file.size() > 5 && file.substr(file.size() - 5) == ".toml";
  try {
    if (toml) {
      std::istringstream stream(text.str());
      cpptoml::parser parser(stream);
      j = ToJson(parser.parse());
    } else {
      j = json::parse(text.str());
    }
  } catch (const std::exception& e) {
    throw ValueError("scenario '" + file + "' is not valid " + (toml ? "TOML" : "JSON") + ": " +
                     e.what());
  }
  if (!j.is_object()) throw ValueError("scenario '" + file + "' must be a table/object.");
  Scenario sc;
  sc.file = file;
  sc.name = j.value("name", file);
  for (const auto& [key, value] : j.items()) {
    static const char* known[] = {"name",    "duration", "keyframe",
                                  "initial", "controls", "assertions"};
    if (std::find(std::begin(known), std::end(known), key) == std::end(known)) {
      throw ValueError("scenario '" + file + "': unknown entry '" + key +
                       "'; known: name, duration, keyframe, initial, controls, assertions.");
    }
  }
  sc.duration = Number(j, "duration", 2.0, "scenario '" + file + "'");
  if (!(sc.duration > 0)) throw ValueError("scenario '" + file + "': duration must be > 0 s.");
  if (j.contains("keyframe")) {
    std::string key = j["keyframe"].is_string() ? j["keyframe"].get<std::string>() : "";
    sc.keyframe = mj_name2id(model.get(), mjOBJ_KEY, key.c_str());
    if (sc.keyframe < 0) {
      std::vector<std::string> names;
      for (int k = 0; k < model->nkey; ++k) names.push_back(model.Name(mjOBJ_KEY, k));
      throw ValueError(
          "scenario '" + file + "': no keyframe named '" + key + "'. " +
          (names.empty() ? "The model has no named keyframe." : DidYouMean(key, names)));
    }
  }
  if (j.contains("initial")) {
    if (!j["initial"].is_object()) {
      throw ValueError("scenario '" + file + "': 'initial' maps paths to values.");
    }
    for (const auto& [path, value] : j["initial"].items()) {
      std::string values;
      if (value.is_array()) {
        for (const json& v : value) values += (values.empty() ? "" : ",") + v.dump();
      } else {
        values = value.is_string() ? value.get<std::string>() : value.dump();
      }
      try {
        sc.initial.push_back(ParseAssignment(model, path + "=" + values));
      } catch (const Error& e) {
        throw ValueError("scenario '" + file + "', initial: " + e.what());
      }
    }
  }
  if (j.contains("controls")) {
    for (const json& c : j["controls"]) {
      ControlSchedule s;
      std::string where = "scenario '" + file + "', control " + c.dump();
      s.actuator = c.value("actuator", "");
      s.id = mj_name2id(model.get(), mjOBJ_ACTUATOR, s.actuator.c_str());
      if (s.id < 0) {
        std::vector<std::string> names;
        for (int u = 0; u < model->nu; ++u) names.push_back(model.Name(mjOBJ_ACTUATOR, u));
        throw ValueError(where + ": no actuator named '" + s.actuator + "'. " +
                         DidYouMean(s.actuator, names));
      }
      s.type = c.value("type", "constant");
      if (s.type != "constant" && s.type != "step" && s.type != "ramp" && s.type != "sine") {
        throw ValueError(where + ": type must be constant, step, ramp or sine.");
      }
      s.value = Number(c, s.type == "sine" ? "offset" : "value", 0, where);
      s.before = Number(c, s.type == "ramp" ? "from" : "before", 0, where);
      s.at = Number(c, "at", 0, where);
      s.start = Number(c, "start", 0, where);
      s.end = Number(c, "end", s.start, where);
      s.to = Number(c, "to", 0, where);
      s.amplitude = Number(c, "amplitude", 0, where);
      s.frequency = Number(c, "frequency", 0, where);
      s.phase = Number(c, "phase", 0, where);
      if (s.type == "ramp" && !(s.end > s.start))
        throw ValueError(where + ": a ramp needs end > start.");
      sc.controls.push_back(s);
    }
  }
  if (j.contains("assertions")) {
    for (const json& a : j["assertions"]) {
      if (!a.is_string()) throw ValueError("scenario '" + file + "': assertions are strings.");
      try {
        sc.assertions.push_back(ParseAssertion(model, a.get<std::string>()));
      } catch (const Error& e) {
        throw ValueError("scenario '" + file + "': " + e.what());
      }
    }
  }
  return sc;
}

}  // namespace plumb
