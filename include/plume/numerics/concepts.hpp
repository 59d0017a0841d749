// plume/numerics/concepts.hpp - the numeric concepts generic plume code is written against.
//
// Each refines the one before:
//   Num     + - *, comparisons giving mask_t<T>, min/max/clamp, zero/one/min/max constants
//   Signed  Num with unary minus, abs, signum                    (int32, float, double, ...)
//   Real    Signed with /, sqrt, rounding, mul_add, sin/exp/...  (float, double and batches)
//   Float   Real in IEEE 754 binary format: nan, infinity, epsilon, is_nan/is_finite as
//           masks, bit casts
// Beside them:
//   Int         integer Num (int32_t, uint32_t, int64_t, uint64_t and batches)
//   Mask        bool or batch_bool: & | ^ !, any/all/none, bitmask
//   ScalarReal  a Real that is a plain scalar: its mask is bool, so plain `if` is allowed
//   WideReal    a Real that is a batch: branch with masks and select only
// Generic code that must run wide uses select(mask, a, b) and masks, never `if` on a value.
#pragma once

#include <plume/numerics/traits.hpp>

#include <concepts>
#include <limits>
#include <type_traits>

namespace plume {

template <class T>
concept Element = is_element_v<T>;

template <class T>
concept Mask = Element<T> && is_mask_v<T>;

template <class T>
concept Num =
    Element<T> && !is_mask_v<T> && std::is_arithmetic_v<scalar_t<T>> && requires(T a, T b) {
  { a + b } -> std::convertible_to<T>;
  { a - b } -> std::convertible_to<T>;
  { a* b } -> std::convertible_to<T>;
  { a < b } -> std::convertible_to<mask_t<T>>;
  { a == b } -> std::convertible_to<mask_t<T>>;
};

template <class T>
concept Signed = Num<T> && std::is_signed_v<scalar_t<T>> && requires(T a) {
  { -a } -> std::convertible_to<T>;
};

template <class T>
concept Real = Signed<T> && std::is_floating_point_v<scalar_t<T>> && requires(T a, T b) {
  { a / b } -> std::convertible_to<T>;
};

template <class T>
concept Float = Real<T> && std::numeric_limits<scalar_t<T>>::is_iec559;

template <class T>
concept Int = Num<T> && std::is_integral_v<scalar_t<T>>;

template <class T>
concept ScalarReal = Real<T> && !is_batch_v<T>;

template <class T>
concept WideReal = Real<T> && is_batch_v<T>;

} // namespace plume
