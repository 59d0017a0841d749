// Velocity projection: agreement of the n-step algorithm with brute force (17 normals, 1000
// directions), the optimality conditions against an independent QP oracle, named geometric
// cases, bad input, and lane-exactness of the wide forms.
#include "character_support.hpp"

#include <plume/solver/character/velocity_projection.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>

using namespace plume;
using namespace plume::test;

namespace {

template <class S>
GVelocityProjectionConfig<S> default_cfg() {
  return {};
}

/// Max over planes of -n . u (how far u moves into the set).
template <class Vec>
auto intrusion(Vec const& u, std::vector<Vec> const& n) {
  typename Vec::element_type worst = 0;
  for (auto const& ni : n)
    worst = std::max(worst, -ni.dot(u));
  return worst;
}

} // namespace

// ------------------------------------------------------------------------------------ agreement

TEMPLATE_TEST_CASE("agreement with brute force: 17 normals, every prefix, 1000 directions",
                   "[solver][projection]", float, double) {
  using S = TestType;
  auto const cfg = default_cfg<S>();
  std::vector<GVec3<S>> all;
  for (auto const& n : avian_normals_3d())
    all.push_back(to<S>(n));
  std::map<int, int> histogram;
  S worst_gap = -1;
  double worst_fast = 0, worst_brute = 0;
  for (std::size_t k = 1; k <= all.size(); ++k) {
    std::vector<GVec3<S>> const n(all.begin(), all.begin() + std::ptrdiff_t(k));
    plastic_directions dirs;
    // A quarter of the directions in the -O0 sanitizer build, where the full set took 140 s.
    for (int t = 0; t < (PLUME_TEST_UNOPTIMISED ? 250 : 1000); ++t) {
      GVec3<S> const v = to<S>(dirs.next());
      auto const fast = project_velocity(v, n, cfg);
      auto const brute = project_velocity_bruteforce(v, n, cfg);
      INFO("k = " << k << ", v = " << v << ", fast " << fast.velocity << ", brute "
                  << brute.velocity);
      REQUIRE(fast.converged);
      REQUIRE(!fast.invalid_input);
      REQUIRE(intrusion(fast.velocity, n) <= cfg.epsilon);
      REQUIRE(intrusion(brute.velocity, n) <= cfg.epsilon);
      S const gap = (fast.velocity - v).length() - (brute.velocity - v).length();
      REQUIRE(gap <= cfg.epsilon);
      worst_gap = std::max(worst_gap, gap);
      if (k == all.size()) {
        ++histogram[int(fast.steps)];
        // Distance of both answers from the exact projection (double, independent oracle).
        std::vector<Eigen::Vector3d> ne;
        for (auto const& x : n)
          ne.emplace_back(double(x.x), double(x.y), double(x.z));
        Eigen::Vector3d const s3 =
            qp_oracle<3>(Eigen::Vector3d(double(v.x), double(v.y), double(v.z)), ne);
        DVec3 const star{s3.x(), s3.y(), s3.z()};
        worst_fast = std::max(worst_fast, (to<double>(fast.velocity) - star).length());
        worst_brute = std::max(worst_brute, (to<double>(brute.velocity) - star).length());
      }
    }
  }
  // The step counts for the full set of 17 (the header quotes their maximum).
  std::printf("n-step steps, 17 normals x %d directions (%s):", PLUME_TEST_UNOPTIMISED ? 250 : 1000,
              sizeof(S) == 4 ? "f32" : "f64");
  for (auto const& [steps, count] : histogram)
    std::printf(" %d:%d", steps, count);
  std::printf("; worst |u-v| - |brute-v| = %.3g; worst |u-exact| n-step %.3g, brute %.3g\n",
              double(worst_gap), worst_fast, worst_brute);
  // Both accept planes violated by less than epsilon, so both stray from the exact
  // projection by epsilon / sin(angle between planes) (brute force measured 0.065 here, the
  // n-step 0.028): bound the n-step at 10 epsilon.
  CHECK(worst_fast <= 10 * double(cfg.epsilon));
  CHECK(histogram.rbegin()->first <= 4);
}

