// plume/collision/detail/simplex.hpp - the GJK simplex and its closest-point step, written
// with selects so that every lane of a wide T runs the same instructions (not a public
// header; used by collision/gjk.hpp).
//
// The simplex holds up to three old points plus the newest one, w. Each point p lives in the
// set D the query runs on (D = B - A for distances and shape casts, the shape itself for a ray
// cast), with the support points a (on A) and b (on B) that made it; the step looks for the
// point of conv{x - p_i} closest to the origin, x being the query point (0 for distances, the
// ray's current point for casts).
//
// Rather than Johnson's case tree, the step evaluates every sub-simplex that contains w (the
// point, 3 edges, 3 triangles, the tetrahedron), projects the origin on its affine hull, and
// keeps the nearest projection whose barycentric coordinates are all positive: the closest
// point of a simplex lies in the relative interior of exactly one face, where it equals that
// projection, and every other valid projection is a point of the simplex, so no nearer. Flat
// faces (area or volume below a relative epsilon) are skipped; their edges stand in for them.
// Locals are not const, for the reason gjk.hpp gives.
#pragma once

#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <array>
#include <utility>

PLUME_MASK_CODE_BEGIN

namespace plume::detail {

template <Real T>
struct simplex_vertex {
  GVec3<T> p; ///< in D
  GVec3<T> a; ///< on A (zero for a ray cast)
  GVec3<T> b; ///< on B
};

template <Real T>
struct simplex {
  std::array<simplex_vertex<T>, 3> v{};
  std::array<mask_t<T>, 3> present{no_lanes<T>(), no_lanes<T>(), no_lanes<T>()};
};

template <Real T>
struct simplex_step {
  GVec3<T> v;              ///< the closest point of conv{x - p_i} to the origin
  std::array<T, 4> lambda; ///< barycentric weights of w and the three old slots
  simplex<T> next;         ///< the sub-simplex v lies on (w first)
  mask_t<T> inside;        ///< the origin is inside the tetrahedron: v = 0
};

/// One GJK step: the old simplex s, the newest vertex w, the query point x.
template <Real T>
PLUME_INLINE simplex_step<T> closest_on_simplex(simplex<T> const& s, simplex_vertex<T> const& w,
                                                GVec3<T> const& x) noexcept {
  T zero = plume::zero<T>();
  T eps = epsilon<T>();
  GVec3<T> y0 = x - w.p;
  std::array<GVec3<T>, 3> y{x - s.v[0].p, x - s.v[1].p, x - s.v[2].p};

  // The point {w}: always valid.
  simplex_step<T> best;
  best.v = y0;
  best.lambda = {one<T>(), zero, zero, zero};
  best.inside = no_lanes<T>();
  mask_t<T> chosen_member[3] = {no_lanes<T>(), no_lanes<T>(), no_lanes<T>()};
  T best_d2 = y0.dot(y0);

  auto take = [&](mask_t<T> better, GVec3<T> const& v, std::array<T, 4> const& l,
                  std::array<bool, 3> members) {
    best.v = GVec3<T>::select(better, v, best.v);
    for (std::size_t k = 0; k < 4; ++k)
      best.lambda[k] = plume::select(better, l[k], best.lambda[k]);
    for (std::size_t k = 0; k < 3; ++k)
      chosen_member[k] = plume::select(better, mask_t<T>(members[k]), chosen_member[k]);
    best_d2 = plume::select(better, v.dot(v), best_d2);
  };

  // Edges {w, i}: t = -y0 . e / e . e with e = y_i - y0, valid for 0 < t < 1. v = y0 + t e
  // is then taken once more off e: where the edge passes near the origin with its ends far
  // away, the sum cancels to |v| with the ends' rounding, which turns v off the perpendicular
  // and makes the supports along -v favour the edge's own ends (a GJK query then stops early,
  // far from the distance). The second projection leaves an error of eps |v| along e.
  // Each edge's e . e, t and foot y0 + t e (on the whole line) are kept for the triangles.
  std::array<GVec3<T>, 3> foot;
  std::array<T, 3> edge_ee, edge_t;
  // A candidate no lane's simplex has is skipped (its lanes would not be taken either, so
  // every lane's answer is the same as without the test): early iterations, where the old
  // simplex holds one or two points, pay for the edges alone.
  for (std::size_t i = 0; i < 3; ++i) {
    if (!plume::any(s.present[i])) continue;
    GVec3<T> e = y[i] - y0;
    T ee = e.dot(e);
    T num = -y0.dot(e);
    mask_t<T> ok = s.present[i] & (ee > zero) & (num > zero) & (num < ee);
    T safe_ee = plume::select(ee > zero, ee, one<T>());
    T t = num / safe_ee;
    GVec3<T> v = y0 + e * t;
    foot[i] = v, edge_ee[i] = ee, edge_t[i] = t;
    v = v - e * (v.dot(e) / safe_ee);
    std::array<T, 4> l{one<T>() - t, zero, zero, zero};
    l[i + 1] = t;
    std::array<bool, 3> m{false, false, false};
    m[i] = true;
    take(ok & (v.dot(v) < best_d2), v, l, m);
  }

  // Triangles {w, i, j}: with ei = yi - y0, ej = yj - y0 and n = ei x ej, v is the origin's
  // projection on the plane, along n (not the weighted sum of the y's): its direction then
  // comes from the edges alone, accurate even when |v| is tiny next to the coordinates (a ray
  // point a hair off a 1,000 m face), where the weighted sum is all cancellation noise. The
  // plane is taken through r, the foot of the origin on the line of the longer edge from w,
  // not through y0: n carries a rounding of eps / sin radians (sin: the sine of the angle at
  // w), which moves the projection by that angle times the distance from the origin to the
  // point the plane is taken through: through y0, a sliver far from the origin gets v
  // eps |y0| / sin off (docs/fuzzing.md, regress-sliver-face-far-from-origin). r lies within
  // the triangle's width (the other edge times sin) of the projection, so the error is
  // eps |v| / sin plus the rounding floor. The weights likewise: r's (t on its edge) plus
  // those of the short step d = v - r, by cross products with d over |n|^2; from the edges,
  // not from the long vectors to the vertices (for a small triangle far from the query point
  // those cross products are all rounding).
  constexpr std::size_t pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (auto const& pr : pairs) {
    std::size_t const i = pr[0], j = pr[1];
    // (Implies both edges' guards above: foot, edge_t and edge_ee of i and j are set.)
    if (!plume::any(s.present[i] & s.present[j])) continue;
    GVec3<T> ei = y[i] - y0, ej = y[j] - y0;
    GVec3<T> n = ei.cross(ej);
    T nn = n.dot(n);
    T eii = edge_ee[i], ejj = edge_ee[j];
    mask_t<T> flat = nn <= eps * (eii * ejj);
    T rn = one<T>() / plume::select(flat, one<T>(), nn);
    mask_t<T> along_i = eii >= ejj;
    T t = plume::select(along_i, edge_t[i], edge_t[j]); // (e . e > 0 unless flat)
    GVec3<T> r = GVec3<T>::select(along_i, foot[i], foot[j]);
    GVec3<T> v = n * (r.dot(n) * rn);
    GVec3<T> d = v - r;
    T li = d.cross(ej).dot(n) * rn; // d = li ei + lj ej, then t joins the edge's weight
    T lj = ei.cross(d).dot(n) * rn;
    li = li + plume::select(along_i, t, zero);
    lj = lj + plume::select(along_i, zero, t);
    T lw = (one<T>() - li) - lj;
    mask_t<T> ok = s.present[i] & s.present[j] & (!flat) & (lw > zero) & (li > zero) & (lj > zero);
    std::array<T, 4> l{lw, zero, zero, zero};
    l[i + 1] = li;
    l[j + 1] = lj;
    std::array<bool, 3> m{false, false, false};
    m[i] = m[j] = true;
    take(ok & (v.dot(v) < best_d2), v, l, m);
  }

  // The tetrahedron: the origin inside when its four barycentric weights are positive. Two
  // thresholds on |det| against |e0| |e1| |e2|:
  // - within 64 eps (its rounding is a few eps of that) det's sign is in doubt: flat, skipped;
  // - above that, the inside test holds (a weight's rounding moves it by about eps |y0| over
  //   the sine of a face's angle, however flat the tetrahedron), so a point inside a long,
  //   thin sliver is found inside;
  // - but only above sqrt(eps) are the weights good enough to make the closest points from
  //   (sums of supports far apart, whose error grows as the tetrahedron flattens). Between
  //   the two, an origin inside keeps the v and weights of the nearest face or edge through w
  //   (the face opposite w is not a candidate, so the two points can be up to the sliver's
  //   thickness apart) and is flagged inside: the query stops there with those points.
  // docs/fuzzing.md (regress-point-inside-sliver-tetrahedron) has the cases and numbers.
  if (plume::any((s.present[0] & s.present[1]) & s.present[2])) {
    GVec3<T> e0 = y[0] - y0, e1 = y[1] - y0, e2 = y[2] - y0;
    T det = e0.dot(e1.cross(e2));
    T scale = (e0.dot(e0) * e1.dot(e1)) * e2.dot(e2);
    T flat_k = splat<T>(scalar_t<T>(64)) * eps;
    mask_t<T> flat = det * det <= (flat_k * flat_k) * scale;
    mask_t<T> sliver = det * det <= eps * scale;
    T rd = one<T>() / plume::select(flat, one<T>(), det);
    T l0 = -y0.dot(e1.cross(e2)) * rd;
    T l1 = -e0.dot(y0.cross(e2)) * rd; // e0 . ((0 - y0) x e2)
    T l2 = -e0.dot(e1.cross(y0)) * rd; // e0 . (e1 x (0 - y0))
    T lw = (one<T>() - l0 - l1) - l2;
    mask_t<T> ok = (s.present[0] & s.present[1]) & (s.present[2] & (!flat)) &
                   ((l0 > zero) & (l1 > zero)) & ((l2 > zero) & (lw > zero));
    take(ok & (!sliver), GVec3<T>{}, std::array<T, 4>{lw, l0, l1, l2}, {true, true, true});
    best.inside = ok;
  }

  // The next simplex: w, then the chosen old members in slot order.
  best.next.v[0] = w;
  best.next.present[0] = all_lanes<T>();
  // Slot 1 takes the first chosen member, slot 2 the second, slot 3 the third.
  mask_t<T> c0 = chosen_member[0], c1 = chosen_member[1], c2 = chosen_member[2];
  auto pick = [](mask_t<T> m, simplex_vertex<T> const& a, simplex_vertex<T> const& b) {
    return simplex_vertex<T>{GVec3<T>::select(m, a.p, b.p), GVec3<T>::select(m, a.a, b.a),
                             GVec3<T>::select(m, a.b, b.b)};
  };
  best.next.v[1] = pick(c0, s.v[0], pick(c1, s.v[1], s.v[2]));
  best.next.present[1] = (c0 | c1) | c2;
  mask_t<T> second_is_1 = c0 & c1;
  mask_t<T> second_is_2 = (c0 | c1) & c2;
  best.next.v[2] = pick(second_is_1, s.v[1], s.v[2]);
  best.next.present[2] = second_is_1 | second_is_2;
  // (When the origin is inside, the third member is dropped: the query stops there.)
  return best;
}

/// The lanes where w is already a vertex of s (the same point of D): a step with it can
/// learn nothing new.
template <Real T>
PLUME_INLINE mask_t<T> holds(simplex<T> const& s, simplex_vertex<T> const& w) noexcept {
  mask_t<T> out = no_lanes<T>();
  for (std::size_t k = 0; k < 3; ++k)
    out = out | (s.present[k] &
                 (((s.v[k].p.x == w.p.x) & (s.v[k].p.y == w.p.y)) & (s.v[k].p.z == w.p.z)));
  return out;
}

/// The weighted sums of the a and b points of the step's simplex (the closest points on A and
/// B) for the weights of step.lambda over (w, old slots).
template <Real T>
PLUME_INLINE std::pair<GVec3<T>, GVec3<T>> closest_points(simplex<T> const& s,
                                                          simplex_vertex<T> const& w,
                                                          std::array<T, 4> const& l) noexcept {
  GVec3<T> pa = w.a * l[0], pb = w.b * l[0];
  for (std::size_t k = 0; k < 3; ++k) {
    pa += s.v[k].a * l[k + 1];
    pb += s.v[k].b * l[k + 1];
  }
  return {pa, pb};
}

} // namespace plume::detail

PLUME_MASK_CODE_END
