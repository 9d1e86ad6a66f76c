#include "player/decoder/gop_decoder.h"

#include <algorithm>
#include <chrono>
#include <future>
#include <thread>

#include "codec/block_codec.h"
#include "codec/mask_coder.h"

namespace fvv {

bool GopBudget::Covers(const GopBudget& other) const {
  const bool bytes_ok = max_bytes == 0 || (other.max_bytes != 0 && max_bytes >= other.max_bytes);
  const bool ms_ok = max_ms == 0 || (other.max_ms != 0 && max_ms >= other.max_ms);
  return bytes_ok && ms_ok;
}

StatusOr<std::shared_ptr<DecodedGop>> DecodeGop(const StreamInfo& info,
                                                const std::vector<FragmentData>& fragments,
                                                const GopBudget& budget,
                                                const ParallelRunner& runner) {
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
  FVV_RETURN_IF_ERROR(DecodeMotion(MotionBoxHeader(first), first.motion.data(), info.model.skeleton,
                                   info.motion, first.info.frame_count, &gop->motion));
  gop->bitplanes = {99, 99, 99};
  for (const FragmentData& f : fragments) {
    gop->groups.push_back(f.info);
    DecodeBudget b;
    b.max_bytes = budget.max_bytes;
    if (budget.max_ms > 0) {
      b.channel_runner = [](uint32_t n, const std::function<void(uint32_t)>& task) {
        std::vector<std::thread> threads;
        for (uint32_t i = 0; i < n; ++i) threads.emplace_back(task, i);
        for (std::thread& t : threads) t.join();
      };
      const double spent =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      const size_t left = fragments.size() - gop->textures.size();
      b.max_ms = std::max(0.001, (budget.max_ms - spent) / static_cast<double>(left));
    }
    // Masks decode on their own thread while the texture channels use the runner:
    // three SPIHT streams on two cores leave one core idle part of the time.
    std::future<Status> masks_done;
    std::vector<uint8_t> masks;
    if (!f.masks.empty()) {
      const Shape4D shape = f.info.TextureShape(info.header);
      masks.resize(shape.count());
      masks_done = std::async(std::launch::async, [&f, shape, &masks] {
        return DecodeMasks(f.masks.data(), f.masks.size(), shape, masks.data());
      });
    }
    DecodeReport report;
    auto decoded = DecodeBlock(f.texture, b, runner, &report);
    const Status mask_status = masks_done.valid() ? masks_done.get() : Status::Ok();
    if (!decoded.ok()) return decoded.status();
    FVV_RETURN_IF_ERROR(mask_status);
    Block block = std::move(decoded).value();
    gop->textures.push_back(std::move(block));
    gop->bytes_decoded += report.bytes_read;
    gop->bytes_available += f.texture.total_bytes();
    for (int c = 0; c < 3; ++c) {
      gop->bitplanes[c] = std::min(gop->bitplanes[c], report.planes_completed[c]);
    }
    gop->complete = gop->complete && report.complete;
    gop->masks.push_back(std::move(masks));
  }
  gop->ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return gop;
}

}  // namespace fvv
