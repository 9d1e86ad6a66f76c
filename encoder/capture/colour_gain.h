// A camera's colour gain (CaptureCamera::colour_gain): R, G and B factors that
// bring its pixel values to the rig's common colour. The encoder's textures and
// Renderer I read the cameras through them; a view rendered for comparison
// with one camera's footage goes back through that camera's inverse.
#ifndef FVV_ENCODER_CAPTURE_COLOUR_GAIN_H_
#define FVV_ENCODER_CAPTURE_COLOUR_GAIN_H_

#include <array>
#include <cstddef>
#include <cstdint>

#include "encoder/io/image_io.h"

namespace fvv {

// Gains outside this range are refused in capture.json: no exposure or white
// balance a take would use differs by more than two stops.
constexpr double kMinColourGain = 0.25, kMaxColourGain = 4.0;

bool IsUnitGain(const std::array<double, 3>& gain);

// `pixels` RGB8 values times the gain, rounded and clipped to 0..255.
void ApplyColourGain(const std::array<double, 3>& gain, uint8_t* rgb, size_t pixels);
// An RGB8 image (grey or RGBA images are left alone: they carry no colour).
void ApplyColourGain(const std::array<double, 3>& gain, Image* image);

// The gain that undoes `gain`.
std::array<double, 3> InverseGain(const std::array<double, 3>& gain);

}  // namespace fvv

#endif  // FVV_ENCODER_CAPTURE_COLOUR_GAIN_H_
