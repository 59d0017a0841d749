// plume/collision/gjk.hpp - the GJK family over any two convex shapes, generic over T: with a
// wide T every lane runs its own query (its own shapes, poses and motion), all lanes iterate
// until each has finished, and a finished lane is frozen by masks, so lane i equals the
// scalar query on lane i's inputs bit for bit.
//
//   closest_points(a, pose_a, b, pose_b [, cfg, axis])  distance, closest points, normal
//   shape_cast(a, pose_a, motion_a, b, pose_b, cfg)      first time A, moving by t motion_a,
//                                                        comes within target_distance of B
//   ray_cast_gjk(shape, pose, ray, max_toi, solid)       ray cast against any convex shape
//
// Shapes: anything with core_support(dir) and core_radius() (collision/shapes.hpp: sphere,
// capsule, cuboid, cylinder, triangle, segment; collision/convex_hull.hpp: polytopes and
// hulls). GJK runs on the cores and adds the radii afterwards, so spheres and capsules are
// exact (a point and a segment) and a rounded shape never slows convergence.
//
// Algorithms: closest points by GJK (Gilbert, Johnson, Keerthi 1988) with the relative stop
// of van den Bergen (|v|^2 - v.w small); casts by the GJK ray cast (van den Bergen 2004): the
// ray point x advances to the support plane of the set swept (D = B - A, inflated by the radii
// and the target distance) whenever it is outside it, so x never enters D and the time of
// impact is never late. Stop rules are absolute (`tolerance`, in length units) rather than
// relative to the size of the shapes, so large shapes are as accurate as small ones (a
// relative stop is what makes some engines' casts millimetres short on 500 m boxes).
//
// Bad input: a non-finite pose, motion, ray or shape parameter gives `failed` in that lane
// (NaN results, no hit), other lanes untouched; so do coordinates so large that their squares
// overflow (beyond about 1e19 length units from the origin). Every query stops after max_iterations
// and says so. Cores that overlap (penetration deeper than the radii) are reported as overlap /
// penetrating with a zero normal: their depth and normal need EPA.
//
// Locals here and in detail/simplex.hpp are not const: simplex vertices, steps and the masks
// built into them are copied whole (docs/performance.md, "GJK").
#pragma once

#include <plume/collision/detail/simplex.hpp>
#include <plume/collision/ray_cast.hpp>
#include <plume/collision/shapes.hpp>
#include <plume/math/iso3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <concepts>

PLUME_MASK_CODE_BEGIN

namespace plume {

/// A convex shape the GJK family can query: a core with a support function and a radius.
template <class Shape, class T>
concept ConvexShape = Real<T> && requires(Shape const& s, GVec3<T> const& d) {
  { s.core_support(d) } -> std::convertible_to<GVec3<T>>;
  { s.core_radius() } -> std::convertible_to<T>;
};

struct GjkConfig {
  int max_iterations = 64;
  /// Absolute accuracy of distances and of a cast's contact point, in length units. Where
  /// the coordinates are so large that float cannot resolve it (16 eps |coordinates| above
  /// it: beyond about 5 m for the default), the rounding floor takes its place.
  float tolerance = 1e-5f;
  /// Closest points also stop when the distance is known to this relative accuracy.
  float relative_tolerance = 1e-6f;

