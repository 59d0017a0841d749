// Standalone colliders (World::create_collider): shapes without a body. Ids and slots, bad
// input, contacts exactly as a static body's, triggers, teleports, destruction mid-contact,
// continuous collision against them, and every query naming them by ColliderId. (The
// brute-force query tests in test_queries.cpp put standalone colliders in their scenes too.)
#include "../common/types.hpp"
#include "../spatial/mesh_support.hpp"

#include <fixtures/scenes.hpp>
#include <plume/solver/world/world.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

using namespace plume;

namespace {

float const qnan = std::numeric_limits<float>::quiet_NaN();

/// A 4 x 0.2 x 4 m slab whose top is at y = 0.
Cuboid const slab{Vec3{2.0f, 0.1f, 2.0f}};
Iso3 const slab_pose = Iso3::from_translation({0, -0.1f, 0});

bool has(std::vector<ColliderPair> const& v, ColliderId a, ColliderId b) {
  return std::find(v.begin(), v.end(), ColliderPair{a, b}) != v.end();
}

} // namespace

TEST_CASE("standalone colliders: ids, slots, accessors and bad input", "[world][colliders]") {
  World w;
  BodyId const ball = w.create_body({.pose = Iso3::from_translation({0, 3, 0})}).id;
  auto const made = w.create_collider({.pose = slab_pose, .shape = slab, .friction = 0.3f});
  REQUIRE(made);
  ColliderId const c = made.id;
  CHECK(c.standalone);
  CHECK(c.index == 1); // bodies and colliders share the slots
  CHECK(!c.body().valid());
  CHECK(w.is_alive(c));
  CHECK(!w.is_alive(BodyId{c.index, c.generation})); // a slot a BodyId cannot name
  CHECK_THROWS_AS(w.body_id(c.index), std::out_of_range);
  CHECK_THROWS_AS(w.pose(BodyId{c.index, c.generation}), std::out_of_range);
  CHECK(w.collider_id(c.index) == c);
  CHECK(w.collider_id(ball.index) == ColliderId(ball));
  CHECK(ColliderId(ball).body() == ball);
  CHECK(w.is_alive(ColliderId(ball)));
  CHECK(w.alive_count() == 1);
  CHECK(w.collider_count() == 1);
  CHECK(w.body_count() == 2);
  CHECK(w.pose(c).translation.y == -0.1f);
  CHECK(std::get<Cuboid>(w.shape(c)).half_extents.x == 2.0f);
  CHECK(w.friction(c) == 0.3f);
  CHECK(w.aabb(c).max.y == Approx(0.0f).margin(1e-6));
  CHECK(w.aabb(ColliderId(ball)).min.y == Approx(2.5f));
  CHECK(!w.is_sensor(c));
  // A body's collider is not a standalone one: the collider setters refuse it, and
  // destroy_collider does not destroy bodies.
  CHECK(w.set_collider_pose(ColliderId(ball), Iso3{}) == BodyError::bad_body);
  CHECK(w.set_collider_layers(ColliderId(ball), {}) == BodyError::bad_body);
  CHECK(w.destroy_collider(ColliderId(ball)) == BodyError::bad_body);
  CHECK(w.is_alive(ball));
  // Nor does a BodyId forged from a collider's slot reach the collider.
  BodyId const forged{c.index, c.generation};
  CHECK(w.destroy_body(forged) == BodyError::bad_body);
  CHECK(w.set_type(forged, BodyType::dynamic) == BodyError::bad_body);
  CHECK(w.set_pose(forged, Iso3{}) == BodyError::bad_body);
  CHECK(w.set_velocity(forged, {1, 0, 0}, {}) == BodyError::bad_body);
  CHECK(w.apply_impulse(forged, {1, 0, 0}, {}) == BodyError::bad_body);
  CHECK(w.set_layers(forged, {}) == BodyError::bad_body);
  JointDef joint;
  joint.body_a = ball;
  joint.body_b = forged;
  CHECK(w.create_joint(joint).error == JointError::bad_body);
  CHECK(w.is_alive(c));
  CHECK(w.pose(c).translation.y == -0.1f);
  // Bad input leaves the world unchanged.
  Iso3 bad = slab_pose;
  bad.translation.x = qnan;
  CHECK(w.create_collider({.pose = bad, .shape = slab}).error == BodyError::non_finite);
  CHECK(w.create_collider({.pose = Iso3{Quat::from_xyzw(0, 0, 0, 0), {}}, .shape = slab}).error ==
        BodyError::non_finite);
  CHECK(w.create_collider({.shape = slab, .friction = qnan}).error == BodyError::non_finite);
  CHECK(w.create_collider({.shape = slab, .restitution = -0.5f}).error == BodyError::bad_material);
  CHECK(w.create_collider({.shape = MeshShape{}}).error == BodyError::bad_shape);
  CHECK(w.create_collider({.shape = HeightFieldShape{}}).error == BodyError::bad_shape);
  CHECK(w.set_collider_pose(c, bad) == BodyError::non_finite);
  CHECK(w.pose(c).translation.x == 0.0f);
  CHECK(w.collider_count() == 1);
  CHECK(w.body_count() == 2);
  // A rotation is normalised, as a body's.
  CHECK(w.set_collider_pose(c, Iso3{Quat::from_xyzw(0, 0, 0, 2), {0, -0.1f, 0}}) ==
        BodyError::none);
  CHECK(w.pose(c).rotation.w == 1.0f);
  // Destroyed: the id is stale everywhere; the slot goes to the next body, at a new generation.
  CHECK(w.destroy_collider(c) == BodyError::none);
  CHECK(!w.is_alive(c));
  CHECK(w.destroy_collider(c) == BodyError::bad_body);
  CHECK(w.set_collider_pose(c, slab_pose) == BodyError::bad_body);
  CHECK_THROWS_AS(w.pose(c), std::out_of_range);
  CHECK_THROWS_AS(w.collider_id(c.index), std::out_of_range);
  CHECK(w.collider_count() == 0);
  BodyId const reuse = w.create_body({.type = BodyType::static_body, .shape = slab}).id;
  CHECK(reuse.index == c.index);
  CHECK(reuse.generation == c.generation + 1);
  CHECK(!w.is_alive(c));
  CHECK(w.is_alive(ColliderId(reuse)));
  CHECK(w.alive_count() == 2);
  // And a body's freed slot goes to a collider: the body's id is stale, not the collider's.
  CHECK(w.destroy_body(ball) == BodyError::none);
  ColliderId const again = w.create_collider({.shape = slab}).id;
  CHECK(again.index == ball.index);
  CHECK(!w.is_alive(ball));
  CHECK(w.set_pose(ball, Iso3{}) == BodyError::bad_body);
  CHECK(w.is_alive(again));
}

