// HeightField: every query equal, bit for bit, to a TriangleMesh built from the same
// vertices and the documented indices (triangles, normals, edge kinds, rays, boxes, closest
// points, contacts and shape casts); build errors; bad query input.
#include "mesh_support.hpp"

#include <plume/spatial/height_field.hpp>
#include <plume/spatial/mesh_queries.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

using namespace plume;
using namespace plume::test;

namespace {

/// The triangles a box query visits, sorted.
template <class Mesh>
std::vector<std::uint32_t> boxed(Mesh const& mesh, Aabb3 const& box) {
  std::vector<std::uint32_t> out;
  mesh.query_aabb(box, [&](std::uint32_t t) { out.push_back(t); });
  std::sort(out.begin(), out.end());
  return out;
}

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float qnan = std::numeric_limits<float>::quiet_NaN();

HeightField field_of(std::uint32_t nx, std::uint32_t nz, float sx, float sz) {
  std::vector<float> h(std::size_t(nx) * nz);
  for (std::uint32_t z = 0; z < nz; ++z)
    for (std::uint32_t x = 0; x < nx; ++x)
      h[z * nx + x] = terrain_height(float(x) * sx, float(z) * sz);
  // A flat patch (coplanar cells: flat edges) and a spike (convex and concave edges).
  for (std::uint32_t z = 2; z < 6 && z < nz; ++z)
    for (std::uint32_t x = 2; x < 6 && x < nx; ++x)
      h[z * nx + x] = 0.25f;
  if (nx > 8 && nz > 8) h[8 * nx + 8] = 2.0f;
  auto r = HeightField::build(nx, nz, h, sx, sz);
  REQUIRE(r.ok());
  return std::move(r.field);
}

/// The same triangles as a TriangleMesh: the field's vertices and the header's indices.
TriangleMesh mesh_of(HeightField const& f) {
  soup s;
  for (std::uint32_t z = 0; z < f.samples_z(); ++z)
    for (std::uint32_t x = 0; x < f.samples_x(); ++x)
      s.v.push_back(f.vertex(x, z));
  auto const at = [&](std::uint32_t x, std::uint32_t z) { return z * f.samples_x() + x; };
  for (std::uint32_t z = 0; z < f.cells_z(); ++z)
    for (std::uint32_t x = 0; x < f.cells_x(); ++x)
      s.i.insert(s.i.end(), {at(x, z), at(x, z + 1), at(x + 1, z), at(x + 1, z), at(x, z + 1),
                             at(x + 1, z + 1)});
  TriangleMesh m = make(s);
  REQUIRE(m.triangle_count() == f.triangle_count());
  return m;
}

} // namespace

TEST_CASE("height field: triangles, normals and edges are the mesh's", "[spatial][heightfield]") {
  auto const [nx, nz] = GENERATE(std::pair{2u, 2u}, std::pair{17u, 11u}, std::pair{33u, 40u});
  HeightField const f = field_of(nx, nz, 0.5f, 0.75f);
  TriangleMesh const m = mesh_of(f);
  int kinds[5] = {};
  for (std::uint32_t t = 0; t < f.triangle_count(); ++t) {
    INFO("triangle " << t);
    Triangle const a = f.triangle(t), b = m.triangle(t);
    REQUIRE((same_bits(a.a, b.a) && same_bits(a.b, b.b) && same_bits(a.c, b.c)));
    REQUIRE(same_bits(f.face_normal(t), m.face_normal(t)));
    REQUIRE(f.face_normal(t).y > 0.0f);
    TriangleEdges const ef = f.edges(t), em = m.edges(t);
    for (std::size_t k = 0; k < 3; ++k) {
      REQUIRE(ef.neighbour[k] == em.neighbour[k]);
      REQUIRE(ef.kind[k] == em.kind[k]);
      ++kinds[int(ef.kind[k])];
    }
  }
  CHECK(same_bits(f.local_aabb().min, m.local_aabb().min));
  CHECK(same_bits(f.local_aabb().max, m.local_aabb().max));
  if (nx > 8) { // every kind but non-manifold appears
    CHECK(kinds[int(EdgeKind::boundary)] > 0);
    CHECK(kinds[int(EdgeKind::flat)] > 0);
    CHECK(kinds[int(EdgeKind::convex)] > 0);
    CHECK(kinds[int(EdgeKind::concave)] > 0);
  }
}

