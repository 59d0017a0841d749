// plume/spatial/aabb_tree.hpp - GAabbTree<S>: a dynamic bounding volume hierarchy of
// axis-aligned boxes (a binary tree), with stable proxy ids and a user payload per leaf.
//
//   AabbTree tree;                                    // float; GAabbTree<double> also exists
//   ProxyId a = tree.insert(Aabb3{{0, 0, 0}, {1, 1, 1}}, /*user*/ 7);
//   tree.move(a, Aabb3{{0.01f, 0, 0}, {1.01f, 1, 1}}); // inside the enlarged box: no change
//   tree.optimize();                                  // TreeOptimization::adaptive
//   tree.query(Aabb3{{-1, -1, -1}, {0.5f, 0.5f, 0.5f}}, [&](ProxyId id) { ...; return true; });
//
// Leaves store an enlarged ("fat") box: the proxy's tight box grown on every side by
// margin_for(tight) = min(margin, margin_fraction x the tight box's largest extent), Box2D's
// rule (defaults 0.05 length units and 0.125; TreeConfig::scaled changes the
// unit). move() changes nothing while the new tight box stays inside the fat box; otherwise
// the leaf gets a new fat box, its ancestors are enlarged at once (queries stay exact), and
// the leaf is remembered as moved. optimize() then restores the tree's quality:
//   reinsert         each moved leaf is taken out and inserted again (SAH sibling search);
//   partial_rebuild  the inner nodes above moved leaves are dissolved and rebuilt (by the
//                    config's builder) over the subtrees that hang off them;
//   full_rebuild     every inner node is rebuilt over all leaves;
//   adaptive         by the fraction f of moved leaves: f < 0.15 reinsert, f < 0.45 partial
//                    rebuild, else full rebuild (Avian 0.6's thresholds).
// Insertion finds the sibling of least SAH cost by branch and bound over the whole tree (the
// exact optimum of that greedy step, not Box2D's single-path descent). Builds are top-down
// binned SAH by default, or bottom-up PLOC (TreeConfig::builder). Identical boxes
// inserted one by one all tie with the root and form a chain; insert_all() or rebuild()
// balances them (a million boxes at one point give height ceil(log2 N)).
//
// Determinism: the tree is scalar code on S; the same operations in the same order give the
// same tree (node for node) in every build, and queries report leaves in an order fixed by
// the tree. Proxy ids are reused (last freed, first reused).
//
// Bad input: insert() and move() throw std::invalid_argument for a box with a NaN or
// infinite coordinate or min > max on some axis, and leave the tree unchanged. Every call
// taking a ProxyId throws std::out_of_range for an id that names no live proxy (never
// inserted, or removed). validate() checks every invariant and returns what is broken.
#pragma once

#include <plume/collision/ray_cast.hpp>
#include <plume/math/aabb3.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace plume {

/// A leaf of a tree, stable from insert() to remove().
using ProxyId = std::uint32_t;
inline constexpr ProxyId null_proxy = 0xffffffffu;

enum class TreeOptimization : std::uint8_t { reinsert, partial_rebuild, full_rebuild, adaptive };

/// How rebuild(), insert_all() and the rebuilding optimisations build a tree.
enum class TreeBuilder : std::uint8_t {
  binned_sah, ///< top-down, 16 bins per axis on the centroids (Wald 2007)
  ploc,       ///< bottom-up, PLOC (Meister and Bittner 2018) with search radius ploc_radius
};

/// The margin rule of a tree's enlarged boxes.
template <Float S>
struct GTreeConfig {
  S margin = S(0.05);           ///< at most this much on every side (length units)
  S margin_fraction = S(0.125); ///< at most this fraction of the tight box's largest extent
  /// adaptive: below this fraction of moved leaves reinsert, below the next partial rebuild.
  S reinsert_below = S(0.15);
  S partial_below = S(0.45);
  /// The full builder (docs/spatial.md compares the two: binned SAH is the default).
  TreeBuilder builder = TreeBuilder::binned_sah;
  /// PLOC: each cluster looks for its nearest neighbour among this many on either side in
  /// Morton order (1 to 64; larger is slower and closer to a full SAH search).
  int ploc_radius = 8;

