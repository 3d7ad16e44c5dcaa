// The bridge's configuration file (TOML), with file:line in every complaint.

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>
#include <set>

#include "plumb/bridge.h"
#include "plumb/error.h"

namespace plumb {
namespace {

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void Fail(const toml::node* node, const std::string& key,
                         const std::string& why) const {
    std::string at = path_;
    if (node != nullptr && node->source().begin.line > 0) {
      at += fmt::format(":{}:{}", node->source().begin.line, node->source().begin.column);
    }
    throw ValueError(fmt::format("{}: {}: {}", at, key, why));
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

  void OnlyKeys(const toml::table& t, const std::set<std::string>& known,
                const std::string& prefix) {
    for (const auto& [key, node] : t) {
      if (known.count(std::string(key.str())) == 0) {
        std::string listed;
        for (const std::string& k : known) listed += (listed.empty() ? "" : ", ") + k;
        Fail(&node, prefix + std::string(key.str()), "unknown key (known: " + listed + ")");
      }
    }
  }

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace

BridgeConfig LoadBridgeConfig(const std::string& path) {
  toml::table table;
  try {
    table = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw ValueError(fmt::format("{}:{}:{}: {}", path, where.line, where.column, e.description()));
  }
  Reader r(path);
  r.OnlyKeys(table,
             {"family", "mode", "domain", "control_period", "motors", "check_crc", "log", "until",
              "watchdog"},
             "");
  BridgeConfig c;
  c.source = path;
  c.family =
      r.Choice(table, "family", "go", {"go", "hg"}) == "go" ? BridgeFamily::kGo : BridgeFamily::kHg;
  c.mode = r.Choice(table, "mode", "lockstep", {"lockstep", "realtime"}) == "lockstep"
               ? BridgeMode::kLockstep
               : BridgeMode::kRealtime;
  double domain = r.Number(table, "domain", 1, 0, 232);
  if (domain != std::floor(domain)) r.Fail(table.get("domain"), "domain", "must be a whole number");
  c.domain = static_cast<std::uint32_t>(domain);
  c.control_period = r.Number(table, "control_period", 0.002, 1e-5, 1);
  c.until = r.Number(table, "until", INFINITY, 0, INFINITY);
  if (const toml::node* node = table.get("check_crc")) {
    std::optional<bool> v = node->value<bool>();
    if (!v) r.Fail(node, "check_crc", "must be true or false");
    c.check_crc = *v;
  }
  if (const toml::node* node = table.get("log")) {
    std::optional<std::string> v = node->value<std::string>();
    if (!v || v->empty()) r.Fail(node, "log", "must be a file name");
    c.log = *v;
  }
  if (const toml::node* node = table.get("motors")) {
    const toml::array* names = node->as_array();
    if (names == nullptr) r.Fail(node, "motors", "must be a list of actuator or joint names");
    for (const toml::node& name : *names) {
      std::optional<std::string> v = name.value<std::string>();
      if (!v) r.Fail(&name, "motors", "every entry must be a name in quotes");
      c.motors.push_back(*v);
    }
  }
  if (const toml::node* node = table.get("watchdog")) {
    const toml::table* w = node->as_table();
    if (w == nullptr) r.Fail(node, "watchdog", "must be a table: [watchdog]");
    r.OnlyKeys(*w, {"timeout_ms", "kd"}, "watchdog.");
    c.watchdog_timeout = r.Number(*w, "timeout_ms", 100, 1, 60000, "watchdog.") / 1000;
    c.watchdog_kd = r.Number(*w, "kd", 1, 0, 1e6, "watchdog.");
  }
  return c;
}

}  // namespace plumb
