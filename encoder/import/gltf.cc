#include "encoder/import/gltf.h"

#include <stb_image.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

namespace fvv {
namespace {

constexpr size_t kMaxVertices = size_t{1} << 22;
constexpr size_t kMaxJoints = 256;
// Limits on what a character file may make the importer hold: any one file
// it reads (the .gltf/.glb, an external buffer or image) and any one texture.
constexpr uint64_t kMaxFileBytes = uint64_t{1} << 30;
constexpr uint64_t kMaxTexturePixels = uint64_t{8192} * 8192;

// tinygltf's own reader trusts the size a path reports; a URI naming a
// directory reports one it does not have. This one refuses all but regular,
// non-empty files and caps their size.
bool ReadCharacterFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                       void*) {
  StatusOr<std::vector<uint8_t>> bytes = ReadFileBytes(path, kMaxFileBytes);
  if (!bytes.ok()) {
    if (err) *err += bytes.status().message() + "\n";
    return false;
  }
  if (bytes->empty()) {  // tinygltf indexes the first byte of what it reads
    if (err) *err += path + ": empty file\n";
    return false;
  }
  *out = std::move(*bytes);
  return true;
}

// Reads an image's dimensions from its header and refuses one too large
// before tinygltf's decoder allocates for it.
bool LoadBoundedImage(tinygltf::Image* image, const int index, std::string* err, std::string* warn,
                      int req_width, int req_height, const unsigned char* bytes, int size,
                      void* user) {
  int w = 0, h = 0, comp = 0;
  if (stbi_info_from_memory(bytes, size, &w, &h, &comp) &&
      uint64_t(w) * uint64_t(h) > kMaxTexturePixels) {
    if (err)
      *err += "image " + std::to_string(index) + " is " + std::to_string(w) + " x " +
              std::to_string(h) + " pixels, more than the " + std::to_string(kMaxTexturePixels) +
              " allowed\n";
    return false;
  }
  return tinygltf::LoadImageData(image, index, err, warn, req_width, req_height, bytes, size, user);
}

// Reads an accessor as floats (normalised integers scaled to [0, 1]) with
// bounds checks against its buffer.
Status ReadAccessor(const tinygltf::Model& m, int index, int want_components,
                    std::vector<float>* out, const std::string& what) {
  if (index < 0 || size_t(index) >= m.accessors.size()) {
    return Corrupt("glTF: " + what + ": accessor index out of range");
  }
  const tinygltf::Accessor& a = m.accessors[index];
  if (a.sparse.isSparse)
    return Unsupported("glTF: " + what + ": sparse accessors are not supported");
  const int components = tinygltf::GetNumComponentsInType(a.type);
  if (components != want_components) {
    return Corrupt("glTF: " + what + ": expected " + std::to_string(want_components) +
                   " components, got " + std::to_string(components));
  }
  if (a.count > kMaxVertices * 4) return LimitExceeded("glTF: " + what + ": too many elements");
  if (a.bufferView < 0 || size_t(a.bufferView) >= m.bufferViews.size()) {
    return Corrupt("glTF: " + what + ": no buffer view");
  }
  const tinygltf::BufferView& v = m.bufferViews[a.bufferView];
  if (v.buffer < 0 || size_t(v.buffer) >= m.buffers.size())
    return Corrupt("glTF: " + what + ": no buffer");
  const std::vector<unsigned char>& data = m.buffers[v.buffer].data;
  const int size = tinygltf::GetComponentSizeInBytes(a.componentType);
  if (size <= 0) return Corrupt("glTF: " + what + ": bad component type");
  const size_t element = size_t(size) * components;
  const size_t stride = v.byteStride ? v.byteStride : element;
  const size_t start = v.byteOffset + a.byteOffset;
  if (a.count > 0 && (start + stride * (a.count - 1) + element > v.byteOffset + v.byteLength ||
                      v.byteOffset + v.byteLength > data.size())) {
    return Corrupt("glTF: " + what + ": accessor runs past its buffer");
  }
  out->resize(a.count * components);
  for (size_t i = 0; i < a.count; ++i) {
    const unsigned char* p = data.data() + start + i * stride;
    for (int c = 0; c < components; ++c) {
      const unsigned char* q = p + size_t(c) * size;
      float value = 0;
      switch (a.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
          std::memcpy(&value, q, 4);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          value = *q / (a.normalized ? 255.0f : 1.0f);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          uint16_t u;
          std::memcpy(&u, q, 2);
          value = u / (a.normalized ? 65535.0f : 1.0f);
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
          uint32_t u;
          std::memcpy(&u, q, 4);
          value = static_cast<float>(u);
          break;
        }
        default:
          return Unsupported("glTF: " + what + ": component type " +
                             std::to_string(a.componentType));
      }
      if (!std::isfinite(value)) return Corrupt("glTF: " + what + ": non-finite value");
      (*out)[i * components + c] = value;
    }
  }
  return Status::Ok();
}

