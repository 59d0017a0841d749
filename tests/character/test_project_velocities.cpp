// project_velocities (solver/character/project_velocities.hpp): the batch against the single
// call problem by problem, bit for bit, with and without multipliers, in 3D and 2D; the
// configuration passed through; refused arguments write nothing.
#include "batch_problems.hpp"

#include <plume/character.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

using namespace plume;
using plume::test::first_lambda_mismatch;
using plume::test::first_projection_mismatch;
using plume::test::make_projection_batch;

namespace {

template <class Vec>
void check_batch(std::size_t n, std::uint32_t seed, VelocityProjectionConfig const& cfg = {}) {
  auto const b = make_projection_batch<Vec>(n, seed, cfg);
  std::vector<GVelocityProjection<Vec>> out(n);
  std::vector<float> lambda(b.normals.size(), -7.0f);
  REQUIRE(project_velocities(std::span<Vec const>(b.velocities), std::span<Vec const>(b.normals),
                             b.offsets, out, lambda, cfg) == ProjectVelocitiesError::none);
  CHECK(first_projection_mismatch(b, out) == -1);
  CHECK(first_lambda_mismatch(b.expected_lambda, lambda) == -1);
  // Without multipliers: the same answers.
  std::vector<GVelocityProjection<Vec>> out2(n);
  REQUIRE(project_velocities(std::span<Vec const>(b.velocities), std::span<Vec const>(b.normals),
                             b.offsets, out2, {}, cfg) == ProjectVelocitiesError::none);
  CHECK(first_projection_mismatch(b, out2) == -1);
}

} // namespace

TEST_CASE("project_velocities: each problem gets the single call's bits", "[projection]") {
  for (std::size_t n : {1u, 3u, 4u, 5u, 8u, 9u, 16u, 17u, 33u, 1000u}) {
    CAPTURE(n);
    check_batch<Vec3>(n, 11u + static_cast<std::uint32_t>(n));
    check_batch<Vec2>(n, 12u + static_cast<std::uint32_t>(n));
  }
  // The batch is not trivial: planes that bind, several steps, bad problems among good ones.
  auto const b = make_projection_batch<Vec3>(1000, 1011);
  auto const count = [&](auto pred) {
    return std::count_if(b.expected.begin(), b.expected.end(), pred);
  };
  CHECK(count([](auto const& r) { return r.steps >= 3.0f; }) > 20);
  CHECK(count([](auto const& r) { return r.invalid_input; }) > 5);
  CHECK(count([](auto const& r) { return !r.invalid_input && r.converged; }) > 800);
  CHECK(std::count_if(b.expected_lambda.begin(), b.expected_lambda.end(),
                      [](float l) { return l > 0.0f; }) > 300);
}

TEST_CASE("project_velocities: the configuration reaches every problem", "[projection]") {
  VelocityProjectionConfig cfg;
  cfg.max_steps = 1; // many problems stop unconverged
  cfg.epsilon = 0.05f;
  check_batch<Vec3>(200, 5, cfg);
  check_batch<Vec2>(200, 6, cfg);
  auto const b = make_projection_batch<Vec3>(200, 5, cfg);
  CHECK(std::count_if(b.expected.begin(), b.expected.end(),
                      [](auto const& r) { return !r.invalid_input && !r.converged; }) > 5);
}

