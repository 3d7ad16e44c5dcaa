// Where the engine adapters and their virtual environments live, and making an environment.

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "crosscheck/engine_session.h"
#include "io/hash.h"
#include "plumb/crosscheck.h"
#include "plumb/error.h"

extern char** environ;

namespace plumb {
using internal::EngineSetupCommand;
using internal::HashFile;
using internal::RequireKnownEngine;

namespace {

namespace fs = std::filesystem;

std::string Env(const char* name) {
  const char* v = std::getenv(name);
  return v == nullptr ? "" : v;
}

std::string AdapterFolder() {
  std::string given = Env("PLUMB_ENGINES_DIR");
  std::error_code ec;
  if (!given.empty() && !fs::is_regular_file(fs::path(given) / "adapter.py", ec)) {
    throw ValueError(fmt::format(
        "plumb crosscheck: PLUMB_ENGINES_DIR='{}' is not a folder holding adapter.py: set it to "
        "the engines/ folder of plumb's source, or unset it to use the installed one",
        given));
  }
  if (!given.empty()) return given;
  // an installed plumb moved to another prefix finds the adapter beside its own program
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

// The folder that holds the engines' environments, and the variable it comes from (for the
// messages): $PLUMB_ENGINE_VENVS, else $XDG_CACHE_HOME/plumb/engines (an empty or relative
// XDG_CACHE_HOME is ignored, as the XDG base directory rules say), else
// $HOME/.cache/plumb/engines.
struct VenvRoot {
  std::string path, variable, value;
};

VenvRoot FindVenvRoot() {
  if (const char* given = std::getenv("PLUMB_ENGINE_VENVS")) {
    return {given, "PLUMB_ENGINE_VENVS", given};
  }
  const std::string xdg = Env("XDG_CACHE_HOME");
  if (!xdg.empty() && xdg.front() == '/') return {xdg + "/plumb/engines", "XDG_CACHE_HOME", xdg};
  const std::string home = Env("HOME");
  return {home + "/.cache/plumb/engines", "HOME", home};
}

[[noreturn]] void RefuseVenvRoot(const VenvRoot& root, const std::string& problem) {
  const bool given = root.variable == "PLUMB_ENGINE_VENVS";
  const std::string where =
      given ? fmt::format("PLUMB_ENGINE_VENVS='{}'", root.value)
            : fmt::format("{} (from {}='{}')", root.path, root.variable, root.value);
  throw ValueError(fmt::format(
      "plumb crosscheck: {} cannot hold the engines' environments: {}. Set PLUMB_ENGINE_VENVS "
      "to the absolute path of a folder you can write (it is made if missing){}; nothing was "
      "written",
      where, problem, given ? ", or unset it to use ~/.cache/plumb/engines" : ""));
}

// The folder of the environments, made if missing, after checking that it is an absolute
// path to a folder plumb can write: a file on the way, a place that cannot be made (/proc)
// or written (a read-only file system, another user's folder), an empty or a relative value
// are refused before anything is written.
std::string ReadyVenvRoot() {
  const VenvRoot root = FindVenvRoot();
  if (root.value.empty()) {
    RefuseVenvRoot(root, root.variable + (std::getenv(root.variable.c_str()) ? " is empty" : " is not set"));
  }
  if (root.value.front() != '/') {
    RefuseVenvRoot(root, "it is a relative path (the environments would move with the current "
                         "folder)");
  }
  // the nearest part of the path that exists must be a folder: `mkdir -p` would fail on a file
  std::error_code ec;
  for (fs::path part = root.path; !part.empty(); part = part.parent_path()) {
    const fs::file_status status = fs::status(part, ec);
    if (ec && status.type() != fs::file_type::not_found) {
      RefuseVenvRoot(root, fmt::format("{} cannot be looked at ({})", part.string(), ec.message()));
    }
    if (fs::exists(status)) {
      if (!fs::is_directory(status)) {
        RefuseVenvRoot(root, fmt::format("{} is a file, not a folder", part.string()));
      }
      break;
    }
    if (part == part.parent_path()) break;
  }
  fs::create_directories(root.path, ec);
  if (ec) {
    RefuseVenvRoot(root, fmt::format("{} cannot be made ({})", root.path, ec.message()));
  }
  if (access(root.path.c_str(), W_OK | X_OK) != 0) {
    RefuseVenvRoot(root, fmt::format("{} cannot be written ({})", root.path, std::strerror(errno)));
  }
  return root.path;
}

}  // namespace

void internal::RequireKnownEngine(const std::string& engine) {
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
  const std::string venv = ReadyVenvRoot() + "/" + engine + "-" + HashFile(lock).substr(0, 12);
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

std::string internal::EngineSetupCommand(const std::string& engine) {
  return "plumb crosscheck --setup --engine " + engine;  // command
}

}  // namespace plumb
