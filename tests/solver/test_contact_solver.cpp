// The contact solver's pieces: softness coefficients (softness.hpp's worked example), the graph
// colouring's invariants, and the constraint kernels - lane-exact against T = float, and
// against closed forms for one contact.
#include "../common/harness.hpp"
#include "../common/types.hpp"

#include <plume/solver/body_state.hpp>
#include <plume/solver/constraint_graph.hpp>
#include <plume/solver/contact_constraint.hpp>
#include <plume/solver/lane_storage.hpp>
#include <plume/solver/softness.hpp>

#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <tuple>
#include <vector>

using namespace plume;
using plume::test::same_bits;

namespace {

Mat3 random_inv_inertia(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.2f, 2.0f), a(-3.0f, 3.0f);
  Quat const q = Quat::from_axis_angle(Vec3{a(rng), a(rng), a(rng)}.normalize(), a(rng));
  return Mat3::from_diagonal({u(rng), u(rng), u(rng)}).rotate_inertia(Mat3::from_quat(q));
}

Vec3 random_vec(std::mt19937& rng, float r) {
  std::uniform_real_distribution<float> u(-r, r);
  return {u(rng), u(rng), u(rng)};
}

/// A random manifold with `count` points around `at`, normal roughly +y.
Manifold random_manifold(std::mt19937& rng, Vec3 at, int count) {
  Manifold m;
  m.normal = (Vec3::Y + random_vec(rng, 0.2f)).normalize();
  m.count = count;
  std::uniform_real_distribution<float> sep(-0.03f, 0.03f);
  for (int k = 0; k < count; ++k) {
    float const s = sep(rng);
    Vec3 const pa = at + random_vec(rng, 0.5f);
    m.points[std::size_t(k)] = {pa, pa + m.normal * s, s, std::uint64_t(k)};
  }
  return m;
}

/// Bitwise equal vectors.
bool same_vec(Vec3 const& a, Vec3 const& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

} // namespace

TEST_CASE("softness: the header's worked example and the rigid and off limits", "[solver]") {
  Softness const s = Softness::make(30.0f, 10.0f, 1.0f / 240.0f);
  CHECK(s.bias_rate == Approx(9.07).epsilon(1e-3));
  CHECK(s.mass_scale == Approx(0.942).epsilon(1e-3));
  CHECK(s.impulse_scale == Approx(0.058).epsilon(1e-2));
  CHECK(s.mass_scale + s.impulse_scale == Approx(1.0f).epsilon(1e-6)); // a2 a3 + a3 = 1
  Softness const off = Softness::make(0.0f, 10.0f, 1.0f / 240.0f);
  CHECK((off.bias_rate == 0.0f && off.mass_scale == 0.0f && off.impulse_scale == 0.0f));
  Softness const bad = Softness::make(30.0f, 10.0f, 0.0f);
  CHECK((bad.bias_rate == 0.0f && bad.mass_scale == 0.0f && bad.impulse_scale == 0.0f));
  Softness const stiff = Softness::make(1e6f, 0.0f, 1.0f / 240.0f);
  CHECK(stiff.bias_rate == Approx(240.0f).epsilon(1e-4)); // -> 1/h
  CHECK(stiff.mass_scale == Approx(1.0f).epsilon(1e-6));
}

