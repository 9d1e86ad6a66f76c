// Mesh operations on the body model's triangle mesh that shape refinement and
// synthetic surface detail share. The mesh repeats vertices along texture
// seams (same position, different atlas coordinates); "welded" indices name
// one canonical vertex per position, so a displacement moves both copies and
// the surface stays closed.
#ifndef FVV_ENCODER_BODY_MESH_OPS_H_
#define FVV_ENCODER_BODY_MESH_OPS_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "container/body_model.h"

namespace fvv {

// Per vertex, the lowest index of a vertex at exactly the same position.
std::vector<uint32_t> WeldVertices(const std::vector<Eigen::Vector3f>& positions);

// Area-weighted vertex normals, summed over welded copies (unit length).
std::vector<Eigen::Vector3f> VertexNormals(const std::vector<std::array<uint32_t, 3>>& triangles,
                                           const std::vector<Eigen::Vector3f>& positions,
                                           const std::vector<uint32_t>& welded);

// Per canonical vertex, its welded 1-ring neighbours (canonical indices,
// sorted, unique); empty for non-canonical vertices.
std::vector<std::vector<uint32_t>> VertexNeighbours(
    const std::vector<std::array<uint32_t, 3>>& triangles, const std::vector<uint32_t>& welded);

// The mesh's positions as vectors, and back (normals recomputed).
std::vector<Eigen::Vector3f> MeshPositions(const Mesh& mesh);
// The mesh's stored normals as vectors.
std::vector<Eigen::Vector3f> MeshNormals(const Mesh& mesh);
void SetMeshPositions(const std::vector<Eigen::Vector3f>& positions, Mesh* mesh);

}  // namespace fvv

#endif  // FVV_ENCODER_BODY_MESH_OPS_H_
