// plume/numerics/mask.hpp - masks and per-lane selection.
//
// A mask is `bool` for scalars and xsimd::batch_bool for batches; comparisons of element
// types give masks (`a < b`, also `1.f < batch`). Masks combine with & | ^ and !. (For
// scalars `m1 & m2` is an int; every function here takes it as a bool.)
//
//   select(m, a, b)   per lane: m ? a : b    (a or b may be a scalar_t<T> for a batch T)
//   keep_if(m, a)     per lane: m ? a : 0    (select(m, a, 0): one AND where masks are
//                                             float vectors, SSE/AVX)
//   and_not(m, n)     per lane: m && !n      (one ANDN; `m & !n` costs a compare more on
//                                             SSE/AVX)
//   any(m), all(m), none(m)                   horizontal tests
//   bitmask(m)        lane i of m in bit i of a uint64_t
//   mask_cast<T>(m)   a mask of another element type with the same lanes and lane width
//                     (an int32 comparison used to select floats)
//   no_lanes<T>(), all_lanes<T>()   the mask of T (an element or a mask type) with every
//                     lane false / true: the start of a mask that lanes join one by one
#pragma once

#include <plume/numerics/traits.hpp>

#include <bit>
#include <cstdint>
#include <cstring>
#include <type_traits>

PLUME_MASK_CODE_BEGIN

