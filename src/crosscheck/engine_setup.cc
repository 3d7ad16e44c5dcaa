// Where the engine adapters and their virtual environments live, and making an environment.

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "crosscheck/engine_session.h"
#include "io/hash.h"
#include "plumb/crosscheck.h"
#include "plumb/error.h"

extern char** environ;

namespace plumb {
namespace {

namespace fs = std::filesystem;

std::string Env(const char* name) {
  const char* v = std::getenv(name);
  return v == nullptr ? "" : v;
}

std::string AdapterFolder() {
  std::string given = Env("PLUMB_ENGINES_DIR");
  if (!given.empty()) return given;
  // an installed plumb moved to another prefix finds the adapter beside its own program
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const std::string beside =
      ec ? "" : (exe.parent_path().parent_path() / "share/plumb/engines").string();
  for (const std::string& dir :
       {beside, std::string(PLUMB_INSTALL_ENGINES_DIR), std::string(PLUMB_SOURCE_ENGINES_DIR)}) {
    if (!dir.empty() && fs::exists(fs::path(dir) / "adapter.py")) return dir;
  }
  throw UnavailableError(fmt::format(
      "plumb crosscheck: the engine adapter is not installed (looked in {} and {}): reinstall "
      "plumb, or set PLUMB_ENGINES_DIR to the engines/ folder of its source",
      PLUMB_INSTALL_ENGINES_DIR, PLUMB_SOURCE_ENGINES_DIR));
}

std::string VenvRoot() {
  std::string given = Env("PLUMB_ENGINE_VENVS");
  if (!given.empty()) return given;
  std::string cache = Env("XDG_CACHE_HOME");
  if (cache.empty()) cache = Env("HOME").empty() ? "/tmp" : Env("HOME") + "/.cache";
  return cache + "/plumb/engines";
}

}  // namespace

void RequireKnownEngine(const std::string& engine) {
  const auto& engines = CrosscheckEngines();
  if (std::find(engines.begin(), engines.end(), engine) == engines.end()) {
    throw ArgumentError("engine", Quoted(engine), "plumb knows the engines warp and mjx");
  }
}

EngineSetup FindEngineSetup(const std::string& engine) {
  RequireKnownEngine(engine);
  const std::string folder = AdapterFolder();
  const std::string lock = folder + "/requirements-" + engine + ".txt";
  EngineSetup setup;
  setup.adapter = folder + "/adapter.py";
  const std::string venv = VenvRoot() + "/" + engine + "-" + HashFile(lock).substr(0, 12);
  setup.python = venv + "/bin/python";
  return setup;
}

bool EngineEnvironmentReady(const EngineSetup& setup) {
  const fs::path venv = fs::path(setup.python).parent_path().parent_path();
  std::error_code ec;
  if (!fs::exists(setup.python, ec)) return false;
  for (const auto& entry : fs::directory_iterator(venv, ec)) {
    if (entry.path().filename().string().rfind(".complete-", 0) == 0) return true;
  }
  return false;
}

void MakeEngineEnvironment(const std::string& engine, const EngineSetup& setup) {
  const fs::path folder = fs::path(setup.adapter).parent_path();
  const std::string script = (folder / "make-venv.sh").string();
  const std::string venv = fs::path(setup.python).parent_path().parent_path().string();
  std::vector<std::string> args = {"/bin/bash", script, engine, venv};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);  // it prints the python
  pid_t pid = 0;
  const int error = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) {
    throw UnavailableError(
        fmt::format("plumb crosscheck: cannot run {}: {}", script, std::strerror(error)));
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw UnavailableError(fmt::format(
        "plumb crosscheck: could not make the {} engine's environment in {} ({} said why, above); "
        "it needs python3-venv and PyPI: run `{}` where the network is reachable",
        engine, venv, script, EngineSetupCommand(engine)));
  }
}

EngineSetup ReadyEngineSetup(const std::string& engine) {
  EngineSetup setup = FindEngineSetup(engine);
  if (!EngineEnvironmentReady(setup)) MakeEngineEnvironment(engine, setup);
  return setup;
}

std::string EngineSetupCommand(const std::string& engine) {
  return "plumb crosscheck --setup --engine " + engine;  // command
}

}  // namespace plumb
