// plume/solver/character/velocity_projection.hpp - the velocity closest to a desired one that
// does not move into any of a set of contact planes (the sliding step of move-and-slide).
//
// Problem: given v and plane normals n_1..n_k (pointing out of the obstacles), find
//     u = argmin |u - v|^2   subject to   n_i . u >= 0 for every i,
// the projection of v onto the polyhedral cone of allowed velocities. At the optimum
// u = v + sum_i lambda_i n_i with lambda_i >= 0 and lambda_i (n_i . u) = 0 (lambda_i is the
// impulse per unit mass plane i applies); u . (u - v) = 0. Velocities are in the world's
// velocity units, normals in any frame shared with v (the answer is in that frame).
//
//   project_velocity(v, normals [, lambda_out], cfg)     the n-step active-set algorithm
//   project_velocity_bruteforce(v, normals, cfg)         the O(k^3) reference
//   both for GVec3<T> and GVec2<T>, T scalar or wide; results GVelocityProjection<Vec>.
//
// What the answer satisfies (converged lanes, unit normals): it is feasible within epsilon
// (n_i . u >= -epsilon for every i), and it is no farther from v than the exact projection
// plus epsilon (|u - v| <= |u* - v| + epsilon). It is not always near u* itself: a plane
// violated by less than epsilon counts as satisfied, and in a narrow cone (planes at a small
// angle) the answer can then lie far from u* (up to about epsilon / sin of the angle).
// Why: move-and-slide needs a velocity that does not push into contacts and loses as little
// of the requested motion as possible, at a cost of O(k) per step.
//
// The n-step algorithm (after unpairedbracket's "Velocity Projection", the GJK idea on a
// cone): keep an active set of at most two planes (one in 2D) whose exact projection u is
// known; add the most violated plane; replace the active set by the subset of
// {active, new} (the new plane always kept) that satisfies the optimality conditions on
// those planes — the apex, a ray (face), a wedge (crease) or the solid wedge (u = 0) — and
// repeat until no plane is violated by more than cfg.epsilon. Each step is O(k); the most
// violated plane is the one with the smallest n . u, the first in the span on ties. Steps
// seen: at most 4 on +z and the 16 unit normals around it of tests/character (1000
// directions, every prefix of the set), at most 5 on the random contact sets of up to 32
// planes of bench/character. Every step tests the Lagrange multipliers of each candidate
// subset, so a plane that stops helping is dropped whatever the order in which planes become
// active.
//
// Wide use: lane l projects lane l of v against lane l of every normal. Different lanes may
// have different plane counts: pad with zero normals (a zero normal is never violated and
// never changes a result). Every lane runs until all have finished; finished lanes are
// frozen by masks, and lane l equals, bit for bit, the scalar call on lane l's inputs. A
// wide call costs as many steps as its slowest lane.
//
// Conventions and bad input:
//  - Normals should be unit length (PlaneSet3/PlaneSet2 build such sets). A nonzero normal
//    of another length (within the range below) acts as the plane it defines; only the
//    violation tolerance scales with |n|. Zero normals are ignored.
//  - epsilon (velocity units, default 0.005 x length unit / s): a plane counts as violated
//    when n . u < -epsilon. With unit normals, a v with |v| < epsilon comes back unchanged.
//  - parallel_epsilon (dimensionless): two planes whose |n_i x n_j|^2 is at most
//    parallel_epsilon |n_i|^2 |n_j|^2 have no usable crease; three planes whose triple
//    product squared is at most parallel_epsilon |n_i|^2 |n_j|^2 |n_k|^2 no usable corner.
//    Exactly opposite planes give the projection onto their common plane.
//  - Non-finite v or normal in a lane, a component of v beyond 2^40 in magnitude (about
//    1.1e12 velocity units), or a nonzero normal whose length is outside [2^-20, 2^20]
//    (about 1e-6 to 1e6: the formulas multiply up to six lengths and square |v| / |n|): that
//    lane returns zero velocity, status invalid_input, lambda 0; other lanes are unaffected.
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
struct GVelocityProjectionConfig {
  /// A plane is violated when n . u < -epsilon (velocity units).
  S epsilon = S(0.005);
  /// Creases/corners of planes closer to parallel than this (sin^2 of the angle) are unusable.
  S parallel_epsilon = S(1e-6);
  /// Iteration cap of the n-step algorithm (planes added).
  int max_steps = 10;

