// plume/math/sym_mat3.hpp - GSymMat3<T>: a symmetric 3x3 matrix stored as its six distinct
// entries (inverse inertia tensors in world axes), any element type.
//
//   | xx xy xz |
//   | xy yy yz |    m * v = ((xx vx + xy vy) + xz vz, (xy vx + yy vy) + yz vz,
//   | xz yz zz |             (xz vx + yz vy) + zz vz): each row summed left to right.
//
// from_mat3(m) reads the diagonal and the upper triangle of m and assumes m symmetric (it
// does not check or average); to_mat3() gives the full matrix.
#pragma once

#include <plume/math/mat3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

namespace plume {

template <Real T>
struct GSymMat3 {
  T xx, yy, zz, xy, xz, yz;

  static GSymMat3 from_mat3(GMat3<T> const& m) noexcept {
    return {m.x_axis.x, m.y_axis.y, m.z_axis.z, m.y_axis.x, m.z_axis.x, m.z_axis.y};
  }
  GMat3<T> to_mat3() const noexcept { return GMat3<T>::from_symmetric(xx, yy, zz, xy, xz, yz); }
  PLUME_INLINE GVec3<T> operator*(GVec3<T> const& v) const noexcept {
    return {(xx * v.x + xy * v.y) + xz * v.z, (xy * v.x + yy * v.y) + yz * v.z,
            (xz * v.x + yz * v.y) + zz * v.z};
  }
};

using SymMat3 = GSymMat3<float>;
using DSymMat3 = GSymMat3<double>;

} // namespace plume
