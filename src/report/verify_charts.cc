// The run, convergence and period charts (verify_charts.h).

#include "report/verify_charts.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace plumb::report {
namespace {

constexpr std::size_t kJointsPerChart = 6;     // lines a chart keeps apart (and its palette)
constexpr std::size_t kMostPhasePortraits = 24;  // beyond: none, the page says why

// What the nominal run is for the model at hand, so the notes say what healthy looks like.
enum class RunKind { kPendulum, kFloating, kFixedBase };

RunKind KindOf(const Model& model, const VerifyFigures& f) {
  if (f.pendulum) return RunKind::kPendulum;
  const mjModel* m = model.get();
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] == mjJNT_FREE) return RunKind::kFloating;
  }
  return RunKind::kFixedBase;
}

struct RunNotes {
  std::string q, qdot, phase, energy;
};

RunNotes NotesFor(RunKind kind) {
  const char* sick_curve =
      " Sick: a kink or a jump (a contact or a limit acting hard, or a timestep too large), "
      "growth where nothing drives the model (energy is being created), or jitter that never "
      "settles.";
  RunNotes n;
  n.qdot =
      "Healthy: smooth, and zero wherever the coordinate is still. Sick: spikes at single "
      "samples (stiff contacts or constraints resolved in one step) or noise that does not "
      "shrink when the timestep is halved.";
  switch (kind) {
    case RunKind::kPendulum:
      n.q = "A damped pendulum swings with an amplitude that shrinks a little every period and "
            "a period that grows slightly at large angles. Healthy: smooth curves that repeat. "
            "Sick: a kink or a jump (a contact or a limit acting hard, or a timestep too large), "
            "growth where nothing drives the system (energy is being created), or a flat line "
            "where something should move.";
      n.qdot = "The velocity leads the angle by a quarter period and is largest where the angle "
               "crosses its rest value. " + n.qdot;
      n.phase = "Angle against velocity: an undamped swing is a closed loop traced again and "
                "again; damping turns it into a spiral that winds slowly inwards to the rest "
                "point. Sick: a spiral that winds outwards (energy is being created: the "
                "integrator or the timestep), or loops that do not close on an undamped model.";
      n.energy = "With damping the energy falls, in steps where the speed is highest, and never "
                 "rises without an actuator driving. Undamped it should stay on the dashed "
                 "start line to within the integrator's error (RK4: invisible; semi-implicit "
                 "Euler: a small oscillation that does not grow). Sick: a steady climb (energy "
                 "created: too large a timestep, stiff contacts) or a sudden jump (an impact "
                 "resolved badly).";
      return n;
    case RunKind::kFloating:
      n.q = std::string("Zero control from the start pose: a floating robot with no controller "
                        "drops onto whatever is below it, its joints give way under its weight "
                        "until links, limits or the ground hold them, and then stay still. "
                        "Healthy: quick changes in the first moments, then flat lines.") +
            sick_curve;
      n.energy = "The robot falls and lands, so the energy drops (gravity's work goes into "
                 "impacts, friction and damping) and then stays flat; with no actuator driving "
                 "it never rises. Sick: a climb (interpenetrating geoms pushing apart, a "
                 "too-large timestep) or an energy that keeps oscillating after landing "
                 "(nothing damps the joints: add damping or armature).";
      break;
    case RunKind::kFixedBase:
      n.q = std::string("Zero control from the start pose: each joint sags or swings under "
                        "gravity and comes to rest on its damping, springs or limits (with "
                        "little damping it keeps swinging, slowly losing amplitude). Healthy: "
                        "smooth curves that settle or repeat.") +
            sick_curve;
      n.energy = "With no actuator driving, the energy only falls (damping, friction and "
                 "contacts take it) or, with nothing to take it, stays on the dashed start "
                 "line to within the integrator's error. Sick: a steady climb (energy created: "
                 "too large a timestep, stiff contacts) or a sudden jump (an impact resolved "
                 "badly).";
      break;
  }
  n.phase = "The joint's coordinate against its velocity. A joint that comes to rest ends on a "
            "point of the zero-velocity line; one that swings loops around its rest value, "
            "winding inwards when damped. Sick: loops that grow with no actuator (energy "
            "created), or a tangle near zero velocity that never shrinks (jitter at contacts "
            "or constraints).";
  return n;
}

// q(t) and q̇(t) of joints [first, last), side by side.
void AddJointGroup(Page* page, const VerifyFigures& f, std::size_t first, std::size_t last,
                   const RunNotes& notes) {
  // one chart says "each joint's"; small multiples say which joints they hold
  bool one = f.q.size() <= kJointsPerChart;
  std::string joints = fmt::format("joints {}-{} of {}", first + 1, last, f.q.size());
  Chart q(one ? "q(t): each joint's coordinate" : "q(t): coordinates of " + joints, {"t (s)"},
          {"q (rad or m)"});
  Chart qdot(one ? "q\u0307(t): each joint's velocity" : "q\u0307(t): velocities of " + joints,
             {"t (s)"}, {"q\u0307 (rad/s or m/s)"});
  for (std::size_t j = first; j < last; ++j) {
    q.series.push_back({f.coords[j], f.t, f.q[j]});
    qdot.series.push_back({f.coords[j], f.t, f.qdot[j]});
  }
  q.how_to_read = notes.q;
  qdot.how_to_read = notes.qdot;
  page->BeginGrid();
  page->Add(q);
  page->Add(qdot);
  page->EndGrid();
}

