/* fvv decoder: the C API players embed (library fvv::dec, decode-only).
 *
 * Usage, random access over a file:
 *
 *   fvv_decoder_settings settings;
 *   fvv_decoder_default_settings(&settings);
 *   fvv_decoder* dec;
 *   if (fvv_decoder_create(&settings, &dec) != FVV_OK) ...
 *   if (fvv_decoder_open_file(dec, "capture.fvv") != FVV_OK) ... report fvv_decoder_error(dec)
 *   fvv_stream_info info;
 *   fvv_decoder_get_info(dec, &info);
 *   fvv_decode_budget budget = {0};            // 0 = no limit: decode everything
 *   budget.max_ms_per_gop = 20;                // or cut each GOP's decoding at 20 ms
 *   for (uint32_t f = 0; f < info.frame_count; ++f) {
 *     fvv_frame* frame;
 *     fvv_status s = fvv_decoder_decode_frame(dec, f, &budget, &frame);
 *     if (s != FVV_OK) ... report fvv_decoder_error(dec); skip or stop
 *     ... use frame->bone_world, frame->views[c].rgb / .mask, frame->report ...
 *     fvv_frame_release(frame);
 *   }
 *   fvv_decoder_destroy(dec);
 *
 * Usage, streaming (bytes arrive from the network; the stream must be in order):
 *
 *   fvv_decoder_push(dec, chunk, chunk_size);        // any chunk sizes, as they arrive
 *   for (;;) {
 *     fvv_event event;
 *     if (fvv_decoder_process(dec, &event) != FVV_OK) ... error, stop
 *     if (event == FVV_EVENT_NEED_MORE_INPUT) break;   // push the next chunk, process again
 *     if (event == FVV_EVENT_READY) ... header, cameras and model are available
 *     if (event == FVV_EVENT_FRAMES) ... frames up to fvv_decoder_frames_available() decode
 *     if (event == FVV_EVENT_END) ... the stream is complete
 *   }
 *   fvv_decoder_push_end(dec);                       // no more bytes: then process to
 * FVV_EVENT_END
 *
 * Usage, byte ranges (a web page fetching with HTTP Range requests; the stream needs an index):
 *
 *   fvv_decoder_open_ranges(dec, stream_size);       // from the server's Content-Range
 *   fvv_decoder_add_range(dec, 0, first, first_size); // e.g. the first 256 KiB
 *   while (fvv_decoder_process(dec, &event) == FVV_OK && event == FVV_EVENT_NEED_MORE_INPUT) {
 *     fvv_decoder_wanted_range(dec, &offset, &size);  // fetch (at least) these bytes, add them
 *   }
 *   // FVV_EVENT_READY: for each GOP fragment the view needs (fvv_decoder_get_fragment), fetch a
 *   // prefix of its bytes of at least head_size and add it; fvv_decoder_decode_frame decodes
 *   // from what has been added. Fetch more of a fragment later and the frame decodes better.
 *
 * Frames are decoded a GOP (all frames and cameras of a time span) at a time and kept, so
 * consecutive frames cost nothing extra; with settings.decode_ahead the next GOP is decoded on a
 * worker thread while the caller uses the current one.
 *
 * Thread safety: one decoder is used by one thread at a time (calls on one decoder must not
 * overlap); different decoders are independent. A frame is immutable and may be read from any
 * thread until fvv_frame_release. The decoder's own worker threads never call back into user code.
 *
 * Errors: every function returns a status; FVV_INVALID_ARGUMENT for misuse (NULL pointers, a call
 * in the wrong state, a frame out of range), never a crash. fvv_decoder_error gives a message that
 * names the box and byte offset for stream errors.
 */
#ifndef FVV_FVV_DECODER_H_
#define FVV_FVV_DECODER_H_

#include "fvv/fvv_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct fvv_decoder fvv_decoder;

