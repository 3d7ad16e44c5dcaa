// Where the engines' environments go (issue 46): PLUMB_ENGINE_VENVS, or the XDG_CACHE_HOME or
// HOME it derives from, naming a file, a place that cannot be made, an empty or a relative
// value is refused naming the variable and its value, before anything is written; a good one
// is made if missing. PLUMB_ENGINES_DIR without an adapter is refused the same way.

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <optional>
#include <string>

#include "fixture.h"
#include "plumb/crosscheck.h"
#include "plumb/error.h"

namespace plumb {
namespace {

// Sets (or with nullopt unsets) an environment variable for one scope, restoring it after.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, std::optional<std::string> value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) {
      setenv(name, value->c_str(), 1);
    } else {
      unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// FindEngineSetup("warp") throws a ValueError whose message holds each of `parts`.
void ExpectRefused(const std::vector<std::string>& parts) {
  try {
    FindEngineSetup("warp");
    FAIL() << "accepted";
  } catch (const ValueError& e) {
    for (const std::string& part : parts) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << part << " in " << e.what();
    }
  }
}

TEST(EngineSetupTest, AVenvsFolderThatIsAFileOrCannotBeMadeIsRefused) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("f"), "x\n");
  {
    ScopedEnv venvs("PLUMB_ENGINE_VENVS", dir.File("f"));
    ExpectRefused({"PLUMB_ENGINE_VENVS='" + dir.File("f") + "'", "is a file, not a folder",
                   "unset it"});
  }
  {
    ScopedEnv venvs("PLUMB_ENGINE_VENVS", dir.File("f") + "/deeper/still");
    ExpectRefused({"PLUMB_ENGINE_VENVS='" + dir.File("f") + "/deeper/still'",
                   dir.File("f") + " is a file"});
  }
  {
    ScopedEnv venvs("PLUMB_ENGINE_VENVS", "/proc/nope");
    ExpectRefused({"PLUMB_ENGINE_VENVS='/proc/nope'", "/proc/nope cannot be made"});
  }
  EXPECT_FALSE(std::filesystem::exists("/proc/nope"));
  // the file is left as it was, and nothing else appeared beside it
  EXPECT_EQ(testing::ReadFile(dir.File("f")), "x\n");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(EngineSetupTest, AnEmptyOrRelativeVenvsFolderIsRefused) {
  {
    ScopedEnv venvs("PLUMB_ENGINE_VENVS", "");
    ExpectRefused({"PLUMB_ENGINE_VENVS=''", "is empty"});
  }
  {
    ScopedEnv venvs("PLUMB_ENGINE_VENVS", "venvs/here");
    ExpectRefused({"PLUMB_ENGINE_VENVS='venvs/here'", "relative path"});
  }
  EXPECT_FALSE(std::filesystem::exists("venvs"));
}

TEST(EngineSetupTest, ACacheFolderThatIsAFileNamesTheVariableItCameFrom) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("cache"), "x\n");
  ScopedEnv venvs("PLUMB_ENGINE_VENVS", std::nullopt);
  {
    ScopedEnv xdg("XDG_CACHE_HOME", dir.File("cache"));
    ExpectRefused({"(from XDG_CACHE_HOME='" + dir.File("cache") + "')", "is a file"});
  }
  ScopedEnv xdg("XDG_CACHE_HOME", std::nullopt);
  {
    ScopedEnv home("HOME", dir.path());
    testing::WriteFile(dir.File(".cache"), "x\n");
    ExpectRefused({"(from HOME='" + dir.path() + "')", dir.File(".cache") + " is a file"});
  }
  {
    ScopedEnv home("HOME", std::nullopt);
    ExpectRefused({"HOME is not set", "Set PLUMB_ENGINE_VENVS"});
  }
}

TEST(EngineSetupTest, AGoodVenvsFolderIsMadeIfMissing) {
  testing::TempDir dir;
  ScopedEnv venvs("PLUMB_ENGINE_VENVS", dir.File("new/venvs"));
  EngineSetup setup = FindEngineSetup("warp");
  EXPECT_EQ(setup.python.rfind(dir.File("new/venvs/warp-"), 0), 0u) << setup.python;
  EXPECT_TRUE(std::filesystem::is_directory(dir.File("new/venvs")));
  EXPECT_FALSE(EngineEnvironmentReady(setup));
}

TEST(EngineSetupTest, AnEnginesDirWithoutTheAdapterIsRefused) {
  testing::TempDir dir;
  ScopedEnv engines("PLUMB_ENGINES_DIR", dir.path());
  try {
    FindEngineSetup("warp");
    FAIL() << "accepted";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("PLUMB_ENGINES_DIR='" + dir.path() + "'"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace plumb
