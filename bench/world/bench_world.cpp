// The rigid-body world on box pyramids: steps per second for the whole step and for the
// solver stages alone (prepare + substeps + restitution: the part written over T), at every
// f32 width of the build. Names: world_step/<scene>/f32/plume/x<W>, world_solver/...
// narrow_phase/<scene>/f32/plume/x<W>: the narrow phase's manifolds alone (items = pairs
// tested), the cuboid pairs W at a time through the manifold kernel (x1: one at a time), with
// manifold reuse off; narrow_phase/<scene>_reuse/...: the same with the world's default reuse
// (WorldConfig::reuse_distance), where the settled pairs keep their manifolds.
//
// Static-heavy scenes (spatial_static/<statics>/<broad phase>, items = world steps): a grid
// of N static boxes (1 m apart) with 100 dynamic spheres resting on the 10 x 10 boxes at its
// centre, stepped with the widest batch. The dynamic work is the same for every N, so the
// BVH's step time should not grow with N; sort and sweep sorts every body every step.
//
// Batch ray casts into the world (world_ray_batch/<rays>/plume/x<W>, items = rays): 4,096
// rays into the settled 40,000-static scene, through World::ray_cast_with<T> (x1: float, one
// ray at a time), so W rays walk the trees and are cast against a shape together. `fans`:
// 64 fans of 64 rays from one point each (probes, a shotgun, a sensor sweep); `random`: each
// ray from its own point, in its own direction. `loop`: World::ray_cast per ray (the
// baseline). world_shape_cast_batch/<casts>/plume/<x W|loop> (items = casts): 4,096
// capsules of random sizes (radius 0.2-0.4 m, half height 0.3-0.6 m) moving 1 m sideways and
// down over the same scene, World::shape_cast_with<T>: `crowd`, 64 groups of 64 within 2 m
// of each other (a crowd of characters); `random`, each on its own.
//
// Sleeping (world_large/10000/<awake|asleep>, items = world steps): 10,000 boxes and spheres
// (0.8 m, 1.1 m apart) dropped from 0.5 m on a flat 120 m triangle-mesh floor and settled for
// 3 s, then stepped with the widest batch: `awake` with WorldConfig::sleep off (every body is
// simulated), `asleep` with it on (the bodies have fallen asleep). The two figures are the
// step's cost per simulated body and its cost per sleeping one.
//
// Threads (world_step/pyramid15/f32/plume/x<W>/t<threads>, world_large/10000/awake/t<threads>):
// the settled scene stepped on a ThreadPool (solver/world/tasks.hpp) of 1, 2 and 8 threads,
// items per wall-clock second. Each thread count computes the same world for the same steps
// (bitwise), but each benchmark runs its own number of steps from the settled start, so the
// figures compare near-steady piles, not identical stretches.
//
// Every benchmark starts from the same settled world (60 steps after building the scene,
// copied), so the widths do the same work; the solver-stage figures use the world's own
// stage timer (StepProfile) as Google Benchmark's manual time.
#include "../bench_support.hpp"

#include <fixtures/scenes.hpp>
#include <plume/solver/world/world.hpp>

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>

using namespace plume;
using namespace plume::scenes;

