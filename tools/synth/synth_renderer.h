// The synthetic capture generator's OpenGL drawing: a lit, textured, skinned
// actor in a textured studio (floor with tape marks and the actor's soft
// shadow, panelled walls), the empty studio for background plates, and the
// actor's exact silhouette. OpenGL 3.3 core in a context the caller owns.
#ifndef FVV_TOOLS_SYNTH_SYNTH_RENDERER_H_
#define FVV_TOOLS_SYNTH_SYNTH_RENDERER_H_

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"
#include "player/render/gl_api.h"
#include "tools/synth/actor.h"

namespace fvv {

class SynthRenderer {
 public:
  static constexpr size_t kMaxBones = kMaxSkinBones;
  // `clutter`: the studio also holds furniture and equipment (boxes, a
  // cabinet, stands) around the capture volume, each its own colour.
  static StatusOr<std::unique_ptr<SynthRenderer>> Create(const GlApi& gl, const ActorMesh& mesh,
                                                         size_t bone_count, bool clutter = false);
  ~SynthRenderer();
  SynthRenderer(const SynthRenderer&) = delete;
  SynthRenderer& operator=(const SynthRenderer&) = delete;

  // The studio, and the actor in `skinning`'s pose when it is not null; the
  // actor's shadow falls around `root` (its ground projection).
  Status DrawScene(const Camera& camera, const std::vector<Eigen::Matrix4f>* skinning,
                   const Eigen::Vector3d& root);
  // Unlit: the actor shows its texture's own colours (tests compare resampled
  // textures with it); lit by default.
  void SetUnlit(bool unlit) { unlit_ = unlit; }
  // This renderer's actor added to the current drawing (depth-tested against
  // what is there): a second person in a scene another renderer drew.
  Status DrawActorOver(const Camera& camera, const std::vector<Eigen::Matrix4f>& skinning);
  // The actor alone, white on black.
  Status DrawSilhouette(const Camera& camera, const std::vector<Eigen::Matrix4f>& skinning);
  // The actor's bind-pose positions from now on (a surface that moves apart
  // from the skeleton), as many as the mesh has.
  void SetActorPositions(const std::vector<Eigen::Vector3f>& positions);
  // The last drawing, top-down rows (RGB or grey).
  StatusOr<Image> Read(const Camera& camera, int channels);

 private:
  explicit SynthRenderer(const GlApi& gl) : gl_(gl) {}
  Status SetCamera(const Camera& camera);
  void DrawActor(const std::vector<Eigen::Matrix4f>& skinning, int mode);

  GlApi gl_;
  GLuint program_ = 0, actor_vao_ = 0, studio_vao_ = 0, texture_ = 0, bones_ubo_ = 0;
  GLuint actor_positions_ = 0;
  size_t actor_vertices_ = 0;
  std::vector<GLuint> buffers_;
  GLsizei actor_indices_ = 0, studio_indices_ = 0;
  GLint u_view_proj_ = -1, u_skinned_ = -1, u_mode_ = -1, u_shadow_ = -1, u_shadow_on_ = -1;
  GLint u_unlit_ = -1;
  bool unlit_ = false;
};

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_SYNTH_RENDERER_H_