TEST_CASE("project_velocities: bad arguments are refused and nothing is written", "[projection]") {
  auto const b = make_projection_batch<Vec3>(10, 3);
  std::span<Vec3 const> const v(b.velocities), nrm(b.normals);
  VelocityProjection3 sentinel;
  sentinel.velocity = {9.0f, 9.0f, 9.0f};
  sentinel.steps = 99.0f;
  std::vector<VelocityProjection3> out(10, sentinel);
  std::vector<float> lambda(b.normals.size(), -7.0f);
  auto const untouched = [&] {
    return std::all_of(out.begin(), out.end(), [](auto const& r) { return r.steps == 99.0f; }) &&
           std::all_of(lambda.begin(), lambda.end(), [](float l) { return l == -7.0f; });
  };
  using E = ProjectVelocitiesError;
  std::vector<VelocityProjection3> short_out(9, sentinel);
  CHECK(project_velocities(v, nrm, b.offsets, short_out, lambda) == E::length_mismatch);
  CHECK(project_velocities(v, nrm, std::span(b.offsets).first(10), out, lambda) ==
        E::length_mismatch);
  std::vector<float> short_lambda(b.normals.size() - 1, -7.0f);
  CHECK(project_velocities(v, nrm, b.offsets, out, short_lambda) == E::length_mismatch);
  auto offsets = b.offsets;
  offsets[0] = 1;
  CHECK(project_velocities(v, nrm, offsets, out, lambda) == E::bad_offsets);
  offsets = b.offsets;
  offsets.back() += 1; // one normal past the end
  CHECK(project_velocities(v, nrm, offsets, out, lambda) == E::bad_offsets);
  offsets = b.offsets;
  std::size_t k = 1;
  while (offsets[k + 1] == offsets[k])
    ++k;                                 // a problem with planes
  std::swap(offsets[k], offsets[k + 1]); // decreasing
  CHECK(project_velocities(v, nrm, offsets, out, lambda) == E::bad_offsets);
  // A negative or NaN epsilon: the padding's zero normals would count as violated planes.
  VelocityProjectionConfig bad;
  bad.epsilon = -1e-3f;
  CHECK(project_velocities(v, nrm, b.offsets, out, lambda, bad) == E::bad_config);
  bad.epsilon = std::numeric_limits<float>::quiet_NaN();
  CHECK(project_velocities(v, nrm, b.offsets, out, lambda, bad) == E::bad_config);
  CHECK(untouched());
  bad.epsilon = 0.0f; // zero is fine
  std::vector<VelocityProjection3> out0(10);
  CHECK(project_velocities(v, nrm, b.offsets, out0, {}, bad) == E::none);
  // An output over an input (the multipliers over the normals), or over the other output.
  std::vector<Vec3> normals_copy(b.normals);
  std::span<float> const lambda_over_normals(reinterpret_cast<float*>(normals_copy.data()),
                                             normals_copy.size());
  CHECK(project_velocities(v, std::span<Vec3 const>(normals_copy), b.offsets, out,
                           lambda_over_normals) == E::overlap);
  CHECK(std::memcmp(normals_copy.data(), b.normals.data(), b.normals.size() * sizeof(Vec3)) == 0);
  CHECK(untouched());
  Vec3 const two_v[] = {{1, 0, 0}, {0, 1, 0}};
  Vec3 const three_n[] = {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
  std::uint32_t const two_offsets[] = {0, 2, 3};
  std::vector<float> storage(64, -7.0f);
  std::span<VelocityProjection3> const out_in_storage(
      reinterpret_cast<VelocityProjection3*>(storage.data()), 2);
  std::span<float> const lambda_in_out(storage.data() + 1, 3);
  CHECK(project_velocities(two_v, three_n, two_offsets, out_in_storage, lambda_in_out) ==
        E::overlap);
  CHECK(std::all_of(storage.begin(), storage.end(), [](float l) { return l == -7.0f; }));
  CHECK(std::all_of(short_out.begin(), short_out.end(),
                    [](auto const& r) { return r.steps == 99.0f; }));
  CHECK(std::all_of(short_lambda.begin(), short_lambda.end(), [](float l) { return l == -7.0f; }));
  // Every error has its own message.
  CHECK(to_string(E::none) == "none");
  for (E const a :
       {E::length_mismatch, E::bad_offsets, E::too_many_planes, E::overlap, E::bad_config})
    for (E const c :
         {E::length_mismatch, E::bad_offsets, E::too_many_planes, E::overlap, E::bad_config})
      CHECK((a == c) == (to_string(a) == to_string(c)));
  CHECK(to_string(E::bad_offsets).find("offsets") != std::string_view::npos);
  // The empty batch: offsets {0}, nothing to do; without the one offset it is refused.
  std::uint32_t const zero[] = {0};
  CHECK(project_velocities(std::span<Vec3 const>{}, std::span<Vec3 const>{}, zero,
                           std::span<VelocityProjection3>{}) == E::none);
  CHECK(project_velocities(std::span<Vec3 const>{}, std::span<Vec3 const>{},
                           std::span<std::uint32_t const>{},
                           std::span<VelocityProjection3>{}) == E::length_mismatch);
  // Problems without planes: v comes back unchanged, as from the single call, in no steps.
  std::vector<Vec3> vs = {{1, 2, 3}, {0, 0, 0}, {-4, 0.5f, 1e-3f}};
  std::vector<std::uint32_t> const none(4, 0u);
  std::vector<VelocityProjection3> r(3);
  REQUIRE(project_velocities(vs, std::span<Vec3 const>{}, none, r) == E::none);
  for (std::size_t i = 0; i < 3; ++i) {
    auto const one = project_velocity<float>(vs[i], std::span<Vec3 const>{});
    CHECK(test::same_bits(r[i].velocity.x, one.velocity.x));
    CHECK(test::same_bits(r[i].velocity.y, one.velocity.y));
    CHECK(test::same_bits(r[i].velocity.z, one.velocity.z));
    CHECK(r[i].velocity.cmpeq(vs[i]).all());
    CHECK(r[i].converged);
    CHECK(r[i].steps == 0.0f);
  }
  CHECK(detail::character_kernels_isa() == active_isa());
}
