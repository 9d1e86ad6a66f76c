// A small synthetic .fvv stream built from nothing: a stick-figure body model
// (15 bones, 35 DOF, one box per bone), a ring of cameras, a procedural walk,
// and the built-in test-pattern textures and masks as atlas content, written
// with the container writer alone (no encoder session). The conformance
// generator remakes the released cases from it byte for byte; tests, fuzz
// seeds and `fvv sample` use it where a stream must be small and exact.
#ifndef FVV_CONFORMANCE_SAMPLE_SAMPLE_STREAM_H_
#define FVV_CONFORMANCE_SAMPLE_SAMPLE_STREAM_H_

#include <string>
#include <vector>

#include "codec/block_codec.h"
#include "container/fragment.h"
#include "container/stream_info.h"

namespace fvv {

struct SampleStreamOptions {
  uint32_t frames = 8;
  uint16_t cameras = 4;
  uint16_t atlas_width = 64, atlas_height = 64;
  uint16_t gop_frames = 8, gop_cameras = 8;
  WaveletKernel kernel = WaveletKernel::kCdf97;
  // 2 by default, as format versions 1 and 2 had it: the released cases are
  // remade from these options byte for byte. Other values write format version 3.
  int frac_bits_97 = kFracBits97Legacy;
  EntropyCoder coder = EntropyCoder::kArith;
  // kAxisBands by default, as the released cases have it; kOwnBand writes
  // format version 6.
  BandWeights weights = BandWeights::kAxisBands;
  // Fractional bits of the coded samples: 0 by default, as the released cases
  // have it; 1..4 write format version 7 (with the 9/7 and own-band weights; the
  // other codecs code whole samples).
  int sample_frac = 0;
  ChromaFormat chroma = ChromaFormat::k444;
  // With 4:2:0: kBilinear sets tool bit 18 (format version 9).
  ChromaUpsampling upsampling = ChromaUpsampling::kNearest;
  bool lossless = false;  // 5/3 or Haar + RCT at full rate
  // The predictive scheme with shape-adaptive BISK ('ptex', format version 2;
  // needs masks). `lossless` then means every stream whole (lossless in YUV).
  bool predictive = false;
  double bpp = 0.5;
  bool masks = true;
  // Mode 1 by default: the conformance suite's released version-1 cases are
  // made from these options and must stay byte-identical.
  MaskCoding mask_coding = MaskCoding::kContext;
  bool vertex_visibility = false;
  MotionCoder motion_coder = MotionCoder::kArith;
  uint16_t key_interval = 1;
  // The body model on the reference encoder's grid ('modl' version 1, format
  // version 10); floats by default, as the released cases have them.
  bool quantise_model = false;
  bool texture_chunks = false;  // 'txhd' + chunks (format version 11)
  // The surface of every frame ('sfhd' + chunks of channel 3, format version
  // 12; needs texture_chunks): values in steps of 2^-10 m, every fifth vertex
  // swinging by up to `surface_amplitude` steps, the others by up to 30.
  bool surface = false;
  int32_t surface_amplitude = 300;
  bool fast_start = true;  // declare the frame count up front (index at the front)
  uint8_t level = 1;
  uint32_t frame_rate_num = 25, frame_rate_den = 1;
  Metadata metadata = {{"title", "fvv sample stream"}, {"generator", "fvv sample"}};
};

// The smallest useful stream (3 frames, 2 cameras, 8x8 atlas, 2x2 GOPs: two
// fragments): fuzz seeds and the exhaustive prefix and byte-change tests.
SampleStreamOptions TinySampleOptions();

BodyModel MakeSampleBodyModel();
std::vector<Camera> MakeRingCameras(uint32_t count, uint32_t image_width, uint32_t image_height);
// DOF values (radians, metres) of the sample walk at `frame` (25 fps).
std::vector<double> SampleWalkPose(const Skeleton& skeleton, uint32_t frame);

struct SampleStream {
  StreamInfo info;
  std::vector<FragmentData> fragments;
  std::vector<QuantisedPose> poses;  // per frame, as coded
  std::vector<uint8_t> rgb;          // (t, c, y, x, 3): the source textures
  std::vector<uint8_t> masks;        // (t, c, y, x): 1 = used
};

StatusOr<SampleStream> MakeSampleStream(const SampleStreamOptions& options,
                                        const ParallelRunner& runner = SerialRunner);
StatusOr<std::vector<uint8_t>> MakeSampleStreamBytes(const SampleStreamOptions& options,
                                                     const ParallelRunner& runner = SerialRunner);

}  // namespace fvv

#endif  // FVV_CONFORMANCE_SAMPLE_SAMPLE_STREAM_H_
