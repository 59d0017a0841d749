// move_and_slide through a world of static bodies (WorldMoveQuery): the scenarios of a robust
// kinematic move (a capsule of radius 0.5 and half height 0.5, skin 0.01, dt 1/60, speed 5,
// 100 frames unless said), each asserting the property it names; the callback's contract; bad
// input; and a user's collider span (ColliderSetQuery) giving the world's path bit for bit.
#include "../common/harness.hpp"
#include "../common/types.hpp"
#include "../spatial/mesh_support.hpp"

#include <plume/collision/epa.hpp>
#include <plume/solver/character/collider_set.hpp>
#include <plume/solver/character/move_and_slide.hpp>
#include <plume/solver/world/move_query.hpp>
#include <plume/solver/world/world.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

using namespace plume;

namespace {

constexpr float dt = 1.0f / 60.0f;
constexpr float skin = 0.01f;
Capsule const capsule{0.5f, 0.5f}; // half height 0.5, radius 0.5: 2 m tall, bottom at y - 1

BodyId add_box(World& w, Vec3 const& centre, Vec3 const& half, Quat const& rot = Quat::IDENTITY) {
  return w
      .create_body(
          {.type = BodyType::static_body, .pose = Iso3{rot, centre}, .shape = Cuboid{half}})
      .id;
}

BodyId add_floor(World& w, float y = -1.0f - skin) {
  return w
      .create_body({.type = BodyType::static_body,
                    .pose = Iso3::from_translation({0, y, 0}),
                    .shape = HalfSpace{Vec3::Y}})
      .id;
}

/// A character that asks for the same velocity every frame, as a controller's input would.
struct Walk {
  std::vector<Vec3> path;                          // position after each frame
  std::vector<Vec3> velocity;                      // projected velocity of each frame
  std::vector<MoveAndSlideResult<ColliderId>> log; // every frame's result
};

Walk walk(World const& w, Vec3 start, Vec3 desired, int frames = 100,
          MoveAndSlideConfig const& cfg = {}, BodyShape const& shape = capsule) {
  WorldMoveQuery const scene(w);
  Walk out;
  Vec3 p = start;
  for (int f = 0; f < frames; ++f) {
    auto const r = move_and_slide(scene, shape, Iso3::from_translation(p), desired, dt, cfg);
    REQUIRE(!r.invalid_input);
    REQUIRE(r.position.is_finite());
    p = r.position;
    out.path.push_back(p);
    out.velocity.push_back(r.velocity);
    out.log.push_back(r);
  }
  return out;
}

/// The largest distance between any position of the last `frames` frames and their first.
float spread(Walk const& w, int frames = 50) {
  float s = 0;
  Vec3 const ref = w.path[w.path.size() - std::size_t(frames)];
  for (std::size_t i = w.path.size() - std::size_t(frames); i < w.path.size(); ++i)
    s = std::max(s, (w.path[i] - ref).length());
  return s;
}

/// The signed gap between a shape at p and the world's nearest body within 1 (negative:
/// overlap; +inf: nothing that near).
template <class Shape>
float gap(World const& w, Shape const& shape, Vec3 const& p) {
  float best = std::numeric_limits<float>::infinity();
  w.contact_query(shape, Iso3::from_translation(p), 1.0f, [&](ColliderId, Manifold const& m) {
    best = std::min(best, m.min_separation());
    return true;
  });
  return best;
}
float gap(World const& w, Vec3 const& p) { return gap(w, capsule, p); }

/// How deep a shape at p is in the world's deepest body (0: in none).
template <class Shape>
float deepest(World const& w, Shape const& shape, Vec3 const& p) {
  return std::max(0.0f, -gap(w, shape, p));
}

Vec3 dir(float degrees) { // a horizontal unit direction, degrees from +x toward +z
  float const a = degrees * std::numbers::pi_v<float> / 180.0f;
  return {std::cos(a), 0, std::sin(a)};
}

} // namespace

TEST_CASE("move and slide: a zero sweep ends the loop whatever min_sweep", "[character][move]") {
  // With min_sweep <= 0 a standing character's zero sweep was counted as a sweep that cast
  // nothing (found by the move_and_slide fuzz target: sweeps != casts).
  World w;
  add_box(w, {3, 0, 0}, {0.5f, 5, 5});
  WorldMoveQuery const scene(w);
  for (float min_sweep : {0.0f, -1.0f, 1e-4f}) {
    INFO("min_sweep " << min_sweep);
    MoveAndSlideConfig cfg;
    cfg.min_sweep = min_sweep;
    auto const still = move_and_slide(scene, capsule, Iso3{}, Vec3{}, dt, cfg);
    CHECK(still.sweeps == 0);
    CHECK(still.position.length() == 0.0f);
    auto const moving = move_and_slide(scene, capsule, Iso3{}, Vec3{1, 0, 0}, dt, cfg);
    CHECK(moving.sweeps == 1);
  }
}

TEST_CASE("move and slide: head-on into a wall stops at the skin and does not creep",
          "[character][move]") {
  World w;
  add_box(w, {3, 0, 0}, {0.5f, 5, 5}); // face at x = 2.5
  Walk const r = walk(w, {0, 0, 0}, {5, 0, 0});
  float const g = 2.5f - (r.path.back().x + 0.5f);
  CHECK(g >= 0.5f * skin);
  CHECK(g <= 2.0f * skin);
  CHECK(spread(r) < 1e-6f);
  CHECK(r.velocity.back().length() < 0.01f); // the wall takes the whole velocity
  CHECK(r.path.back().y == 0.0f);
  CHECK(r.path.back().z == 0.0f);
}

TEST_CASE("move and slide: 45 degrees into a wall slides at the tangential speed",
          "[character][move]") {
  World w;
  add_box(w, {3, 0, 0}, {0.5f, 5, 50});
  Walk const r = walk(w, {2.0f - skin, 0, -20}, dir(45) * 5.0f);
  float const tangential = 5.0f * std::sin(std::numbers::pi_v<float> / 4);
  float const dz = r.path[99].z - r.path[49].z;
  CHECK(dz == Approx(tangential * 50 * dt).epsilon(1e-3));
  float const g = 2.5f - (r.path.back().x + 0.5f);
  CHECK(g >= 0.5f * skin);
  CHECK(g <= 2.0f * skin);
  CHECK(r.velocity.back().x == Approx(0).margin(0.01));
  CHECK(r.velocity.back().z == Approx(tangential).epsilon(1e-3));
}

TEST_CASE("move and slide: a second plane from the callback (extra_normal) clips the velocity "
          "with the hit's",
          "[character][move]") {
  World w;
  add_box(w, {3, 0, 0}, {0.5f, 5, 50});
  WorldMoveQuery const scene(w);
  Vec3 const start{2.0f - skin, 0, 0};
  Vec3 const v = dir(45) * 5.0f; // into the wall and along +z
  auto const plain = move_and_slide(scene, capsule, Iso3::from_translation(start), v, dt);
  // A plane across the slide (normal -z) added at the wall: the slide stops too.
  int added = 0;
  auto const fenced = move_and_slide(scene, capsule, Iso3::from_translation(start), v, dt, {}, {},
                                     [&](MoveHit<ColliderId>& h) {
                                       if (h.kind == MoveHitKind::sweep) {
                                         h.extra_normal = Vec3{0, 0, -1};
                                         ++added;
                                       }
                                       return HitResponse::accept;
                                     });
  REQUIRE(added >= 1);
  CHECK(plain.velocity.z == Approx(v.z).epsilon(1e-3));
  CHECK(std::abs(fenced.velocity.z) < 1e-3f);
  CHECK(std::abs(fenced.velocity.x) < 1e-3f);
  // A zero or NaN extra normal adds no plane.
  for (Vec3 const extra : {Vec3{}, Vec3{NAN, 0, 0}}) {
    auto const r = move_and_slide(scene, capsule, Iso3::from_translation(start), v, dt, {}, {},
                                  [&](MoveHit<ColliderId>& h) {
                                    h.extra_normal = extra;
                                    return HitResponse::accept;
                                  });
    CHECK(r.velocity.z == plain.velocity.z);
    CHECK(r.position.z == plain.position.z);
  }
}

