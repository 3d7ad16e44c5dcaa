// The verify protocol: load, determinism, warnings, convergence, energy, and for a
// single hinge pendulum the analytic references, experiments and exercises of chapter 1.

#include "plumb/verify.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "core/geometry.h"
#include "core/mujoco_compat.h"
#include "plumb/analytic.h"
#include "plumb/converge.h"
#include "plumb/error.h"
#include "plumb/metric.h"
#include "plumb/run.h"
#include "plumb/timing.h"

namespace plumb {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// a step small enough that RK4 is exact to round-off on the chapter's pendulum
constexpr double kReferenceDt = 1e-4;

double RelError(double measured, double reference) {
  return std::fabs(measured - reference) / std::max(std::fabs(reference), 1e-300);
}

CheckResult Row(std::string id, std::string title) {
  CheckResult r;
  r.id = std::move(id);
  r.title = std::move(title);
  r.measured_value = r.reference_value = r.rel_error = kNaN;
  return r;
}

CheckResult Skip(std::string id, std::string title, std::string why) {
  CheckResult r = Row(std::move(id), std::move(title));
  r.status = CheckStatus::kSkip;
  r.detail = std::move(why);
  return r;
}

void SetNumbers(CheckResult* r, double measured, double reference, const char* unit,
                const char* spec = "{:.10g}") {
  r->measured_value = measured;
  r->reference_value = reference;
  r->rel_error = RelError(measured, reference);
  r->measured = fmt::format(fmt::runtime(spec), measured) + unit;
  r->reference = fmt::format(fmt::runtime(spec), reference) + unit;
}

// Everything a check needs from one run, sampled at every step.
struct Trace {
  std::vector<double> t;
  std::vector<double> energy;               // potential + kinetic, J
  std::vector<double> kinetic;              // J
  std::vector<std::vector<double>> coords;  // each hinge/slide joint's qpos over time
  std::vector<std::string> coord_names;
  std::vector<double> final_state;  // qpos, qvel, act at the end
  int max_ncon = 0;
  int max_nefc = 0;
  RunResult result;
};

class TraceSink : public SampleSink {
 public:
  TraceSink(Trace* trace, bool energy) : trace_(trace), energy_(energy) {}
  void Begin(const std::vector<Path>&) override {}
  void Sample(const std::vector<double>& row) override {
    trace_->t.push_back(row[0]);
    std::size_t first = 1;
    if (energy_) {
      trace_->energy.push_back(row[1] + row[2]);
      trace_->kinetic.push_back(row[2]);
      trace_->max_ncon = std::max(trace_->max_ncon, static_cast<int>(row[3]));
      trace_->max_nefc = std::max(trace_->max_nefc, static_cast<int>(row[4]));
      first = 5;
    }
    for (std::size_t c = 0; c < trace_->coords.size(); ++c) {
      trace_->coords[c].push_back(row[first + c]);
    }
  }

 private:
  Trace* trace_;
  bool energy_;
};

// The scenario under test: the nominal model with the user's assignments.
class Scenario {
 public:
  Scenario(const Model& model, const VerifyOptions& options)
      : model_(model), sets_(options.sets), nominal_(model.Clone()) {
    Data data(nominal_);
    ApplyAssignments(nominal_, data, sets_);
  }

  const Model& model() const { return model_; }
  const std::vector<Assignment>& sets() const { return sets_; }

  Assignment Set(const std::string& text) const { return ParseAssignment(model_, text); }

  // Runs the scenario plus `extra` assignments (applied after the user's) for `until` s.
  // With `energy`, the trace also holds energy and contact counts, which cost one more
  // mj_forward per step; without, those stay empty. Runs are deterministic, so a repeated
  // request is answered from memory.
  const Trace& Simulate(const std::vector<Assignment>& extra, double until,
                        bool energy = false) const {
    std::string key = fmt::format("{:.17g}", until);
    for (const Assignment& a : extra) key += "|" + a.text;
    auto found = memo_.find(key + "|energy");
    if (found != memo_.end()) return found->second;
    if (!energy) {
      found = memo_.find(key);
      if (found != memo_.end()) return found->second;
    }
    return memo_[energy ? key + "|energy" : key] = SimulateAnew(extra, until, energy);
  }

  // Runs without looking in memory (determinism needs a second real run).
  Trace SimulateAnew(const std::vector<Assignment>& extra, double until, bool energy) const {
    Model work = model_.Clone();
    if (energy) work.get_mutable()->opt.enableflags |= mjENBL_ENERGY;
    Data data(work);
    std::vector<Assignment> all = sets_;
    all.insert(all.end(), extra.begin(), extra.end());
    ApplyAssignments(work, data, all);
    const mjModel* m = work.get();
    Trace trace;
    RunSpec spec;
    spec.until = until;
    spec.every = m->opt.timestep;
    spec.columns = {ResolvePath(work, "time")};
    if (energy) {
      for (const char* path : {"energy[0]", "energy[1]", "ncon", "nefc"}) {
        spec.columns.push_back(ResolvePath(work, path));
      }
    }
    for (int j = 0; j < m->njnt; ++j) {
      if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) continue;
      std::string name = work.Name(mjOBJ_JOINT, j);
      Path p = ResolvePath(work, "qpos[" + std::to_string(m->jnt_qposadr[j]) + "]");
      p.text = name.empty() ? p.text : "qpos[" + name + "]";
      spec.columns.push_back(p);
      trace.coord_names.push_back(p.text);
    }
    trace.coords.resize(trace.coord_names.size());
    TraceSink sink(&trace, energy);
    trace.result = Run(work, data, spec, sink);
    const mjData* d = data.get();
    trace.final_state.assign(d->qpos, d->qpos + m->nq);
    trace.final_state.insert(trace.final_state.end(), d->qvel, d->qvel + m->nv);
    trace.final_state.insert(trace.final_state.end(), d->act, d->act + m->na);
    TakeMujocoWarnings();
    return trace;
  }

  // The model after the user's assignments (for reading nominal parameters).
  const Model& Nominal() const { return nominal_; }

