// Sleeping: islands fall asleep when every body stayed slow for time_to_sleep, stay still and
// silent, wake on touch, on setters, on destruction and on demand, and do it at every width.
#include "../common/harness.hpp"

#include "../common/types.hpp"

#include <fixtures/scenes.hpp>
#include <plume/solver/world/world.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

using namespace plume;
using namespace plume::scenes;

namespace {

constexpr float dt = 1.0f / 60.0f;

bool all_sleeping(World const& w, std::vector<BodyId> const& ids) {
  return std::all_of(ids.begin(), ids.end(), [&](BodyId id) { return w.is_sleeping(id); });
}
bool none_sleeping(World const& w, std::vector<BodyId> const& ids) {
  return std::none_of(ids.begin(), ids.end(), [&](BodyId id) { return w.is_sleeping(id); });
}
bool same_pose(Iso3 const& a, Iso3 const& b) {
  Vec3 const t = a.translation - b.translation;
  Quat const q = a.rotation - b.rotation;
  return t.x == 0.0f && t.y == 0.0f && t.z == 0.0f && q.x == 0.0f && q.y == 0.0f && q.z == 0.0f &&
         q.w == 0.0f;
}
bool contains(std::vector<BodyId> const& list, BodyId id) {
  return std::find(list.begin(), list.end(), id) != list.end();
}

/// Steps until every body of `ids` sleeps (at most max_steps); the steps taken, or -1.
int steps_to_sleep(World& w, std::vector<BodyId> const& ids, int max_steps) {
  for (int s = 1; s <= max_steps; ++s) {
    w.step(dt);
    if (all_sleeping(w, ids)) return s;
  }
  return -1;
}

/// Two boxes stacked on the ground, settled and asleep.
struct SleepingStack {
  World w;
  BodyId ground;
  std::vector<BodyId> boxes;
  SleepingStack() {
    ground = add_ground(w);
    boxes = add_box_stack(w, 2);
    REQUIRE(steps_to_sleep(w, boxes, 240) > 0);
  }
};

/// A box resting on the ground inside a 2 m trigger (a standalone sensor collider).
struct SensorOverBox {
  World w;
  ColliderId sensor;
  std::vector<BodyId> box;
  SensorOverBox() {
    add_ground(w);
    ColliderDef trigger;
    trigger.shape = Cuboid{Vec3::splat(1.0f)};
    trigger.sensor = true;
    sensor = w.create_collider(trigger).id;
    box = add_box_stack(w, 1);
  }
};

} // namespace

TEST_CASE("sleep: a pyramid settles and sleeps within 3 s, then stays asleep and still",
          "[world][sleep]") {
  World w;
  add_ground(w);
  std::vector<BodyId> const ids = add_box_pyramid(w, 6);
  std::vector<BodyId> fell;
  int asleep_at = -1;
  for (int s = 1; s <= 180 && asleep_at < 0; ++s) {
    w.step(dt);
    for (BodyId id : w.events().fell_asleep)
      fell.push_back(id);
    CHECK(w.events().woke_up.empty());
    if (all_sleeping(w, ids)) asleep_at = s;
  }
  REQUIRE(asleep_at > 0);
  CHECK(float(asleep_at) * dt >= w.config().time_to_sleep);
  // Each body reported once, as it fell asleep; one island (the boxes touch).
  std::sort(fell.begin(), fell.end(), [](BodyId a, BodyId b) { return a.index < b.index; });
  CHECK(fell == ids);
  CHECK(w.sleeping_count() == ids.size());
  CHECK(w.contacts().empty()); // the solver has nothing left to do
  CHECK(!w.sleeping_contacts().empty());
  for (BodyId id : ids) {
    CHECK(w.linear_velocity(id).length() == 0.0f);
    CHECK(w.angular_velocity(id).length() == 0.0f);
  }
  std::uint64_t const hash = w.state_hash();
  for (int s = 0; s < 120; ++s) {
    w.step(dt);
    CHECK(w.events().contact_begin.empty());
    CHECK(w.events().contact_end.empty());
    CHECK(w.events().woke_up.empty());
    CHECK(w.events().fell_asleep.empty());
  }
  CHECK(w.state_hash() == hash);
  CHECK(all_sleeping(w, ids));
}

