// Importing studio calibrations kept in OpenCV-style files (`fvv capture
// import-calib`): OpenCV FileStorage YAML (`%YAML:1.0`, `!!opencv-matrix`) or
// plain YAML, and TOML. A file holds one camera (named after the file) or
// several (top-level sections named after the cameras). Per camera:
//   K | camera_matrix | cameraMatrix | intrinsics        3x3
//   D | dist | distortion | dist_coeffs | distortion_coefficients   up to 5 (k1 k2 p1 p2 k3)
//   R | rotation | rotation_matrix  (3x3)  or  rvec | rotation_vector (Rodrigues, 3)
//   t | T | tvec | translation      (3; in --translation-unit)
//   width/height | image_width/image_height | image_size [w, h]
// Matrices are opencv-matrix maps (rows, cols, data), nested lists or flat lists.
#ifndef FVV_ENCODER_CAPTURE_CALIBRATION_IMPORT_H_
#define FVV_ENCODER_CAPTURE_CALIBRATION_IMPORT_H_

#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"

namespace fvv {

// `translation_unit`: metres per unit of t (1 for metres, 0.001 for millimetres).
StatusOr<std::vector<Camera>> ImportCalibrationFile(const std::string& path,
                                                    double translation_unit);

}  // namespace fvv

#endif  // FVV_ENCODER_CAPTURE_CALIBRATION_IMPORT_H_
