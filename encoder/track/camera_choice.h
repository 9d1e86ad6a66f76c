// Which cameras the fit needs, of a studio's many. A dome of 30 to 100
// cameras films the actor for texture from every side; the body's pose is
// fixed by far fewer, if they stand apart: each camera the fitter reads costs
// a silhouette (the person network and its mask) and a raster per evaluation,
// so fitting with every camera costs several times what fitting with ten
// does for little more accuracy. The cameras kept are the ones that see the
// whole capture volume (not close-ups), spread as far apart as they go in the
// directions they see the volume from (around it and up and down).
#ifndef FVV_ENCODER_TRACK_CAMERA_CHOICE_H_
#define FVV_ENCODER_TRACK_CAMERA_CHOICE_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"
#include "encoder/capture/capture.h"

namespace fvv {

// The default number of cameras the fit takes from a rig of more than
// kAutoTrackingAbove.
constexpr uint32_t kDefaultTrackingCameras = 10;
constexpr uint32_t kAutoTrackingAbove = 12;
// A tracking-camera setting: a count, or one of these.
constexpr uint32_t kTrackingCamerasAuto = 0;
constexpr uint32_t kTrackingCamerasAll = UINT32_MAX;

struct CameraChoice {
  std::vector<uint32_t> cameras;  // the indices chosen, ascending
  // Per camera of the rig: the share (0..1) of the volume's outline points
  // that fall inside its image (1: it sees the volume whole).
  std::vector<double> coverage;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // where the cameras look, world
};

// The point nearest every camera's optical axis (least squares): the centre
// of the capture volume the rig was set up around.
Eigen::Vector3d CaptureVolumeCentre(const std::vector<Camera>& cameras);

// `count` cameras (all of them where the rig has no more): those seeing the
// volume whole first, then the most of it; among them, farthest-point
// sampling of their directions from the volume's centre, starting from the
// camera nearest the rig's mean height. The volume: a person's extent, a
// vertical cylinder 0.45 m in radius from 0.95 m below the centre to 1.0 m
// above it (fvv's world is y up).
CameraChoice ChooseTrackingCameras(const std::vector<Camera>& cameras, uint32_t count);

// "auto", "all" or a count of 1 to 256 (--track-cameras).
StatusOr<uint32_t> ParseTrackingCameras(const std::string& text);

// How many of a rig's `rig_size` cameras a setting fits with.
uint32_t TrackingCameraCount(uint32_t setting, size_t rig_size);

// The capture cut to `count` cameras (ChooseTrackingCameras), in the rig's
// order; the capture itself where that is every camera. `names`, if given:
// the chosen cameras' names, space-separated.
Capture FittingCapture(const Capture& capture, uint32_t count, std::string* names = nullptr);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_CAMERA_CHOICE_H_
