// Shapes: volumes against their formulas, support points against dense surface samples, and
// boxes at a pose that contain every support point and touch the shape on every side.
#include "../math/math_support.hpp"

#include <plume/collision/shapes.hpp>

#include <cmath>
#include <numbers>

using namespace plume;
using namespace plume::test;

namespace {
constexpr double kpi = std::numbers::pi;

/// The AABB at pose of a convex shape is tight: on each world axis, the support point of the
/// shape (moved by the pose) reaches the box face.
template <class Shape>
void check_aabb_tight(Shape const& s, Iso3 const& pose, float tol) {
  Aabb3 const box = s.aabb(pose);
  Vec3 const axes[3] = {Vec3::X, Vec3::Y, Vec3::Z};
  for (int i = 0; i < 3; ++i)
    for (float sign : {1.0f, -1.0f}) {
      Vec3 const w = axes[i] * sign;
      Vec3 const p = pose.transform_point(s.support(pose.inverse_transform_vector(w)));
      float const face =
          sign > 0 ? box.max.to_array()[std::size_t(i)] : -box.min.to_array()[std::size_t(i)];
      CHECK(std::abs(p.dot(w) - face) <= tol);
    }
}

/// support(dir) maximises p . dir over points of the shape: no sample beats it.
template <class Shape, class Sample>
void check_support(Shape const& s, Sample sample, int n) {
  rng r(9);
  for (int t = 0; t < 200; ++t) {
    Vec3 const d = r.vec3<float>(-1, 1);
    float const best = s.support(d).dot(d);
    float worst_gap = -1e30f;
    for (int k = 0; k < n; ++k)
      worst_gap = std::max(worst_gap, sample(r).dot(d) - best);
    CHECK(worst_gap <= 1e-5f * (1 + d.length()));
  }
}
} // namespace

TEST_CASE("shape volumes and areas", "[collision][shapes]") {
  CHECK(Sphere{2}.volume() == Approx(4.0 / 3.0 * kpi * 8).epsilon(1e-6));
  CHECK(Capsule{1, 0.5f}.volume() ==
        Approx(kpi * 0.25 * 2 + 4.0 / 3.0 * kpi * 0.125).epsilon(1e-6));
  CHECK(Cuboid{{1, 2, 3}}.volume() == 48);
  CHECK(Cylinder{1.5f, 2}.volume() == Approx(kpi * 4 * 3).epsilon(1e-6));
  CHECK(Triangle{{0, 0, 0}, {2, 0, 0}, {0, 3, 0}}.area() == 3);
  CHECK(Triangle{{1, 1, 1}, {2, 2, 2}, {3, 3, 3}}.area() == 0); // collinear: valid, no area
  CHECK(Sphere{0}.volume() == 0);
}

