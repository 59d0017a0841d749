// World::step through the dispatch: every carried instruction set this CPU runs steps the same
// scenes to the same bits, equal to the scalar step (the determinism contract), in one process.
#include "each_isa.hpp"

#include <plume/dispatch.hpp>
#include <plume/world.hpp>

#include "fixtures/scenes.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using namespace plume;

namespace {

// The level (scenes::add_level: a mesh, a height field, 40 static boxes) is geometry that
// baseline code builds and every set's kernels read (the mesh's tree and triangle blocks, the
// broad phase's wide copy of the static tree). A layout that differed between sets (the mesh's
// tree and blocks did, before f32xS) crashes or changes bits.
using scenes::add_level;

// Boxes in a pyramid on the level, a ball thrown at it, a chain, a ragdoll, and boxes and
// balls dropped on the mesh, the height field and the row of static boxes (contacts, mesh and
// field contacts, joints and sleep all in the step), stepped `steps` times; stepper(world)
// advances one step.
template <class Step>
std::vector<std::uint64_t> run_scene(Step stepper, int steps) {
  World world;
  add_level(world);
  scenes::add_box_pyramid(world, 6);
  for (int i = 0; i < 6; ++i) {
    scenes::add_ball(world, {-9.0f + 3.0f * float(i), 1.5f, -6.0f}, 0.3f);
    REQUIRE(world.create_body({.pose = Iso3::from_translation({14.5f + float(i), 1.2f, -7.0f}),
                               .shape = Cuboid{{0.3f, 0.3f, 0.3f}}}));
    REQUIRE(
        world.create_body({.pose = Iso3::from_translation({-11.0f + 4.0f * float(i), 1.5f, 11.0f}),
                           .shape = Capsule{0.3f, 0.2f}}));
  }
  BodyId const ball = scenes::add_ball(world, {-6, 1, 0}, 0.3f);
  (void)world.set_velocity(ball, {12, 2, 0}, {0, 0, 0});
  scenes::add_chain(world, {6, 6, 0}, 8);
  scenes::add_ragdoll(world, {0, 9, 3});
  std::vector<std::uint64_t> hashes;
  for (int i = 0; i < steps; ++i) {
    stepper(world);
    if (i % 20 == 19) hashes.push_back(world.state_hash());
  }
  return hashes;
}

} // namespace

TEST_CASE("dispatch: World::step on every carried set gives the scalar step's bits", "[dispatch]") {
  int const steps = 120;
  auto const scalar = run_scene([](World& w) { w.step_with<float>(1.0f / 60.0f); }, steps);
  REQUIRE(scalar.size() == 6);
  int const ran = test::for_each_runnable_isa([&](Isa isa) {
    CHECK(detail::world_kernels_isa() == isa);
    auto const dispatched = run_scene([](World& w) { w.step(1.0f / 60.0f); }, steps);
    CHECK(dispatched == scalar);
  });
  CHECK(ran >= 1);
}

namespace {

// The level (add_level: mesh, height field, static boxes) with a pyramid and balls on it,
// settled: what the batch queries run against.
World query_scene() {
  World world;
  add_level(world);
  scenes::add_box_pyramid(world, 5);
  for (int i = 0; i < 12; ++i)
    scenes::add_ball(world, {-8.0f + 1.5f * float(i), 0.4f, -3}, 0.4f);
  for (int i = 0; i < 30; ++i)
    world.step_with<float>(1.0f / 60.0f);
  return world;
}

template <class H>
std::string bits(std::optional<H> const& h) {
  if (!h) return "miss";
  std::string b(sizeof(H), '\0');
  H c;
  std::memset(static_cast<void*>(&c), 0, sizeof(H)); // padding zero, then field by field
  c.body = h->body;
  c.toi = h->toi;
  c.point = h->point;
  c.normal = h->normal;
  c.collider = h->collider;
  if constexpr (requires { h->penetrating; }) c.penetrating = h->penetrating;
  std::memcpy(b.data(), &c, sizeof(H));
  return b;
}

} // namespace

TEST_CASE("dispatch: batch ray and shape casts on every carried set give the single forms' bits",
          "[dispatch]") {
  World const world = query_scene();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-10.0f, 10.0f), up(0.1f, 8.0f);
  std::vector<Ray3> rays;
  for (int i = 0; i < 1031; ++i) // a fan from a few origins, rays down at the level, scattered
    rays.push_back(i < 512   ? Ray3{{0, 6, 12}, Vec3{u(rng), u(rng) - 8.0f, -12.0f}}
                   : i < 768 ? Ray3{{1.3f * u(rng), 5.0f, 1.3f * u(rng)},
                                    Vec3{0.1f * u(rng), -1.0f, 0.1f * u(rng)}}
                             : Ray3{{u(rng), up(rng), u(rng)}, Vec3{u(rng), u(rng), u(rng)}});
  std::vector<BodyShape> shapes;
  std::vector<Iso3> poses;
  std::vector<Vec3> motions;
  for (int i = 0; i < 203; ++i) {
    if (i % 3 == 0)
      shapes.emplace_back(Sphere{0.3f});
    else if (i % 3 == 1)
      shapes.emplace_back(Capsule{0.4f, 0.25f});
    else
      shapes.emplace_back(Cuboid{{0.2f, 0.3f, 0.4f}});
    poses.push_back(Iso3::from_translation({u(rng), up(rng), u(rng)}));
    motions.push_back({u(rng), -up(rng), u(rng)});
  }
  std::vector<std::string> ray_ref, shape_ref;
  for (Ray3 const& r : rays)
    ray_ref.push_back(bits(world.ray_cast(r, 50.0f)));
  for (std::size_t i = 0; i < shapes.size(); ++i)
    shape_ref.push_back(bits(world.shape_cast(shapes[i], poses[i], motions[i])));
  std::size_t const hits = static_cast<std::size_t>(
      std::count_if(ray_ref.begin(), ray_ref.end(), [](auto const& b) { return b != "miss"; }));
  REQUIRE(hits > rays.size() / 4); // the rays meet the scene

  int const ran = test::for_each_runnable_isa([&](Isa) {
    std::vector<std::optional<WorldRayHit>> ray_out(rays.size());
    world.ray_cast(rays, 50.0f, ray_out);
    std::vector<std::optional<WorldShapeHit>> shape_out(shapes.size());
    world.shape_cast(shapes, poses, motions, ShapeCastConfig{}, shape_out);
    long bad_ray = -1, bad_shape = -1;
    for (std::size_t i = 0; i < rays.size() && bad_ray < 0; ++i)
      if (bits(ray_out[i]) != ray_ref[i]) bad_ray = long(i);
    for (std::size_t i = 0; i < shapes.size() && bad_shape < 0; ++i)
      if (bits(shape_out[i]) != shape_ref[i]) bad_shape = long(i);
    CHECK(bad_ray == -1);
    CHECK(bad_shape == -1);
    // A span of the wrong length: refused, nothing written (the dispatched path throws too).
    std::vector<std::optional<WorldRayHit>> short_out(rays.size() - 1);
    CHECK_THROWS_AS(world.ray_cast(rays, 50.0f, short_out), std::invalid_argument);
    CHECK(std::none_of(short_out.begin(), short_out.end(),
                       [](auto const& h) { return h.has_value(); }));
  });
  CHECK(ran >= 1);
}
