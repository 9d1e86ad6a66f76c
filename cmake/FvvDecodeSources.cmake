# The decoder's sources, from the project root: one list for the native
# libraries (codec/, container/, player/) and the WebAssembly build
# (player/web/CMakeLists.txt), so the two never drift apart. The zstd frames are
# left out: libzstd natively (container/zstd_frame.cc), the page's
# decompressor in WebAssembly (container/zstd_frame_web.cc).
set(FVV_BASE_SOURCES
  codec/base/atomic_file.cc
  codec/base/large_buffer.cc
  codec/base/status.cc
  codec/base/thread_pool.cc
)
set(FVV_CODEC_DEC_SOURCES
  codec/bisk_dec.cc
  codec/block.cc
  codec/block_codec_common.cc
  codec/block_codec_dec.cc
  codec/block_syntax.cc
  codec/colour.cc
  codec/mask_dec.cc
  codec/predictive_texture_dec.cc
  codec/quadtree4d_common.cc
  codec/sa_wavelet.cc
  codec/spiht4d_common.cc
  codec/quadtree4d_dec.cc
  codec/spiht4d_dec.cc
  codec/subband_weights.cc
  codec/wavelet.cc
)
set(FVV_CONTAINER_DEC_SOURCES
  container/body_model.cc
  container/box.cc
  container/cameras.cc
  container/crc32c.cc
  container/fetched_source.cc
  container/file_header.cc
  container/file_reader.cc
  container/gop_grid.cc
  container/fixed_rotation.cc
  container/fragment.cc
  container/geometric_visibility.cc
  container/index_box.cc
  container/model_quantisation.cc
  container/motion_common.cc
  container/motion_dec.cc
  container/stream_info.cc
  container/stream_reader.cc
  container/surface_displacement.cc
  container/vertex_visibility.cc
  container/xxh64.cc
)
set(FVV_DEC_SOURCES
  player/decoder/c_api.cc
  player/decoder/decoder.cc
  player/decoder/gop_decoder.cc
  player/decoder/pose.cc
  player/decoder/public_camera.cc
  player/decoder/view_pixels.cc
)
get_filename_component(FVV_SOURCE_ROOT "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
# The list `name` with absolute paths, in `out`.
function(fvv_source_paths out name)
  list(TRANSFORM ${name} PREPEND "${FVV_SOURCE_ROOT}/" OUTPUT_VARIABLE paths)
  set(${out} ${paths} PARENT_SCOPE)
endfunction()
