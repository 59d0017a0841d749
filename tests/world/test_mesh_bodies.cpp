// Bodies on triangle meshes and height fields (MeshShape, HeightFieldShape): a box settles on
// a mesh or field floor where it settles on a half-space, slides across the seams without
// bumps, sits in a valley on one contact
// per slope with one contact event; queries see meshes; bad definitions are refused; every
// width steps the same world.
#include "../common/types.hpp"
#include "../spatial/mesh_support.hpp"

#include <plume/solver/world/world.hpp>

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <memory>
#include <vector>

using namespace plume;
using namespace plume::test;

namespace {

constexpr float dt = 1.0f / 60.0f;

/// A flat 16 x 16 m floor of 1 m cells at y = 0, centred on the origin.
std::shared_ptr<TriangleMesh const> flat_floor() {
  return std::make_shared<TriangleMesh const>(
      make(grid(16, 1.0f, [](float, float) { return 0.0f; })));
}

/// A static body of `shape` (a mesh or a height field) with its origin at (-8, 0, -8).
BodyId add_ground_shape(World& w, BodyShape const& shape, float friction = 0.6f) {
  CreateBodyResult const r = w.create_body({.type = BodyType::static_body,
                                            .pose = Iso3::from_translation({-8.0f, 0.0f, -8.0f}),
                                            .shape = shape,
                                            .friction = friction});
  REQUIRE(r);
  return r.id;
}

BodyId add_mesh(World& w, std::shared_ptr<TriangleMesh const> mesh, float friction = 0.6f) {
  return add_ground_shape(w, MeshShape{std::move(mesh)}, friction);
}

/// The same floor as a height field: 17 x 17 samples, 1 m cells.
std::shared_ptr<HeightField const> flat_field() {
  std::vector<float> const zeros(17 * 17, 0.0f);
  auto r = HeightField::build(17, 17, zeros, 1.0f, 1.0f);
  REQUIRE(r.ok());
  return std::make_shared<HeightField const>(std::move(r.field));
}

BodyId add_field(World& w, std::shared_ptr<HeightField const> field, float friction = 0.6f) {
  return add_ground_shape(w, HeightFieldShape{std::move(field)}, friction);
}

BodyId add_half_space(World& w, float friction = 0.6f) {
  CreateBodyResult const r = w.create_body(
      {.type = BodyType::static_body, .shape = HalfSpace{Vec3::Y}, .friction = friction});
  REQUIRE(r);
  return r.id;
}

} // namespace

TEST_CASE("mesh bodies: a box settles on a mesh floor as on a half-space", "[world][mesh]") {
  enum class floor_kind { plane, mesh_first, mesh_second, height_field };
  auto const settle = [](floor_kind kind) {
    World w;
    if (kind == floor_kind::plane) add_half_space(w);
    if (kind == floor_kind::mesh_first) add_mesh(w, flat_floor());
    if (kind == floor_kind::height_field) add_field(w, flat_field());
    // Over a vertex of the grid, turned: its corners over four different cells.
    BodyId const box =
        w.create_body({.pose = Iso3{Quat::from_axis_angle(Vec3::Y, 0.3f), {0.0f, 1.0f, 0.0f}},
                       .shape = Cuboid{Vec3::splat(0.5f)}})
            .id;
    // Created after the box, the mesh is the pair's B: its manifolds are turned round.
    if (kind == floor_kind::mesh_second) add_mesh(w, flat_floor());
    for (int s = 0; s < 120; ++s)
      w.step(dt);
    return std::pair{w.pose(box), w.linear_velocity(box)};
  };
  auto const [on_plane, v_plane] = settle(floor_kind::plane);
  for (floor_kind const kind :
       {floor_kind::mesh_first, floor_kind::mesh_second, floor_kind::height_field}) {
    auto const [on_mesh, v_mesh] = settle(kind);
    CHECK(on_mesh.translation.y == Approx(0.5f).margin(0.02f));
    CHECK(v_mesh.length() < 0.01f);
    CHECK((on_mesh.translation - on_plane.translation).length() < 2e-3f);
    CHECK(on_mesh.rotation.dot(on_plane.rotation) > 0.99999f);
  }
}

