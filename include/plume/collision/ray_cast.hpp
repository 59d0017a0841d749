// plume/collision/ray_cast.hpp - ray casts against the primitive shapes in closed form,
// generic over T: with a wide T, lane i casts ray i against shape i (or one ray against
// many shapes, or many rays against one shape: splat what is shared).
//
//   ray_cast(shape, pose, ray, max_toi, solid = true) -> GRayHit<T>
//   ray_cast_local(shape, ray, max_toi, solid)       the same with the ray in the shape frame
//   ray_cast(GAabb3<T>, ray, max_toi, solid)         an axis-aligned box in world space
//   shapes: GSphere GCapsule GCuboid GCylinder GHalfSpace GTriangle (watertight)
//
// Conventions:
//  - The ray is origin + t dir, t >= 0; dir need not be unit: toi is in units of |dir|.
//    A hit needs toi <= max_toi (inclusive; max_toi may be +infinity).
//  - normal: the outward unit normal of the surface at the hit point, in world space.
//  - Origin inside the (closed) shape: solid casts hit at toi = 0 with a zero normal (there
//    is no surface there); hollow casts hit where the ray leaves the shape, with the outward
//    normal there (pointing along the ray).
//  - Miss: hit false, toi = +infinity, normal zero. A zero direction hits only a solid shape
//    its origin is inside (toi = 0). A non-finite origin or direction, or a NaN max_toi, is
//    a miss in that lane only. Shape sizes are finite and >= 0; an infinite or NaN size
//    gives an unspecified hit (no trap, no hang, other lanes untouched).
//  - Directions of ordinary length: spheres, capsules and cylinders square |dir|, so from
//    outside a direction whose square overflows (|dir| > 1.8e19 in float) misses them, and
//    from inside a solid sphere or capsule a direction whose dot product with the origin
//    (relative to the centre, or to the capsule's upper end) overflows counts as
//    non-finite: a miss (|dir| above about 3e38 / size). A time of impact that overflows float
//    (a direction so short that its square underflows, say |dir| < 1e-19 for a shape 10 m
//    away) is a miss too.
//  - Robust forms (Haines, Guenther and Akenine-Moeller, "Precision Improvements for
//    Ray/Sphere Intersection", Ray Tracing Gems, 2019): the sphere and cylinder discriminants
//    are computed as a (r^2 - |f - (b/a) d|^2) = a r^2 - |f x d|^2, without the cancellation
//    of b^2 - a c for small or far shapes, and the roots as c/q and q/a with
//    q = -(b + sign(b) sqrt(disc)) (one division for both); slab tests treat a zero direction
//    component (+0 or -0), or one so small that 1/d overflows, as parallel and decide by whether
//    the origin lies in the (closed) slab: the 0 * inf = NaN of an origin on a slab plane never
//    rejects the ray, and an entry at t = +infinity is a miss.
//  - A grazing ray that touches the surface in one point hits (tangency counts).
//  - feature: the part of the shape hit, where the shape has parts, -1 on a miss or a solid
//    hit from inside: cuboids and AABBs 0..5 = the -x, +x, -y, +y, -z, +z face; capsules
//    0 side, 1 upper end (+y), 2 lower end; cylinders 0 side, 1 top cap, 2 bottom cap;
//    a box hit exactly on an edge or a corner takes the face of the first of its axes
//    (x, then y, then z), and so does its normal;
//    triangles 0 front (the side (b - a) x (c - a) points to), 1 back; spheres and
//    half-spaces 0. A number of type T, so that wide hits carry one per lane.
//
// Code shape, kept for the wide loops (docs/performance.md, "Ray casts"): locals copied whole
// into a returned struct are not const; normals use normalize_or(GVec3<T>{}), which gives
// normalize_or_zero()'s bits without loading its ZERO constant.
#pragma once

#include <plume/collision/shapes.hpp>
#include <plume/math/aabb3.hpp>
#include <plume/math/iso3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <cstddef>
#include <limits>
#include <type_traits>

PLUME_MASK_CODE_BEGIN

