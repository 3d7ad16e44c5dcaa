// Environment variables naming files or places plumb cannot use (issue 46): each is refused
// with a message naming the variable and its value, before anything is written, and never
// leads to a write somewhere else (PLUMB_ENGINE_VENVS naming a file built a 542 MB environment
// at the root of the file system).

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "fixture.h"
#include "plumb/render.h"

namespace plumb {
namespace {

using testing::RunShell;
using testing::TempDir;

const std::string kPlumb = std::string("'") + PLUMB_CLI + "'";

// A copy of engines/ whose make-venv.sh reaches a stand-in test-venv.sh that records being
// called and makes nothing: a case that got as far as installing cannot reach the network or
// write anywhere (the stand-in's record says it got there).
std::string StandInEngines(const TempDir& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir.File("engines"));
  fs::create_directories(dir.File("scripts"));
  for (const auto& entry : fs::directory_iterator(testing::kSourceDir + "/engines")) {
    if (entry.is_regular_file()) fs::copy_file(entry.path(), dir.File("engines") + "/" +
                                               entry.path().filename().string());
  }
  testing::WriteFile(dir.File("scripts/test-venv.sh"),
                     "#!/usr/bin/env bash\necho \"$1\" >>'" + dir.File("called") + "'\nexit 1\n");
  return dir.File("engines");
}

bool NoEnvironmentAtTheRoot() {
  for (const auto& entry : std::filesystem::directory_iterator("/")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("warp-", 0) == 0 || name.rfind("mjx-", 0) == 0) return false;
  }
  return true;
}

TEST(CliEnvironmentTest, AVenvsFolderThatIsAFileIsExit2BeforeAnyWork) {
  TempDir dir;
  const std::string engines = StandInEngines(dir);
  testing::WriteFile(dir.File("f"), "x\n");
  for (const std::string& args :
       {"crosscheck '" + testing::kPendulum + "' --engine warp --worlds 4 --until 0.2",
        std::string("crosscheck --setup --engine warp")}) {
    auto r = RunShell("PLUMB_ENGINES_DIR='" + engines + "' PLUMB_ENGINE_VENVS='" + dir.File("f") +
                      "' " + kPlumb + " " + args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("PLUMB_ENGINE_VENVS='" + dir.File("f") + "'"), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("is a file, not a folder"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.File("called"))) << "the install was started";
  }
  EXPECT_EQ(testing::ReadFile(dir.File("f")), "x\n");
  EXPECT_TRUE(NoEnvironmentAtTheRoot());
}

TEST(CliEnvironmentTest, AVenvsFolderThatCannotBeMadeEmptyOrRelativeIsExit2) {
  TempDir dir;
  const std::string engines = StandInEngines(dir);
  for (const char* value : {"/proc/nope", "", "relative/venvs"}) {
    auto r = RunShell("PLUMB_ENGINES_DIR='" + engines + "' PLUMB_ENGINE_VENVS='" + std::string(value) + "' " +
                          kPlumb + " crosscheck m.xml --engine warp",
                      dir.path());
    EXPECT_EQ(r.exit_code, 2) << value << "\n" << r.err;
    EXPECT_NE(r.err.find(std::string("PLUMB_ENGINE_VENVS='") + value + "'"), std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.File("called"))) << "the install was started";
  }
  EXPECT_FALSE(std::filesystem::exists(dir.File("relative")));
  EXPECT_TRUE(NoEnvironmentAtTheRoot());
}

TEST(CliEnvironmentTest, AHomeCacheThatIsAFileNamesHome) {
  TempDir dir;
  const std::string engines = StandInEngines(dir);
  std::filesystem::create_directories(dir.File("home"));
  testing::WriteFile(dir.File("home/.cache"), "x\n");
  auto r = RunShell("unset PLUMB_ENGINE_VENVS XDG_CACHE_HOME; PLUMB_ENGINES_DIR='" + engines +
                    "' HOME='" + dir.File("home") + "' " + kPlumb +
                    " crosscheck --setup --engine mjx");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("(from HOME='" + dir.File("home") + "')"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("called"))) << "the install was started";
}

TEST(CliEnvironmentTest, AnFfmpegThatIsAFolderOrNotExecutableIsNamed) {
  if (!RendererBuilt()) GTEST_SKIP() << "no renderer in this build: render stops before ffmpeg";
  TempDir dir;
  testing::WriteFile(dir.File("ffmpeg"), "#!/bin/sh\nexit 0\n");  // not executable
  for (const std::string& value : {dir.path(), dir.File("ffmpeg")}) {
    auto r = RunShell("PLUMB_FFMPEG='" + value + "' " + kPlumb + " render '" + testing::kPendulum +
                      "' --until 0.1 -o " + dir.File("v.mp4"));
    EXPECT_EQ(r.exit_code, 5) << r.err;
    EXPECT_NE(r.err.find("PLUMB_FFMPEG='" + value + "' is not one"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.File("v.mp4")));
  }
}

TEST(CliEnvironmentTest, APluginPathThatIsAFileIsExit2) {
  if (mjVERSION_HEADER < 300) GTEST_SKIP() << "MuJoCo 2.x has no plugins";
  TempDir dir;
  testing::WriteFile(dir.File("f"), "x\n");
  auto r = RunShell("PLUMB_MUJOCO_PLUGIN_PATH='" + dir.File("f") + "' " + kPlumb + " run '" +
                    testing::kPendulum + "' --until 0.01");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("PLUMB_MUJOCO_PLUGIN_PATH='" + dir.File("f") + "' is not a folder"),
            std::string::npos)
      << r.err;
  auto version = RunShell("PLUMB_MUJOCO_PLUGIN_PATH='" + dir.File("f") + "' " + kPlumb +
                          " --version");
  EXPECT_EQ(version.exit_code, 0) << version.err;
  EXPECT_NE(version.out.find("PLUMB_MUJOCO_PLUGIN_PATH"), std::string::npos) << version.out;
}

}  // namespace
}  // namespace plumb
