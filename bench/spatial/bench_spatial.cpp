// plume_bench_spatial: the spatial floor's trees against Embree 3 on a large sphere scene, and
// the dynamic tree's optimisation modes under motion.
//
// Names (items = rays, primitives or proxies; items_per_second is the figure):
//   spatial_ray/spheres100k/plume/x<W>   closest hit of each ray: GWideBvh<T>::ray_cast (T =
//                                         float, f32x4, f32x8, f32x16 as built; K = max(4, W)
//                                         children per node) with plume's scalar sphere cast as
//                                         the leaf. Same rays, tree and answers at every width.
//   spatial_ray/spheres100k/embree/x1    rtcIntersect1 per ray; embree/x8, x16: rtcIntersect8/16
//                                         packets of consecutive rays (skipped where the device
//                                         has no native packets of that size: x16 needs AVX-512).
//   spatial_build/spheres100k/plume/bvh  AabbTree insert of every sphere + rebuild() + the
//                                         WideBvh copy (f32xN); items = spheres.
//   spatial_build/spheres100k/embree     a new scene with its sphere-point geometry to
//                                         rtcCommitScene; items = spheres.
//   spatial_tree/stress10k/<mode>        one frame per iteration: 10,000 boxes on a grid move
//                                         (random walk), then optimize(<mode>); items = proxies.
//   spatial_ray/terrain1m/plume/x<W>     closest hit of each ray on a TriangleMesh of 999,698
//                                         triangles (TriangleMesh::ray_cast_blocks_with its
//                                         make_block_bvh<T>(): leaves of up to
//                                         triangle_block_size triangles, each cast lanes_v<T> at
//                                         a time by the watertight triangle cast).
//   spatial_ray_leaf1/terrain1m/plume/x<W>  the same through a GWideBvh<T> of the mesh's tree:
//                                         one triangle per leaf (as before the blocks).
//   spatial_ray/terrain1m/embree/x1      rtcIntersect1, RTC_GEOMETRY_TYPE_TRIANGLE with the same
//                                         vertices and indices.
//   spatial_build/terrain1m/plume/bvh    TriangleMesh::build (validation, adjacency, tree insert
//                                         + rebuild(), the WideBvh copy); items = triangles.
//   spatial_build/terrain1m/embree       a new scene with the triangle geometry to
//                                         rtcCommitScene; items = triangles.
//   spatial_ray/terrain1m/plume/heightfield  the same rays on a HeightField of the same
//                                         heights (no stored triangles, a min-max pyramid).
//   spatial_shape_cast/terrain1m/plume/<mesh|heightfield>  mesh_shape_cast of a capsule
//                                         (radius 0.3, half height 0.5) from 2 m above the
//                                         terrain, 6 m down and across; items = casts.
//   spatial_overlap/terrain1m/plume/<mesh|heightfield>  mesh_intersects of a 0.4 m box at
//                                         the terrain's surface, half touching; items = queries.
//   spatial_contacts/terrain1m/plume/<mesh|heightfield>  mesh_contacts of a 0.5 m box resting
//                                         1 cm deep (internal edges corrected); items = queries.
//   spatial_builder/<spheres100k|terrain1m>/<sah|ploc>  AabbTree::insert_all of the scene's
//                                         boxes (spheres' boxes; triangles' tight boxes) with
//                                         TreeBuilder binned_sah or ploc; items = boxes.
//                                         Counters: area_ratio, height, and rays_per_second of
//                                         the scene's rays through a WideBvh of that tree
//                                         (timed once per run, outside the build's timing).
//   spatial_ray/stress10k_after_updates/plume/x<W>  rays against the stress tree after 300
//                                         frames of reinsert updates; counters compare it with a
//                                         fresh rebuild of the same boxes.
//
// Scene: 100,000 spheres, centres uniform in [-10, 10]^3, radii 0.03..0.07; R = 4096 rays from
// a sphere of radius 25 around the cube aimed at points uniform in [-9, 9]^3 (incoherent:
// consecutive rays share nothing). About 4 in 5 hit.
// Terrain: a 708 x 708 vertex grid of spacing 0.1 over x, z, two triangles per cell, heights
// from four octaves of sines (amplitudes 4, 1.5, 0.5, 0.15); R rays from 20 to 40 above the
// terrain aimed down at uniform points of it, one in eight grazing (|dir.y| about 0.02 to 0.1
// of the horizontal). The terrain's hits are checked the same way (same triangle, or toi
// within 1e-4 relative).
// Embree: one device with threads=1 (plume is single threaded), scene and geometry at
// Embree's default build quality (RTC_BUILD_QUALITY_MEDIUM) and default scene flags.
// Counters: hit_fraction; nodes, nodes_per_ray and leaf_casts_per_ray (the wide tree's size and
// the work of one ray, counted outside the timing); height and area_ratio of trees (stats()),
// rebuilt_area_ratio of a fresh rebuild of the same boxes, moved_fraction (leaves out of their
// fat boxes per frame), frac_<mode> (what adaptive chose), rebuilt_speedup (rays/s of a fresh
// rebuild over the updated tree's).
// Every width's hits are checked once against width 1 and against Embree (same sphere, or the
// same toi within 1e-4 relative) before timing; a benchmark that disagrees stops with an error.
#include <plume/collision.hpp>
#include <plume/spatial.hpp>

#include "../bench_support.hpp"

#include <benchmark/benchmark.h>

#if PLUME_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using plume::AabbTree;
using plume::ProxyId;
using plume::TreeOptimization;
using plume::TreeRayHit;
using plume::Vec3;

constexpr std::size_t R = 4096;
constexpr std::size_t n_spheres = 100000;
constexpr float inf = std::numeric_limits<float>::infinity();
/// The casts' max_toi: the largest finite float, not +infinity. GWideBvh::ray_cast with
/// max_toi = +infinity takes a leaf's +infinity (a miss) for a hit (t <= limit holds and the
/// proxy is below null_proxy), so a ray that meets fat boxes but no sphere would report the
/// first leaf it tried at toi +infinity. Every toi here is below 100.
constexpr float max_toi_all = std::numeric_limits<float>::max();

