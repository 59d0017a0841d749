// plume/spatial/triangle_mesh.hpp - TriangleMesh: a static triangle soup with a BVH, for ray
// casts, box queries and closest points, and per-edge adjacency for internal-edge handling.
//
//   auto r = TriangleMesh::build(vertices, indices);   // 3 indices per triangle
//   if (!r.ok()) report(r.error, r.bad_item);
//   TriangleMesh const& mesh = r.mesh;
//   MeshRayHit h = mesh.ray_cast(Ray3{o, d}, 100.0f);   // closest hit, local frame
//   mesh.query_aabb(box, [&](std::uint32_t tri) { ...; return true; });
//   MeshClosestPoint c = mesh.closest_point(p, 1.0f);
//
// Units are the vertices' (float, the mesh's local frame); the *(pose, ...) forms take the
// query in world space and place the mesh by pose (rigid). Triangle indices name the mesh's
// triangles 0..triangle_count()-1, the input triangles in input order without the dropped
// degenerate ones (source_triangle(i) gives the input index).
//
// Build: rejects (error, nothing built) an empty vertex or index list, an index count not a
// multiple of 3, an index >= vertex count, a NaN or infinite coordinate; drops (and counts)
// degenerate triangles: |(b - a) x (c - a)|^2 below the smallest normal float, which includes
// repeated vertices and collinear ones; rejects a mesh with no triangle left. Every kept
// triangle gets a tight box (margin 0) in a GAabbTree<float> rebuilt once by binned SAH and
// a WideBvh copy (stored_lanes children per node, at least 4) for the box, swept and
// closest-point queries. Rays use a second copy whose leaves are triangle blocks: each
// highest subtree of at most triangle_block_size triangles is one leaf, its triangles stored
// lane by lane (detail::TriangleBlock), so a ray meets a whole leaf in one batch operation
// per lanes_v<f32xR> triangles. The queries written here as templates (ray casts, box and
// swept queries) run at the calling code's width: f32xR of its own instruction set, also in
// a PLUME_DISPATCH=ON build; closest_point runs at the library's.
//
// Ray casts: watertight per triangle (ray_cast_local(GTriangle)): a ray through a shared edge
// or vertex of consistently wound triangles hits exactly one. Back faces: both faces are hit;
// normal is the unit face normal turned to face the ray (normal . dir <= 0), and `back` says
// the ray came from behind (the side opposite (b - a) x (c - a)). The result is the least toi
// in [0, max_toi] (inclusive, units of |dir|), ties to the lower triangle index: the same
// bits as casting against every triangle, at every node width. A ray with a non-finite or
// zero direction, a non-finite origin, or a NaN or negative max_toi hits nothing.
//
// Adjacency (by vertex index: weld vertices first if the input repeats positions): edge e of
// triangle t runs from vertex e to vertex (e + 1) % 3 of t. An edge shared by exactly two
// triangles that run it in opposite directions has that neighbour and a kind: flat when the
// unit normals' cosine is >= MeshConfig::flat_cosine, else convex when the neighbour's third
// vertex is below t's plane (a ridge), concave when above (a valley). An edge of one triangle
// is boundary; of three or more, or of two with the same direction, non_manifold (no
// neighbour).
//
// Determinism: scalar code throughout but for the node tests of the wide copy (exact
// comparisons); the same input gives the same mesh, tree and query results in every build.
#pragma once

#include <plume/collision/ray_cast.hpp>
#include <plume/collision/shapes.hpp>
#include <plume/math/aabb3.hpp>
#include <plume/math/iso3.hpp>
#include <plume/spatial/aabb_tree.hpp>
#include <plume/spatial/wide_bvh.hpp>

#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace plume {

inline constexpr std::uint32_t no_triangle = 0xffffffffu;

/// Triangles per leaf of a mesh's ray tree: 8, or stored_lanes if more (16 in a static
/// AVX-512 build). The leaves and their boxes differ between builds; ray results do not.
inline constexpr std::size_t triangle_block_size = stored_lanes > 8 ? stored_lanes : 8;

