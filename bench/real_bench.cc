// The real-footage benchmark: a real capture, from its calibration to rendered
// held-out views. There is no ground truth, and a fit scored against the masks
// and keypoints it was fitted to proves little, so each camera is scored while
// it is held out: tracked with the other cameras, then in the held-out camera
// the IoU of the fitted model's silhouette against the person network's mask,
// and the distance of the model's projected joints from the network's
// keypoints (full-resolution pixels), beside the same figures in the cameras
// the fit used. Beside the held-out IoU, the IoU with the model's silhouettes
// moved by the one image shift, the same in every frame, that lays them best
// on that camera's masks (SilhouetteShiftSearch): what a turn of the held-out
// camera by a fraction of a degree against the others would give, so the
// calibration's share of the shortfall apart from the tracking's; a diagnosis,
// not a score, since the shift is taken from the held-out masks.
// Seconds per frame by stage. Then, unless --no-render, the
// held-out camera's view rendered from the other cameras with Renderer II (a
// stream encoded by `fvv encode` at its default rate) and Renderer I (`fvv
// render --renderer projective`, straight from the camera images): PSNR and
// SSIM over the actor's region (the held-out camera's person mask) against the
// real frame; where Renderer II's error lies (the mask's pixels it misses
// against those both cover, and of those the ones deep inside the outline,
// where no outline error reaches), and its PSNR as the learned methods' papers
// count it (over the actor's 3D box projected, the background black in both). A contact sheet of
// real frames, masks, the fitted model, the rendered views, where Renderer II's is off (and
// Renderer II from halfway between the held-out camera and the camera nearest it) goes to
// OUT/contact_sheet.png, the figures to
// OUT/real_bench.json.
//
//   build/bench/real_bench CAPTURE [--frames A:B] [--render-frames N] [--out DIR]
//                          [--fvv PATH] [--models DIR] [--held-out NAME] [--no-render]
//
// CAPTURE: an imported capture (bench/run_real_bench.sh imports
// ../shared/data/real/pose2sim_single and runs this).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "codec/base/thread_pool.h"
#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/capture/capture.h"
#include "encoder/capture/colour_gain.h"
#include "encoder/encode/mask_dilation.h"
#include "encoder/io/child_process.h"
#include "encoder/io/image_io.h"
#include "encoder/shape/depth_map.h"
#include "encoder/track/camera_sync.h"
#include "encoder/track/capture_frames.h"
#include "encoder/track/person_observer.h"
#include "encoder/track/silhouette_shift.h"
#include "encoder/track/track_capture.h"

namespace fvv {
namespace {

// A JSON file this bench had fvv write (an encode's --summary-json).
StatusOr<nlohmann::json> ReadJson(const std::string& path) {
  StatusOr<std::vector<uint8_t>> bytes = ReadFileBytes(path, 1 << 20);
  if (!bytes.ok()) return bytes.status();
  nlohmann::json j = nlohmann::json::parse(bytes->begin(), bytes->end(), nullptr, false);
  if (j.is_discarded() || !j.contains("bytes") || !j.contains("gops")) {
    return Corrupt(path + ": not an encode summary");
  }
  return j;
}

struct Args {
  std::string capture, out = "out/real_bench", fvv, models;
  std::string held_out;  // one camera's name: only that one held out
  uint32_t first = 0, last = 29;
  uint32_t render_frames = 30;
  bool render = true;
  bool surface = false;  // encode with the surface of every frame (fvv encode --surface)
  // fvv encode's --surface-prior, --surface-temporal and --surface-stereo,
  // where given: each option and its value.
  std::vector<std::string> surface_options;
  std::vector<std::string> encode_options;  // --encode-option: passed to both encodes as given
  std::string silhouette_margin;            // fvv encode --silhouette-margin, where given
  // fvv encode --psnr and --atlas, where given: the rate of the stream with
  // masks (the default stream takes its bytes) and both streams' atlas size.
  std::string psnr, atlas;
};

// fvv encode's arguments beyond the stream's own: the surface of every frame,
// the silhouette margin and the atlas size, as asked.
std::vector<std::string> EncodeOptions(const Args& a) {
  std::vector<std::string> out;
  if (a.surface) {
    out.push_back("--surface");
    out.insert(out.end(), a.surface_options.begin(), a.surface_options.end());
  }
  if (!a.silhouette_margin.empty()) {
    out.insert(out.end(), {"--silhouette-margin", a.silhouette_margin});
  }
  if (!a.atlas.empty()) out.insert(out.end(), {"--atlas", a.atlas});
  out.insert(out.end(), a.encode_options.begin(), a.encode_options.end());
  return out;
}

// What the person network saw in every camera of every benchmarked frame.
struct Reference {
  std::vector<std::vector<Image>> masks;  // [frame][camera]
  std::vector<std::vector<std::vector<JointSighting>>> sightings;
};

struct FitScore {
  double iou = 0, joint_px = 0;
  int frames = 0, joint_frames = 0;
  double agreement_px = 0;  // KeypointAgreement, summed over frames
  int agreement_frames = 0;
  // The joints' mean signed offset from the keypoints (model minus keypoint,
  // pixels), summed over frames: a shift common to every joint and frame is
  // the camera's calibration against the others', not the fit.
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
  // Held out: the one image shift that best lays the model on the masks over
  // every frame (BestShift), and the mean IoU with it.
  Eigen::Vector2i shift = Eigen::Vector2i::Zero();
  double shifted_iou = 0;
};

struct RenderScore {
  double psnr = 0, ssim = 0;
  int frames = 0;
  // Renderer II: the render's coverage against the mask (IoU), and PSNR over
  // the pixels both cover.
  double iou = 0, psnr_both = 0;
  // Of the pixels both cover, those kInnerPx or more inside the mask's
  // outline: their PSNR and their share.
  double psnr_inner = 0, inner_share = 0;
  // The share of the squared error, where both cover, that the 5 % of those
  // pixels furthest off hold: a colour in the wrong place (an edge of the
  // shorts a few centimetres off) against a texture a little off everywhere.
  double worst_share = 0;
  // Where both cover, by how many of the other cameras see the surface there
  // (SeenByOthers): none, one, two or more. PSNR (summed over the frames
  // with such pixels, counted in seen_frames) and share.
  std::array<double, 3> seen_psnr{}, seen_share{};
  std::array<int, 3> seen_frames{};
  int coverage_frames = 0;
  // Where the error over the mask is: the share of the mask's pixels the
  // render misses, the render's pixels beyond the mask (as a share of the
  // mask), and the share of the squared error that the missed pixels hold.
  double missed = 0, beyond = 0, missed_error = 0;
  // PSNR as the learned methods' papers score novel views (BoxScore).
  double psnr_box = 0;
};

// Pixels this far inside the mask's outline (the half side of a square) are
// also scored apart: what a pose, a calibration or a mask a few pixels off
// moves is the outline, so there the error is the texture's own.
constexpr int kInnerPx = 12;

// The projection of the posed model's (`posed`: its vertices) 3D bounding box, grown by 5 cm each
// way, into `camera`: the region the learned human-rendering methods (Neural
// Body and those it compares with, on ZJU-MoCap) score a novel view over,
// with the background black in both images. Convex: the hull of the corners.
Image BoxRegion(const std::vector<Eigen::Vector3f>& posed, const Camera& camera) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = -lo;
  for (const Eigen::Vector3f& p : posed) {
    lo = lo.cwiseMin(p.cast<double>()), hi = hi.cwiseMax(p.cast<double>());
  }
  lo.array() -= 0.05, hi.array() += 0.05;
  std::vector<Eigen::Vector2d> corners;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d x(c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(),
                            c & 4 ? hi.z() : lo.z());
    Eigen::Vector2d q;
    if (ProjectPoint(camera, x, &q)) corners.push_back(q);
  }
  Image region;
  region.width = camera.width, region.height = camera.height, region.channels = 1;
  region.pixels.assign(size_t(region.width) * region.height, 0);
  if (corners.size() < 3) return region;
  // The convex hull (monotone chain), counter-clockwise in image axes.
  std::sort(corners.begin(), corners.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  const auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> hull(2 * corners.size());
  size_t k = 0;
  for (size_t i = 0; i < corners.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], corners[i]) <= 0) --k;
    hull[k++] = corners[i];
  }
  for (size_t i = corners.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], corners[i]) <= 0) --k;
    hull[k++] = corners[i];
  }
  hull.resize(k - 1);
  // Only the hull's bounding box can be inside it.
  Eigen::Vector2d lo2 = hull[0], hi2 = hull[0];
  for (const Eigen::Vector2d& h : hull) lo2 = lo2.cwiseMin(h), hi2 = hi2.cwiseMax(h);
  const int x0 = std::max(0, int(std::floor(lo2.x()))), y0 = std::max(0, int(std::floor(lo2.y())));
  const int x1 = std::min(int(region.width) - 1, int(std::ceil(hi2.x())));
  const int y1 = std::min(int(region.height) - 1, int(std::ceil(hi2.y())));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const Eigen::Vector2d q(x, y);
      bool inside = true;
      for (size_t i = 0; i < hull.size() && inside; ++i) {
        inside = cross(hull[i], hull[(i + 1) % hull.size()], q) >= 0;
      }
      region.pixels[size_t(y) * region.width + x] = inside ? 255 : 0;
    }
  }
  return region;
}

