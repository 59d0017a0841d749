// GAabbTree: long random edit sequences checked after every operation (validate) and against
// brute force over every live proxy; move() and the margin rule; optimize()'s modes and the
// adaptive thresholds; rebuild quality; determinism; bad input and extreme scenes.
#include "spatial_support.hpp"

#include <plume/spatial/aabb_tree.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

using namespace plume;
using namespace plume::test;

namespace {

template <class S>
void check_query(GAabbTree<S> const& tree, GAabb3<S> const& q, long op) {
  auto const got = tree_query(tree, q);
  auto const got_sorted = sorted(got);
  INFO("op " << op);
  REQUIRE(std::adjacent_find(got_sorted.begin(), got_sorted.end()) == got_sorted.end());
  REQUIRE(got_sorted == brute_query(tree, q));
}

template <class S>
void check_ray(GAabbTree<S> const& tree, GRay3<S> const& ray, S max_toi, long op) {
  std::vector<RayHitRecord> got;
  tree.ray_query(ray, max_toi, [&](ProxyId id, S entry) {
    got.push_back({id, bits_of(entry)});
    return max_toi;
  });
  INFO("op " << op);
  REQUIRE(sorted(got) == brute_ray(tree, ray, max_toi));
}

template <class S>
GRay3<S> random_ray(std::mt19937& g, double world) {
  GVec3<S> const o = random_point<S>(g, -world, world);
  GVec3<S> d = random_point<S>(g, -1, 1);
  if (g() % 8 == 0) d.x = S(0); // axis-parallel components
  if (g() % 8 == 0) d.z = -S(0);
  if (d.x == S(0) && d.y == S(0) && d.z == S(0)) d.y = S(1);
  return {o, d};
}

/// After optimize() every inner box is the exact union of its children again (the moved
/// leaves' enlarged ancestors were dissolved or refitted).
template <class S>
bool exact_unions(GAabbTree<S> const& tree) {
  auto const nodes = tree.nodes();
  for (auto const& node : nodes)
    if (node.height > 0 && !same_box(node.box, nodes[node.left].box.merge(nodes[node.right].box)))
      return false;
  return true;
}

/// `ops` random operations; validate() after each one, brute force periodically.
template <class S>
void edit_sequence(std::uint32_t seed, long ops) {
  using Box = GAabb3<S>;
  GAabbTree<S> tree;
  std::mt19937 g(seed);
  std::vector<ProxyId> live;
  std::vector<Box> tight; // by id
  std::vector<std::uint64_t> user;
  std::vector<ProxyId> freed; // the reuse rule: last freed, first reused
  std::size_t moves_out = 0, moves_in = 0, max_live = 0;
  TreeOptimization const modes[4] = {TreeOptimization::reinsert, TreeOptimization::partial_rebuild,
                                     TreeOptimization::full_rebuild, TreeOptimization::adaptive};
  for (long op = 0; op < ops; ++op) {
    double const r = uniform<double>(g, 0, 1);
    std::size_t const n = live.size();
    if (n == 0 || (r < 0.3 && n < 1000)) {
      Box const b = random_box<S>(g, 20, 3);
      std::uint64_t const u = g();
      ProxyId const want = freed.empty() ? ProxyId(tight.size()) : freed.back();
      ProxyId const id = tree.insert(b, u);
      REQUIRE(id == want);
      if (!freed.empty()) freed.pop_back();
      if (id >= tight.size()) {
        tight.resize(id + 1);
        user.resize(id + 1);
      }
      tight[id] = b;
      user[id] = u;
      live.push_back(id);
      REQUIRE(same_box(tree.fat_box(id), b.grow(tree.config().margin_for(b))));
    } else if (r < 0.5) {
      std::size_t const k = g() % n;
      ProxyId const id = live[k];
      live[k] = live.back();
      live.pop_back();
      tree.remove(id);
      freed.push_back(id);
      REQUIRE(!tree.contains(id));
    } else if (r < 0.52) {
      ProxyId const id = live[g() % n];
      user[id] = g();
      tree.set_user(id, user[id]);
    } else {
      ProxyId const id = live[g() % n];
      Box b;
      if (g() % 4 != 0) { // small: often still inside the fat box
        GVec3<S> const d = random_point<S>(g, -0.04, 0.04);
        b = {tight[id].min + d, tight[id].max + d};
      } else {
        b = random_box<S>(g, 20, 3);
      }
      Box const fat = tree.fat_box(id);
      std::size_t const moved = tree.moved_count();
      bool const out = !bool(fat.contains_aabb(b));
      REQUIRE(tree.move(id, b) == out);
      if (out) {
        ++moves_out;
        REQUIRE(same_box(tree.fat_box(id), b.grow(tree.config().margin_for(b))));
        REQUIRE(tree.moved_count() >= moved);
      } else {
        ++moves_in;
        REQUIRE(same_box(tree.fat_box(id), fat));
        REQUIRE(tree.moved_count() == moved);
      }
      tight[id] = b;
    }
    if (op % 250 == 249) {
      TreeOptimization const mode = modes[(op / 250) % 4];
      S const f = tree.empty() ? S(0) : S(tree.moved_count()) / S(tree.size());
      TreeOptimization const want = mode != TreeOptimization::adaptive ? mode
                                    : f < S(0.15)                      ? TreeOptimization::reinsert
                                    : f < S(0.45) ? TreeOptimization::partial_rebuild
                                                  : TreeOptimization::full_rebuild;
      bool const had_moves = tree.moved_count() > 0;
      REQUIRE(tree.optimize(mode) == want);
      REQUIRE(tree.moved_count() == 0);
      if (had_moves) REQUIRE(exact_unions(tree));
    }
    if (op % 9973 == 9972) tree.rebuild();
    std::string const v = tree.validate();
    if (!v.empty()) FAIL("validate() after op " << op << ": " << v);
    REQUIRE(tree.size() == live.size());
    max_live = std::max(max_live, live.size());
    if (op % 50 == 0) check_query(tree, random_box<S>(g, 22, 10), op);
    if (op % 200 == 0) {
      GRay3<S> const ray = random_ray<S>(g, 25);
      check_ray(tree, ray, S(g() % 2 ? 60 : 8), op);
    }
    if (op % 1000 == 0) {
      REQUIRE(tree.proxy_ids() == sorted(live));
      for (ProxyId id : live) {
        REQUIRE(same_box(tree.tight_box(id), tight[id]));
        REQUIRE(tree.user(id) == user[id]);
      }
    }
  }
  // The sequence did what it was meant to: both kinds of move, a full tree.
  CHECK(moves_out > std::size_t(ops / 20));
  CHECK(moves_in > std::size_t(ops / 20));
  // The full sequence fills the tree to its 1,000-proxy cap; the sanitizer build's shorter
  // one (fixed seed) reaches 941.
  CHECK((max_live == 1000 || (ops < 100000 && max_live >= 900)));
}

/// A tree of n random boxes, ids 0..n-1.
template <class S>
GAabbTree<S> random_tree(std::uint32_t seed, int n, double world = 20, double size = 3,
                         GTreeConfig<S> const& config = {}) {
  GAabbTree<S> tree(config);
  std::mt19937 g(seed);
  for (int i = 0; i < n; ++i)
    tree.insert(random_box<S>(g, world, size), std::uint64_t(i));
  return tree;
}

template <class S>
void check_many_queries(GAabbTree<S> const& tree, std::uint32_t seed, int count = 200,
                        double world = 22) {
  std::mt19937 g(seed);
  for (int i = 0; i < count; ++i) {
    check_query(tree, random_box<S>(g, world, world / 2), i);
    check_ray(tree, random_ray<S>(g, world), S(4 * world), i);
  }
}

/// Moves the proxies `ids` far outside their fat boxes.
template <class S>
void move_out(GAabbTree<S>& tree, std::vector<ProxyId> const& ids, std::mt19937& g) {
  for (ProxyId id : ids)
    REQUIRE(tree.move(id, random_box<S>(g, 20, 3).grow(S(0.1))));
}

std::vector<ProxyId> first_ids(std::size_t k) {
  std::vector<ProxyId> v(k);
  for (std::size_t i = 0; i < k; ++i)
    v[i] = ProxyId(i);
  return v;
}

} // namespace