TEMPLATE_TEST_CASE("2D agreement with brute force: 5 normals, every prefix, 1000 directions",
                   "[solver][projection][2d]", float, double) {
  using S = TestType;
  auto const cfg = default_cfg<S>();
  std::vector<GVec2<S>> all;
  for (auto const& n : avian_normals_2d())
    all.push_back(to<S>(n));
  for (std::size_t k = 1; k <= all.size(); ++k) {
    std::vector<GVec2<S>> const n(all.begin(), all.begin() + std::ptrdiff_t(k));
    golden_directions dirs;
    for (int t = 0; t < 1000; ++t) {
      GVec2<S> const v = to<S>(dirs.next());
      auto const fast = project_velocity(v, n, cfg);
      auto const brute = project_velocity_bruteforce(v, n, cfg);
      INFO("k = " << k << ", v = " << v << ", fast " << fast.velocity << ", brute "
                  << brute.velocity);
      REQUIRE(fast.converged);
      REQUIRE(fast.steps <= 2);
      REQUIRE(intrusion(fast.velocity, n) <= cfg.epsilon);
      REQUIRE(intrusion(brute.velocity, n) <= cfg.epsilon);
      REQUIRE((fast.velocity - v).length() - (brute.velocity - v).length() <= cfg.epsilon);
    }
  }
}

// ------------------------------------------------------------------------ optimality and oracle

namespace {

/// Random unit normals at least `min_angle_cos` apart, biased against v so that many are
/// violated.
std::vector<DVec3> random_planes(rng& r, DVec3 const& v, std::size_t k) {
  std::vector<DVec3> n;
  while (n.size() < k) {
    DVec3 c = r.unit3<double>();
    if (r.uniform(0, 1) < 0.6 && c.dot(v) > 0) c = -c; // mostly against the motion
    bool far = true;
    for (auto const& m : n)
      far = far && c.dot(m) < 0.985; // the plane-set builder merges within 5 degrees
    if (far) n.push_back(c);
  }
  return n;
}

template <class S>
void check_optimality(std::size_t k, int trials, std::uint64_t seed) {
  rng r(seed);
  GVelocityProjectionConfig<S> cfg;
  cfg.epsilon = sizeof(S) == 4 ? S(1e-4) : S(1e-9);
  int zero_answers = 0;
  struct {
    double slack = 0, recon = 0, orth = 0, oracle = 0;
  } worst;
  for (int t = 0; t < trials; ++t) {
    DVec3 const vd = r.unit3<double>() * r.uniform(0.5, 4);
    auto const nd = random_planes(r, vd, k);
    GVec3<S> const v = to<S>(vd);
    std::vector<GVec3<S>> n;
    for (auto const& x : nd)
      n.push_back(to<S>(x));
    std::vector<S> lambda(k);
    auto const res = project_velocity<S>(v, n, lambda, cfg);
    GVec3<S> const u = res.velocity;
    INFO("trial " << t << ", k = " << k << ", v = " << v << ", u = " << u);
    // Rounding bounds in units of the element type's epsilon times |v|; the worst values
    // seen are printed at the end (each bound is several times above them).
    double const ev = eps_v<S> * vd.length();
    REQUIRE(res.converged);
    // Primal feasibility and the multipliers: lambda >= 0, u = v + N lambda,
    // lambda_i (n_i . u) = 0, hence u . (u - v) = 0.
    DVec3 recon = to<double>(v);
    for (std::size_t i = 0; i < k; ++i) {
      REQUIRE(n[i].dot(u) >= -cfg.epsilon);
      REQUIRE(lambda[i] >= 0);
      if (lambda[i] > 0) {
        worst.slack = std::max(worst.slack, std::abs(double(n[i].dot(u))));
        REQUIRE(std::abs(double(n[i].dot(u))) <= 32 * ev);
      }
      recon = recon + to<double>(n[i]) * double(lambda[i]);
    }
    worst.recon = std::max(worst.recon, (recon - to<double>(u)).length());
    worst.orth = std::max(worst.orth, std::abs(double(u.dot(u - v))));
    REQUIRE((recon - to<double>(u)).length() <= 256 * ev);
    REQUIRE(std::abs(double(u.dot(u - v))) <= 32 * ev * vd.length());
    // The oracle: the exact projection in double from an independent enumeration.
    Eigen::Vector3d const ve(vd.x, vd.y, vd.z);
    std::vector<Eigen::Vector3d> ne;
    for (auto const& x : n)
      ne.emplace_back(double(x.x), double(x.y), double(x.z));
    Eigen::Vector3d const star =
        qp_oracle<3>(Eigen::Vector3d(double(v.x), double(v.y), double(v.z)), ne);
    DVec3 const ustar{star.x(), star.y(), star.z()};
    REQUIRE((to<double>(u) - to<double>(v)).length() <=
            (ustar - to<double>(v)).length() + double(cfg.epsilon));
    // With planes at least 10 degrees apart the answer is well conditioned: a plane ignored
    // for being violated by less than epsilon moves u by at most epsilon / sin(10 deg).
    worst.oracle = std::max(worst.oracle, (to<double>(u) - ustar).length());
    REQUIRE((to<double>(u) - ustar).length() <= 6 * double(cfg.epsilon) + 64 * ev);
    if (ustar.length() == 0) ++zero_answers;
    (void)ve;
  }
  if (k >= 4) CHECK(zero_answers > 0); // the sets do surround v sometimes
  std::printf("optimality %s k=%zu: slack %.3g recon %.3g orth %.3g |u-exact| %.3g\n",
              sizeof(S) == 4 ? "f32" : "f64", k, worst.slack, worst.recon, worst.orth,
              worst.oracle);
}

} // namespace

