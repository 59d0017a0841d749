// TriangleMesh: every query against brute force over the same triangles as separate
// GTriangle shapes (random soups and a grid terrain, at every node width), bad input and its
// errors, degenerate triangles, adjacency and edge convexity on known shapes, determinism.
#include "../common/types.hpp"
#include "mesh_support.hpp"

#include <plume/collision/ray_cast.hpp>
#include <plume/collision/shapes.hpp>
#include <plume/spatial/triangle_mesh.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

using namespace plume;
using namespace plume::test;

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

/// Least (toi, index) over every triangle as a separate shape.
MeshRayHit brute_ray(TriangleMesh const& m, Ray3 const& ray, float max_toi) {
  MeshRayHit best;
  for (std::uint32_t t = 0; t < m.triangle_count(); ++t) {
    RayHit const h = ray_cast_local(m.triangle(t), ray, max_toi);
    if (h.hit && h.toi < best.toi) {
      best.triangle = t;
      best.toi = h.toi;
      best.normal = h.normal;
      best.back = h.feature == 1.0f;
    }
  }
  return best;
}

void check_same(MeshRayHit const& got, MeshRayHit const& want) {
  INFO("got " << got.triangle << " at " << got.toi << ", want " << want.triangle << " at "
              << want.toi);
  REQUIRE(got.triangle == want.triangle);
  REQUIRE(same_bits(got.toi, want.toi));
  REQUIRE(same_bits(got.normal, want.normal));
  REQUIRE(got.back == want.back);
}

std::vector<Ray3> random_rays(std::uint32_t seed, std::size_t n, float spread) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<Ray3> rays;
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 const o{spread * u(g), spread * u(g), spread * u(g)};
    Vec3 const aim{0.5f * spread * u(g), 0.5f * spread * u(g), 0.5f * spread * u(g)};
    Vec3 d = aim - o;
    if (i % 3 == 0) d = d * 3.7f; // not unit
    rays.push_back({o, d});
  }
  return rays;
}

/// Double-precision closest point of a triangle (the oracle's distance).
double closest_distance_double(Triangle const& t, Vec3 const& p) {
  struct D {
    double x, y, z;
    D operator-(D o) const { return {x - o.x, y - o.y, z - o.z}; }
    D operator+(D o) const { return {x + o.x, y + o.y, z + o.z}; }
    D operator*(double s) const { return {x * s, y * s, z * s}; }
    double dot(D o) const { return x * o.x + y * o.y + z * o.z; }
  };
  auto const d = [](Vec3 const& v) { return D{v.x, v.y, v.z}; };
  D const a = d(t.a), b = d(t.b), c = d(t.c), q = d(p);
  D const ab = b - a, ac = c - a, ap = q - a;
  double const d1 = ab.dot(ap), d2 = ac.dot(ap);
  D r{};
  D const bp = q - b, cp = q - c;
  double const d3 = ab.dot(bp), d4 = ac.dot(bp), d5 = ab.dot(cp), d6 = ac.dot(cp);
  double const vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  if (d1 <= 0 && d2 <= 0)
    r = a;
  else if (d3 >= 0 && d4 <= d3)
    r = b;
  else if (vc <= 0 && d1 >= 0 && d3 <= 0)
    r = a + ab * (d1 / (d1 - d3));
  else if (d6 >= 0 && d5 <= d6)
    r = c;
  else if (vb <= 0 && d2 >= 0 && d6 <= 0)
    r = a + ac * (d2 / (d2 - d6));
  else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    r = b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  else
    r = a + ab * (vb / (va + vb + vc)) + ac * (vc / (va + vb + vc));
  D const e = q - r;
  return std::sqrt(e.dot(e));
}

template <class F>
void for_each_bvh(TriangleMesh const& m, F&& f) {
  f(m.bvh());
  f(GWideBvh<float, 2>(m.tree()));
  f(GWideBvh<float, 4>(m.tree()));
  plume::for_each_type<test::f32_types>([&]<class T>() { f(GWideBvh<T>(m.tree())); });
}

