// Which world axis is up in a rig's calibration. capture.json says y or z
// (docs/capture-format.md); a calibration file may not say, and a world read
// with the wrong up lays the actor on his side: tracking still fits, worse
// (a real 4-camera take imported y-up fitted to mean IoU 0.69 against 0.80
// z-up). Cameras are mounted upright above the floor, so their images' up
// points along the world's up; where cameras are rolled (portrait footage on
// a turned camera), their centres lie on a ring or a band around the actor,
// whose normal is the up axis, on the side the cameras look down from.
#ifndef FVV_ENCODER_CAPTURE_UP_AXIS_H_
#define FVV_ENCODER_CAPTURE_UP_AXIS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "container/cameras.h"
#include "encoder/capture/capture.h"

namespace fvv {

struct UpAxisEvidence {
  bool found = false;  // false: the cameras say nothing clear (too few, rolled every way)
  int axis = 1;        // 0 x, 1 y, 2 z
  int sign = 1;        // +1 or -1
  // The cameras' mean image-up along that axis (1: every camera upright).
  double agreement = 0;
  uint32_t upright = 0;          // cameras whose image up lies within 45 degrees of it
  bool from_centres = false;     // their image ups disagreed: the centres' plane decided
  std::string Describe() const;  // e.g. "+z: 4 of 4 cameras' image up within 45 degrees"
};

UpAxisEvidence InferUpAxis(const std::vector<Camera>& cameras);

struct UpAxisChoice {
  char axis = 'y';      // what capture.json says: 'y' or 'z'
  std::string reason;   // printed beside it
  std::string warning;  // empty, or what the cameras say against it
};

// `requested`: "y", "z" or "auto". `format_up`: the up axis the calibration
// format defines (ImportedCalibration::up_axis; 0 where it defines none).
// Auto takes the format's, else the cameras'; an explicit or defined axis
// the cameras contradict gets a warning.
UpAxisChoice ChooseUpAxis(const std::string& requested, char format_up, const std::string& format,
                          const std::vector<Camera>& cameras);

// For a loaded capture's cameras (in fvv's y-up world; `declared_up` is what
// its capture.json said): a warning where they clearly do not stand upright
// in it, else empty.
std::string UprightWarning(const std::vector<CaptureCamera>& cameras, char declared_up);

}  // namespace fvv

#endif  // FVV_ENCODER_CAPTURE_UP_AXIS_H_
