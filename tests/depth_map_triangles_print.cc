// Prints the triangles the native players' depth maps draw for a stream's
// body model (player/playback/depth_map_triangles.h) as "COUNT FNV1A32": the
// count of indices and their hash, which tests/web_decoder_test.mjs compares
// with the WebAssembly module's, so that both players draw the same triangles.
//
//   depth_map_triangles_print STREAM
#include <cstdio>
#include <vector>

#include "fvv/fvv_decoder.hpp"
#include "player/playback/depth_map_triangles.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: depth_map_triangles_print STREAM\n");
    return 2;
  }
  fvv::DecoderPtr decoder = fvv::MakeDecoder();
  if (!decoder) {
    std::fprintf(stderr, "depth_map_triangles_print: cannot create a decoder\n");
    return 1;
  }
  fvv_model model;
  if (fvv_decoder_open_file(decoder.get(), argv[1]) != FVV_OK ||
      fvv_decoder_get_model(decoder.get(), &model) != FVV_OK) {
    std::fprintf(stderr, "%s: %s\n", argv[1], fvv_decoder_error(decoder.get()));
    return 1;
  }
  const std::vector<uint32_t> triangles = fvv::DepthMapTriangles(
      model.positions, model.vertex_count, model.triangles, model.triangle_count);
  uint32_t hash = 2166136261u;
  for (uint32_t i : triangles) {
    hash ^= i;
    hash *= 16777619u;
  }
  std::printf("%zu %08x\n", triangles.size(), hash);
  return 0;
}