namespace {

/// The last step's stages (StepProfile) as counters, in microseconds.
void stage_counters(benchmark::State& st, StepProfile const& p) {
  st.counters["broad_us"] = 1e6 * p.broad_phase;
  st.counters["narrow_us"] = 1e6 * p.narrow_phase;
  st.counters["prepare_us"] = 1e6 * p.prepare;
  st.counters["solve_us"] = 1e6 * p.solve;
  st.counters["finalize_us"] = 1e6 * p.finalize;
  st.counters["continuous_us"] = 1e6 * p.continuous;
  st.counters["sleep_us"] = 1e6 * p.sleep;
}

/// The pyramid of `layers` layers, settled for 60 steps (built once per binary); reuse false:
/// manifold reuse off (WorldConfig::reuse_distance 0), every pair computed every step.
World const& settled_pyramid(int layers, bool reuse = true) {
  static std::map<std::pair<int, bool>, World> cache;
  auto it = cache.find({layers, reuse});
  if (it == cache.end()) {
    WorldConfig cfg;
    cfg.sleep = false; // the whole step, every step: the solver's measure
    if (!reuse) cfg.reuse_distance = 0.0f;
    World w(cfg);
    add_ground(w);
    add_box_pyramid(w, layers);
    for (int s = 0; s < 60; ++s)
      w.step(1.0f / 60.0f);
    it = cache.emplace(std::pair{layers, reuse}, std::move(w)).first;
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
  // The narrow phase's manifolds alone (StepProfile::manifolds as the manual time), items =
  // the pairs it tested: the cuboid pairs W at a time through the manifold kernel, every pair
  // every step (manifold reuse off); <scene>_reuse: the world's default, where the settled
  // pairs keep their manifolds.
  for (bool reuse : {false, true})
    benchmark::RegisterBenchmark(("narrow_phase/" + scene + (reuse ? "_reuse" : "") + w).c_str(),
                                 [layers, reuse](benchmark::State& st) {
                                   World world = settled_pyramid(layers, reuse);
                                   std::size_t pairs = 0;
                                   for (auto _ : st) {
                                     world.step_with<T>(1.0f / 60.0f);
                                     StepProfile const& p = world.last_profile();
                                     st.SetIterationTime(p.manifolds);
                                     pairs += p.pairs;
                                   }
                                   st.SetItemsProcessed(std::int64_t(pairs));
                                   StepProfile const& p = world.last_profile();
                                   st.counters["pairs"] = double(p.pairs);
                                   st.counters["box_pairs"] = double(p.box_pairs);
                                   st.counters["general"] = double(p.general_box_pairs);
                                   st.counters["reused"] = double(p.reused_pairs);
                                 })
        ->UseManualTime()
        ->Unit(benchmark::kMicrosecond);
}

/// world_step/<scene>/f32/plume/x<W>/t<threads>: the whole step on a ThreadPool of `threads`
/// threads (t1: the pool's inline path, which is the step without a task system).
template <class T>
void register_threads(int layers, std::uint32_t threads) {
  std::string const name = "world_step/pyramid" + std::to_string(layers) + "/f32/plume/x" +
                           std::to_string(lanes_v<T>) + "/t" + std::to_string(threads);
  benchmark::RegisterBenchmark(name.c_str(), [layers, threads](benchmark::State& st) {
    ThreadPool pool(threads);
    World world = settled_pyramid(layers);
    world.set_task_system(&pool);
    plume::bench::run_items_wall(st, 1, [&] { world.step_with<T>(1.0f / 60.0f); });
    stage_counters(st, world.last_profile());
  })->Unit(benchmark::kMillisecond);
}

/// N = side^2 static boxes and 100 dynamic spheres on the central ones, settled 120 steps.
World const& settled_static_scene(int side, BroadPhaseKind kind) {
  static std::map<std::pair<int, int>, World> cache;
  auto const key = std::make_pair(side, int(kind));
  auto it = cache.find(key);
  if (it == cache.end()) {
    WorldConfig cfg;
    cfg.broad_phase = kind;
    cfg.sleep = false; // the broad phase's measure: the balls keep their pairs every step
    World w(cfg);
    float const half = 0.5f * float(side - 1);
    for (int i = 0; i < side; ++i)
      for (int k = 0; k < side; ++k)
        w.create_body({.type = BodyType::static_body,
                       .pose = Iso3::from_translation({float(i) - half, 0.0f, float(k) - half}),
                       .shape = Cuboid{Vec3::splat(0.4f)}});
    for (int i = 0; i < 10; ++i)
      for (int k = 0; k < 10; ++k)
        w.create_body(
            {.pose = Iso3::from_translation(
                 {float(i) - 4.5f + 0.5f * (side % 2 ? 0.0f : 1.0f) + 0.05f * float(k % 3), 0.8f,
                  float(k) - 4.5f + 0.5f * (side % 2 ? 0.0f : 1.0f)}),
             .shape = Sphere{0.3f}});
    for (int s = 0; s < 120; ++s)
      w.step(1.0f / 60.0f);
    it = cache.emplace(key, std::move(w)).first;
  }
  return it->second;
}

void register_static_scene(int side, BroadPhaseKind kind) {
  std::string const name = "spatial_static/" + std::to_string(side * side) + "/" +
                           (kind == BroadPhaseKind::bvh ? "bvh" : "sort_and_sweep");
  benchmark::RegisterBenchmark(name.c_str(), [side, kind](benchmark::State& st) {
    World world = settled_static_scene(side, kind);
    plume::bench::run_items(st, 1, [&] { world.step(1.0f / 60.0f); });
    st.counters["bodies"] = double(world.body_count());
    st.counters["contacts"] = double(world.contacts().size());
    stage_counters(st, world.last_profile());
  })->Unit(benchmark::kMicrosecond);
}

/// The 10,000-body scene on a mesh floor, settled 180 steps, with or without sleeping.
World const& settled_large_scene(bool sleep) {
  static std::map<bool, World> cache;
  auto it = cache.find(sleep);
  if (it == cache.end()) {
    WorldConfig cfg;
    cfg.sleep = sleep;
    World w(cfg);
    std::vector<Vec3> vertices;
    std::vector<std::uint32_t> indices;
    std::uint32_t const n = 101; // 100 x 100 cells of 1.2 m
    for (std::uint32_t z = 0; z < n; ++z)
      for (std::uint32_t x = 0; x < n; ++x)
        vertices.push_back({1.2f * float(x) - 60.0f, 0.0f, 1.2f * float(z) - 60.0f});
    for (std::uint32_t z = 0; z + 1 < n; ++z)
      for (std::uint32_t x = 0; x + 1 < n; ++x) {
        std::uint32_t const a = z * n + x, b = a + 1, c = a + n, d = c + 1;
        indices.insert(indices.end(), {a, c, b, b, c, d});
      }
    auto mesh = TriangleMesh::build(vertices, indices);
    if (!mesh.ok()) throw std::logic_error("bench_world: the large scene's floor");
    w.create_body({.type = BodyType::static_body,
                   .shape = MeshShape{std::make_shared<TriangleMesh const>(std::move(mesh.mesh))}});
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> tilt(-0.3f, 0.3f);
    for (int i = 0; i < 100; ++i)
      for (int k = 0; k < 100; ++k) {
        Vec3 const at{1.1f * float(i) - 54.5f, 0.9f, 1.1f * float(k) - 54.5f};
        Quat const q = Quat::from_rotation_x(tilt(rng)) * Quat::from_rotation_z(tilt(rng));
        if ((i + k) % 2 == 0)
          w.create_body({.pose = Iso3{q, at}, .shape = Cuboid{Vec3::splat(0.4f)}});
        else
          w.create_body({.pose = Iso3::from_translation(at), .shape = Sphere{0.4f}});
      }
    for (int s = 0; s < 180; ++s)
      w.step(1.0f / 60.0f);
    it = cache.emplace(sleep, std::move(w)).first;
  }
  return it->second;
}

/// world_large/10000/<awake|asleep>, and with /t<threads> on a ThreadPool of that many.
void register_large_scene(bool sleep, std::uint32_t threads = 0) {
  std::string const name = std::string("world_large/10000/") + (sleep ? "asleep" : "awake") +
                           (threads ? "/t" + std::to_string(threads) : std::string());
  benchmark::RegisterBenchmark(name.c_str(), [sleep, threads](benchmark::State& st) {
    ThreadPool pool(threads);
    World world = settled_large_scene(sleep);
    if (threads) {
      world.set_task_system(&pool);
      plume::bench::run_items_wall(st, 1, [&] { world.step(1.0f / 60.0f); });
    } else {
      plume::bench::run_items(st, 1, [&] { world.step(1.0f / 60.0f); });
    }
    st.counters["sleeping"] = double(world.sleeping_count());
    st.counters["contacts"] = double(world.contacts().size());
    stage_counters(st, world.last_profile());
  })->Unit(benchmark::kMicrosecond);
}

/// 4,096 rays from above the static scene's grid, downward: fans of 64 or independent ones.
std::vector<Ray3> batch_rays(bool fans) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> at(-90.0f, 90.0f), tilt(-0.6f, 0.6f);
  std::vector<Ray3> rays;
  Vec3 from{};
  for (int k = 0; k < 4096; ++k) {
    if (!fans || k % 64 == 0) from = {at(rng), 4.0f, at(rng)};
    rays.push_back({from, Vec3{tilt(rng), -1.0f, tilt(rng)}});
  }
  return rays;
}

template <class T>
void register_ray_batch(bool fans) {
  std::string const name = std::string("world_ray_batch/") + (fans ? "fans" : "random") +
                           "/plume/x" + std::to_string(lanes_v<T>);
  benchmark::RegisterBenchmark(name.c_str(), [fans](benchmark::State& st) {
    World const& world = settled_static_scene(200, BroadPhaseKind::bvh);
    std::vector<Ray3> const rays = batch_rays(fans);
    std::vector<std::optional<WorldRayHit>> out(rays.size());
    plume::bench::run_items(st, std::int64_t(rays.size()),
                            [&] { world.ray_cast_with<T>(rays, 50.0f, out); });
    st.counters["hit"] =
        double(std::count_if(out.begin(), out.end(), [](auto const& h) { return bool(h); })) /
        double(out.size());
  })->Unit(benchmark::kMicrosecond);
}

/// 4,096 capsule casts over the static scene: crowds of 64 within 2 m, or independent.
struct Casts {
  std::vector<BodyShape> shapes;
  std::vector<Iso3> poses;
  std::vector<Vec3> motions;
};
Casts batch_casts(bool crowd) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> at(-90.0f, 90.0f), near(-1.0f, 1.0f), u(0.0f, 1.0f);
  Casts c;
  Vec3 centre{};
  for (int k = 0; k < 4096; ++k) {
    if (!crowd || k % 64 == 0) centre = {at(rng), 1.6f, at(rng)};
    c.shapes.push_back(Capsule{0.3f + 0.3f * u(rng), 0.2f + 0.2f * u(rng)});
    c.poses.push_back(
        Iso3::from_translation(centre + Vec3{near(rng), 0.2f * near(rng), near(rng)}));
    c.motions.push_back({near(rng), -0.5f - 0.5f * u(rng), near(rng)});
  }
  return c;
}

