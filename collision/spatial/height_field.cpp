// HeightField: validation, the min-max pyramid, triangles and edges from the heights, ray
// casts and closest points. The contract is in include/plume/spatial/height_field.hpp.
#include <plume/spatial/height_field.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace plume {

char const* to_string(HeightFieldError e) noexcept {
  switch (e) {
  case HeightFieldError::none:
    return "none";
  case HeightFieldError::too_small:
    return "fewer than 2 samples along x or z";
  case HeightFieldError::size_mismatch:
    return "height count is not samples_x * samples_z";
  case HeightFieldError::non_finite_height:
    return "non-finite height";
  case HeightFieldError::bad_cell_size:
    return "cell size not positive and finite, too large for the field's extent, or too small";
  case HeightFieldError::too_many_cells:
    return "too many cells (2^29 or more)";
  }
  return "unknown";
}

HeightFieldBuildResult HeightField::build(std::uint32_t samples_x, std::uint32_t samples_z,
                                          std::span<float const> heights, float cell_x,
                                          float cell_z, MeshConfig const& config) {
  HeightFieldBuildResult r;
  auto const fail = [&](HeightFieldError e, std::size_t item) {
    r.error = e;
    r.bad_item = item;
    return std::move(r);
  };
  if (samples_x < 2 || samples_z < 2) return fail(HeightFieldError::too_small, 0);
  std::uint64_t const cells = std::uint64_t(samples_x - 1) * (samples_z - 1);
  if (cells >= (std::uint64_t(1) << 29)) return fail(HeightFieldError::too_many_cells, 0);
  if (heights.size() != std::size_t(samples_x) * samples_z)
    return fail(HeightFieldError::size_mismatch, heights.size());
  if (!(cell_x > 0.0f) || !(cell_z > 0.0f) || !std::isfinite(cell_x) || !std::isfinite(cell_z) ||
      !std::isfinite(float(samples_x - 1) * cell_x) ||
      !std::isfinite(float(samples_z - 1) * cell_z) ||
      !(double(cell_x) * double(cell_z) >= 1.1e-19))
    return fail(HeightFieldError::bad_cell_size, 0);
  for (std::size_t i = 0; i < heights.size(); ++i)
    if (!std::isfinite(heights[i])) return fail(HeightFieldError::non_finite_height, i);

  HeightField& f = r.field;
  f.nx_ = samples_x;
  f.nz_ = samples_z;
  f.sx_ = cell_x;
  f.sz_ = cell_z;
  f.flat_cosine_ = config.flat_cosine;
  f.h_.assign(heights.begin(), heights.end());
  // Level 0: each cell's range over its four samples; then 2 x 2 blocks up to one.
  Level base;
  base.w = samples_x - 1;
  base.d = samples_z - 1;
  base.lo.resize(std::size_t(base.w) * base.d);
  base.hi.resize(base.lo.size());
  for (std::uint32_t z = 0; z < base.d; ++z)
    for (std::uint32_t x = 0; x < base.w; ++x) {
      float const a = f.height(x, z), b = f.height(x + 1, z), c = f.height(x, z + 1),
                  d = f.height(x + 1, z + 1);
      base.lo[z * base.w + x] = std::min(std::min(a, b), std::min(c, d));
      base.hi[z * base.w + x] = std::max(std::max(a, b), std::max(c, d));
    }
  f.levels_.push_back(std::move(base));
  while (f.levels_.back().w > 1 || f.levels_.back().d > 1) {
    Level const& below = f.levels_.back();
    Level up;
    up.w = (below.w + 1) / 2;
    up.d = (below.d + 1) / 2;
    up.lo.assign(std::size_t(up.w) * up.d, std::numeric_limits<float>::infinity());
    up.hi.assign(up.lo.size(), -std::numeric_limits<float>::infinity());
    for (std::uint32_t z = 0; z < below.d; ++z)
      for (std::uint32_t x = 0; x < below.w; ++x) {
        std::size_t const to = std::size_t(z / 2) * up.w + x / 2,
                          from = std::size_t(z) * below.w + x;
        up.lo[to] = std::min(up.lo[to], below.lo[from]);
        up.hi[to] = std::max(up.hi[to], below.hi[from]);
      }
    f.levels_.push_back(std::move(up));
  }
  Level const& top = f.levels_.back();
  f.bounds_ = {{0.0f, top.lo[0], 0.0f},
               {float(samples_x - 1) * cell_x, top.hi[0], float(samples_z - 1) * cell_z}};
  float const reach =
      std::max(f.bounds_.min.abs().max_element(), f.bounds_.max.abs().max_element());
  f.pad_ = reach * 0x1p-20f;
  return r;
}