TEST_CASE("mesh bodies: a box slides across the floor's seams without bumps", "[world][mesh]") {
  // 0.3 friction: decelerates at 0.3 g, from 4 m/s to rest in about 1.4 s over 2.7 m,
  // crossing about four seams and as many diagonals.
  auto const slide = [](int floor, std::vector<Vec3>& path) {
    World w;
    if (floor == 0) add_half_space(w, 0.3f);
    if (floor == 1) add_mesh(w, flat_floor(), 0.3f);
    if (floor == 2) add_field(w, flat_field(), 0.3f);
    BodyId const box = w.create_body({.pose = Iso3::from_translation({-1.3f, 0.5f, 0.2f}),
                                      .linear_velocity = {4.0f, 0.0f, 0.7f},
                                      .shape = Cuboid{Vec3{0.5f, 0.5f, 0.5f}},
                                      .friction = 0.3f})
                           .id;
    float worst_vy = 0.0f;
    for (int s = 0; s < 90; ++s) {
      w.step(dt);
      path.push_back(w.pose(box).translation);
      worst_vy = std::max(worst_vy, std::abs(w.linear_velocity(box).y));
    }
    return worst_vy;
  };
  std::vector<Vec3> on_plane;
  CHECK(slide(0, on_plane) < 0.02f);
  for (int floor : {1, 2}) {
    std::vector<Vec3> on_mesh;
    float const vy_mesh = slide(floor, on_mesh);
    CHECK(vy_mesh < 0.02f);
    float worst = 0.0f, lowest = 1.0f, highest = 0.0f;
    for (std::size_t k = 0; k < on_mesh.size(); ++k) {
      worst = std::max(worst, (on_mesh[k] - on_plane[k]).length());
      lowest = std::min(lowest, on_mesh[k].y);
      highest = std::max(highest, on_mesh[k].y);
    }
    CHECK(worst < 0.01f); // the same path as on a plane, within 1 cm
    CHECK(highest - lowest < 0.005f);
    CHECK(on_mesh.back().x - on_mesh.front().x > 2.0f); // it did cross the seams
  }
}

TEST_CASE("mesh bodies: a box in a valley rests on one contact per slope, one event",
          "[world][mesh]") {
  // A V valley along z: two slopes of 30 degrees meeting at x = 0.
  float const c = 4.0f * std::cos(0.5236f), s = 4.0f * std::sin(0.5236f);
  std::vector<Vec3> const v{{0, 0, -4}, {0, 0, 4}, {-c, s, 0}, {c, s, 0}};
  std::vector<std::uint32_t> const idx{0, 2, 1, 0, 1, 3};
  auto r = TriangleMesh::build(v, idx);
  REQUIRE(r.ok());
  World w;
  BodyId const valley =
      w.create_body({.type = BodyType::static_body,
                     .shape = MeshShape{std::make_shared<TriangleMesh const>(std::move(r.mesh))}})
          .id;
  BodyId const ball =
      w.create_body({.pose = Iso3::from_translation({0.0f, 1.5f, 0.0f}), .shape = Sphere{0.4f}}).id;
  int begins = 0;
  for (int k = 0; k < 120; ++k) {
    w.step(dt);
    begins += int(w.events().contact_begin.size());
  }
  CHECK(begins == 1);
  std::size_t of_pair = 0;
  for (auto const list : {w.contacts(), w.sleeping_contacts()}) // at rest: maybe asleep
    for (Contact const& ct : list)
      of_pair +=
          ColliderPair{w.body_id(ct.body_a), w.body_id(ct.body_b)} == ColliderPair{valley, ball};
  CHECK(of_pair == 2);
  // At rest on both slopes: centre at r / cos(30 deg) above the valley's floor line.
  CHECK(w.pose(ball).translation.y == Approx(0.4f / std::cos(0.5236f)).margin(0.01f));
  CHECK(std::abs(w.pose(ball).translation.x) < 0.01f);
  CHECK(w.linear_velocity(ball).length() < 0.02f);
}

