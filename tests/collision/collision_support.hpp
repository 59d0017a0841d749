// Helpers shared by the collision tests: double vectors for oracles, hulls from points and
// boxes, and lanes_v<T> different hulls packed into one wide polytope.
#pragma once

#include "../math/math_support.hpp"

#include <plume/collision/convex_hull.hpp>

#include <span>
#include <vector>

namespace plume::test {

using D3 = GVec3<double>;
inline D3 to_d(Vec3 v) { return {v.x, v.y, v.z}; }

/// The 8 corners of the box [-e, e] (vertex i: x = bit 0, y = bit 1, z = bit 2).
template <ScalarReal S = float>
std::vector<GVec3<S>> box_points(GVec3<S> e) {
  std::vector<GVec3<S>> p;
  for (int i = 0; i < 8; ++i)
    p.push_back({(i & 1) ? e.x : -e.x, (i & 2) ? e.y : -e.y, (i & 4) ? e.z : -e.z});
  return p;
}

/// The hull of points, which must build.
template <ScalarReal S = float>
GConvexHull<S> hull_of(std::vector<GVec3<S>> const& pts) {
  auto built = GConvexHull<S>::build(pts);
  REQUIRE(built);
  return std::move(built.hull);
}

inline ConvexHull box_hull(Vec3 e) { return hull_of(box_points(e)); }

/// A hull's vertices placed by pose, in double.
inline std::vector<D3> world_vertices(ConvexHull const& h, Iso3 const& pose) {
  std::vector<D3> out;
  for (Vec3 const& v : h.vertices())
    out.push_back(to_d(pose.transform_point(v)));
  return out;
}

/// lanes_v<T> hulls (lane i from point_count(i) points made by point(i)), their vertices
/// packed for one wide polytope, and every lane's vertex list as the wide polytope sees it.
template <class T>
struct packed_hulls {
  using S = scalar_t<T>;
  std::vector<GConvexHull<S>> hulls;
  std::vector<GVec3<T>> packed;
  std::vector<std::vector<GVec3<S>>> lane_points;

  template <class Count, class Point>
  packed_hulls(Count point_count, Point point) {
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      std::vector<GVec3<S>> pts;
      for (std::size_t k = 0; k < point_count(i); ++k)
        pts.push_back(point(i));
      hulls.push_back(hull_of(pts));
    }
    std::vector<std::span<GVec3<S> const>> views;
    for (auto const& h : hulls)
      views.push_back(h.vertices());
    packed = pack_polytopes<T>(views);
    lane_points.resize(lanes_v<T>);
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      for (auto const& p : packed)
        lane_points[i].push_back(lane(p, i));
  }
  GConvexPolytope<T> wide() const { return {packed}; }
  GConvexPolytope<S> lane_polytope(std::size_t i) const { return {lane_points[i]}; }
};

} // namespace plume::test
