// plume/collision/detail/quickhull.hpp - the quickhull builder and the hull's mass
// properties (included by collision/convex_hull.hpp; not a public header).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <span>
#include <vector>

namespace plume {

struct detail_hull_builder {
  struct D3 {
    double x, y, z;
    D3 operator-(D3 const& b) const { return {x - b.x, y - b.y, z - b.z}; }
    D3 operator+(D3 const& b) const { return {x + b.x, y + b.y, z + b.z}; }
    D3 operator*(double s) const { return {x * s, y * s, z * s}; }
    double dot(D3 const& b) const { return x * b.x + y * b.y + z * b.z; }
    D3 cross(D3 const& b) const {
      return {y * b.z - z * b.y, z * b.x - x * b.z, x * b.y - y * b.x};
    }
    double length() const { return std::sqrt(dot(*this)); }
  };

  /// A triangle of the hull under construction: v[i] -> v[i + 1] counter-clockwise from
  /// outside, nb[i] the triangle across that edge.
  struct Tri {
    std::array<int, 3> v;
    std::array<int, 3> nb;
    D3 n;
    double d;
    std::vector<int> outside;
    bool alive = true;
  };

  std::vector<D3> p;
  std::vector<Tri> tris;
  double tol = 0;

  double dist(Tri const& t, int i) const { return t.n.dot(p[std::size_t(i)]) - t.d; }

  int add_tri(int a, int b, int c) {
    Tri t;
    t.v = {a, b, c};
    t.nb = {-1, -1, -1};
    D3 const n =
        (p[std::size_t(b)] - p[std::size_t(a)]).cross(p[std::size_t(c)] - p[std::size_t(a)]);
    double const len = n.length();
    t.n = len > 0 ? n * (1.0 / len) : D3{0, 0, 0};
    t.d = t.n.dot((p[std::size_t(a)] + p[std::size_t(b)] + p[std::size_t(c)]) * (1.0 / 3.0));
    tris.push_back(std::move(t));
    return int(tris.size() - 1);
  }

  /// The index in tri t of the edge a -> b, or -1.
  static int edge_of(Tri const& t, int a, int b) {
    for (int i = 0; i < 3; ++i)
      if (t.v[std::size_t(i)] == a && t.v[std::size_t((i + 1) % 3)] == b) return i;
    return -1;
  }

  /// Gives each point in `pts` to the triangle (among `cands`) it is farthest outside of;
  /// points within tol of every candidate plane are inside and dropped.
  void assign(std::vector<int> const& pts, std::vector<int> const& cands) {
    for (int i : pts) {
      int best = -1;
      double bd = tol;
      for (int c : cands) {
        double const d = dist(tris[std::size_t(c)], i);
        if (d > bd) bd = d, best = c;
      }
      if (best >= 0) tris[std::size_t(best)].outside.push_back(i);
    }
  }

  template <ScalarReal S>
  static GHullBuild<S> run(std::span<GVec3<S> const> in, S tolerance);

  template <ScalarReal S>
  static void finish(detail_hull_builder& b, GConvexHull<S>& hull);

  template <ScalarReal S>
  static GMassProperties<S> mass(GConvexHull<S> const& h, S density);
};

template <ScalarReal S>
GHullBuild<S> detail_hull_builder::run(std::span<GVec3<S> const> in, S tolerance) {
  GHullBuild<S> out;
  if (in.size() < 4) {
    out.error = HullError::too_few_points;
    return out;
  }
  detail_hull_builder b;
  b.p.reserve(in.size());
  D3 amax{0, 0, 0};
  for (auto const& v : in) {
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
      out.error = HullError::non_finite;
      return out;
    }
    b.p.push_back({double(v.x), double(v.y), double(v.z)});
    amax = {std::max(amax.x, std::abs(double(v.x))), std::max(amax.y, std::abs(double(v.y))),
            std::max(amax.z, std::abs(double(v.z)))};
  }
  b.tol = tolerance > S(0)
              ? double(tolerance)
              : 16.0 * double(std::numeric_limits<S>::epsilon()) * (amax.x + amax.y + amax.z);
  int const n = int(b.p.size());
  auto const P = [&](int i) -> D3 const& { return b.p[std::size_t(i)]; };

