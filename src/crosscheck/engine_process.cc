// EngineProcess: the adapter as a child process, driven with poll() on its three streams.
//
// One thread does everything: while a request is written, the reply and the adapter's stderr
// are read in the same poll() loop, so neither side waits on a full pipe (the adapter writes its
// reply only after reading the whole request, but its log may fill stderr at any time). The
// adapter's stdin is a socket, as ffmpeg's is (src/io/video.cc): send() with MSG_NOSIGNAL fails
// with EPIPE when the adapter has gone, where a write to a pipe would raise SIGPIPE in a program
// that does not ignore it. The adapter runs in a process group of its own: Ctrl-C reaches plumb
// alone, which stops it, and killing the group ends whatever the adapter started.

#include "crosscheck/engine_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>

#include "core/child_process.h"
#include "core/demand.h"
#include "plumb/error.h"

namespace plumb::internal {
namespace {

constexpr std::size_t kTailLines = 40;        // stderr lines kept
constexpr std::size_t kQuotedLines = 12;      // of them, quoted in an error's message
constexpr std::size_t kTailLineChars = 1000;  // characters kept of each
constexpr std::size_t kMaxLine = 64u << 20;   // a reply's JSON line, at most
constexpr double kMaxPayloadBytes = 16.0 * (1u << 30);
constexpr int kStopPollMs = 50;  // how often a Request looks at its StopToken
constexpr std::size_t kReadChunk = 1u << 20;

bool LittleEndianHost() {
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

void SwapBytes(std::vector<double>& values) {
  for (double& v : values) {
    unsigned char b[sizeof(double)];
    std::memcpy(b, &v, sizeof b);
    std::reverse(b, b + sizeof b);
    std::memcpy(&v, b, sizeof b);
  }
}

// The number of values an array of `shape` holds, or -1 when an extent is negative or the
// count is beyond any payload.
double ValueCount(const std::vector<long>& shape) {
  double count = 1;
  for (long extent : shape) {
    if (extent < 0) return -1;
    count *= double(extent);
  }
  return count * sizeof(double) > kMaxPayloadBytes ? -1 : count;
}

std::string ShapeText(const std::vector<long>& shape) {
  std::string text = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    text += (i ? ", " : "") + std::to_string(shape[i]);
  }
  return text + "]";
}

std::string Shortened(const std::string& text, std::size_t most) {
  return text.size() <= most ? text : text.substr(0, most) + "...";
}

}  // namespace

const EngineArray* EngineReply::Find(std::string_view name) const {
  for (const EngineArray& array : arrays) {
    if (array.name == name) return &array;
  }
  return nullptr;
}

const EngineArray& EngineReply::Get(std::string_view name) const {
  if (const EngineArray* array = Find(name)) return *array;
  std::string listed;
  for (const EngineArray& array : arrays) listed += (listed.empty() ? "" : ", ") + array.name;
  throw EngineError("the engine adapter's reply has no array '" + std::string(name) + "' (it has " +
                    (listed.empty() ? "none" : listed) +
                    "): the adapter and plumb come from different releases, or the adapter has "
                    "a bug");
}

// ---- what goes out: the request's line and its arrays' bytes, written as poll() allows ----

struct EngineProcess::Outgoing {
  std::string line;
  std::vector<std::vector<double>> swapped;  // the arrays in little-endian order (big-endian host)
  std::vector<std::pair<const char*, std::size_t>> parts;
  std::size_t part = 0;    // the part being written
  std::size_t offset = 0;  // bytes of it written