TEST_CASE("sleep: a ball dropped on a sleeping pyramid wakes it in the step it touches, and "
          "the pyramid sleeps again",
          "[world][sleep]") {
  World w;
  add_ground(w);
  std::vector<BodyId> const ids = add_box_pyramid(w, 4);
  REQUIRE(steps_to_sleep(w, ids, 180) > 0);
  float const top = w.aabb(ids.back()).max.y;
  BodyId const ball = add_ball(w, {0.0f, top + 1.0f, 0.0f}, 0.25f, 0.0f);
  bool woke = false;
  float last_gap = INFINITY;
  for (int s = 0; s < 120 && !woke; ++s) {
    float const gap = w.aabb(ball).min.y - top; // the ball falls straight onto the top box
    w.step(dt);
    if (w.events().woke_up.empty()) {
      CHECK(all_sleeping(w, ids));
      last_gap = gap;
      continue;
    }
    woke = true;
    // The touch is found at the step's start: within the speculative distance then, and not
    // a step before.
    CHECK(gap <= w.config().speculative_distance);
    CHECK(last_gap > w.config().speculative_distance);
    for (BodyId id : ids)
      CHECK(contains(w.events().woke_up, id)); // the whole island
    CHECK(none_sleeping(w, ids));
    CHECK(w.sleeping_contacts().empty());
  }
  REQUIRE(woke);
  std::vector<BodyId> all = ids;
  all.push_back(ball);
  CHECK(steps_to_sleep(w, all, 600) > 0);
}

TEST_CASE("sleep: after waking, the world reaches the state of a world that never slept",
          "[world][sleep]") {
  auto const run = [](bool sleep) {
    WorldConfig cfg;
    cfg.sleep = sleep;
    World w(cfg);
    add_ground(w);
    std::vector<BodyId> ids = add_box_pyramid(w, 4);
    for (int s = 0; s < 180; ++s)
      w.step(dt);
    CHECK(all_sleeping(w, ids) == sleep);
    float const top = w.aabb(ids.back()).max.y;
    ids.push_back(add_ball(w, {0.1f, top + 0.5f, 0.05f}, 0.2f, 0.0f, 0.6f, 500.0f));
    for (int s = 0; s < 240; ++s)
      w.step(dt);
    std::vector<Vec3> at;
    for (BodyId id : ids)
      at.push_back(w.pose(id).translation);
    return at;
  };
  std::vector<Vec3> const slept = run(true), awake = run(false);
  REQUIRE(slept.size() == awake.size());
  float worst = 0.0f;
  for (std::size_t i = 0; i < slept.size(); ++i)
    worst = std::max(worst, (slept[i] - awake[i]).length());
  // The sleeping world skipped the last creep (the threshold's 5 cm/s): millimetres, not a
  // different outcome.
  CHECK(worst < 0.01f);
}

TEST_CASE("sleep: a body put to sleep, or created asleep, never moves until woken",
          "[world][sleep]") {
  World w;
  add_ground(w);
  BodyDef def = cube_def(1.0f, 1000.0f, 0.6f);
  def.pose = Iso3::from_translation({0.0f, 5.0f, 0.0f});
  def.linear_velocity = {1.0f, 2.0f, 0.0f};
  BodyId const put = w.create_body(def).id;
  def.pose = Iso3::from_translation({3.0f, 5.0f, 0.0f});
  def.awake = false;
  BodyId const born = w.create_body(def).id;
  CHECK(w.is_sleeping(born));
  CHECK(w.linear_velocity(born).length() == 0.0f); // created stopped
  CHECK(w.set_awake(put, false) == BodyError::none);
  CHECK(w.is_sleeping(put));
  // Put to sleep and woken before the step: it did not fall asleep in that step.
  BodyId const fickle = w.create_body(def).id;
  w.set_awake(fickle, true);
  CHECK(!w.is_sleeping(fickle));
  CHECK(w.destroy_body(fickle) == BodyError::none);
  CHECK(w.linear_velocity(put).length() == 0.0f);
  Iso3 const p0 = w.pose(put), b0 = w.pose(born);
  w.step(dt); // reported by the next step, as destroy_body's ends
  CHECK(w.events().fell_asleep == std::vector<BodyId>{put, born});
  for (int s = 0; s < 120; ++s)
    w.step(dt);
  CHECK(same_pose(w.pose(put), p0));
  CHECK(same_pose(w.pose(born), b0));
  // Woken, it falls.
  CHECK(w.set_awake(put, true) == BodyError::none);
  w.step(dt);
  CHECK(!w.is_sleeping(put));
  CHECK(w.events().woke_up == std::vector<BodyId>{put});
  CHECK(w.pose(put).translation.y < p0.translation.y);
  CHECK(w.is_sleeping(born));
  w.wake_all();
  CHECK(w.sleeping_count() == 0);
  w.step(dt);
  CHECK(w.pose(born).translation.y < b0.translation.y);
}

