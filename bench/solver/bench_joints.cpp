// Joints in the world (solver/joints/), at every f32 width of the build (items = steps):
//   joint_solve/ragdolls/plume/x<W>        the joint passes alone (StepProfile::joints as
//                                          manual time) of 100 ragdolls (15 bodies, 14
//                                          spherical and revolute joints with limits each)
//                                          lying on a ground plane
//   world_step/ragdolls/f32/plume/x<W>     the whole step of that scene
//   world_step/chains/f32/plume/x<W>       the whole step of 200 chains of 20 links
//                                          (spherical joints) swinging from static anchors
//   joint_solve/chains/plume/x<W>          their joint passes alone
// Every benchmark starts from the same world, settled for 120 steps after building (copied),
// so every width does the same work.
#include "../bench_support.hpp"

#include <fixtures/scenes.hpp>
#include <plume/solver/world/world.hpp>

#include <map>
#include <string>

using namespace plume;
using namespace plume::scenes;

namespace {

/// The joints' solve is measured every step: nothing sleeps.
WorldConfig awake_config() {
  WorldConfig cfg;
  cfg.sleep = false;
  return cfg;
}

/// 100 ragdolls in a 10 x 10 grid, 2.5 m apart, dropped from 0.3 m with a push on the head.
World make_ragdolls() {
  World w(awake_config());
  add_ground(w);
  for (int i = 0; i < 10; ++i)
    for (int k = 0; k < 10; ++k) {
      Jointed const d = add_ragdoll(w, {2.5f * float(i), 1.3f, 2.5f * float(k)});
      w.set_velocity(d.bodies[4], {0.3f * float(i % 3) - 0.3f, 0.0f, 1.5f}, {});
    }
  return w;
}

/// 200 chains of 20 links (0.5 m each) from anchors 12 m up, 0.3 m apart along z, released
/// horizontal.
World make_chains() {
  World w(awake_config());
  add_ground(w);
  for (int i = 0; i < 200; ++i)
    add_chain(w, {0.0f, 12.0f, 0.3f * float(i)}, 20);
  return w;
}

World const& settled(std::string const& scene) {
  static std::map<std::string, World> cache;
  auto it = cache.find(scene);
  if (it == cache.end()) {
    World w = scene == "ragdolls" ? make_ragdolls() : make_chains();
    for (int s = 0; s < 120; ++s)
      w.step(1.0f / 60.0f);
    it = cache.emplace(scene, std::move(w)).first;
  }
  return it->second;
}

/// prefix + scene + middle + "x<W>", built by appending (GCC 12 warns, wrongly, on the
/// chained operator+ of string literals and strings).
std::string bench_name(char const* prefix, std::string const& scene, char const* middle,
                       std::size_t lanes) {
  std::string name = prefix;
  name += scene;
  name += middle;
  name += 'x';
  name += std::to_string(lanes);
  return name;
}

template <class T>
void register_width(std::string const& scene) {
  benchmark::RegisterBenchmark(bench_name("world_step/", scene, "/f32/plume/", lanes_v<T>).c_str(),
                               [scene](benchmark::State& st) {
                                 World world = settled(scene);
                                 plume::bench::run_items(st, 1,
                                                         [&] { world.step_with<T>(1.0f / 60.0f); });
                                 st.counters["joints"] = double(world.joint_count());
                                 st.counters["contacts"] = double(world.contacts().size());
                               })
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(bench_name("joint_solve/", scene, "/plume/", lanes_v<T>).c_str(),
                               [scene](benchmark::State& st) {
                                 World world = settled(scene);
                                 for (auto _ : st) {
                                   world.step_with<T>(1.0f / 60.0f);
                                   st.SetIterationTime(world.last_profile().joints);
                                 }
                                 st.SetItemsProcessed(std::int64_t(st.iterations()));
                               })
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
}

} // namespace

int main(int argc, char** argv) {
  for (std::string const scene : {"ragdolls", "chains"})
    plume::bench::for_each_f32_width([&]<class T>() { register_width<T>(scene); });
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
