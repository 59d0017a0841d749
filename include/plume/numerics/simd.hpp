// plume/numerics/simd.hpp - the one place plume includes xsimd, and what plume adds to it.
//
// Nothing above the numerics module includes <xsimd/xsimd.hpp> directly. This header
//  - includes xsimd in every build but the scalar one (which instantiates no batch type);
//  - names the architectures behind plume's widths: `arch_128` (SSE2 or the best SSE4
//    the flags enable), `arch_256` (AVX2) and `arch_512` (AVX-512 F/CD/DQ/BW);
//  - adds the comparisons with a scalar on the left that xsimd 8.1 lacks
//    (`1.f < batch` gives a batch_bool, like `batch > 1.f`).
#pragma once

#include <plume/config.hpp>

#include <cstddef>
#include <cstdint>
#include <type_traits>

#if !defined(PLUME_SIMD_SCALAR)
#define PLUME_HAS_BATCHES 1
#include <xsimd/xsimd.hpp>
#else
#define PLUME_HAS_BATCHES 0
#endif

#if PLUME_HAS_BATCHES
namespace plume {
#if XSIMD_WITH_SSE4_2
using arch_128 = xsimd::sse4_2;
#elif XSIMD_WITH_SSE4_1
using arch_128 = xsimd::sse4_1;
#else
using arch_128 = xsimd::sse2;
#endif
#if PLUME_HAS_AVX2
using arch_256 = xsimd::avx2;
#endif
#if PLUME_HAS_AVX512
using arch_512 = xsimd::avx512bw;
#endif
} // namespace plume

// xsimd 8.1 defines comparisons as members, so `batch < 1.f` works but `1.f < batch` does
// not. These free operators fill that gap. The `batch == scalar` forms are spelled out too:
// without them C++20 would consider the reversed `scalar == batch` candidate, whose
// batch_bool result is not allowed for a rewritten comparison.
namespace xsimd {
#define PLUME_SCALAR_LEFT_COMPARISON(op)                                                           \
  template <class T, class A>                                                                      \
  inline batch_bool<T, A> operator op(std::type_identity_t<T> s, batch<T, A> const& b) noexcept {  \
    return batch<T, A>(s) op b;                                                                    \
  }
PLUME_SCALAR_LEFT_COMPARISON(<)
PLUME_SCALAR_LEFT_COMPARISON(<=)
PLUME_SCALAR_LEFT_COMPARISON(>)
PLUME_SCALAR_LEFT_COMPARISON(>=)
PLUME_SCALAR_LEFT_COMPARISON(==)
PLUME_SCALAR_LEFT_COMPARISON(!=)
#undef PLUME_SCALAR_LEFT_COMPARISON
template <class T, class A>
inline batch_bool<T, A> operator==(batch<T, A> const& b, std::type_identity_t<T> s) noexcept {
  return b.operator==(batch<T, A>(s));
}
template <class T, class A>
inline batch_bool<T, A> operator!=(batch<T, A> const& b, std::type_identity_t<T> s) noexcept {
  return b.operator!=(batch<T, A>(s));
}
} // namespace xsimd
#endif