TEST_CASE("standalone colliders: contacts are a static body's, bit for bit", "[world][colliders]") {
  // The same scene twice, the floor and a wall static bodies in one world and standalone
  // colliders in the other (the same slots; their friction and restitution in play: the
  // ball bounces): the worlds stay equal, step after step.
  auto const scene = [](bool standalone) {
    World w;
    auto const fixed = [&](BodyShape const& shape, Iso3 const& pose) {
      if (standalone)
        REQUIRE(w.create_collider(
            {.pose = pose, .shape = shape, .friction = 0.5f, .restitution = 0.8f}));
      else
        w.create_body({.type = BodyType::static_body,
                       .pose = pose,
                       .shape = shape,
                       .friction = 0.5f,
                       .restitution = 0.8f});
    };
    fixed(slab, slab_pose);
    fixed(Cuboid{Vec3{0.1f, 1.0f, 2.0f}}, Iso3::from_translation({1.5f, 1.0f, 0}));
    w.create_body({.pose = Iso3::from_translation({0, 1, 0}),
                   .linear_velocity = {3, 0, 0.5f},
                   .shape = Cuboid{Vec3::splat(0.25f)}});
    w.create_body({.pose = Iso3::from_translation({-0.5f, 2, 0.3f}), .shape = Sphere{0.2f}});
    w.create_body({.pose = Iso3{Quat::from_rotation_z(0.3f), {0.5f, 3, -0.5f}},
                   .shape = Capsule{0.3f, 0.15f}});
    return w;
  };
  World a = scene(false), b = scene(true);
  CHECK(b.collider_count() == 2);
  float bounce = 0.0f; // the ball's highest upward speed in the first second
  int touching = 0;
  for (int s = 0; s < 240; ++s) {
    a.step(1.0f / 60.0f);
    b.step(1.0f / 60.0f);
    REQUIRE(a.state_hash() == b.state_hash());
    REQUIRE(a.contacts().size() == b.contacts().size());
    REQUIRE(a.sleeping_contacts().size() == b.sleeping_contacts().size());
    touching += int(b.contacts().size() + b.sleeping_contacts().size());
    if (s < 60) bounce = std::max(bounce, b.linear_velocity(BodyId{3, 0}).y);
  }
  CHECK(touching > 150); // contacts in most steps (bouncing bodies leave them a while)
  CHECK(bounce > 2.0f);  // restitution 0.8 from about 6 m/s
  // Resting on the floor, against the wall.
  Vec3 const box = b.pose(BodyId{2, 0}).translation;
  CHECK(box.y == Approx(0.25f).margin(0.02f));
  CHECK(box.x <= 1.4f - 0.25f + 0.02f);
  // Events name the collider (a.body() invalid) and the body.
  World e = scene(true);
  ColliderId const floor = e.collider_id(0);
  bool began = false;
  for (int s = 0; s < 60 && !began; ++s) {
    e.step(1.0f / 60.0f);
    began = has(e.events().contact_begin, floor, e.body_id(3));
  }
  CHECK(began);
  for (ColliderPair const& p : e.events().contact_begin)
    CHECK(p.a.index < p.b.index);
}