namespace detail {
/// Up to triangle_block_size triangles stored lane by lane: lane i is triangle tri[i]; unused
/// lanes repeat lane 0 (a repeated triangle cannot change a least (toi, index) search).
/// 320 bytes for 8 lanes: five cache lines.
struct alignas(64) TriangleBlock {
  static constexpr std::size_t size = triangle_block_size;
  std::array<float, size> ax, ay, az, bx, by, bz, cx, cy, cz;
  std::array<std::uint32_t, size> tri;

  /// The lanes that hold the block's own triangles (the first ones; the rest repeat lane 0).
  std::size_t count() const noexcept {
    std::size_t n = 1;
    while (n < size && tri[n] != tri[0])
      ++n;
    return n;
  }

  /// Lanes first .. first + lanes_v<T> as a batch triangle (first a multiple of lanes_v<T>).
  template <Real T>
  PLUME_INLINE GTriangle<T> load(std::size_t first) const noexcept {
    auto const l = [&](std::array<float, size> const& a) {
      return plume::load_aligned<T>(a.data() + first);
    };
    return {{l(ax), l(ay), l(az)}, {l(bx), l(by), l(bz)}, {l(cx), l(cy), l(cz)}};
  }
};
static_assert(triangle_block_size % lanes_v<f32xS> == 0 &&
              triangle_block_size % lanes_v<f32xR> == 0);
static_assert(sizeof(TriangleBlock) == 40 * triangle_block_size, "no padding");
} // namespace detail

enum class MeshError : std::uint8_t {
  none,
  empty, ///< no vertices or no indices
  index_count_not_multiple_of_3,
  index_out_of_range, ///< bad_item: the position in the index list
  non_finite_vertex,  ///< bad_item: the vertex
  all_degenerate,     ///< every triangle had zero area
  too_many_triangles, ///< 2^30 or more (edge references are 32-bit)
};
char const* to_string(MeshError e) noexcept;

enum class EdgeKind : std::uint8_t { boundary, convex, flat, concave, non_manifold };

/// A triangle's three edges (edge e: vertex e to vertex (e + 1) % 3).
struct TriangleEdges {
  std::array<std::uint32_t, 3> neighbour{no_triangle, no_triangle, no_triangle};
  std::array<EdgeKind, 3> kind{EdgeKind::boundary, EdgeKind::boundary, EdgeKind::boundary};
};

struct MeshConfig {
  /// Two faces meeting at an edge are flat when the cosine of the angle between their unit
  /// normals is at least this (0.99999: about 0.26 degrees).
  float flat_cosine = 0.99999f;
};

/// The closest hit of a mesh ray cast; triangle no_triangle and toi +infinity for none.
struct MeshRayHit {
  std::uint32_t triangle = no_triangle;
  float toi = std::numeric_limits<float>::infinity();
  Vec3 normal{}; ///< unit face normal facing the ray (world for the posed form)
  bool back = false;
  bool hit() const noexcept { return triangle != no_triangle; }
};

/// The nearest point of the mesh; triangle no_triangle and distance +infinity for none.
struct MeshClosestPoint {
  std::uint32_t triangle = no_triangle;
  Vec3 point{}; ///< on the triangle (world for the posed form)
  float distance = std::numeric_limits<float>::infinity();
  bool found() const noexcept { return triangle != no_triangle; }
};

struct MeshBuildResult;

class TriangleMesh {
public:
  TriangleMesh() = default; ///< an empty mesh: every query finds nothing

  static MeshBuildResult build(std::span<Vec3 const> vertices,
                               std::span<std::uint32_t const> indices,
                               MeshConfig const& config = {});

