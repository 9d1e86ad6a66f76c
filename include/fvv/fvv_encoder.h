/* fvv encoder: the C API studios and tools embed (library fvv::encoder).
 *
 * A capture directory (docs/capture-format.md) in, a .fvv stream out: silhouettes and marker-free
 * motion capture (or poses given), the body model's texture atlas, resampling of every camera into
 * the atlas, 4D-SPIHT texture coding per GOP, shape masks and the motion track.
 *
 * Usage:
 *
 *   fvv_encoder_settings settings;
 *   fvv_encoder_default_settings(&settings);
 *   settings.rate_mode = FVV_RATE_PSNR;          // or FVV_RATE_BPP, FVV_RATE_BYTES_PER_GOP
 *   settings.rate_value = 38;
 *   settings.poses = "take1/poses.json";          // optional: skip tracking
 *   fvv_encoder* enc;
 *   if (fvv_encoder_create(&settings, &enc) != FVV_OK) ...
 *   fvv_encoder_add_metadata(enc, "title", "Take 1");
 *   fvv_encode_report report;
 *   if (fvv_encoder_encode_capture(enc, "take1", "take1.fvv", &report) != FVV_OK)
 *     ... report fvv_encoder_error(enc); nothing was written under "take1.fvv"
 *   fvv_encoder_destroy(enc);
 *
 * The output appears only when encoding succeeds (a temporary file is renamed over it).
 *
 * Thread safety: one encoder is used by one thread at a time; different encoders are independent.
 * The progress callback is called one line at a time, never concurrently, while
 * fvv_encoder_encode_capture runs. When the encoder tracks, a frame's resampling and coding run
 * on a worker thread beside the tracking of the next frames, and its lines come from that thread.
 */
#ifndef FVV_FVV_ENCODER_H_
#define FVV_FVV_ENCODER_H_

#include "fvv/fvv_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct fvv_encoder fvv_encoder;

typedef enum {
  FVV_RATE_PSNR = 0,         /* rate_value: weighted-YUV PSNR in dB over visible texels, per GOP */
  FVV_RATE_BPP = 1,          /* rate_value: bits per atlas texel of a GOP block (seen or not) */
  FVV_RATE_BYTES_PER_GOP = 2 /* rate_value: texture bytes per GOP fragment */
} fvv_rate_mode;

typedef enum { FVV_KERNEL_CDF97 = 0, FVV_KERNEL_LEGALL53 = 1, FVV_KERNEL_HAAR = 2 } fvv_kernel;
/* SPIHT decision coding. FVV_CODER_ARITH3 (the default): range coding with the set and sign
   contexts of format version 5. FVV_CODER_ARITH2: the neighbourhood contexts of format version 4
   (about 0.1 dB lower at equal bytes on atlas textures). FVV_CODER_ARITH: the contexts of format
   versions 1..3, for older decoders (about 0.2 to 0.3 dB lower). FVV_CODER_BINARY: raw
   decisions. FVV_CODER_ARITH4: not SPIHT's sets but a quadtree per subband, format version 8;
   better on still, textured images (+0.05 to +0.13 dB on Kodak). */
typedef enum {
  FVV_CODER_ARITH = 0,
  FVV_CODER_BINARY = 1,
  FVV_CODER_ARITH2 = 2,
  FVV_CODER_ARITH3 = 3,
  FVV_CODER_ARITH4 = 4
} fvv_entropy_coder;
/* Subband weights (SPEC.md 9.3). FVV_WEIGHTS_OWN_BAND (the default): each coefficient weighted by
   the synthesis norm of its own band, format version 6. FVV_WEIGHTS_AXIS_BANDS: the weighting of
   format versions 1..5, for older decoders (0.1 to 0.4 dB lower at equal bytes). */
