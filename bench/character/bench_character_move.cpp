// plume_bench_character_move: move_and_slide through a level, one character at a time and W
// at a time (character_move/level/plume/x<W>: move_and_slide_lanes<T>, x1 = float; `loop`:
// move_and_slide per character). items = character moves.
//
// The level: a floor, a grid of 0.6 m pillars 3 m apart, ramps and low steps between them
// (world bodies, 1,200 in all). 512 capsules of different sizes (radius 0.3-0.4 m, half
// height 0.4-0.6 m) in 8 crowds of 64 within 4 m of each other, each asking for 5 m/s in its
// own direction plus -2 m/s of gravity, for one 1/60 s frame from the same start every
// iteration: the work of a crowd's frame. character_controller/level/plume/loop: the same
// crowd as CharacterControllers walking the level (below).
#include <plume/solver/character/move_and_slide.hpp>
#include <plume/solver/world/character_controller.hpp>
#include <plume/solver/world/move_query.hpp>
#include <plume/solver/world/world.hpp>

#include "../bench_support.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace plume;

constexpr float dt = 1.0f / 60.0f;

void build_level(World& w) {
  w.create_body({.type = BodyType::static_body,
                 .pose = Iso3::from_translation({0, -1.0f, 0}),
                 .shape = HalfSpace{Vec3::Y}});
  for (int i = -10; i < 10; ++i)
    for (int k = -10; k < 10; ++k) {
      Vec3 const at{3.0f * float(i), 0.5f, 3.0f * float(k)};
      w.create_body({.type = BodyType::static_body,
                     .pose = Iso3::from_translation(at),
                     .shape = Cuboid{Vec3{0.3f, 1.5f, 0.3f}}});
      w.create_body({.type = BodyType::static_body,
                     .pose = Iso3{Quat::from_rotation_z(0.25f), at + Vec3{1.5f, -1.2f, 0}},
                     .shape = Cuboid{Vec3{0.8f, 0.2f, 0.5f}}});
      w.create_body({.type = BodyType::static_body,
                     .pose = Iso3::from_translation(at + Vec3{0, -1.4f, 1.5f}),
                     .shape = Cuboid{Vec3{0.5f, 0.15f, 0.5f}}});
    }
  w.step(1.0f / 60.0f); // the step builds the static tree's wide copy the queries walk
}

World const& level() {
  static World const level_world = [] {
    World w;
    build_level(w);
    return w;
  }();
  return level_world;
}

struct Crowd {
  std::vector<BodyShape> shapes;
  std::vector<Vec3> start, velocity;
};

Crowd const& crowd() {
  static Crowd const the_crowd = [] {
    Crowd c;
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> at(-25.0f, 25.0f), near(-2.0f, 2.0f), u(0.0f, 1.0f);
    Vec3 centre{};
    for (int k = 0; k < 512; ++k) {
      if (k % 64 == 0) centre = {at(rng), 0.0f, at(rng)};
      c.shapes.push_back(Capsule{0.4f + 0.2f * u(rng), 0.3f + 0.1f * u(rng)});
      c.start.push_back(centre + Vec3{near(rng), 0.0f, near(rng)});
      float const a = 6.2831853f * u(rng);
      c.velocity.push_back({5.0f * std::cos(a), -2.0f, 5.0f * std::sin(a)});
    }
    return c;
  }();
  return the_crowd;
}

template <class T>
void register_width() {
  constexpr std::size_t W = lanes_v<T>;
  std::string const name = "character_move/level/plume/x" + std::to_string(W);
  benchmark::RegisterBenchmark(name.c_str(), [](benchmark::State& st) {
    WorldMoveQuery const scene(level());
    Crowd const& c = crowd();
    plume::bench::run_items(st, std::int64_t(c.shapes.size()), [&] {
      for (std::size_t first = 0; first + W <= c.shapes.size(); first += W) {
        std::array<Quat, W> rot;
        rot.fill(Quat::IDENTITY);
        GIso3<T> const poses{pack<T>(rot.data()), pack<T>(&c.start[first])};
        auto const r =
            move_and_slide_lanes<T>(scene, std::span<BodyShape const>(&c.shapes[first], W), poses,
                                    pack<T>(&c.velocity[first]), dt, {}, {}, AcceptAllHits{});
        benchmark::DoNotOptimize(r.position);
      }
    });
  })->Unit(benchmark::kMicrosecond);
}

void register_loop() {
  benchmark::RegisterBenchmark("character_move/level/plume/loop", [](benchmark::State& st) {
    WorldMoveQuery const scene(level());
    Crowd const& c = crowd();
    plume::bench::run_items(st, std::int64_t(c.shapes.size()), [&] {
      for (std::size_t k = 0; k < c.shapes.size(); ++k) {
        auto const r = move_and_slide(scene, c.shapes[k], Iso3::from_translation(c.start[k]),
                                      c.velocity[k], dt);
        benchmark::DoNotOptimize(r.position);
      }
    });
  })->Unit(benchmark::kMicrosecond);
}

// CharacterController::update for the crowd's 512 characters in the same level, each with a
// proxy body (so they meet each other), walking 5 m/s on a circle of 5 m (turning 1 rad/s)
// from its start: pillars, ramps, steps, stairs, stick to floor and the other characters.
// One iteration is one frame of all of them; items = character updates.
void register_controller() {
  benchmark::RegisterBenchmark("character_controller/level/plume/loop", [](benchmark::State& st) {
    World w;
    build_level(w);
    Crowd const& c = crowd();
    std::vector<CharacterController> walkers;
    walkers.reserve(c.shapes.size());
    for (std::size_t k = 0; k < c.shapes.size(); ++k)
      walkers.emplace_back(w, CharacterConfig{.shape = c.shapes[k], .position = c.start[k]});
    int frame = 0;
    auto const one_frame = [&] {
      for (std::size_t k = 0; k < walkers.size(); ++k) {
        CharacterController& h = walkers[k];
        float const a = std::atan2(c.velocity[k].z, c.velocity[k].x) + float(frame) * dt;
        Vec3 const walk{5.0f * std::cos(a), 0.0f, 5.0f * std::sin(a)};
        Vec3 const v = h.velocity();
        h.set_velocity(h.on_ground() ? walk : v + w.config().gravity * dt);
        h.update(w, dt);
      }
      ++frame;
    };
    for (int f = 0; f < 30; ++f) // settle on the ground first
      one_frame();
    plume::bench::run_items(st, std::int64_t(walkers.size()), one_frame);
  })->Unit(benchmark::kMicrosecond);
}

} // namespace

int main(int argc, char** argv) {
  plume::bench::for_each_f32_width([]<class T>() { register_width<T>(); });
  register_loop();
  register_controller();
  return plume::bench::run_benchmarks(argc, argv);
}
