#include "conformance/lib/reference_output.h"

#include <cstdio>
#include <cstring>
#include <memory>

#include "codec/base/thread_pool.h"
#include "container/file_reader.h"
#include "container/stream_reader.h"
#include "container/vertex_visibility.h"
#include "player/decoder/gop_decoder.h"
#include "player/decoder/view_pixels.h"

namespace fvv {
namespace {

void PutLe(uint64_t v, int bytes, std::vector<uint8_t>* out) {
  for (int i = 0; i < bytes; ++i) out->push_back(static_cast<uint8_t>(v >> (8 * i)));
}
void PutF32(float v, std::vector<uint8_t>* out) {
  uint32_t bits;
  std::memcpy(&bits, &v, 4);
  PutLe(bits, 4, out);
}
void PutF64(double v, std::vector<uint8_t>* out) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  PutLe(bits, 8, out);
}

// model.bin (Annex B.1): the decoded mesh and its skin.
std::vector<uint8_t> ModelOutput(const Mesh& m) {
  std::vector<uint8_t> out;
  const size_t n = m.positions.size();
  PutLe(n, 4, &out);
  PutLe(m.triangles.size(), 4, &out);
  for (size_t i = 0; i < n; ++i) {
    for (float v : m.positions[i]) PutF32(v, &out);
    for (float v : m.normals[i]) PutF32(v, &out);
    for (float v : m.uvs[i]) PutF32(v, &out);
    for (uint16_t v : m.joints[i]) PutLe(v, 2, &out);
    for (uint16_t v : m.weights[i]) PutLe(v, 2, &out);
  }
  for (const auto& t : m.triangles) {
    for (uint32_t v : t) PutLe(v, 4, &out);
  }
  return out;
}

// cameras.bin (Annex B.1): every camera's calibration as decoded.
std::vector<uint8_t> CamerasOutput(const std::vector<Camera>& cameras) {
  std::vector<uint8_t> out;
  for (const Camera& c : cameras) {
    PutLe(c.width, 4, &out);
    PutLe(c.height, 4, &out);
    for (double v : {c.fx, c.fy, c.cx, c.cy}) PutF64(v, &out);
    for (double v : c.distortion) PutF64(v, &out);
    for (double v : c.rotation) PutF64(v, &out);
    for (double v : c.translation) PutF64(v, &out);
  }
  return out;
}

// Collects the fragments of one GOP time span (they follow each other in GOP
// index order) and emits the span's output files once it is complete.
class SpanEmitter {
 public:
  SpanEmitter(const ReferenceDecodeOptions& options, const OutputSink& sink)
      : options_(options), sink_(sink), pool_(options.threads) {}

  Status Add(const StreamInfo& info, FragmentData fragment) {
    if (!span_.empty() && span_[0].info.first_frame != fragment.info.first_frame) {
      FVV_RETURN_IF_ERROR(Flush(info));
    }
    span_.push_back(std::move(fragment));
    return Status::Ok();
  }

  Status Flush(const StreamInfo& info) {
    if (span_.empty()) return Status::Ok();
    GopBudget budget;
    budget.max_bytes = options_.bytes_per_fragment;
    // A budget is the prefix of each fragment delivered (SPEC.md Annex B.2):
    // one that ends inside a chunked fragment's head is Truncated.
    for (const FragmentData& f : span_) {
      if (f.chunked) FVV_RETURN_IF_ERROR(ChunkedPrefixBytes(f, budget.max_bytes).status());
    }
    FVV_ASSIGN_OR_RETURN(const auto gop,
                         DecodeGop(info, span_, budget, pool_.runner(), pool_.size()));
    for (const DecodedFrame& frame : gop->motion) {
      for (const BoneMotion& bone : frame.bones) {
        for (int32_t q : bone.rotation.c) PutLe(static_cast<uint32_t>(q), 4, &motion_);
        for (int64_t t : bone.translation_um) PutLe(static_cast<uint64_t>(t), 8, &motion_);
      }
    }
    for (size_t t = 0; t < gop->surface.size(); ++t) {
      std::vector<uint8_t> bytes;
      bytes.reserve(gop->surface[t].size() * 4);
      for (float v : gop->surface[t]) PutF32(v, &bytes);
      char name[32];
      std::snprintf(name, sizeof(name), "surface_%06u.bin", unsigned(gop->first_frame + t));
      FVV_RETURN_IF_ERROR(sink_(name, bytes));
    }
    for (size_t g = 0; g < span_.size(); ++g) {
      FVV_RETURN_IF_ERROR(EmitGroup(info, span_[g], *gop, g));
    }
    span_.clear();
    return Status::Ok();
  }

