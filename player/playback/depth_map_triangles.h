// The triangles both players' camera depth maps draw (player/render/
// camera_depth_maps.h, player/web/fvv_renderer.mjs): the body model simplified
// to about kSimplifyShare of its triangles, its surface kept within
// kSimplifyError of the model's extent (container/geometric_visibility.h), over
// the model's own vertices, so that it skins and takes a frame's surface as
// the model does. A software rasteriser's depth pass costs what its triangles
// do; the visibility test's 2 cm tolerance covers a few millimetres of surface.
//
// Edge collapses onto an existing vertex, in rounds of the cheapest by the
// mean squared distance to the planes of the triangles merged into it (the
// generic body in 65 ms natively, 56 ms in WebAssembly in Node once warm; half
// a million triangles in about 2 s, two million in about 10 s, once, for a
// stream without masks; the page makes it in its decoder worker); vertices at one
// position (the atlas's seams) count as one; a collapse that would fold a
// triangle over or join the surface to itself is refused, and a vertex on an
// open border stays. The same code runs in both players (the page's in
// WebAssembly), so both draw the same triangles: it uses no arithmetic whose
// rounding a compiler may choose (built with floating-point contraction off).
#ifndef FVV_PLAYER_PLAYBACK_DEPTH_MAP_TRIANGLES_H_
#define FVV_PLAYER_PLAYBACK_DEPTH_MAP_TRIANGLES_H_

#include <cstdint>
#include <vector>

namespace fvv {

// Vertex indices, three per triangle, each below vertex_count, wound as the
// model's. Triangles with an index out of range, or two corners at one
// position, are left out. Never more triangles than the model's.
std::vector<uint32_t> DepthMapTriangles(const float* positions, uint32_t vertex_count,
                                        const uint32_t* triangles, uint32_t triangle_count);

// The same with a share and an error bound of the caller's (tests).
std::vector<uint32_t> SimplifiedTriangles(const float* positions, uint32_t vertex_count,
                                          const uint32_t* triangles, uint32_t triangle_count,
                                          double share, double max_error);

}  // namespace fvv

#endif  // FVV_PLAYER_PLAYBACK_DEPTH_MAP_TRIANGLES_H_
