// GWideBvh: ray_cast against spheres equals the brute-force closest hit (proxy and toi bits,
// ties to the lower proxy id), ray_query visits exactly the leaves whose fat boxes the ray
// enters, query(box) gives the tree's leaves in the tree's order, for every element type and
// arity; and detail::ray_enters is lane-exact and right on its edge cases.
#include "spatial_support.hpp"

#include <plume/spatial/wide_bvh.hpp>

#include "../math/math_support.hpp"

#include <cmath>
#include <limits>

using namespace plume;
using namespace plume::test;

namespace {

template <class S>
struct Scene {
  GAabbTree<S> tree;
  std::vector<GVec3<S>> centre; // by proxy id
  std::vector<S> radius;

  ProxyId add(GVec3<S> const& c, S r) {
    ProxyId const id = tree.insert(GAabb3<S>::from_sphere(c, r));
    if (id >= centre.size()) {
      centre.resize(id + 1);
      radius.resize(id + 1);
    }
    centre[id] = c;
    radius[id] = r;
    return id;
  }
  void move(ProxyId id, GVec3<S> const& c) {
    tree.move(id, GAabb3<S>::from_sphere(c, radius[id]));
    centre[id] = c;
  }
  /// The leaf cast: the toi of proxy id's sphere, +infinity for a miss.
  S cast(GRay3<S> const& ray, ProxyId id, S max_toi) const {
    GRay3<S> const local{ray.origin - centre[id], ray.dir};
    return ray_cast_local(GSphere<S>{radius[id]}, local, max_toi).toi;
  }
};

/// Spheres in [-20, 20]^3; a fifth of them exact copies of an earlier one (ties), some ids
/// reused, some moved without optimize() (enlarged ancestors), so the tree is not a fresh build.
template <class S>
Scene<S> make_scene(std::uint32_t seed, int n, bool optimised) {
  Scene<S> s;
  std::mt19937 g(seed);
  for (int i = 0; i < n; ++i) {
    if (i > 10 && i % 5 == 0) {
      ProxyId const src = ProxyId(g() % ProxyId(i / 2));
      s.add(s.centre[src], s.radius[src]);
    } else {
      s.add(random_point<S>(g, -20, 20), uniform<S>(g, 0.2, 1.5));
    }
  }
  for (ProxyId id = 3; id < ProxyId(n); id += 7)
    s.tree.remove(id);
  for (ProxyId id = ProxyId(n - 4); id > 2; id -= 7) { // reuse: copies of later spheres
    ProxyId const src = id + 2;
    if (s.tree.contains(src)) s.add(s.centre[src], s.radius[src]);
  }
  for (ProxyId id : s.tree.proxy_ids())
    if (id % 4 == 1) s.move(id, s.centre[id] + random_point<S>(g, -2, 2));
  if (optimised) s.tree.optimize();
  REQUIRE(s.tree.validate() == "");
  return s;
}

template <class S>
GTreeRayHit<S> brute_cast(Scene<S> const& s, GRay3<S> const& ray, S max_toi) {
  GTreeRayHit<S> best;
  if (!detail::usable_ray(ray) || !(max_toi >= S(0))) return best;
  for (ProxyId id : s.tree.proxy_ids()) {
    S const t = s.cast(ray, id, max_toi);
    if (!(t <= max_toi) || t == std::numeric_limits<S>::infinity()) continue;
    if (t < best.toi || (t == best.toi && id < best.proxy)) {
      best.proxy = id;
      best.toi = t;
    }
  }
  return best;
}

template <class S>
struct Probe {
  std::vector<GRay3<S>> rays;
  std::vector<S> max_toi;
  std::vector<GAabb3<S>> boxes;
};

template <class S>
Probe<S> make_probe(Scene<S> const& s, std::uint32_t seed, int count) {
  Probe<S> p;
  std::mt19937 g(seed);
  auto const ids = s.tree.proxy_ids();
  S const inf = std::numeric_limits<S>::infinity();
  for (int i = 0; i < count; ++i) {
    GVec3<S> const o = random_point<S>(g, -30, 30);
    GVec3<S> d;
    switch (i % 4) {
    case 0: // at a sphere's centre (ties where it has copies)
      d = s.centre[ids[g() % ids.size()]] - o;
      break;
    case 1: // near a sphere's surface (grazing, fat-box-only crossings)
    {
      ProxyId const id = ids[g() % ids.size()];
      d = s.centre[id] + random_point<S>(g, -1, 1) * (s.radius[id] * S(1.05)) - o;
      break;
    }
    case 2: // axis-parallel
      d = {S(0), S(0), S(0)};
      (g() % 3 == 0 ? d.x : g() % 2 ? d.y : d.z) = g() % 2 ? S(1) : -S(1);
      break;
    default:
      d = random_point<S>(g, -1, 1);
    }
    if (d.x == S(0) && d.y == S(0) && d.z == S(0)) d.x = S(1);
    p.rays.push_back({o, d});
    S const m[4] = {inf, S(1), S(0.5), S(3)};
    p.max_toi.push_back(m[g() % 4]);
    p.boxes.push_back(random_box<S>(g, 25, g() % 2 ? 2 : 12));
  }
  return p;
}

struct Totals {
  std::size_t hits = 0, ties = 0, fat_only = 0;
};

/// Every check of one (T, K) against brute force and the tree.
template <class T, std::size_t K>
void check_bvh(Scene<scalar_t<T>> const& s, Probe<scalar_t<T>> const& p, Totals* totals) {
  using S = scalar_t<T>;
  INFO("lanes " << lanes_v<T> << ", arity " << K);
  GWideBvh<T, K> const bvh(s.tree);
  REQUIRE(bvh.leaf_count() == s.tree.size());
  for (std::size_t i = 0; i < p.rays.size(); ++i) {
    GRay3<S> const& ray = p.rays[i];
    S const max_toi = p.max_toi[i];
    INFO("ray " << i << ": " << ray.origin << " + t " << ray.dir << ", max_toi " << max_toi);
    auto const want = brute_cast(s, ray, max_toi);
    auto const got =
        bvh.ray_cast(ray, max_toi, [&](ProxyId id, S limit) { return s.cast(ray, id, limit); });
    REQUIRE(got.proxy == want.proxy);
    REQUIRE(bits_of(got.toi) == bits_of(want.toi));
    // Leaves visited: exactly those whose fat boxes the ray enters, with the entry.
    std::vector<RayHitRecord> visited;
    bvh.ray_query(ray, max_toi, [&](ProxyId id, S entry) {
      visited.push_back({id, bits_of(entry)});
      return max_toi;
    });
    auto const entered = brute_ray(s.tree, ray, max_toi);
    REQUIRE(sorted(visited) == entered);
    if (totals) {
      totals->hits += want.hit();
      std::size_t at_best = 0;
      for (auto const& e : entered)
        at_best += want.hit() && s.cast(ray, e.id, max_toi) == want.toi;
      totals->ties += at_best > 1;
      for (auto const& e : entered)
        totals->fat_only += !(s.cast(ray, e.id, max_toi) <= max_toi);
    }
    // Box queries: the tree's leaves, in the tree's order.
    GAabb3<S> const& q = p.boxes[i];
    std::vector<ProxyId> got_q;
    bvh.query(q, [&](ProxyId id) {
      got_q.push_back(id);
      return true;
    });
    REQUIRE(got_q == tree_query(s.tree, q));
    REQUIRE(sorted(got_q) == brute_query(s.tree, q));
  }
}

template <class T>
void check_all_arities(Scene<scalar_t<T>> const& s, Probe<scalar_t<T>> const& p, Totals* totals) {
  constexpr std::size_t L = lanes_v<T>;
  constexpr std::size_t K1 = L < 2 ? 2 : L;
  check_bvh<T, K1>(s, p, totals);
  check_bvh<T, 2 * K1>(s, p, nullptr);
  check_bvh<T, 4 * K1>(s, p, nullptr);
  check_bvh<T, default_arity_v<T>>(s, p, nullptr);
}

using f64_list = test::f64_types;

} // namespace

