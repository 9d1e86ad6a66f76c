#include "encoder/track/silhouette_truth.h"

#include <sys/stat.h>

#include <cstdio>

#include "encoder/io/image_io.h"

namespace fvv {
namespace {

bool IsDir(const std::string& p) {
  struct stat st;
  return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

}  // namespace

StatusOr<SilhouetteAgreement> CompareSilhouettesWithTruth(const std::string& truth,
                                                          const std::string& saved,
                                                          const std::vector<std::string>& cameras,
                                                          uint32_t first, uint32_t last) {
  std::string root = truth;
  if (IsDir(root + "/truth/silhouettes")) root += "/truth";
  root += "/silhouettes";
  if (!IsDir(root)) return IoError("truth: no true silhouettes in " + root);
  SilhouetteAgreement a;
  a.cameras = cameras;
  a.frames = last >= first ? last - first + 1 : 0;
  double sum = 0;
  for (const std::string& camera : cameras) {
    double camera_sum = 0;
    for (uint32_t f = first; f <= last && f >= first; ++f) {
      char name[32];
      std::snprintf(name, sizeof(name), "%06u.png", f);
      const std::string true_path = root + "/" + camera + "/" + name;
      const std::string saved_path = saved + "/" + camera + "_" + name;
      FVV_ASSIGN_OR_RETURN(const Image t, ReadImage(true_path));
      FVV_ASSIGN_OR_RETURN(const Image s, ReadImage(saved_path));
      if (t.width != s.width || t.height != s.height) {
        return InvalidArgument(saved_path + ": " + std::to_string(s.width) + "x" +
                               std::to_string(s.height) + ", the true silhouette " +
                               std::to_string(t.width) + "x" + std::to_string(t.height));
      }
      uint64_t both = 0, either = 0;
      for (size_t i = 0; i < size_t(t.width) * t.height; ++i) {
        const bool in_t = t.pixels[i * t.channels] != 0, in_s = s.pixels[i * s.channels] != 0;
        both += in_t && in_s;
        either += in_t || in_s;
      }
      camera_sum += either ? double(both) / either : 1.0;
    }
    a.iou.push_back(a.frames ? camera_sum / a.frames : 0);
    sum += camera_sum;
  }
  a.mean = a.frames && !cameras.empty() ? sum / (double(a.frames) * cameras.size()) : 0;
  return a;
}

}  // namespace fvv
