#include "player/export/gltf_writer.h"

#include <algorithm>
#include <cstring>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <vector>

#include "codec/base/atomic_file.h"
#include "player/export/png_encode.h"

namespace fvv {
namespace {

using nlohmann::json;

constexpr int kFloat = 5126, kUnsignedShort = 5123, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The binary buffer and the JSON arrays that describe it.
class Builder {
 public:
  json doc;
  std::vector<uint8_t> bin;

  Builder() {
    doc["bufferViews"] = json::array();
    doc["accessors"] = json::array();
  }

  // A buffer view over `bytes` (4-byte aligned); target 0 = none.
  int View(const void* data, size_t bytes, int target) {
    while (bin.size() % 4) bin.push_back(0);
    json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
    if (target) v["target"] = target;
    const auto* p = static_cast<const uint8_t*>(data);
    bin.insert(bin.end(), p, p + bytes);
    doc["bufferViews"].push_back(v);
    return int(doc["bufferViews"].size()) - 1;
  }

  // An accessor of `count` elements of `type` ("SCALAR", "VEC3", ...) with
  // `components` values each; min and max over the float data when asked.
  int Floats(const std::vector<float>& values, const char* type, int components, int target,
             bool bounds) {
    const size_t count = values.size() / components;
    json a = {{"bufferView", View(values.data(), values.size() * 4, target)},
              {"componentType", kFloat},
              {"count", count},
              {"type", type}};
    if (bounds) {
      std::vector<float> lo(components, 0), hi(components, 0);
      for (size_t i = 0; i < count; ++i) {
        for (int k = 0; k < components; ++k) {
          const float v = values[i * components + k];
          lo[k] = i == 0 ? v : std::min(lo[k], v);
          hi[k] = i == 0 ? v : std::max(hi[k], v);
        }
      }
      a["min"] = lo;
      a["max"] = hi;
    }
    doc["accessors"].push_back(a);
    return int(doc["accessors"].size()) - 1;
  }

