// The world's spatial queries against brute force over every body (the shapes' own pair
// queries at the bodies' poses, no tree), on random scenes of every shape, after steps;
// filters and collision layers; bad input.
#include "../common/types.hpp"
#include "../spatial/mesh_support.hpp"

#include <fixtures/scenes.hpp>
#include <plume/solver/world/world.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

using namespace plume;

namespace {

RayHit brute_ray(BodyShape const& shape, Iso3 const& pose, Ray3 const& ray, float max_toi) {
  return std::visit(
      [&](auto const& s) -> RayHit {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, ConvexHull>) {
          return ray_cast_gjk(s, pose, ray, max_toi);
        } else if constexpr (is_triangle_shape_v<S>) {
          MeshRayHit const h = s.source()->ray_cast(pose, ray, max_toi);
          return {h.hit(), h.toi, h.normal, float(h.triangle)};
        } else {
          return ray_cast(s, pose, ray, max_toi);
        }
      },
      shape);
}

/// The signed distance from a point to a body (negative or zero inside), brute force.
float brute_distance(BodyShape const& shape, Iso3 const& pose, Vec3 const& p) {
  return std::visit(
      [&](auto const& s) -> float {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, HalfSpace>) {
          return pose.transform_vector(s.normal).dot(p - pose.translation);
        } else if constexpr (is_triangle_shape_v<S>) {
          return s.source()->closest_point(pose, p, std::numeric_limits<float>::max()).distance;
        } else {
          ClosestPoints const c = closest_points(Sphere{0.0f}, Iso3::from_translation(p), s, pose);
          return c.overlap ? 0.0f : c.distance;
        }
      },
      shape);
}

ConvexHull tetra_hull() {
  std::vector<Vec3> const pts = {{0, 0, 0}, {0.8f, 0, 0}, {0, 0.8f, 0}, {0, 0, 0.8f}};
  return ConvexHull::build(pts).hull;
}

/// A ground half-space and n bodies of every shape, static and dynamic, in [-6, 6]^2 x [0, 5],
/// half the static ones standalone colliders (every ninth slot destroyed and refilled by the
/// other kind), stepped 20 times.
World random_scene(std::uint32_t seed, int n, BroadPhaseKind kind = BroadPhaseKind::bvh) {
  WorldConfig cfg;
  cfg.broad_phase = kind;
  World w(cfg);
  scenes::add_ground(w);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> at(-6.0f, 6.0f), up(0.3f, 5.0f), r(0.2f, 0.7f);
  ConvexHull const hull = tetra_hull();
  for (int i = 0; i < n; ++i) {
    BodyShape shape;
    switch (rng() % 5) {
    case 0:
      shape = Sphere{r(rng)};
      break;
    case 1:
      shape = Capsule{r(rng), 0.5f * r(rng)};
      break;
    case 2:
      shape = Cuboid{Vec3{r(rng), r(rng), r(rng)}};
      break;
    case 3:
      shape = Cylinder{r(rng), r(rng)};
      break;
    default:
      shape = hull;
      break;
    }
    Vec3 axis{at(rng), at(rng), at(rng)};
    axis = axis.length() > 0.1f ? axis.normalize() : Vec3::Y;
    Quat const q = Quat::from_axis_angle(axis, at(rng));
    Iso3 const pose{q, {at(rng), up(rng), at(rng)}};
    auto const role = rng() % 6;
    if (role == 0)
      REQUIRE(w.create_collider({.pose = pose, .shape = shape}));
    else
      w.create_body({.type = role == 1 ? BodyType::static_body : BodyType::dynamic,
                     .pose = pose,
                     .shape = shape});
  }
  // Every ninth slot emptied and refilled by the other kind (a later generation).
  for (std::uint32_t i = 1; i < w.body_count(); i += 9) {
    ColliderId const c = w.collider_id(i);
    BodyShape const shape = w.shape(c);
    Iso3 const pose = w.pose(c);
    if (c.standalone) {
      REQUIRE(w.destroy_collider(c) == BodyError::none);
      REQUIRE(
          w.create_body({.type = BodyType::static_body, .pose = pose, .shape = shape}).id.index ==
          i);
    } else {
      REQUIRE(w.destroy_body(c.body()) == BodyError::none);
      REQUIRE(w.create_collider({.pose = pose, .shape = shape}).id.index == i);
    }
  }
  for (int s = 0; s < 20; ++s)
    w.step(1.0f / 60.0f);
  return w;
}