  /// The same rule for another length unit (1 for metres, 100 for centimetres, ...).
  GTreeConfig scaled(S length_unit) const noexcept {
    GTreeConfig c = *this;
    c.margin = margin * length_unit;
    return c;
  }
  /// min(margin, margin_fraction x the largest extent of the tight box): never negative.
  S margin_for(GAabb3<S> const& tight) const noexcept;
};
using TreeConfig = GTreeConfig<float>;

/// Measures of a tree's quality.
template <Float S>
struct GTreeStats {
  std::size_t proxies = 0;
  std::size_t nodes = 0; ///< inner nodes and leaves
  int height = 0;        ///< edges on the longest root-to-leaf path (0: a single leaf or none)
  /// SAH cost relative to the root: the sum of every inner node's surface area over the
  /// root's (1 for one inner node; grows with overlap; lower is better).
  S area_ratio = 0;
};

template <Float S>
class GAabbTree {
public:
  using Box = GAabb3<S>;
  using Config = GTreeConfig<S>;
  static constexpr std::uint32_t null_node = 0xffffffffu;

  /// A node of the binary tree. Leaves have left == null_node and name their proxy.
  struct Node {
    Box box; ///< fat box (leaf) or the union of the children's boxes
    std::uint32_t parent = null_node;
    std::uint32_t left = null_node;
    std::uint32_t right = null_node;
    std::uint32_t proxy = null_proxy; ///< the leaf's proxy; null_proxy for inner nodes
    std::int32_t height = 0;          ///< 0 for leaves; -1 for a free node
    bool flagged = false;             ///< partial rebuild: on a path from the root to a moved leaf
    bool is_leaf() const noexcept { return left == null_node; }
  };

  explicit GAabbTree(Config const& config = {}) : config_(config) {}

  Config const& config() const noexcept { return config_; }

  // ---------------------------------------------------------------- edits
  /// A new leaf for the tight box `tight`, carrying `user`. Throws std::invalid_argument for
  /// a non-finite or inverted box (the tree is unchanged).
  ProxyId insert(Box const& tight, std::uint64_t user = 0);
  /// Many leaves at once: the tight boxes `tight` with payloads `user` (0 where `user` is
  /// shorter), then one binned-SAH rebuild of the whole tree instead of a sibling search per
  /// leaf. Returns the new ids in order. Throws std::invalid_argument if any box is unusable,
  /// before changing anything.
  std::vector<ProxyId> insert_all(std::span<Box const> tight,
                                  std::span<std::uint64_t const> user = {});
  /// Removes the proxy; its id may be reused by a later insert().
  void remove(ProxyId id);
  /// The proxy's tight box is now `tight`. Returns true when it left the fat box (the leaf got
  /// a new fat box and counts as moved), false when nothing in the tree changed.
  bool move(ProxyId id, Box const& tight);
  /// Sets the payload.
  void set_user(ProxyId id, std::uint64_t user);
  /// Removes every proxy (ids start again from 0).
  void clear() noexcept;

  // ---------------------------------------------------------------- optimisation
  /// Restores quality after moves (see above) and forgets the moved leaves. Returns the mode
  /// it ran (what adaptive chose; reinsert when nothing moved).
  TreeOptimization optimize(TreeOptimization mode = TreeOptimization::adaptive);
  /// Every inner node rebuilt by binned SAH over all leaves.
  void rebuild();
  /// Every inner node's box recomputed from its children (moves only ever enlarge them).
  void refit() noexcept;
  /// Leaves moved since the last optimize() (in the order they first moved).
  std::size_t moved_count() const noexcept { return dirty_.size(); }

  // ---------------------------------------------------------------- proxies
  bool contains(ProxyId id) const noexcept {
    return id < proxies_.size() && proxies_[id].leaf != null_node;
  }
  std::size_t size() const noexcept { return live_; }
  bool empty() const noexcept { return live_ == 0; }
  std::uint64_t user(ProxyId id) const { return proxy(id).user; }
  Box const& tight_box(ProxyId id) const { return proxy(id).tight; }
  Box const& fat_box(ProxyId id) const { return nodes_[proxy(id).leaf].box; }
  /// Every live proxy id, in increasing order.
  std::vector<ProxyId> proxy_ids() const;