TEMPLATE_TEST_CASE("tree: random edit sequences keep every invariant and answer exactly",
                   "[spatial][tree]", float, double) {
#if PLUME_TEST_UNOPTIMISED
  long const ops = 10000; // the -O0 sanitizer build
#else
  long const ops = 100000;
#endif
  edit_sequence<TestType>(20240601u, ops);
}

TEMPLATE_TEST_CASE("tree: move inside the fat box changes nothing, outside refits",
                   "[spatial][tree]", float, double) {
  using S = TestType;
  using Box = GAabb3<S>;
  GAabbTree<S> tree = random_tree<S>(7, 64);
  for (ProxyId id = 0; id < 64; ++id) {
    Box const t = tree.tight_box(id);
    Box const fat = tree.fat_box(id);
    S const m = tree.config().margin_for(t);
    // Inside (a shift by less than the margin, and the fat box itself: containment is closed).
    GAabbTree<S> const before = tree;
    GVec3<S> const d{m / S(2), -m / S(3), m / S(4)};
    Box const inside{t.min + d, t.max + d};
    REQUIRE(bool(fat.contains_aabb(inside)));
    REQUIRE_FALSE(tree.move(id, inside));
    REQUIRE(compare_nodes(tree, before) == "");
    REQUIRE(tree.moved_count() == 0);
    REQUIRE(same_box(tree.tight_box(id), inside));
    REQUIRE_FALSE(tree.move(id, fat));
    REQUIRE(compare_nodes(tree, before) == "");
    REQUIRE(tree.validate() == "");
    REQUIRE(tree.move(id, t) == false);
  }
  // Outside: a new fat box, every query exact before optimize(), counted once.
  std::mt19937 g(3);
  for (ProxyId id = 0; id < 64; id += 3) {
    Box const t = tree.tight_box(id);
    S const m = tree.config().margin_for(t);
    GVec3<S> const d{m * S(1.5) + S(0.01), S(0), S(0)};
    Box const moved{t.min + d, t.max + d};
    std::size_t const count = tree.moved_count();
    REQUIRE(tree.move(id, moved));
    REQUIRE(same_box(tree.fat_box(id), moved.grow(tree.config().margin_for(moved))));
    REQUIRE(tree.moved_count() == count + 1);
    REQUIRE(tree.validate() == "");
    check_query(tree, tree.fat_box(id), id);
    // Far away, then again: still one moved leaf.
    REQUIRE(tree.move(id, random_box<S>(g, 40, 2).grow(S(0.2))));
    REQUIRE(tree.move(id, random_box<S>(g, 40, 2).grow(S(0.2))));
    REQUIRE(tree.moved_count() == count + 1);
    REQUIRE(tree.validate() == "");
    check_many_queries(tree, id, 20, 45);
  }
  // A removed moved leaf leaves the moved list.
  std::size_t const count = tree.moved_count();
  tree.remove(0);
  REQUIRE(tree.moved_count() == count - 1);
  REQUIRE(tree.validate() == "");
}

TEMPLATE_TEST_CASE("tree: the margin rule", "[spatial][tree]", float, double) {
  using S = TestType;
  using Box = GAabb3<S>;
  GTreeConfig<S> const c;
  CHECK(c.margin == S(0.05));
  CHECK(c.margin_fraction == S(0.125));
  CHECK(c.reinsert_below == S(0.15));
  CHECK(c.partial_below == S(0.45));
  // min(0.05, 0.125 x the largest extent)
  CHECK(c.margin_for(Box{{0, 0, 0}, {1, 0.2f, 0.1f}}) == S(0.05));
  CHECK(c.margin_for(Box{{0, 0, 0}, {0.1f, 3, 0}}) == S(0.05));
  CHECK(c.margin_for(Box{{0, 0, 0}, {S(0.2), S(0.1), S(0)}}) == S(0.125) * S(0.2));
  CHECK(c.margin_for(Box{{0, 0, 0}, {S(0.1), S(0.3), S(0.2)}}) == S(0.125) * S(0.3));
  CHECK(c.margin_for(Box{{0, 0, 0}, {S(0.1), S(0.2), S(0.39)}}) == S(0.125) * S(0.39));
  CHECK(c.margin_for(Box{{1, 2, 3}, {1, 2, 3}}) == S(0));
  // scaled() changes the length unit of the absolute margin only.
  GTreeConfig<S> const cm = c.scaled(S(100));
  CHECK(cm.margin == S(0.05) * S(100));
  CHECK(cm.margin_fraction == S(0.125));
  CHECK(cm.margin_for(Box{{0, 0, 0}, {1, 1, 1}}) == S(0.125));
  CHECK(cm.margin_for(Box{{0, 0, 0}, {100, 1, 1}}) == S(0.05) * S(100));
  CHECK(c.scaled(S(0.01)).margin_for(Box{{0, 0, 0}, {1, 1, 1}}) == S(0.05) * S(0.01));
  // Negative or NaN settings give exact boxes.
  GTreeConfig<S> neg;
  neg.margin = S(-1);
  CHECK(neg.margin_for(Box{{0, 0, 0}, {1, 1, 1}}) == S(0));
  neg.margin = std::numeric_limits<S>::quiet_NaN();
  CHECK(neg.margin_for(Box{{0, 0, 0}, {1, 1, 1}}) == S(0));
  // The tree uses its config.
  GAabbTree<S> tree(cm);
  Box const b{{0, 0, 0}, {1, 2, 1}};
  ProxyId const id = tree.insert(b);
  CHECK(same_box(tree.fat_box(id), b.grow(S(0.25))));
  CHECK(tree.config().margin == cm.margin);
}

