// plume/collision/box_manifold.hpp - the contact manifold of two cuboids, written once over
// the element type: one pair per lane, and lane i of a wide call equal, bit for bit, to the
// scalar call on lane i's pair. contact_manifold(GCuboid, GCuboid) (manifold.hpp) is this at
// float or double, and the world's narrow phase runs its cuboid pairs through it W at a time.
//
//   GBoxPairManifold<f32x8> w = box_pair_manifold(ea, pose_a, eb, pose_b, prediction);
//   GManifold<float> m = w.lane(i);   // or, when w.general is set in lane i, the general path
//
// The steps, each the same in every lane (a batch skips a step only when none of its lanes
// needs it, and a scalar call skips the same):
//  1. A separating-axis test over the 15 axes (3 face axes of each box, 9 edge pairs). A's
//     faces win ties; B's face wins only when it separates by more than 0.1 x prediction, an
//     edge pair only when it beats both by as much, so the reference face does not flicker.
//  2. Apart by more than the prediction distance along the winning axis: no points, the
//     normal is that axis.
//  3. A face axis: the reference face is that face, the incident face the other box's face
//     most anti-parallel to it. The clipped polygon's vertices are found as a fixed set of 24
//     candidates in the reference face's plane coordinates instead of a Sutherland-Hodgman
//     loop with a varying count: the 4 incident vertices inside the reference rectangle, the
//     16 crossings of the 4 incident edges with the 4 side lines that land on the rectangle,
//     and the 4 reference corners inside the incident quadrilateral. Points within the
//     prediction distance stay: up to 4 as they are, in that candidate order; more go through
//     Gregorius' reduction (the deepest, the farthest from it, the largest triangle, the most
//     area added). When the clip keeps nothing (seen along the normal the faces do not
//     overlap: diagonal neighbours in a stack), the nearest of the closest points of the 16
//     pairs of a reference edge and an incident edge, kept when they give the boxes' distance
//     within 1% of the prediction distance (box_nearest_points): one point, the line joining
//     the points (or, for touching boxes, the winning axis) as the normal.
//  4. An edge axis: one point, the closest points of the two supporting edges, with the
//     separation the test found. When those closest points of the edges' lines fall off
//     either edge (nearly parallel edges), the clamped closest points of the two edges,
//     checked as in 3.
// A lane is `general` (not computed here; contact_manifold takes GJK/EPA's path for it) when
// its inputs or the winning separation are not finite, its reference face has no area (a zero
// extent), or its face clip keeps no point, or its edge pair's lines meet off the edges, and
// the nearest edges' points fail the check (a vertex or another face is nearer, or the boxes
// overlap by more than it allows). Which lanes are general depends only on the lane's inputs, so
// scalar and wide callers agree. Negative extents give unspecified results, as for every shape
// (shapes.hpp).
//
// Feature ids (GContactPoint::id, manifold.hpp's id_bits): reference face and incident face
// (0..5: -x, +x, -y, +y, -z, +z), and the key of the point: incident vertex i (0..3, counter
// clockwise seen from outside the incident face, starting at its +u +v corner), clip_key(i, k)
// for incident edge i (from vertex i to i + 1) cut by reference side k (0..3: +u, +v, -u,
// -v), clip_key(side_edge | k, k) for reference corner k (between sides k and k + 1). An edge
// contact's id, and a nearest-edges point's, has reference face 6 + 3 i + j (A's edge
// direction i, B's j) and key 0.
#pragma once

#include <plume/collision/shapes.hpp>
#include <plume/math/iso3.hpp>
#include <plume/math/mat3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <array>
#include <cstddef>
#include <cstdint>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <ScalarReal S>
struct GManifold;

/// The manifolds of lanes_v<T> cuboid pairs (see the header's comment).
template <Float T>
struct GBoxPairManifold {
  /// Unit, world, from A toward B (also when count is 0 and the pair is apart).
  GVec3<T> normal{};
  std::array<GVec3<T>, 4> point_a{}; ///< world, on A's surface
  std::array<GVec3<T>, 4> point_b{}; ///< world, on B's surface
  std::array<T, 4> separation{};     ///< along normal; negative = overlap
  std::array<T, 4> key{}; ///< which candidate: 0..23 (face contact), 24 (edge), 25 (nearest edges)
  T count{};              ///< points kept, 0..4 (points [count, 4) are unset)
  T ref_face{}, inc_face{}; ///< face indices 0..5; the edge pair's 6 + 3 i + j
  mask_t<T> ref_is_b{};     ///< the reference face is B's
  mask_t<T> general{};      ///< not computed: take the general path

