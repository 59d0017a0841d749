// plume/spatial/mesh_queries.hpp - a convex shape against a triangle mesh (TriangleMesh or
// HeightField: any TriangleSource): contact manifolds with internal-edge correction, shape
// casts and overlaps, through the mesh's BVH or the field's pyramid.
//
//   MeshContacts c = mesh_contacts(mesh, mesh_pose, Cuboid{{0.5f, 0.5f, 0.5f}}, pose);
//   for (MeshManifold const& m : c) ... m.manifold.normal (mesh -> shape), m.triangle
//   MeshShapeHit h = mesh_shape_cast(mesh, mesh_pose, Sphere{0.3f}, pose, motion, cast_cfg);
//   bool any = mesh_overlaps(mesh, mesh_pose, shape, pose, [](std::uint32_t tri) { return true; });
//
// The shape is any convex shape of collision/shapes.hpp (sphere, capsule, cuboid, cylinder,
// convex hull, triangle), placed by `pose`; the mesh is placed by `mesh_pose`; everything
// reported is in world space. Triangles are two-sided: a shape is pushed out on the side of
// each triangle where the centre of its bounding box lies, front or back.
//
// Contacts: every triangle whose box meets the shape's box grown by the prediction distance
// is collided as a Triangle (collision/manifold.hpp), in increasing triangle index. Each
// triangle's manifold has its normal from the triangle toward the shape. Then:
//  1. Internal edges and sides (MeshContactConfig::correct_internal_edges). A shape sliding
//     over the shared edge of two coplanar triangles would otherwise get the edge's normal,
//     which points along the surface (a "ghost" bump). When a manifold's normal is not the
//     face normal on the shape's side (the side the centre of its box is on; a centre in the
//     triangle's plane is in front, or behind where the normal points behind and a contact
//     point is on a feature active from behind, such as a boundary edge), further than
//     MeshContactConfig::face_cosine from it, and either points to the far side with no
//     contact point on a boundary edge (there the shape hangs over the mesh's border and
//     EPA's normal pushes it off; a non-manifold edge may be closed by a flipped neighbour or
//     a fin, so it does not count) or has every contact point on
//     the triangle on an inactive feature, the normal becomes that face
//     normal and each point's separation is measured along it (points beyond the prediction
//     distance are dropped). An edge is inactive
//     when it is flat or concave seen from the shape's side (TriangleMesh's edge kinds, with
//     convex and concave swapped behind the triangle); boundary, non-manifold and convex
//     edges are active (a shape may really touch them edge-on); a vertex is inactive when
//     every edge of the triangle through it is; a point inside the face is inactive. "On a
//     feature" means within 1e-4 times the triangle's longest edge of it.
//  2. Merging. Manifolds whose normals are within merge_cosine of each other form one group
//     (the first triangle in index order sets the group's normal); a group's points are
//     reduced to 4 as a single manifold's are. Past 64 points a group keeps its deepest
//     point (of those within a tenth of the prediction distance of the deepest, the farthest
//     from the group's centre) and its extreme points along 16 directions of the contact
//     plane, so that a large shape over many small triangles still gets points across its
//     whole footprint. Up to
//     max_mesh_manifolds groups are kept: the deepest (least separation; ties to the lower
//     triangle). A box resting across several triangles of a flat floor gets one manifold; a box in
//     a valley gets one per slope.
//  Point ids mix the triangle index into the feature id, so the same point on the same
//  triangle keeps its id across frames (warm starting), and ids stay unique in a group.
//
// Shape casts: the least time of impact over the triangles (ties to the lower triangle), each
// cast by collision/gjk.hpp's shape_cast with the same config: bit for bit the result of
// casting against every triangle. The candidates come nearest first from the mesh's tree (or
// the field's pyramid) with every box grown by the shape's box (in the mesh's frame) and the
// target distance, and a box entered later than the best time of impact found so far, plus a
// slack for the cast's tolerance and rounding, is skipped. The normal points out of the mesh
// toward the cast shape. One exception to "bit for bit": a triangle whose cast stops
// unconverged (out_of_iterations: the iteration cap, or steps GJK could not resolve) reports
// an early, conservative toi (collision/gjk.hpp) that its box may not reach, and then brute
// force can report it where this does not.
//
// Bad input: a non-finite pose gives failed contacts (none) and no cast hit or overlap; a
// non-finite motion, a NaN, negative or infinite max_toi, or a NaN, negative or infinite
// target distance gives no cast hit; an empty mesh gives nothing.
#pragma once