  // ---------------------------------------------------------------- queries
  /// f(ProxyId) for every leaf whose fat box intersects `box` (touching counts); f returns
  /// false to stop. Infinite bounds are allowed (-inf..+inf meets every leaf); a box with a
  /// NaN, or min > max on some axis, meets nothing.
  template <class F>
  void query(Box const& box, F&& f) const;
  /// f(ProxyId, entry) for every leaf whose fat box the ray enters at a distance entry in
  /// [0, max_toi] (units of ray.dir), depth first, nearer child first; f returns the new
  /// max_toi (return max_toi to go on, a smaller value to clip, a negative one to stop). A ray
  /// with a non-finite origin or direction, or a zero direction, meets nothing.
  template <class F>
  void ray_query(GRay3<S> const& ray, S max_toi, F&& f) const;
  /// A packet of rays, one per lane of T (S, or a batch of S): f(ProxyId, lanes) for every
  /// leaf whose fat box the ray of some lane enters within that lane's max_toi, `lanes` being
  /// the bitmask of those lanes; f may lower lanes of max_toi (a negative one ends the lane).
  /// Lanes with a negative or NaN max_toi, or an unusable ray (non-finite, zero direction),
  /// take no part. Each lane's box tests compute what ray_query's do (the same operations, so
  /// the same entries), so a lane meets every leaf ray_query meets with the same max_toi;
  /// nodes are visited nearer first by the nearest lane's entry. Coherent rays share the
  /// nodes' loads and tests; incoherent ones visit the union of their paths.
  template <Real T, class F>
  void ray_query_lanes(GRay3<T> const& rays, T& max_toi, F&& f) const;

  // ---------------------------------------------------------------- structure
  std::uint32_t root() const noexcept { return root_; }
  /// Every node slot (free ones have height -1), for traversal by GWideBvh and tests.
  std::span<Node const> nodes() const noexcept { return nodes_; }
  GTreeStats<S> stats() const noexcept;
  /// Every invariant: parents contain their children, links agree both ways, heights are
  /// right, every live proxy is in exactly one leaf and its fat box contains its tight box,
  /// no free node is reachable. Returns "" when all hold, else the first broken one.
  std::string validate() const;

private:
  struct Proxy {
    Box tight;
    std::uint64_t user = 0;
    std::uint32_t leaf = null_node; ///< null_node: free
    bool dirty = false;             ///< in dirty_
  };
  Proxy const& proxy(ProxyId id) const;
  std::uint32_t allocate_node();
  ProxyId new_leaf(Box const& tight, std::uint64_t user);
  void free_node(std::uint32_t n);
  void insert_leaf(std::uint32_t leaf);
  void remove_leaf(std::uint32_t leaf);
  std::uint32_t find_best_sibling(Box const& box);
  void refit_upwards(std::uint32_t n) noexcept;
  void reinsert_dirty();
  void partial_rebuild();
  std::uint32_t build(std::span<std::uint32_t> prims); ///< config_.builder over nodes; the root
  std::uint32_t build_sah(std::span<std::uint32_t> prims);
  std::uint32_t build_ploc(std::span<std::uint32_t> prims);

  Config config_;
  std::vector<Node> nodes_;
  std::vector<Proxy> proxies_;
  std::vector<std::uint32_t> free_nodes_;
  std::vector<ProxyId> free_proxies_;
  std::vector<ProxyId> dirty_;
  std::uint32_t root_ = null_node;
  std::size_t live_ = 0;
  // Scratch, kept to avoid allocations.
  struct Candidate {
    S cost;
    std::uint32_t node;
  };
  std::vector<Candidate> heap_;
  std::vector<std::uint32_t> prims_;
};

using AabbTree = GAabbTree<float>;

extern template struct GTreeConfig<float>;
extern template struct GTreeConfig<double>;
extern template class GAabbTree<float>;
extern template class GAabbTree<double>;

// ------------------------------------------------------------------------ queries

