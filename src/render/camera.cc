// Which camera a picture is drawn from (include/plumb/render.h: ChooseRenderCamera): one rule
// for `plumb render`, plumb.render and the reports' pictures. Compiled with or without the
// renderer, so a bad camera is refused the same way everywhere.

#include <mujoco/mujoco.h>

#include <cerrno>
#include <cstdlib>
#include <string>

#include "plumb/error.h"
#include "plumb/render.h"

namespace plumb {
namespace {

constexpr const char* kBuiltins[] = {"auto", "track", "fixed"};
constexpr const char* kPrefix = "plumb:";

// The model's cameras for a message: "'side', #1, 'top'", or "none".
std::string CameraList(const Model& model) {
  std::string list;
  for (int i = 0; i < model->ncam; ++i) {
    list += (list.empty() ? "" : ", ") + CameraLabel(model, i);
  }
  return list.empty() ? "none" : list;
}

bool IsBuiltin(const std::string& name) {
  for (const char* b : kBuiltins) {
    if (name == b) return true;
  }
  return false;
}

}  // namespace

std::string CameraLabel(const Model& model, int id) {
  std::string name = model.Name(mjOBJ_CAMERA, id);
  return name.empty() ? "#" + std::to_string(id) : "'" + name + "'";
}

CameraChoice ChooseRenderCamera(const Model& model, const std::string& camera) {
  CameraChoice choice;
  std::string prefix = kPrefix;
  if (camera.compare(0, prefix.size(), prefix) == 0 && IsBuiltin(camera.substr(prefix.size()))) {
    choice.builtin = camera.substr(prefix.size());
    return choice;
  }
  choice.id = mj_name2id(model.get(), mjOBJ_CAMERA, camera.c_str());
  if (choice.id >= 0) return choice;
  if (camera.size() > 1 && camera[0] == '#') {
    errno = 0;
    char* end = nullptr;
    long id = std::strtol(camera.c_str() + 1, &end, 10);
    if (*end == '\0' && errno == 0 && camera[1] != '-' && camera[1] != '+' &&
        camera[1] != ' ') {
      if (id < model->ncam) {
        choice.id = static_cast<int>(id);
        return choice;
      }
      throw ArgumentError("camera", Quoted(camera),
                          "the model has " + std::to_string(model->ncam) + " camera" +
                              (model->ncam == 1 ? "" : "s") + " (" + CameraList(model) + ")");
    }
  }
  if (IsBuiltin(camera)) {
    choice.builtin = camera;
    return choice;
  }
  throw ArgumentError("camera", Quoted(camera),
                      "is neither a camera of '" + model.file() + "' (its cameras, by name or " +
                          "as #id: " + CameraList(model) +
                          ") nor plumb's auto, track or fixed (also plumb:auto, plumb:track, " +
                          "plumb:fixed)");
}

}  // namespace plumb