TEST_CASE("move and slide: a 90 degree inside corner stops without jitter", "[character][move]") {
  World w;
  add_box(w, {3, 0, 0}, {0.5f, 5, 5}); // x = 2.5
  add_box(w, {0, 0, 3}, {5, 5, 0.5f}); // z = 2.5
  Walk const r = walk(w, {0, 0, 0}, dir(45) * 5.0f);
  CHECK(spread(r) < 1e-5f);
  CHECK(r.path.back().x + 0.5f <= 2.5f);
  CHECK(r.path.back().z + 0.5f <= 2.5f);
  CHECK(r.path.back().x + 0.5f >= 2.5f - 2 * skin);
  CHECK(r.path.back().z + 0.5f >= 2.5f - 2 * skin);
}

TEST_CASE("move and slide: a floor and two walls stop a move into all three", "[character][move]") {
  World w;
  add_floor(w);
  add_box(w, {3, 0, 0}, {0.5f, 5, 5});
  add_box(w, {0, 0, 3}, {5, 5, 0.5f});
  Walk const r = walk(w, {0, 0, 0}, Vec3{3, -3, 3});
  CHECK(spread(r) < 1e-5f);
  CHECK(r.velocity.back().length() < 0.01f);
  CHECK(r.path.back().y >= -skin);
  CHECK(r.path.back().y <= skin);
}

TEST_CASE("move and slide: jumping into a two-wall corner keeps the vertical speed exactly",
          "[character][move]") {
  World w;
  add_box(w, {3, 0, 0}, {0.5f, 50, 5});
  add_box(w, {0, 0, 3}, {5, 50, 0.5f});
  Walk const r = walk(w, {1.9f, 0, 1.9f}, Vec3{3, 4, 3}, 60);
  for (std::size_t f = 0; f < r.velocity.size(); ++f) {
    INFO("frame " << f);
    REQUIRE(r.velocity[f].y == 4.0f);
  }
  CHECK(r.path.back().y == Approx(4.0f * 60 * dt).epsilon(1e-4));
  CHECK(std::abs(r.velocity.back().x) < 0.01f);
  CHECK(std::abs(r.velocity.back().z) < 0.01f);
}

TEST_CASE("move and slide: a wall-floor crease slides along it and stays on the floor",
          "[character][move]") {
  World w;
  add_floor(w);
  add_box(w, {3, 0, 0}, {0.5f, 5, 50});
  Walk const r = walk(w, {1.99f - skin, 0, -20}, Vec3{2, -3, 4});
  float const dz = r.path[99].z - r.path[49].z;
  CHECK(dz == Approx(4.0f * 50 * dt).epsilon(1e-3));
  for (Vec3 const& p : r.path) {
    REQUIRE(p.y >= -skin);
    REQUIRE(p.y <= skin);
    REQUIRE(p.x + 0.5f <= 2.5f);
  }
}

TEST_CASE("move and slide: V-shaped walls stop a move into the apex or slide along one wall, "
          "never alternating",
          "[character][move]") {
  for (float half_angle : {20.0f, 35.0f, 60.0f}) { // acute to obtuse
    INFO("half angle " << half_angle);
    World w;
    // Two walls meeting at x = 6 on the x axis, each half_angle away from the -x direction.
    for (float side : {-1.0f, 1.0f}) {
      float const a = (180.0f - side * half_angle) * std::numbers::pi_v<float> / 180.0f;
      Vec3 const along{std::cos(a), 0, std::sin(a)};        // from the apex back along the wall
      Vec3 const out_n = Vec3{-along.z, 0, along.x} * side; // into the wedge's inside
      Vec3 const centre = Vec3{6, 0, 0} + along * 5.0f - out_n * 0.5f;
      float const yaw = -std::atan2(along.z, along.x);
      add_box(w, centre, {5, 5, 0.5f}, Quat::from_rotation_y(yaw));
    }
    // Straight into the apex: stops.
    Walk const straight = walk(w, {0, 0, 0}, {5, 0, 0}, 160);
    CHECK(spread(straight) < 1e-5f);
    CHECK(gap(w, straight.path.back()) >= 0.0f);
    // At an angle: one wall takes it and the move never flips from one wall to the other (z
    // grows until the first wall deflects it toward the apex, then only shrinks).
    Walk const slanted = walk(w, {0, 0, 0.2f}, dir(10) * 5.0f, 160);
    int flips = 0;
    for (std::size_t f = 2; f < slanted.path.size(); ++f) {
      float const a = slanted.path[f].z - slanted.path[f - 1].z;
      float const b = slanted.path[f - 1].z - slanted.path[f - 2].z;
      if (a * b < 0 && std::abs(a) > 1e-5f && std::abs(b) > 1e-5f) ++flips;
    }
    CHECK(flips <= 1); // the one turn where the first wall deflects it, then no more
    CHECK(gap(w, slanted.path.back()) >= 0.0f);
  }
}

TEST_CASE("move and slide: a crawlspace wedge never squeezes the character through",
          "[character][move]") {
  World w;
  add_floor(w);
  // A ceiling sloping down toward +x: its underside at y = 1.6 - 0.2 x.
  float const slope = std::atan(0.2f);
  Quat const tilt = Quat::from_rotation_z(-slope);
  Vec3 const n = tilt.mul_vec3(Vec3{0, -1, 0}); // the underside's normal
  Vec3 const c = Vec3{0, 1.6f, 0} - n * 0.5f;
  add_box(w, c, {20, 0.5f, 5}, tilt);
  Walk const r = walk(w, {0, 0, 0}, Vec3{5, -1, 0}, 150);
  for (Vec3 const& p : r.path) {
    REQUIRE(gap(w, p) >= -1e-4f);
  }
  // The capsule (2 m tall) fits where the gap to the floor is at least 2 m: x <= 3 minus what
  // its round top gains.
  CHECK(r.path.back().x < 3.2f);
  CHECK(spread(r) < 1e-4f);
}

TEST_CASE("move and slide: a floor-to-ramp crease climbs smoothly", "[character][move]") {
  World w;
  add_floor(w);
  float const angle = 20.0f * std::numbers::pi_v<float> / 180.0f;
  // A slab whose top face rises from the floor at x = 2 with the given angle.
  Quat const tilt = Quat::from_rotation_z(angle);
  Vec3 const top_n = tilt.mul_vec3(Vec3::Y);
  Vec3 const along = tilt.mul_vec3(Vec3::X);
  Vec3 const c = Vec3{2, -1 - skin, 0} + along * 10.0f - top_n * 0.5f; // flush with the floor
  add_box(w, c, {10, 0.5f, 5}, tilt);
  Walk const r = walk(w, {0, 0, 0}, Vec3{5, 0, 0}, 100);
  float prev_speed = 0;
  for (std::size_t f = 1; f < r.path.size(); ++f) {
    INFO("frame " << f);
    Vec3 const step = r.path[f] - r.path[f - 1];
    REQUIRE(step.y >= -1e-5f);                              // never drops
    REQUIRE(step.length() <= 5.0f * dt * 1.001f);           // never launched
    if (f > 5) REQUIRE(step.length() >= 0.5f * prev_speed); // no sudden stop
    prev_speed = step.length();
  }
  CHECK(r.path.back().y > 1.0f); // it got onto the ramp
  CHECK(gap(w, r.path.back()) >= 0.0f);
}

TEST_CASE("move and slide: standing still on a slope does not drift", "[character][move]") {
  World w;
  float const angle = 30.0f * std::numbers::pi_v<float> / 180.0f;
  Quat const tilt = Quat::from_rotation_z(angle);
  add_box(w, tilt.mul_vec3(Vec3{0, -0.5f, 0}), {20, 0.5f, 5}, tilt); // top face through 0
  Vec3 const n = tilt.mul_vec3(Vec3::Y);
  // The upright capsule's bottom sphere (centre 0.5 below the middle) at the skin.
  Vec3 const start = n * (0.5f + skin) + Vec3{0, 0.5f, 0};
  REQUIRE(gap(w, start) == Approx(skin).margin(1e-5));
  // Nothing asked, and a caller pressing the character into the slope along its normal (gravity
  // cancelled but for a stick-to-ground push): neither slides it down the slope.
  for (Vec3 const v : {Vec3{}, n * -0.5f}) {
    Walk const r = walk(w, start, v, 100);
    CHECK((r.path.back() - start).length() < 1e-4f);
    CHECK(gap(w, r.path.back()) >= 0.0f);
  }
}

TEST_CASE("move and slide: seams between adjacent boxes do not bump the character up",
          "[character][move]") {
  World w;
  for (int i = -5; i < 30; ++i)
    add_box(w, {float(i), -1.5f - skin, 0}, {0.5f, 0.5f, 5}); // top faces at y = -1 - skin
  Walk const r = walk(w, {0, 0, 0}, Vec3{5, -2, 0});
  for (Vec3 const& p : r.path) {
    REQUIRE(p.y <= skin);
    REQUIRE(p.y >= -skin);
  }
  CHECK(r.path.back().x == Approx(100 * 5 * dt).epsilon(1e-3));
}

