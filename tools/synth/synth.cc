#include "tools/synth/synth.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "codec/base/thread_pool.h"
#include "encoder/body/body_shape_json.h"
#include "encoder/body/generic_body.h"
#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/import/bvh.h"
#include "encoder/import/retarget.h"
#include "encoder/track/features.h"
#include "encoder/track/silhouette_calibration.h"
#include "player/render/headless.h"
#include "tools/synth/body_texture.h"
#include "tools/synth/garment.h"
#include "tools/synth/gltf_actor.h"
#include "tools/synth/procedural_motion.h"
#include "tools/synth/rig.h"
#include "tools/synth/surface_detail.h"
#include "tools/synth/synth_renderer.h"

namespace fvv {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Reproducible noise on every platform: a counter-based hash and Box-Muller.
class NoiseSource {
 public:
  explicit NoiseSource(uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 1) {}
  double Uniform() {
    state_ ^= state_ >> 12;
    state_ ^= state_ << 25;
    state_ ^= state_ >> 27;
    return ((state_ * 0x2545F4914F6CDD1Dull) >> 11) * (1.0 / 9007199254740992.0);
  }
  double Gaussian() {
    const double u = std::max(Uniform(), 1e-300), v = Uniform();
    return std::sqrt(-2 * std::log(u)) * std::cos(2 * kPi * v);
  }

 private:
  uint64_t state_;
};

// Sensor noise and per-camera colour response.
void ApplySensor(Image* image, double sigma, const std::array<double, 3>& gain, uint64_t seed) {
  NoiseSource rng(seed);
  for (size_t i = 0; i < image->pixels.size(); ++i) {
    const double v = image->pixels[i] * gain[i % 3] + sigma * rng.Gaussian();
    image->pixels[i] = static_cast<uint8_t>(std::clamp(std::lround(v), 0l, 255l));
  }
}

std::string CameraDir(const Camera& c) { return c.name; }

std::string FrameName(uint32_t frame) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%06u.png", frame);
  return buf;
}

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

std::vector<Camera> MakeStudioCameras(uint32_t count, uint32_t width, uint32_t height, double phase,
                                      const std::string& prefix) {
  std::vector<Camera> out;
  // Framing: about 2.3 m of height at the ring's radius fills the image, so the
  // actor stays in view when it walks up to a camera.
  const double radius = 3.6, focal = 1.5 * height;
  for (uint32_t i = 0; i < count; ++i) {
    const double a = 2 * kPi * (i + phase) / count;
    const double y = (i % 2 == 0) ? 1.3 : 2.0;
    char name[32];
    std::snprintf(name, sizeof(name), "%s%02u", prefix.c_str(), i);
    out.push_back(LookAtCamera(name, width, height, focal,
                               Eigen::Vector3d(radius * std::sin(a), y, radius * std::cos(a)),
                               Eigen::Vector3d(0, 0.9, 0), Eigen::Vector3d(0, 1, 0)));
  }
  return out;
}

std::vector<Camera> MakeDomeCameras(uint32_t count, uint32_t width, uint32_t height) {
  struct Ring {
    double share, height, radius;
  };
  const Ring rings[4] = {{0.25, 0.5, 3.4}, {1.0 / 3, 1.4, 3.8}, {0.25, 2.4, 3.6}, {0, 3.3, 2.6}};
  uint32_t counts[4], placed = 0;
  for (int r = 0; r < 3; ++r) {
    counts[r] = uint32_t(std::lround(rings[r].share * count));
    placed += counts[r];
  }
  counts[3] = count - std::min(placed, count);
  const double focal = 1.5 * std::min(width, height);
  std::vector<Camera> out;
  for (int r = 0; r < 4; ++r) {
    for (uint32_t i = 0; i < counts[r]; ++i) {
      const double a = 2 * kPi * (i + 0.5 * (r % 2)) / counts[r];
      const Eigen::Vector3d centre(rings[r].radius * std::sin(a), rings[r].height,
                                   rings[r].radius * std::cos(a));
      // Close-ups: every fifth camera of the lower rings, on the upper body
      // and the legs in turn.
      const bool close = r < 3 && i % 5 == 4;
      // The low ring looks up a little, at the actor's middle from below.
      const Eigen::Vector3d target(0, close ? (i % 10 == 4 ? 1.3 : 0.5) : r == 0 ? 1.0 : 0.9, 0);
      char name[32];
      std::snprintf(name, sizeof(name), "cam%02zu", out.size());
      out.push_back(LookAtCamera(name, width, height, close ? 2.2 * focal : focal, centre, target,
                                 Eigen::Vector3d(0, 1, 0)));
    }
  }
  return out;
}

