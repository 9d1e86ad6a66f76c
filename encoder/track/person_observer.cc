#include "encoder/track/person_observer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "encoder/body/generic_body.h"

#if defined(FVV_HAVE_OPENCV_DNN)
#include <sys/stat.h>

#include <algorithm>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#endif

namespace fvv {

const char* PersonKeypointName(int index) {
  static const char* const kNames[kPersonKeypoints] = {
      "nose",        "left_eye_inner",  "left_eye",        "left_eye_outer", "right_eye_inner",
      "right_eye",   "right_eye_outer", "left_ear",        "right_ear",      "mouth_left",
      "mouth_right", "left_shoulder",   "right_shoulder",  "left_elbow",     "right_elbow",
      "left_wrist",  "right_wrist",     "left_pinky",      "right_pinky",    "left_index",
      "right_index", "left_thumb",      "right_thumb",     "left_hip",       "right_hip",
      "left_knee",   "right_knee",      "left_ankle",      "right_ankle",    "left_heel",
      "right_heel",  "left_foot_index", "right_foot_index"};
  return index >= 0 && index < kPersonKeypoints ? kNames[index] : "";
}

std::vector<JointSighting> BodyJointSightings(const PersonObservation& observation) {
  // BlazePose's indices of the body's left and right (the person's own)
  // shoulder, elbow, wrist, hip, knee and ankle.
  static const std::pair<int, int> kJoints[] = {
      {11, kLeftShoulder}, {13, kLeftElbow},  {15, kLeftWrist}, {12, kRightShoulder},
      {14, kRightElbow},   {16, kRightWrist}, {23, kLeftHip},   {25, kLeftKnee},
      {27, kLeftAnkle},    {24, kRightHip},   {26, kRightKnee}, {28, kRightAnkle}};
  std::vector<JointSighting> out;
  if (!observation.found) return out;
  for (const auto& [keypoint, joint] : kJoints) {
    const PersonKeypoint& k = observation.keypoints[keypoint];
    out.push_back({joint, k.pixel, std::clamp(k.visibility, 0.0, 1.0)});
  }
  return out;
}

std::string DefaultModelDirectory() {
  if (const char* dir = std::getenv("FVV_MODEL_DIR"); dir && *dir) return dir;
  if (const char* home = std::getenv("HOME"); home && *home) {
    return std::string(home) + "/.cache/fvv/models";
  }
  return ".fvv-models";
}

#if defined(FVV_HAVE_OPENCV_DNN)

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kDetectorSize = 224, kLandmarkSize = 256;
constexpr int kAnchors = 2254, kDetectorValues = 12, kLandmarks = 39, kLandmarkValues = 5;
// The detector's region around the person: twice the hip-to-scale-point
// distance, grown by this factor (MediaPipe's pose graphs use 1.25).
constexpr double kRegionScale = 1.25;

double Sigmoid(double x) { return 1 / (1 + std::exp(-x)); }

double NormaliseAngle(double a) { return a - 2 * kPi * std::floor((a + kPi) / (2 * kPi)); }

// The square region two alignment points define: centred on `a` (the hips'
// centre), `b` (a point the body's extent reaches) at 90 degrees, "up".
PersonRegion RegionFromPoints(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  PersonRegion r;
  r.centre = a;
  r.size = 2 * (b - a).norm() * kRegionScale;
  r.rotation = NormaliseAngle(kPi / 2 - std::atan2(-(b.y() - a.y()), b.x() - a.x()));
  return r;
}

// The affine map from the region's crop (side n pixels) to image pixels.
cv::Mat CropToImage(const PersonRegion& r, int n) {
  const double c = std::cos(r.rotation), s = std::sin(r.rotation), k = r.size / n;
  const double u0 = 0.5 - n / 2.0;  // crop pixel centre u + 0.5 - n/2, scaled by k
  cv::Mat m(2, 3, CV_64F);
  m.at<double>(0, 0) = k * c, m.at<double>(0, 1) = -k * s;
  m.at<double>(1, 0) = k * s, m.at<double>(1, 1) = k * c;
  m.at<double>(0, 2) = r.centre.x() + k * (c * u0 - s * u0);
  m.at<double>(1, 2) = r.centre.y() + k * (s * u0 + c * u0);
  return m;
}

// A point in the region's normalised crop coordinates ([0, 1] across it) in image pixels.
Eigen::Vector2d FromRegion(const PersonRegion& r, double x, double y) {
  const double c = std::cos(r.rotation), s = std::sin(r.rotation);
  x -= 0.5, y -= 0.5;
  return r.centre + r.size * Eigen::Vector2d(c * x - s * y, s * x + c * y);
}

struct Anchor {
  float x, y;
};

// The detector's anchors: one grid per stride (8, 16, then 32 three times, the
// last three merged), two anchors per cell per layer, unit size.
std::vector<Anchor> DetectorAnchors() {
  const int strides[] = {8, 16, 32, 32, 32};
  std::vector<Anchor> anchors;
  for (int layer = 0; layer < 5;) {
    int last = layer, per_cell = 0;
    while (last < 5 && strides[last] == strides[layer]) per_cell += 2, ++last;
    const int grid = (kDetectorSize + strides[layer] - 1) / strides[layer];
    for (int y = 0; y < grid; ++y) {
      for (int x = 0; x < grid; ++x) {
        for (int k = 0; k < per_cell; ++k) {
          anchors.push_back({(x + 0.5f) / grid, (y + 0.5f) / grid});
        }
      }
    }
    layer = last;
  }
  return anchors;
}

bool FileExists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

}  // namespace