// PSNR over `box` with the background black in both: the footage outside the
// actor's mask, the render outside its coverage.
double BoxPsnr(const Image& real, const Image& mask, const Image& render, const Image& coverage,
               const Image& box) {
  double se = 0;
  int64_t count = 0;
  for (size_t i = 0; i < box.pixels.size(); ++i) {
    if (!box.pixels[i]) continue;
    for (int k = 0; k < 3; ++k) {
      const double a = mask.pixels[i] ? real.pixels[3 * i + k] : 0;
      const double b = coverage.pixels[i] ? render.pixels[3 * i + k] : 0;
      se += (a - b) * (a - b);
    }
    count += 3;
  }
  if (count == 0) return 0;
  return 10 * std::log10(255.0 * 255.0 / std::max(se / double(count), 1e-10));
}

// The squared RGB error of pixel `i`.
double PixelSquaredError(const Image& real, const Image& render, size_t i) {
  double se = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = double(real.pixels[3 * i + k]) - render.pixels[3 * i + k];
    se += d * d;
  }
  return se;
}

// Per pixel of `camera`'s view, how many of the other cameras see the fitted
// body's surface there (`posed`: its vertices; 0-3, 3 for three or more; 255
// where the body is not):
// the view's depth taken to the surface point, which another camera sees
// when it lies in its image, within 3 cm of its depth map and inside its
// mask. What one camera alone sees, a held-out view gets from that camera
// through the surface's depth; what two see agrees between them.
std::vector<uint8_t> SeenByOthers(const Mesh& mesh, const std::vector<Eigen::Vector3f>& posed,
                                  const std::vector<Camera>& cameras,
                                  const std::vector<Image>& masks, size_t camera) {
  const Camera& view = cameras[camera];
  const DepthMap depth = RenderDepthMap(mesh.triangles, posed, view);
  std::vector<DepthMap> others(cameras.size());
  for (size_t c = 0; c < cameras.size(); ++c) {
    if (c != camera) others[c] = RenderDepthMap(mesh.triangles, posed, cameras[c]);
  }
  std::vector<uint8_t> seen(depth.depth.size(), 255);
  for (int y = 0; y < depth.height; ++y) {
    for (int x = 0; x < depth.width; ++x) {
      const float z = depth.depth[size_t(y) * depth.width + x];
      if (!std::isfinite(z)) continue;
      const Eigen::Vector3d p = UnprojectPixel(view, Eigen::Vector2d(x, y), z);
      uint8_t count = 0;
      for (size_t c = 0; c < cameras.size(); ++c) {
        if (c == camera) continue;
        Eigen::Vector2d q;
        double zc = 0;
        if (!ProjectPoint(cameras[c], p, &q, &zc)) continue;
        const int qx = int(std::lround(q.x())), qy = int(std::lround(q.y()));
        if (qx < 0 || qy < 0 || qx >= int(masks[c].width) || qy >= int(masks[c].height)) continue;
        if (!masks[c].pixels[size_t(qy) * masks[c].width + qx]) continue;
        if (zc > others[c].At(q) + 0.03) continue;
        ++count;
      }
      seen[size_t(y) * depth.width + x] = std::min<uint8_t>(count, 3);
    }
  }
  return seen;
}

// The share of the squared RGB error over the region that its `fraction` of
// pixels with the largest errors hold.
double WorstShare(const Image& real, const Image& render, const Image& region, double fraction) {
  std::vector<double> errors;
  double all = 0;
  for (size_t i = 0; i < region.pixels.size(); ++i) {
    if (!region.pixels[i]) continue;
    const double se = PixelSquaredError(real, render, i);
    errors.push_back(se), all += se;
  }
  const size_t n = size_t(std::ceil(fraction * double(errors.size())));
  if (n == 0 || all <= 0) return 0;
  std::nth_element(errors.begin(), errors.begin() + (n - 1), errors.end(), std::greater<double>());
  double worst = 0;
  for (size_t i = 0; i < n; ++i) worst += errors[i];
  return worst / all;
}

// The squared RGB error summed over the region's pixels.
double SquaredError(const Image& real, const Image& render, const Image& region) {
  double se = 0;
  for (size_t i = 0; i < region.pixels.size(); ++i) {
    if (region.pixels[i]) se += PixelSquaredError(real, render, i);
  }
  return se;
}

// PSNR (RGB) over the region's pixels; false for an empty region.
bool RegionPsnr(const Image& real, const Image& render, const Image& region, double* psnr) {
  int64_t count = 0;
  for (uint8_t v : region.pixels) count += v ? 3 : 0;
  if (count == 0) return false;
  const double mse = std::max(SquaredError(real, render, region) / double(count), 1e-10);
  *psnr = 10 * std::log10(255.0 * 255.0 / mse);
  return true;
}

double Iou(const Image& a, const Image& b) {
  int64_t inter = 0, uni = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const bool x = a.pixels[i] != 0, y = b.pixels[i] != 0;
    inter += x && y, uni += x || y;
  }
  return uni ? double(inter) / double(uni) : 0;
}

