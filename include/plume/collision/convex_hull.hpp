// plume/collision/convex_hull.hpp - convex polytopes: the wide vertex view GConvexPolytope<T>
// that the GJK family casts against, and GConvexHull<S>, built from a point cloud by
// quickhull, with polygon faces, edges and face adjacency (what contact manifolds clip with).
//
//   auto built = ConvexHull::build(points);        // HullBuild (GHullBuild<float>)
//   if (!built) std::puts(to_string(built.error));  // too few / coincident / collinear / ...
//   ConvexHull const& hull = built.hull;
//
// Build conventions (Barber, Dobkin, Huhdanpaa 1996; computed in double whatever S is):
//  - tolerance: a point within `tolerance` of a face plane is on that face, not outside it.
//    The default is 16 eps(S) times the sum of the largest |coordinate| on each axis, so
//    duplicates, coplanar and nearly coplanar points (noise below the tolerance) add no
//    vertices and no sliver faces. It is also the least: a smaller tolerance is raised to it
//    (faces stored in S cannot be more exact than the rounding of S at those coordinates).
//  - Coplanar triangles are merged into polygon faces; a vertex that lies only on a straight
//    edge between two faces is dropped. Every face is a convex polygon, counter-clockwise seen
//    from outside, with a unit outward normal and offset (normal . p = offset on the face).
//  - Errors (the hull is then empty): fewer than 4 points, a non-finite coordinate, all
//    points within the tolerance of one point, of one line, or of one plane (also when that
//    plane is not the starting tetrahedron's: a hull thinner than the tolerance across one
//    of its faces is coplanar).
#pragma once

#include <plume/collision/mass_properties.hpp>
#include <plume/collision/shapes.hpp>
#include <plume/math/aabb3.hpp>
#include <plume/math/iso3.hpp>
#include <plume/math/pack.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

PLUME_MASK_CODE_BEGIN

namespace plume {

/// A convex polytope given by its vertices (the convex hull of `points`), generic over T:
/// with a wide T lane i is a different polytope, all with the same vertex count (repeat a
/// vertex to pad a shorter one). A view: the points must outlive it. Empty views have no
/// support point (support returns zero).
template <Real T>
struct GConvexPolytope {
  std::span<GVec3<T> const> points;

  /// The vertex farthest along dir (the first one on ties).
  GVec3<T> support(GVec3<T> const& dir) const noexcept {
    if (points.empty()) return {};
    GVec3<T> best = points[0];
    T best_d = best.dot(dir);
    for (std::size_t i = 1; i < points.size(); ++i) {
      T const d = points[i].dot(dir);
      mask_t<T> const better = d > best_d;
      best_d = plume::select(better, d, best_d);
      best = GVec3<T>::select(better, points[i], best);
    }
    return best;
  }
  GVec3<T> core_support(GVec3<T> const& dir) const noexcept { return support(dir); }
  T core_radius() const noexcept { return zero<T>(); }
  /// Lanes whose points are all finite (one pass over them; the queries report the others as
  /// failed: support never picks a point whose dot product is NaN).
  mask_t<T> is_finite() const noexcept {
    mask_t<T> ok = all_lanes<T>();
    for (auto const& p : points)
      ok = ok & p.is_finite();
    return ok;
  }
  GAabb3<T> local_aabb() const noexcept {
    if (points.empty()) return {};
    GAabb3<T> box{points[0], points[0]};
    for (auto const& p : points)
      box = {box.min.min(p), box.max.max(p)};
    return box;
  }
  GAabb3<T> aabb(GIso3<T> const& pose) const noexcept {
    if (points.empty()) return {};
    GVec3<T> const p0 = pose.transform_point(points[0]);
    GAabb3<T> box{p0, p0};
    for (auto const& p : points) {
      GVec3<T> const w = pose.transform_point(p);
      box = {box.min.min(w), box.max.max(w)};
    }
    return box;
  }
};

enum class HullError : std::uint8_t {
  none,
  too_few_points, ///< fewer than 4 points
  non_finite,     ///< a NaN or infinite coordinate
  coincident,     ///< every point within the tolerance of one point
  collinear,      ///< every point within the tolerance of one line
  coplanar,       ///< every point within the tolerance of one plane: no volume
};

constexpr char const* to_string(HullError e) noexcept {
  switch (e) {
  case HullError::none:
    return "none";
  case HullError::too_few_points:
    return "convex hull: fewer than 4 points";
  case HullError::non_finite:
    return "convex hull: a point has a NaN or infinite coordinate";
  case HullError::coincident:
    return "convex hull: all points coincide";
  case HullError::collinear:
    return "convex hull: all points lie on one line";
  case HullError::coplanar:
    return "convex hull: all points lie in one plane (no volume)";
  }
  return "convex hull: unknown error";
}

/// A polygon face of a hull: vertex indices face_vertices[first .. first + count).
template <ScalarReal S>
struct GHullFace {
  GVec3<S> normal; ///< unit, outward
  S offset;        ///< normal . p = offset for p on the face
  std::uint32_t first, count;
};

/// An edge between two faces: a -> b runs counter-clockwise around `left` (and b -> a
/// around `right`).
struct HullEdge {
  std::uint32_t a, b, left, right;
};

template <ScalarReal S>
struct GHullBuild;

namespace detail {
/// What a GConvexHull holds: filled by the quickhull builder (detail/quickhull.hpp).
template <ScalarReal S>
struct hull_data {
  std::vector<GVec3<S>> vertices;
  std::vector<GHullFace<S>> faces;
  std::vector<std::uint32_t> face_vertices, face_neighbors;
  std::vector<HullEdge> edges;
  S tolerance = S(0);
};
namespace hull_builder {
template <ScalarReal S>
GHullBuild<S> run(std::span<GVec3<S> const> in, S tolerance);
} // namespace hull_builder
} // namespace detail

/// A convex hull: vertices, polygon faces with adjacency, edges. Scalar (float or double);
/// polytope() gives the vertex view the GJK family uses; pack_polytopes<T> interleaves the
/// vertices of several hulls into the storage of one wide GConvexPolytope<T>.
template <ScalarReal S>
class GConvexHull {
public:
  using Vec = GVec3<S>;