 private:
  const Model& model_;
  std::vector<Assignment> sets_;
  Model nominal_;
  mutable std::map<std::string, Trace> memo_;
};

std::string Seconds(double t) { return fmt::format("{:g} s", t); }

// ---- load --------------------------------------------------------------------------------

CheckResult CheckLoad(const Model& model) {
  CheckResult r = Row("load", "the model compiles without warnings");
  const mjModel* m = model.get();
  double total = 0;
  int moving = 0;
  for (int b = 1; b < m->nbody; ++b) {
    total += m->body_mass[b];
    if (m->body_weldid[b] != 0) ++moving;
  }
  r.measured = fmt::format("{:.6g} kg in {} bodies", total, m->nbody - 1);
  r.measured_value = total;
  std::string bodies;
  for (int b = 1; b < m->nbody && b <= 6; ++b) {
    std::string name = model.Name(mjOBJ_BODY, b);
    bodies += fmt::format("{}{} {:.4g} kg, I = ({:.4g}, {:.4g}, {:.4g}) kg*m^2",
                          bodies.empty() ? "" : "; ", name.empty() ? "#" + std::to_string(b) : name,
                          m->body_mass[b], m->body_inertia[3 * b], m->body_inertia[3 * b + 1],
                          m->body_inertia[3 * b + 2]);
  }
  if (m->nbody > 7) bodies += fmt::format("; ... ({} more)", m->nbody - 7);
  if (model.compile_warnings().empty()) {
    r.status = CheckStatus::kPass;
    r.detail = fmt::format("compiled cleanly: {} moving bodies, {} dofs. As compiled: {}.", moving,
                           m->nv, bodies);
  } else {
    r.status = CheckStatus::kWarn;
    r.detail = "MuJoCo's compiler warned: " + model.compile_warnings();
  }
  return r;
}

// ---- determinism -----------------------------------------------------------------------

CheckResult CheckDeterminism(const Scenario& s, const Trace& first, double until) {
  CheckResult r = Row("determinism", "the same run twice is bit-identical");
  Trace second = s.SimulateAnew({}, until, /*energy=*/true);
  bool same = first.final_state.size() == second.final_state.size() &&
              std::memcmp(first.final_state.data(), second.final_state.data(),
                          first.final_state.size() * sizeof(double)) == 0 &&
              first.energy.size() == second.energy.size() &&
              std::memcmp(first.energy.data(), second.energy.data(),
                          first.energy.size() * sizeof(double)) == 0;
  r.measured = same ? "identical" : "different";
  r.reference = "identical";
  r.status = same ? CheckStatus::kPass : CheckStatus::kFail;
  r.detail = same ? fmt::format("two runs of {} gave the same state and energy to the last bit",
                                Seconds(until))
                  : "two runs from the same state differ: something non-deterministic (a "
                    "callback, uninitialised memory or threads) enters the simulation";
  return r;
}

// ---- warnings ----------------------------------------------------------------------------

CheckResult CheckWarnings(const Trace& nominal, double until) {
  CheckResult r = Row("warnings", "no MuJoCo warning and no divergence in the nominal run");
  r.reference = "none";
  if (nominal.result.diverged) {
    r.status = CheckStatus::kFail;
    r.measured = "diverged";
    r.detail = nominal.result.divergence->reason +
               " Shrink the timestep and check masses and inertias (plumb run writes a repro).";
    return r;
  }
  if (nominal.result.warnings.empty()) {
    r.status = CheckStatus::kPass;
    r.measured = "none";
    r.detail = fmt::format("{} of simulation raised no warning and stayed finite", Seconds(until));
    return r;
  }
  std::vector<std::string> kinds;
  for (const WarningSummary& w : nominal.result.warnings) {
    kinds.push_back(
        fmt::format("{} x{} (first at t = {:g} s: {})", w.kind, w.count, w.first_time, w.message));
  }
  r.status = CheckStatus::kWarn;
  r.measured = fmt::format("{} kind(s)", kinds.size());
  r.detail = "MuJoCo warned: " + fmt::format("{}", fmt::join(kinds, "; ")) +
             ". A warning means results were truncated or reset; it is not a log line to ignore.";
  return r;
}

// ---- convergence -------------------------------------------------------------------------