TEST_CASE("height field: cells whose cross products overflow float are the mesh's too",
          "[spatial][heightfield][fuzz]") {
  // Cells of 1.7e37 m and a height of -7.7e8: a float cross product of inf - inf, which the
  // mesh took for a triangle without area and dropped (a fuzz finding, height_field
  // regress-overflow-triangles-not-mesh); it now decides such triangles in double.
  std::vector<float> h(10, 0.0f);
  h[1] = -0x1.71e6p+29f;
  auto const r = HeightField::build(5, 2, h, 0x1.e17b84p+122f, 0x1.e17b84p+122f);
  REQUIRE(r.ok());
  TriangleMesh const m = mesh_of(r.field); // requires the same triangle count
  for (std::uint32_t t = 0; t < r.field.triangle_count(); ++t)
    CHECK(same_bits(r.field.face_normal(t), m.face_normal(t)));
}

TEST_CASE("height field: rays, boxes and closest points are the mesh's, bit for bit",
          "[spatial][heightfield]") {
  HeightField const f = field_of(33, 40, 0.5f, 0.75f);
  TriangleMesh const m = mesh_of(f);
  std::mt19937 g(21);
  std::uniform_real_distribution<float> u(-1, 1), x(-2.0f, 18.0f), z(-2.0f, 31.0f);
  int hits = 0;
  for (int k = 0; k < 3000; ++k) {
    Ray3 ray{{x(g), 3.0f * u(g), z(g)}, {u(g), u(g) - 0.3f, u(g)}};
    if (k % 10 == 0) ray.dir = {0.0f, -1.0f, 0.0f}; // vertical: one cell
    if (k % 10 == 1) ray.dir = {1.0f, 0.0f, 0.0f};  // along a grid axis
    if (k % 10 == 2)
      ray.origin = f.vertex(std::uint32_t(g() % 33), std::uint32_t(g() % 40)) +
                   Vec3{0.0f, 1.0f, 0.0f}; // over a vertex
    float const max_toi = k % 7 == 0 ? inf : 40.0f;
    MeshRayHit const a = f.ray_cast(ray, max_toi), b = m.ray_cast(ray, max_toi);
    INFO("ray " << k);
    REQUIRE(a.triangle == b.triangle);
    if (!b.hit()) continue;
    ++hits;
    REQUIRE(same_bits(a.toi, b.toi));
    REQUIRE(same_bits(a.normal, b.normal));
    REQUIRE(a.back == b.back);
  }
  CHECK(hits > 700);
  for (int k = 0; k < 500; ++k) {
    Vec3 const c{x(g), 2.0f * u(g), z(g)};
    Vec3 const half{std::abs(u(g)), std::abs(u(g)) * 0.5f, std::abs(u(g))};
    Aabb3 const box{c - half, c + half};
    REQUIRE(boxed(f, box) == boxed(m, box));
    Vec3 const p{x(g), 3.0f * u(g), z(g)};
    float const reach = k % 5 == 0 ? inf : 1.5f;
    MeshClosestPoint const ca = f.closest_point(p, reach), cb = m.closest_point(p, reach);
    REQUIRE(ca.triangle == cb.triangle);
    if (cb.found()) {
      REQUIRE(same_bits(ca.point, cb.point));
      REQUIRE(same_bits(ca.distance, cb.distance));
    }
  }
  // Infinite boxes, as the mesh (found by the height_field fuzz target: the field visited
  // nothing for a box with an infinite side); a NaN box visits nothing in either.
  float const nan = std::numeric_limits<float>::quiet_NaN();
  for (Aabb3 const& box : {Aabb3{Vec3::splat(-inf), Vec3::splat(inf)},
                           Aabb3{{-inf, -1, 0}, {1, inf, 2}}, Aabb3{{nan, 0, 0}, {1, 1, 1}}}) {
    std::vector<std::uint32_t> const a = boxed(f, box);
    CHECK(a == boxed(m, box));
    if (std::isnan(box.min.x)) CHECK(a.empty());
  }
  std::size_t all = 0;
  f.query_aabb(Aabb3{Vec3::splat(-inf), Vec3::splat(inf)}, [&](std::uint32_t) { ++all; });
  CHECK(all == f.triangle_count());
  // Stopping early: f returns false after the first triangle.
  int visited = 0;
  f.query_aabb(f.local_aabb(), [&](std::uint32_t) { return ++visited, false; });
  CHECK(visited == 1);
}

