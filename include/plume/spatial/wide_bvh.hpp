// plume/spatial/wide_bvh.hpp - GWideBvh<T, K>: a K-ary copy of a GAabbTree for fast queries.
// Each node keeps its K children's boxes coordinate by coordinate (an array of K per
// coordinate), so one ray or box is tested against all of a node's children in K / lanes_v<T>
// batch operations; the scalar build runs the same template with T = float, one child per
// group. The layout depends on S and K only: every query can read the tree with another batch
// U whose lanes divide K (ray_query<U>(...)), with the same results, which is how each
// instruction set of a PLUME_DISPATCH=ON build walks one stored tree at its own width.
//
//   AabbTree tree;  ...inserts...;  tree.rebuild();
//   WideBvh bvh(tree);                     // T = f32xS, K = max(4, stored_lanes): 4, 8 or 16
//   auto hit = bvh.ray_cast(ray, 100.0f, [&](ProxyId id, float max_toi) {
//     return toi_of_my_shape(id, ray, max_toi);   // +infinity (or > max_toi) for a miss
//   });
//   if (hit.hit()) use(hit.proxy, hit.toi);
//
// The copy is built from the tree's shape (each wide node takes the binary node's two children
// and opens the inner child of largest surface area until it has K, Wald's collapse) and
// does not follow later edits: build() again after the tree changes (O(n)).
//
// Results do not depend on T or K: ray_cast() returns the least toi the leaf callback gives,
// ties to the lower proxy id, among the leaves whose fat boxes the ray enters within max_toi
// (pruning is conservative: a node is skipped only when the ray enters its box beyond the
// best toi so far, and rounding is monotone, so a parent's entry never exceeds a child's).
// That holds when each leaf callback returns a toi at or beyond the ray's entry into the
// leaf's fat box, as any shape inside its box does (fat boxes add a margin, so rounding of
// the shape's own cast cannot undercut the box's entry).
//
// Traversal order: nearest entry first (ties to the lower child slot). Rays with a NaN or
// infinite origin or direction, or a zero direction, and negative or NaN max_toi meet
// nothing; max_toi may be +infinity.
#pragma once

#include <plume/numerics/memory.hpp>
#include <plume/spatial/aabb_tree.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace plume {

/// The closest hit of a tree ray cast: proxy null_proxy and toi +infinity for none.
template <Float S>
struct GTreeRayHit {
  ProxyId proxy = null_proxy;
  S toi = std::numeric_limits<S>::infinity();
  bool hit() const noexcept { return proxy != null_proxy; }
};
using TreeRayHit = GTreeRayHit<float>;

/// The default node width: the batch's lanes, but never fewer than 4 children.
template <Real T>
inline constexpr std::size_t default_arity_v = lanes_v<T> < 4 ? 4 : lanes_v<T>;

/// A node of K children, child c's box in lane c of each coordinate's array: the same type
/// for every batch that reads it.
template <Float S, std::size_t K>
struct alignas(64) WideBvhNode {
  std::array<S, K> lo_x, lo_y, lo_z, hi_x, hi_y, hi_z;
  std::array<std::uint32_t, K> child;

  /// The boxes of children g * lanes_v<U> .. (g + 1) * lanes_v<U> - 1 as lanes of U.
  template <Real U>
  PLUME_INLINE GAabb3<U> box(std::size_t g) const noexcept {
    static_assert(std::is_same_v<scalar_t<U>, S> && K % lanes_v<U> == 0);
    std::size_t const o = g * lanes_v<U>;
    return {{plume::load_aligned<U>(&lo_x[o]), plume::load_aligned<U>(&lo_y[o]),
             plume::load_aligned<U>(&lo_z[o])},
            {plume::load_aligned<U>(&hi_x[o]), plume::load_aligned<U>(&hi_y[o]),
             plume::load_aligned<U>(&hi_z[o])}};
  }
};

template <Real T, std::size_t K = default_arity_v<T>>
class GWideBvh {
public:
  using S = scalar_t<T>;
  /// The default reading batch's lanes and groups per node (a query given another U reads
  /// K / lanes_v<U> groups).
  static constexpr std::size_t lanes = lanes_v<T>;
  static constexpr std::size_t arity = K;
  static constexpr std::size_t groups = K / lanes;
  static_assert(K % lanes == 0 && K >= 2 && K <= 64, "K: a multiple of the lanes, 2..64");

  /// A child reference: a node index, or leaf_bit | proxy id, or empty_child.
  static constexpr std::uint32_t leaf_bit = 0x80000000u;
  static constexpr std::uint32_t empty_child = 0xffffffffu;

  using Node = WideBvhNode<S, K>;

