// tests/fuzz/triangle_mesh.cpp - fuzzes TriangleMesh::build (spatial/triangle_mesh.hpp) on
// decoded vertices and indices - triangle soups with shared, out-of-range and repeated
// indices, degenerate triangles, NaN and infinite coordinates, empty lists, index counts not a
// multiple of 3, and consistently wound grids - then its queries (mesh_checks.hpp) and the
// mesh queries of spatial/mesh_queries.hpp against brute force over its triangles.
// Properties:
//  - build: every rejection is the documented error for input that has that fault (bad_item
//    naming an offending vertex or index position), and every input without a fault builds;
//    degenerate triangles (|(b - a) x (c - a)|^2 below the smallest normal float) are dropped
//    and counted; a mesh with none left is all_degenerate; a failed build leaves an empty mesh
//    that finds nothing;
//  - the mesh: the kept triangles in input order (source_triangle, triangle_indices, vertices),
//    unit front-face normals, local_aabb the union of the triangles' boxes, a valid tree of the
//    triangles' tight boxes (proxy = triangle), and edge adjacency and kinds by the header's
//    rule (neighbours only across an edge run by exactly two triangles in opposite directions,
//    symmetric);
//  - queries (ray casts, posed ray casts, closest points, box queries, overlaps, shape casts,
//    contacts) equal brute force over the triangles as mesh_checks.hpp states, and ray casts
//    through other node widths (GWideBvh<float, 4>, GWideBvh<f32x4, 8>) give the same bits;
//  - watertight: on a consistently wound grid, a vertical ray through any interior point
//    (vertices and edges included) hits exactly one triangle, and the mesh's cast hits.
#include "fuzz_input.hpp"
#include "mesh_checks.hpp"

#include <plume/spatial/triangle_mesh.hpp>
#include <plume/spatial/wide_bvh.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace {

using plume::Vec3;
using plume::fuzz::Input;

float coordinate(Input& in, std::uint8_t style) {
  switch (style % 4) {
  case 0:
    return float(in.integer(-3, 3));
  case 1:
    return in.real(-10, 10);
  case 2:
    return in.maybe_bad(-10, 10);
  default: { // half units, at times nudged off them (two reads: sequenced)
    float const v = float(in.integer(-6, 6)) * 0.5f;
    return v + ((style & 4) ? in.real(-1e-6f, 1e-6f) : 0.0f);
  }
  }
}

struct Soup {
  std::vector<Vec3> vertices;
  std::vector<std::uint32_t> indices;
  bool watertight_grid = false; ///< a consistently wound grid of nx x nz cells sx x sz in x, z
  int nx = 0, nz = 0;
  float sx = 0, sz = 0;
};

Soup decode_soup(Input& in) {
  Soup s;
  std::uint8_t const mode = in.byte();
  if (mode % 4 == 0) { // a grid, two triangles per cell, both faces up (as a height field's)
    int const nx = in.integer(1, 4), nz = in.integer(1, 4);
    float const sx = (mode & 4) ? in.real(0.1f, 3) : 1.0f,
                sz = (mode & 8) ? in.real(0.1f, 3) : 1.0f;
    for (int z = 0; z <= nz; ++z)
      for (int x = 0; x <= nx; ++x)
        s.vertices.push_back({float(x) * sx,
                              (mode & 16) ? in.real(-2, 2) : float(in.integer(-2, 2)) * 0.5f,
                              float(z) * sz});
    bool consistent = true;
    for (int z = 0; z < nz; ++z)
      for (int x = 0; x < nx; ++x) {
        auto const v = [&](int i, int j) { return std::uint32_t(j * (nx + 1) + i); };
        std::uint32_t const a = v(x, z), b = v(x + 1, z), c = v(x, z + 1), dd = v(x + 1, z + 1);
        bool const flip = (mode & 32) && in.flag();
        consistent = consistent && !flip;
        std::uint32_t const t0[3] = {a, c, b}, t1[3] = {b, c, dd};
        for (int k = 0; k < 3; ++k)
          s.indices.push_back(flip ? t0[2 - k] : t0[k]);
        for (int k = 0; k < 3; ++k)
          s.indices.push_back(t1[k]);
      }
    if ((mode & 64) && !s.indices.empty()) { // a repeated triangle: non-manifold edges
      std::size_t const t = std::size_t(in.byte()) % (s.indices.size() / 3);
      for (int k = 0; k < 3; ++k)
        s.indices.push_back(s.indices[3 * t + std::size_t(k)]);
      consistent = false;
    }
    s.watertight_grid = consistent;
    s.nx = nx;
    s.nz = nz;
    s.sx = sx;
    s.sz = sz;
    return s;
  }
  // A soup: a few vertices, indices mostly in range.
  int const nv = in.integer(0, 16);
  for (int i = 0; i < nv; ++i) {
    std::uint8_t const style = in.byte();
    s.vertices.push_back({coordinate(in, style), coordinate(in, style), coordinate(in, style)});
  }
  int const ni = in.integer(0, 48);
  std::uint32_t const range = std::uint32_t(nv) + ((mode & 8) ? 2u : 0u);
  for (int i = 0; i < ni; ++i) {
    std::uint8_t const b = in.byte();
    s.indices.push_back(range > 0 ? b % range : b);
  }
  if ((mode & 16) == 0) s.indices.resize(s.indices.size() / 3 * 3);
  if ((mode & 0xe0) == 0xe0 && !s.indices.empty()) s.indices.back() = 0xffffffffu;
  return s;
}