  Outgoing(const nlohmann::json& header, const std::vector<EngineArray>& arrays) {
    PLUMB_DEMAND(header.is_object());
    nlohmann::json message = header;
    nlohmann::json listed = nlohmann::json::array();
    for (const EngineArray& array : arrays) {
      PLUMB_DEMAND(ValueCount(array.shape) == double(array.values.size()));
      listed.push_back({{"name", array.name}, {"shape", array.shape}});
    }
    if (arrays.empty()) {
      message.erase("arrays");
    } else {
      message["arrays"] = std::move(listed);
    }
    line = message.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    parts.emplace_back(line.data(), line.size());
    bool swap = !LittleEndianHost();
    for (const EngineArray& array : arrays) {
      const std::vector<double>* values = &array.values;
      if (swap) {
        swapped.push_back(array.values);
        SwapBytes(swapped.back());
        values = &swapped.back();
      }
      if (!values->empty()) {
        parts.emplace_back(reinterpret_cast<const char*>(values->data()),
                           values->size() * sizeof(double));
      }
    }
  }
  bool done() const { return part == parts.size(); }
};

// ---- what comes in: the reply's line, then its arrays, checked against the line ----------

class EngineProcess::ReplyReader {
 public:
  // Takes the next bytes of the adapter's stdout. Returns false when they break the framing
  // (broken() says how).
  bool Feed(const char* data, std::size_t size) {
    while (size > 0) {
      if (!have_header_) {
        const void* found = std::memchr(data, '\n', size);
        std::size_t take = found ? std::size_t(static_cast<const char*>(found) - data) : size;
        line_.append(data, take);
        if (line_.size() > kMaxLine) return Break("a reply line of more than 64 MB");
        take += found ? 1 : 0;
        data += take;
        size -= take;
        if (found && !TakeHeader()) return false;
        continue;
      }
      if (array_ == arrays.size()) return Break("more bytes than its reply's arrays hold");
      EngineArray& array = arrays[array_];
      std::size_t want = array.values.size() * sizeof(double) - offset_;
      std::size_t take = std::min(want, size);
      std::memcpy(reinterpret_cast<char*>(array.values.data()) + offset_, data, take);
      offset_ += take;
      data += take;
      size -= take;
      SkipFilled();
    }
    return true;
  }
  bool complete() const { return have_header_ && array_ == arrays.size(); }
  const std::string& broken() const { return broken_; }

  nlohmann::json header;
  std::vector<EngineArray> arrays;

 private:
  bool Break(const std::string& why) {
    broken_ = why;
    return false;
  }
  void SkipFilled() {
    while (array_ < arrays.size() && offset_ == arrays[array_].values.size() * sizeof(double)) {
      if (!LittleEndianHost()) SwapBytes(arrays[array_].values);
      ++array_;
      offset_ = 0;
    }
  }
  bool TakeHeader() {
    header = nlohmann::json::parse(line_, nullptr, false);
    if (header.is_discarded() || !header.is_object()) {
      return Break("a reply line that is not a JSON object: '" + Shortened(line_, 200) + "'");
    }
    if (!header.contains("ok") || !header["ok"].is_boolean()) {
      return Break("a reply without \"ok\": true or false: '" + Shortened(line_, 200) + "'");
    }
    have_header_ = true;
    line_.clear();
    if (header.contains("arrays") && !TakeArrays(header["arrays"])) return false;
    SkipFilled();
    return true;
  }
  bool TakeArrays(const nlohmann::json& listed) {
    if (!listed.is_array()) return Break("a reply whose \"arrays\" is not a list");
    double total = 0;
    for (const nlohmann::json& entry : listed) {
      EngineArray array;
      if (!entry.is_object() || !entry.contains("name") || !entry["name"].is_string() ||
          entry["name"].get<std::string>().empty()) {
        return Break("a reply array without a name: " + Shortened(entry.dump(), 200));
      }
      array.name = entry["name"].get<std::string>();
      const nlohmann::json* shape = entry.contains("shape") ? &entry["shape"] : nullptr;
      if (shape == nullptr || !shape->is_array()) {
        return Break("the array '" + array.name + "' without a shape");
      }
      for (const nlohmann::json& extent : *shape) {
        if (!extent.is_number_integer() || extent.get<long long>() < 0 ||
            extent.get<long long>() > std::numeric_limits<long>::max()) {
          return Break("the array '" + array.name + "' with the shape " + shape->dump());
        }
        array.shape.push_back(extent.get<long>());
      }
      double count = ValueCount(array.shape);
      total += count * sizeof(double);
      if (count < 0 || total > kMaxPayloadBytes) {
        return Break("arrays of more than 16 GiB (the array '" + array.name + "' of shape " +
                     ShapeText(array.shape) + ")");
      }
      for (const EngineArray& earlier : arrays) {
        if (earlier.name == array.name) return Break("the array '" + array.name + "' twice");
      }
      array.values.resize(std::size_t(count));
      arrays.push_back(std::move(array));
    }
    return true;
  }