// Mean distance (pixels) of the model's joints from the confident sightings
// (-1 without any), and their mean signed offset.
double JointDistance(const BodyModel& model, const std::vector<double>& dofs, const Camera& cam,
                     const std::vector<JointSighting>& sightings, Eigen::Vector2d* offset) {
  const std::vector<Eigen::Vector3d> joints = JointPositions(model.skeleton, dofs);
  double sum = 0;
  int n = 0;
  offset->setZero();
  for (const JointSighting& s : sightings) {
    if (s.confidence < 0.5) continue;
    Eigen::Vector2d p;
    if (!ProjectPoint(cam, joints[s.joint], &p)) continue;
    sum += (p - s.pixel).norm();
    *offset += p - s.pixel;
    ++n;
  }
  if (n) *offset /= n;
  return n ? sum / n : -1;
}

void Add(FitScore* s, double iou, double joint_px, const Eigen::Vector2d& offset) {
  s->iou += iou;
  ++s->frames;
  if (joint_px >= 0) s->joint_px += joint_px, s->offset += offset, ++s->joint_frames;
}

double Luma(const Image& im, size_t i) {
  const uint8_t* p = &im.pixels[3 * i];
  return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
}

// PSNR (RGB) over the region's pixels, and SSIM (luma, 7x7 windows, the
// usual constants) averaged over the windows centred in the region.
void ScoreRender(const Image& real, const Image& render, const Image& region, RenderScore* s) {
  double psnr = 0;
  if (!RegionPsnr(real, render, region, &psnr)) return;
  const double c1 = 6.5025, c2 = 58.5225;  // (0.01 * 255)^2, (0.03 * 255)^2
  double ssim = 0;
  int64_t windows = 0;
  const int w = int(real.width), h = int(real.height), r = 3;
  for (int y = r; y < h - r; y += 2) {
    for (int x = r; x < w - r; x += 2) {
      if (!region.pixels[size_t(y) * w + x]) continue;
      double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
      for (int dy = -r; dy <= r; ++dy) {
        for (int dx = -r; dx <= r; ++dx) {
          const size_t i = size_t(y + dy) * w + (x + dx);
          const double a = Luma(real, i), b = Luma(render, i);
          sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b;
        }
      }
      const double n = (2 * r + 1) * (2 * r + 1);
      const double ma = sa / n, mb = sb / n;
      const double va = saa / n - ma * ma, vb = sbb / n - mb * mb, cov = sab / n - ma * mb;
      ssim += (2 * ma * mb + c1) * (2 * cov + c2) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
      ++windows;
    }
  }
  s->psnr += psnr;
  s->ssim += windows ? ssim / double(windows) : 0;
  ++s->frames;
}

// The pixels both cover by how many other cameras see the surface there: the
// shares summed over `count` frames (or cameras), the PSNRs over seen_frames.
void PrintSeenByOthers(const RenderScore& s, double count) {
  std::printf(
      "  where both cover, the surface seen by none / one / two or more of the other cameras: "
      "%.1f / %.1f / %.1f %% of the pixels, %.2f / %.2f / %.2f dB\n",
      100 * s.seen_share[0] / count, 100 * s.seen_share[1] / count, 100 * s.seen_share[2] / count,
      s.seen_psnr[0] / std::max(1, s.seen_frames[0]),
      s.seen_psnr[1] / std::max(1, s.seen_frames[1]),
      s.seen_psnr[2] / std::max(1, s.seen_frames[2]));
}

// The box around the non-zero pixels of the masks, grown by a tenth.
struct Box {
  int x0, y0, x1, y1;
};
Box ActorBox(const std::vector<const Image*>& masks) {
  const Image& m0 = *masks[0];
  Box b{int(m0.width), int(m0.height), -1, -1};
  for (const Image* m : masks) {
    for (uint32_t y = 0; y < m->height; ++y) {
      for (uint32_t x = 0; x < m->width; ++x) {
        if (!m->pixels[size_t(y) * m->width + x]) continue;
        b.x0 = std::min(b.x0, int(x)), b.x1 = std::max(b.x1, int(x));
        b.y0 = std::min(b.y0, int(y)), b.y1 = std::max(b.y1, int(y));
      }
    }
  }
  if (b.x1 < 0) return {0, 0, int(m0.width) - 1, int(m0.height) - 1};
  const int gx = (b.x1 - b.x0) / 10 + 8, gy = (b.y1 - b.y0) / 10 + 8;
  return {std::max(0, b.x0 - gx), std::max(0, b.y0 - gy), std::min(int(m0.width) - 1, b.x1 + gx),
          std::min(int(m0.height) - 1, b.y1 + gy)};
}

// `image` (RGB) cropped to `box` and scaled to `height` rows (nearest).
Image CropScaled(const Image& image, const Box& box, uint32_t height) {
  const int bw = box.x1 - box.x0 + 1, bh = box.y1 - box.y0 + 1;
  Image out;
  out.height = height;
  out.width = std::max<uint32_t>(1, uint32_t(std::lround(double(bw) * height / bh)));
  out.channels = 3;
  out.pixels.resize(size_t(out.width) * out.height * 3);
  for (uint32_t y = 0; y < out.height; ++y) {
    const int sy = box.y0 + std::min(bh - 1, int(y * bh / out.height));
    for (uint32_t x = 0; x < out.width; ++x) {
      const int sx = box.x0 + std::min(bw - 1, int(x * bw / out.width));
      for (int k = 0; k < 3; ++k)
        out.pixels[(size_t(y) * out.width + x) * 3 + k] =
            image.pixels[(size_t(sy) * image.width + sx) * 3 + k];
    }
  }
  return out;
}

// The frame with `mask` tinted red, or with the model and the mask drawn as
// fvv track's overlays do (model only red, mask only blue).
Image Tinted(const Image& frame, const Image& mask, const Image* model) {
  Image out = frame;
  for (size_t i = 0; i < mask.pixels.size(); ++i) {
    uint8_t* p = &out.pixels[3 * i];
    const bool s = mask.pixels[i] != 0;
    if (!model) {
      if (s) p[0] = uint8_t((p[0] + 255) / 2), p[1] /= 2, p[2] /= 2;
      continue;
    }
    const bool m = model->pixels[i] != 0;
    if (m == s) continue;
    p[0] = m ? 255 : 0, p[1] = 0, p[2] = m ? 0 : 255;
  }
  return out;
}

// Where Renderer II's view is off, drawn on the footage (dimmed): red where
// render and mask both cover and the colour is more than `levels` off (RMS
// over R, G and B), blue where the mask has the actor and the render nothing.
Image ErrorView(const Image& real, const Image& render, const Image& mask, const Image& coverage,
                double levels) {
  Image out = real;
  for (size_t i = 0; i < mask.pixels.size(); ++i) {
    uint8_t* p = &out.pixels[3 * i];
    const bool in = mask.pixels[i] != 0, covered = coverage.pixels[i] != 0;
    if (in && covered && PixelSquaredError(real, render, i) > 3 * levels * levels) {
      p[0] = 255, p[1] = 0, p[2] = 0;
    } else if (in && !covered) {
      p[0] = 0, p[1] = 0, p[2] = 255;
    } else {
      for (int k = 0; k < 3; ++k) p[k] = uint8_t(p[k] / 3);
    }
  }
  return out;
}

int Fail(const Status& s) {
  std::fprintf(stderr, "real_bench: %s\n", s.ToString().c_str());
  return 1;
}