bool finite_vertex(Vec3 const& v) { return plume::fuzz::finite(v); }

/// The documented build errors this input has.
struct Faults {
  bool empty = false, count = false, non_finite = false, out_of_range = false;
};

Faults faults_of(Soup const& s) {
  Faults f;
  f.empty = s.vertices.empty() || s.indices.empty();
  f.count = s.indices.size() % 3 != 0;
  for (Vec3 const& v : s.vertices)
    f.non_finite = f.non_finite || !finite_vertex(v);
  for (std::uint32_t i : s.indices)
    f.out_of_range = f.out_of_range || i >= s.vertices.size();
  return f;
}

void check_empty_mesh(plume::TriangleMesh const& m) {
  PLUME_FUZZ_CHECK(m.empty() && m.triangle_count() == 0);
  PLUME_FUZZ_CHECK(!m.ray_cast(plume::Ray3{{0, 5, 0}, {0, -1, 0}}, 100.0f).hit());
  PLUME_FUZZ_CHECK(!m.closest_point(Vec3{}, std::numeric_limits<float>::infinity()).found());
  bool any = false;
  m.query_aabb(plume::Aabb3{Vec3::splat(-1e30f), Vec3::splat(1e30f)}, [&](std::uint32_t) {
    any = true;
    return true;
  });
  PLUME_FUZZ_CHECK(!any);
}

void check_edges(plume::TriangleMesh const& m, float flat_cosine) {
  std::uint32_t const n = std::uint32_t(m.triangle_count());
  for (std::uint32_t t = 0; t < n; ++t) {
    auto const& it = m.triangle_indices(t);
    plume::TriangleEdges const& e = m.edges(t);
    for (std::size_t k = 0; k < 3; ++k) {
      std::uint32_t const u = it[k], v = it[(k + 1) % 3];
      // Every other use of the edge {u, v} among the kept triangles.
      int same = 0, opposite = 0;
      std::uint32_t other = plume::no_triangle;
      std::size_t other_edge = 0;
      for (std::uint32_t s = 0; s < n; ++s) {
        auto const& is = m.triangle_indices(s);
        for (std::size_t j = 0; j < 3; ++j) {
          if (s == t && j == k) continue;
          std::uint32_t const a = is[j], b = is[(j + 1) % 3];
          if (a == u && b == v) ++same;
          if (a == v && b == u) {
            ++opposite;
            other = s;
            other_edge = j;
          }
        }
      }
      if (same == 0 && opposite == 0) {
        PLUME_FUZZ_CHECK(e.kind[k] == plume::EdgeKind::boundary);
        PLUME_FUZZ_CHECK(e.neighbour[k] == plume::no_triangle);
      } else if (same == 0 && opposite == 1) {
        PLUME_FUZZ_CHECK(e.neighbour[k] == other);
        PLUME_FUZZ_CHECK(m.edges(other).neighbour[other_edge] == t);
        Vec3 const r = m.vertices()[m.triangle_indices(other)[(other_edge + 2) % 3]];
        plume::EdgeKind const want = plume::detail::edge_kind(
            m.face_normal(t), m.face_normal(other), m.vertices()[u], r, flat_cosine);
        PLUME_FUZZ_CHECK(e.kind[k] == want);
        PLUME_FUZZ_CHECK(want == plume::EdgeKind::convex || want == plume::EdgeKind::flat ||
                         want == plume::EdgeKind::concave);
        if (want == plume::EdgeKind::flat)
          PLUME_FUZZ_CHECK(m.edges(other).kind[other_edge] == plume::EdgeKind::flat);
      } else {
        PLUME_FUZZ_CHECK(e.kind[k] == plume::EdgeKind::non_manifold);
        PLUME_FUZZ_CHECK(e.neighbour[k] == plume::no_triangle);
      }
    }
  }
}

