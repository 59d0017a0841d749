// plume/solver/character/velocity_projection.hpp - the velocity closest to a desired one that does not
// move into any of a set of contact planes (the sliding step of move-and-slide).
//
// Problem: given v and plane normals n_1..n_k (pointing out of the obstacles), find
//     u = argmin |u - v|^2   subject to   n_i . u >= 0 for every i,
// the projection of v onto the polyhedral cone of allowed velocities. At the optimum
// u = v + sum_i lambda_i n_i with lambda_i >= 0 and lambda_i (n_i . u) = 0 (lambda_i is the
// impulse per unit mass plane i applies); u . (u - v) = 0.
//
//   project_velocity(v, normals [, lambda_out], cfg)     the n-step active-set algorithm
//   project_velocity_bruteforce(v, normals, cfg)         the O(k^3) reference
//   both for GVec3<T> and GVec2<T>, T scalar or wide.
//
// The n-step algorithm (after unpairedbracket's "Velocity Projection", the GJK idea on a
// cone): keep an active set of at most two planes (one in 2D) whose exact projection u is
// known; add the most violated plane; replace the active set by the subset of
// {active, new} (the new plane always kept) that satisfies the optimality conditions on
// those planes — the apex, a ray (face), a wedge (crease) or the solid wedge (u = 0) — and
// repeat until no plane is violated by more than cfg.epsilon. Each step is O(k); the most
// violated plane is the one with the smallest n . u, the first in the span on ties. Steps
// seen: at most 4 on the notes' 17-normal test, at most 5 on random contact sets of up to 32
// planes (bench/solver). Unlike Avian's version, every step tests the Lagrange multipliers of each
// candidate subset, so a plane that stops helping is dropped and the answer is the exact
// projection (up to epsilon) whatever the order in which planes become active.
//
// Wide use: lane l projects lane l of v against lane l of every normal. Different lanes may
// have different plane counts: pad with zero normals (a zero normal is never violated and
// never changes a result). Every lane runs until all have finished; finished lanes are
// frozen by masks, and lane l equals, bit for bit, the scalar call on lane l's inputs. A
// wide call costs as many steps as its slowest lane.
//
// Conventions and bad input:
//  - Normals should be unit length (PlaneSet3/PlaneSet2 build such sets). A nonzero normal
//    of any length still acts as the plane it defines (the formulas use n . n); only the
//    violation tolerance scales with |n|. Zero normals are ignored.
//  - epsilon (velocity units, default 0.005 x length unit / s): a plane counts as violated
//    when n . u < -epsilon. With unit normals, a v with |v| < epsilon comes back unchanged.
//  - parallel_epsilon (dimensionless): two planes whose |n_i x n_j|^2 is at most
//    parallel_epsilon |n_i|^2 |n_j|^2 have no usable crease; three planes whose triple
//    product squared is at most parallel_epsilon |n_i|^2 |n_j|^2 |n_k|^2 no usable corner.
//    Exactly opposite planes give the projection onto their common plane.
//  - Non-finite v or normal in a lane: that lane returns zero velocity, status invalid_input,
//    lambda 0; other lanes are unaffected.
//  - A lane that needs more than max_steps steps, or meets a configuration no candidate
//    solves (degenerate, nearly parallel planes), returns zero velocity (always feasible)
//    with converged = false.
#pragma once

#include <plume/math/vec2.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <cassert>
#include <cstddef>
#include <span>
#include <type_traits>

PLUME_MASK_CODE_BEGIN

namespace plume {

/// Tolerances of project_velocity and project_velocity_bruteforce.
template <ScalarReal S>
struct VelocityProjectionConfig {
  /// A plane is violated when n . u < -epsilon (velocity units).
  S epsilon = S(0.005);
  /// Creases/corners of planes closer to parallel than this (sin^2 of the angle) are unusable.
  S parallel_epsilon = S(1e-6);
  /// Iteration cap of the n-step algorithm (planes added).
  int max_steps = 10;