/// f(block bvh) for the mesh's own ray tree and copies of it at other widths.
template <class F>
void for_each_block_bvh(TriangleMesh const& m, F&& f) {
  f(m.block_bvh());
  f(m.make_block_bvh<float, 2>());
  f(m.make_block_bvh<float, 4>());
  plume::for_each_type<test::f32_types>([&]<class T>() { f(m.make_block_bvh<T>()); });
}

/// f.template operator()<U>() for float and every f32 width that reads the mesh's own trees
/// and blocks (lanes dividing WideBvh::arity and triangle_block_size).
template <class F>
void for_each_reader(F&& f) {
  f.template operator()<float>();
  plume::for_each_type<f32_widths>([&]<class U>() {
    if constexpr (WideBvh::arity % lanes_v<U> == 0 && triangle_block_size % lanes_v<U> == 0)
      f.template operator()<U>();
  });
}

} // namespace

TEST_CASE("mesh ray blocks hold every triangle once, lanes filled by repeats", "[mesh][ray]") {
  soup const s = GENERATE(as<soup>{}, random_soup(1, 400, 1.5f), grid(24, 0.5f, terrain_height),
                          random_soup(3, 1, 1.0f), random_soup(4, 9, 1.0f));
  TriangleMesh const m = make(s);
  auto const blocks = m.blocks();
  REQUIRE(m.block_bvh().leaf_count() == blocks.size());
  std::vector<int> seen(m.triangle_count(), 0);
  std::size_t full = 0;
  for (detail::TriangleBlock const& b : blocks) {
    std::size_t const count = b.count();
    REQUIRE(count >= 1);
    REQUIRE(count <= triangle_block_size);
    full += count == triangle_block_size;
    for (std::size_t l = 0; l < triangle_block_size; ++l) {
      std::uint32_t const t = b.tri[l];
      REQUIRE(t < m.triangle_count());
      if (l < count)
        ++seen[t];
      else
        CHECK(t == b.tri[0]); // a repeat of lane 0
      Triangle const& tri = m.triangle(t);
      CHECK(std::bit_cast<std::array<float, 9>>(tri) ==
            std::array<float, 9>{b.ax[l], b.ay[l], b.az[l], b.bx[l], b.by[l], b.bz[l], b.cx[l],
                                 b.cy[l], b.cz[l]});
    }
  }
  CHECK(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; }));
  // Each block is a whole subtree of the tree, so blocks are fuller than one triangle.
  if (m.triangle_count() >= 2 * triangle_block_size) CHECK(full > 0);
  CHECK(blocks.size() <= m.triangle_count());
}

TEST_CASE("mesh ray casts through blocks break ties to the lower triangle", "[mesh][ray]") {
  // Six coplanar triangles over one spot, each shifted 0.1 further to -x: the tree orders
  // them by centre, so the block's first lane holds the highest index and the tie (every toi
  // is 1) must go to triangle 0 against the order of the lanes.
  soup s;
  for (std::uint32_t t = 0; t < 6; ++t) {
    float const x = -0.1f * float(t);
    s.v.insert(s.v.end(), {{x, 0, 0}, {x, 0, 2}, {x + 2, 0, 0}});
    s.i.insert(s.i.end(), {3 * t, 3 * t + 1, 3 * t + 2});
  }
  TriangleMesh const m = make(s);
  REQUIRE(m.blocks().size() == 1);
  REQUIRE(m.blocks()[0].tri[0] != 0); // the lanes are not in index order
  for (float x = 0.05f; x < 1.0f; x += 0.1f)
    for (float z = 0.05f; z < 0.5f; z += 0.1f) {
      Ray3 const r{{x, 1, z}, {0, -1, 0}};
      MeshRayHit const want = brute_ray(m, r, inf);
      REQUIRE(want.triangle == 0);
      for_each_block_bvh(
          m, [&](auto const& bvh) { check_same(m.ray_cast_blocks_with(bvh, r, inf), want); });
    }
  // A tree that is not the block tree is refused, not read past the blocks.
  CHECK_THROWS_AS(m.ray_cast_blocks_with(m.bvh(), Ray3{{0.5f, 1, 0.2f}, {0, -1, 0}}, inf),
                  std::invalid_argument);
}