  std::string line_;
  bool have_header_ = false;
  std::size_t array_ = 0;   // the array being filled
  std::size_t offset_ = 0;  // its bytes filled
  std::string broken_;
};

// ---- the process ----------------------------------------------------------------------------

EngineProcess::EngineProcess(std::vector<std::string> argv,
                             std::vector<std::pair<std::string, std::string>> extra_env)
    : stderr_tail_(kTailLines, kTailLineChars) {
  PLUMB_DEMAND(!argv.empty());
  program_ = argv[0];
  for (const std::string& arg : argv) command_ += (command_.empty() ? "" : " ") + arg;
  int in[2] = {-1, -1}, out[2] = {-1, -1}, err[2] = {-1, -1};
  auto close_all = [&] {
    for (int* fd : {&in[0], &in[1], &out[0], &out[1], &err[0], &err[1]}) CloseFd(*fd);
  };
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, in) != 0 || pipe2(out, O_CLOEXEC) != 0 ||
      pipe2(err, O_CLOEXEC) != 0 || (in[1] = AboveStdio(in[1])) < 0 ||
      (out[1] = AboveStdio(out[1])) < 0 || (err[1] = AboveStdio(err[1])) < 0) {
    std::string why = std::strerror(errno);
    close_all();
    throw EngineError("cannot make the pipes to the engine adapter '" + program_ + "': " + why);
  }
  std::vector<std::string> env = ChildEnvironment(extra_env);
  const int child_fds[3] = {in[1], out[1], err[1]};
  if (int error = SpawnChild(program_, argv, env, child_fds, "", &pid_); error != 0) {
    pid_ = -1;
    close_all();
    throw EngineError("cannot start the engine adapter '" + program_ +
                      "': " + std::strerror(error));
  }
  CloseFd(in[1]);
  CloseFd(out[1]);
  CloseFd(err[1]);
  in_fd_ = in[0];
  out_fd_ = out[0];
  err_fd_ = err[0];
  for (int fd : {in_fd_, out_fd_, err_fd_}) fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
#ifdef F_SETPIPE_SZ
  fcntl(out_fd_, F_SETPIPE_SZ, 1 << 20);  // fewer wake-ups for large replies; best effort
#endif
  int buffer = 1 << 20;
  setsockopt(in_fd_, SOL_SOCKET, SO_SNDBUF, &buffer, sizeof buffer);
}

EngineProcess::~EngineProcess() {
  try {
    if (pid_ > 0 && in_fd_ >= 0) {
      // quit, and the end of its input: either makes a working adapter exit 0
      static const char kQuit[] = "{\"op\":\"quit\"}\n";
      while (send(in_fd_, kQuit, sizeof kQuit - 1, MSG_NOSIGNAL | MSG_DONTWAIT) < 0 &&
             errno == EINTR) {
      }
      CloseFd(in_fd_);
      WaitForExit(2.0);
    }
  } catch (...) {
  }
  Kill();
}

std::string EngineProcess::StderrTail() const {
  std::string text;
  for (const std::string& line : stderr_tail_.lines()) text += line + "\n";
  if (!stderr_tail_.partial().empty()) text += stderr_tail_.partial() + "\n";
  return text;
}

void EngineProcess::ReadStderr() {
  ReadAvailable(err_fd_,
                [this](const char* data, std::size_t size) { stderr_tail_.Add(data, size); });
}

std::string EngineProcess::PumpOnce(Outgoing* out, ReplyReader* reader, int wait_ms) {
  pollfd fds[3];
  int count = 0, in_slot = -1, out_slot = -1, err_slot = -1;
  if (out != nullptr && !out->done() && in_fd_ >= 0) {
    in_slot = count;
    fds[count++] = {in_fd_, POLLOUT, 0};
  }
  if (out_fd_ >= 0) {
    out_slot = count;
    fds[count++] = {out_fd_, POLLIN, 0};
  }
  if (err_fd_ >= 0) {
    err_slot = count;
    fds[count++] = {err_fd_, POLLIN, 0};
  }
  if (poll(fds, nfds_t(count), wait_ms) < 0) {
    return errno == EINTR ? "" : std::string("poll() failed: ") + std::strerror(errno);
  }
  if (err_slot >= 0 && fds[err_slot].revents != 0) ReadStderr();
  if (in_slot >= 0 && fds[in_slot].revents != 0) {
    while (!out->done()) {
      auto [data, size] = out->parts[out->part];
      ssize_t sent =
          send(in_fd_, data + out->offset, size - out->offset, MSG_NOSIGNAL | MSG_DONTWAIT);
      if (sent < 0 && errno == EINTR) continue;
      if (sent < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
      if (sent < 0) {
        return errno == EPIPE || errno == ECONNRESET
                   ? "stopped reading its input"
                   : std::string("could not be written to: ") + std::strerror(errno);
      }
      out->offset += std::size_t(sent);
      if (out->offset == size) {
        ++out->part;
        out->offset = 0;
      }
    }
  }
  if (out_slot >= 0 && fds[out_slot].revents != 0) {
    if (read_buffer_.size() < kReadChunk) read_buffer_.resize(kReadChunk);
    ssize_t got = read(out_fd_, read_buffer_.data(), read_buffer_.size());
    if (got < 0 && (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK)) return "";
    if (got <= 0) {
      CloseFd(out_fd_);
      return got == 0 ? "closed its output"
                      : std::string("could not be read from: ") + std::strerror(errno);
    }
    if (reader != nullptr && !reader->Feed(read_buffer_.data(), std::size_t(got))) {
      return "broke the protocol";  // the reader says how
    }
  }
  return "";
}

bool EngineProcess::WaitForExit(double seconds) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
  while (pid_ > 0) {
    pid_t done = waitpid(pid_, &status_, WNOHANG);
    if (done == pid_ || (done < 0 && errno == ECHILD)) {
      status_known_ = done == pid_;
      pid_ = -1;
      return true;
    }
    if (Clock::now() >= deadline) return false;
    PumpOnce(nullptr, nullptr, 10);
  }
  return true;
}