TEST_CASE("tree: adaptive optimisation picks the mode by the moved fraction", "[spatial][tree]") {
  using R = TreeOptimization;
  struct Case {
    int n, k;
    R want;
  };
  Case const cases[] = {{100, 0, R::reinsert},           {100, 1, R::reinsert},
                        {100, 14, R::reinsert},          {100, 15, R::partial_rebuild},
                        {100, 16, R::partial_rebuild},   {100, 44, R::partial_rebuild},
                        {100, 45, R::full_rebuild},      {100, 46, R::full_rebuild},
                        {100, 100, R::full_rebuild},     {1000, 149, R::reinsert},
                        {1000, 150, R::partial_rebuild}, {1000, 151, R::partial_rebuild},
                        {1000, 449, R::partial_rebuild}, {1000, 450, R::full_rebuild}};
  for (Case const& c : cases) {
    INFO(c.k << " of " << c.n << " moved");
    AabbTree tree = random_tree<float>(11, c.n);
    std::mt19937 g(5);
    move_out(tree, first_ids(std::size_t(c.k)), g);
    REQUIRE(tree.moved_count() == std::size_t(c.k));
    REQUIRE(tree.optimize() == c.want);
    REQUIRE(tree.moved_count() == 0);
    REQUIRE(tree.validate() == "");
    check_many_queries(tree, 9, 50);
    // A second optimize has nothing to do.
    GAabbTree<float> const copy = tree;
    REQUIRE(tree.optimize() == R::reinsert);
    REQUIRE(compare_nodes(tree, copy) == "");
  }
  // The thresholds come from the config.
  TreeConfig cfg;
  cfg.reinsert_below = 0.5f;
  cfg.partial_below = 0.75f;
  for (auto [k, want] : {std::pair{49, R::reinsert}, std::pair{50, R::partial_rebuild},
                         std::pair{74, R::partial_rebuild}, std::pair{75, R::full_rebuild}}) {
    AabbTree tree = random_tree<float>(12, 100, 20, 3, cfg);
    std::mt19937 g(6);
    move_out(tree, first_ids(std::size_t(k)), g);
    REQUIRE(tree.optimize() == want);
    REQUIRE(tree.validate() == "");
  }
}

TEMPLATE_TEST_CASE("tree: every optimisation mode gives a valid, exact, better tree",
                   "[spatial][tree]", float, double) {
  using S = TestType;
  using R = TreeOptimization;
  for (R mode : {R::reinsert, R::partial_rebuild, R::full_rebuild, R::adaptive}) {
    for (std::size_t k : {std::size_t(1), std::size_t(30), std::size_t(300), std::size_t(1000)}) {
      INFO("mode " << int(mode) << ", " << k << " moved");
      GAabbTree<S> tree = random_tree<S>(21, 1000);
      tree.rebuild();
      std::mt19937 g(8);
      std::vector<ProxyId> ids;
      for (std::size_t i = 0; i < k; ++i)
        ids.push_back(ProxyId((i * 7919) % 1000));
      move_out(tree, ids, g);
      S const before = tree.stats().area_ratio;
      R const ran = tree.optimize(mode);
      if (mode != R::adaptive) REQUIRE(ran == mode);
      REQUIRE(tree.moved_count() == 0);
      REQUIRE(tree.validate() == "");
      REQUIRE(exact_unions(tree));
      check_many_queries(tree, 17, 100);
      // Moves only ever enlarge the ancestors: putting the moved leaves back in their place
      // is cheaper (the enlarged ancestors are the cost the optimisation removes).
      if (k >= 30) CHECK(tree.stats().area_ratio < before);
    }
  }
}

