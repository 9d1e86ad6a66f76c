// The conformance output of a stream (SPEC.md Annex B): what the reference
// decoder produces, as named byte files, so that any decoder's output can be
// compared with it by hash.
//
//   motion.bin               every frame in order; per bone the BoneMotion of 6.4:
//                            rotation w x y z (i32 LE), translation x y z (i64 LE, um)
//   yuv_FFFFFF_CCC.bin       frame F, camera C: the Y, U and V planes of 9.6 (chroma
//                            at its coded size), each sample i16 LE, rows top first
//   mask_FFFFFF_CCC.bin      streams with masks: one byte 0/1 per atlas texel
//   vvis_FFFFFF_CCC.bin      fragments with 'vvis': one byte 0/1 per model vertex
//   rgb_FFFFFF_CCC.bin       frame F, camera C: the RGB of 9.7, 3 bytes per texel
//   model.bin, cameras.bin   the decoded mesh and skin, and the calibrations
//
// Under a budget of B bytes per fragment, each channel stream c of a fragment is
// decoded from its first floor(size_c * B / (size_Y + size_U + size_V)) bytes
// (all of them when B = 0 or B >= the sum); motion, masks and vertex
// visibility are always decoded whole. With the texture in chunks (format
// version 11) B is the prefix of each fragment delivered: the channels decode
// from its whole chunks, and a B inside a fragment's head is Truncated.
//
// ReferenceDecode is reference_output.cc; the hashes and the directories are
// output_files.cc (OpenSSL, file I/O), which the WebAssembly build leaves out.
#ifndef FVV_CONFORMANCE_LIB_REFERENCE_OUTPUT_H_
#define FVV_CONFORMANCE_LIB_REFERENCE_OUTPUT_H_

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "codec/base/status.h"

namespace fvv {

// Largest stream or output file the suite's tools read (level 4 fragments and
// planes stay far below it).
constexpr uint64_t kMaxConformanceFileBytes = uint64_t{4} << 30;

// Receives each output file once, in decoding order.
using OutputSink =
    std::function<Status(const std::string& name, const std::vector<uint8_t>& bytes)>;

enum class ReadPath {
  kRandomAccess,  // FileReader: header boxes, index (or a scan), fragments by index
  kStreaming,     // StreamReader: the bytes pushed in order, fragments as they arrive
};

struct ReferenceDecodeOptions {
  uint64_t bytes_per_fragment = 0;  // 0 = whole streams
  ReadPath path = ReadPath::kRandomAccess;
  unsigned threads = 2;
};

// Decodes a whole stream held in memory. The first error ends the decode and is
// returned (files already given to the sink stay given).
Status ReferenceDecode(const uint8_t* data, size_t size, const ReferenceDecodeOptions& options,
                       const OutputSink& sink);

// File name -> SHA-256 (hex) of every output file.
using OutputHashes = std::map<std::string, std::string>;
StatusOr<OutputHashes> ReferenceDecodeHashes(const std::vector<uint8_t>& stream,
                                             const ReferenceDecodeOptions& options);

// A sink that writes each file into `dir` (which must exist).
OutputSink DirectorySink(const std::string& dir);
// Hashes every regular file of `dir` (a decoder's output directory).
StatusOr<OutputHashes> HashDirectory(const std::string& dir);

std::string OutputName(const char* stem, uint32_t frame, uint32_t camera);

}  // namespace fvv

#endif  // FVV_CONFORMANCE_LIB_REFERENCE_OUTPUT_H_
