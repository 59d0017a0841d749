// tests/fuzz/fuzz_shapes.hpp - what the collision fuzz targets share: a convex shape of any
// kind the GJK family takes (sphere, capsule, cuboid, cylinder, triangle, segment, polytope
// view, convex hull) decoded from the fuzzer's bytes, a pose, and the world support function
// the targets check results against (h(u) = max over the shape of x . u, computed in double
// from the shape's own support point, so a check does not trust the query it checks).
//
// Shapes come in two flavours: reasonable (every parameter from Input::real, sizes >= 0,
// degenerate ones included: zero radii and extents, flat triangles, coincident points) and
// hostile (Input::maybe_bad: NaN, infinities, huge and negative values), for which only the
// bad-input contract and survival are checked.
#pragma once

#include "fuzz_input.hpp"

#include <plume/collision/convex_hull.hpp>
#include <plume/collision/shapes.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace plume::fuzz {

enum class Kind : std::uint8_t {
  sphere,
  capsule,
  cuboid,
  cylinder,
  triangle,
  segment,
  polytope,
  hull,
};
inline constexpr int kind_count = 8;

/// One shape of any kind; `visit` calls a function with the concrete shape.
struct AnyShape {
  Kind kind = Kind::sphere;
  Sphere sphere{};
  Capsule capsule{};
  Cuboid cuboid{};
  Cylinder cylinder{};
  Triangle triangle{};
  Segment segment{};
  std::vector<Vec3> points; ///< the polytope view's vertices
  ConvexHull hull;
  bool finite = true; ///< every parameter finite
  bool sized = true;  ///< every size (radius, half height, half extent) >= 0 (not NaN)
  float size = 0;     ///< a bound of |x| over the shape (local frame); +inf or NaN if not finite

  template <class F>
  decltype(auto) visit(F&& f) const {
    switch (kind) {
    case Kind::sphere:
      return f(sphere);
    case Kind::capsule:
      return f(capsule);
    case Kind::cuboid:
      return f(cuboid);
    case Kind::cylinder:
      return f(cylinder);
    case Kind::triangle:
      return f(triangle);
    case Kind::segment:
      return f(segment);
    case Kind::polytope:
      return f(ConvexPolytope{points});
    case Kind::hull:
      break;
    }
    return f(hull);
  }
};

/// Reads values: from real() for a reasonable shape, from maybe_bad() for a hostile one.
struct ValueSource {
  Input& in;
  bool hostile;
  float num(float lo, float hi) { return hostile ? in.maybe_bad(lo, hi) : in.real(lo, hi); }
  /// A size in [0, hi], exactly 0 one time in 8.
  float size(float hi) {
    float const v = num(0, hi);
    return (in.byte() & 7) == 0 ? 0.0f : v;
  }
  Vec3 vec3(float lo, float hi) { return {num(lo, hi), num(lo, hi), num(lo, hi)}; }
};

inline float norm(Vec3 const& v) {
  double const x = v.x, y = v.y, z = v.z;
  return float(std::sqrt(x * x + y * y + z * z));
}