TEMPLATE_LIST_TEST_CASE("wide bvh: f32 ray casts, ray and box queries equal brute force",
                        "[spatial][bvh]", test::f32_types) {
  using S = float;
  for (bool optimised : {false, true}) {
    INFO("optimised " << optimised);
    Scene<S> const s = make_scene<S>(71, 600, optimised);
    // A third of the probes in the -O0 sanitizer build (the full set took 12 s a type there).
    int const k = PLUME_TEST_UNOPTIMISED ? 1 : 3;
    Probe<S> const p = make_probe(s, 72, 500 * k);
    Totals totals;
    check_all_arities<TestType>(s, p, &totals);
    // The scene does what it is meant to: hits, exact ties, fat-box-only crossings.
    CHECK(totals.hits > 100 * k);
    CHECK(totals.ties > 10 * k);
    CHECK(totals.fat_only > 100 * k / 3);
  }
}

TEMPLATE_LIST_TEST_CASE("wide bvh: f64 ray casts, ray and box queries equal brute force",
                        "[spatial][bvh]", f64_list) {
  using S = double;
  Scene<S> const s = make_scene<S>(81, 400, false);
  int const k = PLUME_TEST_UNOPTIMISED ? 1 : 3; // a third of the probes at -O0
  Probe<S> const p = make_probe(s, 82, 200 * k);
  Totals totals;
  check_all_arities<TestType>(s, p, &totals);
  CHECK(totals.hits > 100 * k / 3);
  CHECK(totals.ties > 10 * k / 3);
}

