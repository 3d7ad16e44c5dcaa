// plumb.rehearse: a deployment rehearsal (plumb bridge --client, plumb/rehearse.h). The bridge
// runs the model as the robot, the client command drives it, and the library's verdict comes
// back as a result with typed rows, what plumb saw of the client, how it ended, the bridge's
// counts, the CLI's JSON and table and the HTML report.

#include "plumb/rehearse.h"

#include <fmt/format.h>

#include <cstdint>
#include <memory>
#include <utility>

#include "common.h"
#include "plumb/bridge.h"
#include "plumb/check_table.h"
#include "plumb/error.h"
#include "plumb/report.h"
#include "plumb/result_json.h"

PLUMB_PYTHON_ARG(EnvArg, "collections.abc.Mapping[str, str]")

namespace plumb::python {
namespace {

// plumb.RehearsalFailed, made once by BindRehearse (module state lives as long as the module).
PyObject* g_rehearsal_failed = nullptr;

// plumb.rehearse's result.
struct PyRehearsal {
  std::shared_ptr<PyModel> model;
  std::vector<Assignment> start;
  RehearsalSpec spec;
  RehearsalResult result;
  std::vector<Notice> notices;  // what the call said, the bridge's sentences among them
  std::string html;

  std::string Json() const { return RehearsalToJson(model->name(), result); }
  std::string Table() const {
    return RehearsalTable(model->name(), result, TableDetail::kFindings, "result.rows holds every row");
  }
  void WriteReport(const std::string& path) const {
    WriteRehearsalReport(path, model->model(), start, result,
                         PythonReportInfo("rehearse"));
  }
};

// `env`: a mapping of str to str (os.environ's kind), or None. TypeError naming `env` for
// anything else.
std::vector<std::pair<std::string, std::string>> Environment(nb::handle env) {
  std::vector<std::pair<std::string, std::string>> out;
  if (env.is_none()) return out;
  if (!nb::hasattr(env, "items") || nb::isinstance<nb::str>(env)) {
    throw nb::type_error(fmt::format("env: expected a mapping of str to str (such as "
                                     "{{'POLICY': 'walk.onnx'}}), not {}",
                                     nb::type_name(env.type()).c_str())
                             .c_str());
  }
  for (nb::handle item : env.attr("items")()) {
    nb::handle key = item[0], value = item[1];
    if (!nb::isinstance<nb::str>(key) || !nb::isinstance<nb::str>(value)) {
      throw nb::type_error(fmt::format("env: each name and value must be a str, not {}: {}",
                                       nb::type_name(key.type()).c_str(),
                                       nb::type_name(value.type()).c_str())
                               .c_str());
    }
    out.emplace_back(nb::cast<std::string>(key), nb::cast<std::string>(value));
  }
  return out;
}

// The call's keywords that are not the model's start.
struct RehearseArgs {
  std::string client;
  std::string config;  // a file, or "" for the defaults
  double until = 0;
  std::vector<std::string> assertions;
  std::optional<long long> domain;
  std::optional<std::string> mode;
  std::string cwd, output, log, gamepad, report;
  std::vector<std::pair<std::string, std::string>> env;
  double first_command_timeout = 0, grace = 0;
};

// The rehearsal's spec from the call's keywords: the configuration (its file, then the
// keywords on top, as the command line's flags go on top of --config) and the client.
RehearsalSpec Spec(const RehearseArgs& a) {
  RehearsalSpec spec;
  spec.config = a.config.empty() ? BridgeConfig{} : LoadBridgeConfig(a.config);
  spec.config.until = a.until;
  if (a.domain) {
    if (*a.domain < 0) {
      throw ArgumentError("domain", std::to_string(*a.domain),
                          "a DDS domain id is a whole number from 0 to 232");
    }
    spec.config.domain = static_cast<std::uint32_t>(std::min<long long>(*a.domain, UINT32_MAX));
  }
  if (a.mode) {
    if (*a.mode != "lockstep" && *a.mode != "realtime") {
      throw ArgumentError("mode", Quoted(*a.mode), "expected 'lockstep' or 'realtime'");
    }
    spec.config.mode = *a.mode == "realtime" ? BridgeMode::kRealtime : BridgeMode::kLockstep;
  }
  if (!a.log.empty()) spec.config.log = a.log;
  if (!a.gamepad.empty()) spec.config.gamepad.events = a.gamepad;
  spec.client.command = a.client;
  spec.client.directory = a.cwd;
  spec.client.environment = a.env;
  spec.client.first_command_timeout = a.first_command_timeout;
  spec.client.grace = a.grace;
  spec.client.output = a.output;
  return spec;
}

// Raises plumb.RehearsalFailed with the verdict's table, the result on its .result.
[[noreturn]] void RaiseFailed(const std::shared_ptr<PyRehearsal>& result) {
  nb::object shown = nb::cast(result);
  std::string table = result->Table();
  nb::object error = nb::steal(PyObject_CallFunction(g_rehearsal_failed, "s", table.c_str()));
  if (!error.is_valid()) throw nb::python_error();
  error.attr("result") = shown;
  PyErr_SetObject(g_rehearsal_failed, error.ptr());
  throw nb::python_error();
}

std::shared_ptr<PyRehearsal> CallRehearse(ModelArg model, const RehearseArgs& args,
                                          const std::optional<std::string>& keyframe, SetArg set,
                                          bool strict) {
  auto out = std::make_shared<PyRehearsal>();
  CallNotices notices;
  out->model = ToModel(model, notices.sink());
  std::vector<std::string> sets = SetTexts(set);
  out->spec = Spec(args);
  internal::RefuseOutputsOntoInputs(
      {{"report", args.report}, {"output", args.output},
       {args.log.empty() ? "the config's log" : "log", out->spec.config.log}},
      {{"the model", out->model->name()},
       {"the config file", args.config},
       {"the gamepad events file", out->spec.config.gamepad.events}});
  const Model& work = out->model->model();
  {
    MujocoCallScope scope;
    out->start = StartAssignments(work, out->model->Spec(keyframe, "", "", sets), notices.sink());
    for (const std::string& text : args.assertions) {
      out->spec.assertions.push_back(ParseRehearsalAssertion(work, out->spec.config, text));
    }
  }
  // the bridge's sentences come on its thread while the GIL is released: kept on the call's
  // notices (thread-safe) and issued with the rest when the call returns
  Notices* sink = notices.sink();
  out->result = RunLong([&](StopToken stop) {
    return Rehearse(
        work, out->start, out->spec, stop,
        [sink](const Notice& notice) { sink->Add(notice); }, sink);
  });
  notices.Issue();
  out->notices = notices.all();
  if (!args.report.empty()) {
    RunLong([&](StopToken) {
      out->WriteReport(args.report);
      return 0;
    });
  }
  if (strict && !out->result.passed()) RaiseFailed(out);
  return out;
}

void BindViews(nb::module_& m) {
  nb::class_<ClientEnding>(m, "ClientEnding", "How a rehearsal's client ended.")
      .def_prop_ro(
          "kind", [](const ClientEnding& e) { return std::string(ClientEndingName(e.kind)); },
          "'stopped' (on plumb's signal at the end), 'killed' (it ignored the signal for "
          "`grace` s), 'exited early', 'not started'")
      .def_ro("exit_code", &ClientEnding::exit_code, "its exit status when it exited, else -1")
      .def_ro("signal", &ClientEnding::signal, "the signal that ended it, else 0")
      .def_ro("time", &ClientEnding::time, "simulated time when it ended or was stopped, s")
      .def_ro("wall", &ClientEnding::wall, "s of wall time it ran")
      .def_ro("last_lines", &ClientEnding::last_lines, "its output's last lines")
      .def_ro("text", &ClientEnding::text, "\"exited with status 1 at t = 0.42 s\", ...")
      .def("__repr__",
           [](const ClientEnding& e) { return "<plumb.ClientEnding " + e.text + ">"; });

  nb::class_<ClientMotorView>(m, "ClientMotorView",
                              "What plumb saw of the client's commands to one motor.")
      .def_ro("name", &ClientMotorView::name)
      .def_ro("commands", &ClientMotorView::commands)
      .def_ro("outside_range", &ClientMotorView::outside_range,
              "commanded positions outside the joint's range")
      .def_ro("worst_outside", &ClientMotorView::worst_outside, "by how much at worst, rad or m")
      .def_ro("saturated", &ClientMotorView::saturated,
              "states where the law asked more torque than the motor has")
      .def_ro("saturated_fraction", &ClientMotorView::saturated_fraction)
      .def_ro("worst_torque", &ClientMotorView::worst_torque, "the largest |torque| asked, N*m")
      .def_ro("tracking_rms", &ClientMotorView::tracking_rms, "q_des - q, rad (nan: none)")
      .def_ro("tracking_worst", &ClientMotorView::tracking_worst)
      .def("__repr__", [](const ClientMotorView& v) {
        return fmt::format("<plumb.ClientMotorView {} commands={}>", v.name, v.commands);
      });

  nb::class_<ClientView>(m, "ClientView",
                         "What plumb saw of a rehearsal's client, whatever its own "
                         "configuration says.")
      .def_ro("commands", &ClientView::commands, "good commands from the controller in charge")
      .def_ro("first_command", &ClientView::first_command,
              "s of wall time from the client's start to its first command")
      .def_ro("first_command_time", &ClientView::first_command_time, "simulated time of it, s")
      .def_ro("period_median", &ClientView::period_median,
              "wall time between commands, s (nan with fewer than two)")
      .def_ro("period_p95", &ClientView::period_p95)
      .def_ro("period_worst", &ClientView::period_worst)
      .def_ro("commands_per_period", &ClientView::commands_per_period,
              "commands per control_period of simulated time")
      .def_ro("motors", &ClientView::motors, "a list of plumb.ClientMotorView, in motor order")
      .def_ro("unknown_motors", &ClientView::unknown_motors,
              "slots beyond the model's motors that the client commanded")
      .def_ro("own_pd", &ClientView::own_pd,
              "actuators of the model that add a PD of their own to the commanded one")
      .def("__repr__", [](const ClientView& v) {
        return fmt::format("<plumb.ClientView commands={} motors={}>", v.commands,
                           v.motors.size());
      });

  nb::class_<BridgeStats>(m, "BridgeStats", "What the bridge counted over a rehearsal.")
      .def_ro("commands", &BridgeStats::commands, "applied")
      .def_ro("bad_crc", &BridgeStats::bad_crc)
      .def_ro("non_finite", &BridgeStats::non_finite)
      .def_ro("states", &BridgeStats::states, "published")
      .def_ro("watchdog_trips", &BridgeStats::watchdog_trips)
      .def_ro("dropped_commands", &BridgeStats::dropped_commands)
      .def_ro("dropped_states", &BridgeStats::dropped_states)
      .def_ro("paused_commands", &BridgeStats::paused_commands)
      .def_ro("foreign_commands", &BridgeStats::foreign_commands)
      .def_ro("queue_drops", &BridgeStats::queue_drops)
      .def_ro("steps", &BridgeStats::steps)
      .def_ro("sport_states", &BridgeStats::sport_states)
      .def_ro("secondary_imu_states", &BridgeStats::secondary_imu_states)
      .def_ro("gamepad_messages", &BridgeStats::gamepad_messages)
      .def_ro("band_released", &BridgeStats::band_released)
      .def_ro("time", &BridgeStats::time, "simulated time at the end, s")
      .def_ro("realtime_factor", &BridgeStats::realtime_factor)
      .def_ro("late_periods", &BridgeStats::late_periods)
      .def_ro("worst_lateness", &BridgeStats::worst_lateness)
      .def_ro("late_commands", &BridgeStats::late_commands)
      .def_ro("longest_wait", &BridgeStats::longest_wait)
      .def_ro("diverged", &BridgeStats::diverged)
      .def_ro("problem", &BridgeStats::problem)
      .def("__repr__", [](const BridgeStats& s) {
        return fmt::format("<plumb.BridgeStats {:g} s, {} commands, {} states>", s.time,
                           s.commands, s.states);
      });
}

// .trace: the time axis the report draws.
nb::dict Trace(const RehearsalTrace& trace) {
  nb::dict signals;
  for (std::size_t i = 0; i < trace.signals.size() && i < trace.values.size(); ++i) {
    signals[trace.signals[i].c_str()] = Array(trace.values[i]);
  }
  nb::list events;
  for (const auto& [t, what] : trace.events) events.append(nb::make_tuple(t, what));
  nb::dict out;
  out["time"] = Array(trace.time);
  out["signals"] = signals;
  out["events"] = events;
  return out;
}

}  // namespace

void BindRehearse(nb::module_& m) {
  nb::object base = m.attr("Error");
  g_rehearsal_failed = PyErr_NewExceptionWithDoc(
      "plumb.RehearsalFailed",
      "plumb.rehearse(..., strict=True) did not pass: the message is the verdict's table, "
      ".result the plumb.RehearsalResult.",
      base.ptr(), nullptr);
  if (g_rehearsal_failed == nullptr) throw nb::python_error();
  m.attr("RehearsalFailed") = nb::borrow(g_rehearsal_failed);

  BindViews(m);
  nb::class_<PyRehearsal> type(
      m, "RehearsalResult",
      "plumb.rehearse's result: .passed, .rows (plumb.CheckRow: the assertions, the client's "
      "and the bridge's rows), .client (how it ended), .view (what plumb saw of it), .bridge "
      "(the bridge's counts), .trace, the CLI's JSON and table, and the HTML report.");
  type.def_prop_ro(
          "passed", [](const PyRehearsal& r) { return r.result.passed(); },
          "no FAIL row, and the bridge did not diverge")
      .def_prop_ro(
          "ok", [](const PyRehearsal& r) { return r.result.passed(); }, "the same as .passed")
      .def_prop_ro("rows", [](const PyRehearsal& r) { return RowList(r.result.rows); })
      .def_prop_ro(
          "client", [](const PyRehearsal& r) { return r.result.client; },
          "how the client ended: plumb.ClientEnding")
      .def_prop_ro(
          "view", [](const PyRehearsal& r) { return r.result.view; },
          "what plumb saw of the client: plumb.ClientView")
      .def_prop_ro(
          "bridge", [](const PyRehearsal& r) { return r.result.bridge; },
          "the bridge's counts: plumb.BridgeStats")
      .def_prop_ro(
          "summary",
          [](const PyRehearsal& r) { return BridgeSummary(r.result.bridge, r.spec.config); },
          "the bridge's counts in one paragraph, the line the command prints after the table")
      .def_prop_ro(
          "trace", [](const PyRehearsal& r) { return Trace(r.result.trace); },
          "the time axis: {'time': s simulated, 'signals': {name: values} (the asserted paths, "
          "q_des[m] and q[m]), 'events': [(t, what)]}, numpy arrays");
  AddResultMethods(type, "bridge --client");

  RehearsalClient defaults;
  m.def(
      "rehearse",
      [](ModelArg model, const std::string& client, double until, std::optional<FileArg> config,
         StringsArg assertions, std::optional<std::string> keyframe, SetArg set,
         std::optional<long long> domain, std::optional<std::string> mode,
         std::optional<FileArg> cwd, EnvArg env, double first_command_timeout, double grace,
         std::optional<FileArg> output, std::optional<FileArg> log,
         std::optional<FileArg> gamepad, std::optional<FileArg> report, bool strict) {
        RehearseArgs a;
        a.client = client;
        a.config = OptionalPathArg(config, "config");
        a.until = until;
        a.assertions = StringList(assertions, "assertions");
        a.domain = domain;
        a.mode = mode;
        a.cwd = OptionalPathArg(cwd, "cwd");
        a.env = Environment(env.object);
        a.first_command_timeout = first_command_timeout;
        a.grace = grace;
        a.output = OptionalPathArg(output, "output");
        a.log = OptionalPathArg(log, "log");
        a.gamepad = OptionalPathArg(gamepad, "gamepad");
        a.report = OptionalPathArg(report, "report");
        return CallRehearse(model, a, keyframe, set, strict);
      },
      nb::arg("model"), nb::arg("client"), nb::kw_only(), nb::arg("until"),
      nb::arg("config") = nb::none(), nb::arg("assertions") = nb::tuple(),
      nb::arg("keyframe") = nb::none(), nb::arg("set") = nb::none(),
      nb::arg("domain") = nb::none(), nb::arg("mode") = nb::none(), nb::arg("cwd") = nb::none(),
      nb::arg("env") = nb::none(),
      nb::arg("first_command_timeout") = defaults.first_command_timeout,
      nb::arg("grace") = defaults.grace, nb::arg("output") = nb::none(),
      nb::arg("log") = nb::none(), nb::arg("gamepad") = nb::none(),
      nb::arg("report") = nb::none(), nb::arg("strict") = false,
      "Rehearses a deployment (plumb bridge --client): the bridge runs the model as the robot "
      "over DDS for `until` s of simulated time while `client`, a command line run by /bin/sh "
      "(a vendor's deploy script; '{domain}' in it is the DDS domain, also in "
      "$PLUMB_BRIDGE_DOMAIN), drives it; then the client is stopped (SIGINT, SIGKILL after "
      "`grace` s) and the verdict comes back. `config` is the bridge's TOML file (None: the "
      "defaults); `domain`, `mode` ('lockstep' or 'realtime'), `log` and `gamepad` go on top of "
      "it; `assertions` are plumb's scenario language over the model's paths and the motors' "
      "tracking_error[M], torque[M] and saturated[M] ('xpos[base][2] > 0.2'); `cwd` and `env` "
      "(a dict set on top of this process's environment) are the client's, `output` a file for "
      "its whole output, `first_command_timeout` the s of wall time it has for its first "
      "command; `report` writes the HTML report. Returns a RehearsalResult; with `strict` a "
      "rehearsal that does not pass raises plumb.RehearsalFailed. The bridge's sentences are "
      "issued as plumb.PlumbWarning when the call returns. Raises plumb.Error subclasses for "
      "bad input and KeyboardInterrupt on Ctrl-C (the client is stopped first).");
}

}  // namespace plumb::python