/// Same sphere, or the same toi within 1e-4 relative (both misses agree).
bool same_hit(TreeRayHit const& a, TreeRayHit const& b) {
  if (a.proxy == b.proxy) return true;
  if (!a.hit() || !b.hit()) return false;
  return std::fabs(a.toi - b.toi) <= 1e-4f * std::max(std::fabs(a.toi), std::fabs(b.toi));
}

/// "" when every hit agrees with the reference, else how many differ and the first one.
std::string mismatches(std::span<TreeRayHit const> got, std::span<TreeRayHit const> ref) {
  std::size_t bad = 0, first = 0;
  for (std::size_t i = 0; i < got.size(); ++i)
    if (!same_hit(got[i], ref[i]) && bad++ == 0) first = i;
  if (bad == 0) return "";
  auto const show = [](TreeRayHit const& h) {
    return h.hit() ? std::to_string(h.proxy) + " at " + std::to_string(h.toi) : std::string("none");
  };
  return std::to_string(bad) + " rays differ; ray " + std::to_string(first) + ": " +
         show(got[first]) + " vs " + show(ref[first]);
}

std::size_t hit_count(std::span<TreeRayHit const> hits) {
  return std::size_t(
      std::count_if(hits.begin(), hits.end(), [](auto const& h) { return h.hit(); }));
}

// ------------------------------------------------------------------ the sphere scene

struct sphere {
  Vec3 centre;
  float radius;
};

struct sphere_scene {
  std::vector<sphere> spheres; // indexed by proxy id (ids are 0.. in insertion order)
  std::vector<Vec3> origin, dir;
  AabbTree tree;
  std::vector<TreeRayHit> reference; // GWideBvh<float>: the width-1 answers

  sphere_scene() {
    std::mt19937 g(2024);
    std::uniform_real_distribution<float> u(-1, 1);
    for (std::size_t i = 0; i < n_spheres; ++i) {
      Vec3 const c{10 * u(g), 10 * u(g), 10 * u(g)};
      spheres.push_back({c, 0.05f + 0.02f * u(g)});
    }
    for (std::size_t i = 0; i < R; ++i) {
      Vec3 const o = Vec3{u(g), u(g), u(g) + 0.01f}.normalize() * 25.0f;
      Vec3 const aim{9 * u(g), 9 * u(g), 9 * u(g)};
      origin.push_back(o);
      dir.push_back((aim - o).normalize());
    }
    build_tree(tree, spheres);
  }

  static void build_tree(AabbTree& t, std::span<sphere const> s) {
    t.clear();
    std::vector<plume::Aabb3> boxes(s.size());
    for (std::size_t i = 0; i < s.size(); ++i)
      boxes[i] = plume::Aabb3::from_sphere(s[i].centre, s[i].radius);
    std::vector<ProxyId> const ids = t.insert_all(boxes); // one binned-SAH build
    for (std::size_t i = 0; i < ids.size(); ++i)
      if (ids[i] != ProxyId(i)) throw std::logic_error("bench_spatial: proxy ids not 0..n-1");
  }
};

/// Each ray's closest sphere. Out of line (and named) so its code can be read in the binary.
template <class T>
[[gnu::noinline]] void plume_bench_cast_spheres(plume::GWideBvh<T> const& bvh,
                                                sphere_scene const& s, TreeRayHit* out) {
  sphere const* const sp = s.spheres.data();
  for (std::size_t i = 0; i < R; ++i) {
    Vec3 const o = s.origin[i], d = s.dir[i];
    out[i] = bvh.ray_cast(plume::Ray3{o, d}, max_toi_all, [&](ProxyId id, float max_toi) {
      sphere const& k = sp[id];
      return plume::ray_cast_local(plume::Sphere{k.radius}, plume::Ray3{o - k.centre, d}, max_toi)
          .toi;
    });
  }
}

/// Diagnostics for the counters (not timed): the wide nodes a ray visits, by the traversal
/// GWideBvh::ray_cast does (nearest first, pruned at the best toi), leaves cast as above.
template <class T>
std::size_t nodes_visited(plume::GWideBvh<T> const& bvh, sphere_scene const& s, std::size_t i) {
  using bvh_t = plume::GWideBvh<T>;
  constexpr std::size_t K = bvh_t::arity, L = bvh_t::lanes;
  Vec3 const o = s.origin[i], d = s.dir[i];
  bool const neg[3] = {std::signbit(d.x), std::signbit(d.y), std::signbit(d.z)};
  auto const r =
      plume::detail::make_ray_slab(plume::detail::splat3<T>(o), plume::detail::splat3<T>(d), neg);
  struct entry {
    std::uint32_t ref;
    float at;
  };
  std::vector<entry> stack{{0, 0.0f}};
  float limit = max_toi_all;
  std::size_t visits = 0;
  while (!stack.empty()) {
    entry const e = stack.back();
    stack.pop_back();
    if (e.at > limit) continue;
    if (e.ref & bvh_t::leaf_bit) {
      sphere const& k = s.spheres[e.ref & ~bvh_t::leaf_bit];
      float const t =
          plume::ray_cast_local(plume::Sphere{k.radius}, plume::Ray3{o - k.centre, d}, limit).toi;
      limit = std::min(limit, t);
      continue;
    }
    ++visits;
    auto const& node = bvh.nodes()[e.ref];
    alignas(64) std::array<float, K> at;
    std::uint64_t bits = 0;
    for (std::size_t g = 0; g < K / L; ++g) {
      T en;
      plume::GAabb3<T> const b = node.template box<T>(g);
      auto const m = plume::detail::ray_enters(r, b.min, b.max, plume::splat<T>(limit), en);
      plume::store_aligned(&at[g * L], en);
      bits |= plume::bitmask(m) << (g * L);
    }
    std::vector<entry> met;
    for (; bits; bits &= bits - 1) {
      auto const c = std::size_t(std::countr_zero(bits));
      met.push_back({node.child[c], at[c]});
    }
    std::stable_sort(met.begin(), met.end(), [](entry a, entry b) { return a.at > b.at; });
    stack.insert(stack.end(), met.begin(), met.end());
  }
  return visits;
}