namespace {

// The actor `o` describes; `rig`: o.rig as loaded, whose poses drive the
// built-in actor where o.rig_poses names them.
StatusOr<std::unique_ptr<Actor>> MakeActor(const SynthOptions& o, const Rig& rig) {
  if (o.actor != "builtin") {
    if (!o.motion.empty()) {
      return InvalidArgument(
          "synth: --motion drives the built-in actor; a glTF actor plays its own animation");
    }
    if (o.garment > 0) return InvalidArgument("synth: --garment dresses the built-in actor only");
    StatusOr<std::unique_ptr<GltfActor>> g = GltfActor::Load(o.actor, o.fps, o.frames);
    if (!g.ok()) return Status(g.status().code(), "synth: --actor: " + g.status().message());
    return std::unique_ptr<Actor>(std::move(*g));
  }
  BodyShape shape;
  shape.stature = o.stature;
  if (!o.rig_poses.empty()) {
    if (!o.motion.empty()) return InvalidArgument("synth: --motion or --rig-poses, not both");
    shape = rig.shape;
  }
  FVV_RETURN_IF_ERROR(ValidateBodyShape(shape));
  BodyModel model = MakeGenericBody(shape);
  if (!(o.surface_detail >= 0 && o.surface_detail <= 0.1)) {
    return InvalidArgument("synth: surface detail must be 0..0.1 m");
  }
  AddSurfaceDetail(o.surface_detail, o.seed, &model);
  std::vector<std::vector<double>> poses;
  std::string motion = "built-in walk";
  if (!o.rig_poses.empty()) {
    poses = rig.poses;
    const size_t slash = o.rig_poses.find_last_of('/');
    motion = "the poses of " +
             (slash == std::string::npos ? o.rig_poses : o.rig_poses.substr(slash + 1)) +
             " in their proportions";
  } else if (!o.motion.empty()) {
    // Only the proportions matter: the retargeter scales the root path by leg length.
    StatusOr<BvhMotion> bvh = ReadBvhFile(o.motion, 1.0);
    if (!bvh.ok()) return Status(bvh.status().code(), "synth: --motion: " + bvh.status().message());
    RetargetOptions r;
    r.fps = o.fps;
    r.frames = o.frames;
    r.start_seconds = o.motion_start;
    // CMU's BVH conversions open with a T-pose reference frame that is not part
    // of the performance: the next frame jumps away from it (tens of degrees
    // within one capture interval, which no real motion does): start after it.
    const std::vector<DofRef> bvh_dofs = bvh->skeleton.Dofs();
    bool reference_frame = false;
    for (size_t d = 0; bvh->frames.size() > 1 && d < bvh_dofs.size(); ++d) {
      if (IsRotationDof(bvh_dofs[d].kind) &&
          std::abs(bvh->frames[1][d] - bvh->frames[0][d]) > 0.5) {
        reference_frame = true;
      }
    }
    if (reference_frame && r.start_seconds < bvh->frame_time) r.start_seconds = bvh->frame_time;
    StatusOr<std::vector<std::vector<double>>> retargeted =
        RetargetToGenericBody(*bvh, model.skeleton, r);
    if (!retargeted.ok()) {
      return Status(retargeted.status().code(),
                    "synth: " + o.motion + ": " + retargeted.status().message());
    }
    poses = std::move(*retargeted);
    const size_t slash = o.motion.find_last_of('/');
    motion = "BVH motion " + (slash == std::string::npos ? o.motion : o.motion.substr(slash + 1));
  } else {
    poses = ProceduralWalk(model.skeleton, o.frames, o.fps);
  }
  Image texture = BakeBodyTexture(model, static_cast<int>(o.texture_size), o.seed);
  if (!(o.garment >= 0 && o.garment <= 0.1)) {
    return InvalidArgument("synth: garment must be 0..0.1 m");
  }
  std::vector<std::vector<Eigen::Vector3f>> garment;
  if (o.garment > 0) garment = GarmentPositions(model, poses, o.garment);
  auto actor = std::make_unique<BodyModelActor>(
      std::move(model), std::move(poses), std::move(texture),
      "built-in body model, " + motion + (o.garment > 0 ? ", loose shorts" : ""));
  if (!garment.empty()) actor->SetFramePositions(std::move(garment));
  return std::unique_ptr<Actor>(std::move(actor));
}

}  // namespace

