// Importing studio calibrations (`fvv capture import-calib`). Formats, told
// apart by content and name:
// - OpenCV FileStorage YAML (`%YAML:1.0`, `!!opencv-matrix`), plain YAML and
//   TOML: one camera (named after the file) or a section per camera (named by
//   its `name` field or its key). Per camera:
//     K | camera_matrix | cameraMatrix | intrinsics | matrix        3x3
//     D | dist | distortion(s) | dist_coeffs | distortion_coefficients
//                                               up to 5 (k1 k2 p1 p2 k3)
//     R | rotation | rotation_matrix: 3x3, or 3 entries (a rotation vector)
//     rvec | rotation_vector (3)
//     t | T | tvec | translation                (3; in --translation-unit)
//     width/height | image_width/image_height | image_size | size [w, h]
//   Matrices are opencv-matrix maps (rows, cols, data), nested or flat lists.
//   The anipose / Pose2Sim / FreeMoCap TOML ([cam_N] with name, size, matrix,
//   distortions, rotation as a vector, translation) is this form.
// - EasyMocap: intri.yml (names, K_<cam>, dist_<cam>) and extri.yml (R_<cam>
//   a rotation vector, Rot_<cam>, T_<cam>), given together.
// - Qualisys .qca.txt (XML): QualisysEntries in the .cc says the conventions;
//   positions are in millimetres whatever --translation-unit says.
// docs/capture-format.md has examples of each.
#ifndef FVV_ENCODER_CAPTURE_CALIBRATION_IMPORT_H_
#define FVV_ENCODER_CAPTURE_CALIBRATION_IMPORT_H_

#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"

namespace fvv {

struct ImportedCalibration {
  std::vector<Camera> cameras;  // width and height 0 where the files give no image size
  std::string format;           // e.g. "Qualisys", "TOML", "EasyMocap"
  // The world's up axis where the format defines one ('z': Qualisys Track
  // Manager's lab frame), else 0 (up_axis.h infers it from the cameras).
  char up_axis = 0;
};

// The cameras of one rig from one or more files, merged by camera name (a
// later file adds fields, never replaces one). `translation_unit`: metres per
// unit of t (1 for metres, 0.001 for millimetres).
StatusOr<ImportedCalibration> ImportCalibrationFiles(const std::vector<std::string>& paths,
                                                     double translation_unit);

// One file whose cameras all state their image size.
StatusOr<std::vector<Camera>> ImportCalibrationFile(const std::string& path,
                                                    double translation_unit);

// Sets `camera`'s image size to its frames' `width` x `height`. Where the
// calibration said another size, `note` says by how much (the principal point
// stays where the calibration put it: frames cropped at the right or bottom);
// a principal point outside the image, or a calibration invalid at that size,
// is an error.
Status FitImageSize(uint32_t width, uint32_t height, Camera* camera, std::string* note);

}  // namespace fvv

#endif  // FVV_ENCODER_CAPTURE_CALIBRATION_IMPORT_H_