sphere_scene& spheres_scene() {
  static sphere_scene s = [] {
    sphere_scene t;
    plume::GWideBvh<float> const bvh(t.tree);
    t.reference.resize(R);
    plume_bench_cast_spheres(bvh, t, t.reference.data());
    return t;
  }();
  return s;
}

#if PLUME_HAVE_EMBREE
struct embree_device {
  RTCDevice device = rtcNewDevice("threads=1");
  embree_device() = default;
  ~embree_device() { rtcReleaseDevice(device); }
  embree_device(embree_device const&) = delete;
  embree_device& operator=(embree_device const&) = delete;
};

RTCDevice embree() {
  static embree_device d;
  return d.device;
}

/// A committed scene of the spheres (default build quality).
RTCScene embree_commit(std::span<sphere const> s) {
  RTCScene scn = rtcNewScene(embree());
  RTCGeometry geom = rtcNewGeometry(embree(), RTC_GEOMETRY_TYPE_SPHERE_POINT);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), s.size()));
  for (std::size_t i = 0; i < s.size(); ++i) {
    v[4 * i + 0] = s[i].centre.x;
    v[4 * i + 1] = s[i].centre.y;
    v[4 * i + 2] = s[i].centre.z;
    v[4 * i + 3] = s[i].radius;
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scn, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scn);
  return scn;
}

struct embree_scene {
  RTCScene scn;
  std::vector<TreeRayHit> hits; // rtcIntersect1's answers
  explicit embree_scene(sphere_scene const& s) : scn(embree_commit(s.spheres)), hits(R) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (std::size_t i = 0; i < R; ++i)
      hits[i] = cast1(ctx, s.origin[i], s.dir[i]);
  }
  ~embree_scene() { rtcReleaseScene(scn); }
  embree_scene(embree_scene const&) = delete;
  embree_scene& operator=(embree_scene const&) = delete;

  TreeRayHit cast1(RTCIntersectContext& ctx, Vec3 const& o, Vec3 const& d) const {
    RTCRayHit rh{};
    rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
    rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
    rh.ray.tnear = 0, rh.ray.tfar = inf;
    rh.ray.mask = ~0u, rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scn, &ctx, &rh);
    TreeRayHit h;
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) h.proxy = rh.hit.primID, h.toi = rh.ray.tfar;
    return h;
  }
};

embree_scene const& spheres_embree() {
  static embree_scene const e(spheres_scene());
  return e;
}
#endif

template <class T>
void register_sphere_rays() {
  std::string const name = "spatial_ray/spheres100k/plume/x" + std::to_string(plume::lanes_v<T>);
  benchmark::RegisterBenchmark(name.c_str(), [](benchmark::State& st) {
    sphere_scene const& s = spheres_scene();
    plume::GWideBvh<T> const bvh(s.tree);
    std::vector<TreeRayHit> hits(R);
    plume_bench_cast_spheres(bvh, s, hits.data());
    if (std::string const bad = mismatches(hits, s.reference); !bad.empty()) {
      st.SkipWithError(("hits differ from width 1: " + bad).c_str());
      return;
    }
#if PLUME_HAVE_EMBREE
    if (std::string const bad = mismatches(hits, spheres_embree().hits); !bad.empty()) {
      st.SkipWithError(("hits differ from Embree: " + bad).c_str());
      return;
    }
#endif
    plume::bench::run_items(st, std::int64_t(R), [&] {
      plume_bench_cast_spheres(bvh, s, hits.data());
      benchmark::DoNotOptimize(hits.data());
      benchmark::ClobberMemory();
    });
    st.counters["hit_fraction"] = double(hit_count(hits)) / double(R);
    st.counters["nodes"] = double(bvh.node_count());
    // Leaf casts per ray (the leaves whose fat boxes the ray enters before the best hit).
    std::size_t leaf_casts = 0;
    for (std::size_t i = 0; i < R; ++i) {
      Vec3 const o = s.origin[i], d = s.dir[i];
      (void)bvh.ray_cast(plume::Ray3{o, d}, max_toi_all, [&](ProxyId id, float max_toi) {
        ++leaf_casts;
        sphere const& k = s.spheres[id];
        return plume::ray_cast_local(plume::Sphere{k.radius}, plume::Ray3{o - k.centre, d}, max_toi)
            .toi;
      });
    }
    st.counters["leaf_casts_per_ray"] = double(leaf_casts) / double(R);
    std::size_t visits = 0;
    for (std::size_t i = 0; i < R; ++i)
      visits += nodes_visited(bvh, s, i);
    st.counters["nodes_per_ray"] = double(visits) / double(R);
  });
}

#if PLUME_HAVE_EMBREE
/// rtcIntersect<N> over packets of N consecutive rays (all lanes valid).
template <std::size_t N, class RayHitN, class Intersect>
void embree_packets(benchmark::State& st, RTCDeviceProperty native, Intersect intersect) {
  if (!rtcGetDeviceProperty(embree(), native)) {
    st.SkipWithError(("this CPU has no native " + std::to_string(N) +
                      "-ray packets in Embree (x16 needs AVX-512)")
                         .c_str());
    return;
  }
  sphere_scene const& s = spheres_scene();
  embree_scene const& e = spheres_embree();
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  alignas(64) std::array<int, N> valid;
  valid.fill(-1);
  std::vector<TreeRayHit> hits(R);
  auto const pass = [&] {
    for (std::size_t i = 0; i < R; i += N) {
      alignas(64) RayHitN rh{};
      for (std::size_t l = 0; l < N; ++l) {
        rh.ray.org_x[l] = s.origin[i + l].x, rh.ray.org_y[l] = s.origin[i + l].y;
        rh.ray.org_z[l] = s.origin[i + l].z;
        rh.ray.dir_x[l] = s.dir[i + l].x, rh.ray.dir_y[l] = s.dir[i + l].y;
        rh.ray.dir_z[l] = s.dir[i + l].z;
        rh.ray.tnear[l] = 0, rh.ray.tfar[l] = inf;
        rh.ray.mask[l] = ~0u, rh.ray.flags[l] = 0;
        rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
      }
      intersect(valid.data(), e.scn, &ctx, &rh);
      for (std::size_t l = 0; l < N; ++l) {
        TreeRayHit h;
        if (rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID)
          h.proxy = rh.hit.primID[l], h.toi = rh.ray.tfar[l];
        hits[i + l] = h;
      }
    }
  };
  pass();
  if (std::string const bad = mismatches(hits, s.reference); !bad.empty()) {
    st.SkipWithError(("packet hits differ from plume: " + bad).c_str());
    return;
  }
  plume::bench::run_items(st, std::int64_t(R), [&] {
    pass();
    benchmark::DoNotOptimize(hits.data());
  });
  st.counters["hit_fraction"] = double(hit_count(hits)) / double(R);
}

