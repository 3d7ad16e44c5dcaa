// Loading a model and what MuJoCo said on the way (plumb/load.h).

#include "plumb/load.h"

#include <vector>

#include "plumb/describe.h"

namespace plumb {

Model LoadModel(const std::string& path, Notices* notices) {
  Model model = Model::Load(path);
  AddLoadNotices(model, path, notices);
  return model;
}

void AddLoadNotices(const Model& model, const std::string& path, Notices* notices) {
  const std::string& compiler = model.compile_warnings();
  if (!compiler.empty()) {
    AddTo(notices, {NoticeLevel::kWarning, NoticeTopic::kCompile,
                    "MuJoCo's compiler on '" + path + "'", compiler});
  }
  for (const std::string& w : TakeMujocoWarnings()) {
    if (compiler.find(w) != std::string::npos) continue;  // said once, as the compiler's
    AddTo(notices, {NoticeLevel::kWarning, NoticeTopic::kCompile,
                    "MuJoCo while loading '" + path + "'", w});
  }
  AddModelNotices(model, "'" + path + "'", notices);
}

void AddModelNotices(const Model& model, const std::string& subject, Notices* notices) {
  if (notices == nullptr) return;
  for (const DelayDescription& delay : Delays(model)) {
    if (!delay.shortened()) continue;
    notices->Warn(NoticeTopic::kCompile, subject, delay.Warning() + ".");
  }
}

}  // namespace plumb
