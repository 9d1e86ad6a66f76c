// Camera calibration geometry with OpenCV conventions: x_cam = R X + t, pinhole
// K, Brown-Conrady distortion (k1 k2 p1 p2 k3) applied to normalised coordinates.
// Pixel centres are at integer coordinates (OpenCV), so pixel (0, 0) covers
// [-0.5, 0.5]^2.
#ifndef FVV_ENCODER_CAPTURE_CALIBRATION_H_
#define FVV_ENCODER_CAPTURE_CALIBRATION_H_

#include <Eigen/Core>

#include "codec/base/status.h"
#include "container/cameras.h"

namespace fvv {

Eigen::Matrix3d CameraRotation(const Camera& camera);
Eigen::Vector3d CameraTranslation(const Camera& camera);
Eigen::Vector3d CameraCentre(const Camera& camera);

// World point -> pixel. Returns false for points at or behind the camera.
bool ProjectPoint(const Camera& camera, const Eigen::Vector3d& world, Eigen::Vector2d* pixel,
                  double* depth = nullptr);
// Pixel -> the world point at `depth` (camera z) along its ray; undistortion
// iterates to a residual below 1e-10 in normalised coordinates.
Eigen::Vector3d UnprojectPixel(const Camera& camera, const Eigen::Vector2d& pixel, double depth);

// Distortion of normalised coordinates, and its inverse.
Eigen::Vector2d Distort(const Camera& camera, const Eigen::Vector2d& normalised);
Eigen::Vector2d Undistort(const Camera& camera, const Eigen::Vector2d& distorted);

// Sanity checks a calibration: positive focal lengths, principal point within
// the image (with a margin of half its size), R a proper rotation (orthonormal
// to 1e-4, determinant +1), finite values, distortion small enough to be
// monotonic over the image. Messages start with `what`.
Status ValidateCalibration(const Camera& camera, const std::string& what);

// The integer factor that brings an image's longer side to at most about
// `max_side` pixels (at least 1).
int ReductionFactor(const Camera& camera, int max_side);
// The camera of its image reduced by `factor` (each reduced pixel covering
// factor x factor pixels, the remainder at the right and bottom dropped):
// focal lengths divided, and pixel centres kept at integers.
Camera ReducedCamera(const Camera& full, int factor);

// A camera at `centre` looking at `target`, with world `up` pointing up in the
// image, focal length `focal_px`, principal point at the image centre.
Camera LookAtCamera(const std::string& name, uint32_t width, uint32_t height, double focal_px,
                    const Eigen::Vector3d& centre, const Eigen::Vector3d& target,
                    const Eigen::Vector3d& up);

}  // namespace fvv

#endif  // FVV_ENCODER_CAPTURE_CALIBRATION_H_