TEST_CASE("constraint graph: no dynamic body twice in a colour; static contacts from the top",
          "[solver]") {
  ConstraintGraph g;
  // Dynamic-dynamic: lowest colour; dynamic-static: from the top, never colour 0.
  CHECK(g.add(0, 1, true, true) == 0);
  CHECK(g.add(1, 2, true, true) == 1);
  CHECK(g.add(0, 2, true, true) == 2);
  CHECK(g.add(0, 9, true, false) == ConstraintGraph::color_count - 1);
  CHECK(g.add(9, 0, false, true) == ConstraintGraph::color_count - 2);
  CHECK(g.add(9, 3, false, true) == ConstraintGraph::color_count - 1);
  CHECK(g.add(8, 9, false, false) == ConstraintGraph::overflow); // nothing to solve
  g.release(ConstraintGraph::overflow, 0, 1, true, true);        // no-op: overflow holds no bits
  CHECK((g.test(0, 0) && g.test(0, 1)));
  // Release frees exactly the constraint's bits.
  g.release(1, 1, 2, true, true);
  CHECK(g.add(2, 3, true, true) == 0);
  CHECK(g.add(1, 2, true, true) == 1);

  // A hub body with more dynamic neighbours than colours overflows; invariants hold on a
  // random graph.
  ConstraintGraph h;
  int overflow = 0;
  for (std::uint32_t i = 1; i <= 25; ++i)
    overflow += h.add(0, i, true, true) == ConstraintGraph::overflow;
  CHECK(overflow == 25 - ConstraintGraph::dynamic_colors);

  std::mt19937 rng(7);
  std::uniform_int_distribution<std::uint32_t> body(0, 199);
  ConstraintGraph r;
  std::vector<std::vector<std::uint32_t>> members(ConstraintGraph::color_count);
  for (int k = 0; k < 1500; ++k) {
    std::uint32_t const a = body(rng), b = body(rng);
    if (a == b) continue;
    bool const da = a % 7 != 0, db = b % 7 != 0; // every 7th body is static
    int const c = r.add(a, b, da, db);
    if (c == ConstraintGraph::overflow) continue;
    if (!(da && db)) CHECK(c > 0);
    if (da) members[std::size_t(c)].push_back(a);
    if (db) members[std::size_t(c)].push_back(b);
  }
  for (auto& m : members) {
    std::sort(m.begin(), m.end());
    CHECK(std::adjacent_find(m.begin(), m.end()) == m.end());
  }
}

TEMPLATE_LIST_TEST_CASE("body states: gather and scatter move exactly the named records",
                        "[solver][lane-exact]", plume::test::f32_types) {
  using T = TestType;
  constexpr std::size_t W = lanes_v<T>;
  std::vector<BodyState> states(2 * W + 1);
  for (std::size_t r = 0; r < states.size(); ++r) {
    float const b = float(r) * 100.0f;
    states[r].linear_velocity = {b + 1, b + 2, b + 3};
    states[r].angular_velocity = {b + 4, b + 5, b + 6};
    states[r].delta_position = {b + 7, b + 8, b + 9};
    states[r].delta_rotation = Quat::from_xyzw(b + 10, b + 11, b + 12, b + 13);
  }
  std::array<std::int32_t, W> index{}, write{};
  for (std::size_t i = 0; i < W; ++i) {
    index[i] = std::int32_t((2 * i + 1) % states.size()); // scattered, not in order
    write[i] = i % 3 == 1 ? -1 : index[i];                // some lanes static
  }
  GBodyState<T> const g = gather_states<T>(states.data(), index.data());
  for (std::size_t i = 0; i < W; ++i) {
    BodyState const& r = states[std::size_t(index[i])];
    CHECK(same_vec(lane(g.linear_velocity, i), r.linear_velocity));
    CHECK(same_vec(lane(g.angular_velocity, i), r.angular_velocity));
    CHECK(same_vec(lane(g.delta_position, i), r.delta_position));
    CHECK(lane(g.delta_rotation.w, i) == r.delta_rotation.w);
    CHECK(lane(g.delta_rotation.x, i) == r.delta_rotation.x);
  }
  GBodyState<T> neg = g;
  neg.linear_velocity = -g.linear_velocity;
  neg.angular_velocity = -g.angular_velocity;
  std::vector<BodyState> before = states;
  scatter_velocities<T>(states.data(), write.data(), neg);
  for (std::size_t r = 0; r < states.size(); ++r) {
    bool written = false;
    for (std::size_t i = 0; i < W; ++i)
      written = written || write[i] == std::int32_t(r);
    INFO("record " << r);
    Vec3 const want_v = written ? -before[r].linear_velocity : before[r].linear_velocity;
    Vec3 const want_w = written ? -before[r].angular_velocity : before[r].angular_velocity;
    CHECK(same_vec(states[r].linear_velocity, want_v));
    CHECK(same_vec(states[r].angular_velocity, want_w));
    CHECK(same_vec(states[r].delta_position, before[r].delta_position)); // never written
  }

  // GLaneArray / GLaneVec3: lane writes and whole reads agree.
  GLaneVec3<T> lv;
  for (std::size_t i = 0; i < W; ++i)
    lv.set_lane(i, {float(i), -float(i), 0.5f * float(i)});
  GVec3<T> const v = lv.get();
  for (std::size_t i = 0; i < W; ++i) {
    CHECK(same_vec(lane(v, i), lv.lane(i)));
    CHECK(lv.lane(i).y == -float(i));
  }
}

