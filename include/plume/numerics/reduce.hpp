// plume/numerics/reduce.hpp - horizontal reductions in a fixed order.
//
//   reduce_add(x)   sum of the lanes: the upper half of the lanes is added onto the lower
//                   half, lane by lane, until one lane remains. For 8 lanes:
//                   ((x0+x4) + (x2+x6)) + ((x1+x5) + (x3+x7)). Same order in every build.
//   reduce_min(x), reduce_max(x)   with min/max's NaN rule (any NaN lane gives NaN); the
//                   order does not change the result.
// For a scalar each returns x itself.
#pragma once

#include <plume/numerics/functions.hpp>

#include <array>

PLUME_MASK_CODE_BEGIN

namespace plume {
namespace detail {
template <class T, class Op>
PLUME_INLINE scalar_t<T> reduce_halves(T const& x, Op op) noexcept {
  if constexpr (!is_batch_v<T>) {
    (void)op;
    return x;
  } else {
    auto a = plume::to_array(x);
    for (std::size_t n = lanes_v<T> / 2; n >= 1; n /= 2)
      for (std::size_t i = 0; i < n; ++i)
        a[i] = op(a[i], a[i + n]);
    return a[0];
  }
}
} // namespace detail

template <Num T>
PLUME_INLINE scalar_t<T> reduce_add(T const& x) noexcept {
  return detail::reduce_halves(x, [](scalar_t<T> a, scalar_t<T> b) { return scalar_t<T>(a + b); });
}

template <Num T>
PLUME_INLINE scalar_t<T> reduce_min(T const& x) noexcept {
  return detail::reduce_halves(x, [](scalar_t<T> a, scalar_t<T> b) { return plume::min(a, b); });
}

template <Num T>
PLUME_INLINE scalar_t<T> reduce_max(T const& x) noexcept {
  return detail::reduce_halves(x, [](scalar_t<T> a, scalar_t<T> b) { return plume::max(a, b); });
}

} // namespace plume

PLUME_MASK_CODE_END