TEMPLATE_TEST_CASE("tree: rebuild quality, refit, stats", "[spatial][tree]", float, double) {
  using S = TestType;
  for (int n : {2, 3, 17, 1000, 5000}) {
    INFO(n << " boxes");
    GAabbTree<S> tree = random_tree<S>(31, n, 50, 2);
    int const log2n = int(std::ceil(std::log2(double(n))));
    CHECK(tree.stats().height <= 3 * log2n); // SAH insertion
    tree.rebuild();
    REQUIRE(tree.validate() == "");
    auto const st = tree.stats();
    CHECK(st.proxies == std::size_t(n));
    CHECK(st.nodes == std::size_t(2 * n - 1));
    CHECK(st.height >= log2n);
    CHECK(st.height <= 2 * log2n);
    CHECK(st.area_ratio >= S(1));
    check_many_queries(tree, 2, 50, 55);
  }
  // Binned SAH on evenly spaced equal boxes splits every range at its middle: 2^k boxes in a
  // row give a perfect tree, each child of the root holding one half.
  for (int k : {4, 6, 8}) {
    INFO(k);
    GAabbTree<S> row;
    for (int i = 0; i < (1 << k); ++i)
      row.insert(GAabb3<S>{{S(i), 0, 0}, {S(i) + S(1), 1, 1}});
    row.rebuild();
    REQUIRE(row.validate() == "");
    CHECK(row.stats().height == k);
    auto const& root = row.nodes()[row.root()];
    CHECK(row.nodes()[root.left].box.max.x < S(1 << (k - 1)) + S(0.5));
    CHECK(row.nodes()[root.right].box.min.x > S(1 << (k - 1)) - S(0.5));
  }
  // refit() tightens what moves enlarged back to the exact unions.
  GAabbTree<S> tree = random_tree<S>(32, 300);
  std::mt19937 g(1);
  for (ProxyId id = 0; id < 300; id += 2)
    tree.move(id, random_box<S>(g, 20, 3).grow(S(0.1)));
  S const enlarged = tree.stats().area_ratio;
  tree.refit();
  REQUIRE(tree.validate() == "");
  for (auto const& node : tree.nodes())
    if (node.height > 0)
      REQUIRE(same_box(node.box, tree.nodes()[node.left].box.merge(tree.nodes()[node.right].box)));
  CHECK(tree.stats().area_ratio < enlarged);
  check_many_queries(tree, 4, 50);
  // Stats of small trees.
  GAabbTree<S> one;
  CHECK(one.stats().height == 0);
  CHECK(one.stats().nodes == 0);
  one.insert(GAabb3<S>{{0, 0, 0}, {1, 1, 1}});
  CHECK(one.stats().height == 0);
  CHECK(one.stats().nodes == 1);
  CHECK(one.stats().area_ratio == S(0));
  one.insert(GAabb3<S>{{2, 0, 0}, {3, 1, 1}});
  CHECK(one.stats().height == 1);
  CHECK(one.stats().nodes == 3);
  CHECK(one.stats().area_ratio == S(1));
}

namespace {

/// A fixed sequence of every kind of edit; the log holds every query's callback order.
template <class S>
void scripted(GAabbTree<S>& tree, std::vector<ProxyId>& log, std::uint32_t seed) {
  std::mt19937 g(seed);
  std::vector<ProxyId> live;
  for (int op = 0; op < 6000; ++op) {
    auto const r = g() % 10;
    if (live.empty() || r < 3) {
      live.push_back(tree.insert(random_box<S>(g, 20, 3), std::uint64_t(op)));
    } else if (r < 5) {
      std::size_t const k = g() % live.size();
      tree.remove(live[k]);
      live[k] = live.back();
      live.pop_back();
    } else {
      ProxyId const id = live[g() % live.size()];
      tree.move(id, g() % 2 ? random_box<S>(g, 20, 3) : tree.tight_box(id).grow(S(0.02)));
    }
    if (op % 500 == 499) tree.optimize(TreeOptimization((op / 500) % 4));
    if (op % 7 == 0) {
      auto const q = tree_query(tree, random_box<S>(g, 22, 12));
      log.insert(log.end(), q.begin(), q.end());
      log.push_back(null_proxy);
      tree.ray_query(random_ray<S>(g, 20), S(50), [&](ProxyId id, S) {
        log.push_back(id);
        return S(50);
      });
      log.push_back(null_proxy);
    }
  }
}

/// The tree's shape by proxy: leaves as their ids and box bits, inner nodes as brackets.
template <class S>
std::vector<std::uint64_t> shape_of(GAabbTree<S> const& tree) {
  std::vector<std::uint64_t> out;
  if (tree.root() == GAabbTree<S>::null_node) return out;
  std::vector<std::uint32_t> stack{tree.root()};
  auto const nodes = tree.nodes();
  while (!stack.empty()) {
    std::uint32_t const n = stack.back();
    stack.pop_back();
    if (n == GAabbTree<S>::null_node - 1) {
      out.push_back(~std::uint64_t(1));
      continue;
    }
    auto const& node = nodes[n];
    if (node.is_leaf()) {
      out.push_back(node.proxy);
      for (S v : {node.box.min.x, node.box.min.y, node.box.min.z, node.box.max.x, node.box.max.y,
                  node.box.max.z})
        out.push_back(bits_of(v));
      continue;
    }
    out.push_back(~std::uint64_t(0));
    stack.push_back(GAabbTree<S>::null_node - 1);
    stack.push_back(node.right);
    stack.push_back(node.left);
  }
  return out;
}

} // namespace

TEMPLATE_TEST_CASE("tree: the same operations give the same tree, node for node",
                   "[spatial][tree][determinism]", float, double) {
  using S = TestType;
  GAabbTree<S> a, b;
  std::vector<ProxyId> la, lb;
  scripted(a, la, 99);
  scripted(b, lb, 99);
  REQUIRE(a.validate() == "");
  REQUIRE(compare_nodes(a, b) == "");
  REQUIRE(la == lb);
  REQUIRE(la.size() > 1000);
  // A different sequence gives a different tree (the comparison can fail).
  GAabbTree<S> c;
  std::vector<ProxyId> lc;
  scripted(c, lc, 100);
  REQUIRE(compare_nodes(a, c) != "");

  // rebuild() does not depend on where the leaves sit: the same proxies with the same boxes,
  // reached through a different history (other node slots), give the same shape.
  std::mt19937 g(4);
  std::vector<GAabb3<S>> boxes;
  for (int i = 0; i < 500; ++i)
    boxes.push_back(random_box<S>(g, 20, 3));
  GAabbTree<S> x, y;
  for (auto const& box : boxes)
    x.insert(box);
  for (int i = 0; i < 700; ++i)
    y.insert(random_box<S>(g, 20, 3));
  for (int i = 699; i >= 0; --i)
    y.remove(ProxyId(i)); // freed last to first: the next inserts get 0, 1, 2, ...
  for (std::size_t i = 0; i < boxes.size(); ++i)
    REQUIRE(y.insert(boxes[boxes.size() - 1 - i]) == ProxyId(i));
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    // Far away and back: proxy i has x's tight and fat box, in another leaf slot.
    GVec3<S> const away{S(100), S(0), S(0)};
    REQUIRE(y.move(ProxyId(i), {boxes[i].min + away, boxes[i].max + away}));
    REQUIRE(y.move(ProxyId(i), boxes[i]));
    REQUIRE(same_box(y.fat_box(ProxyId(i)), x.fat_box(ProxyId(i))));
  }
  REQUIRE(shape_of(x) != shape_of(y));
  x.rebuild();
  y.rebuild();
  REQUIRE(y.validate() == "");
  REQUIRE(shape_of(x) == shape_of(y));
}