TEST_CASE("contact tangent: continuous from the previous one, a fallback when degenerate",
          "[solver]") {
  Vec3 const n = Vec3{0.1f, 1.0f, -0.05f}.normalize();
  Vec3 const t = contact_tangent(n, Vec3::X);
  CHECK(std::abs(t.dot(n)) < 1e-6f);
  CHECK(std::abs(t.length() - 1.0f) < 1e-6f);
  CHECK(t.dot(Vec3::X) > 0.99f); // the previous axis projected, not a new basis
  // Degenerate previous tangents: zero, NaN, along the normal -> any_orthonormal_pair()[0].
  Vec3 const fallback = n.any_orthonormal_pair()[0];
  for (Vec3 const prev : {Vec3{}, Vec3{NAN, 0.0f, 0.0f}, n * 3.0f}) {
    Vec3 const f = contact_tangent(n, prev);
    CHECK(same_vec(f, fallback));
  }
  // Near n.z = 0 any_orthonormal_pair flips its basis; the carried tangent does not.
  Vec3 const na = Vec3{1.0f, 0.0f, 1e-6f}.normalize(), nb = Vec3{1.0f, 0.0f, -1e-6f}.normalize();
  Vec3 const ta = contact_tangent(na, Vec3{});
  Vec3 const tb = contact_tangent(nb, ta);
  CHECK(ta.dot(tb) > 0.999f);
  CHECK(na.any_orthonormal_pair()[0].dot(nb.any_orthonormal_pair()[0]) < 0.0f);
}

TEMPLATE_LIST_TEST_CASE("contact kernels: every lane equals the float kernel bit for bit",
                        "[solver][lane-exact]", plume::test::f32_types) {
  using T = TestType;
  constexpr std::size_t W = lanes_v<T>;
  std::mt19937 rng(1234);
  // 2W dynamic bodies with random states, one static (identity) record at the end.
  std::size_t const n = 2 * W;
  std::vector<BodyState> states(n + 1);
  std::vector<SolverBody> bodies(n);
  for (std::size_t i = 0; i < n; ++i) {
    states[i].linear_velocity = random_vec(rng, 2.0f);
    states[i].angular_velocity = random_vec(rng, 3.0f);
    states[i].delta_position = random_vec(rng, 0.01f);
    states[i].delta_rotation = Quat::from_scaled_axis(random_vec(rng, 0.02f));
    bodies[i].state = bodies[i].write = std::int32_t(i);
    bodies[i].inv_mass = std::uniform_real_distribution<float>(0.1f, 2.0f)(rng);
    bodies[i].inv_inertia = random_inv_inertia(rng);
    bodies[i].center = random_vec(rng, 5.0f);
    bodies[i].linear_velocity = states[i].linear_velocity;
    bodies[i].angular_velocity = states[i].angular_velocity;
  }
  SolverBody ground;
  ground.state = std::int32_t(n);
  Softness const soft = Softness::make(30.0f, 10.0f, 1.0f / 240.0f);
  Softness const hard = Softness::make(60.0f, 10.0f, 1.0f / 240.0f);

  // Lane i joins bodies 2i and 2i+1 (or 2i and the ground on odd lanes); point counts 0..4.
  GContactConstraint<T> wide;
  std::vector<GContactConstraint<float>> narrow(W);
  for (std::size_t i = 0; i < W; ++i) {
    SolverBody const& a = bodies[2 * i];
    SolverBody const& b = i % 2 == 0 ? bodies[2 * i + 1] : ground;
    Manifold const m = random_manifold(rng, a.center, int(i % 5));
    ContactImpulses warm;
    for (float& x : warm.normal)
      x = std::uniform_real_distribution<float>(0.0f, 3.0f)(rng);
    warm.tangent1 = 0.5f;
    warm.tangent2 = -0.25f;
    warm.twist = 0.1f;
    float const mu = 0.2f + 0.1f * float(i % 4), e = i % 3 == 0 ? 0.5f : 0.0f;
    Vec3 const t = contact_tangent(m.normal, Vec3::X);
    Softness const& sf = i % 2 == 0 ? soft : hard;
    prepare_contact_lane(wide, i, a, b, m, t, warm, mu, e, sf);
    prepare_contact_lane(narrow[i], 0, a, b, m, t, warm, mu, e, sf);
  }
  std::vector<BodyState> s_wide = states, s_narrow = states;
  for (int pass = 0; pass < 3; ++pass) {
    warm_start_contacts(wide, s_wide.data());
    solve_contacts(wide, s_wide.data(), 240.0f, 3.0f, true);
    solve_contacts(wide, s_wide.data(), 240.0f, 3.0f, false);
    for (auto& c : narrow) {
      warm_start_contacts(c, s_narrow.data());
      solve_contacts(c, s_narrow.data(), 240.0f, 3.0f, true);
      solve_contacts(c, s_narrow.data(), 240.0f, 3.0f, false);
    }
  }
  apply_restitution(wide, s_wide.data(), 1.0f);
  for (auto& c : narrow)
    apply_restitution(c, s_narrow.data(), 1.0f);

  for (std::size_t i = 0; i <= n; ++i) {
    INFO("body " << i);
    CHECK(same_vec(s_wide[i].linear_velocity, s_narrow[i].linear_velocity));
    CHECK(same_vec(s_wide[i].angular_velocity, s_narrow[i].angular_velocity));
  }
  // The static record is never written.
  CHECK(same_vec(s_wide[n].linear_velocity, Vec3{}));
  CHECK(same_vec(s_wide[n].angular_velocity, Vec3{}));
  for (std::size_t i = 0; i < W; ++i) {
    ContactImpulses const a = contact_impulses(wide, i), b = contact_impulses(narrow[i], 0);
    for (std::size_t k = 0; k < 4; ++k)
      CHECK(same_bits(a.normal[k], b.normal[k]));
    CHECK(same_bits(a.tangent1, b.tangent1));
    CHECK(same_bits(a.tangent2, b.tangent2));
    CHECK(same_bits(a.twist, b.twist));
  }
}

