// tests/fuzz/height_field.cpp - fuzzes HeightField::build (spatial/height_field.hpp) on decoded
// sample counts (0 and 1 included), heights (NaN, infinities, huge values, height counts that
// do not match) and cell sizes (zero, negative, NaN, infinite, overflowing extents, cells too
// small), then its queries (mesh_checks.hpp) and the mesh queries of spatial/mesh_queries.hpp
// against brute force over its triangles.
// Properties:
//  - build: every rejection is the documented error for input that has that fault (bad_item the
//    index of a non-finite height), every input without a fault builds, and a failed build
//    leaves an empty field that finds nothing;
//  - the field: its samples, heights, vertices and triangles as the header lays them out (cell c
//    holds 2c = (a, c, b) and 2c + 1 = (b, c, d)), local_aabb the union of the triangles' boxes,
//    and the triangles, face normals and edge kinds of a TriangleMesh built from the same
//    vertices and indices, bit for bit;
//  - queries (ray casts, posed ray casts, closest points, box queries, overlaps, shape casts,
//    contacts) equal brute force over the triangles as mesh_checks.hpp states (the header
//    promises the mesh's results, which are brute force's);
//  - watertight: a vertical ray through any interior point of the field (vertices and edges
//    included) hits exactly one triangle, and the field's cast hits.
#include "fuzz_input.hpp"
#include "mesh_checks.hpp"

#include <plume/spatial/height_field.hpp>
#include <plume/spatial/triangle_mesh.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace {

using plume::Vec3;
using plume::fuzz::Input;

float cell_size(Input& in) {
  std::uint8_t const k = in.byte();
  switch (k % 16) {
  case 0:
    return 0.0f;
  case 1:
    return -in.real(0, 2);
  case 2:
    return (k & 16) ? std::numeric_limits<float>::quiet_NaN()
                    : std::numeric_limits<float>::infinity();
  case 3:
    return (k & 16) ? 1e37f : 3e38f; // the extent overflows with a few cells
  case 4:
    return (k & 16) ? 1e-10f : 3e-10f; // product near the 1.1e-19 floor
  case 5:
    return in.any_float();
  case 6:
  case 7:
    return 1.0f;
  default:
    return in.real(0.05f, 3.0f);
  }
}

float height(Input& in, std::uint8_t style) {
  switch (style % 4) {
  case 0:
    return float(in.integer(-2, 2)) * 0.5f;
  case 1:
    return in.real(-5, 5);
  case 2:
    return in.maybe_bad(-5, 5);
  default:
    return 0.0f;
  }
}

struct Faults {
  bool too_small = false, mismatch = false, cell = false, non_finite = false;
};

void check_empty(plume::HeightField const& f) {
  PLUME_FUZZ_CHECK(f.empty() && f.triangle_count() == 0);
  PLUME_FUZZ_CHECK(!f.ray_cast(plume::Ray3{{0, 5, 0}, {0.1f, -1, 0.1f}}, 100.0f).hit());
  PLUME_FUZZ_CHECK(!f.closest_point(Vec3{}, std::numeric_limits<float>::infinity()).found());
  bool any = false;
  f.query_aabb(plume::Aabb3{Vec3::splat(-1e30f), Vec3::splat(1e30f)}, [&](std::uint32_t) {
    any = true;
    return true;
  });
  PLUME_FUZZ_CHECK(!any);
}

