// plume/collision/detail/quickhull.hpp - the quickhull builder and the hull's mass
// properties (included by collision/convex_hull.hpp; not a public header).
//
// GConvexHull<S>::build runs detail::hull_builder::run: the points are copied to double (all
// of the build computes in double, whatever S is), a starting tetrahedron is grown one
// farthest outside point at a time (Barber, Dobkin, Huhdanpaa 1996), and the triangles are
// merged into the polygon faces GConvexHull stores. The conventions and errors are the ones
// convex_hull.hpp states.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

namespace plume::detail::hull_builder {

/// A triangle of the hull under construction: v[i] -> v[i + 1] counter-clockwise from
/// outside, nb[i] the triangle across that edge; outside: the points assigned to it.
struct tri {
  std::array<int, 3> v;
  std::array<int, 3> nb;
  DVec3 n;  ///< unit outward normal (zero for a degenerate triangle)
  double d; ///< n . centroid
  /// With accurate heights: a bound of the error of n . p - d per unit of |p|_1 + |centroid|_1
  /// (the rounding of the normal, large for a sliver, and of the two dot products), and
  /// |(b - a) x (c - a)|.
  double err = 0, area2 = 0;
  double c1 = 0; ///< |centroid|_1
  std::vector<int> outside;
  bool alive = true;
};

/// Double-double arithmetic (error-free transformations without FMA, Dekker and Knuth): the
/// accurate heights of a build from double points.
namespace dd {
struct num {
  double hi, lo;
};
inline num two_sum(double a, double b) {
  double const s = a + b, bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}
inline num split(double a) {
  double const t = 134217729.0 * a, hi = t - (t - a); // 2^27 + 1
  return {hi, a - hi};
}
inline num two_prod(double a, double b) {
  double const p = a * b;
  num const sa = split(a), sb = split(b);
  return {p, ((sa.hi * sb.hi - p) + sa.hi * sb.lo + sa.lo * sb.hi) + sa.lo * sb.lo};
}
inline num add(num a, num b) {
  num const s = two_sum(a.hi, b.hi);
  double const lo = s.lo + (a.lo + b.lo);
  return two_sum(s.hi, lo);
}
inline num mul(num a, num b) {
  num const p = two_prod(a.hi, b.hi);
  return two_sum(p.hi, p.lo + (a.hi * b.lo + a.lo * b.hi));
}
inline num neg(num a) { return {-a.hi, -a.lo}; }
/// ((b - a) x (c - a)) . (p - a), with every difference exact and the products and sums in
/// double-double: relative error about 2^-100 of the terms.
inline double orient(DVec3 const& a, DVec3 const& b, DVec3 const& c, DVec3 const& p) {
  num const ux = two_sum(b.x, -a.x), uy = two_sum(b.y, -a.y), uz = two_sum(b.z, -a.z);
  num const vx = two_sum(c.x, -a.x), vy = two_sum(c.y, -a.y), vz = two_sum(c.z, -a.z);
  num const wx = two_sum(p.x, -a.x), wy = two_sum(p.y, -a.y), wz = two_sum(p.z, -a.z);
  num const nx = add(mul(uy, vz), neg(mul(uz, vy)));
  num const ny = add(mul(uz, vx), neg(mul(ux, vz)));
  num const nz = add(mul(ux, vy), neg(mul(uy, vx)));
  num const o = add(add(mul(nx, wx), mul(ny, wy)), mul(nz, wz));
  return o.hi + o.lo;
}
} // namespace dd

/// The hull under construction: the input points in double, every triangle made so far (dead
/// ones stay, so that indices are stable), the tolerance, and the points dropped as inside
/// while above a candidate plane (by at most tol), which grow() checks against the finished
/// hull.
struct state {
  std::vector<DVec3> p;
  std::vector<tri> tris;
  double tol = 0;
  double sees = 0; ///< the height above a triangle's plane from which a point sees it
  /// Heights decided in double-double where double's rounding could reach them (points in
  /// double: the default tolerance, 16 eps(double), is at double's own rounding).
  bool accurate = false;
  std::vector<int> near;

  DVec3 const& point(int i) const { return p[std::size_t(i)]; }
  /// The signed distance of point i above t's plane. With `accurate`, a height within the
  /// bound of its rounding is taken again as orient(a, b, c, p) / |(b - a) x (c - a)| with the
  /// orientation in double-double: its sign no longer depends on the rounding of a sliver's
  /// normal, and its size only through |(b - a) x (c - a)| in double (a relative error of a
  /// few eps times the sliver's aspect ratio).
  double dist(tri const& t, int i) const {
    DVec3 const& q = p[std::size_t(i)];
    double const h = t.n.dot(q) - t.d;
    if (!accurate || !(t.area2 > 0)) return h;
    double const bound = t.err * ((std::abs(q.x) + std::abs(q.y) + std::abs(q.z)) + t.c1);
    if (std::abs(h) > bound) return h;
    // (Coordinates beyond about 1e102 overflow the double-double products: h then stands.)
    double const exact = dd::orient(point(t.v[0]), point(t.v[1]), point(t.v[2]), q) / t.area2;
    return std::isfinite(exact) ? exact : h;
  }

