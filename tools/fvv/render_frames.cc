#include "tools/fvv/render_frames.h"

#include <chrono>
#include <cstdio>
#include <optional>

#include "codec/base/thread_pool.h"
#include "encoder/body/generic_body.h"
#include "encoder/body/kinematics.h"
#include "encoder/body/mesh_ops.h"
#include "encoder/capture/capture.h"
#include "encoder/capture/colour_gain.h"
#include "encoder/encode/pose_file.h"
#include "encoder/io/image_io.h"
#include "encoder/shape/surface_tracking.h"
#include "encoder/track/capture_frames.h"
#include "encoder/track/track_capture.h"
#include "fvv/fvv_decoder.hpp"
#include "player/decoder/c_api_internal.h"
#include "player/decoder/public_camera.h"
#include "player/render/projective_renderer.h"

namespace fvv {
namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Frames drawn by renderer type R (both renderers draw and read back alike).
template <class R>
class FramesDrawnBy : public RenderFrames {
 public:
  Status Draw(const RenderView& view, int width, int height) override {
    return renderer_->Draw(view, width, height);
  }
  Status ReadRgb(int width, int height, std::vector<uint8_t>* rgb) override {
    return renderer_->ReadRgb(width, height, rgb);
  }

 protected:
  std::unique_ptr<R> renderer_;
};

class StreamFrames : public FramesDrawnBy<Renderer> {
 public:
  Status ReadCoverage(int width, int height, std::vector<uint8_t>* coverage) override {
    return renderer_->ReadCoverage(width, height, coverage);
  }
  Status Open(const std::string& path, const StreamRenderOptions& o) {
    decoder_ = MakeDecoder();
    if (!decoder_) return Internal("cannot create a decoder");
    if (fvv_decoder_open_file(decoder_.get(), path.c_str()) != FVV_OK) {
      return DecoderStatus(decoder_.get());
    }
    fvv_decoder_get_info(decoder_.get(), &info_);
    first_ = 0;
    last_ = info_.frame_count - 1;
    fps_ = double(info_.frame_rate_num) / info_.frame_rate_den;
    cameras_.resize(info_.camera_count);
    for (uint32_t c = 0; c < info_.camera_count; ++c) {
      fvv_decoder_get_camera(decoder_.get(), c, &cameras_[c]);
    }
    budget_.max_bytes_per_gop = o.bytes;
    budget_.max_ms_per_gop = o.max_ms;
    if (!o.texture.empty()) {
      FVV_ASSIGN_OR_RETURN(Image image, ReadImage(o.texture));
      if (image.width != info_.atlas_width || image.height != info_.atlas_height ||
          image.channels != 3) {
        return InvalidArgument(
            o.texture + ": " + std::to_string(image.width) + "x" + std::to_string(image.height) +
            " with " + std::to_string(image.channels) +
            " channels; --texture needs RGB at the atlas's size, " +
            std::to_string(info_.atlas_width) + "x" + std::to_string(info_.atlas_height));
      }
      texture_ = std::move(image.pixels);
      seen_.assign(size_t{info_.atlas_width} * info_.atlas_height, 1);
      // The poses are what is needed: one byte of the first camera group only
      // (no inverse transforms of the other cameras' textures).
      budget_.max_bytes_per_gop = 1;
      budget_.camera_mask = 1;
    }
    return Status::Ok();
  }
  Status CreateRenderer(const GlApi& gl) override {
    fvv_model model;
    fvv_decoder_get_model(decoder_.get(), &model);
    auto r = Renderer::Create(gl, model, DecoderCameras(decoder_.get()), info_.atlas_width,
                              info_.atlas_height);
    if (!r.ok()) return r.status();
    renderer_ = std::move(r).value();
    return Status::Ok();
  }
  Status Load(uint32_t f, glm::vec3* root) override {
    const auto t0 = Clock::now();
    FramePtr frame = DecodeFrame(decoder_.get(), f, &budget_);
    if (!frame) {
      const Status s = DecoderStatus(decoder_.get());
      return Status(s.code(), "frame " + std::to_string(f) + ": " + s.message());
    }
    decode_s_ += Since(t0);
    const auto t1 = Clock::now();
    if (!texture_.empty()) {
      // Every camera carries the one texture and sees every texel: whatever
      // the blend's weights, each fragment shows the texture's colour.
      std::vector<fvv_view> views(frame->camera_count);
      for (fvv_view& v : views)
        v = {texture_.data(), frame->views[0].mask ? seen_.data() : nullptr};
      fvv_frame single = *frame;
      single.views = views.data();
      FVV_RETURN_IF_ERROR(renderer_->SetFrame(single));
    } else {
      FVV_RETURN_IF_ERROR(renderer_->SetFrame(*frame));
    }
    upload_s_ += Since(t1);
    *root = glm::vec3(frame->bone_world[12], frame->bone_world[13], frame->bone_world[14]);
    return Status::Ok();
  }
  std::string LoadTimes(uint32_t frames) const override {
    char line[160];
    std::snprintf(line, sizeof(line),
                  "Renderer II; texture upload %.1f ms per frame, decode %.0f ms (real-time "
                  "factor %.2f)",
                  upload_s_ * 1e3 / frames, decode_s_ * 1e3, decode_s_ / (frames / fps_));
    return line;
  }

