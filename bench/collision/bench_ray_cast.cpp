// plume_bench_collision: closed-form ray casts, scalar against every width.
//
// Names follow <case>/f32/plume/x<width>; items = ray casts. ray_<shape>, "N rays x N
// shapes": ray i against shape i (N = 4096; origins in [-4, 4]^3 aimed near the shape, so
// about half hit); one_ray_<shape>, "one ray x N shapes": ray 0 (splat) against every shape.
// Shapes are given by a centre (sphere, capsule, cylinder: the ray is moved into the shape
// frame by a subtraction), a world box (AABB, stored as its min and max corners), a full pose
// (oriented box: a quaternion rotation per ray), or world vertices (triangle: the corners of
// the box's axes around the centre). Each cast's whole hit is stored to an array, at every
// width. Peers (AVX2 builds and wider): ray_sphere and one_ray_sphere hand-written in AVX2
// intrinsics, unfused (plume's formulas and operation order: the same bits, checked before
// the benchmarks run) and fused (intrinsics_fma, on CPUs with FMA: what plume's
// build-exactness, which rules fusing out, costs this kernel). The per-ray lambdas are forced
// inline (PLUME_BENCH_INLINE): g++ otherwise may keep one out of line, and the timed loop then
// measures a call and a result passed through memory.
#include <plume/collision.hpp>

#include "../bench_support.hpp"

#include <benchmark/benchmark.h>

#if PLUME_HAS_AVX2
#include <immintrin.h>
#endif

#include <cstdio>
#include <cstring>
#include <limits>
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

#if PLUME_HAS_AVX2
/// c + a * b, rounded twice (Fused = false: what plume computes in every deterministic
/// build, c the left operand as in plume's sums, (x x + y y) + z z and o + d t) or once (true:
/// an FMA instruction).
template <bool Fused>
__attribute__((always_inline, target("fma"))) inline __m256 madd(__m256 a, __m256 b, __m256 c) {
  if constexpr (Fused)
    return _mm256_fmadd_ps(a, b, c);
  else
    return _mm256_add_ps(c, _mm256_mul_ps(a, b));
}
/// c - a * b, fused or not.
template <bool Fused>
__attribute__((always_inline, target("fma"))) inline __m256 nmadd(__m256 a, __m256 b, __m256 c) {
  if constexpr (Fused)
    return _mm256_fnmadd_ps(a, b, c);
  else
    return _mm256_sub_ps(c, _mm256_mul_ps(a, b));
}
/// a * b - c * d: the second product rounded, the first fused into the subtraction or not.
template <bool Fused>
__attribute__((always_inline, target("fma"))) inline __m256 mdiff(__m256 a, __m256 b, __m256 c,
                                                                  __m256 d) {
  if constexpr (Fused)
    return _mm256_fmsub_ps(a, b, _mm256_mul_ps(c, d));
  else
    return _mm256_sub_ps(_mm256_mul_ps(a, b), _mm256_mul_ps(c, d));
}