TEST_CASE("optimality conditions and the QP oracle, random plane sets", "[solver][projection]") {
  for (std::size_t k : {1u, 2u, 3u, 4u, 6u, 8u}) {
    check_optimality<double>(k, 400, 100 + k);
    check_optimality<float>(k, 400, 200 + k);
  }
}

TEST_CASE("2D optimality against the QP oracle", "[solver][projection][2d]") {
  rng r(77);
  DVelocityProjectionConfig cfg;
  cfg.epsilon = 1e-9;
  for (int t = 0; t < 2000; ++t) {
    std::size_t const k = 1 + std::size_t(t % 5);
    DVec2 const v = DVec2::from_angle(r.uniform(-3.2, 3.2)) * r.uniform(0.5, 4);
    std::vector<DVec2> n;
    while (n.size() < k) {
      DVec2 c = DVec2::from_angle(r.uniform(-3.2, 3.2));
      bool far = true;
      for (auto const& m : n)
        far = far && c.dot(m) < 0.985;
      if (far) n.push_back(c);
    }
    std::vector<double> lambda(k);
    auto const res = project_velocity<double>(v, n, lambda, cfg);
    std::vector<Eigen::Vector2d> ne;
    for (auto const& x : n)
      ne.emplace_back(x.x, x.y);
    Eigen::Vector2d const star = qp_oracle<2>(Eigen::Vector2d(v.x, v.y), ne);
    INFO("trial " << t << ", v = " << v << ", u = " << res.velocity);
    REQUIRE(res.converged);
    CHECK((res.velocity - DVec2{star.x(), star.y()}).length() <= 6 * cfg.epsilon);
    DVec2 recon = v;
    for (std::size_t i = 0; i < k; ++i) {
      REQUIRE(lambda[i] >= 0);
      recon = recon + n[i] * lambda[i];
    }
    CHECK((recon - res.velocity).length() <= 1e-12);
  }
}

// -------------------------------------------------------------------------- named geometric cases

namespace {
Vec3 unit(float x, float y, float z) { return Vec3{x, y, z}.normalize(); }
bool near(Vec3 a, Vec3 b, float tol = 1e-6f) { return (a - b).length() <= tol; }
} // namespace

