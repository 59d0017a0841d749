// Manifold reuse (WorldConfig::reuse_distance): a pair keeps its manifolds, moved with its
// bodies, while no point of the smaller shape has moved more than reuse_distance relative to
// the other body since they were computed.
#include <fixtures/scenes.hpp>
#include <plume/solver/world/world.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace plume;

namespace {

constexpr float dt = 1.0f / 60.0f;

/// No gravity, no sleeping, and a reuse distance of 1 mm (ten times the default: motions of
/// a tenth of a millimetre per step show it).
WorldConfig floating() {
  WorldConfig cfg;
  cfg.gravity = Vec3{};
  cfg.sleep = false;
  cfg.reuse_distance = 0.001f;
  return cfg;
}

/// The world's manifold of the pair (a, b) (count 0 when it has no contact).
Manifold world_manifold(World const& w, BodyId a, BodyId b) {
  for (Contact const& c : w.contacts())
    if ((c.body_a == a.index && c.body_b == b.index) ||
        (c.body_a == b.index && c.body_b == a.index))
      return c.manifold;
  return {};
}

/// Every point of `got` has a point of `fresh` with the same id, the same separation within
/// tol and the same surface points within tol; the normals agree within tol.
void require_same_manifold(Manifold const& got, Manifold const& fresh, float tol) {
  REQUIRE(got.count == fresh.count);
  CHECK((got.normal - fresh.normal).length() <= tol);
  for (ContactPoint const& p : got) {
    ContactPoint const* match = nullptr;
    for (ContactPoint const& q : fresh)
      if (q.id == p.id) match = &q;
    REQUIRE(match != nullptr);
    CHECK(std::abs(p.separation - match->separation) <= tol);
    CHECK((p.point_a - match->point_a).length() <= tol);
    CHECK((p.point_b - match->point_b).length() <= tol);
  }
}

} // namespace

TEST_CASE("manifold reuse: a pair moving apart along its normal keeps its manifold, moved and "
          "measured again, until it has drifted reuse_distance",
          "[world][reuse]") {
  World w(floating());
  Cuboid const floor{{2.0f, 0.5f, 2.0f}}, box{Vec3::splat(0.5f)};
  BodyId const a = w.create_body({.type = BodyType::static_body,
                                  .pose = Iso3::from_translation({0, -0.5f, 0}),
                                  .shape = floor})
                       .id;
  // 1 mm above the floor (within the prediction distance), rising 0.1 mm per step.
  BodyId const b = w.create_body({.pose = Iso3::from_translation({0.3f, 0.501f, -0.2f}),
                                  .linear_velocity = {0, 0.006f, 0},
                                  .shape = box})
                       .id;
  int reused = 0, computed = 0, run = 0, longest_run = 0;
  for (int s = 0; s < 40; ++s) {
    // The step's manifolds are those of the poses it starts from.
    Manifold const fresh = contact_manifold(floor, w.pose(a), box, w.pose(b), w.config().manifold);
    w.step(dt);
    bool const kept = w.last_profile().reused_pairs == 1;
    REQUIRE(w.last_profile().pairs == 1);
    (kept ? reused : computed) += 1;
    run = kept ? run + 1 : 0;
    longest_run = std::max(longest_run, run);
    Manifold const got = world_manifold(w, a, b);
    // A translation along the normal moves every clipped point with B: the reused manifold
    // is the fresh one (to rounding), its separations measured again.
    if (fresh.empty()) {
      CHECK(got.empty());
    } else {
      require_same_manifold(got, fresh, 2e-6f);
    }
  }
  // 0.1 mm per step: the manifold computed at step k serves the steps after it until B has
  // risen 1 mm from where it was computed, never longer.
  CHECK(reused >= 30);
  CHECK(computed >= 4);
  CHECK(longest_run >= 8);
  CHECK(longest_run <= 10);
}