  /// This configuration with every length-valued field (epsilon) multiplied by length_unit,
  /// e.g. `VelocityProjectionConfig{}.scaled(100)` for centimetres; the dimensionless
  /// values stay.
  constexpr GVelocityProjectionConfig scaled(S length_unit) const noexcept {
    GVelocityProjectionConfig c = *this;
    c.epsilon = c.epsilon * length_unit;
    return c;
  }
};
using VelocityProjectionConfig = GVelocityProjectionConfig<float>;
using DVelocityProjectionConfig = GVelocityProjectionConfig<double>;

/// Result of project_velocity for one velocity per lane.
template <class Vec>
struct GVelocityProjection {
  using T = typename Vec::element_type;
  Vec velocity;            ///< the projected velocity u
  T steps;                 ///< planes added (0: v was already allowed); a small whole number
  mask_t<T> converged;     ///< no plane violated by more than epsilon at the returned u
  mask_t<T> invalid_input; ///< v or a normal not finite, or v's or a normal's size out of range
};
using VelocityProjection3 = GVelocityProjection<GVec3<float>>;
using VelocityProjection2 = GVelocityProjection<GVec2<float>>;

namespace detail {

template <class Vec>
using vp_elem = typename Vec::element_type;

/// The lanes whose input the algorithm takes: every component of v at most 2^40 in magnitude,
/// and every normal zero or of a length in [2^-20, 2^20] (the candidates' Gram determinants
/// multiply up to six lengths, which must neither overflow nor underflow; a multiplier,
/// |v| / |n|, is squared, which bounds v). A non-finite component fails both tests.
template <class Vec>
PLUME_INLINE mask_t<vp_elem<Vec>> usable_input(Vec const& v,
                                               std::span<Vec const> normals) noexcept {
  using T = vp_elem<Vec>;
  T const lo = splat<T>(0x1p-40), hi = splat<T>(0x1p40), zero = plume::zero<T>();
  mask_t<T> ok = (plume::abs(v.x) <= hi) & (plume::abs(v.y) <= hi);
  if constexpr (Vec::dim == 3) ok = ok & (plume::abs(v.z) <= hi);
  for (Vec const& n : normals) {
    T const l2 = n.dot(n);
    mask_t<T> is_zero = (n.x == zero) & (n.y == zero);
    if constexpr (Vec::dim == 3) is_zero = is_zero & (n.z == zero);
    ok = ok & (is_zero | ((l2 >= lo) & (l2 <= hi)));
  }
  return ok;
}

/// The smallest n_i . u, its normal and (WithIndex) its index as T: the first index that
/// attains the minimum; NaN never wins; no plane gives {+inf, -1, zero}.
///  - Wide: four interleaved running minima (planes i = 0, 1, 2, 3 mod 4), merged comparing
///    indices on ties: shorter compare-select dependency chains than one running minimum.
///  - Scalar: one branch-free pass for the minimum, then the first plane that attains it (one
///    unpredictable branch instead of one per new minimum). The same rule, so the same plane,
///    as the wide form.
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
  T const zero = plume::zero<T>();
  return ((den > zero) & (num >= zero)) | ((den < zero) & (num <= zero));
}

/// The configuration as element values: -epsilon and parallel_epsilon.
template <class T>
struct nstep_tolerances {
  T neg_eps, par;
  explicit nstep_tolerances(GVelocityProjectionConfig<scalar_t<T>> const& cfg) noexcept
      : neg_eps(-splat<T>(cfg.epsilon)), par(splat<T>(cfg.parallel_epsilon)) {}
};

/// Per lane: the projection u of v on the active set, its planes a, b (m of them: 0, 1, 2; 3
/// marks the 3D solid wedge, u = 0; in 2D only a is used and m = 2 marks the 2D solid wedge),
/// the steps taken and, for the multipliers, the active planes' indices ia, ib, ic (-1: none)
/// and multipliers la, lb, lc.
template <class Vec>
struct nstep_state {
  using T = vp_elem<Vec>;
  Vec u, a, b;
  T m, steps;
  T ia, ib, ic, la, lb, lc;
  mask_t<T> running, converged;
};