Status RunFvv(const Args& a, std::vector<std::string> args) {
  args.insert(args.begin(), a.fvv);
  int code = 0;
  StatusOr<std::string> out = RunForOutput(args, &code);
  if (!out.ok()) return out.status();
  if (code != 0) {
    std::string line;
    for (const std::string& s : args) line += s + " ";
    return IoError("'" + line + "' exited with " + std::to_string(code));
  }
  return Status::Ok();
}

std::string Absolute(const std::string& directory, const std::string& path) {
  if (path.empty() || path[0] == '/') return path;
  // The capture given by a relative path: its files from where this runs.
  return std::filesystem::absolute(directory).lexically_normal().string() + "/" + path;
}

// The capture without camera `k`, in `directory`, its sources by absolute path.
Capture WithoutCamera(const Capture& full, uint32_t k, const std::string& directory) {
  Capture c = full;
  c.directory = directory;
  c.cameras.erase(c.cameras.begin() + k);
  for (CaptureCamera& cam : c.cameras) {
    cam.frames.path = Absolute(full.directory, cam.frames.path);
    if (cam.background) cam.background = Absolute(full.directory, *cam.background);
    if (cam.silhouettes) cam.silhouettes->path = Absolute(full.directory, cam.silhouettes->path);
  }
  return c;
}

