// The verify protocol's parts (src/verify/verify_*.cc): the nominal scenario and its runs,
// the rows checks fill in, and the checks themselves. Private to verify (src/verify/); the
// public entry point is plumb::Verify (plumb/verify.h).

#ifndef PLUMB_SRC_VERIFY_VERIFY_PROTOCOL_H_
#define PLUMB_SRC_VERIFY_VERIFY_PROTOCOL_H_

#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "plumb/analytic.h"
#include "plumb/keyframe.h"
#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/run.h"
#include "plumb/sleep.h"
#include "plumb/verify.h"

namespace plumb::verify {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// a step small enough that RK4 is exact to round-off on the chapter's pendulum
constexpr double kReferenceDt = 1e-4;

double RelError(double measured, double reference);

// An empty row: every number NaN until a check fills it in.
CheckRow Row(std::string id, std::string title);

CheckRow Skip(std::string id, std::string title, std::string why);

// Fills in the measured and reference values, their relative error and their text.
void SetNumbers(CheckRow* r, double measured, double reference, const char* unit,
                const char* spec = "{:.10g}");

std::string Seconds(double t);

// Everything a check needs from one run, sampled at every step.
struct Trace {
  std::vector<double> t;
  std::vector<double> energy;               // potential + kinetic, J
  std::vector<double> kinetic;              // J
  std::vector<std::vector<double>> coords;  // each hinge/slide joint's qpos over time
  std::vector<std::vector<double>> vels;    // ... and its qvel
  std::vector<std::string> coord_names;
  std::vector<double> final_state;  // qpos, qvel, act at the end
  bool fatal = false;  // MuJoCo stopped the run with a fatal error (result.divergence says)
  std::vector<int> ncon;  // contacts at each sample (with energy)
  std::vector<int> nefc;  // constraint rows at each sample (with energy)
  int max_ncon = 0;
  int max_nefc = 0;
  RunResult result;
};

// The scenario under test: the nominal model started at the reference pose, with the user's
// assignments on top.
class VerifyScenario {
 public:
  VerifyScenario(const Model& model, const VerifyOptions& options);

  const Model& model() const { return model_; }
  // What every run applies: the reference pose's keyframe, then the user's assignments.
  const std::vector<Assignment>& sets() const { return sets_; }
  // The user's assignments alone (VerifyOptions::sets).
  const std::vector<Assignment>& user_sets() const { return user_sets_; }
  // VerifyReport::start: "keyframe 'home'", "qpos0 with qpos[hinge]=0.7".
  const std::string& start() const { return start_; }
  // The reference pose the runs start from (plumb/keyframe.h).
  const ReferencePose& pose() const { return pose_; }
  const StopToken& stop() const { return stop_; }

  Assignment Set(const std::string& text) const { return ParseAssignment(model_, text); }

  // Runs the scenario plus `extra` assignments (applied after the user's) for `until` s.
  // With `energy`, the trace also holds energy and contact counts, which cost one more
  // mj_forward per step; without, those stay empty. Runs are deterministic, so a repeated
  // request is answered from memory.
  const Trace& Simulate(const std::vector<Assignment>& extra, double until,
                        bool energy = false) const;

  // Runs without looking in memory (determinism needs a second real run).
  Trace SimulateAnew(const std::vector<Assignment>& extra, double until, bool energy) const;

  // The model after the user's assignments (for reading nominal parameters).
  const Model& Nominal() const { return nominal_; }

  // The bodies that start asleep in the model as loaded; every run here is awake
  // (plumb/sleep.h).
  const SleepingStart& asleep() const { return asleep_; }

 private:
  Model model_;  // as loaded, awake
  ReferencePose pose_;
  std::vector<Assignment> sets_;
  std::vector<Assignment> user_sets_;
  std::string start_;
  StopToken stop_;
  Model nominal_;
  SleepingStart asleep_;
  mutable std::map<std::string, Trace> memo_;
};

// What every check is given.
struct VerifyContext {
  const VerifyScenario& s;
  const Model& model;    // as loaded
  const Model& nominal;  // with the user's assignments
  const std::optional<PendulumParams>& pendulum;
  const Trace& trace;  // the nominal run, with energy
  double until;        // its length, s
  // the energy check's run: the nominal one, or longer for a pendulum (several swings)
  const Trace& energy_trace;
  double energy_until;
  double tol;
  int dof = -1;                      // a pendulum's hinge dof (and qpos address)
  double theta0 = 0;                 // its start angle
  VerifyFigures* figures = nullptr;  // where checks leave what a picture shows
};

// What the pendulum checks read from the context, in one line:
//   const auto& [s, p, dof, theta0, tol] = Pendulum(ctx);
struct PendulumCase {
  const VerifyScenario& s;
  const PendulumParams& p;
  int dof;
  double theta0;
  double tol;
};
inline PendulumCase Pendulum(const VerifyContext& ctx) {
  return {ctx.s, *ctx.pendulum, ctx.dof, ctx.theta0, ctx.tol};
}

// Each check fills in `r` (its id and title already set, from the table in verify.cc).
using CheckFunction = CheckRow (*)(const VerifyContext& ctx, CheckRow r);

// Any model (verify_protocol.cc, verify_convergence.cc, verify_energy.cc).
CheckRow CheckLoad(const VerifyContext& ctx, CheckRow r);
CheckRow CheckStart(const VerifyContext& ctx, CheckRow r);
CheckRow CheckDeterminism(const VerifyContext& ctx, CheckRow r);
CheckRow CheckWarnings(const VerifyContext& ctx, CheckRow r);
CheckRow CheckConvergence(const VerifyContext& ctx, CheckRow r);  // verify_convergence.cc
CheckRow CheckEnergy(const VerifyContext& ctx, CheckRow r);       // verify_energy.cc
CheckRow ExerciseRadians(const VerifyContext& ctx, CheckRow r);

// A single hinge pendulum under gravity (verify_pendulum.cc).
CheckRow CheckAnalyticPeriod(const VerifyContext& ctx, CheckRow r);
CheckRow CheckModelPeriod(const VerifyContext& ctx, CheckRow r);
CheckRow CheckDamping(const VerifyContext& ctx, CheckRow r);
CheckRow ExperimentAmplitude(const VerifyContext& ctx, CheckRow r);
CheckRow ExperimentDamping(const VerifyContext& ctx, CheckRow r);
CheckRow ExperimentTimestep(const VerifyContext& ctx, CheckRow r);
CheckRow ExerciseMoon(const VerifyContext& ctx, CheckRow r);
CheckRow ExerciseDensity(const VerifyContext& ctx, CheckRow r);

}  // namespace plumb::verify

#endif  // PLUMB_SRC_VERIFY_VERIFY_PROTOCOL_H_
