// plume/collision/epa.hpp - signed distance with penetration depth: penetration(a, pose_a,
// b, pose_b) gives the distance when the shapes are apart and the depth, normal and deepest
// points when they overlap. Scalar (float or double): EPA's polytope is branchy data, and
// the callers (manifolds, depenetration) run it per pair.
//
// How: GJK first (collision/gjk.hpp). Apart, or only the rounding radii overlapping: the GJK
// answer is exact. Cores overlapping: the expanding polytope algorithm (van den Bergen 2001)
// on the Minkowski difference of the cores, then the radii are added.
//
// EPA here: the initial tetrahedron is made of support points (it need not contain the
// origin: the face with the smallest signed distance is expanded first, which grows the
// polytope over the origin); faces are expanded until the support point along the nearest
// face's normal is within tolerance of it. The polytope is bounded (64 vertices, 128 faces,
// no heap), and so is the iteration count.
//
// Fallbacks (documented results, never a hang):
//  - Flat difference of the cores (two crossing segments, a triangle through a box face's
//    plane, coincident sphere centres): no volume, so the core depth is 0 and the normal is
//    the normal of the flat set (or, for a segment or a point, the direction between the
//    shapes' centres, else +Y), oriented from A toward B; the points are where GJK found the
//    cores meeting. Status `penetrating`.
//  - The polytope is full or out of iterations: the best face found so far. Status
//    `approximate` (the depth is a lower bound within the polytope's reach). With the origin
//    still in front of that face (the polytope never covered it: a grazing contact on a
//    nearly flat D), the depth is 0, and the points are where GJK found the cores meeting
//    when the face's are farther apart than those.
//  - Non-finite input: status `failed`, NaN depth.
#pragma once

#include <plume/collision/gjk.hpp>
#include <plume/math/iso3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace plume {

enum class PenetrationStatus : std::uint8_t {
  separated,   ///< apart: depth = -distance (negative)
  penetrating, ///< overlapping: depth, normal and points are exact up to tolerance
  approximate, ///< overlapping, EPA capped: the best face found
  failed,      ///< non-finite input
};

template <ScalarReal S>
struct GPenetrationResult {
  /// Overlap depth: positive overlapping, negative apart (minus the distance).
  S depth;
  /// Unit, from A toward B: moving B by depth * normal (or A by -depth * normal) makes the
  /// shapes touch.
  GVec3<S> normal;
  GVec3<S> point_a; ///< world, on A's surface (the deepest point of A inside B)
  GVec3<S> point_b; ///< world, on B's surface
  PenetrationStatus status;
  int iterations; ///< EPA iterations (0 when GJK decided)
};

struct EpaConfig {
  int max_iterations = 64;
  /// Convergence: the support point along the nearest face's normal is within this of the
  /// face (length units; plus 16 eps of the coordinates, as in GJK).
  float tolerance = 1e-5f;
  GjkConfig gjk{};

  /// This config with every length-valued field (tolerance, gjk's) multiplied by length_unit.
  EpaConfig scaled(float length_unit) const noexcept {
    EpaConfig c = *this;
    c.tolerance *= length_unit;
    c.gjk = c.gjk.scaled(length_unit);
    return c;
  }
};

namespace detail {

/// EPA's polytope: vertices of D, triangles with outward unit normals; dead faces stay in the
/// list until it is compacted.
///
/// Invariant: every face has the seed tetrahedron's centroid (inside D, inside every later
/// polytope) strictly behind it. Supports on a flat part of D (a cylinder's cap, a box's face)
/// lie in the plane of faces the new vertex does not see, and the new face beside such a face
/// can come out a sliver or turned inward (then the nearest face, with a wrong depth); that
/// face joins the replaced region instead (grow()).
template <ScalarReal S>
struct epa_polytope {
  static constexpr int max_vertices = 64;
  static constexpr int max_faces = 128;
  struct face {
    std::array<int, 3> v;
    GVec3<S> n; ///< unit outward normal
    S d;        ///< n . vertex: the signed distance of the origin's plane
    bool alive;
  };
  /// The horizon of a new vertex: directed edges (a, b).
  using horizon = std::array<std::array<int, 2>, 3 * max_faces>;
  std::array<simplex_vertex<S>, max_vertices> vert;
  std::array<face, max_faces> faces;
  int nv = 0, nf = 0;
  GVec3<S> inside{}; ///< the seed tetrahedron's centroid

