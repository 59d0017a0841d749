// solver/world/world_kernels.cpp - the world's kernels of one instruction set (a
// PLUME_DISPATCH=ON build compiles it, with step.cpp and queries.cpp, once per carried set):
// the step and the batch queries at the set's widest width.
#include "world_kernels.hpp"

#ifndef PLUME_DISPATCH_ISA
#error "compile world_kernels.cpp with PLUME_DISPATCH_ISA set to the instruction set's name"
#endif
#define PLUME_CAT2(a, b) a##b
#define PLUME_CAT(a, b) PLUME_CAT2(a, b)

namespace plume::detail {
namespace {

void step(World& world, float dt) { world.step_with<f32xN>(dt); }

void ray_cast(World const& world, std::span<Ray3 const> rays, float max_toi,
              std::span<std::optional<WorldRayHit>> out, QueryFilter const& filter) {
  world.ray_cast_with<f32xN>(rays, max_toi, out, filter);
}

void shape_cast(World const& world, std::span<BodyShape const> shapes, std::span<Iso3 const> poses,
                std::span<Vec3 const> motions, ShapeCastConfig const& cfg,
                std::span<std::optional<WorldShapeHit>> out, QueryFilter const& filter) {
  world.shape_cast_with<f32xN>(shapes, poses, motions, cfg, out, filter);
}

constexpr WorldKernels table = {
    PLUME_HAS_AVX512 ? Isa::avx512
    : PLUME_HAS_AVX2 ? Isa::avx2
    : PLUME_HAS_SSE2 ? Isa::sse2
                     : Isa::scalar,
    &step,
    &ray_cast,
    &shape_cast,
};

} // namespace
} // namespace plume::detail

extern "C" plume::detail::WorldKernels const* PLUME_CAT(plume_world_table_,
                                                        PLUME_DISPATCH_ISA)() noexcept {
  return &plume::detail::table;
}
