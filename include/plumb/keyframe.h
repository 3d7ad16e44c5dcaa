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

#include <functional>
#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/notice.h"
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

// The assignment that starts a run at the whole qpos `values`: nq numbers separated by commas
// or spaces, in MuJoCo's qpos order (a free joint's x y z and quaternion w x y z, then the
// joints as the model lists them), as `--qpos` takes them. Its text reads "qpos=...".
// @throws ArgumentError (argument "qpos") naming nq and what makes it up when the count
// differs, or for a value that is not a finite number.
Assignment QposAssignment(const Model& model, const std::string& values);

// The assignments of a pose file (`--pose`): either one PATH=VALUE a line as --set takes them
// (`qpos[FL_thigh_joint]=1.2`, `qpos[root][2]=0.1`, any state or parameter), or a whole qpos
// vector alone (numbers only, over one line or several, as QposAssignment). Blank lines and
// lines starting with '#' are skipped. @throws IoError when the file cannot be read;
// ArgumentError (argument "pose", value the file and line) for a line that is not a valid
// assignment, or a vector whose length is not nq.
std::vector<Assignment> PoseFileAssignments(const Model& model, const std::string& path);

// What a run starts from, as every front end takes it (the CLI's --keyframe, --pose, --qpos
// and --set; the Python keywords keyframe, pose, qpos and set): each part empty when not given.
struct StartSpec {
  std::string keyframe;           // a keyframe's name ("#0" by id)
  std::string pose;               // a pose file (PoseFileAssignments)
  std::string qpos;               // a whole qpos vector's text (QposAssignment)
  std::vector<std::string> sets;  // PATH=VALUE texts
};

// The start's assignments in the order a run applies them, each later one winning: the
// keyframe, the pose file, the qpos vector, then every set. Each assignment's warnings go to
// `notices` (AddAssignmentNotices), named by `prefix` and the argument it came from ("pose",
// "qpos", "set"): Python's "set 'ctrl[hip]=5'", the plumb command's prefix "--" gives
// "--set 'ctrl[hip]=5'". @throws as KeyframeAssignments, PoseFileAssignments, QposAssignment
// and ParseAssignment do.
std::vector<Assignment> StartAssignments(const Model& model, const StartSpec& start,
                                         Notices* notices = nullptr,
                                         const std::string& prefix = "");

// Adds each of `a`'s warnings (Assignment::warnings: a ctrl outside its ctrlrange, which MuJoCo
// clamps, ...) to `notices` as a kStart warning about the assignment as the caller wrote it:
// subject "ARGUMENT 'TEXT'", `argument` as the caller names it ("set", "vary", "--set").
void AddAssignmentNotices(const Assignment& a, const std::string& argument, Notices* notices);

// Something about a start its authors would not have meant: a limited joint outside its range
// (the limit throws it back in the first steps, and every check after measures that), or a
// contact deeper than its pair's solimp width (MuJoCo pushes the geoms apart at full
// impedance). One definition for audit, verify and the front ends.
struct StartIssue {
  enum class Kind { kJointOutsideRange, kDeepContact };
  Kind kind = Kind::kJointOutsideRange;
  int id = -1;          // the joint; for a contact its first geom
  int id2 = -1;         // a contact's second geom; -1 for a joint
  std::string element;  // "joint 'thj0' (id 12)", "geoms 'left_pad' (id 3) and 'right_pad' (id 4)"
  std::string unit;     // "rad" or "m"
  double value = 0;     // the joint's position (a ball joint's angle), or the penetration (> 0)
  double lo = 0, hi = 0;  // the joint's range; for a contact 0 and the pair's solimp width
  // One sentence: "joint 'thj0' (id 12) starts at 0 rad, outside its range [0.263, 1.396]
  // (0.263 rad below it)".
  std::string text;
};

// The pose a check judges a model in when no run is asked for (audit's layers, snapshot's
// reference state): the keyframe the user named, else the model's keyframe "home", else
// its keyframe "test", else qpos0. One definition for every command.
//
// A model without either keyframe is run as its authors run it, within its joint ranges: where
// qpos0 puts a limited hinge or slide outside its range (Menagerie's Allegro hand: thj0 at 0,
// range [0.263, 1.396]), the reference pose moves it 1% of the range's width inside its nearest
// bound (`into_range`), so no run starts with a limit throwing the joint back. audit's
// structure.start still FAILs naming qpos0's value (the model has no valid start of its own).
struct ReferencePose {
  int keyframe = -1;        // -1: qpos0
  std::string description;  // "keyframe 'stand' (--keyframe)", "keyframe 'home'", "qpos0"
  // For qpos0 only: one assignment per joint qpos0 puts outside its range, bringing it inside
  // ("qpos[thj0]=0.27433"); StartAtPose and ReferenceStart apply them before the caller's.
  std::vector<Assignment> into_range;
  // The same joints as StartIssues names them at qpos0 (value: qpos0's), in the same order.
  std::vector<StartIssue> outside;
};

// @throws ValueError as FindKeyframe does, for an unknown `named`.
ReferencePose FindReferencePose(const Model& model, const std::string& named = "");

// The assignments that start a run at `pose` with `sets` on top (what a report's pictures start
// from): the pose's keyframe (none for qpos0), then `sets`.
std::vector<Assignment> ReferenceStart(const Model& model, const ReferencePose& pose,
                                       const std::vector<Assignment>& sets);

// What a run from `pose` with `sets` on top starts from, in words, for a report's header:
// "keyframe 'home'", "qpos0 with qpos[hinge]=0.7", "keyframe 'home' with 5 assignments" (the
// assignments by their text when they are few and short, else by their number).
std::string DescribeStart(const ReferencePose& pose, const std::vector<Assignment>& sets);

// Puts `data` at `pose` with `sets` applied: the assignments (parameters and state) in order,
// then the keyframe's state, then the state assignments again, so that the user's --set wins
// over the keyframe. @throws ValueError / PathError as ApplyAssignments does; MujocoError.
void StartAtPose(Model& model, Data& data, const ReferencePose& pose,
                 const std::vector<Assignment>& sets);

// The start issues of `data` (after mj_forward at the start): every limited hinge, slide or
// ball joint whose position lies outside its range by more than 1e-6 of the range's width,
// then every contact whose penetration exceeds its solimp width (the width MuJoCo reaches
// full impedance at). Joints in id order, contacts deepest first. Reads only; throws nothing.
std::vector<StartIssue> StartIssues(const Model& model, const Data& data);

// The joints qpos0 puts outside their ranges (pose.outside) that still sit where `pose` moved
// them in `data` (a state started at `pose`): those the caller's assignments did not move
// elsewhere. Empty for a keyframe. Reads only; throws nothing.
std::vector<StartIssue> MovedIntoRange(const Model& model, const Data& data,
                                       const ReferencePose& pose);

// "joint 'thj0' (id 12) at 0 rad outside [0.263, 1.396]; 10 more" over at most `listed`
// issues, for a one-line header or row; "" when there are none.
std::string DescribeStartIssues(const std::vector<StartIssue>& issues, int listed = 3);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_KEYFRAME_H_