CheckResult CheckConvergence(const Scenario& s, const std::optional<PendulumParams>& pendulum,
                             const Trace& nominal, double until, double tol) {
  CheckResult r = Row("convergence", "the result converges as the timestep shrinks");
  if (!nominal.kinetic.empty() &&
      *std::max_element(nominal.kinetic.begin(), nominal.kinetic.end()) == 0) {
    return Skip(r.id, r.title, "nothing moves in the nominal run: every timestep gives the same");
  }
  const mjModel* m = s.Nominal().get();
  double dt = m->opt.timestep;
  std::string joint = pendulum ? s.Nominal().Name(mjOBJ_JOINT, pendulum->joint) : "";
  if (joint.empty() && pendulum) joint = std::to_string(m->jnt_qposadr[pendulum->joint]);
  std::string metric_text =
      pendulum ? fmt::format("qpos[{}]@{:g}", joint, until) : fmt::format("state@{:g}", until);
  Metric metric = ParseMetric(s.model(), metric_text);
  ConvergenceResult c = Converge(s.model(), s.sets(), metric, 2 * dt, 4, tol, until);
  double expected = ExpectedOrder(m->opt.integrator);
  std::string integrator = compat::NameOf(compat::kIntegrators, m->opt.integrator);
  bool contacts = nominal.max_ncon > 0;
  std::string caveat = contacts ? " Caveat: " + ContactCaveat(nominal.max_ncon) + "." : "";
  if (!c.ok) {
    bool only_coarsest = c.problem.rfind(fmt::format("at dt = {:.3g} s", 2 * dt), 0) == 0 &&
                         std::isfinite(c.levels[1].value);
    r.status = CheckStatus::kWarn;
    r.measured = "a level diverged";
    r.detail = c.problem;
    if (!only_coarsest) r.status = CheckStatus::kFail;
    return r;
  }
  const ConvergenceLevel& own = c.levels[1];  // the model's own timestep
  r.reference = fmt::format("tol {:g} x scale {:.3g}", tol, c.scale);
  r.reference_value = tol * c.scale;
  std::string levels;
  for (const ConvergenceLevel& l : c.levels) {
    levels += fmt::format("{}dt={:g}: {:.10g}", levels.empty() ? "" : ", ", l.dt, l.value);
  }
  if (!c.estimate.resolved) {
    if (c.estimate.noise_from >= 0 && c.estimate.noise_from <= 1) {
      r.status = CheckStatus::kPass;
      r.measured = "round-off";
      r.detail = fmt::format("{} at dt and dt/2 already agree to round-off ({}): converged. {}.{}",
                             metric_text, levels, c.estimate.note, caveat);
    } else {
      r.status = CheckStatus::kWarn;
      r.measured = "no order visible";
      r.detail = fmt::format("{}: {}. Levels {}.{}", metric_text, c.estimate.note, levels, caveat);
    }
    return r;
  }
  r.measured =
      fmt::format("error {:.3g} at dt = {:g} s (order {:.2f})", own.error, dt, c.estimate.order);
  r.measured_value = own.error;
  r.rel_error = own.error / c.scale;
  bool order_as_expected = std::fabs(c.estimate.order - expected) <= 0.5;
  std::string advice =
      c.recommended_dt > 0
          ? fmt::format("the largest timestep that would pass is {:g} s (a tested level)",
                        c.recommended_dt)
          : std::string("no tested timestep passes");
  if (own.error <= tol * c.scale) {
    r.status = CheckStatus::kPass;
    r.detail = fmt::format(
        "{} with {} at dt = {:g} s is within {:.2g}% of the extrapolated {:.10g}; observed order "
        "{:.2f} (expected {:g} for {}). Levels {}.",
        metric_text, integrator, dt, 100 * own.error / c.scale, c.estimate.extrapolated,
        c.estimate.order, expected, integrator, levels);
    if (!order_as_expected) r.detail += " The order differs from the integrator's.";
    r.detail += caveat;
  } else {
    // a clean asymptotic sequence proves the error; contacts or an odd order only suggest it
    r.status = order_as_expected && !contacts ? CheckStatus::kFail : CheckStatus::kWarn;
    r.detail = fmt::format(
        "not converged: {} at dt = {:g} s is off by {:.3g} ({:.2g}% of its scale {:.3g}), more "
        "than tol {:g}; {}. Observed order {:.2f} (expected {:g} for {}).{} Levels {}.",
        metric_text, dt, own.error, 100 * own.error / c.scale, c.scale, tol, advice,
        c.estimate.order, expected, integrator, caveat, levels);
  }
  return r;
}

// ---- energy ------------------------------------------------------------------------------

// Why a model is not passive in the sense of the energy check, or "".
std::string NotPassive(const Scenario& s, const Trace& nominal) {
  const mjModel* m = s.Nominal().get();
  std::string pushing = ActuatorPushingAtZeroControl(s.Nominal());
  if (!pushing.empty()) return pushing;
  for (const Assignment& a : s.sets()) {
    bool input = a.path.field == "ctrl" || a.path.field == "qfrc_applied" ||
                 a.path.field == "xfrc_applied" || a.path.field == "mocap_pos";
    if (input && std::any_of(a.values.begin(), a.values.end(), [](double v) { return v != 0; }))
      return "--set '" + a.text + "' drives it";
  }
  if (m->neq > 0) return "it has equality constraints";
  if (nominal.max_ncon > 0)
    return "contacts occur (MuJoCo's soft contacts bound energy only roughly)";
  // dry friction adds one constraint row per dof or tendon all the time; more rows than
  // that are joint or tendon limits at work, whose soft springs store energy E omits
  int friction_rows = 0;
  for (int i = 0; i < m->nv; ++i) friction_rows += m->dof_frictionloss[i] > 0;
  for (int i = 0; i < m->ntendon; ++i) friction_rows += m->tendon_frictionloss[i] > 0;
  if (nominal.max_nefc > friction_rows)
    return "a joint or tendon limit engages (its soft constraint stores energy that E omits)";
  if (m->opt.density != 0 || m->opt.viscosity != 0) return "it has fluid forces";
  for (int i = 0; i < m->ntendon; ++i) {
    if (m->tendon_damping[i] != 0 || m->tendon_frictionloss[i] != 0) return "it has damped tendons";
  }
  if (m->nmocap > 0) return "it has mocap bodies that can push it";
  return "";
}

bool Dissipative(const mjModel* m) {
  for (int i = 0; i < m->nv; ++i) {
    if (m->dof_damping[i] != 0 || m->dof_frictionloss[i] != 0) return true;
  }
  return false;
}

// Largest rise of total energy above its running minimum.
double LargestRise(const std::vector<double>& energy) {
  double low = energy.empty() ? 0 : energy[0], rise = 0;
  for (double e : energy) {
    low = std::min(low, e);
    rise = std::max(rise, e - low);
  }
  return rise;
}