  GWideBvh() = default;
  explicit GWideBvh(GAabbTree<S> const& tree) { build(tree); }

  /// A copy of the tree's current shape and fat boxes. Throws std::length_error for proxy
  /// ids of 2^31 - 1 or more.
  void build(GAabbTree<S> const& tree) {
    build(tree, [](std::uint32_t) { return null_proxy; });
  }
  /// The same copy cut short: each binary node n for which leaf_of(n) is not null_proxy (the
  /// highest such node on each path) becomes a leaf with that id, its subtree left out; leaves
  /// of the tree above no such node keep their proxy ids. A leaf then stands for a block of
  /// primitives its caller tests together (TriangleMesh's triangle blocks). The same limit on
  /// ids.
  template <class LeafOf>
  void build(GAabbTree<S> const& tree, LeafOf&& leaf_of);

  bool empty() const noexcept { return nodes_.empty(); }
  std::size_t node_count() const noexcept { return nodes_.size(); }
  std::size_t leaf_count() const noexcept { return leaves_; }
  std::vector<Node> const& nodes() const noexcept { return nodes_; }

  // Every query reads the nodes lanes_v<U> children at a time: U = T unless given
  // (bvh.template ray_query<f32x8>(...)), any element type of scalar S whose lanes divide K;
  // the results do not depend on it.

  /// f(ProxyId, entry) for each leaf whose fat box the ray enters at entry in [0, max_toi],
  /// nearest first within each node; f returns the new max_toi (max_toi to go on, smaller to
  /// clip, negative to stop).
  template <Real U = T, class F>
  void ray_query(GRay3<S> const& ray, S max_toi, F&& f) const {
    walk_ray<U, false>(ray, GVec3<S>{}, max_toi, f, [](ProxyId) {});
  }
  /// ray_query that also calls met(ProxyId) for each leaf the ray enters as its node is
  /// visited, before f reaches it (or not, when the search stops or prunes first): the time
  /// to prefetch the leaf's data. met must not change anything f or the results depend on.
  template <Real U = T, class F, class Met>
  void ray_query(GRay3<S> const& ray, S max_toi, F&& f, Met&& met) const {
    walk_ray<U, false>(ray, GVec3<S>{}, max_toi, f, met);
  }
  /// ray_query with every fat box grown by `grow` (>= 0) on each side: the leaves a box of
  /// half extents `grow` centred on the ray's origin may meet while it moves along the ray
  /// (a shape cast's candidates, nearest first).
  template <Real U = T, class F>
  void swept_query(GRay3<S> const& ray, GVec3<S> const& grow, S max_toi, F&& f) const {
    walk_ray<U, true>(ray, grow, max_toi, f, [](ProxyId) {});
  }

  /// The least toi the leaf cast gives, ties to the lower proxy; leaf(ProxyId, S max_toi)
  /// returns the toi of the proxy's shape (a value above max_toi, e.g. +infinity, is a miss).
  template <Real U = T, class LeafCast>
  GTreeRayHit<S> ray_cast(GRay3<S> const& ray, S max_toi, LeafCast&& leaf) const;

  /// f(ProxyId) for each leaf whose fat box intersects `box` (touching counts), in the tree's
  /// order; f returns false to stop. Infinite bounds are allowed; a box with a NaN, or
  /// min > max on some axis, meets nothing.
  template <Real U = T, class F>
  void query(GAabb3<S> const& box, F&& f) const;

private:
  template <Real U, bool Grown, class F, class Met>
  void walk_ray(GRay3<S> const& ray, GVec3<S> const& grow, S max_toi, F& f, Met&& on_met) const;

  std::vector<Node> nodes_;
  std::size_t leaves_ = 0;
};

/// The tree of the structures that outlive a call (a mesh's trees, the broad phase's static
/// copy): stored_lanes children, at least 4 (f32xN's lanes in a static build, 8 in a
/// PLUME_DISPATCH=ON build); kernels read it with f32xR (bvh.template ray_query<f32xR>(...)).
using WideBvh = GWideBvh<f32xS, (stored_lanes < 4 ? 4 : stored_lanes)>;

// ------------------------------------------------------------------------ build

namespace detail {
/// Asks for every cache line of *p ahead of its use (a hint: no effect on results).
template <class N>
PLUME_INLINE void prefetch_node(N const* p) noexcept {
  for (std::size_t o = 0; o < sizeof(N); o += 64)
    __builtin_prefetch(reinterpret_cast<char const*>(p) + o);
}

template <Real T>
PLUME_INLINE GVec3<T> splat3(GVec3<scalar_t<T>> const& v) noexcept {
  return {plume::splat<T>(v.x), plume::splat<T>(v.y), plume::splat<T>(v.z)};
}
} // namespace detail