/// A 0.5 m box resting on a standalone slab collider after `steps` steps.
struct BoxOnSlab {
  World w;
  ColliderId floor;
  BodyId box;
  explicit BoxOnSlab(int steps) {
    floor = w.create_collider({.pose = slab_pose, .shape = slab}).id;
    box = w.create_body(
               {.pose = Iso3::from_translation({0, 0.25f, 0}), .shape = Cuboid{Vec3::splat(0.25f)}})
              .id;
    for (int s = 0; s < steps; ++s)
      w.step(1.0f / 60.0f);
  }
};

TEST_CASE("standalone colliders: new layers take effect", "[world][colliders]") {
  BoxOnSlab f(20);
  World& w = f.w;
  ColliderId const floor = f.floor;
  BodyId const box = f.box;
  CHECK(w.pose(box).translation.y == Approx(0.25f).margin(0.01f));
  Ray3 const down{{1, 5, 1}, {0, -1, 0}};
  CHECK(w.ray_cast(down, 10.0f, {.mask = 1})->collider == floor);
  // Moved to layer 2, interacting with nothing the box is in: the box falls through.
  REQUIRE(w.set_collider_layers(floor, {.memberships = 2, .filters = 2}) == BodyError::none);
  CHECK(w.layers(floor).memberships == 2);
  CHECK(!w.ray_cast(down, 10.0f, {.mask = 1})); // queries see the new layers at once
  CHECK(w.ray_cast(down, 10.0f, {.mask = 2})->collider == floor);
  bool ended = false;
  for (int s = 0; s < 30; ++s) {
    w.step(1.0f / 60.0f);
    ended = ended || has(w.events().contact_end, floor, box);
  }
  CHECK(ended);
  CHECK(w.pose(box).translation.y < -0.5f);
  CHECK(w.set_collider_layers(ColliderId{}, {}) == BodyError::bad_body);
}

