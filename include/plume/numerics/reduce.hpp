// plume/numerics/reduce.hpp - horizontal reductions in a fixed order.
//
//   reduce_add(x)   sum of the lanes: the upper half of the lanes is added onto the lower
//                   half, lane by lane, until one lane remains. For 8 lanes:
//                   ((x0+x4) + (x2+x6)) + ((x1+x5) + (x3+x7)). Same order in every build.
//   reduce_min(x), reduce_max(x)   with min/max's NaN rule (any NaN lane gives NaN); the
//                   order does not change the result.
// For a scalar each returns x itself. Batches reduce in registers: one shift or shuffle and
// one vector op per halving (4 steps for 16 lanes).
#pragma once

#include <plume/numerics/functions.hpp>

#include <bit>
#include <cstddef>
#include <utility>

PLUME_MASK_CODE_BEGIN

namespace plume {
namespace detail {
#if PLUME_HAS_BATCHES
/// The register of x with its bytes moved down by Bytes (lane i + Bytes / lane size lands in
/// lane i; what fills the top is unspecified): one shift or one 128-bit block shuffle.
/// Defined for 16-, 32- and 64-byte registers, Bytes a power of two below the size.
template <std::size_t Bytes, class R>
PLUME_INLINE R bytes_down(R r) noexcept {
  if constexpr (sizeof(R) == 16) {
    return std::bit_cast<R>(_mm_srli_si128(std::bit_cast<__m128i>(r), Bytes));
  }
#if PLUME_HAS_AVX2
  else if constexpr (sizeof(R) == 32) {
    __m256i const i = std::bit_cast<__m256i>(r);
    if constexpr (Bytes == 16)
      return std::bit_cast<R>(_mm256_permute2x128_si256(i, i, 0x01)); // high block down
    else
      return std::bit_cast<R>(_mm256_srli_si256(i, Bytes)); // within each block
  }
#endif
#if PLUME_HAS_AVX512
  else if constexpr (sizeof(R) == 64) {
    __m512i const i = std::bit_cast<__m512i>(r);
    return std::bit_cast<R>(_mm512_alignr_epi32(i, i, Bytes / 4)); // a rotation by dwords
  }
#endif
}
#endif

/// The reduction tree of the header: lane i + n is combined onto lane i for n = lanes / 2,
/// lanes / 4, ..., 1, and lane 0 is the result. Each level is one shift or shuffle
/// (bytes_down) and op on whole batches, whose lanes are op's scalar results, so the answer
/// is the scalar tree's bit for bit (where it is a NaN, which NaN may differ: min and max
/// give a NaN of either sign). Every batch plume has is 16, 32 or 64 bytes.
template <class T, class Op>
PLUME_INLINE scalar_t<T> reduce_halves(T const& x, Op op) noexcept {
  if constexpr (!is_batch_v<T>) {
    (void)op;
    return x;
  } else {
#if PLUME_HAS_BATCHES
    static_assert(sizeof(T) == 16 || sizeof(T) == 32 || sizeof(T) == 64);
    using R = typename T::register_type;
    constexpr std::size_t lane_bytes = sizeof(scalar_t<T>);
    T v = x;
    [&]<std::size_t... K>(std::index_sequence<K...>) {
      ((v = op(v, T(bytes_down<(lanes_v<T> >> (K + 1)) * lane_bytes>(R(v))))), ...);
    }
    (std::make_index_sequence<std::bit_width(lanes_v<T>) - 1>{});
    return plume::lane(v, 0);
#endif
  }
}
} // namespace detail

template <Num T>
PLUME_INLINE scalar_t<T> reduce_add(T const& x) noexcept {
  return detail::reduce_halves(x, [](T const& a, T const& b) { return T(a + b); });
}

template <Num T>
PLUME_INLINE scalar_t<T> reduce_min(T const& x) noexcept {
  return detail::reduce_halves(x, [](T const& a, T const& b) { return plume::min(a, b); });
}

template <Num T>
PLUME_INLINE scalar_t<T> reduce_max(T const& x) noexcept {
  return detail::reduce_halves(x, [](T const& a, T const& b) { return plume::max(a, b); });
}

} // namespace plume

PLUME_MASK_CODE_END
