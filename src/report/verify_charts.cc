// The run, convergence and period charts (verify_charts.h).

#include "report/verify_charts.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace plumb::report {
namespace {

constexpr std::size_t kMostPoints = 1500;  // per curve: enough for the eye, light to draw
constexpr std::size_t kMostJoints = 6;

std::vector<double> Pick(const std::vector<double>& v, const std::vector<std::size_t>& at) {
  std::vector<double> out;
  out.reserve(at.size());
  for (std::size_t i : at) out.push_back(i < v.size() ? v[i] : NAN);
  return out;
}

}  // namespace

void AddRunCharts(Page* page, const VerifyFigures& f) {
  if (f.t.size() < 2) return;
  std::vector<std::size_t> at = Thin(f.t.size(), kMostPoints);
  std::vector<double> t = Pick(f.t, at);
  page->Heading("The nominal run");
  if (!f.q.empty()) {
    Chart q("q(t): each joint's coordinate", {"t (s)"}, {"q (rad or m)"});
    Chart qdot("q\u0307(t): each joint's velocity", {"t (s)"}, {"q\u0307 (rad/s or m/s)"});
    for (std::size_t j = 0; j < f.q.size() && j < kMostJoints; ++j) {
      q.series.push_back({f.coords[j], t, Pick(f.q[j], at)});
      qdot.series.push_back({f.coords[j], t, Pick(f.qdot[j], at)});
    }
    q.how_to_read =
        "A damped pendulum swings with an amplitude that shrinks a little every period and a "
        "period that grows slightly at large angles. Healthy: smooth curves that repeat. Sick: "
        "a kink or a jump (a contact or a limit acting hard, or a timestep too large), growth "
        "where nothing drives the system (energy is being created), or a flat line where "
        "something should move.";
    qdot.how_to_read =
        "The velocity leads the angle by a quarter period and is largest where the angle "
        "crosses its rest value. Healthy: smooth. Sick: spikes at single samples (stiff "
        "contacts or constraints resolved in one step) or noise that does not shrink when the "
        "timestep is halved.";
    page->BeginGrid();
    page->Add(q);
    page->Add(qdot);
    page->EndGrid();
    Chart phase("Phase portrait of " + f.coords[0], {f.coords[0] + " (rad or m)"},
                {"velocity (rad/s or m/s)"});
    phase.series.push_back({f.coords[0], Pick(f.q[0], at), Pick(f.qdot[0], at)});
    phase.how_to_read =
        "Angle against velocity: an undamped swing is a closed loop traced again and again; "
        "damping turns it into a spiral that winds slowly inwards to the rest point. Sick: a "
        "spiral that winds outwards (energy is being created: the integrator or the timestep), "
        "or loops that do not close on an undamped model.";
    page->Add(phase);
  }
  if (!f.energy.empty()) {
    Chart energy("Total energy (potential + kinetic)", {"t (s)"}, {"energy (J)"});
    energy.series.push_back({"total energy", t, Pick(f.energy, at)});
    energy.series.push_back({"start value",
                             {t.front(), t.back()},
                             {f.energy.front(), f.energy.front()},
                             Series::kLine,
                             "#888888",
                             true});
    energy.how_to_read =
        "With damping the energy falls, in steps where the speed is highest, and never rises "
        "without an actuator driving. Undamped it should stay on the dashed start line to "
        "within the integrator's error (RK4: invisible; semi-implicit Euler: a small "
        "oscillation that does not grow). Sick: a steady climb (energy created: too large a "
        "timestep, stiff contacts) or a sudden jump (an impact resolved badly).";
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
