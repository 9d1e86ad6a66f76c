// The GOP index 'indx' (SPEC.md 3.6) and metadata 'meta' (SPEC.md 3.7) boxes.
#ifndef FVV_CONTAINER_INDEX_BOX_H_
#define FVV_CONTAINER_INDEX_BOX_H_

#include <string>
#include <utility>
#include <vector>

#include "codec/base/status.h"
#include "container/box.h"
#include "container/file_header.h"

namespace fvv {

struct IndexEntry {
  uint32_t first_frame = 0;
  uint16_t frame_count = 0;
  uint16_t first_camera = 0;
  uint16_t camera_count = 0;
  uint64_t offset = 0;  // of the 'frag' box, from the start of the file
  uint64_t size = 0;    // of the whole 'frag' box
  // Version 1 (texture-chunks): the box's bytes before its first texture chunk,
  // the least prefix that decodes (SPEC.md 3.5.1); 0 where unknown (an index
  // rebuilt by walking a stream without one).
  uint32_t head_size = 0;
};
constexpr size_t kIndexEntryBytes = 26;  // version 0; version 1 adds head_size u32

// The 'indx' version of a stream with these tools: 1 with texture-chunks.
uint8_t IndexVersion(uint32_t tools);
std::vector<uint8_t> WriteIndexBox(const std::vector<IndexEntry>& entries, uint8_t version);
// Checks entries against the header: GOP alignment, ranges, ascending offsets.
Status ReadIndex(const BoxHeader& box, const uint8_t* payload, const FileHeader& header,
                 std::vector<IndexEntry>* entries);

using Metadata = std::vector<std::pair<std::string, std::string>>;
std::vector<uint8_t> WriteMetadataBox(const Metadata& metadata);
Status ReadMetadata(const BoxHeader& box, const uint8_t* payload, Metadata* metadata);
bool IsValidUtf8(const std::string& s);

}  // namespace fvv

#endif  // FVV_CONTAINER_INDEX_BOX_H_
