#include "encoder/track/capture_frames.h"

namespace fvv {

StatusOr<std::unique_ptr<CaptureFrames>> CaptureFrames::Open(const Capture& capture, bool extract,
                                                             ThreadPool* pool) {
  std::unique_ptr<CaptureFrames> f(new CaptureFrames(capture, pool));
  CaptureReader& reader = f->reader_;
  const size_t n = capture.cameras.size();
  f->given_ = reader.HasSilhouettes() && !extract;
  if (f->given_) return f;
  f->backgrounds_.resize(n);
  for (uint32_t c = 0; c < n; ++c) {
    if (capture.cameras[c].background) {
      StatusOr<Image> plate = reader.ReadBackground(c);
      if (!plate.ok()) return plate.status();
      f->backgrounds_[c].colour = std::move(*plate);
      continue;
    }
    // No plate: the temporal median of up to 15 frames spread over the take.
    std::vector<Image> samples;
    const uint32_t count = std::min<uint32_t>(15, capture.frame_count);
    for (uint32_t k = 0; k < count; ++k) {
      const uint32_t frame =
          uint32_t(uint64_t(k) * (capture.frame_count - 1) / std::max(1u, count - 1));
      StatusOr<Image> image = reader.ReadFrame(c, frame);
      if (!image.ok()) return image.status();
      samples.push_back(std::move(*image));
    }
    f->backgrounds_[c].colour = TemporalMedian(samples);
  }
  return f;
}

Status CaptureFrames::Read(uint32_t frame, std::vector<Image>* images,
                           std::vector<Image>* silhouettes) {
  const uint32_t n = uint32_t(capture().cameras.size());
  silhouettes->assign(n, Image());
  if (images) images->assign(n, Image());
  std::vector<Status> errors(n);
  // One camera per task: the reader keeps one video decoder per camera.
  pool_->Run(n, [&](uint32_t c) {
    StatusOr<Image> image = Image();
    if (images || !given_) {
      image = reader_.ReadFrame(c, frame);
      if (!image.ok()) {
        errors[c] = image.status();
        return;
      }
    }
    StatusOr<Image> s =
        given_ ? reader_.ReadSilhouette(c, frame) : ExtractSilhouette(*image, backgrounds_[c]);
    if (!s.ok()) {
      errors[c] = s.status();
      return;
    }
    (*silhouettes)[c] = std::move(*s);
    if (images) (*images)[c] = std::move(*image);
  });
  for (const Status& s : errors) FVV_RETURN_IF_ERROR(s);
  return Status::Ok();
}

}  // namespace fvv
