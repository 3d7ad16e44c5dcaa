#include "cli_common.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>
#include <optional>

#include "core/strings.h"
#include "plumb/describe.h"
#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/load.h"
#include "plumb/run.h"

namespace plumb::cli {

namespace {
const StopSource command_stop;  // made before main: the signal handler only reads it

// The first SIGINT/SIGTERM asks the command's calls to stop at their next step, so the
// command can keep what finished; a second one ends the process at once, as the user
// expects. RequestStop is one lock-free atomic exchange: async-signal-safe.
void OnSignal(int sig) {
  if (!command_stop.RequestStop()) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}
}  // namespace

const StopSource& CommandStop() { return command_stop; }

void InstallSignalHandlers() {
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  // a closed stdout is seen as a failed write (EPIPE) and ends the command with its own
  // exit code after what finished is stored, not by a signal in the middle of a commit
  std::signal(SIGPIPE, SIG_IGN);
}

void WriteStdout(const std::string& text) {
  if (text.empty()) return;
  errno = 0;
  std::size_t written = std::fwrite(text.data(), 1, text.size(), stdout);
  if (written == text.size() && std::fflush(stdout) == 0) return;
  if (errno == EPIPE) throw OutputClosed();
  throw IoError(std::string("writing to standard output failed: ") + std::strerror(errno));
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

void AddTableDetailOptions(CLI::App* cmd, TableDetail* detail) {
  CLI::Option* all = cmd->add_flag_callback(
      "--all", [detail] { *detail = TableDetail::kAll; },
      "show every check, PASS rows included (default: failures, warnings and skips)");
  CLI::Option* quiet = cmd->add_flag_callback(
      "--quiet", [detail] { *detail = TableDetail::kQuiet; }, "print the count line alone");
  all->excludes(quiet);
}

std::vector<Assignment> StartAssignments(const Model& model, const std::string& keyframe,
                                         const std::vector<std::string>& sets) {
  return StartAssignments(model, keyframe, StartPose{}, sets);
}

std::vector<Assignment> StartAssignments(const Model& model, const std::string& keyframe,
                                         const StartPose& pose,
                                         const std::vector<std::string>& sets) {
  // the library names an assignment by its argument ("set"); the user typed the flag
  return plumb::StartAssignments(model, {keyframe, pose.file, pose.qpos, sets},
                                 &CommandNotices(), "--");
}

std::vector<internal::NamedPath> ModelInputs(const std::string& model, const StartPose& pose,
                                             std::vector<internal::NamedPath> more) {
  std::vector<internal::NamedPath> inputs = {{"the model", model}, {"the --pose file", pose.file}};
  inputs.insert(inputs.end(), more.begin(), more.end());
  return inputs;
}

std::vector<Assignment> PoseAssignments(const Model& model, const StartPose& pose, bool warn) {
  StartSpec start;
  start.pose = pose.file;
  start.qpos = pose.qpos;
  return plumb::StartAssignments(model, start, warn ? &CommandNotices() : nullptr, "--");
}

void AddStartPoseOptions(CLI::App* cmd, StartPose* pose) {
  cmd->add_option("--pose", pose->file,
                  "start from the pose in FILE: one PATH=VALUE a line as --set takes them, or a "
                  "whole qpos vector; after --keyframe, before --qpos and --set");
  cmd->add_option("--qpos", pose->qpos,
                  "start from this whole qpos: nq numbers in MuJoCo's qpos order, separated by "
                  "commas or spaces (a free joint's x y z, quaternion w x y z first); --set "
                  "applies on top");
}

CLI::App* AddCommand(CLI::App& app, const std::string& name, const std::string& description,
                     const std::string& footer) {
  CLI::App* cmd = app.add_subcommand(name, description);
  cmd->footer(footer);
  return cmd;
}

void AddFormatOption(CLI::App* cmd, std::string* format, const std::vector<std::string>& choices,
                     const std::string& help) {
  std::string listed;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    listed += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
  }
  cmd->add_option("--format", *format, help.empty() ? listed : help)
      ->check(CLI::IsMember(choices))
      ->capture_default_str();
}

void AddReportOption(CLI::App* cmd, std::string* report) {
  // checked before the work starts: an hour of rollouts must not end on a typo in a folder
  auto writable_folder = [](const std::string& path) -> std::string {
    std::string folder = std::filesystem::path(path).parent_path().string();
    if (folder.empty()) folder = ".";
    if (access(folder.c_str(), W_OK | X_OK) != 0) {
      return "--report " + path + ": the folder '" + folder +
             "' does not exist or is not writable; create it or choose another";
    }
    return "";
  };
  cmd->add_option("--report", *report,
                  "also write a self-contained HTML report (tables, charts, pictures) here")
      ->check(CLI::Validator(writable_folder, "FILE.html"));
}

int ReportError(const std::exception& error, const std::vector<std::string>& argv) {
  // the reader of stdout went away (`plumb rollout ... | head`): what finished was kept, and
  // there is nobody to tell; the shell's code for a process ended by SIGPIPE
  if (dynamic_cast<const OutputClosed*>(&error)) return kExitOutputClosed;
  if (const auto* stop = dynamic_cast<const Interrupted*>(&error)) {
    std::fprintf(stderr, "plumb: stopped by a signal: %s\n", stop->what());
    return kExitInterrupted;
  }
  if (dynamic_cast<const MujocoError*>(&error)) {
    std::fprintf(stderr, "plumb: error: MuJoCo stopped with a fatal error: %s\n", error.what());
    return kExitMujocoError;
  }
  if (dynamic_cast<const UnavailableError*>(&error)) {
    std::fprintf(stderr, "plumb: error: %s\n", error.what());
    return kExitUnavailable;
  }
  if (dynamic_cast<const EngineError*>(&error)) {
    std::fprintf(stderr, "plumb: error: %s\n", error.what());
    return kExitEngine;
  }
  if (!dynamic_cast<const Error*>(&error)) {
    // not an error plumb reports by design: a bug, memory exhausted, data that cannot be
    std::string command = argv.empty() ? "plumb" : internal::ShellQuote(argv[0]);
    for (std::size_t i = 1; i < argv.size() && i < 3; ++i)
      command += " " + internal::ShellQuote(argv[i]);
    bool memory = dynamic_cast<const std::bad_alloc*>(&error) != nullptr;
    std::fprintf(stderr, "plumb: internal error: %s (in '%s%s'). %s\n",
                 memory ? "out of memory" : error.what(), command.c_str(),
                 argv.size() > 3 ? " ..." : "",
                 memory ? "Give plumb more memory, or fewer threads, cases or samples."
                        : "This is a bug in plumb: please report it with the command line "
                          "and the model.");
    return kExitInternal;
  }
  if (const auto* bad = dynamic_cast<const ArgumentError*>(&error)) {
    // the library names its argument ("ctrl_noise"); the user typed the flag (--ctrl-noise),
    // which an argument the command named itself ("-o", output_path.h) already is
    std::string flag = bad->argument() == "store" ? "--db" : "--" + bad->argument();
    std::replace(flag.begin(), flag.end(), '_', '-');
    if (bad->argument().rfind('-', 0) == 0) flag = bad->argument();
    std::fprintf(stderr, "plumb: error: %s%s: %s\n", flag.c_str(),
                 bad->value().empty() ? "" : (" " + bad->value()).c_str(), bad->problem().c_str());
    return kExitBadInput;
  }
  std::fprintf(stderr, "plumb: error: %s\n", error.what());
  if (const auto* load = dynamic_cast<const LoadError*>(&error)) {
    if (!load->hint().empty()) std::fprintf(stderr, "plumb: %s\n", load->hint().c_str());
  }
  return kExitBadInput;
}

void PrintNotice(const Notice& notice) {
  std::fprintf(stderr, "plumb: %s\n", notice.Line().c_str());
}

PrintedNotices& CommandNotices() {
  static PrintedNotices notices;
  return notices;
}

std::string WithNotices(const std::string& json) {
  return JsonWithNotices(json, CommandNotices().all());
}

Model LoadModel(const std::string& path) { return plumb::LoadModel(path, &CommandNotices()); }

void WarnAboutAssignment(const char* flag, const std::string& text,
                         const std::vector<std::string>& warnings) {
  Assignment a;
  a.text = text;
  a.warnings = warnings;
  AddAssignmentNotices(a, flag, &CommandNotices());
}

std::vector<Assignment> ParseAssignments(const Model& model, const std::vector<std::string>& sets) {
  std::vector<Assignment> out;
  for (const std::string& s : sets) {
    out.push_back(ParseAssignment(model, s));
    AddAssignmentNotices(out.back(), "--set", &CommandNotices());
  }
  return out;
}

namespace {
// Options by their names as typed ("--until", "-o"), positionals left out.
std::vector<std::string> OptionNames(const CLI::App& cmd) {
  std::vector<std::string> names;
  for (const CLI::Option* opt : cmd.get_options()) {
    if (!opt->nonpositional()) continue;
    for (const std::string& l : opt->get_lnames()) names.push_back("--" + l);
    for (const std::string& s : opt->get_snames()) names.push_back("-" + s);
  }
  return names;
}

// The option `token` names ("--until", "--until=2", "-o"), or "" when it is no option name
// (a value such as "-0.5").
std::string OptionToken(const std::string& token) {
  if (token.size() < 2 || token[0] != '-' || internal::ParseNumber(token)) return "";
  if (token[1] != '-') return token.substr(0, 2);
  return token.substr(0, token.find('='));
}

// "; did you mean 'a' or 'b'?" for the plausible typos of `word`, or "".
std::string Suggestion(const std::string& word, const std::vector<std::string>& candidates) {
  std::vector<std::string> quoted;
  for (const std::string& n : internal::Closest(word, candidates)) quoted.push_back("'" + n + "'");
  return quoted.empty() ? "" : "; did you mean " + internal::Join(quoted, " or ") + "?";
}

// An integer option takes an integer in any number notation (CheckNumberOptions).
void AcceptIntegerNotation(CLI::Option* opt, bool is_unsigned) {
  opt->transform(CLI::Validator(
      [is_unsigned](std::string& text) -> std::string {
        std::string kind = is_unsigned ? "a non-negative integer" : "an integer";
        std::optional<double> v = internal::ParseNumber(text);
        if (!v || !std::isfinite(*v) || std::floor(*v) != *v) {
          return "takes " + kind + ", not '" + text + "'";
        }
        if (is_unsigned && (*v < 0 || text.find('-') == 0)) {
          return "takes " + kind + ", not '" + text + "'";
        }
        // digits go to CLI11 without leading zeros (which it would read as octal: "010"
        // is 10, not 8) and otherwise unchanged, so its range checks see every digit; an
        // exact integer in other notation ("1e3", "100.0") is rewritten as its digits
        bool digits = text.find_first_not_of("+-0123456789") == std::string::npos;
        if (digits) {
          std::size_t sign = text[0] == '+' || text[0] == '-' ? 1 : 0;
          std::size_t first = text.find_first_not_of('0', sign);
          text = text.substr(0, sign) + (first == std::string::npos ? "0" : text.substr(first));
          // beyond 64 bits CLI11's conversion saturates (every larger seed would become
          // 2^64 - 1): refuse what does not fit instead
          bool negative = text[0] == '-';
          std::string magnitude = text.substr(sign);
          std::string limit = is_unsigned ? "18446744073709551615"
                              : negative  ? "9223372036854775808"
                                          : "9223372036854775807";
          if (magnitude.size() > limit.size() ||
              (magnitude.size() == limit.size() && magnitude > limit)) {
            return "takes " + kind + " from " +
                   (is_unsigned ? std::string("0 to 18446744073709551615")
                                : std::string("-9223372036854775808 to 9223372036854775807")) +
                   ", not '" + text + "'";
          }
        } else {
          if (std::fabs(*v) > 9007199254740992.0) {
            return "takes " + kind + ": '" + text + "' is too large to be exact; write its digits";
          }
          text = fmt::format("{:.0f}", *v);
        }
        return "";
      },
      "", ""));
}

// A floating-point option refuses NaN: CLI11 reads "nan" as a number, and NaN passes every
// `x < 0` or `x > hi` check after it.
void RefuseNotANumber(CLI::Option* opt) {
  opt->transform(CLI::Validator(
      [](std::string& text) -> std::string {
        std::optional<double> v = internal::ParseNumber(text);
        return v && std::isnan(*v) ? "takes a number, not '" + text + "'" : "";
      },
      "", ""));
}

}  // namespace

void CheckNumberOptions(CLI::App* app) {
  for (CLI::App* sub : app->get_subcommands(std::function<bool(CLI::App*)>())) {
    CheckNumberOptions(sub);
  }
  for (CLI::Option* opt : app->get_options()) {
    std::string type = opt->get_type_name();
    if (type.rfind("UINT", 0) == 0 || type.rfind("INT", 0) == 0) {
      AcceptIntegerNotation(opt, type.rfind("UINT", 0) == 0);
    } else if (type.rfind("FLOAT", 0) == 0) {
      RefuseNotANumber(opt);
    }
  }
}

std::string DiagnoseCommandLine(const CLI::App& app, const std::vector<std::string>& args) {
  std::vector<std::string> commands;
  const CLI::App* cmd = nullptr;
  for (const CLI::App* sub : app.get_subcommands(std::function<bool(const CLI::App*)>())) {
    commands.push_back(sub->get_name());
    if (!args.empty() && args[0] == sub->get_name()) cmd = sub;
  }
  // no command, an unknown one, or an unknown option before it
  std::string list = "The commands are: " + internal::Join(commands, ", ") + ".";
  if (args.empty()) return "no command given. " + list;
  if (cmd == nullptr) {
    std::string name = OptionToken(args[0]);
    if (!name.empty()) {
      return "unknown option " + name + Suggestion(name, OptionNames(app)) + "\n" + list;
    }
    return "unknown command '" + args[0] + "'" + Suggestion(args[0], commands) + "\n" + list;
  }
  // unknown options, with the nearest names of this command's options
  std::vector<std::string> names = OptionNames(*cmd);
  for (const std::string& n : OptionNames(app)) names.push_back(n);
  std::vector<std::string> problems;
  std::vector<std::pair<const CLI::Option*, std::vector<std::string>>> given;  // in order
  for (std::size_t i = 1; i < args.size(); ++i) {
    if (args[i] == "--") break;
    std::string name = OptionToken(args[i]);
    if (name.empty()) continue;
    const CLI::Option* opt = nullptr;
    for (const CLI::Option* o : cmd->get_options()) {
      if (o->nonpositional() && o->check_name(name)) opt = o;
    }
    if (opt == nullptr) {
      if (std::find(names.begin(), names.end(), name) != names.end()) continue;  // --help
      problems.push_back("unknown option " + name + " for 'plumb " + cmd->get_name() + "'" +
                         Suggestion(name, names));
      continue;
    }
    auto it =
        std::find_if(given.begin(), given.end(), [&](const auto& g) { return g.first == opt; });
    if (it == given.end()) it = given.insert(given.end(), {opt, {}});
    std::size_t eq = args[i].find('=');
    if (eq != std::string::npos) {
      it->second.push_back(args[i].substr(eq + 1));
    } else {
      it->second.push_back(i + 1 < args.size() ? args[i + 1] : "");
    }
  }
  // an option that takes one value, given more than once
  for (const auto& [opt, values] : given) {
    bool single = opt->get_type_size_max() == 1 && opt->get_expected_max() == 1;
    if (!single || values.size() < 2) continue;
    std::vector<std::string> quoted;
    for (const std::string& v : values) quoted.push_back("'" + v + "'");
    problems.push_back(fmt::format("{} was given {} times ({}); it takes one value: give it once",
                                   opt->get_name(), values.size(), internal::Join(quoted, ", ")));
  }
  // one problem a line, each as an error of its own
  return internal::Join(problems, "\nplumb: error: ");
}

}  // namespace plumb::cli
