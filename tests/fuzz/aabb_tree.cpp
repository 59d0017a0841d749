// tests/fuzz/aabb_tree.cpp - fuzzes GAabbTree<S> (spatial/aabb_tree.hpp, float and double,
// both builders, fuzzed margins and adaptive thresholds) and its wide copies GWideBvh
// (spatial/wide_bvh.hpp) with a decoded sequence of edits (insert, insert_all, remove, move,
// set_user, optimize in each mode, rebuild, refit, clear) and queries (box overlap, ray walk,
// closest hit, swept walk, ray packets), mirrored by a brute-force list of the live proxies.
// Properties, after every operation:
//  - validate() is empty; size(), contains(), proxy_ids(), user(), tight_box() and fat_box()
//    agree with the mirror; a fat box is tight.grow(margin_for(tight)) as of the last insert or
//    move that left the old fat box, and contains the tight box; stats() counts 2n - 1 nodes;
//  - ids are reused last freed first, and start from 0 after clear(); moved_count() counts the
//    moves that left their fat box since the last optimize()/rebuild(); move() returns whether
//    the new tight box left the old fat box; optimize() returns the mode it ran (adaptive's
//    choice by the moved fraction);
//  - box queries (tree and wide copies) report exactly the live proxies whose fat boxes meet
//    the box (none for a NaN or inverted box), each once, and stop when told to;
//  - ray walks report exactly the live proxies whose fat box the ray enters within max_toi, with
//    that entry; each packet lane reports exactly what the single ray walk reports;
//  - closest hits (clipping ray walk, GWideBvh::ray_cast) give the least toi of a ray cast
//    against the live tight boxes (ties to the lower id for ray_cast), as brute force does;
//  - bad boxes get std::invalid_argument, ids that name no live proxy std::out_of_range, and
//    either leaves the tree unchanged; removed ids never come back from a query.
#include "fuzz_input.hpp"

#include <plume/spatial/aabb_tree.hpp>
#include <plume/spatial/wide_bvh.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>
#include <vector>

