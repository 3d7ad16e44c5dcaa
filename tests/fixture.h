// Test helpers: a fixture that fails on any MuJoCo warning, inline models, and running
// the plumb binary as a user would.

#ifndef PLUMB_TESTS_FIXTURE_H_
#define PLUMB_TESTS_FIXTURE_H_

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "plumb/error.h"
#include "plumb/model.h"

namespace plumb::testing {

inline const std::string kSourceDir = PLUMB_SOURCE_DIR;
inline const std::string kPendulum = kSourceDir + "/models/pendulum.xml";
inline const std::string kHumanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml";

// The chapter's printed lines for the pendulum started at 0.7 rad (t = 0.1 ... 0.5 s).
inline constexpr double kChapterQ[] = {0.65403, 0.52386, 0.32596, 0.08646, -0.16156};
inline constexpr double kChapterDq[] = {-0.89118, -1.66939, -2.23353, -2.49511, -2.40852};

// A <size> element that overfills MuJoCo's contact or constraint buffer within a step,
// and the warning it raises without diverging. The versions differ: 2.x caps contacts
// with nconmax (CONTACTFULL); 3.x allocates contacts dynamically, so nconmax no longer
// caps them, and raises CNSTRFULL when the arena (<size memory>) is too small.
inline const std::string kOverfullSize =
    mjVERSION_HEADER >= 300 ? R"(<size memory="4K"/>)" : R"(<size nconmax="1"/>)";
inline const std::string kOverfullWarning = mjVERSION_HEADER >= 300 ? "CNSTRFULL" : "CONTACTFULL";

// The MuJoCo version plumb is built against, as MuJoCo writes it ("2.2.2", "4.0.1").
inline std::string CompiledMujocoVersion() { return plumb::CompiledMujocoVersion(); }

// True when `text` names line `line` of a MuJoCo load error, however this MuJoCo words it
// ("line = 5" on 2.x, "line 5" on 3.x): tests never match MuJoCo's own wording.
inline bool NamesLine(const std::string& text, int line) {
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const std::string sep : {"line = ", "line ", "line: ", "line="}) {
    if (lower.find(sep + std::to_string(line)) != std::string::npos) return true;
  }
  return false;
}

// Fails the test when MuJoCo raised a warning through its handler (as MuJoCo's own
// MujocoTest fixture does).
class MujocoTest : public ::testing::Test {
 protected:
  void SetUp() override { TakeMujocoWarnings(); }
  void TearDown() override {
    for (const std::string& w : TakeMujocoWarnings()) ADD_FAILURE() << "MuJoCo warning: " << w;
  }
};

// A fresh empty directory under the system temp dir, removed when it goes out of scope.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "plumb-test-XXXXXX").string();
    std::vector<char> name(pattern.begin(), pattern.end());
    name.push_back('\0');
    path_ = mkdtemp(name.data());
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::permissions(path_, std::filesystem::perms::owner_all, ec);
    std::filesystem::remove_all(path_, ec);
  }
  std::string File(const std::string& name) const { return path_ + "/" + name; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

inline void WriteFile(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every MJCF file of MuJoCo's samples (libmujoco-samples) and of the DeepMind Control
// Suite in shared/ (when present), sorted: models nobody here wrote.
inline const std::string kSuite = std::string(PLUMB_SHARED_DIR) + "/models/dm_control/suite";

inline std::vector<std::string> ThirdPartyModels() {
  std::vector<std::string> files;
  for (const std::string& root : {std::string("/usr/share/mujoco/model"), kSuite}) {
    std::error_code ec;
    for (auto it = std::filesystem::recursive_directory_iterator(root, ec);
         !ec && it != std::filesystem::end(it); it.increment(ec)) {
      if (it->path().extension() == ".xml") files.push_back(it->path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Debian's 2.2.2 sample models that MuJoCo 3 refuses to load, with the reason. They are
// checked on the 2.2.2 leg only; on a newer leg a test skips them after confirming that
// they still fail to load (a sample that starts loading must leave this list).
inline const std::map<std::string, std::string> kSamplesForMujocoTwoOnly = {
    {"active_adhesion.xml", "uses <composite>, whose 2.x form MuJoCo 3 removed"},
    {"cloth.xml", "uses <composite type=\"cloth\">, whose 2.x form MuJoCo 3 removed"},
    {"grid2pin.xml", "uses <composite type=\"grid\">, whose 2.x form MuJoCo 3 removed"},
    {"loop.xml", "uses <composite type=\"loop\">, whose 2.x form MuJoCo 3 removed"},
    {"particle.xml", "uses <composite type=\"particle\">, whose 2.x form MuJoCo 3 removed"},
    {"rope.xml", "uses <composite type=\"rope\">, whose 2.x form MuJoCo 3 removed"},
    {"softbox.xml", "uses <composite type=\"box\">, whose 2.x form MuJoCo 3 removed"},
    {"flag.xml", "uses <composite type=\"grid\">, whose 2.x form MuJoCo 3 removed"},
    {"hammock.xml", "uses <composite type=\"grid\">, whose 2.x form MuJoCo 3 removed"},
    {"arm26.xml",
     "its muscles' length ranges no longer converge under MuJoCo 3's lengthrange defaults"},
};

// Loads a third-party model; on MuJoCo 3 and later a sample listed above is skipped with
// its reason (and the test fails if it loads after all). Returns false when skipped.
inline bool LoadThirdParty(const std::string& file, std::optional<Model>* model) {
  std::string name = std::filesystem::path(file).filename().string();
  auto listed = kSamplesForMujocoTwoOnly.find(name);
  if (mjVERSION_HEADER < 300 || listed == kSamplesForMujocoTwoOnly.end() ||
      file.rfind("/usr/share/mujoco/", 0) != 0) {
    model->emplace(Model::Load(file));
    return true;
  }
  try {
    Model::Load(file);
  } catch (const LoadError&) {
    return false;
  }
  ADD_FAILURE() << name << " loads on this MuJoCo: remove it from kSamplesForMujocoTwoOnly ("
                << listed->second << ")";
  return false;
}

// "folder_stem" for a model path, usable as a parameterised test's name.
inline std::string ModelTestName(const ::testing::TestParamInfo<std::string>& info) {
  std::filesystem::path p(info.param);
  std::string name = p.parent_path().filename().string() + "_" + p.stem().string();
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

// Output of one command run.
struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs `command` with /bin/sh in `dir` (default: current), capturing stdout and stderr.
inline CommandResult RunShell(const std::string& command, const std::string& dir = ".") {
  TempDir capture;
  std::string full = "cd '" + dir + "' && " + command + " >'" + capture.File("out") + "' 2>'" +
                     capture.File("err") + "' </dev/null";
  int status = std::system(full.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = ReadFile(capture.File("out"));
  r.err = ReadFile(capture.File("err"));
  return r;
}

// Runs the plumb binary with `args` (already shell-quoted where needed).
inline CommandResult RunPlumb(const std::string& args, const std::string& dir = ".") {
  return RunShell(std::string("'") + PLUMB_CLI + "' " + args, dir);
}

}  // namespace plumb::testing

#endif  // PLUMB_TESTS_FIXTURE_H_