// The node layout depends on the scalar and the arity only, so one stored tree can be read by
// every batch whose lanes divide its arity (each instruction set of a dispatch build reads the
// stored trees at its own width): the same hits, the same leaves in the same order.
static_assert(std::is_same_v<GWideBvh<float, 16>::Node, GWideBvh<f32xN, 16>::Node>);

namespace {
template <std::size_t K>
void check_readers(Scene<float> const& s, Probe<float> const& p) {
  INFO("arity " << K);
  GWideBvh<float, K> const bvh(s.tree);
  struct Answers {
    std::vector<ProxyId> cast;
    std::vector<decltype(bits_of(0.0f))> toi;
    std::vector<RayHitRecord> ray, swept;
    std::vector<ProxyId> box;
    bool operator==(Answers const&) const = default;
  };
  auto const answers = [&]<class U>() {
    Answers a;
    for (std::size_t i = 0; i < p.rays.size(); ++i) {
      Ray3 const& ray = p.rays[i];
      float const max_toi = p.max_toi[i];
      auto const hit = bvh.template ray_cast<U>(
          ray, max_toi, [&](ProxyId id, float limit) { return s.cast(ray, id, limit); });
      a.cast.push_back(hit.proxy);
      a.toi.push_back(bits_of(hit.toi));
      bvh.template ray_query<U>(ray, max_toi, [&](ProxyId id, float entry) {
        a.ray.push_back({id, bits_of(entry)});
        return max_toi;
      });
      bvh.template swept_query<U>(ray, Vec3{0.5f, 0.25f, 1.0f}, max_toi,
                                  [&](ProxyId id, float entry) {
                                    a.swept.push_back({id, bits_of(entry)});
                                    return max_toi;
                                  });
      bvh.template query<U>(p.boxes[i], [&](ProxyId id) {
        a.box.push_back(id);
        return true;
      });
    }
    return a;
  };
  Answers const want = answers.template operator()<float>();
  CHECK(want.ray.size() > p.rays.size() / 2); // the probes do meet leaves (98 of 100 at -O0)
  CHECK(want.swept.size() > want.ray.size());
  plume::for_each_type<f32_widths>([&]<class U>() {
    if constexpr (K % lanes_v<U> == 0) {
      INFO("read with " << lanes_v<U> << " lanes");
      REQUIRE(answers.template operator()<U>() == want);
    }
  });
}
} // namespace

TEST_CASE("wide bvh: one stored tree read at every width that divides its arity",
          "[spatial][bvh]") {
  Scene<float> const s = make_scene<float>(91, 300, true);
  Probe<float> const p = make_probe(s, 92, PLUME_TEST_UNOPTIMISED ? 100 : 300);
  check_readers<4>(s, p);
  check_readers<8>(s, p);
  check_readers<16>(s, p);
}

