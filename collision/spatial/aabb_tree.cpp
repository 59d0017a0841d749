// GAabbTree<S>: edits, SAH insertion by branch and bound, binned-SAH (re)builds, the
// optimisation modes and the validator. The contract is in include/plume/spatial/aabb_tree.hpp.
#include <plume/spatial/aabb_tree.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace plume {

namespace {

template <Float S>
bool box_usable(GAabb3<S> const& b) noexcept {
  return bool(b.is_valid());
}

template <Float S>
S area(GAabb3<S> const& b) noexcept {
  return b.surface_area();
}

template <Float S>
S axis_of(GVec3<S> const& v, int axis) noexcept {
  return axis == 0 ? v.x : axis == 1 ? v.y : v.z;
}

} // namespace

template <Float S>
S GTreeConfig<S>::margin_for(GAabb3<S> const& tight) const noexcept {
  GVec3<S> const e = tight.size();
  S const extent = std::max(std::max(e.x, e.y), e.z);
  S const m = std::min(margin, margin_fraction * extent);
  return m > S(0) ? m : S(0); // a NaN or negative setting gives exact boxes
}

// ------------------------------------------------------------------------ proxies and nodes

template <Float S>
typename GAabbTree<S>::Proxy const& GAabbTree<S>::proxy(ProxyId id) const {
  if (!contains(id))
    throw std::out_of_range("plume::AabbTree: proxy id " + std::to_string(id) +
                            " names no live proxy (never inserted, or removed)");
  return proxies_[id];
}

template <Float S>
std::uint32_t GAabbTree<S>::allocate_node() {
  if (!free_nodes_.empty()) {
    std::uint32_t const n = free_nodes_.back();
    free_nodes_.pop_back();
    nodes_[n] = Node{};
    return n;
  }
  nodes_.push_back(Node{});
  return std::uint32_t(nodes_.size() - 1);
}

template <Float S>
void GAabbTree<S>::free_node(std::uint32_t n) {
  nodes_[n] = Node{};
  nodes_[n].height = -1;
  free_nodes_.push_back(n);
}

template <Float S>
std::vector<ProxyId> GAabbTree<S>::proxy_ids() const {
  std::vector<ProxyId> ids;
  ids.reserve(live_);
  for (std::size_t i = 0; i < proxies_.size(); ++i)
    if (proxies_[i].leaf != null_node) ids.push_back(ProxyId(i));
  return ids;
}

/// A proxy id (the last freed first) and its leaf node with the fat box, not yet linked.
template <Float S>
ProxyId GAabbTree<S>::new_leaf(Box const& tight, std::uint64_t user) {
  ProxyId id;
  if (!free_proxies_.empty()) {
    id = free_proxies_.back();
    free_proxies_.pop_back();
  } else {
    id = ProxyId(proxies_.size());
    proxies_.push_back(Proxy{});
  }
  std::uint32_t const leaf = allocate_node();
  nodes_[leaf].box = tight.grow(config_.margin_for(tight));
  nodes_[leaf].proxy = id;
  proxies_[id] = Proxy{tight, user, leaf, false};
  ++live_;
  return id;
}

template <Float S>
ProxyId GAabbTree<S>::insert(Box const& tight, std::uint64_t user) {
  if (!box_usable(tight))
    throw std::invalid_argument("plume::AabbTree::insert: the box has a NaN or infinite "
                                "coordinate, or min > max on some axis");
  if (live_ >= null_proxy - 1) throw std::length_error("plume::AabbTree: too many proxies");
  ProxyId const id = new_leaf(tight, user);
  insert_leaf(proxies_[id].leaf);
  return id;
}