void check_mesh(plume::MeshBuildResult const& r, Soup const& s, float flat_cosine) {
  plume::TriangleMesh const& m = r.mesh;
  std::size_t const input = s.indices.size() / 3;
  PLUME_FUZZ_CHECK(r.input_triangles == input);
  // Degenerate triangles, as the header defines them, are dropped and counted.
  std::vector<std::uint32_t> kept;
  for (std::size_t t = 0; t < input; ++t) {
    plume::Triangle const tri{s.vertices[s.indices[3 * t]], s.vertices[s.indices[3 * t + 1]],
                              s.vertices[s.indices[3 * t + 2]]};
    if (tri.scaled_normal().length_squared() >= std::numeric_limits<float>::min())
      kept.push_back(std::uint32_t(t));
    else if (std::isnan(tri.scaled_normal().length_squared()))
      kept.push_back(std::uint32_t(t) | 0x80000000u); // overflowed: either is defensible
  }
  std::size_t sure = 0;
  for (std::uint32_t k : kept)
    sure += (k & 0x80000000u) ? 0 : 1;
  PLUME_FUZZ_CHECK(r.triangles + r.degenerate == input);
  PLUME_FUZZ_CHECK(r.triangles >= sure && r.triangles <= kept.size());
  PLUME_FUZZ_CHECK(m.triangle_count() == r.triangles && !m.empty());
  // The kept triangles in input order.
  plume::Aabb3 bounds = m.triangle(0).local_aabb();
  for (std::uint32_t t = 0; t < m.triangle_count(); ++t) {
    std::uint32_t const src = m.source_triangle(t);
    PLUME_FUZZ_CHECK(src < input);
    if (t > 0) PLUME_FUZZ_CHECK(src > m.source_triangle(t - 1));
    auto const& id = m.triangle_indices(t);
    for (std::size_t k = 0; k < 3; ++k)
      PLUME_FUZZ_CHECK(id[k] == s.indices[3 * src + k]);
    plume::Triangle const& tri = m.triangle(t);
    PLUME_FUZZ_CHECK(plume::fuzz::same_bits(tri.a, s.vertices[id[0]]) &&
                     plume::fuzz::same_bits(tri.b, s.vertices[id[1]]) &&
                     plume::fuzz::same_bits(tri.c, s.vertices[id[2]]));
    Vec3 const n = m.face_normal(t);
    PLUME_FUZZ_CHECK(plume::fuzz::unit(n));
    // Along (b - a) x (c - a), computed here in double.
    double const e1[3] = {double(tri.b.x) - tri.a.x, double(tri.b.y) - tri.a.y,
                          double(tri.b.z) - tri.a.z};
    double const e2[3] = {double(tri.c.x) - tri.a.x, double(tri.c.y) - tri.a.y,
                          double(tri.c.z) - tri.a.z};
    double const cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                          e1[0] * e2[1] - e1[1] * e2[0]};
    double const cl = std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    if (cl > 0.0 && std::isfinite(cl))
      PLUME_FUZZ_CHECK((n.x * cr[0] + n.y * cr[1] + n.z * cr[2]) / cl > 0.99);
    bounds = bounds.merge(tri.local_aabb());
    // The tree: proxy t is triangle t with its tight box.
    PLUME_FUZZ_CHECK(m.tree().contains(t));
    PLUME_FUZZ_CHECK(m.tree().user(t) == t);
    plume::Aabb3 const tb = m.tree().tight_box(t), lb = tri.local_aabb();
    PLUME_FUZZ_CHECK(plume::fuzz::same_bits(tb.min, lb.min) &&
                     plume::fuzz::same_bits(tb.max, lb.max));
  }
  PLUME_FUZZ_CHECK(plume::fuzz::same_bits(m.local_aabb().min, bounds.min) &&
                   plume::fuzz::same_bits(m.local_aabb().max, bounds.max));
  PLUME_FUZZ_CHECK(m.tree().size() == m.triangle_count());
  PLUME_FUZZ_CHECK(m.tree().validate().empty());
  PLUME_FUZZ_CHECK(m.bvh().leaf_count() == m.triangle_count());
  PLUME_FUZZ_CHECK(m.block_bvh().leaf_count() == m.blocks().size());
  check_edges(m, flat_cosine);
}

