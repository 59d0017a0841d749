// The contact cache: warm-start impulses by feature id, then by the nearest point, and
// contacts and colours carried across steps.
#include <plume/solver/world/contact_cache.hpp>

#include <catch2/catch.hpp>

using namespace plume;

namespace {

Manifold manifold_of(std::initializer_list<std::pair<std::uint32_t, Vec3>> points) {
  Manifold m;
  m.normal = Vec3::Y;
  for (auto const& [id, at] : points) {
    ContactPoint& p = m.points[std::size_t(m.count++)];
    p.id = id;
    p.point_a = at;
    p.point_b = at;
  }
  return m;
}

} // namespace

TEST_CASE("carry_impulses: feature ids first, then the nearest point within reach",
          "[world][contact-cache]") {
  ContactImpulses before;
  before.normal = {1.0f, 2.0f, 3.0f, 4.0f};
  before.tangent1 = 0.5f;
  before.tangent2 = -0.25f;
  before.twist = 0.125f;
  Manifold const old =
      manifold_of({{10, {0, 0, 0}}, {11, {1, 0, 0}}, {12, {0, 0, 1}}, {13, {5, 0, 5}}});
  // id 11 kept (moved far: still matched by id); id 99 new, 0.004 m from id 10's point
  // (matched by distance); id 13 kept; id 97 new, far from everything: starts at zero.
  Manifold const now =
      manifold_of({{11, {3, 0, 3}}, {99, {0.004f, 0, 0}}, {13, {5, 0, 5}}, {97, {-3, 0, -3}}});
  ContactImpulses const got = carry_impulses(now, old, before, 0.01f);
  CHECK(got.normal[0] == 2.0f);
  CHECK(got.normal[1] == 1.0f);
  CHECK(got.normal[2] == 4.0f);
  CHECK(got.normal[3] == 0.0f);
  CHECK(got.tangent1 == 0.5f);
  CHECK(got.tangent2 == -0.25f);
  CHECK(got.twist == 0.125f);
  // Out of reach: 0.011 m from the nearest old point with a 0.01 m reach.
  Manifold const far = manifold_of({{50, {0.011f, 0, 0}}});
  CHECK(carry_impulses(far, old, before, 0.01f).normal[0] == 0.0f);
  // Each old point is claimed once: two new points near id 10's point, the nearer wins.
  Manifold const two = manifold_of({{60, {0.006f, 0, 0}}, {61, {0.002f, 0, 0}}});
  ContactImpulses const pair = carry_impulses(two, old, before, 0.01f);
  CHECK(pair.normal[0] == 1.0f); // the first new point claims it: matching is in point order
  CHECK(pair.normal[1] == 0.0f);
}

TEST_CASE("contact cache: contacts persist by pair, keep colours, end when apart",
          "[world][contact-cache]") {
  ContactCache cache;
  cache.reserve_bodies(4);
  auto found = [](std::uint32_t a, std::uint32_t b, int points) {
    PairManifold f;
    f.pair = body_pair_key(a, b);
    f.manifold = manifold_of({});
    for (int i = 0; i < points; ++i) {
      ContactPoint& p = f.manifold.points[std::size_t(f.manifold.count++)];
      p.id = std::uint32_t(i);
    }
    f.friction = 0.5f;
    f.dynamic_a = f.dynamic_b = true;
    return f;
  };
  std::vector<PairManifold> step1{found(0, 1, 1), found(1, 2, 2), found(2, 3, 0)};
  cache.update(step1, 0.01f);
  REQUIRE(cache.contacts().size() == 2); // the empty manifold is no contact
  CHECK(cache.contacts()[0].body_a == 0);
  CHECK(cache.contacts()[1].body_b == 2);
  int const c01 = cache.contacts()[0].color, c12 = cache.contacts()[1].color;
  CHECK(c01 != c12); // both touch body 1
  cache.contacts()[1].impulses.normal[1] = 7.0f;
  std::vector<PairManifold> step2{found(1, 2, 2), found(2, 3, 1)};
  cache.update(step2, 0.01f);
  REQUIRE(cache.contacts().size() == 2);
  CHECK(cache.contacts()[0].color == c12);               // kept
  CHECK(cache.contacts()[0].impulses.normal[1] == 7.0f); // warm start by feature id
  CHECK(cache.contacts()[1].impulses.normal[0] == 0.0f); // new
  std::vector<std::uint32_t> const frozen{2};
  cache.remove_bodies(frozen);
  CHECK(cache.contacts().empty());
  // Every colour was freed: a new contact of body 1 takes colour 0 again.
  std::vector<PairManifold> step3{found(0, 1, 1)};
  cache.update(step3, 0.01f);
  CHECK(cache.contacts()[0].color == 0);
}

