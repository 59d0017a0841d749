// plume/numerics/simd.hpp - the one place plume includes xsimd, and what plume adds to it.
//
// Nothing above the numerics module includes <xsimd/xsimd.hpp> directly. This header
//  - includes xsimd in every build (the scalar build instantiates no batch type, but the
//    generic code names xsimd in branches it discards);
//  - names the architectures behind plume's widths: `arch_128` (SSE2 or the best SSE4
//    the flags enable), `arch_256` (AVX2) and `arch_512` (AVX-512 F/CD/DQ/BW);
//  - adds the comparisons with a scalar on the left that xsimd 8.1 lacks
//    (`1.f < batch` gives a batch_bool, like `batch > 1.f`);
//  - repairs xsimd 8.1's AVX-512 mask xor, which computes `a | b` (its kernel
//    `bitwise_xor(batch_bool, batch_bool, requires_arch<avx512f>)` ors the k-registers).
//    The batch_bool member operator^ looks its kernel up where it is defined, so the
//    exact-arch overload below is declared before xsimd is included and wins there as the
//    better match (avx512bw const& binds without a derived-to-base conversion);
//  - repairs xsimd 8.1's AVX and AVX-512 float `a != b`, which uses the ordered predicate
//    (_CMP_NEQ_OQ) and so says NaN != NaN is false, unlike C++ and SSE's cmpneq. The same
//    exact-arch overloads give the IEEE answer (_CMP_NEQ_UQ: true when unordered);
//  - speeds up xsimd 8.1's AVX2 mask equality, and with it `!mask` (which xsimd computes as
//    `mask == false`): AVX2 compares the 256-bit integers in one instruction where xsimd's
//    AVX kernel uses two SSE compares and a lane insert (docs/performance.md, "masks");
//  - repairs xsimd 8.1's AVX-512 float negation, computed as `0 - x` (so -(+0) = +0); the
//    overload flips the sign bit, as the SSE and AVX kernels do;
//  - widens a float batch into two double batches of the same architecture (lanes 0..W/2-1
//    and W/2..W-1, exactly) and narrows two back (each lane rounded once, to nearest), which
//    xsimd 8.1 lacks: `widen_lo`, `widen_hi`, `narrow` (for float pow's double core).
#pragma once

#include <plume/config.hpp>

#include <cstddef>
#include <cstdint>
#include <type_traits>

#if defined(PLUME_SIMD_SCALAR)
#define PLUME_HAS_BATCHES 0
#else
#define PLUME_HAS_BATCHES 1
#endif

namespace xsimd {
struct avx2;
struct avx512bw;
template <class T, class A>
class batch;
template <class T, class A>
class batch_bool;
namespace kernel {
#if PLUME_HAS_AVX512
template <class A, class T>
batch_bool<T, A> bitwise_xor(batch_bool<T, A> const& self, batch_bool<T, A> const& other,
                             avx512bw const&) noexcept;
template <class A>
batch_bool<float, A> neq(batch<float, A> const& a, batch<float, A> const& b,
                         avx512bw const&) noexcept;
template <class A>
batch_bool<double, A> neq(batch<double, A> const& a, batch<double, A> const& b,
                          avx512bw const&) noexcept;
template <class A>
batch<float, A> neg(batch<float, A> const& a, avx512bw const&) noexcept;
template <class A>
batch<double, A> neg(batch<double, A> const& a, avx512bw const&) noexcept;
#endif
#if PLUME_HAS_AVX2
template <class A>
batch_bool<float, A> neq(batch<float, A> const& a, batch<float, A> const& b, avx2 const&) noexcept;
template <class A>
batch_bool<double, A> neq(batch<double, A> const& a, batch<double, A> const& b,
                          avx2 const&) noexcept;
template <class A>
batch_bool<float, A> eq(batch_bool<float, A> const& a, batch_bool<float, A> const& b,
                        avx2 const&) noexcept;
template <class A>
batch_bool<double, A> eq(batch_bool<double, A> const& a, batch_bool<double, A> const& b,
                         avx2 const&) noexcept;
#endif
} // namespace kernel
} // namespace xsimd
#include <xsimd/xsimd.hpp>
static_assert(XSIMD_VERSION_MAJOR == 8,
              "plume's xsimd repairs (simd.hpp) were checked against xsimd 8.1: re-check them");
