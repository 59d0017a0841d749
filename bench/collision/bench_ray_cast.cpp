// plume_bench_collision: closed-form ray casts, scalar against every width.
//
// Names follow <case>/f32/plume/x<width>; items = ray casts. ray_<shape>, "N rays x N
// shapes": ray i against shape i (N = 4096; origins in [-4, 4]^3 aimed near the shape, so
// about half hit); one_ray_<shape>, "one ray x N shapes": ray 0 (splat) against every shape.
// Shapes are given by a centre (sphere, capsule, cylinder: the ray is moved into the shape
// frame by a subtraction), a world box (AABB, stored as its min and max corners), a full pose
// (oriented box: a quaternion rotation per ray), or world vertices (triangle: the corners of
// the box's axes around the centre). Each cast's whole hit is stored to an array, at every
// width. The per-ray lambdas are forced inline
// (PLUME_BENCH_INLINE): g++ otherwise may keep one out of line, and the timed loop then
// measures a call and a result passed through memory.
#include <plume/collision.hpp>

#include "../bench_support.hpp"

#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <type_traits>
#include <vector>

namespace {

constexpr std::size_t N = 4096;

struct scene {
  std::vector<plume::Vec3> o, d, c, e;
  std::vector<float> r, h;
  std::vector<plume::Quat> q;
  scene() {
    std::mt19937 g(21);
    std::uniform_real_distribution<float> u(-1, 1);
    for (std::size_t i = 0; i < N; ++i) {
      plume::Vec3 const centre{u(g), u(g), u(g)};
      plume::Vec3 const origin{4 * u(g), 4 * u(g), 4 * u(g)};
      plume::Vec3 const aim = centre + plume::Vec3{u(g), u(g), u(g)} * 1.5f;
      o.push_back(origin);
      d.push_back((aim - origin).normalize());
      c.push_back(centre);
      e.push_back(plume::Vec3{0.3f + 0.5f * (u(g) + 1), 0.3f + 0.5f * (u(g) + 1),
                              0.3f + 0.5f * (u(g) + 1)});
      r.push_back(0.3f + 0.4f * (u(g) + 1));
      h.push_back(0.2f + 0.4f * (u(g) + 1));
      plume::Vec3 const axis = plume::Vec3{u(g), u(g), u(g) + 2}.normalize();
      float const angle = 3 * u(g); // separate statements: argument order is unspecified
      q.push_back(plume::Quat::from_axis_angle(axis, angle));
    }
  }
};
scene const& data() {
  static scene s;
  return s;
}

/// The scene packed for width L: element i/L holds items i..i+L-1 in its lanes.
template <class T>
struct packed {
  std::vector<plume::GVec3<T>> o, d, c, e;
  std::vector<plume::GAabb3<T>> box; ///< c - e .. c + e, stored as an AABB is (min, max)
  std::vector<T> r, h;
  std::vector<plume::GQuat<T>> q;
  packed() {
    constexpr std::size_t L = plume::lanes_v<T>;
    auto const& s = data();
    for (std::size_t i = 0; i < N; i += L) {
      plume::GVec3<T> o1, d1, c1, e1;
      T r1{}, h1{};
      plume::GQuat<T> q1;
      for (std::size_t l = 0; l < L; ++l) {
        o1 = plume::with_lane(o1, l, s.o[i + l]);
        d1 = plume::with_lane(d1, l, s.d[i + l]);
        c1 = plume::with_lane(c1, l, s.c[i + l]);
        e1 = plume::with_lane(e1, l, s.e[i + l]);
        r1 = plume::with_lane(r1, l, s.r[i + l]);
        h1 = plume::with_lane(h1, l, s.h[i + l]);
        q1 = plume::with_lane(q1, l, s.q[i + l]);
      }
      o.push_back(o1), d.push_back(d1), c.push_back(c1), e.push_back(e1);
      box.push_back(plume::GAabb3<T>{c1 - e1, c1 + e1});
      r.push_back(r1), h.push_back(h1), q.push_back(q1);
    }
  }
};

template <class T>
void register_width() {
  constexpr std::size_t L = plume::lanes_v<T>;
  std::string const w = "/f32/plume/x" + std::to_string(L);
  using V = plume::GVec3<T>;
  T const inf = plume::infinity<T>();
  // Each cast is registered twice: ray_<shape> casts ray i at shape i; one_ray_<shape> casts
  // ray 0, splat over the lanes, at every shape (what the ray's own work costs once it is
  // loop-invariant: 1/d and the ray's validity are hoisted by the compiler).
  auto reg = [&](char const* name, auto cast) {
    auto const run = [cast](benchmark::State& st, auto one_ray) {
      packed<T> const p;
      V const o0(data().o[0]), d0(data().d[0]);
      // Every width stores the whole hit (mask, toi, normal, feature) of every cast, so that
      // each does the same work. (DoNotOptimize(hit.toi) alone would keep a scalar toi in a
      // register and let the compiler drop the scalar normal as dead code, while a wide toi
      // goes through memory and takes the whole hit with it: the widths would time
      // different work.)
      std::vector<plume::GRayHit<T>> out(p.o.size());
      plume::bench::run_items(st, N, [&] {
        if constexpr (decltype(one_ray)::value) {
          // Copies local to the loop: a shared o0 and d0 could alias the output, and the
          // compiler would reload them and redo 1/d on every cast.
          V const o = o0, d = d0;
          for (std::size_t i = 0; i < p.o.size(); ++i)
            out[i] = cast(p, i, o, d);
        } else {
          for (std::size_t i = 0; i < p.o.size(); ++i)
            out[i] = cast(p, i, p.o[i], p.d[i]);
        }
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
      });
    };
    benchmark::RegisterBenchmark((std::string("ray_") + name + w).c_str(),
                                 [run](benchmark::State& st) { run(st, std::false_type{}); });
    benchmark::RegisterBenchmark((std::string("one_ray_") + name + w).c_str(),
                                 [run](benchmark::State& st) { run(st, std::true_type{}); });
  };
  reg("sphere", [inf](packed<T> const& p, std::size_t i, V const& o,
                      V const& d) PLUME_BENCH_INLINE {
    return plume::ray_cast_local(plume::GSphere<T>{p.r[i]}, plume::GRay3<T>{o - p.c[i], d}, inf);
  });
  reg("aabb", [inf](packed<T> const& p, std::size_t i, V const& o, V const& d) PLUME_BENCH_INLINE {
    return plume::ray_cast(p.box[i], plume::GRay3<T>{o, d}, inf);
  });
  reg("capsule",
      [inf](packed<T> const& p, std::size_t i, V const& o, V const& d) PLUME_BENCH_INLINE {
        return plume::ray_cast_local(plume::GCapsule<T>{p.h[i], p.r[i]},
                                     plume::GRay3<T>{o - p.c[i], d}, inf);
      });
  reg("cylinder",
      [inf](packed<T> const& p, std::size_t i, V const& o, V const& d) PLUME_BENCH_INLINE {
        return plume::ray_cast_local(plume::GCylinder<T>{p.h[i], p.r[i]},
                                     plume::GRay3<T>{o - p.c[i], d}, inf);
      });
  reg("oriented_box",
      [inf](packed<T> const& p, std::size_t i, V const& o, V const& d) PLUME_BENCH_INLINE {
        return plume::ray_cast(plume::GCuboid<T>{p.e[i]}, plume::GIso3<T>{p.q[i], p.c[i]},
                               plume::GRay3<T>{o, d}, inf);
      });
  reg("triangle",
      [inf](packed<T> const& p, std::size_t i, V const& o, V const& d) PLUME_BENCH_INLINE {
        T const z = plume::zero<T>();
        plume::GTriangle<T> const tri{p.c[i] + V{p.e[i].x, z, z}, p.c[i] + V{z, p.e[i].y, z},
                                      p.c[i] + V{z, z, p.e[i].z}};
        return plume::ray_cast_local(tri, plume::GRay3<T>{o, d}, inf);
      });
}

} // namespace

int main(int argc, char** argv) {
  plume::bench::for_each_f32_width([]<class T>() { register_width<T>(); });
  return plume::bench::run_benchmarks(argc, argv);
}
