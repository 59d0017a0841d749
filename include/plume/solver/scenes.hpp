// plume/solver/scenes.hpp - reference scenes for tests, benchmarks and demos, each added to
// a World (solver/world.hpp). Y is up, the ground is the plane y = 0, units are SI.
//
//   add_ground(world)                     static half-space y <= 0
//   add_box_pyramid(world, layers, size)  layer i (from 0 at the bottom) is a
//                                         (layers - i) x (layers - i) grid of cubes, centred,
//                                         so odd layers sit half a box off the even ones;
//                                         15 layers = 1,240 boxes (Jolt's pyramid)
//   add_box_stack(world, count, size)     a column of cubes
//   add_ramp(world, angle, ...)           a static slab tilted about z by `angle` (rad)
//   add_rolling_spheres(world, angle, n)  a ramp with n spheres resting on it side by side
//   add_ball(world, position, radius, e)  one dynamic sphere (a bouncing ball for e > 0)
#pragma once

#include <plume/solver/world.hpp>

#include <cmath>
#include <vector>

namespace plume {

/// The static ground plane y = 0 (normal +y).
inline BodyId add_ground(World& world, float friction = 0.6f) {
  BodyDef def;
  def.type = BodyType::static_body;
  def.shape = HalfSpace{Vec3::Y};
  def.friction = friction;
  return world.create_body(def).id;
}

/// A dynamic cube of edge `size` (pose left at the origin).
inline BodyDef cube_def(float size, float density, float friction) {
  BodyDef def;
  def.shape = Cuboid{Vec3::splat(0.5f * size)};
  def.density = density;
  def.friction = friction;
  return def;
}

/// Cubes of edge `size` in a pyramid of `layers` layers resting on y = 0, centred on x = z = 0.
/// Returns the boxes bottom layer first; the last one is the top box.
inline std::vector<BodyId> add_box_pyramid(World& world, int layers, float size = 1.0f,
                                           float density = 1000.0f, float friction = 0.6f) {
  std::vector<BodyId> ids;
  BodyDef def = cube_def(size, density, friction);
  for (int i = 0; i < layers; ++i) {
    int const n = layers - i;
    float const y = (0.5f + float(i)) * size;
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        float const x = (float(j) - 0.5f * float(n - 1)) * size;
        float const z = (float(k) - 0.5f * float(n - 1)) * size;
        def.pose = Iso3::from_translation({x, y, z});
        ids.push_back(world.create_body(def).id);
      }
  }
  return ids;
}

/// `count` cubes of edge `size` stacked at x = z = 0 on y = 0; bottom first.
inline std::vector<BodyId> add_box_stack(World& world, int count, float size = 1.0f,
                                         float density = 1000.0f, float friction = 0.6f) {
  std::vector<BodyId> ids;
  BodyDef def = cube_def(size, density, friction);
  for (int i = 0; i < count; ++i) {
    def.pose = Iso3::from_translation({0.0f, (0.5f + float(i)) * size, 0.0f});
    ids.push_back(world.create_body(def).id);
  }
  return ids;
}

/// A static slab (length x 1 x width, thickness 1) whose top face passes through `top_center`,
/// tilted about +z by `angle` (rad): the top face's downhill direction is
/// (-cos a, -sin a, 0) for angle a > 0.
inline BodyId add_ramp(World& world, float angle, Vec3 top_center, float length = 20.0f,
                       float width = 4.0f, float friction = 0.6f) {
  BodyDef def;
  def.type = BodyType::static_body;
  def.shape = Cuboid{{0.5f * length, 0.5f, 0.5f * width}};
  Quat const r = Quat::from_rotation_z(angle);
  def.pose = Iso3{r, top_center - r * Vec3{0.0f, 0.5f, 0.0f}};
  def.friction = friction;
  return world.create_body(def).id;
}

/// A dynamic sphere of `radius` at `position` with restitution `restitution`.
inline BodyId add_ball(World& world, Vec3 position, float radius = 0.25f, float restitution = 0.5f,
                       float friction = 0.6f, float density = 1000.0f) {
  BodyDef def;
  def.shape = Sphere{radius};
  def.pose = Iso3::from_translation(position);
  def.restitution = restitution;
  def.friction = friction;
  def.density = density;
  return world.create_body(def).id;
}

/// A ramp tilted by `angle` (rad, about +z, its top face through the origin, 40 m long) with
/// `count` spheres of `radius` resting on its top face 1 m apart along z, at rest: they roll
/// down along (-cos a, -sin a, 0). Returns the ramp, then the spheres.
inline std::vector<BodyId> add_rolling_spheres(World& world, float angle, int count,
                                               float radius = 0.25f, float friction = 0.6f) {
  std::vector<BodyId> ids;
  ids.push_back(add_ramp(world, angle, Vec3{}, 40.0f, float(count) + 1.0f, friction));
  Quat const r = Quat::from_rotation_z(angle);
  for (int i = 0; i < count; ++i) {
    float const z = float(i) - 0.5f * float(count - 1);
    ids.push_back(add_ball(world, r * Vec3{0.0f, radius, z}, radius, 0.0f, friction));
  }
  return ids;
}

} // namespace plume
