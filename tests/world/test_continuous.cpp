// Continuous collision (WorldConfig::continuous, BodyDef::bullet): fast bodies stop at thin
// walls, mesh and height-field floors and (bullets) thin dynamic plates that they pass through
// without it; sensors, layers and jointed pairs are not swept against; every width steps the
// same world.
#include "../common/types.hpp"
#include "../spatial/mesh_support.hpp"

#include <plume/solver/world/world.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <memory>
#include <type_traits>
#include <vector>

using namespace plume;
using namespace plume::test;

namespace {

constexpr float dt = 1.0f / 60.0f;

WorldConfig no_gravity(bool continuous = true) {
  WorldConfig c;
  c.gravity = Vec3{};
  c.continuous = continuous;
  return c;
}

/// A static wall 1 cm thick (x in [4.995, 5.005]), 4 m square.
BodyId add_wall(World& w, BodyDef def = {}) {
  def.type = BodyType::static_body;
  def.pose = Iso3::from_translation({5.0f, 0.0f, 0.0f});
  def.shape = Cuboid{{0.005f, 2.0f, 2.0f}};
  CreateBodyResult const r = w.create_body(def);
  REQUIRE(r);
  return r.id;
}

/// A 0.1 m ball (radius 0.05) at the origin flying along +x at `speed`.
BodyId add_ball(World& w, float speed, bool bullet = false) {
  CreateBodyResult const r = w.create_body(
      {.linear_velocity = {speed, 0.0f, 0.0f}, .shape = Sphere{0.05f}, .bullet = bullet});
  REQUIRE(r);
  return r.id;
}

bool stopped_by_sweep(World const& w, BodyId id) {
  auto const& s = w.events().continuous_stops;
  return std::find(s.begin(), s.end(), id) != s.end();
}

/// Steps a ball at `speed` toward the wall for 1 s; the largest x its centre reached.
float farthest_x(World& w, BodyId ball, bool* swept = nullptr) {
  float far = w.pose(ball).translation.x;
  for (int i = 0; i < 60; ++i) {
    w.step(dt);
    far = std::max(far, w.pose(ball).translation.x);
    if (swept && stopped_by_sweep(w, ball)) *swept = true;
  }
  return far;
}

} // namespace

TEST_CASE("a 1 cm wall stops a 0.1 m ball at every speed up to 400 m/s", "[world][continuous]") {
  for (float speed : {20.0f, 50.0f, 100.0f, 200.0f, 400.0f}) {
    CAPTURE(speed);
    World w(no_gravity());
    add_wall(w);
    BodyId const ball = add_ball(w, speed);
    bool swept = false;
    float const far = farthest_x(w, ball, &swept);
    CHECK(swept);
    // The ball's surface never passes the wall's front face by more than the contact's slop.
    CHECK(far + 0.05f <= 4.995f + 0.005f);
    CHECK(w.pose(ball).translation.x < 4.995f);
    CHECK(w.pose(ball).translation.x > 4.9f); // it did fly up to the wall
    CHECK(w.linear_velocity(ball).x <= 0.5f); // stopped (no restitution), not still flying on
  }
}

TEST_CASE("without continuous collision the same balls pass through the wall",
          "[world][continuous]") {
  // The scene above is one a discrete step gets wrong: the test would pass without sweeps
  // only if the speculative contacts alone stopped these balls.
  for (float speed : {100.0f, 200.0f, 400.0f}) {
    CAPTURE(speed);
    World w(no_gravity(false));
    add_wall(w);
    BodyId const ball = add_ball(w, speed);
    farthest_x(w, ball);
    CHECK(w.pose(ball).translation.x > 6.0f);
    CHECK(w.events().continuous_stops.empty());
  }
}

