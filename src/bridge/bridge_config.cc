// The bridge's configuration file (TOML), with file:line in every complaint.

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "bridge/gamepad_script.h"
#include "core/input_file.h"
#include "core/strings.h"
#include "plumb/bridge.h"
#include "plumb/error.h"

namespace plumb {
namespace {

class Reader {
 public:
  // Records where each name was written in `positions` (for the messages of RunBridge).
  Reader(std::string path, BridgePositions* positions)
      : path_(std::move(path)), positions_(positions) {}

  // "FILE:LINE:COLUMN" of `node`, or the file when the node has no position.
  std::string At(const toml::node* node) const {
    if (node == nullptr || node->source().begin.line == 0) return path_;
    return fmt::format("{}:{}:{}", path_, node->source().begin.line, node->source().begin.column);
  }

  [[noreturn]] void Fail(const toml::node* node, const std::string& key,
                         const std::string& why) const {
    throw ValueError(fmt::format("{}: {}: {}", At(node), key, why));
  }

  double Number(const toml::table& t, const std::string& key, double fallback, double lo, double hi,
                const std::string& prefix = "") {
    const toml::node* node = t.get(key);
    if (node == nullptr) return fallback;
    std::optional<double> v = node->value<double>();
    if (!v) Fail(node, prefix + key, "must be a number");
    if (!(*v >= lo && *v <= hi))
      Fail(node, prefix + key, fmt::format("must be in [{:g}, {:g}]", lo, hi));
    return *v;
  }

  // A number as Number reads it that is also a whole number.
  double Whole(const toml::table& t, const std::string& key, double fallback, double lo,
               double hi) {
    double v = Number(t, key, fallback, lo, hi);
    if (v != std::floor(v)) Fail(t.get(key), key, "must be a whole number");
    return v;
  }

  std::string Choice(const toml::table& t, const std::string& key, const std::string& fallback,
                     const std::set<std::string>& choices) {
    const toml::node* node = t.get(key);
    if (node == nullptr) return fallback;
    std::optional<std::string> v = node->value<std::string>();
    std::string listed;
    for (const std::string& c : choices) listed += (listed.empty() ? "\"" : ", \"") + c + "\"";
    if (!v || choices.count(*v) == 0) Fail(node, key, "must be one of " + listed);
    return *v;
  }

  // A non-empty string, or "" when the key is absent.
  std::string Text(const toml::table& t, const std::string& key, const std::string& what,
                   const std::string& prefix = "") {
    const toml::node* node = t.get(key);
    if (node == nullptr) return "";
    std::optional<std::string> v = node->value<std::string>();
    if (!v || v->empty()) Fail(node, prefix + key, "must be " + what + " in quotes");
    (*positions_)[prefix + key] = At(node);
    return *v;
  }

  void OnlyKeys(const toml::table& t, const std::set<std::string>& known,
                const std::string& prefix) {
    for (const auto& [key, node] : t) {
      if (known.count(std::string(key.str())) == 0) {
        std::string listed;
        for (const std::string& k : known) listed += (listed.empty() ? "" : ", ") + k;
        Fail(&node, prefix + internal::Echo(key.str()), "unknown key (known: " + listed + ")");
      }
    }
  }

  // The table under `key`, or nullptr when absent.
  const toml::table* Table(const toml::table& t, const std::string& key) {
    const toml::node* node = t.get(key);
    if (node == nullptr) return nullptr;
    const toml::table* table = node->as_table();
    if (table == nullptr) Fail(node, key, "must be a table: [" + key + "]");
    return table;
  }

  // A list of non-empty names ("" too with `empty_ok`), or `fallback` when the key is absent.
  std::vector<std::string> Names(const toml::table& t, const std::string& key,
                                 const std::string& what, const std::string& prefix,
                                 std::vector<std::string> fallback = {}, bool empty_ok = false) {
    const toml::node* node = t.get(key);
    if (node == nullptr) return fallback;
    const toml::array* names = node->as_array();
    if (names == nullptr) Fail(node, prefix + key, "must be a list of " + what);
    std::vector<std::string> out;
    for (const toml::node& name : *names) {
      std::optional<std::string> v = name.value<std::string>();
      if (!v || (v->empty() && !empty_ok)) {
        Fail(&name, prefix + key, "every entry must be a name in quotes");
      }
      (*positions_)[fmt::format("{}{}[{}]", prefix, key, out.size())] = At(&name);
      out.push_back(*v);
    }
    return out;
  }