/// Hand-written AVX2 solid ray-sphere cast over the packed scene: ray_sphere's work (ray i
/// against sphere i, or with OneRay ray 0 in every lane against every sphere, the whole hit
/// stored). Unfused, it is the same formulas in the same operation order as
/// ray_cast_local(GSphere) with max_toi = +infinity, and gives plume's bits
/// (intrinsics_agree checks it): the abstraction-cost reference. Fused, it is the same kernel
/// with every product that feeds a sum fused: not plume's bits in any deterministic build
/// (their scalar and SSE2 builds have no FMA), so it measures what build-exactness costs.
/// (target("fma") only allows the fused instantiation: -ffp-contract=off keeps the unfused
/// one unfused.)
template <bool Fused, bool OneRay>
__attribute__((target("fma"))) void
sphere_intrinsics(packed<plume::f32x8> const& p, plume::GVec3<plume::f32x8> const& o0,
                  plume::GVec3<plume::f32x8> const& d0, plume::GRayHit<plume::f32x8>* out) {
  using plume::f32x8;
  __m256 const zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.f),
               inf = _mm256_set1_ps(std::numeric_limits<float>::infinity()),
               lim = _mm256_set1_ps(std::numeric_limits<float>::max()), none = _mm256_set1_ps(-1.f),
               sqrt_eps = _mm256_set1_ps(std::sqrt(std::numeric_limits<float>::epsilon()));
  __m256 const ox0 = o0.x.data, oy0 = o0.y.data, oz0 = o0.z.data;
  __m256 const dx0 = d0.x.data, dy0 = d0.y.data, dz0 = d0.z.data;
  for (std::size_t i = 0; i < p.o.size(); ++i) {
    __m256 const fx = _mm256_sub_ps(OneRay ? ox0 : p.o[i].x.data, p.c[i].x.data),
                 fy = _mm256_sub_ps(OneRay ? oy0 : p.o[i].y.data, p.c[i].y.data),
                 fz = _mm256_sub_ps(OneRay ? oz0 : p.o[i].z.data, p.c[i].z.data);
    __m256 const dx = OneRay ? dx0 : p.d[i].x.data, dy = OneRay ? dy0 : p.d[i].y.data,
                 dz = OneRay ? dz0 : p.d[i].z.data, r = p.r[i].data;
    // a = d . d, b = f . d, |f|^2 (sums left to right, as GVec3::dot), c = |f|^2 - r^2
    __m256 const a = madd<Fused>(dz, dz, madd<Fused>(dy, dy, _mm256_mul_ps(dx, dx)));
    __m256 const b = madd<Fused>(fz, dz, madd<Fused>(fy, dy, _mm256_mul_ps(fx, dx)));
    __m256 const ff = madd<Fused>(fz, fz, madd<Fused>(fy, fy, _mm256_mul_ps(fx, fx)));
    __m256 const r2 = _mm256_mul_ps(r, r);
    // disc = a r^2 - |f x d|^2, the entry c / (sqrt(disc) - b)
    __m256 const kx = mdiff<Fused>(fy, dz, fz, dy), ky = mdiff<Fused>(fz, dx, fx, dz),
                 kz = mdiff<Fused>(fx, dy, fy, dx);
    __m256 const k2 = madd<Fused>(kz, kz, madd<Fused>(ky, ky, _mm256_mul_ps(kx, kx)));
    __m256 const disc = _mm256_sub_ps(_mm256_mul_ps(a, r2), k2);
    __m256 const t = _mm256_div_ps(_mm256_sub_ps(ff, r2), _mm256_sub_ps(_mm256_sqrt_ps(disc), b));
    // inside: toi b - b (0, or NaN for a non-finite direction); outside: hit when moving
    // towards the centre and t <= FLT_MAX (a NaN t, disc < 0, fails)
    __m256 const inside = _mm256_cmp_ps(ff, r2, _CMP_LE_OQ);
    __m256 const toward =
        _mm256_and_ps(_mm256_cmp_ps(b, zero, _CMP_LT_OQ), _mm256_cmp_ps(a, zero, _CMP_GT_OQ));
    __m256 const toi = _mm256_blendv_ps(t, _mm256_sub_ps(b, b), inside);
    __m256 const hit =
        _mm256_and_ps(_mm256_or_ps(inside, toward), _mm256_cmp_ps(toi, lim, _CMP_LE_OQ));
    // normal n = (f + d t) / r where the hit has a surface and r > 0, made unit by one Newton
    // step n (1.5 - 0.5 n . n) where |n . n - 1| <= sqrt(eps), else by n / |n| (where that
    // is finite and > 0, zero elsewhere); feature 0 there, else -1
    __m256 const inv_r = _mm256_div_ps(one, r);
    __m256 const nx = _mm256_mul_ps(madd<Fused>(dx, t, fx), inv_r),
                 ny = _mm256_mul_ps(madd<Fused>(dy, t, fy), inv_r),
                 nz = _mm256_mul_ps(madd<Fused>(dz, t, fz), inv_r);
    __m256 const l2 = madd<Fused>(nz, nz, madd<Fused>(ny, ny, _mm256_mul_ps(nx, nx)));
    __m256 const step = nmadd<Fused>(_mm256_set1_ps(0.5f), l2, _mm256_set1_ps(1.5f));
    __m256 ux = _mm256_mul_ps(nx, step), uy = _mm256_mul_ps(ny, step), uz = _mm256_mul_ps(nz, step);
    __m256 const surface = _mm256_andnot_ps(inside, hit);
    __m256 const keep = _mm256_and_ps(surface, _mm256_cmp_ps(r, zero, _CMP_GT_OQ));
    __m256 const off = _mm256_andnot_ps(_mm256_set1_ps(-0.0f), _mm256_sub_ps(l2, one));
    __m256 const far = _mm256_andnot_ps(_mm256_cmp_ps(off, sqrt_eps, _CMP_LE_OQ), keep);
    if (_mm256_movemask_ps(far) != 0) {
      __m256 const rl = _mm256_div_ps(one, _mm256_sqrt_ps(l2));
      __m256 const ok = _mm256_and_ps(far, _mm256_and_ps(_mm256_cmp_ps(rl, inf, _CMP_LT_OQ),
                                                         _mm256_cmp_ps(rl, zero, _CMP_GT_OQ)));
      ux = _mm256_blendv_ps(ux, _mm256_and_ps(ok, _mm256_mul_ps(nx, rl)), far);
      uy = _mm256_blendv_ps(uy, _mm256_and_ps(ok, _mm256_mul_ps(ny, rl)), far);
      uz = _mm256_blendv_ps(uz, _mm256_and_ps(ok, _mm256_mul_ps(nz, rl)), far);
    }
    plume::GRayHit<f32x8>& h = out[i];
    h.hit = plume::mask_t<f32x8>(hit);
    h.toi = f32x8(_mm256_blendv_ps(inf, toi, hit));
    h.normal.x = f32x8(_mm256_and_ps(keep, ux));
    h.normal.y = f32x8(_mm256_and_ps(keep, uy));
    h.normal.z = f32x8(_mm256_and_ps(keep, uz));
    h.feature = f32x8(_mm256_andnot_ps(surface, none));
  }
}