TEST_CASE("move and slide: seams between mesh triangles and height-field cells do not bump "
          "the character up",
          "[character][move][mesh]") {
  // A flat floor of 0.5 m cells, two triangles each (the diagonals run across the path too),
  // as a TriangleMesh and as a HeightField, its top at y = -1 - skin.
  constexpr std::uint32_t n = 80;
  std::vector<float> const heights((n + 1) * (n + 1), 0.0f);
  auto field = HeightField::build(n + 1, n + 1, heights, 0.5f, 0.5f);
  REQUIRE(field.ok());
  // The same vertices and triangles as a mesh (the height field's documented order).
  TriangleMesh mesh = test::make(test::grid(n, 0.5f, [](float, float) { return 0.0f; }));
  Iso3 const at = Iso3::from_translation({-10.0f, -1.0f - skin, -20.0f});
  for (BodyShape const& floor :
       {BodyShape{MeshShape{std::make_shared<TriangleMesh const>(std::move(mesh))}},
        BodyShape{HeightFieldShape{std::make_shared<HeightField const>(std::move(field.field))}}}) {
    World w;
    w.create_body({.type = BodyType::static_body, .pose = at, .shape = floor});
    Walk const r = walk(w, {0, 0, 0}, Vec3{5, -2, 0.7f});
    for (Vec3 const& p : r.path) {
      REQUIRE(p.y <= skin);
      REQUIRE(p.y >= -skin);
    }
    CHECK(r.path.back().x == Approx(100 * 5 * dt).epsilon(1e-3));
    CHECK(r.path.back().z == Approx(100 * 0.7f * dt).epsilon(1e-3));
  }
}

TEST_CASE("move and slide: a thin wall at high speed is never tunnelled", "[character][move]") {
  World w;
  add_box(w, {10, 0, 0}, {0.025f, 5, 5}); // 5 cm thick
  for (float speed : {50.0f, 500.0f, 5000.0f}) {
    INFO("speed " << speed);
    Walk const r = walk(w, {0, 0, 0}, {speed, 0, 0}, 30);
    for (Vec3 const& p : r.path)
      REQUIRE(p.x + 0.5f <= 9.975f);
  }
}

TEST_CASE("move and slide: a corridor exactly as wide as the character passes at full speed",
          "[character][move]") {
  World w;
  add_box(w, {0, 0, 1.0f}, {50, 5, 0.5f});  // z = 0.5
  add_box(w, {0, 0, -1.0f}, {50, 5, 0.5f}); // z = -0.5
  Walk const r = walk(w, {0, 0, 0}, {5, 0, 0});
  CHECK(r.path.back().x == Approx(100 * 5 * dt).epsilon(1e-4));
  // Both walls ask for the skin and cannot both have it: the character stays in the middle,
  // touching both (the mean of the last two depenetration passes), and never jitters.
  for (Vec3 const& p : r.path) {
    REQUIRE(std::abs(p.z) <= 1e-4f);
    REQUIRE(gap(w, p) >= -1e-4f);
  }
}

TEST_CASE("move and slide: a start in overlap is separated after one call", "[character][move]") {
  World w;
  add_box(w, {1, 0, 0}, {0.5f, 5, 5}); // face at x = 0.5; the capsule reaches x = 0.8
  WorldMoveQuery const scene(w);
  Vec3 const start{0.3f, 0, 0};
  REQUIRE(gap(w, start) < -0.2f);
  auto const r =
      move_and_slide(scene, BodyShape{capsule}, Iso3::from_translation(start), Vec3{}, dt);
  CHECK(r.depenetrated);
  CHECK(gap(w, r.position) >= 0.5f * skin);
  CHECK(r.position.x < start.x);
}

TEST_CASE("move and slide: moving away from a wall does not stick", "[character][move]") {
  World w;
  add_box(w, {3, 0, 0}, {0.5f, 5, 5});
  Vec3 const start{2.0f - skin, 0, 0};
  Walk const r = walk(w, start, {-5, 0, 0}, 10);
  CHECK(r.path[0].x == Approx(start.x - 5 * dt).epsilon(1e-5));
  CHECK(r.path.back().x == Approx(start.x - 50 * dt).epsilon(1e-5));
  CHECK(r.log[0].hit_count == 0);
}

TEST_CASE("move and slide: dense nearly parallel planes are merged and the move stays bounded",
          "[character][move]") {
  World w;
  // 40 thin boxes whose faces toward the character are within 3 degrees of each other.
  for (int i = 0; i < 40; ++i) {
    float const yaw = (float(i) / 39.0f - 0.5f) * 3.0f * std::numbers::pi_v<float> / 180.0f;
    add_box(w, {2.6f + 0.0001f * float(i), 0, 0}, {0.1f, 5, 5}, Quat::from_rotation_y(yaw));
  }
  WorldMoveQuery const scene(w);
  std::size_t most = 0, planes = 0;
  bool overflowed = false;
  Vec3 p{};
  for (int f = 0; f < 60; ++f) {
    std::size_t accepted = 0;
    auto const r = move_and_slide(scene, BodyShape{capsule}, Iso3::from_translation(p),
                                  Vec3{5, 0, 1}, dt, {}, {}, [&](MoveHit<ColliderId>&) {
                                    ++accepted;
                                    return HitResponse::accept;
                                  });
    p = r.position;
    most = std::max(most, accepted);
    planes = std::max(planes, r.planes);
    overflowed = overflowed || r.planes_overflowed;
    REQUIRE(gap(w, p) >= -1e-4f);
    REQUIRE(r.planes <= PlaneSetConfig{}.max_planes);
  }
  CHECK(most > 10);     // many planes were offered ...
  CHECK(planes < most); // ... merged into fewer (all within 3 degrees of each other) ...
  CHECK(planes >= 1);
  CHECK(!overflowed);
  CHECK(p.x + 0.5f < 2.5f); // ... and none was crossed
}

TEST_CASE("move and slide: a velocity below epsilon leaves the character in place",
          "[character][move]") {
  World w;
  add_floor(w);
  Walk const r = walk(w, {0, 0, 0}, {1e-4f, 0, 0}, 10);
  CHECK(std::abs(r.path.back().y) < 1e-6f);
  CHECK(std::abs(r.path.back().x) < 1e-4f);
  CHECK(r.log.back().sweeps == 0);
}