/// The batch answers are the single ones, bit for bit (body, toi, point, normal, and
/// penetrating for shape hits); returns how many hit.
template <class Hit>
int same_hits(std::vector<std::optional<Hit>> const& got,
              std::vector<std::optional<Hit>> const& want) {
  int hits = 0;
  for (std::size_t k = 0; k < want.size(); ++k) {
    INFO("query " << k);
    REQUIRE(got[k].has_value() == want[k].has_value());
    if (!want[k]) continue;
    ++hits;
    CHECK(got[k]->body == want[k]->body);
    CHECK(got[k]->collider == want[k]->collider);
    CHECK(test::same_bits(got[k]->toi, want[k]->toi));
    CHECK(test::same_bits(got[k]->point, want[k]->point));
    CHECK(test::same_bits(got[k]->normal, want[k]->normal));
    if constexpr (requires { want[k]->penetrating; })
      CHECK(got[k]->penetrating == want[k]->penetrating);
  }
  return hits;
}

/// random_scene with a mesh, a height field and a moving kinematic body: every kind of body
/// the batch queries meet.
World batch_scene() {
  World w = random_scene(5, 120);
  auto mesh =
      std::make_shared<TriangleMesh const>(test::make(test::grid(12, 0.5f, test::terrain_height)));
  w.create_body({.type = BodyType::static_body,
                 .pose = Iso3::from_translation({-3, 0.5f, -3}),
                 .shape = MeshShape{mesh}});
  std::vector<float> heights(9 * 9);
  for (std::size_t k = 0; k < heights.size(); ++k)
    heights[k] = 0.3f * std::sin(float(k));
  auto field = HeightField::build(9, 9, heights, 0.5f, 0.5f);
  REQUIRE(field.ok());
  w.create_body(
      {.type = BodyType::static_body,
       .pose = Iso3::from_translation({2, 0.8f, 2}),
       .shape = HeightFieldShape{std::make_shared<HeightField const>(std::move(field.field))}});
  w.create_body({.type = BodyType::kinematic,
                 .pose = Iso3::from_translation({0, 3, 0}),
                 .linear_velocity = {0.5f, 0, 0},
                 .shape = Cuboid{Vec3{1, 0.2f, 1}}});
  w.step(1.0f / 60.0f);
  return w;
}

} // namespace

TEST_CASE("world queries: rays against brute force over every body", "[world][queries]") {
  World const w = random_scene(5, 120);
  REQUIRE(w.collider_count() > 10);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> at(-8.0f, 8.0f);
  int hits = 0, standalone = 0;
  for (int k = 0; k < 400; ++k) {
    Ray3 const ray{{at(rng), 6.0f + 0.5f * at(rng), at(rng)}, {at(rng), at(rng) - 4.0f, at(rng)}};
    float const max_toi = k % 4 == 0 ? std::numeric_limits<float>::infinity() : 2.0f;
    std::vector<WorldRayHit> brute;
    for (std::uint32_t i = 0; i < w.body_count(); ++i) {
      RayHit const h = brute_ray(w.shape(w.collider_id(i)), w.pose(w.collider_id(i)), ray,
                                 std::min(max_toi, std::numeric_limits<float>::max()));
      ColliderId const c = w.collider_id(i);
      if (h.hit) brute.push_back({c.body(), h.toi, ray.at(h.toi), h.normal, c});
    }
    std::sort(brute.begin(), brute.end(), [](WorldRayHit const& a, WorldRayHit const& b) {
      return a.toi < b.toi || (a.toi == b.toi && a.collider.index < b.collider.index);
    });
    auto const got = w.ray_cast(ray, max_toi);
    INFO("ray " << k);
    REQUIRE(got.has_value() == !brute.empty());
    if (got) {
      ++hits;
      CHECK(got->body == brute.front().body);
      CHECK(got->collider == brute.front().collider);
      standalone += int(got->collider.standalone);
      CHECK(got->toi == brute.front().toi);
      CHECK(got->normal.x == brute.front().normal.x);
    }
    std::vector<WorldRayHit> all;
    w.ray_cast_all(ray, max_toi, [&](WorldRayHit const& h) {
      all.push_back(h);
      return true;
    });
    REQUIRE(all.size() == brute.size());
    for (std::size_t j = 0; j < all.size(); ++j) {
      CHECK(all[j].body == brute[j].body);
      CHECK(all[j].collider == brute[j].collider);
      CHECK(all[j].toi == brute[j].toi);
    }
    if (all.size() > 1) { // stopping early
      std::size_t seen = 0;
      w.ray_cast_all(ray, max_toi, [&](WorldRayHit const&) { return ++seen < 1; });
      CHECK(seen == 1);
    }
  }
  CHECK(hits > 100);
  CHECK(standalone > 5); // standalone colliders hit, from their own tree
}