CheckResult CheckEnergy(const Scenario& s, const Trace& nominal, double until, double tol) {
  CheckResult r = Row("energy", "total energy is conserved, or only decreases when damped");
  const mjModel* m = s.Nominal().get();
  if (nominal.result.diverged) return Skip(r.id, r.title, "the nominal run diverged");
  std::string why = NotPassive(s, nominal);
  if (!why.empty()) return Skip(r.id, r.title, "no energy bound applies: " + why);
  double max_kinetic = *std::max_element(nominal.kinetic.begin(), nominal.kinetic.end());
  if (max_kinetic <= 0) return Skip(r.id, r.title, "nothing moves in the nominal run");
  double e0 = nominal.energy.front();
  auto [lo, hi] = std::minmax_element(nominal.energy.begin(), nominal.energy.end());

  if (!Dissipative(m)) {
    // conservative: the relative drift of total energy is integration error
    double drift = std::max(std::fabs(*hi - e0), std::fabs(*lo - e0)) / max_kinetic;
    r.measured = fmt::format("{:.3g} of max KE", drift);
    r.reference = fmt::format("<= {:g}", tol);
    r.measured_value = drift;
    r.reference_value = tol;
    r.status = drift <= tol        ? CheckStatus::kPass
               : drift <= 10 * tol ? CheckStatus::kWarn
                                   : CheckStatus::kFail;
    r.detail = fmt::format(
        "nothing dissipates energy, so E = potential + kinetic should stay at {:.6g} J; it "
        "strays by {:.3g} of the largest kinetic energy {:.4g} J over {}. A discrete integrator "
        "never conserves it exactly; a smaller timestep or RK4 shrinks the drift.",
        e0, drift, max_kinetic, Seconds(until));
    return r;
  }

  // dissipative: energy may not rise beyond the integrator's own energy wobble, measured
  // on the same run with dissipation removed
  std::vector<Assignment> undamped;
  for (int i = 0; i < m->nv; ++i) {
    undamped.push_back(s.Set(fmt::format("dof_damping[{}]=0", m->jnt_dofadr[m->dof_jntid[i]])));
    undamped.push_back(
        s.Set(fmt::format("dof_frictionloss[{}]=0", m->jnt_dofadr[m->dof_jntid[i]])));
  }
  const Trace& twin = s.Simulate(undamped, until, /*energy=*/true);
  auto [tlo, thi] = std::minmax_element(twin.energy.begin(), twin.energy.end());
  double wobble = *thi - *tlo;
  double rise = LargestRise(nominal.energy);
  double allowed = 1.5 * wobble + 1e-12 * max_kinetic;
  // the peak envelope of a lone hinge/slide coordinate falls (single samples need not);
  // coupled coordinates trade energy, so one of them may swing higher for a while
  std::string envelope;
  bool envelope_ok = true;
  for (std::size_t c = 0; c < nominal.coords.size() && m->nv == 1; ++c) {
    std::vector<double> peaks = Peaks(nominal.coords[c]);
    if (peaks.size() < 2) continue;
    bool falling = true;
    for (std::size_t k = 1; k < peaks.size(); ++k) falling = falling && peaks[k] < peaks[k - 1];
    envelope_ok = envelope_ok && falling;
    envelope += fmt::format("{}{}: {} peaks {} ({:.5g} -> {:.5g})", envelope.empty() ? "" : "; ",
                            nominal.coord_names[c], peaks.size(), falling ? "fall" : "DO NOT fall",
                            peaks.front(), peaks.back());
  }
  r.measured = fmt::format("largest rise {:.3g} J", rise);
  r.reference = fmt::format("<= {:.3g} J", allowed);
  r.measured_value = rise;
  r.reference_value = allowed;
  r.status = rise <= allowed && envelope_ok ? CheckStatus::kPass : CheckStatus::kFail;
  std::string peaks = m->nv > 1          ? "Peaks are not compared: the coordinates are coupled."
                      : envelope.empty() ? "The coordinate did not swing twice to compare peaks."
                                         : "Peak envelope: " + envelope + ".";
  r.detail = fmt::format(
      "damping only removes energy: E went from {:.6g} J to {:.6g} J over {}; its largest rise "
      "{:.3g} J {} the integrator's own wobble allowance ({:.3g} J, from the undamped twin). {}",
      e0, nominal.energy.back(), Seconds(until), rise, rise <= allowed ? "stays within" : "EXCEEDS",
      allowed, peaks);
  return r;
}

// ---- analytic references for a pendulum --------------------------------------------------

// The swing amplitude of a start angle: angles 2*pi apart are the same pose, so the
// swing is about the equilibrium nearest the start (30 rad swings about 8*pi).
double Amplitude(double theta0, const PendulumParams& p) {
  return std::fabs(std::remainder(theta0 - p.equilibrium, 2 * M_PI));
}

// The equilibrium angle a trace starting at `q0` swings about.
double SwingCentre(double q0, const PendulumParams& p) {
  return q0 - std::remainder(q0 - p.equilibrium, 2 * M_PI);
}

// Where the experiments start: the user's swing (wrapped to one turn), or the chapter's
// 0.7 rad when the pendulum starts at rest.
double ExperimentStart(double theta0, const PendulumParams& p) {
  double amplitude = Amplitude(theta0, p);
  return amplitude > 1e-6 && amplitude < M_PI - 1e-6
             ? p.equilibrium + std::remainder(theta0 - p.equilibrium, 2 * M_PI)
             : p.equilibrium + 0.7;
}

struct PendulumRun {
  double period = kNaN;  // from upward crossings of the equilibrium angle
};

// The scenario with `extra` settings, run long enough for `periods` swings of `expected`.
PendulumRun RunPendulum(const Scenario& s, const PendulumParams& p,
                        const std::vector<Assignment>& extra, double expected, int periods) {
  PendulumRun out;
  double dt = kReferenceDt;
  for (const Assignment& a : extra) {
    if (a.path.field == "opt.timestep") dt = a.values[0];
  }
  // from the largest angle, the first upward crossing comes after 3/4 of a swing
  double until = std::ceil((periods + 0.9) * expected / dt) * dt;
  const Trace& trace = s.Simulate(extra, until);
  if (!trace.coords.empty()) {
    std::optional<double> period = PeriodFromCrossings(
        trace.t, trace.coords[0], SwingCentre(trace.coords[0].front(), p), periods);
    if (period) out.period = *period;
  }
  return out;
}

std::vector<Assignment> Exact(const Scenario& s, int dof, double theta) {
  // RK4 at a tiny step, no damping: the conditions the closed forms assume
  return {s.Set("opt.integrator=RK4"), s.Set(fmt::format("opt.timestep={:.17g}", kReferenceDt)),
          s.Set(fmt::format("dof_damping[{}]=0", dof)),
          s.Set(fmt::format("qpos[{}]={:.17g}", dof, theta)),
          s.Set(fmt::format("qvel[{}]=0", dof))};
}

