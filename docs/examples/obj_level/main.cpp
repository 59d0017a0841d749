// plume's OBJ example: loads a level from a Wavefront OBJ file (load_obj.hpp), makes it a
// static mesh body, drops a box on the floor and a ball on the 0.3 m step, lays a box on the
// 30-degree ramp (held by friction), and checks that each comes to rest on the surface a ray
// cast finds below it.
//
//   plume_obj_level [file.obj]      (default: level.obj beside this file)
//
// Exits 0 when the file loads and every body rests where it should; prints what it found.
#include "load_obj.hpp"

#include <plume/world.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

using namespace plume;

int main(int argc, char** argv) {
  std::string const path = argc > 1 ? argv[1] : PLUME_EXAMPLE_LEVEL;
  plume_example::ObjMesh level = plume_example::load_obj_mesh(path);
  if (!level.error.empty()) {
    std::fprintf(stderr, "obj_level: %s\n", level.error.c_str());
    return 1;
  }
  std::printf("obj_level: %s: %zu triangles kept of %zu, %zu degenerate dropped\n", path.c_str(),
              level.built.triangles, level.built.input_triangles, level.built.degenerate);
  auto const mesh = std::make_shared<TriangleMesh const>(std::move(level.built.mesh));

  World world;
  world.create_body({.type = BodyType::static_body, .shape = MeshShape{mesh}});
  // Where each body starts, and the height of the surface it should rest on (x: where it is).
  float const tan30 = 0.57735f;
  struct drop {
    char const* what;
    BodyShape shape;
    Iso3 at;
    float (*surface)(float x);
  };
  drop const drops[] = {
      {"box on the floor", Cuboid{Vec3::splat(0.5f)}, Iso3::from_translation({5.0f, 2.0f, -7.0f}),
       [](float) { return 0.0f; }},
      {"ball on the step", Sphere{0.4f}, Iso3::from_translation({-4.0f, 2.0f, 4.0f}),
       [](float) { return 0.3f; }},
      // Laid on the ramp, 1 cm above it: friction (0.9 and the level's 0.6 give 0.73) holds
      // it on a 30-degree slope (tan 30 = 0.58).
      {"box on the ramp", Cuboid{Vec3::splat(0.3f)},
       Iso3{Quat::from_axis_angle(Vec3::Z, 0.5235988f),
            Vec3{4.0f, 2.0f * tan30, 3.5f} + Vec3{-0.5f, 0.866f, 0.0f} * 0.31f},
       [](float x) { return (x - 2.0f) * 0.57735f; }},
  };
  BodyId ids[3];
  for (int i = 0; i < 3; ++i)
    ids[i] = world.create_body({.pose = drops[i].at, .shape = drops[i].shape, .friction = 0.9f}).id;
  for (int s = 0; s < 240; ++s)
    world.step(1.0f / 60.0f);

  bool ok = true;
  for (int i = 0; i < 3; ++i) {
    Vec3 const p = world.pose(ids[i]).translation;
    float const speed = world.linear_velocity(ids[i]).length();
    // The surface right under the body, by a ray cast from above it.
    auto const below = world.ray_cast({p + Vec3{0.0f, 5.0f, 0.0f}, {0.0f, -1.0f, 0.0f}}, 20.0f,
                                      {.exclude = std::span<BodyId const>(&ids[i], 1)});
    float const surface = below ? p.y + 5.0f - below->toi : NAN;
    bool const here = std::abs(surface - drops[i].surface(p.x)) < 1e-3f;
    bool const resting = speed < 0.02f && p.y > surface;
    std::printf("obj_level: %-16s at (%.3f, %.3f, %.3f), surface below at %.3f, speed %.4f m/s%s\n",
                drops[i].what, p.x, p.y, p.z, surface, speed, here && resting ? "" : "  <- wrong");
    ok = ok && here && resting;
  }
  return ok ? 0 : 1;
}