  /// Appends the triangle (a, b, c) with no neighbours yet; returns its index.
  int add_tri(int a, int b, int c) {
    tri t;
    t.v = {a, b, c};
    t.nb = {-1, -1, -1};
    DVec3 const e1 = point(b) - point(a), e2 = point(c) - point(a);
    DVec3 const n = e1.cross(e2);
    double const len = n.length();
    t.n = len > 0 ? n * (1.0 / len) : DVec3{};
    DVec3 const centroid = (point(a) + point(b) + point(c)) * (1.0 / 3.0);
    t.d = t.n.dot(centroid);
    if (accurate && len > 0) {
      // The normal's rounding: each edge difference and cross product term within a few eps
      // of |e1| |e2|, so its direction within about 8 eps |e1| |e2| / |n| (the sliver's
      // condition); the centroid's and the dot products' rounding a few eps more. Four
      // times that, as a safe filter.
      double const eps = std::numeric_limits<double>::epsilon();
      double const cond = e1.length() * e2.length() / len;
      t.err = 64.0 * eps * (cond + 1.0);
      t.area2 = len;
      t.c1 = std::abs(centroid.x) + std::abs(centroid.y) + std::abs(centroid.z);
    }
    tris.push_back(std::move(t));
    return int(tris.size() - 1);
  }

