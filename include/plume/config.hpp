// plume/config.hpp - facts of this build, derived from the definitions and flags that the
// plume::config CMake target passes to every translation unit that uses plume.
//
//   PLUME_HAS_SSE2, PLUME_HAS_AVX2, PLUME_HAS_AVX512: 1 when that width family is enabled.
//   PLUME_SIMD_NAME: "scalar", "sse2", "avx2", "avx512" or "native".
//   PLUME_DETERMINISTIC: 1 when results are identical across builds.
//   PLUME_FMA: 1 when mul_add is fused (implies PLUME_DETERMINISTIC 0).
//
// Compiling with -ffast-math is an error (tests/fast_math_guard.cpp checks that it is).
#pragma once

#if defined(__FAST_MATH__)
#error                                                                                             \
    "plume must not be compiled with -ffast-math: it breaks the determinism contract and the termination of iterative algorithms"
#endif

#ifndef PLUME_DETERMINISTIC
#define PLUME_DETERMINISTIC 1
#endif
#ifndef PLUME_FMA
#define PLUME_FMA 0
#endif
#if PLUME_FMA && PLUME_DETERMINISTIC
#error "PLUME_FMA=1 gives up build-exactness: it needs PLUME_DETERMINISTIC=0"
#endif
#if PLUME_FMA && !defined(__FMA__)
#error "PLUME_FMA=1 needs a build with FMA instructions (-mfma, avx512 or native)"
#endif

#if defined(PLUME_SIMD_SCALAR)
#define PLUME_SIMD_NAME "scalar"
#define PLUME_HAS_SSE2 0
#define PLUME_HAS_AVX2 0
#define PLUME_HAS_AVX512 0
#else
#if defined(PLUME_SIMD_SSE2)
#define PLUME_SIMD_NAME "sse2"
#elif defined(PLUME_SIMD_AVX2)
#define PLUME_SIMD_NAME "avx2"
#elif defined(PLUME_SIMD_AVX512)
#define PLUME_SIMD_NAME "avx512"
#else
#define PLUME_SIMD_NAME "native"
#endif
#if defined(__SSE2__)
#define PLUME_HAS_SSE2 1
#else
#define PLUME_HAS_SSE2 0
#endif
#if defined(__AVX2__)
#define PLUME_HAS_AVX2 1
#else
#define PLUME_HAS_AVX2 0
#endif
#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512DQ__) && defined(__AVX512CD__)
#define PLUME_HAS_AVX512 1
#else
#define PLUME_HAS_AVX512 0
#endif
#endif

#if defined(PLUME_SIMD_AVX2) && !PLUME_HAS_AVX2
#error "PLUME_SIMD=avx2 but the compiler flags do not enable AVX2"
#endif
#if defined(PLUME_SIMD_AVX512) && !PLUME_HAS_AVX512
#error "PLUME_SIMD=avx512 but the compiler flags do not enable AVX-512 F/CD/DQ/BW"
#endif

// Generic code combines masks with & | ^ (branch-free, both sides evaluated). For scalar
// `bool` masks clang 14 warns about that (-Wbitwise-instead-of-logical); plume's headers
// wrap their code in PLUME_MASK_CODE_BEGIN / _END, which silences it for plume's own code
// only (clang's diagnostic pragmas follow source locations, also for templates).
#if defined(__clang__)
#define PLUME_MASK_CODE_BEGIN                                                                      \
  _Pragma("clang diagnostic push")                                                                 \
      _Pragma("clang diagnostic ignored \"-Wbitwise-instead-of-logical\"")
#define PLUME_MASK_CODE_END _Pragma("clang diagnostic pop")
#else
#define PLUME_MASK_CODE_BEGIN
#define PLUME_MASK_CODE_END
#endif

// PLUME_INLINE: small functions that must vanish into their caller (a wide kernel that calls
// out of line passes every batch through memory); PLUME_INLINE_LAMBDA the same for a lambda
// (after its parameter list) that a kernel calls from more than one place. PLUME_FLATTEN: on the
// few large entry points (GJK queries) whose size makes g++ stop inlining even trivial methods
// inside them; it inlines every call in their body. Both only when optimising: at -O0 (debug and
// sanitizer builds) forcing them costs compile time and gains nothing (the sanitizer build's
// collision ray-cast tests compiled in 46 s forced, 13 s not), and inlining changes no
// result (-ffp-contract=off: the golden hashes are the same either way).
#if defined(__GNUC__) && defined(__OPTIMIZE__)
#define PLUME_INLINE inline __attribute__((always_inline))
#define PLUME_INLINE_LAMBDA __attribute__((always_inline))
#define PLUME_NOINLINE __attribute__((noinline))
#define PLUME_FLATTEN __attribute__((flatten))
#else
#define PLUME_INLINE inline
#define PLUME_INLINE_LAMBDA
#define PLUME_NOINLINE
#define PLUME_FLATTEN
#endif

namespace plume {
/// The instruction-set family this build was configured for.
inline constexpr const char* simd_name = PLUME_SIMD_NAME;
inline constexpr bool deterministic = PLUME_DETERMINISTIC != 0;
inline constexpr bool fused_mul_add = PLUME_FMA != 0;
} // namespace plume
