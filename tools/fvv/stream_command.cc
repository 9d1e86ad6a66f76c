#include "tools/fvv/stream_command.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "codec/base/thread_pool.h"
#include "conformance/sample/sample_stream.h"
#include "container/file_reader.h"
#include "container/writer.h"
#include "tools/fvv/codec_options.h"

namespace fvv {
namespace {

int Fail(const Status& s) {
  std::fprintf(stderr, "fvv: %s\n", s.ToString().c_str());
  return 1;
}

std::string ToolList(uint32_t tools) {
  std::string s;
  for (uint32_t bit = 1; bit != 0 && bit <= kAllKnownTools; bit <<= 1) {
    if (tools & bit) s += (s.empty() ? "" : " ") + std::string(CodingToolName(bit));
  }
  return s;
}

struct InfoArgs {
  std::string input;
  bool json = false;
  bool no_checksum = false;
};

int RunInfo(const InfoArgs& a) {
  auto source = FileSource::Open(a.input);
  if (!source.ok()) return Fail(source.status());
  FragmentReadOptions options;
  options.verify_checksum = !a.no_checksum;
  auto opened = FileReader::Open(source->get(), options);
  if (!opened.ok()) {
    std::fprintf(stderr, "fvv: %s: %s\n", a.input.c_str(), opened.status().ToString().c_str());
    return 1;
  }
  FileReader& reader = **opened;
  const StreamInfo& info = reader.info();
  const FileHeader& h = info.header;
  auto boxes = reader.ListTopLevelBoxes();
  if (!boxes.ok()) return Fail(boxes.status());

  nlohmann::json j;
  j["file"] = a.input;
  j["size"] = (*source)->size();
  j["header"] = {
      {"format_version", h.format_version},
      {"profile", int(h.profile)},
      {"level", h.level},
      {"tools", ToolList(h.tools)},
      {"frame_rate", std::to_string(h.frame_rate_num) + "/" + std::to_string(h.frame_rate_den)},
      {"frames", h.frame_count},
      {"cameras", h.camera_count},
      {"atlas", {h.atlas_width, h.atlas_height}},
      {"gop", {h.gop_frames, h.gop_cameras}},
      {"index_offset", h.index_offset},
      {"index", reader.fast_start()        ? "front"
                : reader.index_in_stream() ? "end"
                                           : "none (scanned)"}};
  for (const BoxHeader& b : *boxes) {
    j["boxes"].push_back({{"type", FourCCString(b.type)}, {"offset", b.offset}, {"size", b.size}});
  }
  for (const Camera& c : info.cameras) {
    const auto centre = c.Centre();
    j["cameras"].push_back({{"name", c.name},
                            {"image", {c.width, c.height}},
                            {"focal", {c.fx, c.fy}},
                            {"centre", centre}});
  }
  const Skeleton& sk = info.model.skeleton;
  j["model"] = {{"bones", sk.bones.size()},
                {"dofs", sk.Dofs().size()},
                {"vertices", info.model.mesh.positions.size()},
                {"triangles", info.model.mesh.triangles.size()}};
  if (info.model.quantisation.quantised) {
    const ModelQuantisation& q = info.model.quantisation;
    j["model"]["grid"] = {{"position_step_mm", std::ldexp(1000.0, -q.position_exponent)},
                          {"uv_exponent", q.uv_exponent},
                          {"normal_bits", q.normal_bits},
                          {"weight_bits", q.weight_bits}};
  }
  j["motion"] = {{"rotation_step_degrees", info.motion.rotation_step_degrees()},
                 {"translation_step_mm", info.motion.translation_step_um / 1000.0},
                 {"coder", info.motion.coder == MotionCoder::kArith ? "arith" : "zstd"},
                 {"key_interval", info.motion.key_interval}};
  for (const auto& kv : info.metadata) j["metadata"][kv.first] = kv.second;

  uint64_t texture = 0, motion = 0, masks = 0, visibility = 0, surface = 0, damaged = 0;
  for (size_t i = 0; i < reader.fragment_count(); ++i) {
    const IndexEntry& e = info.index[i];
    nlohmann::json g = {{"gop", i},
                        {"frames", {e.first_frame, e.frame_count}},
                        {"cameras", {e.first_camera, e.camera_count}},
                        {"offset", e.offset},
                        {"size", e.size}};
    auto f = reader.ReadFragment(i);
    if (!f.ok()) {
      g["status"] = f.status().ToString();
      ++damaged;
    } else {
      g["status"] = a.no_checksum ? "not verified" : "ok";
      uint64_t tex = 0;
      for (int c = 0; c < 3 && f->predictive; ++c) {
        // 'ptex': bytes per channel over all its streams, and per signal.
        const PredictiveStreams& p = f->predictive_texture;
        uint64_t r0 = 0, r = 0;
        for (const ChannelStreams& cs : p.r0) r0 += cs[c].size();
        for (const ChannelStreams& cs : p.r) r += cs[c].size();
        const uint64_t t00 = p.t00[c].size();
        const int top = t00 > 0 && p.t00[c][0] <= 30 ? p.t00[c][0] + 1 : 0;
        tex += t00 + r0 + r;
        g["texture"][c == 0   ? "Y"
                     : c == 1 ? "U"
                              : "V"] = {{"bytes", t00 + r0 + r},
                                        {"bitplanes", top},
                                        {"truncation_points", nlohmann::json::array()},
                                        {"t00_bytes", t00},
                                        {"r0_bytes", r0},
                                        {"r_bytes", r}};
      }
      for (int c = 0; c < 3 && !f->predictive; ++c) {
        const ChannelStream& s = f->texture.channels[c];
        tex += s.data.size();
        nlohmann::json points = nlohmann::json::array();
        for (const TruncationPoint& p : s.points) points.push_back(p.bytes);
        g["texture"][c == 0   ? "Y"
                     : c == 1 ? "U"
                              : "V"] = {
            {"bytes", s.data.size()}, {"bitplanes", s.planes}, {"truncation_points", points}};
      }
      g["texture_codec"] = f->predictive ? "predictive" : "spiht";
      if (f->chunked) {
        // The texture in chunks (SPEC.md 3.5.1): the least prefix that decodes.
        g["head_bytes"] = f->head_bytes;
        g["chunks"] = f->chunks.size();
      }
      if (f->has_surface) g["surface_bytes"] = f->surface.size();
      surface += f->surface.size();
      g["motion_bytes"] = f->motion.size();
      g["mask_bytes"] = f->masks.size();
      if (!f->masks.empty()) g["mask_mode"] = static_cast<int>(f->mask_mode);
      texture += tex;
      motion += f->motion.size();
      masks += f->masks.size();
      visibility += f->vertex_visibility.size();
    }
    j["gops"].push_back(g);
  }
  // A live stream (no frame count in its header): its fragments' frames.
  const uint32_t frames = info.frames();
  const double seconds = h.fps() > 0 ? frames / h.fps() : 0;
  auto kbps = [seconds](uint64_t bytes) { return seconds > 0 ? bytes * 8 / seconds / 1000 : 0.0; };
  j["bitrate_kbps"] = {{"texture", kbps(texture)}, {"motion", kbps(motion)},
                       {"masks", kbps(masks)},     {"vertex_visibility", kbps(visibility)},
                       {"surface", kbps(surface)}, {"total", kbps((*source)->size())}};
  j["damaged_fragments"] = damaged;

  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return damaged ? 1 : 0;
  }
  std::printf("%s: fvv stream, format version %u, profile %d, level %u, %llu bytes\n",
              a.input.c_str(), h.format_version, int(h.profile), h.level,
              static_cast<unsigned long long>((*source)->size()));
  std::printf(
      "  %u frames%s at %.3f fps (%.2f s), %u cameras, atlas %ux%u, GOP %u frames x %u cameras\n",
      frames, h.frame_count == 0 ? " (live: counted from its fragments)" : "", h.fps(), seconds,
      h.camera_count, h.atlas_width, h.atlas_height, h.gop_frames, h.gop_cameras);
  std::printf("  tools: %s\n", ToolList(h.tools).c_str());
  std::printf("  model: %zu bones, %zu DOF, %zu vertices, %zu triangles", sk.bones.size(),
              sk.Dofs().size(), info.model.mesh.positions.size(), info.model.mesh.triangles.size());
  if (info.model.quantisation.quantised) {
    const ModelQuantisation& q = info.model.quantisation;
    std::printf(", on a grid: positions %.4f mm, uv 2^-%d, normals %d bits, weights %d bits",
                std::ldexp(1000.0, -q.position_exponent), q.uv_exponent, q.normal_bits,
                q.weight_bits);
  }
  std::printf("\n");
  std::printf("  motion: steps %.4f deg / %.3f mm, %s coder, key interval %u\n",
              info.motion.rotation_step_degrees(), info.motion.translation_step_um / 1000.0,
              info.motion.coder == MotionCoder::kArith ? "arith" : "zstd",
              info.motion.key_interval);
  for (const auto& kv : info.metadata)
    std::printf("  %s: %s\n", kv.first.c_str(), kv.second.c_str());
  std::printf("  boxes:");
  for (const BoxHeader& b : *boxes) {
    std::printf(" %s@%llu(%llu)", FourCCString(b.type).c_str(),
                static_cast<unsigned long long>(b.offset), static_cast<unsigned long long>(b.size));
  }
  std::printf("\n  index: %s\n", j["header"]["index"].get<std::string>().c_str());
  std::printf("  bitrate kbps: texture %.1f, motion %.2f, masks %.1f, vertex visibility %.1f, ",
              kbps(texture), kbps(motion), kbps(masks), kbps(visibility));
  if (surface > 0)
    std::printf("surface %.1f (%llu bytes), ", kbps(surface), (unsigned long long)surface);
  std::printf("total %.1f\n", kbps((*source)->size()));
  std::printf("  %-5s %-9s %-7s %9s %9s %7s %7s  %s\n", "gop", "frames", "cameras", "offset",
              "bytes", "motion", "masks",
              "Y/U/V bytes (bitplanes, truncation points; predictive: T00, R0, R bytes; in "
              "chunks: the head and the chunks)");
  for (const auto& g : j["gops"]) {
    std::printf("  %-5d %4d+%-4d %3d+%-3d %9llu %9llu ", g["gop"].get<int>(),
                g["frames"][0].get<int>(), g["frames"][1].get<int>(), g["cameras"][0].get<int>(),
                g["cameras"][1].get<int>(), g["offset"].get<unsigned long long>(),
                g["size"].get<unsigned long long>());
    if (!g.contains("texture")) {
      std::printf("  %s\n", g["status"].get<std::string>().c_str());
      continue;
    }
    std::printf("%7d %7d ", g["motion_bytes"].get<int>(), g["mask_bytes"].get<int>());
    if (g["texture_codec"] == "predictive") {
      // T00 / R0 / R bytes per channel (BISK streams: no truncation points).
      for (const char* c : {"Y", "U", "V"}) {
        const auto& t = g["texture"][c];
        std::printf(" %s %d (T00 %d R0 %d R %d)", c, t["bytes"].get<int>(),
                    t["t00_bytes"].get<int>(), t["r0_bytes"].get<int>(), t["r_bytes"].get<int>());
      }
      std::printf("  %s\n", g["status"].get<std::string>().c_str());
      continue;
    }
    for (const char* c : {"Y", "U", "V"}) {
      std::printf(" %s %d (%d, %zu)", c, g["texture"][c]["bytes"].get<int>(),
                  g["texture"][c]["bitplanes"].get<int>(),
                  g["texture"][c]["truncation_points"].size());
    }
    if (g.contains("chunks")) {
      std::printf("  head %llu, %llu chunks", g["head_bytes"].get<unsigned long long>(),
                  g["chunks"].get<unsigned long long>());
    }
    if (g.contains("surface_bytes")) {
      std::printf(", surface %llu", g["surface_bytes"].get<unsigned long long>());
    }
    std::printf("  %s\n", g["status"].get<std::string>().c_str());
  }
  if (damaged) {
    std::fprintf(stderr, "fvv: %s: %llu damaged fragment(s)\n", a.input.c_str(),
                 static_cast<unsigned long long>(damaged));
    return 1;
  }
  return 0;
}

struct SampleArgs {
  std::string output;
  SampleStreamOptions o;
  CodecOptionArgs codec;
  std::string motion_coder = "arith", texture_codec = "spiht", mask_coder = "context";
  std::vector<uint32_t> atlas{64, 64}, gop{8, 8};
  bool no_masks = false, end_index = false, texture_chunks = false, surface = false;
  unsigned threads = 0;
};

int RunSample(SampleArgs a) {
  a.o.kernel = a.codec.Kernel();
  a.o.frac_bits_97 = a.codec.precision_97;
  a.o.coder = a.codec.Coder();
  a.o.weights = a.codec.Weights();
  a.o.sample_frac = a.codec.sample_bits;
  a.o.chroma = a.codec.Chroma();
  a.o.upsampling = a.codec.Upsampling();
  a.o.predictive = a.texture_codec == "predictive";
  a.o.mask_coding = MaskCoderFromName(a.mask_coder);
  a.o.motion_coder = a.motion_coder == "zstd" ? MotionCoder::kZstd : MotionCoder::kArith;
  a.o.atlas_width = static_cast<uint16_t>(a.atlas[0]);
  a.o.atlas_height = static_cast<uint16_t>(a.atlas[1]);
  a.o.gop_frames = static_cast<uint16_t>(a.gop[0]);
  a.o.gop_cameras = static_cast<uint16_t>(a.gop[1]);
  a.o.masks = !a.no_masks;
  a.o.fast_start = !a.end_index;
  a.o.texture_chunks = a.texture_chunks || a.surface;
  a.o.surface = a.surface;
  if (a.o.lossless && a.o.kernel == WaveletKernel::kCdf97) a.o.kernel = WaveletKernel::kLeGall53;
  ThreadPool pool(a.threads);
  const auto start = std::chrono::steady_clock::now();
  auto sample = MakeSampleStream(a.o, pool.runner());
  if (!sample.ok()) return Fail(sample.status());
  auto writer = FileWriter::Create(a.output, sample->info);
  if (!writer.ok()) return Fail(writer.status());
  for (const FragmentData& f : sample->fragments) {
    Status s = (*writer)->AddFragment(f);
    if (!s.ok()) return Fail(s);
  }
  Status s = (*writer)->Close();
  if (!s.ok()) return Fail(s);
  std::printf(
      "wrote %s: %u frames x %u cameras, atlas %ux%u, %zu fragments, %llu bytes in %.2f s\n",
      a.output.c_str(), a.o.frames, a.o.cameras, a.o.atlas_width, a.o.atlas_height,
      sample->fragments.size(), static_cast<unsigned long long>((*writer)->bytes_written()),
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace

void AddStreamCommands(CLI::App* app, int* exit_code) {
  auto info = std::make_shared<InfoArgs>();
  CLI::App* i = app->add_subcommand(
      "info",
      "Show a .fvv stream's structure, bitrates per track, per-GOP sizes and truncation "
      "points, and checksum status (exit status 1 on a bad file)");
  i->add_option("file", info->input, ".fvv stream")->required()->check(CLI::ExistingFile);
  i->add_flag("--json", info->json, "Machine-readable output");
  i->add_flag("--no-checksum", info->no_checksum, "Do not verify fragment checksums");
  i->callback([info, exit_code] { *exit_code = RunInfo(*info); });

  auto smp = std::make_shared<SampleArgs>();
  CLI::App* s = app->add_subcommand(
      "sample",
      "Write a synthetic .fvv stream (stick-figure model, procedural walk, test-pattern "
      "atlas textures and masks) for trying the tools and testing decoders");
  s->add_option("-o,--output", smp->output, "Output .fvv file")->required();
  s->add_option("--frames", smp->o.frames, "Frames")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  s->add_option("--cameras", smp->o.cameras, "Cameras")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  s->add_option("--atlas", smp->atlas, "Atlas width and height")
      ->expected(2)
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  s->add_option("--gop", smp->gop, "GOP frames and cameras")
      ->expected(2)
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  AddCodecOptions(s, &smp->codec);
  AddTextureCodecOption(s, &smp->texture_codec);
  AddMaskCoderOption(s, &smp->mask_coder);
  s->add_option("--bpp", smp->o.bpp, "Texture bits per texel")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  s->add_flag("--lossless", smp->o.lossless,
              "Lossless textures (reversible colour; 5/3 unless --kernel haar)");
  s->add_flag("--no-masks", smp->no_masks, "Leave out the shape masks");
  s->add_flag("--vertex-visibility", smp->o.vertex_visibility, "Add per-vertex visibility");
  s->add_option("--motion-coder", smp->motion_coder, "Motion entropy coder")
      ->check(CLI::IsMember({"arith", "zstd"}))
      ->capture_default_str();
  s->add_option("--key-interval", smp->o.key_interval,
                "Code every Nth frame's pose and interpolate between (1 = all)")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  s->add_flag("--end-index", smp->end_index,
              "Index at the end (frame count not declared up front)");
  s->add_flag("--texture-chunks", smp->texture_chunks,
              "The texture in chunks (format version 11): any prefix of a fragment past its "
              "head decodes");
  s->add_flag("--surface", smp->surface,
              "A surface of every frame (format version 12; implies --texture-chunks): every "
              "fifth vertex swinging by up to 30 cm, the others by up to 3 cm");
  s->add_option("--level", smp->o.level, "Level (1-4)")
      ->capture_default_str()
      ->check(CLI::Range(1, 4));
  s->add_option("--threads", smp->threads, "Worker threads (0 = all cores)")->capture_default_str();
  s->callback([smp, exit_code] { *exit_code = RunSample(*smp); });
}

}  // namespace fvv