CheckResult CheckAnalyticPeriod(const Scenario& s, const PendulumParams& p, double theta0,
                                int dof) {
  CheckResult r =
      Row("analytic.period", "simulated period = exact large-angle period (elliptic integral)");
  double amplitude = Amplitude(theta0, p);
  if (amplitude < 1e-6) return Skip(r.id, r.title, "the pendulum starts at rest at equilibrium");
  if (amplitude >= M_PI - 1e-6) return Skip(r.id, r.title, "it starts over the top: no swing");
  double t0 = SmallAnglePeriod(p), exact = LargeAnglePeriod(p, amplitude);
  PendulumRun run = RunPendulum(s, p, Exact(s, dof, theta0), exact, 1);
  if (!std::isfinite(run.period)) return Skip(r.id, r.title, "no full swing was observed");
  SetNumbers(&r, run.period, exact, " s", "{:.12g}");
  r.status = r.rel_error <= 1e-6 ? CheckStatus::kPass : CheckStatus::kFail;
  DampingAnalysis damping = AnalyseDamping(p.inertia, p.stiffness, p.damping);
  r.detail = fmt::format(
      "from the compiled model: I = {:.6g} kg*m^2 about the hinge, m = {:.6g} kg, d = {:.6g} m, "
      "g = {:.6g} m/s^2. Small-angle T0 = 2*pi*sqrt(I/(m*g*d)) = {:.10g} s; at amplitude "
      "{:.4g} rad the exact period is T0*(2/pi)*K(sin(theta0/2)) = {:.10g} s ({:.4f} T0). "
      "Simulated with RK4, dt = {:g} s, damping removed: {:.12g} s. Damping c = {:g} N*m*s/rad "
      "gives zeta = {:.4g} ({}){}.",
      p.inertia, p.mass, p.distance, p.gravity, t0, amplitude, exact, exact / t0, kReferenceDt,
      run.period, p.damping, damping.zeta, DampingClassName(damping.kind),
      damping.damped_period > 0 && p.damping > 0
          ? fmt::format(", damped small-angle period {:.10g} s", damping.damped_period)
          : std::string());
  return r;
}

CheckResult CheckModelPeriod(const Scenario& s, const PendulumParams& p, double theta0,
                             double tol) {
  CheckResult r =
      Row("analytic.model_settings", "the period with the model's own integrator and timestep");
  double amplitude = Amplitude(theta0, p);
  if (amplitude < 1e-6 || amplitude >= M_PI - 1e-6) {
    return Skip(r.id, r.title, "no swing to time from this initial angle");
  }
  DampingAnalysis damping = AnalyseDamping(p.inertia, p.stiffness, p.damping);
  if (damping.kind == DampingClass::kOverdamped || damping.kind == DampingClass::kCritical) {
    return Skip(r.id, r.title, "the hinge is not underdamped: it does not oscillate");
  }
  const mjModel* m = s.Nominal().get();
  double dt = m->opt.timestep;
  double expected = LargeAnglePeriod(p, amplitude);
  // the same damped swing, once as the model runs it and once with RK4 at a tiny step:
  // their difference is the integrator's and timestep's error alone (a decaying swing
  // has no closed-form period: it shortens as the amplitude falls)
  PendulumRun own =
      RunPendulum(s, p, {s.Set(fmt::format("opt.timestep={:.17g}", dt))}, expected, 2);
  PendulumRun exact = RunPendulum(
      s, p, {s.Set("opt.integrator=RK4"), s.Set(fmt::format("opt.timestep={:.17g}", kReferenceDt))},
      expected, 2);
  if (!std::isfinite(own.period) || !std::isfinite(exact.period)) {
    return Skip(r.id, r.title, "no full swing was observed");
  }
  SetNumbers(&r, own.period, exact.period, " s", "{:.8g}");
  r.status = r.rel_error <= tol ? CheckStatus::kPass : CheckStatus::kWarn;
  r.detail = fmt::format(
      "mean period of the first 2 swings with the model's {} at dt = {:g} s: {:.8g} s; with RK4 "
      "at dt = {:g} s: {:.8g} s. The difference, {:.2g} relative, is the integration error ({} "
      "tol {:g}). Damping shortens the swings as the amplitude falls (undamped exact: {:.8g} s).",
      compat::NameOf(compat::kIntegrators, m->opt.integrator), dt, own.period, kReferenceDt,
      exact.period, r.rel_error, r.rel_error <= tol ? "within" : "beyond", tol, expected);
  return r;
}

CheckResult CheckDamping(const Scenario& s, const PendulumParams& p, double theta0) {
  CheckResult r = Row("analytic.damping", "the motion matches the damping classification");
  DampingAnalysis damping = AnalyseDamping(p.inertia, p.stiffness, p.damping);
  double amplitude = Amplitude(theta0, p);
  if (amplitude < 1e-6) return Skip(r.id, r.title, "the pendulum starts at rest at equilibrium");
  if (amplitude >= M_PI - 1e-6) {
    return Skip(r.id, r.title,
                "it starts balanced over the top (the unstable equilibrium): it never swings");
  }
  double window =
      3 * (damping.damped_period > 0 ? damping.damped_period : 2 * M_PI / damping.omega0);
  double dt = s.Nominal()->opt.timestep;
  const Trace& trace = s.Simulate({}, std::ceil(window / dt) * dt);
  int crossings = 0;
  const std::vector<double>& q = trace.coords[0];
  double centre = SwingCentre(q.front(), p);
  for (std::size_t i = 1; i < q.size(); ++i) {
    if ((q[i - 1] - centre) * (q[i] - centre) < 0) ++crossings;
  }
  bool oscillates = crossings >= 2;
  bool should =
      damping.kind == DampingClass::kUnderdamped || damping.kind == DampingClass::kUndamped;
  r.measured = fmt::format("{} crossings of equilibrium", crossings);
  r.reference = should ? "oscillates" : "at most one crossing";
  r.measured_value = crossings;  // JSON "measured": the crossings; zeta is in the detail
  r.status = oscillates == should ? CheckStatus::kPass : CheckStatus::kFail;
  r.detail = fmt::format(
      "zeta = c/(2*sqrt(I*m*g*d)) = {:g}/(2*sqrt({:.5g}*{:.5g})) = {:.4g}: {}; in {:.3g} s the "
      "hinge crossed equilibrium {} times.",
      p.damping, p.inertia, p.stiffness, damping.zeta, DampingClassName(damping.kind), window,
      crossings);
  return r;
}

