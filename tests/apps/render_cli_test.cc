// plumb render and --report from the command line: outputs, exit codes, messages.

#include <gtest/gtest.h>

#include <filesystem>

#include "fixture.h"
#include "plumb/image.h"
#include "plumb/render.h"

namespace plumb {
namespace {

using testing::RunPlumb;

#define SKIP_WITHOUT_RENDERER(result) \
  if ((result).exit_code == 5) GTEST_SKIP() << "no renderer here: " << (result).err

TEST(CliRenderTest, WritesAPictureAndSaysHowItWasMade) {
  testing::TempDir dir;
  auto r = RunPlumb("render '" + testing::kPendulum + "' --set 'qpos[hinge]=0.7' --at 0.1 -o " +
                    dir.File("p.png"));
  SKIP_WITHOUT_RENDERER(r);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("t = 0.1 s, 640x480, "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("camera fixed: whole model"), std::string::npos) << r.out;
  Image image = ReadPng(dir.File("p.png"));
  EXPECT_EQ(image.width, 640);
  EXPECT_EQ(image.height, 480);
}

TEST(CliRenderTest, WritesAVideoOfTheRun) {
  if (std::system("command -v ffprobe >/dev/null 2>&1") != 0) GTEST_SKIP() << "no ffmpeg";
  testing::TempDir dir;
  const std::string args = "render '" + testing::kPendulum +
                           "' --set 'qpos[hinge]=0.7' --until 1 --fps 25 --size 320x240 -o " +
                           dir.File("v.mp4");
  // make test-asan sets LP_NUM_THREADS=0 (llvmpipe on one thread) because LeakSanitizer's
  // exit-time scan crashed on llvmpipe's idle worker threads; the video path, though, crashes
  // LeakSanitizer's tracer with it set ("Tracer caught signal 11", exit 1, no leak found) and
  // passes without it. So this one command runs with Mesa's default threads.
  auto r = testing::RunShell("env -u LP_NUM_THREADS '" + std::string(PLUMB_CLI) + "' " + args);
  SKIP_WITHOUT_RENDERER(r);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // 0.04 s = 20 steps a frame: frames at 0, 0.04, ..., 1.0
  EXPECT_NE(r.out.find("26 frames at 25 fps (every 20 steps)"), std::string::npos) << r.out;
  auto probe = testing::RunShell(
      "ffprobe -v error -show_entries stream=codec_name,pix_fmt,"
      "nb_frames -of default=noprint_wrappers=1 " +
      dir.File("v.mp4"));
  EXPECT_NE(probe.out.find("codec_name=h264"), std::string::npos) << probe.out;
  EXPECT_NE(probe.out.find("pix_fmt=yuv420p"), std::string::npos) << probe.out;
  EXPECT_NE(probe.out.find("nb_frames=26"), std::string::npos) << probe.out;
}

TEST(CliRenderTest, BadOptionsAreExit2WithNothingWritten) {
  testing::TempDir dir;
  struct Case {
    std::string args, says;
  } cases[] = {
      {"-o " + dir.File("p.jpg"), "(.png) or a video (.mp4)"},
      {"--until 1 -o " + dir.File("p.png"), "--until makes a video"},
      {"-o " + dir.File("v.mp4"), "a video needs --until"},
      {"--size 640 -o " + dir.File("p.png"), "--size '640'"},
      {"--at -1 -o " + dir.File("p.png"), "--at -1"},
      {"--highlight nosuch -o " + dir.File("p.png"), "--highlight 'nosuch'"},
      {"--camera nosuch -o " + dir.File("p.png"), "--camera 'nosuch'"},
      {"--gl vulkan -o " + dir.File("p.png"), "--gl"},
  };
  for (const Case& c : cases) {
    auto r = RunPlumb("render '" + testing::kPendulum + "' " + c.args);
    if (r.exit_code == 5) continue;  // no renderer: checked below
    EXPECT_EQ(r.exit_code, 2) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args << ": " << r.err;
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(CliRenderTest, MissingFfmpegIsExit5) {
  if (!RendererBuilt()) GTEST_SKIP() << "no renderer in this build: render stops before ffmpeg";
  testing::TempDir dir;
  auto r = testing::RunShell("PLUMB_FFMPEG=/nonexistent '" + std::string(PLUMB_CLI) + "' render '" +
                             testing::kPendulum + "' --until 0.1 -o " + dir.File("v.mp4"));
  EXPECT_EQ(r.exit_code, 5) << r.err;
  EXPECT_NE(r.err.find("ffmpeg"), std::string::npos) << r.err;
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(CliRenderTest, ADivergingRunIsExit3AndNoPicture) {
  testing::TempDir dir;
  // a free body launched at 1e30 m/s: the state goes bad within a few steps
  testing::WriteFile(dir.File("m.xml"), R"(<mujoco><worldbody><body><freejoint/>
      <geom type="sphere" size="0.1"/></body></worldbody></mujoco>)");
  auto r = RunPlumb("render m.xml --set 'qvel[0]=1e30' --at 1 -o p.png", dir.path());
  SKIP_WITHOUT_RENDERER(r);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("diverged"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.File("p.png")));
}

// A build with PLUMB_WITH_RENDER=OFF (make test-norender): render says what is missing,
// and reports are written without their pictures, saying why.
TEST(CliRenderTest, WithoutTheRendererItSaysSo) {
  if (RendererBuilt()) GTEST_SKIP() << "this build has the renderer";
  testing::TempDir dir;
  auto r = RunPlumb("render '" + testing::kPendulum + "' -o " + dir.File("p.png"));
  EXPECT_EQ(r.exit_code, 5) << r.err;
  EXPECT_NE(r.err.find("built without the renderer"), std::string::npos) << r.err;
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
  r = RunPlumb("verify '" + testing::kPendulum + "' --set 'qpos[hinge]=0.7' --report " +
               dir.File("r.html"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::string html = testing::ReadFile(dir.File("r.html"));
  EXPECT_NE(html.find("No pictures: this plumb was built without the renderer"), std::string::npos);
  EXPECT_NE(html.find("class=\"plumb-chart\""), std::string::npos);
}

TEST(CliReportTest, EveryCommandWritesItsReport) {
  testing::TempDir dir;
  std::string m = "'" + testing::kPendulum + "' --set 'qpos[hinge]=0.7'";
  struct Case {
    std::string args, file;
  } cases[] = {
      {"verify " + m, "verify.html"},
      {"audit " + m, "audit.html"},
      {"converge " + m + " --metric 'qpos[hinge]@1'", "converge.html"},
      {"sweep " + m + " --vary 'dof_damping[hinge]=0:1:4' --metric 'qpos[hinge]@1'", "sweep.html"},
      {"rollout " + m +
           " --count 20 --until 1 --randomize 'dof_damping[hinge]=U(0,1)' "
           "--metric 'qpos[hinge]@1'",
       "rollout.html"},
  };
  for (const Case& c : cases) {
    auto r = RunPlumb(c.args + " --report " + dir.File(c.file));
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find("wrote the report " + dir.File(c.file)), std::string::npos) << r.err;
    std::string html = testing::ReadFile(dir.File(c.file));
    EXPECT_NE(html.find("</html>"), std::string::npos) << c.file;
    EXPECT_NE(html.find("plumb-chart"), std::string::npos) << c.file;
  }
  // an unwritable report is bad input, and the command's own output is not half done
  auto r = RunPlumb("verify " + m + " --report " + dir.File("no/such/folder/r.html"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("no/such/folder"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace plumb
