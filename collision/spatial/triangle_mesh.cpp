// TriangleMesh: validation, degenerate-triangle removal, adjacency and edge convexity, the
// BVH build and the closest-point query. The contract is in
// include/plume/spatial/triangle_mesh.hpp.
#include <plume/spatial/triangle_mesh.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace plume {

char const* to_string(MeshError e) noexcept {
  switch (e) {
  case MeshError::none:
    return "none";
  case MeshError::empty:
    return "empty: no vertices or no indices";
  case MeshError::index_count_not_multiple_of_3:
    return "index count not a multiple of 3";
  case MeshError::index_out_of_range:
    return "index out of range";
  case MeshError::non_finite_vertex:
    return "non-finite vertex";
  case MeshError::all_degenerate:
    return "every triangle is degenerate";
  case MeshError::too_many_triangles:
    return "too many triangles (2^31 or more)";
  }
  return "unknown";
}

namespace {

bool finite(Vec3 const& v) noexcept {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// Per-edge adjacency and convexity (see the header): edges sorted by their vertex pair, then
/// by (triangle, edge), so the grouping does not depend on anything but the input.
void classify_edges(std::vector<std::array<std::uint32_t, 3>> const& idx,
                    std::vector<Vec3> const& verts, std::vector<Vec3> const& normals,
                    float flat_cosine, std::vector<TriangleEdges>& out) {
  std::size_t const n = idx.size();
  out.assign(n, TriangleEdges{});
  struct half_edge {
    std::uint64_t key; // lower vertex << 32 | higher vertex
    std::uint32_t ref; // triangle * 3 + edge
  };
  std::vector<half_edge> e;
  e.reserve(3 * n);
  for (std::size_t t = 0; t < n; ++t)
    for (std::uint32_t k = 0; k < 3; ++k) {
      std::uint32_t const p = idx[t][k], q = idx[t][(k + 1) % 3];
      std::uint64_t const lo = std::min(p, q), hi = std::max(p, q);
      e.push_back({lo << 32 | hi, std::uint32_t(t * 3 + k)});
    }
  std::sort(e.begin(), e.end(), [](half_edge const& a, half_edge const& b) {
    return a.key != b.key ? a.key < b.key : a.ref < b.ref;
  });
  auto const kind_of = [&](std::uint32_t t, std::uint32_t k, std::uint32_t u) {
    // u's vertex off the shared edge.
    std::uint32_t const p = idx[t][k], q = idx[t][(k + 1) % 3];
    std::uint32_t r = idx[u][0];
    for (std::uint32_t v : idx[u])
      if (v != p && v != q) r = v;
    return detail::edge_kind(normals[t], normals[u], verts[p], verts[r], flat_cosine);
  };
  for (std::size_t i = 0; i < e.size();) {
    std::size_t j = i + 1;
    while (j < e.size() && e[j].key == e[i].key)
      ++j;
    if (j - i == 1) {
      // boundary: the default
    } else {
      bool paired = false;
      if (j - i == 2) {
        std::uint32_t const t0 = e[i].ref / 3, k0 = e[i].ref % 3;
        std::uint32_t const t1 = e[i + 1].ref / 3, k1 = e[i + 1].ref % 3;
        // Opposite directions: t0 runs p -> q, t1 runs q -> p.
        paired = idx[t0][k0] == idx[t1][(k1 + 1) % 3] && t0 != t1;
        if (paired) {
          out[t0].neighbour[k0] = t1;
          out[t1].neighbour[k1] = t0;
          out[t0].kind[k0] = kind_of(t0, k0, t1);
          out[t1].kind[k1] = kind_of(t1, k1, t0);
        }
      }
      if (!paired)
        for (std::size_t m = i; m < j; ++m)
          out[e[m].ref / 3].kind[e[m].ref % 3] = EdgeKind::non_manifold;
    }
    i = j;
  }
}

/// (b - a) x (c - a) in double: the float cross product of a large triangle overflows (its
/// length, or the products in it), which would give a zero or NaN normal.
DVec3 scaled_normal_in_double(Triangle const& t) noexcept {
  DVec3 const da{t.a.x, t.a.y, t.a.z}, db{t.b.x, t.b.y, t.b.z}, dc{t.c.x, t.c.y, t.c.z};
  return (db - da).cross(dc - da);
}

} // namespace

Vec3 detail::unit_face_normal(Triangle const& t) noexcept {
  return detail::unit_normal_in_double(t.a, t.b, t.c); // the triangle cast's, bit for bit
}

EdgeKind detail::edge_kind(Vec3 const& n, Vec3 const& m, Vec3 const& p, Vec3 const& r,
                           float flat_cosine) noexcept {
  if (n.dot(m) >= flat_cosine) return EdgeKind::flat;
  // The other triangle's vertex off the edge, measured against this one's plane.
  return n.dot(r - p) < 0.0f ? EdgeKind::convex : EdgeKind::concave;
}

MeshBuildResult TriangleMesh::build(std::span<Vec3 const> vertices,
                                    std::span<std::uint32_t const> indices,
                                    MeshConfig const& config) {
  MeshBuildResult r;
  r.input_triangles = indices.size() / 3;
  auto const fail = [&](MeshError e, std::size_t item) {
    r.error = e;
    r.bad_item = item;
    r.triangles = 0;
    return std::move(r);
  };
  if (vertices.empty() || indices.empty()) return fail(MeshError::empty, 0);
  if (indices.size() % 3 != 0)
    return fail(MeshError::index_count_not_multiple_of_3, indices.size());
  // Edge references are triangle * 3 + edge in 32 bits.
  if (r.input_triangles >= (std::size_t(1) << 30)) return fail(MeshError::too_many_triangles, 0);
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (!finite(vertices[i])) return fail(MeshError::non_finite_vertex, i);
  for (std::size_t i = 0; i < indices.size(); ++i)
    if (indices[i] >= vertices.size()) return fail(MeshError::index_out_of_range, i);

  TriangleMesh& m = r.mesh;
  m.vertices_.assign(vertices.begin(), vertices.end());
  for (std::size_t t = 0; t < r.input_triangles; ++t) {
    std::array<std::uint32_t, 3> const id{indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
    Triangle const tri{vertices[id[0]], vertices[id[1]], vertices[id[2]]};
    Vec3 const sn = tri.scaled_normal();
    float const len2 = sn.length_squared();
    bool has_area = len2 >= std::numeric_limits<float>::min();
    if (!std::isfinite(len2)) {
      // The float cross product overflowed (inf, or inf - inf): the area decides in double,
      // where it cannot.
      DVec3 const dn = scaled_normal_in_double(tri);
      has_area = dn.dot(dn) >= double(std::numeric_limits<float>::min());
    }
    if (!has_area) {
      ++r.degenerate;
      continue;
    }
    m.indices_.push_back(id);
    m.tris_.push_back(tri);
    m.normals_.push_back(detail::unit_face_normal(tri));
    m.source_.push_back(std::uint32_t(t));
  }
  if (m.tris_.empty()) {
    std::size_t const d = r.degenerate;
    MeshBuildResult out = fail(MeshError::all_degenerate, 0);
    out.degenerate = d;
    out.mesh = TriangleMesh{};
    return out;
  }
  r.triangles = m.tris_.size();
  classify_edges(m.indices_, m.vertices_, m.normals_, config.flat_cosine, m.edges_);

  TreeConfig tc;
  tc.margin = 0.0f;
  tc.margin_fraction = 0.0f;
  m.tree_ = AabbTree(tc);
  std::vector<Aabb3> boxes(m.tris_.size());
  m.bounds_ = m.tris_[0].local_aabb();
  for (std::size_t t = 0; t < m.tris_.size(); ++t) {
    boxes[t] = m.tris_[t].local_aabb();
    m.bounds_ = m.bounds_.merge(boxes[t]);
  }
  std::vector<std::uint64_t> users(boxes.size());
  for (std::size_t t = 0; t < users.size(); ++t)
    users[t] = t;
  std::vector<ProxyId> const ids = m.tree_.insert_all(boxes, users); // one binned-SAH build
  for (std::size_t t = 0; t < ids.size(); ++t)
    if (ids[t] != ProxyId(t)) throw std::logic_error("plume::TriangleMesh: proxy ids not 0..n-1");
  m.bvh_.build(m.tree_);
  m.build_blocks();
  return r;
}

void TriangleMesh::build_blocks() {
  // Leaves under each node of tree_, children before parents (an explicit post-order).
  auto const& nodes = tree_.nodes();
  std::vector<std::uint32_t> under(nodes.size(), 0);
  std::vector<std::pair<std::uint32_t, bool>> stack{{tree_.root(), false}};
  while (!stack.empty()) {
    auto const [i, done] = stack.back();
    stack.pop_back();
    AabbTree::Node const& n = nodes[i];
    if (n.is_leaf()) {
      under[i] = 1;
    } else if (done) {
      under[i] = under[n.left] + under[n.right];
    } else {
      stack.push_back({i, true});
      stack.push_back({n.right, false});
      stack.push_back({n.left, false});
    }
  }
  // The highest nodes of at most a block's triangles, left to right; each block's triangles
  // in the tree's left-to-right order.
  std::vector<std::uint32_t> tops{tree_.root()}, leaves, walk;
  while (!tops.empty()) {
    std::uint32_t const i = tops.back();
    tops.pop_back();
    if (under[i] > detail::TriangleBlock::size) {
      tops.push_back(nodes[i].right);
      tops.push_back(nodes[i].left);
      continue;
    }
    leaves.clear();
    walk.assign(1, i);
    while (!walk.empty()) {
      std::uint32_t const j = walk.back();
      walk.pop_back();
      if (nodes[j].is_leaf()) {
        leaves.push_back(nodes[j].proxy);
      } else {
        walk.push_back(nodes[j].right);
        walk.push_back(nodes[j].left);
      }
    }
    detail::TriangleBlock& b = blocks_.emplace_back();
    for (std::size_t l = 0; l < b.size; ++l) {
      std::uint32_t const t = leaves[l < leaves.size() ? l : 0];
      Triangle const& tri = tris_[t];
      b.ax[l] = tri.a.x, b.ay[l] = tri.a.y, b.az[l] = tri.a.z;
      b.bx[l] = tri.b.x, b.by[l] = tri.b.y, b.bz[l] = tri.b.z;
      b.cx[l] = tri.c.x, b.cy[l] = tri.c.y, b.cz[l] = tri.c.z;
      b.tri[l] = t;
    }
    block_root_.push_back(i);
  }
  block_bvh_ = make_block_bvh<f32xS, WideBvh::arity>();
}

Vec3 closest_point_on_triangle(Triangle const& t, Vec3 const& p) noexcept {
  Vec3 const ab = t.b - t.a, ac = t.c - t.a, ap = p - t.a;
  float const d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return t.a;
  Vec3 const bp = p - t.b;
  float const d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0f && d4 <= d3) return t.b;
  float const vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return t.a + ab * (d1 / (d1 - d3));
  Vec3 const cp = p - t.c;
  float const d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0f && d5 <= d6) return t.c;
  float const vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return t.a + ac * (d2 / (d2 - d6));
  float const va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
    return t.b + (t.c - t.b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  float const denom = 1.0f / (va + vb + vc);
  return t.a + ab * (vb * denom) + ac * (vc * denom);
}

MeshClosestPoint TriangleMesh::closest_point(Vec3 const& p, float max_distance) const {
  if (bvh_.empty() || !finite(p) || !(max_distance >= 0.0f)) return {};
  using W = WideBvh;
  using T = f32xR;
  constexpr std::size_t K = W::arity, L = lanes_v<T>;
  detail::NearestTrianglePoint nearest(p, max_distance);
  GVec3<T> const q = detail::splat3<T>(p);
  struct entry {
    std::uint32_t ref;
    float d2;
  };
  detail::TraversalStack<entry> stack;
  stack.push_back({0, 0.0f});
  // Boxes are tight and their distance rounds differently from a triangle's: prune only
  // beyond nearest.bound(), so that ties and near-ties are always decided by the triangles.
  while (!stack.empty()) {
    entry const e = stack.pop_back();
    if (e.d2 > nearest.bound()) continue;
    if (e.ref & W::leaf_bit) {
      std::uint32_t const t = e.ref & ~W::leaf_bit;
      nearest.test(tris_[t], t);
      continue;
    }
    auto const& node = bvh_.nodes()[e.ref];
    alignas(64) std::array<float, K> d2s;
    T const zero = plume::zero<T>();
    for (std::size_t g = 0; g < K / L; ++g) {
      GAabb3<T> const b = node.template box<T>(g);
      GVec3<T> const lo = b.min, hi = b.max;
      T const dx = plume::max(plume::max(lo.x - q.x, q.x - hi.x), zero);
      T const dy = plume::max(plume::max(lo.y - q.y, q.y - hi.y), zero);
      T const dz = plume::max(plume::max(lo.z - q.z, q.z - hi.z), zero);
      plume::store_aligned(&d2s[g * L], (dx * dx + dy * dy) + dz * dz);
    }
    // Nearest child popped first (pushed last); empty slots have infinite distance.
    std::array<entry, K> met;
    std::size_t n = 0;
    float const lim = nearest.bound();
    for (std::size_t i = 0; i < K; ++i) {
      if (node.child[i] == W::empty_child || !(d2s[i] <= lim)) continue;
      entry const c{node.child[i], d2s[i]};
      std::size_t j = n++;
      for (; j > 0 && met[j - 1].d2 <= c.d2; --j)
        met[j] = met[j - 1];
      met[j] = c;
    }
    for (std::size_t i = 0; i < n; ++i)
      stack.push_back(met[i]);
  }
  return nearest.result();
}

MeshClosestPoint TriangleMesh::closest_point(Iso3 const& pose, Vec3 const& p,
                                             float max_distance) const {
  MeshClosestPoint c = closest_point(pose.inverse_transform_point(p), max_distance);
  if (c.found()) c.point = pose.transform_point(c.point);
  return c;
}

} // namespace plume