PLUME_WIDE_TEST_CASE("contact kernels: a lane with fewer points than its block keeps its "
                     "bits (signed zeros included) as the float kernel does",
                     "[solver][lane-exact]", plume::test::f32_wide_types) {
  // Blocks whose lanes hold 1..4 points run the most points any lane has, and mask a point
  // out of the lanes that lack it. The float kernel, one manifold at a time, stops at the
  // manifold's own count: every lane must match it bit for bit, with velocities that start
  // at -0, +0 or a value and normals along +-y (zeros in x and z). A mask on the wrong lanes
  // or points fails here; 20,000 trials of this kind found no case where dropping the mask
  // changes a bit (the real points' and friction rows' zero impulses flip a -0 first), so
  // the mask is a guarantee this test cannot show missing.
  using T = TestType;
  constexpr std::size_t W = lanes_v<T>;
  std::mt19937 rng(77);
  std::uniform_int_distribution<int> pick(0, 2);
  auto const signed_zero_vec = [&](float r) {
    Vec3 v = random_vec(rng, r);
    for (float* x : {&v.x, &v.y, &v.z})
      if (int const k = pick(rng); k < 2) *x = k == 0 ? -0.0f : 0.0f;
    return v;
  };
  for (int trial = 0; trial < 40; ++trial) {
    std::size_t const n = 2 * W;
    std::vector<BodyState> states(n + 1);
    std::vector<SolverBody> bodies(n);
    for (std::size_t i = 0; i < n; ++i) {
      states[i].linear_velocity = signed_zero_vec(2.0f);
      states[i].angular_velocity = signed_zero_vec(1.0f);
      bodies[i].state = bodies[i].write = std::int32_t(i);
      bodies[i].inv_mass = 1.0f;
      bodies[i].inv_inertia = trial % 2 == 0 ? Mat3::ZERO : random_inv_inertia(rng);
      bodies[i].center = random_vec(rng, 1.0f);
      bodies[i].linear_velocity = states[i].linear_velocity;
      bodies[i].angular_velocity = states[i].angular_velocity;
    }
    SolverBody ground;
    ground.state = std::int32_t(n);
    Softness const soft = Softness::make(30.0f, 10.0f, 1.0f / 240.0f);
    GContactConstraint<T> wide;
    std::vector<GContactConstraint<float>> narrow(W);
    for (std::size_t i = 0; i < W; ++i) {
      SolverBody const& a = (i + std::size_t(trial)) % 3 == 0 ? ground : bodies[2 * i];
      SolverBody const& b = bodies[2 * i + 1];
      int const count = int((i + std::size_t(trial)) % 4) + 1; // 1..4: every block mixed
      Manifold m = random_manifold(rng, b.center, count);
      m.normal = (i + std::size_t(trial)) % 2 == 0 ? Vec3::Y : -Vec3::Y;
      for (int k = 0; k < count; ++k) {
        ContactPoint& p = m.points[std::size_t(k)];
        p.point_b = p.point_a + m.normal * p.separation;
      }
      ContactImpulses warm;
      for (float& x : warm.normal)
        x = std::uniform_real_distribution<float>(0.0f, 3.0f)(rng);
      float const e = i % 2 == 0 ? 0.5f : 0.0f;
      prepare_contact_lane(wide, i, a, b, m, Vec3::X, warm, 0.0f, e, soft);
      prepare_contact_lane(narrow[i], 0, a, b, m, Vec3::X, warm, 0.0f, e, soft);
    }
    REQUIRE(wide.min_points == 1);
    REQUIRE(wide.max_points == 4);
    std::vector<BodyState> s_wide = states, s_narrow = states;
    // With and without a warm start first (the kernels called on their own).
    bool const warm_first = trial % 2 == 0;
    for (int pass = 0; pass < 2; ++pass) {
      if (warm_first) warm_start_contacts(wide, s_wide.data());
      solve_contacts(wide, s_wide.data(), 240.0f, 3.0f, pass == 0);
      solve_contacts(wide, s_wide.data(), 240.0f, 3.0f, false);
      for (auto& c : narrow) {
        if (warm_first) warm_start_contacts(c, s_narrow.data());
        solve_contacts(c, s_narrow.data(), 240.0f, 3.0f, pass == 0);
        solve_contacts(c, s_narrow.data(), 240.0f, 3.0f, false);
      }
    }
    apply_restitution(wide, s_wide.data(), 0.01f);
    for (auto& c : narrow)
      apply_restitution(c, s_narrow.data(), 0.01f);
    for (std::size_t i = 0; i < n; ++i) {
      INFO("trial " << trial << ", body " << i);
      CHECK(same_vec(s_wide[i].linear_velocity, s_narrow[i].linear_velocity));
      CHECK(same_vec(s_wide[i].angular_velocity, s_narrow[i].angular_velocity));
    }
    for (std::size_t i = 0; i < W; ++i) {
      ContactImpulses const x = contact_impulses(wide, i), y = contact_impulses(narrow[i], 0);
      for (std::size_t k = 0; k < 4; ++k)
        CHECK(same_bits(x.normal[k], y.normal[k]));
    }
  }
}