void register_embree_rays() {
  benchmark::RegisterBenchmark("spatial_ray/spheres100k/embree/x1", [](benchmark::State& st) {
    sphere_scene const& s = spheres_scene();
    embree_scene const& e = spheres_embree();
    if (std::string const bad = mismatches(e.hits, s.reference); !bad.empty()) {
      st.SkipWithError(("Embree's hits differ from plume: " + bad).c_str());
      return;
    }
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    std::size_t hits = 0;
    plume::bench::run_items(st, std::int64_t(R), [&] {
      hits = 0;
      for (std::size_t i = 0; i < R; ++i)
        hits += e.cast1(ctx, s.origin[i], s.dir[i]).hit();
      benchmark::DoNotOptimize(hits);
    });
    st.counters["hit_fraction"] = double(hits) / double(R);
  });
  benchmark::RegisterBenchmark("spatial_ray/spheres100k/embree/x8", [](benchmark::State& st) {
    embree_packets<8, RTCRayHit8>(st, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED,
                                  [](int const* v, RTCScene scn, RTCIntersectContext* c,
                                     RTCRayHit8* rh) { rtcIntersect8(v, scn, c, rh); });
  });
  benchmark::RegisterBenchmark("spatial_ray/spheres100k/embree/x16", [](benchmark::State& st) {
    embree_packets<16, RTCRayHit16>(st, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED,
                                    [](int const* v, RTCScene scn, RTCIntersectContext* c,
                                       RTCRayHit16* rh) { rtcIntersect16(v, scn, c, rh); });
  });
}
#endif

void register_builds() {
  benchmark::RegisterBenchmark("spatial_build/spheres100k/plume/bvh", [](benchmark::State& st) {
    sphere_scene const& s = spheres_scene();
    AabbTree tree;
    plume::WideBvh bvh;
    plume::bench::run_items(st, std::int64_t(n_spheres), [&] {
      sphere_scene::build_tree(tree, s.spheres);
      bvh.build(tree);
      benchmark::DoNotOptimize(bvh.node_count());
    });
    auto const stats = tree.stats();
    st.counters["height"] = double(stats.height);
    st.counters["area_ratio"] = double(stats.area_ratio);
  });
#if PLUME_HAVE_EMBREE
  benchmark::RegisterBenchmark("spatial_build/spheres100k/embree", [](benchmark::State& st) {
    sphere_scene const& s = spheres_scene();
    for (auto _ : st) {
      RTCScene const scn = embree_commit(s.spheres);
      st.PauseTiming();
      rtcReleaseScene(scn);
      st.ResumeTiming();
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(n_spheres));
  });
#endif
}

// ------------------------------------------------------------------ the terrain

constexpr std::uint32_t terrain_side = 708; // vertices per side: 2 x 707^2 = 999,698 triangles

struct terrain_scene {
  std::vector<Vec3> vertices;
  std::vector<std::uint32_t> indices;
  plume::TriangleMesh mesh;
  std::vector<Vec3> origin, dir;
  std::vector<TreeRayHit> reference; // width 1; proxy = input triangle index

  terrain_scene() {
    std::uint32_t const n = terrain_side;
    float const h = 0.1f;
    for (std::uint32_t z = 0; z < n; ++z)
      for (std::uint32_t x = 0; x < n; ++x)
        vertices.push_back({float(x) * h, height(float(x) * h, float(z) * h), float(z) * h});
    for (std::uint32_t z = 0; z + 1 < n; ++z)
      for (std::uint32_t x = 0; x + 1 < n; ++x) {
        std::uint32_t const a = z * n + x, b = a + 1, c = a + n, d = c + 1;
        indices.insert(indices.end(), {a, c, b, b, c, d});
      }
    auto r = plume::TriangleMesh::build(vertices, indices);
    if (!r.ok())
      throw std::logic_error(std::string("bench_spatial: terrain: ") + to_string(r.error));
    mesh = std::move(r.mesh);
    std::mt19937 g(4711);
    std::uniform_real_distribution<float> u(0, 1);
    float const extent = float(n - 1) * h;
    for (std::size_t i = 0; i < R; ++i) {
      Vec3 const aim{extent * u(g), 0, extent * u(g)};
      Vec3 const at{aim.x, height(aim.x, aim.z), aim.z};
      float const phi = 6.2831853f * u(g);
      Vec3 d;
      if (i % 8 == 7) { // grazing
        d = Vec3{std::cos(phi), -(0.02f + 0.08f * u(g)), std::sin(phi)};
      } else {
        float const tilt = 0.8f * u(g);
        d = Vec3{tilt * std::cos(phi), -1, tilt * std::sin(phi)};
      }
      d = d.normalize();
      float const back = (20.0f + 20.0f * u(g)) / -d.y;
      origin.push_back(i % 8 == 7 ? at - d * 30.0f : at - d * back);
      dir.push_back(d);
    }
    reference.resize(R);
    cast<false>(plume::GWideBvh<float>(mesh.tree()), reference.data());
  }
  static float height(float x, float z) {
    return 4.0f * std::sin(0.11f * x) * std::cos(0.13f * z) +
           1.5f * std::sin(0.37f * x + 0.21f * z) * std::cos(0.29f * z - 0.17f * x) +
           0.5f * std::sin(1.3f * x) * std::sin(1.1f * z) + 0.15f * std::cos(3.7f * x + 2.9f * z);
  }
  /// Blocks: bvh is a make_block_bvh() copy (leaves of triangle blocks), else a copy of
  /// tree() (a triangle per leaf).
  template <bool Blocks, class T>
  void cast(plume::GWideBvh<T> const& bvh, TreeRayHit* out) const {
    plume_bench_cast_terrain<Blocks>(mesh, bvh, origin.data(), dir.data(), out);
  }
  template <bool Blocks, class T>
  [[gnu::noinline]] static void
  plume_bench_cast_terrain(plume::TriangleMesh const& m, plume::GWideBvh<T> const& bvh,
                           Vec3 const* o, Vec3 const* d, TreeRayHit* out) {
    for (std::size_t i = 0; i < R; ++i) {
      plume::Ray3 const ray{o[i], d[i]};
      plume::MeshRayHit const h = Blocks ? m.ray_cast_blocks_with(bvh, ray, max_toi_all)
                                         : m.ray_cast_with(bvh, ray, max_toi_all);
      TreeRayHit t;
      if (h.hit()) t.proxy = m.source_triangle(h.triangle), t.toi = h.toi;
      out[i] = t;
    }
  }
};

