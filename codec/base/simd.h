// FVV_SIMD_CLONES marks an inner loop for an AVX2 clone beside the baseline
// one, chosen at load time where the CPU has AVX2: the loops are written so that
// both compute identical results. Off under AddressSanitizer and
// ThreadSanitizer (their instrumentation and ifunc resolvers do not mix: the
// resolver runs before the sanitizer's runtime) and off x86-64.
#ifndef FVV_CODEC_BASE_SIMD_H_
#define FVV_CODEC_BASE_SIMD_H_

// clang names its sanitizers through __has_feature only.
#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define FVV_SIMD_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define FVV_SIMD_SANITIZED 1
#endif

#if defined(__x86_64__) && defined(__GNUC__) && !defined(FVV_SIMD_SANITIZED)
#define FVV_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define FVV_SIMD_CLONES
#endif

// Helpers called from a clone must be inlined into it to run with its
// instruction set: a separate copy is compiled for the baseline only.
#if defined(__GNUC__)
#define FVV_ALWAYS_INLINE inline __attribute__((always_inline))
#define FVV_INLINE_LAMBDA __attribute__((always_inline))  // after a lambda's parameters
#else
#define FVV_ALWAYS_INLINE inline
#define FVV_INLINE_LAMBDA
#endif

#endif  // FVV_CODEC_BASE_SIMD_H_