namespace {

using plume::fuzz::Input;

template <class E, class F>
bool throws(F&& f) {
  try {
    f();
  } catch (E const&) {
    return true;
  } catch (...) {
    return false;
  }
  return false;
}

template <class S>
bool same_box(plume::GAabb3<S> const& a, plume::GAabb3<S> const& b) {
  return a.min.x == b.min.x && a.min.y == b.min.y && a.min.z == b.min.z && a.max.x == b.max.x &&
         a.max.y == b.max.y && a.max.z == b.max.z;
}

/// A usable box: on a coarse grid (ties, identical boxes, touching faces), a point, or anywhere.
template <class S>
plume::GAabb3<S> good_box(Input& in) {
  using V = plume::GVec3<S>;
  std::uint8_t const kind = in.byte();
  V c, h;
  switch (kind % 4) {
  case 0:
    c = V{S(in.integer(-4, 4)), S(in.integer(-4, 4)), S(in.integer(-4, 4))} * S(0.5);
    h = V{S(in.integer(0, 3)), S(in.integer(0, 3)), S(in.integer(0, 3))} * S(0.25);
    break;
  case 1:
    c = V{S(in.real(-20, 20)), S(in.real(-20, 20)), S(in.real(-20, 20))};
    h = V{};
    break;
  case 2:
    c = V{S(in.real(-5, 5)), S(in.real(-5, 5)), S(in.real(-5, 5))};
    h = V{S(in.real(0, 1e-3f)), S(in.real(0, 1e-3f)), S(in.real(0, 1e-3f))};
    break;
  default:
    c = V{S(in.real(-50, 50)), S(in.real(-50, 50)), S(in.real(-50, 50))};
    h = V{S(in.real(0, 10)), S(in.real(0, 10)), S(in.real(0, 10))};
    break;
  }
  return {c - h, c + h};
}

/// A box insert() and move() must refuse: a NaN or infinite coordinate, or min > max.
template <class S>
plume::GAabb3<S> bad_box(Input& in) {
  plume::GAabb3<S> b = good_box<S>(in);
  std::uint8_t const kind = in.byte();
  S* const coords[6] = {&b.min.x, &b.min.y, &b.min.z, &b.max.x, &b.max.y, &b.max.z};
  S& c = *coords[kind % 6];
  switch ((kind / 6) % 4) {
  case 0:
    c = std::numeric_limits<S>::quiet_NaN();
    break;
  case 1:
    c = std::numeric_limits<S>::infinity();
    break;
  case 2:
    c = -std::numeric_limits<S>::infinity();
    break;
  default: { // min > max on one axis
    int const axis = kind % 3;
    S& lo = axis == 0 ? b.min.x : axis == 1 ? b.min.y : b.min.z;
    S& hi = axis == 0 ? b.max.x : axis == 1 ? b.max.y : b.max.z;
    lo = hi + S(1) + S(in.real(0, 5));
    break;
  }
  }
  return b;
}

template <class S>
plume::GAabb3<S> query_box(Input& in) {
  std::uint8_t const kind = in.byte();
  S const inf = std::numeric_limits<S>::infinity();
  plume::GAabb3<S> b = good_box<S>(in);
  switch (kind % 8) {
  case 0: // infinite bounds: meets every leaf on the open sides
    b.min.x = -inf;
    if (kind & 8) b.max.y = inf;
    if (kind & 16) b = {plume::GVec3<S>::splat(-inf), plume::GVec3<S>::splat(inf)};
    break;
  case 1: // NaN or inverted: meets nothing
    if (kind & 8)
      b.max.z = std::numeric_limits<S>::quiet_NaN();
    else
      b.min.y = b.max.y + S(1);
    break;
  case 2: // grown a lot
    b = b.grow(S(in.real(0, 30)));
    break;
  default:
    break;
  }
  return b;
}

/// Live proxies of the mirror.
template <class S>
struct Mirror {
  struct Live {
    plume::GAabb3<S> tight, fat;
    std::uint64_t user = 0;
    bool dirty = false;
  };
  std::map<plume::ProxyId, Live> live;
  std::vector<plume::ProxyId> free_ids;
  plume::ProxyId next_fresh = 0;
  std::size_t dirty = 0;