  /// Gives each point in `pts` to the triangle (among `cands`) it is farthest outside of;
  /// points within tol of every candidate plane are inside and dropped, and listed in `near`
  /// when above one of them by more than the rounding (`sees`: a copy of a hull vertex is
  /// not, and would make grow()'s re-check cost points x faces). A point below every new face
  /// of a cone is inside the cone over the replaced triangles, so inside the hull. Returns
  /// how many points were given.
  std::size_t assign(std::vector<int> const& pts, std::vector<int> const& cands) {
    std::size_t given = 0;
    for (int i : pts) {
      int best = -1;
      double bd = tol, highest = 0;
      for (int c : cands) {
        double const d = dist(tris[std::size_t(c)], i);
        highest = std::max(highest, d);
        if (d > bd) bd = d, best = c;
      }
      if (best >= 0) {
        tris[std::size_t(best)].outside.push_back(i);
        ++given;
      } else if (highest > sees) {
        near.push_back(i);
      }
    }
    return given;
  }
};

/// The index in tri t of the edge a -> b, or -1.
inline int edge_of(tri const& t, int a, int b) {
  for (int i = 0; i < 3; ++i)
    if (t.v[std::size_t(i)] == a && t.v[std::size_t((i + 1) % 3)] == b) return i;
  return -1;
}

// ------------------------------------------------------------------------ the points

/// Copies the points into b in double and sets b.tol: the default, 16 eps(S) times the sum of
/// the largest |coordinate| on each axis (the rounding of S there, which a hull stored in S
/// cannot beat), or a larger positive `tolerance`; too_few_points or non_finite.
template <ScalarReal S>
HullError load_points(std::span<GVec3<S> const> in, S tolerance, state& b) {
  if (in.size() < 4) return HullError::too_few_points;
  b.p.reserve(in.size());
  DVec3 amax{};
  for (auto const& v : in) {
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      return HullError::non_finite;
    b.p.push_back({double(v.x), double(v.y), double(v.z)});
    amax = {std::max(amax.x, std::abs(double(v.x))), std::max(amax.y, std::abs(double(v.y))),
            std::max(amax.z, std::abs(double(v.z)))};
  }
  double const floor =
      16.0 * double(std::numeric_limits<S>::epsilon()) * (amax.x + amax.y + amax.z);
  b.tol = std::max(floor, double(tolerance)); // (a NaN tolerance: the floor)
  // Far below the tolerance, far above the rounding of a height computed in double (a few
  // eps(double) x the coordinates; more for a sliver's normal). With S = double that rounding
  // is at the default tolerance, so heights near it are decided in double-double (`accurate`),
  // whose rounding is far below tol x 2^-20.
  b.accurate = std::is_same_v<S, double>;
  double const rounding =
      b.accurate ? 0.0 : 64.0 * std::numeric_limits<double>::epsilon() * (amax.x + amax.y + amax.z);
  b.sees = std::min(b.tol, std::max(b.tol * 0x1p-20, rounding));
  return HullError::none;
}

// ------------------------------------------------------------- the starting tetrahedron

/// The corners of the starting tetrahedron, i3 below the face (i0, i1, i2).
struct corners {
  int i0, i1, i2, i3;
};

/// Of the three pairs of extreme points along x, y and z, the pair farthest apart (the first
/// on ties) and its length.
inline std::pair<std::array<int, 2>, double> widest_extremes(state const& b) {
  int const n = int(b.p.size());
  auto const P = [&](int i) -> DVec3 const& { return b.point(i); };
  std::array<int, 6> ext{0, 0, 0, 0, 0, 0};
  for (int i = 0; i < n; ++i) {
    if (P(i).x < P(ext[0]).x) ext[0] = i;
    if (P(i).x > P(ext[1]).x) ext[1] = i;
    if (P(i).y < P(ext[2]).y) ext[2] = i;
    if (P(i).y > P(ext[3]).y) ext[3] = i;
    if (P(i).z < P(ext[4]).z) ext[4] = i;
    if (P(i).z > P(ext[5]).z) ext[5] = i;
  }
  int i0 = ext[0], i1 = ext[1];
  double best = (P(i1) - P(i0)).length();
  for (int k = 1; k < 3; ++k) {
    double const l = (P(ext[std::size_t(2 * k + 1)]) - P(ext[std::size_t(2 * k)])).length();
    if (l > best) best = l, i0 = ext[std::size_t(2 * k)], i1 = ext[std::size_t(2 * k + 1)];
  }
  return {{i0, i1}, best};
}

/// The point farthest from the line through point i0 along the unit dir, if farther than
/// tol; else -1.
inline int farthest_from_line(state const& b, int i0, DVec3 const& dir) {
  int best_i = -1;
  double best = b.tol;
  for (int i = 0; i < int(b.p.size()); ++i) {
    double const l = (b.point(i) - b.point(i0)).cross(dir).length();
    if (l > best) best = l, best_i = i;
  }
  return best_i;
}

/// The point farthest from the plane through point i0 with unit normal pn, if farther than
/// tol; else -1.
inline int farthest_from_plane(state const& b, int i0, DVec3 const& pn) {
  int best_i = -1;
  double best = b.tol;
  for (int i = 0; i < int(b.p.size()); ++i) {
    double const l = std::abs((b.point(i) - b.point(i0)).dot(pn));
    if (l > best) best = l, best_i = i;
  }
  return best_i;
}

/// The starting tetrahedron: the widest pair of axis extremes, the point farthest from their
/// line, the point farthest from that plane; coincident, collinear or coplanar when one of
/// them is within the tolerance.
inline HullError find_corners(state const& b, corners& s) {
  auto const [pair, length] = widest_extremes(b);
  s.i0 = pair[0], s.i1 = pair[1];
  if (length <= b.tol) return HullError::coincident;
  DVec3 const dir = (b.point(s.i1) - b.point(s.i0)) * (1.0 / length);
  s.i2 = farthest_from_line(b, s.i0, dir);
  if (s.i2 < 0) return HullError::collinear;
  DVec3 pn = (b.point(s.i1) - b.point(s.i0)).cross(b.point(s.i2) - b.point(s.i0));
  pn = pn * (1.0 / pn.length());
  s.i3 = farthest_from_plane(b, s.i0, pn);
  if (s.i3 < 0) return HullError::coplanar;
  // Orient so that i3 is below the face (i0, i1, i2).
  if ((b.point(s.i3) - b.point(s.i0)).dot(pn) > 0) std::swap(s.i1, s.i2);
  return HullError::none;
}

/// Sets t's neighbour across its edge a -> c: the first other triangle with the edge c -> a.
inline void link_edge(state& b, int t, int a, int c) {
  for (int u = 0; u < int(b.tris.size()); ++u) {
    if (u == t) continue;
    int const e = edge_of(b.tris[std::size_t(u)], c, a);
    if (e >= 0) {
      b.tris[std::size_t(t)].nb[std::size_t(edge_of(b.tris[std::size_t(t)], a, c))] = u;
      return;
    }
  }
}

/// The four triangles of the starting tetrahedron, linked, with every other point given to one of
/// them.
inline void start_tetrahedron(state& b, corners const& s) {
  int const t0 = b.add_tri(s.i0, s.i1, s.i2);
  int const t1 = b.add_tri(s.i0, s.i3, s.i1);
  int const t2 = b.add_tri(s.i1, s.i3, s.i2);
  int const t3 = b.add_tri(s.i2, s.i3, s.i0);
  for (int t : {t0, t1, t2, t3})
    for (int e = 0; e < 3; ++e)
      link_edge(b, t, b.tris[std::size_t(t)].v[std::size_t(e)],
                b.tris[std::size_t(t)].v[std::size_t((e + 1) % 3)]);
  std::vector<int> rest;
  for (int i = 0; i < int(b.p.size()); ++i)
    if (i != s.i0 && i != s.i1 && i != s.i2 && i != s.i3) rest.push_back(i);
  b.assign(rest, {t0, t1, t2, t3});
}

// ------------------------------------------------------------------------------ growth

/// Lists of one growth round, kept across rounds for their capacity.
struct round_lists {
  std::vector<int> visible, stack, horizon_from, horizon_to, horizon_nb;
  std::vector<char> seen; ///< per triangle: visible from the eye
};

/// The point of t's outside set farthest above its plane (the first on ties).
inline int farthest_outside(state const& b, tri const& t) {
  int eye = t.outside[0];
  for (int i : t.outside)
    if (b.dist(t, i) > b.dist(t, eye)) eye = i;
  return eye;
}

/// The triangles that see the eye: a flood from triangle `from` over the neighbours whose
/// plane the eye is above by more than b.sees, a height far below tol: a neighbour the eye is
/// within tol above would stay beside the new cone face across their edge, a fold that turns
/// the wrong way, and when that face is a sliver its plane tilts enough to leave the
/// neighbour's far vertex many tolerances above it. (A height above zero but within the
/// rounding would let a copy of a hull vertex see the triangles at that vertex, and make
/// triangles with a repeated corner.)
inline void find_visible(state const& b, int from, int eye, round_lists& w) {
  w.visible.clear();
  w.stack.assign(1, from);
  w.seen.assign(b.tris.size(), 0);
  w.seen[std::size_t(from)] = 1;
  while (!w.stack.empty()) {
    int const u = w.stack.back();
    w.stack.pop_back();
    w.visible.push_back(u);
    for (int nb : b.tris[std::size_t(u)].nb)
      if (!w.seen[std::size_t(nb)] && b.dist(b.tris[std::size_t(nb)], eye) > b.sees) {
        w.seen[std::size_t(nb)] = 1;
        w.stack.push_back(nb);
      }
  }
}

/// The horizon: each edge from a visible triangle to an invisible one, as from -> to and the
/// invisible triangle across it. False when two of them start at one vertex (rounding made
/// the visible region not a disc).
inline bool find_horizon(state const& b, round_lists& w) {
  std::map<int, std::size_t> by_start;
  w.horizon_from.clear(), w.horizon_to.clear(), w.horizon_nb.clear();
  bool simple = true;
  for (int u : w.visible)
    for (int e = 0; e < 3; ++e) {
      tri const& tu = b.tris[std::size_t(u)];
      int const nb = tu.nb[std::size_t(e)];
      if (w.seen[std::size_t(nb)]) continue;
      int const a = tu.v[std::size_t(e)], c = tu.v[std::size_t((e + 1) % 3)];
      simple = simple && by_start.emplace(a, w.horizon_from.size()).second;
      w.horizon_from.push_back(a), w.horizon_to.push_back(c), w.horizon_nb.push_back(nb);
    }
  return simple;
}

/// Kills the visible triangles; returns their outside points other than the eye.
inline std::vector<int> remove_visible(state& b, int eye, round_lists const& w) {
  std::vector<int> orphans;
  for (int u : w.visible) {
    tri& tu = b.tris[std::size_t(u)];
    tu.alive = false;
    for (int i : tu.outside)
      if (i != eye) orphans.push_back(i);
    tu.outside.clear();
  }
  return orphans;
}

/// One new triangle (a, c, eye) per horizon edge a -> c, linked to the triangle across that
/// edge and to its neighbours around the cone; returns them in horizon order.
inline std::vector<int> build_cone(state& b, int eye, round_lists const& w) {
  std::vector<int> fresh(w.horizon_from.size());
  std::map<int, int> by_from;
  for (std::size_t h = 0; h < w.horizon_from.size(); ++h) {
    int const nt = b.add_tri(w.horizon_from[h], w.horizon_to[h], eye);
    fresh[h] = nt;
    by_from[w.horizon_from[h]] = nt;
    b.tris[std::size_t(nt)].nb[0] = w.horizon_nb[h];
    tri& g = b.tris[std::size_t(w.horizon_nb[h])];
    g.nb[std::size_t(edge_of(g, w.horizon_to[h], w.horizon_from[h]))] = nt;
  }
  for (std::size_t h = 0; h < w.horizon_from.size(); ++h) {
    tri& tn = b.tris[std::size_t(fresh[h])];
    tn.nb[1] = by_from[w.horizon_to[h]]; // edge c -> eye: the triangle starting at c
    tn.nb[2] = -1;                       // edge eye -> a: set by the triangle ending at a
  }
  for (std::size_t h = 0; h < w.horizon_from.size(); ++h) {
    int const next = by_from[w.horizon_to[h]];
    b.tris[std::size_t(next)].nb[2] = fresh[h];
  }
  return fresh;
}

/// Adds the farthest outside point of some triangle until none is left. Each round removes
/// at least one point from the outside sets, so this ends.
inline void grow_outside_sets(state& b) {
  round_lists w;
  for (std::size_t scan = 0; scan < b.tris.size(); ++scan) {
    if (!b.tris[scan].alive || b.tris[scan].outside.empty()) continue;
    int const eye = farthest_outside(b, b.tris[scan]);
    find_visible(b, int(scan), eye, w);
    if (!find_horizon(b, w)) {
      // Rounding made the visible region not a disc: set the eye aside for grow()'s re-check
      // against the finished hull, and go on.
      auto& o = b.tris[scan].outside;
      o.erase(std::find(o.begin(), o.end(), eye));
      b.near.push_back(eye);
      --scan;
      continue;
    }
    std::vector<int> const orphans = remove_visible(b, eye, w);
    std::vector<int> const fresh = build_cone(b, eye, w);
    b.assign(orphans, fresh);
    scan = std::size_t(-1); // restart the scan: earlier triangles may still hold points
  }
}

/// Grows the hull until every input point is within tol of every face's plane. Outside sets
/// hold each point above one face only: a point dropped because it was within tol above every
/// new face of a cone may still be far above an older face (a new face that is a sliver
/// tilts its plane, and "within tol of it" reaches far along it), so the points dropped that
/// way, and eyes set aside (b.near), are checked against the whole hull and grown again. A
/// point is given to a face at most once per round and the rounds stop when none is given;
/// they are capped at 16 (one or two in practice) because an eye set aside each time would
/// come back every round.
inline void grow(state& b) {
  grow_outside_sets(b);
  for (int round = 0; round < 16 && !b.near.empty(); ++round) {
    std::vector<int> pts;
    pts.swap(b.near);
    std::sort(pts.begin(), pts.end());
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    std::vector<int> live;
    for (std::size_t t = 0; t < b.tris.size(); ++t)
      if (b.tris[t].alive) live.push_back(int(t));
    if (b.assign(pts, live) == 0) break;
    grow_outside_sets(b);
  }
}

/// Whether the hull is within tol of one of its faces' planes: every vertex less than tol
/// below some live triangle's plane.
inline bool thinner_than_tolerance(state const& b) {
  std::vector<int> verts;
  for (tri const& t : b.tris)
    if (t.alive) verts.insert(verts.end(), t.v.begin(), t.v.end());
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  for (tri const& t : b.tris) {
    if (!t.alive) continue;
    bool deep = false;
    for (std::size_t k = 0; k < verts.size() && !deep; ++k)
      deep = -b.dist(t, verts[k]) > b.tol;
    if (!deep) return true;
  }
  return false;
}

// ---------------------------------------------------------------------- polygon faces

/// The live triangles grouped into faces: face_of[t] (-1 for a dead triangle) and the
/// triangles of each face.
struct face_groups {
  std::vector<int> face_of;
  std::vector<std::vector<int>> groups;
};

/// Merges each live triangle with the neighbours whose three vertices lie within tol of the
/// seed triangle's plane (checking against the seed keeps curved surfaces from merging).
inline face_groups merge_coplanar(state const& b) {
  std::size_t const nt = b.tris.size();
  face_groups g{std::vector<int>(nt, -1), {}};
  // Seeds in decreasing area (ties: by index): a large triangle's plane is the best fit of its
  // region, where a sliver's normal is mostly rounding and would merge nothing.
  std::vector<std::pair<double, std::size_t>> seeds;
  for (std::size_t t = 0; t < nt; ++t) {
    tri const& tt = b.tris[t];
    if (!tt.alive) continue;
    DVec3 const e1 = b.point(tt.v[1]) - b.point(tt.v[0]), e2 = b.point(tt.v[2]) - b.point(tt.v[0]);
    seeds.push_back({-e1.cross(e2).length(), t});
  }
  std::sort(seeds.begin(), seeds.end());
  for (auto const& [neg_area, s] : seeds) {
    if (g.face_of[s] >= 0) continue;
    int const f = int(g.groups.size());
    g.groups.emplace_back();
    std::vector<int> stack{int(s)};
    g.face_of[s] = f;
    tri const& seed = b.tris[s];
    while (!stack.empty()) {
      int const u = stack.back();
      stack.pop_back();
      g.groups.back().push_back(u);
      for (int nb : b.tris[std::size_t(u)].nb) {
        tri const& tn = b.tris[std::size_t(nb)];
        if (g.face_of[std::size_t(nb)] >= 0 || tn.n.dot(seed.n) <= 0) continue;
        bool flat = true;
        for (int v : tn.v)
          flat = flat && std::abs(b.dist(seed, v)) <= b.tol;
        if (flat) {
          g.face_of[std::size_t(nb)] = f;
          stack.push_back(nb);
        }
      }
    }
  }
  return g;
}

/// The boundary loop of each face: the vertices of its edges whose neighbour is in another
/// face, in order. A face whose boundary is not one loop (a ring of triangles) gets a loop
/// shorter than its boundary: `whole` says which are complete.
inline std::vector<std::vector<int>> boundary_loops(state const& b, face_groups const& g,
                                                    std::vector<bool>& whole) {
  std::size_t const nf = g.groups.size();
  std::vector<std::vector<int>> loops(nf);
  whole.assign(nf, true);
  for (std::size_t f = 0; f < nf; ++f) {
    std::map<int, int> next;
    for (int u : g.groups[f])
      for (int e = 0; e < 3; ++e) {
        tri const& tu = b.tris[std::size_t(u)];
        if (g.face_of[std::size_t(tu.nb[std::size_t(e)])] != int(f))
          next[tu.v[std::size_t(e)]] = tu.v[std::size_t((e + 1) % 3)];
      }
    int const start = next.begin()->first;
    int v = start;
    do {
      loops[f].push_back(v);
      v = next[v];
    } while (v != start && loops[f].size() <= next.size());
    whole[f] = v == start && loops[f].size() == next.size();
  }
  return loops;
}

/// Drops from the loops the vertices that lie on only two faces (on a straight edge between
/// them); returns the points kept, as keys of a map for their hull indices.
inline std::map<int, std::uint32_t> drop_straight_vertices(std::vector<std::vector<int>>& loops) {
  std::map<int, int> degree;
  for (auto const& l : loops)
    for (int v : l)
      ++degree[v];
  std::map<int, std::uint32_t> index;
  for (auto& l : loops) {
    std::erase_if(l, [&](int v) { return degree[v] < 3; });
    for (int v : l)
      index.emplace(v, 0);
  }
  return index;
}

/// Numbers the kept points in increasing order and stores them as the hull's vertices.
template <ScalarReal S>
void emit_vertices(state const& b, std::map<int, std::uint32_t>& index, hull_data<S>& h) {
  std::uint32_t k = 0;
  for (auto& [v, i] : index) {
    i = k++;
    DVec3 const& q = b.p[std::size_t(v)];
    h.vertices.push_back(GVec3<S>{S(q.x), S(q.y), S(q.z)});
  }
}

/// The unit Newell normal of a loop and the mean of its vertices. With accurate heights the
/// normal's sums are taken in double-double: a sliver face of a slab a few tolerances thick
/// has a normal double's rounding would turn by up to eps / (its width), tilting its plane
/// by many tolerances at its far end.
inline std::pair<DVec3, DVec3> newell_plane(state const& b, std::vector<int> const& l) {
  DVec3 nn{}, c{};
  dd::num sx{0, 0}, sy{0, 0}, sz{0, 0};
  for (std::size_t i = 0; i < l.size(); ++i) {
    DVec3 const& a = b.p[std::size_t(l[i])];
    DVec3 const& q = b.p[std::size_t(l[(i + 1) % l.size()])];
    if (b.accurate) {
      using namespace dd;
      sx = add(sx, mul(two_sum(a.y, -q.y), two_sum(a.z, q.z)));
      sy = add(sy, mul(two_sum(a.z, -q.z), two_sum(a.x, q.x)));
      sz = add(sz, mul(two_sum(a.x, -q.x), two_sum(a.y, q.y)));
    } else {
      nn = nn +
           DVec3{(a.y - q.y) * (a.z + q.z), (a.z - q.z) * (a.x + q.x), (a.x - q.x) * (a.y + q.y)};
    }
    c = c + a;
  }
  if (b.accurate) nn = DVec3{sx.hi + sx.lo, sy.hi + sy.lo, sz.hi + sz.lo};
  nn = nn * (1.0 / nn.length());
  c = c * (1.0 / double(l.size()));
  return {nn, c};
}

/// Stores a face per loop (Newell normal, offset at the vertex mean) and its vertex indices;
/// returns the face to the left of each directed edge.
template <ScalarReal S>
std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t>
emit_faces(state const& b, std::vector<std::vector<int>> const& loops,
           std::map<int, std::uint32_t>& index, hull_data<S>& h) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edge_face;
  for (std::size_t f = 0; f < loops.size(); ++f) {
    auto const& l = loops[f];
    auto const [nn, c] = newell_plane(b, l);
    GHullFace<S> face{GVec3<S>{S(nn.x), S(nn.y), S(nn.z)}, S(nn.dot(c)),
                      std::uint32_t(h.face_vertices.size()), std::uint32_t(l.size())};
    h.faces.push_back(face);
    for (std::size_t i = 0; i < l.size(); ++i) {
      std::uint32_t const a = index[l[i]], q = index[l[(i + 1) % l.size()]];
      h.face_vertices.push_back(a);
      edge_face[{a, q}] = std::uint32_t(f);
    }
  }
  return edge_face;
}