TEST_CASE("move and slide: the callback sees the collider touched and its changes are kept",
          "[character][move][callback]") {
  World w;
  BodyId const floor = add_floor(w);
  BodyId const wall = add_box(w, {3, 0, 0}, {0.5f, 5, 5});
  WorldMoveQuery const scene(w);
  Iso3 const start = Iso3::from_translation({1.9f, 0, 0});
  std::vector<MoveHit<ColliderId>> seen;
  auto const r = move_and_slide(scene, BodyShape{capsule}, start, Vec3{6, -1, 0}, dt, {}, {},
                                [&](MoveHit<ColliderId>& h) {
                                  seen.push_back(h);
                                  return HitResponse::accept;
                                });
  REQUIRE(!seen.empty());
  CHECK(seen[0].kind == MoveHitKind::sweep);
  bool floor_seen = false, wall_seen = false;
  for (auto const& h : seen) {
    floor_seen = floor_seen || h.collider == floor;
    wall_seen = wall_seen || h.collider == wall;
    CHECK(h.normal.length() == Approx(1).epsilon(1e-5));
    if (h.collider == wall) CHECK(h.normal.x == Approx(-1).margin(1e-4));
    if (h.collider == floor) CHECK(h.normal.y == Approx(1).margin(1e-4));
  }
  CHECK(floor_seen);
  CHECK(wall_seen);
  // The sweep's distance is the real distance travelled to the hit, not the cast length.
  Vec3 const v{6, -1, 0};
  CHECK(seen[0].distance < v.length() * dt);
  CHECK(seen[0].distance == Approx((seen[0].position - start.translation).length()).margin(1e-6));
  CHECK(seen[0].distance >= 0.0f);
  CHECK(r.hit_count == seen.size());

  // ignore: the plane does not clip; the sweep still stops at the hit.
  auto const ignored =
      move_and_slide(scene, BodyShape{capsule}, Iso3::from_translation({0, 0, 0}), Vec3{200, 0, 0},
                     dt, {}, {}, [&](MoveHit<ColliderId>& h) {
                       return h.collider == wall ? HitResponse::ignore : HitResponse::accept;
                     });
  CHECK(ignored.velocity.x == 200.0f);
  CHECK(ignored.position.x + 0.5f <= 2.5f);
  CHECK(ignored.position.x + 0.5f >= 2.5f - 2 * skin);
  for (auto const& h : ignored.accepted())
    CHECK(h.collider == floor);

  // abort: stops at the first hit.
  int calls = 0;
  auto const aborted = move_and_slide(scene, BodyShape{capsule}, Iso3::from_translation({0, 0, 0}),
                                      Vec3{200, 0, 200}, dt, {}, {}, [&](MoveHit<ColliderId>&) {
                                        ++calls;
                                        return HitResponse::abort;
                                      });
  CHECK(aborted.aborted);
  CHECK(calls == 1);
  CHECK(aborted.sweeps == 1);
  CHECK(aborted.position.x + 0.5f <= 2.5f);
  CHECK(aborted.position.x + 0.5f >= 2.5f - 2 * skin); // it did move up to the hit
  // abort from a contact plane (the floor, after the sweep hit the wall): no more sweeps.
  int contact_calls = 0;
  auto const aborted_contact =
      move_and_slide(scene, BodyShape{capsule}, Iso3::from_translation({0, 0, 0}),
                     Vec3{200, 0, 200}, dt, {}, {}, [&](MoveHit<ColliderId>& h) {
                       if (h.kind != MoveHitKind::contact) return HitResponse::accept;
                       ++contact_calls;
                       return HitResponse::abort;
                     });
  CHECK(aborted_contact.aborted);
  CHECK(contact_calls == 1);
  CHECK(aborted_contact.sweeps == 1);

  // A changed normal is honoured for the sweep's hit: turn the wall into a floor-like plane.
  auto const bent = move_and_slide(scene, BodyShape{capsule}, Iso3::from_translation({1.9f, 2, 0}),
                                   Vec3{6, 0, 0}, dt, {}, {}, [&](MoveHit<ColliderId>& h) {
                                     if (h.collider == wall)
                                       h.normal = Vec3{-std::sqrt(0.5f), std::sqrt(0.5f), 0};
                                     return HitResponse::accept;
                                   });
  CHECK(bent.velocity.y > 2.0f); // deflected upward along the changed plane
  // A changed velocity and position are kept.
  auto const moved = move_and_slide(scene, BodyShape{capsule}, Iso3::from_translation({1.9f, 2, 0}),
                                    Vec3{6, 0, 0}, dt, {}, {}, [&](MoveHit<ColliderId>& h) {
                                      if (h.kind == MoveHitKind::sweep) {
                                        h.velocity = Vec3{0, 0, 3}; // along the wall
                                        h.position = Vec3{0, 2, 0};
                                      }
                                      return HitResponse::accept;
                                    });
  // The rest of the frame (a tenth of it) moves along z from the new position.
  CHECK(moved.velocity.x == 0.0f);
  CHECK(moved.velocity.y == 0.0f);
  CHECK(moved.velocity.z == 3.0f);
  CHECK(moved.position.x == Approx(0).margin(1e-6));
  CHECK(moved.position.z > 0.0f);
  CHECK(moved.position.z < 3.0f * dt);
}

TEST_CASE("move and slide: bad input", "[character][move][bad-input]") {
  World w;
  add_floor(w);
  WorldMoveQuery const scene(w);
  float const nan = std::numeric_limits<float>::quiet_NaN();
  float const inf = std::numeric_limits<float>::infinity();
  Iso3 const at = Iso3::from_translation({0, 0, 0});
  int calls = 0;
  auto const counting = [&](MoveHit<ColliderId>&) {
    ++calls;
    return HitResponse::accept;
  };
  for (float bad : {nan, inf, -1.0f}) {
    auto const a =
        move_and_slide(scene, BodyShape{capsule}, at, Vec3{1, 0, 0}, bad, {}, {}, counting);
    CHECK(a.invalid_input);
    CHECK(a.position.x == 0.0f);
    CHECK(a.velocity.x == 1.0f);
  }
  auto const b = move_and_slide(scene, BodyShape{capsule}, Iso3::from_translation({nan, 0, 0}),
                                Vec3{1, 0, 0}, dt, {}, {}, counting);
  CHECK(b.invalid_input);
  auto const c =
      move_and_slide(scene, BodyShape{capsule}, at, Vec3{inf, 0, 0}, dt, {}, {}, counting);
  CHECK(c.invalid_input);
  CHECK(c.velocity.x == inf); // returned unchanged
  CHECK(calls == 0);
  // dt = 0: only depenetrates.
  auto const d = move_and_slide(scene, BodyShape{capsule}, at, Vec3{5, 0, 0}, 0.0f);
  CHECK(!d.invalid_input);
  CHECK(d.sweeps == 0);
  CHECK(d.position.x == 0.0f);
  // A huge dt is capped at max_move per sweep.
  MoveAndSlideConfig cfg;
  cfg.max_move = 10.0f;
  auto const e = move_and_slide(scene, BodyShape{capsule}, at, Vec3{5, 0, 0}, 1e6f, cfg);
  CHECK(e.position.x <= 10.0f * float(cfg.iterations) + 1e-3f);
  CHECK(e.position.x > 0.0f);
  // A zero-size shape still moves and stops.
  World walls;
  add_box(walls, {3, 0, 0}, {0.5f, 5, 5});
  Walk const dot = walk(walls, {0, 0, 0}, {5, 0, 0}, 60, {}, BodyShape{Sphere{0.0f}});
  CHECK(dot.path.back().x <= 2.5f);
  CHECK(dot.path.back().x >= 2.5f - 2 * skin);
  // A callback that aborts at once still depenetrates.
  World deep;
  add_box(deep, {1, 0, 0}, {0.5f, 5, 5});
  auto const f = move_and_slide(WorldMoveQuery(deep), BodyShape{capsule},
                                Iso3::from_translation({0.3f, 0, 0}), Vec3{5, 0, 0}, dt, {}, {},
                                [](MoveHit<ColliderId>&) { return HitResponse::abort; });
  CHECK(f.aborted);
  CHECK(gap(deep, f.position) >= 0.5f * skin);
}

TEST_CASE("move and slide: user planes hold from the first sweep, hit or not",
          "[character][move][user-planes]") {
  World empty;
  WorldMoveQuery const scene(empty);
  Vec3 const up[] = {Vec3::Y}; // an invisible floor through the character's position
  MoveAndSlideConfig cfg;
  cfg.user_planes = up;
  Vec3 p{};
  for (int f = 0; f < 30; ++f) {
    auto const r = move_and_slide(scene, BodyShape{capsule}, Iso3::from_translation(p),
                                  Vec3{5, -3, 0}, dt, cfg);
    p = r.position;
    REQUIRE(r.velocity.y >= -cfg.projection.epsilon);
    REQUIRE(p.y >= -1e-5f);
  }
  CHECK(p.x == Approx(30 * 5 * dt).epsilon(1e-4));
}

TEST_CASE("move and slide: a start deep inside is pushed out over calls, never swept through",
          "[character][move][deep]") {
  World w;
  add_box(w, {0, 0, 0}, {1, 1, 1});
  Capsule const small{0.3f, 0.3f};
  Vec3 p{0.2f, 0, 0}; // the capsule's core inside the box, 1.1 from the +x face
  bool pushed_out = false;
  for (int f = 0; f < 10; ++f) {
    auto const r = move_and_slide(WorldMoveQuery(w), BodyShape{small}, Iso3::from_translation(p),
                                  Vec3{-5, 0, 0}, dt); // walking inward
    INFO("frame " << f);
    if (f == 0) CHECK(r.deep_start);
    if (r.deep_start) {
      CHECK(r.sweeps == 0);
      CHECK(r.position.x > p.x); // out through the nearest face, against the walk
    }
    p = r.position;
    pushed_out = pushed_out || !r.deep_start;
  }
  CHECK(pushed_out);
  CHECK(p.x - 0.3f >= 1.0f);            // outside the box's +x face ...
  CHECK(p.x - 0.3f <= 1.0f + 2 * skin); // ... and then held at it by the walk
}

