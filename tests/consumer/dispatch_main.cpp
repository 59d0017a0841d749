// plume as one shared library (plume::shared, a PLUME_DISPATCH=ON build): one binary that runs
// the widest kernels of whatever CPU it lands on. Exits 0 when every carried set this CPU runs
// gives the same sines and the same world.
#include <plume/dispatch.hpp>
#include <plume/world.hpp>

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

int main() {
  std::vector<double> x(1001);
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] = 0.01 * static_cast<double>(i) - 5.0;
  std::printf("consumer (shared): best %s, active %s\n",
              std::string(plume::isa_name(plume::best_isa())).c_str(),
              std::string(plume::isa_name(plume::active_isa())).c_str());
  std::vector<double> first;
  std::uint64_t first_world = 0;
  bool ok = true;
  for (plume::Isa const isa : plume::compiled_isas()) {
    if (!plume::cpu_has(isa)) {
      std::printf("consumer (shared): %s skipped, this CPU lacks it\n",
                  std::string(plume::isa_name(isa)).c_str());
      continue;
    }
    std::vector<double> out(x.size());
    ok = ok && plume::set_isa(isa) == plume::IsaError::none &&
         plume::sin(x, out) == plume::SpanError::none;
    plume::World world;
    world.create_body(
        {.type = plume::BodyType::static_body, .shape = plume::HalfSpace{plume::Vec3::Y}});
    for (int i = 0; i < 10; ++i)
      world.create_body(
          {.pose = plume::Iso3::from_translation({0.1f * float(i), 0.5f + float(i), 0}),
           .shape = plume::Cuboid{plume::Vec3::splat(0.5f)}});
    for (int i = 0; i < 60; ++i)
      world.step(1.0f / 60.0f);
    // The batch velocity projection: a floor and a wall against (1, 2, -1), 17 times.
    std::vector<plume::Vec3> v(17, plume::Vec3{1, 2, -1}), n;
    std::vector<std::uint32_t> offsets{0};
    for (int i = 0; i < 17; ++i) {
      n.push_back({0, 0, 1});
      n.push_back({-1, 0, 0});
      offsets.push_back(static_cast<std::uint32_t>(n.size()));
    }
    std::vector<plume::VelocityProjection3> slides(v.size());
    ok = ok &&
         plume::project_velocities(std::span<plume::Vec3 const>(v), std::span<plume::Vec3 const>(n),
                                   offsets, slides) == plume::ProjectVelocitiesError::none;
    for (auto const& s : slides)
      ok = ok && s.converged && s.velocity.x == 0 && s.velocity.y == 2 && s.velocity.z == 0;
    if (first.empty()) {
      first = out;
      first_world = world.state_hash();
    } else {
      ok = ok && out == first && world.state_hash() == first_world;
    }
  }
  return ok && !first.empty() ? 0 : 1;
}