TEST_CASE("named geometric cases", "[solver][projection]") {
  // Normals point out of the obstacles, towards the character; +Z is up.
  Vec3 const wall_x{-1, 0, 0}, wall_y{0, -1, 0}, floor{0, 0, 1};
  auto project = [](Vec3 v, std::vector<Vec3> const& n) {
    auto const fast = project_velocity(v, n);
    auto const brute = project_velocity_bruteforce(v, n);
    CHECK(near(fast.velocity, brute.velocity, 1e-5f));
    CHECK(fast.converged);
    return fast;
  };
  SECTION("one wall, head on: stop") {
    CHECK(near(project({3, 0, 0}, {wall_x}).velocity, Vec3::ZERO));
  }
  SECTION("45 degree approach: keep the tangential part") {
    auto const r = project({2, 2, 0}, {wall_x});
    CHECK(near(r.velocity, {0, 2, 0}));
    CHECK(r.steps == 1);
  }
  SECTION("moving away from a wall: unchanged, no step") {
    auto const r = project({-1, 0.5f, 0}, {wall_x});
    CHECK(r.velocity.x == -1);
    CHECK(r.steps == 0);
  }
  SECTION("90 degree corner: stop") {
    CHECK(near(project({1, 1, 0}, {wall_x, wall_y}).velocity, Vec3::ZERO));
    CHECK(near(project({1, 0.2f, 0}, {wall_x, wall_y}).velocity, Vec3::ZERO));
  }
  SECTION("floor and two walls: stop") {
    CHECK(near(project({1, 1, -1}, {floor, wall_x, wall_y}).velocity, Vec3::ZERO));
    CHECK(near(project({0.3f, 2, -0.1f}, {wall_y, floor, wall_x}).velocity, Vec3::ZERO));
  }
  SECTION("jumping into a corner keeps the vertical component exactly") {
    auto const r = project({1, 1, 5}, {wall_x, wall_y});
    CHECK(r.velocity.z == 5); // exact, not just near
    CHECK(std::abs(r.velocity.x) <= 1e-7f);
    CHECK(std::abs(r.velocity.y) <= 1e-7f);
  }
  SECTION("wall-floor crease: slide along the crease") {
    auto const r = project({1, 1, -1}, {floor, wall_x});
    CHECK(near(r.velocity, {0, 1, 0}));
  }
  SECTION("acute V head on and off axis: stop") {
    float const t = std::tan(0.35f); // walls 20 degrees either side of the -x axis
    std::vector<Vec3> const v_walls = {unit(-t, -1, 0), unit(-t, 1, 0)};
    CHECK(near(project({1, 0, 0}, v_walls).velocity, Vec3::ZERO));
    CHECK(near(project({1, 0.3f, 0}, v_walls).velocity, Vec3::ZERO));
  }
  SECTION("obtuse V off axis: slide along one wall, head on: stop") {
    float const t = std::tan(1.309f); // walls 75 degrees either side of the -x axis
    Vec3 const n1 = unit(-t, -1, 0), n2 = unit(-t, 1, 0);
    Vec3 const v{1, 0.5f, 0};
    Vec3 const along = v - n1 * n1.dot(v); // sliding along wall 1
    auto const r = project(v, {n1, n2});
    CHECK(near(r.velocity, along, 1e-6f));
    CHECK(n2.dot(r.velocity) >= 0);
    CHECK(near(project({1, 0, 0}, {n1, n2}).velocity, Vec3::ZERO));
  }
  SECTION("floor-to-ramp crease: climb the ramp") {
    float const th = 0.5f;
    Vec3 const ramp{-std::sin(th), 0, std::cos(th)};
    auto const r = project({1, 0, 0}, {floor, ramp});
    CHECK(near(r.velocity, {std::cos(th) * std::cos(th), 0, std::sin(th) * std::cos(th)}));
    // Walking down into the crease: the ramp alone is the answer (its slide keeps clear of
    // the floor), not the crease of the two, which would be farther from v.
    Vec3 const v2{1, 0.5f, -1};
    auto const r2 = project(v2, {floor, ramp});
    CHECK(near(r2.velocity, v2 - ramp * ramp.dot(v2)));
    CHECK(r2.velocity.x > 0);
    CHECK(r2.velocity.z > 0);
  }
  SECTION("exactly opposite planes: the projection onto their plane") {
    auto const r = project({1, 2, 3}, {wall_x, -wall_x});
    CHECK(near(r.velocity, {0, 2, 3}));
    auto const r2 = project({1, 2, 3}, {wall_x, -wall_x, floor, -floor});
    CHECK(near(r2.velocity, {0, 2, 0}));
  }
}