TEST_CASE("standalone colliders: pair only with dynamic bodies", "[world][colliders]") {
  World w;
  ColliderId const c = w.create_collider({.pose = slab_pose, .shape = slab}).id;
  BodyId const kin = w.create_body({.type = BodyType::kinematic,
                                    .pose = Iso3::from_translation({0, 0.1f, 0}),
                                    .linear_velocity = {0, -1, 0},
                                    .shape = Cuboid{Vec3::splat(0.5f)}})
                         .id;
  w.create_body({.type = BodyType::static_body,
                 .pose = Iso3::from_translation({1, 0, 0}),
                 .shape = Sphere{0.5f}});
  w.create_collider({.pose = Iso3::from_translation({-1, 0, 0}), .shape = Sphere{0.5f}});
  for (int s = 0; s < 30; ++s)
    w.step(1.0f / 60.0f);
  CHECK(w.contacts().empty());
  CHECK(w.pose(kin).translation.y == Approx(0.1f - 0.5f)); // passes through: kinematic
  // A trigger over a static and a kinematic body reports neither.
  w.create_collider(
      {.pose = Iso3::from_translation({1, 0, 0}), .shape = Sphere{2.0f}, .sensor = true});
  for (int s = 0; s < 5; ++s) {
    w.step(1.0f / 60.0f);
    CHECK(w.events().sensor_begin.empty());
  }
  BodyId const ball =
      w.create_body({.pose = Iso3::from_translation({1.5f, 0.5f, 1.5f}), .shape = Sphere{0.3f}}).id;
  for (int s = 0; s < 60; ++s)
    w.step(1.0f / 60.0f);
  CHECK(w.pose(ball).translation.y == Approx(0.3f).margin(0.01f));
  auto const of_ball = [&](Contact const& k) {
    return w.collider_id(k.body_a) == c && k.body_b == ball.index;
  };
  CHECK((std::any_of(w.contacts().begin(), w.contacts().end(), of_ball) ||
         std::any_of(w.sleeping_contacts().begin(), w.sleeping_contacts().end(), of_ball)));
}

TEST_CASE("standalone colliders: a trigger reports overlaps and takes no response",
          "[world][colliders]") {
  // A ball falls through a sensor box: the same fall as without it, and one begin and one end.
  auto const fall = [](bool trigger) {
    World w;
    w.create_body({.pose = Iso3::from_translation({0, 3, 0}), .shape = Sphere{0.2f}});
    ColliderId t{};
    if (trigger)
      t = w.create_collider({.pose = Iso3::from_translation({0, 1, 0}),
                             .shape = Cuboid{Vec3::splat(0.5f)},
                             .sensor = true})
              .id;
    return std::pair<World, ColliderId>{std::move(w), t};
  };
  auto [with, trigger] = fall(true);
  auto [without, none] = fall(false);
  (void)none;
  CHECK(with.is_sensor(trigger));
  BodyId const ball = with.body_id(0);
  int begins = 0, ends = 0, begin_step = -1, end_step = -1;
  std::vector<float> y;
  for (int s = 0; s < 90; ++s) {
    with.step(1.0f / 60.0f);
    without.step(1.0f / 60.0f);
    y.push_back(with.pose(ball).translation.y);
    REQUIRE(y.back() == without.pose(BodyId{0, 0}).translation.y);
    CHECK(with.contacts().empty());
    if (has(with.events().sensor_begin, ball, trigger)) ++begins, begin_step = s;
    if (has(with.events().sensor_end, ball, trigger)) ++ends, end_step = s;
  }
  CHECK(begins == 1);
  CHECK(ends == 1);
  REQUIRE(begin_step > 1);
  REQUIRE(end_step > begin_step);
  // Overlaps are found at the poses a step starts from (as contacts): it began in the first
  // step that started with the ball's bottom at the box's top (y = 1.5; touching counts) or
  // below, and ended in the first that started with its top below the box's bottom (y = 0.5).
  auto const b = std::size_t(begin_step), e = std::size_t(end_step);
  CHECK(y[b - 1] - 0.2f <= 1.5f);
  CHECK(y[b - 2] - 0.2f > 1.5f);
  CHECK(y[e - 1] + 0.2f < 0.5f);
  CHECK(y[e - 2] + 0.2f >= 0.5f);

  // A trigger teleported onto a resting body begins an overlap (its own query finds the
  // body); destroyed while it overlaps, the overlap ends in the next step's events.
  World r;
  r.create_collider({.pose = slab_pose, .shape = slab});
  BodyId const rest =
      r.create_body({.pose = Iso3::from_translation({1, 0.2f, 1}), .shape = Sphere{0.2f}}).id;
  ColliderId const zone = r.create_collider({.pose = Iso3::from_translation({-5, 1, -5}),
                                             .shape = Cuboid{Vec3::splat(0.5f)},
                                             .sensor = true})
                              .id;
  for (int s = 0; s < 30; ++s) {
    r.step(1.0f / 60.0f);
    CHECK(r.events().sensor_begin.empty());
  }
  REQUIRE(r.set_collider_pose(zone, Iso3::from_translation({1, 0.5f, 1})) == BodyError::none);
  r.step(1.0f / 60.0f);
  CHECK(has(r.events().sensor_begin, rest, zone));
  r.step(1.0f / 60.0f);
  REQUIRE(r.destroy_collider(zone) == BodyError::none);
  r.step(1.0f / 60.0f);
  CHECK(has(r.events().sensor_end, rest, zone));
  CHECK(r.sensor_overlaps().empty());
}

