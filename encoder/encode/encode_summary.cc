// The summary fvv encode prints, and its JSON form (--summary-json).
#include <cstdarg>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "encoder/encode/encoder.h"

namespace fvv {

std::string EncodeSummary::Table() const {
  std::string out;
  char line[256];
  auto add = [&](const char* fmt, auto... args) {
    std::snprintf(line, sizeof(line), fmt, args...);
    out += line;
  };
  add("%s: %u frames (from %u) x %u cameras, atlas %ux%u, %u GOPs, level %u, pose source: %s\n",
      output.c_str(), frames, first_frame, cameras, atlas_size, atlas_size, gops, level,
      pose_source.c_str());
  add("  size              %12llu bytes   %9.1f kbps\n", (unsigned long long)file_bytes,
      kbps(file_bytes));
  add("    textures        %12llu bytes   %9.1f kbps\n", (unsigned long long)texture_bytes,
      kbps(texture_bytes));
  add("    masks           %12llu bytes   %9.1f kbps\n", (unsigned long long)mask_bytes,
      kbps(mask_bytes));
  add("    motion          %12llu bytes   %9.2f kbps\n", (unsigned long long)motion_bytes,
      kbps(motion_bytes));
  if (surface_bytes > 0) {
    add("    surface         %12llu bytes   %9.1f kbps  (%.1f %% of the stream)\n",
        (unsigned long long)surface_bytes, kbps(surface_bytes),
        100.0 * surface_bytes / std::max<uint64_t>(1, file_bytes));
  }
  add("    model, headers  %12llu bytes\n",
      (unsigned long long)(file_bytes - texture_bytes - mask_bytes - motion_bytes - surface_bytes));
  add("  compression       %8.1f:1 vs 24-bit RGB atlases, %.1f:1 vs visible texels (%.1f %% "
      "of atlas texels seen)\n",
      ratio_atlas(), ratio_visible(), 100.0 * visible_texels / std::max<uint64_t>(1, atlas_texels));
  add("  PSNR (visible)    Y %.2f dB  U %.2f dB  V %.2f dB  RGB %.2f dB\n", psnr[0], psnr[1],
      psnr[2], psnr_rgb);
  if (pose_source == "tracked") {
    add("  tracking          mean IoU %.3f, %d frame(s) flagged\n", mean_iou, flagged_frames);
  }
  if (surface_bytes > 0) {
    add("  surface           %.3f s per frame, mean |displacement| %.1f mm",
        surface_s / std::max(1u, frames), 1000 * surface_mean_abs);
    add("; stereo %g", surface_stereo_weight);
    if (surface_stereo_weight > 0) add(" (matches %.1f %% of the vertices)", 100 * surface_stereo);
    add(", pull to the previous frame %g", surface_temporal_weight);
    out += "\n";
  }
  if (fallback_texels > 0 || seamless_s > 0) {
    add("  seamless texture  %.3f s per frame; texel(s) no camera saw filled from the nearest "
        "frames that saw them %llu, from it %llu, from their mirror %llu\n",
        seamless_s / std::max(1u, frames), (unsigned long long)temporal_fill_texels,
        (unsigned long long)fallback_texels, (unsigned long long)mirror_fill_texels);
  }
  if (occluder_s > 0) {
    add("  occluders         %.3f s per frame; something else found in %u frame(s), %llu "
        "sample(s) behind it left out; %u camera frame(s) whose silhouette holds more than the "
        "actor checked against the others, %llu sample(s) dropped\n",
        occluder_s / std::max(1u, frames), occluder_frames, (unsigned long long)occluded_samples,
        suspect_camera_frames, (unsigned long long)suspect_dropped);
  }
  if (agreement_texels > 0) {
    add("  cameras' agreement %llu sample(s) no other camera backs dropped, of %llu texel(s) "
        "seen by 2 cameras or more\n",
        (unsigned long long)agreement_dropped, (unsigned long long)agreement_texels);
  }
  if (player_texels > 0) {
    add("  without masks     %llu texel(s) a player may take from a camera that did not see "
        "them; %.1f %% of them left to the fill\n",
        (unsigned long long)player_texels, 100.0 * player_texels_left / player_texels);
  }
  if (!refine_moves.empty()) {
    add("  shape refinement  %.1f s on the first frame, mean vertex move %.1f mm\n", refine_s, [&] {
      double sum = 0;
      for (double m : refine_moves) sum += m;
      return sum * 1e3;
    }());
  }
  const double f = std::max(1u, frames);
  add("  seconds per frame read %.3f  track %.3f  resample %.3f  code %.3f  write %.3f  "
      "total %.3f (%.2f frames/s)\n",
      read_s / f, track_s / f, resample_s / f, code_s / f, write_s / f, total_s / f,
      f / std::max(1e-9, total_s));
  return out;
}

std::string EncodeSummary::ToJson() const {
  nlohmann::json j = {
      {"output", output},
      {"level", level},
      {"first_frame", first_frame},
      {"frames", frames},
      {"cameras", cameras},
      {"atlas_size", atlas_size},
      {"gops", gops},
      {"poses", pose_source},
      {"bytes",
       {{"file", file_bytes},
        {"texture", texture_bytes},
        {"masks", mask_bytes},
        {"motion", motion_bytes},
        {"surface", surface_bytes}}},
      {"kbps",
       {{"file", kbps(file_bytes)},
        {"texture", kbps(texture_bytes)},
        {"masks", kbps(mask_bytes)},
        {"motion", kbps(motion_bytes)}}},
      {"atlas_texels", atlas_texels},
      {"visible_texels", visible_texels},
      {"ratio_atlas", ratio_atlas()},
      {"ratio_visible", ratio_visible()},
      {"psnr", {{"y", psnr[0]}, {"u", psnr[1]}, {"v", psnr[2]}, {"rgb", psnr_rgb}}},
      {"tracking", {{"mean_iou", mean_iou}, {"flagged", flagged_frames}}},
      {"seamless_texture",
       {{"seconds", seamless_s},
        {"temporal_fill_texels", temporal_fill_texels},
        {"fallback_texels", fallback_texels},
        {"mirror_fill_texels", mirror_fill_texels}}},
      {"agreement", {{"texels", agreement_texels}, {"dropped", agreement_dropped}}},
      {"occluders",
       {{"seconds_per_frame", occluder_s / std::max(1u, frames)},
        {"frames", occluder_frames},
        {"samples_left_out", occluded_samples},
        {"suspect_camera_frames", suspect_camera_frames},
        {"suspect_samples_dropped", suspect_dropped}}},
      {"without_masks",
       {{"player_texels", player_texels}, {"player_texels_left", player_texels_left}}},
      {"surface",
       {{"bytes", surface_bytes},
        {"seconds_per_frame", surface_s / std::max(1u, frames)},
        {"mean_abs_m", surface_mean_abs},
        {"stereo_share", surface_stereo},
        {"stereo_weight", surface_stereo_weight},
        {"temporal_weight", surface_temporal_weight}}},
      {"shape_refinement",
       {{"refined", !refine_moves.empty()},
        {"seconds", refine_s},
        {"mean_move_per_level_m", refine_moves}}},
      {"seconds",
       {{"read", read_s},
        {"track", track_s},
        {"resample", resample_s},
        {"code", code_s},
        {"write", write_s},
        {"total", total_s}}}};
  return j.dump(1) + "\n";
}

}  // namespace fvv
