#include "tools/synth/shape_comparison.h"

#include <cmath>
#include <cstdio>

#include "codec/base/thread_pool.h"
#include "encoder/body/generic_body.h"
#include "encoder/body/kinematics.h"
#include "encoder/body/mesh_ops.h"
#include "encoder/capture/capture.h"
#include "encoder/encode/pose_file.h"
#include "encoder/shape/projective_texturing.h"
#include "encoder/shape/visual_hull.h"
#include "encoder/track/capture_frames.h"
#include "encoder/track/features.h"
#include "player/decoder/public_camera.h"
#include "player/render/headless.h"
#include "player/render/projective_renderer.h"
#include "tools/synth/view_score.h"

namespace fvv {
namespace {

using Triangles = std::vector<std::array<uint32_t, 3>>;

struct Shape {
  std::string name;
  std::vector<Eigen::Vector3f> positions, normals;
  Triangles triangles;
};

// The vertices some camera sees.
std::vector<Eigen::Vector3d> SeenPoints(const Shape& s, const std::vector<Camera>& cameras,
                                        const ParallelRunner& runner) {
  ProjectiveOptions o;
  o.shift_m = 0;
  const auto vis = VertexVisibility(s.triangles, s.positions, s.normals, cameras, o, runner);
  std::vector<Eigen::Vector3d> out;
  for (size_t v = 0; v < s.positions.size(); ++v) {
    bool seen = false;
    for (const auto& c : vis) seen = seen || c[v];
    if (seen) out.push_back(s.positions[v].cast<double>());
  }
  return out;
}

}  // namespace

std::string ShapeComparison::Table() const {
  std::string out;
  char line[256];
  std::snprintf(line, sizeof(line), "%-16s %24s %24s %14s\n", "shape", "truth -> shape (cm)",
                "shape -> truth (cm)", "novel view");
  out += line;
  std::snprintf(line, sizeof(line), "%-16s %11s %12s %11s %12s %14s\n", "", "mean", "95th %",
                "mean", "95th %", "PSNR (dB)");
  out += line;
  for (const ShapeScore& s : shapes) {
    std::snprintf(line, sizeof(line), "%-16s %11.2f %12.2f %11.2f %12.2f %14.2f\n", s.name.c_str(),
                  s.from_truth.mean * 100, s.from_truth.p95 * 100, s.to_truth.mean * 100,
                  s.to_truth.p95 * 100, s.novel_view_psnr);
    out += line;
  }
  return out;
}

StatusOr<ShapeComparison> CompareShapes(const SynthOptions& so, uint32_t frame,
                                        const ShapeRefinementOptions& ro,
                                        const ComparisonOptions& co) {
  ThreadPool pool(2);
  const ParallelRunner runner = pool.runner();
  StatusOr<Capture> cap = LoadCapture(so.output_dir);
  if (!cap.ok()) return cap.status();
  StatusOr<PoseSequence> poses = LoadPoseFile(so.output_dir);
  if (!poses.ok()) return poses.status();
  if (frame < poses->first_frame || frame - poses->first_frame >= poses->poses.size()) {
    return InvalidArgument("shape comparison: no true pose for frame " + std::to_string(frame));
  }
  std::vector<double> dofs = poses->poses[frame - poses->first_frame];
  if (co.pose_error != 0) {
    const Skeleton skeleton = MakeGenericSkeleton(poses->shape);
    const int tx = DofIndex(skeleton, kRoot, 3), bend = DofIndex(skeleton, kLumbar, 0);
    if (tx >= 0) dofs[tx] += co.pose_error;
    if (bend >= 0) dofs[bend] += 5 * co.pose_error;
  }
  std::vector<Camera> cameras;
  for (const auto& c : cap->cameras) cameras.push_back(c.calibration);
  StatusOr<std::unique_ptr<CaptureFrames>> frames = CaptureFrames::Open(*cap, false, &pool);
  if (!frames.ok()) return frames.status();
  RefinementFrame input;
  input.dofs = dofs;
  FVV_RETURN_IF_ERROR((*frames)->Read(frame, &input.images, &input.silhouettes));
  if (co.features) {
    StatusOr<FeatureSet> features =
        LoadFeatures(so.output_dir + "/truth/features.json", cameras, cap->frame_count);
    if (!features.ok()) return features.status();
    if (features->frames.count(frame)) {
      for (const auto& [name, f] : TriangulateFeatures(features->frames.at(frame), cameras)) {
        input.features[name] = f.position;
      }
    }
  }

  // The true surface.
  StatusOr<std::unique_ptr<Actor>> actor = MakeSynthActor(so);
  if (!actor.ok()) return actor.status();
  Shape truth;
  truth.name = "truth";
  truth.positions = (*actor)->PosedPositions(frame);
  const auto& indices = (*actor)->mesh().indices;
  for (size_t i = 0; i + 2 < indices.size(); i += 3) {
    truth.triangles.push_back({indices[i], indices[i + 1], indices[i + 2]});
  }
  truth.normals =
      VertexNormals(truth.triangles, truth.positions, WeldVertices((*actor)->mesh().positions));
  const SurfaceIndex truth_index(truth.positions, truth.triangles);
  const std::vector<Eigen::Vector3d> truth_seen = SeenPoints(truth, cameras, runner);

  // The shapes.
  std::vector<Shape> shapes(3);
  const BodyModel generic = MakeGenericBody(poses->shape);
  const std::vector<uint32_t> welded = WeldVertices(MeshPositions(generic.mesh));
  shapes[0].name = "generic model";
  shapes[0].positions = SkinPositions(generic.mesh, SkinningMatrices(generic.skeleton, dofs));
  shapes[0].triangles = generic.mesh.triangles;
  shapes[0].normals = VertexNormals(generic.mesh.triangles, shapes[0].positions, welded);
  shapes[1].name = "visual hull";
  StatusOr<VisualHull> hull = CarveVisualHull(cameras, input.silhouettes, ro.hull, runner);
  if (!hull.ok()) return hull.status();
  hull->SurfaceMesh(&shapes[1].positions, &shapes[1].triangles);
  shapes[1].normals =
      VertexNormals(shapes[1].triangles, shapes[1].positions, WeldVertices(shapes[1].positions));
  shapes[2].name = "refined model";
  ShapeComparison result;
  FVV_RETURN_IF_ERROR(RefinePosedShape(generic, cameras, input, ro, &shapes[2].positions,
                                       &result.refinement, runner));
  shapes[2].triangles = generic.mesh.triangles;
  shapes[2].normals = VertexNormals(generic.mesh.triangles, shapes[2].positions, welded);

  for (const Shape& s : shapes) {
    ShapeScore score;
    score.name = s.name;
    score.from_truth = SummariseDistances(truth_seen, SurfaceIndex(s.positions, s.triangles));
    score.to_truth = SummariseDistances(SeenPoints(s, cameras, runner), truth_index);
    result.shapes.push_back(score);
  }

  // Novel views from the held-out cameras, drawn by Renderer I.
  StatusOr<Capture> held = LoadCapture(so.output_dir + "/truth/heldout");
  if (!held.ok()) return held.status();
  CaptureReader held_reader(*held);
  std::vector<fvv_camera> pub;
  for (const Camera& c : cameras) pub.push_back(PublicCamera(c));
  for (uint32_t h = 0; h < held->cameras.size(); ++h) {
    const Camera& view_camera = held->cameras[h].calibration;
    StatusOr<Image> truth_image = held_reader.ReadFrame(h, frame);
    if (!truth_image.ok()) return truth_image.status();
    StatusOr<Image> truth_silhouette = held_reader.ReadSilhouette(h, frame);
    if (!truth_silhouette.ok()) return truth_silhouette.status();
    const int w = int(view_camera.width), hgt = int(view_camera.height);
    auto ctx = HeadlessContext::Create(w, hgt);
    if (!ctx.ok()) return ctx.status();
    RenderView view;
    CameraViewProjection(PublicCamera(view_camera), 0.05f, 50.0f, &view.view, &view.projection);
    for (size_t s = 0; s < shapes.size(); ++s) {
      std::vector<uint32_t> flat;
      for (const auto& t : shapes[s].triangles) flat.insert(flat.end(), t.begin(), t.end());
      auto renderer =
          ProjectiveRenderer::Create((*ctx)->gl(), flat, uint32_t(shapes[s].positions.size()), pub);
      if (!renderer.ok()) return renderer.status();
      StatusOr<ProjectiveFrame> pf = MakeProjectiveFrameForMesh(
          shapes[s].triangles, shapes[s].positions, shapes[s].normals, cameras, input.images,
          input.silhouettes, ProjectiveOptions(), runner);
      if (!pf.ok()) return pf.status();
      std::vector<const uint8_t*> rgba;
      for (const Image& i : pf->images) rgba.push_back(i.pixels.data());
      std::vector<uint8_t> rgb;
      FVV_RETURN_IF_ERROR((*renderer)->SetFrame(pf->positions, pf->weights, rgba));
      FVV_RETURN_IF_ERROR((*renderer)->Draw(view, w, hgt));
      FVV_RETURN_IF_ERROR((*renderer)->ReadRgb(w, hgt, &rgb));
      result.shapes[s].novel_view_psnr +=
          ActorPsnr(rgb, *truth_image, *truth_silhouette) / double(held->cameras.size());
    }
  }
  return result;
}

}  // namespace fvv