/// The face across each face edge, and the edge list (each edge once, from its lower index).
template <ScalarReal S>
void link_faces(std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t>& edge_face,
                hull_data<S>& h) {
  h.face_neighbors.resize(h.face_vertices.size());
  for (std::size_t f = 0; f < h.faces.size(); ++f) {
    GHullFace<S> const& face = h.faces[f];
    for (std::uint32_t i = 0; i < face.count; ++i) {
      std::uint32_t const a = h.face_vertices[face.first + i];
      std::uint32_t const q = h.face_vertices[face.first + (i + 1) % face.count];
      std::uint32_t const other = edge_face[{q, a}];
      h.face_neighbors[face.first + i] = other;
      if (a < q) h.edges.push_back(HullEdge{a, q, std::uint32_t(f), other});
    }
  }
}

/// Whether a merged face, as its loop of kept vertices, is a face the hull can have: at least
/// three vertices, each within 4 tol of the loop's plane; convex (every corner turns left
/// about the normal, or lies within 4 tol of the chord from its predecessor to its
/// successor); and every vertex of the triangulation (`all`, the dropped straight ones and
/// those inside merged faces too) at most 4 tol above it (why 4: docs/fuzzing.md). Merging by the
/// seed's plane alone can break each (a dropped vertex outside the plane of the rest, a loop
/// turning back, a face left with two vertices).
inline bool face_is_sound(state const& b, std::vector<int> const& l, std::vector<int> const& all) {
  auto const [n, c] = newell_plane(b, l);
  if (!(std::abs(n.length() - 1.0) < 1e-6)) return false; // (fewer than 3 vertices: no normal)
  double const d = n.dot(c), slack = 4.0 * b.tol;
  for (std::size_t i = 0; i < l.size(); ++i) {
    DVec3 const& p0 = b.p[std::size_t(l[i])];
    DVec3 const& p1 = b.p[std::size_t(l[(i + 1) % l.size()])];
    DVec3 const& p2 = b.p[std::size_t(l[(i + 2) % l.size()])];
    if (std::abs(n.dot(p0) - d) > slack) return false;
    // |e0 x e1 . n| / |p2 - p0| is p1's distance from the chord.
    DVec3 const e0 = p1 - p0, e1 = p2 - p1;
    if (e0.cross(e1).dot(n) < -slack * (p2 - p0).length()) return false;
  }
  for (int v : all)
    if (n.dot(b.p[std::size_t(v)]) - d > slack) return false;
  return true;
}