TEST_CASE("sleep: set_awake(false) takes the body's whole island", "[world][sleep]") {
  World w;
  add_ground(w);
  std::vector<BodyId> const stack = add_box_stack(w, 3);
  BodyId const apart = add_ball(w, {4.0f, 0.25f, 0.0f});
  w.step(dt); // the contacts exist from the first step
  REQUIRE(w.set_awake(stack[1], false) == BodyError::none);
  CHECK(all_sleeping(w, stack));
  CHECK(!w.is_sleeping(apart));
  CHECK(w.sleeping_count() == 3);
  // Static and kinematic bodies have no island: nothing to do.
  BodyDef k;
  k.type = BodyType::kinematic;
  k.pose = Iso3::from_translation({-5.0f, 1.0f, 0.0f});
  BodyId const kin = w.create_body(k).id;
  CHECK(w.set_awake(kin, false) == BodyError::none);
  CHECK(!w.is_sleeping(kin));
}

TEST_CASE("sleep: every setter wakes the island", "[world][sleep]") {
  using Edit = BodyError (*)(World&, BodyId);
  std::vector<std::pair<char const*, Edit>> const edits = {
      {"set_pose", [](World& w, BodyId b) { return w.set_pose(b, w.pose(b)); }},
      {"set_velocity", [](World& w, BodyId b) { return w.set_velocity(b, Vec3{}, Vec3{}); }},
      {"apply_impulse",
       [](World& w, BodyId b) { return w.apply_impulse(b, Vec3{}, w.pose(b).translation); }},
      {"set_type", [](World& w, BodyId b) { return w.set_type(b, BodyType::kinematic); }},
      {"set_layers", [](World& w, BodyId b) { return w.set_layers(b, w.layers(b)); }},
      {"set_bullet", [](World& w, BodyId b) { return w.set_bullet(b, true); }},
      {"set_sleep_enabled", [](World& w, BodyId b) { return w.set_sleep_enabled(b, false); }},
      {"set_sleep_threshold", [](World& w, BodyId b) { return w.set_sleep_threshold(b, 0.1f); }},
  };
  for (auto const& [name, edit] : edits) {
    SleepingStack s;
    INFO(name);
    CHECK(edit(s.w, s.boxes[1]) == BodyError::none);
    CHECK(!s.w.is_sleeping(s.boxes[0])); // the island, not only the body
    CHECK(!s.w.is_sleeping(s.boxes[1]));
    s.w.step(dt);
    CHECK(s.w.events().woke_up.size() == 2);
  }
  SECTION("a refused setter changes nothing") {
    SleepingStack s;
    CHECK(s.w.set_pose(s.boxes[1], Iso3::from_translation({NAN, 0.0f, 0.0f})) ==
          BodyError::non_finite);
    CHECK(s.w.set_sleep_threshold(s.boxes[1], -1.0f) == BodyError::bad_material);
    CHECK(s.w.set_sleep_threshold(s.boxes[1], INFINITY) == BodyError::non_finite);
    CHECK(s.w.set_type(s.boxes[1], BodyType::dynamic) == BodyError::none);    // its own type
    CHECK(s.w.set_type(s.ground, BodyType::dynamic) == BodyError::zero_mass); // a half-space
    CHECK(all_sleeping(s.w, s.boxes));
    CHECK(s.w.sleep_threshold(s.boxes[1]) == 0.05f);
  }
}

