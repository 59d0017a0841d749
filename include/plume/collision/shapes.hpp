// plume/collision/shapes.hpp - the primitive shapes of the collision module, each defined in
// its own local frame and placed in the world by a pose (GIso3<T>), generic over T: with a
// wide T, lane i is a different shape of the same kind.
//
//   GSphere<T>     radius r, centred at the local origin
//   GCapsule<T>    the points within r of the segment from (0, -h, 0) to (0, h, 0)
//   GCuboid<T>     the box [-e, e] (e: half extents)
//   GCylinder<T>   radius r around local Y, flat caps at y = +-h
//   GHalfSpace<T>  the solid side n . p <= 0 of the plane through the local origin (n unit,
//                  pointing out of the solid)
//   GTriangle<T>   vertices a, b, c (no interior: a surface)
//   GSegment<T>    the points between a and b (no interior: a line)
//
// Each shape has is_finite() (the lanes whose parameters are all finite), volume(),
// local_aabb() and aabb(pose) (a half-space's box is infinite), and
// support(dir): the point of the shape farthest along dir (dir need not be unit; a zero dir
// gives a point of the shape). Degenerate sizes (radius 0, zero extents) are valid shapes:
// a point, a segment, a flat box. Sizes are not checked: a negative or non-finite one gives
// unspecified results (the queries in gjk.hpp report a non-finite one as failed).
//
// Rounded form, used by the GJK family (collision/gjk.hpp): every bounded shape is a core
// swept by a ball, shape = core (+) ball(core_radius()); core_support(dir) is the core's
// support point. Spheres are a point core, capsules a segment core; the other shapes are
// their own core with radius 0. support(dir) = core_support(dir) + core_radius() dir/|dir|.
//
// mass_properties(density) (collision/mass_properties.hpp): mass = density * volume, the
// centre of mass and the inertia tensor about that centre, in the shape's frame (units:
// density in mass per length^3). Surfaces and lines (triangle, segment) have mass 0.
#pragma once

#include <plume/collision/mass_properties.hpp>
#include <plume/math/aabb3.hpp>
#include <plume/math/iso3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

namespace detail {
/// The world box of a local box [lo, hi] placed by pose: centre moved, half extents through
/// |R| (each world half extent is the sum of |R_ij| e_j).
template <Real T>
PLUME_INLINE GAabb3<T> place_box(GVec3<T> const& centre, GVec3<T> const& half,
                                 GIso3<T> const& pose) noexcept {
  GVec3<T> const c = pose.transform_point(centre);
  GVec3<T> const ax = pose.rotation * GVec3<T>{half.x, zero<T>(), zero<T>()};
  GVec3<T> const ay = pose.rotation * GVec3<T>{zero<T>(), half.y, zero<T>()};
  GVec3<T> const az = pose.rotation * GVec3<T>{zero<T>(), zero<T>(), half.z};
  GVec3<T> const e = (ax.abs() + ay.abs()) + az.abs();
  return {c - e, c + e};
}
} // namespace detail

template <Real T>
struct GSphere {
  T radius;

  T volume() const noexcept {
    return (splat<T>(4.0 / 3.0) * pi<T>()) * ((radius * radius) * radius);
  }
  GAabb3<T> local_aabb() const noexcept {
    GVec3<T> const e = GVec3<T>::splat(radius);
    return {-e, e};
  }
  GAabb3<T> aabb(GIso3<T> const& pose) const noexcept {
    GVec3<T> const e = GVec3<T>::splat(radius);
    return {pose.translation - e, pose.translation + e};
  }
  /// radius * dir / |dir| (the centre for a zero dir).
  GVec3<T> support(GVec3<T> const& dir) const noexcept { return dir.normalize_or_zero() * radius; }
  /// The core is the centre.
  GVec3<T> core_support(GVec3<T> const&) const noexcept { return {}; }
  T core_radius() const noexcept { return radius; }
  /// Lanes whose parameters are all finite (the queries report the others as failed).
  mask_t<T> is_finite() const noexcept { return plume::is_finite(radius); }
  /// I = 2/5 m r^2 on every axis.
  GMassProperties<T> mass_properties(T density) const noexcept {
    T const m = density * volume();
    return GMassProperties<T>::centred(m, GVec3<T>::splat(splat<T>(0.4) * m * (radius * radius)));
  }
};

template <Real T>
struct GCapsule {
  T half_height;
  T radius;