typedef enum { FVV_WEIGHTS_OWN_BAND = 0, FVV_WEIGHTS_AXIS_BANDS = 1 } fvv_band_weights;
/* FVV_CHROMA_420: chroma halved in both directions and upsampled bilinearly by players, format
   version 9. FVV_CHROMA_420_NEAREST: the same samples replicated over their 2x2 cells, what format
   versions 1..8 decoders read (0.2-0.5 dB lower RGB at high compression). */
typedef enum { FVV_CHROMA_444 = 0, FVV_CHROMA_420 = 1, FVV_CHROMA_420_NEAREST = 2 } fvv_chroma;
/* FVV_MASKS_NONE (the default): no shape masks; players take each camera's visibility from the
   decoded geometry (depth maps of the posed model), and the encoder fills what they may take.
   FVV_MASKS_CODED: mask mode 2 (two context models mixed per texel; format version 2).
   FVV_MASKS_CODED_V1: mask mode 1, about 12 % larger, keeps a SPIHT stream at format version 1
   for older decoders. */
typedef enum { FVV_MASKS_CODED = 0, FVV_MASKS_NONE = 1, FVV_MASKS_CODED_V1 = 2 } fvv_mask_mode;
/* FVV_TEXTURE_SPIHT: 4D wavelet + 4D SPIHT per GOP. FVV_TEXTURE_PREDICTIVE: T00 + R0(t) + R(t, c)
   with shape-adaptive BISK (format version 2; needs coded masks and 4:4:4; give it several
   cameras per GOP: gop_cameras 0 = all, and the 5/3 kernel). */
typedef enum { FVV_TEXTURE_SPIHT = 0, FVV_TEXTURE_PREDICTIVE = 1 } fvv_texture_codec;

typedef struct {
  /* Format. */
  uint32_t atlas_size;   /* atlas side in texels, 16..4096 (default 512) */
  uint32_t gop_frames;   /* frames per GOP (default 8) */
  uint32_t gop_cameras;  /* cameras per GOP (default 1: see docs/encoder.md); 0 = all */
  uint32_t kernel;       /* an fvv_kernel */
  uint32_t coder;        /* an fvv_entropy_coder */
  uint32_t chroma;       /* an fvv_chroma */
  uint32_t mask_mode;    /* an fvv_mask_mode */
  uint32_t rate_mode;    /* an fvv_rate_mode (default FVV_RATE_PSNR) */
  double rate_value;     /* default 36 (dB) */
  uint32_t key_interval; /* motion key frames: 1 = every frame coded (default) */
  uint32_t threads;      /* worker threads, 1..256 (default 2) */
  /* Input. */
  uint32_t first_frame, last_frame; /* capture frames to encode (default 0 and UINT32_MAX: all) */
  const char* poses;         /* poses.json (fvv track) or a synthetic capture's truth: no tracking;
                                NULL: track */
  const char* textures;      /* a directory written by save_textures: no tracking, no resampling */
  const char* save_textures; /* also write the atlas textures and masks before coding (PNG) */
  /* Called with one line of progress per frame and stage; may be NULL. */
  void (*progress)(void* user, const char* line);
  void* progress_user;
  uint32_t texture_codec; /* an fvv_texture_codec (default FVV_TEXTURE_SPIHT) */
  /* Fractional bits of the 9/7 transform's samples, 2..6 (default 5: format version 3).
     2 keeps a 9/7 SPIHT stream readable by format version 1 and 2 decoders. */
  uint32_t precision_97;
  uint32_t weights; /* an fvv_band_weights (default FVV_WEIGHTS_OWN_BAND) */
  /* Fractional bits of the coded YCbCr samples, 0..4 (default 3: format version 7, about 1.9 dB
     better at 20:1 than 0). 0 writes what format version 6 decoders read. Used with the 9/7 SPIHT
     codec and own-band weights (at most precision_97); the others code whole samples. */
  uint32_t sample_bits;
  /* 1 (default): with FVV_RATE_BPP or FVV_RATE_BYTES_PER_GOP, zero the coefficients that only
     the last coded bitplane would make significant with no significant neighbour, code the GOP
     again and keep that if it decodes better (about +0.1 dB at 120:1 on the demo capture; a
     second SPIHT encode and two decodes per GOP). 0: off. Encoder-side only: any decoder reads
     the result. */
  uint32_t prune;
  /* 1 (default): the body model on a grid (format version 10: 0.12 mm positions, 10-bit normals,
     8-bit skin weights; less than half the bytes of its floats). 0: 32-bit floats, what format
     versions 1..9 decoders read. */
  uint32_t quantise_model;
  /* 1 (default): the texture in chunks (format version 11), so that any prefix of a GOP fragment
     past its head decodes: a player fetches what its bandwidth allows with one HTTP range request.
     The same samples, a few hundred bytes more per fragment. 0: 'texr', what format versions 1..10
     decoders read. Ignored with the predictive texture. */
  uint32_t texture_chunks;
  /* Without masks (FVV_MASKS_NONE): a texel a camera did not see but a player may take from it is
     coded, with the seeing cameras' colour, only where that camera can weigh at least this share
     of the reference player's blend from some viewpoint; elsewhere it is left to the coder's fill
     (default 0.25; 0 codes every such texel; at most 1). Encoder-side only. */
  double least_blend_share;
  /* 1: carry the surface of every frame (format version 12, SPEC.md 3.5.2), tracked from the
     cameras' silhouettes and used for resampling; needs texture_chunks and footage (not a
     texture directory). Default 0. */
  uint32_t surface;
  /* 1 (default): where the silhouettes hold something besides the actor (another person, a prop:
     foreground the posed model does not explain), a hull of it is carved from them and a camera's
     samples of the surface it hides are left out. 0: every sample kept. Encoder-side only. */
  uint32_t occluders;
  /* A texel no camera sees in a frame takes the mean colour of the frames of its GOP, at most this
     many frames away, that saw it, before the actor's static texture (default 15; 0: the static
     texture alone; at most 100000). Encoder-side only. */
  uint32_t temporal_fill_frames;
} fvv_encoder_settings;

