// plume_dispatch_overhead: the world's step and 4,096 batch rays, for counting instructions
// under callgrind (docs/performance.md, "Dispatch"). Built in every build with the
// benchmarks; the same source against a static build's libraries and against a
// PLUME_DISPATCH=ON build's compares the dispatched entry points with the static ones
// (B = the build folder; measure_rays likewise):
//   valgrind --tool=callgrind --toggle-collect='*measure_step*' $B/bench/plume_dispatch_overhead
// It prints the world's hash (the same in every build and set) and the set the world ran.
#include <plume/world.hpp>

#include "fixtures/scenes.hpp"

#include <cstdio>
#include <optional>
#include <random>
#include <vector>

using namespace plume;
__attribute__((noinline)) void measure_step(World& w) {
  for (int i = 0; i < 5; ++i)
    w.step(1.0f / 60.0f);
}
__attribute__((noinline)) void measure_rays(World const& w, std::vector<Ray3> const& rays,
                                            std::vector<std::optional<WorldRayHit>>& out) {
  w.ray_cast(rays, 100.0f, out);
}
int main() {
  // The 15-layer pyramid, sleep off, settled 60 steps (as plume_bench_world's world_step).
  WorldConfig cfg;
  cfg.sleep = false;
  World w(cfg);
  scenes::add_ground(w);
  scenes::add_box_pyramid(w, 15);
  for (int s = 0; s < 60; ++s)
    w.step_with<float>(1.0f / 60.0f);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-12.0f, 12.0f), h(2.0f, 20.0f);
  std::vector<Ray3> rays;
  for (int i = 0; i < 4096; ++i) {
    Vec3 const from{u(rng), h(rng), u(rng)}, to{0.5f * u(rng), 0.5f * h(rng), 0.5f * u(rng)};
    rays.push_back({from, to - from});
  }
  std::vector<std::optional<WorldRayHit>> out(rays.size());
  measure_rays(w, rays, out);
  measure_step(w);
  std::printf("%llx isa %s\n", (unsigned long long)w.state_hash(),
              isa_name(detail::world_kernels_isa()).data());
}
