// plume_bench_dispatch: what the dispatched entry points (plume/dispatch.hpp) cost against
// the same kernel compiled into a static build of that instruction set.
//
// Math: every benchmark evaluates one function on N = 4096 inputs (the domains of
// plume_bench_numerics); items = evaluations. World: dispatch/world_step/pyramid15/... steps
// the settled 15-layer pyramid of plume_bench_world (items = steps);
// dispatch/world_rays/4096/... casts 4,096 rays into it through the batch World::ray_cast
// (items = rays); dispatch/world_rays_level/4096/... casts 4,096 rays down at the static level
// of scenes::add_level (a mesh, a height field, 40 boxes: the trees a dispatch build stores
// stored_lanes (8) wide and each set reads at f32xR); dispatch/project_velocities/1024/... projects
// 1,024 velocities against 0 to 8 planes each through project_velocities (items = problems; its
// static path is the same call in a static build, whose one kernel is the build's own). Names are
//   dispatch/<function>/<f32|f64>/<path>/<isa>     dispatch/world_<...>/<path>/<isa>
// with path one of
//   static       (any build but PLUME_DISPATCH=ON) the build's widest batch, the function
//                inlined into the loop (world: step_with<f32xN>, ray_cast_with<f32xN>): the
//                kernel in the static build of <isa>
//   span         (the same builds) the span function, plume::sin(x, out): the checks and the
//                call, with the kernel of the build's own set (math only)
//   dispatched   (a PLUME_DISPATCH=ON build) the span function, World::step or the batch
//                World::ray_cast after set_isa(<isa>), for each set the binary carries and
//                this CPU runs
// The overhead of dispatch on <isa> is dispatched/<isa> in the dispatch build against
// static/<isa> in the <isa> build: the width report (bench/report.sh) builds the dispatch
// variant too and prints the two side by side, in the same rounds.
#include <plume/dispatch.hpp>
#include <plume/numerics.hpp>
#include <plume/world.hpp>

#include "fixtures/scenes.hpp"

#include "../bench_support.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <new>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr std::size_t N = 4096;

template <class S>
struct buffer {
  S* p;
  buffer() : p(new (std::align_val_t(64)) S[N]) {}
  ~buffer() { ::operator delete[](p, std::align_val_t(64)); }
  buffer(buffer const&) = delete;
  buffer& operator=(buffer const&) = delete;
};

struct domain {
  double lo, hi;
};

/// N values in [lo, hi], from a fixed xorshift sequence (as plume_bench_numerics).
template <class S>
void fill(S* p, domain d, std::uint64_t seed) {
  std::uint64_t s = seed * 0x9E3779B97F4A7C15ull + 1;
  for (std::size_t i = 0; i < N; ++i) {
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    p[i] = static_cast<S>(d.lo + (d.hi - d.lo) * (double(s >> 11) * 0x1.0p-53));
  }
}

template <class S>
struct inputs {
  buffer<S> x, y, out;
  inputs(domain dx, domain dy) {
    fill(x.p, dx, 1);
    fill(y.p, dy, 2);
  }
};

template <class S>
char const* type_name() {
  return sizeof(S) == 4 ? "f32" : "f64";
}

std::string name(char const* fn, char const* ty, char const* path, std::string_view isa) {
  return std::string("dispatch/") + fn + "/" + ty + "/" + path + "/" + std::string(isa);
}

// The span call's loop, for any of the paths that go through it.
template <class S, class Call>
void span_loop(benchmark::State& st, domain dx, domain dy, Call call) {
  inputs<S> in(dx, dy);
  for (auto _ : st) {
    if (call(std::span<S const>(in.x.p, N), std::span<S const>(in.y.p, N),
             std::span<S>(in.out.p, N)) != plume::SpanError::none)
      st.SkipWithError("span call refused");
    benchmark::DoNotOptimize(in.out.p);
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * N));
}

#if !PLUME_DISPATCH
template <class W, class F>
void static_loop(benchmark::State& st, domain dx, domain dy, F f) {
  using S = plume::scalar_t<W>;
  inputs<S> in(dx, dy);
  for (auto _ : st) {
    for (std::size_t i = 0; i < N; i += plume::lanes_v<W>)
      plume::store_aligned(
          in.out.p + i, f(plume::load_aligned<W>(in.x.p + i), plume::load_aligned<W>(in.y.p + i)));
    benchmark::DoNotOptimize(in.out.p);
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * N));
}
#endif

constexpr domain trig{-10, 10}, exp_d{-10, 10}, log_d{1e-3, 1e3}, pow_x{0.1, 10}, pow_y{-5, 5},
    atan_d{-10, 10};

