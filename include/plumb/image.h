// Pictures plumb makes: an RGB image in memory and its PNG encoding (libpng).
//
// Example:
//   plumb::Image image = renderer.Render(data);
//   plumb::WritePng(image, "pendulum.png");   // atomically: absent or complete
//
// Thread-safety: the functions keep no state (each call has libpng state of its own), so they
// may run at once from several threads; WritePng writes through AtomicFile (see atomic_file.h).

#ifndef PLUMB_INCLUDE_PLUMB_IMAGE_H_
#define PLUMB_INCLUDE_PLUMB_IMAGE_H_

#include <cstdint>
#include <string>
#include <vector>

namespace plumb {

// 8-bit RGB pixels, rows top-down (row 0 is the top of the picture), no padding.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // width * height * 3 bytes

  // The pixel at column x, row y (from the top): a pointer to its three bytes.
  const std::uint8_t* at(int x, int y) const { return &rgb[(std::size_t(y) * width + x) * 3]; }
};

// PNG compression effort: kFast for frames made many at a time (reports' animations), kSmall
// for single pictures.
enum class PngEffort { kFast, kSmall };

// The PNG file of `image` as bytes. @throws ValueError for an empty image or one whose
// pixel buffer does not match its size; IoError when libpng fails to encode it.
std::string EncodePng(const Image& image, PngEffort effort = PngEffort::kSmall);

// Writes `image` as a PNG file through AtomicFile (a partly written picture never appears).
// @throws IoError naming `path` when it cannot be written; ValueError as EncodePng.
void WritePng(const Image& image, const std::string& path);

// Reads a PNG file (8-bit RGB or RGBA; alpha is dropped), e.g. for tests that look at what
// was written. @throws IoError naming `path` when it is missing or not a PNG plumb can read.
Image ReadPng(const std::string& path);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_IMAGE_H_
