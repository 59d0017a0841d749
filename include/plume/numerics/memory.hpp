// plume/numerics/memory.hpp - loading and storing element types from arrays of lanes.
//
//   load<T>(p)             lanes p[0..lanes_v<T>) ; p needs no alignment
//   load_aligned<T>(p)     same, p aligned to sizeof(T)
//   load_partial<T>(p, n)  lanes p[0..n), the others zero; n >= lanes_v<T> loads all lanes
//   store(p, x), store_aligned(p, x), store_partial(p, x, n)   the reverse
// For scalars these read or write one value. Partial forms never touch memory past p[n).
#pragma once

#include <plume/numerics/traits.hpp>

#include <algorithm>
#include <array>
#include <cstddef>

namespace plume {

template <class T>
PLUME_INLINE T load(scalar_t<T> const* p) noexcept {
  if constexpr (is_batch_v<T>)
    return T::load_unaligned(p);
  else
    return *p;
}

template <class T>
PLUME_INLINE T load_aligned(scalar_t<T> const* p) noexcept {
  if constexpr (is_batch_v<T>)
    return T::load_aligned(p);
  else
    return *p;
}

template <class T>
PLUME_INLINE T load_partial(scalar_t<T> const* p, std::size_t n) noexcept {
  if (n >= lanes_v<T>) return plume::load<T>(p);
  std::array<scalar_t<T>, lanes_v<T>> a{};
  std::copy_n(p, n, a.begin());
  return plume::from_array<T>(a);
}

template <class T>
PLUME_INLINE void store(scalar_t<T>* p, T const& x) noexcept {
  if constexpr (is_batch_v<T>)
    x.store_unaligned(p);
  else
    *p = x;
}

template <class T>
PLUME_INLINE void store_aligned(scalar_t<T>* p, T const& x) noexcept {
  if constexpr (is_batch_v<T>)
    x.store_aligned(p);
  else
    *p = x;
}

template <class T>
PLUME_INLINE void store_partial(scalar_t<T>* p, T const& x, std::size_t n) noexcept {
  if (n >= lanes_v<T>) return plume::store(p, x);
  auto const a = plume::to_array(x);
  std::copy_n(a.begin(), n, p);
}

} // namespace plume