TEST_CASE("a fast box stops on a mesh floor, a height field and a half-space",
          "[world][continuous]") {
  auto const floor_mesh =
      std::make_shared<TriangleMesh const>(make(grid(16, 1.0f, [](float, float) { return 0.0f; })));
  std::vector<float> const zeros(17 * 17, 0.0f);
  auto field = HeightField::build(17, 17, zeros, 1.0f, 1.0f);
  REQUIRE(field.ok());
  auto const floor_field = std::make_shared<HeightField const>(std::move(field.field));
  std::vector<BodyShape> const floors{MeshShape{floor_mesh}, HeightFieldShape{floor_field},
                                      HalfSpace{Vec3::Y}};
  for (std::size_t k = 0; k < floors.size(); ++k) {
    for (bool continuous : {true, false}) {
      CAPTURE(k, continuous);
      WorldConfig c;
      c.continuous = continuous;
      World w(c);
      bool const half_space = k == 2;
      REQUIRE(w.create_body(
          {.type = BodyType::static_body,
           .pose = Iso3::from_translation(half_space ? Vec3{} : Vec3{-8.0f, 0.0f, -8.0f}),
           .shape = floors[k]}));
      CreateBodyResult const box =
          w.create_body({.pose = Iso3::from_translation({0.3f, 22.0f, 0.2f}),
                         .linear_velocity = {0.0f, -300.0f, 0.0f},
                         .shape = Cuboid{Vec3::splat(0.25f)}});
      REQUIRE(box);
      float lowest = 22.0f;
      for (int i = 0; i < 120; ++i) {
        w.step(dt);
        lowest = std::min(lowest, w.pose(box.id).translation.y);
      }
      if (continuous) {
        CHECK(lowest > 0.25f - 0.03f); // at most the contact's slop into the floor
        CHECK(w.pose(box.id).translation.y == Approx(0.25f).margin(0.02f));
      } else if (half_space) {
        CHECK(lowest < -1.0f); // deep in the solid: a discrete step lands it there
      } else {
        CHECK(w.pose(box.id).translation.y < -10.0f); // through the surface, falling
      }
    }
  }
}

TEST_CASE("a box sliding fast on a floor stops at a thin wall of the same mesh",
          "[world][continuous]") {
  // The box starts resting on the floor, so its own sweep starts touching the floor's
  // triangles: the core's sweep must find the wall (two triangles facing -x at world x = 4).
  soup s = grid(16, 1.0f, [](float, float) { return 0.0f; });
  auto const base = std::uint32_t(s.v.size());
  s.v.insert(
      s.v.end(),
      {{12.0f, 0.0f, 0.0f}, {12.0f, 0.0f, 16.0f}, {12.0f, 2.0f, 0.0f}, {12.0f, 2.0f, 16.0f}});
  s.i.insert(s.i.end(), {base, base + 1, base + 2, base + 1, base + 3, base + 2});
  auto const mesh = std::make_shared<TriangleMesh const>(make(s));
  for (float speed : {60.0f, 150.0f, 300.0f}) {
    CAPTURE(speed);
    World w;
    REQUIRE(w.create_body({.type = BodyType::static_body,
                           .pose = Iso3::from_translation({-8.0f, 0.0f, -8.0f}),
                           .shape = MeshShape{mesh}}));
    CreateBodyResult const box =
        w.create_body({.pose = Iso3::from_translation({-4.0f, 0.25f, 0.5f}),
                       .shape = Cuboid{Vec3::splat(0.25f)}});
    REQUIRE(box);
    for (int i = 0; i < 30; ++i) // settle on the floor
      w.step(dt);
    REQUIRE(w.set_velocity(box.id, {speed, 0.0f, 0.0f}, Vec3{}) == BodyError::none);
    float far = -10.0f;
    for (int i = 0; i < 60; ++i) {
      w.step(dt);
      far = std::max(far, w.pose(box.id).translation.x);
    }
    CHECK(far < 4.0f); // the centre never crosses the wall
    CHECK(w.pose(box.id).translation.x < 4.0f - 0.2f);
    CHECK(w.pose(box.id).translation.x > 3.5f); // it did slide up to the wall
    CHECK(w.pose(box.id).translation.y > 0.0f);
  }
}

TEST_CASE("a bullet stops at a thin dynamic plate that a fast ball passes through",
          "[world][continuous]") {
  for (bool bullet : {true, false}) {
    CAPTURE(bullet);
    World w(no_gravity());
    CreateBodyResult const plate = w.create_body({.pose = Iso3::from_translation({5.0f, 0, 0}),
                                                  .shape = Cuboid{{0.005f, 1.0f, 1.0f}},
                                                  .density = 20000.0f});
    REQUIRE(plate);
    BodyId const ball = add_ball(w, 200.0f, bullet);
    CHECK(w.is_bullet(ball) == bullet);
    bool passed = false;
    for (int i = 0; i < 30; ++i) {
      w.step(dt);
      passed = passed || w.pose(ball).translation.x > w.pose(plate.id).translation.x + 0.05f;
    }
    CHECK(passed == !bullet);
    if (bullet) CHECK(w.linear_velocity(plate.id).x > 0.1f); // the plate took the blow
  }
}