TEST_CASE("mesh bodies: queries see meshes", "[world][mesh]") {
  World w;
  BodyId const floor = add_mesh(w, flat_floor());
  Ray3 const down{{0.3f, 2.0f, 0.7f}, {0.0f, -1.0f, 0.0f}};
  auto const hit = w.ray_cast(down, 10.0f);
  REQUIRE(hit);
  CHECK(hit->body == floor);
  CHECK(hit->toi == Approx(2.0f).margin(1e-5));
  CHECK(hit->normal.y == Approx(1.0f).margin(1e-6));

  auto const cast =
      w.shape_cast(Sphere{0.5f}, Iso3::from_translation({0.3f, 2.0f, 0.7f}), {0.0f, -2.0f, 0.0f});
  REQUIRE(cast);
  CHECK(cast->body == floor);
  CHECK(cast->toi == Approx(0.75f).margin(1e-4));
  CHECK(cast->normal.y == Approx(1.0f).margin(1e-4));

  int touching = 0;
  w.overlap_shape(Cuboid{Vec3::splat(0.5f)}, Iso3::from_translation({0.2f, 0.45f, 0.1f}),
                  [&](ColliderId id) { return touching += id == floor, true; });
  CHECK(touching == 1);
  w.overlap_shape(Cuboid{Vec3::splat(0.5f)}, Iso3::from_translation({0.2f, 0.6f, 0.1f}),
                  [&](ColliderId id) { return touching += id == floor, true; });
  CHECK(touching == 1); // 10 cm above: no touch

  auto const near = w.project_point({1.25f, 0.8f, -2.5f}, 5.0f);
  REQUIRE(near);
  CHECK(near->body == floor);
  CHECK(near->distance == Approx(0.8f).margin(1e-5));
  CHECK(near->point.y == Approx(0.0f).margin(1e-5));

  int manifolds = 0;
  w.contact_query(Sphere{0.5f}, Iso3::from_translation({0.3f, 0.49f, 0.7f}), 0.01f,
                  [&](ColliderId id, Manifold const& m) {
                    CHECK(id == floor);
                    CHECK(m.normal.y == Approx(1.0f).margin(1e-5)); // A, the body, to B
                    return ++manifolds, true;
                  });
  CHECK(manifolds == 1);

  // The same questions to a height field.
  World wf;
  BodyId const ground = add_field(wf, flat_field());
  auto const fh = wf.ray_cast(down, 10.0f);
  REQUIRE(fh);
  CHECK(fh->body == ground);
  CHECK(fh->toi == Approx(2.0f).margin(1e-5));
  auto const fc =
      wf.shape_cast(Sphere{0.5f}, Iso3::from_translation({0.3f, 2.0f, 0.7f}), {0.0f, -2.0f, 0.0f});
  REQUIRE(fc);
  CHECK(fc->toi == Approx(0.75f).margin(1e-4));
  auto const fp = wf.project_point({1.25f, 0.8f, -2.5f}, 5.0f);
  REQUIRE(fp);
  CHECK(fp->distance == Approx(0.8f).margin(1e-5));
  int touched = 0;
  wf.overlap_shape(Sphere{0.5f}, Iso3::from_translation({0.3f, 0.45f, 0.7f}),
                   [&](ColliderId id) { return touched += id == ground, true; });
  CHECK(touched == 1);
}

TEST_CASE("mesh bodies: bad definitions are refused", "[world][mesh][bad-input]") {
  World w;
  CHECK(w.create_body({.type = BodyType::static_body, .shape = MeshShape{}}).error ==
        BodyError::bad_shape);
  CHECK(w.create_body({.type = BodyType::static_body,
                       .shape = MeshShape{std::make_shared<TriangleMesh const>()}})
            .error == BodyError::bad_shape);
  CHECK(w.create_body({.type = BodyType::dynamic, .shape = MeshShape{flat_floor()}}).error ==
        BodyError::bad_shape);
  CHECK(w.create_body({.type = BodyType::static_body, .shape = HeightFieldShape{}}).error ==
        BodyError::bad_shape);
  CHECK(w.create_body({.type = BodyType::dynamic, .shape = HeightFieldShape{flat_field()}}).error ==
        BodyError::bad_shape);
  CHECK(w.alive_count() == 0);
  CHECK(w.create_body({.type = BodyType::kinematic, .shape = MeshShape{flat_floor()}}));
  CHECK(w.create_body({.type = BodyType::static_body, .shape = MeshShape{flat_floor()}}));
  // A mesh is not a query shape.
  CHECK_FALSE(w.shape_cast(MeshShape{flat_floor()}, Iso3{}, {0.0f, -1.0f, 0.0f}));
}

TEST_CASE("mesh bodies: every width steps the same world", "[world][mesh][determinism]") {
  auto const run = [&]<class T>(std::type_identity<T>) {
    World w;
    add_mesh(w, std::make_shared<TriangleMesh const>(make(grid(16, 1.0f, terrain_height))));
    // A terrain field beside it, over x in [8, 24].
    std::vector<float> h(17 * 17);
    for (std::uint32_t z = 0; z < 17; ++z)
      for (std::uint32_t x = 0; x < 17; ++x)
        h[z * 17 + x] = terrain_height(float(x), float(z));
    auto built = HeightField::build(17, 17, h, 1.0f, 1.0f);
    REQUIRE(built.ok());
    w.create_body(
        {.type = BodyType::static_body,
         .pose = Iso3::from_translation({8.0f, 0.0f, -8.0f}),
         .shape = HeightFieldShape{std::make_shared<HeightField const>(std::move(built.field))}});
    for (int k = 0; k < 12; ++k)
      w.create_body({.pose = Iso3{Quat::from_axis_angle(Vec3::X, 0.2f * float(k)),
                                  {-3.0f + 2.0f * float(k), 1.5f, 0.3f * float(k)}},
                     .shape = k % 2 ? BodyShape{Cuboid{Vec3::splat(0.3f)}}
                                    : BodyShape{Capsule{0.2f, 0.25f}}});
    for (int s = 0; s < 90; ++s)
      w.template step_with<T>(dt);
    return w.state_hash();
  };
  std::uint64_t const scalar = run(std::type_identity<float>{});
  for_each_type<test::f32_wide_types>(
      [&]<class T>() { CHECK(run(std::type_identity<T>{}) == scalar); });
  CHECK(run(std::type_identity<float>{}) == scalar);
}

