// What the synthetic capture generator films: a skinned, textured character
// and its motion, whatever it came from (the built-in body model driven by BVH
// or procedural motion, or an imported glTF character).
#ifndef FVV_TOOLS_SYNTH_ACTOR_H_
#define FVV_TOOLS_SYNTH_ACTOR_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "container/body_model.h"
#include "encoder/io/image_io.h"

namespace fvv {

// A skinned mesh ready to draw: bind-pose vertices, up to four influences each
// (weights sum to 1), a colour texture addressed by `uvs` (v = 0 at the top row).
struct ActorMesh {
  std::vector<Eigen::Vector3f> positions, normals;
  std::vector<Eigen::Vector2f> uvs;
  std::vector<std::array<uint16_t, 4>> joints;
  std::vector<Eigen::Vector4f> weights;
  std::vector<uint32_t> indices;  // triangles
  Image texture;                  // RGB
};

struct NamedPoint {
  std::string name;
  Eigen::Vector3d position;
};

class Actor {
 public:
  virtual ~Actor() = default;
  virtual std::string Describe() const = 0;
  virtual const ActorMesh& mesh() const = 0;
  virtual size_t bone_count() const = 0;
  virtual uint32_t frame_count() const = 0;
  // Per bone: the matrix taking bind-pose positions to frame `frame`'s pose.
  virtual std::vector<Eigen::Matrix4f> Skinning(uint32_t frame) const = 0;
  // Joint centres at `frame` (ground truth for tracking).
  virtual std::vector<NamedPoint> Joints(uint32_t frame) const = 0;
  // Where the actor stands (for its floor shadow): the root's position.
  virtual Eigen::Vector3d RootPosition(uint32_t frame) const = 0;
  // The bind-pose positions of frame `frame`: the mesh's, unless the surface
  // moves apart from the skeleton (a loose garment).
  virtual const std::vector<Eigen::Vector3f>& BindPositions(uint32_t frame) const {
    return mesh().positions;
  }
  // Whether BindPositions changes from frame to frame.
  virtual bool SurfaceMoves() const { return false; }
  // Posed vertex positions on the CPU (linear-blend skinning).
  std::vector<Eigen::Vector3f> PosedPositions(uint32_t frame) const;
};

// The built-in body model driven by DOF vectors (one per output frame, in
// Skeleton::Dofs() order), textured with the procedural clothing texture.
class BodyModelActor : public Actor {
 public:
  BodyModelActor(BodyModel model, std::vector<std::vector<double>> poses, Image texture,
                 std::string description);
  std::string Describe() const override { return description_; }
  const ActorMesh& mesh() const override { return mesh_; }
  size_t bone_count() const override { return model_.skeleton.bones.size(); }
  uint32_t frame_count() const override { return static_cast<uint32_t>(poses_.size()); }
  std::vector<Eigen::Matrix4f> Skinning(uint32_t frame) const override;
  std::vector<NamedPoint> Joints(uint32_t frame) const override;
  Eigen::Vector3d RootPosition(uint32_t frame) const override;
  const BodyModel& model() const { return model_; }
  const std::vector<double>& pose(uint32_t frame) const { return poses_[frame]; }
  // A loose garment (garment.h): per frame, the bind-pose positions.
  void SetFramePositions(std::vector<std::vector<Eigen::Vector3f>> positions) {
    frame_positions_ = std::move(positions);
  }
  const std::vector<Eigen::Vector3f>& BindPositions(uint32_t frame) const override {
    return frame_positions_.empty() ? mesh_.positions : frame_positions_[frame];
  }
  bool SurfaceMoves() const override { return !frame_positions_.empty(); }

 private:
  BodyModel model_;
  std::vector<std::vector<double>> poses_;
  std::vector<std::vector<Eigen::Vector3f>> frame_positions_;
  ActorMesh mesh_;
  std::string description_;
};

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_ACTOR_H_
