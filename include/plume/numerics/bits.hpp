// plume/numerics/bits.hpp - IEEE 754 bit access and classification.
//
//   to_bits(x)        the bits of each lane as bits_t<T> (float -> uint32_t)
//   from_bits<T>(b)   the reverse
//   is_nan(x) is_finite(x) is_infinite(x) is_sign_negative(x)    masks (mask_t<T>)
//   select_sign(s, a, b)   per lane: the sign bit of s set ? a : b
// is_sign_negative and select_sign read the sign bit: set for -0.0 and for NaNs with the
// sign bit set.
#pragma once

#include <plume/numerics/concepts.hpp>
#include <plume/numerics/constants.hpp>
#include <plume/numerics/mask.hpp>

#include <bit>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Float T>
PLUME_INLINE bits_t<T> to_bits(T x) noexcept {
  if constexpr (is_batch_v<T>)
    return xsimd::bitwise_cast<bits_t<T>>(x);
  else
    return std::bit_cast<bits_t<T>>(x);
}

template <Float T>
PLUME_INLINE T from_bits(bits_t<T> b) noexcept {
  if constexpr (is_batch_v<T>)
    return xsimd::bitwise_cast<T>(b);
  else
    return std::bit_cast<T>(b);
}

namespace detail {
/// A T whose every lane holds the bit pattern b (for masking with & | ^ on float lanes).
template <Float T>
PLUME_INLINE T bit_pattern(std::uint64_t b) noexcept {
  using U = scalar_t<bits_t<T>>;
  return from_bits<T>(splat<bits_t<T>>(static_cast<U>(b)));
}
template <Float T>
inline constexpr std::uint64_t sign_mask_v = sizeof(scalar_t<T>) == 4 ? 0x80000000ull
                                                                      : 0x8000000000000000ull;

/// Bitwise and/or/xor/andnot of float lanes (scalars go through their bits).
template <Float T>
PLUME_INLINE T bit_and(T a, T b) noexcept {
  if constexpr (is_batch_v<T>)
    return a & b;
  else
    return from_bits<T>(plume::to_bits(a) & plume::to_bits(b));
}
template <Float T>
PLUME_INLINE T bit_or(T a, T b) noexcept {
  if constexpr (is_batch_v<T>)
    return a | b;
  else
    return from_bits<T>(plume::to_bits(a) | plume::to_bits(b));
}
template <Float T>
PLUME_INLINE T bit_xor(T a, T b) noexcept {
  if constexpr (is_batch_v<T>)
    return a ^ b;
  else
    return from_bits<T>(plume::to_bits(a) ^ plume::to_bits(b));
}
/// a & ~b
template <Float T>
PLUME_INLINE T bit_andnot(T a, T b) noexcept {
  if constexpr (is_batch_v<T>)
    return a & ~b; // not xsimd::bitwise_andnot: in xsimd 8.1 it computes ~a & b
  else
    return from_bits<T>(plume::to_bits(a) & ~plume::to_bits(b));
}
} // namespace detail

template <Float T>
PLUME_INLINE mask_t<T> is_nan(T x) noexcept {
  return x != x;
}

template <Float T>
PLUME_INLINE mask_t<T> is_infinite(T x) noexcept {
  return detail::bit_andnot(x, detail::bit_pattern<T>(detail::sign_mask_v<T>)) == infinity<T>();
}

template <Float T>
PLUME_INLINE mask_t<T> is_finite(T x) noexcept {
  return detail::bit_andnot(x, detail::bit_pattern<T>(detail::sign_mask_v<T>)) < infinity<T>();
}

template <Float T>
PLUME_INLINE mask_t<T> is_sign_negative(T x) noexcept {
  // The sign bit, moved into a comparison: bits as signed integers are negative.
  if constexpr (is_batch_v<T>) {
    auto const s = xsimd::bitwise_cast<int_t<T>>(x) < int_t<T>(0);
    return mask_cast<T>(s);
  } else {
    return (plume::to_bits(x) >> (8 * sizeof(T) - 1)) != 0;
  }
}

/// Per lane: a where the sign bit of s is set (s < 0, s = -0, a NaN with the sign bit),
/// b elsewhere. select(is_sign_negative(s), a, b), in one instruction where the blend reads
/// the sign bit itself (BLENDVPS on 128/256-bit float batches) instead of a compare and a
/// blend.
template <Float T>
PLUME_INLINE T select_sign(T s, T a, T b) noexcept {
#if PLUME_HAS_BATCHES && defined(__GNUC__) && !defined(__clang__) && defined(__AVX__)
  if constexpr (is_batch_v<T>) {
    using E = scalar_t<T>;
    using A = typename T::arch_type;
    if constexpr (detail::vex_blendable_v<E, A>) {
      using R = typename T::register_type;
      return T(detail::blendv_vex<E, R>(R(s.data), R(a.data), R(b.data)));
    }
  }
#endif
  return plume::select(is_sign_negative(s), a, b);
}

} // namespace plume

PLUME_MASK_CODE_END