TEST_CASE("mesh bodies: the narrow phase turns a mesh's manifolds round when the mesh is B",
          "[world][mesh]") {
  BodyShape const floor = MeshShape{flat_floor()};
  BodyShape const box = Cuboid{Vec3::splat(0.5f)};
  Iso3 const floor_pose = Iso3::from_translation({-8.0f, 0.0f, -8.0f});
  Iso3 const box_pose{Quat::from_axis_angle(Vec3::Y, 0.3f), {0.2f, 0.5f - 0.01f, 0.4f}};
  ManifoldConfig const cfg;
  std::array<Manifold, max_mesh_manifolds> as_a, as_b;
  REQUIRE(detail::collide(floor, floor_pose, box, box_pose, cfg, as_a) == 1);
  REQUIRE(detail::collide(box, box_pose, floor, floor_pose, cfg, as_b) == 1);
  Manifold const& a = as_a[0];
  Manifold const& b = as_b[0];
  CHECK(a.normal.y == Approx(1.0f).margin(1e-6));  // from A (the floor) toward the box
  CHECK(b.normal.y == Approx(-1.0f).margin(1e-6)); // from A (the box) toward the floor
  REQUIRE(a.count == 4);
  REQUIRE(b.count == 4);
  for (int k = 0; k < 4; ++k) {
    ContactPoint const& pa = a.points[std::size_t(k)];
    ContactPoint const& pb = b.points[std::size_t(k)];
    CHECK(pa.point_a.y == Approx(0.0f).margin(1e-5));   // on the floor
    CHECK(pa.point_b.y == Approx(-0.01f).margin(1e-5)); // on the box's bottom face
    CHECK(same_bits(pb.point_a, pa.point_b));           // the same points, turned round
    CHECK(same_bits(pb.point_b, pa.point_a));
    CHECK(same_bits(pb.separation, pa.separation));
  }
}

TEST_CASE("mesh bodies: a kinematic mesh or height field carries and lifts a box",
          "[world][mesh][kinematic]") {
  // A moving platform of triangles: it slides along x at 1 m/s and rises at 0.5 m/s; the box
  // on it rides along by friction and is pushed up, never sinking into it.
  for (int kind = 0; kind < 2; ++kind) {
    INFO((kind == 0 ? "mesh" : "height field"));
    World w;
    BodyShape const shape =
        kind == 0 ? BodyShape{MeshShape{flat_floor()}} : BodyShape{HeightFieldShape{flat_field()}};
    CreateBodyResult const platform =
        w.create_body({.type = BodyType::kinematic,
                       .pose = Iso3::from_translation({-8.0f, 0.0f, -8.0f}),
                       .linear_velocity = {1.0f, 0.0f, 0.0f},
                       .shape = shape,
                       .friction = 1.0f});
    REQUIRE(platform);
    BodyId const box = w.create_body({.pose = Iso3::from_translation({0, 0.5f, 0}),
                                      .shape = Cuboid{Vec3::splat(0.5f)},
                                      .friction = 1.0f})
                           .id;
    float lowest = 1.0f;
    for (int s = 0; s < 180; ++s) {
      if (s == 60) REQUIRE(w.set_velocity(platform.id, {1.0f, 0.5f, 0.0f}, {}) == BodyError::none);
      w.step(dt);
      float const floor_y = w.pose(platform.id).translation.y;
      lowest = std::min(lowest, w.pose(box).translation.y - floor_y);
    }
    float const moved = w.pose(platform.id).translation.x + 8.0f;
    CHECK(moved == Approx(3.0f).margin(1e-3));
    CHECK(w.pose(box).translation.x == Approx(moved).margin(0.06)); // it slips 5 cm starting
    CHECK(w.pose(platform.id).translation.y == Approx(1.0f).margin(1e-3));
    CHECK(w.pose(box).translation.y == Approx(1.5f).margin(0.002));
    CHECK(lowest > 0.495f); // never sank 5 mm into the moving floor
    CHECK(w.linear_velocity(box).x == Approx(1.0f).margin(0.005));
  }
}