TEST_CASE("move and slide: a depenetration out of a narrow V does not push into what it "
          "had not seen",
          "[character][move][deep]") {
  // A ball pressed 0.1 into both walls of a V whose normals are 138 degrees apart: the push
  // out, 0.11 along each normal, is 0.31 up the V (depth over the cosine of the half angle),
  // and a sloped overhang 0.02 above the ball (facing down and toward -z) lies in the way.
  // The contacts were gathered within the skin only, so the overhang was no pair, and the
  // push ended 0.16 deep in it with the depenetration reported converged (the fuzz target's
  // deeper-after-depenetration-2: there the V was a half-space and a cylinder, the overhang a
  // second half-space, and it was move_and_slide's last depenetration).
  World w;
  float const r = 0.5f, a = 69.0f * std::numbers::pi_v<float> / 180.0f;
  auto const wall = [&](Vec3 const& n, float gap) {
    return w
        .create_body({.type = BodyType::static_body,
                      .pose = Iso3::from_translation(-n * (r + gap)),
                      .shape = HalfSpace{n}})
        .id;
  };
  wall({std::sin(a), std::cos(a), 0}, -0.1f);
  wall({-std::sin(a), std::cos(a), 0}, -0.1f);
  wall(Vec3{0, -0.6f, -0.8f}, 0.02f); // the overhang
  Sphere const ball{r};
  auto const deepest = [&](Vec3 const& p) { return ::deepest(w, ball, p); };
  REQUIRE(deepest({0, 0, 0}) == Approx(0.1f).margin(1e-4f));
  WorldMoveQuery const scene(w);
  // Converged means out of everything, whatever the passes.
  for (int passes : {16, 32}) {
    INFO("passes " << passes);
    MoveAndSlideConfig cfg;
    cfg.depenetration.iterations = passes;
    MoveDepenetration const d = depenetrate(scene, BodyShape{ball}, Iso3::IDENTITY, cfg);
    CHECK((!d.converged || deepest(d.correction) <= 1e-3f));
    if (passes == 32) { // three planes this far apart take 20-odd passes
      CHECK(d.converged);
      CHECK(deepest(d.correction) <= 1e-3f); // out of all three, the overhang included
      CHECK(d.correction.z < -0.1f);         // up the V and out from under the overhang
    }
  }
  auto const res = move_and_slide(scene, BodyShape{ball}, Iso3::IDENTITY, Vec3{}, 0.0f);
  CHECK(deepest(res.position) <= 1e-3f);
}

namespace {
/// A MoveQuery whose contacts are given: each query reports every listed contact whose
/// separation is below the distance asked for, and counts the queries.
struct ListedContacts {
  using shape_type = Sphere;
  using filter_type = int;
  using collider_id = int;
  std::vector<MoveContact<int>> list;
  mutable int queries = 0;
  std::optional<MoveCastHit<int>> cast(Sphere const&, Iso3 const&, Vec3 const&, int) const {
    return std::nullopt;
  }
  template <class Sink>
  void contacts(Sphere const&, Iso3 const&, float distance, int, Sink&& sink) const {
    ++queries;
    for (MoveContact<int> const& c : list)
      if (c.separation < distance && !sink(c)) return;
  }
};
} // namespace

TEST_CASE("move and slide: depenetrate(query) on a contact without a direction, and a push "
          "that keeps meeting more",
          "[character][move][bad-input]") {
  MoveAndSlideConfig const cfg;
  SECTION("a NaN normal: the pair is ignored (depenetrate's contract)") {
    ListedContacts q;
    float const nan = std::numeric_limits<float>::quiet_NaN();
    q.list = {{0, {}, {nan, 1, 0}, -0.1f}};
    MoveDepenetration const d = depenetrate(q, Sphere{0.5f}, Iso3::IDENTITY, cfg);
    CHECK(d.correction.length() == 0.0f);
    CHECK(d.converged);
  }
  SECTION("a fix that overflows: no correction, not converged") {
    // Depths near float's largest, allowed by a threshold as large, between walls 160
    // degrees apart: the fix, the depths over cos(80 deg), is beyond float.
    MoveAndSlideConfig huge = cfg;
    huge.depenetration.rejection_threshold = 3e38f;
    ListedContacts q;
    float const a = 80.0f * std::numbers::pi_v<float> / 180.0f;
    q.list = {{0, {}, {std::sin(a), std::cos(a), 0}, -3e38f},
              {1, {}, {-std::sin(a), std::cos(a), 0}, -3e38f}};
    MoveDepenetration const d = depenetrate(q, Sphere{0.5f}, Iso3::IDENTITY, huge);
    CHECK(d.correction.length() == 0.0f);
    CHECK_FALSE(d.converged);
  }
  SECTION("contacts at every distance: at most max_depenetration_queries queries, cut to the "
          "last distance gathered") {
    // Two walls 160 degrees apart push 3 m up the V; planes facing down lie 0.3, 0.6, ...
    // above, each met only by a query that reaches it (ListedContacts ignores the pose, so
    // every round sees the pairs as at the start).
    ListedContacts q;
    float const a = 80.0f * std::numbers::pi_v<float> / 180.0f;
    q.list = {{0, {}, {std::sin(a), std::cos(a), 0}, -0.25f},
              {1, {}, {-std::sin(a), std::cos(a), 0}, -0.25f}};
    for (int k = 1; k <= 12; ++k)
      q.list.push_back({2 + k, {}, {0.1f, -0.99f, 0}, 0.04f * float(k)});
    MoveDepenetration const d = depenetrate(q, Sphere{0.5f}, Iso3::IDENTITY, cfg);
    CHECK(q.queries >= 2);
    CHECK(q.queries <= max_depenetration_queries);
    CHECK(d.correction.is_finite());
    CHECK(d.correction.length() <= max_depenetration_move(cfg) * (1 + 1e-6f));
    CHECK_FALSE(d.converged);
  }
}

TEST_CASE("move and slide: a depenetration moves at most one push per call, out of a slot "
          "over several calls",
          "[character][move][deep]") {
  // A ball wedged 0.3 deep into both walls of a slot whose walls lean 5 degrees from
  // vertical: the fix that satisfies both is 0.3 / cos(85 deg) = 3.4 up the slot. One call
  // used to take all of it (the fuzz target's move-beyond-bound: 9.97 from four colliders
  // and a rejection threshold of 0.89); now each call moves at most
  // max_depenetration_move(cfg) and the calls go on until the ball is out.
  World w;
  float const r = 0.5f, a = 85.0f * std::numbers::pi_v<float> / 180.0f;
  for (float side : {1.0f, -1.0f}) {
    Vec3 const n{side * std::sin(a), std::cos(a), 0};
    REQUIRE(w.create_body({.type = BodyType::static_body,
                           .pose = Iso3::from_translation(-n * (r - 0.3f)),
                           .shape = HalfSpace{n}}));
  }
  Sphere const ball{r};
  auto const deepest = [&](Vec3 const& p) { return ::deepest(w, ball, p); };
  REQUIRE(deepest({0, 0, 0}) == Approx(0.3f).margin(1e-4f));
  WorldMoveQuery const scene(w);
  MoveAndSlideConfig const cfg;
  float const most = max_depenetration_move(cfg);
  REQUIRE(most == Approx(cfg.depenetration.rejection_threshold + cfg.skin));
  MoveDepenetration const d = depenetrate(scene, BodyShape{ball}, Iso3::IDENTITY, cfg);
  CHECK(d.correction.length() <= most * (1 + 1e-6f));
  CHECK(d.correction.length() >= most * 0.99f); // cut, not dropped
  CHECK_FALSE(d.converged);
  CHECK(d.correction.y > 0.9f * d.correction.length()); // up the slot
  Vec3 p{};
  int calls = 0;
  for (; calls < 20 && deepest(p) > 1e-3f; ++calls) {
    auto const res =
        move_and_slide(scene, BodyShape{ball}, Iso3::from_translation(p), Vec3{}, 0.0f, cfg);
    REQUIRE(res.position.is_finite());
    CHECK((res.position - p).length() <= 2 * most * (1 + 1e-6f));
    p = res.position;
  }
  CHECK(deepest(p) <= 1e-3f);
  CHECK(calls >= 3); // 3.4 at two pushes of 0.51 a call
  CHECK(calls <= 6);
}