/// The start of every n-step iteration: lanes where no plane is violated by more than epsilon
/// at u (worst_s, the smallest n . u) join `converged` and leave `running`. True when no lane
/// runs any more.
template <class T>
PLUME_INLINE bool nstep_settle(mask_t<T>& running, mask_t<T>& converged, T worst_s,
                               T neg_eps) noexcept {
  mask_t<T> const ok = !(worst_s < neg_eps);
  converged = converged | (running & ok);
  running = running & !ok;
  return plume::none(running);
}

} // namespace detail

// ================================================================================== 3D n-step

namespace detail {

/// The candidate active sets after adding plane c, each with its validity (every optimality
/// condition on its planes and no violated active plane), its u and |u - v|^2:
///   J the new plane alone (u1, multiplier l1); JA the crease of c and a (Gram determinant
///   dea, multipliers pj2 / dea for c and pa2 / dea for a); JB the crease of c and b (deb,
///   pj3, pb3); JAB the solid wedge, u = 0 (Cramer: det, pj4, pa4, pb4).
template <class T>
struct nstep3_candidates {
  T cc, cv, av, ca, bv, cb; // the dot products the candidates share
  GVec3<T> u1;
  T l1, d1;
  mask_t<T> ok1;
  GVec3<T> u2, ea; // ea = c x a
  T aa, d2, dea, pj2, pa2;
  mask_t<T> ok2;
  GVec3<T> u3;
  T bb, d3, deb, pj3, pb3;
  mask_t<T> ok3;
  T d4, det, pj4, pa4, pb4;
  mask_t<T> ok4;
};

/// J, the new plane alone: multiplier l1 = -cv / cc. Its tests use a . u1 = a . v + l1 (c . a)
/// (the same for b) and |u1 - v|^2 = l1^2 (c . c): the values of u1's, with a shorter chain.
template <class T>
PLUME_INLINE void nstep3_face(nstep3_candidates<T>& k, GVec3<T> const& v, GVec3<T> const& c,
                              mask_t<T> no_a, mask_t<T> no_b, T neg_eps) noexcept {
  T const zero = plume::zero<T>();
  k.l1 = -k.cv / k.cc;
  k.u1 = v + c * k.l1;
  k.ok1 = (-k.cv > zero) & (no_a | !(k.av + k.l1 * k.ca < neg_eps)) &
          (no_b | !(k.bv + k.l1 * k.cb < neg_eps));
  k.d1 = (k.l1 * k.l1) * k.cc;
}

/// JA, the crease of the new plane c and the active plane a.
template <class T>
PLUME_INLINE void nstep3_crease_a(nstep3_candidates<T>& k, GVec3<T> const& v, GVec3<T> const& c,
                                  nstep_state<GVec3<T>> const& s, mask_t<T> has_a, mask_t<T> no_b,
                                  nstep_tolerances<T> const& tol) noexcept {
  T const zero = plume::zero<T>();
  k.aa = s.a.dot(s.a);
  k.ea = c.cross(s.a);
  k.dea = k.ea.dot(k.ea);
  T const s2 = v.dot(k.ea) / k.dea;
  k.u2 = k.ea * s2;
  k.pj2 = k.ca * k.av - k.aa * k.cv, k.pa2 = k.ca * k.cv - k.cc * k.av;
  k.ok2 = has_a & (k.dea > tol.par * (k.cc * k.aa)) & (k.pj2 >= zero) & (k.pa2 >= zero) &
          (no_b | !(s2 * s.b.dot(k.ea) < tol.neg_eps));
  k.d2 = (k.u2 - v).length_squared();
}

/// JB, the crease of c and the active plane b, and JAB, the solid wedge of c, a and b:
/// -v = lj c + la a + lb b with all three >= 0. Needs nstep3_crease_a's aa and ea.
template <class T>
PLUME_INLINE void nstep3_crease_b_and_wedge(nstep3_candidates<T>& k, GVec3<T> const& v,
                                            GVec3<T> const& c, nstep_state<GVec3<T>> const& s,
                                            mask_t<T> has_b,
                                            nstep_tolerances<T> const& tol) noexcept {
  using V = GVec3<T>;
  T const zero = plume::zero<T>();
  k.bb = s.b.dot(s.b);
  V const eb = c.cross(s.b);
  k.deb = eb.dot(eb);
  T const s3 = v.dot(eb) / k.deb;
  k.u3 = eb * s3;
  k.pj3 = k.cb * k.bv - k.bb * k.cv, k.pb3 = k.cb * k.cv - k.cc * k.bv;
  k.ok3 = has_b & (k.deb > tol.par * (k.cc * k.bb)) & (k.pj3 >= zero) & (k.pb3 >= zero) &
          !(s3 * s.a.dot(eb) < tol.neg_eps);
  k.d3 = (k.u3 - v).length_squared();

  V const axb = s.a.cross(s.b), bxc = s.b.cross(c);
  k.det = c.dot(axb);
  k.pj4 = -v.dot(axb), k.pa4 = -v.dot(bxc), k.pb4 = -v.dot(k.ea);
  k.ok4 = has_b & (k.det * k.det > tol.par * ((k.cc * k.aa) * k.bb)) &
          ratio_nonnegative(k.pj4, k.det) & ratio_nonnegative(k.pa4, k.det) &
          ratio_nonnegative(k.pb4, k.det);
}

/// Every candidate for adding plane c to the active sets of s. No lane has an active plane
/// in the first step, none has two in the second: the candidates that need them are skipped
/// when no running lane can take them (they are invalid in every lane then, so every result
/// is the same either way).
template <class T>
PLUME_INLINE nstep3_candidates<T> nstep3_candidates_for(GVec3<T> const& v, GVec3<T> const& c,
                                                        nstep_state<GVec3<T>> const& s,
                                                        nstep_tolerances<T> const& tol) noexcept {
  using M = mask_t<T>;
  T const zero = plume::zero<T>(), one_plane = splat<T>(1), two_planes = splat<T>(2);
  M const no_a = s.m < one_plane, no_b = s.m < two_planes;
  M const has_a = s.m >= one_plane, has_b = s.m >= two_planes;
  nstep3_candidates<T> k;
  k.cc = c.dot(c), k.cv = c.dot(v);
  k.av = s.a.dot(v), k.ca = c.dot(s.a), k.bv = s.b.dot(v), k.cb = c.dot(s.b);
  nstep3_face(k, v, c, no_a, no_b, tol.neg_eps);
  k.ok2 = k.ok3 = k.ok4 = no_lanes<T>();
  k.u2 = k.u3 = k.ea = GVec3<T>{};
  k.d2 = k.d3 = k.aa = k.bb = zero;
  k.dea = k.deb = k.det = one_plane;
  k.pj2 = k.pa2 = k.pj3 = k.pb3 = k.pj4 = k.pa4 = k.pb4 = zero;
  if (plume::any(s.running & has_a)) nstep3_crease_a(k, v, c, s, has_a, no_b, tol);
  if (plume::any(s.running & has_b)) nstep3_crease_b_and_wedge(k, v, c, s, has_b, tol);
  k.d4 = v.length_squared();
  return k;
}

/// The valid candidate nearest to v (all valid ones are optimal up to epsilon; the order J,
/// JA, JB, JAB decides exact ties): sel2 (JA), sel3 (JB), take4 (JAB), else J where found.
template <class T>
struct nstep3_choice {
  mask_t<T> take4, found, sel2, sel3;
};
template <class T>
PLUME_INLINE nstep3_choice<T> nstep3_choose(nstep3_candidates<T> const& k) noexcept {
  using M = mask_t<T>;
  T best = plume::select(k.ok1, k.d1, infinity<T>());
  M const take2 = k.ok2 & (k.d2 < best);
  best = plume::select(take2, k.d2, best);
  M const take3 = k.ok3 & (k.d3 < best);
  best = plume::select(take3, k.d3, best);
  M const take4 = k.ok4 & (k.d4 < best);
  M const found = k.ok1 | k.ok2 | k.ok3 | k.ok4;
  M const sel2 = take2 & !take3 & !take4;
  M const sel3 = take3 & !take4;
  return {take4, found, sel2, sel3};
}

/// The new state of the running lanes:
///   J {c} m = 1;  JA {a, c} m = 2;  JB {c, b} m = 2;  JAB m = 3 (u = 0, finished);
///   none found: u = 0, finished, not converged.
template <bool WithLambda, class T>
PLUME_INLINE void nstep3_advance(nstep_state<GVec3<T>>& s, nstep3_candidates<T> const& k,
                                 nstep3_choice<T> const& ch, GVec3<T> const& c,
                                 T plane_index) noexcept {
  using V = GVec3<T>;
  T const zero = plume::zero<T>(), one_plane = splat<T>(1), two_planes = splat<T>(2);
  T const none_index = splat<T>(-1);
  V nu = V::select(ch.found & !ch.take4, k.u1, V{});
  nu = V::select(ch.sel2, k.u2, nu);
  nu = V::select(ch.sel3, k.u3, nu);
  s.u = V::select(s.running, nu, s.u);
  s.a = V::select(s.running & !ch.sel2, c, s.a);
  s.b = V::select(s.running, V::select(ch.sel2, c, V::select(ch.sel3, s.b, V{})), s.b);
  T const nm = plume::select(ch.sel2 | ch.sel3, two_planes, one_plane);
  s.m = plume::select(s.running, plume::select(ch.take4, splat<T>(3), nm), s.m);
  s.steps = plume::select(s.running, s.steps + one_plane, s.steps);
  if constexpr (WithLambda) {
    // Slots: J (c); JA (a, c); JB (c, b); JAB (c, a, b).
    T const j = plane_index;
    T nia = plume::select(ch.sel2, s.ia, j);
    T nib = plume::select(ch.sel2, j, plume::select(ch.sel3, s.ib, none_index));
    T nla = plume::select(ch.sel2, k.pa2 / k.dea, plume::select(ch.sel3, k.pj3 / k.deb, k.l1));
    T nlb = plume::select(ch.sel2, k.pj2 / k.dea, plume::select(ch.sel3, k.pb3 / k.deb, zero));
    nib = plume::select(ch.take4, s.ia, nib);
    T const nic = plume::select(ch.take4, s.ib, none_index);
    nla = plume::select(ch.take4, k.pj4 / k.det, nla);
    nlb = plume::select(ch.take4, k.pa4 / k.det, nlb);
    T const nlc = plume::select(ch.take4, k.pb4 / k.det, zero);
    s.ia = plume::select(s.running, nia, s.ia);
    s.ib = plume::select(s.running, nib, s.ib);
    s.ic = plume::select(s.running, nic, s.ic);
    s.la = plume::select(s.running, nla, s.la);
    s.lb = plume::select(s.running, nlb, s.lb);
    s.lc = plume::select(s.running, nlc, s.lc);
  }
  // The solid wedge is the exact answer; no valid candidate is a degenerate stop.
  s.converged = s.converged | (s.running & ch.take4);
  s.running = s.running & ch.found & !ch.take4;
}

/// One step of the 3D n-step algorithm: plane c (index `plane_index`) joins the active sets.
template <bool WithLambda, class T>
PLUME_INLINE void nstep_add_plane(nstep_state<GVec3<T>>& s, GVec3<T> const& v, GVec3<T> const& c,
                                  T plane_index, nstep_tolerances<T> const& tol) noexcept {
  nstep3_candidates<T> const k = nstep3_candidates_for(v, c, s, tol);
  nstep3_advance<WithLambda>(s, k, nstep3_choose(k), c, plane_index);
}

// ================================================================================== 2D n-step

/// The candidates after adding plane c: J, the new plane alone (multiplier -cv / cc), and JA,
/// both planes: u = 0 when -v = lj c + la a with both >= 0 (Cramer: det, pj2, pa2). JA is
/// skipped when no running lane has a plane yet (it would be invalid in every lane).
template <class T>
struct nstep2_candidates {
  T cc, cv;
  GVec2<T> u1;
  T d1;
  mask_t<T> ok1;
  T d2, det, pj2, pa2;
  mask_t<T> ok2;
};
template <class T>
PLUME_INLINE nstep2_candidates<T> nstep2_candidates_for(GVec2<T> const& v, GVec2<T> const& c,
                                                        nstep_state<GVec2<T>> const& s,
                                                        nstep_tolerances<T> const& tol) noexcept {
  using M = mask_t<T>;
  T const zero = plume::zero<T>(), one_plane = splat<T>(1);
  M const no_a = s.m < one_plane, has_a = s.m >= one_plane;
  nstep2_candidates<T> k;
  k.cc = c.dot(c), k.cv = c.dot(v);
  k.u1 = v + c * (-k.cv / k.cc);
  k.ok1 = (-k.cv > zero) & (no_a | !(s.a.dot(k.u1) < tol.neg_eps));
  k.d1 = (k.u1 - v).length_squared();
  k.ok2 = no_lanes<T>();
  k.det = one_plane, k.pj2 = zero, k.pa2 = zero;
  if (plume::any(s.running & has_a)) {
    T const aa = s.a.dot(s.a);
    k.det = c.perp_dot(s.a);
    k.pj2 = -v.perp_dot(s.a), k.pa2 = -c.perp_dot(v);
    k.ok2 = has_a & (k.det * k.det > tol.par * (k.cc * aa)) & ratio_nonnegative(k.pj2, k.det) &
            ratio_nonnegative(k.pa2, k.det);
  }
  k.d2 = v.length_squared();
  return k;
}

/// The nearer valid candidate (J on exact ties) and the new state of the running lanes:
///   J: {c}, m = 1.  JA: {a, c}, m = 2, u = 0, finished.  None: u = 0, not converged.
template <bool WithLambda, class T>
PLUME_INLINE void nstep2_advance(nstep_state<GVec2<T>>& s, nstep2_candidates<T> const& k,
                                 GVec2<T> const& c, T plane_index) noexcept {
  using V = GVec2<T>;
  using M = mask_t<T>;
  T const zero = plume::zero<T>(), one_plane = splat<T>(1), none_index = splat<T>(-1);
  M const no1 = !k.ok1;
  M const take2 = k.ok2 & (no1 | (k.d2 < k.d1));
  M const take1 = k.ok1 & !take2;
  M const found = k.ok1 | k.ok2;
  s.u = V::select(s.running, V::select(take1, k.u1, V{}), s.u);
  s.a = V::select(s.running & take1, c, s.a);
  s.m = plume::select(s.running, plume::select(take2, splat<T>(2), one_plane), s.m);
  s.steps = plume::select(s.running, s.steps + one_plane, s.steps);
  if constexpr (WithLambda) {
    s.ib = plume::select(s.running, plume::select(take2, plane_index, none_index), s.ib);
    s.ia = plume::select(s.running & take1, plane_index, s.ia);
    s.lb = plume::select(s.running, plume::select(take2, k.pj2 / k.det, zero), s.lb);
    s.la = plume::select(s.running, plume::select(take2, k.pa2 / k.det, -k.cv / k.cc), s.la);
  }
  s.converged = s.converged | (s.running & take2);
  s.running = s.running & found & !take2;
}

/// One step of the 2D n-step algorithm: plane c (index `plane_index`) joins the active set.
template <bool WithLambda, class T>
PLUME_INLINE void nstep_add_plane(nstep_state<GVec2<T>>& s, GVec2<T> const& v, GVec2<T> const& c,
                                  T plane_index, nstep_tolerances<T> const& tol) noexcept {
  nstep2_advance<WithLambda>(s, nstep2_candidates_for(v, c, s, tol), c, plane_index);
}

// ============================================================================ the n-step loop

/// The n-step algorithm in 3D (active sets of up to two planes) and 2D (one plane; two active
/// planes give u = 0, the 2D solid wedge). WithLambda adds the bookkeeping of plane indices
/// and multipliers; the velocity, steps and masks are the same either way (validity is
/// decided from signs, the multipliers are only divided out for the output).
template <bool WithLambda, class Vec>
GVelocityProjection<Vec>
nstep_project(Vec const& v, std::span<Vec const> normals, std::span<vp_elem<Vec>> lambda_out,
              GVelocityProjectionConfig<scalar_t<vp_elem<Vec>>> const& cfg) noexcept {
  using T = vp_elem<Vec>;
  nstep_tolerances<T> const tol(cfg);
  T const zero = plume::zero<T>(), none_index = splat<T>(-1);
  mask_t<T> const finite = detail::usable_input(v, normals);
  nstep_state<Vec> s{.u = Vec::select(finite, v, Vec{}),
                     .a = Vec{},
                     .b = Vec{},
                     .m = zero,
                     .steps = zero,
                     .ia = none_index,
                     .ib = none_index,
                     .ic = none_index,
                     .la = zero,
                     .lb = zero,
                     .lc = zero,
                     .running = finite,
                     .converged = no_lanes<T>()};
  for (int step = 0;; ++step) {
    auto const worst = detail::find_most_violated<WithLambda, Vec>(s.u, normals);
    if (nstep_settle(s.running, s.converged, worst.s, tol.neg_eps) || step == cfg.max_steps) break;
    nstep_add_plane<WithLambda>(s, v, worst.normal, worst.index, tol);
  }
  // Lanes still running ran out of steps: fall back to the apex (always allowed).
  s.u = Vec::select(s.running, Vec{}, s.u);
  if constexpr (WithLambda && Vec::dim == 3)
    scatter_multipliers<T, 3>(lambda_out, normals.size(), s.converged, {s.ia, s.ib, s.ic},
                              {s.la, s.lb, s.lc});
  else if constexpr (WithLambda)
    scatter_multipliers<T, 2>(lambda_out, normals.size(), s.converged, {s.ia, s.ib}, {s.la, s.lb});
  return {s.u, s.steps, s.converged, !finite};
}

} // namespace detail

