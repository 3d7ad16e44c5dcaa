// Regression snapshots for CI: what a model is (structure, inertia, actuators, sensors,
// options) and what it does (a short golden trajectory), as stable JSON, and a diff that
// names every change in MuJoCo's own words.
//
// Example:
//   std::string text = plumb::MakeSnapshot(model, {});        // pretty JSON
//   plumb::SnapshotDiff diff = plumb::DiffSnapshot(text, edited_model, {}, 1e-6);
//   diff.changes[0].what   // "dof_damping[hinge]: 0.05 → 0.1"
//
// Thread-safety: MakeSnapshot and DiffSnapshot only read `model` (they run on copies of their
// own) and start no threads, so calls may run at once from several threads, also on one Model;
// each takes (and drops) the calling thread's pending MuJoCo warnings (TakeMujocoWarnings).

#ifndef PLUMB_INCLUDE_PLUMB_REGRESSION_H_
#define PLUMB_INCLUDE_PLUMB_REGRESSION_H_

#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"

namespace plumb {

// Number of steps of the golden trajectory.
inline constexpr int kSnapshotSteps = 100;

// The snapshot of `model` after `sets`, as pretty JSON (2-space indent, keys in a fixed
// order, doubles printed to round-trip exactly). The text of each of `sets` is recorded
// ("sets": ["qpos[hinge]=0.7"]) so that DiffSnapshot applies them again. The golden trajectory
// starts at the reference pose (FindReferencePose: keyframe "home", else "test", else qpos0) and
// drives every ctrl-limited actuator i with ctrl = centre + 0.5 * radius * sin(2*pi*t*(1 + 0.37*i))
// (0 for unlimited ones) for kSnapshotSteps steps, recording qpos, qvel and act after each. Every
// element records its id (ids are not compared one by one: a shift is one change). A diverging
// trajectory is recorded up to the step before and `divergence` (when given) receives the reason;
// it is left empty otherwise. @throws ValueError / PathError when the model refuses `sets`;
// MujocoError.
std::string MakeSnapshot(const Model& model, const std::vector<Assignment>& sets,
                         std::string* divergence = nullptr);

// One difference between a snapshot and the current model.
struct SnapshotChange {
  std::string what;  // in words: "body_mass[link]: 1 → 2", "body added: gripper"
  bool beyond_tol = true;
  // What changed, for machines: `kind` is "structure" (sizes, element types, parents,
  // id shifts), "parameter" (a numeric field of an element), "option" (opt.*), "added"
  // or "removed" (an element), "trajectory" (the golden trajectory), "compiler" (see
  // SnapshotDiff::compiler) or "set" (a --set
  // recorded in the snapshot that the current model refuses). `path` names it in
  // plumb's words ("dof_damping[hinge]", "opt.timestep", "body[gripper]",
  // "trajectory.qpos[0]"); `old_value` and `new_value` are JSON texts (a number, a
  // string, an array, or null when there is no value on that side).
  std::string kind;
  std::string path;
  std::string old_value = "null";
  std::string new_value = "null";
  long step = 0;  // for a trajectory departure: the first step beyond tolerance (1-based)
};

struct SnapshotDiff {
  std::string model;                    // the current model's file
  std::vector<std::string> model_sets;  // the caller's `sets` (their text), applied last
  double tol = 0;
  std::vector<SnapshotChange> changes;  // only changes beyond tolerance are listed
  // Under another MuJoCo release than the snapshot's: values its compiler derives from mesh
  // files (kind "compiler": a mesh geom's fitted size, pos, quat, aabb, rbound, and the
  // dof_length scales computed from body sizes) that it
  // derived differently. Listed apart: they say the release changed, not the model.
  std::vector<SnapshotChange> compiler;
  std::vector<std::string> notes;      // e.g. a different MuJoCo version wrote the snapshot
  std::vector<std::string> sets;       // the --set values the snapshot recorded, reapplied
  std::string snapshot_plumb_version;  // the versions that wrote the snapshot
  std::string snapshot_mujoco_version;
  bool diverged = false;  // the current model's trajectory diverged
  bool changed() const { return !changes.empty(); }
};

// Compares `snapshot_text` (as MakeSnapshot wrote it) with `model` after the --set values
// the snapshot recorded (none in snapshots written before they were recorded), then
// `sets` (applied after them, so they win).
// Parameters differ when |a - b| > tol * max(|a|, |b|) (relative: 1e-8 -> 2e-8 is a
// change); trajectory values when |a - b| > tol * max(1, |a|, |b|). @throws ValueError
// when the text is not a plumb snapshot or is damaged, naming the entry, e.g.
// "structure.body.link.body_mass: expected a number, got \"x\""; ArgumentError ("tol") for a
// negative or NaN tol; ValueError / PathError when
// the model refuses `sets` (a recorded --set it refuses is listed as a change instead);
// MujocoError.
SnapshotDiff DiffSnapshot(const std::string& snapshot_text, const Model& model,
                          const std::vector<Assignment>& sets, double tol);

// The default tol of plumb diff (--tol) and plumb.diff (tol=).
inline constexpr double kDiffTolerance = 1e-6;

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_REGRESSION_H_
