// plume/collision/mass_properties.hpp - mass, centre of mass and inertia tensor of a shape,
// generic over T (lanes = different bodies).
//
// Conventions: everything is in the shape's (or body's) local frame; `inertia` is the inertia
// tensor about `center` (not about the origin), symmetric, in mass * length^2. Shapes make
// them with mass_properties(density) (collision/shapes.hpp, collision/convex_hull.hpp).
// A shape of zero volume has mass 0 and zero inertia; callers that need a dynamic body must
// give it mass some other way.
#pragma once

#include <plume/math/iso3.hpp>
#include <plume/math/mat3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Real T>
struct GMassProperties {
  T mass;
  GVec3<T> center;  ///< centre of mass, local frame
  GMat3<T> inertia; ///< about center, local axes

  /// Mass m at the origin with principal moments `principal` along the local axes.
  static GMassProperties centred(T m, GVec3<T> const& principal) noexcept {
    return {m, GVec3<T>{}, GMat3<T>::from_diagonal(principal)};
  }

  /// The same body placed by pose: centre moved, inertia rotated (R I R^T) into the pose's
  /// parent frame.
  GMassProperties transformed(GIso3<T> const& pose) const noexcept {
    GMat3<T> const r = pose.rotation_matrix();
    return {mass, pose.transform_point(center), inertia.rotate_inertia(r)};
  }

  /// The inertia tensor about a point p instead of the centre (parallel axis theorem):
  /// I + m (|d|^2 E - d d^T) with d = p - center.
  GMat3<T> inertia_about(GVec3<T> const& p) const noexcept {
    GVec3<T> const d = p - center;
    return inertia +
           (GMat3<T>::from_diagonal(GVec3<T>::splat(d.dot(d))) - GMat3<T>::outer(d, d)) * mass;
  }

  /// The union of two bodies (compound): masses add, the centre is the mass-weighted mean and
  /// both inertias move to it. Two massless parts give mass 0, centre at their midpoint.
  GMassProperties combine(GMassProperties const& b) const noexcept {
    T const m = mass + b.mass;
    mask_t<T> const massless = m == zero<T>();
    T const wa = plume::select(massless, half<T>(), mass / m);
    GVec3<T> const c = center * wa + b.center * (one<T>() - wa);
    return {m, c, inertia_about(c) + b.inertia_about(c)};
  }

  /// The principal moments are the eigenvalues of `inertia`; this returns its diagonal, which
  /// equals them when the shape's axes are principal (every primitive shape).
  GVec3<T> diagonal() const noexcept { return inertia.diagonal(); }
};

using MassProperties = GMassProperties<float>;
using DMassProperties = GMassProperties<double>;

} // namespace plume

PLUME_MASK_CODE_END