/// The finished triangulation as a hull's data: coplanar triangles merged into polygons,
/// straight-edge vertices dropped, faces and edges linked.
template <ScalarReal S>
hull_data<S> polygon_hull(state const& b) {
  hull_data<S> h;
  face_groups groups = merge_coplanar(b);
  std::vector<std::vector<int>> loops;
  std::map<int, std::uint32_t> index;
  // Every vertex of the triangulation, for the soundness test.
  std::vector<int> all;
  for (tri const& t : b.tris)
    if (t.alive) all.insert(all.end(), t.v.begin(), t.v.end());
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  // Merged faces that are not sound go back to their triangles, until every merged face is;
  // at worst every face is a triangle of the triangulation, which grow() leaves convex (no
  // vertex above a triangle's plane beyond the rounding) with every point within tol below.
  for (;;) {
    std::vector<bool> whole;
    loops = boundary_loops(b, groups, whole);
    index = drop_straight_vertices(loops);
    std::vector<std::size_t> unsound;
    for (std::size_t f = 0; f < loops.size(); ++f) {
      if (groups.groups[f].size() > 1) {
        if (!whole[f] || !face_is_sound(b, loops[f], all)) unsound.push_back(f);
      } else if (loops[f].size() < 3) {
        // A triangle that lost a corner to a merged neighbour wrapped round it: that
        // neighbour goes back to triangles.
        for (int nb : b.tris[std::size_t(groups.groups[f][0])].nb) {
          std::size_t const g = std::size_t(groups.face_of[std::size_t(nb)]);
          if (groups.groups[g].size() > 1) unsound.push_back(g);
        }
      }
    }
    std::sort(unsound.begin(), unsound.end());
    unsound.erase(std::unique(unsound.begin(), unsound.end()), unsound.end());
    if (unsound.empty()) break;
    for (std::size_t f : unsound) {
      std::vector<int> const tris = groups.groups[f];
      groups.groups[f] = {tris[0]};
      for (std::size_t k = 1; k < tris.size(); ++k) {
        groups.face_of[std::size_t(tris[k])] = int(groups.groups.size());
        groups.groups.push_back({tris[k]});
      }
    }
  }
  emit_vertices(b, index, h);
  auto edge_face = emit_faces(b, loops, index, h);
  link_faces(edge_face, h);
  h.tolerance = S(b.tol);
  return h;
}

