// project_velocities (the batch velocity projection) on every carried instruction set this CPU
// runs: each problem's answer and multipliers against the single scalar call, bit for bit.
#include "character/batch_problems.hpp"
#include "each_isa.hpp"

#include <plume/solver/character/project_velocities.hpp>

#include <catch2/catch.hpp>

using namespace plume;

namespace {

template <class Vec>
void check_on(Isa isa, std::size_t n, std::uint32_t seed) {
  auto const b = test::make_projection_batch<Vec>(n, seed);
  std::vector<GVelocityProjection<Vec>> out(n);
  std::vector<float> lambda(b.normals.size(), -7.0f);
  REQUIRE(project_velocities(std::span<Vec const>(b.velocities), std::span<Vec const>(b.normals),
                             b.offsets, out, lambda) == ProjectVelocitiesError::none);
  CHECK(detail::character_kernels_isa() == isa);
  CHECK(test::first_projection_mismatch(b, out) == -1);
  CHECK(test::first_lambda_mismatch(b.expected_lambda, lambda) == -1);
}

} // namespace

TEST_CASE("dispatch: project_velocities on every carried set gives the single call's bits",
          "[dispatch]") {
  int const ran = test::for_each_runnable_isa([](Isa isa) {
    for (std::size_t n : {1u, 7u, 16u, 17u, 515u}) {
      CAPTURE(n);
      check_on<Vec3>(isa, n, 100u + static_cast<std::uint32_t>(n));
      check_on<Vec2>(isa, n, 200u + static_cast<std::uint32_t>(n));
    }
  });
  CHECK(ran >= 1);
}