/// A shape of kind k (sizes up to about 2, vertices within 2 of the local origin).
inline AnyShape make_shape(Input& in, Kind k, bool hostile) {
  ValueSource src{in, hostile};
  AnyShape s;
  s.kind = k;
  switch (k) {
  case Kind::sphere:
    s.sphere = {src.size(2)};
    s.size = s.sphere.radius;
    s.finite = std::isfinite(s.sphere.radius);
    break;
  case Kind::capsule:
    s.capsule = {src.size(2), src.size(1)};
    s.size = s.capsule.half_height + s.capsule.radius;
    s.finite = std::isfinite(s.capsule.half_height) && std::isfinite(s.capsule.radius);
    break;
  case Kind::cuboid:
    s.cuboid = {{src.size(2), src.size(2), src.size(2)}};
    s.size = norm(s.cuboid.half_extents);
    s.finite = finite(s.cuboid.half_extents);
    break;
  case Kind::cylinder:
    s.cylinder = {src.size(2), src.size(1.5f)};
    s.size = s.cylinder.half_height + s.cylinder.radius;
    s.finite = std::isfinite(s.cylinder.half_height) && std::isfinite(s.cylinder.radius);
    break;
  case Kind::triangle: {
    Vec3 const a = src.vec3(-2, 2), b = src.vec3(-2, 2);
    Vec3 c = src.vec3(-2, 2);
    int const shape = in.byte() & 7;
    if (shape == 0) c = a + (b - a) * in.real(-1, 2); // collinear (a flat triangle)
    if (shape == 1) c = b;                            // two vertices coincide
    s.triangle = {a, b, c};
    s.size = std::max({norm(a), norm(b), norm(c)});
    s.finite = finite(a) && finite(b) && finite(c);
    break;
  }
  case Kind::segment: {
    Vec3 const a = src.vec3(-2, 2);
    Vec3 const b = (in.byte() & 7) == 0 ? a : src.vec3(-2, 2); // a point one time in 8
    s.segment = {a, b};
    s.size = std::max(norm(a), norm(b));
    s.finite = finite(a) && finite(b);
    break;
  }
  case Kind::polytope: {
    int const n = in.integer(1, 12);
    for (int i = 0; i < n; ++i) {
      // Repeat an earlier vertex now and then (duplicates are valid).
      bool const repeat = i > 0 && (in.byte() & 7) == 0;
      s.points.push_back(repeat ? s.points[std::size_t(in.integer(0, i - 1))]
                                : src.vec3(-1.5f, 1.5f));
    }
    for (auto const& p : s.points) {
      s.size = std::max(s.size, norm(p));
      s.finite = s.finite && finite(p);
    }
    break;
  }
  case Kind::hull: {
    // Hulls are always reasonable: the builder refuses non-finite points (convex_hull.cpp
    // fuzzes that), so a hostile hull would only be the fallback below.
    int const n = in.integer(4, 16);
    std::vector<Vec3> pts;
    for (int i = 0; i < n; ++i)
      pts.push_back(in.vec3(-1.5f, 1.5f));
    HullBuild built = ConvexHull::build(pts);
    if (!built) {
      // Degenerate points: a fixed tetrahedron instead.
      std::vector<Vec3> const tet{{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
      built = ConvexHull::build(tet);
    }
    s.hull = std::move(built.hull);
    for (auto const& p : s.hull.vertices())
      s.size = std::max(s.size, norm(p));
    break;
  }
  }
  auto const nonneg = [](float v) { return v >= 0; };
  switch (k) {
  case Kind::sphere:
    s.sized = nonneg(s.sphere.radius);
    break;
  case Kind::capsule:
    s.sized = nonneg(s.capsule.half_height) && nonneg(s.capsule.radius);
    break;
  case Kind::cuboid:
    s.sized = nonneg(s.cuboid.half_extents.x) && nonneg(s.cuboid.half_extents.y) &&
              nonneg(s.cuboid.half_extents.z);
    break;
  case Kind::cylinder:
    s.sized = nonneg(s.cylinder.half_height) && nonneg(s.cylinder.radius);
    break;
  default:
    break;
  }
  if (!s.finite) s.size = INFINITY;
  return s;
}

inline Kind read_kind(Input& in) { return Kind(in.integer(0, kind_count - 1)); }

/// A pose: a unit rotation and a translation in [-lim, lim]^3; hostile, a non-finite
/// translation or rotation component now and then.
inline Iso3 make_pose(Input& in, float lim, bool hostile) {
  Quat q = in.rotation();
  Vec3 const t = hostile ? in.maybe_bad_vec3(-lim, lim) : in.vec3(-lim, lim);
  if (hostile && (in.byte() & 15) == 0) q.w = in.any_float();
  return Iso3{q, t};
}

// ------------------------------------------------------------------- support in double

struct D3 {
  double x = 0, y = 0, z = 0;
  D3() = default;
  D3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  explicit D3(Vec3 const& v) : x(v.x), y(v.y), z(v.z) {}
  friend D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
  double dot(D3 b) const { return x * b.x + y * b.y + z * b.z; }
  D3 cross(D3 b) const { return {y * b.z - z * b.y, z * b.x - x * b.z, x * b.y - y * b.x}; }
  double length() const { return std::sqrt(dot(*this)); }
};

/// The world support point of a shape at a pose along dir (any length).
template <class Shape>
Vec3 world_support(Shape const& s, Iso3 const& pose, Vec3 const& dir) {
  return pose.transform_point(s.support(pose.inverse_transform_vector(dir)));
}

/// h(u) = support point . u, in double, for a unit u (the shape's extent along u).
template <class Shape>
double extent_along(Shape const& s, Iso3 const& pose, Vec3 const& u) {
  return D3(world_support(s, pose, u)).dot(D3(u));
}

/// A few unit directions to test support inequalities along: the axes, their diagonals and
/// `extra`.
inline std::array<Vec3, 14> probe_directions() {
  float const k = 0.57735026f;
  return {Vec3{1, 0, 0},  Vec3{-1, 0, 0},  Vec3{0, 1, 0},    Vec3{0, -1, 0}, Vec3{0, 0, 1},
          Vec3{0, 0, -1}, Vec3{k, k, k},   Vec3{-k, -k, -k}, Vec3{k, -k, k}, Vec3{-k, k, -k},
          Vec3{k, k, -k}, Vec3{-k, -k, k}, Vec3{-k, k, k},   Vec3{k, -k, -k}};
}

/// The vertices of a polytope-like shape (cuboid corners, triangle and segment ends, polytope
/// points, hull vertices), local frame; none for the other kinds.
inline std::vector<Vec3> local_vertices(AnyShape const& s) {
  std::vector<Vec3> v;
  switch (s.kind) {
  case Kind::cuboid: {
    Vec3 const e = s.cuboid.half_extents;
    for (int i = 0; i < 8; ++i)
      v.push_back({(i & 1) ? e.x : -e.x, (i & 2) ? e.y : -e.y, (i & 4) ? e.z : -e.z});
    break;
  }
  case Kind::triangle:
    v = {s.triangle.a, s.triangle.b, s.triangle.c};
    break;
  case Kind::segment:
    v = {s.segment.a, s.segment.b};
    break;
  case Kind::polytope:
    v = s.points;
    break;
  case Kind::hull:
    v.assign(s.hull.vertices().begin(), s.hull.vertices().end());
    break;
  default:
    break;
  }
  return v;
}

/// Points of the shape at a pose, world: its vertices and its support points along the probe
/// directions.
inline std::vector<Vec3> sample_points(AnyShape const& s, Iso3 const& pose) {
  std::vector<Vec3> pts;
  for (auto const& v : local_vertices(s))
    pts.push_back(pose.transform_point(v));
  s.visit([&](auto const& shape) {
    for (auto const& u : probe_directions())
      pts.push_back(world_support(shape, pose, u));
  });
  return pts;
}

/// A unit vector from the input (or +x when the bytes give a zero one).
inline Vec3 unit_vector(Input& in) {
  Vec3 const v = in.vec3(-1, 1);
  float const l = norm(v);
  return l > 1e-3f ? v * (1.0f / l) : Vec3{1, 0, 0};
}

} // namespace plume::fuzz