template <Float S>
std::vector<ProxyId> GAabbTree<S>::insert_all(std::span<Box const> tight,
                                              std::span<std::uint64_t const> user) {
  for (std::size_t k = 0; k < tight.size(); ++k)
    if (!box_usable(tight[k]))
      throw std::invalid_argument("plume::AabbTree::insert_all: box " + std::to_string(k) +
                                  " has a NaN or infinite coordinate, or min > max on some axis");
  if (tight.size() >= std::size_t(null_proxy - 1) - live_)
    throw std::length_error("plume::AabbTree: too many proxies");
  std::vector<ProxyId> ids;
  ids.reserve(tight.size());
  proxies_.reserve(proxies_.size() + tight.size());
  nodes_.reserve(nodes_.size() + 2 * tight.size());
  for (std::size_t k = 0; k < tight.size(); ++k) {
    ids.push_back(new_leaf(tight[k], k < user.size() ? user[k] : 0));
  }
  rebuild(); // every leaf, old and new; forgets the moved leaves as rebuild() does
  return ids;
}

template <Float S>
void GAabbTree<S>::remove(ProxyId id) {
  std::uint32_t const leaf = proxy(id).leaf;
  remove_leaf(leaf);
  free_node(leaf);
  if (proxies_[id].dirty) dirty_.erase(std::find(dirty_.begin(), dirty_.end(), id));
  proxies_[id] = Proxy{};
  free_proxies_.push_back(id);
  --live_;
}

template <Float S>
bool GAabbTree<S>::move(ProxyId id, Box const& tight) {
  std::uint32_t const leaf = proxy(id).leaf;
  if (!box_usable(tight))
    throw std::invalid_argument("plume::AabbTree::move: the box has a NaN or infinite "
                                "coordinate, or min > max on some axis");
  Proxy& p = proxies_[id];
  p.tight = tight;
  if (bool(nodes_[leaf].box.contains_aabb(tight))) return false;
  nodes_[leaf].box = tight.grow(config_.margin_for(tight));
  // Enlarge the ancestors so every query stays exact before optimize().
  for (std::uint32_t a = nodes_[leaf].parent; a != null_node; a = nodes_[a].parent) {
    Box const merged = nodes_[nodes_[a].left].box.merge(nodes_[nodes_[a].right].box);
    nodes_[a].box = nodes_[a].box.merge(merged);
  }
  if (!p.dirty) {
    p.dirty = true;
    dirty_.push_back(id);
  }
  return true;
}

template <Float S>
void GAabbTree<S>::set_user(ProxyId id, std::uint64_t user) {
  (void)proxy(id);
  proxies_[id].user = user;
}

template <Float S>
void GAabbTree<S>::clear() noexcept {
  nodes_.clear();
  proxies_.clear();
  free_nodes_.clear();
  free_proxies_.clear();
  dirty_.clear();
  root_ = null_node;
  live_ = 0;
}

// ------------------------------------------------------------------------ insertion

template <Float S>
std::uint32_t GAabbTree<S>::find_best_sibling(Box const& box) {
  // Branch and bound over the tree: making node x the sibling of the new leaf costs
  // area(x u L) plus, for every ancestor a of x, area(a u L) - area(a) (the growth the insert
  // causes above x). Candidates are expanded cheapest lower bound first; a subtree whose
  // lower bound area(L) + inherited cost cannot beat the best found is skipped. Ties go to
  // the candidate found first, then to the lower node index, so the result is deterministic.
  S const leaf_area = area(box);
  std::uint32_t best = root_;
  S best_cost = area(nodes_[root_].box.merge(box));
  auto const later = [](Candidate const& a, Candidate const& b) {
    return a.cost > b.cost || (a.cost == b.cost && a.node > b.node);
  };
  heap_.clear();
  heap_.push_back({S(0), root_}); // inherited cost of the root
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    Candidate const c = heap_.back();
    heap_.pop_back();
    if (c.cost + leaf_area >= best_cost) break; // no candidate left can win
    Node const& node = nodes_[c.node];
    S const merged = area(node.box.merge(box));
    S const cost = merged + c.cost;
    if (cost < best_cost) {
      best_cost = cost;
      best = c.node;
    }
    if (node.is_leaf()) continue;
    S const inherited = c.cost + (merged - area(node.box));
    if (inherited + leaf_area < best_cost) {
      heap_.push_back({inherited, node.left});
      std::push_heap(heap_.begin(), heap_.end(), later);
      heap_.push_back({inherited, node.right});
      std::push_heap(heap_.begin(), heap_.end(), later);
    }
  }
  return best;
}

