// plume_bench_gjk: the GJK family against 32-vertex convex hulls, scalar against every width.
//
// Names follow <case>/f32/plume/x<width>; items = queries. N = 1024 queries, query i against
// hull i (32 points on a unit sphere, built by quickhull, at a random pose within [-1, 1]^3):
//   gjk_ray_hull32       a ray from [-4, 4]^3 aimed near the hull (about two thirds hit)
//   gjk_cast_box_hull32  a 0.3 m cube moving 8 m toward the hull (shape cast)
//   gjk_distance_capsule_hull32  closest points between a capsule near the hull and the hull
// A wide query packs L hulls into one GConvexPolytope<T> (lane l = hull i + l); every lane
// runs until all have finished, so the wide figure includes the cost of waiting for the
// slowest lane.
#include <plume/collision.hpp>

#include "../bench_support.hpp"

#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

namespace {

constexpr std::size_t N = 1024;
constexpr std::size_t V = 32;

struct scene {
  std::vector<plume::Vec3> verts; // V per hull
  std::vector<plume::Iso3> pose;
  std::vector<plume::Vec3> origin, dir, start;
  scene() {
    std::mt19937 g(5);
    std::uniform_real_distribution<float> u(-1, 1);
    for (std::size_t i = 0; i < N; ++i) {
      std::vector<plume::Vec3> pts;
      while (pts.size() < V) {
        plume::Vec3 const p{u(g), u(g), u(g)};
        float const l = p.length();
        if (l > 0.2f && l < 1) pts.push_back(p / l);
      }
      auto const built = plume::ConvexHull::build(pts);
      auto const hv = built.hull.vertices();
      for (std::size_t k = 0; k < V; ++k)
        verts.push_back(hv[k < hv.size() ? k : hv.size() - 1]);
      plume::Vec3 const axis = plume::Vec3{u(g), u(g), u(g) + 2}.normalize();
      float const angle = 3 * u(g);
      plume::Vec3 const centre{u(g), u(g), u(g)};
      pose.push_back({plume::Quat::from_axis_angle(axis, angle), centre});
      plume::Vec3 const o{4 * u(g), 4 * u(g), 4 * u(g)};
      plume::Vec3 const aim = centre + plume::Vec3{u(g), u(g), u(g)};
      origin.push_back(o);
      dir.push_back((aim - o).normalize());
      start.push_back(centre - dir.back() * 4.0f);
    }
  }
};
scene const& data() {
  static scene s;
  return s;
}

template <class T>
struct packed {
  std::vector<plume::GVec3<T>> verts; // V per group of L hulls
  std::vector<plume::GIso3<T>> pose;
  std::vector<plume::GVec3<T>> origin, dir, start;
  packed() {
    constexpr std::size_t L = plume::lanes_v<T>;
    auto const& s = data();
    for (std::size_t i = 0; i < N; i += L) {
      for (std::size_t k = 0; k < V; ++k) {
        plume::GVec3<T> v;
        for (std::size_t l = 0; l < L; ++l)
          v = plume::with_lane(v, l, s.verts[(i + l) * V + k]);
        verts.push_back(v);
      }
      plume::GIso3<T> p;
      plume::GVec3<T> o, d, st;
      for (std::size_t l = 0; l < L; ++l) {
        p = plume::with_lane(p, l, s.pose[i + l]);
        o = plume::with_lane(o, l, s.origin[i + l]);
        d = plume::with_lane(d, l, s.dir[i + l]);
        st = plume::with_lane(st, l, s.start[i + l]);
      }
      pose.push_back(p), origin.push_back(o), dir.push_back(d), start.push_back(st);
    }
  }
  plume::GConvexPolytope<T> hull(std::size_t g) const {
    return {std::span<plume::GVec3<T> const>(verts).subspan(g * V, V)};
  }
};

template <class T>
void register_width() {
  constexpr std::size_t L = plume::lanes_v<T>;
  std::string const w = "/f32/plume/x" + std::to_string(L);
  using S = plume::scalar_t<T>;
  auto reg = [&](char const* name, auto query) {
    benchmark::RegisterBenchmark((std::string(name) + w).c_str(), [query](benchmark::State& st) {
      packed<T> const p;
      plume::bench::run_items(st, N, [&] {
        for (std::size_t g = 0; g < p.pose.size(); ++g) {
          auto const r = query(p, g);
          benchmark::DoNotOptimize(r);
        }
      });
    });
  };
  reg("gjk_ray_hull32", [](packed<T> const& p, std::size_t g) {
    return plume::ray_cast_gjk(p.hull(g), p.pose[g], plume::GRay3<T>{p.origin[g], p.dir[g]},
                               plume::infinity<T>())
        .toi;
  });
  reg("gjk_cast_box_hull32", [](packed<T> const& p, std::size_t g) {
    plume::ShapeCastConfig cfg;
    return plume::shape_cast(plume::GCuboid<T>{plume::GVec3<T>::splat(plume::splat<T>(S(0.3)))},
                             plume::GIso3<T>::from_translation(p.start[g]), p.dir[g] * S(8),
                             p.hull(g), p.pose[g], cfg)
        .toi;
  });
  reg("gjk_distance_capsule_hull32", [](packed<T> const& p, std::size_t g) {
    plume::GIso3<T> const at{p.pose[g].rotation, p.origin[g] * S(0.5)};
    return plume::closest_points(
               plume::GCapsule<T>{plume::splat<T>(S(0.5)), plume::splat<T>(S(0.2))}, at, p.hull(g),
               p.pose[g])
        .distance;
  });
}

} // namespace

int main(int argc, char** argv) {
  plume::bench::for_each_f32_width([]<class T>() { register_width<T>(); });
  return plume::bench::run_benchmarks(argc, argv);
}
