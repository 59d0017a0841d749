// The sort-and-sweep broad phase against a brute-force loop over every pair.
#include <plume/solver/world/broad_phase.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
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