TEMPLATE_LIST_TEST_CASE("wide bvh: exact ties go to the lower proxy id, whatever the order",
                        "[spatial][bvh]", test::f32_types) {
  using T = TestType;
  using S = float;
  // Eight identical spheres; ids 0..3 removed and inserted again, so their leaves are the
  // newer ones (right children) and the traversal meets a higher id first.
  Scene<S> s;
  std::mt19937 g(5);
  for (int i = 0; i < 40; ++i)
    s.add(random_point<S>(g, -20, 20), 0.5f);
  std::vector<ProxyId> copies;
  for (int i = 0; i < 8; ++i)
    copies.push_back(s.add({1, 2, 3}, 1.25f));
  for (int i = 3; i >= 0; --i)
    s.tree.remove(copies[std::size_t(i)]);
  for (int i = 0; i < 4; ++i)
    REQUIRE(s.add({1, 2, 3}, 1.25f) == copies[std::size_t(i)]);
  GWideBvh<T> const bvh(s.tree);
  auto const same_point = [](GVec3<S> const& c) { return c.x == 1 && c.y == 2 && c.z == 3; };
  int higher_first = 0;
  for (int i = 0; i < 200; ++i) {
    GVec3<S> const o = random_point<S>(g, -30, 30);
    GRay3<S> const ray{o, GVec3<S>{1, 2, 3} + random_point<S>(g, -0.5, 0.5) - o};
    auto const hit =
        bvh.ray_cast(ray, 1000.0f, [&](ProxyId id, S limit) { return s.cast(ray, id, limit); });
    auto const want = brute_cast(s, ray, 1000.0f);
    REQUIRE(hit.proxy == want.proxy);
    REQUIRE(bits_of(hit.toi) == bits_of(want.toi));
    if (same_point(s.centre[want.proxy])) {
      REQUIRE(want.proxy == copies[0]);
      // Which copy the traversal reaches first: the rule, not the order, must decide.
      ProxyId first = null_proxy;
      bvh.ray_query(ray, 1000.0f, [&](ProxyId id, S entry) {
        if (first == null_proxy && same_point(s.centre[id])) first = id;
        return entry < 0 ? entry : 1000.0f;
      });
      higher_first += first != copies[0];
    }
  }
  CHECK(higher_first > 20);
}

TEMPLATE_LIST_TEST_CASE("wide bvh: empty, degenerate rays, infinite max_toi, stopping",
                        "[spatial][bvh]", test::f32_types) {
  using T = TestType;
  using S = float;
  S const nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  int calls = 0;
  auto const leaf = [&](ProxyId, S) {
    ++calls;
    return S(1);
  };
  GWideBvh<T> none;
  REQUIRE(none.empty());
  GAabbTree<S> empty_tree;
  GWideBvh<T> const empty(empty_tree);
  REQUIRE(empty.empty());
  REQUIRE(empty.leaf_count() == 0);
  REQUIRE_FALSE(empty.ray_cast(GRay3<S>{{0, 0, 0}, {1, 0, 0}}, inf, leaf).hit());
  empty.query(GAabb3<S>{{-1, -1, -1}, {1, 1, 1}}, [&](ProxyId) {
    ++calls;
    return true;
  });
  REQUIRE(calls == 0);

  Scene<S> s;
  ProxyId const a = s.add({0, 0, 0}, 1);
  ProxyId const far = s.add({1e6f, 0, 0}, 1);
  // A single leaf at the root.
  {
    GAabbTree<S> one;
    one.insert(GAabb3<S>{{0, 0, 0}, {1, 1, 1}}, 0);
    GWideBvh<T> const b1(one);
    REQUIRE(b1.leaf_count() == 1);
    auto const h =
        b1.ray_cast(GRay3<S>{{-1, 0.5f, 0.5f}, {1, 0, 0}}, inf, [](ProxyId, S) { return S(1); });
    REQUIRE(h.proxy == 0);
    REQUIRE(h.toi == 1);
  }
  GWideBvh<T> bvh(s.tree);
  using Ray = GRay3<S>;
  for (Ray const& ray : {Ray{{-5, 0, 0}, {0, 0, 0}}, Ray{{-5, 0, 0}, {-S(0), S(0), -S(0)}},
                         Ray{{nan, 0, 0}, {1, 0, 0}}, Ray{{-5, 0, 0}, {1, nan, 0}},
                         Ray{{-inf, 0, 0}, {1, 0, 0}}, Ray{{-5, 0, 0}, {inf, 0, 0}}}) {
    REQUIRE_FALSE(bvh.ray_cast(ray, inf, leaf).hit());
    bvh.ray_query(ray, inf, [&](ProxyId, S) {
      ++calls;
      return inf;
    });
  }
  Ray const good{{-5, 0, 0}, {1, 0, 0}};
  for (S m : {S(-1), -inf, nan}) {
    REQUIRE_FALSE(bvh.ray_cast(good, m, leaf).hit());
    bvh.ray_query(good, m, [&](ProxyId, S) {
      ++calls;
      return inf;
    });
  }
  bvh.query(GAabb3<S>{{nan, 0, 0}, {1, 1, 1}}, [&](ProxyId) {
    ++calls;
    return true;
  });
  REQUIRE(calls == 0);
  // Infinite max_toi reaches the far sphere; a leaf cast that misses (+infinity) is a miss
  // even then.
  Ray const to_far{{1e6f - 10, 0.5f, 0}, {1, 0, 0}};
  auto const hf =
      bvh.ray_cast(to_far, inf, [&](ProxyId id, S limit) { return s.cast(to_far, id, limit); });
  REQUIRE(hf.proxy == far);
  REQUIRE(bits_of(hf.toi) == bits_of(brute_cast(s, to_far, inf).toi));
  Ray const graze{{-5, 1.02f, 0}, {1, 0, 0}}; // in a's fat box (margin 0.05), off the sphere
  int visited = 0;
  bvh.ray_query(graze, inf, [&](ProxyId id, S) {
    visited += id == a;
    return inf;
  });
  REQUIRE(visited == 1);
  auto const hm =
      bvh.ray_cast(graze, inf, [&](ProxyId id, S limit) { return s.cast(graze, id, limit); });
  REQUIRE_FALSE(hm.hit());
  REQUIRE(hm.proxy == null_proxy);
  REQUIRE(hm.toi == inf);
  // A leaf toi above max_toi, or NaN, or negative, is no hit.
  for (S t : {S(2), nan, S(-1), inf})
    REQUIRE_FALSE(bvh.ray_cast(good, S(1.5), [&](ProxyId, S) { return t; }).hit());
  // Stopping after the first leaf; clipping by the returned value.
  for (int i = 0; i < 50; ++i)
    s.add({S(i) * 3, 0, 0}, 1);
  bvh.build(s.tree); // the copy follows the tree only when built again
  REQUIRE(bvh.leaf_count() == s.tree.size());
  calls = 0;
  bvh.ray_query(good, inf, [&](ProxyId, S) {
    ++calls;
    return S(-1);
  });
  REQUIRE(calls == 1);
  S clip = inf;
  int reported = 0;
  bvh.ray_query(good, inf, [&](ProxyId, S entry) {
    REQUIRE(entry <= clip);
    ++reported;
    clip = entry + S(7);
    return clip;
  });
  REQUIRE(reported >= 3);
  REQUIRE(reported < 50);
  // Nearest first within a node: along +x the first leaf reported is the nearest sphere.
  ProxyId first = null_proxy;
  bvh.ray_query(good, inf, [&](ProxyId id, S) {
    first = id;
    return S(-1);
  });
  REQUIRE(first == a);
  calls = 0;
  bvh.query(GAabb3<S>{{-100, -100, -100}, {200, 100, 100}}, [&](ProxyId) {
    ++calls;
    return calls < 5;
  });
  REQUIRE(calls == 5);
}

