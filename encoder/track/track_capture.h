// The motion-capture front end on a whole capture directory: silhouettes
// (given, or by background subtraction against the plates or a temporal
// median), then initialisation and tracking frame by frame. What `fvv track`,
// the encoder and the tracking benchmark run.
#ifndef FVV_ENCODER_TRACK_TRACK_CAPTURE_H_
#define FVV_ENCODER_TRACK_TRACK_CAPTURE_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "encoder/capture/capture.h"
#include "encoder/track/camera_sync.h"
#include "encoder/track/person_observer.h"
#include "encoder/track/pose_smoothing.h"
#include "encoder/track/silhouette_shift.h"
#include "encoder/track/tracker.h"

namespace fvv {

class CaptureFrames;

struct TrackCaptureOptions {
  // The frames reported (fits, on_frame).
  uint32_t first = 0;
  uint32_t last = UINT32_MAX;  // clamped to the last frame
  // Frames tracked before `first` and after `last` but not reported, within
  // the take's bounds (clamped to the capture): a part of a take tracked on
  // its own (a shard) starts far enough ahead of its first frame for the fit
  // to settle where a run over the whole take would be, and smooths its last
  // frames with the frames after them.
  uint32_t warm_up = 0;
  uint32_t take_first = 0, take_last = UINT32_MAX;
  // Poses of the frames just before `first` (oldest first, two at least), from
  // another run (the part before a shard's): tracking goes on from them
  // instead of a first-frame search, and smoothing reads them; no warm-up
  // before `first`. Needs tracker.fixed_shape.
  std::vector<std::vector<double>> lead_in;
  // Instead of a range: these frames (ascending), each fitted from scratch
  // (initialisation, no smoothing). A take's shared pass fits frames spread
  // over it this way, with the shape fixed.
  std::vector<uint32_t> separate_frames;
  bool extract = false;  // background subtraction even when silhouettes are given
  // Silhouettes from the person network (encoder/track/person_observer.h):
  // kAuto where the capture has neither silhouettes nor plates and the models
  // load (else background subtraction, saying why through `progress`).
  enum class Persons { kAuto, kOff, kOn } persons = Persons::kAuto;
  std::string person_models;  // model directory; empty: DefaultModelDirectory()
  // The network's body keypoints place the body and hold the fit (with person
  // masks only); off: silhouettes alone.
  bool keypoints = true;
  TrackerOptions tracker;
  // Poses are smoothed over time before they are reported (on_frame and the
  // result), each frame once Radius() later frames are tracked. The fit
  // figures (IoU, XOR, flags) stay those of the frame's own fit.
  PoseSmoothing smoothing{1.0};
  // Every this many reported frames, each camera's fit is checked for a
  // shift common to the frames (TrackCaptureResult::camera_shifts): a
  // calibration's shift is the same in every frame, so a sample finds it.
  uint32_t shift_check_every = 5;
  // The first this many frames tracked (consecutive, with the person
  // network's keypoints) are checked for cameras out of step by up to
  // step_check_offset frames (TrackCaptureResult::steps): a take not brought
  // in step (fvv capture sync) fits worse in every frame. 0: no check. Rigs
  // fitted with more than 16 cameras are not checked (pairs at every shift).
  uint32_t step_check_frames = 30;
  int step_check_offset = 3;
  std::string save_silhouettes;  // directory for the silhouettes used (PNG), or empty
  std::string overlays;          // directory for fit overlays (PNG), or empty
  std::function<void(const std::string&)> progress;  // one line per frame
  // Called once the frames are open, before any is read: where the
  // silhouettes on_frame gets come from.
  std::function<void(const CaptureFrames&)> on_open;
  // Called after each frame's fit (smoothed: later by the smoothing's radius)
  // with that frame's images and silhouettes (the
  // encoder resamples textures here, so frames are read once). An error stops
  // tracking and is returned. The tracker gives the body shape and model.
  std::function<Status(uint32_t frame, const FrameFit& fit, const Tracker& tracker,
                       const std::vector<Image>& images, const std::vector<Image>& silhouettes)>
      on_frame;
};

struct TrackCaptureResult {
  Capture capture;
  uint32_t first = 0, last = 0;  // the frames reported (separate frames: the first and last)
  std::vector<uint32_t> frames;  // the frame of each fit
  uint32_t warm_up_frames = 0;   // tracked but not reported
  // The warm-up frames after `last` and their poses (smoothed): the next
  // shard reports them, and the join compares the two.
  std::vector<uint32_t> after_frames;
  std::vector<std::vector<double>> after_poses;
  bool given_silhouettes = false;
  std::string silhouette_source;  // CaptureFrames::silhouette_source()
  std::vector<FrameFit> fits;     // per reported frame
  BodyShape shape;
  BodyModel model;  // the generic body with the fitted shape
  double silhouette_seconds = 0, fit_seconds = 0;
  double first_fit_seconds = 0;  // of fit_seconds: the first frame's (initialisation)
  // Of silhouette_seconds: decoding the frames (person masks only) and the
  // person network.
  double decode_seconds = 0, person_seconds = 0;
  double callback_seconds = 0;  // in on_frame
  int flagged = 0;
  double mean_iou = 0;
  // Camera frames whose keypoints had left and right exchanged to agree with
  // the other cameras' (ExchangeMislabelledSides), warm-up included.
  uint32_t side_exchanges = 0;
  // Per camera: the one image shift that best lays the fitted model on that
  // camera's silhouettes over the frames checked (shift_check_every), and
  // whether it says the camera's calibration disagrees with the others'
  // (CalibrationDisagrees).
  struct CameraShift {
    SilhouetteShift shift;
    double degrees = 0;  // the shift as a turn of the camera
    bool disagrees = false;
  };
  std::vector<CameraShift> camera_shifts;
  // The cameras' frame offsets that best bring their keypoints together over
  // the frames checked (step_check_frames; empty offsets where not checked),
  // and whether they say the cameras run out of step (CamerasOutOfStep).
  FrameOffsets steps;
  bool out_of_step = false;
  std::vector<std::vector<double>> Poses() const;
  // poses.json: DOF names, body shape, per frame DOFs, fit quality and flags.
  std::string ToJson() const;
};

// Whether a camera's common shift says its calibration disagrees with the
// other cameras': found over 3 frames or more (in one frame a poor fit looks
// like a shift), 2 pixels or more (less is the masks' and rasters' grain), a
// turn over a quarter of a degree, and raising its mean IoU by at least 0.01
// (a fit whose misses change from frame to frame gains little from any one
// shift). On the synthetic studios' exact calibrations the shift stays under
// a tenth of a pixel (docs/tracking.md).
bool CalibrationDisagrees(const SilhouetteShift& shift, double degrees);

StatusOr<TrackCaptureResult> TrackCapture(const std::string& capture_path,
                                          const TrackCaptureOptions& options);
// The same on a capture already loaded (its cameras as they are, e.g. a
// calibration being refined).
// The person network for a capture's silhouettes under `persons` (see
// TrackCaptureOptions::persons; `extract` as there): null where it is not
// wanted, or under kAuto where its models do not load (`note`, if given, then
// says why). What tracking and the encoder's textures both take.
StatusOr<std::unique_ptr<PersonObserver>> PersonsForCapture(const Capture& capture, bool extract,
                                                            TrackCaptureOptions::Persons persons,
                                                            const std::string& models,
                                                            std::string* note = nullptr);

StatusOr<TrackCaptureResult> TrackCapture(const Capture& capture,
                                          const TrackCaptureOptions& options);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_TRACK_CAPTURE_H_
