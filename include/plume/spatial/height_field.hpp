// plume/spatial/height_field.hpp - HeightField: a grid of heights, two triangles per cell,
// with the queries of TriangleMesh (ray casts, box queries, closest points, edge kinds)
// computed from the heights, without storing triangles.
//
//   auto r = HeightField::build(129, 129, heights, 0.5f, 0.5f); // heights[z * 129 + x]
//   if (!r.ok()) report(r.error, r.bad_item);
//   HeightField const& ground = r.field;
//   MeshRayHit h = ground.ray_cast(Ray3{{3, 10, 4}, {0, -1, 0}}, 100.0f);
//   MeshContacts c = mesh_contacts(ground, pose, shape, shape_pose);  // spatial/mesh_queries.hpp
//
// Local frame: sample (x, z) is the vertex (x * cell_x, heights[z * samples_x + x],
// z * cell_z), x in [0, samples_x), z in [0, samples_z). Cell (x, z) spans samples x..x+1 and
// z..z+1 and holds two triangles: 2 c (a, c, b) and 2 c + 1 (b, c, d), c = z * cells_x + x,
// with a = (x, z), b = (x + 1, z), c = (x, z + 1), d = (x + 1, z + 1): both front faces up
// (+y), the diagonal from b to c. These are exactly the triangles, in the same order, of a
// TriangleMesh built from the same vertices with those indices, and every query gives that
// mesh's result bit for bit (the tests check it): the same least (toi, triangle) for rays,
// the same triangles for boxes, the same nearest point, the same edge kinds (a border edge
// is boundary, the others flat, convex or concave by MeshConfig::flat_cosine).
//
// Traversal: a min-max pyramid of height ranges (level 0: each cell; each level above: 2 x 2
// blocks of the one below), walked nearest block first with the same slack as the mesh's
// tree, so ties and near-ties are decided by the triangles. Memory: 4 bytes per sample plus
// about 11 bytes per cell.
//
// Build: rejects (error, nothing built) fewer than 2 samples along x or z, a height count
// other than samples_x * samples_z, a NaN or infinite height (bad_item: its index), a cell
// size that is not positive and finite, a field whose extent (cells x cell size) overflows,
// cells so small that their triangles would be degenerate (cell_x * cell_z below 1.1e-19, the
// square root of the smallest normal float: a TriangleMesh would drop such triangles), and
// 2^29 cells or more (triangle indices are 31-bit).
// Queries with non-finite input find nothing, as TriangleMesh's.
#pragma once

#include <plume/collision/ray_cast.hpp>
#include <plume/collision/shapes.hpp>
#include <plume/math/aabb3.hpp>
#include <plume/math/iso3.hpp>
#include <plume/spatial/triangle_mesh.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>
#include <vector>

namespace plume {

enum class HeightFieldError : std::uint8_t {
  none,
  too_small,         ///< fewer than 2 samples along x or z
  size_mismatch,     ///< heights.size() != samples_x * samples_z
  non_finite_height, ///< bad_item: the height's index
  bad_cell_size,     ///< not positive and finite, an extent that overflows, or degenerate cells
  too_many_cells,    ///< 2^29 or more
};
char const* to_string(HeightFieldError e) noexcept;

struct HeightFieldBuildResult;

namespace detail {
/// The ray's entry into a box within [0, limit], or +infinity for a miss (closed slabs).
float ray_box_entry(Ray3 const& ray, Aabb3 const& box, float limit) noexcept;
} // namespace detail

class HeightField {
public:
  HeightField() = default; ///< an empty field: every query finds nothing

  static HeightFieldBuildResult build(std::uint32_t samples_x, std::uint32_t samples_z,
                                      std::span<float const> heights, float cell_x, float cell_z,
                                      MeshConfig const& config = {});