TEST_CASE("height field: contacts and shape casts are the mesh's", "[spatial][heightfield]") {
  HeightField const f = field_of(33, 40, 0.5f, 0.75f);
  TriangleMesh const m = mesh_of(f);
  Iso3 const pose{Quat::from_axis_angle(Vec3{0.2f, 1.0f, 0.1f}.normalize(), -0.6f),
                  Vec3{-3.0f, 1.0f, 0.5f}};
  std::mt19937 g(22);
  std::uniform_real_distribution<float> u(-1, 1), x(0.5f, 15.5f), z(0.5f, 28.0f);
  int touching = 0, cast_hits = 0;
  for (int k = 0; k < 300; ++k) {
    Iso3 const local{Quat{u(g), u(g), u(g), u(g) + 0.1f}.normalize(), {x(g), u(g), z(g)}};
    Cuboid const box{Vec3{0.2f + 0.3f * std::abs(u(g)), 0.3f, 0.25f}};
    MeshContacts const a = mesh_contacts(f, pose, box, pose * local);
    MeshContacts const b = mesh_contacts(m, pose, box, pose * local);
    REQUIRE(a.count == b.count);
    touching += a.count > 0;
    for (int i = 0; i < a.count; ++i) {
      Manifold const& ma = a.manifolds[std::size_t(i)].manifold;
      Manifold const& mb = b.manifolds[std::size_t(i)].manifold;
      REQUIRE(a.manifolds[std::size_t(i)].triangle == b.manifolds[std::size_t(i)].triangle);
      REQUIRE(same_bits(ma.normal, mb.normal));
      REQUIRE(ma.count == mb.count);
      for (int p = 0; p < ma.count; ++p) {
        REQUIRE(
            same_bits(ma.points[std::size_t(p)].separation, mb.points[std::size_t(p)].separation));
        REQUIRE(ma.points[std::size_t(p)].id == mb.points[std::size_t(p)].id);
      }
    }
    Iso3 const above{local.rotation, local.translation + Vec3{0.0f, 2.0f, 0.0f}};
    Vec3 const motion = pose.transform_vector(Vec3{u(g), -3.0f, u(g)});
    MeshShapeHit const ca = mesh_shape_cast(f, pose, Sphere{0.3f}, pose * above, motion);
    MeshShapeHit const cb = mesh_shape_cast(m, pose, Sphere{0.3f}, pose * above, motion);
    REQUIRE(ca.triangle == cb.triangle);
    if (cb.hit()) {
      ++cast_hits;
      REQUIRE(same_bits(ca.toi, cb.toi));
    }
  }
  CHECK(touching > 100);
  CHECK(cast_hits > 100);
}

TEST_CASE("height field: a ray with a tiny direction is cast like the mesh's",
          "[spatial][heightfield][fuzz]") {
  // A posed ray of direction (0, 1e-35, 0) became (1.0e-35, 6.1e-38, 6.1e-38) in the field's
  // frame: its squared length underflows to 0, which the field's walk took for a zero
  // direction and found nothing, where the mesh (and the triangles) hit at toi 2.5e35 (a fuzz
  // finding, height_field hit-differs-from-triangles). Only an all-zero direction is zero.
  HeightField const f = field_of(9, 9, 1.0f, 1.0f);
  TriangleMesh const m = mesh_of(f);
  for (Ray3 const& ray :
       {Ray3{{-1.0f, 1.0f, 3.3f}, {1e-35f, -2e-36f, 6.1e-38f}}, // onto the flat patch
        Ray3{{2.2f, 4.0f, 3.3f}, {0.0f, -1e-35f, 0.0f}},
        Ray3{{0.0f, 0.5f, 0.0f}, {0x1.aac6f6p-117f, 0x1.4a6p-124f, 0x1.4c1cp-124f}}}) {
    REQUIRE(ray.dir.length_squared() == 0.0f);
    MeshRayHit const want = m.ray_cast(ray, inf);
    MeshRayHit const got = f.ray_cast(ray, inf);
    CHECK(want.hit());
    CHECK(got.triangle == want.triangle);
    CHECK(same_bits(got.toi, want.toi));
    CHECK(same_bits(got.normal, want.normal));
    CHECK(got.back == want.back);
  }
}

