// Shape refinement benchmark: a synthetic capture whose
// actor has surface detail the generic model lacks (bumps and hollows up to
// --detail metres), with its true poses and proportions; the generic model,
// the visual hull and the refined model against the true surface (distances)
// and as seen from held-out cameras through Renderer I (PSNR). One table.
// Usage: shape_bench [--out DIR] [--detail M] [--width W --height H]
//                    [--cameras N] [--frame F] [--voxel M] and the refinement's
//                    weights: [--silhouette-weight W] [--stereo-weight W]
//                    [--regularisation W] [--iterations N] [--min-ncc C] [--patch R]
//                    [--contour COS] [--noise N (sensor noise, 8-bit levels)]
//                    [--features 0|1 (the truth's feature points as the features term)]
//                    [--feature-weight W] [--pose-error M (start from a pose this far off)]
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "tools/synth/shape_comparison.h"

int main(int argc, char** argv) {
  fvv::SynthOptions so;
  so.output_dir = "out/bench/shape/capture";
  so.frames = 1;
  so.held_out = 2;
  so.surface_detail = 0.03;
  so.link_silhouettes = true;
  uint32_t frame = 0;
  fvv::ShapeRefinementOptions ro;
  fvv::ComparisonOptions co;
  for (int i = 1; i < argc; i += 2) {
    // A flag without its value (or --help) falls through to the usage.
    const std::string a = i + 1 < argc ? argv[i] : "--help";
    const char* v = i + 1 < argc ? argv[i + 1] : "";
    if (a == "--out") {
      so.output_dir = std::string(v) + "/capture";
    } else if (a == "--detail") {
      so.surface_detail = std::atof(v);
    } else if (a == "--width") {
      so.width = uint32_t(std::atoi(v));
    } else if (a == "--height") {
      so.height = uint32_t(std::atoi(v));
    } else if (a == "--cameras") {
      so.cameras = uint32_t(std::atoi(v));
    } else if (a == "--frame") {
      frame = uint32_t(std::atoi(v));
      so.frames = frame + 1;
    } else if (a == "--silhouette-weight") {
      ro.silhouette_weight = std::atof(v);
    } else if (a == "--stereo-weight") {
      ro.stereo_weight = std::atof(v);
    } else if (a == "--regularisation") {
      ro.regularisation_weight = std::atof(v);
    } else if (a == "--iterations") {
      ro.iterations = std::atoi(v);
    } else if (a == "--min-ncc") {
      ro.min_ncc = std::atof(v);
    } else if (a == "--features") {
      co.features = std::atoi(v) != 0;
    } else if (a == "--pose-error") {
      co.pose_error = std::atof(v);
    } else if (a == "--feature-weight") {
      ro.feature_weight = std::atof(v);
    } else if (a == "--noise") {
      so.noise = std::atof(v);
    } else if (a == "--patch") {
      ro.patch_radius = std::atoi(v);
    } else if (a == "--contour") {
      ro.contour_cosine = std::atof(v);
    } else if (a == "--voxel") {
      ro.hull.voxel_size = std::atof(v);
    } else {
      std::fprintf(
          stderr,
          "usage: shape_bench [--out DIR] [--detail M] [--width W --height H] "
          "[--cameras N] [--frame F] [--voxel M] [--silhouette-weight W] [--stereo-weight W] "
          "[--regularisation W] [--iterations N] [--min-ncc C] [--patch R] [--contour COS] "
          "[--noise N]\n");
      return 2;
    }
  }
  std::system(("rm -rf '" + so.output_dir + "'").c_str());
  std::printf(
      "synthetic capture: %u cameras at %ux%u (+%u held out), surface detail %.3f m, "
      "frame %u, true poses and proportions\n",
      so.cameras, so.width, so.height, so.held_out, so.surface_detail, frame);
  auto synth = fvv::RunSynth(so);
  if (!synth.ok()) {
    std::fprintf(stderr, "%s\n", synth.status().ToString().c_str());
    return 1;
  }
  auto result = fvv::CompareShapes(so, frame, ro, co);
  if (!result.ok()) {
    std::fprintf(stderr, "%s\n", result.status().ToString().c_str());
    return 1;
  }
  for (const auto& l : result->refinement.levels) {
    std::printf(
        "  level %.0f mm: %zu stereo matches, %zu contour vertices, %zu outside the hull, "
        "mean move %.1f mm\n",
        l.range * 1e3, l.stereo_matches, l.contour_vertices, l.outside_hull, l.mean_move * 1e3);
  }
  std::printf("%s", result->Table().c_str());
  return 0;
}
