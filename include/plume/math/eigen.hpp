// plume/math/eigen.hpp - conversions between plume's scalar math types and Eigen's.
//
// Not included by <plume/math.hpp>: include it where you use Eigen (plume itself does not
// depend on Eigen). Copies: to_eigen(Vec3) -> Eigen::Vector3f, from_eigen(...), for
// Vec3/DVec3, Quat/DQuat (Eigen stores w last in memory too, but its constructor takes w
// first) and Mat3/DMat3. Zero-copy views: as_eigen(v) maps a GVec3<S> as Eigen::Vector3 and
// a GMat3<S> as Eigen::Matrix3 (both column-major, 3 or 9 contiguous scalars).
#pragma once

#include <plume/math/mat3.hpp>
#include <plume/math/quat.hpp>
#include <plume/math/vec3.hpp>

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

/// Zero-copy views (writes go through to the plume value).
template <class S>
requires std::is_floating_point_v<S> Eigen::Map<Eigen::Matrix<S, 3, 1>> as_eigen(GVec3<S>& v) {
  return Eigen::Map<Eigen::Matrix<S, 3, 1>>(&v.x);
}
template <class S>
requires std::is_floating_point_v<S> Eigen::Map<Eigen::Matrix<S, 3, 3>> as_eigen(GMat3<S>& m) {
  return Eigen::Map<Eigen::Matrix<S, 3, 3>>(&m.x_axis.x);
}

} // namespace plume