TEST_CASE("standalone colliders: teleports and destruction mid-contact", "[world][colliders]") {
  BoxOnSlab f(30);
  World& w = f.w;
  ColliderId const floor = f.floor;
  BodyId const box = f.box;
  CHECK(w.pose(box).translation.y == Approx(0.25f).margin(0.01f));
  // The floor jumps 10 m away (a teleport): the box falls, and the contact ends.
  REQUIRE(w.set_collider_pose(floor, Iso3::from_translation({10, -0.1f, 0})) == BodyError::none);
  bool ended = false;
  for (int s = 0; s < 10; ++s) {
    w.step(1.0f / 60.0f);
    ended = ended || has(w.events().contact_end, floor, box);
  }
  CHECK(ended);
  CHECK(w.pose(box).translation.y < 0.15f); // 0.25 - g t^2 / 2 = 0.11 after 1/6 s
  // Back under the box, at its new height: it lands and rests again.
  float const y = w.pose(box).translation.y;
  REQUIRE(w.set_collider_pose(floor, Iso3::from_translation({0, y - 0.25f - 0.1f - 0.5f, 0})) ==
          BodyError::none);
  for (int s = 0; s < 90; ++s)
    w.step(1.0f / 60.0f);
  CHECK(w.pose(box).translation.y == Approx(y - 0.5f).margin(0.02f));
  CHECK(w.contacts().size() + w.sleeping_contacts().size() > 0);
  // Destroyed under the box: the contact ends in the next step's events, and the box falls.
  REQUIRE(w.destroy_collider(floor) == BodyError::none);
  CHECK(w.contacts().empty());
  w.step(1.0f / 60.0f);
  CHECK(has(w.events().contact_end, floor, box));
  for (int s = 0; s < 30; ++s)
    w.step(1.0f / 60.0f);
  CHECK(w.pose(box).translation.y < y - 1.0f);
}

TEST_CASE("standalone colliders: continuous collision stops at a thin one", "[world][colliders]") {
  // A 0.1 m ball at 200 m/s and a 1 cm wall (a standalone collider) 5 m ahead.
  WorldConfig cfg;
  cfg.gravity = Vec3{};
  World free_world(cfg);
  World walled(cfg);
  REQUIRE(walled.create_collider(
      {.pose = Iso3::from_translation({5, 0, 0}), .shape = Cuboid{Vec3{0.005f, 2, 2}}}));
  BodyId const ball =
      walled.create_body({.linear_velocity = {200, 0, 0}, .shape = Sphere{0.05f}}).id;
  free_world.create_body({.linear_velocity = {200, 0, 0}, .shape = Sphere{0.05f}});
  int stops = 0;
  for (int s = 0; s < 10; ++s) {
    walled.step(1.0f / 60.0f);
    free_world.step(1.0f / 60.0f);
    auto const& st = walled.events().continuous_stops;
    stops += int(std::count(st.begin(), st.end(), ball));
  }
  CHECK(free_world.pose(BodyId{0, 0}).translation.x > 20.0f); // no wall: far away
  CHECK(stops >= 1);
  float const x = walled.pose(ball).translation.x;
  CHECK(x < 5.0f - 0.005f - 0.05f + 1e-3f); // stopped on the near side, at the wall
  CHECK(x > 4.8f);
}

