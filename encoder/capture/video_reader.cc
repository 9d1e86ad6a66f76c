#include "encoder/capture/video_reader.h"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace fvv {

bool HaveFfmpeg() { return HaveProgram("ffmpeg") && HaveProgram("ffprobe"); }

StatusOr<VideoInfo> ProbeVideo(const std::string& path) {
  if (access(path.c_str(), R_OK) != 0) {
    return IoError("video " + path + ": cannot read (" + std::strerror(errno) + ")");
  }
  if (!HaveFfmpeg()) {
    return IoError("video " + path +
                   ": decoding videos needs the ffmpeg and ffprobe programs (apt-get install "
                   "ffmpeg)");
  }
  int code = 0;
  StatusOr<std::string> probe = RunForOutput(
      {"ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
       "stream=width,height,nb_frames,r_frame_rate", "-of", "default=noprint_wrappers=1", path},
      &code);
  if (!probe.ok()) {
    return Status(probe.status().code(), "video " + path + ": " + probe.status().message());
  }
  VideoInfo info;
  size_t start = 0;
  const std::string& text = *probe;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    const size_t eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    if (key == "width")
      info.width = static_cast<uint32_t>(std::strtoul(value.c_str(), nullptr, 10));
    if (key == "height") {
      info.height = static_cast<uint32_t>(std::strtoul(value.c_str(), nullptr, 10));
    }
    if (key == "nb_frames") {
      info.frames = static_cast<uint32_t>(std::strtoul(value.c_str(), nullptr, 10));
    }
    if (key == "r_frame_rate") {
      const size_t slash = value.find('/');
      const double num = std::strtod(value.c_str(), nullptr);
      const double den =
          slash == std::string::npos ? 1 : std::strtod(value.c_str() + slash + 1, nullptr);
      if (num > 0 && den > 0) info.frame_rate = num / den;
    }
  }
  if (code != 0 || info.width == 0 || info.height == 0) {
    return Corrupt("video " + path + ": ffprobe finds no video stream in it");
  }
  return info;
}

StatusOr<std::unique_ptr<VideoReader>> VideoReader::Open(const std::string& path, uint32_t width,
                                                         uint32_t height, int channels) {
  // Probe the size first: a video whose size differs from the calibration is an
  // error to report, not something to rescale silently.
  StatusOr<VideoInfo> info = ProbeVideo(path);
  if (!info.ok()) return info.status();
  if (info->width != width || info->height != height) {
    return Corrupt("video " + path + ": frames are " + std::to_string(info->width) + "x" +
                   std::to_string(info->height) + ", the calibration says " +
                   std::to_string(width) + "x" + std::to_string(height));
  }
  StatusOr<std::unique_ptr<ChildProcess>> decoder = ChildProcess::Start(
      {"ffmpeg", "-v", "error", "-nostdin", "-i", path, "-f", "rawvideo", "-pix_fmt",
       channels == 1 ? "gray" : "rgb24", "-vsync", "passthrough", "-"},
      ChildProcess::Pipe::kReadStdout);
  if (!decoder.ok()) {
    return Status(decoder.status().code(), "video " + path + ": " + decoder.status().message());
  }
  std::unique_ptr<VideoReader> r(new VideoReader());
  r->path_ = path;
  r->width_ = width;
  r->height_ = height;
  r->channels_ = channels;
  r->decoder_ = std::move(decoder).value();
  return r;
}

// The decoder is killed, not waited for: stopped before the video's end, it
// may be blocked writing a frame nobody will read.
VideoReader::~VideoReader() = default;

StatusOr<Image> VideoReader::Next() {
  Image image;
  image.width = width_;
  image.height = height_;
  image.channels = channels_;
  image.pixels.resize(size_t{width_} * height_ * channels_);
  size_t got = 0;
  while (got < image.pixels.size()) {
    const ssize_t n = decoder_->Read(image.pixels.data() + got, image.pixels.size() - got);
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