  T volume() const noexcept {
    T const r2 = radius * radius;
    return pi<T>() * r2 * (two<T>() * half_height + splat<T>(4.0 / 3.0) * radius);
  }
  GAabb3<T> local_aabb() const noexcept {
    GVec3<T> const e{radius, half_height + radius, radius};
    return {-e, e};
  }
  GAabb3<T> aabb(GIso3<T> const& pose) const noexcept {
    GVec3<T> const tip = pose.rotation * GVec3<T>{zero<T>(), half_height, zero<T>()};
    GVec3<T> const e = tip.abs() + GVec3<T>::splat(radius);
    return {pose.translation - e, pose.translation + e};
  }
  /// The segment end farther along dir (the upper one on ties) plus radius along dir.
  GVec3<T> support(GVec3<T> const& dir) const noexcept {
    T const y = plume::select(dir.y < zero<T>(), -half_height, half_height);
    return GVec3<T>{zero<T>(), y, zero<T>()} + dir.normalize_or_zero() * radius;
  }
  /// The core is the segment (0, -h, 0) .. (0, h, 0).
  GVec3<T> core_support(GVec3<T> const& dir) const noexcept {
    return {zero<T>(), plume::select(dir.y < zero<T>(), -half_height, half_height), zero<T>()};
  }
  T core_radius() const noexcept { return radius; }
  mask_t<T> is_finite() const noexcept {
    return plume::is_finite(half_height) & plume::is_finite(radius);
  }
  /// A cylinder of mass mc and two hemispheres of total mass ms: I_yy = mc r^2/2 + 2/5 ms r^2,
  /// I_xx = I_zz = mc (r^2/4 + h^2/3) + ms (2/5 r^2 + h^2 + 3/4 h r) (each hemisphere's
  /// centre of mass is 3r/8 beyond the end of the segment).
  GMassProperties<T> mass_properties(T density) const noexcept {
    T const r2 = radius * radius, h = half_height;
    T const mc = density * (pi<T>() * r2 * (two<T>() * h));
    T const ms = density * (splat<T>(4.0 / 3.0) * pi<T>() * (r2 * radius));
    T const iy = mc * r2 * half<T>() + splat<T>(0.4) * ms * r2;
    T const ix = mc * (splat<T>(0.25) * r2 + h * h * splat<T>(1.0 / 3.0)) +
                 ms * (splat<T>(0.4) * r2 + h * h + splat<T>(0.75) * h * radius);
    return GMassProperties<T>::centred(mc + ms, GVec3<T>{ix, iy, ix});
  }
};

template <Real T>
struct GCuboid {
  GVec3<T> half_extents;

  T volume() const noexcept {
    return splat<T>(8) * ((half_extents.x * half_extents.y) * half_extents.z);
  }
  GAabb3<T> local_aabb() const noexcept { return {-half_extents, half_extents}; }
  GAabb3<T> aabb(GIso3<T> const& pose) const noexcept {
    return detail::place_box(GVec3<T>{}, half_extents, pose);
  }
  /// The corner farther along dir (positive on ties and zeros).
  GVec3<T> support(GVec3<T> const& dir) const noexcept {
    T const zero = plume::zero<T>();
    return {plume::select(dir.x < zero, -half_extents.x, half_extents.x),
            plume::select(dir.y < zero, -half_extents.y, half_extents.y),
            plume::select(dir.z < zero, -half_extents.z, half_extents.z)};
  }
  GVec3<T> core_support(GVec3<T> const& dir) const noexcept { return support(dir); }
  T core_radius() const noexcept { return zero<T>(); }
  mask_t<T> is_finite() const noexcept { return half_extents.is_finite(); }
  /// I_xx = m (e_y^2 + e_z^2) / 3 and its cyclic counterparts (e: half extents).
  GMassProperties<T> mass_properties(T density) const noexcept {
    T const m = density * volume();
    GVec3<T> const e2 = half_extents * half_extents;
    T const k = m * splat<T>(1.0 / 3.0);
    return GMassProperties<T>::centred(
        m, GVec3<T>{k * (e2.y + e2.z), k * (e2.x + e2.z), k * (e2.x + e2.y)});
  }
};

template <Real T>
struct GCylinder {
  T half_height;
  T radius;

  T volume() const noexcept { return pi<T>() * (radius * radius) * (two<T>() * half_height); }
  GAabb3<T> local_aabb() const noexcept {
    GVec3<T> const e{radius, half_height, radius};
    return {-e, e};
  }
  GAabb3<T> aabb(GIso3<T> const& pose) const noexcept {
    // The rim circle's extent along world axis i is r sqrt(1 - a_i^2) (a: the world axis).
    GVec3<T> const axis = pose.rotation * GVec3<T>::Y;
    GVec3<T> const tip = axis * half_height;
    GVec3<T> const rim{plume::sqrt(plume::max(one<T>() - axis.x * axis.x, zero<T>())),
                       plume::sqrt(plume::max(one<T>() - axis.y * axis.y, zero<T>())),
                       plume::sqrt(plume::max(one<T>() - axis.z * axis.z, zero<T>()))};
    GVec3<T> const e = tip.abs() + rim * radius;
    return {pose.translation - e, pose.translation + e};
  }
  /// The rim point farther along dir: (r dir_xz / |dir_xz|, +-h, ...); the axis end for a dir
  /// along Y.
  GVec3<T> support(GVec3<T> const& dir) const noexcept {
    T const xz2 = dir.x * dir.x + dir.z * dir.z;
    T const s = plume::select(xz2 > zero<T>(), radius / plume::sqrt(xz2), zero<T>());
    return {dir.x * s, plume::select(dir.y < zero<T>(), -half_height, half_height), dir.z * s};
  }
  GVec3<T> core_support(GVec3<T> const& dir) const noexcept { return support(dir); }
  T core_radius() const noexcept { return zero<T>(); }
  mask_t<T> is_finite() const noexcept {
    return plume::is_finite(half_height) & plume::is_finite(radius);
  }
  /// I_yy = m r^2 / 2, I_xx = I_zz = m (r^2/4 + h^2/3) (h: half height).
  GMassProperties<T> mass_properties(T density) const noexcept {
    T const m = density * volume();
    T const r2 = radius * radius;
    T const ix = m * (splat<T>(0.25) * r2 + half_height * half_height * splat<T>(1.0 / 3.0));
    return GMassProperties<T>::centred(m, GVec3<T>{ix, m * r2 * half<T>(), ix});
  }
};