namespace detail {
/// A traversal stack: 128 entries in place, then on the heap (a tree has no height bound).
template <class E>
class TraversalStack {
public:
  void push_back(E const& e) {
    if (size_ < inline_.size())
      inline_[size_] = e;
    else
      spill_.push_back(e);
    ++size_;
  }
  E pop_back() noexcept {
    --size_;
    if (size_ < inline_.size()) return inline_[size_];
    E e = spill_.back();
    spill_.pop_back();
    return e;
  }
  bool empty() const noexcept { return size_ == 0; }

private:
  std::array<E, 128> inline_;
  std::vector<E> spill_;
  std::size_t size_ = 0;
};

/// Entry and exit of a ray (origin o, direction with reciprocal inv, sign `neg` per axis)
/// into box b, clipped to [0, max_toi]: NaN crossings (an origin on a plane of a slab it lies
/// in, with a zero direction on that axis) are skipped, so they never turn a hit into a miss.
/// Exits are conservative: computed with |inv| enlarged by 2^-20 (inv_far), so the rounding
/// of the slab arithmetic (a few ulps of t) never rejects a box a ray grazes at an edge or
/// corner, where a triangle's own test, with its rounding, may hit.
/// Sign is bool (one ray: every lane of T tests the same ray against other boxes) or mask_t<T>
/// (a ray per lane, each with its own signs); the arithmetic is the same, so a lane of the
/// second gives the first's entry and verdict bit for bit.
template <Real T, class Sign = bool>
struct ray_slab_setup {
  GVec3<T> origin, inv, inv_far;
  Sign neg[3];
};
template <Real T>
PLUME_INLINE GVec3<T> slab_inv_far(GVec3<T> const& inv) noexcept {
  return inv * splat<T>(scalar_t<T>(1) + scalar_t<T>(0x1p-20));
}
template <Real T>
PLUME_INLINE ray_slab_setup<T> make_ray_slab(GVec3<T> const& origin, GVec3<T> const& dir,
                                             bool const neg[3]) noexcept {
  T const one = plume::one<T>();
  GVec3<T> const inv{one / dir.x, one / dir.y, one / dir.z};
  return {origin, inv, slab_inv_far(inv), {neg[0], neg[1], neg[2]}};
}
/// A ray per lane: each lane's signs from its direction (inv < 0 is signbit(dir), 1/-0 being
/// -inf).
template <Real T>
PLUME_INLINE ray_slab_setup<T, mask_t<T>> make_ray_slab_lanes(GVec3<T> const& origin,
                                                              GVec3<T> const& dir) noexcept {
  T const one = plume::one<T>(), zero = plume::zero<T>();
  GVec3<T> const inv{one / dir.x, one / dir.y, one / dir.z};
  return {origin, inv, slab_inv_far(inv), {inv.x < zero, inv.y < zero, inv.z < zero}};
}
/// `neg ? hi : lo`, per lane for a mask.
template <Real T, class Sign>
PLUME_INLINE T slab_pick(Sign neg, T const& hi, T const& lo) noexcept {
  if constexpr (std::is_same_v<Sign, bool>)
    return neg ? hi : lo;
  else
    return plume::select(neg, hi, lo);
}
/// The box entry distance (>= 0) where the ray meets box [lo, hi] before max_toi, and a mask.
template <Real T, class Sign>
PLUME_INLINE mask_t<T> ray_enters(ray_slab_setup<T, Sign> const& r, GVec3<T> const& lo,
                                  GVec3<T> const& hi, T max_toi, T& entry) noexcept {
  T const nx = (slab_pick(r.neg[0], hi.x, lo.x) - r.origin.x) * r.inv.x;
  T const fx = (slab_pick(r.neg[0], lo.x, hi.x) - r.origin.x) * r.inv_far.x;
  T const ny = (slab_pick(r.neg[1], hi.y, lo.y) - r.origin.y) * r.inv.y;
  T const fy = (slab_pick(r.neg[1], lo.y, hi.y) - r.origin.y) * r.inv_far.y;
  T const nz = (slab_pick(r.neg[2], hi.z, lo.z) - r.origin.z) * r.inv.z;
  T const fz = (slab_pick(r.neg[2], lo.z, hi.z) - r.origin.z) * r.inv_far.z;
  // max_select/min_select return their second argument for a NaN first one.
  T const tn = plume::max_select(nz, plume::max_select(ny, plume::max_select(nx, zero<T>())));
  T const tf = plume::min_select(fz, plume::min_select(fy, plume::min_select(fx, max_toi)));
  entry = tn;
  return tn <= tf;
}
/// Finite origin and direction, direction not zero.
template <Real S>
inline bool usable_ray(GRay3<S> const& ray) noexcept {
  GVec3<S> const d = ray.dir;
  return plume::all(ray_valid(ray)) && !(d.x == S(0) && d.y == S(0) && d.z == S(0));
}
} // namespace detail