  /// The face (a, b, c) into f: its unit normal and distance; false when it has no area or,
  /// with `check`, when `inside` is not strictly behind it (turned inward by rounding) or its
  /// distance is below min_d (turned sideways: see grow()).
  bool make_face(int a, int b, int c, bool check, S min_d, face& f) const noexcept {
    GVec3<S> const& pa = vert[std::size_t(a)].p;
    GVec3<S> n = (vert[std::size_t(b)].p - pa).cross(vert[std::size_t(c)].p - pa);
    S const len = n.length();
    if (!(len > S(0))) return false;
    n = n / len;
    S const d = n.dot(pa);
    if (check && !(n.dot(inside - pa) < S(0) && d >= min_d)) return false;
    f = face{{a, b, c}, n, d, true};
    return true;
  }

  /// Appends the face (a, b, c) of the seed tetrahedron; false when it has no area.
  bool add_face(int a, int b, int c) {
    if (nf == max_faces) return false;
    face f;
    if (!make_face(a, b, c, false, S(0), f)) return false;
    faces[std::size_t(nf++)] = f;
    return true;
  }

  /// The live face nearest to the origin (smallest signed distance: a negative one means the
  /// origin is still outside it, and expanding it grows the polytope over the origin); -1 if
  /// none. Its distance is a lower bound of the depth wherever the polytope holds the origin
  /// (the polytope lies in D), which is why a capped result reports the nearest face (or a
  /// neighbour within 4 tolerances of it whose plane the origin projects into: face_points).
  int nearest_face() const noexcept {
    int near = -1;
    for (int f = 0; f < nf; ++f)
      if (faces[std::size_t(f)].alive &&
          (near < 0 || faces[std::size_t(f)].d < faces[std::size_t(near)].d))
        near = f;
    return near;
  }

  /// The edges of the faces marked in `in` that no other marked face shares (an edge seen
  /// twice, once per direction, is inside the region): the horizon, into edges; its length.
  int region_horizon(std::array<char, max_faces> const& in, horizon& edges) const noexcept {
    int ne = 0;
    for (int f = 0; f < nf; ++f) {
      if (!in[std::size_t(f)]) continue;
      auto const& fc = faces[std::size_t(f)];
      for (int e = 0; e < 3; ++e) {
        int const ea = fc.v[std::size_t(e)], eb = fc.v[std::size_t((e + 1) % 3)];
        bool shared = false;
        for (int k = 0; k < ne; ++k)
          if (edges[std::size_t(k)][0] == eb && edges[std::size_t(k)][1] == ea) {
            edges[std::size_t(k)] = edges[std::size_t(--ne)];
            shared = true;
            break;
          }
        if (!shared) edges[std::size_t(ne++)] = {ea, eb};
      }
    }
    return ne;
  }

  /// The live face outside `in` with the directed edge (a, b); -1 if none.
  int face_with_edge(int a, int b, std::array<char, max_faces> const& in) const noexcept {
    for (int f = 0; f < nf; ++f) {
      auto const& fc = faces[std::size_t(f)];
      if (!fc.alive || in[std::size_t(f)]) continue;
      for (int e = 0; e < 3; ++e)
        if (fc.v[std::size_t(e)] == a && fc.v[std::size_t((e + 1) % 3)] == b) return f;
    }
    return -1;
  }

  /// Drops the dead faces from the list.
  void compact() noexcept {
    int live = 0;
    for (int f = 0; f < nf; ++f)
      if (faces[std::size_t(f)].alive) faces[std::size_t(live++)] = faces[std::size_t(f)];
    nf = live;
  }