/// Runs the kernel on the scene; o0 and d0 are ray 0 in every lane (one_ray_sphere's ray).
template <bool Fused>
void sphere_intrinsics_run(packed<plume::f32x8> const& p, bool one_ray,
                           plume::GRayHit<plume::f32x8>* out) {
  plume::GVec3<plume::f32x8> const o0(data().o[0]), d0(data().d[0]);
  if (one_ray)
    sphere_intrinsics<Fused, true>(p, o0, d0, out);
  else
    sphere_intrinsics<Fused, false>(p, o0, d0, out);
}

void register_intrinsics() {
  __builtin_cpu_init();
  bool const fma = __builtin_cpu_supports("fma");
  for (bool fused : {false, true})
    for (bool one_ray : {false, true}) {
      if (fused && !fma) continue;
      std::string const name = std::string(one_ray ? "one_ray_sphere" : "ray_sphere") +
                               (fused ? "/f32/intrinsics_fma/x8" : "/f32/intrinsics/x8");
      benchmark::RegisterBenchmark(name.c_str(), [fused, one_ray](benchmark::State& st) {
        packed<plume::f32x8> const p;
        std::vector<plume::GRayHit<plume::f32x8>> out(p.o.size());
        plume::bench::run_items(st, N, [&] {
          if (fused)
            sphere_intrinsics_run<true>(p, one_ray, out.data());
          else
            sphere_intrinsics_run<false>(p, one_ray, out.data());
          benchmark::DoNotOptimize(out.data());
          benchmark::ClobberMemory();
        });
      });
    }
}

/// The unfused intrinsics kernel must compute what plume computes, bit for bit, or the
/// comparison would not be of the same work.
bool intrinsics_agree() {
  using plume::f32x8;
  using V = plume::GVec3<f32x8>;
  packed<f32x8> const p;
  V const o0(data().o[0]), d0(data().d[0]);
  std::vector<plume::GRayHit<f32x8>> got(p.o.size());
  for (bool one_ray : {false, true}) {
    sphere_intrinsics_run<false>(p, one_ray, got.data());
    for (std::size_t i = 0; i < p.o.size(); ++i) {
      V const o = one_ray ? o0 : p.o[i], d = one_ray ? d0 : p.d[i];
      auto const want =
          plume::ray_cast_local(plume::GSphere<f32x8>{p.r[i]}, plume::GRay3<f32x8>{o - p.c[i], d},
                                plume::infinity<f32x8>());
      if (std::memcmp(&want, &got[i], sizeof want) != 0) {
        std::fprintf(stderr, "intrinsics ray-sphere differs from plume at batch %zu%s\n", i,
                     one_ray ? " (one ray)" : "");
        return false;
      }
    }
  }
  return true;
}
#endif

} // namespace

int main(int argc, char** argv) {
  plume::bench::for_each_f32_width([]<class T>() { register_width<T>(); });
#if PLUME_HAS_AVX2
  register_intrinsics();
  if (!intrinsics_agree()) return 1;
#endif
  return plume::bench::run_benchmarks(argc, argv);
}