  Status Finish(const StreamInfo& info) {
    FVV_RETURN_IF_ERROR(Flush(info));
    FVV_RETURN_IF_ERROR(sink_("model.bin", ModelOutput(info.model.mesh)));
    FVV_RETURN_IF_ERROR(sink_("cameras.bin", CamerasOutput(info.cameras)));
    return sink_("motion.bin", motion_);
  }

 private:
  Status EmitGroup(const StreamInfo& info, const FragmentData& f, const DecodedGop& gop, size_t g) {
    const Block& block = gop.textures[g];
    const Shape4D& luma = block.shape();
    const uint32_t nv = static_cast<uint32_t>(info.model.mesh.positions.size());
    std::vector<uint8_t> vvis;
    if (!f.vertex_visibility.empty()) {
      FVV_RETURN_IF_ERROR(DecodeVertexVisibility(f.vertex_visibility.data(),
                                                 f.vertex_visibility.size(), luma.frames(),
                                                 luma.cameras(), nv, &vvis));
    }
    const size_t texels = size_t{luma.height()} * luma.width();
    for (uint32_t t = 0; t < luma.frames(); ++t) {
      for (uint32_t c = 0; c < luma.cameras(); ++c) {
        const uint32_t frame = f.info.first_frame + t, camera = f.info.first_camera + c;
        std::vector<uint8_t> yuv;
        for (const Plane4D& plane : block.channels) {
          const size_t n = size_t{plane.shape.height()} * plane.shape.width();
          const size_t first = (size_t{t} * plane.shape.cameras() + c) * n;
          yuv.reserve(yuv.size() + 2 * n);
          for (size_t i = 0; i < n; ++i) {
            PutLe(static_cast<uint16_t>(static_cast<int16_t>(plane.samples[first + i])), 2, &yuv);
          }
        }
        FVV_RETURN_IF_ERROR(sink_(OutputName("yuv", frame, camera), yuv));
        std::unique_ptr<uint8_t[]> rgb;
        ViewPixels(block, t, c, ViewFormat::kRgb8, &rgb);
        FVV_RETURN_IF_ERROR(sink_(OutputName("rgb", frame, camera),
                                  std::vector<uint8_t>(rgb.get(), rgb.get() + texels * 3)));
        const size_t plane_index = size_t{t} * luma.cameras() + c;
        if (!gop.masks[g].empty()) {
          const auto begin = gop.masks[g].begin() + plane_index * texels;
          FVV_RETURN_IF_ERROR(sink_(OutputName("mask", frame, camera),
                                    std::vector<uint8_t>(begin, begin + texels)));
        }
        if (!vvis.empty()) {
          const auto begin = vvis.begin() + plane_index * nv;
          FVV_RETURN_IF_ERROR(
              sink_(OutputName("vvis", frame, camera), std::vector<uint8_t>(begin, begin + nv)));
        }
      }
    }
    return Status::Ok();
  }

  const ReferenceDecodeOptions& options_;
  const OutputSink& sink_;
  ThreadPool pool_;
  std::vector<FragmentData> span_;
  std::vector<uint8_t> motion_;
};

Status DecodeRandomAccess(const uint8_t* data, size_t size, SpanEmitter* emitter) {
  MemorySource source(data, size);
  FVV_ASSIGN_OR_RETURN(auto reader, FileReader::Open(&source));
  for (size_t i = 0; i < reader->fragment_count(); ++i) {
    FVV_ASSIGN_OR_RETURN(FragmentData f, reader->ReadFragment(i));
    FVV_RETURN_IF_ERROR(emitter->Add(reader->info(), std::move(f)));
  }
  return emitter->Finish(reader->info());
}

Status DecodeStreaming(const uint8_t* data, size_t size, SpanEmitter* emitter) {
  StreamReader reader;
  reader.Push(data, size);
  reader.Finish();
  for (;;) {
    FVV_ASSIGN_OR_RETURN(const ReaderEvent event, reader.Next());
    if (event == ReaderEvent::kEnd) break;
    if (event == ReaderEvent::kNeedMoreInput) {
      return Internal("streaming reader asked for input after Finish()");
    }
    if (event == ReaderEvent::kFragment) {
      FVV_RETURN_IF_ERROR(emitter->Add(reader.info(), reader.TakeFragment()));
    }
  }
  return emitter->Finish(reader.info());
}

}  // namespace

std::string OutputName(const char* stem, uint32_t frame, uint32_t camera) {
  char name[64];
  std::snprintf(name, sizeof(name), "%s_%06u_%03u.bin", stem, frame, camera);
  return name;
}

Status ReferenceDecode(const uint8_t* data, size_t size, const ReferenceDecodeOptions& options,
                       const OutputSink& sink) {
  SpanEmitter emitter(options, sink);
  return options.path == ReadPath::kStreaming ? DecodeStreaming(data, size, &emitter)
                                              : DecodeRandomAccess(data, size, &emitter);
}

}  // namespace fvv
