#include "cli_common.h"

#include <csignal>
#include <cstdio>

#include "plumb/error.h"

namespace plumb::cli {

namespace {
std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop.store(true); }
}  // namespace

const std::atomic<bool>& StopRequested() { return g_stop; }

void InstallSignalHandlers() {
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
}

int ReportError(const std::exception& error) {
  std::fprintf(stderr, "plumb: error: %s\n", error.what());
  if (const auto* load = dynamic_cast<const LoadError*>(&error)) {
    if (!load->hint().empty()) std::fprintf(stderr, "plumb: %s\n", load->hint().c_str());
    return kExitBadInput;
  }
  if (dynamic_cast<const Interrupted*>(&error)) return kExitInterrupted;
  if (dynamic_cast<const PathError*>(&error) || dynamic_cast<const ValueError*>(&error) ||
      dynamic_cast<const IoError*>(&error)) {
    return kExitBadInput;
  }
  if (dynamic_cast<const MujocoError*>(&error)) return kExitDiverged;
  return kExitBadInput;
}

Model LoadModel(const std::string& path) {
  Model model = Model::Load(path);
  if (!model.compile_warnings().empty()) {
    std::fprintf(stderr, "plumb: warning: MuJoCo's compiler on '%s': %s\n", path.c_str(),
                 model.compile_warnings().c_str());
  }
  for (const std::string& w : TakeMujocoWarnings()) {
    std::fprintf(stderr, "plumb: warning: MuJoCo while loading '%s': %s\n", path.c_str(),
                 w.c_str());
  }
  return model;
}

std::vector<Assignment> ParseAssignments(const Model& model, const std::vector<std::string>& sets) {
  std::vector<Assignment> out;
  for (const std::string& s : sets) out.push_back(ParseAssignment(model, s));
  return out;
}

std::vector<std::string> SplitPathList(const std::string& text) {
  std::vector<std::string> parts;
  std::string current;
  int depth = 0;
  for (char c : text) {
    if (c == '[') ++depth;
    if (c == ']') --depth;
    if (c == ',' && depth == 0) {
      parts.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  parts.push_back(current);
  return parts;
}

}  // namespace plumb::cli