/// Projects v onto the cone {u : n_i . u >= 0} with the n-step active-set algorithm (see the
/// file comment). lambda_out must have normals.size() entries and receives the multiplier of
/// each plane (0 for inactive planes, invalid and unconverged lanes).
template <Real T>
GVelocityProjection<GVec3<T>>
project_velocity(GVec3<T> const& v, std::type_identity_t<std::span<GVec3<T> const>> normals,
                 std::type_identity_t<std::span<T>> lambda_out,
                 GVelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  assert(lambda_out.size() >= normals.size());
  return detail::nstep_project<true, GVec3<T>>(v, normals, lambda_out, cfg);
}

/// project_velocity without the multipliers.
template <Real T>
GVelocityProjection<GVec3<T>>
project_velocity(GVec3<T> const& v, std::type_identity_t<std::span<GVec3<T> const>> normals,
                 GVelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  return detail::nstep_project<false, GVec3<T>>(v, normals, std::span<T>{}, cfg);
}

/// 2D form of project_velocity with multipliers (lambda_out: normals.size() entries).
template <Real T>
GVelocityProjection<GVec2<T>>
project_velocity(GVec2<T> const& v, std::type_identity_t<std::span<GVec2<T> const>> normals,
                 std::type_identity_t<std::span<T>> lambda_out,
                 GVelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  assert(lambda_out.size() >= normals.size());
  return detail::nstep_project<true, GVec2<T>>(v, normals, lambda_out, cfg);
}