TEST_CASE("continuous collision skips sensors, other layers and jointed bodies",
          "[world][continuous]") {
  // Each passes the wall in its first steps, never put back by a sweep.
  SECTION("a sensor wall") {
    World w(no_gravity());
    add_wall(w, BodyDef{.sensor = true});
    BodyId const ball = add_ball(w, 200.0f);
    bool swept = false;
    farthest_x(w, ball, &swept);
    CHECK_FALSE(swept);
    CHECK(w.pose(ball).translation.x > 6.0f);
  }
  SECTION("a wall in a layer the ball does not interact with") {
    World w(no_gravity());
    add_wall(w, BodyDef{.layers = {.memberships = 2, .filters = 0xffffffffu}});
    CreateBodyResult const ball = w.create_body({.linear_velocity = {200.0f, 0, 0},
                                                 .shape = Sphere{0.05f},
                                                 .layers = {.memberships = 1, .filters = 1}});
    REQUIRE(ball);
    bool swept = false;
    farthest_x(w, ball.id, &swept);
    CHECK_FALSE(swept);
    CHECK(w.pose(ball.id).translation.x > 6.0f);
  }
  SECTION("a wall jointed to the ball without collide_connected") {
    World w(no_gravity());
    BodyId const wall = add_wall(w);
    BodyId const ball = add_ball(w, 200.0f);
    JointDef j;
    j.body_a = wall;
    j.body_b = ball;
    // A rope up to 100 m: no force on the ball until it is that far.
    j.type = DistanceJoint{
        .min_length = 0.0f, .max_length = 100.0f, .spring_enabled = true, .frequency = 0.0f};
    j.frame_a = w.joint_frame(wall, Vec3{5, 0, 0}, Vec3::X);
    j.frame_b = w.joint_frame(ball, Vec3{}, Vec3::X);
    REQUIRE(w.create_joint(j));
    w.step(dt);
    CHECK_FALSE(stopped_by_sweep(w, ball));
    w.step(dt);
    CHECK_FALSE(stopped_by_sweep(w, ball));
    CHECK(w.pose(ball).translation.x > 5.5f);
  }
  SECTION("set_bullet checks its id") {
    World w;
    BodyId const ball = add_ball(w, 1.0f);
    CHECK(w.set_bullet(ball, true) == BodyError::none);
    CHECK(w.is_bullet(ball));
    REQUIRE(w.destroy_body(ball) == BodyError::none);
    CHECK(w.set_bullet(ball, false) == BodyError::bad_body);
  }
}

TEST_CASE("every width sweeps fast bodies the same", "[world][continuous][lanes]") {
  auto run = [](auto tag) {
    using T = typename decltype(tag)::type;
    World w;
    REQUIRE(w.create_body({.type = BodyType::static_body, .shape = HalfSpace{Vec3::Y}}));
    add_wall(w);
    for (int k = 0; k < 12; ++k) {
      float const f = float(k);
      REQUIRE(w.create_body(
          {.pose = Iso3::from_translation({-2.0f + 0.3f * f, 0.5f + f, 0.3f * f}),
           .linear_velocity = {120.0f + 20.0f * f, -30.0f * f, 5.0f * f},
           .angular_velocity = {f, 0.5f * f, -f},
           .shape = k % 2 ? BodyShape{Cuboid{Vec3::splat(0.1f)}} : BodyShape{Capsule{0.1f, 0.05f}},
           .bullet = k % 3 == 0}));
    }
    std::size_t stops = 0;
    for (int i = 0; i < 40; ++i) {
      w.template step_with<T>(dt);
      stops += w.events().continuous_stops.size();
    }
    CHECK(stops > 0);
    return w.state_hash();
  };
  std::uint64_t const scalar = run(std::type_identity<float>{});
  for_each_type<test::f32_wide_types>(
      [&]<class T>() { CHECK(run(std::type_identity<T>{}) == scalar); });
}