template <Float S>
void GAabbTree<S>::refit_upwards(std::uint32_t n) noexcept {
  for (; n != null_node; n = nodes_[n].parent) {
    Node& node = nodes_[n];
    Node const& l = nodes_[node.left];
    Node const& r = nodes_[node.right];
    node.box = l.box.merge(r.box);
    node.height = 1 + std::max(l.height, r.height);
  }
}

template <Float S>
void GAabbTree<S>::insert_leaf(std::uint32_t leaf) {
  if (root_ == null_node) {
    root_ = leaf;
    nodes_[leaf].parent = null_node;
    return;
  }
  Box const box = nodes_[leaf].box;
  std::uint32_t const sibling = find_best_sibling(box);
  std::uint32_t const old_parent = nodes_[sibling].parent;
  std::uint32_t const parent = allocate_node(); // may reallocate nodes_: no references above
  nodes_[parent].parent = old_parent;
  nodes_[parent].left = sibling;
  nodes_[parent].right = leaf;
  nodes_[sibling].parent = parent;
  nodes_[leaf].parent = parent;
  if (old_parent == null_node) {
    root_ = parent;
  } else if (nodes_[old_parent].left == sibling) {
    nodes_[old_parent].left = parent;
  } else {
    nodes_[old_parent].right = parent;
  }
  refit_upwards(parent);
}

template <Float S>
void GAabbTree<S>::remove_leaf(std::uint32_t leaf) {
  if (leaf == root_) {
    root_ = null_node;
    return;
  }
  std::uint32_t const parent = nodes_[leaf].parent;
  std::uint32_t const grand = nodes_[parent].parent;
  std::uint32_t const sibling =
      nodes_[parent].left == leaf ? nodes_[parent].right : nodes_[parent].left;
  if (grand == null_node) {
    root_ = sibling;
    nodes_[sibling].parent = null_node;
  } else {
    if (nodes_[grand].left == parent)
      nodes_[grand].left = sibling;
    else
      nodes_[grand].right = sibling;
    nodes_[sibling].parent = grand;
    refit_upwards(grand);
  }
  free_node(parent);
  nodes_[leaf].parent = null_node;
}

// ------------------------------------------------------------------------ builds

template <Float S>
std::uint32_t GAabbTree<S>::build(std::span<std::uint32_t> prims) {
  return config_.builder == TreeBuilder::ploc ? build_ploc(prims) : build_sah(prims);
}