  std::size_t triangle_count() const noexcept { return tris_.size(); }
  bool empty() const noexcept { return tris_.empty(); }
  std::span<Vec3 const> vertices() const noexcept { return vertices_; }
  Triangle const& triangle(std::uint32_t t) const noexcept { return tris_[t]; }
  std::span<Triangle const> triangles() const noexcept { return tris_; }
  std::array<std::uint32_t, 3> const& triangle_indices(std::uint32_t t) const noexcept {
    return indices_[t];
  }
  std::uint32_t source_triangle(std::uint32_t t) const noexcept { return source_[t]; }
  TriangleEdges const& edges(std::uint32_t t) const noexcept { return edges_[t]; }
  /// Unit normal of the front face, (b - a) x (c - a) normalised.
  Vec3 const& face_normal(std::uint32_t t) const noexcept { return normals_[t]; }
  Aabb3 local_aabb() const noexcept { return bounds_; }
  /// The binary tree (proxy id = triangle index, tight boxes), for other wide copies.
  AabbTree const& tree() const noexcept { return tree_; }
  WideBvh const& bvh() const noexcept { return bvh_; }
  /// The ray tree: a copy of tree() whose leaves are blocks (proxy id = block index).
  WideBvh const& block_bvh() const noexcept { return block_bvh_; }
  std::span<detail::TriangleBlock const> blocks() const noexcept { return blocks_; }
  /// Another copy of the ray tree (any T and K: ray_cast_blocks_with gives the same hits).
  template <Real T, std::size_t K = default_arity_v<T>>
  GWideBvh<T, K> make_block_bvh() const {
    GWideBvh<T, K> b;
    std::vector<ProxyId> block_of(tree_.nodes().size(), null_proxy);
    for (std::size_t k = 0; k < block_root_.size(); ++k)
      block_of[block_root_[k]] = ProxyId(k);
    b.build(tree_, [&](std::uint32_t node) { return block_of[node]; });
    return b;
  }

  // ------------------------------------------------------------------ queries
  /// The ray through the ray tree, lanes_v<U> nodes' children and triangles at a time: U =
  /// f32xR (the calling code's width), float, or a batch whose lanes divide
  /// WideBvh::arity and triangle_block_size; the result does not depend on U.
  template <Real U = f32xR>
  MeshRayHit ray_cast(Ray3 const& ray, float max_toi) const {
    return ray_cast_blocks<U>(block_bvh_, ray, max_toi);
  }
  /// The ray in world space, the mesh placed by pose; normal in world space.
  template <Real U = f32xR>
  MeshRayHit ray_cast(Iso3 const& pose, Ray3 const& ray, float max_toi) const {
    Ray3 const local{pose.inverse_transform_point(ray.origin),
                     pose.inverse_transform_vector(ray.dir)};
    MeshRayHit h = ray_cast<U>(local, max_toi);
    if (h.hit()) h.normal = pose.transform_vector(h.normal);
    return h;
  }
  /// The same cast through another copy of tree() (GWideBvh<T, K>(mesh.tree())), one
  /// triangle per leaf: the same result for every T and K.
  template <Real T, std::size_t K>
  MeshRayHit ray_cast_with(GWideBvh<T, K> const& bvh, Ray3 const& ray, float max_toi) const;
  /// The same cast through a copy of the ray tree (make_block_bvh<T, K>()), each block's
  /// triangles tested lanes_v<T> at a time: the same result for every T and K. A tree with
  /// another leaf count (a copy of tree(), or another mesh's) throws std::invalid_argument.
  template <Real T, std::size_t K>
  MeshRayHit ray_cast_blocks_with(GWideBvh<T, K> const& block_bvh, Ray3 const& ray,
                                  float max_toi) const {
    return ray_cast_blocks<T>(block_bvh, ray, max_toi);
  }

  /// f(triangle) for each triangle whose box meets `box` (touching counts), in the tree's
  /// order; f returns false to stop (or void to visit all). A box with a NaN meets nothing.
  template <class F>
  void query_aabb(Aabb3 const& box, F&& f) const;