TEST_CASE("manifold reuse: the lever arm - a turn moves far points more than near ones",
          "[world][reuse]") {
  auto run = [](float spin, Vec3 half_extents) {
    World w(floating());
    Cuboid const floor{{20.0f, 0.5f, 20.0f}}, box{half_extents};
    BodyId const a = w.create_body({.type = BodyType::static_body,
                                    .pose = Iso3::from_translation({0, -0.5f, 0}),
                                    .shape = floor})
                         .id;
    // Turning about the floor's normal through its centre: its origin does not move.
    BodyId const b = w.create_body({.pose = Iso3::from_translation({0, half_extents.y + 0.001f, 0}),
                                    .angular_velocity = {0, spin, 0},
                                    .shape = box})
                         .id;
    std::size_t reused = 0;
    for (int s = 0; s < 30; ++s) {
      Manifold const fresh =
          contact_manifold(floor, w.pose(a), box, w.pose(b), w.config().manifold);
      w.step(dt);
      reused += w.last_profile().reused_pairs;
      // B's corners turn with it: reused, they are where a fresh clip puts them.
      require_same_manifold(world_manifold(w, a, b), fresh, 4e-7f * std::max(1.0f, half_extents.x));
    }
    return reused;
  };
  // 0.01 rad/s: 1.7e-4 rad per step. A 1 m cube's corners (0.87 m from its centre) move
  // 0.14 mm per step (reused for 6 steps after each computation); a 10 m plank's (5 m out)
  // 0.83 mm (reused one step in two at most).
  std::size_t const cube = run(0.01f, Vec3::splat(0.5f));
  std::size_t const plank = run(0.01f, {5.0f, 0.5f, 0.3f});
  CHECK(cube >= 24);
  CHECK(plank <= 15);
  // Fast enough that even the cube's corners move more than 1 mm per step: never reused,
  // although its centre stays where it is.
  CHECK(run(0.1f, Vec3::splat(0.5f)) == 0);
  // A 1 cm cube turning 0.015 rad per step: its corners move 0.13 mm, within the distance,
  // but the turn is beyond reuse_angle (0.01 rad), which bounds the error of the normal.
  CHECK(run(0.9f, Vec3::splat(0.005f)) == 0);
  CHECK(run(0.2f, Vec3::splat(0.005f)) >= 18);
}

TEST_CASE("manifold reuse: against a half-space the box's own reach bounds the motion, in "
          "either body order",
          "[world][reuse]") {
  std::size_t counts[2] = {};
  for (bool ground_first : {true, false}) {
    CAPTURE(ground_first);
    World w(floating());
    BodyDef const ground{.type = BodyType::static_body, .shape = HalfSpace{Vec3::Y}};
    // Turning about the vertical through its centre at 0.01 rad/s, 0.5 mm above the floor,
    // far from the half-space's origin: the half-space's own reach is infinite, so only the
    // box's bound (0.87 m + the speculative distance, 0.15 mm per step) can allow reuse.
    BodyDef const box{.pose = Iso3::from_translation({3.0f, 0.5005f, -7.0f}),
                      .angular_velocity = {0, 0.01f, 0},
                      .shape = Cuboid{Vec3::splat(0.5f)}};
    BodyId g, b;
    if (ground_first) {
      g = w.create_body(ground).id;
      b = w.create_body(box).id;
    } else {
      b = w.create_body(box).id;
      g = w.create_body(ground).id;
    }
    std::size_t reused = 0;
    for (int s = 0; s < 21; ++s) {
      w.step(dt);
      reused += w.last_profile().reused_pairs;
      Manifold const got = world_manifold(w, g, b);
      REQUIRE(got.count == 4);
      for (ContactPoint const& p : got)
        CHECK(std::abs(p.separation - 0.0005f) < 2e-6f);
    }
    // Computed at steps 1, 8 and 15 (seven steps turn it 1.03 mm at the corners).
    CHECK(reused == 18);
    counts[ground_first ? 0 : 1] = reused;
  }
  CHECK(counts[0] == counts[1]);
}