Triangle HeightField::triangle(std::uint32_t t) const noexcept {
  std::uint32_t const c = t / 2, x = c % cells_x(), z = c / cells_x();
  if (t % 2 == 0) return {vertex(x, z), vertex(x, z + 1), vertex(x + 1, z)};
  return {vertex(x + 1, z), vertex(x, z + 1), vertex(x + 1, z + 1)};
}

Vec3 HeightField::face_normal(std::uint32_t t) const noexcept {
  return detail::unit_face_normal(triangle(t));
}

TriangleEdges HeightField::edges(std::uint32_t t) const noexcept {
  // Triangle 2c is (a, c, b): edge 0 a->c (x side: cell x - 1's second triangle, its edge 2),
  // edge 1 c->b (the diagonal: this cell's second triangle, its edge 0), edge 2 b->a (z side:
  // cell z - 1's second triangle, its edge 1). Triangle 2c + 1 is (b, c, d): edge 0 c<-b (the
  // diagonal: the first triangle's edge 1), edge 1 c->d (cell z + 1's first triangle, its
  // edge 2), edge 2 d->b (cell x + 1's first triangle, its edge 0).
  std::uint32_t const cx = cells_x(), cz = cells_z();
  std::uint32_t const c = t / 2, x = c % cx, z = c / cx;
  std::array<std::uint32_t, 3> n{no_triangle, no_triangle, no_triangle};
  if (t % 2 == 0) {
    if (x > 0) n[0] = 2 * (c - 1) + 1;
    n[1] = t + 1;
    if (z > 0) n[2] = 2 * (c - cx) + 1;
  } else {
    n[0] = t - 1;
    if (z + 1 < cz) n[1] = 2 * (c + cx);
    if (x + 1 < cx) n[2] = 2 * (c + 1);
  }
  Triangle const me = triangle(t);
  std::array<Vec3, 3> const v{me.a, me.b, me.c};
  Vec3 const normal = detail::unit_face_normal(me);
  TriangleEdges e;
  for (std::size_t k = 0; k < 3; ++k) {
    if (n[k] == no_triangle) continue; // boundary: the default
    e.neighbour[k] = n[k];
    Triangle const other = triangle(n[k]);
    // The neighbour's vertex off the shared edge: the one equal to neither end.
    Vec3 const p = v[k], q = v[(k + 1) % 3];
    Vec3 r = other.a;
    for (Vec3 const& w : {other.a, other.b, other.c})
      if (!w.cmpeq(p).all() && !w.cmpeq(q).all()) r = w;
    e.kind[k] = detail::edge_kind(normal, detail::unit_face_normal(other), p, r, flat_cosine_);
  }
  return e;
}

Aabb3 HeightField::block_box(std::size_t l, std::uint32_t bx, std::uint32_t bz) const noexcept {
  Level const& lv = levels_[l];
  std::uint32_t const x0 = bx << l, z0 = bz << l;
  std::uint32_t const x1 = std::min((bx + 1) << l, cells_x()),
                      z1 = std::min((bz + 1) << l, cells_z());
  std::size_t const i = std::size_t(bz) * lv.w + bx;
  return {{float(x0) * sx_ - pad_, lv.lo[i] - pad_, float(z0) * sz_ - pad_},
          {float(x1) * sx_ + pad_, lv.hi[i] + pad_, float(z1) * sz_ + pad_}};
}

