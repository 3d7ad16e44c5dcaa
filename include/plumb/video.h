// MP4 video (H.264, yuv420p) made by piping raw frames to Debian's ffmpeg program.
//
// The video is written to a hidden temporary file beside the target and renamed into place by
// Finish, so a half-made video never appears under the target's name; destroying a writer
// that was not finished kills ffmpeg and removes the temporary file. What a killed plumb
// leaves (".<name>.tmp-XXXXXX.mp4" and ".log") the next writer of the same target removes.
//
// Example:
//   plumb::VideoWriter video("swing.mp4", 640, 480, 30);
//   for (...) video.Add(renderer.Render(data));
//   video.Finish();
//
// Thread-safety: use a VideoWriter from one thread at a time; different writers (each with its
// own ffmpeg process) may run on different threads, even for one target (each has its own
// locked temporary; the last Finish wins).

#ifndef PLUMB_INCLUDE_PLUMB_VIDEO_H_
#define PLUMB_INCLUDE_PLUMB_VIDEO_H_

#include <sys/types.h>

#include <string>

#include "plumb/image.h"

namespace plumb {

class VideoWriter {
 public:
  // Starts ffmpeg (found on PATH, or at $PLUMB_FFMPEG) writing `path` at `fps` frames per
  // second. Odd sizes are padded by one pixel (yuv420p needs even ones).
  // @throws UnavailableError when ffmpeg cannot be found or started; ValueError for a bad
  //         size or rate; IoError when the folder of `path` cannot be written.
  VideoWriter(std::string path, int width, int height, double fps);
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;
  ~VideoWriter();

  // Sends one frame (its size must be the writer's). @throws IoError when ffmpeg has
  // stopped, with what it said, or the writer is already finished (Finish called, or an Add
  // failed); ValueError for a frame of another size.
  void Add(const Image& frame);
  // Closes the stream, waits for ffmpeg and renames the video into place.
  // @throws IoError with ffmpeg's message when it failed (nothing is left behind then), or when
  // the writer is already finished.
  void Finish();

  int frames() const { return frames_; }

 private:
  void Abandon();
  std::string path_;
  std::string temp_path_;
  std::string log_path_;  // ffmpeg's stderr
  int temp_fd_ = -1;      // holds the temporary's lock until the rename
  int width_, height_;
  int fd_ = -1;  // our end of the socket ffmpeg reads its stdin from
  pid_t pid_ = -1;
  int frames_ = 0;
};

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_VIDEO_H_