  // Accessors taking a sample (x < samples_x(), z < samples_z()), cell or triangle index
  // (< triangle_count()) expect it in range and do not check it, as TriangleMesh's.
  std::uint32_t samples_x() const noexcept { return nx_; }
  std::uint32_t samples_z() const noexcept { return nz_; }
  std::uint32_t cells_x() const noexcept { return nx_ > 0 ? nx_ - 1 : 0; }
  std::uint32_t cells_z() const noexcept { return nz_ > 0 ? nz_ - 1 : 0; }
  float cell_x() const noexcept { return sx_; }
  float cell_z() const noexcept { return sz_; }
  /// The height of sample (x, z), local units.
  float height(std::uint32_t x, std::uint32_t z) const noexcept { return h_[z * nx_ + x]; }
  std::span<float const> heights() const noexcept { return h_; }
  /// The local vertex of sample (x, z).
  Vec3 vertex(std::uint32_t x, std::uint32_t z) const noexcept {
    return {float(x) * sx_, h_[z * nx_ + x], float(z) * sz_};
  }

  std::size_t triangle_count() const noexcept { return 2 * std::size_t(cells_x()) * cells_z(); }
  bool empty() const noexcept { return h_.empty(); }
  Triangle triangle(std::uint32_t t) const noexcept;
  /// Unit normal of the front face (up), as TriangleMesh::face_normal.
  Vec3 face_normal(std::uint32_t t) const noexcept;
  /// The triangle's edges (edge e: vertex e to vertex (e + 1) % 3), as TriangleMesh::edges.
  TriangleEdges edges(std::uint32_t t) const noexcept;
  Aabb3 local_aabb() const noexcept { return bounds_; }

  // ------------------------------------------------------------------ queries
  /// The closest hit (both faces, least toi in [0, max_toi], ties to the lower triangle).
  MeshRayHit ray_cast(Ray3 const& ray, float max_toi) const;
  /// The ray in world space, the field placed by pose; normal in world space.
  MeshRayHit ray_cast(Iso3 const& pose, Ray3 const& ray, float max_toi) const;

  /// f(triangle) for each triangle whose box meets `box` (touching counts), in pyramid order;
  /// f returns false to stop (or void to visit all). A box with a NaN meets nothing.
  template <class F>
  void query_aabb(Aabb3 const& box, F&& f) const {
    visit_cells(box, [&](std::uint32_t t) {
      if constexpr (std::is_void_v<decltype(f(t))>) {
        f(t);
        return true;
      } else {
        return bool(f(t));
      }
    });
  }

  /// As TriangleMesh::swept_query: f(triangle, entry) for each triangle whose cell's box,
  /// grown by `grow`, the ray enters within max_toi, nearest cell first; f returns the new
  /// max_toi (negative to stop).
  template <class F>
  void swept_query(Ray3 const& ray, Vec3 const& grow, float max_toi, F&& f) const {
    walk_ray(ray, grow, max_toi, [&](std::uint32_t cell, float entry, float limit) {
      for (std::uint32_t t = 2 * cell; t < 2 * cell + 2; ++t) {
        limit = f(t, entry);
        if (!(limit >= 0.0f)) break;
      }
      return limit;
    });
  }

  /// The nearest point at distance <= max_distance from p (ties to the lower triangle).
  MeshClosestPoint closest_point(Vec3 const& p, float max_distance) const;
  MeshClosestPoint closest_point(Iso3 const& pose, Vec3 const& p, float max_distance) const;

private:
  /// One level of the pyramid: blocks of 2^level x 2^level cells.
  struct Level {
    std::uint32_t w = 0, d = 0; ///< blocks along x and z
    std::vector<float> lo, hi;  ///< height range per block, z-major
  };
  /// The box of block (bx, bz) of level l, grown by pad_.
  Aabb3 block_box(std::size_t l, std::uint32_t bx, std::uint32_t bz) const noexcept;
  /// Calls f(triangle) for every triangle whose box meets box until f returns false.
  template <class F>
  void visit_cells(Aabb3 const& box, F&& f) const;
  /// Calls f(cell, entry, max_toi) for each cell whose box, grown by `grow`, the ray enters
  /// within max_toi, nearest first; f returns the new max_toi (negative to stop).
  template <class F>
  void walk_ray(Ray3 const& ray, Vec3 const& grow, float max_toi, F&& f) const;

