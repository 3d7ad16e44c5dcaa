// Loading a model and what MuJoCo said on the way, on the call's channel (plumb/notice.h).
//
// MuJoCo's compiler and loader give warnings that Model::Load keeps (Model::compile_warnings)
// or leaves with the calling thread (TakeMujocoWarnings), and MuJoCo shortens a delay longer
// than its buffer without a word. These functions say each once, as the plumb command prints
// them and Python issues them (plumb.CompileWarning):
//
//   plumb::Notices notices(print);
//   plumb::Model model = plumb::LoadModel("robot.xml", &notices);
//
// Thread-safety: LoadModel and AddLoadNotices take the calling thread's pending MuJoCo
// warnings; call them on the thread that loads. AddModelNotices only reads the model.

#ifndef PLUMB_INCLUDE_PLUMB_LOAD_H_
#define PLUMB_INCLUDE_PLUMB_LOAD_H_

#include <string>

#include "plumb/model.h"
#include "plumb/notice.h"

namespace plumb {

// Model::Load(path), then AddLoadNotices. @throws as Model::Load does.
Model LoadModel(const std::string& path, Notices* notices);

// What loading `model` from `path` says, added to `notices` (topic kCompile): MuJoCo's
// compiler warnings (subject "MuJoCo's compiler on 'PATH'"), each warning MuJoCo gave the
// calling thread that the compiler's do not already hold (MuJoCo 4 gives settotalmass's
// deprecation both ways; subject "MuJoCo while loading 'PATH'"), then AddModelNotices with
// subject "'PATH'". Takes the calling thread's pending MuJoCo warnings, also when `notices` is
// null: call it on the thread that loaded, right after Model::Load.
void AddLoadNotices(const Model& model, const std::string& path, Notices* notices);

// What the compiled `model` does differently from what its file asks, added to `notices`
// (topic kCompile, `subject` as given): each delay longer than its buffer, which MuJoCo
// shortens without a word (DelayDescription::Warning). For a model compiled elsewhere too (a
// wrapped mujoco.MjModel), whose compiler's warnings went to whoever compiled it.
void AddModelNotices(const Model& model, const std::string& subject, Notices* notices);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_LOAD_H_