  /// This config with every length-valued field (tolerance) multiplied by length_unit.
  GjkConfig scaled(float length_unit) const noexcept {
    GjkConfig c = *this;
    c.tolerance *= length_unit;
    return c;
  }
};

/// Result of closest_points, per lane.
template <Real T>
struct GClosestPoints {
  /// Between the (rounded) shapes: positive apart, negative when only the radii overlap (then
  /// exactly minus the depth); 0 when the cores overlap (see overlap). NaN when failed.
  T distance;
  GVec3<T> point_a; ///< world, on A's surface (inside B when distance < 0)
  GVec3<T> point_b; ///< world, on B's surface
  GVec3<T> normal;  ///< unit, from A toward B; zero when the cores overlap
  /// The last search direction: pass it as `axis` to the next query on the same pair (warm
  /// start: a pair that moved a little converges in one or two iterations).
  GVec3<T> axis;
  mask_t<T> overlap; ///< the cores intersect
  /// false: stopped by max_iterations, or by steps that stopped getting closer while the
  /// distance was not yet known to the tolerance (the result is then the best seen), or failed
  mask_t<T> converged;
  mask_t<T> failed; ///< non-finite input
  T iterations;
};

/// The contact of a shape cast, per lane. Exactly one of converged / penetrating /
/// out_of_iterations / failed holds in each lane.
template <Real T>
struct GShapeCastHit {
  mask_t<T> hit;
  T toi; ///< time of impact in units of motion (0 when starting in contact); +inf on a miss
  GVec3<T> normal;     ///< unit, from A toward B at the contact; zero on a miss or deep penetration
  GVec3<T> point_a;    ///< world, on A at toi (A moved by toi * motion)
  GVec3<T> point_b;    ///< world, on B
  mask_t<T> converged; ///< a normal answer (hit or miss)
  mask_t<T>
      penetrating; ///< started within target_distance (toi 0); normal zero if the cores overlap
  /// Stopped by the iteration cap, or by steps that stopped getting closer while the gap was
  /// above the tolerance: reported as a hit at a lower bound of the time of impact
  /// (conservative: it may be a miss, never a later hit); normal and points where it stopped.
  mask_t<T> out_of_iterations;
  mask_t<T> failed; ///< non-finite input: no hit
  T iterations;
};

/// Whether a motion moves into a surface it touches: its speed into the surface (`closing`,
/// the motion against the surface's outward normal, positive inward) is positive and steeper
/// than 1e-3 rad (closing^2 > 1e-6 |motion|^2, with motion_length_squared = |motion|^2).
/// Casts and move queries ignore a start in contact that does not (ShapeCastConfig::
/// stop_at_penetration false): the motion leaves the surface or runs along it, within the
/// rounding a contact normal carries. NaN: true (the contact is kept, the safe side).
template <Real T>
PLUME_INLINE mask_t<T> moves_into_surface(T closing, T motion_length_squared) noexcept {
  using S = scalar_t<T>;
  return !((closing <= splat<T>(S(0))) |
           (closing * closing <= splat<T>(S(1e-6)) * motion_length_squared));
}

struct ShapeCastConfig {
  float max_toi = 1.0f;         ///< in units of motion
  float target_distance = 0.0f; ///< report contact at this gap (a skin), length units
  /// A cast that starts within target_distance: true reports it (toi 0); false ignores it
  /// when the motion does not move the shapes further in (it moves out along the contact
  /// normal, or along the surface within 1e-3 rad: a character sliding along a wall it
  /// touches).
  bool stop_at_penetration = true;
  GjkConfig gjk{};
};

namespace detail {

/// GJK steps in a row that may fail to get closer before a query stops unconverged.
inline constexpr int max_stalls = 4;

/// A shape placed by a pose: world core support points.
template <class Shape, Real T>
struct placed {
  Shape const& shape;
  GIso3<T> const& pose;
  PLUME_INLINE GVec3<T> support(GVec3<T> const& d) const noexcept {
    return pose.transform_point(shape.core_support(pose.inverse_transform_vector(d)));
  }
};

template <Real T>
PLUME_INLINE mask_t<T> finite3(GVec3<T> const& v) noexcept {
  return (plume::is_finite(v.x) & plume::is_finite(v.y)) & plume::is_finite(v.z);
}

/// The lanes where a shape's parameters are finite: its is_finite() where it has one (every
/// shape of shapes.hpp; a built hull is finite by construction), else every lane.
template <Real T, class Shape>
PLUME_INLINE mask_t<T> shape_finite(Shape const& s) noexcept {
  if constexpr (requires {
                  { s.is_finite() } -> std::convertible_to<mask_t<T>>;
                })
    return s.is_finite();
  else
    return all_lanes<T>();
}

/// The vertex of D = B - A along d: p = sB(d) - sA(-d).
template <class SA, class SB, Real T>
PLUME_INLINE simplex_vertex<T> minkowski_vertex(SA const& sa, SB const& sb,
                                                GVec3<T> const& d) noexcept {
  GVec3<T> a = sa.support(-d);
  GVec3<T> b = sb.support(d);
  return {b - a, a, b};
}

/// A support "shape" that is the origin (a ray cast has no A).
template <Real T>
struct origin_support {
  PLUME_INLINE GVec3<T> support(GVec3<T> const&) const noexcept { return {}; }
};

/// The GJK ray cast of x(t) = origin + t r against D (given by sa, sb) inflated by radius,
/// t in [0, max_toi]. n: the last separating direction (outward from D at the hit).
template <Real T>
struct cast_state {
  mask_t<T> hit, started_inside, cores_overlap, out_of_iterations, failed;
  T toi;
  GVec3<T> n;
  GVec3<T> pa, pb; ///< closest points on the cores (A at its start pose)
  T iterations;
};

template <class SA, class SB, Real T>
PLUME_INLINE cast_state<T> gjk_cast(SA const& sa, SB const& sb, GVec3<T> const& origin,
                                    GVec3<T> const& r, T max_toi, T radius, GVec3<T> v0,
                                    mask_t<T> bad_input, GjkConfig const& cfg) noexcept {
  using S = scalar_t<T>;
  T zero = plume::zero<T>();
  T tol = splat<T>(S(cfg.tolerance));
  T floor_k = splat<T>(S(16)) * epsilon<T>();

  cast_state<T> out;
  out.hit = no_lanes<T>();
  out.started_inside = no_lanes<T>();
  out.cores_overlap = no_lanes<T>();
  out.out_of_iterations = no_lanes<T>();
  out.failed = bad_input;
  out.toi = zero;
  out.n = GVec3<T>{};
  out.pa = GVec3<T>{};
  out.pb = GVec3<T>{};
  out.iterations = zero;

  simplex<T> s;
  GVec3<T> x = origin;
  GVec3<T> v = GVec3<T>::select(v0.dot(v0) > zero, v0, -r);
  v = GVec3<T>::select(v.dot(v) > zero, v,
                       GVec3<T>{plume::one<T>(), plume::zero<T>(), plume::zero<T>()});
  T d2_ref = infinity<T>(); // |v|^2 of the simplex at the current x (+inf: none yet)
  mask_t<T> active = !bad_input;
  mask_t<T> advanced_ever = no_lanes<T>();
  T stalls = zero; // steps in a row that neither advanced x nor got closer to it
  mask_t<T> gave_up = no_lanes<T>();

  for (int it = 0; it < cfg.max_iterations; ++it) {
    if (plume::none(active)) break;
    out.iterations = plume::select(active, out.iterations + one<T>(), out.iterations);
    simplex_vertex<T> w = minkowski_vertex(sa, sb, v);
    GVec3<T> y = x - w.p;
    T vl = plume::sqrt(v.dot(v));
    // (Squares that overflow: coordinates beyond about 1e19, which float cannot query.)
    mask_t<T> bad =
        !((finite3(w.p) & finite3(v)) & (plume::is_finite(vl) & plume::is_finite(y.dot(y))));
    T vy = v.dot(y);
    T vr = v.dot(r);
    mask_t<T> outside = vy > radius * vl;
    mask_t<T> receding = outside & (vr >= zero);
    T t_new = out.toi - (vy - radius * vl) / plume::select(outside & (vr < zero), vr, -one<T>());
    // An advance to where |x|^2 overflows (beyond about 1e19, or a time beyond float's largest
    // when the motion is tiny) passes every point float can query, so D, if it is ever
    // reached, is reached there: a miss, whatever max_toi (+inf included).
    GVec3<T> x_new = origin + r * t_new;
    mask_t<T> beyond = !(x_new.dot(x_new) < infinity<T>());
    mask_t<T> too_far = outside & (!receding) & ((t_new > max_toi) | beyond);
    mask_t<T> miss = active & (receding | too_far) & (!bad);
    mask_t<T> advance = active & outside & (!receding) & (!too_far) & (!bad);
    // Advance: x moves to the (inflated) support plane; the simplex points stay (they are
    // points of D), only their offsets from x change.
    out.toi = plume::select(advance, t_new, out.toi);
    x = GVec3<T>::select(advance, x_new, x);
    out.n = GVec3<T>::select(advance, v, out.n);
    d2_ref = plume::select(advance, infinity<T>(), d2_ref);
    advanced_ever = advanced_ever | advance;

    simplex_step<T> step = closest_on_simplex(s, w, x);
    T nd2 = step.v.dot(step.v);
    mask_t<T> live = active & (!miss) & (!bad);
    // Close enough: within tolerance of the inflated set, or of its rounding floor (16 eps of
    // the coordinates in play) where float cannot resolve the tolerance.
    T floor = floor_k * plume::sqrt(x.dot(x) + w.p.dot(w.p));
    T reach = radius + plume::max_select(tol, floor);
    mask_t<T> close = (nd2 <= reach * reach) | step.inside;
    // A step that neither advances x nor gets closer to it: float could not resolve the gain
    // (as in closest_points). Taken anyway; after max_stalls in a row the cast stops where x
    // is, a lower bound of the time of impact, as at the iteration cap.
    mask_t<T> stalled = (!advance) & (nd2 >= d2_ref);
    stalls = plume::select(stalled, stalls + one<T>(), plume::zero<T>());
    mask_t<T> give_up = live & (((!close) & stalled) & (stalls >= splat<T>(S(max_stalls))));
    mask_t<T> done_hit = live & close;
    mask_t<T> take = live & (!give_up);
    auto const [pa, pb] = closest_points(s, w, step.lambda);
    out.pa = GVec3<T>::select(take, pa, out.pa);
    out.pb = GVec3<T>::select(take, pb, out.pb);
    s.v[0] = simplex_vertex<T>{GVec3<T>::select(take, step.next.v[0].p, s.v[0].p),
                               GVec3<T>::select(take, step.next.v[0].a, s.v[0].a),
                               GVec3<T>::select(take, step.next.v[0].b, s.v[0].b)};
    for (std::size_t k = 1; k < 3; ++k) {
      s.v[k] = simplex_vertex<T>{GVec3<T>::select(take, step.next.v[k].p, s.v[k].p),
                                 GVec3<T>::select(take, step.next.v[k].a, s.v[k].a),
                                 GVec3<T>::select(take, step.next.v[k].b, s.v[k].b)};
    }
    for (std::size_t k = 0; k < 3; ++k)
      s.present[k] = plume::select(take, step.next.present[k], s.present[k]);
    // x inside the simplex before any advance: the cores overlap at the start (after an
    // advance, x "inside" only means it sits on the surface, within rounding).
    // Or x (nearly) on the simplex, where the core distance is rounding noise and gives no
    // direction.
    mask_t<T> on_core =
        nd2 <= (splat<T>(S(64)) * epsilon<T>()) * (splat<T>(S(64)) * epsilon<T>()) * y.dot(y);
    mask_t<T> inside_now = done_hit & (step.inside | on_core) & (!advanced_ever);
    out.cores_overlap = out.cores_overlap | inside_now;
    out.started_inside = out.started_inside | (done_hit & (!advanced_ever));
    // A hit within the radius of the cores: the normal is the direction from the final simplex
    // to x, sharper than the last advance's (by the angle x moved through), where that direction is
    // resolved (|v| above 64 times the rounding floor; else, as for a hit with no radius, v is
    // noise and the advance direction stays).
    T resolved_d2 = (splat<T>(S(64)) * floor) * (splat<T>(S(64)) * floor);
    mask_t<T> resolved = nd2 > resolved_d2;
    out.n = GVec3<T>::select((done_hit & advanced_ever) & resolved, step.v, out.n);
    // A graze: x within reach but moving away from the simplex's closest point c
    // (v . r > 0), so the ray was nearer c before x. The hit moves back to the ray's closest
    // approach to c, t* = t - (v . r) / (r . r), where the distance to c is at most |v| (still
    // within reach) and the direction from c (v less its part along r) is across the ray:
    // not a normal past the tangent. (D may still be entered later along the ray; this
    // earlier time is within reach anyway.) A t* at or before the start means the start is
    // within reach: a start in contact (toi 0), as any other.
    T vr_hit = step.v.dot(r);
    T rr = r.dot(r);
    mask_t<T> receding_hit =
        (((done_hit & advanced_ever) & resolved) & (vr_hit > zero)) & (rr > zero);
    if (plume::any(receding_hit)) {
      T back = vr_hit / plume::select(receding_hit, rr, one<T>());
      GVec3<T> across = step.v - r * back;
      mask_t<T> graze = receding_hit & (across.dot(across) > resolved_d2);
      T t_star = out.toi - back;
      out.started_inside = out.started_inside | (graze & (t_star <= zero));
      out.toi = plume::select(graze, plume::max_select(t_star, zero), out.toi);
      out.n = GVec3<T>::select(graze, across, out.n);
    }
    v = GVec3<T>::select(take, step.v, v);
    d2_ref = plume::select(take, nd2, d2_ref);
    out.failed = out.failed | (active & bad);
    out.hit = out.hit | done_hit;
    gave_up = gave_up | give_up;
    active = active & (!(((miss | done_hit) | give_up) | bad));
  }
  out.out_of_iterations = active | gave_up;
  // Stopped unconverged before any advance: no advance direction; the last search direction
  // (out of D) stands in, so that a zero normal keeps meaning overlapping cores.
  out.n = GVec3<T>::select(out.out_of_iterations & (!advanced_ever), v, out.n);
  // An unfinished lane is a hit at its toi so far: x never enters D, so that toi is a lower
  // bound of the time of impact (0 if x never advanced), and a caller that stops there cannot
  // pass through B.
  out.hit = (out.hit | out.out_of_iterations) & (!out.failed);
  return out;
}

} // namespace detail

/// Distance, closest points and normal between convex shapes a (at pose_a) and b (at
/// pose_b). `axis`: a warm-start direction (the previous result's axis); zero picks the
/// centre difference.
template <Real T, ConvexShape<T> A, ConvexShape<T> B>
PLUME_FLATTEN GClosestPoints<T> closest_points(A const& a, GIso3<T> const& pose_a, B const& b,
                                               GIso3<T> const& pose_b, GjkConfig const& cfg = {},
                                               GVec3<T> const& axis = {}) noexcept {
  using S = scalar_t<T>;
  T zero = plume::zero<T>();
  detail::placed<A, T> const sa{a, pose_a};
  detail::placed<B, T> const sb{b, pose_b};
  T ra = a.core_radius(), rb = b.core_radius();
  T tol = splat<T>(S(cfg.tolerance));
  T rel = splat<T>(S(cfg.relative_tolerance));
  T eps = epsilon<T>();
  T floor_k = splat<T>(S(16)) * eps;

  mask_t<T> good_input =
      ((pose_a.is_finite() & pose_b.is_finite()) & (plume::is_finite(ra) & plume::is_finite(rb))) &
      (detail::finite3(axis) & (detail::shape_finite<T>(a) & detail::shape_finite<T>(b)));
  mask_t<T> bad_input = !good_input;
  GVec3<T> v =
      GVec3<T>::select(axis.dot(axis) > zero, axis, pose_a.translation - pose_b.translation);
  v = GVec3<T>::select(v.dot(v) > zero, v,
                       GVec3<T>{plume::one<T>(), plume::zero<T>(), plume::zero<T>()});

  detail::simplex<T> s;
  T d2 = infinity<T>();      // |v|^2 of the simplex held
  T best_d2 = infinity<T>(); // the smallest |v|^2 seen, and its v: the answer
  GVec3<T> best_v{};
  T stalls = zero; // steps in a row that did not shrink |v|
  mask_t<T> stalled_out = no_lanes<T>();
  T max_y2 = zero;
  GVec3<T> pa{}, pb{};
  mask_t<T> active = !bad_input;
  mask_t<T> failed = bad_input;
  mask_t<T> overlap = no_lanes<T>();
  mask_t<T> done = no_lanes<T>();
  T iterations = zero;

  for (int it = 0; it < cfg.max_iterations; ++it) {
    if (plume::none(active)) break;
    iterations = plume::select(active, iterations + one<T>(), iterations);
    detail::simplex_vertex<T> w = detail::minkowski_vertex(sa, sb, v);
    GVec3<T> y = -w.p; // a - b
    T y2 = y.dot(y);
    // (A square that overflows: coordinates beyond about 1e19, which float cannot query.)
    mask_t<T> bad = !(detail::finite3(y) & plume::is_finite(y2));
    max_y2 = plume::select(active, plume::max_select(y2, max_y2), max_y2);
    // Stop when the lower bound v.y/|v| is within tolerance of the upper bound |v|.
    T vl = plume::sqrt(d2);
    T gap = d2 - v.dot(y);
    mask_t<T> has_v = d2 < infinity<T>();
    // (Or within the rounding floor, 16 eps of the coordinates in play, where float cannot
    // resolve the tolerance.)
    T floor = floor_k * plume::sqrt(max_y2);
    mask_t<T> bounded = has_v & ((gap <= plume::max_select(tol, floor) * vl) | (gap <= rel * d2));

    detail::simplex_step<T> step = detail::closest_on_simplex(s, w, GVec3<T>{});
    T nd2 = step.v.dot(step.v);
    mask_t<T> no_progress = has_v & (nd2 >= d2);
    mask_t<T> touching =
        step.inside | (nd2 <= (splat<T>(S(64)) * eps) * (splat<T>(S(64)) * eps) * max_y2);
    mask_t<T> ok = active & (!bad);
    // A step that does not shrink |v| while the bounds are still apart. With w already in the
    // simplex, nothing is left to learn: the gap is the rounding of v, and the query has
    // converged as far as float can tell. Otherwise float could not resolve the decrease (a
    // long, thin simplex close to the origin, where the projection's rounding exceeds the
    // step's gain) or a face was skipped as flat; the step's direction is still the better
    // one: take it and keep the best state for the answer; after max_stalls such steps in a
    // row, stop unconverged.
    mask_t<T> settled = no_progress; // (a rare case: the vertex test only then)
    if (plume::any(no_progress)) settled = settled & detail::holds(s, w);
    stalls = plume::select(no_progress, stalls + one<T>(), zero);
    mask_t<T> give_up = (no_progress & (!settled)) & (stalls >= splat<T>(S(detail::max_stalls)));
    mask_t<T> finish = ok & ((bounded | settled) | give_up);
    mask_t<T> take = ok & (!finish);
    auto const [npa, npb] = detail::closest_points(s, w, step.lambda);
    mask_t<T> better = take & (nd2 < best_d2);
    pa = GVec3<T>::select(better, npa, pa);
    pb = GVec3<T>::select(better, npb, pb);
    best_v = GVec3<T>::select(better, step.v, best_v);
    best_d2 = plume::select(better, nd2, best_d2);
    stalled_out = stalled_out | ((ok & give_up) & (!(bounded | settled)));
    for (std::size_t k = 0; k < 3; ++k) {
      s.v[k] = detail::simplex_vertex<T>{GVec3<T>::select(take, step.next.v[k].p, s.v[k].p),
                                         GVec3<T>::select(take, step.next.v[k].a, s.v[k].a),
                                         GVec3<T>::select(take, step.next.v[k].b, s.v[k].b)};
      s.present[k] = plume::select(take, step.next.present[k], s.present[k]);
    }
    v = GVec3<T>::select(take, step.v, v);
    d2 = plume::select(take, nd2, d2);
    mask_t<T> hit_core = take & touching;
    overlap = overlap | hit_core;
    failed = failed | (active & bad);
    done = done | finish | hit_core;
    active = active & (!(finish | hit_core | bad));
  }

  GClosestPoints<T> out;
  T core = plume::sqrt(best_d2);
  v = GVec3<T>::select(best_d2 < infinity<T>(), best_v, v); // (no step taken: the start)
  GVec3<T> n = -v.normalize_or_zero();                      // v = a - b points from B to A
  mask_t<T> apart = (!overlap) & (n.dot(n) > zero);
  out.overlap = overlap | ((!failed) & (!apart));
  out.normal = GVec3<T>::select(out.overlap, GVec3<T>{}, n);
  out.distance = plume::select(out.overlap, zero, (core - ra) - rb);
  out.point_a = pa + out.normal * ra;
  out.point_b = pb - out.normal * rb;
  out.axis = v;
  out.converged = (done & (!failed)) & (!stalled_out);
  out.failed = failed;
  T qnan = nan<T>();
  out.distance = plume::select(failed, qnan, out.distance);
  out.point_a = GVec3<T>::select(failed, GVec3<T>::splat(qnan), out.point_a);
  out.point_b = GVec3<T>::select(failed, GVec3<T>::splat(qnan), out.point_b);
  out.normal = GVec3<T>::select(failed, GVec3<T>{}, out.normal);
  out.iterations = iterations;
  return out;
}

/// The first time of impact of shape a (at pose_a, moving by t * motion_a for t in
/// [0, cfg.max_toi]; B is still: pass the relative motion) with b (at pose_b): the smallest t
/// where their distance is at most cfg.target_distance. A contact only a translation beyond
/// about 1e19 could reach (cfg.max_toi = +inf with a tiny motion) is a miss.
template <Real T, ConvexShape<T> A, ConvexShape<T> B>
PLUME_FLATTEN GShapeCastHit<T>
shape_cast(A const& a, GIso3<T> const& pose_a, GVec3<T> const& motion_a, B const& b,
           GIso3<T> const& pose_b, ShapeCastConfig const& cfg = {}) noexcept {
  using S = scalar_t<T>;
  detail::placed<A, T> const sa{a, pose_a};
  detail::placed<B, T> const sb{b, pose_b};
  T ra = a.core_radius(), rb = b.core_radius();
  T radius = (ra + rb) + splat<T>(S(cfg.target_distance));
  mask_t<T> good_input = ((pose_a.is_finite() & pose_b.is_finite()) &
                          (detail::finite3(motion_a) & plume::is_finite(radius))) &
                         (detail::shape_finite<T>(a) & detail::shape_finite<T>(b));
  mask_t<T> bad_input = !good_input;
  // The ray t * motion_a against D = B - A, from a direction pointing from D to the origin.
  detail::cast_state<T> c =
      detail::gjk_cast(sa, sb, GVec3<T>{}, motion_a, splat<T>(S(cfg.max_toi)), radius,
                       pose_a.translation - pose_b.translation, bad_input, cfg.gjk);
  GShapeCastHit<T> out;
  GVec3<T> n = -c.n.normalize_or_zero(); // c.n points out of D = B - A: from B to A
  // Starting within reach: the normal is the separation direction (none if the cores
  // overlap). The cast stops as soon as it knows the start is within reach, before GJK has
  // found the closest points: they and the normal come from a closest-point query, warm-started
  // from where the cast stopped.
  GVec3<T> core_a = c.pa, core_b = c.pb;
  mask_t<T> cores_overlap = c.cores_overlap;
  GVec3<T> sep = -(c.pa - c.pb).normalize_or_zero();
  mask_t<T> start = c.started_inside & (!(c.failed | c.cores_overlap));
  if (plume::any(start)) {
    GClosestPoints<T> cp = closest_points(a, pose_a, b, pose_b, cfg.gjk, c.pa - c.pb);
    mask_t<T> use = start & (!cp.failed);
    cores_overlap = cores_overlap | (use & cp.overlap);
    sep = GVec3<T>::select(use, cp.normal, sep);
    core_a = GVec3<T>::select(use, cp.point_a - cp.normal * ra, core_a);
    core_b = GVec3<T>::select(use, cp.point_b + cp.normal * rb, core_b);
  }
  GVec3<T> normal =
      GVec3<T>::select(cores_overlap, GVec3<T>{}, GVec3<T>::select(c.started_inside, sep, n));
  // Not moving further in: out along the contact normal, or along the surface (within 1e-3
  // radians: the normal of a started-inside cast carries GJK's rounding, about 1e-5).
  mask_t<T> along = !moves_into_surface(normal.dot(motion_a), motion_a.dot(motion_a));
  mask_t<T> separating = c.started_inside & (!cores_overlap) & along;
  mask_t<T> ignore = cfg.stop_at_penetration ? no_lanes<T>() : separating;
  out.hit = c.hit & (!ignore);
  out.toi = plume::select(out.hit, c.toi, infinity<T>());
  out.normal = GVec3<T>::select(out.hit, normal, GVec3<T>{});
  GVec3<T> moved = motion_a * c.toi;
  out.point_a = GVec3<T>::select(out.hit, core_a + moved + out.normal * ra, GVec3<T>{});
  out.point_b = GVec3<T>::select(out.hit, core_b - out.normal * rb, GVec3<T>{});
  out.failed = c.failed;
  out.penetrating = c.hit & c.started_inside & (!c.failed);
  out.out_of_iterations = c.out_of_iterations & (!c.failed);
  out.converged = (!out.failed) & (!out.penetrating) & (!out.out_of_iterations);
  out.iterations = c.iterations;
  return out;
}

/// A ray cast against any convex shape at a pose by the GJK ray cast (closed forms are in
/// collision/ray_cast.hpp and are faster where they exist). Conventions as in ray_cast.hpp:
/// toi in units of |dir|, outward normal, solid casts from inside hit at 0 with a zero normal,
/// hollow casts from inside hit where the ray leaves the shape. Lanes that hit the iteration
/// cap report their conservative toi as a hit (never later than the true one); a hollow
/// cast's exit search that hits the cap reports no hit, since no exit time is a safe bound.
/// A hit that only a ray point beyond about 1e19 could reach (a tiny direction far from the
/// shape, or a toi that would overflow float) is a miss.
/// feature is -1 (a hull's face can be found from the normal with GConvexHull::support_face).
template <Real T, ConvexShape<T> Shape>
PLUME_FLATTEN GRayHit<T> ray_cast_gjk(Shape const& shape, GIso3<T> const& pose, GRay3<T> const& ray,
                                      T max_toi, bool solid = true,
                                      GjkConfig const& cfg = {}) noexcept {
  T zero = plume::zero<T>();
  detail::origin_support<T> none{};
  detail::placed<Shape, T> const sb{shape, pose};
  T radius = shape.core_radius();
  mask_t<T> good_input = ((pose.is_finite() & detail::finite3(ray.origin)) &
                          (detail::finite3(ray.dir) & plume::is_finite(radius))) &
                         detail::shape_finite<T>(shape);
  mask_t<T> bad_input = (!good_input) | plume::is_nan(max_toi);
  detail::cast_state<T> c = detail::gjk_cast(none, sb, ray.origin, ray.dir, max_toi, radius,
                                             ray.origin - pose.translation, bad_input, cfg);
  GRayHit<T> out;
  out.feature = -one<T>();                              // polytope views have no faces: unknown
  out.hit = (c.hit & (!c.failed)) & (c.toi <= max_toi); // (a start inside: toi 0, max_toi < 0)
  out.toi = plume::select(out.hit, c.toi, infinity<T>());
  out.normal = GVec3<T>::select(out.hit & (!c.started_inside), c.n.normalize_or_zero(), GVec3<T>{});
  if (!solid) {
    // From inside, the exit point: cast back from beyond the shape (its bounding sphere
    // around the start point) toward the origin.
    mask_t<T> inside = out.hit & c.started_inside;
    if (plume::any(inside)) {
      GAabb3<T> box = shape.local_aabb();
      T span = (box.max - box.min).length() + radius * two<T>() +
               (ray.origin - pose.translation).length() * two<T>();
      T dl = plume::sqrt(ray.dir.dot(ray.dir));
      T back = span / plume::select(dl > zero, dl, one<T>()); // in units of dir
      GVec3<T> far = ray.at(back);
      detail::cast_state<T> e =
          detail::gjk_cast(none, sb, far, -ray.dir, back, radius, far - pose.translation,
                           bad_input | (!inside) | (dl == zero), cfg);
      T exit = back - e.toi;
      // A capped back cast's toi is a lower bound, which makes its exit a late one: not found.
      mask_t<T> found = inside & e.hit & (!e.started_inside) & (!e.out_of_iterations);
      mask_t<T> in_range = exit <= max_toi;
      out.hit = (out.hit & (!inside)) | (found & in_range);
      out.toi =
          plume::select(inside, plume::select(found & in_range, exit, infinity<T>()), out.toi);
      out.normal = GVec3<T>::select(inside & found & in_range, e.n.normalize_or_zero(), out.normal);
    }
  }
  return out;
}

using ClosestPoints = GClosestPoints<float>;
using ShapeCastHit = GShapeCastHit<float>;

} // namespace plume

PLUME_MASK_CODE_END
