/* fvv public types: status codes (pinned), version, export macro.
 * C99 and C++; nothing here depends on the rest of fvv. */
#ifndef FVV_FVV_TYPES_H_
#define FVV_FVV_TYPES_H_

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define FVV_EXPORT __declspec(dllexport)
#elif defined(__GNUC__)
#define FVV_EXPORT __attribute__((visibility("default")))
#else
#define FVV_EXPORT
#endif

#define FVV_VERSION_MAJOR 0
#define FVV_VERSION_MINOR 1
#define FVV_VERSION_PATCH 0
/* The highest bitstream format version this library reads (container/SPEC.md). */
#define FVV_FORMAT_VERSION 12

/* Status codes. Pinned: values never change between releases. */
typedef enum {
  FVV_OK = 0,
  FVV_INVALID_ARGUMENT = 1,  /* the caller passed something unusable (misuse of the API) */
  FVV_TRUNCATED = 2,         /* input ended before a syntax element was complete */
  FVV_CORRUPT = 3,           /* input violates the bitstream syntax */
  FVV_LIMIT_EXCEEDED = 4,    /* a count or size beyond the profile/level limits */
  FVV_UNSUPPORTED = 5,       /* valid syntax this library does not implement (newer version) */
  FVV_CHECKSUM_MISMATCH = 6, /* a fragment's checksum failed */
  FVV_IO_ERROR = 7,          /* file system failure */
  FVV_OUT_OF_MEMORY = 8,     /* allocation failed or the memory cap was reached */
  FVV_INTERNAL = 9           /* a bug in fvv; please report it */
} fvv_status;

/* A short constant name for a status ("corrupt"). Never NULL. */
FVV_EXPORT const char* fvv_status_name(fvv_status status);

#ifdef __cplusplus
}
#endif

#endif /* FVV_FVV_TYPES_H_ */