  /// f(triangle, entry) for each triangle whose box, grown by `grow` (>= 0) on each side, the
  /// ray enters at entry in [0, max_toi], nearest first; f returns the new max_toi (smaller
  /// to clip, negative to stop). A box of half extents `grow` swept from the ray's origin
  /// along it meets only these triangles' boxes: a shape cast's candidates.
  template <class F>
  void swept_query(Ray3 const& ray, Vec3 const& grow, float max_toi, F&& f) const {
    bvh_.template swept_query<f32xR>(ray, grow, max_toi, [&](ProxyId id, float entry) {
      return float(f(std::uint32_t(id), entry));
    });
  }

  /// The nearest point of the mesh at distance <= max_distance from p (ties to the lower
  /// triangle). A non-finite p or a NaN or negative max_distance finds nothing.
  MeshClosestPoint closest_point(Vec3 const& p, float max_distance) const;
  MeshClosestPoint closest_point(Iso3 const& pose, Vec3 const& p, float max_distance) const;

private:
  void build_blocks(); ///< blocks_, block_root_ and block_bvh_ from tree_
  /// ray_cast_blocks_with, the tree read with U.
  template <Real U, Real T, std::size_t K>
  MeshRayHit ray_cast_blocks(GWideBvh<T, K> const& block_bvh, Ray3 const& ray, float max_toi) const;
  std::vector<Vec3> vertices_;
  std::vector<std::array<std::uint32_t, 3>> indices_;
  std::vector<Triangle> tris_;
  std::vector<Vec3> normals_;
  std::vector<std::uint32_t> source_;
  std::vector<TriangleEdges> edges_;
  Aabb3 bounds_{};
  AabbTree tree_;
  WideBvh bvh_;
  std::vector<detail::TriangleBlock> blocks_;
  std::vector<std::uint32_t> block_root_; ///< block k: the tree_ node it was cut at
  WideBvh block_bvh_;
};

struct MeshBuildResult {
  MeshError error = MeshError::none;
  std::size_t input_triangles = 0; ///< indices / 3
  std::size_t triangles = 0;       ///< kept
  std::size_t degenerate = 0;      ///< dropped for zero area
  std::size_t bad_item = 0;        ///< the offending index position or vertex (see MeshError)
  TriangleMesh mesh;               ///< empty unless ok()
  bool ok() const noexcept { return error == MeshError::none; }
};

/// The point of triangle t nearest p (Ericson, Real-Time Collision Detection 5.1.5).
Vec3 closest_point_on_triangle(Triangle const& t, Vec3 const& p) noexcept;