#define PLUME_SPAN_UNARY(FN) [](auto x, auto, auto out) { return plume::FN(x, out); }
#define PLUME_SPAN_BINARY(FN) [](auto x, auto y, auto out) { return plume::FN(x, y, out); }
#define PLUME_WIDE_UNARY(FN) [](auto v, auto) PLUME_BENCH_INLINE { return plume::FN(v); }
#define PLUME_WIDE_BINARY(FN) [](auto a, auto b) PLUME_BENCH_INLINE { return plume::FN(a, b); }

template <class S, class SpanCall, class WideCall>
void register_function(char const* fn, domain dx, domain dy, SpanCall span_call,
                       [[maybe_unused]] WideCall wide_call) {
#if PLUME_DISPATCH
  for (plume::Isa const isa : plume::compiled_isas()) {
    if (!plume::cpu_has(isa)) continue;
    benchmark::RegisterBenchmark(
        name(fn, type_name<S>(), "dispatched", plume::isa_name(isa)).c_str(),
        [=](benchmark::State& st) {
          if (plume::set_isa(isa) != plume::IsaError::none) st.SkipWithError("set_isa refused");
          span_loop<S>(st, dx, dy, span_call);
        });
  }
#else
  using W = std::conditional_t<sizeof(S) == 4, plume::f32xN, plume::f64xN>;
  std::string_view const isa = plume::isa_name(plume::active_isa());
  benchmark::RegisterBenchmark(
      name(fn, type_name<S>(), "static", isa).c_str(),
      [=](benchmark::State& st) { static_loop<W>(st, dx, dy, wide_call); });
  benchmark::RegisterBenchmark(name(fn, type_name<S>(), "span", isa).c_str(),
                               [=](benchmark::State& st) { span_loop<S>(st, dx, dy, span_call); });
#endif
}

template <class S>
void register_all() {
  register_function<S>("sin", trig, trig, PLUME_SPAN_UNARY(sin), PLUME_WIDE_UNARY(sin));
  register_function<S>("exp", exp_d, exp_d, PLUME_SPAN_UNARY(exp), PLUME_WIDE_UNARY(exp));
  register_function<S>("log", log_d, log_d, PLUME_SPAN_UNARY(log), PLUME_WIDE_UNARY(log));
  register_function<S>("atan2", atan_d, atan_d, PLUME_SPAN_BINARY(atan2), PLUME_WIDE_BINARY(atan2));
  register_function<S>("pow", pow_x, pow_y, PLUME_SPAN_BINARY(pow), PLUME_WIDE_BINARY(pow));
}

// ------------------------------------------------------------------------------ the world
// The 15-layer pyramid settled for 60 steps, sleep off (as plume_bench_world's world_step).
plume::World const& settled_pyramid() {
  static plume::World const world = [] {
    plume::WorldConfig cfg;
    cfg.sleep = false;
    plume::World w(cfg);
    plume::scenes::add_ground(w);
    plume::scenes::add_box_pyramid(w, 15);
    for (int s = 0; s < 60; ++s)
      w.step(1.0f / 60.0f);
    return w;
  }();
  return world;
}

// 4,096 rays from points above the pyramid toward it, fixed seed.
std::vector<plume::Ray3> const& pyramid_rays() {
  static std::vector<plume::Ray3> const rays = [] {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-12.0f, 12.0f), h(2.0f, 20.0f);
    std::vector<plume::Ray3> r;
    for (int i = 0; i < 4096; ++i) {
      plume::Vec3 const from{u(rng), h(rng), u(rng)},
          to{0.5f * u(rng), 0.5f * h(rng), 0.5f * u(rng)};
      r.push_back({from, to - from});
    }
    return r;
  }();
  return rays;
}

// The level of scenes::add_level (a mesh, a height field, 40 static boxes) alone, and 4,096
// rays down at it from random points above: the static geometry's trees and triangle blocks,
// which a dispatch build stores stored_lanes (8) wide, read by each set at f32xR.
plume::World const& level() {
  static plume::World const world = [] {
    plume::World w;
    plume::scenes::add_level(w);
    w.step(1.0f / 60.0f); // the broad phase's trees built
    return w;
  }();
  return world;
}

std::vector<plume::Ray3> const& level_rays() {
  static std::vector<plume::Ray3> const rays = [] {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> x(-13.0f, 22.0f), z(-13.0f, 13.0f), tilt(-0.4f, 0.4f);
    std::vector<plume::Ray3> r;
    for (int i = 0; i < 4096; ++i)
      r.push_back({{x(rng), 6.0f, z(rng)}, {tilt(rng), -1.0f, tilt(rng)}});
    return r;
  }();
  return rays;
}

template <class Step>
void world_step(benchmark::State& st, Step step) {
  plume::World world = settled_pyramid();
  plume::bench::run_items(st, 1, [&] { step(world); });
}

template <class Cast>
void world_rays(benchmark::State& st, Cast cast, plume::World const& world,
                std::vector<plume::Ray3> const& rays) {
  std::vector<std::optional<plume::WorldRayHit>> out(rays.size());
  plume::bench::run_items(st, std::int64_t(rays.size()), [&] {
    cast(world, rays, out);
    benchmark::DoNotOptimize(out.data());
  });
}