// ------------------------------------------------------------------------ ray_enters

namespace {

template <class S>
std::vector<S> enters_pool(std::uint32_t seed) {
  std::vector<S> v = adversarial<S>();
  std::mt19937 g(seed);
  std::size_t const n = 3 * v.size();
  for (std::size_t i = 0; i < n; ++i)
    v.push_back(uniform<S>(g, -4, 4));
  for (S x : {S(-1), S(0), S(1), S(2)}) // shared by origins and box faces: exact planes
    for (int i = 0; i < 4; ++i)
      v.push_back(x);
  return v;
}

template <class T>
struct EntersCase {
  using S = scalar_t<T>;
  GVec3<T> o, d, lo, hi;
  T max_toi;
  bool neg[3];
};

} // namespace

PLUME_WIDE_TEST_CASE("ray_enters: every lane equals the scalar slab test, bit for bit",
                     "[spatial][bvh][lanes]", test::wide_real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  constexpr std::size_t L = lanes_v<T>;
  std::vector<S> const pool = enters_pool<S>(91);
  std::mt19937 g(92);
  S const inf = std::numeric_limits<S>::infinity();
  auto pick = [&] { return pool[g() % pool.size()]; };
  std::size_t failures = 0, hits = 0, misses = 0;
  for (int k = 0; k < 20000; ++k) {
    // Kinds: 0 anything from the pool; 1 a splatted ray (as the BVH uses it) against
    // lanes of boxes, some EMPTY; 2 origins on the box planes with zero directions.
    int const kind = k % 3;
    std::array<S, L> ox, oy, oz, dx, dy, dz, lx, ly, lz, hx, hy, hz, mt;
    bool neg[3];
    S const so[3] = {pick(), pick(), pick()};
    S sd[3] = {pick(), pick(), pick()};
    if (kind != 0)
      for (S& x : sd)
        if (g() % 3 == 0) x = g() % 2 ? S(0) : -S(0);
    for (int a = 0; a < 3; ++a)
      neg[a] = kind == 0 ? bool(g() % 2) : std::signbit(sd[a]);
    for (std::size_t i = 0; i < L; ++i) {
      if (kind == 0) {
        ox[i] = pick(), oy[i] = pick(), oz[i] = pick();
        dx[i] = pick(), dy[i] = pick(), dz[i] = pick();
      } else {
        ox[i] = so[0], oy[i] = so[1], oz[i] = so[2];
        dx[i] = sd[0], dy[i] = sd[1], dz[i] = sd[2];
      }
      lx[i] = pick(), ly[i] = pick(), lz[i] = pick();
      hx[i] = pick(), hy[i] = pick(), hz[i] = pick();
      if (kind == 2) { // the origin on a face
        (g() % 2 ? lx[i] : hx[i]) = ox[i];
        (g() % 2 ? ly[i] : hy[i]) = oy[i];
      }
      if (kind == 1 && g() % 3 == 0) {
        lx[i] = ly[i] = lz[i] = inf;
        hx[i] = hy[i] = hz[i] = -inf;
      }
      S const m[4] = {inf, S(1), S(0), pick()};
      mt[i] = m[g() % 4];
    }
    auto W = [](std::array<S, L> const& a) { return from_array<T>(a); };
    GVec3<T> const o{W(ox), W(oy), W(oz)}, d{W(dx), W(dy), W(dz)};
    GVec3<T> const lo{W(lx), W(ly), W(lz)}, hi{W(hx), W(hy), W(hz)};
    auto const r = detail::make_ray_slab(o, d, neg);
    T entry;
    std::uint64_t const mask = bitmask(detail::ray_enters(r, lo, hi, W(mt), entry));
    for (std::size_t i = 0; i < L; ++i) {
      auto const rs =
          detail::make_ray_slab(GVec3<S>{ox[i], oy[i], oz[i]}, GVec3<S>{dx[i], dy[i], dz[i]}, neg);
      S es;
      bool const ms = detail::ray_enters(rs, GVec3<S>{lx[i], ly[i], lz[i]},
                                         GVec3<S>{hx[i], hy[i], hz[i]}, mt[i], es);
      bool const mw = (mask >> i) & 1u;
      S const ew = lane(entry, i);
      (ms ? hits : misses) += 1;
      if ((ms != mw || bits_of(es) != bits_of(ew)) && failures++ < 3)
        FAIL_CHECK("lane " << i << " of " << L << ": scalar " << ms << " " << es << ", wide " << mw
                           << " " << ew << " for o " << ox[i] << " " << oy[i] << " " << oz[i]
                           << " d " << dx[i] << " " << dy[i] << " " << dz[i] << " box " << lx[i]
                           << " " << ly[i] << " " << lz[i] << " .. " << hx[i] << " " << hy[i] << " "
                           << hz[i] << " max_toi " << mt[i]);
      // An EMPTY slot meets no ray with a finite origin and direction.
      if (kind == 1 && lx[i] == inf && std::isfinite(ox[i]) && std::isfinite(oy[i]) &&
          std::isfinite(oz[i]) && std::isfinite(dx[i]) && std::isfinite(dy[i]) &&
          std::isfinite(dz[i]) && mw && failures++ < 3)
        FAIL_CHECK("an EMPTY slot was entered (lane " << i << ")");
    }
  }
  CHECK(failures == 0);
  CHECK(hits > 1000);
  CHECK(misses > 1000);
}