template <Float S>
std::uint32_t GAabbTree<S>::build_ploc(std::span<std::uint32_t> prims) {
  // Bottom-up PLOC: the prims (leaves or subtrees) sorted along a Morton curve of their boxes'
  // centres; each pass, every cluster finds the neighbour within ploc_radius places whose
  // merged box has the least area (ties: the nearer, then the partner i ^ 1 - so that equal
  // boxes pair up and halve each pass - then the earlier), mutual pairs merge
  // into a new parent in the place of the first, and the list closes up, until one is left.
  // The global least pair is always mutual, so every pass merges at least one pair.
  if (prims.empty()) return null_node;
  std::size_t const n = prims.size();
  int const radius = std::clamp(config_.ploc_radius, 1, 64);
  auto centre = [&](std::uint32_t node) {
    Box const& b = nodes_[node].box;
    return b.min * S(0.5) + b.max * S(0.5);
  };
  Box cb;
  for (std::uint32_t p : prims)
    cb = cb.grow_to(centre(p));
  GVec3<S> const lo = cb.min, ext = cb.size();
  // 10 bits per axis; an axis without spread (or with a spread that overflows) gives 0.
  auto const quantise = [](S c, S l, S w) -> std::uint32_t {
    S const v = (c - l) / w * S(1023);
    return v > S(0) && v < S(1024) ? std::uint32_t(v) : (v >= S(1024) ? 1023u : 0u);
  };
  auto const spread = [](std::uint32_t v) {
    v = (v | (v << 16)) & 0x030000ffu;
    v = (v | (v << 8)) & 0x0300f00fu;
    v = (v | (v << 4)) & 0x030c30c3u;
    return (v | (v << 2)) & 0x09249249u;
  };
  struct keyed {
    std::uint32_t code, order, node;
  };
  std::vector<keyed> keys(n);
  for (std::size_t i = 0; i < n; ++i) {
    GVec3<S> const c = centre(prims[i]);
    std::uint32_t const x = quantise(c.x, lo.x, ext.x), y = quantise(c.y, lo.y, ext.y),
                        z = quantise(c.z, lo.z, ext.z);
    keys[i] = {(spread(x) << 2) | (spread(y) << 1) | spread(z), std::uint32_t(i), prims[i]};
  }
  std::sort(keys.begin(), keys.end(), [](keyed const& a, keyed const& b) {
    return a.code != b.code ? a.code < b.code : a.order < b.order;
  });
  std::vector<std::uint32_t> clusters(n), next;
  for (std::size_t i = 0; i < n; ++i)
    clusters[i] = keys[i].node;
  std::vector<std::uint32_t> nearest(n);
  while (clusters.size() > 1) {
    std::size_t const m = clusters.size();
    for (std::size_t i = 0; i < m; ++i) {
      std::size_t const first = i >= std::size_t(radius) ? i - std::size_t(radius) : 0;
      std::size_t const last = std::min(m - 1, i + std::size_t(radius));
      Box const& bi = nodes_[clusters[i]].box;
      S best = std::numeric_limits<S>::infinity();
      std::size_t best_j = i == 0 ? 1 : i - 1;
      std::size_t best_gap = m;
      for (std::size_t j = first; j <= last; ++j) {
        if (j == i) continue;
        S const a = area(bi.merge(nodes_[clusters[j]].box));
        std::size_t const gap = j > i ? j - i : i - j;
        bool const better =
            a < best || (a == best && (gap < best_gap || (gap == best_gap && j == (i ^ 1))));
        if (better) { // j ascending: remaining ties go earlier
          best = a;
          best_j = j;
          best_gap = gap;
        }
      }
      nearest[i] = std::uint32_t(best_j);
    }
    next.clear();
    for (std::size_t i = 0; i < m; ++i) {
      std::size_t const j = nearest[i];
      if (nearest[j] == i) {
        if (i > j) continue; // merged into j's place
        std::uint32_t const parent = allocate_node();
        Node& p = nodes_[parent];
        p.left = clusters[i];
        p.right = clusters[j];
        p.box = nodes_[p.left].box.merge(nodes_[p.right].box);
        p.height = 1 + std::max(nodes_[p.left].height, nodes_[p.right].height);
        nodes_[p.left].parent = parent;
        nodes_[p.right].parent = parent;
        next.push_back(parent);
      } else {
        next.push_back(clusters[i]);
      }
    }
    clusters.swap(next);
  }
  return clusters[0];
}