TEST_CASE("move and slide: a box straddling a lone triangle's plane is not pushed along its "
          "face over the edge that clips it",
          "[character][move][mesh]") {
  // The fuzz target's deeper-after-depenetration: a box whose centre lies in the plane of a
  // lone triangle (x = y), whose boundary edge clips the box's corner 0.0107 deep. Its
  // normal points across the plane, so the mesh turns it to the face normal, and the gap of
  // the witness points along that normal came out +0.0056: the depenetration pushed the box
  // 0.059 along the face, which slid its side further over the edge, 0.0415 deep.
  std::vector<Vec3> const v{{-3, -3, -2.7647059f},
                            {-2.7647059f, -2.7647059f, 1.14941645f},
                            {1.16470623f, 1.16470623f, 1.77409029f}};
  std::vector<std::uint32_t> const idx{0, 1, 2};
  auto built = TriangleMesh::build(v, idx);
  REQUIRE(built.ok());
  Triangle const tri = built.mesh.triangle(0);
  Iso3 const mesh_at = Iso3::from_translation({-3, -3, -3});
  World w;
  REQUIRE(w.create_body(
      {.type = BodyType::static_body,
       .pose = mesh_at,
       .shape = MeshShape{std::make_shared<TriangleMesh const>(std::move(built.mesh))}}));
  Cuboid const box{{0.431764722f, 0.652848065f, 0.05f}};
  Iso3 const start = Iso3::from_translation({-3, -3, -3});
  float const before = penetration(box, start, tri, mesh_at).depth;
  REQUIRE(before == Approx(0.0107f).margin(1e-4f));
  MoveAndSlideConfig cfg;
  cfg.skin = 0.0398039222f;
  cfg.plane_distance = 2 * cfg.skin;
  auto const r = move_and_slide(WorldMoveQuery(w), BodyShape{box}, start, Vec3{}, 0.0f, cfg);
  REQUIRE(r.position.is_finite());
  CHECK(penetration(box, Iso3::from_translation(r.position), tri, mesh_at).depth <= before);
}

TEST_CASE("move and slide: a box in front of a triangle, hanging over its boundary edge, is "
          "pushed off the edge",
          "[character][move][mesh]") {
  // The fuzz target's deeper-after-depenetration-3: the box above, its centre 0.071 in front
  // of the triangle's plane, 0.0738 deep over its boundary edge. EPA's normal leans to the
  // back; the mesh turned it to the face normal with a gap of +0.037 along it, inside the
  // skin: both depenetrations pushed the box along the face (0.0027, then 0.0020), further
  // over the edge: 0.0751, then 0.0762 deep, reported converged.
  std::vector<Vec3> const v{{-3, -3, -2.7647059f},
                            {-2.7647059f, -2.7647059f, 1.14941645f},
                            {1.30533314f, 1.16470623f, 1.77409029f},
                            {1.77647066f, 1.77647066f, 1.77647066f}};
  std::vector<std::uint32_t> const idx{0, 1, 2, 2, 1, 3};
  auto built = TriangleMesh::build(v, idx);
  REQUIRE(built.ok());
  Triangle const tri = built.mesh.triangle(0);
  Iso3 const mesh_at = Iso3::from_translation({-3, -3, -3});
  World w;
  REQUIRE(w.create_body(
      {.type = BodyType::static_body,
       .pose = mesh_at,
       .shape = MeshShape{std::make_shared<TriangleMesh const>(std::move(built.mesh))}}));
  Cuboid const box{{0.431764722f, 0.652848065f, 0.05f}};
  Iso3 const start = Iso3::from_translation({-3, -3, -3});
  float const before = penetration(box, start, tri, mesh_at).depth;
  REQUIRE(before == Approx(0.0738f).margin(1e-4f));
  MoveAndSlideConfig cfg;
  cfg.skin = 0.0398039222f;
  cfg.plane_distance = 2 * cfg.skin;
  auto const r = move_and_slide(WorldMoveQuery(w), BodyShape{box}, start, Vec3{}, 0.0f, cfg);
  REQUIRE(r.position.is_finite());
  CHECK(r.depenetrated);
  float const after = penetration(box, Iso3::from_translation(r.position), tri, mesh_at).depth;
  CHECK(after <= 0.0f); // off the edge (by the skin)
}

TEST_CASE("move and slide: callbacks that set NaN, and |v| dt beyond a float",
          "[character][move][bad-input]") {
  World w;
  add_box(w, {3, 0, 0}, {0.5f, 5, 5});
  WorldMoveQuery const scene(w);
  float const nan = std::numeric_limits<float>::quiet_NaN();
  auto const r = move_and_slide(scene, BodyShape{capsule}, Iso3::from_translation({1.9f, 0, 0}),
                                Vec3{6, 0, 0}, dt, {}, {}, [&](MoveHit<ColliderId>& h) {
                                  h.position = Vec3{nan, 0, 0};
                                  h.velocity = Vec3{nan, nan, nan};
                                  h.normal = Vec3{nan, 0, 0};
                                  return HitResponse::accept;
                                });
  CHECK(r.position.is_finite());
  CHECK(r.velocity.is_finite());
  CHECK(r.position.x + 0.5f <= 2.5f);
  // ... also when the callback then aborts (no projection runs after it).
  auto const a = move_and_slide(scene, BodyShape{capsule}, Iso3::from_translation({1.9f, 0, 0}),
                                Vec3{6, 0, 0}, dt, {}, {}, [&](MoveHit<ColliderId>& h) {
                                  h.velocity = Vec3{nan, nan, nan};
                                  return HitResponse::abort;
                                });
  CHECK(a.aborted);
  CHECK(a.velocity.is_finite());
  // |v| dt overflows: the call still moves, at most iterations x max_move.
  World open;
  auto const far =
      move_and_slide(WorldMoveQuery(open), BodyShape{capsule}, Iso3{}, Vec3{1e4f, 0, 0}, 1e36f);
  CHECK(!far.invalid_input);
  CHECK(far.position.x > 0.0f);
  CHECK(far.position.x <= MoveAndSlideConfig{}.max_move * 4 + 1e-3f);
}

TEST_CASE("move and slide: cast_move and intersections on their own, bad input",
          "[character][move][bad-input]") {
  World w;
  add_box(w, {3, 0, 0}, {0.5f, 5, 5});
  WorldMoveQuery const scene(w);
  Iso3 const at = Iso3::from_translation({0, 0, 0});
  // A clear cast: the whole motion. A blocked one: up to a skin from the wall.
  CHECK(cast_move(scene, BodyShape{capsule}, at, Vec3{1, 0, 0}).safe == 1.0f);
  auto const blocked = cast_move(scene, BodyShape{capsule}, at, Vec3{4, 0, 0});
  REQUIRE(blocked.hit);
  CHECK(blocked.safe == Approx(2.0f - skin).margin(1e-4));
  CHECK(blocked.approach == Approx(1).margin(1e-4));
  // Zero, NaN and infinite motion: no hit, nothing safe.
  float const nan = std::numeric_limits<float>::quiet_NaN();
  for (Vec3 const m :
       {Vec3{}, Vec3{nan, 0, 0}, Vec3{std::numeric_limits<float>::infinity(), 0, 0}}) {
    auto const c = cast_move(scene, BodyShape{capsule}, at, m);
    CHECK(!c.hit);
    CHECK(c.safe == 0.0f);
  }
  // intersections: the wall within 2.1 of the capsule's side, not within 1.9; stop on false.
  int found = 0;
  intersections(scene, BodyShape{capsule}, at, 2.1f, {}, [&](MoveContact<ColliderId> const& c) {
    ++found;
    CHECK(c.separation == Approx(2.0f).margin(1e-4));
    CHECK(c.normal.x == Approx(-1).margin(1e-4));
    return false;
  });
  CHECK(found == 1);
  intersections(scene, BodyShape{capsule}, at, 1.9f, {}, [&](MoveContact<ColliderId> const&) {
    ++found;
    return true;
  });
  CHECK(found == 1);
}