namespace plume {

/// A ray: origin + t dir for t >= 0.
template <Real T>
struct GRay3 {
  GVec3<T> origin;
  GVec3<T> dir;
  GVec3<T> at(T t) const noexcept { return origin + dir * t; }
};

/// The result of a ray cast, per lane.
template <Real T>
struct GRayHit {
  mask_t<T> hit;
  T toi;           ///< +infinity where hit is false
  GVec3<T> normal; ///< outward unit normal at the hit; zero on a miss or a solid inside hit
  T feature;       ///< the part hit (see the conventions above); -1 on a miss or inside
};

using Ray3 = GRay3<float>;
using RayHit = GRayHit<float>;

namespace detail {

/// The interval [tin, tout] of a line inside a convex set.
template <Real T>
struct ray_interval {
  mask_t<T> ok; ///< the line meets the set
  T tin, tout;
};

/// select(b < a, b, a) and select(b > a, b, a): a when the pair is unordered or equal.
template <Real T>
PLUME_INLINE T min_of(T a, T b) noexcept {
  return plume::min_select(b, a);
}
template <Real T>
PLUME_INLINE T max_of(T a, T b) noexcept {
  return plume::max_select(b, a);
}

/// Roots of |f + t d|^2 = r^2 in the robust form; the 2D form (xz) when Flat.
template <bool Flat, Real T>
PLUME_INLINE ray_interval<T> quadric_roots(GVec3<T> f, GVec3<T> d, T r) noexcept {
  if constexpr (Flat) {
    f.y = zero<T>();
    d.y = zero<T>();
  }
  T const a = d.dot(d), b = f.dot(d), c = f.dot(f) - r * r;
  // a (r^2 - |f - (b/a) d|^2) = a r^2 - |f x d|^2 (Lagrange's identity): the squared distance
  // of the centre from the line, without b^2 - a c's cancellation and without a division.
  T const disc = a * (r * r) - f.cross(d).length_squared();
  T const sq = plume::sqrt(disc);
  T const q = -(b + plume::copysign(sq, b));
  // Roots c/q and q/a with one division: (c a) / (q a) and (q q) / (q a). q = 0 only when the
  // origin is on the surface and the line tangent there: both roots 0.
  T const rq = one<T>() / (q * a);
  T const t0 = plume::select(q == zero<T>(), zero<T>(), (c * a) * rq);
  T const t1 = plume::select(q == zero<T>(), zero<T>(), (q * q) * rq);
  ray_interval<T> out;
  out.ok = (disc >= zero<T>()) & (a > zero<T>()); // a zero direction meets nothing
  out.tin = min_of(t0, t1);
  out.tout = max_of(t0, t1);
  return out;
}

/// Where a line from outside enters |f + t d| <= r (the xz form, a cylinder's side, when
/// Flat), for solid casts, which need no exit: from outside (c > 0) the roots have the sign
/// of -b, so the set lies ahead exactly where b < 0 and disc >= 0, and the entry is c / q
/// with q = sqrt(disc) - b > 0 (one division, one rounding after c and q). ok is false from
/// inside or on the surface (c <= 0), for a zero direction (a = 0) and for NaN input.
///
/// ok also implies a finite f and d: an infinite or NaN component makes c, b or a NaN, or
/// the cross product's square infinite or NaN and so disc -inf or NaN (inf * 0 and
/// inf - inf included), in every arrangement; callers need not test the ray's validity
/// where they take this entry.
///
/// `toward` is ok without c > 0 and disc >= 0, for a caller that takes another answer
/// wherever the origin is inside and rejects a NaN t: c <= 0 is exactly f . f <= r^2 (the
/// subtraction is exact in sign; a NaN c comes with a NaN b), and where disc < 0 (or NaN)
/// t is NaN, which fails every comparison. b - b is +0 where b is finite and NaN where it
/// is not: for a finite f it is NaN for every non-finite d (each of f's components times
/// an infinity is infinite or NaN), and for a finite d only if |f . d| overflows.
template <Real T>
struct entry_root {
  mask_t<T> ok, toward;
  T t; ///< meaningful where ok; NaN where toward, outside, and not ok
  T b; ///< f . d
};
template <bool Flat, Real T>
PLUME_INLINE entry_root<T> quadric_entry(GVec3<T> const& f, GVec3<T> const& d, T r) noexcept {
  T const zero = plume::zero<T>(), r2 = r * r;
  T a, b, c, disc;
  if constexpr (Flat) {
    a = d.x * d.x + d.z * d.z;
    b = f.x * d.x + f.z * d.z;
    c = (f.x * f.x + f.z * f.z) - r2;
    T const cross_y = f.z * d.x - f.x * d.z;
    disc = a * r2 - cross_y * cross_y;
  } else {
    a = d.dot(d);
    b = f.dot(d);
    c = f.dot(f) - r2;
    disc = a * r2 - f.cross(d).length_squared();
  }
  // The root first, the masks after, so that the masks are not live across the square root
  // and the division (docs/performance.md, "Ray casts"); t, toward and ok are not const.
  T t = c / (plume::sqrt(disc) - b);
  mask_t<T> toward = (b < zero) & (a > zero);
  mask_t<T> ok = (toward & (c > zero)) & (disc >= zero);
  return {ok, toward, t, b};
}

/// One axis of a slab test lo <= o + t d <= hi: the offsets of the planes from the origin and
/// the crossings of the near and far plane, picked by the sign of d (before the division, so
/// a scalar build's branch on it resolves early). A d that is +-0, or so small that 1/d
/// overflows, gives crossings at -inf and +inf when the origin is strictly inside the slab
/// and at one infinity when outside (an empty interval, or one starting at +inf: a miss); an
/// origin on a plane gives 0 * inf = NaN, and is inside the closed slab, so callers ignore a
/// NaN crossing (slab_interval maps it to -inf / +inf, box_cast's max/min skip it).
template <Real T>
struct slab_axis {
  T to_lo, to_hi; ///< lo - o, hi - o: exact in sign (zero only for equal operands)
  T near, far;
};
template <Real T>
PLUME_INLINE slab_axis<T> slab_crossings(T o, T d, T lo, T hi) noexcept {
  T const to_lo = lo - o, to_hi = hi - o;
  T const inv = one<T>() / d;
  return {to_lo, to_hi, select_sign(d, to_hi, to_lo) * inv, select_sign(d, to_lo, to_hi) * inv};
}

/// tin <= tout and tin < +infinity in one compare (every finite tin is <= the largest finite
/// value): the interval is met, and its entry is not at infinity.
template <Real T>
PLUME_INLINE mask_t<T> interval_met(T tin, T tout) noexcept {
  return tin <= plume::min_select(tout, max_value<T>());
}

/// The slab lo <= o + t d <= hi along one axis (slab_crossings with NaN crossings replaced).
template <Real T>
struct slab {
  T tin, tout;
  mask_t<T> in; ///< the origin is in the (closed) slab
};
template <Real T>
PLUME_INLINE slab<T> slab_interval(T o, T d, T lo, T hi) noexcept {
  T const inf = infinity<T>();
  slab_axis<T> const c = slab_crossings(o, d, lo, hi);
  mask_t<T> const in = (c.to_lo <= zero<T>()) & (c.to_hi >= zero<T>());
  return {plume::max_select(c.near, -inf), plume::min_select(c.far, inf), in};
}

/// The hit of the conventions above, before its normal: `leaving` marks hollow hits from
/// inside (the exit point), `bare` the solid hits from inside (toi 0, no normal). `at` is
/// toi before misses are set to +infinity: equal to toi wherever the hit has a normal, so a
/// normal taken at `at` need not wait for the hit test (a wide kernel's longest chain).
template <Real T>
struct pre_hit {
  mask_t<T> hit, leaving, bare;
  T toi, at;
};
template <Real T>
PLUME_INLINE pre_hit<T> finish(mask_t<T> valid, mask_t<T> inside, ray_interval<T> const& iv,
                               T max_toi, bool solid) noexcept {
  T const zero = plume::zero<T>();
  auto const reach = iv.ok & (iv.tout >= zero) & (iv.tin <= iv.tout);
  auto const outside = !inside;
  T const t_enter = max_of(iv.tin, zero);
  pre_hit<T> h;
  if (solid) {
    h.toi = plume::select(inside, zero, t_enter);
    h.hit = valid & (inside | (outside & reach));
    h.leaving = no_lanes<T>();
    h.bare = inside;
  } else {
    h.toi = plume::select(inside, max_of(iv.tout, zero), t_enter);
    h.hit = valid &
            ((outside & reach) | (inside & iv.ok & (iv.tout >= zero) & (iv.tout < infinity<T>())));
    h.leaving = inside;
    h.bare = no_lanes<T>();
  }
  // A time of impact that overflows (a direction so short that |dir|^2 underflows, divided
  // into a finite distance) is a miss, as an entry at +infinity is: toi <= min(FLT_MAX,
  // max_toi), one compare as in the solid paths (min_select keeps a NaN max_toi: a miss).
  h.hit = h.hit & (h.toi <= plume::min_select(max_value<T>(), max_toi));
  h.at = h.toi;
  h.toi = plume::select(h.hit, h.toi, infinity<T>());
  return h;
}
/// select(m, v, 0) per component, as one AND each where masks are lane-wide bit patterns.
template <Real T>
PLUME_INLINE GVec3<T> keep_where(mask_t<T> m, GVec3<T> const& v) noexcept {
  return {plume::keep_if(m, v.x), plume::keep_if(m, v.y), plume::keep_if(m, v.z)};
}
/// The hit h with normal n and feature where it is on the surface (not bare), zero and -1
/// elsewhere; the second form also zeroes n where has_normal is false (a degenerate shape).
template <Real T>
PLUME_INLINE GRayHit<T> with_normal(pre_hit<T> const& h, GVec3<T> const& n,
                                    T feature = zero<T>()) noexcept {
  mask_t<T> const surface = plume::and_not(h.hit, h.bare);
  return {h.hit, h.toi, keep_where(surface, n), plume::select(surface, feature, -one<T>())};
}
template <Real T>
PLUME_INLINE GRayHit<T> with_normal(pre_hit<T> const& h, GVec3<T> const& n, T feature,
                                    mask_t<T> has_normal) noexcept {
  mask_t<T> const surface = plume::and_not(h.hit, h.bare);
  return {h.hit, h.toi, keep_where(surface & has_normal, n),
          plume::select(surface, feature, -one<T>())};
}

/// n made unit on the `needed` lanes, for an n that is unit up to the rounding of the hit
/// point it came from (p / r). Where |n . n - 1| <= sqrt(eps): one Newton step
/// n (3 - n . n) / 2 (for |n| = 1 + e it leaves |n| within 1.5 e^2 of 1, below eps / 2).
/// Elsewhere (a small shape far from the origin, whose hit point's rounding is a fraction of
/// its size): n / |n|, zero where that is not finite. Lane-exact: the second form is taken
/// per lane, computed only when some lane needs it.
template <Real T>
PLUME_INLINE GVec3<T> unit_normal(GVec3<T> const& n, mask_t<T> needed) noexcept {
  T const l2 = n.dot(n);
  GVec3<T> out = n * (splat<T>(1.5) - half<T>() * l2);
  mask_t<T> const near = plume::abs(l2 - one<T>()) <= plume::sqrt(epsilon<T>());
  mask_t<T> const far = plume::and_not(needed, near);
  if (plume::any(far)) out = GVec3<T>::select(far, n.normalize_or(GVec3<T>{}), out);
  return out;
}

/// +0 where d is finite, NaN where it is not: (x - x) summed over the components.
template <Real T>
PLUME_INLINE T zero_if_finite(GVec3<T> const& d) noexcept {
  return ((d.x - d.x) + (d.y - d.y)) + (d.z - d.z);
}

/// Finite origin and direction: x - x is 0 for finite x and NaN otherwise, so the sums for
/// the origin and the direction are equal (both 0) exactly when all six are finite. (A NaN
/// max_toi needs no test: every hit requires toi <= max_toi, which is false for NaN.)
template <Real T>
PLUME_INLINE mask_t<T> ray_valid(GRay3<T> const& ray) noexcept {
  return zero_if_finite(ray.origin) == zero_if_finite(ray.dir);
}

/// Sphere of radius r at f's origin: f is the ray origin relative to the centre.
template <Real T>
PLUME_INLINE ray_interval<T> sphere_part(GVec3<T> const& f, GVec3<T> const& d, T r) noexcept {
  return quadric_roots<false>(f, d, r);
}

} // namespace detail

// ==================================================================================== shapes

/// Sphere (local frame: centred at the origin).
///
/// A solid cast needs only the entry root (quadric_entry); a hollow cast takes both roots.
template <Real T>
PLUME_INLINE GRayHit<T> ray_cast_local(GSphere<T> const& s, GRay3<T> const& ray, T max_toi,
                                       bool solid = true) noexcept {
  T const r2 = s.radius * s.radius;
  detail::pre_hit<T> h;
  if (solid) {
    auto e = detail::quadric_entry<false>(ray.origin, ray.dir, s.radius); // not const (see the top)
    auto const inside = ray.origin.length_squared() <= r2; // after the root (quadric_entry)
    // Validity without ray_valid's eleven operations: an entry implies a finite ray (see
    // quadric_entry), and an origin inside a finite radius is finite, so only the direction
    // of the inside lanes is left: their toi is b - b, +0 for a finite direction and NaN
    // otherwise (see entry_root). The toi <= limit test rejects that NaN, a NaN entry
    // (disc < 0: toward, not ok), an entry at +infinity, and every toi for a NaN max_toi
    // (min_select keeps it).
    T const toi = plume::select(inside, e.b - e.b, e.t);
    h.hit = (inside | e.toward) & (toi <= plume::min_select(max_value<T>(), max_toi));
    h.toi = plume::select(h.hit, toi, infinity<T>());
    h.leaving = no_lanes<T>();
    h.bare = inside;
    // The entry itself: the normal is kept only where the origin is outside, and there toi
    // is e.t (the inside lanes' select need not come first either).
    h.at = e.t;
  } else {
    auto const inside = ray.origin.length_squared() <= r2;
    auto const iv = detail::sphere_part(ray.origin, ray.dir, s.radius);
    h = detail::finish(detail::ray_valid(ray), inside, iv, max_toi, false);
  }
  // The normal p / r, made unit (unit_normal: the hit point's rounding need not be small
  // against r). A zero radius has no normal.
  mask_t<T> const has_normal = s.radius > zero<T>();
  T const inv_r = one<T>() / s.radius;
  GVec3<T> const n =
      detail::unit_normal(ray.at(h.at) * inv_r, plume::and_not(h.hit, h.bare) & has_normal);
  return detail::with_normal(h, n, zero<T>(), has_normal);
}

namespace detail {
/// The box lo <= p <= hi (in the frame the ray is given in): slab test, entry/exit face
/// normals. Shared by cuboids (lo = -e, hi = e) and world AABBs.
///
/// Per axis slab_crossings; the accumulation keeps the crossings NaN (an origin on a plane
/// with a parallel direction, inside that closed slab) and lets max/min skip them
/// (max_select/min_select keep their second argument), which is that answer without the two
/// replacements slab_interval makes per axis. An entry at +infinity is a miss (interval_met).
/// Whether the origin is inside comes from the signs of lo - o and hi - o (exact) for a hollow
/// cast. A solid cast reads it off the entry time instead, one compare for seven: it starts
/// inside (toi +0, no normal, feature -1) where tin <= 0. That is the closed box, and also an
/// origin outside by so little that its entry time (lo - o) / d underflows to 0, which needs
/// a direction component larger than 1 in magnitude (|d| <= 1 keeps a nonzero offset's
/// crossing nonzero); its toi is +0 either way, only the normal is left out.
template <Real T>
PLUME_INLINE GRayHit<T> box_cast(GVec3<T> const& lo, GVec3<T> const& hi, GRay3<T> const& ray,
                                 T max_toi, bool solid) noexcept {
  GVec3<T> const& o = ray.origin;
  GVec3<T> const& d = ray.dir;
  T const zero = plume::zero<T>(), inf = infinity<T>();
  // Written axis by axis, each folded into running values as soon as it is known, so that a
  // wide build keeps few registers live (docs/performance.md, "Ray casts").
  mask_t<T> const valid = ray_valid(ray);
  slab_axis<T> const sx = slab_crossings(o.x, d.x, lo.x, hi.x);
  // Entry: the slab entered last (first axis on ties); exit: the slab left first. NaN
  // crossings lose every comparison, so they are never picked.
  T const tin_x = plume::max_select(sx.near, -inf), tout_x = plume::min_select(sx.far, inf);
  slab_axis<T> const sy = slab_crossings(o.y, d.y, lo.y, hi.y);
  // Inside the closed box: lo - o <= 0 <= hi - o on every axis (a NaN lane is invalid).
  T const below_xy = plume::max_select(sx.to_lo, sy.to_lo);
  T const above_xy = plume::min_select(sx.to_hi, sy.to_hi);
  auto const y_in = sy.near > tin_x, y_out = sy.far < tout_x;
  T const tin_xy = plume::max_select(sy.near, tin_x), tout_xy = plume::min_select(sy.far, tout_x);
  slab_axis<T> const sz = slab_crossings(o.z, d.z, lo.z, hi.z);
  T const below = plume::max_select(below_xy, sz.to_lo);
  T const above = plume::min_select(above_xy, sz.to_hi);
  auto const z_in = sz.near > tin_xy, z_out = sz.far < tout_xy;
  ray_interval<T> iv;
  iv.tin = plume::max_select(sz.near, tin_xy);
  iv.tout = plume::min_select(sz.far, tout_xy);
  pre_hit<T> h;
  if (solid) {
    // tin <= 0 <= tout inside, so no inside term: a hit where max(tin, 0) <= tout, tin is
    // finite and the toi within max_toi, all in one compare: max(tin, 0) <= min(tout, FLT_MAX,
    // max_toi) (tin and tout are never NaN; min_select keeps a NaN max_toi, so it misses).
    T const toi = plume::max_select(iv.tin, zero);
    h.hit = valid & (toi <= plume::min_select(iv.tout, plume::min_select(max_value<T>(), max_toi)));
    h.toi = plume::select(h.hit, toi, inf);
    h.at = toi;
    h.leaving = h.bare = no_lanes<T>(); // not read: the solid normal below tests tin > 0 itself
  } else {
    iv.ok = interval_met(iv.tin, iv.tout);
    h = finish(valid, (below <= zero) & (above >= zero), iv, max_toi, false);
  }
  // Entering: the face of the entry slab, facing -dir; leaving: the exit slab's, facing dir.
  // That slab is z's where zs, else y's where ys, else x's. The normal there is +-1 along the
  // axis with the sign bit of d (on a surface hit d is not +-0 on that axis), flipped when
  // entering. A solid cast never leaves: its masks and sign are spelled out, not selected by
  // the all-false h.leaving (which a compiler need not fold).
  auto const ys = solid ? y_in : plume::select(h.leaving, y_out, y_in);
  auto const zs = solid ? z_in : plume::select(h.leaving, z_out, z_in);
  T const d_axis = plume::select(zs, d.z, plume::select(ys, d.y, d.x));
  T const one_out = solid ? -one<T>() : plume::select(h.leaving, one<T>(), -one<T>());
  T const u = select_sign(d_axis, -one_out, one_out);
  auto const surface = solid ? h.hit & (iv.tin > zero) : h.hit;
  T const nu = plume::keep_if(surface, u);
  GRayHit<T> out;
  out.hit = h.hit;
  out.toi = h.toi;
  out.normal.z = plume::keep_if(zs, nu);
  T const not_z = bit_xor(nu, out.normal.z); // nu where not z's, else 0
  out.normal.y = plume::keep_if(ys, not_z);
  out.normal.x = bit_xor(not_z, out.normal.y);
  // Face 2 axis + (outward normal positive), as (2 axis + 1/2) + u/2 (exact); -1 without
  // a surface.
  T const face =
      plume::select(zs, splat<T>(4.5), plume::select(ys, splat<T>(2.5), half<T>())) + half<T>() * u;
  out.feature = plume::select(surface, face, -one<T>());
  return out;
}
} // namespace detail

/// Cuboid (local frame: the box [-e, e]).
template <Real T>
PLUME_INLINE GRayHit<T> ray_cast_local(GCuboid<T> const& box, GRay3<T> const& ray, T max_toi,
                                       bool solid = true) noexcept {
  return detail::box_cast(-box.half_extents, box.half_extents, ray, max_toi, solid);
}

/// Capsule (local frame: radius r around the segment (0, -h, 0) - (0, h, 0)). A solid cast
/// takes the entry roots of the side and of both end spheres and keeps the first (see
/// below). A hollow cast needs the exit too: the capsule lies inside the infinite cylinder
/// of radius r, so its entry is the cylinder's entry when that point is within |y| <= h,
/// and otherwise the entry into the end sphere on that side (the one facing the ray for a
/// ray along the axis, which misses the side); the exit likewise. Both end spheres are
/// intersected alongside the side, not just the one a crossing needs after it, which would
/// wait for the side's square root and division (docs/performance.md, "Ray casts").
template <Real T>
PLUME_INLINE GRayHit<T> ray_cast_local(GCapsule<T> const& cap, GRay3<T> const& ray, T max_toi,
                                       bool solid = true) noexcept {
  using V = GVec3<T>;
  V const& o = ray.origin;
  V const& d = ray.dir;
  T const zero = plume::zero<T>(), h = cap.half_height, r = cap.radius;
  T const cy = plume::clamp_select(o.y, -h, h); // (a NaN lane is invalid already)
  auto const inside = (V{o.x, o.y - cy, o.z}.length_squared() <= r * r);
  detail::pre_hit<T> hit;
  if (solid) {
    // From outside, the capsule (the union of the finite cylinder and the end spheres, all
    // convex) is entered where the first of them is: the side where its entry lies within
    // |y| <= h (the cylinder's flat ends are inside the spheres), or an end sphere. Three
    // entry roots, each independent of the others (one quadric deep), and their minimum.
    T const inf = infinity<T>();
    // Not const (see the header), like top and bottom.
    auto side = detail::quadric_entry<true>(o, d, r);
    auto top = detail::quadric_entry<false>(V{o.x, o.y - h, o.z}, d, r);
    auto bottom = detail::quadric_entry<false>(V{o.x, o.y + h, o.z}, d, r);
    T const t_side = plume::select(side.ok & (plume::abs(o.y + d.y * side.t) <= h), side.t, inf);
    T const t_ends =
        detail::min_of(plume::select(top.ok, top.t, inf), plume::select(bottom.ok, bottom.t, inf));
    // No entry leaves +infinity, a miss; so is an entry at +infinity and a NaN max_toi. An
    // end sphere's entry implies a finite ray (quadric_entry), and so does the side's where
    // its height passes the test (the side's roots see only x and z, but a non-finite o.y or
    // d.y makes that height infinite or NaN); so, as for spheres, only the direction of the
    // inside lanes is left to test: their toi is b - b of the top sphere (o is finite there),
    // NaN for a non-finite direction.
    T const entry = detail::min_of(t_side, t_ends);
    T const toi = plume::select(inside, top.b - top.b, entry);
    hit.hit = toi <= plume::min_select(max_value<T>(), max_toi);
    hit.toi = plume::select(hit.hit, toi, inf);
    hit.at = entry; // where the normal is kept, the origin is outside: toi is the entry
    hit.leaving = no_lanes<T>();
    hit.bare = inside;
  } else {
    auto const side = detail::quadric_roots<true>(o, d, r);
    // Both end spheres, independent of the side's roots (a wide kernel's latency chain is then
    // one quadric deep, not two); each crossing picks its sphere's roots below.
    auto const top = detail::sphere_part(V{o.x, o.y - h, o.z}, d, r);
    auto const bottom = detail::sphere_part(V{o.x, o.y + h, o.z}, d, r);
    auto const axial = (d.x == zero) & (d.z == zero);
    // The end sphere crossed (true: the top): on the side of the cylinder's crossing, or for a
    // ray along the axis the end facing the ray (entering) or away from it (leaving).
    auto const top_faces = d.y < zero; // the ray moves down, towards the top end's outside
    auto const top_crossed = [&](T t_side, bool entering) {
      T const y = o.y + d.y * t_side;
      return plume::select(axial, entering ? top_faces : !top_faces, !(y < zero));
    };
    auto const on_side = [&](T t_side) { return side.ok & (plume::abs(o.y + d.y * t_side) <= h); };
    mask_t<T> const reach = side.ok | axial;
    mask_t<T> const top_in = top_crossed(side.tin, true);
    mask_t<T> const side_in = on_side(side.tin);
    detail::ray_interval<T> iv;
    iv.tin = plume::select(side_in, side.tin, plume::select(top_in, top.tin, bottom.tin));
    iv.ok = reach & (side_in | plume::select(top_in, top.ok, bottom.ok));
    mask_t<T> const top_out = top_crossed(side.tout, false);
    mask_t<T> const side_out = on_side(side.tout);
    iv.tout = plume::select(side_out, side.tout, plume::select(top_out, top.tout, bottom.tout));
    iv.ok = iv.ok & (side_out | plume::select(top_out, top.ok, bottom.ok));
    hit = detail::finish(detail::ray_valid(ray), inside, iv, max_toi, false);
  }
  // The outward normal (p - nearest point of the segment) / r, made unit (unit_normal); a
  // zero radius has none.
  V const p = ray.at(hit.at);
  T const inv_r = one<T>() / r;
  T const cy_hit = plume::clamp_select(p.y, -h, h);
  V const n = detail::unit_normal(V{p.x, p.y - cy_hit, p.z} * inv_r,
                                  plume::and_not(hit.hit, hit.bare) & (r > zero));
  T const part = plume::select(p.y > h, one<T>(), plume::select(p.y < -h, two<T>(), zero));
  return detail::with_normal(hit, n, part, r > zero);
}

/// Cylinder (local frame: radius r around Y, caps at y = +-h): the intersection of the
/// infinite cylinder's interval and the slab |y| <= h. A ray along the axis is parallel to
/// the side (inside or outside the radius), one with dir.y = 0 parallel to the caps.
template <Real T>
PLUME_INLINE GRayHit<T> ray_cast_local(GCylinder<T> const& cyl, GRay3<T> const& ray, T max_toi,
                                       bool solid = true) noexcept {
  using V = GVec3<T>;
  V const& o = ray.origin;
  V const& d = ray.dir;
  T const zero = plume::zero<T>(), inf = infinity<T>(), h = cyl.half_height, r = cyl.radius;
  auto side = detail::quadric_roots<true>(o, d, r);
  auto const axial = (d.x == zero) & (d.z == zero);
  auto const in_disc = o.x * o.x + o.z * o.z <= r * r;
  side.ok = plume::select(axial, in_disc, side.ok);
  side.tin = plume::select(axial, -inf, side.tin);
  side.tout = plume::select(axial, inf, side.tout);
  auto const caps = detail::slab_interval(o.y, d.y, -h, h);
  auto const cap_in = caps.tin > side.tin, cap_out = caps.tout < side.tout;
  T const tin = plume::select(cap_in, caps.tin, side.tin);
  T const tout = plume::select(cap_out, caps.tout, side.tout);
  T const up = plume::select(d.y < zero, one<T>(), -one<T>()); // the cap entered faces -dir
  // An outside parallel cap slab starts at +infinity: interval_met rejects it.
  mask_t<T> const meets = side.ok & detail::interval_met(tin, tout);
  detail::ray_interval<T> iv{meets, tin, tout};
  auto const inside = in_disc & (plume::abs(o.y) <= h);
  auto hit = detail::finish(detail::ray_valid(ray), inside, iv, max_toi, solid); // not const
  auto const on_cap = plume::select(hit.leaving, cap_out, cap_in);
  V const p = ray.at(hit.toi);
  V const n = V::select(on_cap, V{zero, plume::select(hit.leaving, -up, up), zero},
                        V{p.x, zero, p.z}.normalize_or(V{}));
  T const part = plume::select(on_cap, plume::select(n.y > zero, one<T>(), two<T>()), zero);
  return detail::with_normal(hit, n, part);
}

/// Half-space (local frame: the solid n . p <= 0).
template <Real T>
PLUME_INLINE GRayHit<T> ray_cast_local(GHalfSpace<T> const& hs, GRay3<T> const& ray, T max_toi,
                                       bool solid = true) noexcept {
  T const zero = plume::zero<T>(), inf = infinity<T>();
  T const s = hs.normal.dot(ray.origin), dn = hs.normal.dot(ray.dir);
  T const t = -s / dn;
  auto const inside = s <= zero;
  // Outside: entered at t when moving towards the plane. Inside: left at t when moving out.
  detail::ray_interval<T> iv;
  // (An entry so far that t overflows, from a tiny dn, is a miss.)
  mask_t<T> const entering = (dn < zero) & (t < inf);
  iv.ok = plume::select(inside, dn > zero, entering);
  iv.tin = plume::select(inside, -inf, t);
  iv.tout = plume::select(inside, t, inf);
  return detail::with_normal(detail::finish(detail::ray_valid(ray), inside, iv, max_toi, solid),
                             hs.normal);
}

namespace detail {
/// Edge test of the watertight triangle cast for an edge function e exactly 0: the ray
/// passes through the edge (ex, ey) (sheared 2D coordinates, oriented so the triangle is on
/// its left). Exactly one of an edge and its reverse owns such rays, so a ray through an
/// edge shared by two consistently wound triangles, or through a vertex shared by a fan,
/// hits exactly one of them.
template <Real T>
PLUME_INLINE mask_t<T> owns_edge(T ex, T ey) noexcept {
  T const zero = plume::zero<T>();
  return (ey > zero) | ((ey == zero) & (ex > zero));
}
} // namespace detail

namespace detail {
/// The unit normal of (b - a) x (c - a) computed in double, rounded to float: what a mesh
/// stores as a triangle's face normal (spatial/triangle_mesh.hpp, unit_face_normal); zero
/// for a triangle whose double cross product is zero.
inline GVec3<float> unit_normal_in_double(GVec3<float> const& a, GVec3<float> const& b,
                                          GVec3<float> const& c) noexcept {
  GVec3<double> const da{a.x, a.y, a.z}, db{b.x, b.y, b.z}, dc{c.x, c.y, c.z};
  GVec3<double> const n = (db - da).cross(dc - da).normalize_or_zero();
  return {static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)};
}

/// A triangle's unit normal along (b - a) x (c - a) (zero for a degenerate triangle). The
/// float cross product loses every digit where its products cancel (a sliver beside a very
/// long edge: docs/fuzzing.md, regress-back-face-sliver-normal), which can turn the normal
/// and the back-face flag. Its error is below about 5 eps |b - a| |c - a|, so where |n|^2 >=
/// 2^-16 |b - a|^2 |c - a|^2 (the angle at a at least 2^-8 from 0 and 180 degrees) the float
/// normal is within about 1.5e-4 rad; the other lanes (those, and products that overflow or
/// underflow) take the normal in double, the mesh's face normal bit for bit. Lane by lane,
/// so any width gives the scalar bits.
template <Real T>
PLUME_INLINE GVec3<T> triangle_unit_normal(GTriangle<T> const& tri) noexcept {
  using V = GVec3<T>;
  using S = scalar_t<T>;
  V const e1 = tri.b - tri.a, e2 = tri.c - tri.a;
  V const m = e1.cross(e2);
  V n = m.normalize_or(V{});
  if constexpr (std::is_same_v<S, float>) {
    T const m2 = m.length_squared();
    mask_t<T> const sure =
        plume::is_finite(m2) & (m2 >= plume::splat<T>(std::numeric_limits<float>::min())) &
        (m2 >= plume::splat<T>(0x1p-16f) * (e1.length_squared() * e2.length_squared()));
    if (!plume::all(sure)) [[unlikely]] {
      for (std::size_t i = 0; i < lanes_v<T>; ++i)
        if (!plume::lane(sure, i))
          n = plume::with_lane(n, i,
                               unit_normal_in_double(plume::lane(tri.a, i), plume::lane(tri.b, i),
                                                     plume::lane(tri.c, i)));
    }
  }
  return n;
}

/// The watertight triangle test after its set-up (ray_cast_local(GTriangle) below): A, B, C
/// are the vertices minus the ray's origin with their components permuted so that z is the
/// ray's largest axis (x, y the next ones, swapped when it points down z); (sx, sy, sz) the
/// shear (d_x / d_z, d_y / d_z, 1 / d_z in that order); facing the unit normal turned to face
/// the ray, back whether it was turned, valid the ray's validity. Split out so that a caller
/// that casts one ray against many triangles (a mesh's triangle blocks) sets the ray up once
/// and permutes by choosing arrays, with the same arithmetic per lane.
template <Real T>
PLUME_INLINE GRayHit<T> watertight_sheared(GVec3<T> const& A, GVec3<T> const& B, GVec3<T> const& C,
                                           T sx, T sy, T sz, GVec3<T> const& facing, mask_t<T> back,
                                           mask_t<T> valid, T max_toi) noexcept {
  using M = mask_t<T>;
  using S = scalar_t<T>;
  T const zero = plume::zero<T>();
  T const Ax = A.x - sx * A.z, Ay = A.y - sy * A.z;
  T const Bx = B.x - sx * B.z, By = B.y - sy * B.z;
  T const Cx = C.x - sx * C.z, Cy = C.y - sy * C.z;
  T U = Cx * By - Cy * Bx;
  T W_ = Bx * Ay - By * Ax;
  T Vv = Ax * Cy - Ay * Cx;
  // An edge function exactly zero is rare (a ray through an edge or a vertex, or one that
  // float cannot tell from one), and only there does the edge need more work: a recompute
  // in double, then the ownership rule. Both wait behind one branch on any lane, so the
  // common case costs a compare; lanes with no zero are unchanged by either.
  M const exact_zero = (U == zero) | (Vv == zero) | (W_ == zero);
  bool const any_zero = plume::any(exact_zero);
  if constexpr (std::is_same_v<S, float>) {
    if (any_zero) [[unlikely]] {
      for (std::size_t i = 0; i < lanes_v<T>; ++i) {
        if (!plume::lane(exact_zero, i)) continue;
        auto const dd = [&](T const& x) { return static_cast<double>(plume::lane(x, i)); };
        U = plume::with_lane(U, i, static_cast<S>(dd(Cx) * dd(By) - dd(Cy) * dd(Bx)));
        Vv = plume::with_lane(Vv, i, static_cast<S>(dd(Ax) * dd(Cy) - dd(Ay) * dd(Cx)));
        W_ = plume::with_lane(W_, i, static_cast<S>(dd(Bx) * dd(Ay) - dd(By) * dd(Ax)));
      }
    }
  }
  T const det = (U + Vv) + W_;
  // The distance first: it frees the sheared z coordinates before the edge tests.
  T const tn = (U * (sz * A.z) + Vv * (sz * B.z)) + W_ * (sz * C.z);
  T const t = tn / det;
  // Orient so the triangle is positive (det > 0): inside means every edge function >= 0.
  M const pos = det > zero;
  T const su = plume::select(pos, U, -U), sv = plume::select(pos, Vv, -Vv),
          sw = plume::select(pos, W_, -W_);
  M inside = (su > zero) & (sv > zero) & (sw > zero);
  if (any_zero) [[unlikely]] {
    // Edges opposite A, B, C: B -> C, C -> A, A -> B (reversed for a negative triangle); an
    // edge function still zero passes where the ray is on an edge this triangle owns.
    auto const edge_ok = [&](T e, T x0, T y0, T x1, T y1) {
      T const ex = plume::select(pos, x1 - x0, x0 - x1), ey = plume::select(pos, y1 - y0, y0 - y1);
      return (e > zero) | ((e == zero) & detail::owns_edge(ex, ey));
    };
    inside =
        edge_ok(su, Bx, By, Cx, Cy) & edge_ok(sv, Cx, Cy, Ax, Ay) & edge_ok(sw, Ax, Ay, Bx, By);
  }
  // A toi that overflows float (a direction too short for the distance: for a subnormal d_z,
  // sz = 1 / d_z is +infinity already) is a miss, as in every closed form: t <= min(FLT_MAX,
  // max_toi), which keeps a NaN max_toi (a miss) and differs from t <= max_toi only for
  // t = +infinity with max_toi = +infinity.
  M hit = valid & inside & (det != zero) & (t >= zero) &
          (t <= plume::min_select(max_value<T>(), max_toi)); // not const (see the top)
  return {hit, plume::select(hit, t, infinity<T>()), detail::keep_where(hit, facing),
          plume::select(hit, plume::select(back, one<T>(), zero), -one<T>())};
}
} // namespace detail