TEMPLATE_TEST_CASE("tree: bad boxes and bad ids are refused, the tree unchanged", "[spatial][tree]",
                   float, double) {
  using S = TestType;
  using Box = GAabb3<S>;
  S const nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  GAabbTree<S> tree = random_tree<S>(41, 50);
  std::mt19937 g(2);
  move_out(tree, {3, 4}, g);
  GAabbTree<S> const before = tree;
  std::vector<Box> bad;
  for (int axis = 0; axis < 3; ++axis)
    for (S v : {nan, inf, -inf}) {
      for (int side = 0; side < 2; ++side) {
        Box b{{0, 0, 0}, {1, 1, 1}};
        GVec3<S>& p = side ? b.max : b.min;
        (axis == 0 ? p.x : axis == 1 ? p.y : p.z) = v;
        bad.push_back(b);
      }
    }
  bad.push_back(Box{{0, 0, 0}, {-S(0.001), 1, 1}}); // inverted
  bad.push_back(Box{{0, 2, 0}, {1, 1, 1}});
  bad.push_back(Box{{0, 0, 1}, {1, 1, std::nextafter(S(1), S(0))}});
  bad.push_back(Box{}); // EMPTY
  for (Box const& b : bad) {
    INFO(b.min << " " << b.max);
    REQUIRE_THROWS_AS(tree.insert(b, 1), std::invalid_argument);
    REQUIRE_THROWS_AS(tree.move(5, b), std::invalid_argument);
    REQUIRE_THROWS_AS(tree.move(3, b), std::invalid_argument);
    REQUIRE(tree.size() == 50);
    REQUIRE(tree.moved_count() == 2);
    REQUIRE(compare_nodes(tree, before) == "");
    REQUIRE(same_box(tree.tight_box(5), before.tight_box(5)));
    REQUIRE(same_box(tree.tight_box(3), before.tight_box(3)));
    REQUIRE(tree.validate() == "");
  }
  // The next insert still takes the next id.
  REQUIRE(tree.insert(Box{{0, 0, 0}, {1, 1, 1}}) == 50);
  tree.remove(50);
  // Bad ids.
  tree.remove(7);
  GAabbTree<S> const after = tree;
  for (ProxyId id : {ProxyId(7), ProxyId(50), ProxyId(51), ProxyId(12345), null_proxy}) {
    INFO("id " << id);
    REQUIRE_FALSE(tree.contains(id));
    REQUIRE_THROWS_AS(tree.remove(id), std::out_of_range);
    REQUIRE_THROWS_AS(tree.move(id, Box{{0, 0, 0}, {1, 1, 1}}), std::out_of_range);
    REQUIRE_THROWS_AS(tree.move(id, Box{{0, 0, 0}, {nan, 1, 1}}), std::out_of_range);
    REQUIRE_THROWS_AS(tree.set_user(id, 1), std::out_of_range);
    REQUIRE_THROWS_AS(tree.user(id), std::out_of_range);
    REQUIRE_THROWS_AS(tree.tight_box(id), std::out_of_range);
    REQUIRE_THROWS_AS(tree.fat_box(id), std::out_of_range);
    REQUIRE(compare_nodes(tree, after) == "");
    REQUIRE(tree.validate() == "");
  }
  // Ids are reused, last freed first; clear() starts again from 0.
  tree.remove(9);
  REQUIRE(tree.insert(Box{{0, 0, 0}, {1, 1, 1}}) == 9);
  REQUIRE(tree.insert(Box{{0, 0, 0}, {1, 1, 1}}) == 7);
  REQUIRE(tree.insert(Box{{0, 0, 0}, {1, 1, 1}}) == 50);
  REQUIRE(tree.insert(Box{{0, 0, 0}, {1, 1, 1}}) == 51);
  tree.clear();
  REQUIRE(tree.empty());
  REQUIRE(tree.validate() == "");
  REQUIRE_THROWS_AS(tree.remove(0), std::out_of_range);
  REQUIRE(tree.insert(Box{{0, 0, 0}, {1, 1, 1}}) == 0);
  REQUIRE(tree.validate() == "");
}

TEMPLATE_TEST_CASE("tree: empty trees, degenerate rays and queries", "[spatial][tree]", float,
                   double) {
  using S = TestType;
  using Box = GAabb3<S>;
  using Ray = GRay3<S>;
  S const nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  int calls = 0;
  auto const count = [&](ProxyId) {
    ++calls;
    return true;
  };
  auto const count_ray = [&](ProxyId, S) {
    ++calls;
    return S(100);
  };
  GAabbTree<S> empty;
  REQUIRE(empty.validate() == "");
  REQUIRE(empty.root() == GAabbTree<S>::null_node);
  empty.query(Box{{-1e30f, -1e30f, -1e30f}, {1e30f, 1e30f, 1e30f}}, count);
  empty.ray_query(Ray{{0, 0, 0}, {1, 0, 0}}, inf, count_ray);
  REQUIRE(empty.optimize() == TreeOptimization::reinsert);
  empty.rebuild();
  empty.refit();
  REQUIRE(empty.validate() == "");
  REQUIRE(calls == 0);

  GAabbTree<S> tree = random_tree<S>(51, 200, 10, 3);
  ProxyId const far = tree.insert(Box{{1000, -1, -1}, {1001, 1, 1}});
  std::vector<Ray> const no_hit_rays = {
      Ray{{0, 0, 0}, {0, 0, 0}},   Ray{{0, 0, 0}, {-S(0), S(0), -S(0)}},
      Ray{{nan, 0, 0}, {1, 0, 0}}, Ray{{0, 0, 0}, {1, nan, 0}},
      Ray{{inf, 0, 0}, {1, 0, 0}}, Ray{{0, 0, 0}, {1, 0, -inf}}};
  for (Ray const& ray : no_hit_rays) {
    tree.ray_query(ray, S(100), count_ray);
    tree.ray_query(ray, inf, count_ray);
  }
  Ray const good{{-20, 0.5f, 0.5f}, {1, 0, 0}};
  for (S m : {S(-1), -S(0) - S(1e-30f), -inf, nan})
    tree.ray_query(good, m, count_ray);
  tree.query(Box{{0, 0, 0}, {nan, 1, 1}}, count);
  tree.query(Box{{nan, nan, nan}, {nan, nan, nan}}, count);
  REQUIRE(calls == 0);
  // Zero max_toi: boxes that contain the origin; infinite max_toi reaches everything ahead.
  Ray const inside{tree.tight_box(far).center(), {-1, 0, 0}};
  std::vector<ProxyId> at_zero;
  tree.ray_query(inside, S(0), [&](ProxyId id, S entry) {
    at_zero.push_back(id);
    REQUIRE(entry == S(0));
    return S(0);
  });
  REQUIRE(at_zero == std::vector<ProxyId>{far});
  bool seen_far = false;
  std::vector<RayHitRecord> got;
  Ray const toward{{-30, 0.25f, 0.125f}, {1, 0, 0}};
  tree.ray_query(toward, inf, [&](ProxyId id, S entry) {
    seen_far |= id == far;
    got.push_back({id, bits_of(entry)});
    return inf;
  });
  REQUIRE(seen_far);
  REQUIRE(sorted(got) == brute_ray(tree, toward, inf));
  // Stopping: a negative return ends the query after that leaf.
  calls = 0;
  tree.ray_query(toward, inf, [&](ProxyId, S) {
    ++calls;
    return S(-1);
  });
  REQUIRE(calls == 1);
  // Clipping: every entry reported is within the max_toi the previous leaf returned.
  S clip = inf;
  tree.ray_query(toward, inf, [&](ProxyId, S entry) {
    REQUIRE(entry <= clip);
    clip = entry + S(5);
    return clip;
  });
  calls = 0;
  tree.query(Box{{0, 0, 0}, {1, 1, 1}}, [&](ProxyId) {
    ++calls;
    return false;
  });
  REQUIRE(calls == 1);
}