TEST_CASE("mesh ray casts through blocks with tied, signed-zero and subnormal directions",
          "[mesh][ray]") {
  // The block test sets up the ray's axes once (largest |d| first on ties, -0 not negative);
  // each lane must be the per-triangle cast's arithmetic.
  TriangleMesh const m =
      make(GENERATE(as<soup>{}, random_soup(11, 300, 2.0f), grid(16, 0.5f, terrain_height)));
  float const sub = 1e-40f;
  Vec3 const dirs[] = {{1, 1, 0.5f},   {-1, 1, 0.2f},   {1, -1, -1},         {-0.0f, -1, 0},
                       {0, -1, -0.0f}, {0.5f, -1, 1},   {1, 1, 1},           {-1, -1, -1},
                       {sub, -1, 0},   {-sub, -1, sub}, {0.3f, -0.3f, 0.3f}, {-2, 0.5f, 2}};
  std::size_t hits = 0;
  for (std::uint32_t t = 0; t < m.triangle_count(); t += 3) {
    Triangle const& tri = m.triangle(t);
    Vec3 const c = (tri.a + tri.b + tri.c) * (1.0f / 3.0f);
    for (Vec3 const& d : dirs) {
      Ray3 const r{c - d * 20.0f, d};
      MeshRayHit const want = brute_ray(m, r, inf);
      hits += want.hit();
      for_each_block_bvh(
          m, [&](auto const& bvh) { check_same(m.ray_cast_blocks_with(bvh, r, inf), want); });
    }
  }
  CHECK(hits > 0);
}

TEST_CASE("mesh ray casts equal brute force over separate triangles", "[mesh][ray]") {
  soup const s = GENERATE(as<soup>{}, random_soup(1, 400, 1.5f), random_soup(2, 60, 6.0f),
                          grid(24, 0.5f, terrain_height));
  TriangleMesh const m = make(s);
  // A third of the rays in the -O0 sanitizer build (the full set took 45 s there).
  std::size_t const n = PLUME_TEST_UNOPTIMISED ? 200 : 600;
  std::vector<Ray3> rays = random_rays(7, n, 14.0f);
  for (Ray3 const& r : random_rays(8, n / 6, 14.0f)) // grazing along a face direction
    rays.push_back({r.origin, Vec3{r.dir.x, 0.02f * r.dir.y, r.dir.z}});
  std::size_t hits = 0;
  for (float const max_toi : {inf, std::numeric_limits<float>::max(), 0.8f}) {
    for (Ray3 const& r : rays) {
      MeshRayHit const want = brute_ray(m, r, max_toi);
      hits += want.hit();
      for_each_bvh(m, [&](auto const& bvh) { check_same(m.ray_cast_with(bvh, r, max_toi), want); });
      for_each_block_bvh(
          m, [&](auto const& bvh) { check_same(m.ray_cast_blocks_with(bvh, r, max_toi), want); });
      check_same(m.ray_cast(r, max_toi), want);
      // The mesh's own trees read at every width that divides them (a dispatch build's sets).
      for_each_reader([&]<class U>() { check_same(m.ray_cast<U>(r, max_toi), want); });
    }
  }
  CHECK(hits > rays.size() / 4); // the rays do meet the mesh
}

TEST_CASE("mesh ray casts through grid vertices and edges hit exactly once", "[mesh][ray]") {
  soup const s = grid(8, 1.0f, [](float, float) { return 0.0f; });
  TriangleMesh const m = make(s);
  for (float x = 0.5f; x <= 7.5f; x += 0.5f)
    for (float z = 0.5f; z <= 7.5f; z += 0.5f)
      for (Vec3 const d : {Vec3{0, -1, 0}, Vec3{0.3f, -1, 0.3f}, Vec3{0, 1, 0}}) {
        Ray3 const r{Vec3{x, 0, z} - d * 2.0f, d};
        int count = 0;
        for (std::uint32_t t = 0; t < m.triangle_count(); ++t)
          count += bool(ray_cast_local(m.triangle(t), r, inf).hit);
        REQUIRE(count == 1);
        MeshRayHit const h = m.ray_cast(r, inf);
        REQUIRE(h.hit());
        CHECK(h.toi == Approx(2.0f).margin(1e-6));
        CHECK(h.normal.dot(d) < 0.0f); // facing the ray
        CHECK(h.back == (d.y > 0.0f)); // from below: the back face
      }
}