TEST_CASE("height field: a hit whose toi overflows float is a miss, as the triangles' and the mesh's",
          "[spatial][heightfield][fuzz]") {
  // height_field posed-ray-differs-from-triangles: a posed ray of direction (0, 1.9e-42, 0)
  // became (1.9e-42, 0, -1.4e-45) in the field's frame, through two cells 2 and 5 units away
  // along x: toi about 1e42, beyond float. The field's walk and the mesh's tree miss (a box
  // entered at +infinity is a miss), but the triangle cast hit at toi +infinity: 1 / d.x
  // overflows, and it compared toi with max_toi (+infinity) alone. A toi that overflows is a
  // miss in every cast (collision/ray_cast.hpp), the triangle's too.
  auto const triangles = [](auto const& mesh, Ray3 const& ray, float max_toi) {
    MeshRayHit best;
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
      RayHit const h = ray_cast_local(Triangle(mesh.triangle(t)), ray, max_toi);
      CHECK((!h.hit || std::isfinite(h.toi)));
      if (h.hit && (h.toi < best.toi || (h.toi == best.toi && t < best.triangle))) {
        best.triangle = t;
        best.toi = h.toi;
        best.normal = h.normal;
        best.back = h.feature == 1.0f;
      }
    }
    return best;
  };
  auto const same = [](MeshRayHit const& a, MeshRayHit const& b) {
    return a.triangle == b.triangle && same_bits(a.toi, b.toi) && same_bits(a.normal, b.normal) &&
           a.back == b.back;
  };
  SECTION("the finding") {
    std::vector<float> const h{
        0.0f, 0.0f, -0x1.e0f46p+1f, 0x1.194c5cp+2f, 0x1.7dcd8p-2f, 0x1.fe458p+1f, 0.0f,
        -0x1.eee67p+1f, // z = 0
        0.0f, 0.0f, -0x1.c84e48p+1f, 0.0f, 0x1.a8d4ap+0f, 0.5f, -0x1.1610d6p+2f,
        -0x1.f82d78p+1f, // z = 1
        -0x1.e1e462p+1f, 0x1.df1a54p-17f, -0.5f, -0x1.6db06cp+0f, 0.5f, 0x1.53de5p+0f, 0.5f,
        0.0f, // z = 2
        0.0f, 0.0f, 0x1.194c5cp+2f, -0x1.b9e2p-5f, 0.0f, 0.0f, 0.0f, 0.0f, // z = 3
        0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, // z = 4
        0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, // z = 5
        0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0x1.19194p-3f, 0.0f}; // z = 6
    auto const r = HeightField::build(8, 7, h, 1.0f, 1.0f);
    REQUIRE(r.ok());
    Iso3 const pose{Quat::from_xyzw(-0x1.002984p-1f, -0x1.ffe45p-2f, -0x1.ffe45p-2f,
                                    -0x1.ffe45p-2f),
                    Vec3::splat(-0x1.337374p+3f)};
    Ray3 const ray{{-0x1.30ebfp+3f, -0x1.337374p+3f, -0x1.337374p+3f}, {0.0f, 0x1.554p-139f, 0.0f}};
    Ray3 const local{pose.inverse_transform_point(ray.origin),
                     pose.inverse_transform_vector(ray.dir)};
    REQUIRE(same_bits(local.dir, Vec3{0x1.554p-139f, 0.0f, -0x1p-149f}));
    MeshRayHit const want = triangles(r.field, local, inf);
    CHECK(!want.hit());
    CHECK(same(r.field.ray_cast(pose, ray, inf), want));
    CHECK(same(r.field.ray_cast(local, inf), want));
    CHECK(same(mesh_of(r.field).ray_cast(local, inf), want));
  }
  SECTION("directions 1e-30 to 1e-44 long across a field 8 units wide") {
    // 1 / d overflows below about 3e-39 (subnormal d): from there the triangle's toi is
    // +infinity before the division by its determinant.
    HeightField const f = field_of(9, 9, 1.0f, 1.0f);
    TriangleMesh const m = mesh_of(f);
    int hits = 0, misses = 0;
    for (float len : {1e-30f, 1e-37f, 1e-38f, 1e-39f, 1e-40f, 1e-42f, 1e-44f})
      for (Vec3 const& dir : {Vec3{1.0f, 0.0f, 0.0f}, Vec3{0.0f, 0.0f, 1.0f},
                              Vec3{1.0f, -0.01f, 0.2f}, Vec3{0.0f, -1.0f, 0.0f}})
        for (float y : {-0.1f, 0.05f, 0.3f}) {
          Ray3 const ray{dir.y < 0.0f ? Vec3{3.3f, 4.0f, 2.7f} : Vec3{-1.0f, y, 3.3f}, dir * len};
          MeshRayHit const want = triangles(m, ray, inf);
          INFO("len " << len << " dir " << dir.x << " " << dir.y << " " << dir.z << " y " << y);
          CHECK(same(f.ray_cast(ray, inf), want));
          CHECK(same(m.ray_cast(ray, inf), want));
          hits += int(want.hit());
          misses += int(!want.hit());
        }
    CHECK(hits > 10);   // the longer directions hit, at huge finite tois
    CHECK(misses > 10); // the shortest overflow
  }
}

