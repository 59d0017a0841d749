// plume_bench_ray_scene: closest hits of many rays against a scene of N spheres, plume's
// brute-force loop at every width against Embree's sphere-point geometry (a BVH).
//
// Names: rays_spheres/n<N>/f32/<impl>/x<width>; items = rays (each finds its closest hit
// among all N spheres). R = 4096 rays from [-4, 4]^3 aimed into the scene's box [-1, 1]^3,
// spheres of radius 0.05..0.2 with centres in [-1, 1]^3.
//   plume/x<L>: the ray splatted over L lanes, the spheres packed L at a time, the nearest toi
//               kept per lane and reduced at the end. O(N) per ray: no acceleration structure
//               (plume has no BVH yet), so it wins for small N and loses as N grows.
//   embree/x1:  rtcIntersect1 per ray; embree/x8: rtcIntersect8 packets of 8 rays. The BVH is
//               built once, outside the timing. Built only when libembree-dev is installed.
#include <plume/collision.hpp>

#include "../bench_support.hpp"

#include <benchmark/benchmark.h>

#if PLUME_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

#include <random>
#include <string>
#include <vector>

namespace {

constexpr std::size_t R = 4096;

struct scene {
  std::vector<plume::Vec3> centre;
  std::vector<float> radius;
  std::vector<plume::Vec3> origin, dir;
  explicit scene(std::size_t n) {
    std::mt19937 g(77);
    std::uniform_real_distribution<float> u(-1, 1);
    for (std::size_t i = 0; i < n; ++i) {
      plume::Vec3 const c{u(g), u(g), u(g)};
      centre.push_back(c);
      radius.push_back(0.125f + 0.075f * u(g));
    }
    for (std::size_t i = 0; i < R; ++i) {
      plume::Vec3 const o{4 * u(g), 4 * u(g), 4 * u(g)};
      plume::Vec3 const aim{u(g), u(g), u(g)};
      origin.push_back(o);
      dir.push_back((aim - o).normalize());
    }
  }
};

template <class T>
void register_plume(std::size_t n) {
  constexpr std::size_t L = plume::lanes_v<T>;
  std::string const name =
      "rays_spheres/n" + std::to_string(n) + "/f32/plume/x" + std::to_string(L);
  benchmark::RegisterBenchmark(name.c_str(), [n](benchmark::State& st) {
    scene const s(n);
    // Spheres packed L at a time; a partial last group repeats sphere 0 (same hits).
    std::vector<plume::GVec3<T>> c;
    std::vector<T> r;
    for (std::size_t i = 0; i < n; i += L) {
      plume::GVec3<T> cc;
      T rr{};
      for (std::size_t l = 0; l < L; ++l) {
        std::size_t const k = i + l < n ? i + l : 0;
        cc = plume::with_lane(cc, l, s.centre[k]);
        rr = plume::with_lane(rr, l, s.radius[k]);
      }
      c.push_back(cc), r.push_back(rr);
    }
    std::size_t hits = 0;
    for (auto _ : st) {
      hits = 0;
      for (std::size_t i = 0; i < R; ++i) {
        plume::GVec3<T> const o(s.origin[i]), d(s.dir[i]);
        T best = plume::infinity<T>();
        for (std::size_t k = 0; k < c.size(); ++k) {
          auto const h =
              plume::ray_cast_local(plume::GSphere<T>{r[k]}, plume::GRay3<T>{o - c[k], d}, best);
          best = plume::select(h.hit, h.toi, best);
        }
        float const nearest = plume::reduce_min(best);
        hits += nearest < plume::infinity<float>();
      }
      benchmark::DoNotOptimize(hits);
    }
    st.counters["hit_fraction"] = double(hits) / double(R);
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(R));
  });
}

#if PLUME_HAVE_EMBREE
struct embree_scene {
  RTCDevice device = nullptr;
  RTCScene scn = nullptr;
  explicit embree_scene(scene const& s) {
    device = rtcNewDevice("threads=1");
    scn = rtcNewScene(device);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), s.centre.size()));
    for (std::size_t i = 0; i < s.centre.size(); ++i) {
      v[4 * i + 0] = s.centre[i].x;
      v[4 * i + 1] = s.centre[i].y;
      v[4 * i + 2] = s.centre[i].z;
      v[4 * i + 3] = s.radius[i];
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scn, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scn);
  }
  ~embree_scene() {
    rtcReleaseScene(scn);
    rtcReleaseDevice(device);
  }
  embree_scene(embree_scene const&) = delete;
  embree_scene& operator=(embree_scene const&) = delete;
};

void register_embree(std::size_t n) {
  std::string const base = "rays_spheres/n" + std::to_string(n) + "/f32/embree/";
  benchmark::RegisterBenchmark((base + "x1").c_str(), [n](benchmark::State& st) {
    scene const s(n);
    embree_scene const e(s);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    std::size_t hits = 0;
    for (auto _ : st) {
      hits = 0;
      for (std::size_t i = 0; i < R; ++i) {
        RTCRayHit rh{};
        rh.ray.org_x = s.origin[i].x, rh.ray.org_y = s.origin[i].y, rh.ray.org_z = s.origin[i].z;
        rh.ray.dir_x = s.dir[i].x, rh.ray.dir_y = s.dir[i].y, rh.ray.dir_z = s.dir[i].z;
        rh.ray.tnear = 0, rh.ray.tfar = plume::infinity<float>();
        rh.ray.mask = ~0u, rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(e.scn, &ctx, &rh);
        hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
      }
      benchmark::DoNotOptimize(hits);
    }
    st.counters["hit_fraction"] = double(hits) / double(R);
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(R));
  });
  benchmark::RegisterBenchmark((base + "x8").c_str(), [n](benchmark::State& st) {
    scene const s(n);
    embree_scene const e(s);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    alignas(32) int valid[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
    std::size_t hits = 0;
    for (auto _ : st) {
      hits = 0;
      for (std::size_t i = 0; i < R; i += 8) {
        alignas(32) RTCRayHit8 rh{};
        for (std::size_t l = 0; l < 8; ++l) {
          rh.ray.org_x[l] = s.origin[i + l].x, rh.ray.org_y[l] = s.origin[i + l].y;
          rh.ray.org_z[l] = s.origin[i + l].z;
          rh.ray.dir_x[l] = s.dir[i + l].x, rh.ray.dir_y[l] = s.dir[i + l].y;
          rh.ray.dir_z[l] = s.dir[i + l].z;
          rh.ray.tnear[l] = 0, rh.ray.tfar[l] = plume::infinity<float>();
          rh.ray.mask[l] = ~0u, rh.ray.flags[l] = 0;
          rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect8(valid, e.scn, &ctx, &rh);
        for (std::size_t l = 0; l < 8; ++l)
          hits += rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID;
      }
      benchmark::DoNotOptimize(hits);
    }
    st.counters["hit_fraction"] = double(hits) / double(R);
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(R));
  });
}
#endif

} // namespace

int main(int argc, char** argv) {
  for (std::size_t n : {16, 64, 256}) {
    plume::bench::for_each_f32_width([n]<class T>() { register_plume<T>(n); });
#if PLUME_HAVE_EMBREE
    register_embree(n);
#endif
  }
  return plume::bench::run_benchmarks(argc, argv);
}