// ---- the chapter's three experiments ----------------------------------------------------

CheckResult ExperimentAmplitude(const Scenario& s, const PendulumParams& p, int dof) {
  CheckResult r =
      Row("experiment.A", "initial angle 0.1, 0.7, 2.8 rad: period grows with amplitude");
  double t0 = SmallAnglePeriod(p);
  std::vector<std::string> parts;
  double previous = 0, worst = 0;
  bool growing = true;
  for (double theta : {0.1, 0.7, 2.8}) {
    double exact = LargeAnglePeriod(p, theta);
    PendulumRun run = RunPendulum(s, p, Exact(s, dof, p.equilibrium + theta), exact, 1);
    if (!std::isfinite(run.period)) return Skip(r.id, r.title, "no full swing was observed");
    worst = std::max(worst, RelError(run.period, exact));
    growing = growing && run.period > previous;
    previous = run.period;
    parts.push_back(fmt::format("{:g} rad: T = {:.8g} s = {:.4f} T0 (elliptic {:.4f} T0)", theta,
                                run.period, run.period / t0, exact / t0));
  }
  r.measured = fmt::format("worst {:.2g} rel. to elliptic", worst);
  r.reference = "<= 1e-06";
  r.measured_value = worst;
  r.reference_value = 1e-6;
  r.rel_error = worst;
  r.status = growing && worst <= 1e-6 ? CheckStatus::kPass : CheckStatus::kFail;
  r.detail = fmt::format(
      "T0 = {:.8g} s. {}. The small-angle formula holds only for small swings: the period "
      "grows with amplitude, as the elliptic integral predicts (RK4, dt = {:g} s, undamped).",
      t0, fmt::join(parts, "; "), kReferenceDt);
  return r;
}

CheckResult ExperimentDamping(const Scenario& s, const PendulumParams& p, int dof, double theta0,
                              double tol) {
  CheckResult r = Row("experiment.B", "damping 0, 0.05, 1.0: energy conserved vs. decaying");
  double theta = ExperimentStart(theta0, p);
  std::vector<std::string> parts;
  std::vector<double> losses;
  double drift0 = 0;
  for (double c : {0.0, 0.05, 1.0}) {
    const Trace& trace = s.Simulate(
        {s.Set(fmt::format("dof_damping[{}]={:g}", dof, c)),
         s.Set(fmt::format("qpos[{}]={:.17g}", dof, theta)), s.Set(fmt::format("qvel[{}]=0", dof))},
        2.0, /*energy=*/true);
    if (trace.result.diverged) return Skip(r.id, r.title, "a run diverged");
    double e0 = trace.energy.front();
    double emin = e0 - p.stiffness * (1 - std::cos(theta - p.equilibrium));  // E at rest
    double swing = e0 - emin;
    double loss = (e0 - trace.energy.back()) / swing;
    DampingAnalysis d = AnalyseDamping(p.inertia, p.stiffness, c);
    if (c == 0) {
      auto [lo, hi] = std::minmax_element(trace.energy.begin(), trace.energy.end());
      drift0 = std::max(hi[0] - e0, e0 - lo[0]) / swing;
      parts.push_back(
          fmt::format("c = 0: energy strays by {:.2g} of the swing energy "
                      "(integration error only)",
                      drift0));
    } else {
      parts.push_back(
          fmt::format("c = {:g}: zeta = {:.3g} ({}), {:.1f}% of the swing energy "
                      "lost in 2 s",
                      c, d.zeta, DampingClassName(d.kind), 100 * loss));
    }
    losses.push_back(loss);
  }
  bool ordered = losses[1] > 0 && losses[2] > losses[1];
  r.measured = fmt::format("loss {:.3g} / {:.3g} / {:.3g}", losses[0], losses[1], losses[2]);
  r.reference = "~0 / >0 / larger";
  // damping that does not remove energy is wrong physics; an undamped run that strays is
  // the timestep's error, which the convergence check judges
  r.status = !ordered        ? CheckStatus::kFail
             : drift0 <= tol ? CheckStatus::kPass
                             : CheckStatus::kWarn;
  r.detail = fmt::format(
      "{}. More damping removes energy faster; whether c = 1 is overdamped "
      "depends on the inertia and the gravity stiffness m*g*d = {:.4g} N*m/rad.",
      fmt::join(parts, "; "), p.stiffness);
  return r;
}

CheckResult ExperimentTimestep(const Scenario& s, const PendulumParams& p, int dof, double theta0,
                               double tol) {
  CheckResult r = Row("experiment.C", "timestep 0.0005, 0.002, 0.02 s: q at 2 s converges");
  double theta = ExperimentStart(theta0, p);
  std::vector<Assignment> start = {s.Set(fmt::format("qpos[{}]={:.17g}", dof, theta)),
                                   s.Set(fmt::format("qvel[{}]=0", dof))};
  // reference: RK4 at a tiny step with the model's damping
  std::vector<Assignment> exact = start;
  exact.push_back(s.Set("opt.integrator=RK4"));
  exact.push_back(s.Set(fmt::format("opt.timestep={:.17g}", kReferenceDt)));
  const Trace& ref = s.Simulate(exact, 2.0);
  double reference = ref.coords[0].back();
  double scale = std::fabs(theta - p.equilibrium);
  std::vector<std::string> parts;
  std::vector<double> errors, values;
  for (double dt : {0.0005, 0.002, 0.02}) {
    std::vector<Assignment> run = start;
    run.push_back(s.Set(fmt::format("opt.timestep={:g}", dt)));
    const Trace& trace = s.Simulate(run, 2.0);
    double q = trace.result.diverged ? kNaN : trace.coords[0].back();
    double error = std::fabs(q - reference);
    values.push_back(q);
    errors.push_back(std::isfinite(error) ? error : std::numeric_limits<double>::infinity());
    parts.push_back(fmt::format("dt = {:g}: q(2) = {:.6f}, error {:.2g} ({})", dt, q, error,
                                error <= tol * scale ? "converged" : "NOT converged"));
  }
  bool shrinking = errors[0] < errors[1] && errors[1] < errors[2];
  r.measured = fmt::format("errors {:.2g} / {:.2g} / {:.2g}", errors[0], errors[1], errors[2]);
  r.reference = fmt::format("q(2) = {:.8f} (RK4)", reference);
  // JSON: measured is q(2) at the chapter's dt = 0.002 s, reference the converged q(2)
  SetNumbers(&r, values[1], reference, "", "{:.8f}");
  r.measured = fmt::format("errors {:.2g} / {:.2g} / {:.2g}", errors[0], errors[1], errors[2]);
  r.reference = fmt::format("q(2) = {:.8f} (RK4)", reference);
  r.status = shrinking ? CheckStatus::kPass : CheckStatus::kFail;
  r.detail = fmt::format(
      "{} (tol {:g} x amplitude {:.3g}). Different timesteps give different discrete "
      "trajectories; judge a timestep by halving it until the answer stops changing, not by "
      "how smooth an animation looks.",
      fmt::join(parts, "; "), tol, scale);
  return r;
}