  plume::ProxyId next_id() const { return free_ids.empty() ? next_fresh : free_ids.back(); }
  void take_id(plume::ProxyId id) {
    if (free_ids.empty())
      ++next_fresh;
    else
      free_ids.pop_back();
    (void)id;
  }
  /// A live id (when there is one and the byte says so) or one that names no live proxy.
  plume::ProxyId pick(Input& in, bool& is_live) const {
    std::uint8_t const b = in.byte();
    if (!live.empty() && (b & 3) != 0) {
      auto it = live.begin();
      std::advance(it, static_cast<std::ptrdiff_t>(std::size_t(b >> 2) % live.size()));
      is_live = true;
      return it->first;
    }
    is_live = false;
    if (!free_ids.empty() && (b & 4)) return free_ids[std::size_t(b >> 3) % free_ids.size()];
    if (b & 8) return plume::null_proxy;
    plume::ProxyId id = next_fresh + (b >> 4);
    return id;
  }
};

template <class S>
void check_tree(plume::GAabbTree<S> const& tree, Mirror<S> const& m) {
  PLUME_FUZZ_CHECK(tree.validate().empty());
  PLUME_FUZZ_CHECK(tree.size() == m.live.size());
  PLUME_FUZZ_CHECK(tree.empty() == m.live.empty());
  PLUME_FUZZ_CHECK(tree.moved_count() == m.dirty);
  std::vector<plume::ProxyId> const ids = tree.proxy_ids();
  PLUME_FUZZ_CHECK(ids.size() == m.live.size());
  std::size_t k = 0;
  for (auto const& [id, p] : m.live) {
    PLUME_FUZZ_CHECK(k < ids.size() && ids[k] == id);
    ++k;
    PLUME_FUZZ_CHECK(tree.contains(id));
    PLUME_FUZZ_CHECK(tree.user(id) == p.user);
    PLUME_FUZZ_CHECK(same_box(tree.tight_box(id), p.tight));
    PLUME_FUZZ_CHECK(same_box(tree.fat_box(id), p.fat));
    PLUME_FUZZ_CHECK(bool(p.fat.contains_aabb(p.tight)));
  }
  for (plume::ProxyId const id : m.free_ids)
    PLUME_FUZZ_CHECK(!tree.contains(id));
  PLUME_FUZZ_CHECK(!tree.contains(m.next_fresh));
  PLUME_FUZZ_CHECK(!tree.contains(plume::null_proxy));
  plume::GTreeStats<S> const st = tree.stats();
  PLUME_FUZZ_CHECK(st.proxies == m.live.size());
  PLUME_FUZZ_CHECK(st.nodes == (m.live.empty() ? 0 : 2 * m.live.size() - 1));
  PLUME_FUZZ_CHECK(st.height >= 0 &&
                   std::size_t(st.height) + 1 <= std::max<std::size_t>(m.live.size(), 1));
}

/// A fresh fat box: the tight box grown by the margin rule.
template <class S>
plume::GAabb3<S> expected_fat(plume::GAabbTree<S> const& tree, plume::GAabb3<S> const& tight) {
  S const m = tree.config().margin_for(tight);
  PLUME_FUZZ_CHECK(m >= S(0));
  S const extent = std::max(std::max(tight.size().x, tight.size().y), tight.size().z);
  if (std::isfinite(tree.config().margin))
    PLUME_FUZZ_CHECK(m <= std::max(tree.config().margin, S(0)));
  if (std::isfinite(tree.config().margin_fraction))
    PLUME_FUZZ_CHECK(m <= std::max(tree.config().margin_fraction * extent, S(0)));
  return tight.grow(m);
}

template <class S>
plume::GRay3<S> make_ray(Input& in, Mirror<S> const& m) {
  using V = plume::GVec3<S>;
  std::uint8_t const kind = in.byte();
  V o{S(in.real(-60, 60)), S(in.real(-60, 60)), S(in.real(-60, 60))};
  V d{S(in.real(-1, 1)), S(in.real(-1, 1)), S(in.real(-1, 1))};
  if ((kind & 3) == 1) { // axis aligned, with signed zeros
    int const axis = in.integer(0, 2);
    S const s = (kind & 4) ? S(-1) : S(1);
    S const z = (kind & 8) ? S(-0.0) : S(0.0);
    d = V{axis == 0 ? s : z, axis == 1 ? s : z, axis == 2 ? s : z};
  }
  if ((kind & 16) && !m.live.empty()) { // the origin on a box's planes or corner
    auto it = m.live.begin();
    std::advance(it, static_cast<std::ptrdiff_t>(std::size_t(in.byte()) % m.live.size()));
    plume::GAabb3<S> const& b = (kind & 32) ? it->second.fat : it->second.tight;
    o.x = (kind & 64) ? b.min.x : b.max.x;
    if (kind & 128) o.y = b.min.y;
  }
  if ((kind & 3) == 2 && (kind & 64)) d = V{}; // zero direction: meets nothing
  if ((kind & 3) == 3 && (kind & 64)) {        // non-finite: meets nothing
    S const bad =
        (kind & 128) ? std::numeric_limits<S>::infinity() : std::numeric_limits<S>::quiet_NaN();
    if (kind & 32)
      o.y = bad;
    else
      d.z = bad;
  }
  if ((kind & 3) == 2 && !(kind & 64) && (kind & 32)) d = d * S(1e-20); // 1/d overflows
  return {o, d};
}

template <class S>
S make_max_toi(Input& in) {
  std::uint8_t const k = in.byte();
  switch (k % 8) {
  case 0:
    return std::numeric_limits<S>::infinity();
  case 1:
    return (k & 8) ? std::numeric_limits<S>::quiet_NaN() : S(-in.real(0, 5));
  case 2:
    return S(0);
  default:
    return S(in.real(0, 300));
  }
}

/// Brute force: the live proxies whose fat box the ray enters within max_toi (as the tree's
/// slab test computes the entry), by id.
template <class S>
std::map<plume::ProxyId, S> ray_brute(Mirror<S> const& m, plume::GRay3<S> const& ray, S max_toi,
                                      plume::GVec3<S> const& grow) {
  std::map<plume::ProxyId, S> out;
  if (!plume::detail::usable_ray(ray) || !(max_toi >= S(0))) return out;
  bool const neg[3] = {std::signbit(ray.dir.x), std::signbit(ray.dir.y), std::signbit(ray.dir.z)};
  auto const r = plume::detail::make_ray_slab(ray.origin, ray.dir, neg);
  for (auto const& [id, p] : m.live) {
    S entry;
    if (plume::detail::ray_enters(r, p.fat.min - grow, p.fat.max + grow, max_toi, entry))
      out[id] = entry;
  }
  return out;
}

/// Brute force: the least toi of a solid cast against the live tight boxes, ties to the lower id
/// (a ray the tree cannot walk, a zero direction included, finds nothing).
template <class S>
plume::GTreeRayHit<S> closest_brute(Mirror<S> const& m, plume::GRay3<S> const& ray, S max_toi) {
  plume::GTreeRayHit<S> best;
  if (!plume::detail::usable_ray(ray) || !(max_toi >= S(0))) return best;
  for (auto const& [id, p] : m.live) {
    plume::GRayHit<S> const h = plume::ray_cast(p.tight, ray, max_toi, true);
    if (!bool(h.hit)) continue;
    PLUME_FUZZ_CHECK(h.toi >= S(0) && h.toi <= max_toi);
    if (!(h.toi < std::numeric_limits<S>::infinity())) continue;
    if (h.toi < best.toi) { // map order: ids increase, so ties keep the lower one
      best.toi = h.toi;
      best.proxy = id;
    }
  }
  return best;
}

template <class S, class Bvh>
void check_wide(Bvh const& bvh, Mirror<S> const& m, plume::GAabb3<S> const& qbox,
                plume::GRay3<S> const& ray, S max_toi, plume::GVec3<S> const& grow) {
  PLUME_FUZZ_CHECK(bvh.leaf_count() == m.live.size());
  PLUME_FUZZ_CHECK(bvh.empty() == m.live.empty());
  // Box query.
  std::vector<plume::ProxyId> got;
  bvh.query(qbox, [&](plume::ProxyId id) {
    got.push_back(id);
    return true;
  });
  std::sort(got.begin(), got.end());
  PLUME_FUZZ_CHECK(std::adjacent_find(got.begin(), got.end()) == got.end());
  std::vector<plume::ProxyId> want;
  if (bool(qbox.min.cmple(qbox.max).all()))
    for (auto const& [id, p] : m.live)
      if (bool(p.fat.intersects(qbox))) want.push_back(id);
  PLUME_FUZZ_CHECK(got == want);
  // Ray walk, unclipped: every leaf entered, with its entry.
  std::map<plume::ProxyId, S> const rays = ray_brute(m, ray, max_toi, plume::GVec3<S>{});
  std::map<plume::ProxyId, S> seen;
  bvh.ray_query(ray, max_toi, [&](plume::ProxyId id, S entry) {
    PLUME_FUZZ_CHECK(seen.count(id) == 0);
    seen[id] = entry;
    return max_toi;
  });
  PLUME_FUZZ_CHECK(seen == rays);
  // Swept walk.
  std::map<plume::ProxyId, S> const swept = ray_brute(m, ray, max_toi, grow);
  seen.clear();
  bvh.swept_query(ray, grow, max_toi, [&](plume::ProxyId id, S entry) {
    PLUME_FUZZ_CHECK(seen.count(id) == 0);
    seen[id] = entry;
    return max_toi;
  });
  PLUME_FUZZ_CHECK(seen == swept);
  // Closest hit against the tight boxes.
  plume::GTreeRayHit<S> const want_hit = closest_brute(m, ray, max_toi);
  plume::GTreeRayHit<S> const hit = bvh.ray_cast(ray, max_toi, [&](plume::ProxyId id, S limit) {
    PLUME_FUZZ_CHECK(m.live.count(id) == 1);
    return plume::ray_cast(m.live.at(id).tight, ray, limit, true).toi;
  });
  PLUME_FUZZ_CHECK(hit.proxy == want_hit.proxy);
  PLUME_FUZZ_CHECK(hit.toi == want_hit.toi || (std::isnan(hit.toi) && std::isnan(want_hit.toi)));
}

template <class S>
void check_queries(plume::GAabbTree<S> const& tree, Mirror<S> const& m, Input& in) {
  using V = plume::GVec3<S>;
  // Box overlap against brute force over the fat boxes (touching counts).
  plume::GAabb3<S> const qbox = query_box<S>(in);
  std::vector<plume::ProxyId> got;
  tree.query(qbox, [&](plume::ProxyId id) {
    got.push_back(id);
    return true;
  });
  std::sort(got.begin(), got.end());
  PLUME_FUZZ_CHECK(std::adjacent_find(got.begin(), got.end()) == got.end());
  std::vector<plume::ProxyId> want;
  bool const usable = bool(qbox.min.cmple(qbox.max).all());
  for (auto const& [id, p] : m.live) {
    if (usable && bool(p.fat.intersects(qbox))) want.push_back(id);
    // Every proxy whose tight box meets a usable box is reported (fat contains tight).
    if (usable && bool(p.tight.intersects(qbox)))
      PLUME_FUZZ_CHECK(std::binary_search(got.begin(), got.end(), id));
  }
  PLUME_FUZZ_CHECK(got == want);
  // Early stop: f returning false ends the walk.
  std::size_t const stop_after = std::size_t(in.integer(1, 4));
  std::size_t calls = 0;
  tree.query(qbox, [&](plume::ProxyId) { return ++calls < stop_after; });
  PLUME_FUZZ_CHECK(calls == std::min(stop_after, want.size()));

  // Ray walk, unclipped: exactly the leaves entered within max_toi, each with its entry.
  plume::GRay3<S> const ray = make_ray<S>(in, m);
  S const max_toi = make_max_toi<S>(in);
  std::map<plume::ProxyId, S> const rays = ray_brute(m, ray, max_toi, V{});
  std::map<plume::ProxyId, S> seen;
  tree.ray_query(ray, max_toi, [&](plume::ProxyId id, S entry) {
    PLUME_FUZZ_CHECK(seen.count(id) == 0);
    PLUME_FUZZ_CHECK(entry >= S(0) && entry <= max_toi);
    seen[id] = entry;
    return max_toi;
  });
  PLUME_FUZZ_CHECK(seen == rays);

  // Closest hit by the clipping walk: the least toi of a cast against the tight boxes.
  plume::GTreeRayHit<S> const want_hit = closest_brute(m, ray, max_toi);
  S best = std::numeric_limits<S>::infinity();
  tree.ray_query(ray, max_toi, [&](plume::ProxyId id, S) {
    PLUME_FUZZ_CHECK(m.live.count(id) == 1);
    S const limit = std::min(best, max_toi);
    plume::GRayHit<S> const h = plume::ray_cast(m.live.at(id).tight, ray, limit, true);
    if (bool(h.hit) && h.toi < best) best = h.toi;
    return std::min(best, max_toi);
  });
  PLUME_FUZZ_CHECK(best == want_hit.toi);

  // The wide copies: the default width and a scalar one.
  V const grow{S(in.real(0, 2)), S(in.real(0, 2)), S(in.real(0, 2))};
  if constexpr (std::is_same_v<S, float>) {
    plume::WideBvh const wide(tree);
    check_wide(wide, m, qbox, ray, max_toi, grow);
    plume::GWideBvh<float, 4> const narrow(tree);
    check_wide(narrow, m, qbox, ray, max_toi, grow);
  } else {
    plume::GWideBvh<double> const wide(tree);
    check_wide(wide, m, qbox, ray, max_toi, grow);
  }

  // Ray packets (float): each lane reports exactly the single walk's leaves.
  if constexpr (std::is_same_v<S, float>) {
    using T = plume::f32xN;
    constexpr std::size_t W = plume::lanes_v<T>;
    std::array<plume::Vec3, W> o, d;
    std::array<float, W> limit;
    for (std::size_t k = 0; k < W; ++k) {
      plume::Ray3 const r = (k == 0) ? ray : make_ray<float>(in, m);
      o[k] = r.origin;
      d[k] = r.dir;
      limit[k] = (k == 0) ? max_toi : make_max_toi<float>(in);
    }
    std::array<std::vector<plume::ProxyId>, W> lanes_got;
    T lim = plume::load<T>(limit.data());
    tree.ray_query_lanes(plume::GRay3<T>{plume::pack<T>(o.data()), plume::pack<T>(d.data())}, lim,
                         [&](plume::ProxyId id, std::uint64_t bits) {
                           PLUME_FUZZ_CHECK(bits != 0 && (bits >> W) == 0);
                           for (std::size_t k = 0; k < W; ++k)
                             if ((bits >> k) & 1) lanes_got[k].push_back(id);
                         });
    for (std::size_t k = 0; k < W; ++k) {
      std::vector<plume::ProxyId> single;
      tree.ray_query(plume::Ray3{o[k], d[k]}, limit[k], [&](plume::ProxyId id, float) {
        single.push_back(id);
        return limit[k];
      });
      std::sort(single.begin(), single.end());
      std::sort(lanes_got[k].begin(), lanes_got[k].end());
      PLUME_FUZZ_CHECK(lanes_got[k] == single);
    }
  }
}

template <class S>
void run(Input& in) {
  using Tree = plume::GAabbTree<S>;
  using Box = plume::GAabb3<S>;
  plume::GTreeConfig<S> cfg;
  std::uint8_t const c = in.byte();
  if (c & 1) cfg.builder = plume::TreeBuilder::ploc;
  cfg.ploc_radius = in.integer(1, 64);
  if (c & 2) cfg.margin = S(in.real(0, 1));
  if (c & 4) cfg.margin_fraction = S(in.real(0, 1));
  if (c & 8) {
    cfg.reinsert_below = S(in.real(0, 1));
    cfg.partial_below = S(in.real(0, 1));
  }
  if ((c & 0x30) == 0x30) cfg.margin = S(0); // exact boxes
  Tree tree(cfg);
  Mirror<S> m;
  check_tree(tree, m);

  int const ops = in.integer(1, 48);
  for (int op = 0; op < ops && !in.empty(); ++op) {
    std::uint8_t const kind = in.byte();
    switch (kind % 14) {
    case 0:
    case 1:
    case 2: { // insert
      if (m.live.size() >= 64) break;
      bool const bad = (kind & 0x80) && (kind & 0x40);
      Box const b = bad ? bad_box<S>(in) : good_box<S>(in);
      std::uint64_t const user = in.bits<std::uint64_t>();
      if (bad) {
        PLUME_FUZZ_CHECK(throws<std::invalid_argument>([&] { (void)tree.insert(b, user); }));
        break;
      }
      plume::ProxyId const want = m.next_id();
      plume::ProxyId const id = tree.insert(b, user);
      PLUME_FUZZ_CHECK(id == want);
      m.take_id(id);
      m.live[id] = {b, expected_fat(tree, b), user, false};
      break;
    }
    case 3: { // insert_all, sometimes with one unusable box
      std::size_t const n = std::size_t(in.integer(0, 8));
      if (m.live.size() + n > 64) break;
      std::vector<Box> boxes;
      std::vector<std::uint64_t> users;
      bool const bad = (kind & 0x80) != 0;
      std::size_t const bad_at = n > 0 ? std::size_t(in.byte()) % n : 0;
      for (std::size_t k = 0; k < n; ++k) {
        boxes.push_back(bad && k == bad_at ? bad_box<S>(in) : good_box<S>(in));
        if (kind & 0x40) users.push_back(in.bits<std::uint64_t>());
      }
      if (users.size() > 1 && (kind & 0x20)) users.pop_back(); // shorter: 0 for the rest
      if (bad && n > 0) {
        PLUME_FUZZ_CHECK(throws<std::invalid_argument>([&] {
          (void)tree.insert_all(std::span<Box const>(boxes), std::span<std::uint64_t const>(users));
        }));
        break;
      }
      std::vector<plume::ProxyId> const ids =
          tree.insert_all(std::span<Box const>(boxes), std::span<std::uint64_t const>(users));
      PLUME_FUZZ_CHECK(ids.size() == n);
      for (std::size_t k = 0; k < n; ++k) {
        PLUME_FUZZ_CHECK(ids[k] == m.next_id());
        m.take_id(ids[k]);
        m.live[ids[k]] = {boxes[k], expected_fat(tree, boxes[k]), k < users.size() ? users[k] : 0,
                          false};
      }
      for (auto& [id, p] : m.live)
        p.dirty = false;
      m.dirty = 0; // insert_all rebuilds, which forgets the moved leaves
      break;
    }
    case 4:
    case 5: { // remove
      bool live = false;
      plume::ProxyId const id = m.pick(in, live);
      if (!live) {
        PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { tree.remove(id); }));
        break;
      }
      tree.remove(id);
      if (m.live.at(id).dirty) --m.dirty;
      m.live.erase(id);
      m.free_ids.push_back(id);
      break;
    }
    case 6:
    case 7: { // move: a small step, a jump, or an unusable box
      bool live = false;
      plume::ProxyId const id = m.pick(in, live);
      std::uint8_t const how = in.byte();
      Box b;
      bool const bad = (how & 7) == 0;
      if (bad) {
        b = bad_box<S>(in);
      } else if (live && (how & 8)) {
        plume::GVec3<S> const step{S(in.real(-0.2f, 0.2f)), S(in.real(-0.2f, 0.2f)),
                                   S(in.real(-0.2f, 0.2f))};
        Box const& t = m.live.at(id).tight;
        b = {t.min + step, t.max + step};
      } else {
        b = good_box<S>(in);
      }
      if (!live) {
        PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)tree.move(id, b); }));
        break;
      }
      if (bad) {
        PLUME_FUZZ_CHECK(throws<std::invalid_argument>([&] { (void)tree.move(id, b); }));
        break;
      }
      auto& p = m.live.at(id);
      bool const leaves = !bool(p.fat.contains_aabb(b));
      bool const moved = tree.move(id, b);
      PLUME_FUZZ_CHECK(moved == leaves);
      p.tight = b;
      if (moved) {
        p.fat = expected_fat(tree, b);
        if (!p.dirty) {
          p.dirty = true;
          ++m.dirty;
        }
      }
      break;
    }
    case 8: { // set_user
      bool live = false;
      plume::ProxyId const id = m.pick(in, live);
      std::uint64_t const user = in.bits<std::uint64_t>();
      if (!live) {
        PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { tree.set_user(id, user); }));
        PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)tree.user(id); }));
        PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)tree.tight_box(id); }));
        PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)tree.fat_box(id); }));
        break;
      }
      tree.set_user(id, user);
      m.live.at(id).user = user;
      break;
    }
    case 9: { // optimize in each mode
      auto const mode = static_cast<plume::TreeOptimization>(in.byte() % 4);
      plume::TreeOptimization want = mode;
      if (mode == plume::TreeOptimization::adaptive) {
        S const f = m.live.empty() ? S(0) : S(m.dirty) / S(m.live.size());
        want = f < cfg.reinsert_below  ? plume::TreeOptimization::reinsert
               : f < cfg.partial_below ? plume::TreeOptimization::partial_rebuild
                                       : plume::TreeOptimization::full_rebuild;
      }
      PLUME_FUZZ_CHECK(tree.optimize(mode) == want);
      for (auto& [id, p] : m.live)
        p.dirty = false;
      m.dirty = 0;
      break;
    }
    case 10: // rebuild
      tree.rebuild();
      for (auto& [id, p] : m.live)
        p.dirty = false;
      m.dirty = 0;
      break;
    case 11: // refit
      tree.refit();
      break;
    case 12: // clear (rarely): ids start again from 0
      if ((kind & 0xf0) != 0xf0) break;
      tree.clear();
      m = Mirror<S>{};
      break;
    default:
      check_queries(tree, m, in);
      break;
    }
    check_tree(tree, m);
  }
  check_queries(tree, m, in);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  if (in.byte() & 1)
    run<double>(in);
  else
    run<float>(in);
  return 0;
}
