// plume/numerics/transpose.hpp - rows of memory to lanes and back: the array-of-structures
// <-> structure-of-arrays step of wide kernels that work on records scattered in memory
// (a solver gathering the bodies of W constraints).
//
//   load_transposed<T, K>(rows, cols)    cols[k] lane i = rows[i][k]       (k < K, i < W)
//   store_transposed<T, K>(cols, rows)   rows[i][k] = cols[k] lane i       (rows[i] != null)
//
// T is float or an f32 batch of W = lanes_v<T> lanes; K is a multiple of 4 (8 for W >= 8).
// rows[i] points to K floats aligned to 32 bytes. Pure data movement: results are exact.
// f32x4 uses 4x4 transposes (SSE), f32x8 8x8 (AVX), f32x16 two 8x8 halves joined with
// AVX-512DQ; other types fall back to a plain loop.
#pragma once

#include <plume/config.hpp>
#include <plume/numerics/memory.hpp>
#include <plume/numerics/traits.hpp>
#include <plume/numerics/wide.hpp>

#include <cstddef>
#include <type_traits>

#if PLUME_HAS_BATCHES
#include <immintrin.h>
#endif

namespace plume {

namespace detail {

#if PLUME_HAS_AVX2
/// In-register 8x8 transpose: r[i] lane k -> r[k] lane i.
PLUME_INLINE void transpose8(__m256 (&r)[8]) noexcept {
  __m256 const t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
  __m256 const t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
  __m256 const t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
  __m256 const t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
  __m256 const s0 = _mm256_shuffle_ps(t0, t2, 0x44), s1 = _mm256_shuffle_ps(t0, t2, 0xee);
  __m256 const s2 = _mm256_shuffle_ps(t1, t3, 0x44), s3 = _mm256_shuffle_ps(t1, t3, 0xee);
  __m256 const s4 = _mm256_shuffle_ps(t4, t6, 0x44), s5 = _mm256_shuffle_ps(t4, t6, 0xee);
  __m256 const s6 = _mm256_shuffle_ps(t5, t7, 0x44), s7 = _mm256_shuffle_ps(t5, t7, 0xee);
  r[0] = _mm256_permute2f128_ps(s0, s4, 0x20);
  r[1] = _mm256_permute2f128_ps(s1, s5, 0x20);
  r[2] = _mm256_permute2f128_ps(s2, s6, 0x20);
  r[3] = _mm256_permute2f128_ps(s3, s7, 0x20);
  r[4] = _mm256_permute2f128_ps(s0, s4, 0x31);
  r[5] = _mm256_permute2f128_ps(s1, s5, 0x31);
  r[6] = _mm256_permute2f128_ps(s2, s6, 0x31);
  r[7] = _mm256_permute2f128_ps(s3, s7, 0x31);
}
#endif

} // namespace detail

template <class T, std::size_t K>
PLUME_INLINE void load_transposed(float const* const* rows, T* cols) noexcept {
  static_assert(std::is_same_v<scalar_t<T>, float>, "load_transposed: float lanes");
  static_assert(K % 4 == 0, "load_transposed: K is a multiple of 4");
  constexpr std::size_t W = lanes_v<T>;
  if constexpr (W == 1) {
    for (std::size_t k = 0; k < K; ++k)
      cols[k] = rows[0][k];
#if PLUME_HAS_BATCHES
  } else if constexpr (W == 4) {
    for (std::size_t k = 0; k < K; k += 4) {
      __m128 r0 = _mm_load_ps(rows[0] + k), r1 = _mm_load_ps(rows[1] + k);
      __m128 r2 = _mm_load_ps(rows[2] + k), r3 = _mm_load_ps(rows[3] + k);
      _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
      cols[k] = T(r0), cols[k + 1] = T(r1), cols[k + 2] = T(r2), cols[k + 3] = T(r3);
    }
#endif
#if PLUME_HAS_AVX2
  } else if constexpr (W == 8 && K % 8 == 0) {
    for (std::size_t k = 0; k < K; k += 8) {
      __m256 r[8];
      for (std::size_t i = 0; i < 8; ++i)
        r[i] = _mm256_load_ps(rows[i] + k);
      detail::transpose8(r);
      for (std::size_t i = 0; i < 8; ++i)
        cols[k + i] = T(r[i]);
    }
#endif
#if PLUME_HAS_AVX512
  } else if constexpr (W == 16 && K % 8 == 0) {
    for (std::size_t k = 0; k < K; k += 8) {
      __m256 lo[8], hi[8];
      for (std::size_t i = 0; i < 8; ++i) {
        lo[i] = _mm256_load_ps(rows[i] + k);
        hi[i] = _mm256_load_ps(rows[i + 8] + k);
      }
      detail::transpose8(lo);
      detail::transpose8(hi);
      for (std::size_t i = 0; i < 8; ++i)
        cols[k + i] = T(_mm512_insertf32x8(_mm512_castps256_ps512(lo[i]), hi[i], 1));
    }
#endif
  } else {
    alignas(64) float f[K][W];
    for (std::size_t i = 0; i < W; ++i)
      for (std::size_t k = 0; k < K; ++k)
        f[k][i] = rows[i][k];
    for (std::size_t k = 0; k < K; ++k)
      cols[k] = load_aligned<T>(f[k]);
  }
}

template <class T, std::size_t K>
PLUME_INLINE void store_transposed(T const* cols, float* const* rows) noexcept {
  static_assert(std::is_same_v<scalar_t<T>, float>, "store_transposed: float lanes");
  static_assert(K % 4 == 0, "store_transposed: K is a multiple of 4");
  constexpr std::size_t W = lanes_v<T>;
  if constexpr (W == 1) {
    if (rows[0] != nullptr)
      for (std::size_t k = 0; k < K; ++k)
        rows[0][k] = cols[k];
#if PLUME_HAS_BATCHES
  } else if constexpr (W == 4) {
    for (std::size_t k = 0; k < K; k += 4) {
      __m128 r0 = cols[k], r1 = cols[k + 1], r2 = cols[k + 2], r3 = cols[k + 3];
      _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
      __m128 const r[4] = {r0, r1, r2, r3};
      for (std::size_t i = 0; i < 4; ++i)
        if (rows[i] != nullptr) _mm_store_ps(rows[i] + k, r[i]);
    }
#endif
#if PLUME_HAS_AVX2
  } else if constexpr (W == 8 && K % 8 == 0) {
    for (std::size_t k = 0; k < K; k += 8) {
      __m256 r[8];
      for (std::size_t i = 0; i < 8; ++i)
        r[i] = cols[k + i];
      detail::transpose8(r);
      for (std::size_t i = 0; i < 8; ++i)
        if (rows[i] != nullptr) _mm256_store_ps(rows[i] + k, r[i]);
    }
#endif
#if PLUME_HAS_AVX512
  } else if constexpr (W == 16 && K % 8 == 0) {
    for (std::size_t k = 0; k < K; k += 8) {
      __m256 lo[8], hi[8];
      for (std::size_t i = 0; i < 8; ++i) {
        __m512 const c = cols[k + i];
        lo[i] = _mm512_castps512_ps256(c);
        hi[i] = _mm512_extractf32x8_ps(c, 1);
      }
      detail::transpose8(lo);
      detail::transpose8(hi);
      for (std::size_t i = 0; i < 8; ++i) {
        if (rows[i] != nullptr) _mm256_store_ps(rows[i] + k, lo[i]);
        if (rows[i + 8] != nullptr) _mm256_store_ps(rows[i + 8] + k, hi[i]);
      }
    }
#endif
  } else {
    alignas(64) float f[K][W];
    for (std::size_t k = 0; k < K; ++k)
      store_aligned(f[k], cols[k]);
    for (std::size_t i = 0; i < W; ++i)
      if (rows[i] != nullptr)
        for (std::size_t k = 0; k < K; ++k)
          rows[i][k] = f[k][i];
  }
}

} // namespace plume
