// plume/numerics/approx.hpp - fast approximate reciprocal and reciprocal square root.
//
//   recip_approx(x) ~ 1/x,  rsqrt_approx(x) ~ 1/sqrt(x)    relative error <= 1.5 * 2^-12
//
// These use the CPU's estimate instructions (rcpps/rsqrtps, or rcp14/rsqrt14 on AVX-512),
// whose bits differ between instruction sets and CPU vendors: they are OUTSIDE the
// determinism contract (not lane-exact across widths, not build-exact). Use them only where
// an estimate is enough, or refine with a Newton step. double lanes and scalars without an
// estimate instruction are computed exactly (1/x, 1/sqrt(x)), which meets the same bound.
// x = 0 gives +-inf, x = +inf gives 0; rsqrt_approx of a negative number gives NaN.
#pragma once

#include <plume/numerics/functions.hpp>

#include <immintrin.h>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Float T>
PLUME_INLINE T recip_approx(T x) noexcept {
  using S = scalar_t<T>;
  if constexpr (std::is_same_v<S, float>) {
    if constexpr (!is_batch_v<T>) {
      return _mm_cvtss_f32(_mm_rcp_ss(_mm_set_ss(x)));
    } else if constexpr (lanes_v<T> == 4) {
      return T(_mm_rcp_ps(x));
#if PLUME_HAS_AVX2
    } else if constexpr (lanes_v<T> == 8) {
      return T(_mm256_rcp_ps(x));
#endif
#if PLUME_HAS_AVX512
    } else if constexpr (lanes_v<T> == 16) {
      return T(_mm512_rcp14_ps(x));
#endif
    }
  }
  return plume::recip(x);
}

template <Float T>
PLUME_INLINE T rsqrt_approx(T x) noexcept {
  using S = scalar_t<T>;
  if constexpr (std::is_same_v<S, float>) {
    // xsimd 8.1's avx512 rsqrt uses the AVX-512ER instruction (Xeon Phi only): not used here.
    if constexpr (!is_batch_v<T>) {
      return _mm_cvtss_f32(_mm_rsqrt_ss(_mm_set_ss(x)));
    } else if constexpr (lanes_v<T> == 4) {
      return T(_mm_rsqrt_ps(x));
#if PLUME_HAS_AVX2
    } else if constexpr (lanes_v<T> == 8) {
      return T(_mm256_rsqrt_ps(x));
#endif
#if PLUME_HAS_AVX512
    } else if constexpr (lanes_v<T> == 16) {
      return T(_mm512_rsqrt14_ps(x));
#endif
    }
  }
  return plume::recip(plume::sqrt(x));
}

} // namespace plume

PLUME_MASK_CODE_END
