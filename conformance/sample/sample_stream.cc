#include "conformance/sample/sample_stream.h"

#include <algorithm>
#include <cmath>

#include "codec/colour.h"
#include "codec/mask.h"
#include "codec/predictive_texture.h"
#include "conformance/sample/sample_volume.h"
#include "container/surface_displacement.h"
#include "container/vertex_visibility.h"
#include "container/writer.h"

namespace fvv {
namespace {

// The options' fractional sample bits: whole samples for the predictive codec
// and for lossless coding.
int SampleFrac(const SampleStreamOptions& o) {
  return o.predictive || o.lossless
             ? 0
             : UsableSampleFrac(o.kernel, o.frac_bits_97, o.weights, o.sample_frac);
}

struct BoneSpec {
  const char* name;
  int parent;
  float x, y, z;  // rest offset from the parent joint, metres
  uint8_t dofs;
  float limit;       // symmetric rotation limit, radians
  float dx, dy, dz;  // the segment's extent from its joint (drawn as a box)
};

constexpr uint8_t kRot3 = kDofRotX | kDofRotY | kDofRotZ;
constexpr uint8_t kTrans3 = kDofTransX | kDofTransY | kDofTransZ;

// 15 bones, 35 DOF: 6 at the pelvis, 3 per ball joint, 1 per hinge, 2 per wrist/ankle/neck.
const BoneSpec kBones[] = {
    {"pelvis", -1, 0, 0.95f, 0, kRot3 | kTrans3, 3.14159f, 0, 0.22f, 0},
    {"spine", 0, 0, 0.22f, 0, kRot3, 0.6f, 0, 0.3f, 0},
    {"neck", 1, 0, 0.3f, 0, kDofRotX | kDofRotY, 0.8f, 0, 0.25f, 0},
    {"l_shoulder", 1, 0.18f, 0.25f, 0, kRot3, 3.14159f, 0.28f, 0, 0},
    {"l_elbow", 3, 0.28f, 0, 0, kDofRotY, 2.6f, 0.25f, 0, 0},
    {"l_wrist", 4, 0.25f, 0, 0, kDofRotX | kDofRotZ, 1.2f, 0.1f, 0, 0},
    {"r_shoulder", 1, -0.18f, 0.25f, 0, kRot3, 3.14159f, -0.28f, 0, 0},
    {"r_elbow", 6, -0.28f, 0, 0, kDofRotY, 2.6f, -0.25f, 0, 0},
    {"r_wrist", 7, -0.25f, 0, 0, kDofRotX | kDofRotZ, 1.2f, -0.1f, 0, 0},
    {"l_hip", 0, 0.1f, -0.05f, 0, kRot3, 2.0f, 0, -0.42f, 0},
    {"l_knee", 9, 0, -0.42f, 0, kDofRotX, 2.5f, 0, -0.42f, 0},
    {"l_ankle", 10, 0, -0.42f, 0, kDofRotX | kDofRotZ, 0.8f, 0, -0.05f, 0.15f},
    {"r_hip", 0, -0.1f, -0.05f, 0, kRot3, 2.0f, 0, -0.42f, 0},
    {"r_knee", 12, 0, -0.42f, 0, kDofRotX, 2.5f, 0, -0.42f, 0},
    {"r_ankle", 13, 0, -0.42f, 0, kDofRotX | kDofRotZ, 0.8f, 0, -0.05f, 0.15f},
};
constexpr int kBoneCount = sizeof(kBones) / sizeof(kBones[0]);

std::array<double, 3> Cross(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
std::array<double, 3> Normalised(std::array<double, 3> v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (double& x : v) x /= n;
  return v;
}

// Appends an axis-aligned box (24 vertices with flat normals, 12 triangles)
// skinned rigidly to `bone`, its faces laid out 3x2 in the atlas cell.
void AddBox(Mesh* m, int bone, const std::array<float, 3>& lo, const std::array<float, 3>& hi,
            float u0, float v0, float cell) {
  static const int kFaces[6][4][3] = {
      {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, {{0, 0, 1}, {0, 1, 1}, {0, 1, 0}, {0, 0, 0}},
      {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}, {{0, 0, 1}, {0, 0, 0}, {1, 0, 0}, {1, 0, 1}},
      {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, {{1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {1, 1, 0}}};
  static const float kNormals[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                       {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  for (int f = 0; f < 6; ++f) {
    const uint32_t base = static_cast<uint32_t>(m->positions.size());
    const float fu = u0 + (f % 3) * cell / 3, fv = v0 + (f / 3) * cell / 2;
    static const float kCorner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; ++k) {
      std::array<float, 3> p;
      for (int a = 0; a < 3; ++a) p[a] = kFaces[f][k][a] ? hi[a] : lo[a];
      m->positions.push_back(p);
      m->normals.push_back({kNormals[f][0], kNormals[f][1], kNormals[f][2]});
      // A margin inside each face's rectangle keeps texels from bleeding across faces.
      m->uvs.push_back({fu + (0.1f + 0.8f * kCorner[k][0]) * cell / 3,
                        fv + (0.1f + 0.8f * kCorner[k][1]) * cell / 2});
      m->joints.push_back({static_cast<uint16_t>(bone), 0, 0, 0});
      m->weights.push_back({65535, 0, 0, 0});
      m->segments.push_back(static_cast<uint8_t>(bone));
    }
    m->triangles.push_back({base, base + 1, base + 2});
    m->triangles.push_back({base, base + 2, base + 3});
  }
}

}  // namespace

SampleStreamOptions TinySampleOptions() {
  SampleStreamOptions o;
  o.frames = 3;
  o.cameras = 2;
  o.atlas_width = 8;
  o.atlas_height = 8;
  o.gop_frames = 2;
  o.gop_cameras = 2;
  return o;
}

BodyModel MakeSampleBodyModel() {
  BodyModel model;
  std::vector<std::array<float, 3>> joint(kBoneCount);
  for (int b = 0; b < kBoneCount; ++b) {
    const BoneSpec& s = kBones[b];
    Bone bone;
    bone.name = s.name;
    bone.parent = s.parent;
    bone.rest_translation = {s.x, s.y, s.z};
    bone.order = RotationOrder::kZYX;
    bone.dof_mask = s.dofs;
    for (int k = 0; k < kDofKinds; ++k) {
      if (!(s.dofs & (1u << k))) continue;  // limits exist only for the bone's DOFs
      bone.dof_min[k] = IsRotationDof(k) ? -s.limit : -100.0f;
      bone.dof_max[k] = IsRotationDof(k) ? s.limit : 100.0f;
    }
    model.skeleton.bones.push_back(bone);
    joint[b] = {s.x, s.y, s.z};
    if (s.parent >= 0) {
      for (int a = 0; a < 3; ++a) joint[b][a] += joint[s.parent][a];
    }
  }
  const float cell = 0.25f;  // a 4x4 grid of atlas cells
  for (int b = 0; b < kBoneCount; ++b) {
    const BoneSpec& s = kBones[b];
    std::array<float, 3> lo, hi;
    const float d[3] = {s.dx, s.dy, s.dz};
    for (int a = 0; a < 3; ++a) {
      const float end = joint[b][a] + d[a];
      lo[a] = std::min(joint[b][a], end) - 0.05f;
      hi[a] = std::max(joint[b][a], end) + 0.05f;
    }
    AddBox(&model.mesh, b, lo, hi, (b % 4) * cell, (b / 4) * cell, cell);
  }
  return model;
}

std::vector<Camera> MakeRingCameras(uint32_t count, uint32_t image_width, uint32_t image_height) {
  std::vector<Camera> cameras(count);
  for (uint32_t i = 0; i < count; ++i) {
    Camera& c = cameras[i];
    c.name = "cam" + std::to_string(i);
    c.width = image_width;
    c.height = image_height;
    c.fx = c.fy = 1.2 * image_width;
    c.cx = image_width / 2.0;
    c.cy = image_height / 2.0;
    const double a = 2 * M_PI * i / count;
    const std::array<double, 3> centre{3.0 * std::sin(a), 1.2, 3.0 * std::cos(a)};
    const std::array<double, 3> target{0, 1.0, 0};
    const auto f =
        Normalised({target[0] - centre[0], target[1] - centre[1], target[2] - centre[2]});
    const auto r = Normalised(Cross(f, {0, 1, 0}));
    const auto d = Cross(f, r);
    for (int k = 0; k < 3; ++k) {
      c.rotation[k] = r[k];
      c.rotation[3 + k] = d[k];
      c.rotation[6 + k] = f[k];
    }
    for (int row = 0; row < 3; ++row) {
      c.translation[row] = -(c.rotation[3 * row] * centre[0] + c.rotation[3 * row + 1] * centre[1] +
                             c.rotation[3 * row + 2] * centre[2]);
    }
  }
  return cameras;
}

std::vector<double> SampleWalkPose(const Skeleton& skeleton, uint32_t frame) {
  const double t = frame / 25.0, phase = 2 * M_PI * 0.9 * t;
  const double s = std::sin(phase), c = std::cos(phase);
  std::vector<double> values;
  for (const DofRef& d : skeleton.Dofs()) {
    const std::string& name = skeleton.bones[d.bone].name;
    const double side = name[0] == 'r' ? -1 : 1;
    double v = 0;
    if (name == "pelvis") {
      const double pv[6] = {0.05 * std::sin(2 * phase), 0.15 * s, 0.04 * c, 0.03 * s,
                            0.02 * std::cos(2 * phase), 1.1 * t};
      v = pv[d.kind];
    } else if (name == "spine") {
      v = d.kind == 1 ? -0.12 * s : 0.03 * c;
    } else if (name == "neck") {
      v = d.kind == 0 ? 0.05 * std::sin(2 * phase) : 0.08 * s;
    } else if (name.find("shoulder") != std::string::npos) {
      // Arms down from the rest T-pose (left arm along +x: negative z rotation).
      v = d.kind == 0 ? -0.45 * side * s : d.kind == 2 ? -side * (1.2 + 0.05 * c) : 0.0;
    } else if (name.find("elbow") != std::string::npos) {
      v = side * (0.4 + 0.25 * std::max(0.0, -side * s));
    } else if (name.find("wrist") != std::string::npos) {
      v = 0.1 * side * c;
    } else if (name.find("hip") != std::string::npos) {
      v = d.kind == 0 ? 0.5 * side * s : d.kind == 1 ? 0.05 * side : 0.03 * c;
    } else if (name.find("knee") != std::string::npos) {
      v = 0.7 * std::max(0.0, std::sin(phase * side + 1.0));
    } else if (name.find("ankle") != std::string::npos) {
      v = d.kind == 0 ? 0.25 * side * c : 0.02;
    }
    values.push_back(v);
  }
  return values;
}

StatusOr<SampleStream> MakeSampleStream(const SampleStreamOptions& o,
                                        const ParallelRunner& runner) {
  if (o.frames == 0 || o.cameras == 0) return InvalidArgument("sample: frames and cameras >= 1");
  SampleStream out;
  StreamInfo& info = out.info;
  FileHeader& h = info.header;
  h.level = o.level;
  h.frame_rate_num = o.frame_rate_num;
  h.frame_rate_den = o.frame_rate_den;
  h.frame_count = o.fast_start ? o.frames : 0;
  h.camera_count = o.cameras;
  h.atlas_width = o.atlas_width;
  h.atlas_height = o.atlas_height;
  h.gop_frames = o.gop_frames;
  h.gop_cameras = o.gop_cameras;
  h.tools =
      TextureTools(o.kernel, o.coder, o.lossless ? ColourSpace::kRct : ColourSpace::kYCbCr601,
                   o.chroma, KernelFracBits(o.kernel, o.frac_bits_97), o.weights, SampleFrac(o));
  if (o.chroma == ChromaFormat::k420 && o.upsampling == ChromaUpsampling::kBilinear) {
    h.tools |= kToolChromaBilinear;
  }
  if (o.masks) h.tools |= kToolMasks;
  if (o.vertex_visibility) h.tools |= kToolVertexVisibility;
  if (o.key_interval > 1) h.tools |= kToolMotionInterpolation;
  if (o.motion_coder == MotionCoder::kZstd) h.tools |= kToolMotionZstd;
  if (o.quantise_model) h.tools |= kToolQuantisedModel;
  if (o.texture_chunks) h.tools |= kToolTextureChunks;
  if (o.surface) h.tools |= kToolSurface;
  if (o.predictive) {
    if (!o.masks) return InvalidArgument("sample: the predictive texture needs masks");
    if (o.chroma != ChromaFormat::k444) return InvalidArgument("sample: predictive is 4:4:4");
    h.tools =
        (h.tools & ~(kToolSpihtArith | kToolSpihtArith2 | kToolSpihtArith3 | kToolSpihtBinary |
                     kToolReversibleColour | kToolTexturePrecision | kToolOwnBandWeights)) |
        kToolPredictiveTexture;
  }
  h.format_version = RequiredFormatVersion(h.tools, o.mask_coding);
  info.cameras = MakeRingCameras(o.cameras, 640, 480);
  info.model = MakeSampleBodyModel();
  if (o.quantise_model) {
    FVV_RETURN_IF_ERROR(QuantiseModel(
        DefaultModelQuantisation(std::max(o.atlas_width, o.atlas_height)), &info.model));
  }
  info.motion.coder = o.motion_coder;
  info.motion.key_interval = o.key_interval;
  info.metadata = o.metadata;
  FVV_RETURN_IF_ERROR(ValidateFileHeader(h));

  const Skeleton& skeleton = info.model.skeleton;
  for (uint32_t f = 0; f < o.frames; ++f) {
    out.poses.push_back(QuantisePose(skeleton.Dofs(), info.motion, SampleWalkPose(skeleton, f)));
  }
  // An offline encoder knows the whole motion and sends its statistics up front;
  // the live-like variant (frame count unknown) goes without.
  if (o.fast_start) TrainMotionParams(skeleton, out.poses, o.gop_frames, &info.motion);
  const size_t texels = size_t{o.atlas_width} * o.atlas_height;
  out.rgb.resize(size_t{o.frames} * o.cameras * texels * 3);
  out.masks.resize(size_t{o.frames} * o.cameras * texels);
  for (uint32_t t = 0; t < o.frames; ++t) {
    for (uint32_t c = 0; c < o.cameras; ++c) {
      const size_t plane = size_t{t} * o.cameras + c;
      const Image view = SampleView(t, c, o.atlas_width, o.atlas_height);
      std::copy(view.pixels.begin(), view.pixels.end(), out.rgb.begin() + plane * texels * 3);
      const Image mask = SampleMask(t, c, o.atlas_width, o.atlas_height);
      for (size_t i = 0; i < texels; ++i) out.masks[plane * texels + i] = mask.pixels[i] != 0;
    }
  }

  FileHeader grid = h;
  grid.frame_count = o.frames;
  const uint32_t count = grid.time_spans() * grid.camera_groups();
  for (uint32_t g = 0; g < count; ++g) {
    FVV_ASSIGN_OR_RETURN(const FragmentInfo fi, FragmentInfoFor(grid, g));
    FragmentData frag;
    frag.info = fi;
    const Shape4D shape = fi.TextureShape(h);
    std::vector<uint8_t> rgb(shape.count() * 3);
    UsedMask used(shape.count());
    for (uint32_t t = 0; t < shape.frames(); ++t) {
      for (uint32_t c = 0; c < shape.cameras(); ++c) {
        const size_t src = (size_t{fi.first_frame + t} * o.cameras + fi.first_camera + c) * texels;
        const size_t dst = (size_t{t} * shape.cameras() + c) * texels;
        std::copy_n(out.rgb.begin() + src * 3, texels * 3, rgb.begin() + dst * 3);
        std::copy_n(out.masks.begin() + src, texels, used.begin() + dst);
      }
    }
    if (o.predictive) {
      PredictiveGop gop;
      gop.frames = shape.frames(), gop.cameras = shape.cameras();
      gop.width = shape.width(), gop.height = shape.height();
      gop.rgb = rgb;
      gop.mask = used;
      PredictiveEncodeOptions po;
      po.kernel = o.kernel;
      po.runner = runner;
      if (!o.lossless) po.target_bytes = uint64_t(std::ceil(o.bpp * double(shape.count()) / 8));
      FVV_ASSIGN_OR_RETURN(frag.predictive_texture, EncodePredictive(gop, po));
      frag.predictive = true;
    }
    const ColourSpace colour = o.lossless ? ColourSpace::kRct : ColourSpace::kYCbCr601;
    const Block block = BlockFromRgb(rgb.data(), shape, colour, o.chroma, SampleFrac(o));
    EncodeSettings settings;
    settings.kernel = o.kernel;
    settings.frac_bits_97 = o.frac_bits_97;
    settings.coder = o.coder;
    settings.weights = o.weights;
    settings.rate_mode = o.lossless ? RateMode::kLossless : RateMode::kBitsPerSample;
    settings.rate_value = o.bpp;
    // The original pyramid fill: sample streams are what the conformance
    // generator makes, and it must remake every released case byte for byte.
    settings.fill = {FillPull::kParent, 0};
    // Sample streams are the conformance suite's: pinned byte for byte, so they
    // keep the encoder as it was when each case was released.
    settings.prune_isolated = false;
    settings.runner = runner;
    if (!o.predictive) {
      FVV_ASSIGN_OR_RETURN(frag.texture, EncodeBlock(block, o.masks ? &used : nullptr, settings));
    }
    if (o.masks) {
      frag.masks = EncodeMasks(used.data(), shape, o.mask_coding);
      frag.mask_mode = o.mask_coding;
    }
    if (fi.first_camera == 0) {
      std::vector<QuantisedPose> poses(out.poses.begin() + fi.first_frame,
                                       out.poses.begin() + fi.first_frame + fi.frame_count);
      FVV_ASSIGN_OR_RETURN(frag.motion, EncodeMotion(skeleton, info.motion, poses));
      if (o.surface) {
        // Integer patterns (no floating point: the cases are pinned byte for
        // byte): small values with one- and two-byte residuals, every fifth
        // vertex a large swing.
        const uint32_t nv = static_cast<uint32_t>(info.model.mesh.positions.size());
        std::vector<int32_t> values(size_t{fi.frame_count} * nv);
        for (uint32_t t = 0; t < fi.frame_count; ++t) {
          const uint32_t f = fi.first_frame + t;
          for (uint32_t v = 0; v < nv; ++v) {
            values[size_t{t} * nv + v] = v % 5 == 0
                                             ? o.surface_amplitude * (int32_t((f + v) % 3) - 1)
                                             : int32_t((f * 37 + v * 11) % 61) - 30;
          }
        }
        frag.has_surface = true;
        frag.surface_head.step_exponent = 10;
        frag.surface_head.vertex_count = nv;
        frag.surface = EncodeSurfaceDisplacements(values, fi.frame_count, nv);
        frag.surface_head.data_size = static_cast<uint32_t>(frag.surface.size());
      }
    }
    if (o.vertex_visibility) {
      // Vertices facing each camera, with the actor turning slowly.
      const uint32_t nv = static_cast<uint32_t>(info.model.mesh.positions.size());
      std::vector<uint8_t> bits(size_t{shape.frames()} * shape.cameras() * nv);
      for (uint32_t t = 0; t < shape.frames(); ++t) {
        for (uint32_t c = 0; c < shape.cameras(); ++c) {
          const auto centre = info.cameras[fi.first_camera + c].Centre();
          const double turn = 0.1 * (fi.first_frame + t);
          for (uint32_t v = 0; v < nv; ++v) {
            const auto& n = info.model.mesh.normals[v];
            const double nx = n[0] * std::cos(turn) + n[2] * std::sin(turn);
            const double nz = -n[0] * std::sin(turn) + n[2] * std::cos(turn);
            bits[(size_t{t} * shape.cameras() + c) * nv + v] =
                nx * centre[0] + n[1] * (centre[1] - 1) + nz * centre[2] > 0;
          }
        }
      }
      frag.vertex_visibility = EncodeVertexVisibility(bits, shape.frames(), shape.cameras(), nv);
    }
    out.fragments.push_back(std::move(frag));
  }
  return out;
}

StatusOr<std::vector<uint8_t>> MakeSampleStreamBytes(const SampleStreamOptions& options,
                                                     const ParallelRunner& runner) {
  FVV_ASSIGN_OR_RETURN(SampleStream s, MakeSampleStream(options, runner));
  return WriteStreamToMemory(s.info, s.fragments);
}

}  // namespace fvv