struct PersonObserver::Networks {
  cv::dnn::Net detector, landmarks;
  std::vector<Anchor> anchors = DetectorAnchors();
};

bool PersonObserverAvailable() { return true; }

StatusOr<std::unique_ptr<PersonObserver>> PersonObserver::Load(const std::string& dir) {
  const std::string detector = dir + "/pose_detection.onnx";
  const std::string landmarks = dir + "/pose_landmark_full.onnx";
  for (const std::string& path : {detector, landmarks}) {
    if (!FileExists(path)) {
      return IoError("person model " + path +
                     " is missing (tools/setup.sh fetches and converts the models; "
                     "FVV_MODEL_DIR points elsewhere)");
    }
  }
  std::unique_ptr<PersonObserver> o(new PersonObserver());
  o->nets_ = std::make_unique<Networks>();
  try {
    o->nets_->detector = cv::dnn::readNetFromONNX(detector);
    o->nets_->landmarks = cv::dnn::readNetFromONNX(landmarks);
  } catch (const cv::Exception& e) {
    return Corrupt("person models in " + dir + " do not load: " + e.what());
  }
  if (o->nets_->anchors.size() != kAnchors) return Internal("detector anchors miscounted");
  return o;
}

PersonObserver::~PersonObserver() = default;

namespace {

// The detector: the whole image letterboxed into 224 x 224, values in [-1, 1].
// Per anchor scoring over `min_score`: the person's alignment points (the hips'
// centre and a point the whole body's extent reaches) make its region.
std::vector<PersonObserver::Candidate> DetectCandidates(cv::dnn::Net& net,
                                                        const std::vector<Anchor>& anchors,
                                                        const cv::Mat& image, double min_score) {
  const double scale = double(kDetectorSize) / std::max(image.cols, image.rows);
  const int w = std::max(1, int(std::lround(image.cols * scale)));
  const int h = std::max(1, int(std::lround(image.rows * scale)));
  const int pad_x = (kDetectorSize - w) / 2, pad_y = (kDetectorSize - h) / 2;
  cv::Mat letterbox(kDetectorSize, kDetectorSize, CV_8UC3, cv::Scalar(0, 0, 0));
  cv::Mat inside = letterbox(cv::Rect(pad_x, pad_y, w, h));
  cv::resize(image, inside, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  net.setInput(cv::dnn::blobFromImage(letterbox, 2.0 / 255, cv::Size(),
                                      cv::Scalar(127.5, 127.5, 127.5), false, false));
  std::vector<cv::Mat> outs;
  net.forward(outs, std::vector<cv::String>{"Identity", "Identity_1"});
  const float* boxes = outs[0].ptr<float>();
  const float* scores = outs[1].ptr<float>();
  std::vector<PersonObserver::Candidate> all;
  for (int i = 0; i < kAnchors; ++i) {
    const double sc = Sigmoid(std::clamp<double>(scores[i], -100, 100));
    if (sc <= min_score) continue;
    // Values: a face box (x, y, w, h), then keypoints: the hips' centre, a point
    // the whole body reaches, the shoulders' centre, the upper body's.
    const float* v = boxes + size_t{kDetectorValues} * i;
    const Anchor& a = anchors[i];
    auto to_image = [&](float raw_x, float raw_y) {
      const double x = raw_x + a.x * kDetectorSize, y = raw_y + a.y * kDetectorSize;
      return Eigen::Vector2d((x - pad_x) / scale - 0.5, (y - pad_y) / scale - 0.5);
    };
    PersonObserver::Candidate c;
    c.score = sc;
    c.hips = to_image(v[4], v[5]);
    c.region = RegionFromPoints(c.hips, to_image(v[6], v[7]));
    all.push_back(c);
  }
  std::sort(all.begin(), all.end(),
            [](const PersonObserver::Candidate& a, const PersonObserver::Candidate& b) {
              return a.score > b.score;
            });
  // One per person: anchors whose hips fall near a more confident one's are
  // the same person.
  std::vector<PersonObserver::Candidate> kept;
  for (const PersonObserver::Candidate& c : all) {
    bool same = false;
    for (const PersonObserver::Candidate& k : kept) {
      same = same || (c.hips - k.hips).norm() < 0.2 * k.region.size;
    }
    if (!same) kept.push_back(c);
  }
  return kept;
}

// The landmark network on `region`, rotated upright, at 256 x 256 in [0, 1].
PersonObservation Landmarks(cv::dnn::Net& net, const cv::Mat& image, const PersonRegion& region,
                            double min_presence) {
  PersonObservation out;
  out.region = region;
  const cv::Mat to_image = CropToImage(region, kLandmarkSize);
  cv::Mat crop;
  cv::warpAffine(image, crop, to_image, cv::Size(kLandmarkSize, kLandmarkSize),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, cv::Scalar(0, 0, 0));
  net.setInput(cv::dnn::blobFromImage(crop, 1.0 / 255, cv::Size(), cv::Scalar(), false, false));
  std::vector<cv::Mat> outs;
  net.forward(outs, std::vector<cv::String>{"Identity", "Identity_1", "Identity_2"});
  out.score = outs[1].ptr<float>()[0];
  // Per landmark x, y, z (crop pixels), visibility and presence (logits); 33
  // body keypoints, then the two alignment points of the next frame's region.
  const float* lm = outs[0].ptr<float>();
  Eigen::Vector2d aux[2];
  for (int k = 0; k < kLandmarks; ++k) {
    const float* v = lm + size_t{kLandmarkValues} * k;
    const Eigen::Vector2d p = FromRegion(region, v[0] / kLandmarkSize, v[1] / kLandmarkSize);
    if (k < kPersonKeypoints) {
      out.keypoints[k].pixel = p;
      out.keypoints[k].visibility = Sigmoid(v[3]);
    } else if (k < kPersonKeypoints + 2) {
      aux[k - kPersonKeypoints] = p;
    }
  }
  out.next = RegionFromPoints(aux[0], aux[1]);
  out.found = out.score >= min_presence;
  if (!out.found) return out;
  // The person's probability per pixel, back in the image.
  cv::Mat logits(kLandmarkSize, kLandmarkSize, CV_32F, outs[2].ptr<float>());
  cv::Mat probability;
  cv::exp(-logits, probability);
  probability = 255.0 / (1.0 + probability);
  cv::Mat mask;
  cv::warpAffine(probability, mask, to_image, image.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                 cv::Scalar(0));
  out.mask.width = static_cast<uint32_t>(image.cols);
  out.mask.height = static_cast<uint32_t>(image.rows);
  out.mask.channels = 1;
  out.mask.pixels.resize(size_t(image.cols) * image.rows);
  cv::Mat mask8(image.size(), CV_8U, out.mask.pixels.data());
  mask.convertTo(mask8, CV_8U);
  return out;
}

}  // namespace

namespace {

StatusOr<cv::Mat> Wrap(const Image& rgb) {
  if (rgb.channels != 3 || rgb.width == 0 || rgb.height == 0 ||
      rgb.pixels.size() != size_t{rgb.width} * rgb.height * 3) {
    return InvalidArgument("person observer: needs a non-empty RGB image");
  }
  return cv::Mat(static_cast<int>(rgb.height), static_cast<int>(rgb.width), CV_8UC3,
                 const_cast<uint8_t*>(rgb.pixels.data()));
}

}  // namespace

StatusOr<std::vector<PersonObserver::Candidate>> PersonObserver::Detect(const Image& rgb) {
  StatusOr<cv::Mat> image = Wrap(rgb);
  if (!image.ok()) return image.status();
  try {
    return DetectCandidates(nets_->detector, nets_->anchors, *image, min_detection_score);
  } catch (const cv::Exception& e) {
    return Internal(std::string("person observer: OpenCV: ") + e.what());
  }
}

StatusOr<PersonObservation> PersonObserver::ObserveRegion(const Image& rgb,
                                                          const PersonRegion& region) {
  StatusOr<cv::Mat> image = Wrap(rgb);
  if (!image.ok()) return image.status();
  if (!(region.size > 8)) return InvalidArgument("person observer: an empty region");
  try {
    PersonObservation best = Landmarks(nets_->landmarks, *image, region, min_presence_score);
    // The detector places the region from two points and can cut off the feet
    // or the head (a side view); the landmarks, even unsure, place a better one.
    // Two more looks: there, and at the first region grown by half.
    if (!best.found) {
      PersonRegion grown = region;
      grown.size *= 1.5;
      for (const PersonRegion& retry : {best.next, grown}) {
        if (!(retry.size > 8)) continue;
        PersonObservation again = Landmarks(nets_->landmarks, *image, retry, min_presence_score);
        if (again.score > best.score) best = std::move(again);
      }
    }
    return best;
  } catch (const cv::Exception& e) {
    return Internal(std::string("person observer: OpenCV: ") + e.what());
  }
}

StatusOr<PersonObservation> PersonObserver::Observe(const Image& rgb,
                                                    const PersonRegion* previous) {
  if (previous && previous->size > 8) return ObserveRegion(rgb, *previous);
  StatusOr<std::vector<Candidate>> people = Detect(rgb);
  if (!people.ok()) return people.status();
  if (people->empty()) {
    PersonObservation nobody;
    nobody.detected = true;
    return nobody;
  }
  StatusOr<PersonObservation> seen = ObserveRegion(rgb, people->front().region);
  if (seen.ok()) seen->detected = true;
  return seen;
}

#else  // no OpenCV dnn

struct PersonObserver::Networks {};

bool PersonObserverAvailable() { return false; }

StatusOr<std::unique_ptr<PersonObserver>> PersonObserver::Load(const std::string&) {
  return Unsupported(
      "person masks and keypoints need OpenCV's dnn module, which this build of fvv lacks "
      "(apt-get install libopencv-dev, then build again)");
}

PersonObserver::~PersonObserver() = default;

StatusOr<PersonObservation> PersonObserver::Observe(const Image&, const PersonRegion*) {
  return Unsupported("person observer: built without OpenCV's dnn module");
}

StatusOr<std::vector<PersonObserver::Candidate>> PersonObserver::Detect(const Image&) {
  return Unsupported("person observer: built without OpenCV's dnn module");
}

StatusOr<PersonObservation> PersonObserver::ObserveRegion(const Image&, const PersonRegion&) {
  return Unsupported("person observer: built without OpenCV's dnn module");
}

#endif

}  // namespace fvv
