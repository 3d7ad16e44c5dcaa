// MP4 through ffmpeg: a complete video or nothing under the target's name.

#include "plumb/video.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

bool HaveFfmpeg() { return std::system("command -v ffmpeg >/dev/null 2>&1") == 0; }

Image Frame(int w, int h, int k) {
  Image image;
  image.width = w;
  image.height = h;
  image.rgb.assign(std::size_t(w) * h * 3, 0);
  for (int y = 0; y < h; ++y) image.rgb[(std::size_t(y) * w + (k % w)) * 3] = 255;  // a moving line
  return image;
}

// Files in `dir` other than `keep`.
std::vector<std::string> Others(const std::string& dir, const std::string& keep) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().filename() != keep) names.push_back(e.path().filename().string());
  }
  return names;
}

TEST(VideoTest, WritesAnH264Yuv420pMp4) {
  if (!HaveFfmpeg()) GTEST_SKIP() << "ffmpeg is not installed (scripts/install-deps.sh does)";
  testing::TempDir dir;
  VideoWriter video(dir.File("v.mp4"), 63, 31, 25);  // odd: padded to even
  for (int k = 0; k < 20; ++k) video.Add(Frame(63, 31, k));
  EXPECT_FALSE(std::filesystem::exists(dir.File("v.mp4")));  // not before Finish
  video.Finish();
  EXPECT_EQ(video.frames(), 20);
  ASSERT_TRUE(std::filesystem::exists(dir.File("v.mp4")));
  EXPECT_TRUE(Others(dir.path(), "v.mp4").empty());
  testing::CommandResult probe = testing::RunShell(
      "ffprobe -v error -select_streams v:0 -show_entries stream=codec_name,pix_fmt,nb_frames,"
      "width,height -of default=noprint_wrappers=1 '" +
      dir.File("v.mp4") + "'");
  ASSERT_EQ(probe.exit_code, 0) << probe.err;
  EXPECT_NE(probe.out.find("codec_name=h264"), std::string::npos) << probe.out;
  EXPECT_NE(probe.out.find("pix_fmt=yuv420p"), std::string::npos) << probe.out;
  EXPECT_NE(probe.out.find("width=64"), std::string::npos) << probe.out;
  EXPECT_NE(probe.out.find("nb_frames=20"), std::string::npos) << probe.out;
}

TEST(VideoTest, AnUnfinishedVideoLeavesNothing) {
  if (!HaveFfmpeg()) GTEST_SKIP() << "ffmpeg is not installed";
  testing::TempDir dir;
  {
    VideoWriter video(dir.File("v.mp4"), 32, 32, 10);
    video.Add(Frame(32, 32, 1));
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(VideoTest, AFrameOfAnotherSizeIsRefused) {
  if (!HaveFfmpeg()) GTEST_SKIP() << "ffmpeg is not installed";
  testing::TempDir dir;
  VideoWriter video(dir.File("v.mp4"), 32, 32, 10);
  EXPECT_THROW(video.Add(Frame(16, 32, 1)), ValueError);
}

TEST(VideoTest, MissingFfmpegIsUnavailableAndWritesNothing) {
  testing::TempDir dir;
  setenv("PLUMB_FFMPEG", "/nonexistent/ffmpeg", 1);
  try {
    VideoWriter video(dir.File("v.mp4"), 32, 32, 10);
    FAIL() << "no error";
  } catch (const UnavailableError& e) {
    EXPECT_NE(std::string(e.what()).find("ffmpeg"), std::string::npos) << e.what();
  }
  unsetenv("PLUMB_FFMPEG");
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(VideoTest, NoFrameMeansNoVideo) {
  if (!HaveFfmpeg()) GTEST_SKIP() << "ffmpeg is not installed";
  testing::TempDir dir;
  VideoWriter video(dir.File("v.mp4"), 32, 32, 10);
  EXPECT_THROW(video.Finish(), IoError);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(VideoTest, BadSizeOrRateIsAValueError) {
  testing::TempDir dir;
  EXPECT_THROW(VideoWriter(dir.File("v.mp4"), 0, 10, 10), ValueError);
  EXPECT_THROW(VideoWriter(dir.File("v.mp4"), 10, 10, 0), ValueError);
  EXPECT_THROW(VideoWriter(dir.File("v.mp4"), 10, 10, NAN), ValueError);
}

}  // namespace
}  // namespace plumb