template <Real T>
struct GHalfSpace {
  GVec3<T> normal; ///< unit, out of the solid: the solid is normal . p <= 0

  /// Everything (an infinite box); there is no support point for directions along -normal.
  GAabb3<T> aabb(GIso3<T> const&) const noexcept {
    return {GVec3<T>::splat(-infinity<T>()), GVec3<T>::splat(infinity<T>())};
  }
  mask_t<T> is_finite() const noexcept { return normal.is_finite(); }
};

/// A triangle a, b, c (counter-clockwise seen from the side its normal points to). Zero area
/// (collinear or coincident vertices) is valid: rays miss it.
template <Real T>
struct GTriangle {
  GVec3<T> a, b, c;

  /// (b - a) x (c - a): twice the area times the unit normal.
  GVec3<T> scaled_normal() const noexcept { return (b - a).cross(c - a); }
  T area() const noexcept { return half<T>() * scaled_normal().length(); }
  GAabb3<T> local_aabb() const noexcept { return {a.min(b).min(c), a.max(b).max(c)}; }
  GAabb3<T> aabb(GIso3<T> const& pose) const noexcept {
    return GTriangle{pose.transform_point(a), pose.transform_point(b), pose.transform_point(c)}
        .local_aabb();
  }
  /// The vertex farthest along dir (the first of a, b, c on ties).
  GVec3<T> support(GVec3<T> const& dir) const noexcept {
    T const da = a.dot(dir), db = b.dot(dir), dc = c.dot(dir);
    auto const pick_b = db > da;
    T const best = plume::select(pick_b, db, da);
    GVec3<T> const ab = GVec3<T>::select(pick_b, b, a);
    return GVec3<T>::select(dc > best, c, ab);
  }
  GVec3<T> core_support(GVec3<T> const& dir) const noexcept { return support(dir); }
  T core_radius() const noexcept { return zero<T>(); }
  mask_t<T> is_finite() const noexcept { return (a.is_finite() & b.is_finite()) & c.is_finite(); }
  /// A surface has no mass: mass 0, centre at the centroid, zero inertia.
  GMassProperties<T> mass_properties(T) const noexcept {
    return {zero<T>(), (a + b + c) * splat<T>(1.0 / 3.0), GMat3<T>{}};
  }
};

/// The segment from a to b. a == b (a point) is valid.
template <Real T>
struct GSegment {
  GVec3<T> a, b;

  T length() const noexcept { return (b - a).length(); }
  GAabb3<T> local_aabb() const noexcept { return {a.min(b), a.max(b)}; }
  GAabb3<T> aabb(GIso3<T> const& pose) const noexcept {
    return GSegment{pose.transform_point(a), pose.transform_point(b)}.local_aabb();
  }
  /// The end farther along dir (a on ties).
  GVec3<T> support(GVec3<T> const& dir) const noexcept {
    return GVec3<T>::select(b.dot(dir) > a.dot(dir), b, a);
  }
  GVec3<T> core_support(GVec3<T> const& dir) const noexcept { return support(dir); }
  T core_radius() const noexcept { return zero<T>(); }
  mask_t<T> is_finite() const noexcept { return a.is_finite() & b.is_finite(); }
  /// A line has no mass: mass 0, centre at the midpoint, zero inertia.
  GMassProperties<T> mass_properties(T) const noexcept {
    return {zero<T>(), (a + b) * half<T>(), GMat3<T>{}};
  }
};

using Sphere = GSphere<float>;
using Capsule = GCapsule<float>;
using Cuboid = GCuboid<float>;
using Cylinder = GCylinder<float>;
using HalfSpace = GHalfSpace<float>;
using Triangle = GTriangle<float>;
using Segment = GSegment<float>;

} // namespace plume

PLUME_MASK_CODE_END