TEMPLATE_TEST_CASE("ray_enters: the slab test against an explicit per-axis oracle",
                   "[spatial][bvh]", float, double) {
  using S = TestType;
  std::vector<S> pool;
  for (S x : adversarial<S>())
    if (std::isfinite(x)) pool.push_back(x);
  std::mt19937 g(93);
  for (int i = 0; i < 300; ++i)
    pool.push_back(uniform<S>(g, -4, 4));
  for (S x : {S(-1), S(0), S(1), S(2)})
    for (int i = 0; i < 30; ++i)
      pool.push_back(x);
  auto pick = [&] { return pool[g() % pool.size()]; };
  std::size_t failures = 0, hits = 0, plane_hits = 0;
  for (int k = 0; k < 200000; ++k) {
    GVec3<S> const o{pick(), pick(), pick()};
    GVec3<S> d{pick(), pick(), pick()};
    if (g() % 2) d.x = g() % 2 ? S(0) : -S(0);
    if (g() % 3 == 0) d.y = g() % 2 ? S(0) : -S(0);
    GVec3<S> lo{pick(), pick(), pick()}, hi{pick(), pick(), pick()};
    if (g() % 2) (g() % 2 ? lo.x : hi.x) = o.x; // the origin on a plane
    if (lo.x > hi.x) std::swap(lo.x, hi.x);
    if (lo.y > hi.y) std::swap(lo.y, hi.y);
    if (lo.z > hi.z) std::swap(lo.z, hi.z);
    S const max_toi = g() % 2 ? S(1e6) : std::abs(pick());
    bool const neg[3] = {std::signbit(d.x), std::signbit(d.y), std::signbit(d.z)};
    S entry = -1, want = -1;
    bool const got = detail::ray_enters(detail::make_ray_slab(o, d, neg), lo, hi, max_toi, entry);
    bool const ok = slab_oracle(o, d, GAabb3<S>{lo, hi}, max_toi, want);
    hits += ok;
    plane_hits += ok && d.x == S(0) && (o.x == lo.x || o.x == hi.x);
    if ((got != ok || (ok && bits_of(entry) != bits_of(want))) && failures++ < 3)
      FAIL_CHECK("ray_enters " << got << " " << entry << ", oracle " << ok << " " << want
                               << " for o " << o << " d " << d << " box " << lo << " .. " << hi
                               << " max_toi " << max_toi);
  }
  CHECK(failures == 0);
  CHECK(hits > 10000);
  CHECK(plane_hits > 500);
}

