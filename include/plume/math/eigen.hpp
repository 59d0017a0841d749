// plume/math/eigen.hpp - conversions between plume's scalar math types and Eigen's.
//
// Not included by <plume/math.hpp>: include it where you use Eigen (plume itself does not
// depend on Eigen). Copies: to_eigen(v) and from_eigen(e) for GVec2/3/4 <-> Eigen::Vector2/3/4,
// GQuat <-> Eigen::Quaternion (Eigen stores w last in memory too, but its constructor takes
// w first) and GMat2/3/4 <-> Eigen::Matrix2/3/4, for float and double. Zero-copy views:
// as_eigen(v) / as_eigen(m) map a scalar plume vector or matrix in place (both libraries
// are column-major and plume's scalar types are packed scalars).
#pragma once

#include <plume/math/mat2.hpp>
#include <plume/math/mat3.hpp>
#include <plume/math/mat4.hpp>
#include <plume/math/quat.hpp>
#include <plume/math/vec2.hpp>
#include <plume/math/vec3.hpp>
#include <plume/math/vec4.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace plume {

static_assert(
    sizeof(GVec3<float>) == 3 * sizeof(float) && sizeof(GMat3<float>) == 9 * sizeof(float),
    "plume's scalar vectors and matrices are packed scalars (zero-copy views rely on it)");

template <class S>
requires std::is_floating_point_v<S> Eigen::Matrix<S, 3, 1> to_eigen(GVec3<S> const& v) {
  return {v.x, v.y, v.z};
}
template <class S>
GVec3<S> from_eigen(Eigen::Matrix<S, 3, 1> const& v) {
  return {v.x(), v.y(), v.z()};
}
template <class S>
requires std::is_floating_point_v<S> Eigen::Quaternion<S> to_eigen(GQuat<S> const& q) {
  return Eigen::Quaternion<S>(q.w, q.x, q.y, q.z);
}
template <class S>
GQuat<S> from_eigen(Eigen::Quaternion<S> const& q) {
  return {q.x(), q.y(), q.z(), q.w()};
}
template <class S>
requires std::is_floating_point_v<S> Eigen::Matrix<S, 3, 3> to_eigen(GMat3<S> const& m) {
  Eigen::Matrix<S, 3, 3> e;
  e.col(0) = to_eigen(m.x_axis);
  e.col(1) = to_eigen(m.y_axis);
  e.col(2) = to_eigen(m.z_axis);
  return e;
}
template <class S>
GMat3<S> from_eigen(Eigen::Matrix<S, 3, 3> const& e) {
  return {{e(0, 0), e(1, 0), e(2, 0)}, {e(0, 1), e(1, 1), e(2, 1)}, {e(0, 2), e(1, 2), e(2, 2)}};
}

template <class S>
requires std::is_floating_point_v<S> Eigen::Matrix<S, 2, 1> to_eigen(GVec2<S> const& v) {
  return {v.x, v.y};
}
template <class S>
GVec2<S> from_eigen(Eigen::Matrix<S, 2, 1> const& v) {
  return {v.x(), v.y()};
}
template <class S>
requires std::is_floating_point_v<S> Eigen::Matrix<S, 4, 1> to_eigen(GVec4<S> const& v) {
  return {v.x, v.y, v.z, v.w};
}
template <class S>
GVec4<S> from_eigen(Eigen::Matrix<S, 4, 1> const& v) {
  return {v.x(), v.y(), v.z(), v.w()};
}
template <class S>
requires std::is_floating_point_v<S> Eigen::Matrix<S, 2, 2> to_eigen(GMat2<S> const& m) {
  Eigen::Matrix<S, 2, 2> e;
  e << m.x_axis.x, m.y_axis.x, m.x_axis.y, m.y_axis.y;
  return e;
}
template <class S>
GMat2<S> from_eigen(Eigen::Matrix<S, 2, 2> const& e) {
  return {{e(0, 0), e(1, 0)}, {e(0, 1), e(1, 1)}};
}
template <class S>
requires std::is_floating_point_v<S> Eigen::Matrix<S, 4, 4> to_eigen(GMat4<S> const& m) {
  Eigen::Matrix<S, 4, 4> e;
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j)
      e(Eigen::Index(i), Eigen::Index(j)) = m.at(i, j);
  return e;
}
template <class S>
GMat4<S> from_eigen(Eigen::Matrix<S, 4, 4> const& e) {
  auto col = [&e](Eigen::Index j) { return GVec4<S>{e(0, j), e(1, j), e(2, j), e(3, j)}; };
  return {col(0), col(1), col(2), col(3)};
}

/// Zero-copy views (writes go through to the plume value).
template <class S>
requires std::is_floating_point_v<S> Eigen::Map<Eigen::Matrix<S, 3, 1>> as_eigen(GVec3<S>& v) {
  return Eigen::Map<Eigen::Matrix<S, 3, 1>>(&v.x);
}
template <class S>
requires std::is_floating_point_v<S> Eigen::Map<Eigen::Matrix<S, 3, 3>> as_eigen(GMat3<S>& m) {
  return Eigen::Map<Eigen::Matrix<S, 3, 3>>(&m.x_axis.x);
}

template <class S>
requires std::is_floating_point_v<S> Eigen::Map<Eigen::Matrix<S, 2, 1>> as_eigen(GVec2<S>& v) {
  return Eigen::Map<Eigen::Matrix<S, 2, 1>>(&v.x);
}
template <class S>
requires std::is_floating_point_v<S> Eigen::Map<Eigen::Matrix<S, 4, 1>> as_eigen(GVec4<S>& v) {
  return Eigen::Map<Eigen::Matrix<S, 4, 1>>(&v.x);
}
template <class S>
requires std::is_floating_point_v<S> Eigen::Map<Eigen::Matrix<S, 4, 4>> as_eigen(GMat4<S>& m) {
  return Eigen::Map<Eigen::Matrix<S, 4, 4>>(&m.x_axis.x);
}

} // namespace plume