TEST_CASE("cast providers give a unit normal when the cores overlap at the start",
          "[character][move][fuzz]") {
  // The capsule's core segment inside a box: the shape cast has no normal there (its contract:
  // zero), and the providers used to pass it on as the hit normal (a fuzz finding,
  // move_and_slide regress-sweep-hit-zero-normal). The contact manifold's normal (+x, the
  // nearest face) takes its place; a motion out of the box ignores the start.
  std::vector<Collider> const level = {{Cuboid{Vec3{1, 1, 1}}, Iso3{}}};
  ColliderSetQuery<Capsule> const set(level);
  World w;
  add_box(w, {0, 0, 0}, {1, 1, 1});
  WorldMoveQuery const world(w);
  Iso3 const inside = Iso3::from_translation({0.6f, 0, 0});
  Vec3 const in{-1, 0, 0}, out{1, 0, 0}, along{0, 0, 1};
  auto const a = set.cast(capsule, inside, in, {});
  auto const b = world.cast(BodyShape{capsule}, inside, in, {});
  REQUIRE(a);
  REQUIRE(b);
  CHECK(a->toi == 0.0f);
  CHECK(b->toi == 0.0f);
  CHECK(a->normal.distance(Vec3{1, 0, 0}) <= 1e-5f);
  CHECK(b->normal.distance(Vec3{1, 0, 0}) <= 1e-5f);
  CHECK(a->point.x == Approx(1.0f).margin(1e-5));
  CHECK(!set.cast(capsule, inside, out, {}));
  CHECK(!world.cast(BodyShape{capsule}, inside, out, {}));
  CHECK(!set.cast(capsule, inside, along, {}));
  CHECK(!world.cast(BodyShape{capsule}, inside, along, {}));
  // The batch cast gives each lane what cast() gives.
  std::vector<BodyShape> const shapes(3, BodyShape{capsule});
  std::vector<Iso3> const poses(3, inside);
  std::vector<Vec3> const motions{in, out, along};
  std::vector<std::optional<MoveCastHit<ColliderId>>> lanes(3);
  world.cast_lanes(shapes, poses, motions, {}, lanes);
  REQUIRE(lanes[0]);
  CHECK(lanes[0]->normal.distance(b->normal) == 0.0f);
  CHECK(!lanes[1]);
  CHECK(!lanes[2]);
  // A second box the motion runs into after leaving the first: found past the ignored start.
  World two;
  add_box(two, {0, 0, 0}, {1, 1, 1});
  BodyId const far = add_box(two, {5, 0, 0}, {1, 1, 1});
  auto const next = WorldMoveQuery(two).cast(BodyShape{capsule}, inside, Vec3{5, 0, 0}, {});
  REQUIRE(next);
  CHECK(next->collider == far);
  CHECK(next->normal.distance(Vec3{-1, 0, 0}) <= 1e-5f);
}

TEST_CASE("cast providers weigh every manifold of a mesh the cores overlap",
          "[character][move][mesh]") {
  // An L of a floor (y = 0, facing +y) and a wall (x = 1, facing -x) in one mesh body. A
  // capsule's core crosses the floor and its radius reaches into the wall: the cast has no
  // normal, and the mesh gives one manifold per face. The hit is the one the motion runs
  // into: the wall for +x, the floor for -y; a motion that leaves or runs along both is no
  // hit. (Looking at the first manifold only let one of the two through, whichever came
  // first.)
  std::vector<Vec3> const v = {{-4, 0, -4}, {1, 0, -4}, {-4, 0, 4}, {1, 0, 4},
                               {1, 0, -4},  {1, 4, -4}, {1, 0, 4},  {1, 4, 4}};
  std::vector<std::uint32_t> const idx = {0, 2, 1, 1, 2, 3, 4, 6, 5, 5, 6, 7};
  auto built = TriangleMesh::build(v, idx);
  REQUIRE(built.ok());
  World w;
  REQUIRE(w.create_body(
      {.type = BodyType::static_body,
       .shape = MeshShape{std::make_shared<TriangleMesh const>(std::move(built.mesh))}}));
  WorldMoveQuery const scene(w);
  Capsule const thin{0.5f, 0.3f};
  Iso3 const at = Iso3::from_translation({0.8f, 0.45f, 0}); // core from y = -0.05 to 0.95
  auto const into_wall = scene.cast(BodyShape{thin}, at, Vec3{1, 0, 0}, {});
  REQUIRE(into_wall);
  CHECK(into_wall->toi == 0.0f);
  CHECK(into_wall->normal.distance(Vec3{-1, 0, 0}) <= 1e-4f);
  auto const into_floor = scene.cast(BodyShape{thin}, at, Vec3{0, -1, 0}, {});
  REQUIRE(into_floor);
  CHECK(into_floor->toi == 0.0f);
  CHECK(into_floor->normal.distance(Vec3{0, 1, 0}) <= 1e-4f);
  CHECK(!scene.cast(BodyShape{thin}, at, Vec3{-1, 0, 0}, {}));
  CHECK(!scene.cast(BodyShape{thin}, at, Vec3{0, 0, 1}, {}));
}

TEST_CASE("move and slide: config scaled to centimetres gives the same path, scaled",
          "[character][move]") {
  World m, cm;
  add_box(m, {3, 0, 0}, {0.5f, 5, 50});
  add_box(cm, {300, 0, 0}, {50, 500, 5000});
  MoveAndSlideConfig const cfg_cm = MoveAndSlideConfig{}.scaled(100.0f);
  Walk const a = walk(m, {0, 0, 0}, dir(30) * 5.0f, 60);
  Walk const b = walk(cm, {0, 0, 0}, dir(30) * 500.0f, 60, cfg_cm, BodyShape{Capsule{50, 50}});
  for (std::size_t f = 0; f < a.path.size(); ++f) {
    INFO("frame " << f);
    REQUIRE((b.path[f] * 0.01f - a.path[f]).length() < 1e-3f);
  }
}

TEST_CASE("move and slide: a ColliderSetQuery gives the world's path, bit for bit",
          "[character][move][collider-set]") {
  // The same static boxes and a hull as world bodies and as a user's collider span.
  std::vector<Collider> level = {
      {Cuboid{Vec3{20, 0.5f, 20}}, Iso3::from_translation({0, -1.5f - skin, 0})},
      {Cuboid{Vec3{0.5f, 3, 6}}, Iso3::from_translation({4, 0, 0})},
      {Cuboid{Vec3{6, 3, 0.5f}}, Iso3::from_translation({0, 0, 4})},
      {Cuboid{Vec3{3, 0.5f, 3}}, Iso3{Quat::from_rotation_z(0.3f), {-5, -1.2f, 0}}},
      {ConvexHull::build(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}).hull,
       Iso3::from_translation({-2, -1, -3})},
  };
  World w;
  for (Collider const& c : level)
    w.create_body({.type = BodyType::static_body,
                   .pose = c.pose,
                   .shape = std::visit([](auto const& s) { return BodyShape{s}; }, c.shape)});
  ColliderSetQuery<Capsule> const set(level);
  WorldMoveQuery const world(w);
  Vec3 a{0, 0, 0}, b{0, 0, 0};
  std::vector<std::uint32_t> touched;
  for (int f = 0; f < 240; ++f) {
    float const t = float(f) * dt;
    Vec3 const desired{5 * std::cos(0.7f * t), -2, 5 * std::sin(1.3f * t)};
    auto const ra =
        move_and_slide(world, BodyShape{capsule}, Iso3::from_translation(a), desired, dt, {}, {},
                       [](MoveHit<ColliderId>&) { return HitResponse::accept; });
    auto const rb = move_and_slide(set, capsule, Iso3::from_translation(b), desired, dt, {}, {},
                                   [&](MoveHit<std::uint32_t>& h) {
                                     touched.push_back(h.collider);
                                     return HitResponse::accept;
                                   });
    a = ra.position;
    b = rb.position;
    INFO("frame " << f);
    REQUIRE(a.x == b.x);
    REQUIRE(a.y == b.y);
    REQUIRE(a.z == b.z);
    REQUIRE(ra.velocity.x == rb.velocity.x);
    REQUIRE(ra.hit_count == rb.hit_count);
  }
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  CHECK(touched.size() >= 3); // the floor and both walls at least

  // Filters: an excluded or masked-out wall is walked through.
  std::uint32_t const wall[] = {1};
  auto const through = move_and_slide(set, capsule, Iso3::from_translation({2.9f, 0, 0}),
                                      Vec3{60, 0, 0}, dt, {}, {.exclude = wall});
  CHECK(through.position.x > 3.5f);
  level[1].layers = 2;
  auto const masked = move_and_slide(set, capsule, Iso3::from_translation({2.9f, 0, 0}),
                                     Vec3{60, 0, 0}, dt, {}, {.mask = 1});
  CHECK(masked.position.x > 3.5f);
  auto const blocked =
      move_and_slide(set, capsule, Iso3::from_translation({2.9f, 0, 0}), Vec3{60, 0, 0}, dt);
  CHECK(blocked.position.x + 0.5f <= 3.5f);
  // A collider with a non-finite pose is never hit; a non-finite query finds nothing.
  level[1].pose.translation.x = std::numeric_limits<float>::quiet_NaN();
  auto const bad =
      move_and_slide(set, capsule, Iso3::from_translation({2.9f, 0, 0}), Vec3{60, 0, 0}, dt);
  CHECK(bad.position.x > 3.5f);
  CHECK(!set.cast(capsule, Iso3::from_translation({std::numeric_limits<float>::infinity(), 0, 0}),
                  Vec3{1, 0, 0}, {}));
}