namespace detail {
/// The unit normal of (b - a) x (c - a), computed in double (a float cross product of a large
/// triangle overflows), rounded to float; zero for a degenerate triangle.
Vec3 unit_face_normal(Triangle const& t) noexcept;
/// The kind of an edge starting at p of a triangle with unit normal n, shared with a triangle
/// of unit normal m whose vertex off the edge is r (the rule at the top of this header).
EdgeKind edge_kind(Vec3 const& n, Vec3 const& m, Vec3 const& p, Vec3 const& r,
                   float flat_cosine) noexcept;

/// A ray's least (toi, triangle) over triangles tried one by one in any order, as the mesh's
/// and the height field's traversals find it. Their boxes are tight, so a triangle's rounded
/// toi can fall a few ulps before the rounded entry of its box: test() returns best + slack
/// as the traversal's bound, so that no triangle whose toi could tie or beat the best is
/// pruned, which makes the result the least (toi, index) over all triangles.
struct NearestTriangleHit {
  Ray3 ray;
  float max_toi, scale, limit;
  MeshRayHit best;
  // The watertight test's set-up for this ray, as ray_cast_local(GTriangle) makes it per
  // lane: the permuted axes k[0..2] (z last), the shear and the ray's validity.
  std::array<int, 3> k;
  float sx, sy, sz;
  bool valid;
  NearestTriangleHit(Ray3 const& r, float max) noexcept : ray(r), max_toi(max), limit(max) {
    Vec3 const ao = r.origin.abs(), ad = r.dir.abs();
    float const dmax = std::max(std::max(ad.x, ad.y), ad.z);
    scale = (std::max(std::max(ao.x, ao.y), ao.z) + 1.0f) / dmax;
    bool const kz_x = (ad.x >= ad.y) & (ad.x >= ad.z);
    bool const kz_y = (ad.y >= ad.z) & !kz_x;
    int const kz = kz_x   ? 0
                   : kz_y ? 1
                          : 2,
              kx0 = kz_x   ? 1
                    : kz_y ? 2
                           : 0,
              ky0 = kz_x   ? 2
                    : kz_y ? 0
                           : 1;
    float const d[3] = {r.dir.x, r.dir.y, r.dir.z};
    bool const flip = d[kz] < 0.0f;
    k = {flip ? ky0 : kx0, flip ? kx0 : ky0, kz};
    sx = d[k[0]] / d[kz], sy = d[k[1]] / d[kz], sz = 1.0f / d[kz];
    valid = ray_valid(r);
  }
  /// Casts against triangle t; returns the bound beyond which a box holds nothing better.
  float test(Triangle const& tri, std::uint32_t t) noexcept {
    RayHit const h = ray_cast_local(tri, ray, limit);
    if (h.hit && (h.toi < limit || t < best.triangle)) {
      best.triangle = t;
      best.toi = h.toi;
      best.normal = h.normal;
      best.back = h.feature == 1.0f;
      limit = h.toi;
    }
    return bound();
  }
  /// Casts against every triangle of a block, lanes_v<T> at a time; the same best and bound
  /// as test() on each of its triangles in turn.
  template <Real T>
  float test_block(TriangleBlock const& b) noexcept {
    static_assert(TriangleBlock::size % lanes_v<T> == 0, "a block is whole batches");
    using V = GVec3<T>;
    using Lanes = std::array<float, TriangleBlock::size>;
    V const d = detail::splat3<T>(ray.dir);
    float const o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
    T const ox = plume::splat<T>(o[k[0]]), oy = plume::splat<T>(o[k[1]]),
            oz = plume::splat<T>(o[k[2]]);
    T const tsx = plume::splat<T>(sx), tsy = plume::splat<T>(sy), tsz = plume::splat<T>(sz);
    mask_t<T> const tvalid = valid ? all_lanes<T>() : no_lanes<T>();
    Lanes const* const pa[3] = {&b.ax, &b.ay, &b.az};
    Lanes const* const pb[3] = {&b.bx, &b.by, &b.bz};
    Lanes const* const pc[3] = {&b.cx, &b.cy, &b.cz};
    for (std::size_t g = 0; g < TriangleBlock::size; g += lanes_v<T>) {
      // ray_cast_local(b.load<T>(g), ray, limit) with the ray's set-up done once: the
      // permutation picks arrays instead of selecting lanes. The test does not use the normal,
      // so it is computed (the same bits) only for a batch with a hit.
      auto const perm = [&](Lanes const* const* p) {
        auto const l = [&](int axis) { return plume::load_aligned<T>(p[axis]->data() + g); };
        return V{l(k[0]) - ox, l(k[1]) - oy, l(k[2]) - oz};
      };
      GRayHit<T> const h =
          detail::watertight_sheared(perm(pa), perm(pb), perm(pc), tsx, tsy, tsz, V{},
                                     no_lanes<T>(), tvalid, plume::splat<T>(limit));
      std::uint64_t bits = plume::bitmask(h.hit);
      if (bits == 0) continue;
      V const n = detail::triangle_unit_normal(b.load<T>(g));
      mask_t<T> const back = n.dot(d) > zero<T>();
      V const facing = V::select(back, -n, n);
      alignas(64) std::array<float, lanes_v<T>> toi;
      plume::store_aligned(toi.data(), h.toi);
      for (; bits; bits &= bits - 1) {
        auto const i = std::size_t(std::countr_zero(bits));
        std::uint32_t const t = b.tri[g + i];
        // Every lane was cast with the limit at the batch's start: a lane must also beat what
        // an earlier lane of the batch found.
        if (toi[i] < limit || (toi[i] == limit && t < best.triangle)) {
          best.triangle = t;
          best.toi = toi[i];
          best.normal = {plume::lane(facing.x, i), plume::lane(facing.y, i),
                         plume::lane(facing.z, i)};
          best.back = plume::lane(back, i);
          limit = toi[i];
        }
      }
    }
    return bound();
  }
  /// best + slack: beyond it a box holds nothing better.
  float bound() const noexcept {
    float const next = limit + (limit + scale) * 0x1p-12f;
    return next < max_toi ? next : max_toi;
  }
};

/// A point's nearest triangle (least squared distance, ties to the lower index) over
/// triangles tried one by one, as the mesh's and the height field's traversals find it; a box
/// is worth visiting while its squared distance is at most bound() (a relative slack, since
/// boxes round differently from triangles).
struct NearestTrianglePoint {
  Vec3 p;
  float best_d2;
  MeshClosestPoint best;
  NearestTrianglePoint(Vec3 const& point, float max_distance) noexcept
      : p(point), best_d2(std::isinf(max_distance) ? max_distance : max_distance * max_distance) {}
  float bound() const noexcept { return best_d2 + best_d2 * 0x1p-10f; }
  void test(Triangle const& tri, std::uint32_t t) noexcept {
    Vec3 const c = closest_point_on_triangle(tri, p);
    float const d2 = (p - c).length_squared();
    if (d2 < best_d2 || (d2 == best_d2 && t < best.triangle)) {
      best_d2 = d2;
      best.triangle = t;
      best.point = c;
    }
  }
  MeshClosestPoint result() const noexcept {
    MeshClosestPoint r = best;
    if (r.found()) r.distance = std::sqrt(best_d2);
    return r;
  }
};
} // namespace detail