terrain_scene const& terrain() {
  static terrain_scene const t;
  return t;
}

#if PLUME_HAVE_EMBREE
RTCScene embree_commit_triangles(std::span<Vec3 const> v, std::span<std::uint32_t const> idx) {
  RTCScene scn = rtcNewScene(embree());
  RTCGeometry geom = rtcNewGeometry(embree(), RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), v.size()));
  for (std::size_t i = 0; i < v.size(); ++i)
    vb[3 * i + 0] = v[i].x, vb[3 * i + 1] = v[i].y, vb[3 * i + 2] = v[i].z;
  auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), idx.size() / 3));
  std::copy(idx.begin(), idx.end(), ib);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scn, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scn);
  return scn;
}

struct embree_terrain {
  RTCScene scn;
  std::vector<TreeRayHit> hits;
  explicit embree_terrain(terrain_scene const& t)
      : scn(embree_commit_triangles(t.vertices, t.indices)), hits(R) {
    cast_all(t, hits.data());
  }
  ~embree_terrain() { rtcReleaseScene(scn); }
  embree_terrain(embree_terrain const&) = delete;
  embree_terrain& operator=(embree_terrain const&) = delete;
  void cast_all(terrain_scene const& t, TreeRayHit* out) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (std::size_t i = 0; i < R; ++i) {
      RTCRayHit rh{};
      rh.ray.org_x = t.origin[i].x, rh.ray.org_y = t.origin[i].y, rh.ray.org_z = t.origin[i].z;
      rh.ray.dir_x = t.dir[i].x, rh.ray.dir_y = t.dir[i].y, rh.ray.dir_z = t.dir[i].z;
      rh.ray.tnear = 0, rh.ray.tfar = inf;
      rh.ray.mask = ~0u, rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scn, &ctx, &rh);
      TreeRayHit h;
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) h.proxy = rh.hit.primID, h.toi = rh.ray.tfar;
      out[i] = h;
    }
  }
};

embree_terrain const& terrain_embree() {
  static embree_terrain const e(terrain());
  return e;
}
#endif

template <class T, bool Blocks>
void register_terrain_rays() {
  std::string const name = std::string(Blocks ? "spatial_ray" : "spatial_ray_leaf1") +
                           "/terrain1m/plume/x" + std::to_string(plume::lanes_v<T>);
  benchmark::RegisterBenchmark(name.c_str(), [](benchmark::State& st) {
    terrain_scene const& t = terrain();
    plume::GWideBvh<T> const bvh =
        Blocks ? t.mesh.make_block_bvh<T>() : plume::GWideBvh<T>(t.mesh.tree());
    std::vector<TreeRayHit> hits(R);
    t.cast<Blocks>(bvh, hits.data());
    if (std::string const bad = mismatches(hits, t.reference); !bad.empty()) {
      st.SkipWithError(("hits differ from width 1: " + bad).c_str());
      return;
    }
#if PLUME_HAVE_EMBREE
    if (std::string const bad = mismatches(hits, terrain_embree().hits); !bad.empty()) {
      st.SkipWithError(("hits differ from Embree: " + bad).c_str());
      return;
    }
#endif
    plume::bench::run_items(st, std::int64_t(R), [&] {
      t.cast<Blocks>(bvh, hits.data());
      benchmark::DoNotOptimize(hits.data());
      benchmark::ClobberMemory();
    });
    st.counters["hit_fraction"] = double(hit_count(hits)) / double(R);
    st.counters["nodes"] = double(bvh.node_count());
  });
}

/// The terrain's heights as a HeightField, and R poses for the shape queries.
struct terrain_queries {
  plume::HeightField field;
  std::vector<plume::Iso3> above, resting, touching;
  std::vector<Vec3> motion;
  terrain_queries() {
    terrain_scene const& t = terrain();
    std::vector<float> h(t.vertices.size());
    for (std::size_t i = 0; i < h.size(); ++i)
      h[i] = t.vertices[i].y;
    auto r = plume::HeightField::build(terrain_side, terrain_side, h, 0.1f, 0.1f);
    if (!r.ok())
      throw std::logic_error(std::string("bench_spatial: height field: ") + to_string(r.error));
    field = std::move(r.field);
    std::mt19937 g(4712);
    std::uniform_real_distribution<float> u(0, 1);
    float const extent = float(terrain_side - 1) * 0.1f;
    for (std::size_t i = 0; i < R; ++i) {
      float const x = 1.0f + (extent - 2.0f) * u(g), z = 1.0f + (extent - 2.0f) * u(g);
      float const y = terrain_scene::height(x, z);
      plume::Quat const q =
          plume::Quat::from_axis_angle(Vec3{u(g), 1.0f, u(g)}.normalize(), 6.28f * u(g));
      above.push_back({q, {x, y + 2.0f, z}});
      motion.push_back({u(g) - 0.5f, -6.0f, u(g) - 0.5f});
      resting.push_back({q, {x, y + 0.5f - 0.01f, z}});
      touching.push_back({q, {x, y + (i % 2 ? 0.3f : 0.6f), z}});
    }
  }
};

