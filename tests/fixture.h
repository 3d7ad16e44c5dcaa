// Test helpers: a fixture that fails on any MuJoCo warning, inline models, and running
// the plumb binary as a user would.

#ifndef PLUMB_TESTS_FIXTURE_H_
#define PLUMB_TESTS_FIXTURE_H_

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/model.h"

namespace plumb::testing {

inline const std::string kSourceDir = PLUMB_SOURCE_DIR;
inline const std::string kPendulum = kSourceDir + "/models/pendulum.xml";
inline const std::string kHumanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml";

// The chapter's printed lines for the pendulum started at 0.7 rad (t = 0.1 ... 0.5 s).
inline constexpr double kChapterQ[] = {0.65403, 0.52386, 0.32596, 0.08646, -0.16156};
inline constexpr double kChapterDq[] = {-0.89118, -1.66939, -2.23353, -2.49511, -2.40852};

// A model that overfills MuJoCo's contact or constraint buffer on every step without
// diverging (ten boxes resting on a floor), and the warning it raises. The versions differ:
// 2.x caps contacts with nconmax (CONTACTFULL); 3.x allocates contacts dynamically, so
// nconmax no longer caps them, and raises CNSTRFULL when the arena (<size memory>) holds the
// step's stack but not its constraints (48K does on 3.11.0 and 4.0.1; less overflows the
// stack, which is a MuJoCo error, and 96K holds everything).
inline std::string OverfullModel() {
  std::string size = mjVERSION_HEADER >= 300 ? R"(<size memory="48K"/>)" : R"(<size nconmax="1"/>)";
  std::string boxes;
  for (int i = 0; i < 10; ++i) {
    boxes += "<body pos=\"" + std::to_string(0.3 * i) +
             " 0 0.05\"><freejoint/><geom type=\"box\" size=\"0.1 0.1 0.05\"/></body>";
  }
  return "<mujoco model=\"crowded\">" + size +
         R"(<worldbody><geom name="floor" type="plane" size="5 5 0.1"/>)" + boxes +
         "</worldbody></mujoco>";
}
inline const std::string kOverfullWarning = mjVERSION_HEADER >= 300 ? "CNSTRFULL" : "CONTACTFULL";

// The MuJoCo version plumb is built against, as MuJoCo writes it ("2.2.2", "4.0.1").
inline std::string CompiledMujocoVersion() { return plumb::CompiledMujocoVersion(); }

// True when `text` names line `line` of a MuJoCo load error, however this MuJoCo words it
// ("line = 5" on 2.x, "line 5" on 3.x): tests never match MuJoCo's own wording.
inline bool NamesLine(const std::string& text, int line) {
  std::string lower = plumb::internal::Lowercase(text);
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

// The message of the ValueError `f` throws, or "" when it throws none.
inline std::string ValueErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ValueError& e) {
    return e.what();
  }
  return "";
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// How many times `what` occurs in `text` (events and rows of a log, lines of stderr).
inline long Occurrences(const std::string& text, const std::string& what) {
  long n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Every MJCF file of MuJoCo's samples (libmujoco-samples, installed by
// scripts/install-deps.sh) and of the DeepMind Control Suite (carried in tests/models), sorted:
// models nobody here wrote. VerifyModelsListTest fails, saying how to get them, when either
// folder is missing.
// A pendulum whose damping is NaN and whose rod's colour holds an infinity: MuJoCo compiles
// both with at most a warning (hostile_models.py found verify and audit passing such models).
inline const char* const kNonFiniteXml = R"(<mujoco><option timestep="0.002"/><worldbody>
    <body name="arm" pos="0 0 1"><joint name="hinge" axis="0 1 0" damping="nan"/>
      <geom name="rod" type="capsule" fromto="0 0 0 0 0 -1" size="0.05" rgba="1 inf 0 1"/>
    </body></worldbody></mujoco>)";

inline const std::string kSamples = "/usr/share/mujoco/model";
inline const std::string kSuite = PLUMB_DM_CONTROL_DIR;

inline std::vector<std::string> ThirdPartyModels() {
  std::vector<std::string> files;
  for (const std::string& root : {kSamples, kSuite}) {
    std::error_code ec;
    for (auto it = std::filesystem::recursive_directory_iterator(root, ec);
         !ec && it != std::filesystem::end(it); it.increment(ec)) {
      if (it->path().extension() == ".xml") files.push_back(it->path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Debian's 2.2.2 sample models that newer MuJoCo releases refuse to load: the first
// release (mjVERSION_HEADER) that refuses each, and why. They are checked on the older
// legs; on a newer leg a test skips them after confirming that they still fail to load
// (a sample that starts loading must leave this list).
struct RefusedSample {
  int since;
  const char* reason;
};
inline const std::map<std::string, RefusedSample> kRefusedSamples = {
    {"active_adhesion.xml", {300, "uses <composite>, whose 2.x form MuJoCo 3 removed"}},
    {"cloth.xml", {300, "uses <composite type=\"cloth\">, whose 2.x form MuJoCo 3 removed"}},
    {"grid2pin.xml", {300, "uses <composite type=\"grid\">, whose 2.x form MuJoCo 3 removed"}},
    {"loop.xml", {300, "uses <composite type=\"loop\">, whose 2.x form MuJoCo 3 removed"}},
    {"particle.xml", {300, "uses <composite type=\"particle\">, whose 2.x form MuJoCo 3 removed"}},
    {"rope.xml", {300, "uses <composite type=\"rope\">, whose 2.x form MuJoCo 3 removed"}},
    {"softbox.xml", {300, "uses <composite type=\"box\">, whose 2.x form MuJoCo 3 removed"}},
    {"flag.xml", {300, "uses <composite type=\"grid\">, whose 2.x form MuJoCo 3 removed"}},
    {"hammock.xml", {300, "uses <composite type=\"grid\">, whose 2.x form MuJoCo 3 removed"}},
    {"arm26.xml",
     {4000000, "MuJoCo 4's muscle length-range computation does not converge for actuator 1"}},
};

// The reason `file` does not load on this MuJoCo, or nullptr when it should load.
inline const char* RefusedReason(const std::string& file) {
  if (file.rfind("/usr/share/mujoco/", 0) != 0) return nullptr;
  auto listed = kRefusedSamples.find(std::filesystem::path(file).filename().string());
  if (listed == kRefusedSamples.end() || mjVERSION_HEADER < listed->second.since) return nullptr;
  return listed->second.reason;
}

// Loads a third-party model; a sample this MuJoCo refuses (above) is confirmed to still
// fail to load, and the test fails if it loads after all. Returns false when refused.
inline bool LoadThirdParty(const std::string& file, std::optional<Model>* model) {
  const char* refused = RefusedReason(file);
  if (!refused) {
    model->emplace(Model::Load(file));
    return true;
  }
  try {
    Model::Load(file);
  } catch (const LoadError&) {
    return false;
  }
  ADD_FAILURE() << file << " loads on this MuJoCo: remove it from kRefusedSamples (" << refused
                << ")";
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

// The lines of `text`, without their newlines.
inline std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// The numbers of CSV line `line` (0 = header) of `csv`.
inline std::vector<double> CsvRow(const std::string& csv, int line) {
  std::vector<std::string> lines = Lines(csv);
  std::vector<double> values;
  if (line < 0 || line >= static_cast<int>(lines.size())) return values;
  std::istringstream fields(lines[line]);
  for (std::string field; std::getline(fields, field, ',');) values.push_back(std::stod(field));
  return values;
}

// The numbers of CSV column `column` (0-based) below the header line.
inline std::vector<double> CsvColumn(const std::string& csv, int column) {
  std::vector<std::string> lines = Lines(csv);
  std::vector<double> values;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    std::istringstream cells(lines[i]);
    std::string cell;
    for (int c = 0; c <= column && std::getline(cells, cell, ','); ++c) {
    }
    values.push_back(std::stod(cell));
  }
  return values;
}

// Where scripts/fetch-robots.sh puts the robot corpus (make corpus): $PLUMB_CACHE/robots,
// else ${XDG_CACHE_HOME:-$HOME/.cache}/plumb/robots.
inline std::filesystem::path CorpusRoot() {
  if (const char* cache = std::getenv("PLUMB_CACHE"); cache && *cache) {
    return std::filesystem::path(cache) / "robots";
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) {
    return std::filesystem::path(xdg) / "plumb" / "robots";
  }
  const char* home = std::getenv("HOME");
  return std::filesystem::path(home ? home : "/") / ".cache" / "plumb" / "robots";
}

// A model of the robot corpus by its path below CorpusRoot, or "" when the corpus is not
// fetched (a test then skips, or fails when PLUMB_REQUIRE_CORPUS is set: see
// RequireCorpusModel).
inline std::string CorpusModel(const std::string& relative) {
  std::filesystem::path p = CorpusRoot() / relative;
  return std::filesystem::exists(p) ? p.string() : "";
}

// Two hinged links about y (joints "a" and "b", 0.3 m capsules) with `actuators` as the
// model's <actuator> content.
inline std::string TwoHingeArm(const std::string& actuators) {
  return R"(<mujoco><worldbody>
      <body><joint name="a" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/>
        <body pos="0.3 0 0"><joint name="b" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/></body></body></worldbody>
    <actuator>)" +
         actuators + "</actuator></mujoco>";
}

// CorpusModel for a test that needs it: "" when it is missing, and then a failure as well
// when PLUMB_REQUIRE_CORPUS is set (make test sets it). The corpus needs MuJoCo 3 or later:
// on 2.x it is always "", without a failure.
inline std::string RequireCorpusModel(const std::string& relative) {
  if (mjVERSION_HEADER < 300) return "";
  std::string path = CorpusModel(relative);
  if (path.empty() && std::getenv("PLUMB_REQUIRE_CORPUS")) {
    ADD_FAILURE() << "the robot corpus is missing " << relative << ": run make corpus";
  }
  return path;
}

// A copy of the model file at `path` with each `edits` pair's first text replaced by its
// second (each must occur once at least: a missing one fails the test), written into `dir`
// beside links to everything in the model's folder, so its meshes and includes resolve.
// Returns the copy's path.
inline std::string EditedModelCopy(const std::string& path,
                                   const std::vector<std::pair<std::string, std::string>>& edits,
                                   const std::string& dir) {
  std::string xml = ReadFile(path);
  for (const auto& [from, to] : edits) {
    size_t at = xml.find(from);
    EXPECT_NE(at, std::string::npos) << "no '" << from << "' in " << path;
    if (at != std::string::npos) xml.replace(at, from.size(), to);
  }
  std::filesystem::path folder = std::filesystem::path(path).parent_path();
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    std::filesystem::path link = std::filesystem::path(dir) / entry.path().filename();
    if (!std::filesystem::exists(std::filesystem::symlink_status(link))) {
      std::filesystem::create_symlink(entry.path(), link);
    }
  }
  std::string edited = (std::filesystem::path(dir) / "edited.xml").string();
  WriteFile(edited, xml);
  return edited;
}

// Output of one command run.
struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs `command` (a whole shell list) with /bin/sh in `dir` (default: current), capturing
// stdout and stderr.
inline CommandResult RunShell(const std::string& command, const std::string& dir = ".") {
  TempDir capture;
  std::string full = "cd '" + dir + "' && (" + command + "\n) >'" + capture.File("out") + "' 2>'" +
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
