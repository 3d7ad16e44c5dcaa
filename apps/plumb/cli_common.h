// What every plumb subcommand shares: exit codes, error reporting, model loading with
// the chapter's hints, signal handling, and option parsing helpers.

#ifndef PLUMB_APPS_PLUMB_CLI_COMMON_H_
#define PLUMB_APPS_PLUMB_CLI_COMMON_H_

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/output_path.h"
#include "plumb/check_table.h"
#include "plumb/model.h"
#include "plumb/notice.h"
#include "plumb/path.h"
#include "plumb/rollout.h"
#include "plumb/stop.h"

namespace plumb::cli {

// Documented exit codes (docs/exit-codes.md, `plumb help exit-codes`, `plumb --help`).
enum ExitCode : int {
  kExitOk = 0,              // success
  kExitCheckFailed = 1,     // a check failed
  kExitBadInput = 2,        // bad input or usage: missing file, XML error, unknown path, ...
  kExitDiverged = 3,        // the simulation diverged (a repro folder was written)
  kExitMujocoError = 4,     // MuJoCo stopped with a fatal error (mju_error), not a divergence
  kExitUnavailable = 5,     // a part is missing: the renderer in this build, GL, ffmpeg
  kExitEngine = 6,          // the engine adapter (crosscheck's MuJoCo Warp or MJX) failed
  kExitInternal = 70,       // an internal error: a plumb bug, out of memory (sysexits' EX_SOFTWARE)
  kExitInterrupted = 130,   // SIGINT/SIGTERM: what finished was kept
  kExitOutputClosed = 141,  // stdout was closed by its reader (as a SIGPIPE death)
};

// Thrown by WriteStdout when the reader of stdout has gone (EPIPE).
class OutputClosed : public std::runtime_error {
 public:
  OutputClosed() : std::runtime_error("standard output was closed by its reader") {}
};

// Writes and flushes `text` to stdout, so rows reach a pipe as they are made.
// @throws OutputClosed when the reader has gone; IoError for another failed write.
void WriteStdout(const std::string& text);

// Shared state of one invocation.
struct Context {
  std::vector<std::string> argv;  // the exact command line
  // The selected subcommand's action, returning its exit code.
  std::function<int()> action;
};

// The options every model command shares: the MODEL positional and repeatable --set
// PATH=VALUE (one value per occurrence), with `when` saying when the assignments apply.
void AddModelOptions(CLI::App* cmd, std::string* model, std::vector<std::string>* sets,
                     const std::string& when);

// Adds subcommand `name` with its one-line `description` and the `footer` its --help ends
// with (examples, exit codes).
CLI::App* AddCommand(CLI::App& app, const std::string& name, const std::string& description,
                     const std::string& footer);

// --format, one of `choices` (the first is the default the options struct holds); `help`
// explains them, else they are listed ("table or json").
void AddFormatOption(CLI::App* cmd, std::string* format, const std::vector<std::string>& choices,
                     const std::string& help = "");

// --report FILE.html: the command's self-contained HTML report (plumb/report.h).
void AddReportOption(CLI::App* cmd, std::string* report);
// --keyframe NAME: start from the model's keyframe NAME (as mj_resetDataKeyframe), with
// every --set applied on top. Commands read it with StartAssignments.
void AddKeyframeOption(CLI::App* cmd, std::string* keyframe);

// A start pose given whole: --pose FILE (plumb/keyframe.h PoseFileAssignments) and --qpos
// VALUES (nq numbers). Commands that take them read them with StartAssignments.
struct StartPose {
  std::string file;  // --pose
  std::string qpos;  // --qpos
};
void AddStartPoseOptions(CLI::App* cmd, StartPose* pose);
// The pose's assignments: the file's, then --qpos (none when neither is given); each one's
// warnings are said (CommandNotices) when `warn`. @throws as StartAssignments.
std::vector<Assignment> PoseAssignments(const Model& model, const StartPose& pose,
                                        bool warn = true);

// The inputs of a model command, as RefuseOutputsOntoInputs (io/output_path.h) names them in
// its message: the model, the --pose file (when given), then `more`. A command refuses an
// output onto one of them before it writes anything:
//   RefuseOutputsOntoInputs({{"-o", o.output}}, ModelInputs(o.model, o.pose));
std::vector<internal::NamedPath> ModelInputs(const std::string& model, const StartPose& pose = {},
                                             std::vector<internal::NamedPath> more = {});

// What a check table says about the PASS rows it leaves out.
inline constexpr const char* kSeeAllRows = "--all shows every check";

// Prints a notice as the plumb command says everything besides its result: "plumb: " and
// Notice::Line() on stderr ("plumb: warning: models/g1.xml: ...").
void PrintNotice(const Notice& notice);

// The channel a command gives a library call: each notice printed as it comes; all() keeps
// them for a JSON document.
class PrintedNotices : public Notices {
 public:
  PrintedNotices() : Notices(PrintNotice) {}
};

// The channel of the command this process runs: what its library calls say (LoadModel's
// compile warnings, StartAssignments' warnings, a cut log's note), each printed as it comes;
// a command's JSON document carries all() as "notices" (WithNotices).
PrintedNotices& CommandNotices();

// `json`, a JSON object's text, with "notices": the command's notices (CommandNotices) as
// NoticesToJson writes them, added as its last member.
std::string WithNotices(const std::string& json);

// Says an assignment's warnings (Assignment::warnings) on the command's channel, naming it as
// the user wrote it: "plumb: warning: --set 'ctrl[hip]=5': ..." (AddAssignmentNotices).
void WarnAboutAssignment(const char* flag, const std::string& text,
                         const std::vector<std::string>& warnings);

// Adds --all and --quiet (mutually exclusive) to `cmd`, setting `*detail`.
void AddTableDetailOptions(CLI::App* cmd, TableDetail* detail);

// The assignments a run starts from: keyframe `keyframe` (when not empty), then every
// --set in order. @throws ValueError for an unknown keyframe; PathError / ValueError
// for a bad --set.
std::vector<Assignment> StartAssignments(const Model& model, const std::string& keyframe,
                                         const std::vector<std::string>& sets);
// The same with a whole pose: the keyframe, then the pose file, then --qpos, then every --set
// (each later one wins). @throws ArgumentError (pose, qpos) for a bad file or a vector whose
// length is not nq; IoError for an unreadable file; as above.
std::vector<Assignment> StartAssignments(const Model& model, const std::string& keyframe,
                                         const StartPose& pose,
                                         const std::vector<std::string>& sets);

// Maps an exception to its exit code after printing it on stderr as one paragraph. `argv`
// (the command line) gives an internal error its context.
int ReportError(const std::exception& error, const std::vector<std::string>& argv = {});

// Loads a model, saying what MuJoCo said on the way on the command's channel (plumb/load.h).
Model LoadModel(const std::string& path);

// Parses every --set assignment against the model.
std::vector<Assignment> ParseAssignments(const Model& model, const std::vector<std::string>& sets);

// A progress bar with rate and ETA on stderr, drawn only when stderr is a terminal.
// Update may be called from any thread; redraws are limited to ten per second.
class ProgressBar {
 public:
  ProgressBar(long total, std::string unit);
  void Update(long done);
  void Finish();  // clears the line
  // Clears the bar before other output shares the terminal (table rows, messages), so
  // lines do not run into it; the next Update draws it again.
  void Clear();