template <Float S>
std::uint32_t GAabbTree<S>::build_sah(std::span<std::uint32_t> prims) {
  // Top-down binned SAH (16 bins per axis on the centroids' bounds). Each task splits a
  // range of prims into two and makes their parent; a range of one is that prim itself.
  // Where every centroid is the same point, or no plane separates the bins, the range is
  // split at its middle (so a million boxes at one point still give a balanced tree).
  constexpr int bins = 16;
  if (prims.empty()) return null_node;
  struct Task {
    std::uint32_t begin, end;
    std::uint32_t parent; ///< null_node for the root
    bool left;
  };
  std::uint32_t result = null_node;
  std::vector<Task> tasks;
  tasks.push_back({0, std::uint32_t(prims.size()), null_node, true});
  // Halves first: (min + max) / 2 overflows for boxes near the largest float.
  auto centre = [&](std::uint32_t n) {
    Box const& b = nodes_[n].box;
    return b.min * S(0.5) + b.max * S(0.5);
  };
  // The bin of centroid coordinate c: NaN (an overflowed c - lo) and negatives go to 0.
  auto const bin_of = [](S c, S lo, S scale) {
    S const v = (c - lo) * scale;
    return v >= S(bins) ? bins - 1 : v > S(0) ? int(v) : 0;
  };
  auto const attach = [&](Task const& t, std::uint32_t n) {
    nodes_[n].parent = t.parent;
    if (t.parent == null_node)
      result = n;
    else if (t.left)
      nodes_[t.parent].left = n;
    else
      nodes_[t.parent].right = n;
  };
  std::vector<std::uint32_t> inner_order; // to set heights bottom-up at the end
  while (!tasks.empty()) {
    Task const t = tasks.back();
    tasks.pop_back();
    std::uint32_t const count = t.end - t.begin;
    if (count == 1) {
      attach(t, prims[t.begin]);
      continue;
    }
    Box cb; // centroid bounds
    for (std::uint32_t i = t.begin; i < t.end; ++i)
      cb = cb.grow_to(centre(prims[i]));
    GVec3<S> const ext = cb.size();
    int best_axis = -1, best_plane = -1;
    S best_cost = std::numeric_limits<S>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
      S const lo = axis_of(cb.min, axis), w = axis_of(ext, axis);
      S const scale = S(bins) / w;
      // A spread that overflowed (w = inf, scale 0) or is subnormal (scale = inf) bins nothing.
      if (!(w > S(0)) || !std::isfinite(w) || !(scale > S(0)) || !std::isfinite(scale)) continue;
      std::array<Box, bins> bb{};
      std::array<std::uint32_t, bins> bc{};
      for (std::uint32_t i = t.begin; i < t.end; ++i) {
        std::uint32_t const n = prims[i];
        int const b = bin_of(axis_of(centre(n), axis), lo, scale);
        bb[b] = bb[b].merge(nodes_[n].box);
        ++bc[b];
      }
      // Right-to-left sweep of areas and counts, then left-to-right evaluation.
      std::array<S, bins> right_area{};
      std::array<std::uint32_t, bins> right_count{};
      Box acc;
      std::uint32_t cnt = 0;
      for (int b = bins - 1; b > 0; --b) {
        acc = acc.merge(bb[b]);
        cnt += bc[b];
        right_area[b] = cnt ? area(acc) : S(0);
        right_count[b] = cnt;
      }
      Box lacc;
      std::uint32_t lcnt = 0;
      for (int p = 1; p < bins; ++p) { // plane between bins p-1 and p
        lacc = lacc.merge(bb[p - 1]);
        lcnt += bc[p - 1];
        if (lcnt == 0 || right_count[p] == 0) continue;
        S const cost = area(lacc) * S(lcnt) + right_area[p] * S(right_count[p]);
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_plane = p;
        }
      }
    }
    std::uint32_t mid;
    if (best_axis < 0) {
      mid = t.begin + count / 2;
    } else {
      S const lo = axis_of(cb.min, best_axis), scale = S(bins) / axis_of(ext, best_axis);
      auto const first_right = std::stable_partition(
          prims.begin() + t.begin, prims.begin() + t.end, [&](std::uint32_t n) {
            return bin_of(axis_of(centre(n), best_axis), lo, scale) < best_plane;
          });
      mid = std::uint32_t(first_right - prims.begin());
      if (mid == t.begin || mid == t.end) mid = t.begin + count / 2; // cannot happen; safe
    }
    std::uint32_t const parent = allocate_node();
    attach(t, parent);
    inner_order.push_back(parent);
    tasks.push_back({mid, t.end, parent, false});
    tasks.push_back({t.begin, mid, parent, true});
  }
  // Parents were made before their children: refit in reverse.
  for (auto it = inner_order.rbegin(); it != inner_order.rend(); ++it) {
    Node& node = nodes_[*it];
    node.box = nodes_[node.left].box.merge(nodes_[node.right].box);
    node.height = 1 + std::max(nodes_[node.left].height, nodes_[node.right].height);
  }
  return result;
}