  bool Flag(const toml::table& t, const std::string& key, bool fallback,
            const std::string& prefix = "") {
    const toml::node* node = t.get(key);
    if (node == nullptr) return fallback;
    std::optional<bool> v = node->value<bool>();
    if (!v) Fail(node, prefix + key, "must be true or false");
    return *v;
  }

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  BridgePositions* positions_;
};

// The settings of fault `f` that its kind takes (a latency's delays, a noise's signal and
// sigma, ...) into `spec`, its text without the times; adds the keys it read to `keys`.
void ReadFaultSettings(Reader& r, const toml::table& f, const std::string& prefix, FaultSpec* spec,
                       std::set<std::string>* keys) {
  using Kind = FaultSpec::Kind;
  auto direction = [&] {
    keys->insert("direction");
    spec->state = r.Choice(f, "direction", "command", {"command", "state"}) == "state";
    return spec->state ? "states" : "commands";
  };
  auto motor = [&](bool required) {
    keys->insert("motor");
    if (required && f.get("motor") == nullptr)
      r.Fail(&f, prefix + "motor", "is missing: the motor's index");
    spec->motor = static_cast<int>(r.Number(f, "motor", -1, -1, 34, prefix));
    return spec->motor < 0 ? std::string("every motor") : fmt::format("motor {}", spec->motor);
  };
  switch (spec->kind) {
    case Kind::kLatency: {
      const char* d = direction();
      keys->insert({"fixed_ms", "jitter_ms"});
      spec->fixed = r.Number(f, "fixed_ms", 0, 0, 60000, prefix) / 1000;
      spec->jitter = r.Number(f, "jitter_ms", 0, 0, 60000, prefix) / 1000;
      spec->text = fmt::format("latency of {} ({:g} ms + up to {:g} ms)", d, spec->fixed * 1000,
                               spec->jitter * 1000);
      break;
    }
    case Kind::kDrop: {
      const char* d = direction();
      keys->insert("probability");
      spec->probability = r.Number(f, "probability", 0, 0, 1, prefix);
      spec->text = fmt::format("drop of {} (p = {:g})", d, spec->probability);
      break;
    }
    case Kind::kNoise: {
      keys->insert({"signal", "sigma", "bias"});
      spec->signal = r.Choice(
          f, "signal", "q",
          {"q", "dq", "tau_est", "gyro", "accel", "quat", "position", "velocity", "foot_force"});
      spec->sigma = r.Number(f, "sigma", 0, 0, 1e6, prefix);
      spec->bias = r.Number(f, "bias", 0, -1e6, 1e6, prefix);
      std::string who = motor(false);
      spec->text = fmt::format("noise on {} of {} (sigma {:g}, bias {:g})", spec->signal, who,
                               spec->sigma, spec->bias);
      break;
    }
    case Kind::kTorqueLimit: {
      keys->insert("limit");
      spec->limit = r.Number(f, "limit", 0, 0, 1e6, prefix);
      spec->text = fmt::format("torque limit {:g} N*m on {}", spec->limit, motor(false));
      break;
    }
    case Kind::kMotorFailure: {
      keys->insert("behavior");
      std::string who = motor(true);
      spec->stuck = r.Choice(f, "behavior", "zero", {"zero", "stuck"}) == "stuck";
      spec->text = fmt::format("{} failed ({})", who, spec->stuck ? "stuck" : "zero torque");
      break;
    }
    case Kind::kImuFreeze:
      spec->text = "IMU frozen";
      break;
    case Kind::kControllerPause:
      spec->text = "controller paused";
      break;
  }
}

FaultSpec ReadFault(Reader& r, const toml::table& f, const std::string& prefix) {
  using Kind = FaultSpec::Kind;
  static const std::map<std::string, Kind> kKinds = {{"latency", Kind::kLatency},
                                                     {"drop", Kind::kDrop},
                                                     {"noise", Kind::kNoise},
                                                     {"torque_limit", Kind::kTorqueLimit},
                                                     {"motor_failure", Kind::kMotorFailure},
                                                     {"imu_freeze", Kind::kImuFreeze},
                                                     {"controller_pause", Kind::kControllerPause}};
  std::set<std::string> names;
  for (const auto& [name, kind] : kKinds) names.insert(name);
  const toml::node* kind_node = f.get("kind");
  if (kind_node == nullptr)
    r.Fail(&f, prefix + "kind", "is missing (one of latency, drop, noise, ...)");
  std::string kind = r.Choice(f, "kind", "", names);
  FaultSpec spec;
  spec.kind = kKinds.at(kind);
  std::set<std::string> keys = {"kind", "start", "stop"};
  spec.start = r.Number(f, "start", 0, 0, INFINITY, prefix);
  spec.stop = r.Number(f, "stop", INFINITY, spec.start, INFINITY, prefix);
  std::string when = std::isfinite(spec.stop)
                         ? fmt::format(" from {:g} s to {:g} s", spec.start, spec.stop)
                         : fmt::format(" from {:g} s", spec.start);
  ReadFaultSettings(r, f, prefix, &spec, &keys);
  r.OnlyKeys(f, keys, prefix);
  spec.text += when;
  return spec;
}

BridgeImuSource ReadImu(Reader& r, const toml::table& imu, const std::string& key) {
  std::string prefix = key + ".";
  r.OnlyKeys(imu, {"quaternion", "gyroscope", "accelerometer", "body"}, prefix);
  BridgeImuSource source;
  source.quaternion = r.Text(imu, "quaternion", "a framequat sensor's name", prefix);
  source.gyroscope = r.Text(imu, "gyroscope", "a gyro sensor's name", prefix);
  source.accelerometer = r.Text(imu, "accelerometer", "an accelerometer sensor's name", prefix);
  source.body = r.Text(imu, "body", "a body's name", prefix);
  return source;
}

BridgeSportState ReadSportState(Reader& r, const toml::table& t) {
  r.OnlyKeys(t, {"publish", "base", "feet"}, "sport_state.");
  BridgeSportState s;
  s.publish = r.Flag(t, "publish", true, "sport_state.");
  s.base = r.Text(t, "base", "a body's name", "sport_state.");
  s.feet = r.Names(t, "feet", "site, geom or body names", "sport_state.");
  if (s.feet.size() > 4) {
    r.Fail(t.get("feet"), "sport_state.feet",
           fmt::format("{} feet, but SportModeState_ carries 4: name at most 4", s.feet.size()));
  }
  return s;
}

BridgeBand ReadBand(Reader& r, const toml::table& t) {
  const std::string p = "band.";
  r.OnlyKeys(t,
             {"body", "anchor", "stiffness", "damping", "length", "release_at", "release_button",
              "hold_stiffness", "hold_damping"},
             p);
  BridgeBand b;
  b.body = r.Text(t, "body", "a body's name", p);
  if (b.body.empty()) r.Fail(&t, p + "body", "is missing: the body the band holds");
  if (const toml::node* node = t.get("anchor")) {
    const toml::array* xyz = node->as_array();
    if (xyz == nullptr || xyz->size() != 3) r.Fail(node, p + "anchor", "must be [x, y, z] in m");
    for (std::size_t k = 0; k < 3; ++k) {
      std::optional<double> v = (*xyz)[k].value<double>();
      if (!v || !std::isfinite(*v)) r.Fail(node, p + "anchor", "must be [x, y, z] in m");
      b.anchor[k] = *v;
    }
  }
  b.stiffness = r.Number(t, "stiffness", b.stiffness, 0, 1e9, p);
  b.damping = r.Number(t, "damping", b.damping, 0, 1e9, p);
  b.length = r.Number(t, "length", NAN, 0, 1e3, p);
  b.hold_stiffness = r.Number(t, "hold_stiffness", NAN, 0, 1e9, p);
  b.hold_damping = r.Number(t, "hold_damping", NAN, 0, 1e9, p);
  b.release_at = r.Number(t, "release_at", INFINITY, 0, INFINITY, p);
  b.release_button = r.Text(t, "release_button", "a gamepad button's name", p);
  if (!b.release_button.empty() && bridge::ButtonBit(b.release_button) < 0) {
    std::string names;
    for (const char* n : bridge::kButtonNames)
      names += (names.empty() ? "" : ", ") + std::string(n);
    r.Fail(t.get("release_button"), p + "release_button",
           fmt::format("'{}' is not a gamepad button (buttons: {})",
                       internal::Echo(b.release_button), names));
  }
  return b;
}

BridgeGamepad ReadGamepad(Reader& r, const toml::table& t) {
  const std::string p = "gamepad.";
  r.OnlyKeys(t, {"events", "rate", "topics"}, p);
  BridgeGamepad g;
  g.events = r.Text(t, "events", "a file name", p);
  if (!g.events.empty() && std::filesystem::path(g.events).is_relative()) {
    g.events = (std::filesystem::path(r.path()).parent_path() / g.events).string();
  }
  g.rate = r.Number(t, "rate", g.rate, 1, 10000, p);
  g.topics = r.Names(t, "topics", "topic names", p, g.topics);
  if (g.topics.empty()) r.Fail(t.get("topics"), p + "topics", "names no topic");
  return g;
}

// Refuses a motor named twice (the flight recorder names its columns by motor, and a log with
// a column twice is one plumb replay refuses) and a list of empty slots only: a "" entry is a
// slot of the robot's the model has no motor for, and some slot must drive the model.
void CheckMotors(const Reader& r, const toml::table& table,
                 const std::vector<std::string>& motors) {
  const toml::array* nodes = table.get_as<toml::array>("motors");
  if (!motors.empty() &&
      std::all_of(motors.begin(), motors.end(), [](const std::string& m) { return m.empty(); })) {
    r.Fail(nodes, "motors",
           "every slot is empty (\"\"): name at least one actuator or joint of the model; "
           "\"\" marks only a slot of the robot's the model has no motor for");
  }
  for (std::size_t j = 0; j < motors.size(); ++j) {
    for (std::size_t i = 0; i < j; ++i) {
      if (motors[j].empty() || motors[i] != motors[j]) continue;
      r.Fail(nodes->get(j), "motors",
             fmt::format("'{}' is named twice, as motor {} (at {}) and motor {}: name each "
                         "motor once",
                         internal::Echo(motors[j]), i, r.At(nodes->get(i)), j));
    }
  }
}

}  // namespace

BridgeConfig LoadBridgeConfig(const std::string& path) {
  // a FIFO, a directory or /dev/zero is refused, not read: the user meant a file
  std::string text = internal::ReadInputFile(path, internal::InputKind::kBridgeConfig);
  toml::table table;
  try {
    table = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw ValueError(fmt::format("{}:{}:{}: {}", path, where.line, where.column, e.description()));
  }
  BridgeConfig c;
  Reader r(path, &c.positions);
  r.OnlyKeys(table,
             {"family", "mode", "domain", "control_period", "start_tick", "mode_machine", "motors",
              "check_crc", "log", "until", "watchdog", "imu", "secondary_imu", "sport_state",
              "band", "gamepad", "faults", "seed", "command_queue"},
             "");
  c.source = path;
  c.family =
      r.Choice(table, "family", "go", {"go", "hg"}) == "go" ? BridgeFamily::kGo : BridgeFamily::kHg;
  c.mode = r.Choice(table, "mode", "lockstep", {"lockstep", "realtime"}) == "lockstep"
               ? BridgeMode::kLockstep
               : BridgeMode::kRealtime;
  c.domain = static_cast<std::uint32_t>(r.Whole(table, "domain", 1, 0, 232));
  c.command_queue = static_cast<std::size_t>(r.Whole(table, "command_queue", 64, 1, 1e6));
  c.control_period = r.Number(table, "control_period", 0.002, 1e-5, 1);
  // at most 4e9: days of ticks are left before the 32-bit tick wraps
  c.start_tick = static_cast<std::uint32_t>(r.Whole(table, "start_tick", 1000, 1, 4e9));
  if (const toml::node* node = table.get("mode_machine"); node && c.family == BridgeFamily::kGo) {
    r.Fail(node, "mode_machine",
           "is a unitree_hg field (family = \"hg\"): unitree_go's LowState_ has none");
  }
  c.mode_machine = static_cast<int>(r.Whole(table, "mode_machine", -1, 0, 255));
  c.until = r.Number(table, "until", INFINITY, 0, INFINITY);
  c.check_crc = r.Flag(table, "check_crc", true);
  c.log = r.Text(table, "log", "a file name");
  // "": a slot of the robot's the model has no motor for
  c.motors = r.Names(table, "motors", "actuator or joint names", "", {}, true);
  CheckMotors(r, table, c.motors);
  if (const toml::table* w = r.Table(table, "watchdog")) {
    r.OnlyKeys(*w, {"timeout_ms", "kd", "patience_s"}, "watchdog.");
    c.watchdog_timeout = r.Number(*w, "timeout_ms", 100, 1, 60000, "watchdog.") / 1000;
    c.watchdog_kd = r.Number(*w, "kd", 1, 0, 1e6, "watchdog.");
    c.watchdog_patience = r.Number(*w, "patience_s", 10, 0.001, 86400, "watchdog.");
  }
  if (const toml::table* imu = r.Table(table, "imu")) c.imu = ReadImu(r, *imu, "imu");
  if (const toml::table* imu = r.Table(table, "secondary_imu")) {
    c.secondary_imu = ReadImu(r, *imu, "secondary_imu");
    c.secondary_imu_configured = true;
  }
  if (const toml::table* t = r.Table(table, "sport_state")) c.sport_state = ReadSportState(r, *t);
  if (const toml::table* t = r.Table(table, "band")) c.band = ReadBand(r, *t);
  if (const toml::table* t = r.Table(table, "gamepad")) c.gamepad = ReadGamepad(r, *t);
  double seed = r.Number(table, "seed", 0, 0, 9007199254740992.0);
  c.seed = static_cast<std::uint64_t>(seed);
  if (const toml::node* node = table.get("faults")) {
    const toml::array* faults = node->as_array();
    if (faults == nullptr) r.Fail(node, "faults", "must be an array of tables: [[faults]]");
    int index = 0;
    for (const toml::node& entry : *faults) {
      const toml::table* f = entry.as_table();
      std::string prefix = fmt::format("faults[{}].", index++);
      if (f == nullptr) r.Fail(&entry, prefix, "must be a table");
      c.faults.push_back(ReadFault(r, *f, prefix));
    }
  }
  return c;
}

}  // namespace plumb