TEMPLATE_LIST_TEST_CASE("wide bvh and tree: traversal order, nearest first, ties to the lower slot",
                        "[spatial][bvh]", test::f32_types) {
  using T = TestType;
  using S = float;
  GTreeConfig<S> exact;
  exact.margin = 0; // fat boxes = tight boxes
  // Cubes along x: after a rebuild every sibling pair is split by an x plane, so nearest
  // first in each node is nearest first overall, in both directions.
  GAabbTree<S> line(exact);
  for (int i = 0; i < 64; ++i) {
    S const x = S((i * 37) % 64) * 3; // inserted out of order
    line.insert(GAabb3<S>{{x, 0, 0}, {x + 1, 1, 1}});
  }
  line.rebuild();
  GWideBvh<T> const bvh(line);
  GWideBvh<T, 4 * (lanes_v<T> < 2 ? 2 : lanes_v<T>)> const bvh4(line);
  for (S dir : {S(1), S(-1)}) {
    GRay3<S> const ray{{dir > 0 ? S(-10) : S(300), 0.5f, 0.5f}, {dir, 0, 0}};
    auto const ordered = [&](auto const& q) {
      std::vector<S> entries;
      q.ray_query(ray, S(1000), [&](ProxyId, S entry) {
        entries.push_back(entry);
        return S(1000);
      });
      REQUIRE(entries.size() == 64);
      REQUIRE(std::is_sorted(entries.begin(), entries.end()));
    };
    ordered(line);
    ordered(bvh);
    ordered(bvh4);
  }
  // Identical boxes: every entry ties, so the ray visits leaves in slot order, which is
  // the box query's order (the tree's left-first order).
  std::mt19937 g(3);
  for (int n : {3, 4, 5, 16, 40}) {
    GAabbTree<S> same(exact);
    for (int i = 0; i < n; ++i)
      same.insert(GAabb3<S>{{0, 0, 0}, {1, 1, 1}});
    for (int round = 0; round < 2; ++round) {
      INFO(n << " identical boxes, round " << round);
      GWideBvh<T> const wb(same);
      GWideBvh<T, 2 * (lanes_v<T> < 2 ? 2 : lanes_v<T>)> const wb2(same);
      GRay3<S> const ray{{-1, 0.5f, 0.5f}, {1, 0, 0}};
      auto const order = [&](auto const& q) {
        std::vector<ProxyId> ids;
        q.ray_query(ray, S(10), [&](ProxyId id, S) {
          ids.push_back(id);
          return S(10);
        });
        return ids;
      };
      auto const want = tree_query(same, GAabb3<S>{{0, 0, 0}, {1, 1, 1}});
      REQUIRE(want.size() == std::size_t(n));
      REQUIRE(order(same) == want);
      std::vector<ProxyId> wq;
      wb.query(GAabb3<S>{{0, 0, 0}, {1, 1, 1}}, [&](ProxyId id) {
        wq.push_back(id);
        return true;
      });
      REQUIRE(wq == want);
      REQUIRE(order(wb) == want);
      REQUIRE(order(wb2) == want);
      same.rebuild();
    }
  }
  // An entry exactly at max_toi counts, in the tree and the wide copy.
  GAabbTree<S> two(exact);
  two.insert(GAabb3<S>{{1, 0, 0}, {2, 1, 1}});
  two.insert(GAabb3<S>{{3, 0, 0}, {4, 1, 1}});
  GWideBvh<T> const wt(two);
  GRay3<S> const ray{{0, 0.5f, 0.5f}, {1, 0, 0}};
  for (S m : {S(1), S(3)}) {
    std::size_t const want = m == S(1) ? 1 : 2;
    std::size_t a = 0, b = 0;
    two.ray_query(ray, m, [&](ProxyId, S) {
      ++a;
      return m;
    });
    wt.ray_query(ray, m, [&](ProxyId, S) {
      ++b;
      return m;
    });
    CHECK(a == want);
    CHECK(b == want);
    auto const h = wt.ray_cast(ray, m, [&](ProxyId id, S) { return id == 0 ? S(1) : S(3); });
    CHECK(h.proxy == 0);
    // A leaf toi exactly at max_toi is a hit.
    auto const h1 = wt.ray_cast(ray, m, [&](ProxyId id, S) { return id == 1 ? m : S(5); });
    CHECK(h1.proxy == (m == S(3) ? 1u : null_proxy));
  }
}