template <Float S>
void GAabbTree<S>::rebuild() {
  prims_.clear();
  for (std::size_t n = 0; n < nodes_.size(); ++n) {
    if (nodes_[n].height < 0) continue;
    if (nodes_[n].is_leaf()) prims_.push_back(std::uint32_t(n));
  }
  for (std::size_t n = 0; n < nodes_.size(); ++n)
    if (nodes_[n].height >= 0 && !nodes_[n].is_leaf()) free_node(std::uint32_t(n));
  // Leaves in proxy order, so the build does not depend on where leaves happen to sit.
  std::sort(prims_.begin(), prims_.end(),
            [&](std::uint32_t a, std::uint32_t b) { return nodes_[a].proxy < nodes_[b].proxy; });
  root_ = build(prims_);
  if (root_ != null_node) nodes_[root_].parent = null_node;
  for (ProxyId id : dirty_)
    proxies_[id].dirty = false;
  dirty_.clear();
}

template <Float S>
void GAabbTree<S>::reinsert_dirty() {
  for (ProxyId id : dirty_) {
    std::uint32_t const leaf = proxies_[id].leaf;
    remove_leaf(leaf);
    insert_leaf(leaf);
    proxies_[id].dirty = false;
  }
  dirty_.clear();
}

template <Float S>
void GAabbTree<S>::partial_rebuild() {
  // Flag every node on a path from a moved leaf to the root; dissolve the flagged inner
  // nodes; rebuild over what hangs off them (unflagged subtrees whole, and the moved leaves).
  for (ProxyId id : dirty_)
    for (std::uint32_t a = nodes_[proxies_[id].leaf].parent; a != null_node && !nodes_[a].flagged;
         a = nodes_[a].parent)
      nodes_[a].flagged = true;
  prims_.clear();
  std::vector<std::uint32_t> stack{root_};
  while (!stack.empty()) {
    std::uint32_t const n = stack.back();
    stack.pop_back();
    if (!nodes_[n].flagged) {
      prims_.push_back(n);
      continue;
    }
    stack.push_back(nodes_[n].right);
    stack.push_back(nodes_[n].left);
    free_node(n);
  }
  root_ = build(prims_);
  nodes_[root_].parent = null_node;
  for (ProxyId id : dirty_)
    proxies_[id].dirty = false;
  dirty_.clear();
}

template <Float S>
TreeOptimization GAabbTree<S>::optimize(TreeOptimization mode) {
  if (mode == TreeOptimization::adaptive) {
    S const f = live_ ? S(dirty_.size()) / S(live_) : S(0);
    mode = f < config_.reinsert_below  ? TreeOptimization::reinsert
           : f < config_.partial_below ? TreeOptimization::partial_rebuild
                                       : TreeOptimization::full_rebuild;
  }
  if (dirty_.empty() && mode != TreeOptimization::full_rebuild) return mode;
  switch (mode) {
  case TreeOptimization::reinsert:
    reinsert_dirty();
    break;
  case TreeOptimization::partial_rebuild:
    partial_rebuild();
    break;
  default:
    rebuild();
    break;
  }
  return mode;
}

template <Float S>
void GAabbTree<S>::refit() noexcept {
  if (root_ == null_node) return;
  // Post-order without recursion: children before parents.
  std::vector<std::uint32_t> order;
  std::vector<std::uint32_t> stack{root_};
  while (!stack.empty()) {
    std::uint32_t const n = stack.back();
    stack.pop_back();
    if (nodes_[n].is_leaf()) continue;
    order.push_back(n);
    stack.push_back(nodes_[n].left);
    stack.push_back(nodes_[n].right);
  }
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    Node& node = nodes_[*it];
    node.box = nodes_[node.left].box.merge(nodes_[node.right].box);
  }
}

