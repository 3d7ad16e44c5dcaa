// VideoWriter: raw RGB frames over a socket to ffmpeg's stdin, H.264 in an MP4 out.
//
// A socket rather than a pipe so a write to an ffmpeg that died fails with EPIPE
// (MSG_NOSIGNAL) instead of raising SIGPIPE in a program that did not ignore it.

#include "plumb/video.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "io/temp_file.h"
#include "plumb/error.h"

extern char** environ;

namespace plumb {
using internal::CreateLockedTemporary;
using internal::RemoveStaleTemporaries;

namespace {

// Why `path` is not a program plumb can start ("" when it is one): a folder passes access(X_OK).
std::string NotAProgram(const std::string& path) {
  struct stat st;
  if (stat(path.c_str(), &st) != 0) return std::strerror(errno);
  if (S_ISDIR(st.st_mode)) return "it is a folder";
  if (!S_ISREG(st.st_mode)) return "it is not a regular file";
  if (access(path.c_str(), X_OK) != 0) return "it is not executable";
  return "";
}

// $PLUMB_FFMPEG, else the first executable `ffmpeg` on PATH; "" when there is none.
// @throws UnavailableError naming PLUMB_FFMPEG when it is set to what is not a program.
std::string FindFfmpeg(const std::string& target) {
  if (const char* given = std::getenv("PLUMB_FFMPEG"); given != nullptr && *given != '\0') {
    if (std::string why = NotAProgram(given); !why.empty()) {
      throw UnavailableError("writing '" + target + "' needs the ffmpeg program, and PLUMB_FFMPEG='" +
                             given + "' is not one (" + why +
                             "): set PLUMB_FFMPEG to the path of ffmpeg, or unset it to use "
                             "the ffmpeg on PATH.");
    }
    return given;
  }
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    std::string candidate = (dir.empty() ? "." : dir) + "/ffmpeg";
    if (NotAProgram(candidate).empty()) return candidate;
  }
  return "";
}

// The last lines ffmpeg wrote on stderr (its reason for failing).
std::string Tail(const std::string& log_path) {
  std::ifstream in(log_path);
  std::string line, text;
  std::vector<std::string> lines;
  while (std::getline(in, line)) {
    if (!line.empty()) lines.push_back(line);
  }
  for (std::size_t i = lines.size() > 4 ? lines.size() - 4 : 0; i < lines.size(); ++i) {
    text += (text.empty() ? "" : " | ") + lines[i];
  }
  return text.empty() ? "(it printed nothing)" : text;
}

}  // namespace

VideoWriter::VideoWriter(std::string path, int width, int height, double fps)
    : path_(std::move(path)), width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width > 8192 || height > 8192) {
    throw ValueError("a video frame must be 1 to 8192 pixels a side, not " + std::to_string(width) +
                     "x" + std::to_string(height));
  }
  if (!(fps > 0) || !std::isfinite(fps) || fps > 1000) {
    throw ValueError("a video's frame rate must be above 0 and at most 1000 per second");
  }
  std::string ffmpeg = FindFfmpeg(path_);
  if (ffmpeg.empty()) {
    throw UnavailableError(
        "writing '" + path_ +
        "' needs the ffmpeg program, which is not on PATH. Install it "
        "(Debian: apt-get install ffmpeg; scripts/install-deps.sh does), set PLUMB_FFMPEG to "
        "its path, or write a PNG picture instead.");
  }
  // the video and ffmpeg's messages go to hidden temporary files beside the target, each
  // locked while its writer lives (ffmpeg inherits the log's lock), after removing those of
  // writers that were killed (temp_file.h)
  RemoveStaleTemporaries(path_);
  temp_fd_ = CreateLockedTemporary(path_, ".mp4", &temp_path_);
  fchmod(temp_fd_, 0644);  // as a file the user made (mkstemp makes it 0600)
  int log_fd = -1;
  try {
    log_fd = CreateLockedTemporary(path_, ".log", &log_path_);
  } catch (const IoError&) {
    Abandon();
    throw;
  }

  int sockets[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sockets) != 0) {
    ::close(log_fd);
    Abandon();
    throw IoError(std::string("cannot make a socket for ffmpeg: ") + std::strerror(errno));
  }
  char pad[] = "pad=ceil(iw/2)*2:ceil(ih/2)*2";
  std::string size = std::to_string(width) + "x" + std::to_string(height);
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.9g", fps);
  std::vector<std::string> args = {
      ffmpeg,     "-nostdin",  "-hide_banner", "-loglevel", "error", "-y",      "-f",
      "rawvideo", "-pix_fmt",  "rgb24",        "-s",        size,    "-r",      rate,
      "-i",       "pipe:0",    "-vf",          pad,         "-c:v",  "libx264", "-pix_fmt",
      "yuv420p",  "-movflags", "+faststart",   "-f",        "mp4",   temp_path_};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, sockets[1], 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, log_fd, 2);
  // -nostdin is about keyboard interaction; ffmpeg still reads the frames from pipe:0
  int spawn_error = posix_spawn(&pid_, ffmpeg.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(sockets[1]);
  ::close(log_fd);
  if (spawn_error != 0) {
    close(sockets[0]);
    pid_ = -1;
    Abandon();
    throw UnavailableError("cannot start '" + ffmpeg + "': " + std::strerror(spawn_error));
  }
  fd_ = sockets[0];
}

VideoWriter::~VideoWriter() { Abandon(); }

void VideoWriter::Abandon() {
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
  if (pid_ > 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
  if (!temp_path_.empty()) {
    std::remove(temp_path_.c_str());
    if (!log_path_.empty()) std::remove(log_path_.c_str());
    temp_path_.clear();
  }
  if (temp_fd_ >= 0) close(temp_fd_);
  temp_fd_ = -1;
}

void VideoWriter::Add(const Image& frame) {
  if (fd_ < 0) throw IoError("the video '" + path_ + "' is already finished");
  if (frame.width != width_ || frame.height != height_ ||
      frame.rgb.size() != std::size_t(width_) * height_ * 3) {
    throw ValueError("a frame of " + std::to_string(frame.width) + "x" +
                     std::to_string(frame.height) + " pixels does not fit the video '" + path_ +
                     "' of " + std::to_string(width_) + "x" + std::to_string(height_));
  }
  const std::uint8_t* data = frame.rgb.data();
  std::size_t left = frame.rgb.size();
  while (left > 0) {
    ssize_t sent = send(fd_, data, left, MSG_NOSIGNAL);
    if (sent < 0 && errno == EINTR) continue;
    if (sent <= 0) {
      std::string said = Tail(log_path_);
      Abandon();
      throw IoError("ffmpeg stopped while writing '" + path_ + "': " + said);
    }
    data += sent;
    left -= std::size_t(sent);
  }
  ++frames_;
}

void VideoWriter::Finish() {
  if (fd_ < 0) throw IoError("the video '" + path_ + "' is already finished");
  close(fd_);
  fd_ = -1;
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || frames_ == 0) {
    std::string said = frames_ == 0 ? "no frame was given" : Tail(log_path_);
    Abandon();
    throw IoError("ffmpeg could not write '" + path_ + "': " + said);
  }
  // on disk before it takes the target's name, as AtomicFile does
  if (fsync(temp_fd_) != 0 || std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
    std::string why = std::strerror(errno);
    Abandon();
    throw IoError("cannot move the video into place as '" + path_ + "': " + why);
  }
  std::remove(log_path_.c_str());
  temp_path_.clear();
  close(temp_fd_);
  temp_fd_ = -1;
}

}  // namespace plumb