/// A consistently wound grid is watertight from above: a vertical ray through an interior point
/// hits exactly one triangle.
void check_watertight(plume::TriangleMesh const& m, Soup const& s, Input& in) {
  // Anywhere inside, or exactly on the grid's lines (vertices, edges, the diagonals' ends).
  std::uint8_t const k = in.byte();
  float const w = float(s.nx) * s.sx, d = float(s.nz) * s.sz;
  float x = float(in.integer(1, 63)) / 64.0f * w, z = float(in.integer(1, 63)) / 64.0f * d;
  if ((k & 1) && s.nx > 1) x = float(in.integer(1, s.nx - 1)) * s.sx;
  if ((k & 2) && s.nz > 1) z = float(in.integer(1, s.nz - 1)) * s.sz;
  if (!(x > 0.0f && x < w && z > 0.0f && z < d)) return;
  plume::Ray3 const ray{{x, 100.0f, z}, {0.0f, -1.0f, 0.0f}};
  int hits = 0;
  for (std::uint32_t t = 0; t < m.triangle_count(); ++t)
    hits +=
        bool(plume::ray_cast_local(m.triangle(t), ray, std::numeric_limits<float>::infinity()).hit)
            ? 1
            : 0;
  PLUME_FUZZ_CHECK(hits == 1);
  PLUME_FUZZ_CHECK(m.ray_cast(ray, std::numeric_limits<float>::infinity()).hit());
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  plume::MeshConfig cfg;
  std::uint8_t const c = in.byte();
  if (c & 1) cfg.flat_cosine = in.real(0.5f, 1.0f);
  Soup const s = decode_soup(in);
  plume::MeshBuildResult const r = plume::TriangleMesh::build(
      std::span<Vec3 const>(s.vertices), std::span<std::uint32_t const>(s.indices), cfg);
  Faults const f = faults_of(s);
  bool const any_fault = f.empty || f.count || f.non_finite || f.out_of_range;
  switch (r.error) {
  case plume::MeshError::none:
    PLUME_FUZZ_CHECK(!any_fault);
    check_mesh(r, s, cfg.flat_cosine);
    break;
  case plume::MeshError::empty:
    PLUME_FUZZ_CHECK(f.empty);
    break;
  case plume::MeshError::index_count_not_multiple_of_3:
    PLUME_FUZZ_CHECK(f.count);
    break;
  case plume::MeshError::index_out_of_range:
    PLUME_FUZZ_CHECK(f.out_of_range);
    PLUME_FUZZ_CHECK(r.bad_item < s.indices.size() && s.indices[r.bad_item] >= s.vertices.size());
    break;
  case plume::MeshError::non_finite_vertex:
    PLUME_FUZZ_CHECK(f.non_finite);
    PLUME_FUZZ_CHECK(r.bad_item < s.vertices.size() && !finite_vertex(s.vertices[r.bad_item]));
    break;
  case plume::MeshError::all_degenerate: {
    PLUME_FUZZ_CHECK(!any_fault);
    PLUME_FUZZ_CHECK(r.degenerate == s.indices.size() / 3);
    for (std::size_t t = 0; t < s.indices.size() / 3; ++t) {
      plume::Triangle const tri{s.vertices[s.indices[3 * t]], s.vertices[s.indices[3 * t + 1]],
                                s.vertices[s.indices[3 * t + 2]]};
      PLUME_FUZZ_CHECK(
          !(tri.scaled_normal().length_squared() >= std::numeric_limits<float>::min()));
    }
    break;
  }
  default:
    PLUME_FUZZ_CHECK(false && "an error the input cannot have (too_many_triangles)");
  }
  PLUME_FUZZ_CHECK(r.ok() == (r.error == plume::MeshError::none));
  if (!r.ok()) {
    PLUME_FUZZ_CHECK(r.triangles == 0);
    check_empty_mesh(r.mesh);
    check_empty_mesh(plume::TriangleMesh{});
    return 0;
  }
  plume::TriangleMesh const& mesh = r.mesh;
  // Other node widths and the blocks give the same ray casts (the header's promise).
  plume::GWideBvh<float, 4> const narrow(mesh.tree());
  plume::GWideBvh<plume::f32x4, 8> const eight(mesh.tree());
  plume::GWideBvh<float, 2> const narrow_blocks = mesh.make_block_bvh<float, 2>();
  int const queries = in.integer(1, 12);
  for (int q = 0; q < queries && !in.empty(); ++q) {
    if (s.watertight_grid && (in.byte() & 3) == 0) check_watertight(mesh, s, in);
    plume::fuzz::fuzz_query(in, mesh, 12.0f);
    plume::Ray3 const ray = plume::fuzz::mesh_ray(in, mesh, 12.0f);
    float const max_toi = plume::fuzz::mesh_max(in);
    plume::MeshRayHit const want = mesh.ray_cast(ray, max_toi);
    if (plume::fuzz::ordinary(mesh)) {
      PLUME_FUZZ_CHECK(plume::fuzz::same_hit(mesh.ray_cast_with(narrow, ray, max_toi), want));
      PLUME_FUZZ_CHECK(plume::fuzz::same_hit(mesh.ray_cast_with(eight, ray, max_toi), want));
      PLUME_FUZZ_CHECK(
          plume::fuzz::same_hit(mesh.ray_cast_blocks_with(narrow_blocks, ray, max_toi), want));
    }
  }
  return 0;
}