void EngineProcess::Kill() {
  if (pid_ > 0) {
    kill(-pid_, SIGKILL);  // its process group: the adapter and whatever it started
    kill(pid_, SIGKILL);
    killed_ = true;
    pid_t done;
    while ((done = waitpid(pid_, &status_, 0)) < 0 && errno == EINTR) {
    }
    status_known_ = done == pid_;
    pid_ = -1;
  }
  try {
    ReadStderr();  // what it wrote before it ended
  } catch (...) {
  }
  CloseFd(in_fd_);
  CloseFd(out_fd_);
  CloseFd(err_fd_);
}

std::string EngineProcess::HowItEnded() const {
  if (!status_known_) return "its exit status is unknown (another part of the program reaped it)";
  return WaitStatusText(status_, killed_);
}

void EngineProcess::Fail(const std::string& what, double grace_s) {
  if (grace_s > 0) WaitForExit(grace_s);  // it may be on its way out: let it end, and say how
  Kill();
  std::string quoted;
  const std::deque<std::string>& lines = stderr_tail_.lines();
  std::size_t first = lines.size() > kQuotedLines ? lines.size() - kQuotedLines : 0;
  for (std::size_t i = first; i < lines.size(); ++i) quoted += "\n  " + lines[i];
  if (!stderr_tail_.partial().empty()) quoted += "\n  " + stderr_tail_.partial();
  failure_ =
      "the engine adapter (" + command_ + ") " + what + "; " + HowItEnded() + ". " +
      (quoted.empty() ? "It wrote nothing on stderr." : "Its last lines on stderr:" + quoted);
  throw EngineError(failure_);
}

EngineReply EngineProcess::Request(const nlohmann::json& header,
                                   const std::vector<EngineArray>& arrays, double timeout_s,
                                   const StopToken& stop) {
  if (!failure_.empty()) throw EngineError("the engine adapter is gone: " + failure_);
  PLUMB_DEMAND(pid_ > 0);
  std::string op = header.is_object() && header.contains("op") && header["op"].is_string()
                       ? header["op"].get<std::string>()
                       : "?";
  Outgoing out(header, arrays);
  ReplyReader reader;
  const bool timed = timeout_s > 0 && std::isfinite(timeout_s);
  const auto deadline = Clock::now() + std::chrono::duration<double>(timed ? timeout_s : 0);
  while (!reader.complete()) {
    if (stop.stop_requested()) {
      Kill();
      failure_ = "it was stopped while it ran '" + op + "'";
      throw Interrupted("stopped while the engine adapter ran '" + op + "'");
    }
    int wait_ms = kStopPollMs;
    if (timed) {
      auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      if (left.count() <= 0) {
        char limit[32];
        std::snprintf(limit, sizeof limit, "%g", timeout_s);
        Fail("did not reply to '" + op + "' within " + limit + " s", 0);
      }
      wait_ms = int(std::min<long long>(wait_ms, left.count() + 1));
    }
    std::string problem = PumpOnce(&out, &reader, wait_ms);
    if (!reader.broken().empty()) {  // it is still running
      Fail("broke the protocol in its reply to '" + op + "': it sent " + reader.broken(), 0);
    }
    if (!problem.empty()) Fail(problem + " during '" + op + "'", 2.0);  // it may be exiting
    if (reader.complete() && !out.done()) {
      Fail("replied to '" + op + "' before it had read the whole request", 0);
    }
  }
  nlohmann::json& reply = reader.header;
  if (!reply["ok"].get<bool>()) {
    std::string error = reply.contains("error") && reply["error"].is_string()
                            ? reply["error"].get<std::string>()
                            : "(none named)";
    std::string message = reply.contains("message") && reply["message"].is_string()
                              ? reply["message"].get<std::string>()
                              : reply.dump();
    if (error == "refused") throw EngineRefused(message);
    throw EngineError("the engine adapter answered '" + op + "' with the error '" + error +
                      "': " + message);
  }
  return EngineReply{std::move(reply), std::move(reader.arrays)};
}

}  // namespace plumb::internal