int Run(const Args& a) {
  StatusOr<Capture> loaded = LoadCapture(a.capture);
  if (!loaded.ok()) {
    std::fprintf(stderr, "real_bench: %s\n", loaded.status().ToString().c_str());
    return 1;
  }
  const Capture full = *loaded;
  const uint32_t n = uint32_t(full.cameras.size());
  const uint32_t first = a.first, last = std::min(a.last, full.frame_count - 1);
  if (n < 3 || first > last) {
    std::fprintf(stderr, "real_bench: needs 3 cameras or more and frames within the capture\n");
    return 1;
  }
  const std::string models = a.models.empty() ? DefaultModelDirectory() : a.models;
  StatusOr<std::unique_ptr<PersonObserver>> observer = PersonObserver::Load(models);
  if (!observer.ok()) {
    std::fprintf(stderr, "real_bench: %s (the person network scores the held-out cameras)\n",
                 observer.status().ToString().c_str());
    return 1;
  }
  if (Status s = MakeDirectories(a.out); !s.ok()) {
    std::fprintf(stderr, "real_bench: %s\n", s.ToString().c_str());
    return 1;
  }
  std::printf("real_bench: %s, %u cameras, frames %u..%u\n", full.directory.c_str(), n, first,
              last);

  // The network's masks and keypoints in every camera: the reference.
  Reference ref;
  {
    ThreadPool pool(2);
    StatusOr<std::unique_ptr<CaptureFrames>> frames =
        CaptureFrames::Open(full, false, &pool, observer->get());
    if (!frames.ok()) {
      std::fprintf(stderr, "real_bench: %s\n", frames.status().ToString().c_str());
      return 1;
    }
    for (uint32_t f = first; f <= last; ++f) {
      std::vector<Image> sils;
      if (Status s = (*frames)->Read(f, nullptr, &sils); !s.ok()) {
        std::fprintf(stderr, "real_bench: %s\n", s.ToString().c_str());
        return 1;
      }
      ref.masks.push_back(std::move(sils));
      ref.sightings.push_back((*frames)->sightings());
    }
  }

  std::vector<Camera> calibrations;
  for (const CaptureCamera& c : full.cameras) calibrations.push_back(c.calibration);
  nlohmann::json report;
  report["capture"] = full.directory;
  report["frames"] = {first, last};
  std::vector<Image> sheet;
  std::vector<FitScore> held(n), own(n);
  std::vector<RenderScore> renderer2(n), renderer2_masks(n), renderer1(n);
  // Renderer II in the rig's common colour, as the stream carries it: before
  // the held-out camera's own colour response (its colour_gain undone).
  std::vector<RenderScore> renderer2_rig_colour(n);
  // The surface as rendered from the cameras the stream was made from, against
  // their own masks (the floor the held-out IoU is read beside).
  std::vector<double> own_rendered_iou(n, 0);
  std::vector<int> own_rendered_frames(n, 0);
  struct Times {
    double decode = 0, persons = 0, masks = 0, initialise = 0, fit = 0;
  };
  std::vector<Times> times(n);
  std::vector<uint32_t> scored;
  for (uint32_t k = 0; k < n; ++k) {
    if (a.held_out.empty() || full.cameras[k].calibration.name == a.held_out) scored.push_back(k);
  }
  if (scored.empty()) {
    std::fprintf(stderr, "real_bench: --held-out %s: no such camera\n", a.held_out.c_str());
    return 1;
  }
  for (uint32_t k : scored) {
    const std::string name = full.cameras[k].calibration.name;
    const std::string dir = a.out + "/without_" + name;
    Capture part = WithoutCamera(full, k, dir);
    if (Status s = MakeDirectories(dir); !s.ok()) return Fail(s);
    if (Status s = SaveCapture(part); !s.ok()) return Fail(s);
    TrackCaptureOptions o;
    o.first = first, o.last = last;
    o.persons = TrackCaptureOptions::Persons::kOn;
    o.person_models = models;
    std::printf("camera %s held out: tracking with the other %u\n", name.c_str(), n - 1);
    std::fflush(stdout);
    StatusOr<TrackCaptureResult> r = TrackCapture(dir, o);
    if (!r.ok()) {
      std::fprintf(stderr, "real_bench: %s\n", r.status().ToString().c_str());
      return 1;
    }
    const std::string poses = dir + "/poses.json";
    const std::string json = r->ToJson();
    const Status written =
        WriteFileAtomic(poses, reinterpret_cast<const uint8_t*>(json.data()), json.size());
    if (!written.ok()) return Fail(written);
    Times& t = times[k];
    const double frames = double(last - first + 1);
    t.decode = r->decode_seconds / frames;
    t.persons = r->person_seconds / frames;
    t.masks = (r->silhouette_seconds - r->decode_seconds - r->person_seconds) / frames;
    t.initialise = r->fits.empty() ? 0 : r->first_fit_seconds;
    t.fit = frames > 1 ? (r->fit_seconds - r->first_fit_seconds) / (frames - 1) : 0;
    SilhouetteShiftSearch shift_search;
    std::vector<Image> held_models;
    for (uint32_t f = first; f <= last; ++f) {
      const double agreement = KeypointAgreement(calibrations, k, ref.sightings[f - first], 20.0);
      if (agreement >= 0) held[k].agreement_px += agreement, ++held[k].agreement_frames;
      const std::vector<double>& dofs = r->fits[f - first].dofs;
      for (uint32_t c = 0; c < n; ++c) {
        const Camera& cam = full.cameras[c].calibration;
        const Image model = BodySilhouette(r->model, cam, dofs);
        const double iou = Iou(model, ref.masks[f - first][c]);
        Eigen::Vector2d offset;
        const double px = JointDistance(r->model, dofs, cam, ref.sightings[f - first][c], &offset);
        Add(c == k ? &held[k] : &own[k], iou, px, offset);
        if (c == k) {
          shift_search.Add(model, ref.masks[f - first][c]);
          held_models.push_back(model);
        }
      }
    }
    {
      // How much of the held-out shortfall one image shift (a small turn of
      // the camera against the others) explains: a diagnosis of the
      // calibration, not a score (the shift is taken from the held-out masks).
      const Eigen::Vector2d best = shift_search.Best().pixels;
      const Eigen::Vector2i shift(int(std::lround(best.x())), int(std::lround(best.y())));
      double sum = 0;
      for (uint32_t f = first; f <= last; ++f) {
        sum +=
            ShiftedMaskIou(held_models[f - first], ref.masks[f - first][k], shift.x(), shift.y());
      }
      held[k].shift = shift;
      held[k].shifted_iou = sum / double(held_models.size());
    }
    const FitScore& h = held[k];
    std::printf(
        "  held out: IoU %.3f, joints %.1f px (mean offset %+.1f, %+.1f px; the others' "
        "keypoints %.1f px); used cameras: IoU %.3f, joints %.1f px; IoU %.3f with the model "
        "shifted %+d, %+d px in every frame\n",
        h.iou / h.frames, h.joint_frames ? h.joint_px / h.joint_frames : -1.0,
        h.joint_frames ? h.offset.x() / h.joint_frames : 0.0,
        h.joint_frames ? h.offset.y() / h.joint_frames : 0.0,
        h.agreement_frames ? h.agreement_px / h.agreement_frames : -1.0, own[k].iou / own[k].frames,
        own[k].joint_frames ? own[k].joint_px / own[k].joint_frames : -1.0, h.shifted_iou,
        h.shift.x(), h.shift.y());

    const uint32_t render_last = std::min(last, first + std::max(1u, a.render_frames) - 1);
    std::vector<Image> rendered2, rendered1, errors2;
    Image between_view;
    if (a.render) {
      const std::string range = std::to_string(first) + ":" + std::to_string(render_last);
      const std::string stream = dir + "/stream.fvv";
      std::printf("  encoding frames %s from the other cameras, rendering camera %s's view\n",
                  range.c_str(), name.c_str());
      std::fflush(stdout);
      // The default stream, and beside it one with shape masks at the same
      // total bytes (docs/encoder.md, "Streams without masks").
      const std::string masked = dir + "/stream_masks.fvv", masked_json = masked + ".json";
      std::vector<std::string> masked_args = {
          "encode",   dir,   "-o",      masked, "--poses",        poses,
          "--frames", range, "--masks", "-q",   "--summary-json", masked_json};
      const std::vector<std::string> options = EncodeOptions(a);
      masked_args.insert(masked_args.end(), options.begin(), options.end());
      if (!a.psnr.empty()) masked_args.insert(masked_args.end(), {"--psnr", a.psnr});
      Status s = RunFvv(a, masked_args);
      StatusOr<nlohmann::json> masked_summary = ReadJson(masked_json);
      if (s.ok() && !masked_summary.ok()) s = masked_summary.status();
      if (s.ok()) {
        const nlohmann::json& b = (*masked_summary)["bytes"];
        const uint64_t per_gop = (b["texture"].get<uint64_t>() + b["masks"].get<uint64_t>()) /
                                 std::max<uint64_t>(1, (*masked_summary)["gops"].get<uint64_t>());
        std::vector<std::string> args = {
            "encode", dir,        "-o",  stream,    "--poses",
            poses,    "--frames", range, "--bytes", std::to_string(per_gop),
            "-q"};
        args.insert(args.end(), options.begin(), options.end());
        s = RunFvv(a, args);
      }
      const std::string out2 = dir + "/renderer2", out2m = dir + "/renderer2_masks",
                        out1 = dir + "/renderer1";
      if (s.ok()) {
        s = RunFvv(a, {"render", stream, "--cameras-from", full.directory, "--camera",
                       std::to_string(k), "-o", out2, "--coverage"});
      }
      if (s.ok()) {
        s = RunFvv(a, {"render", masked, "--cameras-from", full.directory, "--camera",
                       std::to_string(k), "-o", out2m});
      }
      if (s.ok()) {
        s = RunFvv(a, {"render", dir, "--renderer", "projective", "--poses", poses,
                       "--cameras-from", full.directory, "--camera", std::to_string(k), "--first",
                       std::to_string(first), "--last", std::to_string(render_last), "-o", out1});
      }
      for (uint32_t c = 0; s.ok() && c < n; ++c) {
        if (c == k) continue;
        const std::string fitted = dir + "/renderer2_fitted_" + full.cameras[c].calibration.name;
        s = RunFvv(a, {"render", stream, "--cameras-from", full.directory, "--camera",
                       std::to_string(c), "-o", fitted, "--coverage"});
        for (uint32_t f = first; s.ok() && f <= render_last; ++f) {
          char file[64];
          std::snprintf(file, sizeof(file), "/coverage_f%05u.png", f - first);
          StatusOr<Image> coverage = ReadImage(fitted + file);
          if (!coverage.ok()) {
            s = coverage.status();
            break;
          }
          own_rendered_iou[k] += Iou(*coverage, ref.masks[f - first][c]);
          ++own_rendered_frames[k];
        }
      }
      // Between cameras: Renderer II from halfway between the held-out
      // camera and the camera nearest it, at the first frame, for the sheet.
      const std::string between = dir + "/between";
      if (s.ok()) {
        const Camera& view = full.cameras[k].calibration;
        const Eigen::Vector3d here = CameraCentre(view);
        Eigen::Vector3d nearest = here;
        double best = 1e30;
        for (size_t j = 0; j < full.cameras.size(); ++j) {
          const double d = (CameraCentre(full.cameras[j].calibration) - here).norm();
          if (j != k && d < best) best = d, nearest = CameraCentre(full.cameras[j].calibration);
        }
        const Eigen::Vector3d eye = (here + nearest) / 2;
        const double fov = 2 * std::atan(view.height / (2 * view.fy)) * 180 / M_PI;
        const nlohmann::json path = {{"keyframes",
                                      {{{"frame", 0},
                                        {"eye", {eye.x(), eye.y(), eye.z()}},
                                        {"target", "actor"},
                                        {"fov", fov}}}}};
        const std::string text = path.dump(), path_file = dir + "/between_path.json";
        s = WriteFileAtomic(path_file, reinterpret_cast<const uint8_t*>(text.data()), text.size());
        if (s.ok()) {
          s = RunFvv(
              a, {"render", stream, "--path", path_file, "--first", "0", "--last", "0", "--size",
                  std::to_string(view.width / 2) + "x" + std::to_string(view.height / 2), "-o",
                  between, "--coverage"});
        }
      }
      if (!s.ok()) {
        std::fprintf(stderr, "real_bench: %s\n", s.ToString().c_str());
        return 1;
      }
      StatusOr<Image> b = ReadImage(between + "/render_f00000.png");
      StatusOr<Image> b_coverage = ReadImage(between + "/coverage_f00000.png");
      if (b.ok() && b_coverage.ok()) {
        between_view = CropScaled(*b, ActorBox({&*b_coverage}), 480);
      }
      CaptureReader reader(full);
      for (uint32_t f = first; f <= render_last; ++f) {
        StatusOr<Image> real = reader.ReadFrame(k, f);
        char file[64];
        // The stream numbers its frames from 0; Renderer I keeps the capture's.
        std::snprintf(file, sizeof(file), "/render_f%05u.png", f - first);
        StatusOr<Image> two = ReadImage(out2 + file);
        StatusOr<Image> two_masks = ReadImage(out2m + file);
        std::snprintf(file, sizeof(file), "/render_f%05u.png", f);
        StatusOr<Image> one = ReadImage(out1 + file);
        if (!real.ok() || !two.ok() || !one.ok() || !two_masks.ok()) {
          std::fprintf(stderr, "real_bench: frame %u of camera %s: %s\n", f, name.c_str(),
                       (!real.ok()        ? real.status()
                        : !two.ok()       ? two.status()
                        : !two_masks.ok() ? two_masks.status()
                                          : one.status())
                           .ToString()
                           .c_str());
          return 1;
        }
        const Image& region = ref.masks[f - first][k];
        ScoreRender(*real, *two, region, &renderer2_rig_colour[k]);
        // The renders are in the rig's common colour; the held-out camera
        // sees it through its own response (its calibration, like its pose).
        const std::array<double, 3> response = InverseGain(full.cameras[k].colour_gain);
        for (Image* im : {&*two, &*two_masks, &*one}) ApplyColourGain(response, im);
        ScoreRender(*real, *two, region, &renderer2[k]);
        // What the surface as rendered covers: against the mask, and the
        // pixels both cover (where the texture, not the outline, is scored).
        std::snprintf(file, sizeof(file), "/coverage_f%05u.png", f - first);
        StatusOr<Image> coverage = ReadImage(out2 + file);
        if (!coverage.ok()) {
          std::fprintf(stderr, "real_bench: %s\n", coverage.status().ToString().c_str());
          return 1;
        }
        Image both = region, missed = region;
        int64_t area = 0, missed_area = 0, beyond_area = 0;
        for (size_t i = 0; i < both.pixels.size(); ++i) {
          const bool in = region.pixels[i] != 0, covered = coverage->pixels[i] != 0;
          both.pixels[i] = in && covered ? 255 : 0;
          missed.pixels[i] = in && !covered ? 255 : 0;
          area += in, missed_area += in && !covered, beyond_area += covered && !in;
        }
        RenderScore both_score;
        ScoreRender(*real, *two, both, &both_score);
        const std::vector<uint8_t> deep =
            DilateMask(region.pixels.data(), int(region.width), int(region.height), -kInnerPx);
        Image inner = both;
        int64_t both_area = 0, inner_area = 0;
        for (size_t i = 0; i < inner.pixels.size(); ++i) {
          inner.pixels[i] = both.pixels[i] && deep[i] ? 255 : 0;
          both_area += both.pixels[i] != 0, inner_area += inner.pixels[i] != 0;
        }
        double inner_psnr = 0;
        if (RegionPsnr(*real, *two, inner, &inner_psnr)) renderer2[k].psnr_inner += inner_psnr;
        renderer2[k].inner_share += both_area ? double(inner_area) / double(both_area) : 0;
        renderer2[k].worst_share += WorstShare(*real, *two, both, 0.05);
        // The fitted body in this frame, for what the other cameras see and
        // for the box the learned methods score.
        const std::vector<Eigen::Vector3f> posed = SkinPositions(
            r->model.mesh, SkinningMatrices(r->model.skeleton, r->fits[f - first].dofs));
        const std::vector<uint8_t> seen =
            SeenByOthers(r->model.mesh, posed, calibrations, ref.masks[f - first], k);
        for (int c = 0; c < 3; ++c) {
          Image by = both;
          int64_t count = 0;
          for (size_t i = 0; i < by.pixels.size(); ++i) {
            const bool in = both.pixels[i] && seen[i] != 255 && std::min<int>(seen[i], 2) == c;
            by.pixels[i] = in ? 255 : 0;
            count += in;
          }
          if (count == 0 || both_area == 0) continue;
          double by_psnr = 0;
          RegionPsnr(*real, *two, by, &by_psnr);
          renderer2[k].seen_psnr[c] += by_psnr;
          renderer2[k].seen_share[c] += double(count) / double(both_area);
          ++renderer2[k].seen_frames[c];
        }
        if (area > 0) {
          const double all = SquaredError(*real, *two, region);
          renderer2[k].missed += double(missed_area) / double(area);
          renderer2[k].beyond += double(beyond_area) / double(area);
          renderer2[k].missed_error += all > 0 ? SquaredError(*real, *two, missed) / all : 0;
        }
        renderer2[k].psnr_box +=
            BoxPsnr(*real, region, *two, *coverage, BoxRegion(posed, full.cameras[k].calibration));
        renderer2[k].iou += Iou(*coverage, region);
        renderer2[k].psnr_both += both_score.psnr;
        ++renderer2[k].coverage_frames;
        ScoreRender(*real, *two_masks, region, &renderer2_masks[k]);
        ScoreRender(*real, *one, region, &renderer1[k]);
        if (f == first) {
          rendered2.push_back(*two), rendered1.push_back(*one);
          errors2.push_back(ErrorView(*real, *two, region, *coverage, 60));
        }
      }
      std::printf(
          "  Renderer II: IoU %.3f as rendered, PSNR %.2f dB (%.2f dB where both cover, %.2f dB "
          "of them %d px or more inside the outline; %.2f dB "
          "in the rig's colour, before the camera's response), SSIM "
          "%.3f (with masks, same bytes: %.2f dB, %.3f); Renderer I: PSNR %.2f dB, SSIM %.3f\n",
          renderer2[k].iou / renderer2[k].coverage_frames, renderer2[k].psnr / renderer2[k].frames,
          renderer2[k].psnr_both / renderer2[k].coverage_frames,
          renderer2[k].psnr_inner / renderer2[k].coverage_frames, kInnerPx,
          renderer2_rig_colour[k].psnr / renderer2_rig_colour[k].frames,
          renderer2[k].ssim / renderer2[k].frames,
          renderer2_masks[k].psnr / renderer2_masks[k].frames,
          renderer2_masks[k].ssim / renderer2_masks[k].frames,
          renderer1[k].psnr / renderer1[k].frames, renderer1[k].ssim / renderer1[k].frames);
      std::printf("  Renderer II from the cameras the stream was made from: IoU %.3f as rendered\n",
                  own_rendered_iou[k] / std::max(1, own_rendered_frames[k]));
      std::printf(
          "  Renderer II misses %.1f %% of the mask (%.1f %% of the squared error), covers %.1f "
          "%% of its area beyond it; %.2f dB over the actor's box, background black; where both "
          "cover, the 5 %% of pixels furthest off hold %.1f %% of the squared error\n",
          100 * renderer2[k].missed / renderer2[k].coverage_frames,
          100 * renderer2[k].missed_error / renderer2[k].coverage_frames,
          100 * renderer2[k].beyond / renderer2[k].coverage_frames,
          renderer2[k].psnr_box / renderer2[k].coverage_frames,
          100 * renderer2[k].worst_share / renderer2[k].coverage_frames);
      PrintSeenByOthers(renderer2[k], renderer2[k].coverage_frames);
    }
    // Contact sheet row: the real frame, the network's mask, the fitted
    // model against it, Renderer I, Renderer II and where it is off.
    StatusOr<Image> real = CaptureReader(full).ReadFrame(k, first);
    if (real.ok()) {
      const Image& mask = ref.masks[0][k];
      const Image model = BodySilhouette(r->model, full.cameras[k].calibration, r->fits[0].dofs);
      const Box box = ActorBox({&mask, &model});
      sheet.push_back(CropScaled(*real, box, 480));
      sheet.push_back(CropScaled(Tinted(*real, mask, nullptr), box, 480));
      sheet.push_back(CropScaled(Tinted(*real, mask, &model), box, 480));
      for (const Image* im :
           {rendered1.empty() ? nullptr : &rendered1[0],
            rendered2.empty() ? nullptr : &rendered2[0], errors2.empty() ? nullptr : &errors2[0]}) {
        if (im) sheet.push_back(CropScaled(*im, box, 480));
      }
      if (!between_view.pixels.empty()) sheet.push_back(between_view);
    }
  }

  // The table.
  std::printf("\nleave one camera out, frames %u..%u (pixels at full resolution)\n", first, last);
  std::printf("%-10s %8s %9s %9s %8s %9s %8s %9s %9s %8s %9s %8s\n", "held out", "IoU", "joints",
              "kp agree", "shifted", "by (px)", "own IoU", "own jts", "II PSNR", "II SSIM",
              "I PSNR", "I SSIM");
  FitScore all_held, all_own;
  RenderScore all2, all1;
  double all_own_rendered = 0;
  nlohmann::json rows = nlohmann::json::array();
  for (uint32_t k : scored) {
    const FitScore &h = held[k], &w = own[k];
    const double hj = h.joint_frames ? h.joint_px / h.joint_frames : -1;
    const double wj = w.joint_frames ? w.joint_px / w.joint_frames : -1;
    const double agree = h.agreement_frames ? h.agreement_px / h.agreement_frames : -1;
    const RenderScore &r2 = renderer2[k], &r1 = renderer1[k];
    auto mean = [](double v, int count) { return count ? v / count : 0.0; };
    const std::string by = std::to_string(h.shift.x()) + "," + std::to_string(h.shift.y());
    std::printf("%-10s %8.3f %9.1f %9.1f %8.3f %9s %8.3f %9.1f %9.2f %8.3f %9.2f %8.3f\n",
                full.cameras[k].calibration.name.c_str(), h.iou / h.frames, hj, agree,
                h.shifted_iou, by.c_str(), w.iou / w.frames, wj, mean(r2.psnr, r2.frames),
                mean(r2.ssim, r2.frames), mean(r1.psnr, r1.frames), mean(r1.ssim, r1.frames));
    rows.push_back(
        {{"camera", full.cameras[k].calibration.name},
         {"held_out_iou", h.iou / h.frames},
         {"held_out_joint_px", hj},
         {"held_out_shift_px", {h.shift.x(), h.shift.y()}},
         {"held_out_shifted_iou", h.shifted_iou},
         {"held_out_joint_offset_px",
          {h.joint_frames ? h.offset.x() / h.joint_frames : 0.0,
           h.joint_frames ? h.offset.y() / h.joint_frames : 0.0}},
         {"keypoint_agreement_px", agree},
         {"own_iou", w.iou / w.frames},
         {"own_joint_px", wj},
         {"renderer2_psnr", mean(r2.psnr, r2.frames)},
         {"renderer2_psnr_rig_colour",
          mean(renderer2_rig_colour[k].psnr, renderer2_rig_colour[k].frames)},
         {"colour_gain", full.cameras[k].colour_gain},
         {"renderer2_iou", mean(r2.iou, r2.coverage_frames)},
         {"renderer2_own_iou", mean(own_rendered_iou[k], own_rendered_frames[k])},
         {"renderer2_psnr_both_cover", mean(r2.psnr_both, r2.coverage_frames)},
         {"renderer2_psnr_inner", mean(r2.psnr_inner, r2.coverage_frames)},
         {"renderer2_inner_share", mean(r2.inner_share, r2.coverage_frames)},
         {"renderer2_worst5_error_share", mean(r2.worst_share, r2.coverage_frames)},
         {"renderer2_seen_by_others",
          {{"share",
            {mean(r2.seen_share[0], r2.coverage_frames), mean(r2.seen_share[1], r2.coverage_frames),
             mean(r2.seen_share[2], r2.coverage_frames)}},
           {"psnr",
            {mean(r2.seen_psnr[0], r2.seen_frames[0]), mean(r2.seen_psnr[1], r2.seen_frames[1]),
             mean(r2.seen_psnr[2], r2.seen_frames[2])}}}},
         {"renderer2_missed_share", mean(r2.missed, r2.coverage_frames)},
         {"renderer2_psnr_box", mean(r2.psnr_box, r2.coverage_frames)},
         {"renderer2_beyond_share", mean(r2.beyond, r2.coverage_frames)},
         {"renderer2_missed_error_share", mean(r2.missed_error, r2.coverage_frames)},
         {"renderer2_ssim", mean(r2.ssim, r2.frames)},
         {"renderer2_masks_psnr", mean(renderer2_masks[k].psnr, renderer2_masks[k].frames)},
         {"renderer2_masks_ssim", mean(renderer2_masks[k].ssim, renderer2_masks[k].frames)},
         {"renderer1_psnr", mean(r1.psnr, r1.frames)},
         {"renderer1_ssim", mean(r1.ssim, r1.frames)},
         {"seconds_per_frame",
          {{"decode", times[k].decode},
           {"person_network", times[k].persons},
           {"masks", times[k].masks},
           {"fit", times[k].fit},
           {"first_frame_fit", times[k].initialise}}}});
    all_held.iou += h.iou / h.frames, all_held.joint_px += hj, all_held.agreement_px += agree;
    all_held.shifted_iou += h.shifted_iou;
    all_own.iou += w.iou / w.frames, all_own.joint_px += wj;
    all2.psnr += mean(r2.psnr, r2.frames), all2.ssim += mean(r2.ssim, r2.frames);
    all2.iou += mean(r2.iou, r2.coverage_frames);
    all_own_rendered += mean(own_rendered_iou[k], own_rendered_frames[k]);
    all2.psnr_both += mean(r2.psnr_both, r2.coverage_frames);
    all2.psnr_inner += mean(r2.psnr_inner, r2.coverage_frames);
    all2.inner_share += mean(r2.inner_share, r2.coverage_frames);
    all2.worst_share += mean(r2.worst_share, r2.coverage_frames);
    for (int c = 0; c < 3; ++c) {
      all2.seen_share[c] += mean(r2.seen_share[c], r2.coverage_frames);
      if (r2.seen_frames[c] > 0) {
        all2.seen_psnr[c] += mean(r2.seen_psnr[c], r2.seen_frames[c]);
        ++all2.seen_frames[c];
      }
    }
    all2.missed += mean(r2.missed, r2.coverage_frames);
    all2.psnr_box += mean(r2.psnr_box, r2.coverage_frames);
    all2.beyond += mean(r2.beyond, r2.coverage_frames);
    all2.missed_error += mean(r2.missed_error, r2.coverage_frames);
    all1.psnr += mean(r1.psnr, r1.frames), all1.ssim += mean(r1.ssim, r1.frames);
  }
  const double count = double(scored.size());
  std::printf("%-10s %8.3f %9.1f %9.1f %8.3f %9s %8.3f %9.1f %9.2f %8.3f %9.2f %8.3f\n", "mean",
              all_held.iou / count, all_held.joint_px / count, all_held.agreement_px / count,
              all_held.shifted_iou / count, "", all_own.iou / count, all_own.joint_px / count,
              all2.psnr / count, all2.ssim / count, all1.psnr / count, all1.ssim / count);
  if (a.render) {
    std::printf(
        "Renderer II as rendered, mean: IoU %.3f (%.3f in the cameras the stream was made from), "
        "PSNR %.2f dB where both cover\n",
        all2.iou / count, all_own_rendered / count, all2.psnr_both / count);
    std::printf(
        "  of the pixels both cover, %.1f %% lie %d px or more inside the mask's outline: %.2f dB "
        "there; the 5 %% furthest off hold %.1f %% of their squared error\n",
        100 * all2.inner_share / count, kInnerPx, all2.psnr_inner / count,
        100 * all2.worst_share / count);
    PrintSeenByOthers(all2, count);
    std::printf(
        "  the render misses %.1f %% of the mask (%.1f %% of the squared error is there) and "
        "covers %.1f %% of the mask's area beyond it\n",
        100 * all2.missed / count, 100 * all2.missed_error / count, 100 * all2.beyond / count);
    std::printf(
        "  PSNR %.2f dB over the projection of the actor's 3D box grown by 5 cm, the background "
        "black in both (how the learned methods' papers score a novel view)\n",
        all2.psnr_box / count);
  }
  std::printf("\nseconds per frame, %u cameras tracking (after the first frame)\n", n - 1);
  std::printf("%-10s %8s %8s %8s %8s %8s %12s\n", "held out", "decode", "network", "masks", "fit",
              "total", "first frame");
  for (uint32_t k : scored) {
    const Times& t = times[k];
    std::printf("%-10s %8.2f %8.2f %8.2f %8.2f %8.2f %12.1f\n",
                full.cameras[k].calibration.name.c_str(), t.decode, t.persons, t.masks, t.fit,
                t.decode + t.persons + t.masks + t.fit, t.initialise);
  }
  report["cameras"] = rows;
  const std::string text = report.dump(1) + "\n";
  Status s = WriteFileAtomic(a.out + "/real_bench.json",
                             reinterpret_cast<const uint8_t*>(text.data()), text.size());
  if (s.ok() && !sheet.empty()) {
    s = WritePng(a.out + "/contact_sheet.png", MakeContactSheet(sheet, a.render ? 7 : 3));
  }
  if (!s.ok()) {
    std::fprintf(stderr, "real_bench: %s\n", s.ToString().c_str());
    return 1;
  }
  std::printf(
      "\nfigures: %s/real_bench.json; contact sheet (per held-out camera: frame, mask, "
      "fitted model%s): %s/contact_sheet.png\n",
      a.out.c_str(),
      a.render ? ", Renderer I, Renderer II, where Renderer II is off (red: more than 60 levels, "
                 "blue: the actor missed), Renderer II between it and the nearest camera"
               : "",
      a.out.c_str());
  return 0;
}