TEMPLATE_TEST_CASE("tree: a ray gliding along a face, or starting on one, meets the box",
                   "[spatial][tree]", float, double) {
  using S = TestType;
  using Box = GAabb3<S>;
  GTreeConfig<S> exact;
  exact.margin = S(0); // fat box = tight box
  GAabbTree<S> tree(exact);
  ProxyId const a = tree.insert(Box{{0, 0, 0}, {1, 1, 1}});
  tree.insert(Box{{5, 5, 5}, {6, 6, 6}});
  REQUIRE(same_box(tree.fat_box(a), Box{{0, 0, 0}, {1, 1, 1}}));
  struct Case {
    GVec3<S> o, d;
    bool hit;
    S entry;
  };
  S const tiny = std::numeric_limits<S>::denorm_min();
  Case const cases[] = {
      {{-1, 0, 0.5f}, {1, 0, 0}, true, S(1)},        // on the plane y = 0, d.y = +0
      {{-1, 0, 0.5f}, {1, -S(0), 0}, true, S(1)},    // d.y = -0
      {{-1, 1, 1}, {1, 0, -S(0)}, true, S(1)},       // along an edge
      {{2, 1, 0.5f}, {-2, 0, 0}, true, S(0.5)},      // on y = 1 from the other side
      {{0, 0.5f, 0.5f}, {-1, 0, 0}, true, S(0)},     // origin on the face, leaving
      {{0.5f, 0.5f, 0}, {0, tiny, 0}, true, S(0)},   // 1/d overflows, origin on z = 0
      {{0.5f, 0, 0.5f}, {0, tiny, 0}, true, S(0)},   // 1/d overflows, origin on y = 0
      {{-1, 0.5f, 0.5f}, {tiny, 0, 0}, false, 0},    // entry 1/tiny: beyond max_toi
      {{-1, -S(0.001), 0.5f}, {1, 0, 0}, false, 0},  // just outside the slab
      {{-1, 1.001f, 0.5f}, {1, -S(0), 0}, false, 0}, // just outside, -0
  };
  for (Case const& c : cases) {
    INFO(c.o << " + t " << c.d);
    std::vector<std::pair<ProxyId, S>> got;
    S const max_toi = S(1e3);
    tree.ray_query(GRay3<S>{c.o, c.d}, max_toi, [&](ProxyId id, S entry) {
      got.push_back({id, entry});
      return max_toi;
    });
    if (c.hit) {
      REQUIRE(got.size() == 1);
      CHECK(got[0].first == a);
      CHECK(got[0].second == c.entry);
    } else {
      CHECK(got.empty());
    }
  }
}

TEMPLATE_TEST_CASE("tree: a million proxies at one point", "[spatial][tree][extreme]", float,
                   double) {
  using S = TestType;
  using Box = GAabb3<S>;
#if PLUME_TEST_UNOPTIMISED
  int const n = 200000; // the -O0 sanitizer build
#else
  int const n = 1000000;
#endif
  GAabbTree<S> tree;
  Box const b{{1, 2, 3}, {1.5f, 2.5f, 3.5f}};
  for (int i = 0; i < n; ++i)
    tree.insert(b);
  REQUIRE(tree.validate() == "");
  tree.rebuild();
  REQUIRE(tree.validate() == "");
  int const log2n = int(std::ceil(std::log2(double(n))));
  CHECK(tree.stats().height == log2n);
  std::vector<char> seen(std::size_t(n), 0);
  std::size_t count = 0;
  tree.query(Box{{1.25f, 2.25f, 3.25f}, {1.25f, 2.25f, 3.25f}}, [&](ProxyId id) {
    REQUIRE(id < ProxyId(n));
    REQUIRE(!seen[id]);
    seen[id] = 1;
    ++count;
    return true;
  });
  CHECK(count == std::size_t(n));
  count = 0;
  tree.query(Box{{2, 2, 3}, {3, 3, 4}}, [&](ProxyId) {
    ++count;
    return true;
  });
  CHECK(count == 0);
  tree.ray_query(GRay3<S>{{-5, 2.25f, 3.25f}, {1, 0, 0}}, S(100), [&](ProxyId, S entry) {
    REQUIRE(entry == (tree.fat_box(0).min.x - S(-5)) * (S(1) / S(1))); // the fat box's face
    ++count;
    return S(100);
  });
  CHECK(count == std::size_t(n));
  // Edits on the balanced tree stay exact.
  std::mt19937 g(1);
  for (ProxyId id = 0; id < 1000; ++id)
    tree.move(ProxyId(id * 997 % ProxyId(n)), random_box<S>(g, 10, 1).grow(S(0.1)));
  REQUIRE(tree.optimize() == TreeOptimization::reinsert);
  REQUIRE(tree.validate() == "");
  check_query(tree, Box{{-10, -10, -10}, {0, 10, 10}}, 0);
}