void register_world() {
#if PLUME_DISPATCH
  for (plume::Isa const isa : plume::compiled_isas()) {
    if (!plume::cpu_has(isa)) continue;
    std::string const i(plume::isa_name(isa));
    benchmark::RegisterBenchmark(("dispatch/world_step/pyramid15/dispatched/" + i).c_str(),
                                 [isa](benchmark::State& st) {
                                   if (plume::set_isa(isa) != plume::IsaError::none)
                                     st.SkipWithError("set_isa refused");
                                   world_step(st, [](plume::World& w) { w.step(1.0f / 60.0f); });
                                 })
        ->Unit(benchmark::kMillisecond);
    for (bool const on_level : {false, true})
      benchmark::RegisterBenchmark(
          ((on_level ? "dispatch/world_rays_level/4096/dispatched/"
                     : "dispatch/world_rays/4096/dispatched/") +
           i)
              .c_str(),
          [isa, on_level](benchmark::State& st) {
            if (plume::set_isa(isa) != plume::IsaError::none) st.SkipWithError("set_isa refused");
            world_rays(
                st, [](plume::World const& w, auto const& r, auto& o) { w.ray_cast(r, 100.0f, o); },
                on_level ? level() : settled_pyramid(), on_level ? level_rays() : pyramid_rays());
          });
  }
#else
  std::string const i(plume::isa_name(plume::active_isa()));
  benchmark::RegisterBenchmark(
      ("dispatch/world_step/pyramid15/static/" + i).c_str(),
      [](benchmark::State& st) {
        world_step(st, [](plume::World& w) { w.step_with<plume::f32xN>(1.0f / 60.0f); });
      })
      ->Unit(benchmark::kMillisecond);
  for (bool const on_level : {false, true})
    benchmark::RegisterBenchmark(((on_level ? "dispatch/world_rays_level/4096/static/"
                                            : "dispatch/world_rays/4096/static/") +
                                  i)
                                     .c_str(),
                                 [on_level](benchmark::State& st) {
                                   world_rays(
                                       st,
                                       [](plume::World const& w, auto const& r, auto& o) {
                                         w.ray_cast_with<plume::f32xN>(r, 100.0f, o);
                                       },
                                       on_level ? level() : settled_pyramid(),
                                       on_level ? level_rays() : pyramid_rays());
                                 });
#endif
}

// ------------------------------------------------------------------ velocity projection
// 1,024 problems of 0 to 8 planes facing the velocity (the contact sets of a crowd), fixed seed.
struct ProjectionProblems {
  std::vector<plume::Vec3> v, n;
  std::vector<std::uint32_t> offsets{0};
  ProjectionProblems() {
    std::mt19937 rng(5);
    std::normal_distribution<float> g;
    auto unit = [&] {
      plume::Vec3 const a{g(rng), g(rng), g(rng)};
      return a * (1.0f / std::max(1e-3f, a.length()));
    };
    for (int p = 0; p < 1024; ++p) {
      plume::Vec3 const vel = unit() * 3.0f;
      v.push_back(vel);
      for (int i = 0; i < p % 9; ++i) {
        plume::Vec3 c = unit();
        if (c.dot(vel) > 0.0f) c = c * -1.0f;
        n.push_back(c);
      }
      offsets.push_back(static_cast<std::uint32_t>(n.size()));
    }
  }
};

void project_batch(benchmark::State& st) {
  static ProjectionProblems const p;
  std::vector<plume::VelocityProjection3> out(p.v.size());
  plume::bench::run_items(st, std::int64_t(p.v.size()), [&] {
    if (plume::project_velocities(std::span<plume::Vec3 const>(p.v),
                                  std::span<plume::Vec3 const>(p.n), p.offsets,
                                  out) != plume::ProjectVelocitiesError::none)
      st.SkipWithError("project_velocities refused");
    benchmark::DoNotOptimize(out.data());
  });
}

void register_projection() {
#if PLUME_DISPATCH
  for (plume::Isa const isa : plume::compiled_isas()) {
    if (!plume::cpu_has(isa)) continue;
    benchmark::RegisterBenchmark(
        ("dispatch/project_velocities/1024/dispatched/" + std::string(plume::isa_name(isa)))
            .c_str(),
        [isa](benchmark::State& st) {
          if (plume::set_isa(isa) != plume::IsaError::none) st.SkipWithError("set_isa refused");
          project_batch(st);
        });
  }
#else
  benchmark::RegisterBenchmark(("dispatch/project_velocities/1024/static/" +
                                std::string(plume::isa_name(plume::active_isa())))
                                   .c_str(),
                               project_batch);
#endif
}

} // namespace

int main(int argc, char** argv) {
  register_all<float>();
  register_all<double>();
  register_world();
  register_projection();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