template <Real T, std::size_t K>
template <class LeafOf>
void GWideBvh<T, K>::build(GAabbTree<S> const& tree, LeafOf&& leaf_of) {
  nodes_.clear();
  leaves_ = 0;
  auto const& bin = tree.nodes();
  std::uint32_t const root = tree.root();
  if (root == GAabbTree<S>::null_node) return;
  using BinNode = typename GAabbTree<S>::Node;
  // The leaf id of binary node i, or null_proxy for an inner node this copy opens.
  auto const leaf_id = [&](std::uint32_t i) -> ProxyId {
    ProxyId const cut = leaf_of(i);
    return cut != null_proxy ? cut : bin[i].is_leaf() ? bin[i].proxy : null_proxy;
  };
  auto const leaf_ref = [&](ProxyId id) {
    // 0x7fffffff would spell empty_child with the leaf bit.
    if (id >= leaf_bit - 1)
      throw std::length_error("plume::GWideBvh: proxy id of 2^31 - 1 or more");
    ++leaves_;
    return leaf_bit | id;
  };
  // Each task: fill wide node `slot` from binary node `from`.
  struct Task {
    std::uint32_t slot, from;
  };
  std::vector<Task> tasks;
  nodes_.emplace_back();
  tasks.push_back({0, root});
  while (!tasks.empty()) {
    Task const t = tasks.back();
    tasks.pop_back();
    // Open the inner child of largest area until there are K children (Wald's collapse).
    std::array<std::uint32_t, K> kids{};
    std::size_t n = 0;
    if (leaf_id(t.from) != null_proxy) {
      kids[n++] = t.from;
    } else {
      kids[n++] = bin[t.from].left;
      kids[n++] = bin[t.from].right;
    }
    while (n < K) {
      std::size_t best = K;
      S best_area = S(-1);
      for (std::size_t i = 0; i < n; ++i) {
        BinNode const& c = bin[kids[i]];
        if (leaf_id(kids[i]) != null_proxy) continue;
        S const a = c.box.surface_area();
        if (a > best_area) {
          best_area = a;
          best = i;
        }
      }
      if (best == K) break;
      std::uint32_t const opened = kids[best];
      for (std::size_t i = n; i > best + 1; --i)
        kids[i] = kids[i - 1];
      kids[best] = bin[opened].left;
      kids[best + 1] = bin[opened].right;
      ++n;
    }
    std::array<S, K> lo_x, lo_y, lo_z, hi_x, hi_y, hi_z;
    std::array<std::uint32_t, K> child;
    S const inf = std::numeric_limits<S>::infinity();
    for (std::size_t i = 0; i < K; ++i) {
      if (i >= n) {
        lo_x[i] = lo_y[i] = lo_z[i] = inf; // EMPTY: no ray or box meets it
        hi_x[i] = hi_y[i] = hi_z[i] = -inf;
        child[i] = empty_child;
        continue;
      }
      BinNode const& c = bin[kids[i]];
      lo_x[i] = c.box.min.x, lo_y[i] = c.box.min.y, lo_z[i] = c.box.min.z;
      hi_x[i] = c.box.max.x, hi_y[i] = c.box.max.y, hi_z[i] = c.box.max.z;
      if (ProxyId const id = leaf_id(kids[i]); id != null_proxy) {
        child[i] = leaf_ref(id);
      } else {
        child[i] = std::uint32_t(nodes_.size());
        nodes_.emplace_back();
        tasks.push_back({child[i], kids[i]});
      }
    }
    Node& node = nodes_[t.slot];
    node.child = child;
    node.lo_x = lo_x, node.lo_y = lo_y, node.lo_z = lo_z;
    node.hi_x = hi_x, node.hi_y = hi_y, node.hi_z = hi_z;
  }
}

// ------------------------------------------------------------------------ queries