/// Quickhull over `in` (GConvexHull<S>::build; tolerance <= 0 picks the default).
template <ScalarReal S>
GHullBuild<S> run(std::span<GVec3<S> const> in, S tolerance) {
  GHullBuild<S> out;
  state b;
  corners s{};
  out.error = load_points(in, tolerance, b);
  if (out.error == HullError::none) out.error = find_corners(b, s);
  if (out.error != HullError::none) return out;
  start_tetrahedron(b, s);
  grow(b);
  // The starting face's apex is more than tol off its plane, but the set may be thinner in
  // another direction: all points within tol of a plane (a face's plane, which the minimum
  // width of the hull, up to the edge-edge directions, is measured along) is coplanar too.
  if (thinner_than_tolerance(b)) {
    out.error = HullError::coplanar;
    return out;
  }
  out.hull = GConvexHull<S>(polygon_hull<S>(b));
  return out;
}

// -------------------------------------------------------------------- mass properties

/// Integrals over a hull's solid, relative to the point r: the volume, the first moment and
/// the covariance (second moment) about r.
struct moments {
  DVec3 r;
  double vol = 0;
  DVec3 first{};
  double cov[3][3] = {};
};

/// The moments of the tetrahedra (r, a, b, c) with r the vertex centroid and (a, b, c) a fan
/// of each face. For a tetrahedron at r with edge matrix A = [a-r b-r c-r], the covariance
/// about r is det(A) A C0 A^T with C0 = [[2 1 1] [1 2 1] [1 1 2]] / 120, its volume det(A) / 6
/// and its centroid r + (a + b + c - 3r) / 4.
template <ScalarReal S>
moments fan_moments(GConvexHull<S> const& h) {
  auto const vs = h.vertices();
  moments m;
  for (auto const& v : vs)
    m.r = m.r + DVec3{double(v.x), double(v.y), double(v.z)};
  m.r = m.r * (1.0 / double(vs.size()));
  auto const at = [&](std::uint32_t i) {
    return DVec3{double(vs[i].x), double(vs[i].y), double(vs[i].z)} - m.r;
  };
  for (std::size_t f = 0; f < h.faces().size(); ++f) {
    auto const fv = h.face_vertices(f);
    for (std::size_t i = 1; i + 1 < fv.size(); ++i) {
      DVec3 const a = at(fv[0]), bb = at(fv[i]), c = at(fv[i + 1]);
      double const det = a.dot(bb.cross(c));
      m.vol += det / 6.0;
      m.first = m.first + (a + bb + c) * (det / 24.0);
      double const A[3][3] = {{a.x, bb.x, c.x}, {a.y, bb.y, c.y}, {a.z, bb.z, c.z}};
      for (int r0 = 0; r0 < 3; ++r0)
        for (int r1 = 0; r1 < 3; ++r1) {
          double sum = 0;
          for (int k = 0; k < 3; ++k)
            for (int l = 0; l < 3; ++l)
              sum += A[r0][k] * (k == l ? 2.0 : 1.0) * A[r1][l];
          m.cov[r0][r1] += det * sum / 120.0;
        }
    }
  }
  return m;
}