  std::uint32_t nx_ = 0, nz_ = 0;
  float sx_ = 0.0f, sz_ = 0.0f;
  float flat_cosine_ = MeshConfig{}.flat_cosine;
  float pad_ = 0.0f; ///< block boxes grow by it, so rounding never drops a cell
  std::vector<float> h_;
  std::vector<Level> levels_; ///< levels_[0]: cells; back(): one block
  Aabb3 bounds_{};
};

struct HeightFieldBuildResult {
  HeightFieldError error = HeightFieldError::none;
  std::size_t bad_item = 0; ///< the offending height (non_finite_height)
  HeightField field;        ///< empty unless ok()
  bool ok() const noexcept { return error == HeightFieldError::none; }
};

// ------------------------------------------------------------------------ templates

template <class F>
void HeightField::visit_cells(Aabb3 const& box, F&& f) const {
  // Every box with min <= max (NaN fails) walks, infinite ones too, as TriangleMesh's.
  if (levels_.empty() || !bool(box.min.cmple(box.max).all())) return;
  struct entry {
    std::uint32_t level, bx, bz;
  };
  std::vector<entry> stack{{std::uint32_t(levels_.size() - 1), 0, 0}};
  while (!stack.empty()) {
    entry const e = stack.back();
    stack.pop_back();
    if (!bool(block_box(e.level, e.bx, e.bz).intersects(box))) continue;
    if (e.level == 0) {
      std::uint32_t const c = e.bz * cells_x() + e.bx;
      for (std::uint32_t t = 2 * c; t < 2 * c + 2; ++t)
        if (bool(triangle(t).local_aabb().intersects(box)) && !f(t)) return;
      continue;
    }
    Level const& below = levels_[e.level - 1];
    for (std::uint32_t j = 2; j-- > 0;) // pushed in reverse: popped in z-major order
      for (std::uint32_t i = 2; i-- > 0;) {
        std::uint32_t const x = 2 * e.bx + i, z = 2 * e.bz + j;
        if (x < below.w && z < below.d) stack.push_back({e.level - 1, x, z});
      }
  }
}

template <class F>
void HeightField::walk_ray(Ray3 const& ray, Vec3 const& grow, float max_toi, F&& f) const {
  // A zero direction is one whose components are all zero: a tiny one (1e-35, whose squared
  // length underflows to 0) still reaches the triangles at a huge toi.
  if (levels_.empty() || !(max_toi >= 0.0f) || !bool(ray.origin.is_finite()) ||
      !bool(ray.dir.is_finite()) || (ray.dir.x == 0.0f && ray.dir.y == 0.0f && ray.dir.z == 0.0f))
    return;
  float const inf = std::numeric_limits<float>::infinity();
  auto const enter = [&](Aabb3 const& b, float limit) {
    return detail::ray_box_entry(ray, {b.min - grow, b.max + grow}, limit);
  };
  struct entry {
    std::uint32_t level, bx, bz;
    float t;
  };
  std::vector<entry> stack;
  std::size_t const top = levels_.size() - 1;
  // An entry of +infinity is a miss (ray_box_entry's), even when max_toi is +infinity.
  if (float const t = enter(block_box(top, 0, 0), max_toi); t <= max_toi && t < inf)
    stack.push_back({std::uint32_t(top), 0, 0, t});
  while (!stack.empty()) {
    entry const e = stack.back();
    stack.pop_back();
    if (e.t > max_toi) continue;
    if (e.level == 0) {
      max_toi = f(e.bz * cells_x() + e.bx, e.t, max_toi);
      if (!(max_toi >= 0.0f)) return;
      continue;
    }
    Level const& below = levels_[e.level - 1];
    std::array<entry, 4> met;
    std::size_t n = 0;
    for (std::uint32_t j = 0; j < 2; ++j)
      for (std::uint32_t i = 0; i < 2; ++i) {
        std::uint32_t const x = 2 * e.bx + i, z = 2 * e.bz + j;
        if (x >= below.w || z >= below.d) continue;
        float const t = enter(block_box(e.level - 1, x, z), max_toi);
        if (!(t <= max_toi && t < inf)) continue;
        // Sorted far to near: the nearest is pushed last and popped first.
        entry const c{e.level - 1, x, z, t};
        std::size_t k = n++;
        for (; k > 0 && met[k - 1].t < c.t; --k)
          met[k] = met[k - 1];
        met[k] = c;
      }
    for (std::size_t k = 0; k < n; ++k)
      stack.push_back(met[k]);
  }
}

} // namespace plume