  /// The defaults for a world whose length unit is `length_unit` (e.g. 100 for centimetres):
  /// epsilon scales with it, the dimensionless values do not.
  static constexpr VelocityProjectionConfig scaled(S length_unit) noexcept {
    VelocityProjectionConfig c;
    c.epsilon = c.epsilon * length_unit;
    return c;
  }
};

/// Result of project_velocity for one velocity per lane.
template <class Vec>
struct VelocityProjection {
  using T = typename Vec::element_type;
  Vec velocity;            ///< the projected velocity u
  T steps;                 ///< planes added (0: v was already allowed); a small whole number
  mask_t<T> converged;     ///< no plane violated by more than epsilon at the returned u
  mask_t<T> invalid_input; ///< v or a normal was not finite (velocity is zero)
};

namespace detail {

template <class Vec>
using vp_elem = typename Vec::element_type;

/// Sum over all normals of (c - c) for every component: zero iff every value is finite.
template <class Vec>
PLUME_INLINE mask_t<vp_elem<Vec>> all_finite(Vec const& v, std::span<Vec const> normals) noexcept {
  using T = vp_elem<Vec>;
  auto const fin = [](Vec const& a) {
    if constexpr (Vec::dim == 3)
      return ((a.x - a.x) + (a.y - a.y)) + (a.z - a.z);
    else
      return (a.x - a.x) + (a.y - a.y);
  };
  T acc = fin(v);
  for (Vec const& n : normals)
    acc = acc + fin(n);
  return acc == zero<T>();
}

/// The smallest n_i . u, its normal and (WithIndex) its index as T: the first index that
/// attains the minimum; NaN never wins; no plane gives {+inf, -1, zero}.
///  - Wide: four interleaved running minima (planes i = 0, 1, 2, 3 mod 4) cut the
///    compare-select dependency chain fourfold; merging them compares indices on ties.
///  - Scalar: one branch-free pass for the minimum (minss), then the first plane that attains
///    it (one unpredictable branch instead of one per new minimum). The same rule, so the same
///    plane, as the wide form.
template <class Vec>
struct most_violated {
  vp_elem<Vec> s;
  vp_elem<Vec> index;
  Vec normal;
};
template <class Vec>
PLUME_INLINE void merge_violated(most_violated<Vec>& into,
                                 most_violated<Vec> const& other) noexcept {
  auto const better = (other.s < into.s) | ((other.s == into.s) & (other.index < into.index));
  into.s = plume::select(better, other.s, into.s);
  into.index = plume::select(better, other.index, into.index);
  into.normal = Vec::select(better, other.normal, into.normal);
}
template <bool WithIndex, class Vec>
PLUME_INLINE most_violated<Vec> find_most_violated(Vec const& u,
                                                   std::span<Vec const> normals) noexcept {
  using T = vp_elem<Vec>;
  std::size_t const k = normals.size();
  if constexpr (!is_batch_v<T>) {
    T m = infinity<T>();
    for (std::size_t i = 0; i < k; ++i) {
      T const s = normals[i].dot(u);
      m = s < m ? s : m;
    }
    for (std::size_t i = 0; i < k; ++i)
      if (normals[i].dot(u) == m) return {m, static_cast<T>(i), normals[i]};
    return {m, T(-1), Vec{}};
  } else {
    most_violated<Vec> best[4];
    for (auto& b : best)
      b = {infinity<T>(), splat<T>(-1), Vec{}};
    for (std::size_t i = 0; i < k; i += 4) {
      for (std::size_t j = 0; j < 4 && i + j < k; ++j) {
        T const s = normals[i + j].dot(u);
        auto const better = s < best[j].s;
        best[j].s = plume::select(better, s, best[j].s);
        best[j].index = plume::select(better, splat<T>(static_cast<double>(i + j)), best[j].index);
        best[j].normal = Vec::select(better, normals[i + j], best[j].normal);
      }
    }
    merge_violated(best[0], best[1]);
    merge_violated(best[2], best[3]);
    merge_violated(best[0], best[2]);
    return best[0];
  }
}

/// lambda_out[i] = the multiplier of the active slot holding plane i (index as T), or 0; 0
/// for lanes that did not converge.
template <class T, std::size_t N>
PLUME_INLINE void scatter_multipliers(std::span<T> lambda_out, std::size_t k, mask_t<T> converged,
                                      T const (&index)[N], T const (&value)[N]) noexcept {
  for (std::size_t i = 0; i < k; ++i) {
    T const idx = splat<T>(static_cast<double>(i));
    T l = zero<T>();
    for (std::size_t j = 0; j < N; ++j)
      l = plume::select(index[j] == idx, value[j], l);
    lambda_out[i] = plume::select(converged, l, zero<T>());
  }
}

/// num / den >= 0 without the division (den != 0): the signs agree or num is zero.
template <class T>
PLUME_INLINE mask_t<T> ratio_nonnegative(T num, T den) noexcept {
  T const z = zero<T>();
  return ((den > z) & (num >= z)) | ((den < z) & (num <= z));
}

} // namespace detail

// ================================================================================== 3D n-step

namespace detail {

/// The 3D n-step algorithm. WithLambda adds the bookkeeping of plane indices and multipliers;
/// the velocity, steps and masks are the same either way (validity is decided from signs, the
/// multipliers are only divided out for the output).
template <bool WithLambda, class T>
VelocityProjection<GVec3<T>> project3(GVec3<T> const& v, std::span<GVec3<T> const> normals,
                                      std::span<T> lambda_out,
                                      VelocityProjectionConfig<scalar_t<T>> const& cfg) noexcept {
  using V = GVec3<T>;
  using M = mask_t<T>;
  T const neg_eps = -splat<T>(cfg.epsilon);
  T const par = splat<T>(cfg.parallel_epsilon);
  T const z = zero<T>();
  T const one_plane = splat<T>(1), two_planes = splat<T>(2);
  T const none_index = splat<T>(-1);

  M const finite = detail::all_finite(v, normals);
  // Active set: m planes (0, 1, 2) with normals a, b; m = 3 marks the solid wedge (u = 0).
  // With multipliers: indices ia, ib, ic and multipliers la, lb, lc of the active planes.
  V u = V::select(finite, v, V{});
  V a{}, b{};
  T m = z, steps = z;
  [[maybe_unused]] T ia = none_index, ib = none_index, ic = none_index, la = z, lb = z, lc = z;
  M running = finite;
  M converged = z < z; // all false
  for (int step = 0;; ++step) {
    auto const worst = detail::find_most_violated<WithLambda, V>(u, normals);
    M const ok = !(worst.s < neg_eps);
    converged = converged | (running & ok);
    running = running & !ok;
    if (plume::none(running) || step == cfg.max_steps) break;

    V const& c = worst.normal;
    M const no_a = m < one_plane, no_b = m < two_planes;
    M const has_a = m >= one_plane, has_b = m >= two_planes;
    T const cc = c.dot(c), cv = c.dot(v);
    T const av = a.dot(v), ca = c.dot(a), bv = b.dot(v), cb = c.dot(b);
    // Candidate J, the new plane alone: multiplier l1 = -cv / cc. Its tests use
    // a . u1 = a . v + l1 (c . a) (and the same for b), |u1 - v|^2 = l1^2 (c . c): the same
    // values as from u1, with a shorter dependency chain.
    T const l1 = -cv / cc;
    V const u1 = v + c * l1;
    M const ok1 =
        (-cv > z) & (no_a | !(av + l1 * ca < neg_eps)) & (no_b | !(bv + l1 * cb < neg_eps));
    T const d1 = (l1 * l1) * cc;

    // The other candidates need one or two active planes. No lane has them in the first step,
    // none has two in the second: skip what no running lane can take (the skipped
    // candidates are invalid in every lane, so every result is the same either way).
    M ok2 = z < z, ok3 = z < z, ok4 = z < z;
    V u2{}, u3{}, ea{};
    T d2 = z, d3 = z, aa = z;
    [[maybe_unused]] T dea = one_plane, pj2 = z, pa2 = z, deb = one_plane, pj3 = z, pb3 = z;
    [[maybe_unused]] T det = one_plane, pj4 = z, pa4 = z, pb4 = z;
    if (plume::any(running & has_a)) {
      // Candidate JA, the crease of the new plane and a (Gram determinant dea = |c x a|^2):
      // multipliers pj2 / dea (new) and pa2 / dea (a).
      aa = a.dot(a);
      ea = c.cross(a);
      dea = ea.dot(ea);
      T const s2 = v.dot(ea) / dea;
      u2 = ea * s2;
      pj2 = ca * av - aa * cv, pa2 = ca * cv - cc * av;
      ok2 = has_a & (dea > par * (cc * aa)) & (pj2 >= z) & (pa2 >= z) &
            (no_b | !(s2 * b.dot(ea) < neg_eps));
      d2 = (u2 - v).length_squared();
    }
    if (plume::any(running & has_b)) { // implies the block above ran
      // Candidate JB, the crease of the new plane and b.
      T const bb = b.dot(b);
      V const eb = c.cross(b);
      deb = eb.dot(eb);
      T const s3 = v.dot(eb) / deb;
      u3 = eb * s3;
      pj3 = cb * bv - bb * cv, pb3 = cb * cv - cc * bv;
      ok3 = has_b & (deb > par * (cc * bb)) & (pj3 >= z) & (pb3 >= z) & !(s3 * a.dot(eb) < neg_eps);
      d3 = (u3 - v).length_squared();

      // Candidate JAB, the solid wedge: -v = lj c + la a + lb b with all three >= 0
      // (Cramer: numerators over det = c . (a x b)); u = 0.
      V const axb = a.cross(b), bxc = b.cross(c);
      det = c.dot(axb);
      pj4 = -v.dot(axb), pa4 = -v.dot(bxc), pb4 = -v.dot(ea);
      ok4 = has_b & (det * det > par * ((cc * aa) * bb)) & ratio_nonnegative(pj4, det) &
            ratio_nonnegative(pa4, det) & ratio_nonnegative(pb4, det);
    }
    T const d4 = v.length_squared();

    // The valid candidate nearest to v (all valid ones are optimal up to epsilon; the order
    // J, JA, JB, JAB decides exact ties).
    T best = plume::select(ok1, d1, infinity<T>());
    M const take2 = ok2 & (d2 < best);
    best = plume::select(take2, d2, best);
    M const take3 = ok3 & (d3 < best);
    best = plume::select(take3, d3, best);
    M const take4 = ok4 & (d4 < best);
    M const found = ok1 | ok2 | ok3 | ok4;
    M const sel2 = take2 & !take3 & !take4;
    M const sel3 = take3 & !take4;

    // New state of the running lanes:
    //   J {c} m = 1;  JA {a, c} m = 2;  JB {c, b} m = 2;  JAB m = 3 (u = 0, finished);
    //   none: u = 0, finished, not converged.
    V nu = V::select(found & !take4, u1, V{});
    nu = V::select(sel2, u2, nu);
    nu = V::select(sel3, u3, nu);
    u = V::select(running, nu, u);
    a = V::select(running & !sel2, c, a);
    b = V::select(running, V::select(sel2, c, V::select(sel3, b, V{})), b);
    T nm = plume::select(sel2 | sel3, two_planes, one_plane);
    m = plume::select(running, plume::select(take4, splat<T>(3), nm), m);
    steps = plume::select(running, steps + one_plane, steps);
    if constexpr (WithLambda) {
      // Slots: J (c); JA (a, c); JB (c, b); JAB (c, a, b).
      T const j = worst.index;
      T nia = plume::select(sel2, ia, j);
      T nib = plume::select(sel2, j, plume::select(sel3, ib, none_index));
      T nla = plume::select(sel2, pa2 / dea, plume::select(sel3, pj3 / deb, -cv / cc));
      T nlb = plume::select(sel2, pj2 / dea, plume::select(sel3, pb3 / deb, z));
      nib = plume::select(take4, ia, nib);
      T const nic = plume::select(take4, ib, none_index);
      nla = plume::select(take4, pj4 / det, nla);
      nlb = plume::select(take4, pa4 / det, nlb);
      T const nlc = plume::select(take4, pb4 / det, z);
      ia = plume::select(running, nia, ia);
      ib = plume::select(running, nib, ib);
      ic = plume::select(running, nic, ic);
      la = plume::select(running, nla, la);
      lb = plume::select(running, nlb, lb);
      lc = plume::select(running, nlc, lc);
    }
    // The solid wedge is the exact answer; no valid candidate is a degenerate stop.
    converged = converged | (running & take4);
    running = running & found & !take4;
  }
  // Lanes still running ran out of steps: fall back to the apex (always allowed).
  u = V::select(running, V{}, u);
  if constexpr (WithLambda)
    scatter_multipliers<T, 3>(lambda_out, normals.size(), converged, {ia, ib, ic}, {la, lb, lc});
  return {u, steps, converged, !finite};
}

} // namespace detail

/// Projects v onto the cone {u : n_i . u >= 0} with the n-step active-set algorithm (see the
/// file comment). lambda_out must have normals.size() entries and receives the multiplier of
/// each plane (0 for inactive planes, invalid and unconverged lanes).
template <Real T>
VelocityProjection<GVec3<T>>
project_velocity(GVec3<T> const& v, std::type_identity_t<std::span<GVec3<T> const>> normals,
                 std::type_identity_t<std::span<T>> lambda_out,
                 VelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  assert(lambda_out.size() >= normals.size());
  return detail::project3<true, T>(v, normals, lambda_out, cfg);
}

/// project_velocity without the multipliers.
template <Real T>
VelocityProjection<GVec3<T>>
project_velocity(GVec3<T> const& v, std::type_identity_t<std::span<GVec3<T> const>> normals,
                 VelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  return detail::project3<false, T>(v, normals, std::span<T>{}, cfg);
}

// ================================================================================== 2D n-step

namespace detail {

/// The 2D n-step algorithm: the active set holds at most one plane; two active planes give
/// u = 0 (the 2D solid wedge).
template <bool WithLambda, class T>
VelocityProjection<GVec2<T>> project2(GVec2<T> const& v, std::span<GVec2<T> const> normals,
                                      std::span<T> lambda_out,
                                      VelocityProjectionConfig<scalar_t<T>> const& cfg) noexcept {
  using V = GVec2<T>;
  using M = mask_t<T>;
  T const neg_eps = -splat<T>(cfg.epsilon);
  T const par = splat<T>(cfg.parallel_epsilon);
  T const z = zero<T>();
  T const one_plane = splat<T>(1);
  T const none_index = splat<T>(-1);

  M const finite = detail::all_finite(v, normals);
  V u = V::select(finite, v, V{});
  V a{};
  T m = z, steps = z;
  [[maybe_unused]] T ia = none_index, ib = none_index, la = z, lb = z;
  M running = finite;
  M converged = z < z;
  for (int step = 0;; ++step) {
    auto const worst = detail::find_most_violated<WithLambda, V>(u, normals);
    M const ok = !(worst.s < neg_eps);
    converged = converged | (running & ok);
    running = running & !ok;
    if (plume::none(running) || step == cfg.max_steps) break;

    V const& c = worst.normal;
    M const no_a = m < one_plane, has_a = m >= one_plane;
    T const cc = c.dot(c), cv = c.dot(v);
    // Candidate J, the new plane alone: multiplier -cv / cc.
    V const u1 = v + c * (-cv / cc);
    M const ok1 = (-cv > z) & (no_a | !(a.dot(u1) < neg_eps));
    T const d1 = (u1 - v).length_squared();
    // Candidate JA, both planes: u = 0 when -v = lj c + la a with both >= 0 (Cramer).
    // Skipped when no running lane has a plane yet (it would be invalid in every lane).
    M ok2 = z < z;
    [[maybe_unused]] T det = one_plane, pj2 = z, pa2 = z;
    if (plume::any(running & has_a)) {
      T const aa = a.dot(a);
      det = c.perp_dot(a);
      pj2 = -v.perp_dot(a), pa2 = -c.perp_dot(v);
      ok2 = has_a & (det * det > par * (cc * aa)) & ratio_nonnegative(pj2, det) &
            ratio_nonnegative(pa2, det);
    }
    T const d2 = v.length_squared();

    M const no1 = !ok1;
    M const take2 = ok2 & (no1 | (d2 < d1));
    M const take1 = ok1 & !take2;
    M const found = ok1 | ok2;

    // J: {c}, m = 1.  JA: {a, c}, m = 2, u = 0, finished.  None: u = 0, not converged.
    u = V::select(running, V::select(take1, u1, V{}), u);
    a = V::select(running & take1, c, a);
    m = plume::select(running, plume::select(take2, splat<T>(2), one_plane), m);
    steps = plume::select(running, steps + one_plane, steps);
    if constexpr (WithLambda) {
      ib = plume::select(running, plume::select(take2, worst.index, none_index), ib);
      ia = plume::select(running & take1, worst.index, ia);
      lb = plume::select(running, plume::select(take2, pj2 / det, z), lb);
      la = plume::select(running, plume::select(take2, pa2 / det, -cv / cc), la);
    }
    converged = converged | (running & take2);
    running = running & found & !take2;
  }
  u = V::select(running, V{}, u);
  if constexpr (WithLambda)
    scatter_multipliers<T, 2>(lambda_out, normals.size(), converged, {ia, ib}, {la, lb});
  return {u, steps, converged, !finite};
}

} // namespace detail

/// 2D form of project_velocity with multipliers (lambda_out: normals.size() entries).
template <Real T>
VelocityProjection<GVec2<T>>
project_velocity(GVec2<T> const& v, std::type_identity_t<std::span<GVec2<T> const>> normals,
                 std::type_identity_t<std::span<T>> lambda_out,
                 VelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  assert(lambda_out.size() >= normals.size());
  return detail::project2<true, T>(v, normals, lambda_out, cfg);
}

/// project_velocity (2D) without the multipliers.
template <Real T>
VelocityProjection<GVec2<T>>
project_velocity(GVec2<T> const& v, std::type_identity_t<std::span<GVec2<T> const>> normals,
                 VelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  return detail::project2<false, T>(v, normals, std::span<T>{}, cfg);
}

// ================================================================================ brute force

namespace detail {
/// Every n . u >= -epsilon.
template <class Vec>
PLUME_INLINE mask_t<vp_elem<Vec>> allowed(Vec const& u, std::span<Vec const> normals,
                                          vp_elem<Vec> neg_eps) noexcept {
  using T = vp_elem<Vec>;
  mask_t<T> ok = !(zero<T>() < zero<T>()); // all true
  for (Vec const& n : normals)
    ok = ok & !(n.dot(u) < neg_eps);
  return ok;
}

/// The face candidates of the brute force: for each plane violated by v, v projected onto it,
/// kept in best when nearer than best_d and allowed by every plane.
template <class Vec>
PLUME_INLINE void nearest_allowed_face(Vec const& v, std::span<Vec const> normals,
                                       vp_elem<Vec> neg_eps, Vec& best,
                                       vp_elem<Vec>& best_d) noexcept {
  for (Vec const& n : normals) {
    auto const nv = n.dot(v);
    Vec const p = v - n * (nv / n.dot(n));
    auto const d = (p - v).length_squared();
    auto const take = (nv < neg_eps) & (d < best_d) & allowed(p, normals, neg_eps);
    best = Vec::select(take, p, best);
    best_d = plume::select(take, d, best_d);
  }
}
} // namespace detail

/// The O(k^3) reference (Avian 0.6's first solver): v if no plane is violated by more than
/// epsilon; else the nearest allowed (within epsilon) of the face projections
/// v - (n_i . v) n_i / |n_i|^2 of the violated planes and the crease projections
/// e (v . e) / |e|^2, e = n_i x n_j; else zero. Same conventions as project_velocity; the
/// result carries no step count (steps = 0) and converged is true for finite lanes.
template <Real T>
VelocityProjection<GVec3<T>>
project_velocity_bruteforce(GVec3<T> const& v,
                            std::type_identity_t<std::span<GVec3<T> const>> normals,
                            VelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  using V = GVec3<T>;
  using M = mask_t<T>;
  T const neg_eps = -splat<T>(cfg.epsilon);
  T const par = splat<T>(cfg.parallel_epsilon);
  M const finite = detail::all_finite(v, normals);
  M const inside = detail::allowed(v, normals, neg_eps);
  V best{};
  T best_d = infinity<T>();
  detail::nearest_allowed_face(v, normals, neg_eps, best, best_d);
  for (std::size_t i = 0; i < normals.size(); ++i) {
    for (std::size_t j = i + 1; j < normals.size(); ++j) {
      V const e = normals[i].cross(normals[j]);
      T const ee = e.dot(e);
      M const usable = ee > par * (normals[i].dot(normals[i]) * normals[j].dot(normals[j]));
      V const p = e * (v.dot(e) / ee);
      T const d = (p - v).length_squared();
      M const take = usable & (d < best_d) & detail::allowed(p, normals, neg_eps);
      best = V::select(take, p, best);
      best_d = plume::select(take, d, best_d);
    }
  }
  V const u = V::select(finite & inside, v, V::select(finite, best, V{}));
  return {u, zero<T>(), finite, !finite};
}

/// 2D brute force: v, else the nearest allowed face projection, else zero.
template <Real T>
VelocityProjection<GVec2<T>>
project_velocity_bruteforce(GVec2<T> const& v,
                            std::type_identity_t<std::span<GVec2<T> const>> normals,
                            VelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  using V = GVec2<T>;
  using M = mask_t<T>;
  T const neg_eps = -splat<T>(cfg.epsilon);
  M const finite = detail::all_finite(v, normals);
  M const inside = detail::allowed(v, normals, neg_eps);
  V best{};
  T best_d = infinity<T>();
  detail::nearest_allowed_face(v, normals, neg_eps, best, best_d);
  V const u = V::select(finite & inside, v, V::select(finite, best, V{}));
  return {u, zero<T>(), finite, !finite};
}

} // namespace plume

PLUME_MASK_CODE_END