TEST_CASE(
    "world queries: the batch ray cast is the single one per ray, bit for bit, at every width",
    "[world][queries][determinism]") {
  // Every shape, a mesh and a height field (lane by lane), a kinematic body; rays in packets
  // of neighbours (a fan from one point), at random, unusable and filtered; counts that leave
  // a partial packet.
  World const w = batch_scene();
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> at(-8.0f, 8.0f), unit(-1.0f, 1.0f);
  std::vector<Ray3> rays;
  for (int fan = 0; fan < 12; ++fan) { // fans: coherent packets
    Vec3 const from{at(rng), 7.0f, at(rng)};
    for (int k = 0; k < 23; ++k)
      rays.push_back({from, {0.4f * unit(rng), -1.0f, 0.4f * unit(rng)}});
  }
  for (int k = 0; k < 150; ++k) // incoherent
    rays.push_back({{at(rng), 4.0f + 0.5f * at(rng), at(rng)}, {at(rng), at(rng), at(rng)}});
  float const inf = std::numeric_limits<float>::infinity();
  rays[3].dir = Vec3{};                                        // a zero direction
  rays[40].origin.x = std::numeric_limits<float>::quiet_NaN(); // a NaN origin
  rays[77] = {{0, 2, 0}, {0, -1, 0}};                          // straight down, maybe from inside
  rays[78] = {{0.5f, 9, 0.5f}, {-0.0f, -1, 0.0f}};             // signed zero components
  BodyId const skip = w.body_id(7);
  for (QueryFilter const& filter :
       {QueryFilter{}, QueryFilter{.exclude = std::span<BodyId const>(&skip, 1)},
        QueryFilter{.predicate = [](ColliderId id) { return id.index % 3 != 0; }}})
    for (float max_toi : {20.0f, 3.0f, inf}) {
      std::vector<std::optional<WorldRayHit>> want(rays.size());
      for (std::size_t k = 0; k < rays.size(); ++k)
        want[k] = w.ray_cast(rays[k], max_toi, filter);
      auto const check = [&]<class T>() {
        std::vector<std::optional<WorldRayHit>> got(rays.size());
        w.ray_cast_with<T>(rays, max_toi, got, filter);
        INFO("width " << lanes_v<T> << ", max_toi " << max_toi);
        CHECK(same_hits(got, want) > 20);
      };
      check.template operator()<float>();
      for_each_type<test::f32_wide_types>(check);
      std::vector<std::optional<WorldRayHit>> batch(rays.size());
      w.ray_cast(rays, max_toi, batch, filter); // the default width
      for (std::size_t k = 0; k < rays.size(); ++k)
        CHECK(batch[k].has_value() == want[k].has_value());
    }
  // Some of every kind of body are hit (the lanes' casts against each shape, the lane-by-lane
  // mesh and field).
  std::vector<std::optional<WorldRayHit>> got(rays.size());
  w.ray_cast(rays, inf, got);
  std::set<std::size_t> kinds;
  for (auto const& h : got)
    if (h) kinds.insert(w.shape(h->collider).index());
  CHECK(kinds.size() >= 6);
  // Ties: pairs of bodies with the same shape at the same pose; the lower index wins, whether
  // it is in the tree walked first (static) or in a later one (kinematic).
  World t;
  auto const add = [&](BodyType type, float x) {
    return t
        .create_body({.type = type,
                      .pose = Iso3::from_translation({x, 1, 0}),
                      .shape = Cuboid{Vec3::splat(0.5f)}})
        .id;
  };
  BodyId const low_kinematic = add(BodyType::kinematic, 0);
  add(BodyType::static_body, 0);
  BodyId const low_static = add(BodyType::static_body, 10);
  add(BodyType::kinematic, 10);
  std::vector<Ray3> down;
  for (int k = 0; k < 38; ++k)
    down.push_back({{0.05f * float(k % 19 - 9) + (k < 19 ? 0.0f : 10.0f), 5, 0.02f * float(k % 19)},
                    {0, -1, 0}});
  std::vector<std::optional<WorldRayHit>> tied(down.size());
  auto const check_ties = [&]<class T>() {
    t.ray_cast_with<T>(down, 20.0f, tied);
    for (std::size_t k = 0; k < down.size(); ++k) {
      REQUIRE(tied[k]);
      CHECK(tied[k]->body == (k < 19 ? low_kinematic : low_static));
      CHECK(tied[k]->toi == 3.5f);
    }
  };
  check_ties.template operator()<float>();
  for_each_type<test::f32_wide_types>(check_ties);
  // Spans of different lengths: an error, nothing written.
  std::vector<std::optional<WorldRayHit>> short_out(rays.size() - 1);
  CHECK_THROWS_AS(w.ray_cast(rays, 20.0f, short_out), std::invalid_argument);
  CHECK(std::none_of(short_out.begin(), short_out.end(), [](auto const& h) { return h; }));
  std::vector<Ray3> none;
  std::vector<std::optional<WorldRayHit>> none_out;
  w.ray_cast(none, 20.0f, none_out); // empty spans: nothing to do
  // A NaN or negative max_toi finds nothing, as the single form (every width).
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), -1.0f}) {
    auto const none_found = [&]<class T>() {
      std::vector<std::optional<WorldRayHit>> cleared(rays.size(), WorldRayHit{});
      w.ray_cast_with<T>(rays, bad, cleared);
      CHECK(std::none_of(cleared.begin(), cleared.end(),
                         [](auto const& h) { return h.has_value(); }));
    };
    none_found.template operator()<float>();
    for_each_type<test::f32_wide_types>(none_found);
  }
}