TEMPLATE_TEST_CASE("tree: coordinates around 1e6", "[spatial][tree]", float, double) {
  using S = TestType;
  GAabbTree<S> tree;
  std::mt19937 g(61);
  std::vector<ProxyId> ids;
  for (int i = 0; i < 2000; ++i) {
    GAabb3<S> b = random_box<S>(g, 200, 4);
    b.min = b.min + GVec3<S>{S(1e6), S(-1e6), S(1e6)};
    b.max = b.max + GVec3<S>{S(1e6), S(-1e6), S(1e6)};
    ids.push_back(tree.insert(b));
  }
  REQUIRE(tree.validate() == "");
  GVec3<S> const off{S(1e6), S(-1e6), S(1e6)};
  auto const check_all = [&] {
    for (int i = 0; i < 100; ++i) {
      GAabb3<S> q = random_box<S>(g, 210, 40);
      q = {q.min + off, q.max + off};
      check_query(tree, q, i);
      GRay3<S> ray = random_ray<S>(g, 220);
      ray.origin = ray.origin + off;
      check_ray(tree, ray, S(1000), i);
    }
  };
  check_all();
  for (int i = 0; i < 2000; i += 3) {
    GAabb3<S> b = tree.tight_box(ids[std::size_t(i)]);
    GVec3<S> const d = random_point<S>(g, -1, 1);
    tree.move(ids[std::size_t(i)], {b.min + d, b.max + d});
  }
  REQUIRE(tree.validate() == "");
  check_all();
  tree.optimize(TreeOptimization::partial_rebuild);
  REQUIRE(tree.validate() == "");
  check_all();
  tree.rebuild();
  CHECK(tree.stats().height <= 2 * 11);
  check_all();
}

TEST_CASE("aabb tree: infinite query bounds meet every leaf, NaN and inverted ones none",
          "[spatial][tree][bad-input]") {
  AabbTree tree;
  std::vector<ProxyId> ids;
  for (int i = 0; i < 50; ++i)
    ids.push_back(
        tree.insert(Aabb3::from_center_half_extents(Vec3::splat(float(i)), Vec3::splat(0.5f))));
  float const inf = std::numeric_limits<float>::infinity(),
              nan = std::numeric_limits<float>::quiet_NaN();
  auto const count = [&](Aabb3 const& q) {
    std::size_t n = 0, w = 0;
    tree.query(q, [&](ProxyId) { return ++n > 0; });
    WideBvh const bvh(tree);
    bvh.query(q, [&](ProxyId) { return ++w > 0; });
    CHECK(n == w);
    return n;
  };
  CHECK(count({Vec3::splat(-inf), Vec3::splat(inf)}) == 50);
  CHECK(count({Vec3{-inf, -inf, -inf}, Vec3{10.0f, inf, inf}}) == 11); // centres 0..10
  CHECK(count({Vec3{nan, 0, 0}, Vec3::splat(inf)}) == 0);
  CHECK(count({Vec3::splat(5.0f), Vec3::splat(4.0f)}) == 0); // inverted
  CHECK(count(Aabb3{}) == 0);                                // EMPTY
}

TEST_CASE("aabb tree: builds over centroid spreads that overflow or are subnormal",
          "[spatial][tree][bad-input]") {
  // Found in review: the binned build's scale (bins / spread) was 0 or infinite there, and a
  // NaN bin index wrote outside the bins.
  float const big = 2e38f, tiny = 1e-40f;
  for (auto const& xs : {std::vector<float>{-big, big, 0.0f, big * 0.5f},
                         std::vector<float>{0.0f, tiny, 2 * tiny, 3 * tiny, 5 * tiny}}) {
    AabbTree tree;
    std::vector<Aabb3> boxes;
    for (float x : xs)
      boxes.push_back({{x, 0, 0}, {x, 1, 1}});
    std::vector<ProxyId> const ids = tree.insert_all(boxes);
    CHECK(tree.validate() == "");
    CHECK(tree.size() == xs.size());
    std::size_t n = 0;
    tree.query({Vec3{-std::numeric_limits<float>::infinity(), 0, 0},
                Vec3{std::numeric_limits<float>::infinity(), 1, 1}},
               [&](ProxyId) { return ++n > 0; });
    CHECK(n == xs.size());
    for (ProxyId id : ids) // moves to the other extreme, then every optimisation
      tree.move(id, {{-xs[id % xs.size()], 0, 0}, {-xs[id % xs.size()], 1, 1}});
    tree.optimize(TreeOptimization::partial_rebuild);
    tree.rebuild();
    CHECK(tree.validate() == "");
  }
}

TEMPLATE_TEST_CASE("tree: PLOC builds valid, exact, balanced trees close to binned SAH's",
                   "[spatial][tree][ploc]", float, double) {
  using S = TestType;
  GTreeConfig<S> ploc;
  ploc.builder = TreeBuilder::ploc;
  for (int n : {1, 2, 3, 17, 1000, 5000}) {
    INFO(n << " boxes");
    GAabbTree<S> tree = random_tree<S>(31, n, 50, 2, ploc);
    tree.rebuild();
    REQUIRE(tree.validate() == "");
    REQUIRE(exact_unions(tree));
    auto const st = tree.stats();
    CHECK(st.proxies == std::size_t(n));
    CHECK(st.nodes == std::size_t(2 * n - 1));
    check_many_queries(tree, 2, 50, 55);
    if (n < 1000) continue;
    // The same boxes built by binned SAH: PLOC's SAH cost is no more than 15% above it.
    GAabbTree<S> sah = random_tree<S>(31, n, 50, 2);
    sah.rebuild();
    CHECK(st.area_ratio <= sah.stats().area_ratio * S(1.15));
    CHECK(st.height <= 3 * int(std::ceil(std::log2(double(n)))));
  }
  // Every optimisation mode over it stays exact.
  for (TreeOptimization mode : {TreeOptimization::reinsert, TreeOptimization::partial_rebuild,
                                TreeOptimization::full_rebuild}) {
    GAabbTree<S> tree = random_tree<S>(21, 1000, 20, 3, ploc);
    tree.rebuild();
    std::mt19937 g(8);
    std::vector<ProxyId> ids;
    for (std::size_t i = 0; i < 300; ++i)
      ids.push_back(ProxyId((i * 7919) % 1000));
    move_out(tree, ids, g);
    tree.optimize(mode);
    REQUIRE(tree.validate() == "");
    REQUIRE(exact_unions(tree));
    check_many_queries(tree, 17, 100);
  }
  // Equal boxes pair up every pass: 2^16 boxes at one point give a perfect tree (a tie rule
  // that paired only the first two would need 2^16 passes and a chain).
  GAabbTree<S> same(ploc);
  std::vector<GAabb3<S>> const boxes(std::size_t(1) << 16, GAabb3<S>{{1, 2, 3}, {2, 3, 4}});
  same.insert_all(boxes);
  REQUIRE(same.validate() == "");
  CHECK(same.stats().height == 16);
  // The same boxes in the same order give the same tree, node for node.
  GAabbTree<S> a = random_tree<S>(41, 3000, 30, 2, ploc), b = random_tree<S>(41, 3000, 30, 2, ploc);
  a.rebuild();
  b.rebuild();
  REQUIRE(a.nodes().size() == b.nodes().size());
  for (std::size_t k = 0; k < a.nodes().size(); ++k) {
    REQUIRE(a.nodes()[k].left == b.nodes()[k].left);
    REQUIRE(a.nodes()[k].right == b.nodes()[k].right);
    REQUIRE(same_box(a.nodes()[k].box, b.nodes()[k].box));
  }
}

