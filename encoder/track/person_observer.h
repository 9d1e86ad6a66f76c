// A person in one camera image, seen by a pretrained network: where the body's
// 33 keypoints are (with how visible each is) and which pixels are the person.
// The networks are MediaPipe's BlazePose detector and landmark model, converted
// to ONNX by the project's set-up (tools/models/) and run with OpenCV's dnn
// module; nothing outside this file knows which network made an observation.
#ifndef FVV_ENCODER_TRACK_PERSON_OBSERVER_H_
#define FVV_ENCODER_TRACK_PERSON_OBSERVER_H_

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "encoder/io/image_io.h"
#include "encoder/track/joint_sighting.h"

namespace fvv {

constexpr int kPersonKeypoints = 33;
// BlazePose's keypoint order: nose, eyes, ears, mouth, shoulders, elbows,
// wrists, hand points, hips, knees, ankles, heels, foot tips.
const char* PersonKeypointName(int index);

// The square, rotated image region the landmark network looks at.
struct PersonRegion {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // pixels
  double size = 0;                                   // side, pixels
  double rotation = 0;                               // radians, image y down
};

struct PersonKeypoint {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  double visibility = 0;  // 0..1: in view and not occluded
};

struct PersonObservation {
  bool found = false;
  double score = 0;  // the landmark network's confidence that a person is there
  std::array<PersonKeypoint, kPersonKeypoints> keypoints{};
  Image mask;             // grey, the image's size: 255 * P(person) per pixel
  PersonRegion region;    // where the network looked
  PersonRegion next;      // where to look in the next frame
  bool detected = false;  // the detector ran (no region was carried over)
};

class PersonObserver {
 public:
  // Loads pose_detection.onnx and pose_landmark_full.onnx from `model_dir`.
  // Unsupported when fvv was built without OpenCV's dnn module; NotFound-like
  // IoError naming the file when a model is missing.
  static StatusOr<std::unique_ptr<PersonObserver>> Load(const std::string& model_dir);
  ~PersonObserver();

  // One RGB image. `previous`: the region from the last frame of the same
  // camera, to skip the detector; without it the detector runs and the most
  // confident person is taken.
  StatusOr<PersonObservation> Observe(const Image& rgb, const PersonRegion* previous);

  // Every person the detector finds, most confident first (a person found
  // twice is kept once).
  struct Candidate {
    double score = 0;
    Eigen::Vector2d hips = Eigen::Vector2d::Zero();  // the hips' centre, pixels
    PersonRegion region;
  };
  StatusOr<std::vector<Candidate>> Detect(const Image& rgb);
  // The landmark network on one region (a candidate's, or one carried over).
  StatusOr<PersonObservation> ObserveRegion(const Image& rgb, const PersonRegion& region);

  // Tuning: the detector's minimum score, the landmark network's minimum
  // presence score.
  double min_detection_score = 0.5;
  double min_presence_score = 0.5;

 private:
  struct Networks;
  PersonObserver() = default;
  std::unique_ptr<Networks> nets_;
};

// The observation's keypoints that are joints of the generic body
// (shoulders, elbows, wrists, hips, knees, ankles), their visibility as
// confidence; none when no person was found.
std::vector<JointSighting> BodyJointSightings(const PersonObservation& observation);

// Where the models live by default: $FVV_MODEL_DIR, else the directory the
// set-up fills (build-independent, shared by every build of this checkout).
std::string DefaultModelDirectory();

// Whether this build can run the networks at all.
bool PersonObserverAvailable();

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_PERSON_OBSERVER_H_