// Whether an image was decoded to 8-bit samples, all of them present.
bool HoldsDecoded8Bit(const tinygltf::Image& img) {
  return img.bits == 8 && img.width > 0 && img.height > 0 && img.component > 0 &&
         img.image.size() >= size_t(img.width) * size_t(img.height) * size_t(img.component);
}

Image ToRgb(const tinygltf::Image& img, const std::vector<double>& factor) {
  Image out;
  out.width = img.width;
  out.height = img.height;
  out.pixels.resize(size_t(img.width) * img.height * 3);
  const int comp = img.component;
  for (size_t i = 0; i < size_t(img.width) * img.height; ++i) {
    for (int k = 0; k < 3; ++k) {
      const int v = img.image[i * comp + std::min(k, comp - 1)];
      out.pixels[i * 3 + k] = static_cast<uint8_t>(std::clamp(v * factor[k], 0.0, 255.0));
    }
  }
  return out;
}

Eigen::Matrix4d Trs(const Eigen::Vector3d& t, const Eigen::Quaterniond& r,
                    const Eigen::Vector3d& s) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = r.normalized().toRotationMatrix() * s.asDiagonal();
  m.topRightCorner<3, 1>() = t;
  return m;
}

}  // namespace

StatusOr<GltfCharacter> LoadGltf(const std::string& path) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  tinygltf::FsCallbacks fs{&tinygltf::FileExists, &tinygltf::ExpandFilePath, &ReadCharacterFile,
                           &tinygltf::WriteWholeFile, nullptr};
  loader.SetFsCallbacks(fs);
  loader.SetImageLoader(&LoadBoundedImage, nullptr);
  std::string err, warn;
  const bool binary = path.size() > 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                         : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  while (!err.empty() && std::isspace(static_cast<unsigned char>(err.back()))) err.pop_back();
  if (!ok) return Corrupt("glTF " + path + ": " + (err.empty() ? "cannot load" : err));
  GltfCharacter c;
  for (size_t n = 0; n < model.nodes.size(); ++n) {
    const tinygltf::Node& src = model.nodes[n];
    GltfNode node;
    node.name = src.name.empty() ? "node" + std::to_string(n) : src.name;
    if (src.translation.size() == 3)
      node.translation = {src.translation[0], src.translation[1], src.translation[2]};
    if (src.rotation.size() == 4)
      node.rotation =
          Eigen::Quaterniond(src.rotation[3], src.rotation[0], src.rotation[1], src.rotation[2]);
    if (src.scale.size() == 3) node.scale = {src.scale[0], src.scale[1], src.scale[2]};
    if (src.matrix.size() == 16) {
      node.has_matrix = true;
      for (int i = 0; i < 16; ++i) node.matrix(i % 4, i / 4) = src.matrix[i];
    }
    c.nodes.push_back(node);
  }
  for (size_t n = 0; n < model.nodes.size(); ++n) {
    for (int child : model.nodes[n].children) {
      if (child < 0 || size_t(child) >= c.nodes.size() || c.nodes[child].parent >= 0 ||
          child == int(n)) {
        return Corrupt("glTF " + path + ": node hierarchy is not a tree");
      }
      c.nodes[child].parent = static_cast<int>(n);
    }
  }
  // Reject cycles: every chain of parents must end within the node count.
  for (size_t n = 0; n < c.nodes.size(); ++n) {
    int p = c.nodes[n].parent;
    for (size_t steps = 0; p >= 0; ++steps, p = c.nodes[p].parent) {
      if (steps > c.nodes.size()) return Corrupt("glTF " + path + ": node hierarchy has a cycle");
    }
  }

  // The skinned meshes (nodes with both a mesh and a skin); one skin for all.
  int skin = -1;
  std::vector<Image> textures;
  std::vector<int> texture_of_material(model.materials.size() + 1, -1);
  std::vector<std::pair<size_t, int>> vertex_ranges;  // (first vertex, texture slot)
  for (const tinygltf::Node& node : model.nodes) {
    if (node.mesh < 0 || node.skin < 0) continue;
    if (size_t(node.mesh) >= model.meshes.size() || size_t(node.skin) >= model.skins.size()) {
      return Corrupt("glTF " + path + ": node refers to a missing mesh or skin");
    }
    if (skin >= 0 && node.skin != skin) return Unsupported("glTF " + path + ": more than one skin");
    skin = node.skin;
    for (const tinygltf::Primitive& prim : model.meshes[node.mesh].primitives) {
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) continue;
      auto attr = [&](const char* name) {
        auto it = prim.attributes.find(name);
        return it == prim.attributes.end() ? -1 : it->second;
      };
      if (attr("POSITION") < 0 || attr("JOINTS_0") < 0 || attr("WEIGHTS_0") < 0) continue;
      std::vector<float> pos, nor, uv, jnt, wgt, idx;
      FVV_RETURN_IF_ERROR(ReadAccessor(model, attr("POSITION"), 3, &pos, "POSITION"));
      const size_t n = pos.size() / 3, base = c.positions.size();
      if (base + n > kMaxVertices) return LimitExceeded("glTF " + path + ": more than 4M vertices");
      if (attr("NORMAL") >= 0)
        FVV_RETURN_IF_ERROR(ReadAccessor(model, attr("NORMAL"), 3, &nor, "NORMAL"));
      if (attr("TEXCOORD_0") >= 0)
        FVV_RETURN_IF_ERROR(ReadAccessor(model, attr("TEXCOORD_0"), 2, &uv, "TEXCOORD_0"));
      FVV_RETURN_IF_ERROR(ReadAccessor(model, attr("JOINTS_0"), 4, &jnt, "JOINTS_0"));
      FVV_RETURN_IF_ERROR(ReadAccessor(model, attr("WEIGHTS_0"), 4, &wgt, "WEIGHTS_0"));
      if (nor.size() != 0 && nor.size() != 3 * n) return Corrupt("glTF: NORMAL count differs");
      if ((uv.size() != 0 && uv.size() != 2 * n) || jnt.size() != 4 * n || wgt.size() != 4 * n) {
        return Corrupt("glTF " + path + ": vertex attribute counts differ");
      }
      for (size_t v = 0; v < n; ++v) {
        c.positions.emplace_back(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]);
        c.normals.push_back(
            nor.empty() ? Eigen::Vector3f(0, 1, 0)
                        : Eigen::Vector3f(nor[3 * v], nor[3 * v + 1], nor[3 * v + 2]).normalized());
        c.uvs.push_back(uv.empty() ? Eigen::Vector2f(0.5f, 0.5f)
                                   : Eigen::Vector2f(uv[2 * v], uv[2 * v + 1]));
        Eigen::Vector4f w(wgt[4 * v], wgt[4 * v + 1], wgt[4 * v + 2], wgt[4 * v + 3]);
        const float sum = w.sum();
        w = sum > 0 ? Eigen::Vector4f(w / sum) : Eigen::Vector4f(1, 0, 0, 0);
        c.weights.push_back(w);
        std::array<uint16_t, 4> j;
        for (int k = 0; k < 4; ++k) {
          const float index = jnt[4 * v + k];
          if (!(index >= 0 && index <= 65535 && index == std::floor(index))) {
            return Corrupt("glTF " + path + ": JOINTS_0 of vertex " + std::to_string(v) +
                           " is not a joint index");
          }
          j[k] = static_cast<uint16_t>(index);
        }
        c.joints.push_back(j);
      }
      if (prim.indices >= 0) {
        FVV_RETURN_IF_ERROR(ReadAccessor(model, prim.indices, 1, &idx, "indices"));
      } else {
        for (size_t v = 0; v < n; ++v) idx.push_back(float(v));
      }
      for (float i : idx) {
        if (i < 0 || i >= n) return Corrupt("glTF " + path + ": triangle index out of range");
        c.indices.push_back(static_cast<uint32_t>(base + size_t(i)));
      }
      if (c.indices.size() % 3)
        return Corrupt("glTF " + path + ": index count is not a multiple of 3");
      // The primitive's base colour texture (times its factor), or a flat colour.
      const int material = prim.material;
      const size_t slot = material >= 0 && size_t(material) < model.materials.size()
                              ? material
                              : model.materials.size();
      if (texture_of_material[slot] < 0) {
        std::vector<double> factor = {1, 1, 1, 1};
        Image tex;
        if (slot < model.materials.size()) {
          const auto& pbr = model.materials[slot].pbrMetallicRoughness;
          if (pbr.baseColorFactor.size() == 4) factor = pbr.baseColorFactor;
          const int t = pbr.baseColorTexture.index;
          if (t >= 0 && size_t(t) < model.textures.size()) {
            const int source = model.textures[t].source;
            if (source >= 0 && size_t(source) < model.images.size() &&
                HoldsDecoded8Bit(model.images[source])) {
              tex = ToRgb(model.images[source], factor);
            }
          }
        }
        if (tex.pixels.empty()) {
          tex.width = tex.height = 4;
          tex.pixels.resize(48);
          for (size_t i = 0; i < 48; ++i)
            tex.pixels[i] = uint8_t(std::clamp(factor[i % 3] * 200.0, 0.0, 255.0));
        }
        texture_of_material[slot] = static_cast<int>(textures.size());
        textures.push_back(std::move(tex));
      }
      vertex_ranges.push_back({base, texture_of_material[slot]});
    }
  }
  if (skin < 0 || c.positions.empty()) {
    return InvalidArgument("glTF " + path +
                           ": no skinned triangle mesh (a character needs a skin)");
  }
  const tinygltf::Skin& s = model.skins[skin];
  if (s.joints.empty() || s.joints.size() > kMaxJoints) {
    return LimitExceeded("glTF " + path + ": skin has " + std::to_string(s.joints.size()) +
                         " joints (1..256)");
  }
  for (int j : s.joints) {
    if (j < 0 || size_t(j) >= c.nodes.size())
      return Corrupt("glTF " + path + ": skin joint out of range");
    c.joint_nodes.push_back(j);
  }
  for (const auto& j : c.joints) {
    for (uint16_t k : j) {
      if (k >= c.joint_nodes.size())
        return Corrupt("glTF " + path + ": vertex joint index out of range");
    }
  }
  c.inverse_bind.assign(c.joint_nodes.size(), Eigen::Matrix4d::Identity());
  if (s.inverseBindMatrices >= 0) {
    std::vector<float> ibm;
    FVV_RETURN_IF_ERROR(
        ReadAccessor(model, s.inverseBindMatrices, 16, &ibm, "inverseBindMatrices"));
    if (ibm.size() != 16 * c.joint_nodes.size())
      return Corrupt("glTF: inverse bind matrix count differs");
    for (size_t j = 0; j < c.joint_nodes.size(); ++j) {
      for (int i = 0; i < 16; ++i) c.inverse_bind[j](i % 4, i / 4) = ibm[16 * j + i];
    }
  }

  // Textures of several materials: stacked vertically, UVs remapped (wrapped into [0, 1)).
  const uint32_t width =
      std::max_element(textures.begin(), textures.end(), [](const Image& a, const Image& b) {
        return a.width < b.width;
      })->width;
  c.texture.width = width;
  uint32_t row = 0;
  std::vector<std::pair<uint32_t, uint32_t>> placement;  // (first row, rows)
  for (const Image& t : textures) {
    const uint32_t rows = std::max<uint32_t>(1, uint32_t(uint64_t(t.height) * width / t.width));
    placement.push_back({row, rows});
    row += rows;
  }
  c.texture.height = row;
  c.texture.pixels.resize(size_t(width) * row * 3);
  for (size_t k = 0; k < textures.size(); ++k) {
    const Image& t = textures[k];
    for (uint32_t y = 0; y < placement[k].second; ++y) {
      for (uint32_t x = 0; x < width; ++x) {
        const size_t sx = size_t(x) * t.width / width,
                     sy = size_t(y) * t.height / placement[k].second;
        std::copy_n(&t.pixels[(sy * t.width + sx) * 3], 3,
                    &c.texture.pixels[((placement[k].first + y) * size_t(width) + x) * 3]);
      }
    }
  }
  if (textures.size() > 1) {
    for (size_t r = 0; r < vertex_ranges.size(); ++r) {
      const size_t end = r + 1 < vertex_ranges.size() ? vertex_ranges[r + 1].first : c.uvs.size();
      const auto [first_row, rows] = placement[vertex_ranges[r].second];
      for (size_t v = vertex_ranges[r].first; v < end; ++v) {
        const float u = c.uvs[v].x() - std::floor(c.uvs[v].x()),
                    w = c.uvs[v].y() - std::floor(c.uvs[v].y());
        c.uvs[v] = Eigen::Vector2f(u, (first_row + w * rows) / float(c.texture.height));
      }
    }
  }

  for (const tinygltf::Animation& a : model.animations) {
    GltfAnimation anim;
    anim.name = a.name;
    for (const tinygltf::AnimationChannel& ch : a.channels) {
      if (ch.target_node < 0 || size_t(ch.target_node) >= c.nodes.size()) continue;
      if (ch.sampler < 0 || size_t(ch.sampler) >= a.samplers.size())
        return Corrupt("glTF: bad sampler");
      GltfChannel out;
      out.node = ch.target_node;
      int components = 3;
      if (ch.target_path == "translation") {
        out.path = GltfChannel::Path::kTranslation;
      } else if (ch.target_path == "rotation") {
        out.path = GltfChannel::Path::kRotation;
        components = 4;
      } else if (ch.target_path == "scale") {
        out.path = GltfChannel::Path::kScale;
      } else {
        continue;  // morph weights: not used for characters here
      }
      const tinygltf::AnimationSampler& sm = a.samplers[ch.sampler];
      out.interpolation = sm.interpolation == "STEP" ? GltfChannel::Interpolation::kStep
                          : sm.interpolation == "CUBICSPLINE"
                              ? GltfChannel::Interpolation::kCubicSpline
                              : GltfChannel::Interpolation::kLinear;
      FVV_RETURN_IF_ERROR(ReadAccessor(model, sm.input, 1, &out.times, "animation input"));
      FVV_RETURN_IF_ERROR(
          ReadAccessor(model, sm.output, components, &out.values, "animation output"));
      const size_t per_key =
          components * (out.interpolation == GltfChannel::Interpolation::kCubicSpline ? 3 : 1);
      if (out.times.empty() || out.values.size() != out.times.size() * per_key) {
        return Corrupt("glTF " + path + ": animation key counts differ");
      }
      for (size_t k = 1; k < out.times.size(); ++k) {
        if (!(out.times[k] >= out.times[k - 1])) return Corrupt("glTF: animation times decrease");
      }
      anim.duration = std::max(anim.duration, double(out.times.back()));
      anim.channels.push_back(std::move(out));
    }
    c.animations.push_back(std::move(anim));
  }
  return c;
}