typedef struct {
  uint32_t threads;          /* worker threads for decoding; 0 = one per core */
  uint64_t memory_cap_bytes; /* bound on buffered input and decoded GOPs; 0 = 1 GiB */
  int decode_ahead;          /* non-zero: decode the next GOP in the background */
  /* The decoder's claim by limits (SPEC.md 5.1), beside the level limits every stream obeys: a
     stream whose GOPs hold more samples (atlas width x height x GOP frames x GOP cameras), or
     whose fragments more bytes, is FVV_LIMIT_EXCEEDED when its header (or the fragment) is read,
     before anything it sizes is allocated, whatever level it declares. What the decoder needs is
     about 16 bytes per GOP sample plus the fragment bytes (SPEC.md 5). 0 = the stream's level's
     limit. The WebAssembly build's JavaScript claims 2^26 samples and 32 MiB (level 2's): a page
     holds 4 GiB, and a 31-camera stream of small GOPs, level 3 for its camera count alone, plays.
   */
  uint64_t max_gop_samples;
  uint64_t max_fragment_bytes;
} fvv_decoder_settings;

FVV_EXPORT void fvv_decoder_default_settings(fvv_decoder_settings* settings);
FVV_EXPORT fvv_status fvv_decoder_create(const fvv_decoder_settings* settings,
                                         fvv_decoder** decoder);
/* NULL is allowed. Frames obtained from the decoder stay valid after it is destroyed. */
FVV_EXPORT void fvv_decoder_destroy(fvv_decoder* decoder);
/* The message of the last error (empty when none); valid until the next call on the decoder. */
FVV_EXPORT const char* fvv_decoder_error(const fvv_decoder* decoder);

/* Input: either open a file (random access; the header boxes are read at once), or push bytes. */
FVV_EXPORT fvv_status fvv_decoder_open_file(fvv_decoder* decoder, const char* path);
FVV_EXPORT fvv_status fvv_decoder_push(fvv_decoder* decoder, const uint8_t* data, size_t size);
FVV_EXPORT fvv_status fvv_decoder_push_end(fvv_decoder* decoder);

typedef enum {
  FVV_EVENT_NEED_MORE_INPUT = 0, /* push more bytes (or fvv_decoder_push_end) */
  FVV_EVENT_READY = 1,           /* header, cameras, model and motion parameters are known */
  FVV_EVENT_FRAMES = 2,          /* more frames can be decoded (fvv_decoder_frames_available) */
  FVV_EVENT_END = 3              /* the whole stream has been read */
} fvv_event;
FVV_EXPORT fvv_status fvv_decoder_process(fvv_decoder* decoder, fvv_event* event);
/* Frames [0, n) are decodable now (all of them after open_file, and after open_ranges once
   FVV_EVENT_READY came). */
FVV_EXPORT uint32_t fvv_decoder_frames_available(const fvv_decoder* decoder);

/* Byte ranges: random access over a stream of `stream_size` bytes of which only the ranges added
 * are known. fvv_decoder_process returns FVV_EVENT_NEED_MORE_INPUT until the header boxes and the
 * index have been added (then FVV_EVENT_READY); a stream without an index is FVV_UNSUPPORTED here
 * (push it instead). Ranges may come in any order and overlap; bytes already added are kept.
 * No GOP is decoded ahead: the caller decides what is fetched and decoded. */
FVV_EXPORT fvv_status fvv_decoder_open_ranges(fvv_decoder* decoder, uint64_t stream_size);
FVV_EXPORT fvv_status fvv_decoder_add_range(fvv_decoder* decoder, uint64_t offset,
                                            const uint8_t* data, size_t size);
/* Before FVV_EVENT_READY: the bytes the header boxes or the index need next (1), or 0 when the
   decoder needs none it knows of: the box it is reading and 4 KiB more, for the next boxes'
   headers. Fetching more than asked saves requests. */
FVV_EXPORT int fvv_decoder_wanted_range(const fvv_decoder* decoder, uint64_t* offset,
                                        uint64_t* size);

/* The GOP fragments of a stream opened by file or by ranges, in index order (time span, then
   camera group): fragment (frame / gop_frames) * groups + camera / gop_cameras holds a frame and
   camera, groups = ceil(camera_count / gop_cameras). */
