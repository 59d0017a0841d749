// The broad phases: sort and sweep against a brute-force loop over every pair, the BVH broad
// phase against brute force through random moves, category changes and unbounded boxes, and
// the world stepped with each (the same world, bit for bit).
#include "../common/types.hpp"

#include <fixtures/scenes.hpp>
#include <plume/solver/world/broad_phase.hpp>
#include <plume/solver/world/world.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

using namespace plume;

namespace {

bool overlap(Aabb3 const& a, Aabb3 const& b) {
  return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
         a.min.z <= b.max.z && b.min.z <= a.max.z;
}

} // namespace

TEST_CASE("sort and sweep: the pairs a brute-force loop finds, sorted", "[world][broad-phase]") {
  std::mt19937 rng(11);
  SortAndSweep sweep;
  std::vector<std::uint64_t> pairs;
  for (int trial = 0; trial < 40; ++trial) {
    std::size_t const n = std::size_t(rng() % 300);
    std::uniform_real_distribution<float> at(-10.0f, 10.0f), size(0.0f, 2.0f);
    std::vector<Aabb3> boxes(n);
    for (Aabb3& b : boxes) {
      // Snapped to a 0.5 grid so that boxes share faces and minimum x (ties) often.
      Vec3 const lo{std::round(at(rng)) * 0.5f, std::round(at(rng)) * 0.5f,
                    std::round(at(rng)) * 0.5f};
      b = {lo, lo + Vec3{std::round(size(rng)) * 0.5f, std::round(size(rng)) * 0.5f,
                         std::round(size(rng)) * 0.5f}};
    }
    auto const keep = [](std::uint32_t a, std::uint32_t b) { return (a + b) % 3 != 0; };
    sweep.find_pairs(boxes, keep, pairs);
    std::vector<std::uint64_t> brute;
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t j = i + 1; j < n; ++j)
        if (overlap(boxes[i], boxes[j]) && keep(i, j)) brute.push_back(body_pair_key(i, j));
    CHECK(std::is_sorted(pairs.begin(), pairs.end()));
    CHECK(pairs == brute);
  }
}

TEST_CASE("body pair keys order by the smaller index, either argument order",
          "[world][broad-phase]") {
  CHECK(body_pair_key(3, 7) == body_pair_key(7, 3));
  CHECK(body_pair_first(body_pair_key(7, 3)) == 3);
  CHECK(body_pair_second(body_pair_key(7, 3)) == 7);
  CHECK(body_pair_key(1, 0xffffffffu) > body_pair_key(0, 0xffffffffu));
  CHECK(body_pair_key(1, 2) < body_pair_key(2, 1) + 1);
}