TEST_CASE("2D named cases", "[solver][projection][2d]") {
  Vec2 const floor{0, 1}, wall{-1, 0};
  CHECK(project_velocity(Vec2{1, -1}, std::vector<Vec2>{floor}).velocity.x == 1);
  CHECK(project_velocity(Vec2{1, -1}, std::vector<Vec2>{floor}).velocity.y == 0);
  auto const corner = project_velocity(Vec2{1, -1}, std::vector<Vec2>{floor, wall});
  CHECK(corner.velocity.x == 0);
  CHECK(corner.velocity.y == 0);
  CHECK(corner.converged);
  auto const opposite = project_velocity(Vec2{1, 2}, std::vector<Vec2>{wall, -wall});
  CHECK(opposite.velocity.x == 0);
  CHECK(opposite.velocity.y == 2);
  // A component beyond 2^40 is invalid input (the fuzz target found |v| = 1.7e38 coming back
  // infinite); at 2^40, with normals of the shortest length allowed, the answer is finite.
  std::vector<Vec2> const tiny{floor * 0x1p-20f, Vec2{-1, 0.05f} * 0x1p-20f};
  for (Vec2 const big : {Vec2{0x1p41f, -1}, Vec2{1, -1.7e38f}, Vec2{-3.4e38f, 0}}) {
    auto const r = project_velocity(big, tiny);
    CHECK(r.invalid_input);
    CHECK(!r.converged);
    CHECK(r.velocity.x == 0);
    CHECK(project_velocity_bruteforce(big, tiny).invalid_input);
  }
  for (Vec2 const edge : {Vec2{0x1p40f, -0x1p40f}, Vec2{-0x1p40f, -0x1p40f}}) {
    auto const r = project_velocity(edge, tiny);
    CHECK(!r.invalid_input);
    CHECK(r.converged);
    CHECK(std::isfinite(r.velocity.x));
    CHECK(std::isfinite(r.velocity.y));
  }
}

// ------------------------------------------------------------------------------------- bad input