namespace {

/// Two results are the same, bit for bit: position, velocity, flags and every kept hit.
void require_same(MoveAndSlideResult<ColliderId> const& a,
                  MoveAndSlideResult<ColliderId> const& b) {
  REQUIRE(test::same_bits(a.position, b.position));
  REQUIRE(test::same_bits(a.velocity, b.velocity));
  REQUIRE(a.sweeps == b.sweeps);
  REQUIRE(a.aborted == b.aborted);
  REQUIRE(a.invalid_input == b.invalid_input);
  REQUIRE(a.depenetrated == b.depenetrated);
  REQUIRE(a.deep_start == b.deep_start);
  REQUIRE(a.planes == b.planes);
  REQUIRE(a.planes_overflowed == b.planes_overflowed);
  REQUIRE(a.hit_count == b.hit_count);
  REQUIRE(a.hits_dropped == b.hits_dropped);
  for (std::size_t h = 0; h < a.hit_count; ++h) {
    REQUIRE(a.hits[h].collider == b.hits[h].collider);
    REQUIRE(a.hits[h].kind == b.hits[h].kind);
    REQUIRE(a.hits[h].iteration == b.hits[h].iteration);
    REQUIRE(test::same_bits(a.hits[h].point, b.hits[h].point));
    REQUIRE(test::same_bits(a.hits[h].normal, b.hits[h].normal));
    REQUIRE(test::same_bits(a.hits[h].position, b.hits[h].position));
    REQUIRE(test::same_bits(a.hits[h].velocity, b.hits[h].velocity));
    REQUIRE(test::same_bits(a.hits[h].distance, b.hits[h].distance));
    REQUIRE(test::same_bits(a.hits[h].separation, b.hits[h].separation));
    REQUIRE(a.hits[h].touching == b.hits[h].touching);
  }
}

} // namespace

TEST_CASE("move and slide: W characters in lanes move exactly as each one alone",
          "[character][move][lanes]") {
  // A level of boxes, a ramp, a hull and a mesh floor patch; a crowd of capsules of different
  // sizes walking in different directions, some starting in overlap, one with a NaN pose, one
  // whose callback aborts and one that ignores walls, over 90 frames, through the world
  // (cast_lanes: the world's batch casts) and through a ColliderSetQuery (one cast at a time).
  World w;
  add_floor(w);
  add_box(w, {4, 0, 0}, {0.5f, 3, 6});
  add_box(w, {0, 0, 4}, {6, 3, 0.5f});
  add_box(w, {-5, -1.2f, 0}, {3, 0.5f, 3}, Quat::from_rotation_z(0.3f));
  add_box(w, {1.5f, -0.7f, 1.5f}, {0.4f, 0.3f, 0.4f});
  auto mesh = std::make_shared<TriangleMesh const>(
      test::make(test::grid(6, 0.5f, [](float x, float z) { return 0.05f * x + 0.02f * z; })));
  w.create_body({.type = BodyType::static_body,
                 .pose = Iso3::from_translation({-2, -1.0f - skin, -4}),
                 .shape = MeshShape{mesh}});
  WorldMoveQuery const scene(w);
  std::vector<Collider> level = {
      {Cuboid{Vec3{20, 0.5f, 20}}, Iso3::from_translation({0, -1.5f - skin, 0})},
      {Cuboid{Vec3{0.5f, 3, 6}}, Iso3::from_translation({4, 0, 0})},
      {ConvexHull::build(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}).hull,
       Iso3::from_translation({-2, -1, -3})},
  };
  ColliderSetQuery<Capsule> const set(level);
  auto const run = [&]<class T>() {
    constexpr std::size_t W = lanes_v<T>;
    std::vector<BodyShape> shapes;
    std::vector<Capsule> capsules;
    std::array<Vec3, W> pos, vel;
    for (std::size_t k = 0; k < W; ++k) {
      capsules.push_back(Capsule{0.3f + 0.04f * float(k % 3), 0.3f + 0.05f * float(k % 4)});
      shapes.push_back(capsules.back());
      pos[k] = {-1.0f + 0.7f * float(k % 4), -0.2f + 0.01f * float(k), -1.0f + 0.6f * float(k / 4)};
      vel[k] = {5 * std::cos(0.9f * float(k)), -2, 5 * std::sin(1.7f * float(k))};
    }
    if (W > 2) pos[2] = {3.7f, 0, 0}; // starts in the wall
    if (W > 3) pos[3].x = std::numeric_limits<float>::quiet_NaN();
    auto const respond = [](std::size_t lane, auto& h) {
      if (lane == 1 && h.iteration == 1) return HitResponse::abort;
      if (lane % 4 == 0 && std::abs(h.normal.y) < 0.5f) return HitResponse::ignore;
      return HitResponse::accept;
    };
    MoveAndSlideConfig cfg;
    Vec3 const ceiling[] = {Vec3{0, -1, 0}};
    int walls = 0;
    for (int frame = 0; frame < 90; ++frame) {
      if (frame == 45) cfg.user_planes = ceiling;
      std::array<Quat, W> rot;
      rot.fill(Quat::IDENTITY);
      GIso3<T> const poses{pack<T>(rot.data()), pack<T>(pos.data())};
      auto const lanes = move_and_slide_lanes<T>(scene, std::span<BodyShape const>(shapes), poses,
                                                 pack<T>(vel.data()), dt, cfg, {}, respond);
      auto const lanes_set = move_and_slide_lanes<T>(set, std::span<Capsule const>(capsules), poses,
                                                     pack<T>(vel.data()), dt, cfg, {}, respond);
      std::array<Vec3, W> next;
      unpack(lanes.position, next.data());
      for (std::size_t k = 0; k < W; ++k) {
        INFO("width " << W << ", frame " << frame << ", lane " << k);
        auto const one =
            move_and_slide(scene, shapes[k], Iso3::from_translation(pos[k]), vel[k], dt, cfg, {},
                           [&](MoveHit<ColliderId>& h) { return respond(k, h); });
        require_same(lanes.lanes[k], one);
        REQUIRE(test::same_bits(next[k], one.position));
        auto const one_set =
            move_and_slide(set, capsules[k], Iso3::from_translation(pos[k]), vel[k], dt, cfg, {},
                           [&](MoveHit<std::uint32_t>& h) { return respond(k, h); });
        REQUIRE(test::same_bits(lanes_set.lanes[k].position, one_set.position));
        REQUIRE(test::same_bits(lanes_set.lanes[k].velocity, one_set.velocity));
        REQUIRE(lanes_set.lanes[k].sweeps == one_set.sweeps);
        REQUIRE(lanes_set.lanes[k].hit_count == one_set.hit_count);
        for (auto const& h : one.accepted())
          walls += std::abs(h.normal.y) < 0.5f ? 1 : 0;
      }
      for (std::size_t k = 0; k < W; ++k)
        if (!lanes.lanes[k].invalid_input) pos[k] = lanes.lanes[k].position;
    }
    if (W > 3) CHECK(std::isnan(pos[3].x)); // never moved: invalid input
    if (W > 1) CHECK(walls > 0);            // the walls were met
  };
  run.template operator()<float>();
  for_each_type<test::f32_wide_types>(run);
  // A shape count other than the width is refused.
  std::vector<BodyShape> two(2, BodyShape{capsule});
  CHECK_THROWS_AS(move_and_slide_lanes<float>(scene, std::span<BodyShape const>(two), Iso3{},
                                              Vec3{}, dt, {}, {}, AcceptAllHits{}),
                  std::invalid_argument);
  // cast_lanes: spans of different lengths are refused, nothing written; each answer is cast()'s.
  std::vector<Iso3> at(2, Iso3::from_translation({0, 0, 0}));
  std::vector<Vec3> go{{10, 0, 0}, {0, 0, 10}};
  std::vector<std::optional<MoveCastHit<ColliderId>>> one_out(1);
  CHECK_THROWS_AS(scene.cast_lanes(two, at, go, {}, one_out), std::invalid_argument);
  CHECK(!one_out[0]);
  std::vector<std::optional<MoveCastHit<ColliderId>>> out(2);
  scene.cast_lanes(two, at, go, {}, out);
  for (std::size_t k = 0; k < 2; ++k) {
    auto const single = scene.cast(two[k], at[k], go[k], {});
    REQUIRE(out[k].has_value() == single.has_value());
    if (single) {
      CHECK(out[k]->collider == single->collider);
      CHECK(test::same_bits(out[k]->toi, single->toi));
      CHECK(test::same_bits(out[k]->normal, single->normal));
    }
  }
  CHECK(out[0].has_value()); // the wall at x = 3.5
}