TEST_CASE("bvh broad phase: the pairs brute force finds, through moves and kind changes",
          "[world][broad-phase]") {
  // Bodies 0..n of each kind (static, kinematic, dynamic), some unbounded (a half-space's
  // infinite box), whose boxes creep inside their fat boxes, drift out of them and jump; some
  // change kind, leave and come back. The candidate pairs persist between calls, so a pair
  // missed when a body moved stays missed: brute force every step finds that.
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> at(-8.0f, 8.0f), size(0.0f, 1.5f), drift(-0.1f, 0.1f),
      creep(-0.004f, 0.004f);
  std::size_t const n = 300;
  std::vector<Aabb3> boxes(n);
  std::vector<ProxyKind> kind(n);
  std::vector<char> unbounded(n), live(n, 1);
  BvhBroadPhase bvh;
  std::vector<std::uint64_t> pairs;
  auto const random_box = [&] {
    Vec3 const lo{at(rng), at(rng), at(rng)};
    return Aabb3{lo, lo + Vec3{size(rng), size(rng), size(rng)}};
  };
  auto const random_kind = [&] { return ProxyKind(rng() % proxy_kind_count); };
  for (std::uint32_t i = 0; i < n; ++i) {
    kind[i] = random_kind();
    unbounded[i] = rng() % 10 == 0;
    boxes[i] = random_box();
  }
  std::size_t queries = 0, calls = 0;
  for (int step = 0; step < 200; ++step) {
    for (std::uint32_t i = 0; i < n; ++i) {
      auto const r = std::uint32_t(rng() % 1000);
      if (r < 5) { // leaves the broad phase, or comes back
        live[i] = !live[i];
        if (!live[i]) bvh.remove(i);
      }
      if (!live[i]) continue;
      if (r >= 5 && r < 20) kind[i] = random_kind();
      if (r >= 20 && r < 25) unbounded[i] = !unbounded[i];
      bool const moves = (kind[i] != ProxyKind::static_body || r < 40) && !(r >= 5 && r < 25);
      if (moves) {
        if (r < 60)
          boxes[i] = random_box(); // a jump
        else {
          bool const small = r % 2 == 0; // stays inside the fat box, mostly
          Vec3 const d = small ? Vec3{creep(rng), creep(rng), creep(rng)}
                               : Vec3{drift(rng), drift(rng), drift(rng)};
          boxes[i] = {boxes[i].min + d, boxes[i].max + d};
        }
      }
      Aabb3 box = boxes[i];
      if (unbounded[i]) box.min.y = -std::numeric_limits<float>::infinity(); // a half-space
      bvh.set_box(i, box, kind[i]);
    }
    auto const keep = [&](std::uint32_t a, std::uint32_t b) { return (a + 2 * b) % 7 != 0; };
    bvh.find_pairs(keep, pairs);
    queries += bvh.last_query_count();
    ++calls;
    std::vector<std::uint64_t> brute;
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t j = i + 1; j < n; ++j) {
        if (!live[i] || !live[j]) continue;
        Aabb3 a = boxes[i], b = boxes[j];
        if (unbounded[i]) a.min.y = -std::numeric_limits<float>::infinity();
        if (unbounded[j]) b.min.y = -std::numeric_limits<float>::infinity();
        // A dynamic body, or a sleeping one and a kinematic one.
        bool const kinds = kind[i] == ProxyKind::dynamic || kind[j] == ProxyKind::dynamic ||
                           (kind[i] == ProxyKind::sleeping && kind[j] == ProxyKind::kinematic) ||
                           (kind[i] == ProxyKind::kinematic && kind[j] == ProxyKind::sleeping);
        if (kinds && overlap(a, b) && keep(i, j)) brute.push_back(body_pair_key(i, j));
      }
    INFO("step " << step);
    REQUIRE(pairs == brute);
    for (AabbTree const* t : bvh.trees())
      REQUIRE(t->validate() == "");
    REQUIRE(bvh.candidate_count() >= pairs.size());
  }
  std::size_t in_trees = 0;
  for (AabbTree const* t : bvh.trees())
    in_trees += t->size();
  CHECK(in_trees + bvh.unbounded().size() <= n);
  // Statics and creeping bodies query nothing: fewer queries than bodies per call.
  CHECK(queries < calls * n * 2 / 5); // about a third of the bodies move out per call
}

