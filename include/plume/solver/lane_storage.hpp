// plume/solver/lane_storage.hpp - structure-of-arrays fields that are written one lane at a
// time (when constraints are prepared, in plain float) and read whole (when the wide kernels
// run): GGLaneArray<T> holds lanes_v<T> scalars, aligned so get() is one aligned load;
// GGLaneVec3<T> holds three of them, GLaneQuat<T> four (a rotation), GLaneSymMat3<T> the six
// entries of a symmetric matrix.
// For T = float each is a single value.
#pragma once

#include <plume/math/mat3.hpp>
#include <plume/math/quat.hpp>
#include <plume/math/sym_mat3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <array>
#include <cstddef>

namespace plume {

template <Real T>
struct GLaneArray {
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
struct GLaneVec3 {
  GLaneArray<T> x, y, z;

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

/// A symmetric 3x3 matrix per lane (world inverse inertia), six lane-wide fields.
template <Real T>
struct GLaneSymMat3 {
  GLaneArray<T> xx, yy, zz, xy, xz, yz;

  GSymMat3<T> get() const noexcept {
    return {xx.get(), yy.get(), zz.get(), xy.get(), xz.get(), yz.get()};
  }
  void set_lane(std::size_t i, GMat3<scalar_t<T>> const& m) noexcept {
    auto const s = GSymMat3<scalar_t<T>>::from_mat3(m);
    xx[i] = s.xx;
    yy[i] = s.yy;
    zz[i] = s.zz;
    xy[i] = s.xy;
    xz[i] = s.xz;
    yz[i] = s.yz;
  }
};

/// A rotation per lane, four lane-wide fields.
template <Real T>
struct GLaneQuat {
  GLaneArray<T> x, y, z, w;

  GQuat<T> get() const noexcept { return {x.get(), y.get(), z.get(), w.get()}; }
  void set_lane(std::size_t i, GQuat<scalar_t<T>> const& q) noexcept {
    x[i] = q.x;
    y[i] = q.y;
    z[i] = q.z;
    w[i] = q.w;
  }
};

} // namespace plume