#include <plume/collision/gjk.hpp>
#include <plume/collision/manifold.hpp>
#include <plume/collision/shapes.hpp>
#include <plume/math/aabb3.hpp>
#include <plume/math/iso3.hpp>
#include <plume/spatial/height_field.hpp>
#include <plume/spatial/triangle_mesh.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

namespace plume {

/// What these queries need of a mesh: its triangles, their face normals and edges (as
/// TriangleMesh's), and a box query. TriangleMesh and HeightField are such meshes.
template <class M>
concept TriangleSource = requires(M const& m, std::uint32_t t, Aabb3 const& box) {
  { m.triangle(t) } -> std::convertible_to<Triangle>;
  { m.face_normal(t) } -> std::convertible_to<Vec3>;
  { m.edges(t) } -> std::convertible_to<TriangleEdges>;
  { m.triangle_count() } -> std::convertible_to<std::size_t>;
  { m.local_aabb() } -> std::convertible_to<Aabb3>;
  m.query_aabb(box, [](std::uint32_t) {});
  m.swept_query(Ray3{}, Vec3{}, 1.0f, [](std::uint32_t, float) { return 1.0f; });
};

/// The most manifolds mesh_contacts reports for one shape.
inline constexpr int max_mesh_manifolds = 4;

struct MeshContactConfig {
  ManifoldConfig manifold{};
  /// Triangles' manifolds whose normals have at least this cosine merge (about 1.1 degrees).
  float merge_cosine = 0.9998f;
  /// Face normals for contacts on flat and concave edges and vertices (see the header).
  bool correct_internal_edges = true;
  /// A triangle's manifold whose normal has at least this cosine with the face normal on the
  /// shape's side is a face contact and is kept as it is (about 1e-3 rad).
  float face_cosine = 0.9999995f;
};

/// One manifold of a shape against a mesh: normal from the mesh toward the shape (A is the
/// mesh, B the shape), and the triangle of its deepest point.
struct MeshManifold {
  Manifold manifold;
  std::uint32_t triangle = no_triangle;
};

struct MeshContacts {
  std::array<MeshManifold, max_mesh_manifolds> manifolds{};
  int count = 0;
  bool failed = false; ///< non-finite pose (count 0)
  MeshManifold const* begin() const noexcept { return manifolds.data(); }
  MeshManifold const* end() const noexcept { return manifolds.data() + count; }
  bool empty() const noexcept { return count == 0; }
};

/// A shape cast's first contact with a mesh; triangle no_triangle and toi +infinity for none.
struct MeshShapeHit {
  std::uint32_t triangle = no_triangle;
  float toi = std::numeric_limits<float>::infinity(); ///< in units of the motion
  Vec3 point{};                                       ///< world, on the mesh
  Vec3 normal{}; ///< unit, out of the mesh toward the cast shape (zero if the cores overlap)
  bool penetrating = false; ///< started within the target distance (toi 0)
  bool hit() const noexcept { return triangle != no_triangle; }
};

namespace detail {

/// Whether an edge of this kind can be touched edge-on from the front (behind: convex and
/// concave swap).
inline bool edge_active(EdgeKind k, bool behind) noexcept {
  switch (k) {
  case EdgeKind::flat:
    return false;
  case EdgeKind::convex:
    return !behind;
  case EdgeKind::concave:
    return behind;
  case EdgeKind::boundary:
  case EdgeKind::non_manifold:
    return true;
  }
  return true;
}

/// Distance from p to the segment [a, b].
inline float segment_distance(Vec3 const& p, Vec3 const& a, Vec3 const& b) noexcept {
  Vec3 const ab = b - a;
  float const l2 = ab.dot(ab);
  float const t = l2 > 0.0f ? std::clamp((p - a).dot(ab) / l2, 0.0f, 1.0f) : 0.0f;
  return (a + ab * t - p).length();
}

/// Which edges of triangle tri (edge e from vertex e to e + 1) local point p lies on, within
/// 1e-4 of the triangle's longest edge.
inline std::array<bool, 3> edges_near(Triangle const& tri, Vec3 const& p) noexcept {
  std::array<Vec3, 3> const v{tri.a, tri.b, tri.c};
  float longest = 0.0f;
  for (int e = 0; e < 3; ++e)
    longest = std::max(longest, (v[std::size_t((e + 1) % 3)] - v[std::size_t(e)]).length());
  float const tol = 1e-4f * longest;
  std::array<bool, 3> near{};
  for (std::size_t e = 0; e < 3; ++e)
    near[e] = segment_distance(p, v[e], v[(e + 1) % 3]) <= tol;
  return near;
}

/// Whether a contact at local point p of mesh triangle t lies on an active feature.
template <TriangleSource Mesh>
bool on_active_feature(Mesh const& mesh, std::uint32_t t, Vec3 const& p, bool behind) noexcept {
  std::array<bool, 3> const near = edges_near(mesh.triangle(t), p);
  TriangleEdges const edges = mesh.edges(t);
  bool any_on = false, active = false;
  for (std::size_t e = 0; e < 3; ++e)
    if (near[e]) {
      any_on = true;
      active = active || edge_active(edges.kind[e], behind);
    }
  return any_on && active; // inside the face (no edge near) counts as inactive
}

/// Whether a contact at local point p of mesh triangle t lies on a boundary edge (no other
/// triangle has it), within on_active_feature's tolerance.
template <TriangleSource Mesh>
bool on_boundary_edge(Mesh const& mesh, std::uint32_t t, Vec3 const& p) noexcept {
  std::array<bool, 3> const near = edges_near(mesh.triangle(t), p);
  TriangleEdges const edges = mesh.edges(t);
  for (std::size_t e = 0; e < 3; ++e)
    if (near[e] && edges.kind[e] == EdgeKind::boundary) return true;
  return false;
}

/// A group of triangles' contact points sharing one normal, before reduction.
struct mesh_group {
  Vec3 normal;
  std::uint32_t triangle = no_triangle; ///< of the deepest point
  float deepest = std::numeric_limits<float>::infinity();
  float depth_tolerance = 0.0f; ///< see compact()
  bool overflowed = false;      ///< compacted at least once
  candidates<float> points;
  void add(ContactPoint const& c, std::uint32_t tri) noexcept {
    if (c.separation < deepest) {
      deepest = c.separation;
      triangle = tri;
    }
    if (points.n == candidates<float>::capacity) {
      compact(depth_tolerance);
      overflowed = true;
    }
    points.add(c);
  }
  /// Keeps the deepest point and the extreme points along 16 directions of the contact plane
  /// (the first of equals), at most 17 of the 64: the extremes of all the points a group ever
  /// gathers are extremes of what is kept, so the final reduction still spans the footprint
  /// of a large shape over many small triangles. The deepest goes first; points within
  /// `tolerance` of the deepest count as deep as it, and of those the farthest from the
  /// points' centre is taken (a flat box: a corner, not a point in the middle).
  void compact(float tolerance) noexcept {
    std::array<bool, candidates<float>::capacity> keep{};
    float least = points.pts[0].separation;
    Vec3 mid{};
    for (int k = 0; k < points.n; ++k) {
      least = std::min(least, points.pts[std::size_t(k)].separation);
      mid = mid + points.pts[std::size_t(k)].point_a;
    }
    mid = mid * (1.0f / float(points.n));
    int deepest_k = -1;
    float far = -1.0f;
    for (int k = 0; k < points.n; ++k) {
      ContactPoint const& p = points.pts[std::size_t(k)];
      float const d = (p.point_a - mid).length_squared();
      if (p.separation <= least + tolerance && d > far) {
        far = d;
        deepest_k = k;
      }
    }
    keep[std::size_t(deepest_k)] = true;
    auto const basis = normal.any_orthonormal_pair();
    for (int d = 0; d < 16; ++d) {
      float const angle = float(d) * 0.39269908f; // 2 pi / 16
      Vec3 const dir = basis[0] * std::cos(angle) + basis[1] * std::sin(angle);
      int best = 0;
      for (int k = 1; k < points.n; ++k)
        if (points.pts[std::size_t(k)].point_a.dot(dir) >
            points.pts[std::size_t(best)].point_a.dot(dir))
          best = k;
      keep[std::size_t(best)] = true;
    }
    std::array<ContactPoint, candidates<float>::capacity> kept;
    int n = 0;
    kept[std::size_t(n++)] = points.pts[std::size_t(deepest_k)];
    for (int k = 0; k < points.n; ++k)
      if (keep[std::size_t(k)] && k != deepest_k)
        kept[std::size_t(n++)] = points.pts[std::size_t(k)];
    for (int k = 0; k < n; ++k)
      points.pts[std::size_t(k)] = kept[std::size_t(k)];
    points.n = n;
  }
};

/// The feature id of a point of triangle t's manifold, unique per (triangle, feature).
inline std::uint64_t mesh_point_id(std::uint64_t id, std::uint32_t t) noexcept {
  std::uint64_t z = id + (std::uint64_t(t) + 1) * 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

/// A box with its sides clamped to +-2^125: a box that big (a huge target distance or
/// prediction) still covers every triangle a float mesh can hold, and its centre, half
/// extents and rotated extents stay finite (an infinite side would give inf - inf and 0 * inf:
/// NaN, a box that meets nothing).
inline Aabb3 clamp_box(Aabb3 const& b) noexcept {
  Vec3 const big = Vec3::splat(0x1p125f);
  return {b.min.max(-big).min(big), b.max.max(-big).min(big)};
}

/// The box of a world-space box in the mesh's local frame, sides clamped to +-2^125. In
/// double, with infinite sides first clamped to float's largest: the box keeps its place
/// relative to the mesh wherever both are, even near float's largest, and an
/// infinite side gives no NaN. A NaN side gives a box that meets nothing.
inline Aabb3 to_mesh_local(Aabb3 const& world_box, Iso3 const& mesh_pose) noexcept {
  double const top = double(std::numeric_limits<float>::max());
  auto const d = [&](Vec3 const& v) {
    auto const c = [&](float x) { return x != x ? double(x) : std::clamp(double(x), -top, top); };
    return DVec3{c(v.x), c(v.y), c(v.z)};
  };
  DVec3 const lo = d(world_box.min), hi = d(world_box.max);
  Vec3 const& t = mesh_pose.translation;
  DVec3 const centre = (lo + hi) * 0.5 - DVec3{t.x, t.y, t.z}, half = (hi - lo) * 0.5;
  Mat3 const m = mesh_pose.rotation_matrix(); // local = m^T (world - t)
  auto const dv = [](Vec3 const& v) { return DVec3{v.x, v.y, v.z}; };
  GMat3<double> const r = GMat3<double>::from_cols(dv(m.x_axis), dv(m.y_axis), dv(m.z_axis));
  DVec3 const lc = r.mul_transpose_vec3(centre), lh = r.abs().mul_transpose_vec3(half);
  double const big = 0x1p125;
  auto const f = [&](DVec3 const& v) {
    auto const c = [&](double x) { return float(x != x ? x : std::clamp(x, -big, big)); };
    return Vec3{c(v.x), c(v.y), c(v.z)};
  };
  return {f(lc - lh), f(lc + lh)};
}

/// The mesh's triangles whose boxes meet a world box, in increasing index.
template <TriangleSource Mesh>
void mesh_candidates(Mesh const& mesh, Iso3 const& mesh_pose, Aabb3 const& box,
                     std::vector<std::uint32_t>& out) {
  out.clear();
  Aabb3 const local = to_mesh_local(box, mesh_pose);
  if (!bool(local.is_valid())) return;
  mesh.query_aabb(local, [&](std::uint32_t t) { out.push_back(t); });
  std::sort(out.begin(), out.end());
}

} // namespace detail

/// The contact manifolds of a convex shape (at pose) against a mesh (at mesh_pose); the
/// rules are at the top of this header.
template <TriangleSource Mesh, class Shape>
MeshContacts mesh_contacts(Mesh const& mesh, Iso3 const& mesh_pose, Shape const& shape,
                           Iso3 const& pose, MeshContactConfig const& cfg = {}) {
  MeshContacts out;
  if (!mesh_pose.is_finite() || !pose.is_finite()) {
    out.failed = true;
    return out;
  }
  Aabb3 const box = shape.aabb(pose);
  Vec3 const centre = box.min * 0.5f + box.max * 0.5f;
  std::vector<std::uint32_t> tris;
  detail::mesh_candidates(mesh, mesh_pose, box.grow(cfg.manifold.prediction), tris);
  std::vector<detail::mesh_group> groups;
  for (std::uint32_t const t : tris) {
    Manifold m = contact_manifold(mesh.triangle(t), mesh_pose, shape, pose, cfg.manifold);
    if (m.empty()) continue;
    Vec3 const face = mesh_pose.transform_vector(mesh.face_normal(t));
    // The shape's side of the triangle: where the centre of its box is. A centre in the
    // plane (within the rounding of its height and of the box) is in front, unless the
    // normal leans back and a contact point is on a feature active from behind (a boundary
    // edge the shape straddles): then behind, so a shape straddling a lone triangle is
    // pushed off the edge it overlaps, not across, and one centred on a floor goes up.
    Vec3 const corner = mesh_pose.transform_point(mesh.triangle(t).a);
    float const height = (centre - corner).dot(face);
    float const rounding = 8.0f * std::numeric_limits<float>::epsilon() *
                           (std::max(box.min.abs().max_element(), box.max.abs().max_element()) +
                            corner.abs().max_element());
    bool behind = height < 0.0f;
    if (std::abs(height) <= rounding && m.normal.dot(face) < 0.0f) {
      behind = false;
      for (ContactPoint const& c : m)
        behind = behind || detail::on_active_feature(
                               mesh, t, mesh_pose.inverse_transform_point(c.point_a), true);
    }
    float const along = m.normal.dot(behind ? -face : face);
    if (cfg.correct_internal_edges && along < cfg.face_cosine) {
      // A normal toward the far side is kept only at a boundary edge (the shape hangs over the
      // mesh's border: EPA's normal pushes it off the edge; turned to the face
      // normal, the gap measured along it can be positive where the shapes overlap, and the
      // push slides the shape further over the edge). Elsewhere it would push the shape
      // through the surface.
      bool active = false;
      for (ContactPoint const& c : m) {
        Vec3 const p = mesh_pose.inverse_transform_point(c.point_a);
        active = active || (along >= 0.0f ? detail::on_active_feature(mesh, t, p, behind)
                                          : detail::on_boundary_edge(mesh, t, p));
      }
      if (!active) {
        Vec3 const n = behind ? -face : face;
        Manifold fixed;
        fixed.normal = n;
        for (ContactPoint c : m) {
          c.separation = (c.point_b - c.point_a).dot(n);
          if (!(c.separation <= cfg.manifold.prediction)) continue;
          c.point_b = c.point_a + n * c.separation;
          fixed.points[std::size_t(fixed.count++)] = c;
        }
        m = fixed;
        if (m.empty()) continue;
      }
    }
    auto g = std::find_if(groups.begin(), groups.end(), [&](detail::mesh_group const& x) {
      return x.normal.dot(m.normal) >= cfg.merge_cosine;
    });
    if (g == groups.end()) {
      groups.push_back({});
      g = groups.end() - 1;
      g->normal = m.normal;
      g->depth_tolerance = 0.1f * cfg.manifold.prediction;
    }
    for (ContactPoint c : m) {
      c.id = detail::mesh_point_id(c.id, t);
      g->add(c, t);
    }
  }
  // The deepest groups (ties: the lower triangle), reported in that order.
  std::stable_sort(
      groups.begin(), groups.end(), [](detail::mesh_group const& a, detail::mesh_group const& b) {
        return a.deepest < b.deepest || (a.deepest == b.deepest && a.triangle < b.triangle);
      });
  for (detail::mesh_group const& g : groups) {
    if (out.count == max_mesh_manifolds) break;
    MeshManifold& mm = out.manifolds[std::size_t(out.count++)];
    mm.manifold.normal = g.normal;
    mm.triangle = g.triangle;
    if (g.overflowed) { // the final reduction sees the same kind of set each compaction kept
      detail::mesh_group last = g;
      last.compact(g.depth_tolerance);
      detail::reduce_into(last.points, g.normal, mm.manifold);
    } else {
      detail::reduce_into(g.points, g.normal, mm.manifold);
    }
  }
  return out;
}

/// The first triangle a convex shape (at pose) hits moving by t * motion, t in
/// [0, cfg.max_toi]; the rules are at the top of this header.
template <TriangleSource Mesh, class Shape>
MeshShapeHit mesh_shape_cast(Mesh const& mesh, Iso3 const& mesh_pose, Shape const& shape,
                             Iso3 const& pose, Vec3 const& motion,
                             ShapeCastConfig const& cfg = {}) {
  MeshShapeHit best;
  if (!mesh_pose.is_finite() || !pose.is_finite() || !bool(motion.is_finite()) ||
      !(cfg.max_toi >= 0.0f) || !std::isfinite(cfg.max_toi) || !(cfg.target_distance >= 0.0f) ||
      !std::isfinite(cfg.target_distance))
    return best;
  Aabb3 const start = shape.aabb(pose);
  if (!bool(start.is_valid())) return best;
  auto const test = [&](std::uint32_t t) {
    ShapeCastHit const c = shape_cast(shape, pose, motion, mesh.triangle(t), mesh_pose, cfg);
    if (!c.hit || c.failed) return;
    if (!(c.toi < best.toi || (c.toi == best.toi && t < best.triangle))) return;
    best.triangle = t;
    best.toi = c.toi;
    best.point = c.point_b;
    best.normal = -c.normal;
    best.penetrating = bool(c.penetrating);
  };
  // GJK reports a contact once the gap is within its tolerance (or the rounding floor of the
  // coordinates in play, the triangles' among them) of the target distance, so the shape's
  // box grows by that much: at any reported toi the grown box touches the triangle's box,
  // whatever the angle of approach.
  Aabb3 const bounds = mesh.local_aabb();
  float const mesh_extent = mesh.triangle_count() == 0 ? 0.0f
                                                       : std::max(bounds.min.abs().max_element(),
                                                                  bounds.max.abs().max_element());
  float const reach = std::max(pose.translation.abs().max_element(),
                               mesh_pose.translation.abs().max_element() + mesh_extent) +
                      start.size().max_element() + 1.0f;
  float const margin = 4.0f * cfg.gjk.tolerance + 64.0f * 0x1p-23f * reach;
  if (motion.abs().max_element() == 0.0f || cfg.max_toi == 0.0f) {
    // No sweep: only a start in contact can hit.
    std::vector<std::uint32_t> tris;
    detail::mesh_candidates(mesh, mesh_pose, start.grow(cfg.target_distance + margin), tris);
    for (std::uint32_t const t : tris)
      test(t);
    return best;
  }
  // The grown box in the mesh's frame, swept along the motion from its centre: a box entered
  // after the best toi so far (plus a relative rounding slack) holds no triangle that could
  // report a toi at or below it.
  Aabb3 const local =
      detail::clamp_box(detail::to_mesh_local(start, mesh_pose).grow(cfg.target_distance + margin));
  Vec3 const half = (local.max - local.min) * 0.5f, centre = (local.min + local.max) * 0.5f;
  Ray3 const sweep{centre, mesh_pose.inverse_transform_vector(motion)};
  mesh.swept_query(sweep, half, cfg.max_toi, [&](std::uint32_t t, float) {
    test(t);
    if (!best.hit()) return cfg.max_toi;
    float const bound = best.toi + (best.toi + 0x1p-20f) * 0x1p-12f;
    return bound < cfg.max_toi ? bound : cfg.max_toi;
  });
  return best;
}

/// Calls f(triangle) for each triangle the convex shape (at pose) touches or overlaps (GJK
/// distance <= 0), in increasing index; f returns false to stop (or void to visit all).
/// Returns whether any triangle touched.
template <TriangleSource Mesh, class Shape, class F>
bool mesh_overlaps(Mesh const& mesh, Iso3 const& mesh_pose, Shape const& shape, Iso3 const& pose,
                   F&& f) {
  if (!mesh_pose.is_finite() || !pose.is_finite()) return false;
  std::vector<std::uint32_t> tris;
  detail::mesh_candidates(mesh, mesh_pose, shape.aabb(pose), tris);
  bool any = false;
  for (std::uint32_t const t : tris) {
    ClosestPoints const c = closest_points(shape, pose, mesh.triangle(t), mesh_pose);
    if (c.failed || !(c.overlap || c.distance <= 0.0f)) continue;
    any = true;
    if constexpr (std::is_void_v<decltype(f(t))>) {
      f(t);
    } else {
      if (!bool(f(t))) break;
    }
  }
  return any;
}

/// Whether the convex shape (at pose) touches or overlaps any triangle of the mesh.
template <TriangleSource Mesh, class Shape>
bool mesh_intersects(Mesh const& mesh, Iso3 const& mesh_pose, Shape const& shape,
                     Iso3 const& pose) {
  return mesh_overlaps(mesh, mesh_pose, shape, pose, [](std::uint32_t) { return false; });
}

} // namespace plume