// ---- the chapter's exercises -------------------------------------------------------------

CheckResult ExerciseMoon(const Scenario& s, const PendulumParams& p, int dof, double theta0) {
  CheckResult r =
      Row("exercise.moon_gravity", "gravity -1.62 m/s^2 stretches the period by sqrt(9.81/1.62)");
  double amplitude = Amplitude(theta0, p);
  if (amplitude < 1e-6 || amplitude >= M_PI - 1e-6) amplitude = 0.7;
  double theta = p.equilibrium + amplitude;
  const mjtNum* g = s.Nominal()->opt.gravity;
  double scale = 1.62 / 9.81;
  double earth = LargeAnglePeriod(p, amplitude);
  PendulumRun here = RunPendulum(s, p, Exact(s, dof, theta), earth, 1);
  std::vector<Assignment> moon = Exact(s, dof, theta);
  moon.push_back(s.Set(fmt::format("opt.gravity={:.17g},{:.17g},{:.17g}", g[0] * scale,
                                   g[1] * scale, g[2] * scale)));
  PendulumRun there = RunPendulum(s, p, moon, earth / std::sqrt(scale), 1);
  if (!std::isfinite(here.period) || !std::isfinite(there.period)) {
    return Skip(r.id, r.title, "no full swing was observed");
  }
  SetNumbers(&r, there.period / here.period, std::sqrt(9.81 / 1.62), "", "{:.8g}");
  r.status = r.rel_error <= 1e-6 ? CheckStatus::kPass : CheckStatus::kFail;
  r.detail = fmt::format(
      "periods scale as 1/sqrt(g) at any amplitude: {:.8g} s here, {:.8g} s with gravity scaled "
      "to 1.62/9.81 of the model's; the ratio {:.8g} vs sqrt(9.81/1.62) = {:.8g}.",
      here.period, there.period, there.period / here.period, std::sqrt(9.81 / 1.62));
  return r;
}


const char* GeomTypeName(int type) {
  switch (type) {
    case mjGEOM_SPHERE:
      return "sphere";
    case mjGEOM_CAPSULE:
      return "capsule";
    case mjGEOM_CYLINDER:
      return "cylinder";
    case mjGEOM_BOX:
      return "box";
    case mjGEOM_ELLIPSOID:
      return "ellipsoid";
    default:
      return "";
  }
}

CheckResult ExerciseDensity(const Model& model, const PendulumParams& p) {
  CheckResult r = Row("exercise.density", "density instead of mass: mass = density x volume");
  const mjModel* m = model.get();
  int body = m->jnt_bodyid[p.joint];
  int geom = m->body_geomnum[body] > 0 ? m->body_geomadr[body] : -1;
  if (geom < 0 || !*GeomTypeName(m->geom_type[geom])) {
    return Skip(r.id, r.title, "the swinging body has no primitive geom to give a density");
  }
  const mjtNum* size = m->geom_size + 3 * geom;
  double volume = PrimitiveVolume(m->geom_type[geom], size);
  // the same geom, given density 1000 kg/m^3 instead of a mass, compiled by MuJoCo
  Model variant = Model::FromXmlString(
      fmt::format("<mujoco><worldbody><body><freejoint/><geom type=\"{}\" size=\"{:.17g} "
                  "{:.17g} {:.17g}\" density=\"1000\"/></body></worldbody></mujoco>",
                  GeomTypeName(m->geom_type[geom]), size[0], size[1], size[2]),
      "density exercise");
  SetNumbers(&r, variant->body_mass[1], 1000 * volume, " kg", "{:.10g}");
  r.status = r.rel_error <= 1e-9 ? CheckStatus::kPass : CheckStatus::kFail;
  r.detail = fmt::format(
      "the compiler turns density into mass through the geom's volume: this {} (size {:.4g}, "
      "{:.4g}) has V = {:.6g} m^3, so density 1000 kg/m^3 gives {:.6g} kg; inertia follows from "
      "the same solid shape.",
      GeomTypeName(m->geom_type[geom]), size[0], size[1], volume, 1000 * volume);
  return r;
}

CheckResult ExerciseRadians(const Scenario& s) {
  CheckResult r = Row("exercise.radians", "initial angles are radians at run time");
  const mjModel* m = s.model().get();
  std::vector<std::string> seen;
  bool suspicious = false;
  for (const Assignment& a : s.sets()) {
    if (a.path.field != "qpos") continue;
    for (long k = 0; k < a.path.count; ++k) {
      long adr = a.path.first + k;
      for (int j = 0; j < m->njnt; ++j) {
        if (m->jnt_type[j] != mjJNT_HINGE || m->jnt_qposadr[j] != adr) continue;
        double v = a.values[k];
        bool big = std::fabs(v) > 2 * M_PI;
        suspicious = suspicious || big;
        seen.push_back(
            big ? fmt::format("{} = {:g} rad is {:.2f} turns: if you meant {:g} "
                              "degrees, write {:.6g}",
                              a.path.text, v, std::fabs(v) / (2 * M_PI), v, v * M_PI / 180)
                : fmt::format("{} = {:g} rad = {:.1f} degrees", a.path.text, v, v * 180 / M_PI));
      }
    }
  }
  if (seen.empty()) return Skip(r.id, r.title, "no hinge angle was set with --set");
  r.status = suspicious ? CheckStatus::kWarn : CheckStatus::kPass;
  r.measured = suspicious ? "looks like degrees" : "plausible radians";
  r.reference = "|angle| <= 2*pi";
  r.detail = fmt::format(
      "{}. MuJoCo's C API uses radians whatever the MJCF <compiler angle> "
      "says.",
      fmt::join(seen, "; "));
  return r;
}

}  // namespace