TEMPLATE_LIST_TEST_CASE("bad input: empty sets, zero and non-unit normals, tiny velocities",
                        "[solver][projection]", real_types) {
  using T = TestType;
  using V = GVec3<T>;
  using S = scalar_t<T>;
  V const v{splat<T>(1), splat<T>(2), splat<T>(-3)};
  auto const same_vec = [](V const& a, V const& b) { return same_lanes(a, b); };
  SECTION("empty plane set: v, no step") {
    auto const r = project_velocity(v, std::span<V const>{});
    CHECK(same_vec(r.velocity, v));
    CHECK(plume::all(r.converged));
    CHECK(plume::all(r.steps == zero<T>()));
  }
  SECTION("zero normals are ignored") {
    std::vector<V> const z(3);
    auto const r = project_velocity(v, z);
    CHECK(same_vec(r.velocity, v));
    std::vector<V> const with_floor = {V{}, V{zero<T>(), zero<T>(), one<T>()}, V{}};
    std::vector<V> const floor_only = {V{zero<T>(), zero<T>(), one<T>()}};
    CHECK(same_vec(project_velocity(v, with_floor).velocity,
                   project_velocity(v, floor_only).velocity));
    CHECK(same_vec(project_velocity_bruteforce(v, with_floor).velocity,
                   project_velocity_bruteforce(v, floor_only).velocity));
  }
  SECTION("a non-unit normal acts as its plane") {
    std::vector<V> const big = {V{zero<T>(), zero<T>(), splat<T>(4)}};
    auto const r = project_velocity(v, big);
    CHECK(plume::all(r.velocity.z == zero<T>()));
    CHECK(plume::all(r.velocity.x == splat<T>(1)));
  }
  SECTION("velocity below epsilon comes back unchanged") {
    V const tiny{splat<T>(S(0.001)), zero<T>(), splat<T>(S(-0.004))};
    std::vector<V> const floor = {V{zero<T>(), zero<T>(), one<T>()}};
    CHECK(same_vec(project_velocity(tiny, floor).velocity, tiny));
    CHECK(same_vec(project_velocity_bruteforce(tiny, floor).velocity, tiny));
  }
  SECTION("non-finite v or normal: zero velocity, invalid_input, lambda 0") {
    std::vector<V> const floor = {V{zero<T>(), zero<T>(), one<T>()}};
    for (S bad : {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity()}) {
      V const bv{splat<T>(bad), zero<T>(), zero<T>()};
      std::array<T, 1> lambda;
      auto const r = project_velocity<T>(bv, floor, lambda);
      CHECK(same_vec(r.velocity, V{}));
      CHECK(plume::all(r.invalid_input));
      CHECK(plume::none(r.converged));
      CHECK(plume::all(lambda[0] == zero<T>()));
      std::vector<V> const bad_normals = {floor[0], V{zero<T>(), splat<T>(bad), zero<T>()}};
      auto const r2 = project_velocity(v, bad_normals);
      CHECK(same_vec(r2.velocity, V{}));
      CHECK(plume::all(r2.invalid_input));
      CHECK(same_vec(project_velocity_bruteforce(v, bad_normals).velocity, V{}));
    }
  }
  SECTION("a nonzero normal shorter than 2^-20 or longer than 2^20: invalid_input") {
    V const floor{zero<T>(), zero<T>(), one<T>()};
    for (S len : {S(0x1p21), S(1e30), S(1.7e38), S(0x1p-21), S(1e-30)}) {
      std::vector<V> const normals = {floor, V{zero<T>(), splat<T>(len), zero<T>()}};
      auto const r = project_velocity(v, normals);
      CHECK(same_vec(r.velocity, V{}));
      CHECK(plume::all(r.invalid_input));
      CHECK(plume::none(r.converged));
      CHECK(plume::all(project_velocity_bruteforce(v, normals).invalid_input));
    }
    for (S len : {S(0x1p20), S(0x1p-20)}) { // the ends of the range act as their planes
      std::vector<V> const normals = {V{zero<T>(), zero<T>(), splat<T>(len)}};
      auto const r = project_velocity(v, normals);
      CHECK(plume::none(r.invalid_input));
      CHECK(plume::all(r.converged));
      CHECK(plume::all(r.velocity.z >= -splat<T>(S(0.005)) / splat<T>(len)));
    }
  }
  SECTION("a component of v beyond 2^40: invalid_input; up to 2^40, a finite answer") {
    // Found by the velocity_projection fuzz target: |v| near float's largest against a
    // crease or a corner came back infinite and marked converged (n . v times the crease and
    // corner solves overflowed).
    S const tilt = S(0x1p-20) * S(0.05);
    std::vector<V> const corner = {V{zero<T>(), zero<T>(), splat<T>(S(0x1p-20))},
                                   V{splat<T>(-S(0x1p-20)), zero<T>(), splat<T>(tilt)},
                                   V{splat<T>(tilt), splat<T>(-S(0x1p-20)), zero<T>()}};
    for (S big : {S(0x1p41), S(-1e20), S(1.7e38), S(-3.4e38)}) {
      INFO("component " << big);
      for (int axis = 0; axis < 3; ++axis) {
        V bv = v;
        (axis == 0 ? bv.x : axis == 1 ? bv.y : bv.z) = splat<T>(big);
        std::array<T, 3> lambda;
        auto const r = project_velocity<T>(bv, corner, lambda);
        CHECK(same_vec(r.velocity, V{}));
        CHECK(plume::all(r.invalid_input));
        CHECK(plume::none(r.converged));
        CHECK(plume::all(lambda[0] == zero<T>()));
        CHECK(plume::all(project_velocity_bruteforce(bv, corner).invalid_input));
      }
    }
    // At the bound, into the corner and along its creases, with the shortest normals allowed
    // (the largest multipliers, |v| / |n| = 2^60, squared below float's largest) and with
    // the longest (the largest Gram determinants and n . v).
    T const m = splat<T>(S(0x1p40));
    std::vector<V> long_corner;
    for (V const& n : corner)
      long_corner.push_back(n * splat<T>(S(0x1.fcp39))); // (just below 2^20 long)
    std::array<std::vector<V> const*, 2> const sets{&corner, &long_corner};
    for (auto const* planes : sets)
      for (V const& edge : {V{m, m, -m}, V{m, -m, -m}, V{-m, m, -m}, V{-m, -m, m}}) {
        std::array<T, 3> lambda;
        auto const r = project_velocity<T>(edge, *planes, lambda);
        CHECK(plume::none(r.invalid_input));
        CHECK(plume::all(r.converged));
        CHECK(plume::all(r.velocity.is_finite()));
        for (V const& n : *planes) // (the violation tolerance scales with |n|)
          CHECK(plume::all(n.dot(r.velocity) >= splat<T>(S(-0.005)) * n.length()));
        for (T const& l : lambda)
          CHECK(plume::all(plume::is_finite(l) & (l >= zero<T>())));
        auto const b = project_velocity_bruteforce(edge, *planes);
        CHECK(plume::none(b.invalid_input));
        CHECK(plume::all(b.velocity.is_finite()));
      }
  }
  SECTION("out of steps: zero velocity, not converged") {
    GVelocityProjectionConfig<S> cfg;
    cfg.max_steps = 1;
    std::vector<V> const crease = {V{zero<T>(), zero<T>(), one<T>()},
                                   V{-one<T>(), zero<T>(), zero<T>()}};
    auto const r = project_velocity(v, crease, cfg); // the crease needs two steps
    CHECK(plume::none(r.converged));
    CHECK(same_vec(r.velocity, V{}));
    cfg.max_steps = 2;
    CHECK(plume::all(project_velocity(v, crease, cfg).converged));
  }
}

