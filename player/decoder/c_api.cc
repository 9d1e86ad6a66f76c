// The C API of include/fvv/fvv_decoder.h over fvv::Decoder: argument checks,
// status codes and messages, and the flat arrays C callers read.
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "fvv/fvv_decoder.h"
#include "player/decoder/c_api_internal.h"
#include "player/decoder/decoder.h"

static_assert(FVV_FORMAT_VERSION == fvv::kFormatVersion,
              "the public header and the container must agree on the format version");
#include "player/decoder/pose.h"
#include "player/decoder/public_camera.h"
#include "player/decoder/view_pixels.h"

struct fvv_decoder {
  explicit fvv_decoder(const fvv_decoder_settings& s) : impl(s) {}
  fvv::Decoder impl;
  fvv::Status status;  // of the last call
  std::string error;   // status.ToString(), what fvv_decoder_error returns
  // The model as flat arrays, built on first request.
  bool model_built = false;
  std::vector<int32_t> parents;
  std::vector<glm::mat4> rest_world, rest_inverse;
  std::vector<float> positions, normals, uvs, weights;
  std::vector<uint16_t> joints;
  std::vector<uint32_t> triangles;
};

namespace {

struct FrameImpl {
  fvv_frame frame;  // first member: fvv_frame* and FrameImpl* convert by reinterpret_cast
  std::vector<float> world, skin;
  std::vector<fvv_view> views;
  // Uninitialised on allocation: every byte is written by ViewPixels, and
  // zero-filling megabytes per frame first would cost a pass over memory.
  std::vector<std::unique_ptr<uint8_t[]>> pixels;
  std::shared_ptr<const fvv::DecodedGop> gop;  // keeps the masks alive
};

fvv_status Report(fvv_decoder* d, const fvv::Status& s) {
  if (d) {
    d->status = s;
    d->error = s.ok() ? std::string() : s.ToString();
  }
  return static_cast<fvv_status>(s.code());
}

fvv_status Misuse(fvv_decoder* d, const char* what) {
  return Report(d, fvv::InvalidArgument(what));
}

void BuildModel(fvv_decoder* d) {
  if (d->model_built) return;
  const fvv::BodyModel& m = d->impl.info().model;
  d->rest_world = fvv::RestWorldTransforms(m.skeleton);
  for (const glm::mat4& w : d->rest_world) d->rest_inverse.push_back(glm::inverse(w));
  for (const fvv::Bone& b : m.skeleton.bones) d->parents.push_back(b.parent);
  for (size_t v = 0; v < m.mesh.positions.size(); ++v) {
    for (int k = 0; k < 3; ++k) d->positions.push_back(m.mesh.positions[v][k]);
    for (int k = 0; k < 3; ++k) d->normals.push_back(m.mesh.normals[v][k]);
    for (int k = 0; k < 2; ++k) d->uvs.push_back(m.mesh.uvs[v][k]);
    for (int k = 0; k < 4; ++k) {
      d->joints.push_back(m.mesh.joints[v][k]);
      d->weights.push_back(m.mesh.weights[v][k] / 65535.0f);
    }
  }
  for (const auto& t : m.mesh.triangles)
    d->triangles.insert(d->triangles.end(), t.begin(), t.end());
  d->model_built = true;
}

// The getters' common precondition: a decoder and an output, after READY.
fvv_status RequireReady(fvv_decoder* d, const void* out, const char* what) {
  if (!d || !out) return Misuse(d, (std::string(what) + ": NULL argument").c_str());
  if (!d->impl.ready()) return Misuse(d, (std::string(what) + " before FVV_EVENT_READY").c_str());
  return FVV_OK;
}

fvv::GopBudget ToGopBudget(const fvv_decode_budget* budget) {
  fvv::GopBudget gb;
  if (budget) {
    gb.max_bytes = budget->max_bytes_per_gop;
    gb.max_ms = budget->max_ms_per_gop > 0 ? budget->max_ms_per_gop : 0;
    gb.cameras = budget->camera_mask;
    gb.floor_share = gb.max_ms > 0 && budget->floor_share > 0 ? budget->floor_share : 0;
  }
  return gb;
}

}  // namespace