int Usage(const char* self, int code) {
  std::printf(
      "usage: %s CAPTURE [--frames A:B] [--render-frames N] [--out DIR] [--fvv PATH]\n"
      "       [--models DIR] [--held-out NAME] [--no-render] [--surface] [--surface-prior W]\n"
      "       [--surface-temporal W] [--surface-stereo W] [--silhouette-margin N] [--psnr P]\n"
      "       [--atlas N] [--encode-option OPT ...]\n"
      "Leave-one-camera-out tracking and rendering on a real capture (bench/README.md).\n"
      "  --frames A:B         frames to track (default 0:29)\n"
      "  --render-frames N    frames from A to encode and render per held-out camera (default 30)\n"
      "  --out DIR            where the figures, poses, streams and renders go (out/real_bench)\n"
      "  --fvv PATH           the fvv program (default: tools/fvv/fvv beside this build's bench/)\n"
      "  --models DIR         the person models (default: $FVV_MODEL_DIR or ~/.cache/fvv/models)\n"
      "  --held-out NAME      hold out this camera only (default: each in turn)\n"
      "  --no-render          tracking figures only\n"
      "  --surface            encode with the surface of every frame (fvv encode --surface)\n"
      "  --surface-prior W    with it, fvv encode --surface-prior W\n"
      "  --surface-temporal W with it, fvv encode --surface-temporal W\n"
      "  --surface-stereo W   with it, fvv encode --surface-stereo W\n"
      "  --silhouette-margin N  fvv encode --silhouette-margin N (default: the encoder's)\n"
      "  --psnr P             fvv encode --psnr P for the stream with masks, whose bytes the\n"
      "                       default stream takes (default: the encoder's rate)\n"
      "  --atlas N            fvv encode --atlas N (default: the encoder's)\n"
      "  --encode-option OPT  pass OPT to both encodes as one argument, e.g. --no-mirror-fill\n"
      "                       or --temporal-fill=0 (repeat for more)\n",
      self);
  return code;
}

}  // namespace
}  // namespace fvv