TEST_CASE("bvh broad phase: a body that stays inside its fat box queries nothing",
          "[world][broad-phase]") {
  BvhBroadPhase bvh;
  std::vector<std::uint64_t> pairs;
  auto const keep = [](std::uint32_t, std::uint32_t) { return true; };
  auto const unit = [](Vec3 lo) { return Aabb3{lo, lo + Vec3::splat(1.0f)}; };
  bvh.set_box(0, unit({0, 0, 0}), ProxyKind::static_body);
  bvh.set_box(1, unit({0.5f, 0, 0}), ProxyKind::dynamic);
  bvh.set_box(2, unit({5, 0, 0}), ProxyKind::kinematic);
  bvh.set_box(3, unit({5.5f, 0, 0}), ProxyKind::static_body); // kinematic-static: no pair
  bvh.find_pairs(keep, pairs);
  CHECK(bvh.last_query_count() == 4);
  CHECK(pairs == std::vector<std::uint64_t>{body_pair_key(0, 1)});
  // Inside the fat boxes (margin 0.05): no query, the same pair.
  bvh.set_box(1, unit({0.52f, 0.01f, 0}), ProxyKind::dynamic);
  bvh.set_box(2, unit({5.03f, 0, 0}), ProxyKind::kinematic);
  bvh.find_pairs(keep, pairs);
  CHECK(bvh.last_query_count() == 0);
  CHECK(pairs == std::vector<std::uint64_t>{body_pair_key(0, 1)});
  // Out of it: one query, and the pair ends when the boxes part.
  bvh.set_box(1, unit({1.2f, 0, 0}), ProxyKind::dynamic);
  bvh.find_pairs(keep, pairs);
  CHECK(bvh.last_query_count() == 1);
  CHECK(pairs.empty());
  CHECK(bvh.candidate_count() == 0);
  // A kind change counts as a move: the kinematic body turned dynamic meets the static one.
  bvh.set_box(2, unit({5.03f, 0, 0}), ProxyKind::dynamic);
  bvh.find_pairs(keep, pairs);
  CHECK(bvh.last_query_count() == 1);
  CHECK(pairs == std::vector<std::uint64_t>{body_pair_key(2, 3)});
  // And back: a kinematic body and a static one make no pair, though their boxes overlap.
  bvh.set_box(2, unit({5.03f, 0, 0}), ProxyKind::kinematic);
  bvh.find_pairs(keep, pairs);
  CHECK(pairs.empty());
  CHECK(bvh.candidate_count() == 0);
  // Removing a body ends its pairs.
  bvh.set_box(2, unit({5.03f, 0, 0}), ProxyKind::dynamic);
  bvh.find_pairs(keep, pairs);
  CHECK(pairs == std::vector<std::uint64_t>{body_pair_key(2, 3)});
  bvh.remove(3);
  bvh.find_pairs(keep, pairs);
  CHECK(pairs.empty());
  CHECK(bvh.candidate_count() == 0);
  // The static tree's wide copy: fresh after find_pairs, stale (null, queries fall back to the
  // tree) from a static edit until the next refresh, and fresh again after it.
  auto const statics_at = [&](Aabb3 const& q) {
    std::vector<std::uint64_t> found;
    bvh.query_static(q, [&](ProxyId p) {
      found.push_back(bvh.tree(ProxyKind::static_body).user(p));
      return true;
    });
    std::sort(found.begin(), found.end());
    return found;
  };
  bvh.set_box(6, unit({-10, 0, 0}), ProxyKind::static_body);
  bvh.find_pairs(keep, pairs);
  REQUIRE(bvh.static_wide() != nullptr);
  CHECK(statics_at(unit({-10, 0, 0})) == std::vector<std::uint64_t>{6});
  bvh.set_box(6, unit({-20, 0, 0}), ProxyKind::static_body); // moved out of its fat box
  CHECK(bvh.static_wide() == nullptr);
  CHECK(statics_at(unit({-20, 0, 0})) == std::vector<std::uint64_t>{6});
  CHECK(statics_at(unit({-10, 0, 0})).empty());
  bvh.refresh_static();
  REQUIRE(bvh.static_wide() != nullptr);
  CHECK(statics_at(unit({-20, 0, 0})) == std::vector<std::uint64_t>{6});
  bvh.remove(6);
  CHECK(bvh.static_wide() == nullptr);
  CHECK(statics_at(unit({-20, 0, 0})).empty());
  bvh.find_pairs(keep, pairs);
  // An unbounded dynamic body that stays put is found by a kinematic body moving into it.
  Aabb3 slab = unit({20, 0, 0});
  slab.min.y = -std::numeric_limits<float>::infinity();
  bvh.set_box(4, slab, ProxyKind::dynamic);
  bvh.set_box(5, unit({30, 0, 0}), ProxyKind::kinematic);
  bvh.find_pairs(keep, pairs);
  CHECK(pairs.empty());
  bvh.set_box(4, slab, ProxyKind::dynamic); // unchanged: no query
  bvh.set_box(5, unit({20.5f, -3, 0}), ProxyKind::kinematic);
  bvh.find_pairs(keep, pairs);
  CHECK(bvh.last_query_count() == 1);
  CHECK(pairs == std::vector<std::uint64_t>{body_pair_key(4, 5)});
}

