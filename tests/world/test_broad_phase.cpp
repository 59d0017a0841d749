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

TEST_CASE("bvh broad phase: the pairs brute force finds, through moves and category changes",
          "[world][broad-phase]") {
  // Bodies 0..n: a category each step (static, moving, unbounded), boxes that drift, jump and
  // sometimes become infinite. Queriers are moving bodies, "dynamic" ones (even index) also
  // asking the static tree; keep() is the world's rule: at least one body dynamic.
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> at(-8.0f, 8.0f), size(0.0f, 1.5f), drift(-0.1f, 0.1f);
  std::size_t const n = 300;
  std::vector<Aabb3> boxes(n);
  std::vector<int> kind(n); // 0 static, 1 moving, 2 unbounded
  BvhBroadPhase bvh;
  std::vector<std::uint64_t> pairs;
  auto const random_box = [&] {
    Vec3 const lo{at(rng), at(rng), at(rng)};
    return Aabb3{lo, lo + Vec3{size(rng), size(rng), size(rng)}};
  };
  for (std::uint32_t i = 0; i < n; ++i) {
    kind[i] = int(rng() % 10 < 6 ? 1 : rng() % 10 < 9 ? 0 : 2);
    boxes[i] = random_box();
  }
  for (int step = 0; step < 200; ++step) {
    for (std::uint32_t i = 0; i < n; ++i) {
      auto const r = std::uint32_t(rng() % 100);
      if (r < 2) kind[i] = int(rng() % 3); // change category
      if (kind[i] == 1 || r < 3) {
        if (r < 10)
          boxes[i] = random_box(); // a jump
        else {
          Vec3 const d{drift(rng), drift(rng), drift(rng)};
          boxes[i] = {boxes[i].min + d, boxes[i].max + d};
        }
      }
      Aabb3 box = boxes[i];
      if (kind[i] == 2) box.min.y = -std::numeric_limits<float>::infinity(); // a half-space
      bvh.set_box(i, box, kind[i] == 1);
    }
    std::vector<std::uint32_t> dyn, kin;
    for (std::uint32_t i = 0; i < n; ++i)
      if (kind[i] == 1) (i % 2 == 0 ? dyn : kin).push_back(i);
    auto const is_dynamic = [&](std::uint32_t i) { return kind[i] == 1 && i % 2 == 0; };
    auto const keep = [&](std::uint32_t a, std::uint32_t b) {
      return is_dynamic(a) || is_dynamic(b);
    };
    bvh.find_pairs(dyn, kin, keep, pairs);
    std::vector<std::uint64_t> brute;
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t j = i + 1; j < n; ++j) {
        Aabb3 a = boxes[i], b = boxes[j];
        if (kind[i] == 2) a.min.y = -std::numeric_limits<float>::infinity();
        if (kind[j] == 2) b.min.y = -std::numeric_limits<float>::infinity();
        // Only a querier finds pairs: a pair of non-moving bodies is never reported.
        if ((kind[i] == 1 || kind[j] == 1) && overlap(a, b) && keep(i, j))
          brute.push_back(body_pair_key(i, j));
      }
    INFO("step " << step);
    REQUIRE(pairs == brute);
    REQUIRE(bvh.static_tree().validate() == "");
    REQUIRE(bvh.moving_tree().validate() == "");
  }
  CHECK(bvh.moving_tree().size() + bvh.static_tree().size() <= n);
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