StatusOr<std::unique_ptr<Actor>> MakeSynthActor(const SynthOptions& o) {
  Rig rig;
  if (!o.rig_poses.empty()) {
    FVV_ASSIGN_OR_RETURN(rig, LoadRig(o.rig, o.rig_poses, o.frames));
  }
  return MakeActor(o, rig);
}

// The bystander: the generic body, a little shorter and dressed otherwise,
// walking the built-in gait along a straight line behind the actor (from the
// left of camera 0's view to its right), passing the middle at mid-take.
StatusOr<std::unique_ptr<Actor>> MakeBystander(const SynthOptions& o) {
  BodyShape shape;
  shape.stature = 0.94;
  BodyModel model = MakeGenericBody(shape);
  std::vector<std::vector<double>> poses = ProceduralWalk(model.skeleton, o.frames, o.fps);
  const int x = DofIndex(model.skeleton, kRoot, 3), z = DofIndex(model.skeleton, kRoot, 5);
  const int yaw = DofIndex(model.skeleton, kRoot, 1);
  if (x < 0 || z < 0 || yaw < 0) return Internal("synth: the body model has no root translation");
  const double speed = 1.1, line_z = -1.7;  // metres per second; metres behind the centre
  for (uint32_t f = 0; f < o.frames; ++f) {
    const double t = (f - 0.5 * (o.frames - 1)) / o.fps;
    poses[f][x] = std::clamp(speed * t, -4.5, 4.5);
    poses[f][z] = line_z;
    poses[f][yaw] = kPi / 2;  // facing +x, the way it walks
  }
  Image texture = BakeBodyTexture(model, static_cast<int>(o.texture_size / 2), o.seed + 101);
  // Dressed otherwise: the clothing's colours turned (red to green, blue to red).
  for (size_t i = 0; i + 2 < texture.pixels.size(); i += 3) {
    std::rotate(texture.pixels.begin() + i, texture.pixels.begin() + i + 1,
                texture.pixels.begin() + i + 3);
  }
  return std::unique_ptr<Actor>(
      new BodyModelActor(std::move(model), std::move(poses), std::move(texture), "bystander"));
}