/// Mass properties of a hull (GConvexHull<S>::mass_properties): the centre of mass from the
/// moments, the covariance moved there, inertia = trace(C) E - C, times density.
template <ScalarReal S>
GMassProperties<S> mass(GConvexHull<S> const& h, S density) {
  if (h.empty()) return {S(0), GVec3<S>{}, GMat3<S>::ZERO};
  moments const m = fan_moments(h);
  DVec3 const cm = m.first * (1.0 / m.vol); // relative to r
  double cc[3][3];
  double const cmv[3] = {cm.x, cm.y, cm.z};
  for (int r0 = 0; r0 < 3; ++r0)
    for (int r1 = 0; r1 < 3; ++r1)
      cc[r0][r1] = m.cov[r0][r1] - m.vol * cmv[r0] * cmv[r1];
  double const tr = cc[0][0] + cc[1][1] + cc[2][2];
  double const rho = double(density);
  auto const I = [&](int r0, int r1) { return S(rho * ((r0 == r1 ? tr : 0.0) - cc[r0][r1])); };
  DVec3 const centre = m.r + cm;
  return {S(rho * m.vol), GVec3<S>{S(centre.x), S(centre.y), S(centre.z)},
          GMat3<S>::from_symmetric(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2))};
}

} // namespace plume::detail::hull_builder

namespace plume {

template <ScalarReal S>
GHullBuild<S> GConvexHull<S>::build(std::span<Vec const> points, S tolerance) {
  return detail::hull_builder::run<S>(points, tolerance);
}

template <ScalarReal S>
GMassProperties<S> GConvexHull<S>::mass_properties(S density) const noexcept {
  return detail::hull_builder::mass(*this, density);
}

} // namespace plume