  // Initial simplex: the two extreme points farthest apart on an axis, the point farthest
  // from their line, the point farthest from that plane.
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
  if (best <= b.tol) {
    out.error = HullError::coincident;
    return out;
  }
  D3 const dir = (P(i1) - P(i0)) * (1.0 / best);
  int i2 = -1;
  best = b.tol;
  for (int i = 0; i < n; ++i) {
    double const l = (P(i) - P(i0)).cross(dir).length();
    if (l > best) best = l, i2 = i;
  }
  if (i2 < 0) {
    out.error = HullError::collinear;
    return out;
  }
  D3 pn = (P(i1) - P(i0)).cross(P(i2) - P(i0));
  pn = pn * (1.0 / pn.length());
  int i3 = -1;
  best = b.tol;
  for (int i = 0; i < n; ++i) {
    double const l = std::abs((P(i) - P(i0)).dot(pn));
    if (l > best) best = l, i3 = i;
  }
  if (i3 < 0) {
    out.error = HullError::coplanar;
    return out;
  }
  // Orient so that i3 is below the face (i0, i1, i2).
  if ((P(i3) - P(i0)).dot(pn) > 0) std::swap(i1, i2);
  int const t0 = b.add_tri(i0, i1, i2);
  int const t1 = b.add_tri(i0, i3, i1);
  int const t2 = b.add_tri(i1, i3, i2);
  int const t3 = b.add_tri(i2, i3, i0);
  auto const link = [&](int t, int a, int c) {
    for (int u = 0; u < int(b.tris.size()); ++u) {
      if (u == t) continue;
      int const e = edge_of(b.tris[std::size_t(u)], c, a);
      if (e >= 0) {
        b.tris[std::size_t(t)].nb[std::size_t(edge_of(b.tris[std::size_t(t)], a, c))] = u;
        return;
      }
    }
  };
  for (int t : {t0, t1, t2, t3})
    for (int e = 0; e < 3; ++e)
      link(t, b.tris[std::size_t(t)].v[std::size_t(e)],
           b.tris[std::size_t(t)].v[std::size_t((e + 1) % 3)]);
  {
    std::vector<int> rest;
    for (int i = 0; i < n; ++i)
      if (i != i0 && i != i1 && i != i2 && i != i3) rest.push_back(i);
    b.assign(rest, {t0, t1, t2, t3});
  }

  // Grow: add the farthest outside point of some triangle until none is left. Each round
  // removes at least one point from the outside sets, so this ends.
  std::vector<int> visible, stack, horizon_from, horizon_to, horizon_nb;
  for (std::size_t scan = 0; scan < b.tris.size(); ++scan) {
    if (!b.tris[scan].alive || b.tris[scan].outside.empty()) continue;
    Tri& t = b.tris[scan];
    int eye = t.outside[0];
    for (int i : t.outside)
      if (b.dist(t, i) > b.dist(t, eye)) eye = i;
    // Visible triangles: flood from t over neighbours that see the eye.
    visible.clear();
    stack.assign(1, int(scan));
    std::vector<char> seen(b.tris.size(), 0);
    seen[scan] = 1;
    while (!stack.empty()) {
      int const u = stack.back();
      stack.pop_back();
      visible.push_back(u);
      for (int nb : b.tris[std::size_t(u)].nb)
        if (!seen[std::size_t(nb)] && b.dist(b.tris[std::size_t(nb)], eye) > b.tol) {
          seen[std::size_t(nb)] = 1;
          stack.push_back(nb);
        }
    }
    // Horizon: edges from a visible triangle to an invisible one, as a map start -> edge.
    std::map<int, std::size_t> by_start;
    horizon_from.clear(), horizon_to.clear(), horizon_nb.clear();
    bool simple = true;
    for (int u : visible)
      for (int e = 0; e < 3; ++e) {
        Tri const& tu = b.tris[std::size_t(u)];
        int const nb = tu.nb[std::size_t(e)];
        if (seen[std::size_t(nb)]) continue;
        int const a = tu.v[std::size_t(e)], c = tu.v[std::size_t((e + 1) % 3)];
        simple = simple && by_start.emplace(a, horizon_from.size()).second;
        horizon_from.push_back(a), horizon_to.push_back(c), horizon_nb.push_back(nb);
      }
    if (!simple) {
      // Rounding made the visible region not a disc: drop the eye (it is within a hair of
      // the hull) and go on.
      auto& o = b.tris[scan].outside;
      o.erase(std::find(o.begin(), o.end(), eye));
      --scan;
      continue;
    }
    std::vector<int> orphans;
    for (int u : visible) {
      Tri& tu = b.tris[std::size_t(u)];
      tu.alive = false;
      for (int i : tu.outside)
        if (i != eye) orphans.push_back(i);
      tu.outside.clear();
    }
    // One new triangle (a, c, eye) per horizon edge a -> c, linked around the cone.
    std::vector<int> fresh(horizon_from.size());
    std::map<int, int> by_from;
    for (std::size_t h = 0; h < horizon_from.size(); ++h) {
      int const nt = b.add_tri(horizon_from[h], horizon_to[h], eye);
      fresh[h] = nt;
      by_from[horizon_from[h]] = nt;
      b.tris[std::size_t(nt)].nb[0] = horizon_nb[h];
      Tri& g = b.tris[std::size_t(horizon_nb[h])];
      g.nb[std::size_t(edge_of(g, horizon_to[h], horizon_from[h]))] = nt;
    }
    for (std::size_t h = 0; h < horizon_from.size(); ++h) {
      Tri& tn = b.tris[std::size_t(fresh[h])];
      tn.nb[1] = by_from[horizon_to[h]]; // edge c -> eye: the triangle starting at c
      tn.nb[2] = -1;                     // edge eye -> a: set by the triangle ending at a
    }
    for (std::size_t h = 0; h < horizon_from.size(); ++h) {
      int const next = by_from[horizon_to[h]];
      b.tris[std::size_t(next)].nb[2] = fresh[h];
    }
    b.assign(orphans, fresh);
    scan = std::size_t(-1); // restart the scan: earlier triangles may still hold points
  }
  finish(b, out.hull);
  out.hull.tolerance_ = S(b.tol);
  return out;
}

