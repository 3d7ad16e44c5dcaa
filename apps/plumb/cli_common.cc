#include "cli_common.h"

#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>

#include "plumb/error.h"
#include "plumb/keyframe.h"

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

ProgressBar::ProgressBar(long total, std::string unit)
    : total_(total),
      unit_(std::move(unit)),
      enabled_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()) {}

void ProgressBar::Update(long done) {
  if (!enabled_) return;
  auto now = std::chrono::steady_clock::now();
  long long ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now - start_).count();
  if (done < total_ && ns - last_draw_ns_.load() < 100'000'000) return;
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  last_draw_ns_ = ns;
  double seconds = ns * 1e-9;
  double rate = seconds > 0 ? done / seconds : 0;
  double eta = rate > 0 ? (total_ - done) / rate : 0;
  constexpr int kWidth = 30;
  int filled = total_ > 0 ? static_cast<int>(kWidth * done / total_) : kWidth;
  std::fprintf(stderr, "\r[%s%s] %ld/%ld %s  %.1f/s  ETA %.0f s ", std::string(filled, '#').c_str(),
               std::string(kWidth - filled, ' ').c_str(), done, total_, unit_.c_str(), rate, eta);
  std::fflush(stderr);
}

void ProgressBar::Finish() {
  if (enabled_) std::fprintf(stderr, "\r%80s\r", "");
}

void ProgressBar::Clear() {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  std::fprintf(stderr, "\r%80s\r", "");
  std::fflush(stderr);
  last_draw_ns_ = 0;  // drawn again at the next update
}

void AddModelOptions(CLI::App* cmd, std::string* model, std::vector<std::string>* sets,
                     const std::string& when) {
  cmd->add_option("model", *model, "MJCF (.xml) or binary (.mjb) model file")->required();
  cmd->add_option("--set", *sets,
                  "PATH=VALUE " + when +
                      ", e.g. 'qpos[hinge]=0.7', 'opt.gravity=0,0,-1.62', "
                      "'opt.integrator=RK4' (repeatable)")
      ->allow_extra_args(false);
}

void AddKeyframeOption(CLI::App* cmd, std::string* keyframe) {
  cmd->add_option("--keyframe", *keyframe,
                  "start from the model's keyframe NAME (qpos, qvel, act, ctrl, mocap, time as "
                  "mj_resetDataKeyframe); --set applies on top");
}

std::vector<Assignment> StartAssignments(const Model& model, const std::string& keyframe,
                                         const std::vector<std::string>& sets) {
  std::vector<Assignment> out = KeyframeAssignments(model, keyframe);
  for (Assignment& a : ParseAssignments(model, sets)) out.push_back(std::move(a));
  return out;
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

std::string CsvNumber(double v) {
  if (std::isnan(v)) return "";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", v);
  return buffer;
}

std::string CsvText(const std::string& field) {
  if (field.find_first_of(",\"\n") == std::string::npos) return field;
  std::string out = "\"";
  for (char c : field) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string CsvHeader(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + CsvText(fields[i]);
  return line + "\n";
}

std::vector<std::string> RolloutCsvColumns(const std::vector<std::string>& params,
                                           const std::vector<std::string>& metrics) {
  std::vector<std::string> columns = {"rollout"};
  columns.insert(columns.end(), params.begin(), params.end());
  columns.insert(columns.end(), metrics.begin(), metrics.end());
  for (const char* c : {"diverged", "diverged_at", "problem"}) columns.push_back(c);
  return columns;
}

std::string RolloutCsvRow(const RolloutResult& r) {
  std::string out = std::to_string(r.index);
  for (double v : r.params) out += "," + CsvNumber(v);
  for (double v : r.metrics) out += "," + CsvNumber(v);
  out += r.diverged ? ",1," + CsvNumber(r.diverged_time) : ",0,";
  return out + "," + CsvText(r.problem) + "\n";
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