TEST_CASE("contact kernels: point counts run only the points prepared", "[solver]") {
  // A default constraint runs nothing; prepare records each lane's count, padding lanes
  // (clear_contact_lane) none.
  GContactConstraint<f32xN> c;
  CHECK(c.max_points == 0);
  std::mt19937 rng(3);
  SolverBody a, b;
  b.state = b.write = 0;
  b.inv_mass = 1.0f;
  prepare_contact_lane(c, 0, a, b, random_manifold(rng, Vec3{}, 2), Vec3::X, {}, 0.5f, 0.0f,
                       Softness{});
  CHECK(c.max_points == 2);
  CHECK(c.min_points == 2);
  CHECK(c.point_count[0] == 2.0f);
  if constexpr (lanes_v < f32xN >> 1) {
    clear_contact_lane(c, 1, 1);
    CHECK(c.max_points == 2);
    CHECK(c.min_points == 2);
    CHECK(c.point_count[1] == 0.0f);
    prepare_contact_lane(c, 2, a, b, random_manifold(rng, Vec3{}, 3), Vec3::X, {}, 0.5f, 0.0f,
                         Softness{});
    CHECK(c.max_points == 3);
    CHECK(c.min_points == 2);
  }
}

TEST_CASE("contact kernels: one point against closed forms", "[solver]") {
  // A unit-mass point body (no rotation: zero inverse inertia) 0.1 m above static ground,
  // falling at 10 m/s; substep h = 1/100 s.
  float const h = 0.01f;
  std::vector<BodyState> states(2);
  states[0].linear_velocity = {0.0f, -10.0f, 0.0f};
  SolverBody ground, body;
  ground.state = 1;
  body.state = body.write = 0;
  body.inv_mass = 1.0f;
  body.center = {0.0f, 0.1f, 0.0f};
  body.linear_velocity = states[0].linear_velocity;
  Manifold m;
  m.normal = Vec3::Y; // from the ground (A) to the body (B)
  m.count = 1;
  m.points[0] = {Vec3{}, {0.0f, 0.1f, 0.0f}, 0.1f, 0};
  GContactConstraint<float> c;
  prepare_contact_lane(c, 0, ground, body, m, Vec3::X, ContactImpulses{}, 0.5f, 0.0f,
                       Softness::make(30.0f, 10.0f, h));
  CHECK(c.points[0].normal_mass[0] == 1.0f);
  CHECK(c.points[0].relative_velocity[0] == -10.0f);

  // Speculative: it may close the 0.1 m gap this substep, no more: v = -s/h = -10 m/s.
  solve_contacts(c, states.data(), 1.0f / h, 3.0f, true);
  CHECK(states[0].linear_velocity.y == Approx(-10.0f));
  CHECK(c.points[0].normal_impulse[0] == 0.0f);
  states[0].linear_velocity.y = -20.0f;
  solve_contacts(c, states.data(), 1.0f / h, 3.0f, true);
  CHECK(states[0].linear_velocity.y == Approx(-10.0f));
  CHECK(c.points[0].normal_impulse[0] == Approx(10.0f));

  // In contact (0.01 m deep): the relax pass stops it exactly; the solve pass pushes it out
  // no faster than max_push_speed.
  m.points[0] = {Vec3{}, {0.0f, -0.01f, 0.0f}, -0.01f, 0};
  prepare_contact_lane(c, 0, ground, body, m, Vec3::X, ContactImpulses{}, 0.5f, 0.0f,
                       Softness::make(30.0f, 10.0f, h));
  states[0].linear_velocity = {0.0f, -1.0f, 0.0f};
  solve_contacts(c, states.data(), 1.0f / h, 3.0f, false);
  CHECK(states[0].linear_velocity.y == 0.0f);
  m.points[0] = {Vec3{}, {0.0f, -5.0f, 0.0f}, -5.0f, 0};
  prepare_contact_lane(c, 0, ground, body, m, Vec3::X, ContactImpulses{}, 0.5f, 0.0f,
                       Softness::make(1e6f, 0.0f, h));
  solve_contacts(c, states.data(), 1.0f / h, 3.0f, true);
  CHECK(states[0].linear_velocity.y == Approx(3.0f).epsilon(1e-5));

  // Friction: sliding at 2 m/s with normal impulse 1 N s and mu 0.5 loses 0.5 m/s per pass.
  m.points[0] = {Vec3{}, Vec3{}, 0.0f, 0};
  ContactImpulses warm;
  warm.normal[0] = 1.0f;
  prepare_contact_lane(c, 0, ground, body, m, Vec3::X, warm, 0.5f, 0.0f,
                       Softness::make(30.0f, 10.0f, h));
  states[0].linear_velocity = {2.0f, 0.0f, 0.0f};
  solve_contacts(c, states.data(), 1.0f / h, 3.0f, false);
  CHECK(states[0].linear_velocity.x == Approx(1.5f));
  CHECK(c.tangent_impulse1[0] == Approx(-0.5f));

  // Restitution: approached at 10 m/s with e = 0.5 -> leaves at 5 m/s.
  m.points[0] = {Vec3{}, Vec3{}, 0.0f, 0};
  states[0].linear_velocity = {0.0f, -10.0f, 0.0f};
  body.linear_velocity = states[0].linear_velocity;
  prepare_contact_lane(c, 0, ground, body, m, Vec3::X, ContactImpulses{}, 0.0f, 0.5f,
                       Softness::make(30.0f, 10.0f, h));
  solve_contacts(c, states.data(), 1.0f / h, 3.0f, false); // stops it, carries an impulse
  CHECK(states[0].linear_velocity.y == 0.0f);
  apply_restitution(c, states.data(), 1.0f);
  CHECK(states[0].linear_velocity.y == Approx(5.0f));

  // An empty manifold applies nothing, bit for bit.
  Manifold empty;
  empty.normal = Vec3::Y;
  prepare_contact_lane(c, 0, ground, body, empty, Vec3::X, warm, 0.5f, 0.5f,
                       Softness::make(30.0f, 10.0f, h));
  states[0].linear_velocity = {1.0f, -2.0f, 3.0f};
  states[0].angular_velocity = {0.5f, 0.25f, -1.0f};
  BodyState const before = states[0];
  warm_start_contacts(c, states.data());
  solve_contacts(c, states.data(), 1.0f / h, 3.0f, true);
  solve_contacts(c, states.data(), 1.0f / h, 3.0f, false);
  apply_restitution(c, states.data(), 1.0f);
  CHECK(same_vec(states[0].linear_velocity, before.linear_velocity));
  CHECK(same_vec(states[0].angular_velocity, before.angular_velocity));
}