TEST_CASE("standalone colliders: every query names them", "[world][colliders][queries]") {
  World w;
  scenes::add_ground(w);
  ColliderId const c = w.create_collider({.pose = Iso3::from_translation({0, 1, 0}),
                                          .shape = Cuboid{Vec3::splat(0.5f)},
                                          .layers = {.memberships = 2}})
                           .id;
  BodyId const ball = w.create_body({.type = BodyType::static_body,
                                     .pose = Iso3::from_translation({3, 1, 0}),
                                     .shape = Sphere{0.5f}})
                          .id;
  Ray3 const down{{0, 5, 0}, {0, -1, 0}};
  auto const hit = w.ray_cast(down, 10.0f);
  REQUIRE(hit);
  CHECK(hit->collider == c);
  CHECK(!hit->body.valid());
  CHECK(hit->toi == Approx(3.5f));
  // The layers mask and the predicate see it; a BodyId with its slot does not exclude it.
  CHECK(w.ray_cast(down, 10.0f, {.mask = 1})->collider == ColliderId(BodyId{0, 0}));
  CHECK(w.ray_cast(down, 10.0f, {.predicate = [&](ColliderId id) { return id != c; }})->body ==
        BodyId{0, 0});
  BodyId const same_slot{c.index, c.generation};
  CHECK(w.ray_cast(down, 10.0f, {.exclude = std::span<BodyId const>(&same_slot, 1)})->collider ==
        c);
  std::vector<ColliderId> all;
  w.ray_cast_all(down, 10.0f, [&](WorldRayHit const& h) {
    all.push_back(h.collider);
    return true;
  });
  CHECK(all == std::vector<ColliderId>{c, ColliderId(BodyId{0, 0})});
  std::vector<Ray3> rays(9, down);
  for (std::size_t k = 0; k < rays.size(); ++k)
    rays[k].origin.x = 0.05f * float(k);
  std::vector<std::optional<WorldRayHit>> batch(rays.size());
  w.ray_cast(rays, 10.0f, batch);
  for (auto const& h : batch)
    CHECK((h && h->collider == c && !h->body.valid()));
  // Shape casts, single and in lanes.
  auto const cast = w.shape_cast(Sphere{0.25f}, Iso3::from_translation({0, 5, 0}), {0, -10, 0});
  REQUIRE(cast);
  CHECK(cast->collider == c);
  CHECK(!cast->body.valid());
  std::vector<BodyShape> shapes(5, BodyShape{Sphere{0.25f}});
  std::vector<Iso3> poses(5, Iso3::from_translation({0, 5, 0}));
  std::vector<Vec3> motions(5, Vec3{0, -10, 0});
  std::vector<std::optional<WorldShapeHit>> casts(5);
  w.shape_cast(shapes, poses, motions, {}, casts);
  for (auto const& h : casts)
    CHECK((h && h->collider == c && !h->body.valid() && h->toi == cast->toi));
  // Overlaps, points and contacts.
  std::vector<ColliderId> got;
  auto const collect = [&](ColliderId id) {
    got.push_back(id);
    return true;
  };
  ColliderId const ground = w.collider_id(0);
  w.overlap_aabb(Aabb3{{-0.2f, 0.8f, -0.2f}, {0.2f, 1.2f, 0.2f}}, collect);
  CHECK(got == std::vector<ColliderId>{ground, c}); // a half-space's box is unbounded
  got.clear();
  w.overlap_shape(Sphere{0.3f}, Iso3::from_translation({0.7f, 1, 0}), collect);
  CHECK(got == std::vector<ColliderId>{c});
  got.clear();
  w.point_query({0.1f, 1.2f, 0}, collect);
  CHECK(got == std::vector<ColliderId>{c});
  got.clear();
  w.contact_query(Sphere{0.3f}, Iso3::from_translation({0, 1.75f, 0}), 0.1f,
                  [&](ColliderId id, Manifold const& m) {
                    got.push_back(id);
                    CHECK(m.normal.y == Approx(1.0f).margin(1e-4));
                    return true;
                  });
  CHECK(got == std::vector<ColliderId>{c});
  auto const near = w.project_point({0, 2, 0}, 1.0f);
  REQUIRE(near);
  CHECK(near->collider == c);
  CHECK(!near->body.valid());
  CHECK(near->distance == Approx(0.5f));
  auto const other = w.project_point({3, 2, 0}, 1.0f);
  REQUIRE(other);
  CHECK(other->body == ball);
  CHECK(other->collider == ColliderId(ball));
  // Moved: the queries follow at once (the trees sync on the first query).
  REQUIRE(w.set_collider_pose(c, Iso3::from_translation({-3, 1, 0})) == BodyError::none);
  CHECK(w.ray_cast(down, 10.0f)->collider == ColliderId(BodyId{0, 0}));
  CHECK(w.ray_cast({{-3, 5, 0}, {0, -1, 0}}, 10.0f)->collider == c);
  // Destroyed: gone from every query.
  REQUIRE(w.destroy_collider(c) == BodyError::none);
  CHECK(w.ray_cast({{-3, 5, 0}, {0, -1, 0}}, 10.0f)->collider == ColliderId(BodyId{0, 0}));
  got.clear();
  w.overlap_aabb(Aabb3{{-3.2f, 0.8f, -0.2f}, {-2.8f, 1.2f, 0.2f}}, collect);
  CHECK(got == std::vector<ColliderId>{ground});
}