TEST_CASE("world queries: points, boxes and shapes against brute force", "[world][queries]") {
  World const w = random_scene(17, 120);
  REQUIRE(w.collider_count() > 10);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> at(-7.0f, 7.0f), h(-0.5f, 5.0f);
  float const margin = w.config().speculative_distance;
  int contained = 0, overlapped = 0;
  for (int k = 0; k < 300; ++k) {
    Vec3 const p{at(rng), h(rng), at(rng)};
    INFO("query " << k << " at " << p);
    // point_query
    std::vector<ColliderId> got, want; // whole ids: slot, generation, kind
    w.point_query(p, [&](ColliderId id) {
      got.push_back(id);
      return true;
    });
    for (std::uint32_t i = 0; i < w.body_count(); ++i)
      if (brute_distance(w.shape(w.collider_id(i)), w.pose(w.collider_id(i)), p) <= 0.0f)
        want.push_back(w.collider_id(i));
    REQUIRE(got == want);
    contained +=
        int(std::any_of(got.begin(), got.end(), [](ColliderId c) { return c.index != 0; }));
    // project_point
    float const reach = 1.5f;
    auto const near = w.project_point(p, reach);
    float best = std::numeric_limits<float>::infinity();
    for (std::uint32_t i = 0; i < w.body_count(); ++i)
      best = std::min(best, std::max(0.0f, brute_distance(w.shape(w.collider_id(i)),
                                                          w.pose(w.collider_id(i)), p)));
    REQUIRE(near.has_value() == (best <= reach));
    if (near) CHECK(near->distance == Approx(best).margin(1e-4));
    // overlap_aabb: the grown boxes
    Aabb3 const box = Aabb3::from_center_half_extents(p, Vec3{0.5f, 0.3f, 0.7f});
    got.clear();
    want.clear();
    w.overlap_aabb(box, [&](ColliderId id) {
      got.push_back(id);
      return true;
    });
    for (std::uint32_t i = 0; i < w.body_count(); ++i)
      if (bool(w.aabb(w.collider_id(i)).grow(margin).intersects(box)))
        want.push_back(w.collider_id(i));
    REQUIRE(got == want);
    // overlap_shape: a box at p, exact
    Cuboid const probe{Vec3{0.5f, 0.3f, 0.7f}};
    Iso3 const probe_pose = Iso3::from_translation(p);
    got.clear();
    want.clear();
    w.overlap_shape(probe, probe_pose, [&](ColliderId id) {
      got.push_back(id);
      return true;
    });
    for (std::uint32_t i = 0; i < w.body_count(); ++i) {
      BodyShape const& s = w.shape(w.collider_id(i));
      bool touch;
      if (auto const* hs = std::get_if<HalfSpace>(&s)) {
        Vec3 const n = w.pose(w.collider_id(i)).transform_vector(hs->normal);
        touch = n.dot(probe_pose.transform_point(probe.core_support(-n)) -
                      w.pose(w.collider_id(i)).translation) <= 0.0f;
      } else {
        touch = std::visit(
            [&](auto const& b) {
              using B = std::decay_t<decltype(b)>;
              if constexpr (std::is_same_v<B, HalfSpace>) {
                return false;
              } else if constexpr (is_triangle_shape_v<B>) {
                return mesh_intersects(*b.source(), w.pose(w.collider_id(i)), probe, probe_pose);
              } else {
                ClosestPoints const c =
                    closest_points(probe, probe_pose, b, w.pose(w.collider_id(i)));
                return bool(c.overlap) || c.distance <= 0.0f;
              }
            },
            s);
      }
      if (touch) want.push_back(w.collider_id(i));
    }
    REQUIRE(got == want);
    overlapped += int(got.size() > 1);
    // shape_cast: a sphere from p moving down 6 m
    Sphere const ball{0.25f};
    ShapeCastConfig cfg;
    auto const cast = w.shape_cast(ball, probe_pose, {0.3f, -6.0f, 0.2f}, cfg);
    float first = std::numeric_limits<float>::infinity();
    std::uint32_t first_body = ~0u;
    for (std::uint32_t i = 0; i < w.body_count(); ++i) {
      BodyShape const& s = w.shape(w.collider_id(i));
      float t = std::numeric_limits<float>::infinity();
      if (auto const* hs = std::get_if<HalfSpace>(&s)) {
        Vec3 const n = w.pose(w.collider_id(i)).transform_vector(hs->normal);
        float const gap = n.dot(p - w.pose(w.collider_id(i)).translation) - ball.radius;
        float const closing = -n.dot(Vec3{0.3f, -6.0f, 0.2f});
        t = gap <= 0.0f ? 0.0f : (closing > 0.0f && gap <= closing ? gap / closing : t);
      } else {
        std::visit(
            [&](auto const& b) {
              using B = std::decay_t<decltype(b)>;
              if constexpr (is_triangle_shape_v<B>) {
                t = mesh_shape_cast(*b.source(), w.pose(w.collider_id(i)), ball, probe_pose,
                                    Vec3{0.3f, -6.0f, 0.2f}, cfg)
                        .toi;
              } else if constexpr (!std::is_same_v<B, HalfSpace>) {
                ShapeCastHit const c = plume::shape_cast(ball, probe_pose, Vec3{0.3f, -6.0f, 0.2f},
                                                         b, w.pose(w.collider_id(i)), cfg);
                if (c.hit && !c.failed) t = c.toi;
              }
            },
            s);
      }
      if (t < first) {
        first = t;
        first_body = i;
      }
    }
    REQUIRE(cast.has_value() == std::isfinite(first));
    if (cast) {
      CHECK(cast->collider.index == first_body);
      CHECK(cast->collider == w.collider_id(first_body));
      CHECK(cast->body == cast->collider.body());
      CHECK(cast->toi == first);
    }
  }
  CHECK(contained > 0);
  CHECK(overlapped > 10);
}

