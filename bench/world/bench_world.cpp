// The rigid-body world on box pyramids: steps per second for the whole step and for the
// solver stages alone (prepare + substeps + restitution: the part written over T), at every
// f32 width of the build. Names: world_step/<scene>/f32/plume/x<W>, world_solver/...
//
// Every benchmark starts from the same settled world (60 steps after building the scene,
// copied), so the widths do the same work; the solver-stage figures use the world's own
// stage timer (StepProfile) as Google Benchmark's manual time.
#include "../bench_support.hpp"

#include <fixtures/scenes.hpp>
#include <plume/solver/world/world.hpp>

#include <map>
#include <string>

using namespace plume;
using namespace plume::scenes;

namespace {

/// The scene with `layers` layers, settled for 60 steps (built once per binary).
World const& settled_pyramid(int layers) {
  static std::map<int, World> cache;
  auto it = cache.find(layers);
  if (it == cache.end()) {
    World w;
    add_ground(w);
    add_box_pyramid(w, layers);
    for (int s = 0; s < 60; ++s)
      w.step(1.0f / 60.0f);
    it = cache.emplace(layers, std::move(w)).first;
  }
  return it->second;
}

template <class T>
void register_width(int layers) {
  std::string const scene = "pyramid" + std::to_string(layers);
  std::string const w = "/f32/plume/x" + std::to_string(lanes_v<T>);
  benchmark::RegisterBenchmark(("world_step/" + scene + w).c_str(), [layers](benchmark::State& st) {
    World world = settled_pyramid(layers);
    plume::bench::run_items(st, 1, [&] { world.step_with<T>(1.0f / 60.0f); });
    st.counters["bodies"] = double(world.body_count());
    st.counters["contacts"] = double(world.contacts().size());
  })->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(("world_solver/" + scene + w).c_str(),
                               [layers](benchmark::State& st) {
                                 World world = settled_pyramid(layers);
                                 for (auto _ : st) {
                                   world.step_with<T>(1.0f / 60.0f);
                                   StepProfile const& p = world.last_profile();
                                   st.SetIterationTime(p.prepare + p.solve);
                                 }
                                 st.SetItemsProcessed(std::int64_t(st.iterations()));
                               })
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
}

} // namespace

int main(int argc, char** argv) {
  for (int layers : {15, 20})
    plume::bench::for_each_f32_width([&]<class T>() { register_width<T>(layers); });
  return plume::bench::run_benchmarks(argc, argv);
}