TEST_CASE("tree: a packet of rays meets, lane by lane, the leaves each ray meets alone",
          "[spatial][tree][lanes]") {
  std::mt19937 g(77);
  GAabbTree<float> tree;
  for (int i = 0; i < 600; ++i)
    tree.insert(random_box<float>(g, 20, 3));
  float const inf = std::numeric_limits<float>::infinity();
  float const nan = std::numeric_limits<float>::quiet_NaN();
  auto const check = [&]<class T>() {
    constexpr std::size_t W = lanes_v<T>;
    for (int packet = 0; packet < 60; ++packet) {
      std::array<Vec3, W> o, d;
      alignas(64) std::array<float, W> limit;
      Vec3 const near = random_point<float>(g, -20, 20);
      for (std::size_t k = 0; k < W; ++k) {
        GRay3<float> const r = random_ray<float>(g, 20);
        o[k] = packet % 2 ? near : r.origin; // coherent packets share an origin
        d[k] = r.dir;
        if (g() % 6 == 0) d[k].x = -0.0f; // signed zeros on every axis
        if (g() % 6 == 0) d[k].y = g() % 2 ? -0.0f : 0.0f;
        if (d[k].x == 0.0f && d[k].y == 0.0f && d[k].z == 0.0f) d[k].z = 1.0f;
        limit[k] = k % 5 == 4 ? inf : float(g() % 40);
      }
      if (packet % 7 == 3) { // unusable lanes: zero direction, NaN origin, NaN or negative limit
        d[0] = Vec3{};
        if (W > 1) o[1].y = nan;
        if (W > 2) limit[2] = nan;
        if (W > 3) limit[3] = -1.0f;
      }
      std::array<std::vector<ProxyId>, W> got;
      T lim = load_aligned<T>(limit.data());
      tree.ray_query_lanes(GRay3<T>{pack<T>(o.data()), pack<T>(d.data())}, lim,
                           [&](ProxyId id, std::uint64_t lanes) {
                             for (std::size_t k = 0; k < W; ++k)
                               if (lanes >> k & 1) got[k].push_back(id);
                           });
      for (std::size_t k = 0; k < W; ++k) {
        std::vector<ProxyId> want;
        tree.ray_query(GRay3<float>{o[k], d[k]}, limit[k], [&](ProxyId id, float) {
          want.push_back(id);
          return limit[k];
        });
        INFO("width " << W << ", packet " << packet << ", lane " << k);
        CHECK(sorted(got[k]) == sorted(want));
      }
    }
  };
  check.template operator()<float>();
  for_each_type<f32_widths>(check);
  // An empty tree meets nothing, and bad lanes are marked out of the walk (max_toi -1).
  GAabbTree<float> const empty;
  float lim = 5.0f;
  empty.ray_query_lanes(GRay3<float>{{0, 0, 0}, {1, 0, 0}}, lim,
                        [](ProxyId, std::uint64_t) { FAIL("an empty tree met a leaf"); });
  float bad = 5.0f;
  tree.ray_query_lanes(GRay3<float>{{0, 0, 0}, {0, 0, 0}}, bad,
                       [](ProxyId, std::uint64_t) { FAIL("a zero direction met a leaf"); });
  CHECK(bad == -1.0f);
}

TEST_CASE("aabb tree: a slab exit is never before the exact exit", "[spatial][tree]") {
  // The claim behind inv_far: (plane - origin) * inv_far rounds four times (the difference, the
  // reciprocal, its enlargement and the product, each within 2^-24), less than the 2^-20 it is
  // enlarged by, so every exit at or after the origin is at or after the exact one (computed
  // in double from the same floats: a difference of floats is exact there, and the quotient
  // within 2^-53).
  std::mt19937 rng(2026);
  std::uniform_real_distribution<float> mant(1.0f, 2.0f), unit(-1.0f, 1.0f);
  std::uniform_int_distribution<int> expo(-20, 20);
  auto value = [&] { return std::ldexp(mant(rng), expo(rng)) * (unit(rng) < 0 ? -1.0f : 1.0f); };
  auto comp = [](Vec3 const& v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; };
  long checked = 0, early = 0;
  for (int i = 0; i < 200000; ++i) {
    Vec3 const origin{value(), value(), value()}, dir{value(), value(), value()};
    bool const neg[3] = {dir.x < 0, dir.y < 0, dir.z < 0};
    auto const slab = detail::make_ray_slab(origin, dir, neg);
    for (int a = 0; a < 3; ++a) {
      float const plane = value();
      float const exit = (plane - comp(slab.origin, a)) * comp(slab.inv_far, a);
      double const exact = (double(plane) - double(comp(origin, a))) / double(comp(dir, a));
      if (!(exact >= 0.0) || exact < 1e-30) continue;
      ++checked;
      if (double(exit) < exact) ++early;
    }
  }
  CHECK(checked > 250000);
  CHECK(early == 0);
}