terrain_queries const& terrain_query_scene() {
  static terrain_queries const q;
  return q;
}

/// Registers one terrain shape query on the mesh and on the height field; `run` answers query i
/// on the given TriangleSource and returns something to keep alive.
template <class Run>
void register_terrain_query(std::string const& kind, Run run) {
  auto const add = [&](std::string const& source, auto pick) {
    std::string const name = "spatial_" + kind + "/terrain1m/plume/" + source;
    benchmark::RegisterBenchmark(name.c_str(), [run, pick](benchmark::State& st) {
      terrain_queries const& q = terrain_query_scene();
      auto const& mesh = pick(q);
      float sink = 0.0f;
      plume::bench::run_items(st, std::int64_t(R), [&] {
        for (std::size_t i = 0; i < R; ++i)
          sink += run(mesh, q, i);
        benchmark::DoNotOptimize(sink);
      });
    });
  };
  add("mesh", [](terrain_queries const&) -> plume::TriangleMesh const& { return terrain().mesh; });
  add("heightfield", [](terrain_queries const& q) -> plume::HeightField const& { return q.field; });
}

void register_terrain_queries() {
  benchmark::RegisterBenchmark("spatial_ray/terrain1m/plume/heightfield", [](benchmark::State& st) {
    terrain_scene const& t = terrain();
    plume::HeightField const& f = terrain_query_scene().field;
    std::vector<TreeRayHit> hits(R);
    auto const cast = [&] {
      for (std::size_t i = 0; i < R; ++i) {
        plume::MeshRayHit const h = f.ray_cast(plume::Ray3{t.origin[i], t.dir[i]}, max_toi_all);
        TreeRayHit r;
        if (h.hit()) r.proxy = h.triangle, r.toi = h.toi;
        hits[i] = r;
      }
    };
    cast();
    if (std::string const bad = mismatches(hits, t.reference); !bad.empty()) {
      st.SkipWithError(("hits differ from the mesh's: " + bad).c_str());
      return;
    }
    plume::bench::run_items(st, std::int64_t(R), [&] {
      cast();
      benchmark::DoNotOptimize(hits.data());
      benchmark::ClobberMemory();
    });
  });
  register_terrain_query(
      "shape_cast", [](auto const& mesh, terrain_queries const& q, std::size_t i) {
        plume::ShapeCastConfig cfg;
        plume::MeshShapeHit const h = plume::mesh_shape_cast(
            mesh, plume::Iso3{}, plume::Capsule{0.5f, 0.3f}, q.above[i], q.motion[i], cfg);
        return h.toi < 2.0f ? h.toi : 0.0f;
      });
  register_terrain_query("overlap", [](auto const& mesh, terrain_queries const& q, std::size_t i) {
    return plume::mesh_intersects(mesh, plume::Iso3{}, plume::Cuboid{Vec3::splat(0.4f)},
                                  q.touching[i])
               ? 1.0f
               : 0.0f;
  });
  register_terrain_query("contacts", [](auto const& mesh, terrain_queries const& q, std::size_t i) {
    plume::MeshContacts const c =
        plume::mesh_contacts(mesh, plume::Iso3{}, plume::Cuboid{Vec3::splat(0.5f)}, q.resting[i]);
    return float(c.count);
  });
}