template <ScalarReal S>
void detail_hull_builder::finish(detail_hull_builder& b, GConvexHull<S>& hull) {
  // Merge each live triangle with the neighbours whose three vertices lie within tol of the
  // seed triangle's plane (checking against the seed keeps curved surfaces from merging).
  std::size_t const nt = b.tris.size();
  std::vector<int> face_of(nt, -1);
  std::vector<std::vector<int>> groups;
  for (std::size_t s = 0; s < nt; ++s) {
    if (!b.tris[s].alive || face_of[s] >= 0) continue;
    int const f = int(groups.size());
    groups.emplace_back();
    std::vector<int> stack{int(s)};
    face_of[s] = f;
    Tri const& seed = b.tris[s];
    while (!stack.empty()) {
      int const u = stack.back();
      stack.pop_back();
      groups.back().push_back(u);
      for (int nb : b.tris[std::size_t(u)].nb) {
        Tri const& tn = b.tris[std::size_t(nb)];
        if (face_of[std::size_t(nb)] >= 0 || tn.n.dot(seed.n) <= 0) continue;
        bool flat = true;
        for (int v : tn.v)
          flat = flat && std::abs(b.dist(seed, v)) <= b.tol;
        if (flat) {
          face_of[std::size_t(nb)] = f;
          stack.push_back(nb);
        }
      }
    }
  }
  // Boundary loop of each group: its edges whose neighbour is in another group.
  std::size_t const nf = groups.size();
  std::vector<std::vector<int>> loops(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    std::map<int, int> next;
    for (int u : groups[f])
      for (int e = 0; e < 3; ++e) {
        Tri const& tu = b.tris[std::size_t(u)];
        if (face_of[std::size_t(tu.nb[std::size_t(e)])] != int(f))
          next[tu.v[std::size_t(e)]] = tu.v[std::size_t((e + 1) % 3)];
      }
    int const start = next.begin()->first;
    int v = start;
    do {
      loops[f].push_back(v);
      v = next[v];
    } while (v != start && loops[f].size() <= next.size());
  }
  // Drop vertices that lie on only two faces (on a straight edge between them).
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
  std::uint32_t k = 0;
  for (auto& [v, i] : index) {
    i = k++;
    D3 const& q = b.p[std::size_t(v)];
    hull.vertices_.push_back(GVec3<S>{S(q.x), S(q.y), S(q.z)});
  }
  // Faces: Newell normal of the loop, offset the mean over its vertices.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edge_face;
  for (std::size_t f = 0; f < nf; ++f) {
    auto const& l = loops[f];
    D3 nn{0, 0, 0}, c{0, 0, 0};
    for (std::size_t i = 0; i < l.size(); ++i) {
      D3 const& a = b.p[std::size_t(l[i])];
      D3 const& q = b.p[std::size_t(l[(i + 1) % l.size()])];
      nn = nn + D3{(a.y - q.y) * (a.z + q.z), (a.z - q.z) * (a.x + q.x), (a.x - q.x) * (a.y + q.y)};
      c = c + a;
    }
    nn = nn * (1.0 / nn.length());
    c = c * (1.0 / double(l.size()));
    GHullFace<S> face{GVec3<S>{S(nn.x), S(nn.y), S(nn.z)}, S(nn.dot(c)),
                      std::uint32_t(hull.face_vertices_.size()), std::uint32_t(l.size())};
    hull.faces_.push_back(face);
    for (std::size_t i = 0; i < l.size(); ++i) {
      std::uint32_t const a = index[l[i]], q = index[l[(i + 1) % l.size()]];
      hull.face_vertices_.push_back(a);
      edge_face[{a, q}] = std::uint32_t(f);
    }
  }
  hull.face_neighbors_.resize(hull.face_vertices_.size());
  for (std::size_t f = 0; f < nf; ++f) {
    GHullFace<S> const& face = hull.faces_[f];
    for (std::uint32_t i = 0; i < face.count; ++i) {
      std::uint32_t const a = hull.face_vertices_[face.first + i];
      std::uint32_t const q = hull.face_vertices_[face.first + (i + 1) % face.count];
      std::uint32_t const other = edge_face[{q, a}];
      hull.face_neighbors_[face.first + i] = other;
      if (a < q) hull.edges_.push_back(HullEdge{a, q, std::uint32_t(f), other});
    }
  }
}

