// plume_bench_character_move: move_and_slide through a level, one character at a time and W
// at a time (character_move/level/plume/x<W>: move_and_slide_lanes<T>, x1 = float; `loop`:
// move_and_slide per character). items = character moves.
//
// The level: a floor, a grid of 0.6 m pillars 3 m apart, ramps and low steps between them
// (world bodies, 1,200 in all). 512 capsules of different sizes (radius 0.3-0.4 m, half
// height 0.4-0.6 m) in 8 crowds of 64 within 4 m of each other, each asking for 5 m/s in its
// own direction plus -2 m/s of gravity, for one 1/60 s frame from the same start every
// iteration: the work of a crowd's frame.
#include <plume/solver/character/move_and_slide.hpp>
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

World const& level() {
  static World const level_world = [] {
    World w;
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

} // namespace

int main(int argc, char** argv) {
  plume::bench::for_each_f32_width([]<class T>() { register_width<T>(); });
  register_loop();
  return plume::bench::run_benchmarks(argc, argv);
}
