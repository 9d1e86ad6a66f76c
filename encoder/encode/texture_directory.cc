// The texture directory of fvv encode --save-textures and --textures: the
// atlas textures and masks as coded, per camera and frame, and textures.json.
// A mask texel is 255 where the camera saw the texel, 0 where it is unused, and
// for streams without masks 128 where a player may take it from the camera
// though the camera did not see it (it holds the seeing cameras' colour).
#include "encoder/encode/encoder_session.h"

namespace fvv {
namespace encoding {

Status Session::SaveTextures(uint32_t frame, uint32_t slot) {
  const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
  for (uint32_t c = 0; c < sum_.cameras; ++c) {
    const size_t plane = size_t(slot) * sum_.cameras + c;
    Image tex{s_.atlas_size, s_.atlas_size, 3, {}};
    tex.pixels.assign(&span_rgb_[plane * texels * 3], &span_rgb_[(plane + 1) * texels * 3]);
    Image mask{s_.atlas_size, s_.atlas_size, 1, std::vector<uint8_t>(texels)};
    for (size_t i = 0; i < texels; ++i) {
      const size_t t = plane * texels + i;
      mask.pixels[i] = span_mask_[t]                              ? kSeenTexel
                       : !span_usable_.empty() && span_usable_[t] ? kUsableTexel
                                                                  : 0;
    }
    FVV_RETURN_IF_ERROR(WritePng(TexturePath(s_.save_textures, camera_dirs_[c], frame), tex));
    FVV_RETURN_IF_ERROR(WritePng(TextureMaskPath(s_.save_textures, camera_dirs_[c], frame), mask));
  }
  return Status::Ok();
}

Status Session::ReadTextures(uint32_t frame, uint32_t slot) {
  const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
  std::vector<Status> errors(sum_.cameras);
  pool_.Run(sum_.cameras, [&](uint32_t c) {
    const size_t plane = size_t(slot) * sum_.cameras + c;
    const std::string tp = TexturePath(s_.textures, camera_dirs_[c], frame);
    const std::string mp = TextureMaskPath(s_.textures, camera_dirs_[c], frame);
    StatusOr<Image> tex = ReadImage(tp);
    StatusOr<Image> mask = tex.ok() ? ReadImage(mp) : tex;
    if (!mask.ok()) {
      errors[c] = mask.status();
      return;
    }
    for (const auto* im : {&*tex, &*mask}) {
      if (im->width != s_.atlas_size || im->height != s_.atlas_size) {
        errors[c] = InvalidArgument((im == &*tex ? tp : mp) + ": " + std::to_string(im->width) +
                                    "x" + std::to_string(im->height) + ", the atlas is " +
                                    std::to_string(s_.atlas_size) + " square");
        return;
      }
    }
    for (size_t i = 0; i < texels; ++i) {
      const uint8_t m = mask->pixels[i * mask->channels];
      span_mask_[plane * texels + i] = m != 0 && m != kUsableTexel;
      if (!span_usable_.empty()) span_usable_[plane * texels + i] = m != 0;
      for (int k = 0; k < 3; ++k) {
        span_rgb_[(plane * texels + i) * 3 + k] =
            tex->channels == 3 ? tex->pixels[i * 3 + k] : tex->pixels[i];
      }
    }
  });
  for (const Status& e : errors) FVV_RETURN_IF_ERROR(e);
  return Status::Ok();
}

Status Session::MakeTextureDirectories() const {
  for (const std::string& dir : camera_dirs_) {
    FVV_RETURN_IF_ERROR(MakeDirectories(s_.save_textures + "/" + dir));
  }
  return Status::Ok();
}

// textures.json: what the textures are (atlas, cameras, frames) and the
// poses and body shape they were resampled with, so `--textures` can encode
// them again (it is also a valid poses file).
Status Session::WriteTexturesJson() const {
  nlohmann::json j;
  j["generator"] = "fvv encode --save-textures";
  j["atlas_size"] = s_.atlas_size;
  j["first_frame"] = first_;
  j["frame_count"] = sum_.frames;
  j["cameras"] = camera_dirs_;
  j["texture_pattern"] = "<camera>/texture_%06d.png";
  j["mask_pattern"] = "<camera>/mask_%06d.png";
  j["dof_names"] = GenericDofNames();
  j["body_shape"] = BodyShapeToJson(shape_);
  nlohmann::json frames = nlohmann::json::array();
  for (size_t i = 0; i < raw_poses_.size(); ++i) {
    frames.push_back({{"frame", first_ + i}, {"dofs", raw_poses_[i]}});
  }
  j["frames"] = frames;
  const std::string text = j.dump(1) + "\n";
  return WriteFileAtomic(s_.save_textures + "/textures.json",
                         reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

}  // namespace encoding

std::string TexturePath(const std::string& dir, const std::string& camera, uint32_t frame) {
  return encoding::FrameFile(dir, camera, "texture", frame);
}
std::string TextureMaskPath(const std::string& dir, const std::string& camera, uint32_t frame) {
  return encoding::FrameFile(dir, camera, "mask", frame);
}

}  // namespace fvv
