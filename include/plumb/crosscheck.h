// Cross-checking CPU MuJoCo against a GPU engine (MuJoCo Warp, MJX): does the engine a policy
// trains on compute the same physics as the MuJoCo it deploys through?
//
// Five checks, each a set of CheckRows:
//   support     features the engine refuses, or treats differently without a word
//   stages      one step from states along a CPU run, compared stage by stage (kinematics,
//               mass matrix, contact set, constraint rows, constraint forces, accelerations,
//               sensors, next state); the first stage that disagrees is the finding
//   trajectory  open-loop runs from K starts: when each signal parts from CPU MuJoCo's,
//               against a chaos baseline (CPU MuJoCo rounding its state to float32 every step)
//   statistics  N randomized worlds in both: an equivalence test (two one-sided tests) of
//               each metric's mean, with a stated margin
//   throughput  steps per second of the engine and of plumb's rollout on all cores
//
// The engine runs in an adapter process (docs/engine-protocol.md) in its own virtual
// environment; every comparison and verdict is made here.
//
// Example:
//   plumb::CrosscheckOptions options;
//   options.engine = "warp";
//   options.sets = {plumb::ParseAssignment(model, "qpos[hinge]=0.7")};
//   plumb::CrosscheckReport report = plumb::Crosscheck(model, options);
//   report.failed()
//
// Thread-safety: Crosscheck only reads `model` and may run on several threads at once, each
// starting its own adapter.

#ifndef PLUMB_INCLUDE_PLUMB_CROSSCHECK_H_
#define PLUMB_INCLUDE_PLUMB_CROSSCHECK_H_

#include <string>
#include <vector>

#include "plumb/check.h"
#include "plumb/metric.h"
#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/rollout.h"
#include "plumb/stop.h"

namespace plumb {

// Where the engine's adapter and its Python come from.
struct EngineSetup {
  std::string python;   // the engine venv's python
  std::string adapter;  // engines/adapter.py
  // Extra environment for the adapter ("WARP_CACHE_PATH", ...).
  std::vector<std::pair<std::string, std::string>> env;
  double timeout = 1800;  // s per request; past it the adapter is killed (EngineError)
};

struct CrosscheckOptions {
  std::string engine = "warp";  // "warp" or "mjx"
  std::string device = "cpu";   // "cpu" or "cuda"
  EngineSetup setup;
  std::vector<Assignment> sets;  // the nominal scenario (--set, --keyframe, pose)
  double until = 1;              // s: the CPU run the stage samples come from, and each run
  std::vector<std::string> checks = {"support", "stages", "trajectory", "statistics", "throughput"};
  int samples = 8;  // states for the stage check
  int starts = 4;   // K: starts of the trajectory check
  // A signal has parted when the runs differ by more than tol times the larger of its swing on
  // the CPU run and one unit (m or rad).
  double tol = 1e-2;
  double chaos_ratio = 0.5;  // FAIL when the engine parts before this fraction of the baseline
  // statistics
  int worlds = 32;  // N
  std::vector<Randomization> randomize;
  double ctrl_noise = 0;
  std::vector<Metric> metrics;  // none: the final position of every joint (qpos[*]@until)
  double margin = 0.1;          // equivalence margin, of the CPU metric's spread (floor: tol)
  double alpha = 0.05;
  std::uint64_t seed = 0;
  // throughput
  int throughput_steps = 200;
  int threads = 0;  // plumb's rollout: 0 = all cores
  StopToken stop;
};

// What ran on the other side.
struct EngineInfo {
  std::string engine, engine_version, backend, mujoco_version, mujoco_library, device, precision;
};

// A signal of the trajectory check and when it parted, per start.
struct DivergenceTrack {
  std::string signal;  // "qpos[hinge]", "xpos[torso]", "xquat[torso]"
  CheckElement element;
  double threshold = 0;               // m or rad
  std::vector<double> engine, chaos;  // time it parted at each start, s; NaN: never
};

struct ThroughputFigures {
  int worlds = 0;
  long steps = 0;
  double engine_steps_per_second = 0;  // world-steps per second
  double engine_compile_seconds = 0;
  double cpu_steps_per_second = 0;  // plumb rollout, all cores
  int cpu_threads = 0;
};

struct CrosscheckReport {
  std::string model;
  std::string mujoco_version;  // plumb's
  EngineInfo engine;
  std::string model_transfer;  // how the engine got the model ("XML + 3 edits", ...)
  std::vector<CheckRow> rows;  // section = the check's name
  std::vector<DivergenceTrack> divergence;
  ThroughputFigures throughput;
  int Count(CheckStatus status) const;
  bool failed() const { return Count(CheckStatus::kFail) > 0; }
};

// Runs the checks of `options` against the engine. The model is the one plumb runs, with
// options.sets applied; the engine gets the same (docs/crosscheck.md says how).
// @throws ValueError / PathError for bad options; UnavailableError when the adapter or its
// Python is missing; EngineError when the adapter fails (not when the engine refuses the
// model: that is a support row); Interrupted when options.stop asks; MujocoError.
CrosscheckReport Crosscheck(const Model& model, const CrosscheckOptions& options);

// The engines plumb knows: {"warp", "mjx"}.
const std::vector<std::string>& CrosscheckEngines();

// Where plumb finds `engine`'s adapter and virtual environment:
// - the adapter folder: $PLUMB_ENGINES_DIR, else share/plumb/engines beside the running
//   program (an installed plumb, wherever its prefix went), else the configured install
//   prefix's, else the source tree's engines/ (a build tree);
// - the environment: $PLUMB_ENGINE_VENVS/ENGINE-HASH, else $XDG_CACHE_HOME (or ~/.cache)
//   /plumb/engines/ENGINE-HASH, HASH that of the engine's lock file, so a new lock makes a
//   new environment. The folder holding the environments is made if missing; it must be an
//   absolute path plumb can write, checked before anything else is written.
// @throws ArgumentError for an unknown engine; ValueError naming the variable when
// PLUMB_ENGINE_VENVS (or the XDG_CACHE_HOME or HOME it derives from) is empty, relative, has a
// file on its way, or cannot be made or written, and when PLUMB_ENGINES_DIR holds no
// adapter.py; UnavailableError when no adapter folder exists.
EngineSetup FindEngineSetup(const std::string& engine);

// Whether `setup`'s environment is complete (made, and its last install finished).
bool EngineEnvironmentReady(const EngineSetup& setup);

// Makes the environment from PyPI (hash-pinned; MuJoCo Warp is about 540 MB, MJX about
// 690 MB), saying so on stderr first. @throws UnavailableError naming what is missing when it
// cannot (no network, no python3-venv).
void MakeEngineEnvironment(const std::string& engine, const EngineSetup& setup);

// FindEngineSetup, with the environment made first when it is not ready (a first crosscheck).
// @throws as those two do.
EngineSetup ReadyEngineSetup(const std::string& engine);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_CROSSCHECK_H_