// ------------------------------------------------------------------------ templates

template <Real T, std::size_t K>
MeshRayHit TriangleMesh::ray_cast_with(GWideBvh<T, K> const& bvh, Ray3 const& ray,
                                       float max_toi) const {
  if (!(max_toi >= 0.0f)) return {};
  detail::NearestTriangleHit nearest(ray, max_toi); // node boxes are tight (margin 0)
  Triangle const* const tris = tris_.data();
  bvh.ray_query(ray, max_toi, [&](ProxyId id, float) { return nearest.test(tris[id], id); });
  return nearest.best;
}

template <Real U, Real T, std::size_t K>
MeshRayHit TriangleMesh::ray_cast_blocks(GWideBvh<T, K> const& block_bvh, Ray3 const& ray,
                                         float max_toi) const {
  // Leaf ids index blocks_: a tree of triangle leaves would read past them.
  if (block_bvh.leaf_count() != blocks_.size())
    throw std::invalid_argument("plume::TriangleMesh::ray_cast_blocks_with: not this mesh's "
                                "block tree (make_block_bvh)");
  if (!(max_toi >= 0.0f)) return {};
  detail::NearestTriangleHit nearest(ray, max_toi); // block boxes are tight (margin 0)
  detail::TriangleBlock const* const blocks = blocks_.data();
  block_bvh.template ray_query<U>(
      ray, max_toi, [&](ProxyId id, float) { return nearest.template test_block<U>(blocks[id]); },
      [&](ProxyId id) { detail::prefetch_node(&blocks[id]); });
  return nearest.best;
}

template <class F>
void TriangleMesh::query_aabb(Aabb3 const& box, F&& f) const {
  bvh_.template query<f32xR>(box, [&](ProxyId id) {
    if constexpr (std::is_void_v<decltype(f(std::uint32_t(id)))>) {
      f(std::uint32_t(id));
      return true;
    } else {
      return bool(f(std::uint32_t(id)));
    }
  });
}

} // namespace plume
