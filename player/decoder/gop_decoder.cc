#include "player/decoder/gop_decoder.h"

#include <algorithm>
#include <chrono>
#include <future>
#include <thread>

#include "codec/base/threads.h"
#include "codec/block_codec.h"
#include "codec/mask.h"
#include "codec/predictive_texture.h"
#include "container/surface_displacement.h"

namespace fvv {

bool GopBudget::Covers(const GopBudget& other) const {
  const bool bytes_ok = max_bytes == 0 || (other.max_bytes != 0 && max_bytes >= other.max_bytes);
  const bool ms_ok = max_ms == 0 || (other.max_ms != 0 && max_ms >= other.max_ms);
  const bool cameras_ok = cameras == 0 || (other.cameras != 0 && (other.cameras & ~cameras) == 0);
  return bytes_ok && ms_ok && cameras_ok;
}

bool GopBudget::WantsGroup(uint32_t first, uint32_t count) const {
  if (cameras == 0) return true;
  for (uint32_t c = first; c < first + count && c < 64; ++c) {
    if (cameras & (uint64_t{1} << c)) return true;
  }
  return false;
}

namespace {

// A 'ptex' texture decoded to the same YUV block a 'texr' gives (YCbCr 4:4:4).
// A time budget does not cut it (its streams are cut by bytes only).
StatusOr<Block> DecodePredictiveFragment(const FragmentData& f, const Shape4D& shape,
                                         uint64_t max_bytes, const std::vector<uint8_t>& masks,
                                         const ParallelRunner& runner, DecodeReport* report) {
  PredictiveGop gop;
  gop.frames = shape.frames(), gop.cameras = shape.cameras();
  gop.width = shape.width(), gop.height = shape.height();
  gop.mask = masks;
  PredictiveDecodeOptions options;
  options.max_bytes = max_bytes;
  options.runner = runner;
  PredictiveDecoded decoded;
  FVV_RETURN_IF_ERROR(DecodePredictive(f.predictive_texture, gop, &decoded, options, false));
  Block block;
  block.colour = ColourSpace::kYCbCr601;
  block.chroma = ChromaFormat::k444;
  const size_t texels = size_t(gop.width) * gop.height;
  for (int k = 0; k < 3; ++k) {
    Plane4D& plane = block.channels[k];
    plane = Plane4D(shape);
    for (size_t tc = 0; tc < decoded.yuv.size(); ++tc) {
      std::copy(decoded.yuv[tc][k].begin(), decoded.yuv[tc][k].end(),
                plane.samples.begin() + tc * texels);
    }
  }
  const uint64_t total = f.predictive_texture.Bytes();
  report->bytes_read = max_bytes == 0 || max_bytes >= total ? total : max_bytes;
  report->complete = report->bytes_read == total;
  report->planes_completed = {0, 0, 0};  // bitplanes differ per stream; not summarised
  return block;
}

// How much of fragment `f`'s texture a byte budget decodes: Annex B.2's
// split of max_bytes texture bytes over the channels, or with chunks, what the
// fragment's first max_bytes bytes hold of each channel (SPEC.md 3.5.1). A
// budget is a cap on what is decoded, not bytes delivered: one shorter than a
// chunked fragment's head decodes the head (motion, masks) and no texture.
Status ApplyByteBudget(const FragmentData& f, uint64_t max_bytes, DecodeBudget* b) {
  if (!f.chunked) {
    b->max_bytes = max_bytes;
    return Status::Ok();
  }
  b->max_bytes = 0;
  const uint64_t prefix = max_bytes == 0 ? 0 : std::max(max_bytes, f.head_bytes);
  FVV_ASSIGN_OR_RETURN(b->channel_max_bytes, ChunkedPrefixBytes(f, prefix));
  return Status::Ok();
}

// A fragment's coded masks, decoded into `out` (sized here).
Status DecodeFragmentMasks(const FragmentData& f, const Shape4D& shape, std::vector<uint8_t>* out) {
  out->resize(shape.count());
  return DecodeMasks(f.masks.data(), f.masks.size(), shape, f.mask_mode, out->data());
}

}  // namespace

DecodedGop::~DecodedGop() {
  if (!sample_pool) return;
  for (Block& block : textures)
    for (Plane4D& plane : block.channels) sample_pool->Give(std::move(plane.samples));
}

namespace {

// The surface of the first camera group's fragment, whole: each frame's
// bind-pose positions.
Status DecodeSurface(const StreamInfo& info, const FragmentData& f,
                     std::vector<std::vector<float>>* surface) {
  const Mesh& mesh = info.model.mesh;
  const uint32_t vertices = static_cast<uint32_t>(mesh.positions.size());
  if (f.surface_head.vertex_count != vertices) {
    return Corrupt("fragment " + std::to_string(f.info.gop_index) + ": 'sfhd' declares " +
                   std::to_string(f.surface_head.vertex_count) + " vertices, the model has " +
                   std::to_string(vertices));
  }
  std::vector<int32_t> values;
  Status s = DecodeSurfaceDisplacements(f.surface.data(), f.surface.size(), f.info.frame_count,
                                        vertices, &values);
  if (!s.ok()) {
    return Status(s.code(), "fragment " + std::to_string(f.info.gop_index) + ": " + s.message());
  }
  surface->resize(f.info.frame_count);
  for (uint32_t t = 0; t < f.info.frame_count; ++t) {
    SurfacePositions(mesh, values.data() + size_t(t) * vertices, f.surface_head.step_exponent,
                     &(*surface)[t]);
  }
  return Status::Ok();
}

}  // namespace

StatusOr<std::shared_ptr<DecodedGop>> DecodeGop(const StreamInfo& info,
                                                const std::vector<FragmentData>& fragments,
                                                const GopBudget& budget,
                                                const ParallelRunner& runner, unsigned threads,
                                                std::shared_ptr<SamplePool> sample_pool) {
  const auto start = std::chrono::steady_clock::now();
  if (fragments.empty() || fragments[0].info.first_camera != 0) {
    return Internal("GOP decode without its first camera group");
  }
  auto gop = std::make_shared<DecodedGop>();
  const FragmentData& first = fragments[0];
  gop->span = first.info.first_frame / info.header.gop_frames;
  gop->first_frame = first.info.first_frame;
  gop->frame_count = first.info.frame_count;
  gop->budget = budget;
  gop->sample_pool = std::move(sample_pool);
  FVV_RETURN_IF_ERROR(DecodeMotion(MotionBoxHeader(first), first.motion.data(), info.model.skeleton,
                                   info.motion, first.info.frame_count, &gop->motion));
  if (PrefixHoldsSurface(first, budget.max_bytes)) {
    FVV_RETURN_IF_ERROR(DecodeSurface(info, first, &gop->surface));
  }
  gop->bitplanes = {99, 99, 99};
  const size_t n = fragments.size();
  gop->textures.resize(n);
  gop->masks.resize(n);
  std::vector<DecodeReport> reports(n);
  std::vector<Status> statuses(n);
  gop->decoded.resize(n);
  std::vector<uint32_t> wanted;  // the fragments the budget's cameras ask for
  for (size_t i = 0; i < n; ++i) {
    gop->decoded[i] =
        budget.WantsGroup(fragments[i].info.first_camera, fragments[i].info.camera_count);
    if (gop->decoded[i]) wanted.push_back(static_cast<uint32_t>(i));
  }
  const size_t wanted_count = wanted.size();
  // With at least a fragment per thread, fragments decode in parallel, each on
  // one thread with its channels in turn; under a time budget each channel then
  // gets an equal share of the pool's time.
  const bool parallel = wanted_count > 1 && wanted_count >= threads;
  const double channel_ms =
      budget.max_ms > 0 && parallel
          ? std::max(0.001, budget.max_ms * std::max(1u, threads) / wanted_count / 3.0)
          : 0.0;
  // Decodes fragment i: its texture channels spread over `inner`, its masks
  // alongside on a thread of their own when `masks_async`.
  const auto decode_one = [&](size_t i, const ParallelRunner& inner, bool masks_async) {
    const FragmentData& f = fragments[i];
    if (!gop->decoded[i]) return;  // a camera the player does not blend now
    DecodeBudget b;
    statuses[i] = ApplyByteBudget(f, budget.max_bytes, &b);
    if (!statuses[i].ok()) return;
    b.floor_share = budget.floor_share;
    b.sample_pool = gop->sample_pool.get();
    if (budget.max_ms > 0 && parallel) {
      b.channel_runner = SerialRunner;
      b.max_ms = channel_ms;
    } else if (budget.max_ms > 0) {
      b.channel_runner = [](uint32_t count, const std::function<void(uint32_t)>& task) {
        std::vector<std::thread> channel_threads;
        for (uint32_t k = 0; k < count; ++k) channel_threads.emplace_back(task, k);
        for (std::thread& t : channel_threads) t.join();
      };
      const double spent =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      size_t left = 0;  // fragments still to decode, this one included
      for (size_t k = i; k < n; ++k) left += gop->decoded[k] ? 1 : 0;
      b.max_ms = std::max(0.001, (budget.max_ms - spent) / static_cast<double>(left));
      if (!kThreadsAvailable) {
        // One thread: the channels in turn, each with a third of the time.
        b.channel_runner = SerialRunner;
        b.max_ms /= 3;
      }
    }
    std::vector<uint8_t>& masks = gop->masks[i];
    const Shape4D shape = f.info.TextureShape(info.header);
    const auto decode_masks = [&f, shape, &masks] { return DecodeFragmentMasks(f, shape, &masks); };
    if (f.predictive) {
      // 'ptex': the masks are the signals' supports, so they come first.
      Status st = decode_masks();
      if (st.ok()) {
        auto decoded =
            DecodePredictiveFragment(f, shape, budget.max_bytes, masks, inner, &reports[i]);
        if (decoded.ok()) {
          gop->textures[i] = std::move(decoded).value();
        } else {
          st = decoded.status();
        }
      }
      statuses[i] = st;
      return;
    }
    std::future<Status> masks_done;
    Status mask_status;
    if (!f.masks.empty() && masks_async && kThreadsAvailable) {
      masks_done = std::async(std::launch::async, decode_masks);
    }
    auto decoded = DecodeBlock(f.texture, b, inner, &reports[i]);
    if (!f.masks.empty()) mask_status = masks_done.valid() ? masks_done.get() : decode_masks();
    if (!decoded.ok()) {
      statuses[i] = decoded.status();
    } else {
      statuses[i] = mask_status;
      gop->textures[i] = std::move(decoded).value();
    }
  };
  if (parallel && budget.max_ms == 0) {
    // Several camera groups (one camera per fragment by default) without a time
    // budget: every fragment's channels and masks are tasks of their own, the
    // large ones first, so the threads run out of work together at the span's
    // end (whole fragments per thread leave one idle for half a fragment).
    std::vector<DecodeBudget> whole(n);
    std::vector<BlockDecode> blocks(n);
    std::vector<Status> mask_statuses(n);
    enum Kind : uint8_t { kY, kU, kV, kMasks, kWhole };
    std::vector<std::pair<uint32_t, Kind>> tasks;
    for (uint32_t i : wanted) {
      if (fragments[i].predictive) {
        tasks.emplace_back(i, kWhole);  // 'ptex': its masks come first, in one task
        continue;
      }
      whole[i].sample_pool = gop->sample_pool.get();
      statuses[i] = ApplyByteBudget(fragments[i], budget.max_bytes, &whole[i]);
      if (statuses[i].ok()) statuses[i] = blocks[i].Start(fragments[i].texture, whole[i]);
      if (!statuses[i].ok()) continue;
      for (Kind k : {kY, kU, kV}) tasks.emplace_back(i, k);
      if (!fragments[i].masks.empty()) tasks.emplace_back(i, kMasks);
    }
    std::stable_sort(tasks.begin(), tasks.end(), [](const auto& x, const auto& y) {
      static constexpr int kOrder[] = {1, 3, 4, 2, 0};  // whole, Y, masks, U, V
      return kOrder[x.second] < kOrder[y.second];
    });
    runner(static_cast<uint32_t>(tasks.size()), [&](uint32_t k) {
      const auto [i, kind] = tasks[k];
      const FragmentData& f = fragments[i];
      if (kind == kWhole) {
        decode_one(i, SerialRunner, false);
      } else if (kind == kMasks) {
        mask_statuses[i] = DecodeFragmentMasks(f, f.info.TextureShape(info.header), &gop->masks[i]);
      } else {
        blocks[i].Channel(kind);
      }
    });
    for (uint32_t i : wanted) {
      if (fragments[i].predictive || !statuses[i].ok()) continue;
      gop->textures[i] = blocks[i].Finish(&reports[i]);
      statuses[i] = mask_statuses[i];
    }
  } else if (parallel) {
    // The same under a time budget: whole fragments in parallel, each on one
    // thread with an equal share of the time for each of its channels.
    runner(static_cast<uint32_t>(wanted.size()),
           [&](uint32_t k) { decode_one(wanted[k], SerialRunner, false); });
  } else {
    // Few fragments: one by one, each spread over the runner (a time budget is
    // shared out in fragment order).
    for (size_t i = 0; i < n; ++i) decode_one(i, runner, true);
  }
  for (size_t i = 0; i < n; ++i) {
    FVV_RETURN_IF_ERROR(statuses[i]);
    gop->groups.push_back(fragments[i].info);
    if (!gop->decoded[i]) continue;
    const DecodeReport& report = reports[i];
    gop->bytes_decoded += report.bytes_read;
    gop->bytes_available += TextureBytes(fragments[i]);
    for (int c = 0; c < 3; ++c) {
      gop->bitplanes[c] = std::min(gop->bitplanes[c], report.planes_completed[c]);
    }
    // A chunked fragment read from a prefix lacks the chunks after it.
    gop->complete =
        gop->complete && report.complete &&
        (!fragments[i].chunked || fragments[i].texture.total_bytes() == TextureBytes(fragments[i]));
    // The stream's 4:2:0 rule (tool bit 18, SPEC.md 9.7) goes with its samples.
    if (info.header.tools & kToolChromaBilinear) {
      gop->textures[i].upsampling = ChromaUpsampling::kBilinear;
    }
  }
  gop->ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return gop;
}

}  // namespace fvv