 private:
  long total_;
  std::string unit_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
  std::atomic<long long> last_draw_ns_{0};
  std::mutex mutex_;
};

// The stop request of the command this process runs: each command passes its token to
// the library calls it makes. SIGINT/SIGTERM request it once InstallSignalHandlers ran
// (main installs them for every command); a second signal ends the process at once.
// --max-seconds requests it too (a StopTimer). SIGPIPE is ignored: WriteStdout reports
// a closed stdout instead.
const StopSource& CommandStop();
void InstallSignalHandlers();

// Registers the subcommands; each sets ctx.action when selected.
void SetupRunCommand(CLI::App& app, Context& ctx);
void SetupInspectCommand(CLI::App& app, Context& ctx);
void SetupConvergeCommand(CLI::App& app, Context& ctx);
void SetupCrosscheckCommand(CLI::App& app, Context& ctx);
void SetupVerifyCommand(CLI::App& app, Context& ctx);
void SetupAuditCommand(CLI::App& app, Context& ctx);
void SetupSweepCommand(CLI::App& app, Context& ctx);
void SetupRolloutCommand(CLI::App& app, Context& ctx);
void SetupResultsCommand(CLI::App& app, Context& ctx);
void SetupMergeCommand(CLI::App& app, Context& ctx);
void SetupSnapshotCommand(CLI::App& app, Context& ctx);
void SetupDiffCommand(CLI::App& app, Context& ctx);
void SetupRenderCommand(CLI::App& app, Context& ctx);
void SetupBridgeCommand(CLI::App& app, Context& ctx);
void SetupReplayCommand(CLI::App& app, Context& ctx);
void SetupIdentifyCommand(CLI::App& app, Context& ctx);
void SetupHelpCommand(CLI::App& app, Context& ctx);  // the manual's pages, docs/*.md

// Checks the numbers of every option of `app` and of its subcommands, in one walk:
// - an integer option takes an integer written in any number notation ("--count 1e3" is
//   1000) and refuses anything else with the option's name ("--count takes an integer, not
//   '1.5'"; unsigned options also refuse negative values);
// - a floating-point option refuses NaN ("--every: takes a number, not 'nan'"), which no
//   option means (the library refuses NaN too: its checks are written !(x >= 0)).
// Call once, after every subcommand is set up.
void CheckNumberOptions(CLI::App* app);

// Why `args` (the command line without the program name) failed to parse, said for a
// user: an unknown command or option with the nearest valid names, or an option that takes
// one value given more than once (several problems: one a line, each after the first starting
// "plumb: error: "). Empty when none of these is the reason.
std::string DiagnoseCommandLine(const CLI::App& app, const std::vector<std::string>& args);

}  // namespace plumb::cli

#endif  // PLUMB_APPS_PLUMB_CLI_COMMON_H_