template <ScalarReal S>
GMassProperties<S> detail_hull_builder::mass(GConvexHull<S> const& h, S density) {
  // Tetrahedra (r, a, b, c) with r the vertex centroid and (a, b, c) a fan of each face. For a
  // tetrahedron at r with edge matrix A = [a-r b-r c-r], the second moment (covariance) about
  // r is det(A) A C0 A^T with C0 = [[2 1 1] [1 2 1] [1 1 2]] / 120, its volume det(A) / 6 and
  // its centroid r + (a + b + c - 3r) / 4.
  if (h.empty()) return {S(0), GVec3<S>{}, GMat3<S>::ZERO};
  auto const vs = h.vertices();
  D3 r{0, 0, 0};
  for (auto const& v : vs)
    r = r + D3{double(v.x), double(v.y), double(v.z)};
  r = r * (1.0 / double(vs.size()));
  double vol = 0;
  D3 first{0, 0, 0};
  double cov[3][3] = {};
  auto const at = [&](std::uint32_t i) {
    return D3{double(vs[i].x), double(vs[i].y), double(vs[i].z)} - r;
  };
  for (std::size_t f = 0; f < h.faces().size(); ++f) {
    auto const fv = h.face_vertices(f);
    for (std::size_t i = 1; i + 1 < fv.size(); ++i) {
      D3 const a = at(fv[0]), bb = at(fv[i]), c = at(fv[i + 1]);
      double const det = a.dot(bb.cross(c));
      vol += det / 6.0;
      first = first + (a + bb + c) * (det / 24.0);
      double const A[3][3] = {{a.x, bb.x, c.x}, {a.y, bb.y, c.y}, {a.z, bb.z, c.z}};
      for (int r0 = 0; r0 < 3; ++r0)
        for (int r1 = 0; r1 < 3; ++r1) {
          double sum = 0;
          for (int m = 0; m < 3; ++m)
            for (int l = 0; l < 3; ++l)
              sum += A[r0][m] * (m == l ? 2.0 : 1.0) * A[r1][l];
          cov[r0][r1] += det * sum / 120.0;
        }
    }
  }
  D3 const cm = first * (1.0 / vol); // relative to r
  // Covariance about the centre of mass, then inertia = trace(C) E - C, times density.
  double cc[3][3];
  double const cmv[3] = {cm.x, cm.y, cm.z};
  for (int r0 = 0; r0 < 3; ++r0)
    for (int r1 = 0; r1 < 3; ++r1)
      cc[r0][r1] = cov[r0][r1] - vol * cmv[r0] * cmv[r1];
  double const tr = cc[0][0] + cc[1][1] + cc[2][2];
  double const rho = double(density);
  auto const I = [&](int r0, int r1) { return S(rho * ((r0 == r1 ? tr : 0.0) - cc[r0][r1])); };
  D3 const centre = r + cm;
  return {S(rho * vol), GVec3<S>{S(centre.x), S(centre.y), S(centre.z)},
          GMat3<S>::from_symmetric(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2))};
}

template <ScalarReal S>
GHullBuild<S> GConvexHull<S>::build(std::span<Vec const> points, S tolerance) {
  return detail_hull_builder::run<S>(points, tolerance);
}

template <ScalarReal S>
GMassProperties<S> GConvexHull<S>::mass_properties(S density) const noexcept {
  return detail_hull_builder::mass(*this, density);
}

} // namespace plume