float detail::ray_box_entry(Ray3 const& ray, Aabb3 const& b, float limit) noexcept {
  auto const sx = detail::slab_interval(ray.origin.x, ray.dir.x, b.min.x, b.max.x);
  auto const sy = detail::slab_interval(ray.origin.y, ray.dir.y, b.min.y, b.max.y);
  auto const sz = detail::slab_interval(ray.origin.z, ray.dir.z, b.min.z, b.max.z);
  float const tin = std::max(std::max(std::max(sx.tin, sy.tin), sz.tin), 0.0f);
  float const tout = std::min(std::min(std::min(sx.tout, sy.tout), sz.tout), limit);
  return tin <= tout ? tin : std::numeric_limits<float>::infinity();
}

MeshRayHit HeightField::ray_cast(Ray3 const& ray, float max_toi) const {
  if (!(max_toi >= 0.0f)) return {};
  detail::NearestTriangleHit nearest(ray, max_toi); // blocks are tight (up to pad_)
  walk_ray(ray, Vec3{}, max_toi, [&](std::uint32_t cell, float, float) {
    nearest.test(triangle(2 * cell), 2 * cell);
    return nearest.test(triangle(2 * cell + 1), 2 * cell + 1);
  });
  return nearest.best;
}

MeshRayHit HeightField::ray_cast(Iso3 const& pose, Ray3 const& ray, float max_toi) const {
  Ray3 const local{pose.inverse_transform_point(ray.origin),
                   pose.inverse_transform_vector(ray.dir)};
  MeshRayHit h = ray_cast(local, max_toi);
  if (h.hit()) h.normal = pose.transform_vector(h.normal);
  return h;
}

MeshClosestPoint HeightField::closest_point(Vec3 const& p, float max_distance) const {
  if (levels_.empty() || !bool(p.is_finite()) || !(max_distance >= 0.0f)) return {};
  detail::NearestTrianglePoint nearest(p, max_distance); // prunes beyond nearest.bound()
  auto const box_d2 = [&](Aabb3 const& b) {
    float const dx = std::max(std::max(b.min.x - p.x, p.x - b.max.x), 0.0f);
    float const dy = std::max(std::max(b.min.y - p.y, p.y - b.max.y), 0.0f);
    float const dz = std::max(std::max(b.min.z - p.z, p.z - b.max.z), 0.0f);
    return (dx * dx + dy * dy) + dz * dz;
  };
  struct entry {
    std::uint32_t level, bx, bz;
    float d2;
  };
  std::vector<entry> stack{{std::uint32_t(levels_.size() - 1), 0, 0, 0.0f}};
  while (!stack.empty()) {
    entry const e = stack.back();
    stack.pop_back();
    if (e.d2 > nearest.bound()) continue;
    if (e.level == 0) {
      std::uint32_t const c = e.bz * cells_x() + e.bx;
      for (std::uint32_t t = 2 * c; t < 2 * c + 2; ++t)
        nearest.test(triangle(t), t);
      continue;
    }
    Level const& below = levels_[e.level - 1];
    std::array<entry, 4> met;
    std::size_t n = 0;
    float const lim = nearest.bound();
    for (std::uint32_t j = 0; j < 2; ++j)
      for (std::uint32_t i = 0; i < 2; ++i) {
        std::uint32_t const x = 2 * e.bx + i, z = 2 * e.bz + j;
        if (x >= below.w || z >= below.d) continue;
        float const d2 = box_d2(block_box(e.level - 1, x, z));
        if (!(d2 <= lim)) continue;
        entry const c{e.level - 1, x, z, d2};
        std::size_t k = n++;
        for (; k > 0 && met[k - 1].d2 <= c.d2; --k)
          met[k] = met[k - 1];
        met[k] = c;
      }
    for (std::size_t k = 0; k < n; ++k)
      stack.push_back(met[k]);
  }
  return nearest.result();
}

MeshClosestPoint HeightField::closest_point(Iso3 const& pose, Vec3 const& p,
                                            float max_distance) const {
  MeshClosestPoint c = closest_point(pose.inverse_transform_point(p), max_distance);
  if (c.found()) c.point = pose.transform_point(c.point);
  return c;
}

} // namespace plume
