// solver/world/entry_points.cpp - the world's dispatched entry points: World::step and the
// batch forms of World::ray_cast and World::shape_cast run the widest width of the build, or
// in a PLUME_DISPATCH=ON build that of the chosen instruction set
// (include/plume/numerics/isa.hpp), through its table (world_kernels.cpp).
#include <plume/solver/world/world.hpp>
#include <plume_dispatch_list.hpp>

#if PLUME_DISPATCH
#include "world_kernels.hpp"

#define PLUME_DECLARE_TABLE(suffix)                                                                \
  extern "C" plume::detail::WorldKernels const* plume_world_table_##suffix() noexcept;
PLUME_DISPATCH_LIST(PLUME_DECLARE_TABLE)
#undef PLUME_DECLARE_TABLE
#endif

namespace plume {

#if PLUME_DISPATCH
namespace {
using Accessor = detail::WorldKernels const* (*)() noexcept;
#define PLUME_ACCESSOR(suffix) &plume_world_table_##suffix,
constexpr Accessor accessors[] = {PLUME_DISPATCH_LIST(PLUME_ACCESSOR)};
#undef PLUME_ACCESSOR
detail::WorldKernels const& kernels() noexcept { return *accessors[detail::active_isa_index()](); }
} // namespace

Isa detail::world_kernels_isa() noexcept { return kernels().isa; }

void World::step(float dt) { kernels().step(*this, dt); }

void World::ray_cast(std::span<Ray3 const> rays, float max_toi,
                     std::span<std::optional<WorldRayHit>> out, QueryFilter const& filter) const {
  kernels().ray_cast(*this, rays, max_toi, out, filter);
}

void World::shape_cast(std::span<BodyShape const> shapes, std::span<Iso3 const> poses,
                       std::span<Vec3 const> motions, ShapeCastConfig const& cfg,
                       std::span<std::optional<WorldShapeHit>> out,
                       QueryFilter const& filter) const {
  kernels().shape_cast(*this, shapes, poses, motions, cfg, out, filter);
}
#else
Isa detail::world_kernels_isa() noexcept { return active_isa(); } // the build's own set

void World::step(float dt) { step_with<f32xN>(dt); }

void World::ray_cast(std::span<Ray3 const> rays, float max_toi,
                     std::span<std::optional<WorldRayHit>> out, QueryFilter const& filter) const {
  ray_cast_with<f32xN>(rays, max_toi, out, filter);
}

void World::shape_cast(std::span<BodyShape const> shapes, std::span<Iso3 const> poses,
                       std::span<Vec3 const> motions, ShapeCastConfig const& cfg,
                       std::span<std::optional<WorldShapeHit>> out,
                       QueryFilter const& filter) const {
  shape_cast_with<f32xN>(shapes, poses, motions, cfg, out, filter);
}
#endif

} // namespace plume