int main(int argc, char** argv) {
  using namespace fvv;
  KillChildrenOnTerminatingSignals();
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    if (s == "-h" || s == "--help") return Usage(argv[0], 0);
    if (s == "--frames") {
      const char* v = value();
      if (!v || std::sscanf(v, "%u:%u", &a.first, &a.last) != 2) return Usage(argv[0], 2);
    } else if (s == "--render-frames") {
      const char* v = value();
      if (!v || std::sscanf(v, "%u", &a.render_frames) != 1) return Usage(argv[0], 2);
    } else if (s == "--out" || s == "--fvv" || s == "--models") {
      const char* v = value();
      if (!v) return Usage(argv[0], 2);
      (s == "--out" ? a.out : s == "--fvv" ? a.fvv : a.models) = v;
    } else if (s == "--held-out") {
      const char* v = value();
      if (!v) return Usage(argv[0], 2);
      a.held_out = v;
    } else if (s == "--no-render") {
      a.render = false;
    } else if (s == "--surface") {
      a.surface = true;
    } else if (s == "--surface-prior" || s == "--surface-temporal" || s == "--surface-stereo") {
      const char* v = value();
      if (!v) return Usage(argv[0], 2);
      a.surface = true;
      a.surface_options.insert(a.surface_options.end(), {s, v});
    } else if (s == "--psnr" || s == "--atlas") {
      const char* v = value();
      if (!v) return Usage(argv[0], 2);
      (s == "--psnr" ? a.psnr : a.atlas) = v;
    } else if (s == "--encode-option") {
      const char* v = value();
      if (!v || v[0] != '-') return Usage(argv[0], 2);
      a.encode_options.push_back(v);
    } else if (s == "--silhouette-margin") {
      const char* v = value();
      int margin = 0;
      if (!v || std::sscanf(v, "%d", &margin) != 1) return Usage(argv[0], 2);
      a.silhouette_margin = std::to_string(margin);
    } else if (a.capture.empty() && s[0] != '-') {
      a.capture = s;
    } else {
      return Usage(argv[0], 2);
    }
  }
  if (a.capture.empty()) return Usage(argv[0], 2);
  if (a.fvv.empty()) {
    // This program lives in BUILD/bench/; the CLI in BUILD/tools/fvv/.
    const std::string self = argv[0];
    const size_t slash = self.rfind('/');
    a.fvv = (slash == std::string::npos ? std::string(".") : self.substr(0, slash)) +
            "/../tools/fvv/fvv";
  }
  return Run(a);
}
