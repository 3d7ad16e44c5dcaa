// PNG encoding and the atomic write of pictures.

#include "plumb/image.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

Image Gradient(int w, int h) {
  Image image;
  image.width = w;
  image.height = h;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      image.rgb.push_back(static_cast<std::uint8_t>(x));
      image.rgb.push_back(static_cast<std::uint8_t>(y));
      image.rgb.push_back(static_cast<std::uint8_t>(x ^ y));
    }
  }
  return image;
}

TEST(PngTest, RoundTripsEveryPixelInBothEfforts) {
  testing::TempDir dir;
  Image image = Gradient(37, 21);  // odd sizes: no row padding may creep in
  for (PngEffort effort : {PngEffort::kFast, PngEffort::kSmall}) {
    std::string bytes = EncodePng(image, effort);
    ASSERT_GT(bytes.size(), 8u);
    EXPECT_EQ(bytes.substr(1, 3), "PNG");
    testing::WriteFile(dir.File("a.png"), bytes);
    Image back = ReadPng(dir.File("a.png"));
    EXPECT_EQ(back.width, 37);
    EXPECT_EQ(back.height, 21);
    EXPECT_EQ(back.rgb, image.rgb);
  }
}

TEST(PngTest, WritePngIsReadBack) {
  testing::TempDir dir;
  Image image = Gradient(8, 5);
  WritePng(image, dir.File("b.png"));
  EXPECT_EQ(ReadPng(dir.File("b.png")).rgb, image.rgb);
}

TEST(PngTest, RefusesAnImageWhoseBufferDoesNotMatchItsSize) {
  Image image = Gradient(4, 4);
  image.rgb.pop_back();
  EXPECT_THROW(EncodePng(image), ValueError);
  EXPECT_THROW(EncodePng(Image{}), ValueError);
}

TEST(PngTest, AnUnwritableFolderLeavesNothing) {
  testing::TempDir dir;
  std::filesystem::create_directory(dir.File("ro"));
  std::filesystem::permissions(
      dir.File("ro"), std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  if (access(dir.File("ro").c_str(), W_OK) == 0) GTEST_SKIP() << "running as root";
  EXPECT_THROW(WritePng(Gradient(2, 2), dir.File("ro/c.png")), IoError);
  EXPECT_TRUE(std::filesystem::is_empty(dir.File("ro")));
}

TEST(PngTest, ReadingSomethingElseSaysWhichFile) {
  testing::TempDir dir;
  testing::WriteFile(dir.File("not.png"), "hello");
  try {
    ReadPng(dir.File("not.png"));
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("not.png"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace plumb