/// project_velocity (2D) without the multipliers.
template <Real T>
GVelocityProjection<GVec2<T>>
project_velocity(GVec2<T> const& v, std::type_identity_t<std::span<GVec2<T> const>> normals,
                 GVelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  return detail::nstep_project<false, GVec2<T>>(v, normals, std::span<T>{}, cfg);
}

// ================================================================================ brute force

namespace detail {
/// Every n . u >= -epsilon.
template <class Vec>
PLUME_INLINE mask_t<vp_elem<Vec>> allowed(Vec const& u, std::span<Vec const> normals,
                                          vp_elem<Vec> neg_eps) noexcept {
  using T = vp_elem<Vec>;
  mask_t<T> ok = all_lanes<T>();
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
GVelocityProjection<GVec3<T>>
project_velocity_bruteforce(GVec3<T> const& v,
                            std::type_identity_t<std::span<GVec3<T> const>> normals,
                            GVelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  using V = GVec3<T>;
  using M = mask_t<T>;
  T const neg_eps = -splat<T>(cfg.epsilon);
  T const par = splat<T>(cfg.parallel_epsilon);
  M const finite = detail::usable_input(v, normals);
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
GVelocityProjection<GVec2<T>>
project_velocity_bruteforce(GVec2<T> const& v,
                            std::type_identity_t<std::span<GVec2<T> const>> normals,
                            GVelocityProjectionConfig<scalar_t<T>> const& cfg = {}) noexcept {
  using V = GVec2<T>;
  using M = mask_t<T>;
  T const neg_eps = -splat<T>(cfg.epsilon);
  M const finite = detail::usable_input(v, normals);
  M const inside = detail::allowed(v, normals, neg_eps);
  V best{};
  T best_d = infinity<T>();
  detail::nearest_allowed_face(v, normals, neg_eps, best, best_d);
  V const u = V::select(finite & inside, v, V::select(finite, best, V{}));
  return {u, zero<T>(), finite, !finite};
}

} // namespace plume

PLUME_MASK_CODE_END
