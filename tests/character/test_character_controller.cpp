// CharacterController in a world: the controller scenarios (stairs, ramps, ledges, moving and
// rotating platforms, pushing a crate, two characters meeting, crouching under a ceiling), each
// asserting the property it names, driven by the game loop of the header's comment: the world
// steps, then the character gets its walking velocity (gravity added in the air) and updates.
// The character is the default capsule (radius 0.3, half height 0.5: 1.6 m tall, its centre
// 0.8 + skin above the floor it stands on).
#include <plume/solver/world/character_controller.hpp>
#include <plume/solver/world/world.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

using namespace plume;

namespace {

constexpr float dt = 1.0f / 60.0f;
constexpr float skin = 0.01f;
constexpr float stand = 0.8f + skin; // the capsule's centre above the floor it stands on

BodyId add_box(World& w, Vec3 const& centre, Vec3 const& half, Quat const& rot = Quat::IDENTITY,
               BodyType type = BodyType::static_body) {
  return w.create_body({.type = type, .pose = Iso3{rot, centre}, .shape = Cuboid{half}}).id;
}

/// A floor whose top is at y = 0.
BodyId add_floor(World& w) { return add_box(w, {0, -0.5f, 0}, {60, 0.5f, 60}); }

/// A ramp rising along +x at `degrees` from its foot at (x0, 0), 3 m wide in z.
BodyId add_ramp(World& w, float x0, float degrees, float length = 12.0f) {
  float const a = degrees * std::numbers::pi_v<float> / 180.0f;
  Quat const r = Quat::from_rotation_z(a);
  Vec3 const n = r * Vec3{0, 1, 0};
  Vec3 const centre = Vec3{x0, 0, 0} + r * Vec3{length, 0, 0} - n * 0.5f;
  return add_box(w, centre, {length, 0.5f, 3.0f}, r);
}

struct Frame {
  Vec3 position;
  GroundState state;
};

/// With PLUME_TRAJECTORY_DIR set, drive() writes each scenario's frames (position, ground
/// state) and the contact planes of each move to <dir>/<scenario>.csv, for
/// tools/plot_trajectories.py to draw.
class Trajectory {
public:
  static Trajectory& get() {
    static Trajectory t;
    return t;
  }
  void start(std::string const& name) {
    close();
    char const* dir = std::getenv("PLUME_TRAJECTORY_DIR");
    if (!dir) return;
    file_ = std::fopen((std::string(dir) + "/" + name + ".csv").c_str(), "w");
    if (file_) std::fprintf(file_, "kind,frame,x,y,z,state,nx,ny,nz\n");
    frame_ = 0;
  }
  void frame(CharacterController const& c) {
    if (!file_) return;
    Vec3 const p = c.position();
    std::fprintf(file_, "frame,%d,%.6f,%.6f,%.6f,%d,0,0,0\n", frame_, p.x, p.y, p.z,
                 int(c.ground_state()));
    for (MoveHit<ColliderId> const& h : c.last_update().move.accepted())
      std::fprintf(file_, "plane,%d,%.6f,%.6f,%.6f,0,%.6f,%.6f,%.6f\n", frame_, h.point.x,
                   h.point.y, h.point.z, h.normal.x, h.normal.y, h.normal.z);
    ++frame_;
  }
  ~Trajectory() { close(); }

private:
  void close() {
    if (file_) std::fclose(file_);
    file_ = nullptr;
  }
  std::FILE* file_ = nullptr;
  int frame_ = 0;
};

void record(std::string const& name) { Trajectory::get().start(name); }

/// The game loop: step the world, then walk. On the ground the velocity is `walk` (plus one
/// frame of gravity with `always_gravity`, as Jolt's samples do); off it, the last velocity
/// plus gravity (momentum kept: a slide down a steep slope speeds up).
std::vector<Frame> drive(World& w, CharacterController& c, Vec3 const& walk, int frames,
                         bool step_world = true, bool always_gravity = false) {
  std::vector<Frame> out;
  Vec3 const g = w.config().gravity;
  for (int f = 0; f < frames; ++f) {
    if (step_world) w.step(dt);
    Vec3 v = c.velocity();
    if (c.on_ground())
      v = always_gravity ? walk + g * dt : walk;
    else
      v = v + g * dt;
    REQUIRE(c.set_velocity(v) == CharacterError::none);
    CharacterUpdate const& u = c.update(w, dt);
    REQUIRE(!u.invalid_input);
    REQUIRE(c.position().is_finite());
    out.push_back({c.position(), c.ground_state()});
    Trajectory::get().frame(c);
  }
  return out;
}

bool same(Vec3 const& a, Vec3 const& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

float spread(std::vector<Frame> const& path, std::size_t last) {
  Vec3 const ref = path[path.size() - last].position;
  float s = 0;
  for (std::size_t i = path.size() - last; i < path.size(); ++i)
    s = std::max(s, (path[i].position - ref).length());
  return s;
}

float max_y(std::vector<Frame> const& path) {
  float m = -1e30f;
  for (Frame const& f : path)
    m = std::max(m, f.position.y);
  return m;
}

int count(std::vector<Frame> const& path, GroundState s, std::size_t from = 0) {
  int n = 0;
  for (std::size_t i = from; i < path.size(); ++i)
    n += path[i].state == s ? 1 : 0;
  return n;
}

/// Steps of rise h, 0.5 m deep, the first face at x = 2, up to `steps`, then a long top.
void add_stairs(World& w, float h, int steps) {
  for (int k = 1; k <= steps; ++k) {
    float const x0 = 2.0f + 0.5f * float(k - 1);
    add_box(w, {x0 + 6.0f, 0.5f * h * float(k), 0}, {6.0f, 0.5f * h * float(k), 3.0f});
  }
}

} // namespace

TEST_CASE("character: lands on a floor, stands still without drift, walks at its speed",
          "[character][controller]") {
  record("floor");
  World w;
  BodyId const floor = add_floor(w);
  CharacterController c(w, {.position = {0, 1.5f, 0}});
  CHECK(c.ground_state() == GroundState::in_air);
  auto const fall = drive(w, c, {}, 60);
  CHECK(fall.front().state == GroundState::in_air);
  REQUIRE(c.on_ground());
  CHECK(c.ground().body == floor);
  CHECK(c.ground().normal.y > 0.9999f);
  CHECK(c.position().y == Approx(stand).margin(2e-3));
  auto const still = drive(w, c, {}, 120, true, true);
  CHECK(spread(still, 120) < 1e-5f);
  CHECK(count(still, GroundState::on_ground) == 120);

  Vec3 const from = c.position();
  auto const run = drive(w, c, {4, 0, 0}, 60);
  CHECK(count(run, GroundState::on_ground) == 60);
  CHECK(c.position().x - from.x == Approx(4.0f).epsilon(0.01));
  CHECK(std::abs(c.position().y - from.y) < 1e-3f);
  CHECK(c.world_velocity().x == Approx(4.0f).epsilon(1e-3));
}

TEST_CASE("character: a level of standalone colliders is walked as one of static bodies, "
          "frame for frame",
          "[character][controller]") {
  // A floor, a ramp and a wall, as static bodies in one world and as colliders without bodies
  // in the other (the same slots): the same walk, bit for bit, and the ground named by its
  // collider (no body).
  auto const level = [](bool standalone) {
    World w;
    auto const add = [&](Vec3 const& centre, Vec3 const& half, Quat const& rot) {
      if (standalone)
        REQUIRE(w.create_collider({.pose = Iso3{rot, centre}, .shape = Cuboid{half}}));
      else
        add_box(w, centre, half, rot);
    };
    add({0, -0.5f, 0}, {60, 0.5f, 60}, Quat::IDENTITY);
    Quat const r = Quat::from_rotation_z(20.0f * std::numbers::pi_v<float> / 180.0f);
    add(Vec3{3, 0, 0} + r * Vec3{4, 0, 0} - r * Vec3{0, 0.5f, 0}, {4, 0.5f, 3}, r);
    add({-3, 1, 0}, {0.2f, 1, 3}, Quat::IDENTITY);
    return w;
  };
  World a = level(false), b = level(true);
  REQUIRE(b.collider_count() == 3);
  CharacterController ca(a, {.position = {0, 1.5f, 0}});
  CharacterController cb(b, {.position = {0, 1.5f, 0}});
  for (Vec3 const walk : {Vec3{}, Vec3{3, 0, 0}, Vec3{-6, 0, 0.5f}}) {
    auto const pa = drive(a, ca, walk, 90);
    auto const pb = drive(b, cb, walk, 90);
    for (std::size_t f = 0; f < pa.size(); ++f) {
      INFO("frame " << f);
      REQUIRE(same(pa[f].position, pb[f].position));
      REQUIRE(pa[f].state == pb[f].state);
    }
    REQUIRE(cb.on_ground());
    CHECK(cb.ground().collider.standalone);
    CHECK(!cb.ground().body.valid());
    CHECK(cb.ground().collider.index == ca.ground().body.index);
    CHECK(same(cb.ground().velocity, Vec3{}));
  }
  CHECK(cb.position().x < -2.4f); // stopped by the wall (its face at x = -2.8)
  CHECK(cb.position().x > -2.8f);
}

TEST_CASE("character: a 30 degree ramp is walked up and stood on without drifting",
          "[character][controller]") {
  record("ramp_30");
  World w;
  add_floor(w);
  BodyId const ramp = add_ramp(w, 2.0f, 30.0f);
  CharacterController c(w, {.position = {0, stand, 0}});
  drive(w, c, {}, 5);
  REQUIRE(c.on_ground());
  auto const up = drive(w, c, {2, 0, 0}, 240);
  // On the ground all the way, across the crease; 2 m/s horizontally on the ramp.
  CHECK(count(up, GroundState::on_ground) == 240);
  CHECK(c.ground().body == ramp);
  float const tan30 = std::tan(std::numbers::pi_v<float> / 6.0f);
  Vec3 const a = up[179].position, b = up[239].position;
  CHECK(b.x - a.x == Approx(2.0f).epsilon(0.01));
  CHECK(b.y - a.y == Approx(2.0f * tan30).epsilon(0.01));
  // Standing still on it, gravity pulling every frame: no slide.
  auto const still = drive(w, c, {}, 180, true, true);
  CHECK(count(still, GroundState::on_ground) == 180);
  CHECK(spread(still, 175) < 1e-4f);
  // Walking up it with gravity every frame keeps the horizontal speed too.
  Vec3 const at = c.position();
  auto const again = drive(w, c, {2, 0, 0}, 60, true, true);
  CHECK(count(again, GroundState::on_ground) == 60);
  CHECK(c.position().x - at.x == Approx(2.0f).epsilon(0.01));
  // Walking down it does not lift off.
  auto const down = drive(w, c, {-2, 0, 0}, 60);
  CHECK(count(down, GroundState::on_ground) == 60);
}

TEST_CASE("character: a 60 degree ramp cannot be climbed, and it slides down it",
          "[character][controller]") {
  record("ramp_60_walk");
  World w;
  add_floor(w);
  add_ramp(w, 2.0f, 60.0f, 6.0f);
  CharacterController c(w, {.position = {0, stand, 0}});
  auto const into = drive(w, c, {3, 0, 0}, 180);
  CHECK(max_y(into) < stand + 0.02f);
  CHECK(c.position().x < 2.0f);
  CHECK(spread(into, 60) < 1e-3f);

  // Dropped onto the slope, it slides down to the floor.
  record("ramp_60_slide");
  World w2;
  add_floor(w2);
  add_ramp(w2, 2.0f, 60.0f, 6.0f);
  CharacterController s(w2, {.position = {4.0f, 6.0f, 0}});
  auto const slide = drive(w2, s, {}, 180);
  CHECK(count(slide, GroundState::on_steep_ground) > 10);
  CHECK(s.on_ground());
  CHECK(s.position().y == Approx(stand).margin(5e-3));
  CHECK(s.position().x < 2.0f);
}

TEST_CASE("character: a jump into a 60 degree slope goes no higher than a jump in the open",
          "[character][controller]") {
  record("ramp_60_jump");
  World w;
  add_floor(w);
  add_ramp(w, 2.0f, 60.0f, 6.0f);
  CharacterController c(w, {.position = {1.0f, stand, 0}});
  drive(w, c, {}, 2);
  REQUIRE(c.on_ground());
  // 3 m/s at the slope and 5 m/s up: the slope is a wall to the horizontal part, so it
  // cannot turn it into height (without the wall it slides up the slope, higher).
  REQUIRE(c.set_velocity({3, 5, 0}) == CharacterError::none);
  c.update(w, dt);
  auto const jump = drive(w, c, {}, 150);
  float top = 0; // the open jump's peak, as the loop integrates it
  for (float v = 5.0f; v > 0.0f; v -= 9.81f * dt)
    top += v * dt;
  CHECK(max_y(jump) - stand < top + 0.005f);
  CHECK(max_y(jump) - stand > top - 0.05f);
  CHECK(c.position().y < stand + 0.3f); // back down at the foot
}

TEST_CASE("character: the ground is the nearest walkable support (a 5 mm mat on a floor)",
          "[character][controller]") {
  World w;
  add_floor(w);
  BodyId const mat = add_box(w, {-5, 0.0025f, 0}, {5, 0.0025f, 5}); // top at 5 mm, x < 0
  CharacterController c(w, {.position = {-1, stand + 0.005f, 0}});
  drive(w, c, {}, 10);
  REQUIRE(c.on_ground());
  // The floor is within the ground tolerance too (1.5 cm under the capsule), and as flat.
  CHECK(c.ground().body == mat);
  CHECK(c.ground().separation == Approx(skin).margin(1e-3));
  CHECK(c.position().y == Approx(stand + 0.005f).margin(1e-3));
}

TEST_CASE("character: the step ignores the proxy (a ball falls through the character)",
          "[character][controller]") {
  World w;
  add_floor(w);
  CharacterController c(w, {.position = {0, stand, 0}});
  BodyId const ball =
      w.create_body({.pose = Iso3::from_translation({0, 3, 0}), .shape = Sphere{0.2f}}).id;
  CHECK(w.layers(c.proxy()).filters == 0u);
  drive(w, c, {}, 120);
  CHECK(w.pose(ball).translation.y == Approx(0.2f).margin(0.02));
}

TEST_CASE("character: feeding its velocity back does not launch it off the steps it rolls up",
          "[character][controller][stairs]") {
  record("stairs_10cm_fed_back");
  World w;
  add_floor(w);
  add_stairs(w, 0.1f, 3);
  CharacterController c(w, {.position = {0, stand, 0}});
  Vec3 const g = w.config().gravity, walk{2, 0, 0};
  float top = 0;
  for (int f = 0; f < 180; ++f) {
    w.step(dt);
    Vec3 const v = c.velocity();
    // The vertical part kept, gravity always: what a game that never resets it does.
    c.set_velocity(walk + Vec3{0, v.y, 0} + g * dt);
    c.update(w, dt);
    top = std::max(top, c.position().y);
    Trajectory::get().frame(c);
  }
  CHECK(top < 0.3f + stand + 0.005f);
  CHECK(c.position().y == Approx(0.3f + stand).margin(5e-3));
}

TEST_CASE("character: wedged in a V of two 60 degree slopes, it stands",
          "[character][controller]") {
  record("valley");
  World w;
  add_ramp(w, 0.0f, 60.0f, 6.0f);
  float const a = std::numbers::pi_v<float> / 3.0f;
  Quat const r = Quat::from_rotation_z(-a); // the mirror image, rising along -x
  Vec3 const n = r * Vec3{0, 1, 0};
  add_box(w, r * Vec3{-6.0f, 0, 0} - n * 0.5f, {6.0f, 0.5f, 3.0f}, r);
  CharacterController c(w, {.position = {0, 3.0f, 0}});
  auto const path = drive(w, c, {}, 120);
  CHECK(c.on_ground());
  CHECK(c.ground().normal.y == Approx(1.0f).margin(1e-4));
  CHECK(count(path, GroundState::on_ground, 60) == 60);
  CHECK(spread(path, 60) < 1e-5f);
  CHECK(std::abs(c.position().x) < 1e-3f);
}

TEST_CASE("character: stairs up to the step height are climbed, higher ones block",
          "[character][controller][stairs]") {
  for (float h : {0.1f, 0.2f, 0.3f, 0.35f}) {
    INFO("step " << h);
    record("stairs_" + std::to_string(int(h * 100)) + "cm");
    World w;
    add_floor(w);
    add_stairs(w, h, 3);
    CharacterController c(w, {.position = {0, stand, 0}});
    auto const path = drive(w, c, {2, 0, 0}, 180);
    CHECK(c.on_ground());
    CHECK(c.position().y == Approx(3 * h + stand).margin(5e-3));
    CHECK(c.position().x > 4.5f);
    CHECK(max_y(path) < 3 * h + stand + 0.02f); // not launched
    CHECK(count(path, GroundState::in_air) == 0);
    // And back down: stuck to each step, never in the air.
    auto const down = drive(w, c, {-2, 0, 0}, 180);
    CHECK(count(down, GroundState::in_air) == 0);
    CHECK(c.position().y == Approx(stand).margin(5e-3));
  }
  for (float h : {0.45f, 0.6f}) {
    INFO("step " << h);
    record("stairs_blocked_" + std::to_string(int(h * 100)) + "cm");
    World w;
    add_floor(w);
    add_stairs(w, h, 3);
    CharacterController c(w, {.position = {0, stand, 0}});
    auto const path = drive(w, c, {2, 0, 0}, 180);
    CHECK(max_y(path) < stand + 0.02f);
    CHECK(c.position().x < 2.0f - 0.3f + 0.02f);
    CHECK(c.on_ground());
  }
}

TEST_CASE("character: walking off a ledge sticks to the floor below within the distance, "
          "falls beyond it",
          "[character][controller]") {
  for (float drop : {0.2f, 0.45f, 1.0f}) {
    INFO("drop " << drop);
    record("ledge_" + std::to_string(int(drop * 100)) + "cm");
    World w;
    add_floor(w);
    add_box(w, {-4.0f, 0.5f * drop, 0}, {6.0f, 0.5f * drop, 3.0f}); // ledge edge at x = 2
    CharacterController c(w, {.position = {0, drop + stand, 0}});
    auto const path = drive(w, c, {2, 0, 0}, 120);
    CHECK(c.on_ground());
    CHECK(c.position().y == Approx(stand).margin(5e-3));
    int const air = count(path, GroundState::in_air);
    if (drop < 0.5f)
      CHECK(air == 0);
    else
      CHECK(air > 5);
  }
}

TEST_CASE("character: a moving and a rotating platform carry it", "[character][controller]") {
  SECTION("moving") {
    record("platform_moving");
    World w;
    BodyId const p = add_box(w, {0, -0.25f, 0}, {2, 0.25f, 2}, Quat::IDENTITY, BodyType::kinematic);
    w.set_velocity(p, {1, 0, 0}, {});
    CharacterController c(w, {.position = {0, stand, 0}});
    drive(w, c, {}, 2);
    REQUIRE(c.on_ground());
    Vec3 const from = c.position();
    auto const path = drive(w, c, {}, 90);
    CHECK(count(path, GroundState::on_ground) == 90);
    CHECK(c.position().x - from.x == Approx(1.5f).margin(0.02));
    CHECK(std::abs(c.position().y - from.y) < 2e-3f);
    CHECK(c.world_velocity().x == Approx(1.0f).epsilon(1e-3));
  }
  SECTION("rising") {
    record("platform_rising");
    World w;
    BodyId const p = add_box(w, {0, -0.25f, 0}, {2, 0.25f, 2}, Quat::IDENTITY, BodyType::kinematic);
    w.set_velocity(p, {0, 1, 0}, {});
    CharacterController c(w, {.position = {0, stand, 0}});
    auto const path = drive(w, c, {}, 90);
    CHECK(count(path, GroundState::on_ground, 2) == 88);
    float const top = w.pose(p).translation.y + 0.25f;
    CHECK(c.position().y - top == Approx(stand).margin(5e-3));
  }
  SECTION("rotating") {
    record("platform_rotating");
    World w;
    BodyId const p = add_box(w, {0, -0.25f, 0}, {3, 0.25f, 3}, Quat::IDENTITY, BodyType::kinematic);
    w.set_velocity(p, {}, {0, 1, 0});
    CharacterController c(w, {.position = {2, stand, 0}});
    drive(w, c, {}, 1);
    REQUIRE(c.on_ground());
    float const a0 = std::atan2(-c.position().z, c.position().x);
    auto const path = drive(w, c, {}, 120); // 2 rad
    CHECK(count(path, GroundState::on_ground) == 120);
    Vec3 const q = c.position();
    CHECK(std::hypot(q.x, q.z) == Approx(2.0f).margin(0.01));
    CHECK(std::atan2(-q.z, q.x) - a0 == Approx(2.0f).margin(0.02));
    // The character turned with it, about up.
    auto const [axis, angle] = c.rotation().to_axis_angle();
    CHECK(std::abs(angle) == Approx(2.0f).margin(0.02));
    CHECK(std::abs(axis.y) == Approx(1.0f).margin(1e-3));
  }
}

TEST_CASE("character: jumping off a moving platform keeps its velocity; landing on one sheds it",
          "[character][controller]") {
  World w;
  BodyId const p = add_box(w, {0, -0.25f, 0}, {20, 0.25f, 2}, Quat::IDENTITY, BodyType::kinematic);
  w.set_velocity(p, {2, 0, 0}, {});
  CharacterController c(w, {.position = {0, stand, 0}});
  drive(w, c, {}, 3);
  REQUIRE(c.on_ground());
  CHECK(c.velocity().x == 0.0f); // relative to the platform
  CHECK(c.world_velocity().x == Approx(2.0f));
  w.step(dt);
  c.set_velocity({0, 4, 0}); // a jump, relative to the platform
  c.update(w, dt);
  REQUIRE(c.ground_state() == GroundState::in_air);
  CHECK(c.velocity().x == Approx(2.0f)); // in the world now
  float const x0 = c.position().x, p0 = w.pose(p).translation.x;
  auto const air = drive(w, c, {}, 60);
  // Back on the platform: it moved along with it, and the velocity is relative again.
  REQUIRE(c.on_ground());
  CHECK(count(air, GroundState::in_air) > 20);
  CHECK((c.position().x - x0) - (w.pose(p).translation.x - p0) == Approx(0.0f).margin(0.04));
  CHECK(std::abs(c.velocity().x) < 1e-3f);
}

TEST_CASE("character: sensors are walked through unless sensors_block", "[character][controller]") {
  for (bool const block : {false, true}) {
    World w;
    add_floor(w);
    w.create_body({.type = BodyType::static_body,
                   .pose = Iso3::from_translation({2, 1, 0}),
                   .shape = Cuboid{{0.5f, 1, 2}},
                   .sensor = true});
    CharacterController c(w, {.position = {0, stand, 0}, .sensors_block = block});
    drive(w, c, {2, 0, 0}, 120);
    if (block)
      CHECK(c.position().x < 1.5f - 0.3f + 0.02f);
    else
      CHECK(c.position().x > 3.5f);
  }
}

TEST_CASE("character: pushing a 50 kg crate moves it at the speed its strength allows",
          "[character][controller][push]") {
  World w;
  w.create_body({.type = BodyType::static_body,
                 .pose = Iso3::from_translation({0, -0.5f, 0}),
                 .shape = Cuboid{{60, 0.5f, 60}},
                 .friction = 0.1f});
  BodyId const crate = w.create_body({.pose = Iso3::from_translation({1.5f, 0.5f, 0}),
                                      .shape = Cuboid{{0.5f, 0.5f, 0.5f}},
                                      .density = 50.0f,
                                      .friction = 0.1f})
                           .id;
  REQUIRE(w.mass(crate) == Approx(50.0f));
  CharacterController c(w, {.position = {0, stand, 0}});
  // 100 N against 0.1 x 50 kg x 9.81 of friction: 1.02 m/s^2 until it walks as fast as the
  // character (2 m/s).
  std::vector<float> speed;
  int first = -1;
  for (int f = 0; f < 240; ++f) {
    drive(w, c, {2, 0, 0}, 1);
    speed.push_back(w.linear_velocity(crate).x);
    if (first < 0 && !c.pushes().empty()) first = f;
    for (CharacterPush const& p : c.pushes())
      CHECK(p.impulse.length() <= c.config().max_strength * dt * 1.0001f);
  }
  REQUIRE(first >= 0);
  REQUIRE(first < 60);
  float const a = (100.0f - 0.1f * 50.0f * 9.81f) / 50.0f;
  CHECK(speed[std::size_t(first + 60)] == Approx(a).epsilon(0.15));
  CHECK(*std::max_element(speed.begin(), speed.end()) < 2.02f);
  CHECK(speed.back() > 1.7f);

  // Too heavy to move (500 kg on a 0.6 floor): it stands, and so does the character.
  World h;
  add_floor(h);
  BodyId const heavy = h.create_body({.pose = Iso3::from_translation({1.5f, 0.5f, 0}),
                                      .shape = Cuboid{{0.5f, 0.5f, 0.5f}},
                                      .density = 500.0f})
                           .id;
  CharacterController d(h, {.position = {0, stand, 0}});
  drive(h, d, {2, 0, 0}, 120);
  CHECK(std::abs(h.pose(heavy).translation.x - 1.5f) < 0.01f);
  CHECK(d.position().x < 1.5f - 0.5f - 0.3f + 0.02f);
}

TEST_CASE("character: on a moving platform, a crate ahead is pushed by the walk relative to it",
          "[character][controller][push]") {
  // Platform, crate and character all move at 2 m/s; the character walks 1 m/s faster, so it
  // closes on the crate at 1 m/s and pushes it, though the crate outruns its walking speed.
  World w;
  BodyId const p = w.create_body({.type = BodyType::kinematic,
                                  .pose = Iso3::from_translation({0, -0.25f, 0}),
                                  .linear_velocity = {2, 0, 0},
                                  .shape = Cuboid{{40, 0.25f, 3}},
                                  .friction = 0.1f})
                       .id;
  BodyId const crate = w.create_body({.pose = Iso3::from_translation({1.5f, 0.5f, 0}),
                                      .linear_velocity = {2, 0, 0},
                                      .shape = Cuboid{{0.5f, 0.5f, 0.5f}},
                                      .density = 50.0f,
                                      .friction = 0.1f})
                           .id;
  CharacterController c(w, {.position = {0, stand, 0}});
  int pushed = 0;
  for (int f = 0; f < 180; ++f) {
    drive(w, c, {1, 0, 0}, 1);
    pushed += c.pushes().empty() ? 0 : 1;
  }
  REQUIRE(c.on_ground());
  CHECK(c.ground().body == p);
  CHECK(pushed > 60);
  // Pushed along relative to the platform, no faster than the character walks on it.
  float const relative = w.linear_velocity(crate).x - 2.0f;
  CHECK(relative > 0.3f);
  CHECK(relative < 1.02f);
}

TEST_CASE("character: its weight pushes down on the dynamic body it stands on",
          "[character][controller][push]") {
  World w;
  add_floor(w);
  BodyId const crate = w.create_body({.pose = Iso3::from_translation({0, 0.5f, 0}),
                                      .shape = Cuboid{{1, 0.5f, 1}},
                                      .density = 50.0f})
                           .id;
  CharacterController c(w, {.position = {0.2f, 1.0f + stand, 0}});
  drive(w, c, {}, 30);
  REQUIRE(c.on_ground());
  REQUIRE(c.ground().body == crate);
  REQUIRE(c.pushes().size() == 1);
  CharacterPush const& p = c.pushes()[0];
  CHECK(p.body == crate);
  CHECK(p.impulse.y == Approx(-9.81f * 70.0f * dt).epsilon(1e-5));
  CHECK(p.point.y == Approx(1.0f).margin(1e-3));
  CHECK(p.point.x == Approx(0.2f).margin(1e-3));
}

TEST_CASE("character: two characters walking into each other stop, touching, without overlap",
          "[character][controller]") {
  World w;
  add_floor(w);
  CharacterController a(w, {.position = {-2, stand, 0}});
  CharacterController b(w, {.position = {2, stand, 0}});
  std::vector<Vec3> pa, pb;
  for (int f = 0; f < 150; ++f) {
    drive(w, a, {2, 0, 0}, 1);
    drive(w, b, {-2, 0, 0}, 1, false);
    pa.push_back(a.position());
    pb.push_back(b.position());
    Vec3 const d = b.position() - a.position();
    CHECK(std::hypot(d.x, d.z) >= 0.6f);
  }
  Vec3 const d = pb.back() - pa.back();
  CHECK(std::hypot(d.x, d.z) < 0.6f + 3 * skin);
  for (std::size_t i = 120; i < 150; ++i) {
    CHECK((pa[i] - pa[119]).length() < 0.02f);
    CHECK((pb[i] - pb[119]).length() < 0.02f);
  }
  CHECK(a.on_ground());
  CHECK(b.on_ground());
  // A ray cast from the side finds a character's proxy.
  auto const hit = w.ray_cast(Ray3{{pa.back().x, 1.0f, -5}, {0, 0, 1}}, 10.0f);
  REQUIRE(hit);
  CHECK(hit->body == a.proxy());
}

TEST_CASE("character: crouching under a low ceiling, and standing refused until out",
          "[character][controller][crouch]") {
  record("crouch");
  World w;
  add_floor(w);
  add_box(w, {4, 1.2f + 0.5f, 0}, {2, 0.5f, 3}); // ceiling at 1.2 m over x in [2, 6]
  CharacterController c(w, {.position = {0, stand, 0}});
  drive(w, c, {}, 2);
  // Standing, it cannot walk under.
  drive(w, c, {2, 0, 0}, 90);
  CHECK(c.position().x < 2.0f - 0.3f + 0.02f);
  // Crouched (0.8 m tall), the feet stay on the floor and it walks under.
  float const feet = c.position().y - 0.8f;
  REQUIRE(c.set_shape(w, Capsule{0.1f, 0.3f}) == CharacterError::none);
  CHECK(c.position().y - 0.4f == Approx(feet).margin(1e-5));
  CHECK(std::get<Capsule>(w.shape(c.proxy())).half_height == 0.1f);
  CHECK(w.alive_count() == 3); // floor, ceiling, one proxy: the old one is gone
  drive(w, c, {2, 0, 0}, 90);
  CHECK(c.position().x > 3.5f);
  CHECK(c.on_ground());
  // Standing up under the ceiling is refused, and nothing changes.
  Vec3 const here = c.position();
  CHECK(c.set_shape(w, Capsule{0.5f, 0.3f}) == CharacterError::overlap);
  CHECK(std::get<Capsule>(c.shape()).half_height == 0.1f);
  CHECK(same(c.position(), here));
  drive(w, c, {2, 0, 0}, 120);
  REQUIRE(c.position().x > 6.5f);
  CHECK(c.set_shape(w, Capsule{0.5f, 0.3f}) == CharacterError::none);
  CHECK(c.position().y == Approx(stand).margin(2e-3));
}

TEST_CASE("character: another up direction gives the same walk, rotated",
          "[character][controller]") {
  // The stairs scene with +z up and gravity along -z, against the +y original.
  WorldConfig zc;
  zc.gravity = {0, 0, -9.81f};
  World y, z(zc);
  add_floor(y);
  add_stairs(y, 0.3f, 3);
  Quat const rot = Quat::from_rotation_x(std::numbers::pi_v<float> / 2); // +y -> +z
  for (std::uint32_t i = 0; i < y.body_count(); ++i) {
    BodyId const id = y.body_id(i);
    Iso3 const p = y.pose(id);
    z.create_body({.type = BodyType::static_body,
                   .pose = Iso3{rot * p.rotation, rot * p.translation},
                   .shape = y.shape(id)});
  }
  CharacterController cy(y, {.position = {0, stand, 0}});
  CharacterController cz(z, {.position = rot * Vec3{0, stand, 0}, .up = {0, 0, 1}});
  auto const py = drive(y, cy, {2, 0, 0}, 150);
  auto const pz = drive(z, cz, {2, 0, 0}, 150);
  int differ = 0;
  for (std::size_t i = 0; i < py.size(); ++i) {
    CHECK((rot * py[i].position - pz[i].position).length() < 2e-3f);
    differ += py[i].state != pz[i].state ? 1 : 0;
  }
  CHECK(differ <= 2); // rounding can tip a contact on a step's edge either way
  CHECK(cz.position().z == Approx(0.9f + stand).margin(5e-3));
}

TEST_CASE("character: bad input", "[character][controller][bad-input]") {
  World w;
  add_floor(w);
  CHECK_THROWS_AS(CharacterController(w, {.up = {0, 0, 0}}), std::invalid_argument);
  CHECK_THROWS_AS(CharacterController(w, {.shape = HalfSpace{Vec3::Y}}), std::invalid_argument);
  CHECK_THROWS_AS(CharacterController(w, {.shape = Sphere{0.0f}}), std::invalid_argument);
  CHECK_THROWS_AS(CharacterController(w, {.max_slope = -1.0f}), std::invalid_argument);
  CHECK_THROWS_AS(CharacterController(w, {.max_slope = 1.5707964f}), std::invalid_argument);
  static_assert(std::is_move_constructible_v<CharacterController>);
  static_assert(!std::is_move_assignable_v<CharacterController>); // would leak a proxy
  static_assert(!std::is_copy_constructible_v<CharacterController>);
  CHECK(CharacterConfig{}.scaled(100.0f).max_strength == 100.0f * 100.0f); // N: kg m/s^2
  CHECK_THROWS_AS(CharacterController(w, {.position = {NAN, 0, 0}}), std::invalid_argument);
  std::size_t const bodies = w.alive_count();

  CharacterController c(w, {.position = {0, stand, 0}});
  CHECK(w.alive_count() == bodies + 1);
  drive(w, c, {}, 3);
  Vec3 const at = c.position();
  for (float bad : {NAN, INFINITY, -1.0f}) {
    CharacterUpdate const& u = c.update(w, bad);
    CHECK(u.invalid_input);
    CHECK(same(c.position(), at));
  }
  CHECK(c.set_velocity({NAN, 0, 0}) == CharacterError::non_finite);
  CHECK(c.set_position(w, {0, INFINITY, 0}) == CharacterError::non_finite);
  CHECK(c.set_rotation(w, Quat::from_xyzw(0, 0, 0, 0)) == CharacterError::non_finite);
  CHECK(c.set_shape(w, HalfSpace{Vec3::Y}) == CharacterError::bad_shape);
  CHECK(c.set_shape(w, Capsule{0.5f, -0.3f}) == CharacterError::bad_shape);
  CHECK(c.set_shape(w, Capsule{0.1f, 0.3f}, -1.0f) == CharacterError::bad_shape);
  CHECK(same(c.position(), at));
  // dt = 0 moves nothing.
  c.set_velocity({5, 0, 0});
  c.update(w, 0.0f);
  CHECK(same(c.position(), at));
  // A huge dt moves at most iterations x max_move.
  c.update(w, 1e30f);
  CHECK((c.position() - at).length() <= 4 * 100.0f + 1.0f);
  // Destroying the proxy takes its body out of the world; a moved-from controller has none.
  CharacterController moved = std::move(c);
  CHECK(!c.proxy().valid());
  moved.destroy(w);
  CHECK(w.alive_count() == bodies);
}