TEST_CASE("contact cache: a pair with several manifolds matches each by its normal",
          "[world][contact-cache][mesh]") {
  ContactCache cache;
  cache.reserve_bodies(3);
  // Two manifolds of pair (0, 1) (a body in a mesh valley) and one of pair (1, 2); every
  // point has id 0, so only the normals can tell the pair's two contacts apart.
  auto const found = [](std::uint32_t a, std::uint32_t b, Vec3 const& normal) {
    PairManifold f;
    f.pair = body_pair_key(a, b);
    f.manifold = manifold_of({{0, {0, 0, 0}}});
    f.manifold.normal = normal;
    f.dynamic_b = true;
    return f;
  };
  Vec3 const left = Vec3{-0.5f, 0.866f, 0.0f}, right = Vec3{0.5f, 0.866f, 0.0f};
  std::vector<PairManifold> step1{found(0, 1, left), found(0, 1, right), found(1, 2, Vec3::Y)};
  cache.update(step1, 0.01f);
  REQUIRE(cache.contacts().size() == 3);
  cache.contacts()[0].impulses.normal[0] = 1.0f; // left
  cache.contacts()[1].impulses.normal[0] = 2.0f; // right
  int const color_left = cache.contacts()[0].color, color_right = cache.contacts()[1].color;
  CHECK(color_left != color_right); // both touch body 1
  // The narrow phase now lists them the other way round, turned a little: each keeps its
  // own impulses and colour.
  Vec3 const left2 = Vec3{-0.45f, 0.89f, 0.0f}.normalize(),
             right2 = Vec3{0.55f, 0.83f, 0.0f}.normalize();
  std::vector<PairManifold> step2{found(0, 1, right2), found(0, 1, left2), found(1, 2, Vec3::Y)};
  cache.update(step2, 0.01f);
  REQUIRE(cache.contacts().size() == 3);
  CHECK(cache.contacts()[0].impulses.normal[0] == 2.0f);
  CHECK(cache.contacts()[0].color == color_right);
  CHECK(cache.contacts()[1].impulses.normal[0] == 1.0f);
  CHECK(cache.contacts()[1].color == color_left);
  // One of them ends, and a new one far from the other's normal starts from zero.
  std::vector<PairManifold> step3{found(0, 1, left2), found(0, 1, Vec3{0.0f, 0.0f, 1.0f}),
                                  found(1, 2, Vec3::Y)};
  cache.update(step3, 0.01f);
  REQUIRE(cache.contacts().size() == 3);
  CHECK(cache.contacts()[0].impulses.normal[0] == 1.0f);
  CHECK(cache.contacts()[1].impulses.normal[0] == 0.0f);
  // One contact before (up), two manifolds now, the steeper one first: the up manifold, not
  // the first in line, takes the contact's impulses (found in review: matching in arrival
  // order gave them to the slope).
  std::vector<PairManifold> up1{found(0, 1, Vec3::Y), found(1, 2, Vec3::Y)};
  ContactCache fresh;
  fresh.reserve_bodies(3);
  fresh.update(up1, 0.01f);
  fresh.contacts()[0].impulses.normal[0] = 9.0f;
  Vec3 const slope = Vec3{0.6f, 0.8f, 0.0f}; // 37 degrees from up: within the 60 degrees
  std::vector<PairManifold> two{found(0, 1, slope), found(0, 1, Vec3::Y), found(1, 2, Vec3::Y)};
  fresh.update(two, 0.01f);
  REQUIRE(fresh.contacts().size() == 3);
  CHECK(fresh.contacts()[0].impulses.normal[0] == 0.0f);
  CHECK(fresh.contacts()[1].impulses.normal[0] == 9.0f);
  // A pair with one manifold before and now matches it whatever the normal (as before meshes).
  std::vector<PairManifold> step4{found(1, 2, Vec3::X)};
  cache.contacts()[2].impulses.normal[0] = 5.0f;
  cache.update(step4, 0.01f);
  REQUIRE(cache.contacts().size() == 1);
  CHECK(cache.contacts()[0].impulses.normal[0] == 5.0f);
}