  /// Adds vertex w: the faces that see it are replaced by a fan from the horizon to it. A
  /// face w does not see but lies almost in the plane of (a flat part of D: a cylinder's cap,
  /// a box's face) would leave the new face beside it a sliver or turned inward; such a face
  /// joins the replaced region and the horizon is taken again. min_d: the smallest distance
  /// a new face may have. A polytope that holds the origin only grows, so no face of the
  /// next one is nearer the origin than the nearest face now; a new face that is (beyond the
  /// rounding) was made from a horizon edge nearly in line with w, its normal set by
  /// rounding, and is refused the same way. False, with the polytope unchanged, when the
  /// vertices or faces are full or no region gives valid faces (EPA then reports the best
  /// face found).
  bool grow(simplex_vertex<S> const& w, S min_d) noexcept {
    if (nv == max_vertices) return false;
    // Compact the face list now and then so it does not fill with dead faces.
    if (nf > max_faces - 3 * 16) compact();
    int const vi = nv;
    vert[std::size_t(vi)] = w; // not counted until the faces are in
    std::array<char, max_faces> in{};
    for (int f = 0; f < nf; ++f) {
      auto const& fc = faces[std::size_t(f)];
      in[std::size_t(f)] = fc.alive && fc.n.dot(w.p - vert[std::size_t(fc.v[0])].p) > S(0);
    }
    horizon edges;
    std::array<face, max_faces> fresh;
    for (int round = 0; round < 8; ++round) {
      int const ne = region_horizon(in, edges);
      if (ne == 0 || nf + ne > max_faces) return false;
      bool ok = true;
      for (int k = 0; k < ne; ++k) {
        int const ea = edges[std::size_t(k)][0], eb = edges[std::size_t(k)][1];
        if (make_face(ea, eb, vi, true, min_d, fresh[std::size_t(k)])) continue;
        ok = false;
        int const across = face_with_edge(eb, ea, in);
        if (across < 0) return false;
        in[std::size_t(across)] = 1;
      }
      if (!ok) continue;
      ++nv;
      for (int f = 0; f < nf; ++f)
        if (in[std::size_t(f)]) faces[std::size_t(f)].alive = false;
      for (int k = 0; k < ne; ++k)
        faces[std::size_t(nf++)] = fresh[std::size_t(k)];
      return true;
    }
    return false;
  }
};

/// D = A - B for two placed cores (p = a - b): the origin is inside D when the cores
/// overlap, normals point out of D, and the nearest face's normal is the direction from A
/// toward B.
template <class A, class B, ScalarReal S>
struct core_difference {
  placed<A, S> sa;
  placed<B, S> sb;
  /// The vertex of D along d, with the support points of A and B that make it.
  simplex_vertex<S> vertex(GVec3<S> const& d) const noexcept {
    GVec3<S> const pa = sa.support(d), pb = sb.support(-d);
    return simplex_vertex<S>{pa - pb, pa, pb};
  }
};

/// The start of EPA: the initial tetrahedron (built into the polytope), or the normal to
/// report when D is flat.
template <ScalarReal S>
struct epa_seed {
  bool built;
  /// D flat: the normal of the flat set, unoriented; built: the normal of the plane of the
  /// first three vertices (the fallback if the expansion loses every face).
  GVec3<S> flat_normal;
  S scale; ///< the largest |vertex| along the axes: the size of D
};

/// The vertices of D along +-X, +-Y, +-Z; the largest of their distances from the origin into
/// scale.
template <ScalarReal S, class Diff>
std::array<simplex_vertex<S>, 6> axis_extremes(Diff const& diff, S& scale) noexcept {
  std::array<GVec3<S>, 6> const axes{GVec3<S>::X,  -GVec3<S>::X, GVec3<S>::Y,
                                     -GVec3<S>::Y, GVec3<S>::Z,  -GVec3<S>::Z};
  std::array<simplex_vertex<S>, 6> ext;
  scale = S(0);
  for (std::size_t k = 0; k < 6; ++k) {
    ext[k] = diff.vertex(axes[k]);
    scale = std::max(scale, ext[k].p.length());
  }
  return ext;
}

/// Of the three pairs of opposite extremes, the two farthest apart (the first on ties).
template <ScalarReal S>
std::pair<std::size_t, std::size_t>
farthest_pair(std::array<simplex_vertex<S>, 6> const& ext) noexcept {
  std::size_t i0 = 0, i1 = 1;
  for (std::size_t k = 0; k < 6; k += 2)
    if ((ext[k].p - ext[k + 1].p).length_squared() > (ext[i0].p - ext[i1].p).length_squared())
      i0 = k, i1 = k + 1;
  return {i0, i1};
}

/// The third vertex: of the supports along four directions perpendicular to the line (from
/// p0 along `line`), the farthest from it, and that distance.
template <ScalarReal S, class Diff>
std::pair<simplex_vertex<S>, S> farthest_from_line(Diff const& diff, GVec3<S> const& p0,
                                                   GVec3<S> const& line,
                                                   GVec3<S> const& u) noexcept {
  GVec3<S> const w = line.normalize().cross(u);
  std::array<GVec3<S>, 4> const perp{u, -u, w, -w};
  simplex_vertex<S> p2{};
  S best = S(-1);
  for (auto const& d : perp) {
    simplex_vertex<S> const c = diff.vertex(d);
    S const dist = (c.p - p0).cross(line).length() / line.length();
    if (dist > best) best = dist, p2 = c;
  }
  return {p2, best};
}

/// Sets the polytope to the tetrahedron of its four vertices, faces oriented outward (vertex
/// 3 below face (0, 1, 2), whose normal is +-pn); false if a face has no area.
template <ScalarReal S>
bool close_tetrahedron(epa_polytope<S>& poly, GVec3<S> const& pn) {
  poly.nv = 4;
  poly.inside = ((poly.vert[0].p + poly.vert[1].p) + (poly.vert[2].p + poly.vert[3].p)) * S(0.25);
  bool const flip = (poly.vert[3].p - poly.vert[0].p).dot(pn) > S(0);
  return flip ? poly.add_face(0, 2, 1) && poly.add_face(0, 1, 3) && poly.add_face(1, 2, 3) &&
                    poly.add_face(2, 0, 3)
              : poly.add_face(0, 1, 2) && poly.add_face(0, 3, 1) && poly.add_face(1, 3, 2) &&
                    poly.add_face(2, 3, 0);
}

/// The initial tetrahedron: the extreme points along +-X farthest apart (or Y, Z), then the
/// farthest from their line, then the farthest from their plane (both sides tried). It need
/// not contain the origin. When D is a point, a segment or flat (within 64 eps of its size),
/// there is no tetrahedron and the seed holds the normal to report: the direction between the
/// shapes' centres (else +Y) for a point, its part perpendicular to the segment (else a
/// perpendicular) for a segment, the plane's normal for a flat D.
template <ScalarReal S, class Diff>
epa_seed<S> initial_tetrahedron(Diff const& diff, GVec3<S> const& centre_dir,
                                epa_polytope<S>& poly) noexcept {
  epa_seed<S> seed{};
  std::array<simplex_vertex<S>, 6> const ext = axis_extremes(diff, seed.scale);
  S const tiny = S(64) * std::numeric_limits<S>::epsilon() * seed.scale;
  auto const [i0, i1] = farthest_pair(ext);
  GVec3<S> const line = ext[i1].p - ext[i0].p;
  if (line.length() <= tiny) { // D is a point: the cores coincide
    seed.flat_normal = centre_dir.length_squared() > S(0) ? centre_dir.normalize() : GVec3<S>::Y;
    return seed;
  }
  GVec3<S> const u = line.normalize().any_orthonormal_vector(); // (it needs a unit vector)
  auto const [p2, dist] = farthest_from_line(diff, ext[i0].p, line, u);
  if (dist <= tiny) { // D is a segment
    GVec3<S> const lu = line.normalize();
    GVec3<S> const n = centre_dir - lu * centre_dir.dot(lu);
    // With centre_dir along the segment what the rejection leaves is rounding, along the
    // segment as much as across it (lu is unit only to the rounding): a normal from it could
    // lie along the segment, reporting depth 0 where the overlap along it is the segment's
    // length. Below 64 eps of centre_dir, any perpendicular; above, rejected once more.
    S const noise = S(64) * std::numeric_limits<S>::epsilon() * centre_dir.length();
    seed.flat_normal = n.length() > noise ? (n - lu * n.dot(lu)).normalize() : u;
    return seed;
  }
  // The cross product of D's extents taken at scale 1 (a power of two near the line's largest
  // component, so the scaling is exact and the normal's bits are those of the unscaled
  // product where that does not overflow): at D's own scale (up to the 1e19 GJK accepts) its
  // squared length can overflow, which would make the normal zero.
  int exponent = 0;
  std::frexp(line.abs().max_element(), &exponent);
  S const inv = std::ldexp(S(1), -exponent);
  GVec3<S> const pn = (line * inv).cross((p2.p - ext[i0].p) * inv).normalize();
  seed.flat_normal = pn;
  simplex_vertex<S> const up = diff.vertex(pn), down = diff.vertex(-pn);
  S const hu = (up.p - ext[i0].p).dot(pn), hd = (ext[i0].p - down.p).dot(pn);
  if (std::max(hu, hd) <= tiny) return seed; // D is flat
  poly.vert[0] = ext[i0], poly.vert[1] = ext[i1], poly.vert[2] = p2;
  poly.vert[3] = hu >= hd ? up : down;
  seed.built = close_tetrahedron(poly, pn);
  return seed;
}

/// How the expansion ended: the nearest face found last (its index, -1 when no face is left
/// alive) and a copy of it (expanding kills it), the status and the iteration count.
template <ScalarReal S>
struct epa_outcome {
  int best_face;
  typename epa_polytope<S>::face chosen;
  PenetrationStatus status;
  int iterations;
};

/// Expands the polytope's nearest face until the support point along its normal is within
/// the tolerance (or the rounding floor, 16 eps of the coordinates) of it: penetrating. The
/// iteration cap, full vertices or a sliver face stop it first: approximate.
template <ScalarReal S, class Diff>
epa_outcome<S> expand(epa_polytope<S>& poly, Diff const& diff, S scale,
                      EpaConfig const& cfg) noexcept {
  S const eps = std::numeric_limits<S>::epsilon();
  S const tol = S(cfg.tolerance);
  epa_outcome<S> r{poly.nearest_face(), {}, PenetrationStatus::approximate, 0};
  r.chosen = poly.faces[std::size_t(r.best_face)]; // the tetrahedron's faces are all alive
  for (; r.iterations < cfg.max_iterations; ++r.iterations) {
    r.best_face = poly.nearest_face();
    if (r.best_face < 0) break;
    r.chosen = poly.faces[std::size_t(r.best_face)];
    auto const& bf = r.chosen;
    simplex_vertex<S> const w = diff.vertex(bf.n);
    S const gain = w.p.dot(bf.n) - bf.d;
    S const floor = S(16) * eps * (w.p.length() + scale);
    if (gain <= std::max(tol, floor) && bf.d >= -std::max(tol, floor)) {
      r.status = PenetrationStatus::penetrating;
      break;
    }
    // The nearest face's distance, less the rounding, bounds the next polytope's faces from
    // below once the polytope holds the origin.
    S const min_d = bf.d >= S(0) ? bf.d - std::max(tol, floor) : -infinity<S>();
    if (!poly.grow(w, min_d)) break; // keep the best face found
  }
  return r;
}

/// The barycentric weights of point q (in face f's plane) over f's vertices.
template <ScalarReal S>
std::array<S, 3> face_weights(epa_polytope<S> const& poly, typename epa_polytope<S>::face const& f,
                              GVec3<S> const& q) noexcept {
  GVec3<S> const& p0 = poly.vert[std::size_t(f.v[0])].p;
  GVec3<S> const& p1 = poly.vert[std::size_t(f.v[1])].p;
  GVec3<S> const& p2 = poly.vert[std::size_t(f.v[2])].p;
  GVec3<S> const n = (p1 - p0).cross(p2 - p0);
  S const nn = n.length_squared();
  S const l0 = (p1 - q).cross(p2 - q).dot(n) / nn;
  S const l1 = (p2 - q).cross(p0 - q).dot(n) / nn;
  return {l0, l1, S(1) - l0 - l1};
}

/// The barycentric weights of the point of face f's boundary nearest q, and its squared
/// distance from q: of the three edges' nearest points (q's foot on the edge's line, clamped
/// to its ends), the nearest (the first on ties). Where q's projection falls outside f, this
/// is f's nearest point. Each foot comes from one dot product over
/// the edge's squared length, accurate whatever the triangle's shape: the region tests of
/// the usual closed form (differences of products of dot products) cancel to rounding on a
/// sliver face, and put the point up to the sliver's length off the edge q lies on
/// (docs/fuzzing.md, regress-hull-point-on-edge).
template <ScalarReal S>
std::pair<std::array<S, 3>, S> nearest_face_weights(epa_polytope<S> const& poly,
                                                    typename epa_polytope<S>::face const& f,
                                                    GVec3<S> const& q) noexcept {
  std::array<S, 3> best{S(1), S(0), S(0)};
  S best_d2 = infinity<S>();
  for (std::size_t i = 0; i < 3; ++i) {
    std::size_t const j = (i + 1) % 3;
    GVec3<S> const& a = poly.vert[std::size_t(f.v[i])].p;
    GVec3<S> const e = poly.vert[std::size_t(f.v[j])].p - a;
    S const ee = e.length_squared();
    S const t = ee > S(0) ? std::clamp((q - a).dot(e) / ee, S(0), S(1)) : S(0);
    S const d2 = ((a + e * t) - q).length_squared();
    if (!(d2 < best_d2)) continue;
    best_d2 = d2;
    best = {S(0), S(0), S(0)};
    best[i] = S(1) - t;
    best[j] = t;
  }
  return {best, best_d2};
}

/// The origin's projection on face bf, in barycentric weights of its vertices, applied to
/// their support points: the deepest points of A and B. When the projection falls outside bf
/// (a coplanar neighbour as near as bf holds it: the polytope's faces there are one flat
/// face of D split in triangles), the weights come from the live face of the same plane
/// (within `slack` in distance, 1e-4 in normal) that holds it, so the points are convex
/// combinations of support points (on A and B), not extrapolations past them; else from the
/// nearest live face of nearly bf's orientation within 4 `slack` of its distance that holds
/// its own projection and that D does not pass by more than `slack` (a support of `diff`),
/// which `reported` then names (the normal and depth to report; otherwise bf); else from
/// the point of the polytope's surface nearest the projection: of the edges (bf's and every
/// live face's), or, when those are all farther than `slack`, of a face's inside.
template <ScalarReal S, class Diff>
std::pair<GVec3<S>, GVec3<S>> face_points(epa_polytope<S> const& poly, Diff const& diff,
                                          typename epa_polytope<S>::face const& bf, S slack,
                                          typename epa_polytope<S>::face& reported) noexcept {
  reported = bf;
  GVec3<S> const q = bf.n * bf.d;
  auto const inside = [](std::array<S, 3> const& l) {
    return l[0] >= S(0) && l[1] >= S(0) && l[2] >= S(0);
  };
  typename epa_polytope<S>::face f = bf;
  std::array<S, 3> l = face_weights(poly, bf, q);
  for (int k = 0; k < poly.nf && !inside(l); ++k) {
    auto const& g = poly.faces[std::size_t(k)];
    if (!g.alive || !(std::abs(g.d - bf.d) <= slack) || !(g.n.dot(bf.n) >= S(1) - S(1e-4)))
      continue;
    std::array<S, 3> const lg = face_weights(poly, g, q);
    if (inside(lg)) {
      f = g;
      l = lg;
    }
  }
  if (!inside(l)) {
    // No face of that plane holds it, where the rounding of a sliver face (a short edge beside
    // long ones) left bf nearest though the origin projects beyond its short edge: a live
    // neighbour of nearly bf's orientation (within 2.6 degrees)
    // within 4 `slack` of its distance is as near within a few convergence tolerances (a
    // converged depth lies between bf's distance and that plus the tolerance), and the
    // nearest of those whose own projection it holds is reported instead (its normal,
    // distance and weights), if D reaches no farther than `slack` beyond its plane (the
    // test bf passed). Only once the polytope holds the origin (bf.d >= 0).
    for (int k = 0; k < poly.nf && bf.d >= S(0); ++k) {
      auto const& g = poly.faces[std::size_t(k)];
      if (!g.alive || !(g.d <= bf.d + S(4) * slack) || !(g.n.dot(bf.n) >= S(0.999)) ||
          (inside(l) && !(g.d < f.d)))
        continue;
      std::array<S, 3> const lg = face_weights(poly, g, g.n * g.d);
      // Certified as bf was: D reaches no farther than `slack` beyond g's plane.
      if (inside(lg) && diff.vertex(g.n).p.dot(g.n) - g.d <= slack) {
        f = g;
        l = lg;
        reported = g;
      }
    }
  }
  if (!inside(l)) {
    // No face of that plane holds the projection (an approximate answer, or a sliver face
    // the projection misses by rounding): negative weights would extrapolate the points off
    // the shapes, so the weights are those of the point of the polytope's surface (an edge
    // of bf or of a live face) nearest the projection, which keeps each point a convex
    // combination of its shape's support points (on the shape) and moves their difference
    // only by the projection's distance from that point (dropping the negative weights and
    // renormalising would move it by that times the face's aspect ratio). Of every face, not
    // bf's alone: where the origin is a vertex of D that bf does not have (a neighbour has
    // it, of nearly bf's plane but with weights a rounding below 0, or its distance off by
    // its own normal's rounding on a sliver), bf's nearest point can be a whole edge away
    // (docs/fuzzing.md, regress-shared-vertex).
    auto [lb, best] = nearest_face_weights(poly, bf, q);
    l = lb;
    for (int k = 0; k < poly.nf && best > S(0); ++k) {
      auto const& g = poly.faces[std::size_t(k)];
      if (!g.alive) continue;
      auto const [lg, dg] = nearest_face_weights(poly, g, q);
      if (dg < best) {
        best = dg;
        f = g;
        l = lg;
      }
    }
    // The surface's nearest point can lie inside a face, not on an edge: a face whose
    // projection of q lies inside it is d = g.n . q - g.d from q, along its normal. Where
    // the origin projects into a coplanar neighbour of a sliver bf (two faces of a flat
    // quad of D split along its long diagonal, a ruled side of a cylinder and a segment's
    // difference) whose distance is off by its normal's rounding beyond `slack`, the
    // nearest edge point is up to the sliver's width away across the plane, while the
    // neighbour's inside is that rounding away along the normal. Only when the edges'
    // best is farther than `slack` (so an origin on an edge or a vertex keeps its edge).
    for (int k = 0; k < poly.nf && best > slack * slack; ++k) {
      auto const& g = poly.faces[std::size_t(k)];
      if (!g.alive) continue;
      std::array<S, 3> const lg = face_weights(poly, g, q);
      S const h = g.n.dot(q) - g.d;
      if (inside(lg) && h * h < best) {
        best = h * h;
        f = g;
        l = lg;
      }
    }
  }
  auto const& v0 = poly.vert[std::size_t(f.v[0])];
  auto const& v1 = poly.vert[std::size_t(f.v[1])];
  auto const& v2 = poly.vert[std::size_t(f.v[2])];
  return {(v0.a * l[0] + v1.a * l[1]) + v2.a * l[2], (v0.b * l[0] + v1.b * l[1]) + v2.b * l[2]};
}

/// A penetration from GJK's answer (the shapes apart, or only their rounding radii
/// overlapping: exact).
template <ScalarReal S>
GPenetrationResult<S> from_closest_points(GClosestPoints<S> const& g) noexcept {
  GPenetrationResult<S> out{};
  out.depth = -g.distance;
  out.normal = g.normal;
  out.point_a = g.point_a;
  out.point_b = g.point_b;
  out.status = g.distance < S(0) ? PenetrationStatus::penetrating : PenetrationStatus::separated;
  out.iterations = 0;
  return out;
}

} // namespace detail