TEST_CASE("height field: bad input", "[spatial][heightfield][bad-input]") {
  std::vector<float> h(12, 0.0f);
  CHECK(HeightField::build(1, 12, h, 1.0f, 1.0f).error == HeightFieldError::too_small);
  CHECK(HeightField::build(4, 4, h, 1.0f, 1.0f).error == HeightFieldError::size_mismatch);
  CHECK(HeightField::build(4, 3, h, 0.0f, 1.0f).error == HeightFieldError::bad_cell_size);
  CHECK(HeightField::build(4, 3, h, 1.0f, -1.0f).error == HeightFieldError::bad_cell_size);
  CHECK(HeightField::build(4, 3, h, 1.0f, inf).error == HeightFieldError::bad_cell_size);
  CHECK(HeightField::build(4, 3, h, qnan, 1.0f).error == HeightFieldError::bad_cell_size);
  CHECK(HeightField::build(1u << 15, 1u << 15, h, 1.0f, 1.0f).error ==
        HeightFieldError::too_many_cells);
  // Found in review: an extent that overflows (inf vertices), and cells so small that a
  // TriangleMesh of the same vertices would drop their triangles as degenerate.
  CHECK(HeightField::build(4, 3, h, 2e38f, 1.0f).error == HeightFieldError::bad_cell_size);
  CHECK(HeightField::build(4, 3, h, 1e-10f, 1e-10f).error == HeightFieldError::bad_cell_size);
  CHECK(HeightField::build(4, 3, h, 1e-9f, 1e-9f).ok());
  h[7] = qnan;
  auto const r = HeightField::build(4, 3, h, 1.0f, 1.0f);
  CHECK(r.error == HeightFieldError::non_finite_height);
  CHECK(r.bad_item == 7);
  CHECK(r.field.empty());
  CHECK(std::string(to_string(HeightFieldError::non_finite_height)) == "non-finite height");
  h[7] = 0.0f;
  auto const ok = HeightField::build(4, 3, h, 1.0f, 1.0f);
  REQUIRE(ok.ok());
  HeightField const& f = ok.field;
  CHECK(f.triangle_count() == 12);
  Ray3 const down{{1.5f, 1.0f, 1.5f}, {0.0f, -1.0f, 0.0f}};
  CHECK(f.ray_cast(down, 2.0f).hit());
  CHECK_FALSE(f.ray_cast(down, 0.5f).hit()); // short of the surface
  CHECK_FALSE(f.ray_cast(down, qnan).hit());
  CHECK_FALSE(f.ray_cast(down, -1.0f).hit());
  CHECK_FALSE(f.ray_cast({{qnan, 1.0f, 1.5f}, {0.0f, -1.0f, 0.0f}}, 2.0f).hit());
  CHECK_FALSE(f.ray_cast({{1.5f, 1.0f, 1.5f}, {0.0f, 0.0f, 0.0f}}, 2.0f).hit());
  CHECK_FALSE(f.closest_point({qnan, 0.0f, 0.0f}, 1.0f).found());
  CHECK_FALSE(f.closest_point({1.0f, 0.0f, 1.0f}, -1.0f).found());
  CHECK(f.closest_point({1.0f, 0.5f, 1.0f}, 1.0f).distance == 0.5f);
  // A ray that misses, with an infinite reach, visits no cell (found in review: entries of
  // +infinity, a miss, passed the test against an infinite max_toi, and every cell was cast).
  int cells = 0;
  auto const count = [&](std::uint32_t, float) { return ++cells, inf; };
  f.swept_query({{1.5f, 1.0f, 1.5f}, {0.0f, 1.0f, 0.0f}}, Vec3{}, inf, count);   // up, away
  f.swept_query({{1.5f, 5.0f, 1.5f}, {1.0f, 0.0f, 0.0f}}, Vec3{}, inf, count);   // level, above
  f.swept_query({{-5.0f, 0.0f, 1.5f}, {-1.0f, 0.0f, 0.0f}}, Vec3{}, inf, count); // away
  CHECK(cells == 0);
  f.swept_query({{1.5f, 1.0f, 1.5f}, {0.0f, -1.0f, 0.0f}}, Vec3{}, inf, count); // down: a cell
  CHECK(cells == 2); // the cell's two triangles
  HeightField const none;
  CHECK_FALSE(none.ray_cast(down, 2.0f).hit());
  CHECK_FALSE(none.closest_point({1.0f, 0.5f, 1.0f}, 1.0f).found());
  int visited = 0;
  none.query_aabb(Aabb3{{-10, -10, -10}, {10, 10, 10}}, [&](std::uint32_t) { ++visited; });
  CHECK(visited == 0);
}
