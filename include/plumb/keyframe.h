// Starting a run from a keyframe of the model (MJCF <keyframe><key name="home" .../>),
// the common way to start from a pose: `--keyframe NAME` on run, verify, converge,
// sweep, rollout, audit and snapshot.
//
// Example:
//   std::vector<plumb::Assignment> start = plumb::KeyframeAssignments(model, "home");
//   start.push_back(plumb::ParseAssignment(model, "qvel[hinge]=1"));  // --set on top
//   plumb::ApplyAssignments(model, data, start);
//
// Thread-safety: FindKeyframe, KeyframeAssignments and FindReferencePose only read the model and
// may be called from several threads at once. StartAtPose writes `model` and `data`: no other
// thread may use them meanwhile.

#ifndef PLUMB_INCLUDE_PLUMB_KEYFRAME_H_
#define PLUMB_INCLUDE_PLUMB_KEYFRAME_H_

#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"

namespace plumb {

// The index of keyframe `name` in `model` (unnamed keyframes by id: "#0").
// @throws ValueError for an unknown name, listing the model's keyframes and the nearest
//         ("did you mean"), or saying the model has none.
int FindKeyframe(const Model& model, const std::string& name);

// The state assignments that put a run at keyframe `name` as mj_resetDataKeyframe does:
// time, qpos, qvel, act, ctrl, mocap_pos and mocap_quat of the key (arrays of size zero
// are left out). ApplyAssignments resets the data before it writes state, so everything
// else starts at MuJoCo's reset values, as after mj_resetDataKeyframe. Put the user's
// --set assignments after these so they apply on top. Each assignment's text reads
// "keyframe 'home': qpos". Empty `name`: no assignments.
// @throws ValueError as FindKeyframe does.
std::vector<Assignment> KeyframeAssignments(const Model& model, const std::string& name);

// The pose a check judges a model in when no run is asked for (audit's layers, snapshot's
// reference state): the keyframe the user named, else the model's keyframe "home", else
// its keyframe "test", else qpos0. One definition for every command.
struct ReferencePose {
  int keyframe = -1;        // -1: qpos0
  std::string description;  // "keyframe 'stand' (--keyframe)", "keyframe 'home'", "qpos0"
};

// @throws ValueError as FindKeyframe does, for an unknown `named`.
ReferencePose FindReferencePose(const Model& model, const std::string& named = "");

// Puts `data` at `pose` with `sets` applied: the assignments (parameters and state) in order,
// then the keyframe's state, then the state assignments again, so that the user's --set wins
// over the keyframe. @throws ValueError / PathError as ApplyAssignments does; MujocoError.
void StartAtPose(Model& model, Data& data, const ReferencePose& pose,
                 const std::vector<Assignment>& sets);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_KEYFRAME_H_