TEST_CASE("manifold reuse: a slot taken by a new body is never mistaken for the old pair",
          "[world][reuse]") {
  World w(floating());
  Cuboid const floor{{2.0f, 0.5f, 2.0f}};
  BodyId const a = w.create_body({.type = BodyType::static_body,
                                  .pose = Iso3::from_translation({0, -0.5f, 0}),
                                  .shape = floor})
                       .id;
  Iso3 const at = Iso3::from_translation({0, 0.5f, 0});
  BodyId const box = w.create_body({.pose = at, .shape = Cuboid{Vec3::splat(0.5f)}}).id;
  w.step(dt);
  w.step(dt);
  REQUIRE(w.last_profile().reused_pairs == 1);
  REQUIRE(world_manifold(w, a, box).count == 4);
  REQUIRE(w.destroy_body(box) == BodyError::none);
  BodyId const ball = w.create_body({.pose = at, .shape = Sphere{0.5f}}).id;
  REQUIRE(ball.index == box.index); // the same slot, at its next generation
  Manifold const fresh =
      contact_manifold(floor, w.pose(a), Sphere{0.5f}, w.pose(ball), w.config().manifold);
  w.step(dt);
  CHECK(w.last_profile().reused_pairs == 0);
  Manifold const got = world_manifold(w, a, ball);
  CHECK(got.count == 1);
  require_same_manifold(got, fresh, 0.0f);
}

TEST_CASE("manifold reuse: a pair reused as apart is found again before it comes within "
          "prediction - reuse_distance, whatever reuse_distance asks",
          "[world][reuse]") {
  for (float asked : {0.001f, 0.005f, 1.0f}) {
    CAPTURE(asked);
    WorldConfig cfg = floating();
    cfg.reuse_distance = asked;
    World w(cfg);
    w.create_body({.type = BodyType::static_body, .shape = HalfSpace{Vec3::Y}});
    float const prediction = w.config().manifold.prediction; // the speculative distance
    // 0.5 mm beyond the prediction distance, falling at 0.2 mm per step: computed apart at
    // the first step, then reused as apart for as long as the rule allows.
    BodyId const b =
        w.create_body({.pose = Iso3::from_translation({0, 0.5f + prediction + 0.0005f, 0}),
                       .linear_velocity = {0, -0.012f, 0},
                       .shape = Cuboid{Vec3::splat(0.5f)}})
            .id;
    // Values above half the prediction distance act as half of it.
    float const limit = std::min(asked, 0.5f * prediction);
    std::size_t reused = 0, apart = 0;
    for (int s = 0; s < 200; ++s) {
      float const gap = w.pose(b).translation.y - 0.5f; // what the step's manifolds see
      w.step(dt);
      reused += w.last_profile().reused_pairs;
      CAPTURE(s, gap);
      CHECK(gap > -1e-4f); // the speculative contact stops it at the floor
      if (gap <= prediction - limit) CHECK(w.contacts().size() == 1);
      if (w.contacts().empty()) ++apart;
    }
    // Apart until the fall has covered the 0.5 mm or the reuse distance, whichever is
    // later: the reuse as apart ends no earlier than it may.
    CHECK(apart >= std::size_t(std::max(0.0005f, limit) / 0.0002f) - 1);
    CHECK(reused > 100);
  }
}

TEST_CASE("manifold reuse: reuse_distance or reuse_angle 0, negative or NaN computes every "
          "pair every step",
          "[world][reuse]") {
  float const nan = std::numeric_limits<float>::quiet_NaN();
  for (auto [distance, angle] : {std::pair{0.0f, 0.01f},
                                 {-1.0f, 0.01f},
                                 {nan, 0.01f},
                                 {0.001f, 0.0f},
                                 {0.001f, -1.0f},
                                 {0.001f, nan}}) {
    CAPTURE(distance, angle);
    WorldConfig cfg;
    cfg.sleep = false;
    cfg.reuse_distance = distance;
    cfg.reuse_angle = angle;
    World w(cfg);
    scenes::add_ground(w);
    scenes::add_box_pyramid(w, 4);
    // And a box floating still above a floor: nothing moves, not even by rounding.
    w.create_body({.type = BodyType::static_body,
                   .pose = Iso3::from_translation({50, 0, 0}),
                   .shape = Cuboid{Vec3::splat(0.5f)}});
    w.create_body({.pose = Iso3::from_translation({50, 1.001f, 0}),
                   .shape = Cuboid{Vec3::splat(0.5f)},
                   .gravity_scale = 0.0f});
    for (int s = 0; s < 30; ++s) {
      w.step(dt);
      REQUIRE(w.last_profile().reused_pairs == 0);
    }
  }
}