/// The field's structure against the header's layout and the equivalent TriangleMesh.
void check_field(plume::HeightField const& f, std::uint32_t nx, std::uint32_t nz,
                 std::vector<float> const& h, float cx, float cz, float flat_cosine) {
  PLUME_FUZZ_CHECK(f.samples_x() == nx && f.samples_z() == nz);
  PLUME_FUZZ_CHECK(f.cells_x() == nx - 1 && f.cells_z() == nz - 1);
  PLUME_FUZZ_CHECK(f.cell_x() == cx && f.cell_z() == cz);
  PLUME_FUZZ_CHECK(f.triangle_count() == 2 * std::size_t(nx - 1) * (nz - 1) && !f.empty());
  std::vector<Vec3> vertices;
  for (std::uint32_t z = 0; z < nz; ++z)
    for (std::uint32_t x = 0; x < nx; ++x) {
      PLUME_FUZZ_CHECK(f.height(x, z) == h[z * nx + x]);
      Vec3 const v{float(x) * cx, h[z * nx + x], float(z) * cz};
      PLUME_FUZZ_CHECK(plume::fuzz::same_bits(f.vertex(x, z), v));
      vertices.push_back(v);
    }
  std::vector<std::uint32_t> indices;
  for (std::uint32_t z = 0; z + 1 < nz; ++z)
    for (std::uint32_t x = 0; x + 1 < nx; ++x) {
      std::uint32_t const a = z * nx + x, b = a + 1, c = a + nx, d = c + 1;
      for (std::uint32_t i : {a, c, b, b, c, d})
        indices.push_back(i);
    }
  plume::Aabb3 bounds = f.triangle(0).local_aabb();
  for (std::uint32_t t = 0; t < f.triangle_count(); ++t) {
    plume::Triangle const tri = f.triangle(t);
    PLUME_FUZZ_CHECK(plume::fuzz::same_bits(tri.a, vertices[indices[3 * t]]) &&
                     plume::fuzz::same_bits(tri.b, vertices[indices[3 * t + 1]]) &&
                     plume::fuzz::same_bits(tri.c, vertices[indices[3 * t + 2]]));
    PLUME_FUZZ_CHECK(plume::fuzz::unit(f.face_normal(t)));
    PLUME_FUZZ_CHECK(f.face_normal(t).y >= 0.0f); // both front faces up (or vertical)
    bounds = bounds.merge(tri.local_aabb());
  }
  PLUME_FUZZ_CHECK(plume::fuzz::same_bits(f.local_aabb().min, bounds.min) &&
                   plume::fuzz::same_bits(f.local_aabb().max, bounds.max));
  // The same triangles, normals and edges as the TriangleMesh of those vertices and indices.
  plume::MeshConfig mc;
  mc.flat_cosine = flat_cosine;
  plume::MeshBuildResult const r = plume::TriangleMesh::build(
      std::span<Vec3 const>(vertices), std::span<std::uint32_t const>(indices), mc);
  PLUME_FUZZ_CHECK(r.ok());
  PLUME_FUZZ_CHECK(r.mesh.triangle_count() == f.triangle_count());
  for (std::uint32_t t = 0; t < f.triangle_count(); ++t) {
    plume::Triangle const a = f.triangle(t), b = r.mesh.triangle(t);
    PLUME_FUZZ_CHECK(plume::fuzz::same_bits(a.a, b.a) && plume::fuzz::same_bits(a.b, b.b) &&
                     plume::fuzz::same_bits(a.c, b.c));
    PLUME_FUZZ_CHECK(plume::fuzz::same_bits(f.face_normal(t), r.mesh.face_normal(t)));
    plume::TriangleEdges const ef = f.edges(t), em = r.mesh.edges(t);
    for (std::size_t k = 0; k < 3; ++k) {
      PLUME_FUZZ_CHECK(ef.neighbour[k] == em.neighbour[k]);
      PLUME_FUZZ_CHECK(ef.kind[k] == em.kind[k]);
    }
  }
}

