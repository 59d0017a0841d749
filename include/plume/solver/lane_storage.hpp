// plume/solver/lane_storage.hpp - structure-of-arrays fields that are written one lane at a
// time (when constraints are prepared, in plain float) and read whole (when the wide kernels
// run): LaneArray<T> holds lanes_v<T> scalars, aligned so get() is one aligned load;
// LaneVec3<T> holds three of them. For T = float both are a single value.
#pragma once

#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <array>
#include <cstddef>

namespace plume {

template <Real T>
struct LaneArray {
  using scalar_type = scalar_t<T>;
  static constexpr std::size_t lanes = lanes_v<T>;
  alignas(alignof(T)) std::array<scalar_type, lanes> v{};

  T get() const noexcept {
    if constexpr (lanes == 1)
      return v[0];
    else
      return load_aligned<T>(v.data());
  }
  void set(T const& x) noexcept {
    if constexpr (lanes == 1)
      v[0] = x;
    else
      store_aligned(v.data(), x);
  }
  scalar_type& operator[](std::size_t i) noexcept { return v[i]; }
  scalar_type const& operator[](std::size_t i) const noexcept { return v[i]; }
};

template <Real T>
struct LaneVec3 {
  LaneArray<T> x, y, z;

  GVec3<T> get() const noexcept { return {x.get(), y.get(), z.get()}; }
  void set(GVec3<T> const& p) noexcept {
    x.set(p.x);
    y.set(p.y);
    z.set(p.z);
  }
  GVec3<scalar_t<T>> lane(std::size_t i) const noexcept { return {x[i], y[i], z[i]}; }
  void set_lane(std::size_t i, GVec3<scalar_t<T>> const& p) noexcept {
    x[i] = p.x;
    y[i] = p.y;
    z[i] = p.z;
  }
};

} // namespace plume