template <Real T, std::size_t K>
template <Real U, bool Grown, class F, class Met>
void GWideBvh<T, K>::walk_ray(GRay3<S> const& ray, GVec3<S> const& grow, S max_toi, F& f,
                              Met&& on_met) const {
  static_assert(std::is_same_v<scalar_t<U>, S> && K % lanes_v<U> == 0,
                "a reading batch of the tree's scalar whose lanes divide its arity");
  constexpr std::size_t L = lanes_v<U>;
  if (nodes_.empty() || !detail::usable_ray(ray) || !(max_toi >= S(0))) return;
  [[maybe_unused]] GVec3<U> const g3 = detail::splat3<U>(grow);
  bool const neg[3] = {std::signbit(ray.dir.x), std::signbit(ray.dir.y), std::signbit(ray.dir.z)};
  auto const r =
      detail::make_ray_slab(detail::splat3<U>(ray.origin), detail::splat3<U>(ray.dir), neg);
  struct Entry {
    std::uint32_t ref;
    S entry;
  };
  detail::TraversalStack<Entry> stack;
  stack.push_back({0, S(0)});
  while (!stack.empty()) {
    Entry const e = stack.pop_back();
    if (e.entry > max_toi) continue;
    if (e.ref & leaf_bit) {
      max_toi = f(ProxyId(e.ref & ~leaf_bit), e.entry);
      if (!(max_toi >= S(0))) return;
      continue;
    }
    Node const& node = nodes_[e.ref];
    alignas(64) std::array<S, K> entry;
    std::uint64_t bits = 0;
    U const limit = plume::splat<U>(max_toi);
    for (std::size_t g = 0; g < K / L; ++g) {
      GAabb3<U> const b = node.template box<U>(g);
      U en;
      mask_t<U> m;
      if constexpr (Grown)
        m = detail::ray_enters(r, b.min - g3, b.max + g3, limit, en);
      else
        m = detail::ray_enters(r, b.min, b.max, limit, en);
      plume::store_aligned(&entry[g * L], en);
      bits |= plume::bitmask(m) << (g * L);
    }
    // The children met, farthest pushed first (ties: higher slot first), nearest on top.
    std::array<Entry, K> met;
    std::size_t n = 0;
    for (; bits; bits &= bits - 1) {
      auto const i = std::size_t(std::countr_zero(bits));
      if (node.child[i] == empty_child) continue; // never entered (EMPTY box); kept safe
      // The children's memory is asked for now, while the sort and the siblings run.
      if (node.child[i] & leaf_bit)
        on_met(ProxyId(node.child[i] & ~leaf_bit));
      else
        detail::prefetch_node(&nodes_[node.child[i]]);
      Entry const c{node.child[i], entry[i]};
      std::size_t j = n++;
      for (; j > 0 && met[j - 1].entry <= c.entry; --j) // descending entry, ties: higher slot first
        met[j] = met[j - 1];
      met[j] = c;
    }
    for (std::size_t i = 0; i < n; ++i)
      stack.push_back(met[i]);
  }
}

template <Real T, std::size_t K>
template <Real U, class LeafCast>
auto GWideBvh<T, K>::ray_cast(GRay3<S> const& ray, S max_toi, LeafCast&& leaf) const
    -> GTreeRayHit<S> {
  GTreeRayHit<S> best;
  if (!(max_toi >= S(0))) return best;
  S limit = max_toi;
  ray_query<U>(ray, max_toi, [&](ProxyId id, S) {
    S const t = leaf(id, limit);
    // +infinity is a miss even for an infinite max_toi (where it is not above the limit).
    if (t <= limit && t < std::numeric_limits<S>::infinity() && (t < limit || id < best.proxy) &&
        t >= S(0)) {
      best.proxy = id;
      best.toi = t;
      limit = t;
    }
    return limit;
  });
  return best;
}

template <Real T, std::size_t K>
template <Real U, class F>
void GWideBvh<T, K>::query(GAabb3<S> const& box, F&& f) const {
  static_assert(std::is_same_v<scalar_t<U>, S> && K % lanes_v<U> == 0,
                "a reading batch of the tree's scalar whose lanes divide its arity");
  constexpr std::size_t L = lanes_v<U>;
  if (nodes_.empty() || !bool(box.min.cmple(box.max).all())) return;
  GAabb3<U> const q{detail::splat3<U>(box.min), detail::splat3<U>(box.max)};
  detail::TraversalStack<std::uint32_t> stack;
  stack.push_back(0);
  while (!stack.empty()) {
    std::uint32_t const ref = stack.pop_back();
    if (ref & leaf_bit) {
      if (!f(ProxyId(ref & ~leaf_bit))) return;
      continue;
    }
    Node const& node = nodes_[ref];
    std::uint64_t bits = 0;
    for (std::size_t g = 0; g < K / L; ++g)
      bits |= plume::bitmask(node.template box<U>(g).intersects(q)) << (g * L);
    // Highest slot pushed first, so slot order is kept.
    while (bits) {
      auto const i = std::size_t(63 - std::countl_zero(bits));
      // An unused slot's EMPTY box meets a query box with infinite bounds: skip it.
      if (node.child[i] != empty_child) stack.push_back(node.child[i]);
      bits &= ~(std::uint64_t(1) << i);
    }
  }
}

} // namespace plume