std::vector<Eigen::Matrix4d> GltfCharacter::NodeWorld(int animation, double seconds) const {
  std::vector<Eigen::Vector3d> t(nodes.size()), s(nodes.size());
  std::vector<Eigen::Quaterniond> r(nodes.size());
  for (size_t n = 0; n < nodes.size(); ++n)
    t[n] = nodes[n].translation, r[n] = nodes[n].rotation, s[n] = nodes[n].scale;
  if (animation >= 0 && size_t(animation) < animations.size()) {
    const GltfAnimation& a = animations[animation];
    const double time = a.duration > 0 ? std::fmod(std::max(seconds, 0.0), a.duration) : 0.0;
    for (const GltfChannel& ch : a.channels) {
      const int comps = ch.path == GltfChannel::Path::kRotation ? 4 : 3;
      const bool cubic = ch.interpolation == GltfChannel::Interpolation::kCubicSpline;
      const size_t stride = comps * (cubic ? 3 : 1);
      const size_t keys = ch.times.size();
      size_t k = std::upper_bound(ch.times.begin(), ch.times.end(), float(time)) - ch.times.begin();
      k = k == 0 ? 0 : k - 1;
      const size_t k1 = std::min(k + 1, keys - 1);
      const double span = ch.times[k1] - ch.times[k];
      double u = span > 0 ? std::clamp((time - ch.times[k]) / span, 0.0, 1.0) : 0.0;
      if (ch.interpolation == GltfChannel::Interpolation::kStep) u = 0;
      Eigen::Vector4d v;
      const size_t off = cubic ? comps : 0;  // cubic keys: in-tangent, value, out-tangent
      for (int c = 0; c < comps; ++c) {
        const double p0 = ch.values[k * stride + off + c], p1 = ch.values[k1 * stride + off + c];
        if (cubic) {
          const double m0 = span * ch.values[k * stride + 2 * comps + c];
          const double m1 = span * ch.values[k1 * stride + c];
          const double u2 = u * u, u3 = u2 * u;
          v[c] = (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * p1 +
                 (u3 - u2) * m1;
        } else {
          v[c] = p0 + u * (p1 - p0);
        }
      }
      if (ch.path == GltfChannel::Path::kRotation) {
        if (!cubic && ch.interpolation != GltfChannel::Interpolation::kStep) {
          const Eigen::Quaterniond q0(ch.values[k * stride + 3], ch.values[k * stride],
                                      ch.values[k * stride + 1], ch.values[k * stride + 2]);
          const Eigen::Quaterniond q1(ch.values[k1 * stride + 3], ch.values[k1 * stride],
                                      ch.values[k1 * stride + 1], ch.values[k1 * stride + 2]);
          r[ch.node] = q0.normalized().slerp(u, q1.normalized());
        } else {
          r[ch.node] = Eigen::Quaterniond(v[3], v[0], v[1], v[2]).normalized();
        }
      } else if (ch.path == GltfChannel::Path::kTranslation) {
        t[ch.node] = v.head<3>();
      } else {
        s[ch.node] = v.head<3>();
      }
    }
  }
  std::vector<Eigen::Matrix4d> world(nodes.size());
  std::vector<char> done(nodes.size(), 0);
  for (size_t n = 0; n < nodes.size(); ++n) {
    // Parents may come after children in glTF: walk up, then fill top-down.
    std::vector<size_t> chain;
    for (int p = int(n); p >= 0 && !done[p]; p = nodes[p].parent) chain.push_back(size_t(p));
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const GltfNode& node = nodes[*it];
      const Eigen::Matrix4d local = node.has_matrix ? node.matrix : Trs(t[*it], r[*it], s[*it]);
      world[*it] = node.parent >= 0 ? Eigen::Matrix4d(world[node.parent] * local) : local;
      done[*it] = 1;
    }
  }
  return world;
}

std::vector<Eigen::Matrix4d> GltfCharacter::Skinning(int animation, double seconds) const {
  const std::vector<Eigen::Matrix4d> world = NodeWorld(animation, seconds);
  std::vector<Eigen::Matrix4d> out(joint_nodes.size());
  for (size_t j = 0; j < joint_nodes.size(); ++j) out[j] = world[joint_nodes[j]] * inverse_bind[j];
  return out;
}

}  // namespace fvv