template <Float S>
template <class F>
void GAabbTree<S>::query(Box const& box, F&& f) const {
  if (root_ == null_node || !bool(box.min.cmple(box.max).all())) return;
  detail::TraversalStack<std::uint32_t> stack;
  stack.push_back(root_);
  while (!stack.empty()) {
    std::uint32_t const n = stack.pop_back();
    Node const& node = nodes_[n];
    if (!node.box.intersects(box)) continue;
    if (node.is_leaf()) {
      if (!f(ProxyId(node.proxy))) return;
    } else {
      stack.push_back(node.right);
      stack.push_back(node.left); // left first
    }
  }
}

template <Float S>
template <class F>
void GAabbTree<S>::ray_query(GRay3<S> const& ray, S max_toi, F&& f) const {
  if (root_ == null_node || !detail::usable_ray(ray) || !(max_toi >= S(0))) return;
  bool const neg[3] = {std::signbit(ray.dir.x), std::signbit(ray.dir.y), std::signbit(ray.dir.z)};
  auto const r = detail::make_ray_slab(ray.origin, ray.dir, neg);
  detail::TraversalStack<std::uint32_t> stack;
  stack.push_back(root_);
  while (!stack.empty()) {
    std::uint32_t const n = stack.pop_back();
    Node const& node = nodes_[n];
    S entry;
    if (!detail::ray_enters(r, node.box.min, node.box.max, max_toi, entry)) continue;
    if (node.is_leaf()) {
      max_toi = f(ProxyId(node.proxy), entry);
      if (!(max_toi >= S(0))) return;
      continue;
    }
    Node const& l = nodes_[node.left];
    Node const& rt = nodes_[node.right];
    S el, er;
    bool const hl = detail::ray_enters(r, l.box.min, l.box.max, max_toi, el);
    bool const hr = detail::ray_enters(r, rt.box.min, rt.box.max, max_toi, er);
    // Push the farther one first so the nearer is popped first (left on ties).
    if (hl && hr) {
      if (er < el) {
        stack.push_back(node.left);
        stack.push_back(node.right);
      } else {
        stack.push_back(node.right);
        stack.push_back(node.left);
      }
    } else if (hl) {
      stack.push_back(node.left);
    } else if (hr) {
      stack.push_back(node.right);
    }
  }
}

template <Float S>
template <Real T, class F>
void GAabbTree<S>::ray_query_lanes(GRay3<T> const& rays, T& max_toi, F&& f) const {
  static_assert(std::is_same_v<scalar_t<T>, S>, "rays of the tree's scalar type");
  if (root_ == null_node) return;
  T const zero_t = zero<T>(), one_t = one<T>();
  GVec3<T> const d = rays.dir;
  mask_t<T> const usable =
      detail::ray_valid(rays) & ((d.x != zero_t) | (d.y != zero_t) | (d.z != zero_t));
  max_toi = plume::select(usable & (max_toi >= zero_t), max_toi, -one_t);
  // ray_query's slab test with each lane's own signs: each lane's entry and verdict are the
  // one-ray walk's.
  auto const r = detail::make_ray_slab_lanes(rays.origin, d);
  auto const enters = [&](Box const& b, T& entry) {
    return detail::ray_enters(r, GVec3<T>(b.min), GVec3<T>(b.max), max_toi, entry);
  };
  S const inf = std::numeric_limits<S>::infinity();
  auto const nearest = [&](T const& entry, mask_t<T> const& m) {
    return plume::reduce_min(plume::select(m, entry, T(inf)));
  };
  detail::TraversalStack<std::uint32_t> stack;
  stack.push_back(root_);
  while (!stack.empty()) {
    std::uint32_t const n = stack.pop_back();
    Node const& node = nodes_[n];
    T entry;
    std::uint64_t const bits = plume::bitmask(enters(node.box, entry));
    if (bits == 0) continue;
    if (node.is_leaf()) {
      f(ProxyId(node.proxy), bits);
      continue;
    }
    T el, er;
    mask_t<T> const ml = enters(nodes_[node.left].box, el);
    mask_t<T> const mr = enters(nodes_[node.right].box, er);
    bool const bl = plume::any(ml), br = plume::any(mr);
    if (bl && br) { // the farther one first, so the nearer is popped first (left on ties)
      bool const right_first = nearest(er, mr) < nearest(el, ml);
      stack.push_back(right_first ? node.left : node.right);
      stack.push_back(right_first ? node.right : node.left);
    } else if (bl) {
      stack.push_back(node.left);
    } else if (br) {
      stack.push_back(node.right);
    }
  }
}

} // namespace plume
