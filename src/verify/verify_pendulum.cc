// The verify checks for a single hinge pendulum under gravity: the analytic references
// (exact large-angle period, the model's own settings, the damping classification), the
// chapter's three experiments and its exercises.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/geometry.h"
#include "core/mujoco_compat.h"
#include "plumb/converge.h"
#include "plumb/error.h"
#include "plumb/metric.h"
#include "plumb/timing.h"
#include "verify/verify_protocol.h"

namespace plumb::verify {
using internal::PrimitiveVolume;

namespace {

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
PendulumRun RunPendulum(const VerifyScenario& s, const PendulumParams& p,
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

std::vector<Assignment> Exact(const VerifyScenario& s, int dof, double theta) {
  // RK4 at a tiny step, no damping: the conditions the closed forms assume
  return {s.Set("opt.integrator=RK4"), s.Set(fmt::format("opt.timestep={:.17g}", kReferenceDt)),
          s.Set(fmt::format("dof_damping[{}]=0", dof)),
          s.Set(fmt::format("qpos[{}]={:.17g}", dof, theta)),
          s.Set(fmt::format("qvel[{}]=0", dof))};
}

}  // namespace

CheckRow CheckAnalyticPeriod(const VerifyContext& ctx, CheckRow r) {
  const auto& [s, p, dof, theta0, tol] = Pendulum(ctx);
  double amplitude = Amplitude(theta0, p);
  if (amplitude < 1e-6) return Skip(r.id, r.title, "the pendulum starts at rest at equilibrium");
  if (amplitude >= M_PI - 1e-6) return Skip(r.id, r.title, "it starts over the top: no swing");
  double t0 = SmallAnglePeriod(p), exact = LargeAnglePeriod(p, amplitude);
  PendulumRun run = RunPendulum(s, p, Exact(s, dof, theta0), exact, 1);
  if (!std::isfinite(run.period)) return Skip(r.id, r.title, "no full swing was observed");
  SetNumbers(&r, run.period, exact, " s", "{:.12g}");
  r.status = r.rel_error <= 1e-6 ? CheckStatus::kPass : CheckStatus::kFail;
  DampingAnalysis damping = AnalyseDamping(p.inertia, p.stiffness, p.damping);
  r.explanation = fmt::format(
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

CheckRow CheckModelPeriod(const VerifyContext& ctx, CheckRow r) {
  const auto& [s, p, dof, theta0, tol] = Pendulum(ctx);
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
  r.explanation = fmt::format(
      "mean period of the first 2 swings with the model's {} at dt = {:g} s: {:.8g} s; with RK4 "
      "at dt = {:g} s: {:.8g} s. The difference, {:.2g} relative, is the integration error ({} "
      "tol {:g}). Damping shortens the swings as the amplitude falls (undamped exact: {:.8g} s).",
      compat::NameOf(compat::kIntegrators, m->opt.integrator), dt, own.period, kReferenceDt,
      exact.period, r.rel_error, r.rel_error <= tol ? "within" : "beyond", tol, expected);
  return r;
}

CheckRow CheckDamping(const VerifyContext& ctx, CheckRow r) {
  const auto& [s, p, dof, theta0, tol] = Pendulum(ctx);
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
  r.measured_text = fmt::format("{} crossings of equilibrium", crossings);
  r.reference_text = should ? "oscillates" : "at most one crossing";
  r.measured.value = crossings;  // JSON "measured": the crossings; zeta is in the detail
  r.status = oscillates == should ? CheckStatus::kPass : CheckStatus::kFail;
  r.explanation = fmt::format(
      "zeta = c/(2*sqrt(I*m*g*d)) = {:g}/(2*sqrt({:.5g}*{:.5g})) = {:.4g}: {}; in {:.3g} s the "
      "hinge crossed equilibrium {} times.",
      p.damping, p.inertia, p.stiffness, damping.zeta, DampingClassName(damping.kind), window,
      crossings);
  return r;
}

// ---- the chapter's three experiments ----------------------------------------------------

CheckRow ExperimentAmplitude(const VerifyContext& ctx, CheckRow r) {
  const auto& [s, p, dof, theta0, tol] = Pendulum(ctx);
  double t0 = SmallAnglePeriod(p);
  std::vector<std::string> parts;
  double previous = 0, worst = 0;
  bool growing = true;
  PendulumFigures figures;
  for (double theta : {0.1, 0.7, 2.8}) {
    double exact = LargeAnglePeriod(p, theta);
    PendulumRun run = RunPendulum(s, p, Exact(s, dof, p.equilibrium + theta), exact, 1);
    if (!std::isfinite(run.period)) return Skip(r.id, r.title, "no full swing was observed");
    worst = std::max(worst, RelError(run.period, exact));
    growing = growing && run.period > previous;
    previous = run.period;
    figures.periods.push_back({theta, run.period, exact});
    parts.push_back(fmt::format("{:g} rad: T = {:.8g} s = {:.4f} T0 (elliptic {:.4f} T0)", theta,
                                run.period, run.period / t0, exact / t0));
  }
  if (ctx.figures != nullptr) {
    figures.small_angle_period = t0;
    for (int i = 1; i <= 60; ++i) {
      double theta = 3.0 * i / 60;  // up to 3 rad, where the period grows steeply
      figures.exact_curve.push_back({theta, kNaN, LargeAnglePeriod(p, theta)});
    }
    ctx.figures->pendulum = std::move(figures);
  }
  r.measured_text = fmt::format("worst {:.2g} rel. to elliptic", worst);
  r.reference_text = "<= 1e-06";
  r.measured.value = worst;
  r.reference.value = 1e-6;
  r.rel_error = worst;
  r.status = growing && worst <= 1e-6 ? CheckStatus::kPass : CheckStatus::kFail;
  r.explanation = fmt::format(
      "T0 = {:.8g} s. {}. The small-angle formula holds only for small swings: the period "
      "grows with amplitude, as the elliptic integral predicts (RK4, dt = {:g} s, undamped).",
      t0, fmt::join(parts, "; "), kReferenceDt);
  return r;
}

CheckRow ExperimentDamping(const VerifyContext& ctx, CheckRow r) {
  const auto& [s, p, dof, theta0, tol] = Pendulum(ctx);
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
  r.measured_text = fmt::format("loss {:.3g} / {:.3g} / {:.3g}", losses[0], losses[1], losses[2]);
  r.reference_text = "~0 / >0 / larger";
  // damping that does not remove energy is wrong physics; an undamped run that strays is
  // the timestep's error, which the convergence check judges
  r.status = !ordered        ? CheckStatus::kFail
             : drift0 <= tol ? CheckStatus::kPass
                             : CheckStatus::kWarn;
  r.explanation = fmt::format(
      "{}. More damping removes energy faster; whether c = 1 is overdamped "
      "depends on the inertia and the gravity stiffness m*g*d = {:.4g} N*m/rad.",
      fmt::join(parts, "; "), p.stiffness);
  return r;
}

CheckRow ExperimentTimestep(const VerifyContext& ctx, CheckRow r) {
  const auto& [s, p, dof, theta0, tol] = Pendulum(ctx);
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
  r.measured_text = fmt::format("errors {:.2g} / {:.2g} / {:.2g}", errors[0], errors[1], errors[2]);
  r.reference_text = fmt::format("q(2) = {:.8f} (RK4)", reference);
  // JSON: measured is q(2) at the chapter's dt = 0.002 s, reference the converged q(2)
  SetNumbers(&r, values[1], reference, "", "{:.8f}");
  r.measured_text = fmt::format("errors {:.2g} / {:.2g} / {:.2g}", errors[0], errors[1], errors[2]);
  r.reference_text = fmt::format("q(2) = {:.8f} (RK4)", reference);
  r.status = shrinking ? CheckStatus::kPass : CheckStatus::kFail;
  r.explanation = fmt::format(
      "{} (tol {:g} x amplitude {:.3g}). Different timesteps give different discrete "
      "trajectories; judge a timestep by halving it until the answer stops changing, not by "
      "how smooth an animation looks.",
      fmt::join(parts, "; "), tol, scale);
  return r;
}

// ---- the chapter's exercises -------------------------------------------------------------

CheckRow ExerciseMoon(const VerifyContext& ctx, CheckRow r) {
  const auto& [s, p, dof, theta0, tol] = Pendulum(ctx);
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
  r.explanation = fmt::format(
      "periods scale as 1/sqrt(g) at any amplitude: {:.8g} s here, {:.8g} s with gravity scaled "
      "to 1.62/9.81 of the model's; the ratio {:.8g} vs sqrt(9.81/1.62) = {:.8g}.",
      here.period, there.period, there.period / here.period, std::sqrt(9.81 / 1.62));
  return r;
}

CheckRow ExerciseDensity(const VerifyContext& ctx, CheckRow r) {
  const Model& model = ctx.nominal;
  const PendulumParams& p = *ctx.pendulum;
  const mjModel* m = model.get();
  int body = m->jnt_bodyid[p.joint];
  int geom = m->body_geomnum[body] > 0 ? m->body_geomadr[body] : -1;
  const mjtNum* size = geom >= 0 ? m->geom_size + 3 * geom : nullptr;
  double volume = geom >= 0 ? PrimitiveVolume(m->geom_type[geom], size) : NAN;
  if (std::isnan(volume)) {
    return Skip(r.id, r.title, "the swinging body has no primitive geom to give a density");
  }
  std::string type = compat::NameOf(compat::kGeomTypes, m->geom_type[geom]);
  // the same geom, given density 1000 kg/m^3 instead of a mass, compiled by MuJoCo
  Model variant = Model::FromXmlString(
      fmt::format("<mujoco><worldbody><body><freejoint/><geom type=\"{}\" size=\"{:.17g} "
                  "{:.17g} {:.17g}\" density=\"1000\"/></body></worldbody></mujoco>",
                  type, size[0], size[1], size[2]),
      "density exercise");
  SetNumbers(&r, variant->body_mass[1], 1000 * volume, " kg", "{:.10g}");
  r.status = r.rel_error <= 1e-9 ? CheckStatus::kPass : CheckStatus::kFail;
  r.explanation = fmt::format(
      "the compiler turns density into mass through the geom's volume: this {} (size {:.4g}, "
      "{:.4g}) has V = {:.6g} m^3, so density 1000 kg/m^3 gives {:.6g} kg; inertia follows from "
      "the same solid shape.",
      type, size[0], size[1], volume, 1000 * volume);
  return r;
}

}  // namespace plumb::verify