TEST_CASE("support points and boxes at a pose", "[collision][shapes]") {
  rng r(4);
  Iso3 const pose{Quat::from_axis_angle(Vec3{1, 2, 3}.normalize(), 0.7f), {3, -2, 1}};
  auto const on_sphere = [](rng& g, float rad) { return g.unit3<float>() * rad; };
  Sphere const sp{1.5f};
  check_support(
      sp, [&](rng& g) { return on_sphere(g, 1.5f); }, 400);
  check_aabb_tight(sp, pose, 1e-5f);
  Capsule const cap{0.75f, 0.5f};
  check_support(
      cap,
      [&](rng& g) {
        return Vec3{0, float(g.uniform(-0.75, 0.75)), 0} + on_sphere(g, 0.5f);
      },
      400);
  check_aabb_tight(cap, pose, 1e-5f);
  Cuboid const box{{1, 0.5f, 2}};
  check_support(
      box, [&](rng& g) { return g.vec3<float>(-1, 1) * box.half_extents; }, 400);
  check_aabb_tight(box, pose, 1e-5f);
  Cylinder const cyl{0.75f, 0.5f};
  check_support(
      cyl,
      [&](rng& g) {
        float const a = float(g.uniform(0, 2 * kpi));
        return Vec3{0.5f * std::cos(a), float(g.uniform(-0.75, 0.75)), 0.5f * std::sin(a)};
      },
      400);
  check_aabb_tight(cyl, pose, 1e-5f);
  Triangle const tri{{0, 0, 0}, {1, 2, 0}, {-1, 0.5f, 3}};
  check_support(
      tri,
      [&](rng& g) {
        float u = float(g.uniform(0, 1)), v = float(g.uniform(0, 1));
        if (u + v > 1) u = 1 - u, v = 1 - v;
        return tri.a + (tri.b - tri.a) * u + (tri.c - tri.a) * v;
      },
      400);
  check_aabb_tight(tri, pose, 1e-5f);
  // Degenerate sizes: a point, a segment, a flat box; a zero direction gives a shape point.
  CHECK(Sphere{0}.support({1, 0, 0}).length() == 0);
  CHECK(Sphere{1}.support({0, 0, 0}).length() == 0);
  CHECK(Capsule{1, 0}.support({0, -1, 0}).y == -1);
  CHECK(Cuboid{{1, 0, 1}}.aabb(Iso3::IDENTITY).max.y == 0);
  CHECK(Cylinder{1, 1}.support({0, 1, 0}).x == 0);
  CHECK(HalfSpace{{0, 1, 0}}.aabb(pose).max.x == std::numeric_limits<float>::infinity());
  // Ties go the documented way (GJK's answers then do not depend on rounding noise): the
  // positive side for zero components (+0 and -0), the upper end, the first vertex.
  auto const equal = [](Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
  for (float zero : {0.0f, -0.0f}) {
    CHECK(equal(box.support({zero, zero, zero}), box.half_extents));
    CHECK(equal(box.support({-1, zero, 1}), Vec3{-1, 0.5f, 2}));
    CHECK(equal(cap.support({1, zero, 0}), Vec3{0.5f, 0.75f, 0}));
    CHECK(equal(cyl.support({zero, zero, 1}), Vec3{0, 0.75f, 0.5f}));
    CHECK(equal(Segment{{0, 0, 0}, {0, 1, 0}}.support({1, zero, 0}), Vec3{0, 0, 0}));
  }
  CHECK(equal(Triangle{{0, 1, 0}, {0, 1, 1}, {0, 1, 2}}.support({0, 1, 0}), Vec3{0, 1, 0}));
  CHECK(equal(Triangle{{0, 0, 0}, {0, 1, 1}, {0, 1, 2}}.support({0, 1, 0}), Vec3{0, 1, 1}));
  (void)r;
}

PLUME_WIDE_TEST_CASE("shape methods are lane-exact", "[collision][shapes][lanes]",
                     wide_real_types) {
  using T = TestType;
  rng r(6);
  check_lanes<T>(
      "sphere", 50,
      [&](std::size_t) {
        return std::tuple{r.elem<T>(0, 2), r.vec3<T>(), r.quat<T>(), r.vec3<T>()};
      },
      [](auto rad, auto d, auto q, auto t) {
        using E = std::remove_cvref_t<decltype(rad)>;
        GSphere<E> const s{rad};
        GAabb3<E> const b = s.aabb(GIso3<E>{q, t});
        return std::array{s.support(d), b.min, b.max, GVec3<E>::splat(s.volume())};
      });
  check_lanes<T>(
      "capsule, cylinder, cuboid", 50,
      [&](std::size_t) {
        return std::tuple{r.elem<T>(0, 2), r.elem<T>(0, 2), r.vec3<T>(), r.quat<T>()};
      },
      [](auto h, auto rad, auto d, auto q) {
        using E = std::remove_cvref_t<decltype(h)>;
        GIso3<E> const pose{q, d};
        GCapsule<E> const c{h, rad};
        GCylinder<E> const y{h, rad};
        GCuboid<E> const x{d.abs()};
        return std::array{c.support(d),
                          c.aabb(pose).max,
                          y.support(d),
                          y.aabb(pose).min,
                          x.support(d),
                          x.aabb(pose).max,
                          GVec3<E>{c.volume(), y.volume(), x.volume()}};
      });
}