TEST_CASE("world queries: contact_query reports every body within the distance, with its manifold",
          "[world][queries]") {
  World const w = random_scene(23, 120);
  REQUIRE(w.collider_count() > 10);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> at(-7.0f, 7.0f), h(0.0f, 5.0f);
  Capsule const probe{0.4f, 0.3f};
  float const distance = 0.1f;
  int reported = 0;
  for (int k = 0; k < 200; ++k) {
    Iso3 const pose{Quat::from_rotation_x(at(rng)), {at(rng), h(rng), at(rng)}};
    INFO("query " << k << " at " << pose.translation);
    std::vector<ColliderId> got;
    w.contact_query(probe, pose, distance, [&](ColliderId id, Manifold const& m) {
      got.push_back(id);
      REQUIRE(!m.empty());
      REQUIRE(m.normal.length() == Approx(1).epsilon(1e-4));
      REQUIRE(m.min_separation() <= distance);
      return true;
    });
    REQUIRE(std::is_sorted(got.begin(), got.end(),
                           [](ColliderId a, ColliderId b) { return a.index < b.index; }));
    reported += int(got.size());
    // An independent oracle: the distance between the probe and each body.
    for (std::uint32_t i = 0; i < w.body_count(); ++i) {
      BodyShape const& s = w.shape(w.collider_id(i));
      Iso3 const pb = w.pose(w.collider_id(i));
      float d;
      if (auto const* hs = std::get_if<HalfSpace>(&s)) {
        Vec3 const n = pb.transform_vector(hs->normal);
        Vec3 const deepest =
            pose.transform_point(probe.core_support(pose.inverse_transform_vector(-n))) -
            n * probe.core_radius();
        d = n.dot(deepest - pb.translation);
      } else {
        d = std::visit(
            [&](auto const& b) {
              using B = std::decay_t<decltype(b)>;
              if constexpr (std::is_same_v<B, HalfSpace>) {
                return 0.0f;
              } else if constexpr (is_triangle_shape_v<B>) {
                float least = std::numeric_limits<float>::infinity();
                for (std::uint32_t t = 0; t < b.source()->triangle_count(); ++t) {
                  ClosestPoints const c = closest_points(probe, pose, b.source()->triangle(t), pb);
                  least = std::min(least, c.overlap ? -1.0f : c.distance);
                }
                return least;
              } else {
                ClosestPoints const c = closest_points(probe, pose, b, pb);
                return c.overlap ? -1.0f : c.distance;
              }
            },
            s);
      }
      bool const in = std::find(got.begin(), got.end(), w.collider_id(i)) != got.end();
      INFO("body " << i << " at distance " << d);
      if (d < distance - 1e-3f) REQUIRE(in);
      if (d > distance + 1e-3f) REQUIRE(!in);
    }
  }
  CHECK(reported > 50); // the scene is dense enough for the test to mean something
  // Bad input finds nothing; f returning false stops.
  int calls = 0;
  auto const count = [&](ColliderId, Manifold const&) {
    ++calls;
    return true;
  };
  float const nan = std::numeric_limits<float>::quiet_NaN();
  w.contact_query(probe, Iso3::from_translation({nan, 0, 0}), distance, count);
  w.contact_query(probe, Iso3::from_translation({0, 0.2f, 0}), -1.0f, count);
  w.contact_query(probe, Iso3::from_translation({0, 0.2f, 0}), nan, count);
  w.contact_query(HalfSpace{Vec3::Y}, Iso3{}, distance, count);
  CHECK(calls == 0);
  w.contact_query(Cuboid{Vec3::splat(6)}, Iso3::from_translation({0, 2, 0}), distance,
                  [&](ColliderId, Manifold const&) {
                    ++calls;
                    return false;
                  });
  CHECK(calls == 1);
}

