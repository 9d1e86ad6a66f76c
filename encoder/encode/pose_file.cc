#include "encoder/encode/pose_file.h"

#include <sys/stat.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "container/crc32c.h"
#include "encoder/body/body_shape_json.h"
#include "encoder/io/image_io.h"
#include "encoder/io/json_number.h"

namespace fvv {

std::vector<std::string> GenericDofNames() {
  static const char* kKinds[] = {"rx", "ry", "rz", "tx", "ty", "tz"};
  const BodyModel body = MakeGenericBody(BodyShape(), MeshResolution{8, 6});
  std::vector<std::string> names;
  for (const DofRef& d : body.skeleton.Dofs()) {
    names.push_back(body.skeleton.bones[d.bone].name + "." + kKinds[d.kind]);
  }
  return names;
}

StatusOr<PoseSequence> ParsePoseFile(const std::string& text, const std::string& what) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return Corrupt(what + ": not a JSON object");
  const std::vector<std::string> names = GenericDofNames();
  if (!j.contains("dof_names") || j["dof_names"] != nlohmann::json(names)) {
    return InvalidArgument(what +
                           ": dof_names are not the generic body's 35 DOFs (poses of another "
                           "skeleton cannot drive the encoder's body model)");
  }
  PoseSequence out;
  try {
    if (j.contains("body_shape")) {
      StatusOr<BodyShape> shape = BodyShapeFromJson(j["body_shape"], what);
      if (!shape.ok()) return shape.status();
      out.shape = *shape;
    } else if (j.contains("stature")) {
      out.shape.stature = j["stature"].get<double>();
    }
    if (j.contains("atlas_size"))
      out.atlas_size = JsonWhole<uint32_t>(j["atlas_size"], "atlas_size");
    const Status shape_ok = ValidateBodyShape(out.shape);
    if (!shape_ok.ok()) return Corrupt(what + ": " + shape_ok.message());
    const auto& frames = j.at("frames");
    if (!frames.is_array() || frames.empty()) return Corrupt(what + ": no frames");
    for (size_t i = 0; i < frames.size(); ++i) {
      const uint32_t frame = JsonWhole<uint32_t>(frames[i].at("frame"), "frame");
      if (i == 0) out.first_frame = frame;
      if (frame != out.first_frame + i) {
        return Corrupt(what + ": frames[" + std::to_string(i) + "] is frame " +
                       std::to_string(frame) + "; frames must be consecutive");
      }
      std::vector<double> dofs = frames[i].at("dofs").get<std::vector<double>>();
      if (dofs.size() != names.size()) {
        return Corrupt(what + ": frame " + std::to_string(frame) + " has " +
                       std::to_string(dofs.size()) + " DOF values, not " +
                       std::to_string(names.size()));
      }
      for (double v : dofs) {
        if (!std::isfinite(v) || std::abs(v) > 1000) {
          return Corrupt(what + ": frame " + std::to_string(frame) + ": a DOF value is not finite");
        }
      }
      out.poses.push_back(std::move(dofs));
    }
  } catch (const std::exception& e) {  // nlohmann's, or JsonWhole's range
    return Corrupt(what + ": " + e.what());
  }
  return out;
}

StatusOr<PoseSequence> LoadPoseFile(const std::string& path) {
  std::string file = path;
  struct stat st;
  if (stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) file = path + "/truth/truth.json";
  StatusOr<std::vector<uint8_t>> bytes = ReadFileBytes(file, 256u << 20);
  if (!bytes.ok()) return bytes.status();
  StatusOr<PoseSequence> poses = ParsePoseFile(std::string(bytes->begin(), bytes->end()), file);
  if (poses.ok()) poses->crc32c = Crc32c(bytes->data(), bytes->size());
  return poses;
}

}  // namespace fvv