TEST_CASE("world: the BVH and sort-and-sweep broad phases give the same world, bit for bit",
          "[world][broad-phase][determinism]") {
  // Ground, a pyramid, a kinematic pusher, a static box teleported mid-run and a body that
  // turns non-finite (frozen): every path of the world's BVH bookkeeping.
  auto const run = [](BroadPhaseKind kind) {
    WorldConfig cfg;
    cfg.broad_phase = kind;
    World w(cfg);
    scenes::add_ground(w);
    scenes::add_box_pyramid(w, 5);
    BodyId const wall = w.create_body({.type = BodyType::static_body,
                                       .pose = Iso3::from_translation({8, 1, 0}),
                                       .shape = Cuboid{Vec3{0.5f, 1, 3}}})
                            .id;
    BodyId const pusher = w.create_body({.type = BodyType::kinematic,
                                         .pose = Iso3::from_translation({-6, 0.5f, 0}),
                                         .linear_velocity = {1.5f, 0, 0},
                                         .shape = Cuboid{Vec3::splat(0.5f)}})
                              .id;
    BodyId const wild =
        w.create_body({.pose = Iso3::from_translation({0, 12, 4}), .shape = Sphere{0.4f}}).id;
    std::vector<std::uint64_t> hashes;
    // 150 steps in the -O0 sanitizer build (still past every edit below), else 240.
    for (int s = 0; s < (PLUME_TEST_UNOPTIMISED ? 150 : 240); ++s) {
      if (s == 60)
        REQUIRE(w.set_pose(wall, Iso3::from_translation({2.5f, 1, 0})) == BodyError::none);
      if (s == 90) REQUIRE(w.set_velocity(wild, {3e38f, 3e38f, 0}, {}) == BodyError::none);
      if (s == 120) {
        w.create_body({.pose = Iso3::from_translation({0, 8, 0}), .shape = Sphere{0.5f}});
        w.create_body({.type = BodyType::static_body,
                       .pose = Iso3::from_translation({-3, 0.25f, 3}),
                       .shape = Cuboid{Vec3::splat(0.25f)}});
      }
      // The persistent pairs' risky paths: a body destroyed and its slot reused in the same
      // step, type changes (of a frozen body too), layers that forbid and allow again.
      if (s == 125) {
        REQUIRE(w.destroy_body(w.body_id(3)) == BodyError::none);
        w.create_body(
            {.pose = Iso3::from_translation({0.3f, 5, 0.2f}), .shape = Cuboid{Vec3::splat(0.4f)}});
      }
      if (s == 130) REQUIRE(w.set_type(w.body_id(5), BodyType::kinematic) == BodyError::none);
      if (s == 135) REQUIRE(w.set_type(w.body_id(5), BodyType::dynamic) == BodyError::none);
      if (s == 137) REQUIRE(w.set_type(wild, BodyType::dynamic) == BodyError::none); // frozen
      if (s == 140)
        REQUIRE(w.set_layers(w.body_id(7), {.memberships = 2, .filters = 2}) == BodyError::none);
      if (s == 145) REQUIRE(w.set_layers(w.body_id(7), {}) == BodyError::none);
      if (s == 148) REQUIRE(w.set_type(w.body_id(6), BodyType::static_body) == BodyError::none);
      w.step(1.0f / 60.0f);
      hashes.push_back(w.state_hash());
    }
    (void)pusher;
    return std::make_pair(hashes, w.contacts().size());
  };
  auto const bvh = run(BroadPhaseKind::bvh);
  auto const sweep = run(BroadPhaseKind::sort_and_sweep);
  CHECK(bvh.second == sweep.second);
  CHECK(bvh.second > 0);
  for (std::size_t s = 0; s < bvh.first.size(); ++s) {
    INFO("step " << s);
    REQUIRE(bvh.first[s] == sweep.first[s]);
  }
}

TEST_CASE("bvh broad phase: standalone colliders pair as statics, in a tree of their own",
          "[world][broad-phase]") {
  BvhBroadPhase bvh;
  std::vector<std::uint64_t> pairs;
  auto const keep = [](std::uint32_t, std::uint32_t) { return true; };
  auto const unit = [](Vec3 lo) { return Aabb3{lo, lo + Vec3::splat(1.0f)}; };
  bvh.set_box(0, unit({0, 0, 0}), ProxyKind::standalone);
  bvh.set_box(1, unit({0.5f, 0, 0}), ProxyKind::dynamic);
  bvh.set_box(2, unit({0.2f, 0, 0}), ProxyKind::kinematic);    // meets the collider: no pair
  bvh.set_box(3, unit({-0.2f, 0, 0}), ProxyKind::static_body); // likewise
  bvh.set_box(4, unit({-0.4f, 0, 0}), ProxyKind::standalone);  // two colliders: no pair
  bvh.find_pairs(keep, pairs);
  CHECK(pairs == std::vector<std::uint64_t>{body_pair_key(0, 1), body_pair_key(1, 2),
                                            body_pair_key(1, 3), body_pair_key(1, 4)});
  CHECK(bvh.tree(ProxyKind::standalone).size() == 2);
  CHECK(bvh.tree(ProxyKind::static_body).size() == 1);
  REQUIRE(bvh.static_wide() != nullptr);
  // A collider that moves (here every call, as a trigger carried by a game object) is an edit
  // of its own tree: the static tree's wide copy stays fresh, and the pairs follow it.
  for (int k = 1; k <= 20; ++k) {
    bvh.set_box(0, unit({0.5f * float(k), 0, 0}), ProxyKind::standalone);
    bvh.find_pairs(keep, pairs);
    CHECK(bvh.static_wide() != nullptr);
    bool const meets = 0.5f * float(k) <= 1.5f; // the dynamic box spans x in [0.5, 1.5]
    CHECK(std::count(pairs.begin(), pairs.end(), body_pair_key(0, 1)) == int(meets));
    CHECK(bvh.tree(ProxyKind::standalone).validate() == "");
  }
  // A collider that becomes a static body leaves its tree for the static one.
  bvh.set_box(4, unit({-0.4f, 0, 0}), ProxyKind::static_body);
  bvh.find_pairs(keep, pairs);
  CHECK(bvh.tree(ProxyKind::standalone).size() == 1);
  CHECK(bvh.tree(ProxyKind::static_body).size() == 2);
  CHECK(std::count(pairs.begin(), pairs.end(), body_pair_key(1, 4)) == 1);
  bvh.remove(0);
  CHECK(bvh.tree(ProxyKind::standalone).size() == 0);
}