/// Triangle, watertight (Woop, Benthin and Wald 2013): the vertices are moved to the ray
/// origin, the axes permuted so the largest direction component is z, and sheared so the ray
/// is the z axis; the edge functions U, V, W are 2D cross products of the sheared vertices.
/// Where one is exactly zero in float it is recomputed in double (exact products), and an
/// edge-ownership rule makes rays through shared edges and vertices hit exactly one triangle
/// of a consistently wound mesh: no leaks, no double hits. Both windings are hit; solid is
/// ignored (a triangle has no inside); the normal is the unit geometric normal turned to face
/// the ray. Rays in the triangle's plane and zero-area triangles miss, and so does a hit whose
/// toi overflows float (a subnormal direction), as in the closed forms.
template <Real T>
PLUME_INLINE GRayHit<T> ray_cast_local(GTriangle<T> const& tri, GRay3<T> const& ray, T max_toi,
                                       bool = true) noexcept {
  using V = GVec3<T>;
  using M = mask_t<T>;
  T const zero = plume::zero<T>();
  V const& d = ray.dir;
  // The normal and the ray's validity first, so that the vertices and the ray need not stay
  // live to the end for them.
  V const n = detail::triangle_unit_normal(tri);
  M const back = n.dot(d) > zero; // coming from behind: the back face
  V const facing = V::select(back, -n, n);
  M const valid = detail::ray_valid(ray);
  // kz: the axis of the largest |d| (first on ties); kx, ky the next ones cyclically, swapped
  // when d[kz] < 0 so the winding is kept.
  T const ax = plume::abs(d.x), ay = plume::abs(d.y), az = plume::abs(d.z);
  M const kz_x = (ax >= ay) & (ax >= az);
  M const kz_y = (ay >= az) & (!kz_x);
  auto const pz = [&](V const& p) {
    return plume::select(kz_x, p.x, plume::select(kz_y, p.y, p.z));
  };
  auto const px0 = [&](V const& p) {
    return plume::select(kz_x, p.y, plume::select(kz_y, p.z, p.x));
  };
  auto const py0 = [&](V const& p) {
    return plume::select(kz_x, p.z, plume::select(kz_y, p.x, p.y));
  };
  T const dz = pz(d);
  M const flip = dz < zero;
  auto const px = [&](V const& p) { return plume::select(flip, py0(p), px0(p)); };
  auto const py = [&](V const& p) { return plume::select(flip, px0(p), py0(p)); };
  auto const perm = [&](V const& p) { return V{px(p), py(p), pz(p)}; };
  T const sx = px(d) / dz, sy = py(d) / dz, sz = one<T>() / dz;
  return detail::watertight_sheared(perm(tri.a - ray.origin), perm(tri.b - ray.origin),
                                    perm(tri.c - ray.origin), sx, sy, sz, facing, back, valid,
                                    max_toi);
}

/// Any shape at a pose: the ray is moved into the shape frame, the normal back out.
template <class Shape, Real T>
PLUME_INLINE GRayHit<T> ray_cast(Shape const& shape, GIso3<T> const& pose, GRay3<T> const& ray,
                                 T max_toi, bool solid = true) noexcept {
  GRay3<T> const local{pose.inverse_transform_point(ray.origin),
                       pose.inverse_transform_vector(ray.dir)};
  GRayHit<T> h = ray_cast_local(shape, local, max_toi, solid);
  h.normal = pose.transform_vector(h.normal);
  return h;
}

/// An axis-aligned box in world space (the slab test of GCuboid without a pose).
template <Real T>
PLUME_INLINE GRayHit<T> ray_cast(GAabb3<T> const& box, GRay3<T> const& ray, T max_toi,
                                 bool solid = true) noexcept {
  return detail::box_cast(box.min, box.max, ray, max_toi, solid);
}

} // namespace plume

PLUME_MASK_CODE_END