/// A vertical ray through an interior point (often exactly on a vertex or an edge) hits exactly
/// one triangle (of a field whose triangles' float cross products do not overflow).
void check_watertight(plume::HeightField const& f, Input& in) {
  std::uint8_t const k = in.byte();
  float const w = float(f.cells_x()) * f.cell_x(), d = float(f.cells_z()) * f.cell_z();
  float x = float(in.integer(1, 63)) / 64.0f * w, z = float(in.integer(1, 63)) / 64.0f * d;
  if ((k & 1) && f.cells_x() > 1) x = float(in.integer(1, int(f.cells_x()) - 1)) * f.cell_x();
  if ((k & 2) && f.cells_z() > 1) z = float(in.integer(1, int(f.cells_z()) - 1)) * f.cell_z();
  if (!(x > 0.0f && x < w && z > 0.0f && z < d)) return;
  float const top = f.local_aabb().max.y + 10.0f;
  if (!std::isfinite(top)) return;
  // Triangles whose float cross products overflow are beyond the triangle cast's range.
  for (std::uint32_t t = 0; t < f.triangle_count(); ++t)
    if (!std::isfinite(f.triangle(t).scaled_normal().length_squared())) return;
  plume::Ray3 const ray{{x, top, z}, {0.0f, -1.0f, 0.0f}};
  float const inf = std::numeric_limits<float>::infinity();
  int hits = 0;
  for (std::uint32_t t = 0; t < f.triangle_count(); ++t)
    hits += bool(plume::ray_cast_local(f.triangle(t), ray, inf).hit) ? 1 : 0;
  PLUME_FUZZ_CHECK(hits == 1);
  PLUME_FUZZ_CHECK(f.ray_cast(ray, inf).hit());
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  std::uint8_t const c = in.byte();
  plume::MeshConfig cfg;
  if (c & 1) cfg.flat_cosine = in.real(0.5f, 1.0f);
  std::uint32_t const nx = std::uint32_t(in.integer(0, 9)), nz = std::uint32_t(in.integer(0, 9));
  std::size_t count = std::size_t(nx) * nz;
  if ((c & 6) == 6) count = std::size_t(in.integer(0, 40)); // most likely a mismatch
  std::uint8_t const style = in.byte();
  std::vector<float> h;
  for (std::size_t i = 0; i < count; ++i)
    h.push_back(height(in, (style & 0x80) ? in.byte() : style));
  float const cx = (c & 8) ? cell_size(in) : 1.0f;
  float const cz = (c & 16) ? cell_size(in) : 1.0f;

  plume::HeightFieldBuildResult const r =
      plume::HeightField::build(nx, nz, std::span<float const>(h), cx, cz, cfg);
  Faults f;
  f.too_small = nx < 2 || nz < 2;
  f.mismatch = h.size() != std::size_t(nx) * nz;
  f.cell = !(cx > 0.0f) || !(cz > 0.0f) || !std::isfinite(cx) || !std::isfinite(cz) ||
           (nx > 0 && !std::isfinite(float(nx - 1) * cx)) ||
           (nz > 0 && !std::isfinite(float(nz - 1) * cz)) || !(double(cx) * double(cz) >= 1.1e-19);
  for (float v : h)
    f.non_finite = f.non_finite || !std::isfinite(v);
  switch (r.error) {
  case plume::HeightFieldError::none:
    PLUME_FUZZ_CHECK(!f.too_small && !f.mismatch && !f.cell && !f.non_finite);
    break;
  case plume::HeightFieldError::too_small:
    PLUME_FUZZ_CHECK(f.too_small);
    break;
  case plume::HeightFieldError::size_mismatch:
    PLUME_FUZZ_CHECK(f.mismatch);
    break;
  case plume::HeightFieldError::non_finite_height:
    PLUME_FUZZ_CHECK(f.non_finite);
    PLUME_FUZZ_CHECK(r.bad_item < h.size() && !std::isfinite(h[r.bad_item]));
    break;
  case plume::HeightFieldError::bad_cell_size:
    PLUME_FUZZ_CHECK(f.cell);
    break;
  default:
    PLUME_FUZZ_CHECK(false && "an error the input cannot have (too_many_cells)");
  }
  PLUME_FUZZ_CHECK(r.ok() == (r.error == plume::HeightFieldError::none));
  if (!r.ok()) {
    check_empty(r.field);
    check_empty(plume::HeightField{});
    return 0;
  }
  plume::HeightField const& field = r.field;
  check_field(field, nx, nz, h, cx, cz, cfg.flat_cosine);
  float const reach = std::max(float(nx) * cx, float(nz) * cz) + 6.0f;
  int const queries = in.integer(1, 12);
  for (int q = 0; q < queries && !in.empty(); ++q) {
    if ((in.byte() & 3) == 0) check_watertight(field, in);
    plume::fuzz::fuzz_query(in, field, std::min(reach, 1e4f));
  }
  return 0;
}
