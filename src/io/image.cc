// PNG through libpng: encoding to memory (reports inline pictures) and reading back (tests).

#include "plumb/image.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <memory>
#include <string>

#include "io/atomic_file.h"
#include "plumb/error.h"

namespace plumb {
using internal::AtomicFile;

namespace {

void AppendBytes(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  out->append(reinterpret_cast<const char*>(data), length);
}

void NoFlush(png_structp) {}

// libpng reports errors by longjmp; the message is kept for the exception thrown after it.
void KeepError(png_structp png, png_const_charp message) {
  auto* text = static_cast<std::string*>(png_get_error_ptr(png));
  if (text != nullptr) *text = message;
  png_longjmp(png, 1);
}

void IgnoreWarning(png_structp, png_const_charp) {}

}  // namespace

std::string EncodePng(const Image& image, PngEffort effort) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != std::size_t(image.width) * image.height * 3) {
    throw ValueError("cannot encode a PNG of " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + " pixels from " +
                     std::to_string(image.rgb.size()) + " bytes");
  }
  std::string out;
  std::string error;
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, KeepError, IgnoreWarning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    throw std::bad_alloc();
  }
  // nothing with a destructor lives between setjmp and the end of the encoding
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw IoError("libpng could not encode the picture: " + error);
  }
  png_set_write_fn(png, &out, AppendBytes, NoFlush);
  png_set_compression_level(png, effort == PngEffort::kFast ? 1 : 6);
  if (effort == PngEffort::kFast) png_set_filter(png, 0, PNG_FILTER_SUB);
  png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y) {
    png_write_row(png, const_cast<png_bytep>(image.at(0, y)));
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

void WritePng(const Image& image, const std::string& path) {
  std::string bytes = EncodePng(image);
  AtomicFile file(path);
  if (std::fwrite(bytes.data(), 1, bytes.size(), file.stream()) != bytes.size()) {
    throw IoError("cannot write '" + path + "'");
  }
  file.Commit();
}

Image ReadPng(const std::string& path) {
  png_image reader{};
  reader.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&reader, path.c_str())) {
    throw IoError("cannot read '" + path + "' as a PNG: " + reader.message);
  }
  reader.format = PNG_FORMAT_RGB;
  Image image;
  image.width = int(reader.width);
  image.height = int(reader.height);
  image.rgb.resize(PNG_IMAGE_SIZE(reader));
  if (!png_image_finish_read(&reader, nullptr, image.rgb.data(), 0, nullptr)) {
    std::string message = reader.message;
    png_image_free(&reader);
    throw IoError("cannot read '" + path + "' as a PNG: " + message);
  }
  return image;
}

}  // namespace plumb