typedef struct {
  uint32_t first_frame, frame_count;
  uint32_t first_camera, camera_count;
  uint64_t offset, size; /* the fragment's bytes in the stream */
  uint64_t head_size;    /* the shortest prefix that decodes: the fragment's head in streams with
                            the texture in chunks (format version 11, SPEC.md 3.5.1), any longer
                            prefix decoding more of its texture; = size in older streams, which
                            decode whole fragments only */
  uint64_t held;         /* bytes of it the decoder holds from its first on (= size for a file) */
  uint64_t surface_size; /* with the surface of every frame (format version 12, camera group 0):
                            the bytes right past the head that carry it whole, known once the
                            decoder has read the fragment (decoded a frame of it); 0 before, and
                            without a surface. A player plans the next GOP's prefix with the last
                            one's (the surface decodes whole or not at all, SPEC.md 3.5.2) */
} fvv_fragment_info;
FVV_EXPORT uint32_t fvv_decoder_fragment_count(const fvv_decoder* decoder);
FVV_EXPORT fvv_status fvv_decoder_get_fragment(const fvv_decoder* decoder, uint32_t index,
                                               fvv_fragment_info* fragment);

typedef struct {
  uint32_t format_version;
  uint32_t profile, level;
  uint32_t frame_count;
  uint32_t frame_rate_num, frame_rate_den;
  uint32_t camera_count;
  uint32_t atlas_width, atlas_height;
  uint32_t gop_frames, gop_cameras;
  uint32_t bone_count, vertex_count, triangle_count;
  uint32_t has_masks; /* frames carry visibility masks */
} fvv_stream_info;
FVV_EXPORT fvv_status fvv_decoder_get_info(const fvv_decoder* decoder, fvv_stream_info* info);

typedef struct {
  const char* name; /* valid while the decoder lives */
  uint32_t width, height;
  double fx, fy, cx, cy;
  double distortion[5]; /* k1 k2 p1 p2 k3 */
  double rotation[9];   /* world -> camera, row-major */
  double translation[3];
  double centre[3]; /* camera centre in world coordinates */
} fvv_camera;
FVV_EXPORT fvv_status fvv_decoder_get_camera(const fvv_decoder* decoder, uint32_t index,
                                             fvv_camera* camera);

/* The body model, as arrays owned by the decoder (valid while it lives). */
typedef struct {
  uint32_t bone_count;
  const int32_t* bone_parent;   /* [bone_count], -1 for roots */
  const float* bone_rest_world; /* [bone_count][16] column-major rest-pose joint transforms */
  uint32_t vertex_count;
  const float* positions; /* [vertex_count][3] metres, bind pose */
  const float* normals;   /* [vertex_count][3] */
  const float* uvs;       /* [vertex_count][2] atlas coordinates in [0, 1] */
  const uint16_t* joints; /* [vertex_count][4] skin bones */
  const float* weights;   /* [vertex_count][4] skin weights, sum 1 */
  uint32_t triangle_count;
  const uint32_t* triangles; /* [triangle_count][3] */
} fvv_model;
FVV_EXPORT fvv_status fvv_decoder_get_model(const fvv_decoder* decoder, fvv_model* model);

typedef enum {
  FVV_FORMAT_RGB8 = 0,  /* interleaved R G B, one byte each */
  FVV_FORMAT_YUV444 = 1 /* three planes Y, U, V of width x height bytes (4:2:0 streams upsampled) */
} fvv_pixel_format;