template <class T>
void register_cast_batch(bool crowd) {
  std::string const name = std::string("world_shape_cast_batch/") + (crowd ? "crowd" : "random") +
                           "/plume/x" + std::to_string(lanes_v<T>);
  benchmark::RegisterBenchmark(name.c_str(), [crowd](benchmark::State& st) {
    World const& world = settled_static_scene(200, BroadPhaseKind::bvh);
    Casts const c = batch_casts(crowd);
    std::vector<std::optional<WorldShapeHit>> out(c.shapes.size());
    plume::bench::run_items(st, std::int64_t(c.shapes.size()), [&] {
      world.shape_cast_with<T>(c.shapes, c.poses, c.motions, ShapeCastConfig{}, out);
    });
    st.counters["hit"] =
        double(std::count_if(out.begin(), out.end(), [](auto const& h) { return bool(h); })) /
        double(out.size());
  })->Unit(benchmark::kMicrosecond);
}

void register_cast_loop(bool crowd) {
  std::string const name =
      std::string("world_shape_cast_batch/") + (crowd ? "crowd" : "random") + "/plume/loop";
  benchmark::RegisterBenchmark(name.c_str(), [crowd](benchmark::State& st) {
    World const& world = settled_static_scene(200, BroadPhaseKind::bvh);
    Casts const c = batch_casts(crowd);
    std::vector<std::optional<WorldShapeHit>> out(c.shapes.size());
    plume::bench::run_items(st, std::int64_t(c.shapes.size()), [&] {
      for (std::size_t k = 0; k < c.shapes.size(); ++k)
        out[k] = world.shape_cast(c.shapes[k], c.poses[k], c.motions[k]);
    });
  })->Unit(benchmark::kMicrosecond);
}