TEST_CASE("mesh ray casts with a pose equal the posed triangle casts", "[mesh][ray]") {
  TriangleMesh const m = make(random_soup(3, 200, 2.0f));
  Iso3 const pose{Quat::from_axis_angle(Vec3{1, 2, 3}.normalize(), 0.8f), Vec3{3, -1, 2}};
  for (Ray3 const& r : random_rays(9, 300, 14.0f)) {
    MeshRayHit want;
    for (std::uint32_t t = 0; t < m.triangle_count(); ++t) {
      RayHit const h = plume::ray_cast(m.triangle(t), pose, r, inf);
      if (h.hit && h.toi < want.toi) want = {t, h.toi, h.normal, h.feature == 1.0f};
    }
    check_same(m.ray_cast(pose, r, inf), want);
    for_each_reader([&]<class U>() { check_same(m.ray_cast<U>(pose, r, inf), want); });
  }
}

TEST_CASE("mesh ray casts reject unusable rays", "[mesh][ray]") {
  TriangleMesh const m = make(grid(4, 1.0f, [](float, float) { return 0.0f; }));
  float const nan = std::numeric_limits<float>::quiet_NaN();
  Ray3 const down{{1.2f, 1, 1.7f}, {0, -1, 0}};
  REQUIRE(m.ray_cast(down, inf).hit());
  CHECK(!m.ray_cast(down, -1.0f).hit());
  CHECK(!m.ray_cast(down, nan).hit());
  CHECK(!m.ray_cast(down, 0.5f).hit());
  CHECK(m.ray_cast(down, 1.0f).hit()); // max_toi inclusive
  CHECK(!m.ray_cast({{1.2f, 1, 1.7f}, {0, 0, 0}}, inf).hit());
  CHECK(!m.ray_cast({{nan, 1, 1.7f}, {0, -1, 0}}, inf).hit());
  CHECK(!m.ray_cast({{1.2f, 1, 1.7f}, {0, -inf, 0}}, inf).hit());
  CHECK(!m.ray_cast({{1.2f, 1, 1.7f}, {0, 1, 0}}, inf).hit()); // away
  CHECK(!TriangleMesh{}.ray_cast(down, inf).hit());
}

TEST_CASE("mesh box queries equal brute force", "[mesh][aabb]") {
  soup const s = GENERATE(as<soup>{}, random_soup(4, 500, 1.0f), grid(20, 0.5f, terrain_height));
  TriangleMesh const m = make(s);
  std::mt19937 g(11);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int q = 0; q < 200; ++q) {
    Vec3 const c{10 * u(g), 2 * u(g), 10 * u(g)};
    Vec3 const h = Vec3{u(g) + 1, u(g) + 1, u(g) + 1} * (q % 2 ? 0.3f : 2.0f);
    Aabb3 const box = Aabb3::from_center_half_extents(c, h);
    std::vector<std::uint32_t> got, want;
    m.query_aabb(box, [&](std::uint32_t t) { got.push_back(t); });
    for (std::uint32_t t = 0; t < m.triangle_count(); ++t)
      if (m.triangle(t).local_aabb().intersects(box)) want.push_back(t);
    std::sort(got.begin(), got.end());
    REQUIRE(got == want);
  }
  // Stopping early, and touching boxes.
  std::size_t calls = 0;
  m.query_aabb(m.local_aabb(), [&](std::uint32_t) { return ++calls < 3; });
  CHECK(calls == 3);
  Aabb3 const b0 = m.triangle(0).local_aabb();
  bool met = false;
  m.query_aabb(Aabb3{b0.max, b0.max + Vec3{1, 1, 1}}, [&](std::uint32_t t) { met |= t == 0; });
  CHECK(met);
  calls = 0;
  float const nan = std::numeric_limits<float>::quiet_NaN();
  m.query_aabb(Aabb3{{nan, 0, 0}, {1, 1, 1}}, [&](std::uint32_t) { ++calls; });
  CHECK(calls == 0);
}