TEST_CASE("standalone colliders: their own tree, which a teleport edits without touching the "
          "static one",
          "[world][colliders]") {
  World w;
  scenes::add_ground(w);
  for (int k = 0; k < 50; ++k) // a level of static boxes
    w.create_body({.type = BodyType::static_body,
                   .pose = Iso3::from_translation({float(k % 10), 0.5f, float(k / 10)}),
                   .shape = Cuboid{Vec3::splat(0.4f)}});
  ColliderId const trigger =
      w.create_collider(
           {.pose = Iso3::from_translation({0, 2, 0}), .shape = Sphere{0.5f}, .sensor = true})
          .id;
  w.step(1.0f / 60.0f);
  BvhBroadPhase const& bp = w.broad_phase();
  CHECK(bp.tree(ProxyKind::static_body).size() == 50);
  CHECK(bp.tree(ProxyKind::standalone).size() == 1);
  REQUIRE(bp.static_wide() != nullptr);
  // A trigger carried along every frame: each move is an edit of its tree; the static tree's
  // wide copy stays fresh for the queries in between (a static body's teleport makes it
  // stale until the next step).
  for (int s = 1; s <= 30; ++s) {
    Vec3 const at{0.3f * float(s), 2, 0.1f * float(s)};
    REQUIRE(w.set_collider_pose(trigger, Iso3::from_translation(at)) == BodyError::none);
    auto const hit = w.ray_cast({at + Vec3{0, 3, 0}, {0, -1, 0}}, 10.0f);
    REQUIRE(hit);
    CHECK(hit->collider == trigger);
    CHECK(bp.static_wide() != nullptr);
    w.step(1.0f / 60.0f);
    CHECK(bp.tree(ProxyKind::standalone).validate() == "");
  }
  REQUIRE(w.set_pose(w.body_id(1), Iso3::from_translation({-5, 0.5f, -5})) == BodyError::none);
  CHECK(w.ray_cast({{-5, 3, -5}, {0, -1, 0}}, 10.0f)->body == w.body_id(1));
  CHECK(bp.static_wide() == nullptr);
  CHECK(bp.tree(ProxyKind::standalone).size() == 1);
  CHECK(bp.tree(ProxyKind::static_body).size() == 50);
}