// One phase portrait per joint (none past kMostPhasePortraits, and the page says so).
void AddPhasePortraits(Page* page, const VerifyFigures& f, const RunNotes& notes) {
  if (f.q.size() > kMostPhasePortraits) {
    page->Paragraph(fmt::format("No phase portraits: {} joints are more than a page can show "
                                "({} at most); q(t) and q\u0307(t) above show every joint.",
                                f.q.size(), kMostPhasePortraits),
                    "note");
    return;
  }
  if (f.q.size() > 1) page->BeginGrid();
  for (std::size_t j = 0; j < f.q.size(); ++j) {
    Chart phase("Phase portrait of " + f.coords[j], {f.coords[j] + " (rad or m)"},
                {"velocity (rad/s or m/s)"});
    phase.series.push_back({f.coords[j], f.q[j], f.qdot[j]});
    phase.how_to_read = notes.phase;
    page->Add(phase);
  }
  if (f.q.size() > 1) page->EndGrid();
}

}  // namespace

void AddRunCharts(Page* page, const Model& model, const VerifyFigures& f) {
  if (f.t.size() < 2) return;
  RunNotes notes = NotesFor(KindOf(model, f));
  // the curves end where the run the checks judged ends: say where
  page->Heading(fmt::format("The nominal run, t = 0 to {:g} s", f.t.back()));
  if (!f.q.empty()) {
    if (f.q.size() > kJointsPerChart) {
      page->Paragraph(fmt::format("All {} hinge and slide joints, {} to a chart; click a name "
                                  "in a legend to hide or show that joint.",
                                  f.q.size(), kJointsPerChart));
    }
    for (std::size_t first = 0; first < f.q.size(); first += kJointsPerChart) {
      AddJointGroup(page, f, first, std::min(f.q.size(), first + kJointsPerChart), notes);
    }
    AddPhasePortraits(page, f, notes);
  }
  if (!f.energy.empty()) {
    Chart energy("Total energy (potential + kinetic)", {"t (s)"}, {"energy (J)"});
    energy.series.push_back({"total energy", f.t, f.energy});
    energy.series.push_back({"start value",
                             {f.t.front(), f.t.back()},
                             {f.energy.front(), f.energy.front()},
                             Series::kLine,
                             "#888888",
                             true});
    energy.how_to_read = notes.energy;
    page->Add(energy);
  }
}

void AddConvergenceChart(Page* page, const std::string& metric, const ConvergenceResult& c,
                         double expected_order) {
  std::vector<double> dt, diff, error;
  for (const ConvergenceLevel& l : c.levels) {
    dt.push_back(l.dt);
    diff.push_back(l.diff);
    error.push_back(l.error);
  }
  if (dt.empty()) return;
  page->Heading("Convergence as the timestep shrinks");
  std::string order = c.estimate.resolved ? fmt::format("{:.2f}", c.estimate.order) : "not seen";
  Chart chart(fmt::format("{}: difference to the next halving against dt (observed order {}, "
                          "expected {:g})",
                          metric, order, expected_order),
              {"timestep dt (s)", true}, {"difference |v(dt) - v(dt/2)|", true});
  chart.series.push_back({"difference to dt/2", dt, diff, Series::kPoints});
  chart.series.push_back({"estimated error", dt, error, Series::kPoints, "", false, "crossRot"});
  chart.series.push_back({"difference to dt/2 (joined)", dt, diff});
  // a line of the expected slope through the finest difference above round-off
  for (std::size_t i = c.levels.size(); i-- > 0;) {
    const ConvergenceLevel& l = c.levels[i];
    if (std::isfinite(l.diff) && l.diff > 0 && !l.roundoff) {
      std::vector<double> x = {dt.front(), l.dt};
      std::vector<double> y = {l.diff * std::pow(dt.front() / l.dt, expected_order), l.diff};
      chart.series.push_back({fmt::format("expected slope {:g}", expected_order), x, y,
                              Series::kLine, "#888888", true});
      break;
    }
  }
  chart.how_to_read =
      "On log-log axes a method of order p gives a straight line of slope p: halving dt "
      "divides the difference by 2^p (Euler: 2, RK4: 16). Healthy: the points lie along the "
      "dashed line of the expected slope until they reach round-off (about 1e-12 of the "
      "value), where they flatten into noise. Sick: a slope well below the expected one "
      "(contacts, limits or friction switching on and off lower the order), or points that "
      "do not fall at all (the timestep is far too large, or the run is chaotic).";
  page->Add(chart);
  if (!c.caveat.empty()) page->Paragraph("Caveat: " + c.caveat, "note");
}

void AddPeriodChart(Page* page, const PendulumFigures& f) {
  if (f.periods.empty()) return;
  page->Heading("Period against amplitude");
  Chart chart("Period of the free swing against its amplitude", {"amplitude (rad)"},
              {"period (s)"});
  std::vector<double> ax, ay, px, py;
  for (const auto& p : f.exact_curve) {
    ax.push_back(p.amplitude);
    ay.push_back(p.exact);
  }
  for (const auto& p : f.periods) {
    px.push_back(p.amplitude);
    py.push_back(p.period);
  }
  chart.series.push_back({"exact (elliptic integral)", ax, ay});
  chart.series.push_back({"simulated (RK4)", px, py, Series::kPoints});
  if (!ax.empty()) {
    chart.series.push_back({"small-angle 2\u03c0\u221a(I/mgd)",
                            {ax.front(), ax.back()},
                            {f.small_angle_period, f.small_angle_period},
                            Series::kLine,
                            "#888888",
                            true});
  }
  chart.how_to_read =
      "The small-angle formula says the period does not depend on amplitude; the exact one "
      "(an elliptic integral) says it grows, slowly at first and steeply towards 180\u00b0. "
      "Healthy: the simulated points sit on the exact curve (to about 1e-6 here). Sick: points "
      "on the dashed small-angle line at large amplitudes (the simulation is not a pendulum), "
      "or off both curves (wrong mass, inertia or gravity).";
  page->Add(chart);
}

}  // namespace plumb::report
