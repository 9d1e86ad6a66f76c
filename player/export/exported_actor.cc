#include "player/export/exported_actor.h"

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <string>

#include "fvv/fvv_decoder.hpp"
#include "player/decoder/c_api_internal.h"
#include "player/export/texture_blend.h"

namespace fvv {

StatusOr<ExportedActor> GatherActor(fvv_decoder* decoder, const fvv_export_settings& s,
                                    bool with_texture) {
  const StreamInfo* si = DecoderStreamInfo(decoder);
  if (!si) return InvalidArgument("export before the stream's header boxes were read");
  const uint32_t available = fvv_decoder_frames_available(decoder);
  if (s.first_frame >= available) {
    return InvalidArgument("export from frame " + std::to_string(s.first_frame) +
                           ": the stream has " + std::to_string(available) + " frames available");
  }
  const uint32_t count = s.frame_count ? s.frame_count : available - s.first_frame;
  if (uint64_t{s.first_frame} + count > available) {
    return InvalidArgument("export of frames " + std::to_string(s.first_frame) + ".." +
                           std::to_string(uint64_t{s.first_frame} + count - 1) +
                           ": the stream has " + std::to_string(available) + " frames available");
  }
  if (with_texture && s.texture_frame >= 0 &&
      (uint32_t(s.texture_frame) < s.first_frame ||
       uint32_t(s.texture_frame) >= s.first_frame + count)) {
    return InvalidArgument("texture frame " + std::to_string(s.texture_frame) +
                           " is outside the frames exported");
  }
  if (s.texture_size > 8192) {
    return InvalidArgument("texture size " + std::to_string(s.texture_size) + " (at most 8192)");
  }
  fvv_stream_info info;
  fvv_model model;
  fvv_decoder_get_info(decoder, &info);
  if (fvv_decoder_get_model(decoder, &model) != FVV_OK) return DecoderStatus(decoder);

  ExportedActor a;
  a.fps = double(info.frame_rate_num) / info.frame_rate_den;
  a.first_frame = s.first_frame;
  for (const Bone& b : si->model.skeleton.bones) {
    ExportedJoint j;
    j.name = b.name;
    j.parent = b.parent;
    j.rest_translation =
        glm::vec3(b.rest_translation[0], b.rest_translation[1], b.rest_translation[2]);
    j.rest_rotation = glm::normalize(
        glm::quat(b.rest_rotation[0], b.rest_rotation[1], b.rest_rotation[2], b.rest_rotation[3]));
    j.order = b.order;
    a.joints.push_back(j);
  }
  const size_t bones = a.joints.size();
  for (size_t b = 0; b < bones; ++b) {
    a.inverse_bind.push_back(glm::inverse(glm::make_mat4(model.bone_rest_world + 16 * b)));
  }
  a.positions.assign(model.positions, model.positions + 3 * size_t(model.vertex_count));
  a.normals.assign(model.normals, model.normals + 3 * size_t(model.vertex_count));
  a.uvs.assign(model.uvs, model.uvs + 2 * size_t(model.vertex_count));
  a.weights.assign(model.weights, model.weights + 4 * size_t(model.vertex_count));
  a.skin_joints.assign(model.joints, model.joints + 4 * size_t(model.vertex_count));
  a.triangles.assign(model.triangles, model.triangles + 3 * size_t(model.triangle_count));

  std::unique_ptr<TextureBlend> blend;
  if (with_texture) {
    std::vector<fvv_camera> cameras(info.camera_count);
    for (uint32_t c = 0; c < info.camera_count; ++c)
      fvv_decoder_get_camera(decoder, c, &cameras[c]);
    blend = std::make_unique<TextureBlend>(model, info.atlas_width, info.atlas_height, cameras);
  }
  fvv_decode_budget budget{};
  if (!with_texture) {
    // The motion (and the surface) is all that is needed: camera group 0,
    // one byte of it where no surface can follow its head.
    budget.max_bytes_per_gop = info.format_version >= 12 ? 0 : 1;
    budget.camera_mask = 1;
  }
  // A morph target per frame where frames carry a surface: bounded, so that a
  // long range fails here and not as an allocation.
  constexpr uint64_t kMaxSurfaceBytes = 512ull << 20;
  bool any_surface = false;
  for (uint32_t f = s.first_frame; f < s.first_frame + count; ++f) {
    FramePtr frame = DecodeFrame(decoder, f, &budget);
    if (!frame) {
      return Corrupt("frame " + std::to_string(f) + ": " + fvv_decoder_error(decoder));
    }
    std::vector<glm::mat4> world(bones);
    std::vector<glm::vec3> translation(bones);
    std::vector<glm::quat> rotation(bones);
    for (size_t b = 0; b < bones; ++b) {
      world[b] = glm::make_mat4(frame->bone_world + 16 * b);
      // The local transform is what the parent's world leaves: T * R, no scale.
      const glm::mat4 local =
          a.joints[b].parent >= 0 ? glm::inverse(world[a.joints[b].parent]) * world[b] : world[b];
      translation[b] = glm::vec3(local[3]);
      rotation[b] = glm::normalize(glm::quat_cast(glm::mat3(local)));
      // q and -q are the same rotation; keyframes keep to one hemisphere so
      // that interpolating between them takes the short way.
      if (!a.rotation.empty() && glm::dot(rotation[b], a.rotation.back()[b]) < 0) {
        rotation[b] = -rotation[b];
      }
    }
    if (frame->surface) {
      if (uint64_t(count) * model.vertex_count * 12 > kMaxSurfaceBytes) {
        return InvalidArgument("the stream carries the surface of every frame: " +
                               std::to_string(count) + " frames of it as morph targets would " +
                               "take more than 512 MB; export fewer frames (--frames)");
      }
      if (!any_surface) {
        a.surface_deltas.assign(a.world.size(), std::vector<float>(a.positions.size(), 0.0f));
      }
      any_surface = true;
      std::vector<float> delta(a.positions.size());
      for (size_t i = 0; i < delta.size(); ++i) delta[i] = frame->surface[i] - a.positions[i];
      a.surface_deltas.push_back(std::move(delta));
    } else if (any_surface) {
      a.surface_deltas.emplace_back(a.positions.size(), 0.0f);
    }
    a.world.push_back(std::move(world));
    a.translation.push_back(std::move(translation));
    a.rotation.push_back(std::move(rotation));
    if (blend && (s.texture_frame < 0 || uint32_t(s.texture_frame) == f)) blend->Add(*frame);
  }
  if (blend) {
    a.texture_rgb = blend->Finish(s.texture_size);
    a.texture_width = s.texture_size ? s.texture_size : info.atlas_width;
    a.texture_height = s.texture_size ? s.texture_size : info.atlas_height;
  }
  return a;
}

}  // namespace fvv