  template <typename T>
  int Integers(const std::vector<T>& values, int component_type, const char* type, int components,
               int target) {
    json a = {{"bufferView", View(values.data(), values.size() * sizeof(T), target)},
              {"componentType", component_type},
              {"count", values.size() / components},
              {"type", type}};
    doc["accessors"].push_back(a);
    return int(doc["accessors"].size()) - 1;
  }
};

std::vector<float> Flat(const std::vector<glm::vec3>& v) {
  std::vector<float> out;
  for (const glm::vec3& x : v) out.insert(out.end(), {x.x, x.y, x.z});
  return out;
}

}  // namespace

Status WriteGltf(const ExportedActor& a, const std::string& path) {
  const bool binary = EndsWith(path, ".glb");
  if (!binary && !EndsWith(path, ".gltf")) {
    return InvalidArgument(path + ": a glTF export is written to a .glb or .gltf file");
  }
  if (a.texture_rgb.empty()) return InvalidArgument("glTF export without a texture");
  const size_t joints = a.joints.size(), frames = a.rotation.size();
  Builder b;
  json& doc = b.doc;
  doc["asset"] = {{"version", "2.0"}, {"generator", "fvv export"}};
  doc["extensionsUsed"] = {"KHR_materials_unlit"};

  // Joints: one node each, in the rest pose; the mesh node beside the roots.
  json nodes = json::array(), scene_nodes = json::array();
  for (size_t j = 0; j < joints; ++j) {
    const ExportedJoint& joint = a.joints[j];
    const glm::quat& r = joint.rest_rotation;
    json node = {{"name", joint.name.empty() ? "joint" + std::to_string(j) : joint.name},
                 {"translation",
                  {joint.rest_translation.x, joint.rest_translation.y, joint.rest_translation.z}},
                 {"rotation", {r.x, r.y, r.z, r.w}}};
    json children = json::array();
    for (size_t c = 0; c < joints; ++c) {
      if (a.joints[c].parent == int32_t(j)) children.push_back(c);
    }
    if (!children.empty()) node["children"] = children;
    nodes.push_back(node);
    if (joint.parent < 0) scene_nodes.push_back(j);
  }

  // The skinned mesh.
  const size_t vertices = a.positions.size() / 3;
  std::vector<float> weights = a.weights;
  std::vector<uint16_t> skin_joints = a.skin_joints;
  for (size_t v = 0; v < vertices; ++v) {
    float sum = 0;
    for (int k = 0; k < 4; ++k) sum += weights[4 * v + k];
    for (int k = 0; k < 4; ++k) {
      weights[4 * v + k] = sum > 0 ? weights[4 * v + k] / sum : (k == 0 ? 1.0f : 0.0f);
      if (weights[4 * v + k] == 0) skin_joints[4 * v + k] = 0;  // unused slots name joint 0
    }
  }
  json attributes = {{"POSITION", b.Floats(a.positions, "VEC3", 3, kArrayBuffer, true)},
                     {"NORMAL", b.Floats(a.normals, "VEC3", 3, kArrayBuffer, false)},
                     {"TEXCOORD_0", b.Floats(a.uvs, "VEC2", 2, kArrayBuffer, false)},
                     {"JOINTS_0", b.Integers(skin_joints, kUnsignedShort, "VEC4", 4, kArrayBuffer)},
                     {"WEIGHTS_0", b.Floats(weights, "VEC4", 4, kArrayBuffer, false)}};
  const int indices = b.Integers(a.triangles, kUnsignedInt, "SCALAR", 1, kElementArrayBuffer);
  json primitive = {{"attributes", attributes}, {"indices", indices}, {"material", 0}};
  // The surface of every frame (format version 12): a morph target per frame,
  // which the animation switches on one at a time.
  const bool morphs = !a.surface_deltas.empty() && a.surface_deltas.size() == frames;
  if (morphs) {
    json targets = json::array();
    for (const std::vector<float>& delta : a.surface_deltas) {
      targets.push_back({{"POSITION", b.Floats(delta, "VEC3", 3, kArrayBuffer, true)}});
    }
    primitive["targets"] = targets;
  }
  doc["meshes"] = {{{"name", "actor"}, {"primitives", {primitive}}}};
  if (morphs) doc["meshes"][0]["weights"] = std::vector<float>(frames, 0.0f);
  std::vector<float> ibm;
  for (const glm::mat4& m : a.inverse_bind)
    ibm.insert(ibm.end(), glm::value_ptr(m), glm::value_ptr(m) + 16);
  json skin_joint_nodes = json::array();
  for (size_t j = 0; j < joints; ++j) skin_joint_nodes.push_back(j);
  doc["skins"] = {{{"name", "body"},
                   {"joints", skin_joint_nodes},
                   {"inverseBindMatrices", b.Floats(ibm, "MAT4", 16, 0, false)}}};
  if (!scene_nodes.empty()) doc["skins"][0]["skeleton"] = scene_nodes[0];
  nodes.push_back({{"name", "actor"}, {"mesh", 0}, {"skin", 0}});
  scene_nodes.push_back(joints);
  doc["nodes"] = nodes;
  doc["scene"] = 0;
  doc["scenes"] = {{{"name", "capture"}, {"nodes", scene_nodes}}};

  // The texture, unlit: the capture's light is in it.
  FVV_ASSIGN_OR_RETURN(std::vector<uint8_t> png,
                       EncodePng(a.texture_rgb.data(), a.texture_width, a.texture_height));
  doc["materials"] = {
      {{"name", "captured"},
       {"pbrMetallicRoughness",
        {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}},
       {"extensions", {{"KHR_materials_unlit", json::object()}}}}};
  doc["samplers"] = {
      {{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 33071}, {"wrapT", 33071}}};
  doc["textures"] = {{{"sampler", 0}, {"source", 0}}};
  const std::string stem = path.substr(0, path.size() - (binary ? 4 : 5));
  const std::string base = stem.substr(stem.find_last_of('/') + 1);
  if (binary) {
    doc["images"] = {
        {{"bufferView", b.View(png.data(), png.size(), 0)}, {"mimeType", "image/png"}}};
  } else {
    doc["images"] = {{{"uri", base + ".png"}}};
  }

  // The motion: key times from the frame rate; rotations of every joint,
  // translations of the joints whose translation changes.
  if (frames > 0) {
    std::vector<float> times;
    for (size_t f = 0; f < frames; ++f) times.push_back(float(f / a.fps));
    const int input = b.Floats(times, "SCALAR", 1, 0, true);
    json samplers = json::array(), channels = json::array();
    const auto add = [&](int output, size_t node, const char* path_name) {
      samplers.push_back({{"input", input}, {"output", output}, {"interpolation", "LINEAR"}});
      channels.push_back(
          {{"sampler", samplers.size() - 1}, {"target", {{"node", node}, {"path", path_name}}}});
    };
    for (size_t j = 0; j < joints; ++j) {
      std::vector<float> q;
      for (size_t f = 0; f < frames; ++f) {
        const glm::quat& r = a.rotation[f][j];
        q.insert(q.end(), {r.x, r.y, r.z, r.w});
      }
      add(b.Floats(q, "VEC4", 4, 0, false), j, "rotation");
      std::vector<glm::vec3> t;
      bool moves = a.joints[j].parent < 0;
      for (size_t f = 0; f < frames; ++f) {
        t.push_back(a.translation[f][j]);
        moves = moves || glm::length(t.back() - a.translation[0][j]) > 1e-6f;
      }
      if (moves) add(b.Floats(Flat(t), "VEC3", 3, 0, false), j, "translation");
    }
    if (morphs) {
      std::vector<float> one_hot(frames * frames, 0.0f);
      for (size_t f = 0; f < frames; ++f) one_hot[f * frames + f] = 1.0f;
      samplers.push_back({{"input", input},
                          {"output", b.Floats(one_hot, "SCALAR", 1, 0, false)},
                          {"interpolation", "STEP"}});
      channels.push_back(
          {{"sampler", samplers.size() - 1}, {"target", {{"node", joints}, {"path", "weights"}}}});
    }
    doc["animations"] = {{{"name", "capture"}, {"samplers", samplers}, {"channels", channels}}};
  }

  while (b.bin.size() % 4) b.bin.push_back(0);
  doc["buffers"] = {{{"byteLength", b.bin.size()}}};
  if (!binary) {
    doc["buffers"][0]["uri"] = base + ".bin";
    FVV_RETURN_IF_ERROR(WriteFileAtomic(stem + ".bin", b.bin.data(), b.bin.size()));
    FVV_RETURN_IF_ERROR(WriteFileAtomic(stem + ".png", png.data(), png.size()));
    const std::string text = doc.dump(1) + "\n";
    return WriteFileAtomic(path, reinterpret_cast<const uint8_t*>(text.data()), text.size());
  }
  // GLB: header, JSON chunk (padded with spaces), BIN chunk.
  std::string text = doc.dump();
  while (text.size() % 4) text.push_back(' ');
  std::vector<uint8_t> out;
  const auto u32 = [&out](uint32_t v) {
    for (int k = 0; k < 4; ++k) out.push_back(uint8_t(v >> (8 * k)));
  };
  u32(0x46546C67);  // "glTF"
  u32(2);
  u32(uint32_t(12 + 8 + text.size() + 8 + b.bin.size()));
  u32(uint32_t(text.size()));
  u32(0x4E4F534A);  // "JSON"
  out.insert(out.end(), text.begin(), text.end());
  u32(uint32_t(b.bin.size()));
  u32(0x004E4942);  // "BIN\0"
  out.insert(out.end(), b.bin.begin(), b.bin.end());
  return WriteFileAtomic(path, out.data(), out.size());
}

}  // namespace fvv