/// The baseline: the single-ray World::ray_cast in a loop (world_ray_batch/<rays>/plume/loop).
void register_ray_loop(bool fans) {
  std::string const name =
      std::string("world_ray_batch/") + (fans ? "fans" : "random") + "/plume/loop";
  benchmark::RegisterBenchmark(name.c_str(), [fans](benchmark::State& st) {
    World const& world = settled_static_scene(200, BroadPhaseKind::bvh);
    std::vector<Ray3> const rays = batch_rays(fans);
    std::vector<std::optional<WorldRayHit>> out(rays.size());
    plume::bench::run_items(st, std::int64_t(rays.size()), [&] {
      for (std::size_t k = 0; k < rays.size(); ++k)
        out[k] = world.ray_cast(rays[k], 50.0f);
    });
  })->Unit(benchmark::kMicrosecond);
}

} // namespace

int main(int argc, char** argv) {
  for (int layers : {15, 20})
    plume::bench::for_each_f32_width([&]<class T>() { register_width<T>(layers); });
  for (int side : {200, 20})
    for (BroadPhaseKind kind : {BroadPhaseKind::bvh, BroadPhaseKind::sort_and_sweep})
      register_static_scene(side, kind);
  for (std::uint32_t threads : {1u, 2u, 8u})
    plume::bench::for_each_f32_width([&]<class T>() { register_threads<T>(15, threads); });
  for (bool sleep : {false, true})
    register_large_scene(sleep);
  for (std::uint32_t threads : {1u, 2u, 8u})
    register_large_scene(false, threads);
  for (bool fans : {true, false}) {
    plume::bench::for_each_f32_width([&]<class T>() { register_ray_batch<T>(fans); });
    register_ray_loop(fans);
    plume::bench::for_each_f32_width([&]<class T>() { register_cast_batch<T>(fans); });
    register_cast_loop(fans);
  }
  return plume::bench::run_benchmarks(argc, argv);
}