TEST_CASE("sleep: destroying, teleporting or creating what a sleeping body rests on wakes it",
          "[world][sleep]") {
  SECTION("the body below is destroyed") {
    SleepingStack s;
    float const y = s.w.pose(s.boxes[1]).translation.y;
    REQUIRE(s.w.destroy_body(s.boxes[0]) == BodyError::none);
    CHECK(!s.w.is_sleeping(s.boxes[1]));
    for (int i = 0; i < 60; ++i)
      s.w.step(dt);
    CHECK(s.w.pose(s.boxes[1]).translation.y < y - 0.9f); // it fell to the ground
  }
  SECTION("a standalone floor is destroyed") {
    World w;
    ColliderDef floor;
    floor.shape = Cuboid{{5.0f, 0.5f, 5.0f}};
    floor.pose = Iso3::from_translation({0.0f, -0.5f, 0.0f});
    ColliderId const f = w.create_collider(floor).id;
    std::vector<BodyId> const box = add_box_stack(w, 1);
    REQUIRE(steps_to_sleep(w, box, 240) > 0);
    REQUIRE(w.destroy_collider(f) == BodyError::none);
    CHECK(!w.is_sleeping(box[0]));
    w.step(dt);
    CHECK(w.linear_velocity(box[0]).y < 0.0f);
  }
  SECTION("the ground is teleported away") {
    SleepingStack s;
    REQUIRE(s.w.set_type(s.ground, BodyType::static_body) == BodyError::none);
    CHECK(all_sleeping(s.w, s.boxes)); // no change: nothing to do
    REQUIRE(s.w.set_pose(s.ground, Iso3::from_translation({0.0f, -10.0f, 0.0f})) ==
            BodyError::none);
    CHECK(none_sleeping(s.w, s.boxes));
  }
  SECTION("a static body or a collider is created over it") {
    SleepingStack s;
    BodyDef wall;
    wall.type = BodyType::static_body;
    wall.shape = Cuboid{{0.1f, 2.0f, 2.0f}};
    wall.pose = Iso3::from_translation({0.45f, 1.0f, 0.0f});
    s.w.create_body(wall);
    CHECK(none_sleeping(s.w, s.boxes));
    s.w.set_awake(s.boxes[0], false);
    REQUIRE(all_sleeping(s.w, s.boxes));
    ColliderDef c;
    c.shape = Sphere{0.2f};
    c.pose = Iso3::from_translation({0.0f, 1.5f, 0.45f});
    s.w.create_collider(c);
    CHECK(none_sleeping(s.w, s.boxes));
  }
  SECTION("a collider far away wakes nothing") {
    SleepingStack s;
    ColliderDef c;
    c.shape = Sphere{0.2f};
    c.pose = Iso3::from_translation({10.0f, 1.0f, 0.0f});
    ColliderId const far = s.w.create_collider(c).id;
    CHECK(all_sleeping(s.w, s.boxes));
    s.w.set_collider_pose(far, Iso3::from_translation({0.0f, 1.9f, 0.0f})); // into the top box
    CHECK(none_sleeping(s.w, s.boxes));
  }
}

TEST_CASE("sleep: joints share an island; creating, destroying or driving one wakes it",
          "[world][sleep]") {
  World w;
  add_ground(w);
  std::vector<BodyId> const boxes = add_box_stack(w, 1);
  BodyId const ball = add_ball(w, {3.0f, 0.25f, 0.0f});
  JointDef jd;
  jd.body_a = boxes[0];
  jd.body_b = ball;
  jd.frame_a = w.joint_frame(boxes[0], {1.5f, 0.25f, 0.0f}, Vec3::X);
  jd.frame_b = w.joint_frame(ball, {1.5f, 0.25f, 0.0f}, Vec3::X);
  jd.type = RevoluteJoint{};
  JointId const j = w.create_joint(jd).id;
  std::vector<BodyId> const both = {boxes[0], ball};
  REQUIRE(steps_to_sleep(w, both, 300) > 0);
  // Asleep, the joint is not solved: nothing moves.
  std::uint64_t const hash = w.state_hash();
  for (int s = 0; s < 30; ++s)
    w.step(dt);
  CHECK(w.state_hash() == hash);
  // One island: they fell asleep in the same step.
  CHECK(w.set_awake(ball, true) == BodyError::none);
  CHECK(none_sleeping(w, both));
  REQUIRE(steps_to_sleep(w, both, 300) > 0);
  REQUIRE(w.set_motor(j, Motor{}) == JointError::none);
  CHECK(none_sleeping(w, both));
  REQUIRE(steps_to_sleep(w, both, 300) > 0);
  REQUIRE(w.destroy_joint(j) == JointError::none);
  CHECK(none_sleeping(w, both));
  // Two islands now; a new joint between them wakes both.
  REQUIRE(steps_to_sleep(w, both, 300) > 0);
  REQUIRE(w.create_joint(jd));
  CHECK(none_sleeping(w, both));
}