TEST_CASE("world queries: filters, layers, fresh poses, both broad phases, bad input",
          "[world][queries]") {
  World w;
  scenes::add_ground(w);
  BodyId const a = w.create_body({.type = BodyType::static_body,
                                  .pose = Iso3::from_translation({0, 1, 0}),
                                  .shape = Cuboid{Vec3::splat(0.5f)},
                                  .layers = {.memberships = 2, .filters = 0xffffffffu}})
                       .id;
  BodyId const b = w.create_body({.pose = Iso3::from_translation({0, 4, 0}),
                                  .shape = Sphere{0.5f},
                                  .layers = {.memberships = 4, .filters = ~2u}})
                       .id;
  Ray3 const down{{0, 10, 0}, {0, -1, 0}};
  auto hit = w.ray_cast(down, 100.0f);
  REQUIRE(hit);
  CHECK(hit->body == b); // the falling sphere, before the step
  CHECK(hit->toi == Approx(5.5f));
  // mask, exclude and predicate
  CHECK(w.ray_cast(down, 100.0f, {.mask = 2})->body == a);
  BodyId const skip[] = {b};
  CHECK(w.ray_cast(down, 100.0f, {.exclude = skip})->body == a);
  CHECK(w.ray_cast(down, 100.0f, {.predicate = [&](ColliderId id) { return id != b && id != a; }})
            ->body == BodyId{0});
  CHECK(!w.ray_cast(down, 100.0f, {.mask = 8}));
  // Layers: the sphere (filters exclude layer 2) falls through the box onto the ground.
  for (int s = 0; s < 180; ++s)
    w.step(1.0f / 60.0f);
  CHECK(w.pose(b).translation.y == Approx(0.5f).margin(0.05f));
  // The queries see the pose after the steps.
  hit = w.ray_cast({{0, 0.5f, -5}, {0, 0, 1}}, 100.0f);
  REQUIRE(hit);
  CHECK(((hit->body == b) || (hit->body == a)));
  CHECK(hit->toi == Approx(4.5f).margin(0.06f));
  // Shape casts: normals out of the body hit, toward the cast shape.
  auto const onto_box = w.shape_cast(Sphere{0.2f}, Iso3::from_translation({0, 3, 0}), {0, -3, 0},
                                     {}, {.exclude = skip});
  REQUIRE(onto_box);
  CHECK(onto_box->body == a);
  CHECK(onto_box->toi == Approx(1.3f / 3.0f).margin(1e-3));
  CHECK(onto_box->normal.y == Approx(1.0f).margin(1e-4));
  CHECK(onto_box->point.y == Approx(1.5f).margin(1e-3));
  auto const onto_ground =
      w.shape_cast(Sphere{0.2f}, Iso3::from_translation({3, 3, 3}), {0, -3, 0});
  REQUIRE(onto_ground);
  CHECK(onto_ground->body == BodyId{0});
  CHECK(onto_ground->toi == Approx(2.8f / 3.0f));
  CHECK(onto_ground->normal.y == 1.0f);
  CHECK(onto_ground->point.y == Approx(0.0f).margin(1e-5));
  // set_layers: the pair now touches.
  CHECK(w.set_layers(b, {}) == BodyError::none);
  CHECK(w.set_layers(BodyId{99}, {}) == BodyError::bad_body);
  CHECK(w.layers(b).memberships == 1);
  // A stale id in exclude excludes nothing, not the slot's new body (found in review).
  {
    World v;
    BodyId const old = v.create_body({.type = BodyType::static_body, .shape = Sphere{1.0f}}).id;
    REQUIRE(v.destroy_body(old) == BodyError::none);
    BodyId const now = v.create_body({.type = BodyType::static_body, .shape = Sphere{1.0f}}).id;
    REQUIRE(now.index == old.index);
    BodyId const stale[] = {old};
    auto const h = v.ray_cast({{0, 5, 0}, {0, -1, 0}}, 10.0f, {.exclude = stale});
    REQUIRE(h);
    CHECK(h->body == now);
    BodyId const current[] = {now};
    CHECK(!v.ray_cast({{0, 5, 0}, {0, -1, 0}}, 10.0f, {.exclude = current}));
  }
  // A zero direction finds nothing, also inside a half-space (the ground).
  CHECK(!w.ray_cast({{3, -1, 3}, {0, 0, 0}}, 10.0f));
  // Bad input finds nothing and does not crash.
  float const nan = std::numeric_limits<float>::quiet_NaN();
  CHECK(!w.ray_cast({{nan, 0, 0}, {0, -1, 0}}, 10.0f));
  CHECK(!w.ray_cast(down, -1.0f));
  CHECK(!w.ray_cast(down, nan));
  CHECK(!w.ray_cast({{0, 10, 0}, {0, 0, 0}}, 10.0f));
  CHECK(!w.project_point({nan, 0, 0}, 1.0f));
  CHECK(!w.shape_cast(Sphere{0.1f}, Iso3::from_translation({0, 5, 0}), {nan, 0, 0}));
  CHECK(!w.shape_cast(HalfSpace{Vec3::Y}, Iso3{}, {0, -1, 0})); // not a convex query shape
  CHECK(!w.shape_cast(Sphere{0.1f}, Iso3::from_translation({0, 5, 0}), {0, -10, 0},
                      {.target_distance = std::numeric_limits<float>::infinity()}));
  CHECK(!w.shape_cast(Sphere{0.1f}, Iso3::from_translation({0, 5, 0}), {0, -10, 0},
                      {.target_distance = nan}));
  int calls = 0;
  w.point_query({nan, 0, 0}, [&](ColliderId) { return ++calls > 0; });
  w.overlap_aabb({Vec3::splat(nan), Vec3::splat(nan)}, [&](ColliderId) { return ++calls > 0; });
  CHECK(calls == 0);
  // The ground (a half-space) contains every point below it.
  std::vector<BodyId> in;
  w.point_query({3, -1, 3}, [&](ColliderId id) {
    in.push_back(id.body());
    return true;
  });
  CHECK(in == std::vector<BodyId>{BodyId{0}});

  // Sort and sweep keeps no trees of its own for pairs; the queries still work.
  World const s = random_scene(5, 60, BroadPhaseKind::sort_and_sweep);
  World const t = random_scene(5, 60, BroadPhaseKind::bvh);
  CHECK(s.state_hash() == t.state_hash());
  for (int k = 0; k < 20; ++k) {
    Ray3 const r{{float(k) - 10.0f, 8.0f, 0.5f}, {0.05f, -1.0f, 0.02f}};
    auto const hs = s.ray_cast(r, 50.0f), ht = t.ray_cast(r, 50.0f);
    REQUIRE(hs.has_value() == ht.has_value());
    if (hs) CHECK(hs->body == ht->body);
  }
}