/// Builds a tree of `boxes` with `builder` per iteration; counters as at the top.
template <class CastAll>
void builder_benchmark(benchmark::State& st, std::vector<plume::Aabb3> const& boxes,
                       plume::TreeConfig const& cfg, CastAll cast_all) {
  AabbTree tree(cfg);
  plume::bench::run_items(st, std::int64_t(boxes.size()), [&] {
    tree.clear();
    std::vector<ProxyId> const ids = tree.insert_all(boxes);
    benchmark::DoNotOptimize(ids.data());
  });
  auto const stats = tree.stats();
  st.counters["height"] = double(stats.height);
  st.counters["area_ratio"] = double(stats.area_ratio);
  plume::WideBvh const bvh(tree);
  auto const t0 = std::chrono::steady_clock::now();
  int rounds = 0;
  double seconds = 0.0;
  while (rounds < 3 || seconds < 0.2) { // at least 0.2 s of rays
    cast_all(bvh);
    ++rounds;
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  st.counters["rays_per_second"] = double(R) * double(rounds) / seconds;
}

void register_builders() {
  for (plume::TreeBuilder const builder :
       {plume::TreeBuilder::binned_sah, plume::TreeBuilder::ploc}) {
    std::string const name = builder == plume::TreeBuilder::ploc ? "ploc" : "sah";
    plume::TreeConfig cfg;
    cfg.builder = builder;
    benchmark::RegisterBenchmark(("spatial_builder/spheres100k/" + name).c_str(),
                                 [cfg](benchmark::State& st) {
                                   sphere_scene const& s = spheres_scene();
                                   std::vector<plume::Aabb3> boxes;
                                   for (sphere const& k : s.spheres)
                                     boxes.push_back(plume::Aabb3::from_sphere(k.centre, k.radius));
                                   std::vector<TreeRayHit> hits(R);
                                   builder_benchmark(
                                       st, boxes, cfg, [&](plume::WideBvh const& bvh) {
                                         plume_bench_cast_spheres(bvh, s, hits.data());
                                       });
                                   // The work of a ray, free of the machine's noise.
                                   AabbTree tree(cfg);
                                   tree.insert_all(boxes);
                                   plume::WideBvh const bvh(tree);
                                   std::size_t visits = 0;
                                   for (std::size_t i = 0; i < R; ++i)
                                     visits += nodes_visited(bvh, s, i);
                                   st.counters["nodes_per_ray"] = double(visits) / double(R);
                                 })
        ->Unit(benchmark::kMillisecond);
    plume::TreeConfig tight = cfg;
    tight.margin = 0.0f;
    tight.margin_fraction = 0.0f;
    benchmark::RegisterBenchmark(
        ("spatial_builder/terrain1m/" + name).c_str(),
        [tight](benchmark::State& st) {
          terrain_scene const& t = terrain();
          std::vector<plume::Aabb3> boxes;
          for (plume::Triangle const& tri : t.mesh.triangles())
            boxes.push_back(tri.local_aabb());
          std::vector<TreeRayHit> hits(R);
          builder_benchmark(st, boxes, tight,
                            [&](plume::WideBvh const& bvh) { t.cast<false>(bvh, hits.data()); });
        })
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
  }
}

void register_terrain() {
  plume::bench::for_each_f32_width([]<class T>() { register_terrain_rays<T, true>(); });
  plume::bench::for_each_f32_width([]<class T>() { register_terrain_rays<T, false>(); });
  register_terrain_queries();
#if PLUME_HAVE_EMBREE
  benchmark::RegisterBenchmark("spatial_ray/terrain1m/embree/x1", [](benchmark::State& st) {
    terrain_scene const& t = terrain();
    embree_terrain const& e = terrain_embree();
    if (std::string const bad = mismatches(e.hits, t.reference); !bad.empty()) {
      st.SkipWithError(("Embree's hits differ from plume: " + bad).c_str());
      return;
    }
    std::vector<TreeRayHit> hits(R);
    plume::bench::run_items(st, std::int64_t(R), [&] {
      e.cast_all(t, hits.data());
      benchmark::DoNotOptimize(hits.data());
      benchmark::ClobberMemory();
    });
    st.counters["hit_fraction"] = double(hit_count(hits)) / double(R);
  });
#endif
  benchmark::RegisterBenchmark("spatial_build/terrain1m/plume/bvh",
                               [](benchmark::State& st) {
                                 terrain_scene const& t = terrain();
                                 std::size_t n = 0;
                                 plume::bench::run_items(
                                     st, std::int64_t(t.indices.size() / 3), [&] {
                                       auto r = plume::TriangleMesh::build(t.vertices, t.indices);
                                       n = r.triangles;
                                       benchmark::DoNotOptimize(r.mesh.bvh().node_count());
                                     });
                                 auto const stats = t.mesh.tree().stats();
                                 st.counters["height"] = double(stats.height);
                                 st.counters["area_ratio"] = double(stats.area_ratio);
                                 st.counters["triangles"] = double(n);
                               })
      ->Unit(benchmark::kMillisecond)
      ->Iterations(3);
#if PLUME_HAVE_EMBREE
  benchmark::RegisterBenchmark("spatial_build/terrain1m/embree", [](benchmark::State& st) {
    terrain_scene const& t = terrain();
    for (auto _ : st) {
      RTCScene const scn = embree_commit_triangles(t.vertices, t.indices);
      st.PauseTiming();
      rtcReleaseScene(scn);
      st.ResumeTiming();
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(t.indices.size() / 3));
  })->Unit(benchmark::kMillisecond);
#endif
}

// ------------------------------------------------------------------ the stress scene

/// xorshift32: cheap enough not to show in a frame's time.
struct xorshift {
  std::uint32_t s;
  float operator()() noexcept { // uniform in [-1, 1)
    s ^= s << 13, s ^= s >> 17, s ^= s << 5;
    return float(s >> 8) * (2.0f / 16777216.0f) - 1.0f;
  }
};

/// 10,000 boxes (half extents 0.2..0.35) on a 25 x 20 x 20 grid of spacing 1, each on a random
/// walk within 0.4 of its grid point: four in five slow (|v| <= 0.005 per axis and frame),
/// one in five fast (<= 0.04), so a frame moves a fifth to a quarter of the leaves out of
/// their fat boxes (margin 0.05).
struct stress_scene {
  static constexpr std::size_t n = 10000;
  std::vector<Vec3> home, pos, vel, half;
  std::vector<float> vmax;
  std::vector<ProxyId> ids;
  AabbTree tree;
  xorshift rng{12345};
  std::size_t frames = 0, moved = 0;

  stress_scene() {
    for (std::size_t i = 0; i < n; ++i) {
      Vec3 const h{float(i % 25), float(i / 25 % 20), float(i / 500)};
      home.push_back(h);
      pos.push_back(h);
      half.push_back(
          Vec3{0.275f + 0.075f * rng(), 0.275f + 0.075f * rng(), 0.275f + 0.075f * rng()});
      vmax.push_back(i % 5 == 0 ? 0.04f : 0.005f);
      vel.push_back(Vec3{rng(), rng(), rng()} * vmax.back());
      ids.push_back(tree.insert(box(i)));
      if (ids.back() != ProxyId(i)) throw std::logic_error("bench_spatial: proxy ids not 0..n-1");
    }
    tree.rebuild();
  }
  plume::Aabb3 box(std::size_t i) const {
    return plume::Aabb3::from_center_half_extents(pos[i], half[i]);
  }
  static float step(float& p, float& v, float home_p, float vm, float noise) {
    v = std::clamp(v + 0.25f * vm * noise, -vm, vm);
    if (std::fabs(p + v - home_p) > 0.4f) v = -v;
    return p += v;
  }
  /// Moves every box; returns how many left their fat boxes.
  std::size_t move_all() {
    std::size_t out = 0;
    for (std::size_t i = 0; i < n; ++i) {
      step(pos[i].x, vel[i].x, home[i].x, vmax[i], rng());
      step(pos[i].y, vel[i].y, home[i].y, vmax[i], rng());
      step(pos[i].z, vel[i].z, home[i].z, vmax[i], rng());
      out += tree.move(ids[i], box(i));
    }
    ++frames, moved += out;
    return out;
  }
};

void register_stress() {
  struct mode_name {
    TreeOptimization mode;
    char const* name;
  };
  for (mode_name const m : {mode_name{TreeOptimization::reinsert, "reinsert"},
                            mode_name{TreeOptimization::partial_rebuild, "partial_rebuild"},
                            mode_name{TreeOptimization::full_rebuild, "full_rebuild"},
                            mode_name{TreeOptimization::adaptive, "adaptive"}}) {
    std::string const name = std::string("spatial_tree/stress10k/") + m.name;
    benchmark::RegisterBenchmark(name.c_str(), [mode = m.mode](benchmark::State& st) {
      stress_scene s;
      for (int i = 0; i < 20; ++i) // past the first frames, where every box is still inside
        s.move_all(), s.tree.optimize(mode);
      s.frames = s.moved = 0;
      std::array<std::size_t, 3> picked{};
      plume::bench::run_items(st, std::int64_t(stress_scene::n), [&] {
        s.move_all();
        ++picked[std::size_t(s.tree.optimize(mode))];
      });
      auto const stats = s.tree.stats();
      st.counters["height"] = double(stats.height);
      st.counters["area_ratio"] = double(stats.area_ratio);
      st.counters["moved_fraction"] =
          double(s.moved) / (double(std::max<std::size_t>(s.frames, 1)) * double(stress_scene::n));
      AabbTree fresh = s.tree;
      fresh.rebuild();
      st.counters["rebuilt_area_ratio"] = double(fresh.stats().area_ratio);
      if (mode == TreeOptimization::adaptive) {
        double const f = double(std::max<std::size_t>(s.frames, 1));
        st.counters["frac_reinsert"] = double(picked[0]) / f;
        st.counters["frac_partial"] = double(picked[1]) / f;
        st.counters["frac_full"] = double(picked[2]) / f;
      }
    });
  }
}

/// The stress tree after 300 frames of reinsert updates, its rays (from a sphere of radius 40
/// around the grid's centre, aimed inside it) and their width-1 answers on a fresh rebuild.
struct updated_scene {
  stress_scene s;
  AabbTree fresh;
  std::vector<Vec3> origin, dir;
  std::vector<TreeRayHit> reference;
  updated_scene() {
    for (int i = 0; i < 300; ++i)
      s.move_all(), s.tree.optimize(TreeOptimization::reinsert);
    fresh = s.tree;
    fresh.rebuild();
    std::mt19937 g(99);
    std::uniform_real_distribution<float> u(-1, 1);
    Vec3 const c{12, 9.5f, 9.5f};
    for (std::size_t i = 0; i < R; ++i) {
      Vec3 const o = c + Vec3{u(g), u(g), u(g) + 0.01f}.normalize() * 40.0f;
      Vec3 const aim = c + Vec3{12 * u(g), 9.5f * u(g), 9.5f * u(g)};
      origin.push_back(o);
      dir.push_back((aim - o).normalize());
    }
    reference.resize(R);
    cast(plume::GWideBvh<float>(fresh), reference.data());
  }
  template <class T>
  void cast(plume::GWideBvh<T> const& bvh, TreeRayHit* out) const {
    for (std::size_t i = 0; i < R; ++i) {
      plume::Ray3 const ray{origin[i], dir[i]};
      out[i] = bvh.ray_cast(ray, max_toi_all, [&](ProxyId id, float max_toi) {
        return plume::ray_cast(s.box(id), ray, max_toi).toi;
      });
    }
  }
};

updated_scene const& stress_updated() {
  static updated_scene const u;
  return u;
}

template <class T>
void register_updated_rays() {
  std::string const name =
      "spatial_ray/stress10k_after_updates/plume/x" + std::to_string(plume::lanes_v<T>);
  benchmark::RegisterBenchmark(name.c_str(), [](benchmark::State& st) {
    updated_scene const& u = stress_updated();
    plume::GWideBvh<T> const updated(u.s.tree), fresh(u.fresh);
    std::vector<TreeRayHit> hits(R), hits_fresh(R);
    u.cast(updated, hits.data());
    u.cast(fresh, hits_fresh.data());
    if (!mismatches(hits, u.reference).empty() || !mismatches(hits_fresh, u.reference).empty()) {
      st.SkipWithError("hits differ between widths or between the updated and rebuilt trees");
      return;
    }
    plume::bench::run_items(st, std::int64_t(R), [&] {
      u.cast(updated, hits.data());
      benchmark::DoNotOptimize(hits.data());
      benchmark::ClobberMemory();
    });
    // The same rays on the fresh rebuild, timed here (best of 5 passes each) for the ratio.
    auto const best_time = [&](plume::GWideBvh<T> const& bvh) {
      double best = inf;
      for (int k = 0; k < 5; ++k) {
        auto const t0 = std::chrono::steady_clock::now();
        u.cast(bvh, hits.data());
        benchmark::DoNotOptimize(hits.data());
        best = std::min(
            best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      return best;
    };
    double const t_updated = best_time(updated), t_fresh = best_time(fresh);
    st.counters["rebuilt_speedup"] = t_updated / t_fresh; // > 1: the rebuild casts faster
    st.counters["area_ratio"] = double(u.s.tree.stats().area_ratio);
    st.counters["rebuilt_area_ratio"] = double(u.fresh.stats().area_ratio);
    st.counters["hit_fraction"] = double(hit_count(hits)) / double(R);
  });
}

} // namespace

int main(int argc, char** argv) {
  plume::bench::for_each_f32_width([]<class T>() { register_sphere_rays<T>(); });
#if PLUME_HAVE_EMBREE
  register_embree_rays();
#endif
  register_builds();
  register_terrain();
  register_builders();
  register_stress();
  plume::bench::for_each_f32_width([]<class T>() { register_updated_rays<T>(); });
  return plume::bench::run_benchmarks(argc, argv);
}