TEST_CASE("sleep: a moving kinematic body keeps what it carries awake and wakes what it meets",
          "[world][sleep]") {
  World w;
  BodyDef p;
  p.type = BodyType::kinematic;
  p.shape = Cuboid{{2.0f, 0.25f, 2.0f}};
  p.pose = Iso3::from_translation({0.0f, -0.25f, 0.0f});
  p.linear_velocity = {0.02f, 0.0f, 0.0f}; // slower than the sleep threshold
  BodyId const platform = w.create_body(p).id;
  BodyDef box = cube_def(0.5f, 1000.0f, 1.0f);
  box.pose = Iso3::from_translation({0.0f, 0.25f, 0.0f});
  BodyId const rider = w.create_body(box).id;
  for (int s = 0; s < 90; ++s)
    w.step(dt);
  // Carried at 0.02 m/s, below its threshold: awake all the same (asleep, the platform would
  // slide out from under it).
  CHECK(!w.is_sleeping(rider));
  CHECK(w.sleep_time(rider) == 0.0f);
  CHECK(w.linear_velocity(rider).x == Approx(0.02f).margin(1e-3f));
  // Stopped, the platform lets it sleep; moving again, it wakes it.
  w.set_velocity(platform, Vec3{}, Vec3{});
  std::vector<BodyId> const one = {rider};
  REQUIRE(steps_to_sleep(w, one, 120) > 0);
  w.set_velocity(platform, {0.5f, 0.0f, 0.0f}, Vec3{});
  CHECK(w.is_sleeping(rider)); // a platform's setter is not the rider's
  w.step(dt);
  CHECK(!w.is_sleeping(rider));
  CHECK(w.events().woke_up == one);
  // A moving kinematic body that comes to touch a sleeping one wakes it.
  World v;
  add_ground(v);
  std::vector<BodyId> const target = add_box_stack(v, 1);
  REQUIRE(steps_to_sleep(v, target, 240) > 0);
  BodyDef pusher;
  pusher.type = BodyType::kinematic;
  pusher.shape = Sphere{0.25f};
  pusher.pose = Iso3::from_translation({-2.0f, 0.5f, 0.0f});
  pusher.linear_velocity = {1.0f, 0.0f, 0.0f};
  v.create_body(pusher);
  int woke_at = -1;
  for (int s = 1; s <= 120 && woke_at < 0; ++s) {
    v.step(dt);
    if (!v.is_sleeping(target[0])) woke_at = s;
  }
  // It reaches the box (1.25 m away) after 75 steps: woken within the speculative distance.
  CHECK(woke_at >= 74);
  CHECK(woke_at <= 76);
}

TEST_CASE("sleep: the speed measured is that of the farthest point, spin included",
          "[world][sleep]") {
  WorldConfig cfg;
  cfg.gravity = Vec3{};
  World w(cfg);
  // A 1 m cube's farthest point is sqrt(3)/2 = 0.866 m from its centre: at 0.09 rad/s it moves
  // at 0.078 m/s (awake), at 0.05 rad/s at 0.043 m/s (asleep after 0.5 s).
  BodyDef def = cube_def(1.0f, 1000.0f, 0.6f);
  def.angular_velocity = {0.0f, 0.09f, 0.0f};
  BodyId const fast = w.create_body(def).id;
  def.pose = Iso3::from_translation({5.0f, 0.0f, 0.0f});
  def.angular_velocity = {0.0f, 0.05f, 0.0f};
  BodyId const slow = w.create_body(def).id;
  def.pose = Iso3::from_translation({-5.0f, 0.0f, 0.0f});
  def.angular_velocity = Vec3{};
  def.linear_velocity = {0.0f, 0.0f, 0.06f}; // just above the threshold
  BodyId const drifting = w.create_body(def).id;
  for (int s = 0; s < 40; ++s)
    w.step(dt);
  CHECK(!w.is_sleeping(fast));
  CHECK(w.is_sleeping(slow));
  CHECK(!w.is_sleeping(drifting));
}