typedef struct {
  uint64_t max_bytes_per_gop; /* texture bytes to decode per GOP fragment; 0 = all. In streams
                                 with the texture in chunks (format version 11): the prefix of each
                                 fragment decoded, head included (SPEC.md Annex B.2); less than a
                                 fragment's head_size decodes its head (motion, masks) and none of
                                 its texture. (Bytes held, with open_ranges, are another matter:
                                 fewer than a head is FVV_TRUNCATED.) */
  double max_ms_per_gop;      /* time for the GOP's embedded-stream (SPIHT) decoding, after which
                                 it stops with what it has; set-up and the inverse transform come
                                 on top. 0 = no limit. GOPs of the predictive texture (format
                                 version 2, 'ptex') are cut by max_bytes_per_gop only: a time
                                 budget decodes them whole */
  uint32_t format;            /* an fvv_pixel_format (a plain integer: any value is checked) */
  uint64_t camera_mask;       /* cameras to decode: bit c = camera c (streams have at most 64);
                                 0 = all. A player passes the cameras its view blends; with one
                                 camera per GOP fragment (the encoder's default) the others are
                                 not decoded at all. Views of cameras left out have NULL pixels
                                 and mask. A camera group is decoded whole when any of its
                                 cameras is asked for. Under a time budget (a real-time
                                 player), a GOP already decoded, or decoding ahead, under
                                 another time budget or camera set is used as it is: the
                                 next GOP gets the new set. */
  double floor_share;         /* the quality floor of a time budget, 0 to 1: the share of each
                                 texture stream's bytes that is decoded even when
                                 max_ms_per_gop has run out (its first bitplanes; fvv play
                                 keeps 0.15). 0 = none: the time budget alone cuts.
                                 Ignored without a time budget */
} fvv_decode_budget;

typedef struct {
  const uint8_t* pixels; /* atlas texture in the requested format; NULL for a camera the
                            budget's camera_mask left out */
  const uint8_t* mask;   /* atlas_width x atlas_height bytes, 1 = the texture holds a sample
                            of the surface there (the camera saw the texel, or the encoder
                            filled it from other frames: SPEC.md section 7);
                            NULL when the stream carries no masks */
} fvv_view;

typedef struct {
  uint64_t bytes_decoded;   /* texture bytes read for this frame's GOP (all its fragments) */
  uint64_t bytes_available; /* texture bytes the GOP's streams hold (of the cameras decoded) */
  uint32_t bitplanes[3];    /* fewest complete bitplanes over the GOP's fragments, Y U V */
  double decode_ms;         /* time spent decoding the GOP */
  int complete;             /* every stream decoded to its end */
  double max_ms_per_gop;    /* the time budget the GOP was decoded under (a GOP decoded ahead
                               has the budget of the request that started it); 0 = none */
} fvv_decode_report;

typedef struct {
  uint32_t index; /* frame number */
  uint32_t bone_count;
  const float* bone_world; /* [bone_count][16] column-major bone-to-world transforms */
  const float* bone_skin;  /* [bone_count][16] bone_world * inverse(rest world): skinning */
  uint32_t camera_count;
  uint32_t width, height; /* atlas size */
  fvv_pixel_format format;
  const fvv_view* views; /* [camera_count] */
  fvv_decode_report report;
  const float* surface; /* [vertex_count][3] the frame's own surface in the bind pose (format
                           version 12, SPEC.md 3.5.2), skinned with bone_skin like the model's
                           positions; NULL: the model's positions (the stream carries no
                           surface for the frame, or a byte budget ended before it) */
} fvv_frame;

/* Decodes (or takes from the GOP cache) frame `index`. The cached GOP is reused while the same
 * budget is asked for, and decoded again under a different one; time budgets (max_ms_per_gop > 0)
 * all count as the same, so a real-time player that retunes its budget every GOP keeps what was
 * decoded ahead. budget may be NULL (decode everything). Frames of GOPs that were dropped under the
 * memory cap (streaming) are FVV_INVALID_ARGUMENT. */
FVV_EXPORT fvv_status fvv_decoder_decode_frame(fvv_decoder* decoder, uint32_t index,
                                               const fvv_decode_budget* budget, fvv_frame** frame);
FVV_EXPORT void fvv_frame_release(fvv_frame* frame);

/* For players that must not block: start decoding frame `index`'s GOP in the background
 * (a no-op when it is cached or already under way), and ask whether fvv_decoder_decode_frame
 * would return without decoding. While it is not ready, keep showing the last frame. */
FVV_EXPORT fvv_status fvv_decoder_prefetch(fvv_decoder* decoder, uint32_t index,
                                           const fvv_decode_budget* budget);
FVV_EXPORT int fvv_decoder_frame_ready(fvv_decoder* decoder, uint32_t index,
                                       const fvv_decode_budget* budget);

#ifdef __cplusplus
}
#endif

#endif /* FVV_FVV_DECODER_H_ */