  /// Quickhull over points (see the conventions at the top); tolerance <= 0 picks the default.
  static GHullBuild<S> build(std::span<Vec const> points, S tolerance = S(0));

  /// The empty hull (no vertices, no faces).
  GConvexHull() = default;

  std::span<Vec const> vertices() const noexcept { return d_.vertices; }
  std::span<GHullFace<S> const> faces() const noexcept { return d_.faces; }
  std::span<HullEdge const> edges() const noexcept { return d_.edges; }
  /// The vertex indices of face f, counter-clockwise seen from outside.
  std::span<std::uint32_t const> face_vertices(std::size_t f) const noexcept {
    return std::span<std::uint32_t const>(d_.face_vertices)
        .subspan(d_.faces[f].first, d_.faces[f].count);
  }
  /// neighbors(f)[i]: the face across the edge face_vertices(f)[i] -> [i + 1].
  std::span<std::uint32_t const> face_neighbors(std::size_t f) const noexcept {
    return std::span<std::uint32_t const>(d_.face_neighbors)
        .subspan(d_.faces[f].first, d_.faces[f].count);
  }
  /// Every face's vertex indices, one face after the other (face f from faces()[f].first).
  std::span<std::uint32_t const> face_vertex_indices() const noexcept { return d_.face_vertices; }
  /// The tolerance the hull was built with (the one asked for, or the default where that is
  /// larger).
  S tolerance() const noexcept { return d_.tolerance; }
  bool empty() const noexcept { return d_.vertices.empty(); }

  GConvexPolytope<S> polytope() const noexcept { return {d_.vertices}; }
  Vec support(Vec const& dir) const noexcept { return polytope().support(dir); }
  Vec core_support(Vec const& dir) const noexcept { return support(dir); }
  S core_radius() const noexcept { return S(0); }
  GAabb3<S> local_aabb() const noexcept { return polytope().local_aabb(); }
  GAabb3<S> aabb(GIso3<S> const& pose) const noexcept { return polytope().aabb(pose); }

  /// The face whose outward normal is most aligned with dir (the first on ties).
  std::size_t support_face(Vec const& dir) const noexcept {
    std::size_t best = 0;
    for (std::size_t f = 1; f < d_.faces.size(); ++f)
      if (d_.faces[f].normal.dot(dir) > d_.faces[best].normal.dot(dir)) best = f;
    return best;
  }

  /// Volume and mass properties, from the faces split into tetrahedra with the vertex
  /// centroid (exact for the polytope, up to rounding).
  S volume() const noexcept { return mass_properties(S(1)).mass; }
  GMassProperties<S> mass_properties(S density) const noexcept;

private:
  explicit GConvexHull(detail::hull_data<S>&& d) noexcept : d_(std::move(d)) {}

  detail::hull_data<S> d_;

  // Only the builder makes non-empty hulls (from the data it computed).
  friend GHullBuild<S> detail::hull_builder::run<S>(std::span<Vec const>, S);
};

template <ScalarReal S>
struct GHullBuild {
  GConvexHull<S> hull;
  HullError error = HullError::none;
  explicit operator bool() const noexcept { return error == HullError::none; }
};

using ConvexHull = GConvexHull<float>;
using DConvexHull = GConvexHull<double>;
using HullFace = GHullFace<float>;
using DHullFace = GHullFace<double>;
using HullBuild = GHullBuild<float>;
using DHullBuild = GHullBuild<double>;
using ConvexPolytope = GConvexPolytope<float>;

/// The vertices of lanes_v<T> polytopes (one per lane) interleaved for a wide
/// GConvexPolytope<T>: entry i holds vertex i of every lane; a lane with fewer vertices repeats
/// its last one (which changes no support point). Empty input lanes give zero points.
template <Real T>
std::vector<GVec3<T>> pack_polytopes(std::span<std::span<GVec3<scalar_t<T>> const> const> lanes) {
  std::size_t n = 0;
  for (auto const& l : lanes)
    n = l.size() > n ? l.size() : n;
  std::vector<GVec3<T>> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::array<GVec3<scalar_t<T>>, lanes_v<T>> row{};
    for (std::size_t k = 0; k < lanes_v<T> && k < lanes.size(); ++k) {
      auto const& l = lanes[k];
      if (!l.empty()) row[k] = l[i < l.size() ? i : l.size() - 1];
    }
    out[i] = pack<T>(row.data(), lanes_v<T>);
  }
  return out;
}

} // namespace plume

#include <plume/collision/detail/quickhull.hpp>

PLUME_MASK_CODE_END