// ------------------------------------------------------------------------ measures

template <Float S>
GTreeStats<S> GAabbTree<S>::stats() const noexcept {
  GTreeStats<S> s;
  s.proxies = live_;
  s.nodes = nodes_.size() - free_nodes_.size();
  if (root_ == null_node) return s;
  s.height = nodes_[root_].height;
  S sum = 0;
  for (Node const& n : nodes_)
    if (n.height > 0) sum += area(n.box);
  S const root_area = area(nodes_[root_].box);
  s.area_ratio = root_area > S(0) ? sum / root_area : S(0);
  return s;
}

template <Float S>
std::string GAabbTree<S>::validate() const {
  auto const where = [](std::uint32_t n) { return " (node " + std::to_string(n) + ")"; };
  std::vector<char> seen(nodes_.size(), 0);
  std::size_t leaves = 0, reached = 0;
  if (root_ != null_node) {
    if (root_ >= nodes_.size()) return "root out of range";
    if (nodes_[root_].parent != null_node) return "root has a parent";
    std::vector<std::uint32_t> stack{root_};
    while (!stack.empty()) {
      std::uint32_t const n = stack.back();
      stack.pop_back();
      if (n >= nodes_.size()) return "link out of range";
      if (seen[n]) return "node reached twice" + where(n);
      seen[n] = 1;
      ++reached;
      Node const& node = nodes_[n];
      if (node.height < 0) return "free node reachable" + where(n);
      if (node.flagged) return "flag left set" + where(n);
      if (node.is_leaf()) {
        ++leaves;
        if (node.right != null_node) return "leaf with a right child" + where(n);
        if (node.height != 0) return "leaf height not 0" + where(n);
        if (node.proxy >= proxies_.size() || proxies_[node.proxy].leaf != n)
          return "leaf and proxy disagree" + where(n);
        if (!bool(node.box.contains_aabb(proxies_[node.proxy].tight)))
          return "fat box does not contain the tight box" + where(n);
        continue;
      }
      if (node.proxy != null_proxy) return "inner node names a proxy" + where(n);
      if (node.right == null_node) return "inner node with one child" + where(n);
      for (std::uint32_t c : {node.left, node.right}) {
        if (c >= nodes_.size()) return "child out of range" + where(n);
        if (nodes_[c].parent != n) return "child's parent link wrong" + where(c);
        if (!bool(node.box.contains_aabb(nodes_[c].box)))
          return "parent does not contain its child" + where(c);
      }
      if (node.height != 1 + std::max(nodes_[node.left].height, nodes_[node.right].height))
        return "height wrong" + where(n);
      stack.push_back(node.left);
      stack.push_back(node.right);
    }
  }
  if (leaves != live_) return "leaf count differs from the live proxies";
  if (reached != nodes_.size() - free_nodes_.size()) return "unreachable node not on the free list";
  std::size_t live = 0, dirty = 0;
  for (Proxy const& p : proxies_) {
    if (p.leaf == null_node) {
      if (p.dirty) return "free proxy marked moved";
      continue;
    }
    ++live;
    dirty += p.dirty ? 1 : 0;
    if (p.leaf >= nodes_.size() || !seen[p.leaf]) return "proxy's leaf not in the tree";
  }
  if (live != live_) return "live count wrong";
  if (dirty != dirty_.size()) return "moved list and flags disagree";
  if (free_proxies_.size() + live_ != proxies_.size()) return "free proxy list wrong";
  return {};
}

template struct GTreeConfig<float>;
template struct GTreeConfig<double>;
template class GAabbTree<float>;
template class GAabbTree<double>;

} // namespace plume