TEST_CASE("sleep: a kinematic body that starts moving wakes what it is jointed to",
          "[world][sleep]") {
  World w;
  add_ground(w);
  BodyDef k;
  k.type = BodyType::kinematic;
  k.shape = Sphere{0.1f};
  k.pose = Iso3::from_translation({0.0f, 3.0f, 0.0f});
  BodyId const crane = w.create_body(k).id;
  BodyDef def = cube_def(0.5f, 1000.0f, 0.6f);
  def.pose = Iso3::from_translation({0.0f, 2.0f, 0.0f});
  BodyId const load = w.create_body(def).id;
  JointDef jd;
  jd.body_a = crane;
  jd.body_b = load;
  jd.frame_a = w.joint_frame(crane, {0.0f, 3.0f, 0.0f}, Vec3::X);
  jd.frame_b = w.joint_frame(load, {0.0f, 3.0f, 0.0f}, Vec3::X);
  jd.type = SphericalJoint{};
  REQUIRE(w.create_joint(jd));
  std::vector<BodyId> const one = {load};
  REQUIRE(steps_to_sleep(w, one, 240) > 0); // hanging still
  w.set_velocity(crane, {1.0f, 0.0f, 0.0f}, Vec3{});
  w.step(dt);
  CHECK(!w.is_sleeping(load));
  for (int s = 0; s < 60; ++s)
    w.step(dt);
  CHECK(w.pose(load).translation.x > 0.5f); // carried along
}

TEST_CASE("sleep: a sensor moved away ends its overlap with a sleeping body",
          "[world][sleep][events]") {
  SensorOverBox f;
  World& w = f.w;
  ColliderId const sensor = f.sensor;
  std::vector<BodyId> const& box = f.box;
  REQUIRE(steps_to_sleep(w, box, 240) > 0);
  REQUIRE(w.sensor_overlaps().size() == 1);
  w.set_collider_pose(sensor, Iso3::from_translation({20.0f, 0.0f, 0.0f}));
  w.step(dt);
  CHECK(w.events().sensor_end.size() == 1);
  CHECK(w.sensor_overlaps().empty());
}

TEST_CASE("sleep: what cannot touch a sleeping body does not wake it", "[world][sleep]") {
  SleepingStack s;
  BodyDef ghost;
  ghost.type = BodyType::kinematic;
  ghost.shape = Sphere{0.3f};
  ghost.pose = Iso3::from_translation({0.0f, 1.5f, 0.0f}); // inside the top box
  ghost.layers.filters = 0;                                // interacts with nothing
  BodyId const g = s.w.create_body(ghost).id;
  CHECK(all_sleeping(s.w, s.boxes));
  s.w.set_pose(g, Iso3::from_translation({0.0f, 0.5f, 0.0f}));
  CHECK(all_sleeping(s.w, s.boxes));
  s.w.step(dt);
  CHECK(all_sleeping(s.w, s.boxes));
  // With layers that meet the boxes', the same teleport wakes them.
  s.w.set_layers(g, CollisionLayers{});
  CHECK(none_sleeping(s.w, s.boxes));
}

TEST_CASE("sleep: a body that may not sleep keeps its island awake", "[world][sleep]") {
  World w;
  add_ground(w);
  std::vector<BodyId> const stack = add_box_stack(w, 2);
  REQUIRE(w.set_sleep_enabled(stack[1], false) == BodyError::none);
  CHECK(!w.sleep_enabled(stack[1]));
  BodyDef def = cube_def(1.0f, 1000.0f, 0.6f);
  def.pose = Iso3::from_translation({5.0f, 0.5f, 0.0f});
  BodyId const alone = w.create_body(def).id;
  for (int s = 0; s < 240; ++s)
    w.step(dt);
  CHECK(w.is_sleeping(alone));
  CHECK(none_sleeping(w, stack));
  // Not even on demand, nor from birth.
  CHECK(w.set_awake(stack[0], false) == BodyError::none);
  CHECK(none_sleeping(w, stack));
  def.pose = Iso3::from_translation({8.0f, 0.5f, 0.0f});
  def.enable_sleep = false;
  def.awake = false;
  CHECK(!w.is_sleeping(w.create_body(def).id));
}

TEST_CASE("sleep: contacts and sensor overlaps of sleeping bodies neither end nor begin",
          "[world][sleep][events]") {
  SensorOverBox f;
  World& w = f.w;
  ColliderId const sensor = f.sensor;
  std::vector<BodyId> const& box = f.box;
  w.step(dt);
  REQUIRE(w.events().sensor_begin.size() == 1);
  REQUIRE(w.sensor_overlaps().size() == 1);
  REQUIRE(steps_to_sleep(w, box, 240) > 0);
  for (int s = 0; s < 30; ++s) {
    w.step(dt);
    CHECK(w.events().sensor_end.empty());
    CHECK(w.events().contact_end.empty());
  }
  CHECK(w.sensor_overlaps().size() == 1);
  // Woken: the contact and the overlap go on, no new begin.
  w.set_awake(box[0], true);
  w.step(dt);
  CHECK(w.events().contact_begin.empty());
  CHECK(w.events().sensor_begin.empty());
  CHECK(w.sensor_overlaps().size() == 1);
  // Destroyed while asleep: the ends are reported, and the body is in no wake list.
  REQUIRE(steps_to_sleep(w, box, 240) > 0);
  REQUIRE(w.destroy_body(box[0]) == BodyError::none);
  w.step(dt);
  CHECK(w.events().woke_up.empty());
  CHECK(w.events().contact_end.size() == 1);
  CHECK(w.events().sensor_end.size() == 1);
  CHECK(w.is_alive(sensor));
}