namespace fvv {

const StreamInfo* DecoderStreamInfo(const fvv_decoder* decoder) {
  return decoder && decoder->impl.ready() ? &decoder->impl.info() : nullptr;
}

fvv_status ReportDecoderStatus(fvv_decoder* decoder, const Status& status) {
  return Report(decoder, status);
}

Status DecoderStatus(const fvv_decoder* decoder) {
  return decoder ? decoder->status : InvalidArgument("no decoder");
}

}  // namespace fvv

extern "C" {

void fvv_decoder_default_settings(fvv_decoder_settings* settings) {
  if (!settings) return;
  settings->threads = 0;
  settings->memory_cap_bytes = 0;
  settings->decode_ahead = 1;
  settings->max_gop_samples = 0;
  settings->max_fragment_bytes = 0;
}

fvv_status fvv_decoder_create(const fvv_decoder_settings* settings, fvv_decoder** decoder) {
  if (!decoder) return FVV_INVALID_ARGUMENT;
  *decoder = nullptr;
  fvv_decoder_settings s;
  fvv_decoder_default_settings(&s);
  if (settings) s = *settings;
  if (s.threads > 256) return FVV_INVALID_ARGUMENT;
  *decoder = new (std::nothrow) fvv_decoder(s);
  return *decoder ? FVV_OK : FVV_OUT_OF_MEMORY;
}

void fvv_decoder_destroy(fvv_decoder* decoder) { delete decoder; }

const char* fvv_decoder_error(const fvv_decoder* decoder) {
  return decoder ? decoder->error.c_str() : "no decoder";
}

fvv_status fvv_decoder_open_file(fvv_decoder* d, const char* path) {
  if (!d || !path) return Misuse(d, "open_file: NULL argument");
  return Report(d, d->impl.OpenFile(path));
}

fvv_status fvv_decoder_open_ranges(fvv_decoder* d, uint64_t stream_size) {
  if (!d) return FVV_INVALID_ARGUMENT;
  return Report(d, d->impl.OpenRanges(stream_size));
}

fvv_status fvv_decoder_add_range(fvv_decoder* d, uint64_t offset, const uint8_t* data,
                                 size_t size) {
  if (!d || (!data && size > 0)) return Misuse(d, "add_range: NULL argument");
  return Report(d, d->impl.AddRange(offset, data, size));
}

int fvv_decoder_wanted_range(const fvv_decoder* d, uint64_t* offset, uint64_t* size) {
  if (!d || !offset || !size) return 0;
  return d->impl.WantedRange(offset, size) ? 1 : 0;
}

uint32_t fvv_decoder_fragment_count(const fvv_decoder* d) {
  if (!d || !d->impl.ready() || !d->impl.random_access()) return 0;
  return static_cast<uint32_t>(d->impl.info().index.size());
}

fvv_status fvv_decoder_get_fragment(const fvv_decoder* cd, uint32_t index, fvv_fragment_info* out) {
  fvv_decoder* d = const_cast<fvv_decoder*>(cd);
  if (const fvv_status s = RequireReady(d, out, "get_fragment"); s != FVV_OK) return s;
  if (!d->impl.random_access()) {
    return Misuse(d, "get_fragment: a pushed stream has no fragment ranges");
  }
  const std::vector<fvv::IndexEntry>& index_entries = d->impl.info().index;
  if (index >= index_entries.size()) {
    return Misuse(d, ("get_fragment: fragment " + std::to_string(index) + " of " +
                      std::to_string(index_entries.size()))
                         .c_str());
  }
  const fvv::IndexEntry& e = index_entries[index];
  *out = fvv_fragment_info{};
  out->first_frame = e.first_frame;
  out->frame_count = e.frame_count;
  out->first_camera = e.first_camera;
  out->camera_count = e.camera_count;
  out->offset = e.offset;
  out->size = e.size;
  out->head_size = e.head_size != 0 ? e.head_size : e.size;
  out->held = d->impl.FragmentBytesHeld(index);
  out->surface_size = d->impl.FragmentSurfaceBytes(index);
  return FVV_OK;
}

fvv_status fvv_decoder_push(fvv_decoder* d, const uint8_t* data, size_t size) {
  if (!d || (!data && size > 0)) return Misuse(d, "push: NULL argument");
  return Report(d, d->impl.Push(data, size));
}

fvv_status fvv_decoder_push_end(fvv_decoder* d) {
  if (!d) return FVV_INVALID_ARGUMENT;
  return Report(d, d->impl.PushEnd());
}

fvv_status fvv_decoder_process(fvv_decoder* d, fvv_event* event) {
  if (!d || !event) return Misuse(d, "process: NULL argument");
  auto e = d->impl.Process();
  if (!e.ok()) return Report(d, e.status());
  *event = *e;
  return Report(d, fvv::Status::Ok());
}

uint32_t fvv_decoder_frames_available(const fvv_decoder* d) {
  return d ? d->impl.frames_available() : 0;
}

fvv_status fvv_decoder_get_info(const fvv_decoder* cd, fvv_stream_info* out) {
  fvv_decoder* d = const_cast<fvv_decoder*>(cd);
  if (const fvv_status s = RequireReady(d, out, "get_info"); s != FVV_OK) return s;
  const fvv::StreamInfo& si = d->impl.info();
  const fvv::FileHeader& h = si.header;
  *out = fvv_stream_info{};
  out->format_version = h.format_version;
  out->profile = static_cast<uint32_t>(h.profile);
  out->level = h.level;
  out->frame_count = h.frame_count;
  out->frame_rate_num = h.frame_rate_num;
  out->frame_rate_den = h.frame_rate_den;
  out->camera_count = h.camera_count;
  out->atlas_width = h.atlas_width;
  out->atlas_height = h.atlas_height;
  out->gop_frames = h.gop_frames;
  out->gop_cameras = h.gop_cameras;
  out->bone_count = static_cast<uint32_t>(si.model.skeleton.bones.size());
  out->vertex_count = static_cast<uint32_t>(si.model.mesh.positions.size());
  out->triangle_count = static_cast<uint32_t>(si.model.mesh.triangles.size());
  out->has_masks = (h.tools & fvv::kToolMasks) != 0;
  return Report(d, fvv::Status::Ok());
}

fvv_status fvv_decoder_get_camera(const fvv_decoder* cd, uint32_t index, fvv_camera* out) {
  fvv_decoder* d = const_cast<fvv_decoder*>(cd);
  if (const fvv_status s = RequireReady(d, out, "get_camera"); s != FVV_OK) return s;
  const auto& cams = d->impl.info().cameras;
  if (index >= cams.size()) return Misuse(d, "get_camera: index beyond the camera count");
  *out = fvv::PublicCamera(cams[index]);
  return Report(d, fvv::Status::Ok());
}

fvv_status fvv_decoder_get_model(const fvv_decoder* cd, fvv_model* out) {
  fvv_decoder* d = const_cast<fvv_decoder*>(cd);
  if (const fvv_status s = RequireReady(d, out, "get_model"); s != FVV_OK) return s;
  BuildModel(d);
  out->bone_count = static_cast<uint32_t>(d->parents.size());
  out->bone_parent = d->parents.data();
  out->bone_rest_world = glm::value_ptr(d->rest_world[0]);
  out->vertex_count = static_cast<uint32_t>(d->positions.size() / 3);
  out->positions = d->positions.data();
  out->normals = d->normals.data();
  out->uvs = d->uvs.data();
  out->joints = d->joints.data();
  out->weights = d->weights.data();
  out->triangle_count = static_cast<uint32_t>(d->triangles.size() / 3);
  out->triangles = d->triangles.data();
  return Report(d, fvv::Status::Ok());
}

fvv_status fvv_decoder_decode_frame(fvv_decoder* d, uint32_t index, const fvv_decode_budget* budget,
                                    fvv_frame** frame) {
  if (!d || !frame) return Misuse(d, "decode_frame: NULL argument");
  *frame = nullptr;
  fvv_decode_budget b{};
  if (budget) b = *budget;
  if (b.format != FVV_FORMAT_RGB8 && b.format != FVV_FORMAT_YUV444) {
    return Misuse(d, "decode_frame: unknown pixel format");
  }
  if (!(b.max_ms_per_gop >= 0)) return Misuse(d, "decode_frame: negative time budget");
  if (!(b.floor_share >= 0 && b.floor_share <= 1)) {
    return Misuse(d, "decode_frame: floor_share outside 0..1");
  }
  if (d->impl.ready() && b.camera_mask != 0 && d->impl.info().header.camera_count < 64 &&
      (b.camera_mask >> d->impl.info().header.camera_count) != 0) {
    return Misuse(d, "decode_frame: camera_mask names cameras the stream does not have");
  }
  if (d->impl.ready() && b.format == FVV_FORMAT_YUV444 &&
      (d->impl.info().header.tools & fvv::kToolReversibleColour)) {
    return Misuse(d, "decode_frame: RCT (lossless) streams have no 8-bit YUV form; ask for RGB8");
  }
  auto gop = d->impl.Gop(index, ToGopBudget(&b));
  if (!gop.ok()) return Report(d, gop.status());
  BuildModel(d);
  const fvv::StreamInfo& si = d->impl.info();
  const fvv::DecodedGop& g = **gop;
  auto* impl = new (std::nothrow) FrameImpl();
  if (!impl) return Report(d, fvv::Status(fvv::StatusCode::kOutOfMemory, "frame"));
  impl->gop = *gop;
  const uint32_t t = index - g.first_frame;
  const auto world = fvv::WorldTransforms(si.model.skeleton, g.motion[t].bones);
  for (size_t bone = 0; bone < world.size(); ++bone) {
    const glm::mat4 skin = world[bone] * d->rest_inverse[bone];
    impl->world.insert(impl->world.end(), glm::value_ptr(world[bone]),
                       glm::value_ptr(world[bone]) + 16);
    impl->skin.insert(impl->skin.end(), glm::value_ptr(skin), glm::value_ptr(skin) + 16);
  }
  const uint32_t cameras = si.header.camera_count;
  impl->pixels.resize(cameras);
  impl->views.resize(cameras);
  const size_t texels = size_t{si.header.atlas_width} * si.header.atlas_height;
  // On the calling thread: the pool may be busy decoding the next GOP ahead,
  // and waiting for it would stall the frame.
  for (uint32_t c = 0; c < cameras; ++c) {
    const uint32_t group = c / si.header.gop_cameras;
    const uint32_t local = c - g.groups[group].first_camera;
    if (!g.decoded[group]) {  // left out by the budget's camera_mask
      impl->views[c].pixels = nullptr;
      impl->views[c].mask = nullptr;
      continue;
    }
    fvv::ViewPixels(g.textures[group], t, local,
                    b.format == FVV_FORMAT_RGB8 ? fvv::ViewFormat::kRgb8 : fvv::ViewFormat::kYuv444,
                    &impl->pixels[c]);
    impl->views[c].pixels = impl->pixels[c].get();
    const auto& masks = g.masks[group];
    const uint32_t group_cameras = g.groups[group].camera_count;
    impl->views[c].mask =
        masks.empty() ? nullptr : masks.data() + (size_t{t} * group_cameras + local) * texels;
  }
  fvv_frame& f = impl->frame;
  f.index = index;
  f.bone_count = static_cast<uint32_t>(world.size());
  f.bone_world = impl->world.data();
  f.bone_skin = impl->skin.data();
  f.camera_count = cameras;
  f.width = si.header.atlas_width;
  f.height = si.header.atlas_height;
  f.format = static_cast<fvv_pixel_format>(b.format);
  f.views = impl->views.data();
  f.report.bytes_decoded = g.bytes_decoded;
  f.report.bytes_available = g.bytes_available;
  for (int c = 0; c < 3; ++c) f.report.bitplanes[c] = static_cast<uint32_t>(g.bitplanes[c]);
  f.report.decode_ms = g.ms;
  f.report.complete = g.complete;
  f.report.max_ms_per_gop = g.budget.max_ms;
  f.surface = g.surface.empty() ? nullptr : g.surface[t].data();
  *frame = &impl->frame;
  return Report(d, fvv::Status::Ok());
}

void fvv_frame_release(fvv_frame* frame) { delete reinterpret_cast<FrameImpl*>(frame); }

fvv_status fvv_decoder_prefetch(fvv_decoder* d, uint32_t index, const fvv_decode_budget* budget) {
  if (!d) return FVV_INVALID_ARGUMENT;
  return Report(d, d->impl.Prefetch(index, ToGopBudget(budget)));
}

int fvv_decoder_frame_ready(fvv_decoder* d, uint32_t index, const fvv_decode_budget* budget) {
  return d ? d->impl.Ready(index, ToGopBudget(budget)) : 0;
}

}  // extern "C"
