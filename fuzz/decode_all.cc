#include "fuzz/decode_all.h"

#include <algorithm>

#include "codec/block_codec.h"
#include "codec/mask.h"
#include "codec/predictive_texture.h"
#include "container/stream_reader.h"
#include "container/vertex_visibility.h"

namespace fvv {
namespace {

void Mix(uint64_t* h, const void* data, size_t size) {
  const uint8_t* p = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < size; ++i) *h = (*h ^ p[i]) * 0x100000001b3ull;
}

Status DecodeFragment(const StreamInfo& info, const FragmentData& f, DecodeAllReport* report) {
  const Shape4D shape = f.info.TextureShape(info.header);
  if (!f.motion.empty()) {
    std::vector<DecodedFrame> frames;
    FVV_RETURN_IF_ERROR(DecodeMotion(MotionBoxHeader(f), f.motion.data(), info.model.skeleton,
                                     info.motion, f.info.frame_count, &frames));
    for (const DecodedFrame& fr : frames) {
      for (const BoneMotion& b : fr.bones) {
        Mix(&report->hash, b.rotation.c.data(), sizeof(b.rotation.c));
        Mix(&report->hash, b.translation_um.data(), sizeof(b.translation_um));
      }
    }
    report->frames += frames.size();
  }
  std::vector<uint8_t> masks;
  if (!f.masks.empty()) {
    masks.resize(shape.count());
    FVV_RETURN_IF_ERROR(
        DecodeMasks(f.masks.data(), f.masks.size(), shape, f.mask_mode, masks.data()));
    Mix(&report->hash, masks.data(), masks.size());
  }
  if (!f.vertex_visibility.empty()) {
    std::vector<uint8_t> bits;
    FVV_RETURN_IF_ERROR(DecodeVertexVisibility(
        f.vertex_visibility.data(), f.vertex_visibility.size(), shape.frames(), shape.cameras(),
        static_cast<uint32_t>(info.model.mesh.positions.size()), &bits));
  }
  if (f.predictive) {
    PredictiveGop gop;
    gop.frames = shape.frames(), gop.cameras = shape.cameras();
    gop.width = shape.width(), gop.height = shape.height();
    gop.mask = std::move(masks);
    PredictiveDecoded decoded;
    FVV_RETURN_IF_ERROR(
        DecodePredictive(f.predictive_texture, gop, &decoded, PredictiveDecodeOptions(), false));
    for (const auto& view : decoded.yuv) {
      for (const auto& p : view) Mix(&report->hash, p.data(), p.size() * sizeof(p[0]));
    }
  } else {
    FVV_ASSIGN_OR_RETURN(const Block block, DecodeBlock(f.texture, DecodeBudget(), SerialRunner));
    for (const Plane4D& p : block.channels) {
      Mix(&report->hash, p.samples.data(), p.samples.size() * sizeof(p.samples[0]));
    }
  }
  ++report->fragments;
  return Status::Ok();
}

}  // namespace

Status DecodeAll(const uint8_t* data, size_t size, size_t chunk, DecodeAllReport* report) {
  *report = DecodeAllReport();
  report->hash = 0xcbf29ce484222325ull;
  StreamReader reader;
  size_t pos = 0;
  for (;;) {
    FVV_ASSIGN_OR_RETURN(const ReaderEvent e, reader.Next());
    if (e == ReaderEvent::kEnd) return Status::Ok();
    if (e == ReaderEvent::kFragment) {
      FVV_RETURN_IF_ERROR(DecodeFragment(reader.info(), reader.fragment(), report));
    } else if (e == ReaderEvent::kNeedMoreInput) {
      if (pos == size) {
        reader.Finish();
        continue;
      }
      const size_t n = chunk == 0 ? size - pos : std::min(chunk, size - pos);
      reader.Push(data + pos, n);
      pos += n;
    }
  }
}

}  // namespace fvv