TEST_CASE("sleep: bodies created and destroyed while others sleep leave no dangling island",
          "[world][sleep][bad-input]") {
  World w;
  add_ground(w);
  std::vector<BodyId> stacks[3];
  for (int k = 0; k < 3; ++k) {
    BodyDef def = cube_def(1.0f, 1000.0f, 0.6f);
    for (int i = 0; i < 2; ++i) {
      def.pose = Iso3::from_translation({3.0f * float(k), 0.5f + float(i), 0.0f});
      stacks[k].push_back(w.create_body(def).id);
    }
  }
  std::vector<BodyId> all;
  for (auto const& s : stacks)
    all.insert(all.end(), s.begin(), s.end());
  REQUIRE(steps_to_sleep(w, all, 240) > 0);
  // Destroy a sleeping top box: only its island wakes.
  REQUIRE(w.destroy_body(stacks[1][1]) == BodyError::none);
  CHECK(!w.is_sleeping(stacks[1][0]));
  CHECK(all_sleeping(w, stacks[0]));
  CHECK(all_sleeping(w, stacks[2]));
  CHECK(w.sleeping_count() == 4);
  // Its slot is reused by a new body (asleep from birth), then everything sleeps again.
  BodyDef def = cube_def(1.0f, 1000.0f, 0.6f);
  def.pose = Iso3::from_translation({9.0f, 0.5f, 0.0f});
  def.awake = false;
  BodyId const fresh = w.create_body(def).id;
  CHECK(fresh.index == stacks[1][1].index);
  CHECK(w.is_sleeping(fresh));
  CHECK(w.sleeping_count() == 5);
  std::vector<BodyId> live = {stacks[0][0], stacks[0][1], stacks[1][0],
                              stacks[2][0], stacks[2][1], fresh};
  REQUIRE(steps_to_sleep(w, live, 240) > 0);
  CHECK(w.sleeping_count() == 6);
  // Stale ids: refused.
  CHECK(w.set_awake(stacks[1][1], true) == BodyError::bad_body);
  CHECK(w.set_sleep_enabled(stacks[1][1], false) == BodyError::bad_body);
  CHECK(w.set_sleep_threshold(stacks[1][1], 1.0f) == BodyError::bad_body);
  CHECK_THROWS(w.is_sleeping(stacks[1][1]));
  // Destroy every sleeping body, one by one: the count follows.
  for (BodyId id : live)
    REQUIRE(w.destroy_body(id) == BodyError::none);
  CHECK(w.sleeping_count() == 0);
  w.step(dt);
  CHECK(w.alive_count() == 1);
}

TEST_CASE("sleep: bad sleep settings are refused at creation", "[world][sleep][bad-input]") {
  World w;
  BodyDef def;
  def.sleep_threshold = -0.01f;
  CHECK(w.create_body(def).error == BodyError::bad_material);
  def.sleep_threshold = NAN;
  CHECK(w.create_body(def).error == BodyError::non_finite);
  def.sleep_threshold = INFINITY;
  CHECK(w.create_body(def).error == BodyError::non_finite);
  CHECK(w.alive_count() == 0);
  // A zero threshold: only a body at exactly rest sleeps (gravity-free, it does).
  WorldConfig cfg;
  cfg.gravity = Vec3{};
  World still(cfg);
  def.sleep_threshold = 0.0f;
  BodyId const b = still.create_body(def).id;
  std::vector<BodyId> const one = {b};
  int const n = steps_to_sleep(still, one, 40); // 0.5 s of 1/60 s steps, summed in float
  CHECK(n >= 30);
  CHECK(n <= 31);
}