TEST_CASE("manifold reuse: a settled pyramid keeps all of its manifolds and stands as it "
          "does without reuse",
          "[world][reuse]") {
  auto settle = [](float reuse_distance) {
    WorldConfig cfg;
    cfg.sleep = false;
    cfg.reuse_distance = reuse_distance;
    auto w = std::make_unique<World>(cfg);
    scenes::add_ground(*w);
    scenes::add_box_pyramid(*w, 8);
    for (int s = 0; s < 180; ++s) {
      w->step(dt);
      // Without reuse, every settled cuboid pair goes through the kernel, none to GJK/EPA
      // (the nearest-edges check answers the diagonal neighbours).
      if (!(reuse_distance > 0.0f) && s >= 60) {
        CHECK(w->last_profile().box_pairs > 0);
        CHECK(w->last_profile().general_box_pairs == 0);
      }
    }
    return w;
  };
  auto const with = settle(WorldConfig{}.reuse_distance);
  auto const without = settle(0.0f);
  StepProfile const& p = with->last_profile();
  CHECK(p.reused_pairs == p.pairs); // every build and width steps the same world
  CHECK(p.pairs > 1000);
  // Same bodies in the same slots: every box ends within 2 mm of where it ends without reuse.
  REQUIRE(with->body_count() == without->body_count());
  float worst = 0.0f;
  for (std::uint32_t i = 0; i < with->body_count(); ++i) {
    BodyId const id = with->body_id(i);
    worst = std::max(worst, (with->pose(id).translation - without->pose(id).translation).length());
  }
  CHECK(worst < 0.002f);
}

TEST_CASE("manifold reuse: on a tilted floor the kept normal turns with the floor's frame",
          "[world][reuse]") {
  World w(floating());
  // A floor tilted 20 degrees about z, the box resting on it 0.5 mm above, both at rest.
  Quat const tilt = Quat::from_axis_angle(Vec3::Z, 0.349f);
  Cuboid const floor{{4.0f, 0.5f, 4.0f}}, box{Vec3::splat(0.5f)};
  BodyId const a = w.create_body({.type = BodyType::static_body,
                                  .pose = {tilt, tilt * Vec3{0, -0.5f, 0}},
                                  .shape = floor})
                       .id;
  // The box turned a further 0.005 rad about the floor's x axis (within reuse_angle): its
  // corners 0.5 to 5.5 mm above the floor, whose face is the reference. A normal that turned
  // with B instead of A would be 0.005 off.
  Quat const lean = tilt * Quat::from_axis_angle(Vec3::X, 0.005f);
  BodyId const b =
      w.create_body({.pose = {lean, tilt * Vec3{0.2f, 0.5030f, 0.1f}}, .shape = box}).id;
  std::size_t reused = 0;
  for (int s = 0; s < 10; ++s) {
    Manifold const fresh = contact_manifold(floor, w.pose(a), box, w.pose(b), w.config().manifold);
    w.step(dt);
    reused += w.last_profile().reused_pairs;
    Manifold const got = world_manifold(w, a, b);
    require_same_manifold(got, fresh, 1e-6f);
    CHECK((got.normal - tilt * Vec3::Y).length() < 1e-6f);
  }
  CHECK(reused == 9);
}

TEST_CASE("manifold reuse: a reuse_angle beyond 1 rad acts as 1 rad", "[world][reuse]") {
  // 2 sin(angle / 2) of 100 rad is negative: without the cap, reuse would be off.
  for (float angle : {1.0f, 100.0f, std::numeric_limits<float>::infinity()}) {
    CAPTURE(angle);
    WorldConfig cfg = floating();
    cfg.reuse_angle = angle;
    World w(cfg);
    w.create_body({.type = BodyType::static_body, .shape = HalfSpace{Vec3::Y}});
    w.create_body({.pose = Iso3::from_translation({0, 0.5005f, 0}), .shape = Sphere{0.5f}});
    std::size_t reused = 0;
    for (int s = 0; s < 10; ++s) {
      w.step(dt);
      reused += w.last_profile().reused_pairs;
    }
    CHECK(reused == 9);
  }
}
