// plume/numerics/traits.hpp - what an element type is, and how to reach its lanes.
//
// An element type T is a scalar (float, double, int32_t, uint32_t, int64_t, uint64_t, bool)
// or an xsimd batch / batch_bool of those. For every element type:
//   lanes_v<T>      number of lanes (1 for scalars)
//   scalar_t<T>     the type of one lane (bool for masks)
//   mask_t<T>       what a comparison of two T gives (bool for scalars, batch_bool for batches)
//   rebind_t<T, U>  the element type with the same lanes holding U (U itself for scalars)
//   bits_t<T>       the unsigned integer type of the same lane width (float -> uint32_t)
//   is_batch_v<T>   true for batches and batch_bools
//   splat<T>(s)     every lane set to s
//   lane(x, i)      lane i of x as a scalar; with_lane(x, i, s) a copy of x with lane i = s
// Lane indices out of range are a precondition violation (checked by assert in debug builds).
#pragma once

#include <plume/numerics/simd.hpp>

#include <array>
#include <bit>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace plume {

template <class T>
struct element_traits {
  static constexpr bool is_element = false;
};

namespace detail {
template <class S>
struct scalar_element_traits {
  static constexpr bool is_element = true;
  static constexpr bool is_batch = false;
  static constexpr bool is_mask = std::is_same_v<S, bool>;
  static constexpr std::size_t lanes = 1;
  using scalar = S;
  using mask = bool;
  template <class U>
  using rebind = U;
};
} // namespace detail

template <>
struct element_traits<float> : detail::scalar_element_traits<float> {};
template <>
struct element_traits<double> : detail::scalar_element_traits<double> {};
template <>
struct element_traits<std::int32_t> : detail::scalar_element_traits<std::int32_t> {};
template <>
struct element_traits<std::uint32_t> : detail::scalar_element_traits<std::uint32_t> {};
template <>
struct element_traits<std::int64_t> : detail::scalar_element_traits<std::int64_t> {};
template <>
struct element_traits<std::uint64_t> : detail::scalar_element_traits<std::uint64_t> {};
template <>
struct element_traits<bool> : detail::scalar_element_traits<bool> {};

#if PLUME_HAS_BATCHES
template <class E, class A>
struct element_traits<xsimd::batch<E, A>> {
  static constexpr bool is_element = element_traits<E>::is_element && !std::is_same_v<E, bool>;
  static constexpr bool is_batch = true;
  static constexpr bool is_mask = false;
  static constexpr std::size_t lanes = xsimd::batch<E, A>::size;
  using scalar = E;
  using mask = xsimd::batch_bool<E, A>;
  template <class U>
  using rebind = xsimd::batch<U, A>;
};
template <class E, class A>
struct element_traits<xsimd::batch_bool<E, A>> {
  static constexpr bool is_element = element_traits<E>::is_element;
  static constexpr bool is_batch = true;
  static constexpr bool is_mask = true;
  static constexpr std::size_t lanes = xsimd::batch_bool<E, A>::size;
  using scalar = bool;
  using mask = xsimd::batch_bool<E, A>;
  template <class U>
  using rebind = xsimd::batch_bool<U, A>;
};
#endif

template <class T>
inline constexpr bool is_element_v = element_traits<std::remove_cvref_t<T>>::is_element;
template <class T>
inline constexpr std::size_t lanes_v = element_traits<T>::lanes;
template <class T>
inline constexpr bool is_batch_v = element_traits<T>::is_batch;
template <class T>
inline constexpr bool is_mask_v = element_traits<T>::is_mask;
template <class T>
using scalar_t = typename element_traits<T>::scalar;
template <class T>
using mask_t = typename element_traits<T>::mask;
template <class T, class U>
using rebind_t = typename element_traits<T>::template rebind<U>;

namespace detail {
template <std::size_t N>
struct uint_of_size;
template <>
struct uint_of_size<4> {
  using type = std::uint32_t;
};
template <>
struct uint_of_size<8> {
  using type = std::uint64_t;
};
template <std::size_t N>
struct int_of_size;
template <>
struct int_of_size<4> {
  using type = std::int32_t;
};
template <>
struct int_of_size<8> {
  using type = std::int64_t;
};
} // namespace detail

/// Unsigned integer element type with the lanes and lane width of T (float -> uint32_t).
template <class T>
using bits_t = rebind_t<T, typename detail::uint_of_size<sizeof(scalar_t<T>)>::type>;
/// Signed integer element type with the lanes and lane width of T (f64x4 -> i64x4).
template <class T>
using int_t = rebind_t<T, typename detail::int_of_size<sizeof(scalar_t<T>)>::type>;

/// Every lane set to s (converted to the lane type).
template <class T, class S>
PLUME_INLINE constexpr T splat(S s) noexcept {
  if constexpr (is_batch_v<T>) {
    return T(static_cast<scalar_t<T>>(s));
  } else {
    return static_cast<T>(s);
  }
}

/// Lane i of x.
template <class T>
PLUME_INLINE scalar_t<T> lane(T const& x, std::size_t i) noexcept {
  assert(i < lanes_v<T>);
  if constexpr (is_batch_v<T>) {
    return x.get(i);
  } else {
    (void)i;
    return x;
  }
}

/// A copy of x whose lane i holds s.
template <class T>
PLUME_INLINE T with_lane(T const& x, std::size_t i, scalar_t<T> s) noexcept {
  assert(i < lanes_v<T>);
  if constexpr (is_batch_v<T>) {
    alignas(64) std::array<scalar_t<T>, lanes_v<T>> a;
    x.store_unaligned(a.data());
    a[i] = s;
    return T::load_unaligned(a.data());
  } else {
    (void)i;
    (void)x;
    return s;
  }
}

/// All lanes of x as an array (lane 0 first).
template <class T>
PLUME_INLINE std::array<scalar_t<T>, lanes_v<T>> to_array(T const& x) noexcept {
  std::array<scalar_t<T>, lanes_v<T>> a;
  if constexpr (is_batch_v<T>) {
    x.store_unaligned(a.data());
  } else {
    a[0] = x;
  }
  return a;
}

/// The element type whose lanes are a[0], a[1], ...
template <class T>
PLUME_INLINE T from_array(std::array<scalar_t<T>, lanes_v<T>> const& a) noexcept {
  if constexpr (is_batch_v<T>) {
    return T::load_unaligned(a.data());
  } else {
    return a[0];
  }
}

} // namespace plume
