// plumb: makes MuJoCo simulations credible. One file per subcommand beside this one.

#include <cstdio>
#include <exception>

#include "cli_common.h"
#include "plumb/error.h"
#include "plumb/model.h"
#include "plumb/mpi_rollout.h"
#include "plumb/version.h"

int main(int argc, char** argv) {
  using namespace plumb::cli;
  Context ctx;
  ctx.argv.assign(argv, argv + argc);

  CLI::App app{"plumb " PLUMB_VERSION
               ": load an MJCF model, run it headless, and check the numbers are credible."};
  app.require_subcommand(1);
  app.set_version_flag("--version", [] {
    std::string plugins;
    try {
      plugins = plumb::MujocoPluginPath();
    } catch (const plumb::Error& e) {
      plugins = e.what();  // PLUMB_MUJOCO_PLUGIN_PATH names no folder: --version says so
    }
    return std::string("plumb " PLUMB_VERSION ", MuJoCo ") + plumb::MujocoVersion() +
           "\n  MuJoCo compiled against: " + plumb::CompiledMujocoVersion() +
           "\n  MuJoCo loaded:           " + plumb::MujocoVersion() + " from " +
           plumb::MujocoLibraryPath() +
           "\n  plugin libraries:        " + (plugins.empty() ? "none" : plugins);
  });
  app.footer(
      "Exit codes: 0 ok, 1 a check failed, 2 bad input or usage, 3 simulation diverged,\n"
      "4 MuJoCo fatal error, 5 a part is missing (renderer, GL, ffmpeg), 6 the engine\n"
      "adapter failed (crosscheck), 70 internal error, 130 interrupted, 141 stdout closed.\n"
      "Example: plumb run models/pendulum.xml --set 'qpos[hinge]=0.7' --until 2 --every 0.1");
  SetupVerifyCommand(app, ctx);
  SetupAuditCommand(app, ctx);
  SetupSnapshotCommand(app, ctx);
  SetupDiffCommand(app, ctx);
  SetupRunCommand(app, ctx);
  SetupInspectCommand(app, ctx);
  SetupConvergeCommand(app, ctx);
  SetupCrosscheckCommand(app, ctx);
  SetupSweepCommand(app, ctx);
  SetupRolloutCommand(app, ctx);
  SetupRenderCommand(app, ctx);
  SetupBridgeCommand(app, ctx);
  SetupReplayCommand(app, ctx);
  SetupIdentifyCommand(app, ctx);
  SetupResultsCommand(app, ctx);
  SetupMergeCommand(app, ctx);
  SetupHelpCommand(app, ctx);
  CheckNumberOptions(&app);

  plumb::MpiInit(&argc, &argv);
  struct Finalize {
    ~Finalize() { plumb::MpiFinalize(); }
  } finalize;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // say what was meant where we can tell (typos, repeated options), else CLI11's words
    std::vector<std::string> args(argv + 1, argv + argc);
    std::string why = DiagnoseCommandLine(app, args);
    if (why.empty()) why = e.what();
    std::string help = "plumb";
    const CLI::App& commands = app;
    for (const CLI::App* sub : commands.get_subcommands(std::function<bool(const CLI::App*)>())) {
      if (!args.empty() && args[0] == sub->get_name()) help += " " + args[0];
    }
    std::fprintf(stderr, "plumb: error: %s\nRun '%s --help' for usage.\n", why.c_str(),
                 help.c_str());
    return kExitBadInput;
  }
  InstallSignalHandlers();
  try {
    return ctx.action ? ctx.action() : kExitBadInput;
  } catch (const std::exception& e) {
    int code = ReportError(e, ctx.argv);
    plumb::MpiAbortOnError(code);  // other ranks may be waiting for this one
    return code;
  }
}