StatusOr<SynthSummary> RunSynth(const SynthOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  auto say = [&](const std::string& line) {
    if (o.progress) o.progress(line);
  };
  if (o.output_dir.empty()) return InvalidArgument("synth: no output directory given");
  if (o.cameras < 1 || o.cameras > 64) return InvalidArgument("synth: --cameras must be 1..64");
  if (o.dome != 0 && (o.dome < 4 || o.dome > 256)) {
    return InvalidArgument("synth: --dome must be 4..256 cameras");
  }
  if (o.held_out > 16) return InvalidArgument("synth: --held-out must be 0..16");
  if (!(o.calibration_error >= 0 && o.calibration_error <= 10)) {
    return InvalidArgument("synth: --calibration-error must be 0..10 degrees");
  }
  if (!o.rig_poses.empty() && o.rig.empty()) {
    return InvalidArgument("synth: --rig-poses places the actor in a --rig; give the rig too");
  }
  if (!o.rig.empty() && (o.dome != 0 || o.overhead || o.held_out != 0)) {
    return InvalidArgument(
        "synth: --rig films with the capture's cameras alone: no --dome, --overhead or "
        "--held-out (hold one of the rig's cameras out instead)");
  }
  if (!o.rig_poses.empty() && o.actor != "builtin") {
    return InvalidArgument("synth: --rig-poses drives the built-in actor");
  }
  if (o.width < 16 || o.height < 16 || o.width > 4096 || o.height > 4096) {
    return InvalidArgument("synth: image size must be 16..4096 on each side");
  }
  if (o.frames < 1 || o.frames > 100000)
    return InvalidArgument("synth: --frames must be 1..100000");
  if (!(o.fps > 0 && o.fps <= 240)) return InvalidArgument("synth: --fps must be in (0, 240]");
  if (!(o.noise >= 0 && o.noise <= 50)) return InvalidArgument("synth: --noise must be 0..50");
  if (!(o.colour_mismatch >= 0 && o.colour_mismatch <= 0.5)) {
    return InvalidArgument("synth: --colour-mismatch must be 0..0.5");
  }
  if (o.texture_size < 64 || o.texture_size > 4096) {
    return InvalidArgument("synth: texture size must be 64..4096");
  }

  Rig rig;
  if (!o.rig.empty()) {
    FVV_ASSIGN_OR_RETURN(rig, LoadRig(o.rig, o.rig_poses, o.frames));
  }
  StatusOr<std::unique_ptr<Actor>> made = MakeActor(o, rig);
  if (!made.ok()) return made.status();
  const Actor& actor = **made;
  if (actor.frame_count() < o.frames) {
    return Internal("synth: actor has fewer frames than asked for");
  }
  say("synth: actor: " + actor.Describe());

  std::vector<Camera> cameras;
  if (!o.rig.empty()) {
    cameras = rig.cameras;
    char moved[64];
    std::snprintf(moved, sizeof(moved), "(%.2f, %.2f) m", rig.moved_by.x(), rig.moved_by.z());
    say("synth: " + std::to_string(cameras.size()) + " cameras of " + o.rig + ", moved by " +
        moved + " on the floor to the actor");
  } else if (o.dome) {
    cameras = MakeDomeCameras(o.dome, o.width, o.height);
  } else {
    cameras = MakeStudioCameras(o.cameras, o.width, o.height, 0.0, "cam");
  }
  if (o.overhead) {
    cameras.push_back(LookAtCamera("top", o.width, o.height, 0.9 * o.height,
                                   Eigen::Vector3d(0, 4.2, 0.3), Eigen::Vector3d(0, 0, 0),
                                   Eigen::Vector3d(0, 1, 0)));
  }
  const std::vector<Camera> held = MakeStudioCameras(o.held_out, o.width, o.height, 0.5, "held");
  // What the cameras film with: turned about their own centres by the
  // calibration error, while capture.json keeps `cameras` as calibrated.
  std::vector<Camera> filmed = cameras;
  nlohmann::json turns = nlohmann::json::array();
  if (o.calibration_error > 0) {
    NoiseSource rng(uint64_t{o.seed} * 104729u + 3);
    for (Camera& cam : filmed) {
      // The image shift a turn by the error in this direction gives.
      const double direction = 2 * kPi * rng.Uniform(), angle = o.calibration_error * kPi / 180;
      const Eigen::Vector2d shift(angle * cam.fx * std::cos(direction),
                                  angle * cam.fy * std::sin(direction));
      cam = TurnedByImageShift(cam, shift);
      turns.push_back({{"camera", cam.name}, {"shift_px", {shift.x(), shift.y()}}});
    }
  }

  const std::string dir = o.output_dir;
  if (o.plates) FVV_RETURN_IF_ERROR(MakeDirectories(dir + "/background"));
  FVV_RETURN_IF_ERROR(MakeDirectories(dir + "/truth/heldout"));
  for (const Camera& c : cameras) {
    FVV_RETURN_IF_ERROR(MakeDirectories(dir + "/" + CameraDir(c)));
    FVV_RETURN_IF_ERROR(MakeDirectories(dir + "/truth/silhouettes/" + CameraDir(c)));
  }
  for (const Camera& c : held) {
    FVV_RETURN_IF_ERROR(MakeDirectories(dir + "/truth/heldout/" + CameraDir(c)));
    FVV_RETURN_IF_ERROR(MakeDirectories(dir + "/truth/heldout/silhouettes/" + CameraDir(c)));
  }

  uint32_t max_w = o.width, max_h = o.height;
  for (const Camera& c : cameras)
    max_w = std::max(max_w, c.width), max_h = std::max(max_h, c.height);
  StatusOr<std::unique_ptr<HeadlessContext>> context =
      HeadlessContext::Create(static_cast<int>(max_w), static_cast<int>(max_h));
  if (!context.ok()) return context.status();
  StatusOr<std::unique_ptr<SynthRenderer>> renderer =
      SynthRenderer::Create((*context)->gl(), actor.mesh(), actor.bone_count(), o.clutter);
  if (!renderer.ok()) return renderer.status();
  SynthRenderer& r = **renderer;
  r.SetUnlit(o.unlit);
  std::unique_ptr<Actor> bystander;
  std::unique_ptr<SynthRenderer> bystander_renderer;
  if (o.bystander) {
    StatusOr<std::unique_ptr<Actor>> b = MakeBystander(o);
    if (!b.ok()) return b.status();
    bystander = std::move(*b);
    StatusOr<std::unique_ptr<SynthRenderer>> br =
        SynthRenderer::Create((*context)->gl(), bystander->mesh(), bystander->bone_count());
    if (!br.ok()) return br.status();
    bystander_renderer = std::move(*br);
    say("synth: a bystander walks through behind the actor");
  }

  // Per-camera colour response (gains around 1) and noise seeds.
  NoiseSource gains_rng(o.seed * 7919u + 17);
  std::vector<std::array<double, 3>> gain(cameras.size() + held.size());
  for (auto& g : gain) {
    const double common = 1 + o.colour_mismatch * (2 * gains_rng.Uniform() - 1);
    for (double& c : g) c = common * (1 + 0.3 * o.colour_mismatch * (2 * gains_rng.Uniform() - 1));
  }
  auto seed_of = [&](uint32_t camera, uint32_t frame) {
    return (uint64_t{o.seed} << 40) ^ (uint64_t{camera} << 24) ^ frame;
  };

  ThreadPool pool(2);
  struct Pending {
    std::string path;
    Image image;
  };
  auto write_all = [&](std::vector<Pending>* pending) -> Status {
    std::vector<Status> results(pending->size());
    pool.Run(static_cast<uint32_t>(pending->size()),
             [&](uint32_t i) { results[i] = WritePng((*pending)[i].path, (*pending)[i].image); });
    pending->clear();
    for (Status& s : results) FVV_RETURN_IF_ERROR(s);
    return Status::Ok();
  };

  // Background plates: the empty studio, with its own sensor noise.
  std::vector<Pending> pending;
  for (uint32_t c = 0; o.plates && c < cameras.size(); ++c) {
    FVV_RETURN_IF_ERROR(r.DrawScene(filmed[c], nullptr, Eigen::Vector3d::Zero()));
    StatusOr<Image> plate = r.Read(filmed[c], 3);
    if (!plate.ok()) return plate.status();
    ApplySensor(&*plate, o.noise, gain[c], seed_of(c, 0xFFFFFF));
    pending.push_back({dir + "/background/" + CameraDir(cameras[c]) + ".png", std::move(*plate)});
  }
  FVV_RETURN_IF_ERROR(write_all(&pending));

  nlohmann::json truth_frames = nlohmann::json::array();
  FeatureSet features;
  const auto body = dynamic_cast<const BodyModelActor*>(&actor);
  for (uint32_t f = 0; f < o.frames; ++f) {
    const std::vector<Eigen::Matrix4f> skin = actor.Skinning(f);
    const Eigen::Vector3d root = actor.RootPosition(f);
    if (actor.SurfaceMoves()) {
      // The frame's own surface: drawn, and kept as truth (posed positions,
      // x, y, z as f32 per vertex).
      r.SetActorPositions(actor.BindPositions(f));
      const std::vector<Eigen::Vector3f> posed = actor.PosedPositions(f);
      char name[48];
      std::snprintf(name, sizeof(name), "/truth/surface_f%06u.bin", f);
      FVV_RETURN_IF_ERROR(WriteFileAtomic(dir + name,
                                          reinterpret_cast<const uint8_t*>(posed.data()),
                                          posed.size() * sizeof(Eigen::Vector3f)));
    }
    auto film = [&](const Camera& cam, uint32_t index, const std::string& image_dir,
                    const std::string& silhouette_dir) -> Status {
      FVV_RETURN_IF_ERROR(r.DrawScene(cam, &skin, root));
      if (bystander) {
        FVV_RETURN_IF_ERROR(bystander_renderer->DrawActorOver(cam, bystander->Skinning(f)));
      }
      StatusOr<Image> frame = r.Read(cam, 3);
      if (!frame.ok()) return frame.status();
      ApplySensor(&*frame, o.noise, gain[index], seed_of(index, f));
      pending.push_back({image_dir + "/" + FrameName(f), std::move(*frame)});
      FVV_RETURN_IF_ERROR(r.DrawSilhouette(cam, skin));
      StatusOr<Image> sil = r.Read(cam, 1);
      if (!sil.ok()) return sil.status();
      pending.push_back({silhouette_dir + "/" + FrameName(f), std::move(*sil)});
      return Status::Ok();
    };
    for (uint32_t c = 0; c < cameras.size(); ++c) {
      const std::string name = CameraDir(cameras[c]);
      FVV_RETURN_IF_ERROR(film(filmed[c], c, dir + "/" + name, dir + "/truth/silhouettes/" + name));
    }
    for (uint32_t c = 0; c < held.size(); ++c) {
      const std::string name = CameraDir(held[c]);
      FVV_RETURN_IF_ERROR(film(held[c], uint32_t(cameras.size()) + c,
                               dir + "/truth/heldout/" + name,
                               dir + "/truth/heldout/silhouettes/" + name));
    }
    FVV_RETURN_IF_ERROR(write_all(&pending));

    // Feature points: the joints seen by each camera (truth/features.json,
    // as a studio's annotation or a keypoint detector would give them).
    for (const NamedPoint& j : actor.Joints(f)) {
      if (!IsFeatureName(j.name)) continue;
      for (uint32_t c = 0; c < cameras.size(); ++c) {
        Eigen::Vector2d px;
        if (ProjectPoint(filmed[c], j.position, &px) && px.x() >= 0 && px.y() >= 0 &&
            px.x() <= cameras[c].width - 1 && px.y() <= cameras[c].height - 1) {
          features.frames[f][j.name][c] = px;
        }
      }
    }
    nlohmann::json tf;
    tf["frame"] = f;
    nlohmann::json joints = nlohmann::json::object();
    for (const NamedPoint& j : actor.Joints(f)) joints[j.name] = Vec(j.position);
    tf["joints"] = joints;
    if (body) tf["dofs"] = body->pose(f);
    truth_frames.push_back(tf);

    if (o.progress && ((f + 1) % 10 == 0 || f + 1 == o.frames)) {
      const double elapsed =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double eta = elapsed / (f + 1) * (o.frames - f - 1);
      char line[160];
      std::snprintf(line, sizeof(line),
                    "synth: frame %u/%u (%zu cameras + %zu held out), %.1f s, ETA %.0f s", f + 1,
                    o.frames, cameras.size(), held.size(), elapsed, eta);
      say(line);
    }
  }

  // The actor's texture, and the ground-truth record.
  FVV_RETURN_IF_ERROR(WritePng(dir + "/truth/texture.png", actor.mesh().texture));
  nlohmann::json truth;
  truth["generator"] = "fvv synth";
  truth["actor"] = actor.Describe();
  truth["seed"] = o.seed;
  truth["frame_rate"] = o.fps;
  truth["frame_count"] = o.frames;
  truth["noise"] = o.noise;
  truth["unlit"] = o.unlit;
  truth["colour_mismatch"] = o.colour_mismatch;
  // Each camera's colour response (the studio's cameras, then the held-out
  // ones): what its pixel values were multiplied by.
  truth["camera_responses"] = gain;
  truth["plates"] = o.plates;
  truth["clutter"] = o.clutter;
  truth["bystander"] = o.bystander;
  // The cameras filmed turned by this many degrees from what capture.json
  // says, each by the image shift (pixels) recorded.
  if (o.calibration_error > 0) {
    truth["calibration_error"] = {{"degrees", o.calibration_error}, {"turns", turns}};
  }
  if (body) {
    truth["body_model"] = "generic";
    truth["stature"] = o.rig_poses.empty() ? o.stature : rig.shape.stature;
    if (!o.rig_poses.empty()) truth["body_shape"] = BodyShapeToJson(rig.shape);
    truth["surface_detail"] = o.surface_detail;
    truth["garment"] = o.garment;
    if (o.garment > 0)
      truth["surface_files"] = "surface_fFFFFFF.bin: posed vertex positions, f32 x y z";
    nlohmann::json dofs = nlohmann::json::array();
    for (const DofRef& d : body->model().skeleton.Dofs()) {
      static const char* kKinds[] = {"rx", "ry", "rz", "tx", "ty", "tz"};
      dofs.push_back(body->model().skeleton.bones[d.bone].name + "." + kKinds[d.kind]);
    }
    truth["dof_names"] = dofs;
  }
  truth["frames"] = truth_frames;
  const std::string features_text = FeaturesToJson(features, cameras);
  FVV_RETURN_IF_ERROR(WriteFileAtomic(dir + "/truth/features.json",
                                      reinterpret_cast<const uint8_t*>(features_text.data()),
                                      features_text.size()));
  const std::string truth_text = truth.dump(1) + "\n";
  FVV_RETURN_IF_ERROR(WriteFileAtomic(dir + "/truth/truth.json",
                                      reinterpret_cast<const uint8_t*>(truth_text.data()),
                                      truth_text.size()));

  // capture.json last: a directory with one is complete.
  auto capture_of = [&](const std::vector<Camera>& cams, const std::string& cdir, bool silhouettes,
                        bool backgrounds) {
    Capture c;
    c.directory = cdir;
    c.frame_rate = o.fps;
    c.frame_count = o.frames;
    c.up_axis = 'y';
    for (const Camera& cam : cams) {
      CaptureCamera cc;
      cc.calibration = cam;
      cc.frames.path = CameraDir(cam) + "/%06d.png";
      if (backgrounds) cc.background = "background/" + CameraDir(cam) + ".png";
      if (silhouettes) {
        FrameSource s;
        s.path =
            (cdir == dir ? "truth/silhouettes/" : "silhouettes/") + CameraDir(cam) + "/%06d.png";
        cc.silhouettes = s;
      }
      c.cameras.push_back(cc);
    }
    return c;
  };
  if (!held.empty()) {
    FVV_RETURN_IF_ERROR(SaveCapture(capture_of(held, dir + "/truth/heldout", true, false)));
  }
  SynthSummary summary;
  summary.capture = capture_of(cameras, dir, o.link_silhouettes, o.plates);
  FVV_RETURN_IF_ERROR(SaveCapture(summary.capture));
  summary.actor = actor.Describe();
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace fvv
