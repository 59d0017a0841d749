// Uses plume as a user project would (and runs the README's tour example); exits 0 when the
// numbers are right.
#include <plume/plume.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

template <plume::Real T>
T bounce_height(T x, T height) {
  T const s = plume::sin(x) * height;
  return plume::select(s < T(0), -s, s);
}

int main() {
  float const s = plume::sin(plume::frac_pi_2<float>());
  double const l = plume::log2(1024.0);
  std::printf("consumer: sin(pi/2) = %g, log2(1024) = %g, build %s\n", s, l, plume::simd_name);
  float const one = bounce_height(4.0f, 2.0f);
  plume::f32xN const many = bounce_height(plume::f32xN(4.0f), plume::f32xN(2.0f));
  bool lanes_equal = true;
  for (std::size_t i = 0; i < plume::lanes_v<plume::f32xN>; ++i)
    lanes_equal = lanes_equal && plume::lane(many, i) == one;
  // The README's geometry example.
  using namespace plume;
  Vec3 const my_vec3_array[16] = {{1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
  Vec3xN const dirs = pack<f32xN>(my_vec3_array);
  QuatxN const rot = QuatxN(Quat::from_axis_angle(Vec3::Y, 0.5f));
  Vec3xN const turned = rot * dirs.normalize_or_zero();
  auto [unit, ok] = turned.try_normalize();
  Vec3 const first = lane(turned, 0);
  bool const geometry_ok = plume::lane(ok, 0) && std::abs(first.length() - 1.0f) < 1e-6f &&
                           std::abs(lane(unit, 0).y) < 1e-6f;
  std::printf("consumer: first turned direction (%g, %g, %g)\n", first.x, first.y, first.z);
  // The README's solver example.
  Vec3 const floor_normal{0, 0, 1}, wall_normal{-1, 0, 0};
  Vec3 const velocity{1, 2, -1};
  PlaneSet3 planes(velocity);
  planes.add(floor_normal);
  planes.add(wall_normal);
  auto slide = project_velocity(velocity, planes.normals());
  Vec3xN const crowd(velocity);
  std::vector<Vec3xN> const lane_planes = {Vec3xN(floor_normal), Vec3xN(wall_normal)};
  auto slides = project_velocity(crowd, lane_planes);
  Penetration3 const hits[] = {{floor_normal, 0.02f}, {wall_normal, 0.01f}};
  Vec3 const fix = depenetrate(hits).correction;
  // The batch form (compiled, in the character library): the same problem twice.
  Vec3 const batch_v[] = {velocity, velocity};
  Vec3 const batch_n[] = {floor_normal, wall_normal, floor_normal, wall_normal};
  std::uint32_t const batch_offsets[] = {0, 2, 4};
  VelocityProjection3 batch[2];
  bool const batch_ok =
      project_velocities(batch_v, batch_n, batch_offsets, batch) == ProjectVelocitiesError::none &&
      batch[1].velocity.x == slide.velocity.x && batch[1].velocity.y == slide.velocity.y &&
      batch[1].velocity.z == slide.velocity.z;
  bool const solver_ok = slide.converged && slide.velocity.x == 0 && slide.velocity.y == 2 &&
                         slide.velocity.z == 0 && lane(slides.velocity, 0).y == 2 &&
                         fix.x == -0.01f && fix.y == 0 && fix.z == 0.02f && batch_ok;
  std::printf("consumer: slide (%g, %g, %g), fix (%g, %g, %g)\n", slide.velocity.x,
              slide.velocity.y, slide.velocity.z, fix.x, fix.y, fix.z);
  // The README's ray-cast example (capsules of half height 1, radius 0.5 at x = 10, rays
  // from the origin along +x).
  f32xN const half_heights(1.0f), radii(0.5f);
  QuatxN const rotations(Quat::IDENTITY);
  Vec3xN const centres(Vec3{10, 0, 0}), origins(Vec3::ZERO), directions(Vec3{2, 0, 0});
  GCapsule<f32xN> const caps{half_heights, radii};
  GIso3<f32xN> const poses{rotations, centres};
  GRay3<f32xN> const rays{origins, directions};
  GRayHit<f32xN> const hit = ray_cast(caps, poses, rays, infinity<f32xN>());
  bool const ray_ok =
      plume::all(hit.hit) && lane(hit.toi, 0) == 4.75f && lane(hit.normal, 0).x == -1;
  std::printf("consumer: ray toi %g\n", lane(hit.toi, 0));
  // The README's hull / GJK / EPA / manifold example: a 2 m cube of rock at x = 5, a capsule
  // at the origin moving 10 m along +x, a crate overlapping the rock by 0.1 m.
  std::vector<Vec3> points;
  for (int i = 0; i < 8; ++i)
    points.push_back({(i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : -1.0f});
  points.push_back({0, 0, 0}); // inside: dropped
  auto built = ConvexHull::build(points);
  if (!built) std::puts(to_string(built.error));
  ConvexHull const& rock = built.hull;
  MassProperties const mass = rock.mass_properties(2500.0f);
  Iso3 const rock_pose = Iso3::from_translation({5, 0, 0}), player{},
             crate = Iso3::from_translation({3.6f, 0, 0});
  Vec3 const motion{10, 0, 0};
  ClosestPoints const d = closest_points(Capsule{0.9f, 0.3f}, player, rock, rock_pose);
  ShapeCastConfig cast;
  cast.target_distance = 0.01f;
  ShapeCastHit const sweep = shape_cast(Capsule{0.9f, 0.3f}, player, motion, rock, rock_pose, cast);
  PenetrationResult const p = penetration(Cuboid{{0.5f, 0.5f, 0.5f}}, crate, rock, rock_pose);
  Manifold const m = contact_manifold(Cuboid{{0.5f, 0.5f, 0.5f}}, crate, rock, rock_pose);
  bool const contact_ok = built && rock.faces().size() == 6 && std::abs(mass.mass - 20000) < 1 &&
                          std::abs(d.distance - 3.7f) < 1e-4f && sweep.hit &&
                          std::abs(sweep.toi - 0.369f) < 1e-4f &&
                          std::abs(p.depth - 0.1f) < 1e-4f && m.count == 4 &&
                          std::abs(m.min_separation() + 0.1f) < 1e-4f;
  std::printf("consumer: hull %zu faces, mass %g, distance %g, toi %g, depth %g, %d contacts\n",
              rock.faces().size(), mass.mass, d.distance, sweep.toi, p.depth, m.count);
  // The README's world example, solved at the widest width and at x1: the same bits.
  auto const run_world = [](bool scalar) {
    World world;
    world.create_body({.type = BodyType::static_body, .shape = HalfSpace{Vec3::Y}});
    BodyId box = world
                     .create_body({.pose = Iso3::from_translation({0, 2, 0}),
                                   .shape = Cuboid{Vec3::splat(0.5f)}})
                     .id;
    CreateBodyResult made = world.create_body(
        {.pose = Iso3::from_translation({0, 20, 0}), .shape = Sphere{0.25f}, .restitution = 0.5f});
    if (!made) std::puts(to_string(made.error).data());
    for (int i = 0; i < 600; ++i)
      scalar ? world.step_with<float>(1.0f / 60.0f) : world.step(1.0f / 60.0f);
    Iso3 const where = world.pose(box);
    return std::pair{where.translation.y, world.state_hash()};
  };
  auto const [top_y, hash] = run_world(false);
  bool const world_ok = std::abs(top_y - 0.5f) < 0.05f && run_world(true).second == hash;
  std::printf("consumer: box at y = %g, world hash %016llx\n", top_y, (unsigned long long)hash);
  // The README's spatial example: one box in a tree, a ray along +x into it.
  AabbTree tree;
  ProxyId const box_id = tree.insert(Aabb3{{0, 0, 0}, {1, 1, 1}}, 42);
  bool const stayed = !tree.move(box_id, Aabb3{{0.02f, 0, 0}, {1.02f, 1, 1}});
  tree.optimize();
  int found = 0;
  tree.query(Aabb3{{-1, -1, -1}, {0.5f, 0.5f, 0.5f}}, [&](ProxyId id) {
    found += tree.user(id) == 42 ? 1 : 0;
    return true;
  });
  WideBvh const bvh(tree);
  TreeRayHit const tree_hit =
      bvh.ray_cast(Ray3{{-5, 0.5f, 0.5f}, {1, 0, 0}}, 100.0f, [&](ProxyId, float) { return 5.0f; });
  bool const spatial_ok = stayed && found == 1 && tree.validate().empty() && tree_hit.hit() &&
                          tree_hit.proxy == box_id && tree_hit.toi == 5.0f;
  std::printf("consumer: tree hit %u at %g\n", tree_hit.proxy, tree_hit.toi);
  // The README's move-and-slide example: a capsule walks into a wall and slides along it.
  World level;
  level.create_body({.type = BodyType::static_body,
                     .pose = Iso3::from_translation({0, -1.01f, 0}),
                     .shape = HalfSpace{Vec3::Y}});
  level.create_body({.type = BodyType::static_body,
                     .pose = Iso3::from_translation({3, 0, 0}),
                     .shape = Cuboid{Vec3{0.5f, 5, 5}}});
  WorldMoveQuery const scene(level);
  Vec3 feet{0, 0, 0};
  for (int frame = 0; frame < 60; ++frame) {
    auto const r = move_and_slide(scene, Capsule{0.5f, 0.5f}, Iso3::from_translation(feet),
                                  Vec3{5, -1, 2}, 1.0f / 60.0f, {}, {},
                                  [](MoveHit<ColliderId>&) { return HitResponse::accept; });
    feet = r.position;
  }
  // The README's crowd: W capsules at the origin, each moved as alone.
  std::array<BodyShape, lanes_v<f32xN>> walkers;
  walkers.fill(Capsule{0.5f, 0.5f});
  auto const moved =
      move_and_slide_lanes<f32xN>(scene, walkers, GIso3<f32xN>{}, GVec3<f32xN>(Vec3{5, -1, 2}),
                                  1.0f / 60.0f, {}, {}, AcceptAllHits{});
  auto const alone = move_and_slide(scene, Capsule{0.5f, 0.5f}, Iso3{}, Vec3{5, -1, 2},
                                    1.0f / 60.0f, {}, {}, AcceptAllHits{});
  bool const crowd_ok = lane(moved.position.x, 0) == alone.position.x &&
                        lane(moved.position.z, lanes_v<f32xN> - 1) == alone.position.z;
  bool const move_ok = crowd_ok && std::abs(2.5f - (feet.x + 0.5f) - 0.01f) < 0.002f &&
                       std::abs(feet.y) < 0.002f && std::abs(feet.z - 2.0f) < 0.05f;
  std::printf("consumer: character at (%g, %g, %g)\n", feet.x, feet.y, feet.z);
  // The README's controller: walks at the wall, jumps on the way, ends on the floor against
  // the wall, and crouches.
  CharacterController hero(level, {.shape = Capsule{0.5f, 0.3f}, .position = {0, -0.2f, 0}});
  bool jumped = false;
  for (int frame = 0; frame < 120; ++frame) {
    level.step(1.0f / 60.0f);
    Vec3 const walk{3, 0, 0};
    Vec3 v = hero.velocity();
    if (hero.on_ground())
      v = walk + (frame == 30 ? hero.up() * 5.0f : Vec3{});
    else
      v = v + level.config().gravity * (1.0f / 60.0f);
    hero.set_velocity(v);
    hero.update(level, 1.0f / 60.0f);
    jumped = jumped || hero.position().y > 0.5f;
  }
  bool const crouched = hero.set_shape(level, Capsule{0.1f, 0.3f}) == CharacterError::none;
  bool const hero_ok = jumped && crouched && hero.on_ground() &&
                       std::abs(hero.position().x - (2.5f - 0.3f - 0.01f)) < 0.002f &&
                       std::abs(hero.position().y - (-1.01f + 0.4f + 0.01f)) < 0.002f;
  std::printf("consumer: hero at (%g, %g), %s\n", hero.position().x, hero.position().y,
              std::string(to_string(hero.ground_state())).c_str());
  // The README's mesh and terrain bodies: a box dropped on a two-triangle floor and a crate
  // on a 3 x 3 height field settle on them.
  std::vector<Vec3> const floor_v{{-4, 0, -4}, {4, 0, -4}, {-4, 0, 4}, {4, 0, 4}};
  std::vector<std::uint32_t> const floor_i{0, 2, 1, 1, 2, 3};
  auto floor_built = TriangleMesh::build(floor_v, floor_i);
  std::vector<float> const heights(9, 0.0f);
  auto terrain = HeightField::build(3, 3, heights, 4.0f, 4.0f);
  World grounds;
  auto level_mesh = std::make_shared<TriangleMesh const>(std::move(floor_built.mesh));
  grounds.create_body({.type = BodyType::static_body, .shape = MeshShape{level_mesh}});
  grounds.create_body(
      {.type = BodyType::static_body,
       .pose = Iso3::from_translation({10, 0, -4}),
       .shape = HeightFieldShape{std::make_shared<HeightField const>(terrain.field)}});
  BodyId const on_mesh = grounds
                             .create_body({.pose = Iso3::from_translation({0.5f, 1, 0.5f}),
                                           .shape = Cuboid{Vec3::splat(0.5f)}})
                             .id;
  BodyId const on_field = grounds
                              .create_body({.pose = Iso3::from_translation({14, 1, 0}),
                                            .shape = Cuboid{Vec3::splat(0.5f)}})
                              .id;
  for (int i = 0; i < 120; ++i)
    grounds.step(1.0f / 60.0f);
  bool const ground_ok = floor_built.ok() && terrain.ok() &&
                         std::abs(grounds.pose(on_mesh).translation.y - 0.5f) < 0.02f &&
                         std::abs(grounds.pose(on_field).translation.y - 0.5f) < 0.02f;
  std::printf("consumer: boxes on a mesh and a height field at y = %g, %g\n",
              grounds.pose(on_mesh).translation.y, grounds.pose(on_field).translation.y);
  // The README's joints example: a motorised hinge reaches its target speed.
  World jointed;
  BodyId post = jointed.create_body({.type = BodyType::static_body, .shape = Sphere{0.05f}}).id;
  BodyId fan = jointed
                   .create_body({.pose = Iso3::from_translation({0, -0.5f, 0}),
                                 .shape = Cuboid{{0.8f, 0.05f, 0.1f}}})
                   .id;
  JointId hinge =
      jointed
          .create_joint({.body_a = post,
                         .body_b = fan,
                         .frame_a = jointed.joint_frame(post, {0, -0.5f, 0}, Vec3::Y),
                         .frame_b = jointed.joint_frame(fan, {0, -0.5f, 0}, Vec3::Y),
                         .type = RevoluteJoint{.motor = Motor::velocity_control(6.0f, 50.0f)}})
          .id;
  for (int i = 0; i < 120; ++i)
    jointed.step(1.0f / 60.0f);
  JointState const js = jointed.joint_state(hinge);
  bool const joint_ok = std::abs(js.angular_speed - 6.0f) < 0.01f &&
                        jointed.set_motor(hinge, Motor::position_control(1.0f)) == JointError::none;
  std::printf("consumer: a motorised hinge turns at %g rad/s\n", js.angular_speed);
  // The README's dispatch example: sines of an array on the widest kernels this CPU has.
  std::vector<float> angles(1000, 0.5f), sines(1000);
  SpanError const span_error = plume::sin(angles, sines);
  bool const dispatch_ok =
      span_error == SpanError::none && sines[999] == plume::sin(0.5f) && cpu_has(active_isa());
  std::printf("consumer: %zu sines on %s kernels\n", sines.size(),
              std::string(isa_name(active_isa())).c_str());
  return (s == 1.0f && l == 10.0 && lanes_equal && one > 1.5f && geometry_ok && solver_ok &&
          ray_ok && contact_ok && world_ok && spatial_ok && move_ok && ground_ok && hero_ok &&
          joint_ok && dispatch_ok)
             ? 0
             : 1;
}
