// The charts of a verify run, also used by other reports: the nominal run's q(t), q̇(t),
// phase portrait and energy; a convergence study on log-log axes; a pendulum's period
// against amplitude.

#ifndef PLUMB_SRC_REPORT_VERIFY_CHARTS_H_
#define PLUMB_SRC_REPORT_VERIFY_CHARTS_H_

#include <string>

#include "plumb/converge.h"
#include "plumb/model.h"
#include "plumb/verify.h"
#include "report/html.h"

namespace plumb::report {

// q(t) and q̇(t) of every hinge and slide joint (six to a chart), a phase portrait per
// joint (none past 24 joints), and the total energy, each with notes for the kind of model
// `model` is: a pendulum (figures.pendulum), a floating robot (a free joint) or a fixed-base
// mechanism. Nothing when the run has no samples.
void AddRunCharts(Page* page, const Model& model, const VerifyFigures& figures);

// The successive differences (and estimated errors) against dt on log-log axes, with a
// line of the expected slope through the finest resolved point. Nothing without levels.
void AddConvergenceChart(Page* page, const std::string& metric, const ConvergenceResult& c,
                         double expected_order);

// Simulated periods against the elliptic-integral curve and the small-angle period.
// Nothing when no period was measured.
void AddPeriodChart(Page* page, const PendulumFigures& figures);

}  // namespace plumb::report

#endif  // PLUMB_SRC_REPORT_VERIFY_CHARTS_H_