TEST_CASE("world queries: the batch shape cast is the single one per query, bit for bit, at "
          "every width",
          "[world][queries][determinism]") {
  World const w = batch_scene();
  std::mt19937 rng(43);
  std::uniform_real_distribution<float> at(-7.0f, 7.0f), unit(-1.0f, 1.0f), size(0.1f, 0.6f);
  std::vector<BodyShape> shapes;
  std::vector<Iso3> poses;
  std::vector<Vec3> motions;
  auto const add = [&](BodyShape const& shape, bool near_packet) {
    Vec3 const from = near_packet && !poses.empty()
                          ? poses.back().translation + Vec3{0.3f * unit(rng), 0, 0.3f * unit(rng)}
                          : Vec3{at(rng), 3.0f + 2.0f * unit(rng), at(rng)};
    Vec3 axis{unit(rng), unit(rng), unit(rng)};
    axis = axis.length() > 0.1f ? axis.normalize() : Vec3::Y;
    shapes.push_back(shape);
    poses.push_back(Iso3{Quat::from_axis_angle(axis, 3.0f * unit(rng)), from});
    motions.push_back({2.0f * unit(rng), -4.0f + unit(rng), 2.0f * unit(rng)});
  };
  for (int run = 0; run < 24; ++run) { // runs of one kind, of every size, coherent or not
    int const len = 1 + int(rng() % 21);
    for (int k = 0; k < len; ++k) {
      switch (run % 4) {
      case 0:
        add(Sphere{size(rng)}, run % 3 == 0);
        break;
      case 1:
        add(Capsule{size(rng), size(rng)}, run % 3 == 0);
        break;
      case 2:
        add(Cuboid{Vec3{size(rng), size(rng), size(rng)}}, run % 3 == 0);
        break;
      default:
        add(Cylinder{size(rng), size(rng)}, run % 3 == 0);
        break;
      }
    }
  }
  for (int k = 0; k < 12; ++k) // a mixed run, hulls and shapes that are no query shape
    add(k % 3 == 0   ? BodyShape{Sphere{0.3f}}
        : k % 3 == 1 ? BodyShape{tetra_hull()}
                     : BodyShape{HalfSpace{Vec3::Y}},
        false);
  poses[5].translation.x = std::numeric_limits<float>::quiet_NaN(); // unusable lanes
  motions[9] = Vec3{std::numeric_limits<float>::infinity(), 0, 0};
  poses[30] = Iso3::from_translation({0, 0.2f, 0}); // starts in the ground
  motions[31] = Vec3{};                             // does not move
  ShapeCastConfig skin;
  skin.target_distance = 0.05f;
  skin.stop_at_penetration = false;
  ShapeCastConfig short_cast;
  short_cast.max_toi = 0.3f;
  BodyId const skip = w.body_id(9);
  struct Case {
    ShapeCastConfig cfg;
    QueryFilter filter;
  };
  std::vector<Case> cases;
  cases.push_back({ShapeCastConfig{}, QueryFilter{}});
  cases.push_back({skin, QueryFilter{.exclude = std::span<BodyId const>(&skip, 1)}});
  cases.push_back(
      {short_cast, QueryFilter{.predicate = [](ColliderId id) { return id.index % 4 != 0; }}});
  for (Case const& c : cases) {
    std::vector<std::optional<WorldShapeHit>> want(shapes.size());
    for (std::size_t k = 0; k < shapes.size(); ++k)
      want[k] = w.shape_cast(shapes[k], poses[k], motions[k], c.cfg, c.filter);
    auto const check = [&]<class T>() {
      std::vector<std::optional<WorldShapeHit>> got(shapes.size());
      w.shape_cast_with<T>(shapes, poses, motions, c.cfg, got, c.filter);
      INFO("width " << lanes_v<T> << ", target distance " << c.cfg.target_distance);
      CHECK(same_hits(got, want) > 30);
    };
    check.template operator()<float>();
    for_each_type<test::f32_wide_types>(check);
  }
  // Spans of different lengths: an error, nothing written.
  std::vector<std::optional<WorldShapeHit>> out(shapes.size());
  std::span<Vec3 const> const fewer(motions.data(), motions.size() - 1);
  CHECK_THROWS_AS(w.shape_cast(shapes, poses, fewer, ShapeCastConfig{}, out),
                  std::invalid_argument);
  CHECK(std::none_of(out.begin(), out.end(), [](auto const& h) { return h.has_value(); }));
  // A configuration the single form refuses (NaN or negative max_toi or target distance)
  // finds nothing in any lane, and clears what out held.
  for (int bad = 0; bad < 3; ++bad) {
    ShapeCastConfig cfg;
    if (bad == 0) cfg.max_toi = std::numeric_limits<float>::quiet_NaN();
    if (bad == 1) cfg.max_toi = -1.0f;
    if (bad == 2) cfg.target_distance = -0.1f;
    auto const none_found = [&]<class T>() {
      std::vector<std::optional<WorldShapeHit>> got(shapes.size(), WorldShapeHit{});
      w.shape_cast_with<T>(shapes, poses, motions, cfg, got);
      CHECK(std::none_of(got.begin(), got.end(), [](auto const& h) { return h.has_value(); }));
    };
    none_found.template operator()<float>();
    for_each_type<test::f32_wide_types>(none_found);
  }
}