 private:
  DecoderPtr decoder_;
  fvv_stream_info info_{};
  fvv_decode_budget budget_{};
  std::vector<uint8_t> texture_, seen_;  // --texture: the image, and a mask of ones
  double decode_s_ = 0, upload_s_ = 0;
};

class CaptureFramesSource : public FramesDrawnBy<ProjectiveRenderer> {
 public:
  Status ReadCoverage(int, int, std::vector<uint8_t>*) override {
    return Unsupported(
        "--coverage: Renderer I (projective) resolves every pixel; Renderer II only");
  }
  CaptureFramesSource() : pool_(2) {}
  Status Open(const std::string& path, const CaptureRenderOptions& o) {
    options_ = o;
    StatusOr<Capture> cap = LoadCapture(path);
    if (!cap.ok()) return cap.status();
    capture_ = std::move(cap).value();
    const uint32_t last = std::min(o.last, capture_.frame_count - 1);
    if (o.first > last) {
      return InvalidArgument("--first beyond the capture's " +
                             std::to_string(capture_.frame_count) + " frames");
    }
    if (!o.poses.empty()) {
      StatusOr<PoseSequence> poses = LoadPoseFile(o.poses);
      if (!poses.ok()) return poses.status();
      first_ = std::max(o.first, poses->first_frame);
      last_ = std::min<uint32_t>(last, poses->first_frame + uint32_t(poses->poses.size()) - 1);
      if (first_ > last_) {
        return InvalidArgument(o.poses + " has poses for frames " +
                               std::to_string(poses->first_frame) + ".." +
                               std::to_string(poses->first_frame + poses->poses.size() - 1) +
                               ", none of the frames asked for");
      }
      model_ = MakeGenericBody(poses->shape);
      for (uint32_t f = first_; f <= last_; ++f)
        poses_.push_back(poses->poses[f - poses->first_frame]);
    } else {
      // No poses: the capture front end tracks the actor first.
      TrackCaptureOptions to;
      to.first = o.first;
      to.last = last;
      to.progress = o.progress;
      StatusOr<TrackCaptureResult> tracked = TrackCapture(path, to);
      if (!tracked.ok()) return tracked.status();
      first_ = tracked->first;
      last_ = tracked->last;
      model_ = tracked->model;
      poses_ = tracked->Poses();
    }
    fps_ = capture_.frame_rate;
    for (const CaptureCamera& c : capture_.cameras) {
      calibrations_.push_back(c.calibration);
    }
    for (const Camera& c : calibrations_) cameras_.push_back(PublicCamera(c));
    StatusOr<std::unique_ptr<CaptureFrames>> frames = CaptureFrames::Open(capture_, false, &pool_);
    if (!frames.ok()) return frames.status();
    frames_ = std::move(frames).value();
    return Status::Ok();
  }
  Status CreateRenderer(const GlApi& gl) override {
    std::vector<uint32_t> indices;
    for (const auto& t : model_.mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
    auto r =
        ProjectiveRenderer::Create(gl, indices, uint32_t(model_.mesh.positions.size()), cameras_);
    if (!r.ok()) return r.status();
    renderer_ = std::move(r).value();
    return Status::Ok();
  }
  Status Load(uint32_t f, glm::vec3* root) override {
    const auto t0 = Clock::now();
    std::vector<Image> images, silhouettes;
    FVV_RETURN_IF_ERROR(frames_->Read(f, &images, &silhouettes));
    // In the rig's common colour, as the encoder's textures are.
    for (size_t c = 0; c < images.size() && c < capture_.cameras.size(); ++c) {
      ApplyColourGain(capture_.cameras[c].colour_gain, &images[c]);
    }
    read_s_ += Since(t0);
    const auto t1 = Clock::now();
    const std::vector<double>& dofs = poses_[f - first_];
    const BodyModel* drawn = &model_;
    if (options_.surface) {
      // Each frame's surface from the one before: a jump starts afresh.
      if (!tracker_ || f != tracked_ + 1) {
        tracker_ = std::make_unique<SurfaceTracker>(model_.mesh, SurfaceTrackingOptions());
        surface_ = model_;
        std::vector<Eigen::Vector3f> bind_positions;
        for (const auto& q : model_.mesh.positions) bind_positions.emplace_back(q[0], q[1], q[2]);
        welded_ = WeldVertices(bind_positions);
      }
      StatusOr<std::vector<float>> d =
          tracker_->Track(SkinningMatrices(model_.skeleton, dofs), calibrations_, silhouettes,
                          images, nullptr, pool_.runner());
      if (!d.ok()) return d.status();
      tracked_ = f;
      // The positions moved along the bind normals; visibility and blend
      // weights read the normals, so the surface's own.
      const Mesh& bind = model_.mesh;
      std::vector<Eigen::Vector3f> p(bind.positions.size());
      for (size_t v = 0; v < p.size(); ++v) {
        for (int k = 0; k < 3; ++k) p[v][k] = bind.positions[v][k] + (*d)[v] * bind.normals[v][k];
        surface_.mesh.positions[v] = {p[v].x(), p[v].y(), p[v].z()};
      }
      const std::vector<Eigen::Vector3f> n = VertexNormals(bind.triangles, p, welded_);
      for (size_t v = 0; v < p.size(); ++v) {
        surface_.mesh.normals[v] = {n[v].x(), n[v].y(), n[v].z()};
      }
      drawn = &surface_;
    }
    surface_s_ += Since(t1);
    const auto t1b = Clock::now();
    StatusOr<ProjectiveFrame> frame = MakeProjectiveFrame(
        *drawn, dofs, calibrations_, images, silhouettes, options_.projective, pool_.runner());
    if (!frame.ok()) return frame.status();
    prepare_s_ += Since(t1b);
    const auto t2 = Clock::now();
    std::vector<const uint8_t*> rgba;
    for (const Image& i : frame->images) rgba.push_back(i.pixels.data());
    FVV_RETURN_IF_ERROR(renderer_->SetFrame(frame->positions, frame->weights, rgba));
    upload_s_ += Since(t2);
    *root = glm::vec3(float(frame->root.x()), float(frame->root.y()), float(frame->root.z()));
    return Status::Ok();
  }
  std::string LoadTimes(uint32_t frames) const override {
    char line[260];
    std::snprintf(line, sizeof(line),
                  "Renderer I (projective); per frame: images and silhouettes read %.0f ms, "
                  "%svisibility and weights %.0f ms, upload %.1f ms",
                  read_s_ * 1e3 / frames,
                  options_.surface ? ("surface tracked " +
                                      std::to_string(int(surface_s_ * 1e3 / frames)) + " ms, ")
                                         .c_str()
                                   : "",
                  prepare_s_ * 1e3 / frames, upload_s_ * 1e3 / frames);
    return line;
  }

 private:
  CaptureRenderOptions options_;
  ThreadPool pool_;
  Capture capture_;
  std::vector<Camera> calibrations_;  // cameras_ names point into these
  BodyModel model_;
  std::vector<std::vector<double>> poses_;  // first_..last_
  std::unique_ptr<CaptureFrames> frames_;
  std::unique_ptr<SurfaceTracker> tracker_;  // with options_.surface
  BodyModel surface_;                        // model_ with the frame's surface
  std::vector<uint32_t> welded_;             // model_'s welded vertices
  uint32_t tracked_ = 0;                     // the frame the tracker saw last
  double read_s_ = 0, surface_s_ = 0, prepare_s_ = 0, upload_s_ = 0;
};

}  // namespace

StatusOr<std::unique_ptr<RenderFrames>> OpenStreamFrames(const std::string& path,
                                                         const StreamRenderOptions& options) {
  auto frames = std::make_unique<StreamFrames>();
  FVV_RETURN_IF_ERROR(frames->Open(path, options));
  return std::unique_ptr<RenderFrames>(std::move(frames));
}

StatusOr<std::unique_ptr<RenderFrames>> OpenCaptureFrames(const std::string& path,
                                                          const CaptureRenderOptions& options) {
  auto frames = std::make_unique<CaptureFramesSource>();
  FVV_RETURN_IF_ERROR(frames->Open(path, options));
  return std::unique_ptr<RenderFrames>(std::move(frames));
}

}  // namespace fvv
