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

/// Cubes of edge `size` in a pyramid of `layers` layers resting on y = 0, centred on x = z = 0.
/// Returns the boxes bottom layer first; the last one is the top box.
inline std::vector<BodyId> add_box_pyramid(World& world, int layers, float size = 1.0f,
                                           float density = 1000.0f, float friction = 0.6f) {
  std::vector<BodyId> ids;
  BodyDef def;
  def.shape = Cuboid{Vec3::splat(0.5f * size)};
  def.density = density;
  def.friction = friction;
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
  BodyDef def;
  def.shape = Cuboid{Vec3::splat(0.5f * size)};
  def.density = density;
  def.friction = friction;
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

} // namespace plume