typedef struct {
  uint32_t frames, cameras, atlas_size, gops, level;
  uint64_t file_bytes, texture_bytes, mask_bytes, motion_bytes;
  uint64_t visible_texels;       /* texels some camera saw, over frames and cameras */
  double psnr_y, psnr_u, psnr_v; /* over visible texels, decoded at full length */
  double psnr_rgb;
  double ratio_atlas;   /* 24-bit RGB of every atlas texel / file bytes */
  double ratio_visible; /* 24-bit RGB of the visible texels / file bytes */
  double seconds;       /* wall time of the whole encode */
} fvv_encode_report;

FVV_EXPORT void fvv_encoder_default_settings(fvv_encoder_settings* settings);
/* settings may be NULL (the defaults). FVV_INVALID_ARGUMENT, and *encoder NULL, when a setting is
 * out of its range or an enum value unknown; fvv_encoder_settings_error() says
 * which. */
FVV_EXPORT fvv_status fvv_encoder_create(const fvv_encoder_settings* settings,
                                         fvv_encoder** encoder);
/* Why the last fvv_encoder_create on this thread failed ("" if it did not). */
FVV_EXPORT const char* fvv_encoder_settings_error(void);
FVV_EXPORT void fvv_encoder_destroy(fvv_encoder* encoder);
/* The message of the last failure ("" after success). Valid until the next call on encoder. */
FVV_EXPORT const char* fvv_encoder_error(const fvv_encoder* encoder);
/* UTF-8 key/value pairs written into the stream's metadata box. */
FVV_EXPORT fvv_status fvv_encoder_add_metadata(fvv_encoder* encoder, const char* key,
                                               const char* value);
/* Encodes capture directory `capture` (or its capture.json) into `output`. report may be NULL. */
FVV_EXPORT fvv_status fvv_encoder_encode_capture(fvv_encoder* encoder, const char* capture,
                                                 const char* output, fvv_encode_report* report);

#ifdef __cplusplus
}
#endif

#endif /* FVV_FVV_ENCODER_H_ */
