// The verify convergence check for any model: the model's own timestep against plumb
// converge's ladder of finer ones, on the pendulum's angle or the whole state at the end of
// the nominal run.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "core/mujoco_compat.h"
#include "plumb/converge.h"
#include "plumb/metric.h"
#include "verify/verify_protocol.h"

namespace plumb::verify {

namespace {

// The metric the convergence check follows: the pendulum's angle, or the whole state, at
// the end of the run.
std::string ConvergenceMetric(const VerifyContext& ctx) {
  const std::optional<PendulumParams>& pendulum = ctx.pendulum;
  const Model& nominal = ctx.s.Nominal();
  std::string joint = pendulum ? nominal.Name(mjOBJ_JOINT, pendulum->joint) : "";
  if (joint.empty() && pendulum) joint = std::to_string(nominal->jnt_qposadr[pendulum->joint]);
  return pendulum ? fmt::format("qpos[{}]@{:g}", joint, ctx.until)
                  : fmt::format("state@{:g}", ctx.until);
}

// Row `r` when a level diverged: the ladder starts at the model's own timestep, so any
// diverged level is a failure.
CheckRow Diverged(CheckRow r, const ConvergenceResult& c) {
  r.status = CheckStatus::kFail;
  r.measured_text = "a level diverged";
  r.explanation = c.problem;
  return r;
}

// Why the model's own timestep (level 0) is not the recommended one: its own error or
// spread, or else the first finer level that misses the tolerance.
std::string WhyNotConverged(const ConvergenceResult& c, const std::string& metric_text) {
  double target = c.tol * c.scale;
  const ConvergenceLevel& own = c.levels[0];
  auto share = [&](double v) { return fmt::format("{:.3g} ({:.2g}% of its scale {:.3g})", v,
                                                  100 * v / c.scale, c.scale); };
  if (std::isfinite(own.error) && own.error > target) {
    return fmt::format("{} at dt = {:g} s is off by {}, more than tol {:g}", metric_text, own.dt,
                       share(own.error), c.tol);
  }
  if (!LevelMeetsTolerance(own, false, target)) {
    return fmt::format("{} at dt = {:g} s differs from a finer level by {}, more than tol {:g}",
                       metric_text, own.dt, share(own.spread), c.tol);
  }
  std::size_t i = 1;
  while (i + 1 < c.levels.size() && LevelMeetsTolerance(c.levels[i], false, target)) ++i;
  const ConvergenceLevel& finer = c.levels[i];
  double miss = std::isfinite(finer.error) && finer.error > target ? finer.error : finer.spread;
  return fmt::format(
      "{} at dt = {:g} s meets tol {:g}, but the finer dt = {:g} s does not (off by {}): the "
      "estimates do not settle as dt shrinks, so no level above it is recommended",
      metric_text, own.dt, c.tol, finer.dt, share(miss));
}

// The explanation of a passing row: the error against the extrapolation where an order shows,
// else the levels' agreement.
std::string Converged(const ConvergenceResult& c, const std::string& metric_text,
                      const std::string& integrator, double expected) {
  const ConvergenceLevel& own = c.levels[0];
  if (c.estimate.resolved && std::isfinite(own.error)) {
    std::string text = fmt::format(
        "{} with {} at dt = {:g} s is within {:.2g}% of the extrapolated {:.10g}; observed "
        "order {:.2f} (expected {:g} for {}).",
        metric_text, integrator, own.dt, 100 * own.error / c.scale, c.estimate.extrapolated,
        c.estimate.order, expected, integrator);
    if (std::fabs(c.estimate.order - expected) > 0.5) {
      text += " The order differs from the integrator's.";
    }
    return text;
  }
  return fmt::format(
      "{} with {} at dt = {:g} s and every finer level agree within {:.3g} ({:.2g}% of its scale "
      "{:.3g}), inside tol {:g}: converged. The order is information, not the verdict: {}.",
      metric_text, integrator, own.dt, own.spread, 100 * own.spread / c.scale, c.scale, c.tol,
      c.estimate.note);
}

// Each level's timestep and value, for the row's explanation: "dt=0.002: 0.5, dt=0.001: ...".
std::string LevelsText(const ConvergenceResult& c) {
  std::string levels;
  for (const ConvergenceLevel& l : c.levels) {
    levels += fmt::format("{}dt={:g}: {:.10g}", levels.empty() ? "" : ", ", l.dt, l.value);
  }
  return levels;
}

// Fills in row `r`'s numbers for the model's own timestep `dt` (level 0): its error against
// the extrapolation where an order shows (then true), else how far the finer levels spread.
bool SetLevelNumbers(CheckRow* r, const ConvergenceResult& c, double dt, double tol) {
  const ConvergenceLevel& own = c.levels[0];
  r->reference_text = fmt::format("tol {:g} x scale {:.3g}", tol, c.scale);
  r->reference.value = tol * c.scale;
  bool estimated = c.estimate.resolved && std::isfinite(own.error);
  r->measured.value = estimated ? own.error : own.spread;
  r->rel_error = r->measured.value / c.scale;
  r->measured_text =
      estimated ? fmt::format("error {:.3g} at dt = {:g} s (order {:.2f})", own.error, dt,
                              c.estimate.order)
                : fmt::format("levels within {:.3g} at dt = {:g} s (no order)", own.spread, dt);
  return estimated;
}

// What a row that did not converge advises: the timestep plumb converge recommends, if any.
std::string NotConvergedAdvice(const ConvergenceResult& c, const std::string& metric_text,
                               double tol) {
  return c.recommended_dt > 0
             ? fmt::format(
                   "the largest timestep that would pass, with every finer level, is "
                   "{:g} s (as plumb converge --metric '{}' --tol {:g} recommends from "  // command
                   "this start)",
                   c.recommended_dt, metric_text, tol)
             : std::string("no tested timestep passes");
}

}  // namespace

CheckRow CheckConvergence(const VerifyContext& ctx, CheckRow r) {
  const VerifyScenario& s = ctx.s;
  const Trace& nominal = ctx.trace;
  double tol = ctx.tol;
  if (!nominal.kinetic.empty() &&
      *std::max_element(nominal.kinetic.begin(), nominal.kinetic.end()) == 0) {
    return Skip(r.id, r.title, "nothing moves in the nominal run: every timestep gives the same");
  }
  const mjModel* m = s.Nominal().get();
  double dt = m->opt.timestep;
  std::string metric_text = ConvergenceMetric(ctx);
  Metric metric = ParseMetric(s.model(), metric_text);
  // plumb converge's ladder (dt to dt/16) and rule, so both recommend the same timestep
  ConvergenceResult c = Converge(s.model(), s.sets(), metric, dt, 4, tol, ctx.until, s.stop());
  double expected = ExpectedOrder(m->opt.integrator);
  if (ctx.figures != nullptr) {
    ctx.figures->convergence_metric = metric_text;
    ctx.figures->convergence = c;
    ctx.figures->expected_order = expected;
  }
  if (!c.ok) return Diverged(std::move(r), c);
  std::string integrator = compat::NameOf(compat::kIntegrators, m->opt.integrator);
  bool contacts = nominal.max_ncon > 0;
  std::string notes = contacts ? " Caveat: " + ContactCaveat(nominal.max_ncon) + "." : "";
  if (!SolrefNote(c).empty()) notes += " The " + SolrefNote(c) + ".";
  const ConvergenceLevel& own = c.levels[0];  // the model's own timestep
  std::string levels = LevelsText(c);
  bool estimated = SetLevelNumbers(&r, c, dt, tol);
  if (c.recommended_dt == dt) {
    r.status = CheckStatus::kPass;
    r.explanation =
        Converged(c, metric_text, integrator, expected) + notes + " Levels " + levels + ".";
    return r;
  }
  // a clean asymptotic sequence proves the error; contacts or an odd order only suggest it
  bool proven = estimated && own.error > tol * c.scale && !contacts &&
                std::fabs(c.estimate.order - expected) <= 0.5;
  r.status = proven ? CheckStatus::kFail : CheckStatus::kWarn;
  std::string order = c.estimate.resolved
                          ? fmt::format("Observed order {:.2f} (expected {:g} for {}).",
                                        c.estimate.order, expected, integrator)
                          : "No order visible: " + c.estimate.note + ".";
  r.explanation =
      fmt::format("not converged: {}; {}. {}{} Levels {}.", WhyNotConverged(c, metric_text),
                  NotConvergedAdvice(c, metric_text, tol), order, notes, levels);
  return r;
}

}  // namespace plumb::verify
