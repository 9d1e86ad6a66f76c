#include "tools/fvv/export_command.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "fvv/fvv_decoder.hpp"
#include "fvv/fvv_export.h"
#include "tools/fvv/frame_range.h"

namespace fvv {
namespace {

bool EndsWith(const std::string& s, const char* suffix) {
  const std::string x(suffix);
  return s.size() >= x.size() && s.compare(s.size() - x.size(), x.size(), x) == 0;
}

}  // namespace

void AddExportCommand(CLI::App* app, int* exit_code) {
  struct Args {
    std::string input, output, frames;
    int texture_frame = -1;
    uint32_t texture_size = 0;
    bool quiet = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* e = app->add_subcommand(
      "export", "Export the actor for other tools: glTF 2.0 (.glb, .gltf) or BVH (.bvh)");
  e->footer(
      "glTF: the decoded body model as a skinned mesh (joint hierarchy, inverse bind matrices, "
      "atlas UVs), the motion track as an animation at the stream's frame rate, and one colour "
      "texture blended from the camera textures over the frames exported (each texel from the "
      "cameras whose masks say they saw it, weighted by how squarely), or one frame's with "
      "--texture-frame. Blender, three.js, Unity and other engines read it. .gltf writes its "
      "buffer and texture beside it (STEM.bin, STEM.png).\n"
      "BVH: the motion on the model's skeleton (offsets in centimetres, Euler angles in each "
      "joint's rotation order).\n"
      "Examples: fvv export take.fvv -o actor.glb\n"
      "          fvv export take.fvv -o motion.bvh --frames 0:99");
  e->add_option("stream", a->input, ".fvv stream")->required()->check(CLI::ExistingFile);
  e->add_option("-o,--output", a->output, "The file to write: .glb, .gltf or .bvh")->required();
  e->add_option("--frames", a->frames, "Frames to export: A:B (inclusive); default all");
  e->add_option("--texture-frame", a->texture_frame,
                "glTF: the texture of this frame only, not blended over the frames exported")
      ->check(CLI::NonNegativeNumber);
  e->add_option("--texture-size", a->texture_size,
                "glTF: the texture's width and height in texels (default: the atlas's)")
      ->check(CLI::Range(16u, 8192u));
  e->add_flag("-q,--quiet", a->quiet, "No summary");
  e->callback([a, exit_code] {
    *exit_code = 1;
    const bool bvh = EndsWith(a->output, ".bvh");
    if (!bvh && !EndsWith(a->output, ".glb") && !EndsWith(a->output, ".gltf")) {
      std::fprintf(stderr, "fvv: --output %s: export writes .glb, .gltf or .bvh\n",
                   a->output.c_str());
      return;
    }
    DecoderPtr dec = MakeDecoder();
    if (!dec || fvv_decoder_open_file(dec.get(), a->input.c_str()) != FVV_OK) {
      std::fprintf(stderr, "fvv: %s\n", dec ? fvv_decoder_error(dec.get()) : "no decoder");
      return;
    }
    fvv_stream_info info;
    fvv_decoder_get_info(dec.get(), &info);
    fvv_export_settings s;
    fvv_export_default_settings(&s);
    if (!a->frames.empty()) {
      uint32_t first = 0, last = 0;
      const Status st = ParseFrameRange(a->frames, &first, &last);
      if (!st.ok()) {
        std::fprintf(stderr, "fvv: %s\n", st.ToString().c_str());
        return;
      }
      s.first_frame = first;
      s.frame_count = last - first + 1;
    }
    s.texture_frame = a->texture_frame;
    s.texture_size = a->texture_size;
    const auto start = std::chrono::steady_clock::now();
    const fvv_status r = bvh ? fvv_export_bvh(dec.get(), &s, a->output.c_str())
                             : fvv_export_gltf(dec.get(), &s, a->output.c_str());
    if (r != FVV_OK) {
      std::fprintf(stderr, "fvv: export to %s: %s\n", a->output.c_str(),
                   fvv_decoder_error(dec.get()));
      return;
    }
    const uint32_t frames = s.frame_count ? s.frame_count : info.frame_count - s.first_frame;
    if (!a->quiet) {
      fvv_model model;
      fvv_decoder_get_model(dec.get(), &model);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("wrote %s: %u joints, %u frames from %u at %.3g fps", a->output.c_str(),
                  model.bone_count, frames, s.first_frame,
                  double(info.frame_rate_num) / info.frame_rate_den);
      if (!bvh) {
        const uint32_t size = s.texture_size ? s.texture_size : info.atlas_width;
        std::printf(", %u vertices, %u triangles, texture %ux%u (%s)", model.vertex_count,
                    model.triangle_count, size, s.texture_size ? size : info.atlas_height,
                    s.texture_frame >= 0 ? ("frame " + std::to_string(s.texture_frame)).c_str()
                                         : "blended over the frames exported");
      }
      std::printf(" in %.1f s\n", seconds);
    }
    *exit_code = 0;
  });
}

}  // namespace fvv