// --------------------------------------------------------------------------------- lane exactness

namespace {

/// Per-lane plane sets of different sizes (0..max_k), mixing the Avian normals, random unit
/// normals, duplicated and opposite planes; velocities of different sizes.
template <class T>
struct wide_case {
  GVec3<T> v;
  std::vector<GVec3<T>> normals;
};

template <class T>
wide_case<T> make_wide_case(rng& r, std::size_t max_k) {
  using S = scalar_t<T>;
  auto const avian = avian_normals_3d();
  std::vector<std::vector<GVec3<S>>> per_lane(lanes_v<T>);
  GVec3<T> v;
  for (std::size_t l = 0; l < lanes_v<T>; ++l) {
    std::size_t const k = std::size_t(r.uniform(0, double(max_k) + 0.999));
    int const kind = int(r.uniform(0, 3));
    for (std::size_t i = 0; i < k; ++i) {
      DVec3 n = kind == 0 ? avian[i % avian.size()] : r.unit3<double>();
      if (kind == 2 && i % 4 == 3) n = -to<double>(per_lane[l].back()); // opposite plane
      if (kind == 1 && i % 5 == 4)          // an exact duplicate three slots back: ties across the
        n = to<double>(per_lane[l][i - 3]); // wide search's interleaved minima
      per_lane[l].push_back(to<S>(n));
    }
    v = with_lane(v, l, to<S>(r.unit3<double>() * r.uniform(0.001, 20)));
  }
  return {v, pack_planes3<T>(per_lane)};
}

} // namespace