const char* CheckStatusName(CheckStatus status) {
  switch (status) {
    case CheckStatus::kPass:
      return "PASS";
    case CheckStatus::kWarn:
      return "WARN";
    case CheckStatus::kFail:
      return "FAIL";
    case CheckStatus::kSkip:
      return "SKIP";
  }
  return "?";
}

int VerifyReport::Count(CheckStatus status) const {
  return static_cast<int>(std::count_if(checks.begin(), checks.end(),
                                        [&](const CheckResult& c) { return c.status == status; }));
}

VerifyReport Verify(const Model& model, const VerifyOptions& options) {
  if (!(options.tol > 0)) throw ValueError("--tol must be a positive relative tolerance");
  VerifyReport report;
  report.model = model.file();
  Scenario s(model, options);
  const Model& nominal = s.Nominal();
  const mjModel* m = nominal.get();
  std::string why_not;
  std::optional<PendulumParams> pendulum = DetectPendulum(nominal, &why_not);

  // the nominal run: 2 s like the chapter; for other models at most 250 steps and at
  // most 1e5 / nv steps (the convergence ladder runs ~16 times as many), always a whole
  // number of 2*dt so the ladder lands on it exactly
  double dt = RunTimestep(model, options.sets);
  double max_steps =
      std::max(20.0, std::min(250.0, 1e5 / std::max(1.0, static_cast<double>(m->nv))));
  double until = options.until ? *options.until : pendulum ? 2.0 : std::min(2.0, max_steps * dt);
  if (options.until && !(*options.until > 0 && std::isfinite(*options.until))) {
    // a run of zero steps would pass determinism and warnings without testing anything
    throw ValueError(
        fmt::format("--until {:g}: the nominal run length must be a positive number "
                    "of seconds (a run of zero steps checks nothing).",
                    *options.until));
  }
  if (!(options.tol > 0 && std::isfinite(options.tol))) {
    throw ValueError(fmt::format("--tol {:g}: the relative tolerance must be positive and finite.",
                                 options.tol));
  }
  if (options.until) {
    // the convergence ladder runs at 2*dt too, so the run must end on a whole 2*dt
    RequireWholeSteps(*options.until, 2 * dt, fmt::format("--until {:g}", *options.until),
                      "twice the timestep: the convergence ladder's coarsest level");
  }
  until = std::max(2 * dt, std::round(until / (2 * dt)) * 2 * dt);

  report.checks.push_back(CheckLoad(model));
  const Trace& trace = s.Simulate({}, until, /*energy=*/true);
  report.checks.push_back(CheckDeterminism(s, trace, until));
  report.checks.push_back(CheckWarnings(trace, until));
  if (trace.result.diverged) {
    report.checks.push_back(Skip("convergence", "the result converges as the timestep shrinks",
                                 "the nominal run diverged"));
  } else {
    report.checks.push_back(CheckConvergence(s, pendulum, trace, until, options.tol));
  }
  // a pendulum's energy check watches several swings, so peaks can be compared
  const Trace* energy_trace = &trace;
  double energy_until = until;
  if (pendulum && !trace.result.diverged) {
    double want = std::ceil(3.5 * SmallAnglePeriod(*pendulum) / dt) * dt;
    if (want > until) {
      energy_until = want;
      energy_trace = &s.Simulate({}, want, /*energy=*/true);
    }
  }
  report.checks.push_back(CheckEnergy(s, *energy_trace, energy_until, options.tol));

  const char* pendulum_titles[][2] = {
      {"analytic.period", "simulated period = exact large-angle period (elliptic integral)"},
      {"analytic.model_settings", "the period with the model's own integrator and timestep"},
      {"analytic.damping", "the motion matches the damping classification"},
      {"experiment.A", "initial angle 0.1, 0.7, 2.8 rad: period grows with amplitude"},
      {"experiment.B", "damping 0, 0.05, 1.0: energy conserved vs. decaying"},
      {"experiment.C", "timestep 0.0005, 0.002, 0.02 s: q at 2 s converges"},
      {"exercise.moon_gravity", "gravity -1.62 m/s^2 stretches the period by sqrt(9.81/1.62)"},
      {"exercise.density", "density instead of mass: mass = density x volume"},
  };
  if (pendulum && !trace.result.diverged) {
    // a single hinge: its qpos and dof address are the same index
    int dof = m->jnt_qposadr[pendulum->joint];
    double theta0 = trace.coords[0].front();
    report.checks.push_back(CheckAnalyticPeriod(s, *pendulum, theta0, dof));
    report.checks.push_back(CheckModelPeriod(s, *pendulum, theta0, options.tol));
    report.checks.push_back(CheckDamping(s, *pendulum, theta0));
    report.checks.push_back(ExperimentAmplitude(s, *pendulum, dof));
    report.checks.push_back(ExperimentDamping(s, *pendulum, dof, theta0, options.tol));
    report.checks.push_back(ExperimentTimestep(s, *pendulum, dof, theta0, options.tol));
    report.checks.push_back(ExerciseMoon(s, *pendulum, dof, theta0));
    report.checks.push_back(ExerciseDensity(nominal, *pendulum));
  } else {
    std::string why = pendulum ? "the nominal run diverged"
                               : "not a single hinge pendulum under gravity: " + why_not;
    for (const auto& [id, title] : pendulum_titles) report.checks.push_back(Skip(id, title, why));
  }
  report.checks.push_back(ExerciseRadians(s));
  return report;
}

}  // namespace plumb
