// plume/math/pack.hpp - between arrays of scalar vectors (AoS) and wide vectors (SoA).
//
//   pack<T>(const GVec3<S>* p, n)        lanes 0..n-1 from p[0..n), the rest from fill
//   pack_strided<T>(const S* base, stride_bytes, n)   the same from x,y,z at base + i*stride
//   unpack(v, GVec3<S>* out, n)          lanes 0..n-1 to out[0..n)
//   load_soa<T>(xs, ys, zs, n)           from separate x/y/z arrays (n < lanes: zero tail)
//   load_soa_aligned<T>(xs, ys, zs)      arrays aligned to the batch width
//   store_soa(v, xs, ys, zs, n)          and store_soa_aligned
// n defaults to the full width and is clamped to it. For counts that are not a multiple of
// the width, process full batches and then one partial batch with n = count % lanes; the
// tail mask tail_mask<T>(n) is true on the lanes that hold data. The same functions exist
// for GQuat (pack/unpack).
#pragma once

#include <plume/math/quat.hpp>
#include <plume/math/vec3.hpp>

#include <cstring>

PLUME_MASK_CODE_BEGIN

namespace plume {

/// Lanes [0, n) true.
template <Num T>
PLUME_INLINE mask_t<T> tail_mask(std::size_t n) noexcept {
  using S = scalar_t<T>;
  std::array<S, lanes_v<T>> idx;
  for (std::size_t i = 0; i < lanes_v<T>; ++i)
    idx[i] = static_cast<S>(i);
  return plume::from_array<T>(idx) < splat<T>(static_cast<S>(n));
}

template <Num T>
PLUME_INLINE GVec3<T> pack(GVec3<scalar_t<T>> const* p, std::size_t n = lanes_v<T>,
                           GVec3<scalar_t<T>> const& fill = {}) noexcept {
  using S = scalar_t<T>;
  std::array<S, lanes_v<T>> x, y, z;
  for (std::size_t i = 0; i < lanes_v<T>; ++i) {
    GVec3<S> const& v = i < n ? p[i] : fill;
    x[i] = v.x, y[i] = v.y, z[i] = v.z;
  }
  return {plume::from_array<T>(x), plume::from_array<T>(y), plume::from_array<T>(z)};
}

/// x, y, z of lane i read at base + i * stride_bytes (+ 0, + sizeof(S), + 2 sizeof(S)).
template <Num T>
PLUME_INLINE GVec3<T> pack_strided(void const* base, std::size_t stride_bytes,
                                   std::size_t n = lanes_v<T>) noexcept {
  using S = scalar_t<T>;
  std::array<S, lanes_v<T>> x{}, y{}, z{};
  auto const* bytes = static_cast<unsigned char const*>(base);
  for (std::size_t i = 0; i < lanes_v<T> && i < n; ++i) {
    S v[3];
    std::memcpy(v, bytes + i * stride_bytes, sizeof v);
    x[i] = v[0], y[i] = v[1], z[i] = v[2];
  }
  return {plume::from_array<T>(x), plume::from_array<T>(y), plume::from_array<T>(z)};
}

template <Num T>
PLUME_INLINE void unpack(GVec3<T> const& v, GVec3<scalar_t<T>>* out,
                         std::size_t n = lanes_v<T>) noexcept {
  for (std::size_t i = 0; i < lanes_v<T> && i < n; ++i)
    out[i] = plume::lane(v, i);
}

template <Float T>
PLUME_INLINE GQuat<T> pack(GQuat<scalar_t<T>> const* p, std::size_t n = lanes_v<T>) noexcept {
  using S = scalar_t<T>;
  std::array<S, lanes_v<T>> x, y, z, w;
  for (std::size_t i = 0; i < lanes_v<T>; ++i) {
    GQuat<S> const v = i < n ? p[i] : GQuat<S>{};
    x[i] = v.x, y[i] = v.y, z[i] = v.z, w[i] = v.w;
  }
  return {plume::from_array<T>(x), plume::from_array<T>(y), plume::from_array<T>(z),
          plume::from_array<T>(w)};
}

template <Float T>
PLUME_INLINE void unpack(GQuat<T> const& q, GQuat<scalar_t<T>>* out,
                         std::size_t n = lanes_v<T>) noexcept {
  for (std::size_t i = 0; i < lanes_v<T> && i < n; ++i)
    out[i] = plume::lane(q, i);
}

template <Num T>
PLUME_INLINE GVec3<T> load_soa(scalar_t<T> const* xs, scalar_t<T> const* ys, scalar_t<T> const* zs,
                               std::size_t n = lanes_v<T>) noexcept {
  return {plume::load_partial<T>(xs, n), plume::load_partial<T>(ys, n),
          plume::load_partial<T>(zs, n)};
}
template <Num T>
PLUME_INLINE GVec3<T> load_soa_aligned(scalar_t<T> const* xs, scalar_t<T> const* ys,
                                       scalar_t<T> const* zs) noexcept {
  return {plume::load_aligned<T>(xs), plume::load_aligned<T>(ys), plume::load_aligned<T>(zs)};
}
template <Num T>
PLUME_INLINE void store_soa(GVec3<T> const& v, scalar_t<T>* xs, scalar_t<T>* ys, scalar_t<T>* zs,
                            std::size_t n = lanes_v<T>) noexcept {
  plume::store_partial(xs, v.x, n);
  plume::store_partial(ys, v.y, n);
  plume::store_partial(zs, v.z, n);
}
template <Num T>
PLUME_INLINE void store_soa_aligned(GVec3<T> const& v, scalar_t<T>* xs, scalar_t<T>* ys,
                                    scalar_t<T>* zs) noexcept {
  plume::store_aligned(xs, v.x);
  plume::store_aligned(ys, v.y);
  plume::store_aligned(zs, v.z);
}

} // namespace plume

PLUME_MASK_CODE_END