PLUME_WIDE_TEST_CASE("wide projection equals scalar per lane, different plane counts",
                     "[solver][projection][lanes]", wide_real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  rng r(4242);
  int failures = 0;
  for (int t = 0; t < 300; ++t) {
    auto const c = make_wide_case<T>(r, std::size_t(1 + t % 24));
    std::vector<T> lambda(c.normals.size());
    auto const wide = project_velocity<T>(c.v, c.normals, lambda);
    auto const wide_bf = project_velocity_bruteforce<T>(c.v, c.normals);
    for (std::size_t l = 0; l < lanes_v<T>; ++l) {
      auto const n = lane_planes(c.normals, l);
      std::vector<S> ls(n.size());
      auto const one = project_velocity<S>(lane(c.v, l), n, ls);
      auto const one_bf = project_velocity_bruteforce<S>(lane(c.v, l), n);
      bool ok = same(lane(wide.velocity, l), one.velocity) &&
                same(lane(wide.steps, l), one.steps) && lane(wide.converged, l) == one.converged &&
                lane(wide.invalid_input, l) == one.invalid_input &&
                same(lane(wide_bf.velocity, l), one_bf.velocity);
      for (std::size_t i = 0; i < n.size(); ++i)
        ok = ok && same(lane(lambda[i], l), ls[i]);
      if (!ok && failures++ < 3)
        FAIL_CHECK("case " << t << " lane " << l << ": wide " << lane(wide.velocity, l)
                           << " scalar " << one.velocity);
    }
  }
  CHECK(failures == 0);
}

PLUME_WIDE_TEST_CASE("wide 2D projection equals scalar per lane", "[solver][projection][lanes][2d]",
                     wide_real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  rng r(99);
  int failures = 0;
  for (int t = 0; t < 300; ++t) {
    std::vector<std::vector<GVec2<S>>> per_lane(lanes_v<T>);
    GVec2<T> v;
    for (std::size_t l = 0; l < lanes_v<T>; ++l) {
      std::size_t const k = std::size_t(r.uniform(0, 6.999));
      for (std::size_t i = 0; i < k; ++i)
        per_lane[l].push_back(GVec2<S>::from_angle(S(r.uniform(-3.2, 3.2))));
      if (k > 2 && l % 3 == 0) per_lane[l][1] = -per_lane[l][0];
      v = with_lane(v, l, GVec2<S>::from_angle(S(r.uniform(-3.2, 3.2))) * S(r.uniform(0.001, 20)));
    }
    auto const normals = pack_planes2<T>(per_lane);
    std::vector<T> lambda(normals.size());
    auto const wide = project_velocity<T>(v, normals, lambda);
    auto const wide_bf = project_velocity_bruteforce<T>(v, normals);
    for (std::size_t l = 0; l < lanes_v<T>; ++l) {
      auto const n = lane_planes(normals, l);
      std::vector<S> ls(n.size());
      auto const one = project_velocity<S>(lane(v, l), n, ls);
      bool ok =
          same(lane(wide.velocity, l), one.velocity) && same(lane(wide.steps, l), one.steps) &&
          same(lane(wide_bf.velocity, l), project_velocity_bruteforce<S>(lane(v, l), n).velocity);
      for (std::size_t i = 0; i < n.size(); ++i)
        ok = ok && same(lane(lambda[i], l), ls[i]);
      if (!ok && failures++ < 3)
        FAIL_CHECK("case " << t << " lane " << l << ": wide " << lane(wide.velocity, l)
                           << " scalar " << one.velocity);
    }
  }
  CHECK(failures == 0);
}

PLUME_WIDE_TEST_CASE("a NaN in one lane leaves the other lanes untouched",
                     "[solver][projection][lanes]", wide_real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  rng r(5);
  auto c = make_wide_case<T>(r, 6);
  c.normals.resize(std::max<std::size_t>(c.normals.size(), 1));
  auto const clean = project_velocity<T>(c.v, c.normals);
  auto bad = c.normals;
  bad[0] = with_lane(bad[0], 1, GVec3<S>{std::numeric_limits<S>::quiet_NaN(), 0, 0});
  auto const dirty = project_velocity<T>(c.v, bad);
  for (std::size_t l = 0; l < lanes_v<T>; ++l) {
    if (l == 1) {
      CHECK(lane(dirty.invalid_input, l));
      CHECK(same(lane(dirty.velocity, l), GVec3<S>{}));
    } else {
      CHECK(same(lane(dirty.velocity, l), lane(clean.velocity, l)));
    }
  }
}