namespace plume {

/// The mask of T (an element type or a mask type) with every lane false.
template <class T>
PLUME_INLINE constexpr mask_t<T> no_lanes() noexcept {
  return mask_t<T>(false);
}
/// The mask of T (an element type or a mask type) with every lane true.
template <class T>
PLUME_INLINE constexpr mask_t<T> all_lanes() noexcept {
  return mask_t<T>(true);
}

PLUME_INLINE constexpr bool any(bool m) noexcept { return m; }
PLUME_INLINE constexpr bool all(bool m) noexcept { return m; }
PLUME_INLINE constexpr bool none(bool m) noexcept { return !m; }
PLUME_INLINE constexpr std::uint64_t bitmask(bool m) noexcept { return m ? 1u : 0u; }

template <class T>
requires(is_element_v<T> && !is_batch_v<T>) PLUME_INLINE constexpr T
    select(bool m, T a, T b) noexcept {
  return m ? a : b;
}

template <class T>
requires(is_element_v<T> && !is_batch_v<T>) PLUME_INLINE constexpr T keep_if(bool m, T a) noexcept {
  return m ? a : T(0);
}

PLUME_INLINE constexpr bool and_not(bool m, bool n) noexcept { return m && !n; }

template <class T>
requires(is_element_v<T> && !is_batch_v<T>) PLUME_INLINE constexpr bool mask_cast(bool m) noexcept {
  return m;
}

#if PLUME_HAS_BATCHES
template <class E, class A>
PLUME_INLINE bool any(xsimd::batch_bool<E, A> const& m) noexcept {
  return xsimd::any(m);
}
template <class E, class A>
PLUME_INLINE bool all(xsimd::batch_bool<E, A> const& m) noexcept {
  return xsimd::all(m);
}
template <class E, class A>
PLUME_INLINE bool none(xsimd::batch_bool<E, A> const& m) noexcept {
  return !xsimd::any(m);
}
/// Lane i's flag in bit i: one MOVMSKPS/MOVMSKPD for SSE and AVX masks, the mask register
/// itself on AVX-512 (a loop over stored bools took 45 instructions for 8 lanes).
template <class E, class A>
PLUME_INLINE std::uint64_t bitmask(xsimd::batch_bool<E, A> const& m) noexcept {
  using B = xsimd::batch_bool<E, A>;
  constexpr std::size_t n = B::size;
  if constexpr (sizeof(B) * 8 == n || (sizeof(B) == 1 && n < 8)) { // a bit-mask register
    if constexpr (sizeof(B) == 1) {
      std::uint8_t r;
      std::memcpy(&r, &m, 1);
      return r & ((1u << n) - 1u);
    } else if constexpr (sizeof(B) == 2) {
      std::uint16_t r;
      std::memcpy(&r, &m, 2);
      return r;
    } else {
      std::uint32_t r;
      std::memcpy(&r, &m, sizeof(r));
      return r;
    }
  }
#if defined(__SSE2__)
  else if constexpr (sizeof(B) == 16 && (sizeof(E) == 4 || sizeof(E) == 8)) {
    __m128d r;
    std::memcpy(&r, &m, 16);
    if constexpr (sizeof(E) == 4)
      return std::uint64_t(unsigned(_mm_movemask_ps(_mm_castpd_ps(r))));
    else
      return std::uint64_t(unsigned(_mm_movemask_pd(r)));
  }
#endif
#if defined(__AVX__)
  else if constexpr (sizeof(B) == 32 && (sizeof(E) == 4 || sizeof(E) == 8)) {
    __m256d r;
    std::memcpy(&r, &m, 32);
    if constexpr (sizeof(E) == 4)
      return std::uint64_t(unsigned(_mm256_movemask_ps(_mm256_castpd_ps(r))));
    else
      return std::uint64_t(unsigned(_mm256_movemask_pd(r)));
  }
#endif
  else {
    bool b[n];
    m.store_unaligned(b);
    std::uint64_t r = 0;
    for (std::size_t i = 0; i < n; ++i)
      r |= std::uint64_t(b[i]) << i;
    return r;
  }
}

namespace detail {
#if defined(__GNUC__) && !defined(__clang__) && defined(__AVX__)
/// The blend as one VBLENDVPS/VBLENDVPD that the compiler cannot rewrite into a sign test
/// plus blend (g++ 12 does, adding a compare per mask: docs/performance.md, "select").
/// For a mask that is a full compare result the sign test is redundant. VEX form: registers
/// xmm0-15 ("x").
template <class E, class R>
PLUME_INLINE R blendv_vex(R m, R a, R b) noexcept {
  R r;
  if constexpr (sizeof(E) == 4)
    asm("vblendvps {%3, %2, %1, %0|%0, %1, %2, %3}" : "=x"(r) : "x"(b), "xm"(a), "x"(m));
  else
    asm("vblendvpd {%3, %2, %1, %0|%0, %1, %2, %3}" : "=x"(r) : "x"(b), "xm"(a), "x"(m));
  return r;
}
/// 128- and 256-bit float batches, whose masks are vectors of the same register type.
template <class E, class A>
inline constexpr bool vex_blendable_v = std::is_floating_point_v<E> &&
                                        (sizeof(typename xsimd::batch<E, A>::register_type) == 16 ||
                                         sizeof(typename xsimd::batch<E, A>::register_type) ==
                                             32) &&
                                        sizeof(typename xsimd::batch_bool<E, A>::register_type) ==
                                            sizeof(typename xsimd::batch<E, A>::register_type);
#else
template <class E, class A>
inline constexpr bool vex_blendable_v = false;
#endif
} // namespace detail

template <class E, class A>
PLUME_INLINE xsimd::batch<E, A> select(xsimd::batch_bool<E, A> const& m,
                                       xsimd::batch<E, A> const& a,
                                       xsimd::batch<E, A> const& b) noexcept {
#if defined(__GNUC__) && !defined(__clang__) && defined(__AVX__)
  if constexpr (detail::vex_blendable_v<E, A>) {
    using R = typename xsimd::batch<E, A>::register_type;
    return xsimd::batch<E, A>(
        detail::blendv_vex<E, R>(std::bit_cast<R>(m.data), R(a.data), R(b.data)));
  }
#endif
  return xsimd::select(m, a, b);
}
template <class E, class A>
PLUME_INLINE xsimd::batch<E, A> select(xsimd::batch_bool<E, A> const& m,
                                       xsimd::batch<E, A> const& a,
                                       std::type_identity_t<E> b) noexcept {
  return xsimd::select(m, a, xsimd::batch<E, A>(b));
}
template <class E, class A>
PLUME_INLINE xsimd::batch<E, A> select(xsimd::batch_bool<E, A> const& m, std::type_identity_t<E> a,
                                       xsimd::batch<E, A> const& b) noexcept {
  return xsimd::select(m, xsimd::batch<E, A>(a), b);
}
template <class E, class A>
PLUME_INLINE xsimd::batch_bool<E, A> select(xsimd::batch_bool<E, A> const& m,
                                            xsimd::batch_bool<E, A> const& a,
                                            xsimd::batch_bool<E, A> const& b) noexcept {
  return (m & a) | (b & (!m));
}

/// select(m, a, 0): the same bits (+0 where m is false), as an AND of the mask's all-ones
/// lanes where masks are vectors of a's register type (SSE/AVX float and double batches).
template <class E, class A>
PLUME_INLINE xsimd::batch<E, A> keep_if(xsimd::batch_bool<E, A> const& m,
                                        xsimd::batch<E, A> const& a) noexcept {
  using R = typename xsimd::batch<E, A>::register_type;
  using RM = typename xsimd::batch_bool<E, A>::register_type;
  if constexpr (std::is_floating_point_v<E> && sizeof(R) == sizeof(RM))
    return xsimd::batch<E, A>(std::bit_cast<R>(m.data)) & a;
  else
    return xsimd::select(m, a, xsimd::batch<E, A>(E(0)));
}

/// m & !n: one ANDN of the lanes' bits. xsimd 8.1's bitwise_andnot(a, b) computes ~a & b on
/// SSE/AVX masks (vectors) but a & ~b on AVX-512 masks (k-registers); both are used here in
/// the order that gives m & !n.
template <class E, class A>
PLUME_INLINE xsimd::batch_bool<E, A> and_not(xsimd::batch_bool<E, A> const& m,
                                             xsimd::batch_bool<E, A> const& n) noexcept {
  if constexpr (sizeof(m.data) < 16) // a k-register: at most 64 bits
    return xsimd::bitwise_andnot(m, n);
  else
    return xsimd::bitwise_andnot(n, m);
}

/// The mask m (of any element type of T's lanes and lane width) as a mask of T.
template <class T, class E, class A>
requires is_batch_v<T> PLUME_INLINE mask_t<T> mask_cast(xsimd::batch_bool<E, A> const& m)
noexcept {
  static_assert(sizeof(E) == sizeof(scalar_t<T>) && lanes_v<T> == xsimd::batch_bool<E, A>::size,
                "mask_cast needs the same lanes and lane width");
  using R = typename mask_t<T>::register_type;
  using RE = typename xsimd::batch_bool<E, A>::register_type;
  // AVX-512 masks are the same k-register type for every element; SSE/AVX masks are all-ones
  // lanes in an __m128/__m128i/... register of the same size: a reinterpretation either way.
  return mask_t<T>(std::bit_cast<R>(static_cast<RE>(m)));
}
#endif

} // namespace plume

PLUME_MASK_CODE_END
