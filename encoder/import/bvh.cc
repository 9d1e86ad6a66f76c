#include "encoder/import/bvh.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace fvv {
namespace {

constexpr size_t kMaxJoints = 1024;
constexpr size_t kMaxValues = size_t{1} << 28;
constexpr size_t kMaxFrames = size_t{1} << 20;  // 4.8 hours at 60 fps

class Tokens {
 public:
  explicit Tokens(const std::string& text) : text_(text) {}
  // Next whitespace-separated token; empty at the end.
  std::string Next() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  bool NextNumber(double* v) {
    const std::string t = Next();
    if (t.empty()) return false;
    char* end = nullptr;
    *v = std::strtod(t.c_str(), &end);
    return end == t.c_str() + t.size() && std::isfinite(*v);
  }
  int line() const { return line_; }

 private:
  const std::string& text_;
  size_t pos_ = 0;
  int line_ = 1;
};

struct Channel {
  size_t bone;
  int kind;  // Dof bit index
};

Status Error(const Tokens& t, const std::string& what) {
  return Corrupt("BVH line " + std::to_string(t.line()) + ": " + what);
}

}  // namespace

StatusOr<BvhMotion> ParseBvh(const std::string& text, double unit_metres) {
  Tokens t(text);
  if (t.Next() != "HIERARCHY") return Error(t, "file does not start with HIERARCHY");
  BvhMotion m;
  std::vector<Channel> channels;
  std::vector<int> stack;  // open joints; -1 for an End Site
  std::string tok = t.Next();
  if (tok != "ROOT") return Error(t, "expected ROOT, got '" + tok + "'");
  for (;;) {
    if (tok == "ROOT" || tok == "JOINT") {
      if (m.skeleton.bones.size() >= kMaxJoints) return Error(t, "more than 1024 joints");
      Bone b;
      b.name = t.Next();
      b.parent = -1;
      for (auto it = stack.rbegin(); it != stack.rend(); ++it) {
        if (*it >= 0) {
          b.parent = *it;
          break;
        }
      }
      if (tok == "JOINT" && b.parent < 0) return Error(t, "JOINT outside any ROOT");
      if (t.Next() != "{") return Error(t, "expected '{' after " + b.name);
      stack.push_back(static_cast<int>(m.skeleton.bones.size()));
      m.skeleton.bones.push_back(b);
    } else if (tok == "End") {
      t.Next();  // "Site"
      if (t.Next() != "{") return Error(t, "expected '{' after End Site");
      stack.push_back(-1);
    } else if (tok == "OFFSET") {
      double v[3];
      for (double& x : v) {
        if (!t.NextNumber(&x)) return Error(t, "OFFSET needs three numbers");
      }
      if (stack.empty()) return Error(t, "OFFSET outside a joint");
      if (stack.back() >= 0) {
        Bone& b = m.skeleton.bones[stack.back()];
        for (int a = 0; a < 3; ++a) b.rest_translation[a] = static_cast<float>(v[a] * unit_metres);
      }
    } else if (tok == "CHANNELS") {
      double n;
      if (!t.NextNumber(&n) || n < 0 || n > 6 || n != std::floor(n)) {
        return Error(t, "CHANNELS count must be 0..6");
      }
      if (stack.empty() || stack.back() < 0) return Error(t, "CHANNELS outside a joint");
      Bone& b = m.skeleton.bones[stack.back()];
      std::string order;
      for (int i = 0; i < int(n); ++i) {
        const std::string c = t.Next();
        if (c.size() != 9 || (c[0] != 'X' && c[0] != 'Y' && c[0] != 'Z')) {
          return Error(t, "unknown channel '" + c + "'");
        }
        const int axis = c[0] - 'X';
        const std::string what = c.substr(1);
        int kind;
        if (what == "rotation") {
          kind = axis;
          order += c[0];
        } else if (what == "position") {
          kind = 3 + axis;
        } else {
          return Error(t, "unknown channel '" + c + "'");
        }
        if (b.dof_mask & (1u << kind)) return Error(t, "channel '" + c + "' given twice");
        b.dof_mask |= static_cast<uint8_t>(1u << kind);
        channels.push_back({static_cast<size_t>(stack.back()), kind});
      }
      if (order.size() == 3) {
        static const char* const kOrders[] = {"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"};
        for (int o = 0; o < 6; ++o) {
          if (order == kOrders[o]) b.order = static_cast<RotationOrder>(o);
        }
      }
      for (int k = 0; k < kDofKinds; ++k) {
        b.dof_min[k] = -1e6f;  // BVH declares no limits
        b.dof_max[k] = 1e6f;
      }
    } else if (tok == "}") {
      if (stack.empty()) return Error(t, "unbalanced '}'");
      stack.pop_back();
      if (stack.empty()) {
        tok = t.Next();
        if (tok == "MOTION") break;
        if (tok != "ROOT") return Error(t, "expected MOTION after the hierarchy");
        continue;
      }
    } else if (tok.empty()) {
      return Error(t, "file ends inside the hierarchy");
    } else {
      return Error(t, "unexpected '" + tok + "'");
    }
    tok = t.Next();
  }
  double frames, frame_time;
  if (t.Next() != "Frames:" || !t.NextNumber(&frames) || frames < 0 ||
      frames != std::floor(frames)) {
    return Error(t, "expected 'Frames: N'");
  }
  if (t.Next() != "Frame" || t.Next() != "Time:" || !t.NextNumber(&frame_time) ||
      !(frame_time > 0)) {
    return Error(t, "expected 'Frame Time: seconds'");
  }
  if (channels.empty()) return Error(t, "the hierarchy has no CHANNELS");
  // Frames count on their own too (a vector each), besides the values.
  if (frames > double(kMaxFrames) || frames * channels.size() > double(kMaxValues)) {
    return Error(t, "motion too long");
  }
  m.frame_time = frame_time;
  // Map file channel order to the skeleton's DOF order.
  const std::vector<DofRef> dofs = m.skeleton.Dofs();
  std::vector<size_t> slot(channels.size());
  for (size_t i = 0; i < channels.size(); ++i) {
    for (size_t d = 0; d < dofs.size(); ++d) {
      if (dofs[d].bone == channels[i].bone && dofs[d].kind == channels[i].kind) slot[i] = d;
    }
  }
  m.frames.assign(static_cast<size_t>(frames), std::vector<double>(dofs.size()));
  for (auto& f : m.frames) {
    for (size_t i = 0; i < channels.size(); ++i) {
      double v;
      if (!t.NextNumber(&v)) return Error(t, "frame data ends early or is not a number");
      f[slot[i]] = IsRotationDof(channels[i].kind) ? v * M_PI / 180 : v * unit_metres;
    }
  }
  // Unwrap rotations: BVH exporters wrap angles into (-180, 180].
  for (size_t d = 0; d < dofs.size(); ++d) {
    if (!IsRotationDof(dofs[d].kind)) continue;
    for (size_t f = 1; f < m.frames.size(); ++f) {
      const double prev = m.frames[f - 1][d];
      double& v = m.frames[f][d];
      v -= 2 * M_PI * std::round((v - prev) / (2 * M_PI));
    }
  }
  return m;
}

StatusOr<BvhMotion> ReadBvhFile(const std::string& path, double unit_metres) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return IoError("cannot open " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  auto m = ParseBvh(ss.str(), unit_metres);
  if (!m.ok()) return Status(m.status().code(), path + ": " + m.status().message());
  return m;
}

std::vector<std::vector<double>> ResampleMotion(const BvhMotion& motion, double fps,
                                                double start_seconds) {
  std::vector<std::vector<double>> out;
  if (motion.frames.empty()) return out;
  const double duration = (motion.frames.size() - 1) * motion.frame_time;
  for (size_t k = 0;; ++k) {
    const double t = start_seconds + k / fps;
    if (t > duration + 1e-9) break;
    const double pos = t / motion.frame_time;
    const size_t i = std::min(static_cast<size_t>(pos), motion.frames.size() - 1);
    const size_t j = std::min(i + 1, motion.frames.size() - 1);
    const double w = pos - i;
    std::vector<double> f(motion.frames[i].size());
    for (size_t d = 0; d < f.size(); ++d) {
      f[d] = motion.frames[i][d] * (1 - w) + motion.frames[j][d] * w;
    }
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace fvv
