// Helpers for the spatial tests: random boxes, brute-force answers over every live proxy,
// and node-for-node comparison of trees.
#pragma once

#include "../common/harness.hpp"
#include "../common/types.hpp"

#include <plume/spatial.hpp>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace plume::test {

template <class S>
S uniform(std::mt19937& g, double lo, double hi) {
  return S(lo + (hi - lo) * (double(g()) / 4294967296.0));
}

template <class S>
GVec3<S> random_point(std::mt19937& g, double lo, double hi) {
  S const x = uniform<S>(g, lo, hi);
  S const y = uniform<S>(g, lo, hi);
  S const z = uniform<S>(g, lo, hi);
  return {x, y, z};
}

/// A box in [-world, world]^3 with sides up to max_size; one in twenty is a point or flat.
template <class S>
GAabb3<S> random_box(std::mt19937& g, double world, double max_size) {
  GVec3<S> const lo = random_point<S>(g, -world, world);
  GVec3<S> size = random_point<S>(g, 0, max_size);
  auto const kind = g() % 20;
  if (kind == 0) size = {S(0), S(0), S(0)};
  if (kind == 1) size.y = S(0);
  return {lo, lo + size};
}

/// Every live proxy whose fat box intersects q, increasing ids.
template <class S>
std::vector<ProxyId> brute_query(GAabbTree<S> const& tree, GAabb3<S> const& q) {
  std::vector<ProxyId> out;
  if (!bool(q.is_valid())) return out;
  for (ProxyId id : tree.proxy_ids())
    if (bool(tree.fat_box(id).intersects(q))) out.push_back(id);
  return out;
}

/// The tree's answer in callback order.
template <class S>
std::vector<ProxyId> tree_query(GAabbTree<S> const& tree, GAabb3<S> const& q) {
  std::vector<ProxyId> out;
  tree.query(q, [&](ProxyId id) {
    out.push_back(id);
    return true;
  });
  return out;
}

template <class V>
V sorted(V v) {
  std::sort(v.begin(), v.end());
  return v;
}

/// The slab test written out per axis (an independent oracle for ray_enters): a zero
/// direction component keeps the ray in the closed slab or misses; a crossing of 0 x inf
/// (the origin on a plane, 1/d overflowing) is no constraint. Entry in [0, max_toi].
template <class S>
bool slab_oracle(GVec3<S> const& o, GVec3<S> const& d, GAabb3<S> const& b, S max_toi, S& entry) {
  S const oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
  S const lo[3] = {b.min.x, b.min.y, b.min.z}, hi[3] = {b.max.x, b.max.y, b.max.z};
  S tn = S(0), tf = max_toi;
  for (int i = 0; i < 3; ++i) {
    if (dd[i] == S(0)) {
      if (oo[i] < lo[i] || oo[i] > hi[i]) return false;
      continue;
    }
    // Exits with |1/d| enlarged by 2^-20, as the tree's test (conservative exits).
    S const inv = S(1) / dd[i], inv_far = inv * (S(1) + S(0x1p-20));
    S t1 = (lo[i] - oo[i]) * inv, t2 = (hi[i] - oo[i]) * inv_far;
    if (dd[i] < S(0)) {
      t1 = (hi[i] - oo[i]) * inv;
      t2 = (lo[i] - oo[i]) * inv_far;
    }
    if (t1 == t1 && t1 > tn) tn = t1;
    if (t2 == t2 && t2 < tf) tf = t2;
  }
  entry = tn;
  return tn <= tf;
}

struct RayHitRecord {
  ProxyId id;
  std::uint64_t entry_bits;
  bool operator<(RayHitRecord const& o) const {
    return id < o.id || (id == o.id && entry_bits < o.entry_bits);
  }
  bool operator==(RayHitRecord const& o) const = default;
};

template <class S>
std::uint64_t bits_of(S s) {
  return std::uint64_t(std::bit_cast<bits_t<S>>(s));
}

/// Every live proxy whose fat box the ray enters within max_toi, with the entry, by id.
template <class S>
std::vector<RayHitRecord> brute_ray(GAabbTree<S> const& tree, GRay3<S> const& ray, S max_toi) {
  std::vector<RayHitRecord> out;
  if (!detail::usable_ray(ray) || !(max_toi >= S(0))) return out;
  for (ProxyId id : tree.proxy_ids()) {
    S entry;
    if (slab_oracle(ray.origin, ray.dir, tree.fat_box(id), max_toi, entry))
      out.push_back({id, bits_of(entry)});
  }
  return out;
}

template <class S>
bool same_box(GAabb3<S> const& a, GAabb3<S> const& b) {
  return same_bits(a.min.x, b.min.x) && same_bits(a.min.y, b.min.y) &&
         same_bits(a.min.z, b.min.z) && same_bits(a.max.x, b.max.x) &&
         same_bits(a.max.y, b.max.y) && same_bits(a.max.z, b.max.z);
}

/// Node for node: same slots, links, proxies, heights, flags and box bits, and the same root.
template <class S>
std::string compare_nodes(GAabbTree<S> const& a, GAabbTree<S> const& b) {
  auto const na = a.nodes(), nb = b.nodes();
  if (a.root() != b.root()) return "roots differ";
  if (na.size() != nb.size()) return "node counts differ";
  for (std::size_t i = 0; i < na.size(); ++i) {
    auto const &x = na[i], &y = nb[i];
    if (!same_box(x.box, y.box) || x.parent != y.parent || x.left != y.left || x.right != y.right ||
        x.proxy != y.proxy || x.height != y.height || x.flagged != y.flagged)
      return "node " + std::to_string(i) + " differs";
  }
  return {};
}

} // namespace plume::test