TEST_CASE("mesh closest points equal brute force", "[mesh][closest]") {
  soup const s = GENERATE(as<soup>{}, random_soup(5, 300, 1.0f), grid(20, 0.5f, terrain_height));
  TriangleMesh const m = make(s);
  std::mt19937 g(13);
  std::uniform_real_distribution<float> u(-1, 1);
  Iso3 const pose{Quat::from_axis_angle(Vec3{0, 1, 1}.normalize(), -0.6f), Vec3{-2, 1, 4}};
  for (int q = 0; q < 300; ++q) {
    Vec3 const p{12 * u(g), 3 * u(g), 12 * u(g)};
    float const maxd = q % 3 == 0 ? inf : 1.5f;
    MeshClosestPoint want;
    float want_d2 = maxd == inf ? inf : maxd * maxd;
    double oracle = inf;
    for (std::uint32_t t = 0; t < m.triangle_count(); ++t) {
      Vec3 const c = closest_point_on_triangle(m.triangle(t), p);
      float const d2 = (p - c).length_squared();
      if (d2 < want_d2 || (d2 == want_d2 && !want.found()))
        want_d2 = d2, want.triangle = t, want.point = c;
      oracle = std::min(oracle, closest_distance_double(m.triangle(t), p));
    }
    MeshClosestPoint const got = m.closest_point(p, maxd);
    INFO("query " << q);
    REQUIRE(got.triangle == want.triangle);
    if (!want.found()) {
      CHECK(oracle > double(maxd) - 1e-5);
      continue;
    }
    REQUIRE(same_bits(got.point, want.point));
    REQUIRE(got.distance == Approx(oracle).margin(1e-5));
    // Posed: the query point in world space.
    MeshClosestPoint const gp = m.closest_point(pose, pose.transform_point(p), maxd);
    if (gp.found()) {
      CHECK(gp.distance == Approx(oracle).margin(1e-4));
      CHECK(pose.inverse_transform_point(gp.point).distance(want.point) < 1e-3f);
    }
  }
  float const nan = std::numeric_limits<float>::quiet_NaN();
  CHECK(!m.closest_point(Vec3{nan, 0, 0}, inf).found());
  CHECK(!m.closest_point(Vec3{0, 0, 0}, -1.0f).found());
  CHECK(!m.closest_point(Vec3{0, 0, 0}, nan).found());
  CHECK(!TriangleMesh{}.closest_point(Vec3{0, 0, 0}, inf).found());
}

