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
//    shapes' centres, else +Y), oriented from A toward B. Status `penetrating`.
//  - The polytope is full or out of iterations: the best face found so far. Status
//    `approximate` (the depth is a lower bound within the polytope's reach).
//  - Non-finite input: status `failed`, NaN depth.
#pragma once

#include <plume/collision/gjk.hpp>
#include <plume/math/iso3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

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
};

namespace detail {

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
  std::array<simplex_vertex<S>, max_vertices> vert;
  std::array<face, max_faces> faces;
  int nv = 0, nf = 0;

  bool add_face(int a, int b, int c) {
    if (nf == max_faces) return false;
    GVec3<S> const& pa = vert[std::size_t(a)].p;
    GVec3<S> n = (vert[std::size_t(b)].p - pa).cross(vert[std::size_t(c)].p - pa);
    S const len = n.length();
    if (!(len > S(0))) return false;
    n = n / len;
    faces[std::size_t(nf++)] = face{{a, b, c}, n, n.dot(pa), true};
    return true;
  }
};

} // namespace detail

/// Signed distance / penetration between convex shapes a (at pose_a) and b (at pose_b).
template <ScalarReal S, ConvexShape<S> A, ConvexShape<S> B>
GPenetrationResult<S> penetration(A const& a, GIso3<S> const& pose_a, B const& b,
                                  GIso3<S> const& pose_b, EpaConfig const& cfg = {}) noexcept {
  GPenetrationResult<S> out{};
  GClosestPoints<S> const g = closest_points(a, pose_a, b, pose_b, cfg.gjk);
  if (g.failed) {
    S const q = std::numeric_limits<S>::quiet_NaN();
    return {q, GVec3<S>{}, GVec3<S>::splat(q), GVec3<S>::splat(q), PenetrationStatus::failed, 0};
  }
  if (!g.overlap) {
    out.depth = -g.distance;
    out.normal = g.normal;
    out.point_a = g.point_a;
    out.point_b = g.point_b;
    out.status = g.distance < S(0) ? PenetrationStatus::penetrating : PenetrationStatus::separated;
    out.iterations = 0;
    return out;
  }

  S const ra = a.core_radius(), rb = b.core_radius();
  detail::placed<A, S> const sa{a, pose_a};
  detail::placed<B, S> const sb{b, pose_b};
  // Vertices of D = A - B (p = a - b here: the origin is inside D; normals point out of D,
  // and the nearest face's normal is the direction from A toward B).
  auto const vertex = [&](GVec3<S> const& d) {
    GVec3<S> const pa = sa.support(d), pb = sb.support(-d);
    return detail::simplex_vertex<S>{pa - pb, pa, pb};
  };
  GVec3<S> const centre_dir = pose_b.translation - pose_a.translation;
  auto const finish = [&](S core_depth, GVec3<S> n, GVec3<S> pa, GVec3<S> pb, PenetrationStatus st,
                          int it) {
    return GPenetrationResult<S>{core_depth + ra + rb, n, pa + n * ra, pb - n * rb, st, it};
  };
  auto const flat_fallback = [&](GVec3<S> const& n_flat, detail::simplex_vertex<S> const& at) {
    GVec3<S> n = n_flat;
    if (n.dot(centre_dir) < S(0)) n = -n;
    return finish(S(0), n, at.a, at.b, PenetrationStatus::penetrating, 0);
  };

  // Initial tetrahedron: extreme points along +-X, then the farthest from their line, then
  // the farthest from their plane (both sides tried).
  detail::epa_polytope<S> poly;
  std::array<GVec3<S>, 6> const axes{GVec3<S>::X,  -GVec3<S>::X, GVec3<S>::Y,
                                     -GVec3<S>::Y, GVec3<S>::Z,  -GVec3<S>::Z};
  std::array<detail::simplex_vertex<S>, 6> ext;
  S scale = S(0);
  for (std::size_t k = 0; k < 6; ++k) {
    ext[k] = vertex(axes[k]);
    scale = std::max(scale, ext[k].p.length());
  }
  S const eps = std::numeric_limits<S>::epsilon();
  S const tiny = S(64) * eps * scale;
  // The two extremes farthest apart.
  std::size_t i0 = 0, i1 = 1;
  for (std::size_t k = 0; k < 6; k += 2)
    if ((ext[k].p - ext[k + 1].p).length_squared() > (ext[i0].p - ext[i1].p).length_squared())
      i0 = k, i1 = k + 1;
  GVec3<S> const line = ext[i1].p - ext[i0].p;
  if (line.length() <= tiny) // D is a point: the cores coincide
    return flat_fallback(centre_dir.length_squared() > S(0) ? centre_dir.normalize() : GVec3<S>::Y,
                         ext[i0]);
  // Third point: the support along the directions perpendicular to the line, farthest out.
  GVec3<S> const u = line.any_orthonormal_vector();
  GVec3<S> const w = line.normalize().cross(u);
  std::array<GVec3<S>, 4> const perp{u, -u, w, -w};
  detail::simplex_vertex<S> p2{};
  S best = S(-1);
  for (auto const& d : perp) {
    detail::simplex_vertex<S> const c = vertex(d);
    S const dist = (c.p - ext[i0].p).cross(line).length() / line.length();
    if (dist > best) best = dist, p2 = c;
  }
  if (best <= tiny) { // D is a segment
    GVec3<S> const lu = line.normalize();
    GVec3<S> n = centre_dir - lu * centre_dir.dot(lu);
    n = n.length_squared() > S(0) ? n.normalize() : u;
    return flat_fallback(n, ext[i0]);
  }
  GVec3<S> const pn = line.cross(p2.p - ext[i0].p).normalize();
  detail::simplex_vertex<S> const up = vertex(pn), down = vertex(-pn);
  S const hu = (up.p - ext[i0].p).dot(pn), hd = (ext[i0].p - down.p).dot(pn);
  if (std::max(hu, hd) <= tiny) // D is flat
    return flat_fallback(pn, ext[i0]);
  detail::simplex_vertex<S> const p3 = hu >= hd ? up : down;
  poly.vert[0] = ext[i0], poly.vert[1] = ext[i1], poly.vert[2] = p2, poly.vert[3] = p3;
  poly.nv = 4;
  // Orient the faces outward: p3 must be below face (0, 1, 2).
  bool const flip = (p3.p - ext[i0].p).dot(pn) > S(0);
  bool ok = flip ? poly.add_face(0, 2, 1) && poly.add_face(0, 1, 3) && poly.add_face(1, 2, 3) &&
                       poly.add_face(2, 0, 3)
                 : poly.add_face(0, 1, 2) && poly.add_face(0, 3, 1) && poly.add_face(1, 3, 2) &&
                       poly.add_face(2, 3, 0);
  if (!ok) return flat_fallback(pn, ext[i0]);

  S const tol = S(cfg.tolerance);
  // The live face nearest to the origin (smallest signed distance: a negative one means the
  // origin is still outside it, and expanding it grows the polytope over the origin); -1 if
  // none. Its distance is a lower bound of the depth wherever the polytope holds the origin
  // (the polytope lies in D), which is why a capped result reports the nearest face.
  auto const nearest_face = [&poly] {
    int near = -1;
    for (int f = 0; f < poly.nf; ++f)
      if (poly.faces[std::size_t(f)].alive &&
          (near < 0 || poly.faces[std::size_t(f)].d < poly.faces[std::size_t(near)].d))
        near = f;
    return near;
  };
  int best_face = nearest_face(); // the tetrahedron's faces are all alive: >= 0
  typename detail::epa_polytope<S>::face chosen = poly.faces[std::size_t(best_face)];
  PenetrationStatus status = PenetrationStatus::approximate;
  int it = 0;
  for (; it < cfg.max_iterations; ++it) {
    best_face = nearest_face();
    if (best_face < 0) break;
    chosen = poly.faces[std::size_t(best_face)]; // kept: expanding kills it
    auto const& bf = chosen;
    detail::simplex_vertex<S> const nv = vertex(bf.n);
    S const gain = nv.p.dot(bf.n) - bf.d;
    S const floor = S(16) * eps * (nv.p.length() + scale);
    if (gain <= std::max(tol, floor) && bf.d >= -std::max(tol, floor)) {
      status = PenetrationStatus::penetrating;
      break;
    }
    if (poly.nv == poly.max_vertices) break;
    // Remove the faces that see the new point; the edges they do not share form the horizon.
    int const vi = poly.nv;
    poly.vert[std::size_t(poly.nv++)] = nv;
    std::array<std::array<int, 2>, 3 * detail::epa_polytope<S>::max_faces> edges;
    int ne = 0;
    for (int f = 0; f < poly.nf; ++f) {
      auto& fc = poly.faces[std::size_t(f)];
      if (!fc.alive || fc.n.dot(nv.p - poly.vert[std::size_t(fc.v[0])].p) <= S(0)) continue;
      fc.alive = false;
      for (int e = 0; e < 3; ++e) {
        int const ea = fc.v[std::size_t(e)], eb = fc.v[std::size_t((e + 1) % 3)];
        // An edge seen twice (once per direction) is inside the removed region.
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
    bool grown = ne > 0;
    for (int k = 0; k < ne && grown; ++k)
      grown = poly.add_face(edges[std::size_t(k)][0], edges[std::size_t(k)][1], vi);
    if (!grown) break; // full, or a sliver face: keep the best face found
    // Compact the face list now and then so it does not fill with dead faces.
    if (poly.nf > poly.max_faces - 3 * 16) {
      int live = 0;
      for (int f = 0; f < poly.nf; ++f)
        if (poly.faces[std::size_t(f)].alive)
          poly.faces[std::size_t(live++)] = poly.faces[std::size_t(f)];
      poly.nf = live;
    }
  }
  if (best_face < 0) return flat_fallback(pn, ext[i0]);
  // The origin's projection on the nearest face, in barycentric weights of its vertices.
  auto const& bf = chosen;
  auto const& v0 = poly.vert[std::size_t(bf.v[0])];
  auto const& v1 = poly.vert[std::size_t(bf.v[1])];
  auto const& v2 = poly.vert[std::size_t(bf.v[2])];
  GVec3<S> const q = bf.n * bf.d;
  GVec3<S> const n = (v1.p - v0.p).cross(v2.p - v0.p);
  S const nn = n.length_squared();
  S const l0 = (v1.p - q).cross(v2.p - q).dot(n) / nn;
  S const l1 = (v2.p - q).cross(v0.p - q).dot(n) / nn;
  S const l2 = S(1) - l0 - l1;
  GVec3<S> const pa = (v0.a * l0 + v1.a * l1) + v2.a * l2;
  GVec3<S> const pb = (v0.b * l0 + v1.b * l1) + v2.b * l2;
  return finish(std::max(bf.d, S(0)), bf.n, pa, pb, status, it);
}

using PenetrationResult = GPenetrationResult<float>;

} // namespace plume