TEST_CASE("sleep: time_to_sleep of zero or NaN", "[world][sleep][bad-input]") {
  for (float limit : {0.0f, -1.0f, NAN}) {
    WorldConfig cfg;
    cfg.time_to_sleep = limit;
    World w(cfg);
    add_ground(w);
    BodyId const ball = add_ball(w, {0.0f, 5.0f, 0.0f}, 0.25f, 0.0f);
    std::vector<BodyId> const box = add_box_stack(w, 1);
    w.set_velocity(box[0], Vec3{}, Vec3{});
    INFO("time_to_sleep " << limit);
    w.step(dt);
    CHECK(!w.is_sleeping(ball)); // falling: never asleep, whatever the limit
    if (std::isnan(limit)) {
      for (int s = 0; s < 120; ++s)
        w.step(dt);
      CHECK(!w.is_sleeping(box[0])); // NaN: never
      CHECK(!w.is_sleeping(ball));
    } else {
      CHECK(w.is_sleeping(box[0])); // at rest in its first step: asleep at once
    }
  }
}

TEST_CASE("sleep: turned off, nothing sleeps, even a body created asleep", "[world][sleep]") {
  WorldConfig cfg;
  cfg.sleep = false;
  World w(cfg);
  add_ground(w);
  std::vector<BodyId> const box = add_box_stack(w, 1);
  BodyDef def = cube_def(1.0f, 1000.0f, 0.6f);
  def.pose = Iso3::from_translation({3.0f, 0.5f, 0.0f});
  def.awake = false;
  BodyId const b = w.create_body(def).id;
  CHECK(!w.is_sleeping(b));
  CHECK(w.set_awake(box[0], false) == BodyError::none);
  for (int s = 0; s < 120; ++s)
    w.step(dt);
  CHECK(!w.is_sleeping(box[0]));
  CHECK(!w.is_sleeping(b));
  CHECK(w.sleep_time(box[0]) == 0.0f);
}

TEST_CASE("sleep: every solver width sleeps and wakes the same world",
          "[world][sleep][determinism]") {
  auto const run = []<class T>(std::type_identity<T>) {
    World w;
    add_ground(w);
    std::vector<BodyId> const ids = add_box_pyramid(w, 4);
    std::uint64_t h = 0;
    std::size_t asleep = 0;
    for (int s = 0; s < 150; ++s)
      w.template step_with<T>(dt);
    asleep = w.sleeping_count();
    float const top = w.aabb(ids.back()).max.y;
    add_ball(w, {0.2f, top + 1.0f, 0.1f}, 0.25f, 0.3f);
    for (int s = 0; s < 200; ++s) {
      w.template step_with<T>(dt);
      h = h * 31 + w.state_hash() + w.sleeping_count();
    }
    return std::pair{h, asleep};
  };
  auto const scalar = run(std::type_identity<float>{});
  CHECK(scalar.second == 30); // the pyramid slept before the ball came
  for_each_type<test::f32_wide_types>(
      [&]<class T>() { CHECK(run(std::type_identity<T>{}) == scalar); });
}

TEST_CASE("sleep: both broad phases sleep and wake the same world", "[world][sleep]") {
  auto const run = [](BroadPhaseKind kind) {
    WorldConfig cfg;
    cfg.broad_phase = kind;
    World w(cfg);
    add_ground(w);
    std::vector<BodyId> const ids = add_box_pyramid(w, 3);
    std::uint64_t h = 0;
    for (int s = 0; s < 150; ++s)
      w.step(dt);
    h = h * 31 + w.sleeping_count();
    // A static bar created through the pyramid's top, a ball dropped on a corner, a teleport.
    BodyDef bar;
    bar.type = BodyType::static_body;
    bar.shape = Cuboid{{2.0f, 0.05f, 0.05f}};
    bar.pose = Iso3::from_translation({0.0f, 2.9f, 0.0f});
    BodyId const b = w.create_body(bar).id;
    h = h * 31 + w.sleeping_count();
    for (int s = 0; s < 60; ++s) {
      w.step(dt);
      h = h * 31 + w.state_hash() + w.sleeping_count();
    }
    add_ball(w, {1.0f, 4.0f, 1.0f});
    w.set_pose(b, Iso3::from_translation({0.0f, -3.0f, 0.0f}));
    for (int s = 0; s < 200; ++s) {
      w.step(dt);
      h = h * 31 + w.state_hash() + w.sleeping_count();
    }
    return std::pair{h, all_sleeping(w, ids)};
  };
  auto const bvh = run(BroadPhaseKind::bvh);
  CHECK(bvh == run(BroadPhaseKind::sort_and_sweep));
  CHECK(bvh.second); // asleep again at the end
}
