#include "container/stream_info.h"

namespace fvv {

uint64_t MaxTopLevelBoxSize(const StreamInfo& info, FourCC type) {
  if (type == box::kFileHeader) return 64;
  if (!info.has_header) return 0;
  const LevelLimits& lim = LimitsOf(info.header);
  if (type == box::kFragment) return lim.max_fragment_bytes + kMaxBoxHeaderSize;
  if (type == box::kModel) {
    // Compressed data never needs to be larger than the raw bound it decodes to.
    return uint64_t{lim.max_vertices} * 64 + uint64_t{lim.max_triangles} * 12 +
           uint64_t{lim.max_bones} * 512 + 4096;
  }
  if (type == box::kIndex) {
    return kMaxBoxHeaderSize + 4 +
           kIndexEntryBytes * (uint64_t{0xFFFFFFFFu / info.header.gop_frames} + 1) *
               info.header.camera_groups();
  }
  if (type == box::kCameras)
    return kMaxBoxHeaderSize + 2 + uint64_t{lim.max_cameras} * (65535 + 200);
  return 1u << 20;  // metadata, motion parameters, and boxes a reader skips unread
}

Status ApplyTopLevelBox(const BoxHeader& b, const uint8_t* payload, StreamInfo* info) {
  auto once = [&](bool seen) {
    return seen ? Corrupt(BoxContext(b) + "appears twice") : Status::Ok();
  };
  if (!info->has_header) {
    if (b.type != box::kFileHeader) {
      return Corrupt("not an fvv stream: it starts with box '" + FourCCString(b.type) +
                     "', not 'fvvh'");
    }
    FVV_RETURN_IF_ERROR(ReadFileHeader(b, payload, &info->header));
    info->has_header = true;
    return Status::Ok();
  }
  if (b.type == box::kFileHeader) return once(true);
  if (b.type == box::kCameras) {
    FVV_RETURN_IF_ERROR(once(info->has_cameras));
    FVV_RETURN_IF_ERROR(ReadCameras(b, payload, info->header.camera_count, &info->cameras));
    info->has_cameras = true;
  } else if (b.type == box::kModel) {
    FVV_RETURN_IF_ERROR(once(info->has_model));
    FVV_RETURN_IF_ERROR(ReadModel(b, payload, LimitsOf(info->header), &info->model));
    const bool declared = (info->header.tools & kToolQuantisedModel) != 0;
    if (declared != info->model.quantisation.quantised) {
      return Corrupt(BoxContext(b) + "version " + std::to_string(b.version) + " in a stream " +
                     (declared ? "declaring" : "not declaring") +
                     " quantised-model (tool bit 19 and 'modl' version 1 go together)");
    }
    info->has_model = true;
  } else if (b.type == box::kMotionParams) {
    FVV_RETURN_IF_ERROR(once(info->has_motion));
    FVV_RETURN_IF_ERROR(ReadMotionParams(b, payload, &info->motion));
    info->has_motion = true;
  } else if (b.type == box::kMetadata) {
    FVV_RETURN_IF_ERROR(once(info->has_metadata));
    FVV_RETURN_IF_ERROR(ReadMetadata(b, payload, &info->metadata));
    info->has_metadata = true;
  } else if (b.type == box::kIndex) {
    FVV_RETURN_IF_ERROR(once(info->has_index));
    FVV_RETURN_IF_ERROR(ReadIndex(b, payload, info->header, &info->index));
    info->has_index = true;
  } else if (b.type == box::kFragment) {
    return Internal("fragments are not header boxes");
  } else if (b.essential()) {
    return Unsupported(BoxContext(b) + "essential box type unknown to this decoder");
  }
  return Status::Ok();
}

Status CheckReadyForFragments(const StreamInfo& info, uint64_t offset) {
  const char* missing = !info.has_cameras  ? "cams"
                        : !info.has_model  ? "modl"
                        : !info.has_motion ? "mtrk"
                                           : nullptr;
  if (missing) {
    return Corrupt("fragment at offset " + std::to_string(offset) + " comes before the '" +
                   missing + "' box");
  }
  return Status::Ok();
}

}  // namespace fvv