  /// Lane i as a scalar manifold (its ids built from key, ref_face, inc_face). Meaningless
  /// for a general lane.
  GManifold<scalar_t<T>> lane(std::size_t i) const noexcept;
};

namespace detail {

template <class T>
PLUME_INLINE T pick3(T k, T a, T b, T c) noexcept {
  return plume::select(k == zero<T>(), a, plume::select(k == one<T>(), b, c));
}
template <class T>
PLUME_INLINE GVec3<T> pick3(T k, GVec3<T> const& a, GVec3<T> const& b, GVec3<T> const& c) noexcept {
  return GVec3<T>::select(k == zero<T>(), a, GVec3<T>::select(k == one<T>(), b, c));
}

/// One candidate point of a face clip: on the incident face, its height above the reference
/// plane, the point the reduction measures (B's point), and whether it is kept.
template <class T>
struct box_candidate {
  GVec3<T> p;
  T h;
  GVec3<T> pos;
  mask_t<T> ok;
};

/// Candidate `pick` (< used) of cand, copied: by index for a scalar, by selecting it in each
/// lane for a batch (the same values either way); nothing for a pick below 0.
template <class T>
PLUME_INLINE void take_candidate(std::array<box_candidate<T>, 24> const& cand, std::size_t used,
                                 T pick, GVec3<T>& p, T& h) noexcept {
  if constexpr (is_batch_v<T>) {
    for (std::size_t s = 0; s < used; ++s) {
      mask_t<T> const here = pick == splat<T>(scalar_t<T>(s));
      p = GVec3<T>::select(here, cand[s].p, p);
      h = plume::select(here, cand[s].h, h);
    }
  } else if (pick >= T(0)) {
    p = cand[std::size_t(pick)].p;
    h = cand[std::size_t(pick)].h;
  }
}

/// The closest points of segments p0 + s d1 and q0 + t d2 (s, t in [0, 1]): the clamped
/// minimum of the lines; for (nearly) parallel segments the middle of the part of p's segment
/// that q's covers, or the nearer end when none is. Returns whether they are parallel.
template <class T>
PLUME_INLINE mask_t<T> segment_closest(GVec3<T> const& p0, GVec3<T> const& d1, GVec3<T> const& q0,
                                       GVec3<T> const& d2, GVec3<T>& cp, GVec3<T>& cq) noexcept {
  using S = scalar_t<T>;
  T const z = zero<T>(), o = one<T>();
  GVec3<T> const r = p0 - q0;
  T const a = d1.dot(d1), e = d2.dot(d2), b = d1.dot(d2);
  T const c = d1.dot(r), f = d2.dot(r);
  T const a_s = plume::select(a > z, a, o), e_s = plume::select(e > z, e, o);
  T const den = a * e - b * b;
  mask_t<T> const parallel = den <= splat<T>(S(1e-6)) * (a * e);
  T const s0 = -c / a_s, s1 = (b - c) / a_s;
  T const lo = plume::max_select(z, plume::min_select(s0, s1));
  T const hi = plume::min_select(o, plume::max_select(s0, s1));
  T const s_par = (lo + hi) * splat<T>(S(0.5));
  T const s_gen = (b * f - c * e) / plume::select(parallel, o, den);
  T s = plume::clamp_select(plume::select(parallel, s_par, s_gen), z, o);
  T const t_line = (b * s + f) / e_s;
  T const t = plume::clamp_select(t_line, z, o);
  s = plume::select(t_line == t, s, plume::clamp_select((b * t - c) / a_s, z, o));
  cp = p0 + d1 * s;
  cq = q0 + d2 * t;
  return parallel;
}

template <class T>
void box_nearest_points(GBoxPairManifold<T>& out, mask_t<T> todo, GVec3<T> const& pr,
                        GVec3<T> const& pi, T dist2, T axis_r, T axis_i,
                        std::array<GVec3<T>, 3> const& rx, std::array<GVec3<T>, 3> const& ix,
                        GVec3<T> const& er, GVec3<T> const& ei, GVec3<T> const& tr,
                        GVec3<T> const& d, GVec3<T> const& sat_n, T sat_sep, T pred) noexcept;

/// box_face_contact's lanes (todo) whose clip kept no point although the separating-axis test
/// put the boxes within the prediction distance: seen along the normal the faces do not
/// overlap (or every clipped point is beyond the prediction distance), and the nearest
/// features are edges (the vertical edges of diagonal neighbours in a stack). In coordinates
/// centred on R (tr, its centre; d, I's centre), the nearest of the closest points of the 16
/// pairs of a reference edge (rc[s] to rc[s + 1]) and an incident edge (iv[i] to iv[i + 1])
/// go to box_nearest_points with the test's axis (sat_n, from R toward I) and separation.
template <class T>
void box_edge_closest(GBoxPairManifold<T>& out, mask_t<T> todo, GVec3<T> const (&rc)[4],
                      GVec3<T> const (&iv)[4], std::array<T, 2> const& ref_axis,
                      std::array<T, 2> const& inc_axis, std::array<GVec3<T>, 3> const& rx,
                      std::array<GVec3<T>, 3> const& ix, GVec3<T> const& er, GVec3<T> const& ei,
                      GVec3<T> const& tr, GVec3<T> const& d, GVec3<T> const& sat_n, T sat_sep,
                      T pred) noexcept {
  using S = scalar_t<T>;
  using V = GVec3<T>;
  using M = mask_t<T>;
  T const z = zero<T>();
  T best = infinity<T>(), axis_r = z, axis_i = z;
  M best_par{};
  V pr{}, pi{};
  T const more = splat<T>(S(1) + S(1e-4)), less = splat<T>(S(1) - S(1e-4));
  for (std::size_t s = 0; s < 4; ++s)
    for (std::size_t i = 0; i < 4; ++i) {
      V cp, cq;
      M const par =
          segment_closest(rc[s], rc[(s + 1) % 4] - rc[s], iv[i], iv[(i + 1) % 4] - iv[i], cp, cq);
      T const d2 = (cq - cp).length_squared();
      // The nearest, the first of equals; but parallel edges (the middle of their common
      // part) win a tie, within 1e-4 of the squared distance, against the end of a crossing
      // edge that is as near (the corner where they meet), so the point does not jump from
      // one end of the common part to the other with the rounding.
      M const b = ((par == best_par) & (d2 < best)) | (par & !best_par & (d2 <= best * more)) |
                  (best_par & !par & (d2 < best * less));
      best_par = (best_par & !b) | (par & b);
      best = plume::select(b, d2, best);
      pr = V::select(b, cp, pr);
      pi = V::select(b, cq, pi);
      axis_r = plume::select(b, ref_axis[s % 2], axis_r);
      axis_i = plume::select(b, inc_axis[i % 2], axis_i);
    }
  box_nearest_points(out, todo, pr, pi, best, axis_r, axis_i, rx, ix, er, ei, tr, d, sat_n, sat_sep,
                     pred);
}

/// The lanes of todo whose boxes R (centre tr, axes rx, half extents er) and I (centre tr + d)
/// are nearest, the caller believes, at pr and pi (relative to tr; dist2 apart) on R's edge
/// along axis_r and I's along axis_i. The points' distance is an upper bound on the boxes'
/// distance; the gap between the boxes' supports along any unit axis is a lower bound. The
/// lane is answered when the bounds meet within slack = 1% of the prediction distance + 16 eps
/// x size (size = the six extents plus |d|'s largest component), first along the line
/// joining the points (normal: that line; separation: their distance), else along the
/// separating-axis test's axis sat_n, whose separation sat_sep is its gap (normal: sat_n;
/// separation: the points' offset along it; the point on R moved to pi - sat_n x separation,
/// as a face contact's point on its reference face). Two points closer than their rounding
/// allows give a line that is mostly noise (touching boxes: the settled pyramid's diagonal
/// neighbours, micrometres apart); the axis is exact. Either way the separation is within
/// slack of the boxes' distance (or of minus their overlap); one point (key 25, ids as an
/// edge contact's) when it is within the prediction distance. Lanes neither bound certifies
/// (a vertex or another face is nearer, or the boxes overlap more than slack) are general.
template <class T>
void box_nearest_points(GBoxPairManifold<T>& out, mask_t<T> todo, GVec3<T> const& pr,
                        GVec3<T> const& pi, T dist2, T axis_r, T axis_i,
                        std::array<GVec3<T>, 3> const& rx, std::array<GVec3<T>, 3> const& ix,
                        GVec3<T> const& er, GVec3<T> const& ei, GVec3<T> const& tr,
                        GVec3<T> const& d, GVec3<T> const& sat_n, T sat_sep, T pred) noexcept {
  using S = scalar_t<T>;
  using V = GVec3<T>;
  using M = mask_t<T>;
  T const z = zero<T>(), o = one<T>();
  M const rb = out.ref_is_b;
  T const dist = plume::sqrt(dist2);
  M const apart = (dist > z) & (dist < infinity<T>());
  V const n = (pi - pr) / plume::select(apart, dist, o); // from R toward I
  // How far each box reaches past its point along n: R beyond pr, I before pi. The gap
  // along n, dist - (hr - hi), is a lower bound on the boxes' distance, and dist an upper one.
  T const hr = ((er.x * plume::abs(rx[0].dot(n)) + er.y * plume::abs(rx[1].dot(n))) +
                er.z * plume::abs(rx[2].dot(n))) -
               pr.dot(n);
  T const hi =
      (d - pi).dot(n) - ((ei.x * plume::abs(ix[0].dot(n)) + ei.y * plume::abs(ix[1].dot(n))) +
                         ei.z * plume::abs(ix[2].dot(n)));
  T const size =
      (((er.x + er.y) + er.z) + ((ei.x + ei.y) + ei.z)) +
      plume::max_select(plume::max_select(plume::abs(d.x), plume::abs(d.y)), plume::abs(d.z));
  T const slack = splat<T>(S(16) * epsilon<S>()) * size + splat<T>(S(0.01)) * pred;
  // Certified by the line joining the points, or else by the separating-axis test's axis
  // (its separation is a lower bound too): the direction between two points closer than the
  // rounding of their coordinates allows is noise, the axis is not.
  M const by_points = apart & (hr - hi <= slack); // false for NaN
  M const by_axis = (dist < infinity<T>()) & (dist - sat_sep <= slack) & !by_points;
  M const ok = todo & (by_points | by_axis);
  V const n_out = V::select(by_points, n, sat_n);
  T const sep = plume::select(by_points, dist, (pi - pr).dot(sat_n));
  out.general = out.general | (todo & !ok);
  M const hit = ok & (sep <= pred);
  T const ia = plume::select(rb, axis_i, axis_r), jb = plume::select(rb, axis_r, axis_i);
  out.normal = V::select(ok, V::select(rb, -n_out, n_out), out.normal);
  // On the axis, the point on R is I's point moved back along the axis (as a face contact's
  // point on its reference face), so point_b - point_a is separation x normal.
  V const pr_w = tr + V::select(by_points, pr, pi - sat_n * sep), pi_w = tr + pi;
  out.point_a[0] = V::select(hit, V::select(rb, pi_w, pr_w), out.point_a[0]);
  out.point_b[0] = V::select(hit, V::select(rb, pr_w, pi_w), out.point_b[0]);
  out.separation[0] = plume::select(hit, sep, out.separation[0]);
  out.key[0] = plume::select(hit, splat<T>(S(25)), out.key[0]);
  out.ref_face = plume::select(ok, splat<T>(S(6)) + splat<T>(S(3)) * ia + jb, out.ref_face);
  out.inc_face = plume::select(ok, z, out.inc_face);
  out.count = plume::select(hit, o, out.count);
  out.ref_is_b = out.ref_is_b & !ok;
}

/// box_pair_manifold's face contact, for the lanes of `todo` (near, finite, a face axis k of
/// the reference box): the reference face, the incident face, the 24 candidates and the
/// reduction.
template <class T>
void box_face_contact(GBoxPairManifold<T>& out, mask_t<T> todo, std::array<GVec3<T>, 3> const& ax,
                      std::array<GVec3<T>, 3> const& bx, GVec3<T> const& ea, GVec3<T> const& eb,
                      GIso3<T> const& pose_a, GIso3<T> const& pose_b, T k, T separation,
                      T pred) noexcept {
  using S = scalar_t<T>;
  using V = GVec3<T>;
  using M = mask_t<T>;
  T const z = zero<T>(), o = one<T>(), none = splat<T>(S(-1));
  // The reference box R and the incident box I.
  M const rb_ = out.ref_is_b;
  std::array<V, 3> const rx = {V::select(rb_, bx[0], ax[0]), V::select(rb_, bx[1], ax[1]),
                               V::select(rb_, bx[2], ax[2])};
  std::array<V, 3> const ix = {V::select(rb_, ax[0], bx[0]), V::select(rb_, ax[1], bx[1]),
                               V::select(rb_, ax[2], bx[2])};
  V const er = V::select(rb_, eb, ea), ei = V::select(rb_, ea, eb);
  V const tr = V::select(rb_, pose_b.translation, pose_a.translation);
  V const ti = V::select(rb_, pose_a.translation, pose_b.translation);
  V const rn = V::select(rb_, -out.normal, out.normal); // the reference face's outward normal
  V const axis_k = pick3(k, rx[0], rx[1], rx[2]);
  T const sign_r = plume::select(rn.dot(axis_k) >= z, o, -o);
  V const u = pick3(k, rx[1], rx[2], rx[0]);
  V const v = pick3(k, rx[2], rx[0], rx[1]);
  T const hu = pick3(k, er.y, er.z, er.x);
  T const hv = pick3(k, er.z, er.x, er.y);
  V const c = tr + rn * pick3(k, er.x, er.y, er.z);
  M const has_area = (hu > z) & (hv > z);
  M const face = todo & has_area;
  M const flat = !has_area;
  out.general = out.general | (todo & flat);
  // The incident face: the face of I whose outward normal is most against rn.
  T best_i = none, ji = z, sign_i = o;
  for (std::size_t j = 0; j < 3; ++j) {
    T const dj = ix[j].dot(rn);
    M const better = plume::abs(dj) > best_i;
    best_i = plume::select(better, plume::abs(dj), best_i);
    ji = plume::select(better, splat<T>(S(j)), ji);
    sign_i = plume::select(better, plume::select(dj > z, -o, o), sign_i);
  }
  out.ref_face = plume::select(face, k + k + plume::select(sign_r > z, o, z), z);
  out.inc_face = plume::select(face, ji + ji + plume::select(sign_i > z, o, z), z);
  V const m = pick3(ji, ix[0], ix[1], ix[2]) * sign_i;
  V const ci = ti + m * pick3(ji, ei.x, ei.y, ei.z);
  V const p = pick3(ji, ix[1], ix[2], ix[0]) * pick3(ji, ei.y, ei.z, ei.x);
  V const q = pick3(ji, ix[2], ix[0], ix[1]) * pick3(ji, ei.z, ei.x, ei.y);
  // Counter-clockwise seen from outside the incident face when sign_i > 0 (p x q = +m); the
  // other face runs the same corners the other way.
  V const iv[4] = {(ci + p) + q, (ci - p) + q, (ci - p) - q, (ci + p) - q};
  std::array<T, 4> x{}, y{};
  for (std::size_t i = 0; i < 4; ++i) {
    V const w = iv[i] - c;
    x[i] = w.dot(u);
    y[i] = w.dot(v);
  }
  std::array<box_candidate<T>, 24> cand;
  auto const finish = [&](box_candidate<T>& cd, M ok) {
    cd.h = (cd.p - c).dot(rn);
    cd.pos = V::select(rb_, cd.p - rn * cd.h, cd.p);
    cd.ok = ok & (cd.h <= pred) & face;
  };
  M all_inside = face;
  for (std::size_t i = 0; i < 4; ++i) {
    cand[i].p = iv[i];
    M const inside = (plume::abs(x[i]) <= hu) & (plume::abs(y[i]) <= hv);
    all_inside = all_inside & inside;
    finish(cand[i], inside);
  }
  // With every incident vertex inside the rectangle no edge crosses a side and no corner is
  // strictly inside the incident face: only the first 4 candidates can be kept.
  std::size_t used = 4;
  if (plume::any(face & !all_inside)) {
    used = 24;
    for (std::size_t i = 0; i < 4; ++i) {
      std::size_t const j = (i + 1) % 4;
      for (std::size_t s = 0; s < 4; ++s) {
        bool const along_u = s % 2 == 0; // sides 0, 2 are the lines u = +-hu
        T const bound = s == 0 ? hu : s == 1 ? hv : s == 2 ? -hu : -hv;
        T const other = along_u ? hv : hu;
        std::array<T, 4> const& cut = along_u ? x : y;
        std::array<T, 4> const& run = along_u ? y : x;
        T const si = cut[i] - bound, sj = cut[j] - bound;
        M const crosses = ((si < z) & (sj > z)) | ((si > z) & (sj < z));
        T const t = si / plume::select(crosses, si - sj, o);
        T const at = run[i] + (run[j] - run[i]) * t;
        box_candidate<T>& cd = cand[4 + 4 * i + s];
        cd.p = iv[i] + (iv[j] - iv[i]) * t;
        finish(cd, crosses & (plume::abs(at) <= other));
      }
    }
    T const denom = rn.dot(m); // < 0: the incident face is against rn
    for (std::size_t s = 0; s < 4; ++s) {
      T const cx = s == 0 || s == 3 ? hu : -hu;
      T const cy = s <= 1 ? hv : -hv;
      std::array<T, 4> side{};
      for (std::size_t i = 0; i < 4; ++i) {
        std::size_t const j = (i + 1) % 4;
        side[i] = (x[j] - x[i]) * (cy - y[i]) - (y[j] - y[i]) * (cx - x[i]);
      }
      M const inside = ((side[0] > z) & (side[1] > z) & (side[2] > z) & (side[3] > z)) |
                       ((side[0] < z) & (side[1] < z) & (side[2] < z) & (side[3] < z));
      V const corner = (c + u * cx) + v * cy;
      T const h = (ci - corner).dot(m) / plume::select(denom < z, denom, -o);
      box_candidate<T>& cd = cand[20 + s];
      cd.p = corner + rn * h;
      finish(cd, inside & (denom < z));
    }
  }

  // Up to 4 candidates: all of them, in candidate order.
  std::array<T, 4> pick = {none, none, none, none};
  T kept = z;
  for (std::size_t s = 0; s < used; ++s) {
    for (std::size_t slot = 0; slot < 4; ++slot)
      pick[slot] =
          plume::select(cand[s].ok & (kept == splat<T>(S(slot))), splat<T>(S(s)), pick[slot]);
    kept = kept + plume::select(cand[s].ok, o, z);
  }
  // More: Gregorius' reduction, measured at B's points.
  M const reduce = kept > splat<T>(S(4));
  if (plume::any(reduce)) {
    V const fn = V::select(rb_, -rn, rn); // the manifold's normal
    T i0 = none, b0 = infinity<T>();
    V p0{};
    for (std::size_t s = 0; s < 24; ++s) { // the deepest (the first of equals)
      M const b = cand[s].ok & (cand[s].h < b0);
      b0 = plume::select(b, cand[s].h, b0);
      i0 = plume::select(b, splat<T>(S(s)), i0);
      p0 = V::select(b, cand[s].pos, p0);
    }
    auto const farthest = [&](std::size_t s, T val, T& best, T& idx, V& pos, M extra) {
      M const b = cand[s].ok & extra & (val > best);
      best = plume::select(b, val, best);
      idx = plume::select(b, splat<T>(S(s)), idx);
      pos = V::select(b, cand[s].pos, pos);
    };
    T i1 = none, b1 = none;
    V p1{};
    for (std::size_t s = 0; s < 24; ++s) // the farthest from it
      farthest(s, (cand[s].pos - p0).length_squared(), b1, i1, p1, i0 != splat<T>(S(s)));
    T i2 = none, b2 = none;
    V p2{};
    for (std::size_t s = 0; s < 24; ++s) { // the largest triangle with them
      T const id = splat<T>(S(s));
      farthest(s, plume::abs((p1 - p0).cross(cand[s].pos - p0).dot(fn)), b2, i2, p2,
               (i0 != id) & (i1 != id));
    }
    // Counter-clockwise around the normal, then the point most outside one of its edges.
    M const flip = (p1 - p0).cross(p2 - p0).dot(fn) < z;
    T const j1 = plume::select(flip, i2, i1), j2 = plume::select(flip, i1, i2);
    V const q1 = V::select(flip, p2, p1), q2 = V::select(flip, p1, p2);
    T i3 = none, b3 = z;
    for (std::size_t s = 0; s < 24; ++s) {
      T const id = splat<T>(S(s));
      M const other = (i0 != id) & (j1 != id) & (j2 != id) & cand[s].ok;
      V const& ps = cand[s].pos;
      T const e0 = (q1 - p0).cross(ps - p0).dot(fn);
      T const e1 = (q2 - q1).cross(ps - q1).dot(fn);
      T const e2 = (p0 - q2).cross(ps - q2).dot(fn);
      for (T const a : {e0, e1, e2}) { // the most negative edge area (below zero)
        M const b = other & (a < b3);
        b3 = plume::select(b, a, b3);
        i3 = plume::select(b, id, i3);
      }
    }
    // With more than 4 candidates i1 and i2 exist unless distances or areas are NaN; then
    // keep what was picked.
    M const tri = i2 >= z;
    pick[0] = plume::select(reduce, i0, pick[0]);
    pick[1] = plume::select(reduce, plume::select(tri, j1, i1), pick[1]);
    pick[2] = plume::select(reduce, plume::select(tri, j2, none), pick[2]);
    pick[3] = plume::select(reduce, plume::select(tri, i3, none), pick[3]);
  }
  T count = z;
  for (std::size_t slot = 0; slot < 4; ++slot) {
    count = count + plume::select(pick[slot] >= z, o, z);
    V pt{};
    T h = z;
    take_candidate(cand, used, pick[slot], pt, h);
    V const on_ref = pt - rn * h;
    out.point_a[slot] = V::select(rb_, pt, on_ref);
    out.point_b[slot] = V::select(rb_, on_ref, pt);
    out.separation[slot] = h;
    out.key[slot] = pick[slot];
  }
  out.normal = V::select(face, V::select(rb_, -rn, rn), out.normal);
  out.count = plume::select(face, count, out.count);
  M const empty = face & (count == z);
  if (plume::any(empty)) {
    // In coordinates centred on R (the rounding of the points, and so of the direction
    // between them, scales with the boxes, not with their distance from the origin).
    V const cr = rn * pick3(k, er.x, er.y, er.z), d = ti - tr;
    V const rc[4] = {(cr + u * hu) + v * hv, (cr - u * hu) + v * hv, (cr - u * hu) - v * hv,
                     (cr + u * hu) - v * hv};
    V const ci_r = d + m * pick3(ji, ei.x, ei.y, ei.z);
    V const iv_r[4] = {(ci_r + p) + q, (ci_r - p) + q, (ci_r - p) - q, (ci_r + p) - q};
    auto const next = [&](T a) { return plume::select(a == splat<T>(S(2)), z, a + o); };
    T const ku = next(k), ji_p = next(ji);
    box_edge_closest(out, empty, rc, iv_r, {ku, next(ku)}, {ji_p, next(ji_p)}, rx, ix, er, ei, tr,
                     d, rn, separation, pred);
  }
}

/// box_pair_manifold's edge contact, for the lanes of `todo` (near, finite, an edge axis n
/// between A's edge direction ie and B's je): the closest points of the supporting edges.
template <class T>
void box_edge_contact(GBoxPairManifold<T>& out, mask_t<T> todo, std::array<GVec3<T>, 3> const& ax,
                      std::array<GVec3<T>, 3> const& bx, std::array<T, 3> const& e_a,
                      std::array<T, 3> const& e_b, GIso3<T> const& pose_a, GIso3<T> const& pose_b,
                      GVec3<T> const& n, T separation, T ie, T je, GVec3<T> const& ea,
                      GVec3<T> const& eb, T pred) noexcept {
  using S = scalar_t<T>;
  using V = GVec3<T>;
  using M = mask_t<T>;
  T const z = zero<T>(), o = one<T>();
  // In coordinates centred on A.
  V const d = pose_b.translation - pose_a.translation;
  V ca{}, cb = d;
  for (std::size_t kk = 0; kk < 3; ++kk) {
    T const kf = splat<T>(S(kk));
    T const sa = plume::select(ax[kk].dot(n) >= z, e_a[kk], -e_a[kk]);
    T const sb = plume::select(bx[kk].dot(n) >= z, -e_b[kk], e_b[kk]);
    ca = ca + ax[kk] * plume::select(ie == kf, z, sa);
    cb = cb + bx[kk] * plume::select(je == kf, z, sb);
  }
  V const ua = pick3(ie, ax[0], ax[1], ax[2]);
  V const ub = pick3(je, bx[0], bx[1], bx[2]);
  T const la = pick3(ie, e_a[0], e_a[1], e_a[2]);
  T const lb = pick3(je, e_b[0], e_b[1], e_b[2]);
  V const w = ca - cb;
  T const bb = ua.dot(ub), dd = ua.dot(w), ee = ub.dot(w);
  T const den = o - bb * bb;
  T const den_safe = plume::select(den > z, den, o);
  T const s_a = (bb * ee - dd) / den_safe;
  T const s_b = (ee - bb * dd) / den_safe;
  // The lines' closest points off either edge, or no closest points (edges parallel within the
  // rounding): the edges' own closest points, checked as box_edge_closest checks its own.
  M const off = todo & !((den > z) & (plume::abs(s_a) <= la) & (plume::abs(s_b) <= lb));
  if (plume::any(off)) {
    V cp, cq;
    segment_closest(ca - ua * la, ua * (la + la), cb - ub * lb, ub * (lb + lb), cp, cq);
    box_nearest_points(out, off, cp, cq, (cq - cp).length_squared(), ie, je, ax, bx, ea, eb,
                       pose_a.translation, d, n, separation, pred);
  }
  todo = todo & !off;
  out.point_a[0] = V::select(todo, pose_a.translation + (ca + ua * s_a), out.point_a[0]);
  out.point_b[0] = V::select(todo, pose_a.translation + (cb + ub * s_b), out.point_b[0]);
  out.separation[0] = plume::select(todo, separation, out.separation[0]);
  out.key[0] = plume::select(todo, splat<T>(S(24)), out.key[0]);
  out.ref_face = plume::select(todo, splat<T>(S(6)) + splat<T>(S(3)) * ie + je, out.ref_face);
  out.inc_face = plume::select(todo, z, out.inc_face);
  out.count = plume::select(todo, o, out.count);
}

} // namespace detail