namespace {

/// The header's collapse rule, written out: the binary node's two children, then the inner
/// child of largest surface area (the first of equal ones) opened in place until there are K.
template <class T, std::size_t K>
void check_collapse(GWideBvh<T, K> const& bvh, GAabbTree<scalar_t<T>> const& tree,
                    std::uint32_t wide, std::uint32_t bin, std::size_t& leaves) {
  using S = scalar_t<T>;
  using W = GWideBvh<T, K>;
  auto const nodes = tree.nodes();
  std::vector<std::uint32_t> kids;
  if (nodes[bin].is_leaf())
    kids = {bin};
  else
    kids = {nodes[bin].left, nodes[bin].right};
  while (kids.size() < K) {
    std::size_t best = kids.size();
    S best_area = S(-1);
    for (std::size_t i = 0; i < kids.size(); ++i)
      if (!nodes[kids[i]].is_leaf() && nodes[kids[i]].box.surface_area() > best_area) {
        best_area = nodes[kids[i]].box.surface_area();
        best = i;
      }
    if (best == kids.size()) break;
    std::uint32_t const opened = kids[best];
    kids[best] = nodes[opened].right;
    kids.insert(kids.begin() + std::ptrdiff_t(best), nodes[opened].left);
  }
  auto const& node = bvh.nodes()[wide];
  for (std::size_t i = 0; i < K; ++i) {
    INFO("wide node " << wide << " slot " << i);
    GAabb3<S> const lane_box{{node.lo_x[i], node.lo_y[i], node.lo_z[i]},
                             {node.hi_x[i], node.hi_y[i], node.hi_z[i]}};
    if (i >= kids.size()) {
      REQUIRE(node.child[i] == W::empty_child);
      REQUIRE(same_box(lane_box, GAabb3<S>{})); // EMPTY
      continue;
    }
    auto const& c = nodes[kids[i]];
    REQUIRE(same_box(lane_box, c.box));
    if (c.is_leaf()) {
      REQUIRE(node.child[i] == (W::leaf_bit | c.proxy));
      ++leaves;
    } else {
      REQUIRE(node.child[i] < bvh.node_count());
      check_collapse(bvh, tree, node.child[i], kids[i], leaves);
    }
  }
}

template <class T, std::size_t K>
void check_collapse_all(GAabbTree<scalar_t<T>> const& tree) {
  GWideBvh<T, K> const bvh(tree);
  std::size_t leaves = 0;
  check_collapse(bvh, tree, 0, tree.root(), leaves);
  REQUIRE(leaves == tree.size());
}

} // namespace

TEMPLATE_LIST_TEST_CASE("wide bvh: the copy is the header's collapse of the tree", "[spatial][bvh]",
                        test::f32_types) {
  using T = TestType;
  constexpr std::size_t K1 = lanes_v<T> < 2 ? 2 : lanes_v<T>;
  for (bool optimised : {false, true}) {
    Scene<float> const s = make_scene<float>(75, 300, optimised);
    check_collapse_all<T, K1>(s.tree);
    check_collapse_all<T, 2 * K1>(s.tree);
    check_collapse_all<T, default_arity_v<T>>(s.tree);
  }
}
