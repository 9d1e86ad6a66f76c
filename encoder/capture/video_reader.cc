#include "encoder/capture/video_reader.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>

extern char** environ;

namespace fvv {

bool HaveFfmpeg() {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string dirs(path);
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = dirs.find(':', start);
    const std::string dir =
        dirs.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!dir.empty() && access((dir + "/ffmpeg").c_str(), X_OK) == 0) return true;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return false;
}

namespace {

// Starts `args` with stdout on a pipe; returns the read end.
Status Spawn(std::vector<std::string> args, pid_t* pid, int* read_fd) {
  int pipe_fd[2];
  if (pipe(pipe_fd) != 0) return IoError("pipe failed: " + std::string(std::strerror(errno)));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fd[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipe_fd[0]);
  posix_spawn_file_actions_addclose(&actions, pipe_fd[1]);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const int rc = posix_spawnp(pid, args[0].c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(pipe_fd[1]);
  if (rc != 0) {
    close(pipe_fd[0]);
    return IoError("cannot start " + args[0] + " (" + std::strerror(rc) + ")");
  }
  *read_fd = pipe_fd[0];
  return Status::Ok();
}

// The whole stdout of a short-lived command, and its exit status.
StatusOr<std::string> RunForOutput(std::vector<std::string> args, int* exit_code) {
  pid_t pid = -1;
  int fd = -1;
  Status s = Spawn(std::move(args), &pid, &fd);
  if (!s.ok()) return s;
  std::string out;
  char buffer[4096];
  for (;;) {
    const ssize_t n = read(fd, buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    if (out.size() < (1u << 20)) out.append(buffer, static_cast<size_t>(n));
  }
  close(fd);
  int status = 0;
  waitpid(pid, &status, 0);
  *exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

}  // namespace

StatusOr<std::unique_ptr<VideoReader>> VideoReader::Open(const std::string& path, uint32_t width,
                                                         uint32_t height, int channels) {
  if (access(path.c_str(), R_OK) != 0) {
    return IoError("video " + path + ": cannot read (" + std::strerror(errno) + ")");
  }
  if (!HaveFfmpeg()) {
    return IoError("video " + path +
                   ": decoding videos needs the ffmpeg program (apt-get install ffmpeg)");
  }
  // Probe the size first: a video whose size differs from the calibration is an
  // error to report, not something to rescale silently.
  int code = 0;
  StatusOr<std::string> probe =
      RunForOutput({"ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
                    "stream=width,height", "-of", "csv=p=0:s=x", path},
                   &code);
  if (!probe.ok())
    return Status(probe.status().code(), "video " + path + ": " + probe.status().message());
  std::string dims = *probe;
  while (!dims.empty() && (dims.back() == '\n' || dims.back() == '\r')) dims.pop_back();
  if (code != 0 || dims.empty()) {
    return Corrupt("video " + path + ": ffprobe finds no video stream in it");
  }
  const std::string want = std::to_string(width) + "x" + std::to_string(height);
  if (dims != want) {
    return Corrupt("video " + path + ": frames are " + dims + ", the calibration says " + want);
  }
  std::unique_ptr<VideoReader> r(new VideoReader());
  pid_t pid = -1;
  int fd = -1;
  Status s = Spawn({"ffmpeg", "-v", "error", "-nostdin", "-i", path, "-f", "rawvideo", "-pix_fmt",
                    channels == 1 ? "gray" : "rgb24", "-vsync", "passthrough", "-"},
                   &pid, &fd);
  if (!s.ok()) return Status(s.code(), "video " + path + ": " + s.message());
  r->path_ = path;
  r->width_ = width;
  r->height_ = height;
  r->channels_ = channels;
  r->fd_ = fd;
  r->pid_ = pid;
  return r;
}

VideoReader::~VideoReader() {
  if (fd_ >= 0) close(fd_);
  if (pid_ > 0) {
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
}

StatusOr<Image> VideoReader::Next() {
  Image image;
  image.width = width_;
  image.height = height_;
  image.channels = channels_;
  image.pixels.resize(size_t{width_} * height_ * channels_);
  size_t got = 0;
  while (got < image.pixels.size()) {
    const ssize_t n = read(fd_, image.pixels.data() + got, image.pixels.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got += static_cast<size_t>(n);
  }
  if (got != image.pixels.size()) {
    const std::string frame = std::to_string(next_);
    if (got == 0) {
      return IoError("video " + path_ + ": no frame " + frame +
                     " (the video ends earlier, or ffmpeg cannot decode it)");
    }
    return Corrupt("video " + path_ + ": frame " + frame + " ends early (truncated stream)");
  }
  ++next_;
  return image;
}

}  // namespace fvv
