// plume_bench_character: velocity projection and depenetration, scalar against every width.
//
// Names follow <case>/k<planes>/f32/<implementation>/x<width>; items = projections (or
// depenetrations). "plume" is the n-step algorithm, "bruteforce" the O(k^3) reference (x1).
// Every width solves the same P = 4096 problems: a character's contact set of k unit normals
// (floors, slopes, walls and ceilings: z in [-0.3, 1]) and a velocity of speed 0.5..5 in a
// random direction; wide widths put a different problem in each lane. P matters: with 512
// problems repeated every iteration the branch predictor learnt the scalar code's branches
// (scalar k = 8 ran at 13.6M/s instead of 5.6M/s), which no game's fresh contacts allow.
#include <plume/character.hpp>

#include "../bench_support.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr std::size_t P = 4096;
constexpr int plane_counts[] = {1, 2, 4, 8, 16, 32};

struct problems {
  std::vector<plume::Vec3> v;
  std::vector<plume::Vec3> n;           // P * k, problem-major
  std::vector<plume::Penetration3> pen; // P * k
};

problems const& data(int k) {
  static std::map<int, problems> cache;
  auto it = cache.find(k);
  if (it != cache.end()) return it->second;
  problems p;
  std::mt19937 g(1234u + unsigned(k));
  std::uniform_real_distribution<float> u(-1, 1);
  auto unit = [&](float zmin) {
    for (;;) {
      plume::Vec3 const c{u(g), u(g), u(g)};
      float const l = c.length();
      if (l < 0.1f || l > 1) continue;
      if (c.z / l < zmin) continue;
      return c / l;
    }
  };
  for (std::size_t i = 0; i < P; ++i) {
    plume::Vec3 const dir = unit(-1); // before the speed: operand order is unspecified
    p.v.push_back(dir * (0.5f + 2.25f * (u(g) + 1)));
    for (int j = 0; j < k; ++j) {
      plume::Vec3 const n = unit(-0.3f);
      p.n.push_back(n);
      p.pen.push_back({n, 0.05f * (u(g) + 1)});
    }
  }
  return cache.emplace(k, std::move(p)).first->second;
}

/// The problems packed for width L: group g's slot j holds problem g*L + l's normal j in lane l.
template <class T>
struct packed {
  std::vector<plume::GVec3<T>> v, n;
  std::vector<plume::GPenetration<plume::GVec3<T>>> pen;
};

template <class T>
packed<T> pack(problems const& p, int k) {
  constexpr std::size_t L = plume::lanes_v<T>;
  packed<T> out;
  for (std::size_t g = 0; g < P / L; ++g) {
    plume::GVec3<T> v;
    for (std::size_t l = 0; l < L; ++l)
      v = plume::with_lane(v, l, p.v[g * L + l]);
    out.v.push_back(v);
    for (int j = 0; j < k; ++j) {
      plume::GVec3<T> n;
      T d{};
      for (std::size_t l = 0; l < L; ++l) {
        std::size_t const idx = (g * L + l) * std::size_t(k) + std::size_t(j);
        n = plume::with_lane(n, l, p.n[idx]);
        d = plume::with_lane(d, l, p.pen[idx].depth);
      }
      out.n.push_back(n);
      out.pen.push_back({n, d});
    }
  }
  return out;
}

template <class T>
void register_width() {
  constexpr std::size_t L = plume::lanes_v<T>;
  std::string const w = "/f32/plume/x" + std::to_string(L);
  for (int k : plane_counts) {
    std::string const kk = "/k" + std::to_string(k);
    benchmark::RegisterBenchmark(("project_velocity" + kk + w).c_str(), [k](benchmark::State& st) {
      auto const p = pack<T>(data(k), k);
      plume::bench::run_items(st, P, [&] {
        for (std::size_t g = 0; g < p.v.size(); ++g) {
          auto const r = plume::project_velocity<T>(
              p.v[g], std::span(p.n.data() + g * std::size_t(k), std::size_t(k)));
          benchmark::DoNotOptimize(r.velocity);
        }
      });
    });
    benchmark::RegisterBenchmark(("depenetrate" + kk + w).c_str(), [k](benchmark::State& st) {
      auto const p = pack<T>(data(k), k);
      plume::bench::run_items(st, P, [&] {
        for (std::size_t g = 0; g < p.v.size(); ++g) {
          auto const r = plume::depenetrate<plume::GVec3<T>>(
              std::span(p.pen.data() + g * std::size_t(k), std::size_t(k)));
          benchmark::DoNotOptimize(r.correction);
        }
      });
    });
  }
}

void register_bruteforce() {
  for (int k : plane_counts) {
    std::string const name = "project_velocity/k" + std::to_string(k) + "/f32/bruteforce/x1";
    benchmark::RegisterBenchmark(name.c_str(), [k](benchmark::State& st) {
      auto const& p = data(k);
      plume::bench::run_items(st, P, [&] {
        for (std::size_t i = 0; i < P; ++i) {
          auto const r = plume::project_velocity_bruteforce<float>(
              p.v[i], std::span(p.n.data() + i * std::size_t(k), std::size_t(k)));
          benchmark::DoNotOptimize(r.velocity);
        }
      });
    });
  }
}

/// The step counts of the problem set, so the width ratios can be read against how often
/// lanes wait for each other (a wide group runs as many steps as its slowest lane).
void print_steps() {
  for (int k : plane_counts) {
    auto const& p = data(k);
    std::map<int, int> h;
    for (std::size_t i = 0; i < P; ++i)
      ++h[int(plume::project_velocity<float>(
                  p.v[i], std::span(p.n.data() + i * std::size_t(k), std::size_t(k)))
                  .steps)];
    std::fprintf(stderr, "k = %2d steps:", k);
    for (auto const& [s, c] : h)
      std::fprintf(stderr, " %d:%d", s, c);
    std::fprintf(stderr, "\n");
  }
}

} // namespace

int main(int argc, char** argv) {
  print_steps();
  plume::bench::for_each_f32_width([]<class T>() { register_width<T>(); });
  register_bruteforce();
  return plume::bench::run_benchmarks(argc, argv);
}
