#include "plumb/keyframe.h"

#include "core/mujoco_compat.h"
#include "plumb/error.h"
#include "plumb/strings.h"

namespace plumb {

namespace {
std::string KeyLabel(const Model& model, int k) {
  std::string name = model.Name(mjOBJ_KEY, k);
  return name.empty() ? "#" + std::to_string(k) : name;
}
}  // namespace

int FindKeyframe(const Model& model, const std::string& name) {
  const mjModel* m = model.get();
  std::vector<std::string> names;
  for (int k = 0; k < m->nkey; ++k) {
    names.push_back(KeyLabel(model, k));
    if (names.back() == name) return k;
  }
  if (names.empty()) {
    throw ArgumentError(
        "keyframe", Quoted(name),
        "the model '" + model.file() +
            "' has no keyframes (MJCF <keyframe><key name=... qpos=.../></keyframe>). "
            "Set the start state with assignments (qpos[...]=...) instead.");
  }
  std::string hint = DidYouMean(name, names);
  throw ArgumentError("keyframe", Quoted(name),
                      "no such keyframe in '" + model.file() + "'. Its keyframes: " +
                          Join(names, ", ") + "." + (hint.empty() ? "" : " " + hint));
}

std::vector<Assignment> KeyframeAssignments(const Model& model, const std::string& name) {
  if (name.empty()) return {};
  const mjModel* m = model.get();
  int k = FindKeyframe(model, name);
  std::string label = "keyframe '" + KeyLabel(model, k) + "': ";
  std::vector<Assignment> out;
  auto add = [&](const char* field, const mjtNum* source, long n) {
    if (n == 0) return;
    Assignment a;
    a.text = label + field;
    a.path = ResolvePath(model, field);
    a.values.assign(source + k * n, source + (k + 1) * n);
    out.push_back(std::move(a));
  };
  add("time", m->key_time, 1);
  add("qpos", m->key_qpos, m->nq);
  add("qvel", m->key_qvel, m->nv);
  add("act", m->key_act, m->na);
  add("ctrl", m->key_ctrl, m->nu);
  add("mocap_pos", m->key_mpos, 3L * m->nmocap);
  add("mocap_quat", m->key_mquat, 4L * m->nmocap);
  auto [plastic, nplastic] = compat::KeyPlastic(m);
  if (plastic) add("plastic", plastic, nplastic);
  return out;
}

ReferencePose FindReferencePose(const Model& model, const std::string& named) {
  ReferencePose pose;
  if (!named.empty()) {
    pose.keyframe = FindKeyframe(model, named);
    pose.description = "keyframe '" + named + "' (named by the caller)";
    return pose;
  }
  for (const char* name : {"home", "test"}) {
    int k = mj_name2id(model.get(), mjOBJ_KEY, name);
    if (k >= 0) {
      pose.keyframe = k;
      pose.description = std::string("keyframe '") + name + "'";
      return pose;
    }
  }
  pose.description = "qpos0";
  return pose;
}

void StartAtPose(Model& model, Data& data, const ReferencePose& pose,
                 const std::vector<Assignment>& sets) {
  ApplyAssignments(model, data, sets);
  if (pose.keyframe < 0) return;
  mj_resetDataKeyframe(model.get(), data.get(), pose.keyframe);
  WriteState(model, data, sets);
  data.Forward();
}

}  // namespace plumb
