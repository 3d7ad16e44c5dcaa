// The verify energy check for any model: whether the nominal run is passive (nothing drives
// it, no constraint stores energy), and then whether total energy stays put (nothing
// dissipates) or only falls (damping).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "core/mujoco_compat.h"
#include "core/strings.h"
#include "verify/verify_protocol.h"

namespace plumb::verify {
using internal::Join;

namespace {

// Whether `m` sets MuJoCo's disable flag `name`, as mjDISABLESTRING spells it ("Actuation",
// "Damper"); false when this MuJoCo has no flag of that name.
bool Disabled(const mjModel* m, const char* name) {
  for (int i = 0; i < mjNDISABLE; ++i) {
    if (std::strcmp(mjDISABLESTRING[i], name) == 0) return (m->opt.disableflags & (1 << i)) != 0;
  }
  return false;
}

// Whether MuJoCo applies the joint and tendon damping, and their dry friction, of `m`
// (MuJoCo 2.x turns damping off with "Passive", 3.x with "Damper").
bool DampingActs(const mjModel* m) { return !Disabled(m, "Damper") && !Disabled(m, "Passive"); }
bool FrictionlossActs(const mjModel* m) {
  return !Disabled(m, "Frictionloss") && !Disabled(m, "Constraint");
}

// What drives the model from outside with actuation as its flags leave it, or "": an actuator
// pushing at ctrl = 0, or an assignment of a nonzero input (a keyframe's ctrl among them).
std::string Driven(const VerifyScenario& s) {
  const mjModel* m = s.Nominal().get();
  bool actuation = !Disabled(m, "Actuation");
  if (actuation) {
    std::string pushing = ActuatorPushingAtZeroControl(s.Nominal());
    if (!pushing.empty()) return pushing;
  }
  for (const Assignment& a : s.sets()) {
    bool input = (a.path.field == "ctrl" && actuation) || a.path.field == "qfrc_applied" ||
                 a.path.field == "xfrc_applied" || a.path.field == "mocap_pos";
    if (input && std::any_of(a.values.begin(), a.values.end(), [](double v) { return v != 0; }))
      return "the assignment '" + a.text + "' drives it";
  }
  return "";
}

// Why a model is not passive in the sense of the energy check whatever its run does, or "".
// Whatever the model's disable flags switch off (actuation, equality constraints, damping, dry
// friction) is not held against it.
std::string NotPassive(const VerifyScenario& s) {
  const mjModel* m = s.Nominal().get();
  if (std::string driven = Driven(s); !driven.empty()) return driven;
  if (m->neq > 0 && !Disabled(m, "Equality") && !Disabled(m, "Constraint"))
    return "it has equality constraints";
  if (m->opt.density != 0 || m->opt.viscosity != 0) return "it has fluid forces";
  for (int i = 0; i < m->ntendon; ++i) {
    if ((m->tendon_damping[i] != 0 && DampingActs(m)) ||
        (m->tendon_frictionloss[i] != 0 && FrictionlossActs(m)))
      return "it has damped tendons";
  }
  if (m->nmocap > 0) return "it has mocap bodies that can push it";
  return "";
}

// The first sample of `run` at which a contact or a joint or tendon limit acts, and what it is;
// sample -1 when none does. Past it, E omits what their soft constraints store.
struct ConstraintOnset {
  long sample = -1;
  std::string why;
};
ConstraintOnset FirstConstraint(const mjModel* m, const Trace& run) {
  // dry friction adds one constraint row per dof or tendon all the time; more rows than
  // that are joint or tendon limits at work, whose soft springs store energy E omits
  int friction_rows = 0;
  for (int i = 0; i < m->nv && FrictionlossActs(m); ++i) {
    friction_rows += m->dof_frictionloss[i] > 0;
  }
  for (int i = 0; i < m->ntendon && FrictionlossActs(m); ++i) {
    friction_rows += m->tendon_frictionloss[i] > 0;
  }
  for (std::size_t k = 0; k < run.ncon.size(); ++k) {
    if (run.ncon[k] > 0) {
      return {static_cast<long>(k),
              "contacts occur (MuJoCo's soft contacts bound energy only roughly)"};
    }
    if (run.nefc[k] > friction_rows) {
      return {static_cast<long>(k),
              "a joint or tendon limit engages (its soft constraint stores energy that E omits)"};
    }
  }
  return {};
}

// The first `samples` samples of `run`: what the energy check judges when a constraint acts
// later.
Trace Head(const Trace& run, long samples) {
  Trace head;
  auto first = [samples](const auto& v) { return std::vector(v.begin(), v.begin() + samples); };
  head.t = first(run.t);
  head.energy = first(run.energy);
  head.kinetic = first(run.kinetic);
  for (const auto& c : run.coords) head.coords.push_back(first(c));
  for (const auto& v : run.vels) head.vels.push_back(first(v));
  head.coord_names = run.coord_names;
  return head;
}

bool Dissipative(const mjModel* m) {
  for (int i = 0; i < m->nv; ++i) {
    if ((m->dof_damping[i] != 0 && DampingActs(m)) ||
        (m->dof_frictionloss[i] != 0 && FrictionlossActs(m)))
      return true;
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

// Row `r` for a run where nothing dissipates: the relative drift of total energy is integration
// error.
CheckRow JudgeConservative(CheckRow r, const Trace& run, double until, double tol) {
  double max_kinetic = *std::max_element(run.kinetic.begin(), run.kinetic.end());
  double e0 = run.energy.front();
  auto [lo, hi] = std::minmax_element(run.energy.begin(), run.energy.end());
  double drift = std::max(std::fabs(*hi - e0), std::fabs(*lo - e0)) / max_kinetic;
  r.measured_text = fmt::format("{:.3g} of max KE", drift);
  r.reference_text = fmt::format("<= {:g}", tol);
  r.measured.value = drift;
  r.reference.value = tol;
  r.status = drift <= tol        ? CheckStatus::kPass
             : drift <= 10 * tol ? CheckStatus::kWarn
                                 : CheckStatus::kFail;
  r.explanation = fmt::format(
      "nothing dissipates energy, so E = potential + kinetic should stay at {:.6g} J; it "
      "strays by {:.3g} of the largest kinetic energy {:.4g} J over {}. A discrete integrator "
      "never conserves it exactly; a smaller timestep or RK4 shrinks the drift.",
      e0, drift, max_kinetic, Seconds(until));
  return r;
}

// Row `r` for a damped run: energy may not rise beyond the integrator's own energy wobble,
// measured on the same run with dissipation removed.
CheckRow JudgeDissipative(CheckRow r, const VerifyScenario& s, const Trace& run, double until) {
  const mjModel* m = s.Nominal().get();
  double max_kinetic = *std::max_element(run.kinetic.begin(), run.kinetic.end());
  std::vector<Assignment> undamped;
  for (int i = 0; i < m->nv; ++i) {
    undamped.push_back(s.Set(fmt::format("dof_damping[{}]=0", m->jnt_dofadr[m->dof_jntid[i]])));
    undamped.push_back(
        s.Set(fmt::format("dof_frictionloss[{}]=0", m->jnt_dofadr[m->dof_jntid[i]])));
  }
  const Trace& twin = s.Simulate(undamped, until, /*energy=*/true);
  auto [tlo, thi] = std::minmax_element(twin.energy.begin(), twin.energy.end());
  double wobble = *thi - *tlo;
  double rise = LargestRise(run.energy);
  double allowed = 1.5 * wobble + 1e-12 * max_kinetic;
  // the peak envelope of a lone hinge/slide coordinate falls (single samples need not);
  // coupled coordinates trade energy, so one of them may swing higher for a while
  std::string envelope;
  bool envelope_ok = true;
  for (std::size_t c = 0; c < run.coords.size() && m->nv == 1; ++c) {
    std::vector<double> peaks = Peaks(run.coords[c]);
    if (peaks.size() < 2) continue;
    bool falling = true;
    for (std::size_t k = 1; k < peaks.size(); ++k) falling = falling && peaks[k] < peaks[k - 1];
    envelope_ok = envelope_ok && falling;
    envelope += fmt::format("{}{}: {} peaks {} ({:.5g} -> {:.5g})", envelope.empty() ? "" : "; ",
                            run.coord_names[c], peaks.size(), falling ? "fall" : "DO NOT fall",
                            peaks.front(), peaks.back());
  }
  r.measured_text = fmt::format("largest rise {:.3g} J", rise);
  r.reference_text = fmt::format("<= {:.3g} J", allowed);
  r.measured = {rise, "J"};
  r.reference = {allowed, "J"};
  r.status = rise <= allowed && envelope_ok ? CheckStatus::kPass : CheckStatus::kFail;
  std::string peaks = m->nv > 1          ? "Peaks are not compared: the coordinates are coupled."
                      : envelope.empty() ? "The coordinate did not swing twice to compare peaks."
                                         : "Peak envelope: " + envelope + ".";
  r.explanation = fmt::format(
      "damping only removes energy: E went from {:.6g} J to {:.6g} J over {}; its largest rise "
      "{:.3g} J {} the integrator's own wobble allowance ({:.3g} J, from the undamped twin). {}",
      run.energy.front(), run.energy.back(), Seconds(until), rise,
      rise <= allowed ? "stays within" : "EXCEEDS", allowed, peaks);
  return r;
}

// What the model's disable flags take out of the energy balance, for the row's explanation.
std::string DisabledNote(const mjModel* m) {
  std::vector<std::string> off;
  if (m->nu > 0 && Disabled(m, "Actuation")) {
    off.push_back("actuation (its actuators exert nothing)");
  }
  if (Disabled(m, "Gravity")) off.push_back("gravity (no potential energy of height)");
  if (!DampingActs(m)) off.push_back("damping");
  if (off.empty()) return "";
  return " The model's opt.disableflags switch off " + Join(off, ", ") + ".";
}

}  // namespace

CheckRow CheckEnergy(const VerifyContext& ctx, CheckRow r) {
  const VerifyScenario& s = ctx.s;
  const Trace& nominal = ctx.energy_trace;
  const mjModel* m = s.Nominal().get();
  if (nominal.result.diverged) return Skip(r.id, r.title, "the nominal run diverged");
  std::string why = NotPassive(s);
  if (!why.empty()) return Skip(r.id, r.title, "no energy bound applies: " + why);
  // before a contact or a limit acts, the run is a plain passive system: judge that part when
  // it is at least a quarter of the run
  ConstraintOnset onset = FirstConstraint(m, nominal);
  long samples = static_cast<long>(nominal.t.size());
  if (onset.sample >= 0 && onset.sample < samples / 4) {
    return Skip(r.id, r.title, "no energy bound applies: " + onset.why);
  }
  std::optional<Trace> head;
  if (onset.sample >= 0) head = Head(nominal, onset.sample);
  const Trace& run = head ? *head : nominal;
  double until = head ? (onset.sample - 1) * m->opt.timestep : ctx.energy_until;
  double max_kinetic = *std::max_element(run.kinetic.begin(), run.kinetic.end());
  if (max_kinetic <= 0) return Skip(r.id, r.title, "nothing moves in the nominal run");
  r = Dissipative(m) ? JudgeDissipative(std::move(r), s, run, until)
                     : JudgeConservative(std::move(r), run, until, ctx.tol);
  if (head) {
    r.explanation +=
        fmt::format(" Judged on the first {} of the {} run: at t = {:g} s {}.", Seconds(until),
                    Seconds(ctx.energy_until), nominal.t[onset.sample], onset.why);
  }
  r.explanation += DisabledNote(m);
  return r;
}

}  // namespace plumb::verify
