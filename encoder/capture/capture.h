// The capture directory: what "a finished capture" is (docs/capture-format.md).
// `capture.json` holds the calibrated cameras, frame rate and count, the world
// up axis, and per camera where its frames come from (an image sequence or a
// video file), plus optional background plates and silhouettes. The loader
// checks everything it can without decoding images and names the camera, frame
// and field of every problem.
#ifndef FVV_ENCODER_CAPTURE_CAPTURE_H_
#define FVV_ENCODER_CAPTURE_CAPTURE_H_

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"
#include "encoder/io/image_io.h"

namespace fvv {

// Where a camera's frames (or silhouettes) come from.
struct FrameSource {
  enum class Kind { kImages, kVideo } kind = Kind::kImages;
  // kImages: a printf-style pattern with one integer conversion (%d, %06d),
  // relative to the capture directory; frame f is file pattern % (first + f).
  // kVideo: a video file, decoded with ffmpeg; frame f is its (first + f)-th
  // frame (counting from 0: `first` frames are skipped, a camera that started
  // recording early; fvv capture sync measures it).
  std::string path;
  int64_t first = 0;
};

struct CaptureCamera {
  Camera calibration;
  FrameSource frames;
  std::optional<std::string> background;   // a plate of the empty studio
  std::optional<FrameSource> silhouettes;  // grey images, non-zero = actor
  // What the camera's R, G and B values are multiplied by to read the rig's
  // common colour (fvv capture calibrate-colour; colour_gain.h).
  std::array<double, 3> colour_gain{1.0, 1.0, 1.0};
};

struct Capture {
  std::string directory;  // where capture.json lives; paths are relative to it
  double frame_rate = 25;
  uint32_t frame_count = 0;
  // The world axis pointing up. fvv's world is y-up: ParseCapture turns the
  // cameras of a z-up capture into it and sets 'y' (remembering the original
  // axis below), so everything downstream sees one convention.
  char up_axis = 'y';
  char declared_up_axis = 'y';  // what capture.json said
  std::vector<CaptureCamera> cameras;
};

constexpr int kCaptureFormatVersion = 1;
constexpr uint32_t kMaxCaptureCameras = 256;
constexpr uint32_t kMaxCaptureFrames = 1000000;

// Parses and validates capture.json text (`directory` resolves relative paths).
// A z-up capture's cameras come back in fvv's y-up world (X_y = (x, z, -y)).
StatusOr<Capture> ParseCapture(const std::string& json_text, const std::string& directory);
// Loads DIR/capture.json (or a capture.json path).
StatusOr<Capture> LoadCapture(const std::string& path);
// capture.json text for a capture (paths stay relative).
std::string CaptureToJson(const Capture& capture);
// Writes DIR/capture.json atomically.
Status SaveCapture(const Capture& capture);

// Whether every source the capture reads (frames and silhouettes) holds
// `frames`: an image sequence the files of those frames, a video the frames up
// to the last as far as its container says. A missing file or a short video is
// refused before any work, naming the camera and the frame it lacks. Videos
// whose container gives no frame count pass (their reader fails at the frame).
Status CheckFramesPresent(const Capture& capture, const std::vector<uint32_t>& frames);

// The file an image-sequence source names for frame `frame`.
std::string FramePath(const Capture& capture, const FrameSource& source, uint32_t frame);

// Reads frames and silhouettes, checking sizes against the calibration. Keeps
// one ffmpeg decoder open per video camera, so reading frames in order is
// cheap; seeking backwards restarts the decoder.
class CaptureReader {
 public:
  explicit CaptureReader(Capture capture);
  ~CaptureReader();
  const Capture& capture() const { return capture_; }

  StatusOr<Image> ReadFrame(uint32_t camera, uint32_t frame);       // RGB
  StatusOr<Image> ReadBackground(uint32_t camera);                  // RGB
  StatusOr<Image> ReadSilhouette(uint32_t camera, uint32_t frame);  // grey, 0 or 255
  bool HasSilhouettes() const;
  bool HasBackgrounds() const;
  // Checks that every image file exists (videos: that the file exists and
  // ffprobe-free: the first frame decodes with the right size).
  Status CheckFiles();

 private:
  struct Video;
  StatusOr<Image> Read(uint32_t camera, const FrameSource& source, uint32_t frame, int channels,
                       const char* what);
  Capture capture_;
  std::vector<std::unique_ptr<Video>> videos_;
};

}  // namespace fvv

#endif  // FVV_ENCODER_CAPTURE_CAPTURE_H_