TEST_CASE("mesh build rejects bad input with its error", "[mesh][build]") {
  std::vector<Vec3> const v{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  using I = std::vector<std::uint32_t>;
  auto const err = [&](std::vector<Vec3> const& vs, I const& is) {
    return TriangleMesh::build(vs, is);
  };
  CHECK(err({}, I{0, 1, 2}).error == MeshError::empty);
  CHECK(err(v, I{}).error == MeshError::empty);
  CHECK(err(v, I{0, 1, 2, 3}).error == MeshError::index_count_not_multiple_of_3);
  auto const oob = err(v, I{0, 1, 2, 1, 3, 4});
  CHECK(oob.error == MeshError::index_out_of_range);
  CHECK(oob.bad_item == 5);
  CHECK(oob.mesh.empty());
  for (float const bad : {std::numeric_limits<float>::quiet_NaN(), inf, -inf}) {
    for (std::size_t at : {std::size_t(2), v.size() - 1}) {
      std::vector<Vec3> w = v;
      w[at].y = bad;
      auto const r = err(w, I{0, 1, 2});
      CHECK(r.error == MeshError::non_finite_vertex); // even if no triangle uses it
      CHECK(r.bad_item == at);
    }
  }
  auto const all = err(v, I{0, 0, 1, 0, 1, 1});
  CHECK(all.error == MeshError::all_degenerate);
  CHECK(all.degenerate == 2);
  CHECK(all.mesh.empty());
  auto const ok = err(v, I{0, 1, 2});
  CHECK(ok.ok());
  CHECK(std::string(to_string(MeshError::index_out_of_range)) == "index out of range");
}

TEST_CASE("mesh ray casts find a hit exactly at a corner", "[mesh][ray][fuzz]") {
  // The ray reaches x = 0, y = -1, z = 0 (the corner of triangle 0 and its box) at t = 2
  // exactly; the box's x exit, (0 - o.x) * (1 / d.x), rounded to just below 2 and the tree
  // skipped a triangle the triangle test hits (a fuzz finding, triangle_mesh
  // regress-mesh-ray-corner-miss). Exits are now computed conservatively.
  std::vector<Vec3> const v{{0, -1, 0}, {0, -1, 1}, {1, -1, 0}, {1, -1, 1}};
  std::vector<std::uint32_t> const i{0, 1, 2, 2, 1, 3};
  auto const built = TriangleMesh::build(v, i);
  REQUIRE(built.ok());
  Ray3 const ray{{0x1.595cd8p+3f, -12, -12}, {-0x1.595cd8p+2f, 5.5f, 6}};
  RayHit const direct = ray_cast_local(Triangle{v[0], v[1], v[2]}, ray, 1e30f);
  REQUIRE(direct.hit);
  MeshRayHit const h = built.mesh.ray_cast(ray, std::numeric_limits<float>::infinity());
  REQUIRE(h.hit());
  CHECK(h.toi == direct.toi);
  CHECK(built.mesh.source_triangle(h.triangle) == 0);
}

TEST_CASE("mesh ray casts report the back face by the face normal beside a vertex 3e12 away",
          "[mesh][ray][fuzz]") {
  // A sliver with one vertex 3.3e12 away: the float cross product (b - a) x (c - a) cancels
  // (its z, a difference of two products near 4.8e23, came out 0), so the triangle cast's
  // normal was (0.999, -0.044, 0), 100 degrees off the face normal (-0.215, 0.009, 0.977),
  // and a ray hitting the front face (face normal . dir = -21 with |dir| = 42.6) was reported
  // back (a fuzz finding, triangle_mesh back-face-flag). Such lanes take the normal in double.
  Vec3 const a{0x1.0f285ap+37f, 0x1.81bdb8p+41f, -0x1.aea93p+2f}, b{-2, -1, 0},
      c{0x1.589fd8p+2f, -0x1.3c7abep+2f, 0x1.aa9bap+0f};
  std::vector<Vec3> const v{a, b, c};
  std::vector<std::uint32_t> const i{0, 1, 2};
  auto const built = TriangleMesh::build(v, i);
  REQUIRE(built.ok());
  TriangleMesh const& m = built.mesh;
  Ray3 const ray{{0x1.4b5448p+2f, 0x1.d07adp+2f, 0x1.5a5a6p+2f},
                 {-0x1.d78bc2p+4f, -0x1.99ba84p+3f, -0x1.beaac8p+4f}};
  float const max_toi = 29.0556183f;
  Vec3 const n = m.face_normal(0);
  REQUIRE(n.dot(ray.dir) < -0.4f * ray.dir.length()); // clearly the front face
  RayHit const direct = ray_cast_local(Triangle{a, b, c}, ray, max_toi);
  REQUIRE(direct.hit);
  CHECK(direct.feature == 0.0f); // front
  CHECK(same_bits(direct.normal, n));
  MeshRayHit const h = m.ray_cast(ray, max_toi);
  REQUIRE(h.hit());
  CHECK_FALSE(h.back);
  CHECK(same_bits(h.normal, n));
  CHECK(h.toi == direct.toi);
  for_each_block_bvh(m, [&](auto const& bvh) {
    MeshRayHit const w = m.ray_cast_blocks_with(bvh, ray, max_toi);
    CHECK_FALSE(w.back);
    CHECK(same_bits(w.normal, n));
  });
  // From behind: the back face and the reversed normal.
  Ray3 const behind{ray.origin + ray.dir * (2.0f * direct.toi), -ray.dir};
  MeshRayHit const hb = m.ray_cast(behind, inf);
  REQUIRE(hb.hit());
  CHECK(hb.back);
  CHECK(same_bits(hb.normal, -n));
}

TEST_CASE("mesh build drops and counts degenerate triangles", "[mesh][build]") {
  // Triangles: good, repeated vertex, collinear, good, tiny (|cross|^2 = 1e-24) but not degenerate.
  std::vector<Vec3> const v{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {1, 1, 0}, {0, 0, 1e-12f}};
  std::vector<std::uint32_t> const i{0, 1, 2, 0, 0, 1, 0, 1, 3, 1, 4, 2, 0, 1, 5};
  auto const r = TriangleMesh::build(v, i);
  REQUIRE(r.ok());
  CHECK(r.input_triangles == 5);
  CHECK(r.degenerate == 2);
  CHECK(r.triangles == 3);
  TriangleMesh const& m = r.mesh;
  REQUIRE(m.triangle_count() == 3);
  CHECK(m.source_triangle(0) == 0);
  CHECK(m.source_triangle(1) == 3);
  CHECK(m.source_triangle(2) == 4);
  CHECK(m.triangle_indices(1) == std::array<std::uint32_t, 3>{1, 4, 2});
  CHECK(m.face_normal(0).distance(Vec3{0, 0, 1}) < 1e-6f);
  // Rays at the dropped triangles' places hit nothing there; the kept ones are found.
  MeshRayHit const h = m.ray_cast({{0.9f, 0.6f, 1}, {0, 0, -1}}, inf);
  REQUIRE(h.hit());
  CHECK(h.triangle == 1);
}

namespace {
/// The unit cube's 12 triangles, wound outward.
soup cube() {
  soup s;
  for (int k = 0; k < 8; ++k)
    s.v.push_back({float(k & 1), float(k >> 1 & 1), float(k >> 2 & 1)});
  std::uint32_t const quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  Vec3 const centre{0.5f, 0.5f, 0.5f};
  for (auto const& q : quads)
    for (auto tri : {std::array<std::uint32_t, 3>{q[0], q[1], q[2]}, {q[0], q[2], q[3]}}) {
      Triangle const t{s.v[tri[0]], s.v[tri[1]], s.v[tri[2]]};
      if (t.scaled_normal().dot(t.a - centre) < 0) std::swap(tri[1], tri[2]);
      s.i.insert(s.i.end(), tri.begin(), tri.end());
    }
  return s;
}

std::size_t count_kind(TriangleMesh const& m, EdgeKind k) {
  std::size_t n = 0;
  for (std::uint32_t t = 0; t < m.triangle_count(); ++t)
    for (EdgeKind e : m.edges(t).kind)
      n += e == k;
  return n;
}

void check_neighbours_symmetric(TriangleMesh const& m) {
  for (std::uint32_t t = 0; t < m.triangle_count(); ++t)
    for (int e = 0; e < 3; ++e) {
      std::uint32_t const u = m.edges(t).neighbour[std::size_t(e)];
      if (u == no_triangle) continue;
      auto const& ne = m.edges(u).neighbour;
      REQUIRE(std::count(ne.begin(), ne.end(), t) == 1);
      // They share the edge's two vertices.
      auto const& a = m.triangle_indices(t);
      auto const& b = m.triangle_indices(u);
      std::uint32_t const p = a[std::size_t(e)], q = a[std::size_t(e + 1) % 3];
      REQUIRE(std::count(b.begin(), b.end(), p) == 1);
      REQUIRE(std::count(b.begin(), b.end(), q) == 1);
    }
}
} // namespace

TEST_CASE("mesh edges: a cube is all convex, its diagonals flat", "[mesh][edges]") {
  TriangleMesh const m = make(cube());
  check_neighbours_symmetric(m);
  // 18 edges: 12 cube edges (convex) and 6 face diagonals (flat), each seen from two sides.
  CHECK(count_kind(m, EdgeKind::convex) == 24);
  CHECK(count_kind(m, EdgeKind::flat) == 12);
  CHECK(count_kind(m, EdgeKind::boundary) == 0);
  for (std::uint32_t t = 0; t < m.triangle_count(); ++t)
    for (std::uint32_t u : m.edges(t).neighbour)
      CHECK(u != no_triangle);
}

TEST_CASE("mesh edges: a flat grid is flat inside, boundary outside", "[mesh][edges]") {
  std::uint32_t const n = 6;
  TriangleMesh const m = make(grid(n, 0.7f, [](float, float) { return 0.0f; }));
  check_neighbours_symmetric(m);
  CHECK(count_kind(m, EdgeKind::boundary) == 4 * n);
  CHECK(count_kind(m, EdgeKind::flat) == 3 * 2 * n * n - 4 * n);
  CHECK(count_kind(m, EdgeKind::convex) + count_kind(m, EdgeKind::concave) == 0);
}

TEST_CASE("mesh edges: a valley is concave, a ridge convex", "[mesh][edges]") {
  for (float const lift : {0.5f, -0.5f, 0.01f, 0.0001f}) {
    // Two triangles sharing the edge (0,0,0)-(0,0,1); outer vertices at x = -1 and x = +1,
    // raised by lift (a valley for lift > 0, facing +y).
    std::vector<Vec3> const v{{0, 0, 0}, {0, 0, 1}, {-1, lift, 0}, {1, lift, 0}};
    std::vector<std::uint32_t> const i{0, 2, 1, 0, 1, 3};
    auto const r = TriangleMesh::build(v, i);
    REQUIRE(r.ok());
    TriangleMesh const& m = r.mesh;
    REQUIRE(m.face_normal(0).y > 0);
    REQUIRE(m.face_normal(1).y > 0);
    EdgeKind const want = lift == 0.0001f ? EdgeKind::flat
                          : lift > 0      ? EdgeKind::concave
                                          : EdgeKind::convex;
    INFO("lift " << lift);
    CHECK(m.edges(0).kind[2] == want); // edge 1 -> 0 of triangle 0
    CHECK(m.edges(0).neighbour[2] == 1);
    CHECK(m.edges(1).kind[0] == want); // edge 0 -> 1 of triangle 1
    CHECK(m.edges(1).neighbour[0] == 0);
    CHECK(count_kind(m, EdgeKind::boundary) == 4);
  }
  // Inconsistent winding and three triangles on one edge: non-manifold, no neighbour.
  std::vector<Vec3> const v{{0, 0, 0}, {0, 0, 1}, {-1, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  auto const same_dir = TriangleMesh::build(v, std::vector<std::uint32_t>{0, 2, 1, 0, 3, 1});
  REQUIRE(same_dir.ok());
  CHECK(same_dir.mesh.edges(0).kind[2] == EdgeKind::non_manifold);
  CHECK(same_dir.mesh.edges(0).neighbour[2] == no_triangle);
  auto const fin = TriangleMesh::build(v, std::vector<std::uint32_t>{0, 2, 1, 0, 1, 3, 0, 1, 4});
  REQUIRE(fin.ok());
  CHECK(count_kind(fin.mesh, EdgeKind::non_manifold) == 3);
  CHECK(fin.mesh.edges(1).neighbour[0] == no_triangle);
}

TEST_CASE("mesh build and queries are deterministic", "[mesh][determinism]") {
  soup const s = random_soup(6, 500, 1.0f);
  TriangleMesh const a = make(s), b = make(s);
  auto const na = a.tree().nodes(), nb = b.tree().nodes();
  REQUIRE(na.size() == nb.size());
  for (std::size_t k = 0; k < na.size(); ++k) {
    REQUIRE(same_bits(na[k].box.min, nb[k].box.min));
    REQUIRE(same_bits(na[k].box.max, nb[k].box.max));
    REQUIRE(na[k].left == nb[k].left);
    REQUIRE(na[k].proxy == nb[k].proxy);
  }
  REQUIRE(a.bvh().node_count() == b.bvh().node_count());
  for (std::uint32_t t = 0; t < a.triangle_count(); ++t) {
    REQUIRE(a.edges(t).neighbour == b.edges(t).neighbour);
    REQUIRE(a.edges(t).kind == b.edges(t).kind);
  }
  for (Ray3 const& r : random_rays(10, 200, 14.0f))
    check_same(a.ray_cast(r, inf), b.ray_cast(r, inf));
}