/// Signed distance / penetration between convex shapes a (at pose_a) and b (at pose_b).
template <ScalarReal S, ConvexShape<S> A, ConvexShape<S> B>
GPenetrationResult<S> penetration(A const& a, GIso3<S> const& pose_a, B const& b,
                                  GIso3<S> const& pose_b, EpaConfig const& cfg = {}) noexcept {
  GClosestPoints<S> const g = closest_points(a, pose_a, b, pose_b, cfg.gjk);
  if (g.failed) {
    S const q = std::numeric_limits<S>::quiet_NaN();
    return {q, GVec3<S>{}, GVec3<S>::splat(q), GVec3<S>::splat(q), PenetrationStatus::failed, 0};
  }
  if (!g.overlap) return detail::from_closest_points(g);

  // The cores overlap: EPA on their difference, then the radii are added.
  S const ra = a.core_radius(), rb = b.core_radius();
  detail::core_difference<A, B, S> const diff{{a, pose_a}, {b, pose_b}};
  GVec3<S> const centre_dir = pose_b.translation - pose_a.translation;
  auto const finish = [&](S core_depth, GVec3<S> n, GVec3<S> pa, GVec3<S> pb, PenetrationStatus st,
                          int it) {
    return GPenetrationResult<S>{core_depth + ra + rb, n, pa + n * ra, pb - n * rb, st, it};
  };
  auto const flat_fallback = [&](detail::epa_seed<S> const& seed) {
    GVec3<S> n = seed.flat_normal;
    if (n.dot(centre_dir) < S(0)) n = -n;
    // The points: where GJK found the cores meeting (a point of both), so that they are
    // depth * normal apart once the radii are added.
    return finish(S(0), n, g.point_a, g.point_b, PenetrationStatus::penetrating, 0);
  };
  detail::epa_polytope<S> poly;
  detail::epa_seed<S> const seed = detail::initial_tetrahedron(diff, centre_dir, poly);
  if (!seed.built) return flat_fallback(seed);
  detail::epa_outcome<S> const r = detail::expand(poly, diff, seed.scale, cfg);
  if (r.best_face < 0) return flat_fallback(seed);
  S const slack =
      std::max(S(cfg.tolerance), S(16) * std::numeric_limits<S>::epsilon() * seed.scale);
  typename detail::epa_polytope<S>::face used;
  auto const [pa, pb] = detail::face_points(poly, diff, r.chosen, slack, used);
  // With the origin in front of the face (d < 0) the depth reported is 0, and the points
  // for depth 0 meet. The face's are about -d apart (more where a sliver's weights put them
  // off its plane); GJK's, where it found the cores meeting, are its |v| apart (within its
  // rounding floor). When the expansion stopped before the polytope covered the origin (D
  // thin there, its faces slivers whose normals are set by rounding: d can be far below 0)
  // and the face's points are farther apart than GJK's by more than `slack`, GJK's are
  // reported, as for a flat D.
  bool const in_front = S(0) > used.d;
  if (in_front && (pa - pb).length() > (g.point_a - g.point_b).length() + slack)
    return finish(S(0), used.n, g.point_a, g.point_b, r.status, r.iterations);
  return finish(std::max(used.d, S(0)), used.n, pa, pb, r.status, r.iterations);
}

using PenetrationResult = GPenetrationResult<float>;

} // namespace plume
