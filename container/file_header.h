// The file header box 'fvvh' (SPEC.md 3.1) and the profile/level limits it
// declares (SPEC.md section 5). Every count a reader takes from the stream is
// checked against these limits before anything is allocated.
#ifndef FVV_CONTAINER_FILE_HEADER_H_
#define FVV_CONTAINER_FILE_HEADER_H_

#include <cstdint>
#include <vector>

#include "codec/base/status.h"
#include "container/box.h"

namespace fvv {

// Highest format version this library reads. Writers write the lowest version
// that has every tool they use (RequiredFormatVersion), so streams without
// the newer tools stay readable by older decoders.
constexpr uint16_t kFormatVersion = 12;

// Coding tools (FileHeader::tools bits). A stream declares every tool it uses;
// a profile allows a subset.
enum CodingTool : uint32_t {
  kToolHaar = 1u << 0,
  kToolLeGall53 = 1u << 1,
  kToolCdf97 = 1u << 2,
  kToolSpihtBinary = 1u << 3,
  kToolSpihtArith = 1u << 4,
  kToolChroma420 = 1u << 5,
  kToolReversibleColour = 1u << 6,
  kToolMasks = 1u << 7,
  kToolVertexVisibility = 1u << 8,
  kToolMotionInterpolation = 1u << 9,
  kToolMotionZstd = 1u << 10,
  kToolPredictiveTexture = 1u << 11,  // format version 2: 'ptex' instead of 'texr'
  kToolTexturePrecision = 1u << 12,   // format version 3: 'texr' version 1 declares the 9/7's f
  kToolSpihtArith2 = 1u << 13,        // format version 4: SPIHT coder 2 (neighbourhood contexts)
  kToolSpihtArith3 = 1u << 14,        // format version 5: SPIHT coder 3 (set and sign contexts)
  kToolOwnBandWeights = 1u << 15,     // format version 6: 'texr' version 2, own-band weights
  kToolSamplePrecision = 1u << 16,    // format version 7: 'texr' version 3, fractional samples
  kToolQuadtreeArith4 = 1u << 17,     // format version 8: coder 4, quadtrees per subband
  kToolChromaBilinear = 1u << 18,     // format version 9: 4:2:0 chroma upsampled bilinearly
  kToolQuantisedModel = 1u << 19,     // format version 10: 'modl' version 1, the mesh on a grid
  // Bit 20 is left undefined: the released case invalid/unknown_tool_bit sets it.
  kToolTextureChunks = 1u << 21,  // format version 11: 'txhd' + 'txck', every prefix decodes
  kToolSurface = 1u << 22,        // format version 12: 'sfhd' + chunks, the surface of every frame
};
constexpr uint32_t kAllKnownTools = ((1u << 20) - 1) | kToolTextureChunks | kToolSurface;
// The format version that introduced the newest of `tools`.
uint16_t RequiredFormatVersion(uint32_t tools);
const char* CodingToolName(uint32_t tool_bit);

enum class Profile : uint8_t { kMain = 1 };

struct LevelLimits {
  uint8_t level;
  uint32_t max_atlas_side;
  uint32_t max_cameras;
  uint32_t max_gop_frames;
  uint32_t max_gop_cameras;
  uint64_t max_gop_samples;         // gop_frames * gop_cameras * atlas_height * atlas_width
  uint64_t max_samples_per_second;  // atlas texels * cameras * frame rate
  uint64_t max_fragment_bytes;
  uint32_t max_bones;
  uint32_t max_vertices;
  uint32_t max_triangles;
};
// nullptr for an unknown level.
const LevelLimits* FindLevel(uint8_t level);
const std::vector<LevelLimits>& AllLevels();
uint32_t ProfileTools(Profile profile);

struct FileHeader {
  uint16_t format_version = kFormatVersion;
  Profile profile = Profile::kMain;
  uint8_t level = 1;
  uint32_t tools = 0;
  uint32_t frame_rate_num = 25;
  uint32_t frame_rate_den = 1;
  uint32_t frame_count = 0;  // 0 while a writer does not know it yet
  uint16_t camera_count = 1;
  uint16_t atlas_width = 0;
  uint16_t atlas_height = 0;
  uint16_t gop_frames = 8;
  uint16_t gop_cameras = 8;
  uint64_t index_offset = 0;  // file offset of the 'indx' box; 0 = none

  double fps() const { return frame_rate_den ? double(frame_rate_num) / frame_rate_den : 0; }
  // Number of GOP time spans and camera groups; fragments = spans * groups.
  uint32_t time_spans() const { return (frame_count + gop_frames - 1) / gop_frames; }
  uint32_t camera_groups() const { return (camera_count + gop_cameras - 1) / gop_cameras; }
};

// Byte offset of index_offset inside the 'fvvh' box (the writer patches it).
constexpr size_t kHeaderIndexOffsetPos = 12 + 30;
constexpr size_t kHeaderFrameCountPos = 12 + 16;

std::vector<uint8_t> WriteFileHeaderBox(const FileHeader& h);
// Parses the payload of an 'fvvh' box and validates it (profile, level, sizes).
Status ReadFileHeader(const BoxHeader& box, const uint8_t* payload, FileHeader* h);
// The checks ReadFileHeader applies; the writer runs them too, so it never
// writes what a reader would reject.
Status ValidateFileHeader(const FileHeader& h);
const LevelLimits& LimitsOf(const FileHeader& h);  // h must be valid
// A decoder's claim by limits (SPEC.md 5.1): LimitExceeded when the stream's
// GOPs hold more than `max_gop_samples` samples (0: no claim beyond the level).
Status CheckGopSamplesClaim(const FileHeader& h, uint64_t max_gop_samples);

}  // namespace fvv

#endif  // FVV_CONTAINER_FILE_HEADER_H_
