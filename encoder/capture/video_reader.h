// Decoding a video file frame by frame through the ffmpeg program (a child
// process writing raw RGB24 to a pipe), so any format ffmpeg reads works as a
// capture's frame source without linking libavcodec. A reader destroyed before
// the video's end ends its decoder at once.
#ifndef FVV_ENCODER_CAPTURE_VIDEO_READER_H_
#define FVV_ENCODER_CAPTURE_VIDEO_READER_H_

#include <memory>
#include <string>

#include "codec/base/status.h"
#include "encoder/io/child_process.h"
#include "encoder/io/image_io.h"

namespace fvv {

class VideoReader {
 public:
  // Starts decoding `path`, whose frames must be width x height.
  static StatusOr<std::unique_ptr<VideoReader>> Open(const std::string& path, uint32_t width,
                                                     uint32_t height, int channels = 3);
  ~VideoReader();
  VideoReader(const VideoReader&) = delete;
  VideoReader& operator=(const VideoReader&) = delete;

  // The next frame; an error past the last frame (naming the frame index).
  StatusOr<Image> Next();
  uint32_t next_index() const { return next_; }

 private:
  VideoReader() = default;
  std::string path_;
  uint32_t width_ = 0, height_ = 0, next_ = 0;
  int channels_ = 3;
  std::unique_ptr<ChildProcess> decoder_;
};

struct VideoInfo {
  uint32_t width = 0, height = 0;
  uint32_t frames = 0;    // 0 when the container does not say
  double frame_rate = 0;  // 0 when the container does not say
};
// The first video stream's size, frame count and rate (ffprobe).
StatusOr<VideoInfo> ProbeVideo(const std::string& path);

// Whether the ffmpeg and ffprobe executables are on PATH.
bool HaveFfmpeg();

}  // namespace fvv

#endif  // FVV_ENCODER_CAPTURE_VIDEO_READER_H_