#if PLUME_HAS_AVX512
template <class A, class T>
xsimd::batch_bool<T, A> xsimd::kernel::bitwise_xor(batch_bool<T, A> const& self,
                                                   batch_bool<T, A> const& other,
                                                   avx512bw const&) noexcept {
  using register_type = typename batch_bool<T, A>::register_type;
  return register_type(self.data ^ other.data);
}
template <class A>
xsimd::batch_bool<float, A> xsimd::kernel::neq(batch<float, A> const& a, batch<float, A> const& b,
                                               avx512bw const&) noexcept {
  return _mm512_cmp_ps_mask(a, b, _CMP_NEQ_UQ);
}
template <class A>
xsimd::batch_bool<double, A>
xsimd::kernel::neq(batch<double, A> const& a, batch<double, A> const& b, avx512bw const&) noexcept {
  return _mm512_cmp_pd_mask(a, b, _CMP_NEQ_UQ);
}
template <class A>
xsimd::batch<float, A> xsimd::kernel::neg(batch<float, A> const& a, avx512bw const&) noexcept {
  return _mm512_castsi512_ps(
      _mm512_xor_si512(_mm512_castps_si512(a), _mm512_set1_epi32(static_cast<int>(0x80000000u))));
}
template <class A>
xsimd::batch<double, A> xsimd::kernel::neg(batch<double, A> const& a, avx512bw const&) noexcept {
  return _mm512_castsi512_pd(_mm512_xor_si512(
      _mm512_castpd_si512(a), _mm512_set1_epi64(static_cast<long long>(0x8000000000000000ull))));
}
#endif
#if PLUME_HAS_AVX2
template <class A>
xsimd::batch_bool<float, A> xsimd::kernel::neq(batch<float, A> const& a, batch<float, A> const& b,
                                               avx2 const&) noexcept {
  return _mm256_cmp_ps(a, b, _CMP_NEQ_UQ);
}
template <class A>
xsimd::batch_bool<double, A> xsimd::kernel::neq(batch<double, A> const& a,
                                                batch<double, A> const& b, avx2 const&) noexcept {
  return _mm256_cmp_pd(a, b, _CMP_NEQ_UQ);
}
template <class A>
xsimd::batch_bool<float, A> xsimd::kernel::eq(batch_bool<float, A> const& a,
                                              batch_bool<float, A> const& b, avx2 const&) noexcept {
  return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_castps_si256(a), _mm256_castps_si256(b)));
}
template <class A>
xsimd::batch_bool<double, A> xsimd::kernel::eq(batch_bool<double, A> const& a,
                                               batch_bool<double, A> const& b,
                                               avx2 const&) noexcept {
  return _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_castpd_si256(a), _mm256_castpd_si256(b)));
}
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

#if PLUME_HAS_BATCHES
namespace plume::detail {
/// Lanes 0..W/2-1 of a float batch as doubles (exact).
template <class A>
inline xsimd::batch<double, A> widen_lo(xsimd::batch<float, A> const& v) noexcept {
  if constexpr (sizeof(v.data) == 16) return _mm_cvtps_pd(v);
#if PLUME_HAS_AVX2
  else if constexpr (sizeof(v.data) == 32)
    return _mm256_cvtps_pd(_mm256_castps256_ps128(v));
#endif
#if PLUME_HAS_AVX512
  else
    return _mm512_cvtps_pd(_mm512_castps512_ps256(v));
#endif
}
/// Lanes W/2..W-1 of a float batch as doubles (exact).
template <class A>
inline xsimd::batch<double, A> widen_hi(xsimd::batch<float, A> const& v) noexcept {
  if constexpr (sizeof(v.data) == 16) return _mm_cvtps_pd(_mm_movehl_ps(v, v));
#if PLUME_HAS_AVX2
  else if constexpr (sizeof(v.data) == 32)
    return _mm256_cvtps_pd(_mm256_extractf128_ps(v, 1));
#endif
#if PLUME_HAS_AVX512
  else
    return _mm512_cvtps_pd(_mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(v), 1)));
#endif
}
/// The float batch whose lanes are lo's then hi's, each rounded to nearest (overflow gives
/// inf, tiny values round once to a subnormal or zero).
template <class A>
inline xsimd::batch<float, A> narrow(xsimd::batch<double, A> const& lo,
                                     xsimd::batch<double, A> const& hi) noexcept {
  if constexpr (sizeof(lo.data) == 16) return _mm_movelh_ps(_mm_cvtpd_ps(lo), _mm_cvtpd_ps(hi));
#if PLUME_HAS_AVX2
  else if constexpr (sizeof(lo.data) == 32)
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm256_cvtpd_ps(lo)), _mm256_cvtpd_ps(hi),
                                1);
#endif
#if PLUME_HAS_AVX512
  else
    return _mm512_castpd_ps(
        _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_castps_pd(_mm512_cvtpd_ps(lo))),
                           _mm256_castps_pd(_mm512_cvtpd_ps(hi)), 1));
#endif
}
} // namespace plume::detail
#endif
