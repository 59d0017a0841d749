// solver/world/world_kernels.hpp - the table of the world's kernels that one instruction set
// provides (private to the world floor): world_kernels.cpp fills one per carried set of a
// PLUME_DISPATCH=ON build, entry_points.cpp calls through the active one.
#pragma once

#include <plume/numerics/isa.hpp>
#include <plume/solver/world/world.hpp>

namespace plume::detail {

struct WorldKernels {
  Isa isa; // the set the kernels were compiled for
  void (*step)(World& world, float dt);
  void (*ray_cast)(World const& world, std::span<Ray3 const> rays, float max_toi,
                   std::span<std::optional<WorldRayHit>> out, QueryFilter const& filter);
  void (*shape_cast)(World const& world, std::span<BodyShape const> shapes,
                     std::span<Iso3 const> poses, std::span<Vec3 const> motions,
                     ShapeCastConfig const& cfg, std::span<std::optional<WorldShapeHit>> out,
                     QueryFilter const& filter);
};

} // namespace plume::detail

// Each world_kernels.cpp object defines its table's accessor
// `extern "C" WorldKernels const* plume_world_table_<suffix>() noexcept`, the one global
// symbol of its isolated object (cmake/PlumeDispatch.cmake).
