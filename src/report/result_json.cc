// The JSON documents of plumb's results (include/plumb/result_json.h).

#include "plumb/result_json.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "plumb/model.h"

namespace plumb {
namespace {

using Json = nlohmann::ordered_json;

Json Number(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

// The number, else the text, else null.
Json NumberOrText(const Quantity& q, const std::string& text) {
  if (q.known()) return q.value;
  if (text.empty()) return nullptr;
  return text;
}

Json RowJson(const CheckRow& row) {
  return {{"id", row.id},
          {"section", row.section},
          {"title", row.title},
          {"status", CheckStatusName(row.status)},
          {"element", row.About()},
          {"element_type", row.element.kind},
          {"element_name", row.element.name},
          {"element_id", row.element.id},
          {"measured", NumberOrText(row.measured, row.measured_text)},
          {"measured_unit", row.measured.unit},
          {"measured_text", row.measured_text},
          {"reference", NumberOrText(row.reference, row.reference_text)},
          {"reference_unit", row.reference.unit},
          {"reference_text", row.reference_text},
          {"threshold", row.threshold},
          {"rel_error", Number(row.rel_error)},
          {"explanation", row.explanation},
          {"fix", row.fix},
          {"accepted", row.accepted.empty() ? Json(nullptr) : Json(row.accepted)}};
}

Json NumberArray(const std::vector<double>& values) {
  Json out = Json::array();
  for (double v : values) out.push_back(Number(v));
  return out;
}

// One change of a diff: a trajectory's departure also says at which step.
Json ChangeJson(const SnapshotChange& c) {
  Json one = {{"path", c.path},
              {"old", Json::parse(c.old_value)},
              {"new", Json::parse(c.new_value)},
              {"kind", c.kind}};
  if (c.step > 0) one["step"] = c.step;
  one["what"] = c.what;
  return one;
}

// The rows by status, the accepted ones apart (as the tables count them).
Json Summary(const std::vector<CheckRow>& rows) {
  return {{"pass", CountUnaccepted(rows, CheckStatus::kPass)},
          {"warn", CountUnaccepted(rows, CheckStatus::kWarn)},
          {"fail", CountUnaccepted(rows, CheckStatus::kFail)},
          {"skip", CountUnaccepted(rows, CheckStatus::kSkip)},
          {"accepted", CountAccepted(rows)}};
}

}  // namespace

std::string VerifyToJson(const VerifyReport& report) {
  Json j;
  j["model"] = report.model;
  j["mujoco_version"] = MujocoVersion();
  j["tol"] = report.tol;
  j["start"] = report.start;
  const VerifyHorizon& h = report.horizon;
  j["horizon"] = {{"until", h.until},
                  {"requested", h.requested},
                  {"steps", h.steps},
                  {"shortened", h.shortened()},
                  {"why", h.why}};
  Json checks = Json::array();
  for (const CheckRow& row : report.checks) checks.push_back(RowJson(row));
  j["checks"] = checks;
  j["summary"] = Summary(report.checks);
  return j.dump(2) + "\n";
}

std::string AuditToJson(const AuditReport& report) {
  Json j;
  j["model"] = report.model;
  j["mujoco_version"] = MujocoVersion();
  j["start"] = report.start;
  Json layers = Json::object();
  for (const CheckRow& row : report.findings) layers[row.section].push_back(RowJson(row));
  j["layers"] = layers;
  j["repro_folders"] = report.repro_folders;
  j["summary"] = Summary(report.findings);
  return j.dump(2) + "\n";
}

std::string CrosscheckToJson(const CrosscheckReport& report) {
  Json j;
  j["model"] = report.model;
  j["mujoco_version"] = report.mujoco_version;
  const EngineInfo& e = report.engine;
  j["engine"] = {{"engine", e.engine},
                 {"engine_version", e.engine_version},
                 {"backend", e.backend},
                 {"mujoco_version", e.mujoco_version},
                 {"mujoco_library", e.mujoco_library},
                 {"device", e.device},
                 {"precision", e.precision}};
  j["model_transfer"] = report.model_transfer;
  Json checks = Json::array();
  for (const CheckRow& row : report.rows) checks.push_back(RowJson(row));
  j["checks"] = checks;
  Json divergence = Json::array();
  for (const DivergenceTrack& t : report.divergence) {
    divergence.push_back({{"signal", t.signal},
                          {"element", ElementLabel(t.element)},
                          {"threshold", t.threshold},
                          {"engine", NumberArray(t.engine)},
                          {"chaos", NumberArray(t.chaos)}});
  }
  j["divergence"] = divergence;
  const ThroughputFigures& f = report.throughput;
  j["throughput"] = {{"worlds", f.worlds},
                     {"steps", f.steps},
                     {"engine_steps_per_second", f.engine_steps_per_second},
                     {"engine_compile_seconds", f.engine_compile_seconds},
                     {"cpu_steps_per_second", f.cpu_steps_per_second},
                     {"cpu_threads", f.cpu_threads}};
  j["summary"] = Summary(report.rows);
  return j.dump(2) + "\n";
}

std::string ConvergeToJson(const ConvergenceResult& r) {
  Json j;
  j["metric"] = r.metric;
  j["model"] = r.model;
  j["integrator_expected_order"] = r.expected_order;
  Json levels = Json::array();
  for (const ConvergenceLevel& l : r.levels) {
    levels.push_back({{"dt", l.dt},
                      {"value", Number(l.value)},
                      {"diff", Number(l.diff)},
                      {"spread", Number(l.spread)},
                      {"order", Number(l.order)},
                      {"error", Number(l.error)},
                      {"error_is_richardson", l.error_is_richardson},
                      {"roundoff", l.roundoff}});
  }
  j["levels"] = levels;
  j["observed_order"] = r.estimate.resolved ? Number(r.estimate.order) : nullptr;
  j["order_resolved"] = r.estimate.resolved;
  j["extrapolated"] = Number(r.estimate.extrapolated);  // an estimate, not a measured level
  j["scale"] = r.scale;
  j["tol"] = r.tol;
  j["recommended_dt"] = r.recommended_dt > 0 ? Number(r.recommended_dt) : nullptr;
  j["contacts"] = r.max_contacts;
  j["caveat"] = r.caveat.empty() ? Json(nullptr) : Json(r.caveat);
  j["solref_floor"] = r.solref_floor > 0 ? Json(r.solref_floor) : Json(nullptr);
  j["solref_held"] = r.solref_held.empty() ? Json(nullptr) : Json(r.solref_held);
  j["note"] = r.ok ? r.estimate.note : r.problem;
  return j.dump(2) + "\n";
}

std::string DiffToJson(const SnapshotDiff& diff, const std::string& snapshot) {
  Json j;
  j["snapshot"] = snapshot;
  j["model"] = diff.model;
  j["identical"] = !diff.changed();
  j["tol"] = diff.tol;
  j["snapshot_plumb_version"] = diff.snapshot_plumb_version;
  j["snapshot_mujoco_version"] = diff.snapshot_mujoco_version;
  j["mujoco_version"] = MujocoVersion();
  j["snapshot_sets"] = diff.sets;
  j["sets"] = diff.model_sets;
  j["diverged"] = diff.diverged;
  j["notes"] = diff.notes;
  Json changes = Json::array();
  for (const SnapshotChange& c : diff.changes) changes.push_back(ChangeJson(c));
  j["changes"] = changes;
  Json compiler = Json::array();  // a compiler's change is never a trajectory's: no step
  for (const SnapshotChange& c : diff.compiler) compiler.push_back(ChangeJson(c));
  j["compiler_changes"] = compiler;
  return j.dump(2) + "\n";
}

std::string ReplayToJson(const std::string& model, const RobotLog& log,
                         const ReplayOptions& options, const ReplayResult& r) {
  Json j;
  j["model"] = model;
  j["log"] = log.source;
  j["window"] = options.window;
  j["input_delay"] = options.input_delay;
  j["sensor_delay"] = options.sensor_delay;
  Json signals = Json::array();
  for (const SignalFit& f : r.signals) {
    signals.push_back({{"column", f.column},
                       {"path", f.path},
                       {"samples", f.samples},
                       {"rms", Number(f.rms)},
                       {"max_abs", Number(f.max_abs)},
                       {"worst_time", f.worst_time},
                       {"fit", Number(f.fit)},
                       {"noise", Number(f.noise)},
                       {"noise_fit", Number(f.noise_fit)},
                       {"spread", Number(f.spread)},
                       {"fit_beyond_noise", Number(f.fit_beyond_noise)}});
  }
  j["signals"] = signals;
  j["fit"] = Number(r.fit);
  j["diverged"] = r.simulated.diverged;
  j["problem"] = r.simulated.problem;
  j["notes"] = r.notes;
  return j.dump(2) + "\n";
}

namespace {

// The residuals' diagnosis of a fit (plumb identify).
Json MisspecificationJson(const Misspecification& m) {
  Json signals = Json::array();
  for (const ResidualStructure& s : m.signals) {
    signals.push_back({{"log", s.log},
                       {"column", s.column},
                       {"samples", s.samples},
                       {"autocorrelation", Number(s.autocorrelation)},
                       {"autocorrelation_z", Number(s.autocorrelation_z)},
                       {"runs_z", Number(s.runs_z)},
                       {"structured", s.structured}});
  }
  return {{"detected", m.detected},
          {"reason", m.reason},
          {"threshold", m.threshold},
          {"false_alarm", m.false_alarm},
          {"structured", m.structured},
          {"before_cost", Number(m.before_cost)},
          {"after_cost", Number(m.after_cost)},
          {"worse_than_nominal", m.worse_than_nominal},
          {"signals", signals}};
}

}  // namespace

std::string IdentifyToJson(const std::string& model, const IdentifyResult& r,
                           const std::vector<RobotLog>& logs, DelayKind delay,
                           const HeldOutLog* validation) {
  Json j;
  j["model"] = model;
  Json estimates = Json::array();
  for (const Estimate& e : r.estimates) {
    estimates.push_back({{"path", e.path},
                         {"nominal", e.nominal},
                         {"value", e.value},
                         {"std_error", Number(e.std_error)},
                         {"classical_std_error", Number(e.classical_std_error)},
                         {"lo", Number(e.lo)},
                         {"hi", Number(e.hi)},
                         {"at_bound", e.at_bound},
                         {"sensitivity", Number(e.sensitivity)}});
  }
  j["estimates"] = estimates;
  Json correlation = Json::array();
  for (const std::vector<double>& row : r.correlation) correlation.push_back(NumberArray(row));
  j["correlation"] = correlation;
  j["singular_values"] = r.singular_values;
  if (delay != DelayKind::kNone) {
    j["delay"] = {{"kind", delay == DelayKind::kInput ? "ctrl" : "sensor"}, {"value", r.delay}};
  }
  j["first_solve"] = {{"iterations", r.first_pass_iterations}, {"cost", r.first_pass_cost}};
  j["iterations"] = r.iterations;  // of the noise-weighted solve
  j["solved_again"] = r.solved_again;
  j["weight_change"] = r.weight_change;
  j["converged"] = r.converged;
  j["termination"] = r.termination;
  j["runs"] = r.runs;  // simulations of the logs, for every solve and the standard errors
  j["jacobians"] = r.jacobians;
  j["jacobian_runs"] = r.jacobian_runs;
  j["runs_per_jacobian"] = r.runs_per_jacobian;
  j["start_unknowns"] = r.start_unknowns;
  j["start_groups"] = r.start_groups;
  j["relative_offset"] = Number(r.relative_offset);
  j["cost"] = r.cost;
  j["residual_variance"] = Number(r.residual_variance);
  j["std_errors"] = {{"kind", StdErrorKindName(r.std_errors.kind)},
                     {"bandwidth", r.std_errors.bandwidth},
                     {"why", r.std_errors.why}};
  j["misspecification"] = MisspecificationJson(r.misspecification);
  Json per_log = Json::array();
  for (std::size_t l = 0; l < logs.size(); ++l) {
    Json noise;
    for (std::size_t i = 0; i < logs[l].measured.size(); ++i) {
      noise[logs[l].measured[i].column] = Number(r.noise[l][i]);
    }
    per_log.push_back({{"log", logs[l].source},
                       {"fit_nominal", Number(r.before[l].fit)},
                       {"fit_fitted", Number(r.after[l].fit)},
                       {"noise", noise}});
  }
  j["logs"] = per_log;
  if (validation != nullptr) {
    j["validation"] = {{"log", validation->log->source},
                       {"fit_nominal", Number(validation->nominal.fit)},
                       {"fit_fitted", Number(validation->fitted.fit)}};
  }
  j["warnings"] = r.warnings;
  return j.dump(2) + "\n";
}

}  // namespace plumb

namespace plumb {
namespace {

Json ClientJson(const ClientEnding& c) {
  return {{"kind", ClientEndingName(c.kind)},
          {"exit_code", c.exit_code >= 0 ? Json(c.exit_code) : Json(nullptr)},
          {"signal", c.signal},
          {"time", Number(c.time)},
          {"wall", Number(c.wall)},
          {"last_lines", c.last_lines},
          {"text", c.text}};
}

Json ViewJson(const ClientView& v) {
  Json motors = Json::array();
  for (const ClientMotorView& m : v.motors) {
    motors.push_back({{"name", m.name},
                      {"commands", m.commands},
                      {"outside_range", m.outside_range},
                      {"worst_outside", Number(m.worst_outside)},
                      {"saturated", m.saturated},
                      {"saturated_fraction", Number(m.saturated_fraction)},
                      {"worst_torque", Number(m.worst_torque)},
                      {"tracking_rms", Number(m.tracking_rms)},
                      {"tracking_worst", Number(m.tracking_worst)}});
  }
  return {{"commands", v.commands},
          {"first_command", Number(v.first_command)},
          {"first_command_time", Number(v.first_command_time)},
          {"period_median", Number(v.period_median)},
          {"period_p95", Number(v.period_p95)},
          {"period_worst", Number(v.period_worst)},
          {"commands_per_period", Number(v.commands_per_period)},
          {"motors", motors},
          {"unknown_motors", v.unknown_motors},
          {"own_pd", v.own_pd}};
}

Json BridgeJson(const BridgeStats& b) {
  return {{"commands", b.commands},
          {"bad_crc", b.bad_crc},
          {"non_finite", b.non_finite},
          {"states", b.states},
          {"watchdog_trips", b.watchdog_trips},
          {"dropped_commands", b.dropped_commands},
          {"dropped_states", b.dropped_states},
          {"paused_commands", b.paused_commands},
          {"foreign_commands", b.foreign_commands},
          {"queue_drops", b.queue_drops},
          {"steps", b.steps},
          {"sport_states", b.sport_states},
          {"secondary_imu_states", b.secondary_imu_states},
          {"gamepad_messages", b.gamepad_messages},
          {"band_released", Number(b.band_released)},
          {"time", Number(b.time)},
          {"realtime_factor", Number(b.realtime_factor)},
          {"late_periods", b.late_periods},
          {"worst_lateness", Number(b.worst_lateness)},
          {"late_commands", b.late_commands},
          {"longest_wait", Number(b.longest_wait)},
          {"diverged", b.diverged},
          {"problem", b.problem}};
}

}  // namespace

std::string RehearsalToJson(const std::string& model, const RehearsalResult& r) {
  Json j;
  j["command"] = "rehearse";
  j["model"] = model;
  j["mujoco_version"] = MujocoVersion();
  j["passed"] = r.passed();
  Json rows = Json::array();
  for (const CheckRow& row : r.rows) rows.push_back(RowJson(row));
  j["rows"] = rows;
  j["summary"] = Summary(r.rows);
  j["client"] = ClientJson(r.client);
  j["view"] = ViewJson(r.view);
  j["bridge"] = BridgeJson(r.bridge);
  Json events = Json::array();
  for (const auto& [t, what] : r.trace.events)
    events.push_back({{"time", Number(t)}, {"what", what}});
  j["events"] = events;
  // the client's output is whatever it printed: bytes that are not UTF-8 are replaced
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace plumb