/// The contact manifold of cuboids with half extents ea (at pose_a) and eb (at pose_b), points
/// kept up to `prediction` apart; one pair per lane.
template <Float T>
GBoxPairManifold<T> box_pair_manifold(GVec3<T> const& ea, GIso3<T> const& pose_a,
                                      GVec3<T> const& eb, GIso3<T> const& pose_b,
                                      scalar_t<T> prediction) noexcept {
  using S = scalar_t<T>;
  using V = GVec3<T>;
  using M = mask_t<T>;
  T const z = zero<T>(), o = one<T>(), pred = splat<T>(prediction);
  T const tol = splat<T>(S(0.1) * prediction);
  GBoxPairManifold<T> out;

  GMat3<T> const ma = GMat3<T>::from_quat(pose_a.rotation);
  GMat3<T> const mb = GMat3<T>::from_quat(pose_b.rotation);
  std::array<V, 3> const ax = {ma.x_axis, ma.y_axis, ma.z_axis};
  std::array<V, 3> const bx = {mb.x_axis, mb.y_axis, mb.z_axis};
  std::array<T, 3> const e_a = {ea.x, ea.y, ea.z};
  std::array<T, 3> const e_b = {eb.x, eb.y, eb.z};
  V const d = pose_b.translation - pose_a.translation;

  // 1. Separating axes. |a_i . b_j| is padded so nearly parallel edges make no bogus axis.
  std::array<std::array<T, 3>, 3> r{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j)
      r[i][j] = plume::abs(ax[i].dot(bx[j])) + splat<T>(S(1e-6));
  T best_a = neg_infinity<T>(), best_b = best_a, best_e = best_a;
  V na{}, nb{}, ne{};
  T ia = z, jb = z, ie = z, je = z;
  for (std::size_t i = 0; i < 3; ++i) {
    T const t = d.dot(ax[i]);
    T const sep =
        plume::abs(t) - (e_a[i] + (e_b[0] * r[i][0] + e_b[1] * r[i][1]) + e_b[2] * r[i][2]);
    M const better = sep > best_a;
    best_a = plume::select(better, sep, best_a);
    na = V::select(better, V::select(t >= z, ax[i], -ax[i]), na);
    ia = plume::select(better, splat<T>(S(i)), ia);
  }
  for (std::size_t j = 0; j < 3; ++j) {
    T const t = d.dot(bx[j]);
    T const sep =
        plume::abs(t) - ((e_a[0] * r[0][j] + e_a[1] * r[1][j]) + e_a[2] * r[2][j] + e_b[j]);
    M const better = sep > best_b;
    best_b = plume::select(better, sep, best_b);
    nb = V::select(better, V::select(t >= z, bx[j], -bx[j]), nb);
    jb = plume::select(better, splat<T>(S(j)), jb);
  }
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) {
      V const c = ax[i].cross(bx[j]);
      T const len = c.length();
      M const usable = len > splat<T>(S(1e-4)); // parallel edges: the face axes cover them
      V const n = c / plume::select(usable, len, o);
      T const t = d.dot(n);
      T const ra = (e_a[0] * plume::abs(ax[0].dot(n)) + e_a[1] * plume::abs(ax[1].dot(n))) +
                   e_a[2] * plume::abs(ax[2].dot(n));
      T const rb = (e_b[0] * plume::abs(bx[0].dot(n)) + e_b[1] * plume::abs(bx[1].dot(n))) +
                   e_b[2] * plume::abs(bx[2].dot(n));
      T const sep = plume::abs(t) - (ra + rb);
      M const better = usable & (sep > best_e);
      best_e = plume::select(better, sep, best_e);
      ne = V::select(better, V::select(t >= z, n, -n), ne);
      ie = plume::select(better, splat<T>(S(i)), ie);
      je = plume::select(better, splat<T>(S(j)), je);
    }
  M const face_b = best_b > best_a + tol;
  T separation = plume::select(face_b, best_b, best_a);
  V normal = V::select(face_b, nb, na);
  M const edge = best_e > separation + tol;
  separation = plume::select(edge, best_e, separation);
  normal = V::select(edge, ne, normal);
  M const finite = plume::is_finite(separation) & ea.is_finite() & eb.is_finite() &
                   pose_a.is_finite() & pose_b.is_finite();
  M const near = separation <= pred; // false for NaN
  out.normal = normal;
  out.general = !finite;
  out.ref_is_b = face_b & !edge;

  // 3. Face contact. A batch skips what none of its lanes needs: the results of the lanes
  // that need it are the same either way.
  M const face_try = near & finite & !edge;
  if (plume::any(face_try))
    detail::box_face_contact(out, face_try, ax, bx, ea, eb, pose_a, pose_b,
                             plume::select(out.ref_is_b, jb, ia), separation, pred);
  // 4. Edge contact: the edges of A along axis ie and of B along je that support the axis.
  M const edge_hit = near & finite & edge;
  if (plume::any(edge_hit))
    detail::box_edge_contact(out, edge_hit, ax, bx, e_a, e_b, pose_a, pose_b, ne, best_e, ie, je,
                             ea, eb, pred);
  return out;
}

} // namespace plume

PLUME_MASK_CODE_END
