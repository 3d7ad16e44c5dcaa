// Reading a scenario file: JSON, or TOML through toml++ turned into the same JSON tree, so
// both formats share one reader. Every error names the entry: file:line:column for TOML (from
// toml++'s source positions), file and JSON pointer for JSON.

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <utility>

#include "core/input_file.h"
#include "core/mujoco_compat.h"
#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/scenario.h"

namespace plumb {
using internal::DidYouMean;
using internal::InputKind;
using internal::Join;
using internal::ReadInputFile;

namespace {

using nlohmann::json;

// Where each entry of a TOML file is, by JSON pointer ("/controls/0/value"): the key's
// line and column for a table entry, the element's for an array element.
using Positions = std::map<std::string, toml::source_position>;

// TOML -> JSON (dates and times, which no scenario entry takes, become their TOML text and
// are refused by the entry's type check), noting where each entry is.
json ToJson(const toml::node& node, const std::string& pointer, Positions* at) {
  if (const toml::table* table = node.as_table()) {
    json j = json::object();
    for (const auto& [key, value] : *table) {
      std::string name(key.str());
      (*at)[pointer + "/" + name] = key.source().begin;
      j[name] = ToJson(value, pointer + "/" + name, at);
    }
    return j;
  }
  if (const toml::array* array = node.as_array()) {
    json j = json::array();
    for (std::size_t i = 0; i < array->size(); ++i) {
      std::string item = pointer + "/" + std::to_string(i);
      (*at)[item] = (*array)[i].source().begin;
      j.push_back(ToJson((*array)[i], item, at));
    }
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

// Where an entry of a scenario file is, for messages: "stand.toml:12:1 (controls[1].type)"
// for TOML, "stand.json at /controls/1/type (controls[1].type)" for JSON.
class Locator {
 public:
  Locator(std::string file, std::optional<Positions> toml)
      : file_(std::move(file)), toml_(std::move(toml)) {}

  // `table`: "" (top level), "initial", "controls" or "assertions"; `index`: which
  // [[controls]] table (or which assertion), -1 for none; `key`: the entry ("" for the
  // table itself).
  std::string At(const std::string& table, int index, const std::string& key) const {
    std::string entry = table.empty() ? key : table;
    if (index >= 0) entry += "[" + std::to_string(index) + "]";
    if (!table.empty() && !key.empty()) entry += "." + key;
    std::string pointer = "/" + (table.empty() ? key : table);
    if (index >= 0) pointer += "/" + std::to_string(index);
    if (!table.empty() && !key.empty()) pointer += "/" + key;
    if (!toml_) return file_ + " at " + pointer + " (" + entry + ")";
    // an entry that is not there (a missing key) is placed at the table that lacks it
    for (std::string p = pointer; !p.empty(); p = p.substr(0, p.rfind('/'))) {
      auto found = toml_->find(p);
      if (found != toml_->end()) {
        return fmt::format("{}:{}:{} ({})", file_, found->second.line, found->second.column, entry);
      }
    }
    return file_ + " (" + entry + ")";
  }

 private:
  std::string file_;
  std::optional<Positions> toml_;
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

double Number(const json& j, const std::string& key, double fallback, const std::string& where) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_number()) Bad(where, "must be a number, got " + j[key].dump());
  double v = j[key].get<double>();
  if (!std::isfinite(v)) Bad(where, "is not finite");
  return v;
}

// Refuses entries of `object` not in `known`, naming the nearest known one.
void RefuseUnknown(const json& object, const std::vector<std::string>& known,
                   const std::function<std::string(const std::string&)>& where,
                   const std::string& what) {
  for (const auto& [key, value] : object.items()) {
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    Bad(where(key), what + " has no entry '" + key + "'; it reads " + Join(known, ", ") + ". " +
                        DidYouMean(key, known));
  }
}

// name, duration, keyframe.
void ReadHeader(const Model& model, const json& j, const Locator& at, Scenario* sc) {
  if (j.contains("name")) {
    if (!j["name"].is_string())
      Bad(at.At("", -1, "name"), "must be a string, got " + j["name"].dump());
    sc->name = j["name"].get<std::string>();
  }
  sc->duration = Number(j, "duration", 2.0, at.At("", -1, "duration"));
  if (!(sc->duration > 0)) Bad(at.At("", -1, "duration"), "must be > 0 s");
  if (!j.contains("keyframe")) return;
  std::string where = at.At("", -1, "keyframe");
  if (!j["keyframe"].is_string()) {
    Bad(where, "must be a keyframe's name (a string), got " + j["keyframe"].dump() +
                   "; keyframes are referred to by name");
  }
  std::string key = j["keyframe"].get<std::string>();
  sc->keyframe = mj_name2id(model.get(), mjOBJ_KEY, key.c_str());
  if (sc->keyframe < 0) {
    std::vector<std::string> names;
    for (int k = 0; k < model->nkey; ++k) names.push_back(model.Name(mjOBJ_KEY, k));
    Bad(where, "no keyframe named '" + key + "'. " +
                   (names.empty() ? "The model has no named keyframe." : DidYouMean(key, names)));
  }
}

// initial: path = value or [values].
void ReadInitial(const Model& model, const json& initial, const Locator& at, Scenario* sc) {
  if (!initial.is_object()) {
    Bad(at.At("", -1, "initial"), "'initial' maps paths to values, e.g. \"qpos[elbow]\" = 0.2");
  }
  for (const auto& [path, value] : initial.items()) {
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
      sc->initial.push_back(ParseAssignment(model, path + "=" + values));
    } catch (const Error& e) {
      Bad(where, e.what());
    }
  }
}

// The entries each control shape reads.
const std::vector<std::string>& ControlKeys(ControlShape shape) {
  static const std::map<ControlShape, std::vector<std::string>> keys = {
      {ControlShape::kConstant, {"actuator", "type", "value"}},
      {ControlShape::kStep, {"actuator", "type", "before", "value", "at"}},
      {ControlShape::kRamp, {"actuator", "type", "from", "to", "start", "end"}},
      {ControlShape::kSine, {"actuator", "type", "offset", "amplitude", "frequency", "phase"}},
  };
  return keys.at(shape);
}

ControlShape ReadShape(const json& c, const std::string& where) {
  if (!c.contains("type")) return ControlShape::kConstant;
  if (!c["type"].is_string()) Bad(where, "must be a string");
  std::string type = c["type"].get<std::string>();
  for (ControlShape shape :
       {ControlShape::kConstant, ControlShape::kStep, ControlShape::kRamp, ControlShape::kSine}) {
    if (type == ControlShapeName(shape)) return shape;
  }
  Bad(where, "type '" + type + "' is not one of constant, step, ramp, sine");
}

// controls[index]: {actuator, type, and the entries of its type}.
ControlSchedule ReadControl(const Model& model, const json& c, int index, const Locator& at) {
  auto where = [&](const std::string& key) { return at.At("controls", index, key); };
  if (!c.is_object())
    Bad(where(""), "a control is a table with actuator and type, got " + c.dump());
  ControlSchedule s;
  if (!c.contains("actuator") || !c["actuator"].is_string()) {
    Bad(where("actuator"), "give the actuator's name as a string");
  }
  s.actuator = c["actuator"].get<std::string>();
  s.id = mj_name2id(model.get(), mjOBJ_ACTUATOR, s.actuator.c_str());
  if (s.id < 0) {
    std::vector<std::string> names;
    for (int u = 0; u < compat::ActuatorCount(model.get()); ++u) {
      names.push_back(model.Name(mjOBJ_ACTUATOR, u));
    }
    Bad(where("actuator"),
        "no actuator named '" + s.actuator + "'. " + DidYouMean(s.actuator, names));
  }
  s.type = ReadShape(c, where("type"));
  std::string shape = ControlShapeName(s.type);
  RefuseUnknown(c, ControlKeys(s.type), where, "a " + shape + " control");
  auto number = [&](const char* key, double fallback) {
    return Number(c, key, fallback, where(key));
  };
  s.value = number(s.type == ControlShape::kSine ? "offset" : "value", 0);
  s.before = number(s.type == ControlShape::kRamp ? "from" : "before", 0);
  s.at = number("at", 0);
  s.start = number("start", 0);
  s.end = number("end", s.start);
  s.to = number("to", 0);
  s.amplitude = number("amplitude", 0);
  s.frequency = number("frequency", 0);
  s.phase = number("phase", 0);
  if (s.type == ControlShape::kRamp && !(s.end > s.start))
    Bad(where("end"), "a ramp needs end > start");
  return s;
}

void ReadAssertions(const Model& model, const json& list, const Locator& at, Scenario* sc) {
  if (!list.is_array()) {
    Bad(at.At("", -1, "assertions"),
        "'assertions' is a list of strings, e.g. [\"maxabs(qvel[*]) < 50\"]");
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const json& a = list[i];
    std::string where = at.At("assertions", static_cast<int>(i), "");
    if (!a.is_string()) Bad(where, "an assertion is a string, got " + a.dump());
    Assertion parsed;
    try {
      parsed = ParseAssertion(model, a.get<std::string>());
    } catch (const Error& e) {
      Bad(where, e.what());
    }
    if (parsed.from > sc->duration || parsed.to > sc->duration) {
      Bad(where, fmt::format("the window [{:g}, {:g}] ends after the scenario's duration "
                             "({:g} s): shorten the window or raise duration",
                             parsed.from, parsed.to, sc->duration));
    }
    sc->assertions.push_back(std::move(parsed));
  }
}

Scenario ReadScenario(const Model& model, const std::string& file, const json& j,
                      const Locator& at) {
  if (!j.is_object()) Bad(file, "a scenario must be a table/object, got " + std::string(KindOf(j)));
  RefuseUnknown(
      j, {"name", "duration", "keyframe", "initial", "controls", "assertions"},
      [&](const std::string& key) { return at.At("", -1, key); }, "a scenario");
  Scenario sc;
  sc.file = file;
  sc.name = file;
  ReadHeader(model, j, at, &sc);
  if (j.contains("initial")) ReadInitial(model, j["initial"], at, &sc);
  if (j.contains("controls")) {
    const json& controls = j["controls"];
    if (!controls.is_array()) {
      Bad(at.At("", -1, "controls"), "'controls' is a list of tables ([[controls]] in TOML), got " +
                                         std::string(KindOf(controls)));
    }
    for (std::size_t i = 0; i < controls.size(); ++i) {
      sc.controls.push_back(ReadControl(model, controls[i], static_cast<int>(i), at));
    }
  }
  if (j.contains("assertions")) ReadAssertions(model, j["assertions"], at, &sc);
  return sc;
}

}  // namespace

Scenario LoadScenario(const Model& model, const std::string& file) {
  std::string text = ReadInputFile(file, InputKind::kScenario);
  json j;
  bool toml = file.size() > 5 && file.substr(file.size() - 5) == ".toml";
  std::optional<Positions> positions;
  try {
    if (toml) {
      positions.emplace();
      j = ToJson(toml::parse(text, file), "", &*positions);
    } else {
      j = json::parse(text);
    }
  } catch (const toml::parse_error& e) {
    // toml++ knows where: the line and column of the first problem
    throw ValueError(fmt::format("scenario '{}' is not valid TOML: line {}, column {}: {}", file,
                                 e.source().begin.line, e.source().begin.column, e.description()));
  } catch (const std::exception& e) {
    throw ValueError("scenario '" + file + "' is not valid " + (toml ? "TOML" : "JSON") + ": " +
                     e.what());
  }
  try {
    return ReadScenario(model, file, j, Locator(file, std::move(positions)));
  } catch (const json::exception& e) {
    // a shape the checks above missed: still bad input, never a crash
    throw ValueError("scenario '" + file + "': unexpected entry: " + e.what() +
                     ". See docs/audit.md (plumb help audit) for the format.");
  }
}

}  // namespace plumb
